// Adaptive subdivision of the control faces: the CPU reference of the GPU passes.
// Bauman, Livny & El-Sana, §3.3 (longest-edge bisection in screen space against a tolerance tau,
// weighted by the edges' "geometric curvature"), §3.4 (culling on the face's bounding prism,
// elevations from mip maps) and §5.2 (processed and rendered triangles).
//
// Steps for one instance and one view:
//  1. cull: a control face survives when its prism (corners displaced by the face's lowest and
//     highest elevation) meets the view frustum and is not wholly back-facing (normal cone test);
//  2. bisect, pass by pass: a triangle splits when one of its edges passes the segment test (the
//     edge is longer than one pattern grid unit and its projected length times its weight exceeds
//     tau) and bisects the longest such edge at its midpoint, longest in the pattern's own metric
//     (the parameter domain, where longest-edge bisection keeps its few triangle shapes), the
//     projected length breaking ties (the error criterion; the paper's rules keep the longest on
//     screen); otherwise it is final. Departure: the longest edge on screen cut triangles ever
//     thinner in the pattern where an edge short in it was long on screen: hard-surface models,
//     refined to the finest level, drew 3-5 times the pattern's triangles; now 1.6-2.7 times fewer
//     at equal or lower Luv (docs/RESULTS.md "Displaced mesh: bisecting the longest edge of the
//     pattern");
//  3. displace each final vertex along its normalised interpolated normal by the elevation read
//     from the level whose spacing projects to about tau pixels (trilinear between two levels).
// Why the segment test makes the result crack-free: every quantity it reads (endpoint positions,
// weights, grid length) is a function of the segment alone, computed the same way from either
// face (face_point.h), so a segment is split by all triangles that have it or by none. The paper's
// literal rule (the longest edge decides for the whole triangle) lets one side of an edge split it
// while the other does not (Criterion::seed keeps that rule, to count the T-junctions it leaves).
#include "reps/displaced_mesh/refine.h"

#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/shaders/displaced_layout.glsl"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace standin::displaced_mesh {

namespace {

constexpr float k_weight_min = 0.25f, k_weight_max = 4.0f;
constexpr float k_cone_margin = 0.0873f;      // 5 degrees: coarse triangles' normals stray from the finest ones'
constexpr float k_sphere_margin = 0.01f;      // of the longest edge
constexpr float k_segment_min_units = 1.001f; // segments up to one pattern grid unit are not split
// The constants the GPU shares live in shaders/displaced_layout.glsl.
// A chord of length L on a curve of curvature kappa strays kappa L^2 / 8 from it; a triangle's
// linear interpolant up to about kappa L^2 / 6 inside (equilateral, circumradius L / sqrt 3).
constexpr float k_chord_error = float(DM_CHORD_ERROR);
// The chord strays along the surface normal: on screen that shows times the sine of the angle
// between normal and view direction (full on the silhouette, none face-on). The floor keeps depth,
// shadows and self-occlusion within a few tau of the surface where it faces the viewer.
constexpr float k_min_visible = float(DM_MIN_VISIBLE);
// Near the silhouette (|cos| of the normal's angle to the view below k_silhouette_cos) a chord
// shrinks the outline, and every pixel it leaves is a hole against the original: the error counts
// RefineOptions::outline times there (docs/RESULTS.md weighs holes against triangles).
constexpr float k_silhouette_cos = float(DM_SILHOUETTE_COS);

// Which faces' backs no eye outside the model sees, so that back-face culling keeps the picture:
// those of a closed part wound outward (every edge of the part joins two faces walking it in
// opposite directions, and its signed volume is positive). The reference draws both sides, so an
// open part shows its back faces through its holes, and a closed part wound inside out (assimp's
// FBX/animation_with_skeleton.fbx: a capsule whose winding and normals both point inward) shows
// only faces its winding calls backs: culling them left the far wall's inside, its shading
// mirrored (thesis Luv 9.97 against 0.07 unculled). Parts are the faces joined across edges. A
// part holding a face with cut-outs (`see_through`, per face; may be empty) is seen into through
// them: assimp's FBX box with a cut-out paper texture showed holes where the far wall's inside was culled.
std::vector<std::uint8_t> faces_with_hidden_backs(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                                                  const ControlTopology& topology, const std::vector<std::uint8_t>& see_through)
{
    const std::size_t faces = indices.size() / 3;
    std::vector<std::uint32_t> parent(faces);
    for (std::size_t f = 0; f < faces; ++f) parent[f] = std::uint32_t(f);
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const ControlEdge& edge : topology.edges)
        for (std::size_t k = 1; k < edge.faces.size(); ++k) {
            std::uint32_t a = root(edge.faces[0]), b = root(edge.faces[k]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    // a part fails on an open or non-manifold edge, or two faces walking an edge the same way
    std::vector<std::uint8_t> closed(faces, 1);
    for (std::size_t f = 0; f < faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const ControlEdge& edge = topology.edges[topology.face_edges[f][std::size_t(k)]];
            bool paired = edge.faces.size() == 2;
            if (paired) {
                const std::uint32_t other = edge.faces[0] == f ? edge.faces[1] : edge.faces[0];
                int other_k = 0;
                while (other_k < 3 && topology.face_edges[other][std::size_t(other_k)] != topology.face_edges[f][std::size_t(k)]) ++other_k;
                paired = other_k < 3 && topology.reversed(std::uint32_t(f), k) != topology.reversed(other, other_k);
            }
            if (!paired) closed[root(std::uint32_t(f))] = 0;
        }
    for (std::size_t f = 0; f < see_through.size() && f < faces; ++f)
        if (see_through[f]) closed[root(std::uint32_t(f))] = 0;
    std::vector<double> volume(faces, 0.0);
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::dvec3 p0(positions[indices[3 * f]]), p1(positions[indices[3 * f + 1]]), p2(positions[indices[3 * f + 2]]);
        volume[root(std::uint32_t(f))] += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
    }
    std::vector<std::uint8_t> hidden(faces);
    for (std::size_t f = 0; f < faces; ++f) {
        const std::uint32_t part = root(std::uint32_t(f));
        hidden[f] = closed[part] && volume[part] > 0.0;
    }
    return hidden;
}

const std::uint32_t* corners_of(const RefineSurface& s, std::uint32_t face) { return &(*s.indices)[3 * std::size_t(face)]; }

FacePoint point_of(const RefineSurface& s, std::uint32_t face, std::uint32_t q1, std::uint32_t q2)
{
    return face_point(s.positions->data(), s.normals->data(), corners_of(s, face), q1, q2);
}

glm::vec3 to_view(const RefineView& view, glm::vec3 p) { return glm::vec3(view.view_from_object * glm::vec4(p, 1.0f)); }

// Projected length in pixels of a segment with view-space ends a and b (symmetric in a and b).
float projected_length(const RefineView& view, glm::vec3 a, glm::vec3 b)
{
    float length = glm::length(a - b) * view.pixels_per_unit;
    if (view.orthographic) return length;
    return length / std::max(view.near_plane, std::min(-a.z, -b.z));
}

// A segment's squared length in pattern grid units (the pattern's own equilateral metric, from the
// integer weights: symmetric in the two ends); longer than one unit splits.
float pattern_units2(const std::uint32_t* a, const std::uint32_t* b, int segments)
{
    float d1 = float(std::int32_t(a[0] - b[0])) / float(k_bary_one);
    float d2 = float(std::int32_t(a[1] - b[1])) / float(k_bary_one);
    float d0 = -(d1 + d2);
    return 0.5f * (d0 * d0 + d1 * d1 + d2 * d2) * float(segments) * float(segments);
}


// The weight of a segment: its control edge's when both ends lie on one, else the face's. Ends are
// (q1, q2); a zero weight on corner c for both ends puts the segment on the edge opposite c.
// The face edge a segment lies on (-1: inside the face).
int segment_edge(const std::uint32_t* a, const std::uint32_t* b)
{
    if (a[1] == 0 && b[1] == 0) return 0;                                                 // c0 -> c1
    if (a[0] + a[1] == k_bary_one && b[0] + b[1] == k_bary_one) return 1;                 // c1 -> c2
    if (a[0] == 0 && b[0] == 0) return 2;                                                 // c2 -> c0
    return -1;
}

float segment_weight(const FaceRefineData& face, const std::uint32_t* a, const std::uint32_t* b)
{
    int edge = segment_edge(a, b);
    return edge >= 0 ? face.edge_weight[edge] : face.interior_weight;
}

// The error criterion's weight: curvature x world length x k_chord_error (view-space length over
// the instance's scale gives object units, the curvature's), times how much of a deviation along
// the normal shows on screen. a, b: view-space ends; na, nb: their unit view-space normals.
float error_weight(const FaceRefineData& face, const std::uint32_t* qa, const std::uint32_t* qb, glm::vec3 a, glm::vec3 b,
                   glm::vec3 na, glm::vec3 nb, float scale, bool orthographic, float outline)
{
    int edge = segment_edge(qa, qb);
    float curvature = edge >= 0 ? face.edge_curvature[edge] : face.interior_curvature;
    glm::vec3 normal = unit_direction(na + nb);
    glm::vec3 to_eye = orthographic ? glm::vec3(0.0f, 0.0f, 1.0f) : unit_direction(-(a + b));
    float facing = glm::dot(normal, to_eye);
    float visible = std::max(std::sqrt(std::max(1.0f - facing * facing, 0.0f)), k_min_visible);
    if (std::abs(facing) < k_silhouette_cos) visible *= outline;
    return curvature * glm::length(a - b) / scale * k_chord_error * visible;
}

// The edge of the face holding a point with a zero weight (or -1 inside): zero on corner c puts it
// on the edge opposite c, numbered (c + 1) % 3.
int edge_of_point(std::uint32_t q1, std::uint32_t q2)
{
    if (q2 == 0) return 0;
    if (q1 + q2 == k_bary_one) return 1;
    if (q1 == 0) return 2;
    return -1;
}

// Value of pattern vertex (i, j) of `level` of a face.
float stored(const RefineSurface& s, const PatternLayout& layout, std::uint32_t face, int level, int i, int j)
{
    return (*s.elevations)[std::size_t(face) * layout.samples_per_face + layout.index(level, i, j)];
}

float elevation_at_level(const RefineSurface& s, const PatternLayout& layout, std::uint32_t face, std::uint32_t q1,
                         std::uint32_t q2, int level)
{
    const int n = layout.level_segments(level);
    const std::uint32_t* corner = corners_of(s, face);
    const std::uint32_t q[3] = {k_bary_one - q1 - q2, q1, q2};
    for (int k = 0; k < 3; ++k)
        if (q[k] == k_bary_one) {
            int i = 0, j = 0;
            edge_vertex(n, k, 0, i, j);
            return stored(s, layout, face, level, i, j);
        }
    int edge = edge_of_point(q1, q2);
    if (edge >= 0) {
        // along the edge only, from its lower vertex index
        int a = edge, b = (edge + 1) % 3;
        int hi = corner[a] < corner[b] ? b : a;
        float t = float(q[hi]) / float(k_bary_one) * float(n);
        int s0 = std::min(int(std::floor(t)), n);
        float fraction = t - float(s0);
        bool reversed = s.topology->reversed(face, edge);
        auto value = [&](int canonical) {
            int i = 0, j = 0;
            edge_vertex(n, edge, reversed ? n - canonical : canonical, i, j);
            return stored(s, layout, face, level, i, j);
        };
        float v0 = value(s0);
        if (!(fraction > 0.0f) || s0 >= n) return v0;
        float v1 = value(s0 + 1);
        return v0 + fraction * (v1 - v0);
    }
    // inside: the pattern triangle of this level holding the point, barycentric there
    float x = float(q1) / float(k_bary_one) * float(n), y = float(q2) / float(k_bary_one) * float(n);
    int i0 = std::min(int(std::floor(y)), n - 1);
    int j0 = std::min(int(std::floor(x)), n - 1 - i0);
    float fx = x - float(j0), fy = y - float(i0);
    if (fx + fy <= 1.0f)
        return (1.0f - fx - fy) * stored(s, layout, face, level, i0, j0) + fx * stored(s, layout, face, level, i0, j0 + 1) +
               fy * stored(s, layout, face, level, i0 + 1, j0);
    return (1.0f - fy) * stored(s, layout, face, level, i0, j0 + 1) + (fx + fy - 1.0f) * stored(s, layout, face, level, i0 + 1, j0 + 1) +
           (1.0f - fx) * stored(s, layout, face, level, i0 + 1, j0);
}

// The finest grid spacing at a point, world units: its control edge's length / (k - 1) on an edge
// (the same on both faces), the face's mean inside.
float grid_spacing(const RefineSurface& s, const PatternLayout& layout, std::uint32_t face, std::uint32_t q1, std::uint32_t q2)
{
    int edge = edge_of_point(q1, q2);
    if (edge < 0) return (*s.faces)[face].grid_length;
    const std::uint32_t* corner = corners_of(s, face);
    std::uint32_t a = corner[edge], b = corner[(edge + 1) % 3];
    glm::vec3 lo = (*s.positions)[std::min(a, b)], hi = (*s.positions)[std::max(a, b)];
    return glm::length(hi - lo) / float(layout.segments);
}

struct Decision {
    int edge = -1;       // the edge to bisect, -1: final
};

Decision decide(const RefineSurface& s, const PatternLayout& layout, const RefinedTriangle& t, const RefineView& view,
                const RefineOptions& options)
{
    const FaceRefineData& face = (*s.faces)[t.face];
    glm::vec3 p[3], normal[3];
    for (int k = 0; k < 3; ++k) {
        FacePoint point = point_of(s, t.face, t.q[k][0], t.q[k][1]);
        p[k] = to_view(view, point.position);
        normal[k] = unit_direction(glm::mat3(view.view_from_object) * point.normal);
    }
    float length[3], weight[3], units2[3];
    bool can_split[3];
    const float scale = glm::length(glm::vec3(view.view_from_object[0]));
    for (int k = 0; k < 3; ++k) {
        const std::uint32_t* a = t.q[k];
        const std::uint32_t* b = t.q[(k + 1) % 3];
        length[k] = projected_length(view, p[k], p[(k + 1) % 3]);
        if (options.criterion == Criterion::length) weight[k] = 1.0f;
        else if (options.criterion == Criterion::error)
            weight[k] = error_weight(face, a, b, p[k], p[(k + 1) % 3], normal[k], normal[(k + 1) % 3], scale, view.orthographic,
                                     options.outline);
        else weight[k] = segment_weight(face, a, b);
        units2[k] = pattern_units2(a, b, layout.segments);
        can_split[k] = units2[k] > k_segment_min_units * k_segment_min_units;
    }
    Decision d;
    if (options.criterion == Criterion::seed) {
        int longest = -1;
        for (int k = 0; k < 3; ++k)
            if (can_split[k] && (longest < 0 || length[k] > length[longest])) longest = k;
        if (longest >= 0 && length[longest] * weight[longest] > options.tau) d.edge = longest;
        return d;
    }
    // the error criterion: longest in pattern units, the projected length breaking ties (step 2);
    // the paper's weighted and length rules: longest on screen
    const bool by_pattern = options.criterion == Criterion::error;
    float units[3];
    for (int k = 0; k < 3; ++k) units[k] = by_pattern ? units2[k] : 0.0f;
    for (int k = 0; k < 3; ++k)
        if (can_split[k] && length[k] * weight[k] > options.tau &&
            (d.edge < 0 || units[k] > units[d.edge] * 1.0001f || (!(units[d.edge] > units[k] * 1.0001f) && length[k] > length[d.edge])))
            d.edge = k;
    return d;
}

} // namespace

bool parse_criterion(const std::string& name, Criterion& out)
{
    if (name == "weighted") return out = Criterion::weighted, true;
    if (name == "length") return out = Criterion::length, true;
    if (name == "seed") return out = Criterion::seed, true;
    if (name == "error") return out = Criterion::error, true;
    return false;
}

int refinement_passes(int degree, int max_depth)
{
    if (max_depth > 0) return max_depth;
    return 3 * pattern_exponent(degree) + 6;
}

RefineView make_refine_view(const Camera& camera, int viewport_height, const glm::mat4& world_from_object)
{
    RefineView view;
    view.view_from_object = camera.view_from_world * world_from_object;
    view.clip_from_view = camera.clip_from_view;
    view.orthographic = camera.orthographic;
    view.near_plane = camera.near_plane;
    float half_height = camera.orthographic ? camera.ortho_half_height
                                            : std::tan(glm::radians(camera.fov_y_degrees) * 0.5f);
    view.pixels_per_unit = float(viewport_height) / (2.0f * half_height);
    return view;
}

std::vector<FaceRefineData> prepare_faces(const std::vector<glm::vec3>& positions, const std::vector<glm::vec3>& normals,
                                          const std::vector<std::uint32_t>& indices, const ControlTopology& topology,
                                          const PatternLayout& layout, const std::vector<float>& elevations,
                                          const std::vector<float>& face_error, const std::vector<std::uint8_t>& see_through,
                                          const std::vector<std::uint8_t>& kept_whole)
{
    const std::size_t faces = indices.size() / 3;
    const int n = layout.segments;
    std::vector<FaceRefineData> out(faces);
    const std::vector<std::uint8_t> backs_hidden = faces_with_hidden_backs(positions, indices, topology, see_through);
    std::vector<float> magnitude(faces); // h_f + ∆_f: the largest |elevation| plus the sampling error (the paper's ∆e terms)
    std::vector<float> curvatures(faces); // of the displaced surface (the error criterion)
    for (std::size_t f = 0; f < faces; ++f) {
        FaceRefineData& d = out[f];
        const float* values = &elevations[f * layout.samples_per_face];
        auto [lo, hi] = std::minmax_element(values, values + layout.samples_per_face);
        d.h_min = *lo, d.h_max = *hi;
        magnitude[f] = std::max(std::abs(d.h_min), std::abs(d.h_max)) + face_error[f];
        const std::uint32_t* c = &indices[3 * f];
        glm::vec3 p0 = positions[c[0]], p1 = positions[c[1]], p2 = positions[c[2]];
        d.grid_length = (glm::length(p1 - p0) + glm::length(p2 - p1) + glm::length(p0 - p2)) / (3.0f * float(n));

        // the cone of the finest displaced triangles' normals around the face normal, and how far
        // normalised interpolated normals carry points out of the prism
        glm::vec3 axis = glm::cross(p1 - p0, p2 - p0);
        axis = glm::length(axis) > 0.0f ? glm::normalize(axis) : glm::vec3(0.0f, 0.0f, 1.0f);
        std::vector<glm::vec3> displaced(layout.finest_samples);
        auto point_at = [&](int i, int j) {
            return face_point(positions.data(), normals.data(), c, std::uint32_t(j) * (k_bary_one / std::uint32_t(n)),
                              std::uint32_t(i) * (k_bary_one / std::uint32_t(n)))
                .position;
        };
        float min_normal = 1.0f;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                std::uint32_t q1 = std::uint32_t(j) * (k_bary_one / std::uint32_t(n)), q2 = std::uint32_t(i) * (k_bary_one / std::uint32_t(n));
                FacePoint point = face_point(positions.data(), normals.data(), c, q1, q2);
                std::size_t at = triangle_index(n, i, j);
                displaced[at] = point.position + values[at] * unit_direction(point.normal);
                min_normal = std::min(min_normal, glm::length(point.normal));
            }
        d.normal_shrink = 1.0f - min_normal;
        // curvature: second differences of the displaced grid along its three directions, over
        // the squared spacing of the undisplaced grid
        float curvature = 0.0f;
        auto bend = [&](int ia, int ja, int ib, int jb, int ic, int jc) {
            glm::vec3 second = displaced[triangle_index(n, ia, ja)] - 2.0f * displaced[triangle_index(n, ib, jb)] +
                               displaced[triangle_index(n, ic, jc)];
            float spacing = 0.5f * glm::length(point_at(ia, ja) - point_at(ic, jc));
            if (spacing > 0.0f) curvature = std::max(curvature, glm::length(second) / (spacing * spacing));
        };
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                if (j >= 1 && j + 1 <= n - i) bend(i, j - 1, i, j, i, j + 1);
                if (i >= 1 && i + 1 <= n - j) bend(i - 1, j, i, j, i + 1, j);
                if (i >= 1 && j >= 1 && i + 1 + j - 1 <= n) bend(i - 1, j + 1, i, j, i + 1, j - 1);
            }
        curvatures[f] = curvature;
        d.interior_curvature = curvature;
        float widest = 0.0f;
        auto widen = [&](std::size_t a, std::size_t b, std::size_t e) {
            glm::vec3 m = glm::cross(displaced[b] - displaced[a], displaced[e] - displaced[a]);
            float length = glm::length(m);
            if (!(length > 0.0f)) return;
            widest = std::max(widest, std::acos(std::clamp(glm::dot(m / length, axis), -1.0f, 1.0f)));
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                widen(triangle_index(n, i, j), triangle_index(n, i, j + 1), triangle_index(n, i + 1, j));
                if (j < n - i - 1) widen(triangle_index(n, i, j + 1), triangle_index(n, i + 1, j + 1), triangle_index(n, i + 1, j));
            }
        d.cone_half_angle = widest + k_cone_margin >= 0.5f * std::numbers::pi_v<float> ? std::numbers::pi_v<float> : widest + k_cone_margin;
    }

    // ∆e per control edge, its length-weighted mean, then the normalised weights
    std::vector<float> edge_value(topology.edges.size());
    std::vector<std::uint8_t> edge_whole(topology.edges.size(), 0);
    double sum = 0.0, total_length = 0.0;
    for (std::size_t e = 0; e < topology.edges.size(); ++e) {
        const ControlEdge& edge = topology.edges[e];
        float h = 0.0f, delta = 0.0f;
        bool whole = !kept_whole.empty();
        for (std::uint32_t f : edge.faces) {
            h = std::max(h, magnitude[f] - face_error[f]);
            delta = std::max(delta, face_error[f]);
            whole = whole && kept_whole[f];
        }
        edge_value[e] = h + delta;
        edge_whole[e] = whole;
        if (whole) continue;
        double length = glm::length(positions[edge.hi] - positions[edge.lo]);
        sum += edge_value[e] * length;
        total_length += length;
    }
    double mean = total_length > 0.0 ? sum / total_length : 0.0;
    for (std::size_t f = 0; f < faces; ++f)
        if (!backs_hidden[f]) out[f].cone_half_angle = std::numbers::pi_v<float>;
    auto normalise = [&](float value) {
        return mean > 0.0 ? std::clamp(float(value / mean), k_weight_min, k_weight_max) : 1.0f;
    };
    std::vector<float> edge_curvature(topology.edges.size(), 0.0f);
    for (std::size_t e = 0; e < topology.edges.size(); ++e)
        for (std::uint32_t f : topology.edges[e].faces) edge_curvature[e] = std::max(edge_curvature[e], curvatures[f]);
    for (std::size_t f = 0; f < faces; ++f) {
        for (int k = 0; k < 3; ++k) out[f].edge_curvature[k] = edge_curvature[topology.face_edges[f][std::size_t(k)]];
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t e = topology.face_edges[f][std::size_t(k)];
            out[f].edge_weight[k] = edge_whole[e] ? 0.0f : normalise(edge_value[e]);
        }
        out[f].interior_weight = !kept_whole.empty() && kept_whole[f] ? 0.0f : normalise(magnitude[f]);
    }
    return out;
}

bool face_visible(const RefineSurface& s, std::uint32_t face, const RefineView& view)
{
    const FaceRefineData& d = (*s.faces)[face];
    const std::uint32_t* c = corners_of(s, face);
    // the prism's corners in view space and a sphere around them
    glm::vec3 corners[6];
    for (int k = 0; k < 3; ++k) {
        glm::vec3 p = (*s.positions)[c[k]], n = (*s.normals)[c[k]];
        corners[k] = to_view(view, p + d.h_min * n);
        corners[k + 3] = to_view(view, p + d.h_max * n);
    }
    glm::vec3 centre(0.0f);
    for (const glm::vec3& p : corners) centre += p / 6.0f;
    float radius = 0.0f, longest = 0.0f;
    for (const glm::vec3& p : corners) radius = std::max(radius, glm::length(p - centre));
    for (int k = 0; k < 3; ++k) longest = std::max(longest, glm::length(corners[k] - corners[(k + 1) % 3]));
    float scale = glm::length(glm::vec3(view.view_from_object[0]));
    radius += k_sphere_margin * longest + scale * std::max(std::abs(d.h_min), std::abs(d.h_max)) * d.normal_shrink;

    // frustum: the sphere against the six planes of clip_from_view (Gribb & Hartmann 2001)
    const glm::mat4& m = view.clip_from_view;
    glm::vec4 row[4];
    for (int r = 0; r < 4; ++r) row[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
    for (int plane = 0; plane < 6; ++plane) {
        glm::vec4 e = row[3] + (plane % 2 ? -1.0f : 1.0f) * row[plane / 2];
        float length = glm::length(glm::vec3(e));
        if (glm::dot(glm::vec3(e), centre) + e.w < -radius * length) return false;
    }

    // back faces: every normal of the cone faces away from every point of the sphere
    if (d.cone_half_angle >= 0.5f * std::numbers::pi_v<float>) return true;
    glm::vec3 p0 = to_view(view, (*s.positions)[c[0]]), p1 = to_view(view, (*s.positions)[c[1]]);
    glm::vec3 p2 = to_view(view, (*s.positions)[c[2]]);
    // (a mirroring transform turns the cross product of the face's edges against its normal)
    glm::vec3 axis = glm::cross(p1 - p0, p2 - p0);
    if (glm::determinant(glm::mat3(view.view_from_object)) < 0.0f) axis = -axis;
    if (!(glm::length(axis) > 0.0f)) return true;
    axis = glm::normalize(axis);
    float sin_cone = std::sin(d.cone_half_angle);
    if (view.orthographic) return glm::dot(glm::vec3(0.0f, 0.0f, -1.0f), axis) < sin_cone;
    float distance = glm::length(centre);
    if (distance <= radius) return true;
    return glm::dot(centre / distance, axis) < sin_cone + radius / distance;
}

float elevation_at(const RefineSurface& s, std::uint32_t face, std::uint32_t q1, std::uint32_t q2, float level)
{
    const PatternLayout layout(s.degree);
    int l0 = std::clamp(int(std::floor(level)), 0, layout.exponent);
    float fraction = level - float(l0);
    float h0 = elevation_at_level(s, layout, face, q1, q2, l0);
    if (!(fraction > 0.0f) || l0 >= layout.exponent) return h0;
    float h1 = elevation_at_level(s, layout, face, q1, q2, l0 + 1);
    return h0 + fraction * (h1 - h0);
}

glm::vec3 displaced_position(const RefineSurface& s, std::uint32_t face, std::uint32_t q1, std::uint32_t q2,
                             const RefineView& view, const RefineOptions& options)
{
    const PatternLayout layout(s.degree);
    FacePoint point = point_of(s, face, q1, q2);
    float level = 0.0f;
    if (options.mip) {
        // the level whose spacing projects to about tau pixels at this point
        float scale = glm::length(glm::vec3(view.view_from_object[0]));
        float spacing = grid_spacing(s, layout, face, q1, q2) * scale * view.pixels_per_unit;
        if (!view.orthographic) spacing /= std::max(view.near_plane, -to_view(view, point.position).z);
        level = spacing > 0.0f ? std::clamp(std::log2(options.tau / spacing), 0.0f, float(layout.exponent)) : 0.0f;
    }
    return point.position + elevation_at(s, face, q1, q2, level) * unit_direction(point.normal);
}

std::vector<RefinedTriangle> refine(const RefineSurface& s, const RefineView& view, const RefineOptions& options, RefineStats& stats)
{
    const PatternLayout layout(s.degree);
    const int passes = refinement_passes(s.degree, options.max_depth);
    std::vector<RefinedTriangle> current, next, final_list;
    for (std::uint32_t f = 0; f < s.indices->size() / 3; ++f) {
        if (options.cull && !face_visible(s, f, view)) continue;
        RefinedTriangle root;
        root.face = f;
        root.q[1][0] = k_bary_one; // corner 1: q1 = one
        root.q[2][1] = k_bary_one; // corner 2: q2 = one
        current.push_back(root);
    }
    stats.faces_visible += current.size();
    for (int pass = 0; pass < passes && !current.empty(); ++pass) {
        next.clear();
        for (const RefinedTriangle& t : current) {
            ++stats.processed;
            Decision d = decide(s, layout, t, view, options);
            if (d.edge < 0 || pass == passes - 1) {
                stats.capped += d.edge >= 0;
                final_list.push_back(t);
                continue;
            }
            // bisect edge k (corner k -> k + 1) at its midpoint m: (k, m, k + 2) and (m, k + 1, k + 2)
            int k = d.edge, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
            std::uint32_t m[2] = {(t.q[k][0] >> 1) + (t.q[k1][0] >> 1) + (t.q[k][0] & t.q[k1][0] & 1u),
                                  (t.q[k][1] >> 1) + (t.q[k1][1] >> 1) + (t.q[k][1] & t.q[k1][1] & 1u)};
            RefinedTriangle a = t, b = t;
            a.depth = b.depth = t.depth + 1;
            a.q[0][0] = t.q[k][0], a.q[0][1] = t.q[k][1];
            a.q[1][0] = m[0], a.q[1][1] = m[1];
            a.q[2][0] = t.q[k2][0], a.q[2][1] = t.q[k2][1];
            b.q[0][0] = m[0], b.q[0][1] = m[1];
            b.q[1][0] = t.q[k1][0], b.q[1][1] = t.q[k1][1];
            b.q[2][0] = t.q[k2][0], b.q[2][1] = t.q[k2][1];
            next.push_back(a);
            next.push_back(b);
        }
        std::swap(current, next);
    }
    stats.rendered += final_list.size();
    return final_list;
}

} // namespace standin::displaced_mesh
