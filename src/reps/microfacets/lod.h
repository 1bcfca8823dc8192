// Level of detail for microfacets: the screen-space error of a facet (Yamazaki et al. 2002 eq. 2),
// the per-node octree cut that keeps it under a bound, and the seed's "cone" of view candidates
// (§6.2). The renderer's compute shader (shaders/select.comp) evaluates the same rules per node on
// the GPU; these CPU versions are its reference and are tested against it.
#pragma once

#include "reps/microfacets/voxels.h"

#include <standin/camera.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace standin::microfacets {

// Eq. 2: two facets `interval` apart along a ray of a captured view, seen at an angle `delta` from
// that view, show the view's texel at two places `interval * tan(delta)` apart.
inline float parallax_error(float interval, float tan_delta) { return interval * tan_delta; }

// How many pixels one world unit covers: perspective at a distance, orthographic anywhere.
struct ScreenScale {
    bool orthographic = false;
    float pixels = 1.0f; // perspective: pixels per world unit at distance 1; orthographic: per world unit
    float at(float distance) const { return orthographic ? pixels : pixels / distance; }
};
ScreenScale screen_scale(const Camera& camera, int viewport_height);

// The LOD rule. A node of voxel size W (object units) at level k is fine enough when its facets'
// eq. 2 error on screen, W * scale * tan(delta) * pixels at the distance of the nearest point of
// the node's bounding sphere, is at most max_error_pixels. The sphere of a node holds its
// children's spheres, so the error only falls from a node to its children and "fine enough, and
// the parent is not" picks exactly one node on every path from min_level to max_level: a cut that
// draws every surface voxel once (Yamazaki et al. 2002 §7 names adaptive approximation as future
// work; this is it with eq. 2 as the criterion).
struct LodRule {
    float max_error_pixels = 1.0f;
    float tan_delta = 0.1f;  // tan of the largest angle between a view and its nearest capture
    int min_level = 0, max_level = 0;
    int forced_level = -1;   // >= 0: draw exactly this level (the seed's fixed levels, Table 1)
};

// The error in pixels of a node of world size `voxel_world` whose bounding sphere's nearest point
// is `distance` from the eye (perspective; ignored for orthographic).
float node_error_pixels(const LodRule& rule, const ScreenScale& scale, float voxel_world, float distance);

// The finest level an instance can need: the rule at the nearest point of its bounding sphere
// (world radius and distance of its centre from the eye), clamped to [min_level, max_level].
// A node deeper than this is never drawn, so the facets of one instance are at most the count of
// this level: the renderer sizes its buffers by it.
int finest_level(const LodRule& rule, const ScreenScale& scale, float grid_world, float sphere_distance,
                 float sphere_radius);

struct NodeRef {
    int level = 0;
    std::uint32_t code = 0;
};

// The cut through the octree for one instance (CPU reference of shaders/select.comp, without
// frustum culling): nodes of levels min_level..finest drawn where the node is fine enough (or at
// the finest level) and its parent is not (or it is at min_level). `eye_object` is the eye in
// object space, `world_per_object` the instance's scale.
std::vector<NodeRef> select_cut(const Octree& tree, const LodRule& rule, const ScreenScale& scale,
                                glm::vec3 eye_object, float world_per_object, int finest);

// The largest angle, radians, between a direction and its rank-th nearest capture direction (rank
// 1: the nearest): over the sphere for sphere layouts (estimated on a 6 x 48^2 cube map of
// directions), over the plane of the circle (rank * pi / N) for the turntable layout.
float max_view_angle(const std::vector<glm::vec3>& directions, bool circle, int rank = 1);

// The seed's accelerated selection (Yamazaki et al. 2002 §6.2, Table 1 row c): "a cone which
// includes all possible directions from the viewpoint to microfacets", here with its apex at the
// eye around the bounding sphere; views outside the cone widened by `slack` (max_view_angle at the rank of
// the last view a blend reads) cannot be nearest to any facet and are not candidates. Ascending indices;
// every view when the eye is inside the sphere. Directions point from the model to the camera.
std::vector<std::uint32_t> cone_candidates(const std::vector<glm::vec3>& directions, glm::vec3 eye,
                                           glm::vec3 center, float radius, float slack);

} // namespace standin::microfacets
