// The atlas hull (issue #16): a view-independent convex proxy of a view atlas, the intersection of
// the half-spaces its views bound the model by, on which an engine draws the grid impostor instead
// of a camera-facing quad (docs/FORMAT.md, "role: grid-impostor-hull"). hull.cpp says how.
#pragma once

#include "reps/view_atlas/view_atlas.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace standin::view_atlas {

// The closed half-space {p : dot(normal, p) <= offset}; normal unit.
struct HalfSpace {
    glm::dvec3 normal{0.0, 0.0, 1.0};
    double offset = 0.0;
};

// A convex polytope as its faces: each a convex polygon of indices into `vertices`,
// counter-clockwise seen from outside, with its outward unit normal. Vertices are shared between
// the faces that meet at them (welded).
struct ConvexPolytope {
    std::vector<glm::dvec3> vertices;
    std::vector<std::vector<std::uint32_t>> faces;
    std::vector<glm::dvec3> face_normals;

    bool empty() const { return faces.empty(); }
    // true when p lies inside every face's plane or at most `tolerance` outside it
    bool contains(glm::dvec3 p, double tolerance) const;
    double volume() const;                 // divergence theorem over the faces
    // the sum of the faces' areas; for a convex body, 4x its orthographic screen area averaged over
    // all directions (Cauchy's surface area formula)
    double surface_area() const;
    std::size_t triangle_count() const;    // of a fan triangulation: sum of (corners - 2)
    // the area of its orthographic projection along `direction` (unit): half the sum over the faces
    // of area x |normal . direction| (convex: every covered point is covered twice)
    double projected_area(glm::dvec3 direction) const;
};

// The box [min, max] (max > min on every axis) as six quads.
ConvexPolytope box_polytope(glm::dvec3 min, glm::dvec3 max);

struct ClipStats {
    int planes = 0;  // half-spaces given
    int cut = 0;     // that cut the polytope
    int skipped = 0; // that cut nothing, or less deep than min_cut
    int refused = 0; // that would have left nothing (inconsistent with the others): ignored
};

// The intersection of `polytope` with the half-spaces, clipped one after the other in the order
// given (deterministic). A half-space that would cut no vertex deeper than `min_cut` (object units,
// >= 0) is skipped, so the result always contains the exact intersection (never cuts into it);
// one that would leave nothing is ignored. Classification, welding and dropping of faces left
// without area use a tolerance relative to the polytope's size, so near-coincident planes give no
// slivers or duplicate vertices.
ConvexPolytope clip_polytope(const ConvexPolytope& polytope, const std::vector<HalfSpace>& half_spaces, double min_cut,
                             ClipStats* stats = nullptr);

// The half-spaces a view atlas bounds its model by: per captured view, 4 from the covered texels'
// rectangle (along axis_u and axis_v: slabs for ortho captures, planes through the capture camera
// for perspective ones) and, for "surface" packages, 1 from the nearest depth of its covered
// texels (along direction). Each stands 2 capture texels outside the outermost covered texel's
// centre (the depth plane 2 texels and half a depth code in front of the nearest depth): a smooth
// surface that covers no texel centre sticks out by less than one, a thin tip (the bunny's ears)
// by up to 1.6; only a sliver thinner than a texel and longer than that can stick out further.
std::vector<HalfSpace> atlas_half_spaces(const ViewAtlasPackage& package);

// The capture texel on the plane through the centre, object units (2 half_extent / resolution).
double capture_texel(const ViewAtlasPackage& package);

// The source's bounding box grown by half a capture texel: what the atlas hull and the proxy cut.
ConvexPolytope source_box(const ViewAtlasPackage& package);

// The atlas hull: the source's bounding box grown by half a capture texel, clipped by
// atlas_half_spaces, cuts shallower than a quarter texel skipped.
ConvexPolytope atlas_hull(const ViewAtlasPackage& package, ClipStats* stats = nullptr);

// The renderer's proxy (issue #17, crowds and single instances): fewer fragments than the nearest
// view's crop prism, from a few planes that bound the model. The atlas hull above is no such bound
// for a sheet thinner than a texel seen edge on (it covers no texel there, and the hull cuts it off),
// so the proxy is built from the model's own points at bake time and stored in the package.

// Of `candidates` (half-spaces that each hold the model), at most `max_planes`, chosen greedily:
// starting from `enclosing`, each step takes the one whose cut leaves the least surface area (so
// the least screen area on average, Cauchy: the fragments a proxy starts), until none takes off
// more than `min_gain` of the area left. Returned in the order taken; deterministic (ties: the
// first candidate).
std::vector<HalfSpace> fewest_planes(const std::vector<HalfSpace>& candidates, const ConvexPolytope& enclosing,
                                     int max_planes, double min_gain);

// The supporting half-spaces of `points` along each of `directions` and its opposite ({p : dot(d, p)
// <= max over the points of dot(d, point) + margin}), reduced by fewest_planes from `box`.
constexpr int k_proxy_planes = 24;
std::vector<HalfSpace> proxy_planes(const std::vector<glm::vec3>& points, const std::vector<glm::vec3>& directions,
                                    const ConvexPolytope& box, double margin, int max_planes = k_proxy_planes);

// The package's proxy: its source's bounding box, grown by half a capture texel, clipped by its
// proxy_planes moved out by `margin` (object units); empty when the package has none (packages
// from before issue #17's proxy).
ConvexPolytope proxy_polytope(const ViewAtlasPackage& package, double margin = 0.0);

} // namespace standin::view_atlas
