// View atlas in memory (Saraiva et al. §3): the model rendered from
// many directions around its bounding sphere, each image cropped to its content and packed into
// atlas pages. At run time a camera-facing quad through the sphere's centre shows the nearest view
// (style "seed"), or the views around the viewing direction are blended and, with stored depth,
// intersected per pixel (styles "octahedral-baseline" and "corrected", renderer.cpp). Shared by the
// baker, the package codec and the renderer of this folder.
#pragma once

#include <standin/image.h>
#include <standin/package.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin::view_atlas {

// Crops are placed on a grid of k_cell x k_cell texels and padded to whole cells, so that the first
// k_mip_levels - 1 mip levels of a page never mix two views (renderer.cpp clamps the level there).
constexpr int k_cell = 16;
constexpr int k_mip_levels = 5; // 1, 2, 4, 8, 16 texels
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
};

// One captured view. Capture pixel (x, y) (y down, continuous, 0..resolution) lies on the plane
// through the sphere centre perpendicular to `direction` at
//   centre + (-h + x * 2h / resolution) * axis_u + (-h + y * 2h / resolution) * axis_v,
// h = ViewAtlasPackage::half_extent(). The crop [crop_x, crop_x + width) x [crop_y, crop_y + height)
// of the capture is stored at [atlas_x, atlas_x + width) x [atlas_y, atlas_y + height) of page
// `page` (atlas row atlas_y + r holds capture row crop_y + r). Width and height are multiples of
// k_cell, or 0 when the view saw nothing.
struct View {
    glm::vec3 direction{0, 0, 1}; // unit, from the centre towards the capture camera
    glm::vec3 axis_u{1, 0, 0};    // unit, image columns (camera right)
    glm::vec3 axis_v{0, -1, 0};   // unit, image rows (camera down)
    int crop_x = 0, crop_y = 0, width = 0, height = 0;
    int page = 0, atlas_x = 0, atlas_y = 0;
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

    Options parameters;    // as baked
    BakeSettings settings; // settings_from(parameters)
    glm::vec3 center{0.0f}; // bounding sphere of the source (centre of the box, half its diagonal)
    float radius = 1.0f;
    std::vector<View> views;
    // RGB: lit colour ("lit") or albedo ("surface"), sRGB-encoded; A: coverage 0 / 255.
    std::vector<ImageRGBA8> color_pages;
    // "surface" only. RGB: world normal * 0.5 + 0.5; A: depth (r - dot(p - centre, direction)) /
    // (2r) in [0, 1], 0 nearest to the capture camera.
    std::vector<ImageRGBA8> normal_depth_pages;
};

// The capture directions of a layout (deterministic order).
// icosahedral: centres of the faces of an icosahedron subdivided `subdivisions` times, rotated so
// that one face centre is +Y (the protocols' top view is then a captured view);
// octahedral: centres of a frames x frames grid over the octahedral map of the sphere;
// hemi-octahedral: the same over the upper hemisphere (+Y).
std::vector<glm::vec3> layout_directions(const std::string& layout, int subdivisions, int frames);

// Shelf packing of crops (sizes multiples of k_cell) into pages of page_size: sets page,
// atlas_x, atlas_y of every view and returns the number of pages. Deterministic: tallest first,
// ties by index.
int pack_views(std::vector<View>& views, int page_size);

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

} // namespace standin::view_atlas
