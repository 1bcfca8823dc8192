// The control mesh of a displaced control mesh (Bauman, Livny & El-Sana, "GPU-Based
// Adaptive-Subdivision for View-Dependent Rendering", §3 and §4): the input simplified by quadric
// edge collapse under a per-vertex normal-cone constraint, so that every control face still sees
// one sheet of the original along its interpolated normals. control_mesh.cpp has the algorithm.
#pragma once

#include <standin/mesh.h>
#include <standin/status.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace standin::displaced_mesh {

// A cone of directions: every unit vector within `half_angle` radians of `axis`. An empty cone
// (nothing merged yet) has half_angle < 0.
struct NormalCone {
    glm::vec3 axis{0.0f, 0.0f, 1.0f};
    float half_angle = -1.0f;

    bool empty() const { return half_angle < 0.0f; }
    // Whether `direction` (unit) lies in the cone, within `slack` radians.
    bool contains(glm::vec3 direction, float slack = 1e-4f) const;
};

// The smallest cone holding both cones (exact for two cones on the sphere). A half-angle of pi/2 or
// more means the directions do not fit in an open half-sphere; the axis is then meaningless.
NormalCone merge_cones(const NormalCone& a, const NormalCone& b);
NormalCone merge_direction(const NormalCone& a, glm::vec3 unit_direction);

// What the simplifier shows an observer after every collapse it executes (tests check the cone
// invariant through it). Faces are control-mesh triangles as indices into the welded positions.
class CollapseView {
public:
    virtual ~CollapseView() = default;
    virtual std::uint32_t kept_vertex() const = 0;
    // The kept vertex and every vertex that shares a face with it: the vertices whose cone changed.
    virtual const std::vector<std::uint32_t>& affected_vertices() const = 0;
    virtual NormalCone cone(std::uint32_t vertex) const = 0;
    // Unit normals of the live faces around `vertex`.
    virtual std::vector<glm::vec3> face_normals_around(std::uint32_t vertex) const = 0;
};

struct ControlMeshOptions {
    std::size_t target_faces = 1000;  // stop at (or just under) this many faces
    float cone_angle_degrees = 90.0f;  // a collapse may not make any cone's half-angle reach this
    // Issue #14: faces of alpha-masked materials (leaf cards) keep their vertices, so every card
    // stays whole in the control mesh and its displacement samples lie on it; collapsing a card
    // to one triangle would cut away the half of its leaves no coverage can bring back.
    bool keep_cutout_faces = false;
    // A boundary loop (the outline of an open sheet, the rim of a tube, the hole of an annulus) keeps
    // at least this many vertices (or all it has, when fewer): collapses along a loop that has
    // reached it are refused. Displacement moves points along the normal only, so a sheet's
    // outline is the loop's polygon; 0 lets a loop shrink to a triangle (the old behaviour).
    std::size_t min_loop_vertices = 0;
    // Called after every executed collapse; for tests (slow). May be empty.
    std::function<void(const CollapseView&)> observer;
};

struct ControlMesh {
    std::vector<glm::vec3> positions;   // a subset of the input's (welded) positions
    std::vector<glm::vec3> normals;     // unit; area-weighted mean of the adjacent control faces
    std::vector<std::uint32_t> indices; // three per face, counter-clockwise as in the input
    std::vector<NormalCone> cones;      // per vertex: every input normal it has absorbed

    std::size_t input_faces = 0;        // after welding and dropping degenerate faces
    std::size_t target_faces = 0;
    bool reached_target = false;
    // Why simplification stopped: "target", or "no valid collapse" (the cone, flip or topology
    // constraints refused every remaining edge: the input's shape allows no coarser control mesh).
    std::string stopped_by;
    std::size_t collapses = 0;
    std::size_t refused_cone = 0, refused_flip = 0, refused_topology = 0;

    std::size_t face_count() const { return indices.size() / 3; }
};

// Simplifies `mesh` to about options.target_faces faces (half-edge collapses ordered by quadric
// error; the kept endpoint is the one of lower error, so control vertices lie on the input).
// Deterministic: one thread, ties broken by vertex index. Vertices are welded by exact position
// first (normal and UV seams do not split the control mesh). Faces on non-manifold edges keep
// their vertices. invalid_argument when target_faces is 0 or the cone angle lies outside (0, 180].
Result<ControlMesh> build_control_mesh(const Mesh& mesh, const ControlMeshOptions& options);

} // namespace standin::displaced_mesh
