// Per-facet view selection without a loop over every view (Yamazaki et al. 2002 §6.2 found that loop
// to be the renderer's bottleneck): a cube map of direction cells, each listing the only views that
// can be among the k nearest for a direction inside it. The seed's cone of candidates (§6.2), made
// once per cell at load time instead of once per frame. shaders/select.comp reads the table
// (lookup_cell, the candidate loop); select_views is its CPU reference.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace standin::microfacets {

constexpr int k_lookup_side = 32;      // cells per cube face side (shaders/microfacets_layout.glsl)
constexpr int k_lookup_rank = 5;       // the table is exact for the 5 nearest views: a blend of 4 and
                                       // the fifth, whose cosine is the blend weights' floor
constexpr int k_max_blend = 4;

// The cell of a unit direction: face (0..5: +x, -x, +y, -y, +z, -z) * side^2 + row * side + column.
int lookup_cell(glm::vec3 direction);

struct ViewLookup {
    // per cell: first candidate (bits 8..31) and count (bits 0..7)
    std::vector<std::uint32_t> cells;
    std::vector<std::uint32_t> candidates; // view indices, ascending within a cell
};

// For each cell with centre c and angular radius a (its farthest corner), the views within
// theta_5(c) + 2a of c, theta_5(c) being the angle of c's fifth-nearest view: a direction e in the
// cell is within a of c, so its 5 nearest views are within theta_5(c) + a of e and within
// theta_5(c) + 2a of c. Exact, not a heuristic. At most 255 candidates per cell (the nearest ones
// are kept if a layout ever needs more).
ViewLookup build_view_lookup(const std::vector<glm::vec3>& directions);

// The views blended for a facet seen along `e` (unit, from the facet towards the eye): the `count`
// (1..4) nearest views by cosine (ties by lower index) and weights cos_i - cos_(count+1), normalised
// (Yamazaki et al. 2002 §3.3.2: weights "should change continuously between 0 and 1"; a view enters
// and leaves the blend at weight 0). count 1 is the seed's nearest view, weight 1. Weights of
// missing views are 0; when every weight is 0 the nearest view gets 1.
struct ViewBlend {
    int ids[k_max_blend] = {0, 0, 0, 0};
    float weights[k_max_blend] = {1.0f, 0.0f, 0.0f, 0.0f};
};
ViewBlend select_views(const std::vector<glm::vec3>& directions, const ViewLookup& lookup, glm::vec3 e, int count);

} // namespace standin::microfacets
