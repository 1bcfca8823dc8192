// One step of the greedy construction (Vichitvejpaisal 2005 §3.2 steps 5-9): for a projection direction, find
// the faces one billboard can hold and, when asked, rasterise them into its maps. Internal to the
// enhanced-billboards baker (bake.cpp); see capture.cpp for the method.
#pragma once

#include "reps/enhanced_billboards/billboards.h"

#include <standin/mesh.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <utility>
#include <vector>

namespace standin::billboards {

// Per-face data computed once per bake.
struct FaceData {
    std::vector<glm::vec3> normal; // unit geometric normal, oriented to agree with the vertex normals
    std::vector<double> area;      // world units squared; 0 for degenerate faces
    // Per face, bit k set when its edge (k, k+1) is the edge of an open surface (no other face
    // there; bake.cpp, add_back_sides); empty when the model has none. Captures grow the coverage
    // across such edges by the texels the face overlaps (capture.cpp, write_maps).
    std::vector<std::uint8_t> open_edges;
    // Per face, its connected part (vertices welded by position), with open_edges: a sheet edge's
    // line clips only texels of its own part (another part touching the rim keeps its texels).
    std::vector<std::uint32_t> part;
};
FaceData compute_face_data(const Mesh& mesh);

struct CaptureSettings {
    float texel_size = 1.0f;    // world units per texel
    float depth_limit = 1.0f;   // world units: captured faces lie within this depth of the plane
    float min_facing = 0.0f;    // sin(grazing angle): faces with -n.w below it are not projected
    bool write_maps = false;    // fill Capture::billboard (the final pass); off when only scoring
    // --sheet-edges clip: texels an open edge crosses are covered and store its line, texels an
    // alpha-tested face's cut-out contour crosses store the contour's line, and every other texel
    // the outline of its own surface crosses (a silhouette, the end of a part over what lies behind
    // it) stores that outline's line, grown into the texels beyond where the outline reaches into
    // them (capture.cpp: sheet edge lines, alpha contour lines, outline lines)
    bool edge_lines = false;
    // Per face id, whether this billboard may capture it (null: every face); a face it may not
    // capture still hides what lies behind it
    const std::vector<std::uint8_t>* allowed = nullptr;
    // Partly hidden faces (above 0): a face hidden at some of its texels is captured, at the texels
    // where it is in front, when at least this fraction of its texels are; its hidden texels are
    // left to what hides them (capture.cpp, decide_captured)
    float partly_visible = 0.0f;
};

struct Capture {
    std::vector<std::uint32_t> faces; // captured face ids (S''), ascending
    double area = 0.0;                // their total area
    // of it, the part of partly hidden faces (CaptureSettings::partly_visible) at texels that others
    // hide, by the fraction of their texels hidden
    double hidden_area = 0.0;
    std::vector<std::uint32_t> partly_hidden; // those faces, ascending
    // with CaptureSettings::allowed: (allowed face not captured because hidden, a face hiding it)
    std::vector<std::pair<std::uint32_t, std::uint32_t>> hidden_by;
    Billboard billboard;              // with write_maps and a non-empty capture
};

// The right-handed plane basis (u, v, w) of a projection direction w, deterministic in w: v is the
// world up (+Y, or +Z when w is nearly vertical) made orthogonal to w, u = v x w.
void plane_basis(glm::vec3 w, glm::vec3& u, glm::vec3& v);

// Whether point p of a texel (texel units: the texel is [0, 1]^2) is on the surface's side of the
// sheet edge line coded in colour alpha `code` (128-254; billboard_layout.glsl, EDGE_LINE_*): the
// decoding march.frag does (on_surface). 255 (a whole texel) contains every point.
bool edge_line_contains(std::uint8_t code, glm::vec2 p);

// Captures what a billboard along unit direction w can hold of `remaining` (face ids, ascending).
// Results do not depend on the number of threads.
Capture capture_direction(const Mesh& mesh, const FaceData& faces, const std::vector<std::uint32_t>& remaining,
                          glm::vec3 w, const CaptureSettings& settings);

} // namespace standin::billboards
