// Microfacets in memory (Yamazaki et al. 2002, "Microfacet Billboarding"): the occupied voxels of
// the model as an octree of levels, and reference images of the model from many directions (colour,
// normal and 16-bit depth). At run time every drawn voxel is a square of side sqrt(3) W through its
// centre, facing the viewer, textured from the nearest captured views where their depth says the
// surface lies within W/2 of the square (eq. 1). Shared by the baker, the package codec and the
// renderer of this folder.
#pragma once

#include "reps/microfacets/voxels.h"
#include "reps/common/view_layout.h"

#include <standin/image.h>
#include <standin/package.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin::microfacets {

// Crops of the captured views sit on the view atlas's grid of cells (reps::k_cell), so the
// first k_mip_levels levels of a colour page never mix two views.
using reps::View;
constexpr int k_mip_levels = reps::k_mip_levels;

// Capture samples per texel side for models with alpha-tested materials (issue #14, capture.h).
// With f > 1 their coverage is stored as the covered fraction of each texel and the walk keeps a
// surface where the filtered fraction reaches 1/2 (the view atlas's rule). Measured on the foliage
// tree it did not pay here (docs/RESULTS.md "Fractional coverage in microfacets": thesis IoU 0.9446,
// Luv 7.62 at 2 x 2 against 0.9459, 6.74 binary), so the default stays 1: binary coverage, the
// packages of before. STANDIN_MICROFACETS_COVERAGE_SAMPLES (1..8) sets it for measurements/tests.
constexpr int k_coverage_samples = 1;

// Alpha-tested models without --resolution are captured with texels as fine as their leaf
// texture's, up to this (bake.cpp with_cutout_resolution; 2048 would not fit llvmpipe's texture
// arrays: 9 pages of 4096^2 for the generated tree).
constexpr int k_alpha_max_resolution = 1536;

// Bytes one texture array of pages may take (the normal-depth pages, 8 bytes a texel, are the
// largest): the renderer refuses packages over it (llvmpipe refuses 1 GiB), and the bake lowers a
// resolution it raised itself until the pages fit (bake.cpp fitting_resolution).
constexpr std::uint64_t k_texture_budget_bytes = 960ull << 20;
constexpr std::uint64_t k_page_texel_bytes = 8;
// How many pages of page_size^2 one texture array holds within that budget.
constexpr int budget_pages(int page_size)
{
    return int(k_texture_budget_bytes / (std::uint64_t(page_size) * std::uint64_t(page_size) * k_page_texel_bytes));
}

struct BakeSettings {
    int level = 7;                   // finest octree level: 2^level cells per side (7: 128^3)
    int min_level = 2;               // coarsest level kept (2: 4^3), what distant instances draw
    std::string layout = "icosahedral"; // the view atlas's sphere layouts, or "circle" (the seed's turntable)
    int subdivisions = 1;            // icosahedral: 20 * 4^k views (80: docs/RESULTS.md "Microfacets")
    int frames = 36;                 // circle: views on the circle; (hemi-)octahedral: frames^2 views
    int resolution = 512;            // capture image side, pixels
    int depth_bits = 16;             // 16, or 8 (the seed's range images: "quantized as integer in [0, 255]")
    std::string geometry_from = "full"; // "full", or the incomplete-scan experiment: "simplified", "noisy"
    float geometry_amount = 0.1f;    // simplified: fraction of the triangles kept; noisy: amplitude / radius
    bool fill_holes = true;          // the seed's range-image median filter (only changes degraded geometry)
    int page_size = 2048;            // atlas page side, texels (multiple of reps::k_cell)
};

class MicrofacetsPackage final : public Package {
public:
    std::string representation() const override { return "microfacets"; }

    Options parameters;    // as baked
    BakeSettings settings; // settings_from(parameters)
    Octree octree;          // levels settings.min_level .. settings.level
    glm::vec3 center{0.0f}; // bounding sphere of the source (the capture frame)
    float radius = 1.0f;
    // The largest angle (radians) between any direction and its nearest captured view (in the
    // circle's plane for the circle layout): the delta of eq. 2 the LOD rule assumes.
    float max_view_angle = 0.1f;
    std::vector<View> views; // captured orthographically: half extent = radius (reps/common/view_layout.h, View)
    // RGB: albedo, sRGB-encoded (straight, not premultiplied); A: coverage 0 / 255, or for models
    // with alpha-tested materials the covered fraction of the texel (1..255 where covered).
    std::vector<ImageRGBA8> color_pages;
    // RGB: world normal * 0.5 + 0.5 (captured in 8 bits, x 257); A: depth (r - dot(p - centre,
    // direction)) / (2r) in [0, 1], 0 nearest the capture camera, in 16 bits (multiples of 257 when
    // depth_bits is 8): reps::SurfaceImage's encodings. All zero where the colour page's coverage
    // is 0 (a covered texel never has a zero normal); full values on partly covered texels.
    std::vector<ImageRGBA16> normal_depth_pages;
    // Models with PBR materials only (issue #14), else empty: per page, as reps::write_pbr_texel
    // packs them, occlusion, perceptual roughness, metallic (linear) and coverage; and the emission,
    // sRGB-encoded and clamped to [0, 1], and coverage. All zero where the colour's coverage is 0.
    // Without them the renderer shades with Material's defaults (1, 1, 0; black).
    std::vector<ImageRGBA8> orm_pages, emission_pages;
    bool has_pbr() const { return !orm_pages.empty(); }

};

// The capture directions of a layout: the view atlas's sphere layouts (reps::layout_directions)
// or "circle": `frames` directions on the horizontal circle, azimuth 360 k / frames from +Z.
std::vector<glm::vec3> capture_directions(const BakeSettings& settings);

// bake.cpp, step 1: the crops (width and height) the views along `directions` would take at
// `resolution`, from the model's vertices projected on each view: never smaller than the crop its
// capture covers. fitting_resolution: `resolution` lowered by sixteenths, not under
// `floor_resolution`, until those crops pack into the pages one texture array holds
// (k_texture_budget_bytes).
std::vector<View> estimated_crops(const Mesh& mesh, const BoundingSphere& sphere, const std::vector<glm::vec3>& directions,
                                  int resolution, int page_size);
int fitting_resolution(const Mesh& mesh, const BoundingSphere& sphere, const std::vector<glm::vec3>& directions,
                       int resolution, int floor_resolution, int page_size);

// The bake parameters typed (representation.cpp), and the checks between them.
BakeSettings settings_from(const Options& parameters);
Status check_settings(const BakeSettings& settings);

// The registry entry (representation.cpp): options, debug views and the functions below.
Representation registration();
Result<std::unique_ptr<Package>> bake(const BakeContext& context);
Status write(const Package& package, const std::string& directory);
Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest);
// Uploads a package (one texture array per map: a package that does not fit is refused naming its
// sizes); run-time options as declared in representation.cpp (renderer.h RenderConfig).
Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings);

} // namespace standin::microfacets
