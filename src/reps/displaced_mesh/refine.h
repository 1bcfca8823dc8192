// View-dependent refinement of a displaced control mesh (Bauman, Livny & El-Sana §3.3, §3.4): the
// per-face data the refinement reads, the split rule, and a CPU reference of what the GPU does
// every frame (shaders/refine.comp and friends mirror refine.cpp line for line). Tests compare the
// two and count T-junctions on the CPU side.
#pragma once

#include "reps/displaced_mesh/pattern.h"
#include "reps/displaced_mesh/topology.h"

#include <standin/camera.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin::displaced_mesh {

// What decides a split (§3.3 and the design note's A12/A13):
// weighted: a triangle splits when one of its edges has |e_p| * w_e > tau; it bisects the longest
//           such edge (by projected length). A segment is split only when its own test passes, and
//           then by every triangle that has it, so the result is conforming (no T-junctions).
// length:   the same with w = 1 (the paper's first rule: pure screen-space longest-edge bisection).
// seed:     the paper's literal weighted rule: split when |L_p| * w_L > tau for the longest
//           projected edge L. Not conforming (kept to count its T-junctions).
// error:    beyond the paper: the weight is the segment's estimated chord error over its length,
//           kappa * L / 6 (kappa: the largest curvature of the displaced surface on the edge's
//           faces, L: the segment's length), so |e_p| * w is the segment's geometric error in
//           pixels and tau bounds the error itself, not the edge length. Conforming like weighted;
//           it bisects the longest passing edge in the pattern's own units (refine.cpp step 2).
enum class Criterion { weighted, length, seed, error };
bool parse_criterion(const std::string& name, Criterion& out);

// Per control face, computed once at load time (prepare_faces).
struct FaceRefineData {
    float edge_weight[3] = {1, 1, 1}; // w of the face's edge k (corner k -> k + 1): one value per control edge
    float interior_weight = 1.0f;     // w of segments inside the face
    float h_min = 0.0f, h_max = 0.0f; // elevation range over every level
    float cone_half_angle = 4.0f;     // radians; displaced normals lie within it around the face normal
    float normal_shrink = 0.0f;       // 1 - min |N(w)|: how far a displaced point may leave the prism
    float grid_length = 0.0f;         // mean edge length / (k - 1): the finest spacing inside the face
    float edge_curvature[3] = {0, 0, 0}; // 1 / world units: the largest of the edge's faces' curvature
    float interior_curvature = 0.0f;     // the largest second difference of the displaced finest grid
};

// The package data the refinement reads (non-owning).
struct RefineSurface {
    const std::vector<glm::vec3>* positions = nullptr; // control vertices (object space; animated ones too)
    const std::vector<glm::vec3>* normals = nullptr;
    const std::vector<std::uint32_t>* indices = nullptr;
    const ControlTopology* topology = nullptr;
    const std::vector<float>* elevations = nullptr; // every level of every face, decoded
    const std::vector<FaceRefineData>* faces = nullptr;
    int degree = 17;
};

// The per-face data: weights (∆e = max(h_a, h_b) + max(∆_a, ∆_b) on each control edge, h + ∆ inside
// a face, normalised by their length-weighted mean over the edges and clamped to [1/4, 4], so tau
// keeps its meaning in pixels on average), elevation ranges, normal cones and grid spacing.
// `face_error` is ∆_f per face; `see_through` (per face, or empty) marks faces with cut-outs, whose
// parts keep their back faces (an eye sees into them). `kept_whole` (per face, or empty) marks faces
// the weighted criteria never split (the export's flat leaf cards): zero weight inside them and on
// edges all of whose faces are marked (an edge touching another face keeps its weight, so the
// segment test stays a function of the segment: crack-free), and left out of the mean, which
// thousands of flat cards would pull towards 0 and so push every other edge to the weight cap.
std::vector<FaceRefineData> prepare_faces(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                                          const std::vector<std::uint32_t>& indices, const ControlTopology& topology,
                                          const PatternLayout& layout, const std::vector<float>& elevations,
                                          const std::vector<float>& face_error, const std::vector<std::uint8_t>& see_through = {},
                                          const std::vector<std::uint8_t>& kept_whole = {});

struct RefineOptions {
    float tau = 1.0f;            // screen-space tolerance, pixels
    Criterion criterion = Criterion::error;
    bool cull = true;            // frustum and back-face culling of control faces on their prism
    bool mip = true;             // elevations from the level whose spacing projects to about tau
    float outline = 2.0f;        // error criterion: how much more error counts near the silhouette
    int max_depth = 0;           // bisection passes; 0: 3m + 6 (refinement_passes)
};
int refinement_passes(int degree, int max_depth);

// The camera as the refinement sees one instance: view space of the camera, object space of the
// instance (a similarity transform).
struct RefineView {
    glm::mat4 view_from_object{1.0f};
    glm::mat4 clip_from_view{1.0f};
    bool orthographic = false;
    float pixels_per_unit = 1.0f; // f_px: height / (2 tan(fov/2)), or height / (2 half_height)
    float near_plane = 0.1f;
};
RefineView make_refine_view(const Camera& camera, int viewport_height, const glm::mat4& world_from_object);

// One triangle of the refinement: a control face and three corners as fixed-point barycentric
// weights (q1, q2) of the face's corners 1 and 2 (face_point.h), counter-clockwise as the face.
struct RefinedTriangle {
    std::uint32_t face = 0;
    std::uint32_t q[3][2] = {};
    std::uint32_t depth = 0;
};

struct RefineStats {
    std::uint64_t faces_visible = 0;  // control faces that passed culling
    std::uint64_t processed = 0;      // triangles tested over all passes (the paper's "Proc.")
    std::uint64_t rendered = 0;       // final triangles
    std::uint64_t capped = 0;         // triangles that wanted to split in the last pass
};

// Whether face f (its prism: corners displaced by h_min and h_max) may be visible.
bool face_visible(const RefineSurface& surface, std::uint32_t face, const RefineView& view);

// The whole refinement of one instance, in the GPU's order (pass by pass; within a pass, records in
// order, each record's children or itself in place).
std::vector<RefinedTriangle> refine(const RefineSurface& surface, const RefineView& view, const RefineOptions& options,
                                    RefineStats& stats);

// The displaced object-space position of a refined vertex, as the vertex stage computes it.
glm::vec3 displaced_position(const RefineSurface& surface, std::uint32_t face, std::uint32_t q1, std::uint32_t q2,
                             const RefineView& view, const RefineOptions& options);

// The elevation of a point of a face at (fractional) level `level`, interpolated inside the level's
// grid; points on an edge read only that edge's samples, in its canonical direction.
float elevation_at(const RefineSurface& surface, std::uint32_t face, std::uint32_t q1, std::uint32_t q2, float level);

} // namespace standin::displaced_mesh
