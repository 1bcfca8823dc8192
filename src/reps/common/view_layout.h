// Where an image-based stand-in looks from, and how its cropped captures share atlas pages: the
// view atlas's views and the microfacets' captures are both laid out and packed here.
#pragma once

#include <glm/vec3.hpp>

#include <string>
#include <vector>

namespace standin::reps {

// Crops are placed on a grid of k_cell x k_cell texels and padded to whole cells, so that the first
// k_mip_levels - 1 mip levels of a page never mix two views (the renderers clamp the level there).
constexpr int k_cell = 16;
constexpr int k_mip_levels = 5; // 1, 2, 4, 8, 16 texels

// One captured view. Capture pixel (x, y) (y down, continuous, 0..resolution) lies on the plane
// through the sphere centre perpendicular to `direction` at
//   centre + (-h + x * 2h / resolution) * axis_u + (-h + y * 2h / resolution) * axis_v,
// h the package's half extent. The crop [crop_x, crop_x + width) x [crop_y, crop_y + height)
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

// The capture directions of a layout (deterministic order).
// icosahedral: centres of the faces of an icosahedron subdivided `subdivisions` times, rotated so
// that one face centre is +Y (the protocols' top view is then a captured view);
// octahedral: centres of a frames x frames grid over the octahedral map of the sphere;
// hemi-octahedral: the same over the upper hemisphere (+Y).
std::vector<glm::vec3> layout_directions(const std::string& layout, int subdivisions, int frames);

// The (hemi-)octahedral grids as impostor shaders address them (docs/FORMAT.md, "Grid atlas").
// Frame (i, j), column i and row j of a frames x frames grid, is view j * frames + i of
// layout_directions; its centre has octahedral coordinates e = ((i + 0.5, j + 0.5) / frames) * 2 - 1.
// octahedral_direction (view_layout.cpp) and grid_encode map e in [-1, 1]^2 to a unit direction and back (+Y up; e.y runs
// along +Z); hemi-octahedral ones cover the upper hemisphere (directions below it encode as their
// projection onto the horizon).
glm::vec3 grid_decode(const std::string& layout, float ex, float ey);
void grid_encode(const std::string& layout, glm::vec3 direction, float& ex, float& ey);
// The frame whose cell holds `direction`'s coordinates (column i, row j).
void grid_frame(const std::string& layout, int frames, glm::vec3 direction, int& i, int& j);

// Shelf packing of crops (sizes multiples of k_cell) into pages of page_size: sets page,
// atlas_x, atlas_y of every view and returns the number of pages. Deterministic: tallest first,
// ties by index.
int pack_views(std::vector<View>& views, int page_size);

} // namespace standin::reps
