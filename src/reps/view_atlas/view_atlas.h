// View atlas in memory (Saraiva et al. §3): the model rendered from
// many directions around its bounding sphere, each image cropped to its content and packed into
// atlas pages. At run time a camera-facing quad through the sphere's centre shows the nearest view
// (style "seed"), or the views around the viewing direction are blended and, with stored depth,
// intersected per pixel (styles "octahedral-baseline" and "corrected", renderer.cpp). Shared by the
// baker, the package codec and the renderer of this folder.
#pragma once

#include <standin/image.h>
#include <standin/package.h>

#include "reps/common/view_layout.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin::view_atlas {

// Views, cells, layouts and page packing are the image-based stand-ins' own (reps/common/view_layout.h).
using reps::k_cell;
using reps::k_mip_levels;
using reps::View;
using reps::layout_directions;
using reps::pack_views;

// Capture samples per texel side for models with alpha-tested materials (issue #14, bake.cpp):
// their coverage is stored as a fraction. 2 x 2 measured best on the foliage tree (IoU 0.949 against
// 0.947 with one sample and 0.945 with 4 x 4, whose many partly covered texels each take their
// nearest sample's depth: docs/RESULTS.md "Fractional coverage in the view atlas").
constexpr int k_coverage_samples = 2;

// Capture size per side for models with alpha-tested materials when --resolution is not given
// (issue #14), with one sample per texel. At the default 256 a capture texel of the whole tree is
// about 2 screen pixels at distance 1, and a leaf's cut-out is a few texels wide: its edge, its
// narrow gaps and its colour are blurred over texels that each keep one depth. 512 (the same 512²
// capture as 256 at 2 x 2 samples) gives thesis IoU 0.962 against 0.949 and Luv 7.2 against 9.3 on
// the foliage tree, at about 3x the package and 4x the pages (docs/RESULTS.md "Capture resolution
// for alpha-tested models"). Other models keep 256: their packages do not change. 768 gives Luv 4.42
// against 5.62 at distance 1 but twice the package and 768 MiB of pages for one 4,000-triangle
// tree; not the default (docs/RESULTS.md "View atlas on foliage: colour level and capture resolution").
constexpr int k_alpha_resolution = 512;

// Models with detail finer than the default capture texels (issue #17: the held-out engine's
// nested parts and fins): when over k_detail_edge_fraction of the views' covered texels end their
// surface (bake.cpp depth_edge_fraction), the views are captured again at k_detail_resolution.
constexpr int k_detail_resolution = 512;
constexpr double k_detail_edge_fraction = 0.15;

// The --baseline-below measured for crowds of solid models: the smallest radius in pixels where the
// baseline's picture stays within Luv 3 and IoU 0.95 of the walk on the test models (docs/RESULTS.md,
// "View atlas crowd: the level-of-detail ladder"). Not the default: on the bunny at 8x the base
// distance it costs Luv 1.3 -> 4.7, and on foliage IoU 0.95 -> 0.91 ("early rejection" section); on
// the bunny at 256 x 256 px (radius about 100, perspective) its silhouette is IoU 0.83-0.96 against
// the mesh's whatever its parallax steps, and it writes its hull's depth, not the surface's: at 128
// it fails the representation contract ("Parallax steps").
constexpr float k_solid_baseline_below = 48.0f;
// Parallax steps of the ladder's baseline level (--parallax-steps 0): 3 keep it nearer the walk (the
// torus at 48-128 px: Luv 2.4-3.2 -> 1.7-2.3 against it); the baseline style keeps the impostor
// bakers' one.
constexpr int k_level_parallax_steps = 3;

// Bytes one GPU texture array may hold (llvmpipe refuses textures over 1 GiB).
constexpr std::uint64_t k_texture_budget_bytes = 960ull << 20;

struct BakeSettings {
    std::string layout = "icosahedral"; // "icosahedral", "octahedral", "hemi-octahedral"
    int subdivisions = 2;               // icosahedral: 20 * 4^k views (320: docs/RESULTS.md "Defaults")
    int frames = 16;                    // (hemi-)octahedral: frames x frames views
    std::string projection = "ortho";   // "ortho" or "perspective" (camera at the base distance)
    float fov = 40.0f;                  // perspective capture, vertical = horizontal, degrees
    int resolution = 256;               // capture image size, pixels (square)
    std::string maps = "surface";       // "lit": shaded colour (the seed); "surface": albedo + normal/depth
    int page_size = 2048;               // atlas page size, texels (multiple of k_cell)
    // Pages in the package (package.cpp): "none" PNG; "bc" (format version 4) BC5 octahedral
    // normals and exact R8 depth in KTX2 files, colour PNG; "bc-color" as bc, colour as the DXT5
    // blocks --texture-format bc3 uploads (color_page_blocks), mip levels included.
    std::string compression = "bc";
    // Depth precision over the bounding sphere's diameter, 8..16 bits (issues #14, #17); 0 until the
    // bake chooses it (depth_bits_for). At 8 (packages from before it) a step is 2r/255, two texels
    // of a 512 px capture: surfaces closer than that merge into one and oblique rays meet the steps'
    // treads and risers a texel from where the surface is, so the three blended views disagree.
    int depth_bits = 0;
};

class ViewAtlasPackage final : public Package {
public:
    std::string representation() const override { return "view-atlas"; }

    // Half the side of the captured square on the plane through the centre: r for orthographic
    // captures, r / cos(fov/2) for perspective ones at the base distance r / sin(fov/2).
    float half_extent() const;
    // Distance of the perspective capture camera from the centre (the base distance).
    float capture_distance() const;
    bool has_surface() const { return settings.maps == "surface"; }
    bool has_pbr() const { return !orm_pages.empty(); }
    bool has_fine_depth() const { return has_surface() && settings.depth_bits > 8; }

    Options parameters;    // as baked
    BakeSettings settings; // settings_from(parameters)
    // The source has alpha-tested materials (issue #14); the renderer's --color-level auto read such
    // packages' colour from level 0 at every distance, and now reads every package's so (renderer.cpp).
    // Written to the manifest only when true, so other models' packages do not change; packages from
    // before it read false.
    bool alpha_tested = false;
    glm::vec3 center{0.0f}; // bounding sphere of the source (centre of the box, half its diagonal)
    float radius = 1.0f;
    // The renderer's proxy (hull.h proxy_planes, issue #17): half-spaces {p : dot(xyz, p) <= w},
    // object space, unit normals, that each hold every point of the source; the proxy is the source
    // box cut by them. Empty in packages from before it (the renderer draws the prism).
    std::vector<glm::vec4> proxy_planes;
    std::vector<View> views;
    // RGB: lit colour ("lit") or albedo ("surface"), sRGB-encoded; A: coverage 0 / 255, or for
    // models with alpha-tested materials the covered fraction of the texel (1..255 where covered).
    std::vector<ImageRGBA8> color_pages;
    // "surface" only. RGB: world normal * 0.5 + 0.5; A: depth (r - dot(p - centre, direction)) /
    // (2r) in [0, 1], 0 nearest to the capture camera, in 8 bits.
    std::vector<ImageRGBA8> normal_depth_pages;
    // "surface" with depth_bits over 8 only, else empty: per page, row-major, the same depth in
    // depth_bits bits as a 16-bit code (depth_code; 0 where not covered). normal_depth_pages' A is it
    // rounded to 8 bits, which what needs no more (the hull, the detail rule, the web export) keeps
    // reading; the renderer's walk reads these.
    std::vector<std::vector<std::uint16_t>> depth_pages;
    // "surface" packages of models with PBR materials only (issue #14), else empty: per page, as
    // reps::write_pbr_texel packs them, occlusion, perceptual roughness, metallic (linear) and
    // coverage; and the emission, sRGB-encoded and clamped to [0, 1], and coverage. Without them
    // the renderer shades with Material's defaults (1, 1, 0; black).
    std::vector<ImageRGBA8> orm_pages, emission_pages;
    // As read from a compressed package (empty otherwise, or per page when made by the bake): the
    // BC5 blocks of each page's octahedral normals, written back as they are (re-fitting decoded
    // normals would drift), and each page's DXT5 colour levels (color_page_blocks), which the
    // renderer uploads as they are under --texture-format bc3. The pages above hold them decoded.
    std::vector<std::vector<std::uint8_t>> normal_bc5;
    std::vector<std::vector<std::vector<std::uint8_t>>> color_bc3;
};

// Pages as the GPU filters them (pages.cpp): premultiplied by coverage (colour pages by their own
// alpha, keep_alpha; the other maps by the colour page's alpha, their own alpha too), so that
// filtering averages covered texels only; the next mip level of a premultiplied square (2x2 box,
// rounded, as glGenerateMipmap); and a colour page's DXT5 blocks, k_mip_levels levels of the
// premultiplied page, level 0 first. `any`: premultiplied by 255 wherever the coverage is not 0
// instead (the normal-depth pages' level 0: renderer.cpp, upload_pages, says why).
std::vector<std::uint8_t> premultiplied(const ImageRGBA8& page, const ImageRGBA8& coverage, bool keep_alpha,
                                        bool any = false);
// The normal-depth page of a package with depth over 8 bits as RGBA16 (normals x 257, A the depth
// code), premultiplied by the colour page's alpha like premultiplied(..., false, any).
std::vector<std::uint16_t> premultiplied16(const ImageRGBA8& normal_depth, const std::vector<std::uint16_t>& depth,
                                           const ImageRGBA8& coverage, bool any = false);
std::vector<std::uint8_t> half_level(const std::vector<std::uint8_t>& level, int size);
std::vector<std::vector<std::uint8_t>> color_page_blocks(const ImageRGBA8& page);

// Depth d in [0, 1] held in `bits` (9..16) bits as a 16-bit code: the `bits`-bit value in the
// high bits, the low ones 0 (what a 16-bit grey PNG compresses best; a reader refuses other codes).
// depth_code_max: the code of depth 1. depth8: a code rounded to the 8 bits of normal_depth_pages' A.
inline std::uint32_t depth_code_max(int bits) { return 65536u - (1u << (16 - bits)); }

// --depth-bits 0: the bits a capture of `resolution` px gets. 512 px and up (alpha-tested models,
// models with fine detail): 10, a step of half a 512 px texel (the assembly's thesis Luv 2.28 ->
// 2.11, the tree's at distance 1 5.52 -> 5.45, +25% package); under: 8, a step of one 256 px
// texel, where 10 bits bought the bunny 0.003 Luv for the same +25% (docs/RESULTS.md, "Depth bits").
inline int depth_bits_for(int resolution) { return resolution >= 512 ? 10 : 8; }
inline std::uint16_t depth_code(float d, int bits)
{
    const std::uint32_t levels = (1u << bits) - 1u;
    return std::uint16_t(std::uint32_t(std::lround(std::clamp(d, 0.0f, 1.0f) * float(levels))) << (16 - bits));
}
inline std::uint8_t depth8(std::uint16_t code, int bits)
{
    const std::uint32_t value = code >> (16 - bits), levels = (1u << bits) - 1u;
    return std::uint8_t((value * 255u + levels / 2u) / levels);
}

// The share of a package's covered view texels that end their surface (bake.cpp, k_detail_edge_fraction).
double depth_edge_fraction(const ViewAtlasPackage& package);

// The bake parameters typed (representation.cpp), and the checks between them.
BakeSettings settings_from(const Options& parameters);
Status check_settings(const BakeSettings& settings);

// The registry entry (representation.cpp): options, debug views and the functions below.
Representation registration();
Result<std::unique_ptr<Package>> bake(const BakeContext& context);
Status write(const Package& package, const std::string& directory);
Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest);
// The renderer uploads pages into texture arrays of at most GL_MAX_ARRAY_TEXTURE_LAYERS pages and
// k_texture_budget_bytes each (mip levels included; the environment variable
// STANDIN_ATLAS_TEXTURE_BYTES overrides the budget, e.g. to force several arrays on small packages
// in tests), at most ATLAS_MAX_ARRAYS arrays per map (shaders/atlas_layout.glsl). A package that
// needs more is refused with a status naming it and its sizes; so is one the GL cannot allocate.
Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings);
// `standin export` (export.cpp): the grid atlas, its impostor quad and the atlas hull (hull.h).
std::vector<OptionSpec> export_options();
Result<ExportScene> export_scene(const Package& package, const Options& options);

} // namespace standin::view_atlas
