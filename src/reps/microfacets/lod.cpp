// Level of detail and the cone of view candidates.
// Yamazaki et al. 2002 §4.1 (eq. 2: e = l tan(delta), keep e under a pixel), §5.4 (facet size chosen
// "by considering the size of the screen"; the paper gives no rule) and §6.2 (the cone of candidate
// views, Table 1 row c; no formula given).
// Steps of the per-node rule (LodRule in lod.h):
//  1. pixels per world unit from the camera's projection (screen_scale);
//  2. per node: the nearest point of its bounding sphere (radius sqrt(3)/2 W, the facet's own
//     half diagonal), its eq. 2 error there with l = W (billboarded facets are at most W apart,
//     §4.2 eq. 3) and delta the layout's worst nearest-view angle;
//  3. draw the node when it is fine enough and its parent is not (a cut, see lod.h).
#include "reps/microfacets/lod.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <functional>
#include <numbers>

namespace standin::microfacets {

namespace {

constexpr float k_half_diagonal = 0.8660254f; // sqrt(3) / 2: a node's bounding sphere per unit of W

// distance from the eye to the nearest point of a sphere, kept positive (an eye inside is close)
float distance_to_sphere(float center_distance, float radius, float floor_distance)
{
    return std::max(center_distance - radius, floor_distance);
}

} // namespace

ScreenScale screen_scale(const Camera& camera, int viewport_height)
{
    ScreenScale scale;
    scale.orthographic = camera.orthographic;
    // clip_from_view[1][1] is 1 / tan(fov/2) (perspective) or 1 / half height (orthographic): NDC
    // units per view unit (at distance 1), and a viewport spans 2 NDC units
    scale.pixels = camera.clip_from_view[1][1] * 0.5f * float(viewport_height);
    return scale;
}

float node_error_pixels(const LodRule& rule, const ScreenScale& scale, float voxel_world, float distance)
{
    return parallax_error(voxel_world, rule.tan_delta) * scale.at(distance);
}

int finest_level(const LodRule& rule, const ScreenScale& scale, float grid_world, float sphere_distance,
                 float sphere_radius)
{
    if (rule.forced_level >= 0) return rule.forced_level;
    float nearest = distance_to_sphere(sphere_distance, sphere_radius, 1e-6f * grid_world);
    for (int level = rule.min_level; level < rule.max_level; ++level)
        if (node_error_pixels(rule, scale, grid_world / float(1u << level), nearest) <= rule.max_error_pixels) return level;
    return rule.max_level;
}

std::vector<NodeRef> select_cut(const Octree& tree, const LodRule& rule, const ScreenScale& scale,
                                glm::vec3 eye_object, float world_per_object, int finest)
{
    std::vector<NodeRef> cut;
    const int first = rule.forced_level >= 0 ? rule.forced_level : rule.min_level;
    const float floor_distance = 1e-6f * tree.grid.size * world_per_object;
    // the error of a node at `level` whose centre is `center` (object space)
    auto error = [&](glm::vec3 center, int level) {
        float w = tree.grid.voxel_size(level) * world_per_object;
        float d = distance_to_sphere(glm::length(eye_object - center) * world_per_object, k_half_diagonal * w, floor_distance);
        return node_error_pixels(rule, scale, w, d);
    };
    for (int level = first; level <= finest; ++level) {
        for (std::uint32_t code : tree.at(level)) {
            if (rule.forced_level < 0) {
                bool fine = level == finest || error(tree.grid.center(code, level), level) <= rule.max_error_pixels;
                bool parent_fine = level > first && error(tree.grid.center(code >> 3, level - 1), level - 1) <= rule.max_error_pixels;
                if (!fine || parent_fine) continue;
            }
            cut.push_back({level, code});
        }
    }
    return cut;
}

float max_view_angle(const std::vector<glm::vec3>& directions, bool circle, int rank)
{
    assert(!directions.empty() && rank >= 1);
    rank = std::min(rank, int(directions.size()));
    if (circle) return std::min(float(rank) * std::numbers::pi_v<float> / float(directions.size()), std::numbers::pi_v<float>);
    // the farthest any direction lies from its rank-th nearest view, over a cube map of directions
    constexpr int k_side = 48;
    float worst_cosine = 1.0f;
    std::vector<float> cosines(directions.size());
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f})
            for (int j = 0; j < k_side; ++j)
                for (int i = 0; i < k_side; ++i) {
                    glm::vec3 d;
                    d[axis] = sign;
                    d[(axis + 1) % 3] = (float(i) + 0.5f) / k_side * 2.0f - 1.0f;
                    d[(axis + 2) % 3] = (float(j) + 0.5f) / k_side * 2.0f - 1.0f;
                    d = glm::normalize(d);
                    for (std::size_t k = 0; k < directions.size(); ++k) cosines[k] = glm::dot(directions[k], d);
                    std::nth_element(cosines.begin(), cosines.begin() + (rank - 1), cosines.end(), std::greater<float>());
                    worst_cosine = std::min(worst_cosine, cosines[std::size_t(rank - 1)]);
                }
    return std::acos(std::clamp(worst_cosine, -1.0f, 1.0f));
}

std::vector<std::uint32_t> cone_candidates(const std::vector<glm::vec3>& directions, glm::vec3 eye,
                                           glm::vec3 center, float radius, float slack)
{
    std::vector<std::uint32_t> candidates;
    glm::vec3 to_eye = eye - center;
    float distance = glm::length(to_eye);
    bool inside = distance <= radius;
    // a facet at p in the sphere is seen along normalize(eye - p), which lies within asin(r / d)
    // of the axis; its nearest view lies within `slack` of that
    float half_angle = inside ? std::numbers::pi_v<float> : std::asin(radius / distance) + slack;
    float min_cosine = half_angle >= std::numbers::pi_v<float> ? -2.0f : std::cos(half_angle);
    glm::vec3 axis = inside ? glm::vec3(0, 0, 1) : to_eye / distance;
    for (std::size_t k = 0; k < directions.size(); ++k)
        if (glm::dot(directions[k], axis) >= min_cosine) candidates.push_back(std::uint32_t(k));
    return candidates;
}

} // namespace standin::microfacets
