// Sampling the original surface along the control mesh's interpolated normals.
// Bauman, Livny & El-Sana, §3.1 (Eq. 1a/1b, intersection and interpolation sampling), §3.2
// (displacement maps, the sampling error ∆_f) and §5.1 (the distance d of Tables 2 and 3).
//
// Steps:
//  1. one sample per control vertex, one per interior vertex of each control edge (in the edge's
//     canonical direction), and the interior vertices of each face: the point T(w) and normal N(w)
//     of Eq. 1, a ray each way along N(w)/|N(w)| up to the ray range, the nearer hit kept as a
//     signed elevation; where both rays miss, the closest point of the surface, its offset along
//     the normal as the elevation (counted as a miss). Each hit also gives the original's shading
//     normal and albedo there (the paper never says where its shading normals came from).
//     Departure: a sample that lies on the original (every control vertex is an input vertex; a
//     CAD model's control faces lie on its planes) is the point it lies on: a ray starting on a
//     face may not report it and meet some other part further on.
//     Departure: the nearer hit may be a surface hidden inside a closed part (nested shells,
//     interpenetrating parts); while it is, the sample moves out along the normal to the surface
//     enclosing it (outermost_visible), so the stand-in shows what the model shows; a move onto a
//     surface that the samples of other control faces already draw is undone once all samples
//     are known (undo_covered_moves: a part sunk into another keeps its crease). Departure: a
//     layer a hair over the hit, facing its way (a decal, continents over an ocean), is what an
//     eye on the normal's side sees, and the sample takes it (over_layers).
//     Departure (issue #14): on a model with alpha-masked materials a ray walks on through hits
//     the alpha test cuts out (texture level 0 bilinear, Mesh::covered_at, the truth's rule) and
//     keeps the nearer surviving hit; the sample records whether it found one (its coverage).
//     Where neither direction does, it keeps the nearest hit of any kind for its elevation, so
//     the surface keeps the shape it had without the test and the renderer cuts it out. A sample
//     that lies on the original (leaf cards stay whole in the control mesh) takes the point it
//     lies on, covered or not, without looking behind it;
//  2. "interpolation" sampling replaces each elevation by the mean of sub-ray elevations over the
//     vertex's ring of pattern triangles, weighted by the vertex's hat function: the paper's
//     "roughly equal cells" weighted by distance, with a kernel that vanishes at the ring so
//     neighbouring samples share the work. Rings cross control edges and corners; their sums are
//     gathered per edge and per vertex in increasing face order, so both sides agree;
//  3. every face's finest array is assembled by copying the edge and corner samples in; on models
//     with cut-outs, cut-out samples take their covered neighbours' colour (bleed_into_cutouts);
//     on models with cut-outs a sample that lies on the original takes the mean colour over its
//     cell, the box filter of the truth's mip level at the sample spacing (prefilter_surface_colour;
//     on textured models the bake does the same once their shading detail is chosen:
//     prefilter_texture_colour).
// Then Ms (the sampled mesh) is rebuilt and measured against the original: ∆_f and d.
// Departure: for a textured model the bake may ask for shading 2 or 4 times finer than the pattern
// (sample_fine_shading: the original's shading closest to the displaced surface at the finer
// pattern's vertices).
#include "reps/displaced_mesh/sample.h"

#include "reps/displaced_mesh/face_point.h"
#include "reps/common/coverage_capture.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace standin::displaced_mesh {

namespace {

// The surface a sample's ray met first, where outermost_visible moved the sample out from it.
struct HiddenHit {
    bool moved = false;
    float elevation = 0.0f;
    SurfacePoint hit;
};

struct Sample {
    float elevation = 0.0f;
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec4 albedo{0.8f, 0.8f, 0.8f, 1.0f};
    PbrSample pbr;
    bool missed = false;
    bool covered = true; // the point survives its material's alpha test (issue #14)
    HiddenHit hidden;    // (intersection sampling without cut-outs)
    bool kept_first = false; // undo_covered_moves put it back on its first hit
};

// Cut-out surfaces a ray walks through before it gives up on a direction: leaf cards stacked
// deeper than this along one normal are rare, and the walk must end.
constexpr int k_max_cutouts = 64;
// A sample this close to the original (a fraction of the ray range) lies on it: far below a
// pattern step, far above the rounding of a point interpolated on a control face.
constexpr float k_on_surface = 1e-4f;

// A ray start just past a hit at distance t: a step relative to the distance, so float rounding
// cannot find the hit again.
float past(float t, float range)
{
    return std::nextafter(t + std::max(t, range) * 1e-6f, std::numeric_limits<float>::infinity());
}

// The first hit along `direction` within `range` that survives the alpha test (issue #14): a ray
// through a card's cut-out goes on to what lies behind it, as a view through the hole would.
SurfacePoint first_covered(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction, float range)
{
    float t_min = 0.0f;
    for (int step = 0; step < k_max_cutouts; ++step) {
        SurfacePoint hit = scene.intersect(origin, direction, range, t_min);
        if (!hit.found || original.covered_at(hit.triangle, hit.b1, hit.b2)) return hit;
        t_min = past(hit.t, range);
    }
    return {};
}

// The nearer of a hit along +direction and one along -direction (at least one found), its signed
// distance in `elevation`.
SurfacePoint nearer_of(const SurfacePoint& forward, const SurfacePoint& backward, float& elevation)
{
    if (forward.found && (!backward.found || forward.t <= backward.t)) {
        elevation = forward.t;
        return forward;
    }
    elevation = -backward.t;
    return backward;
}

// The nearer of the hits along +direction and -direction within `range`, as a signed distance;
// the closest point's offset along `direction` when both miss.
SurfacePoint nearest_along(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction, float range,
                           float& elevation, bool& missed, HiddenHit* hidden = nullptr, bool move_out = true);

// The same for a model with alpha-masked materials (issue #14): the nearer hit that survives the
// alpha test, `covered`; where neither direction meets one, the nearest hit of any kind (the
// surface there keeps the shape it had without the test, and is cut out where drawn).
SurfacePoint nearest_covered_along(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction,
                                   float range, float& elevation, bool& missed, bool& covered)
{
    // a sample on the surface itself (a control face on a kept leaf card) is that point: covered
    // or cut out, never what lies behind the card (which its own control faces draw)
    SurfacePoint on = scene.closest(origin, k_on_surface * range);
    if (on.found) {
        elevation = glm::dot(on.position - origin, direction);
        missed = false;
        covered = original.covered_at(on.triangle, on.b1, on.b2);
        return on;
    }
    SurfacePoint forward = first_covered(scene, original, origin, direction, range);
    SurfacePoint backward = first_covered(scene, original, origin, -direction, range);
    missed = false;
    covered = true;
    if (forward.found || backward.found) return nearer_of(forward, backward, elevation);
    SurfacePoint any = nearest_along(scene, original, origin, direction, range, elevation, missed);
    // any ray hit here is cut out; a ray starting on a covered point of the surface reports it
    // through the closest point
    covered = any.found && !missed && original.covered_at(any.triangle, any.b1, any.b2);
    return any;
}

// The winding normal of the triangle `hit` lies on (not unit length).
glm::vec3 winding_normal(const Mesh& original, const SurfacePoint& hit)
{
    const std::uint32_t* t = &original.indices[3 * std::size_t(hit.triangle)];
    const glm::vec3 a = original.positions[t[0]], b = original.positions[t[1]], c = original.positions[t[2]];
    return glm::cross(b - a, c - a);
}

// Whether a ray along `direction` meets `hit` from inside the surface's solid: the triangle's
// winding normal points the ray's way, so the ray leaves through it.
bool leaves_through(const Mesh& original, const SurfacePoint& hit, glm::vec3 direction)
{
    return glm::dot(winding_normal(original, hit), direction) > 0.0f;
}

// Whether `point` lies inside a closed part of the model. Along a ray from a point inside closed,
// consistently wound solids, the surfaces it leaves through outnumber those it enters by the
// number of solids holding the point (nested shells included); from outside they balance, and
// between open sheets (pages of a book, stacked cards) most rays miss. Seven rays, unbounded, in
// directions no model is built along (axis-aligned rays through a CAD model's or a sphere's
// vertices and edges are where a ray tracer may miss or double a crossing); inside where at
// least six count more exits than entries.
bool inside_closed_part(const RayScene& scene, const Mesh& original, glm::vec3 point)
{
    static const glm::vec3 directions[7] = {
        glm::normalize(glm::vec3(0.5386f, 0.8071f, 0.2416f)),  glm::normalize(glm::vec3(-0.7321f, 0.1873f, 0.6549f)),
        glm::normalize(glm::vec3(0.2254f, -0.6413f, 0.7337f)), glm::normalize(glm::vec3(-0.3917f, -0.5218f, -0.7579f)),
        glm::normalize(glm::vec3(0.8829f, -0.2671f, -0.3862f)), glm::normalize(glm::vec3(-0.6183f, 0.6937f, -0.3694f)),
        glm::normalize(glm::vec3(0.1462f, 0.0919f, -0.9850f))};
    const float unbounded = std::numeric_limits<float>::infinity();
    int enclosed = 0;
    for (int k = 0; k < 7; ++k) {
        int winding = 0;
        float t_min = 0.0f;
        for (int crossing = 0; crossing < k_max_cutouts; ++crossing) {
            SurfacePoint hit = scene.intersect(point, directions[k], unbounded, t_min);
            if (!hit.found) break;
            winding += leaves_through(original, hit, directions[k]) ? 1 : -1;
            // past the hit by its own distance's scale (an unbounded ray has no range to scale
            // by; `past` rounds differently and moves some of the engine's samples)
            t_min = std::nextafter(hit.t * (1.0f + 1e-6f) + 1e-30f, unbounded);
        }
        enclosed += winding > 0;
        if (enclosed + (6 - k) < 6) return false; // the rest cannot reach six
    }
    return true;
}

// How far the enclosing surface's facing may turn from the hidden one's for the sample to move
// out to it: a shell around it (nested shells, a ring around a barrel) runs roughly parallel and
// the displaced surface follows it smoothly; a part crossing another at an angle (a bolt through
// a fin, a barrel through a barrel) is enclosed by a surface the sample's neighbours would not
// share, and moving there spans the gap between them with a web. Chosen by measurement (docs/
// RESULTS.md "Surfaces hidden inside closed parts"): 30, 45, 60, 75 degrees and no limit.
constexpr float k_enclosing_turn_degrees = 60.0f;

// Departure from step 1's nearer hit: nested shells and interpenetrating parts put it on a
// surface no eye sees wherever the control mesh lies nearer to that one (assimp's
// UglyVertexColors.lwo: an ellipsoid of three nested shells whose inner ones carry black patches;
// a barrel's length inside the ring it passes through). While the sample's surface (`hit`, at
// `elevation` along `direction` from `origin`) is hidden inside a closed part, it moves out to
// the next surface along the normal, within `range`, that the ray leaves a part through: the one
// enclosing it, where that one faces within k_enclosing_turn_degrees of the hidden one. A surface
// whose outer side is open air keeps the paper's nearer hit, even where a part's far side lies
// further out (a gap between barrels stays a gap, not a web).
SurfacePoint outermost_visible(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction, float range,
                               SurfacePoint hit, float& elevation)
{
    static const float min_cosine = std::cos(glm::radians(k_enclosing_turn_degrees));
    for (int step = 0; step < k_max_cutouts; ++step) {
        // Hidden: the point just off the surface's outer side is enclosed. One short ray decides
        // most surfaces (from the outer side of a visible one it meets open air or enters another
        // part); the candidate and its turn come next, and the full test (seven rays through the
        // whole model) only where the move would otherwise be taken. (A sample moves at most
        // `range`, so a part enclosing it further away could not be taken anyway.)
        const glm::vec3 outward = unit_direction(winding_normal(original, hit));
        const glm::vec3 outside = hit.position + k_on_surface * range * outward;
        SurfacePoint beyond = scene.intersect(outside, outward, 2.0f * range);
        if (!beyond.found || !leaves_through(original, beyond, outward)) return hit;
        // the next surface along the normal that the ray leaves a part through; between a
        // backward hit and the origin there is none (it was the nearest that way)
        float t_min = elevation < 0.0f ? 0.0f : past(elevation, range);
        SurfacePoint next;
        for (int crossing = 0; crossing < k_max_cutouts; ++crossing) {
            next = scene.intersect(origin, direction, range, t_min);
            if (!next.found || leaves_through(original, next, direction)) break;
            t_min = past(next.t, range);
        }
        if (!next.found || glm::dot(outward, unit_direction(winding_normal(original, next))) < min_cosine) return hit;
        if (!inside_closed_part(scene, original, outside)) return hit;
        hit = next;
        elevation = next.t;
    }
    return hit;
}

// How far above a surface another one, facing the same way, hides it as a layer over it: a decal,
// a painted patch, continents modelled over an ocean sphere (assimp's Q3D/earth.q3o, 0.4% of its
// radius above), as a fraction of the ray range (itself 5% of the diagonal by default).
constexpr float k_layer_gap = 0.05f;
// How far the layer's facing may turn from the surface's under it.
constexpr float k_layer_turn_degrees = 30.0f;

// Departure from step 1's nearer hit: where another surface lies a hair above the hit along the
// sample's normal and faces the same way, that one is what an eye on the normal's side sees; the
// nearer hit took the surface under it wherever the control mesh ran on or under the lower one
// (the earth's control vertices are its sphere's, and the continents over it went missing, Luv
// 20.9). Only for surfaces within k_layer_gap x range and k_layer_turn_degrees: a thin wall's other
// side faces the other way, and what lies further out is for the nearer-hit rule to weigh.
SurfacePoint over_layers(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction, float range,
                         SurfacePoint hit, float& elevation)
{
    static const float min_cosine = std::cos(glm::radians(k_layer_turn_degrees));
    float left = k_layer_gap * range; // the layers together lie within the gap of the first hit
    for (int layer = 0; layer < k_max_cutouts; ++layer) {
        const glm::vec3 facing = unit_direction(winding_normal(original, hit));
        if (glm::dot(facing, direction) <= 0.0f) return hit; // seen from the normal's side, a back
        const glm::vec3 above = hit.position + k_on_surface * range * direction;
        SurfacePoint over = scene.intersect(above, direction, left);
        if (!over.found || glm::dot(unit_direction(winding_normal(original, over)), facing) < min_cosine) return hit;
        left -= over.t;
        hit = over;
        elevation = glm::dot(over.position - origin, direction);
    }
    return hit;
}

SurfacePoint nearest_along(const RayScene& scene, const Mesh& original, glm::vec3 origin, glm::vec3 direction, float range,
                           float& elevation, bool& missed, HiddenHit* hidden, bool move_out)
{
    missed = false;
    // a sample on the surface itself (every control vertex is an input vertex) is that point: a ray
    // starting on a face may not report it at t = 0 and meet another part further on (a small
    // ball's vertex inside a large ball took the large ball's surface, 0.2 away)
    SurfacePoint on = scene.closest(origin, k_on_surface * range);
    SurfacePoint forward = on.found ? SurfacePoint{} : scene.intersect(origin, direction, range);
    SurfacePoint backward = on.found ? SurfacePoint{} : scene.intersect(origin, -direction, range);
    if (on.found || forward.found || backward.found) {
        SurfacePoint hit = on.found ? on : nearer_of(forward, backward, elevation);
        if (on.found) elevation = glm::dot(on.position - origin, direction);
        if (!move_out) return hit; // the surface it lies on or meets first (SampleOptions::move_hidden_out)
        hit = over_layers(scene, original, origin, direction, range, hit, elevation);
        const float first_elevation = elevation;
        SurfacePoint visible = outermost_visible(scene, original, origin, direction, range, hit, elevation);
        if (hidden && visible.triangle != hit.triangle) *hidden = {true, first_elevation, hit};
        return visible;
    }
    // nothing within range either way, and not on the surface (above): the closest point's offset
    SurfacePoint closest = scene.closest(origin, std::numeric_limits<float>::infinity());
    elevation = glm::dot(closest.position - origin, direction);
    missed = true;
    return closest;
}

// The original's shading where `hit` lies: its normal, albedo and PBR inputs.
void shade_sample(const Mesh& original, const SurfacePoint& hit, Sample& s)
{
    const std::uint32_t* t = &original.indices[3 * std::size_t(hit.triangle)];
    float b0 = 1.0f - hit.b1 - hit.b2;
    glm::vec3 n = b0 * original.normals[t[0]] + hit.b1 * original.normals[t[1]] + hit.b2 * original.normals[t[2]];
    s.normal = unit_direction(n);
    s.albedo = original.albedo_at(hit.triangle, hit.b1, hit.b2);
    // PBR inputs (issue #14), and the normal bent by a normal map
    const Material& material = original.materials[original.face_materials[hit.triangle]];
    if (material.has_pbr()) {
        s.pbr = original.pbr_at(hit.triangle, hit.b1, hit.b2);
        if (material.normal_texture >= 0) s.normal = unit_direction(original.shading_normal_at(hit.triangle, hit.b1, hit.b2));
    }
}

// `cutouts`: the original has alpha-masked materials, and rays see through their cut-outs.
// `move_out`: a hit under a layer or hidden inside a closed part moves to the layer or the surface
// enclosing it (over_layers, outermost_visible; SampleOptions::move_hidden_out).
Sample sample_at(const Mesh& original, const RayScene& scene, const FacePoint& point, float range, bool cutouts, bool move_out = true)
{
    Sample s;
    glm::vec3 direction = unit_direction(point.normal);
    SurfacePoint hit = cutouts ? nearest_covered_along(scene, original, point.position, direction, range, s.elevation, s.missed, s.covered)
                               : nearest_along(scene, original, point.position, direction, range, s.elevation, s.missed, &s.hidden, move_out);
    if (hit.found) shade_sample(original, hit, s);
    return s;
}

// The sample back on the surface its ray met first (undo_covered_moves).
void take_hidden(const Mesh& original, Sample& s)
{
    s.elevation = s.hidden.elevation;
    s.pbr = PbrSample{};
    shade_sample(original, s.hidden.hit, s);
    s.hidden.moved = false;
    s.kept_first = true;
}

// Pattern vertex (i, j) of a face as fixed-point barycentric weights of corners 1 and 2.
inline std::uint32_t bary(int index, int n) { return std::uint32_t(index) * (k_bary_one / std::uint32_t(n)); }

// Where the displaced surface puts the point of control corners `corner` at weights (q1, q2).
glm::vec3 displaced_point(const ControlGeometry& control, const std::uint32_t corner[3], std::uint32_t q1, std::uint32_t q2, float elevation)
{
    const FacePoint p = face_point(control.positions.data(), control.normals.data(), corner, q1, q2);
    return p.position + elevation * unit_direction(p.normal);
}

// A weight of pattern vertex `index` of an n-segment pattern, moved 3/(32 n) of the way towards the
// face's centroid: a point on a face's edge taken a hair inside the face, so that the face shades a
// crease with its own side (take_own_shading, sample_fine_shading).
double toward_centroid(int index, int n)
{
    const double weight = double(index) / double(n), nudge = 3.0 / (32.0 * double(n));
    return weight + (1.0 / 3.0 - weight) * nudge;
}

// The index among the edge samples (edge-major, n - 1 per edge, in the edge's canonical direction)
// of face f's pattern vertex on its edge `which`, `along` steps from the face's corner `which`.
std::size_t edge_sample_index(const ControlTopology& topology, std::uint32_t f, int which, int along, int n)
{
    const int s = topology.reversed(f, which) ? n - along : along;
    return std::size_t(topology.face_edges[f][std::size_t(which)]) * std::size_t(n - 1) + std::size_t(s - 1);
}

// A sample's values into the finest arrays at `at`.
void store_sample(SampledSurface& out, std::size_t at, const Sample& s, bool cutouts)
{
    out.elevation[at] = s.elevation, out.normal[at] = s.normal, out.albedo[at] = s.albedo;
    if (!out.pbr.empty()) out.pbr[at] = s.pbr;
    if (cutouts) out.coverage[at] = s.covered ? 1 : 0;
}

enum class VertexKind { corner, edge, interior };

// Where pattern vertex (i, j) of a face lives: corner `which`, or edge `which` at position `along`
// (walking from the edge's first corner), or inside.
VertexKind classify(int n, int i, int j, int& which, int& along)
{
    if (i == 0 && j == 0) return which = 0, VertexKind::corner;
    if (i == 0 && j == n) return which = 1, VertexKind::corner;
    if (i == n) return which = 2, VertexKind::corner;
    if (i == 0) return which = 0, along = j, VertexKind::edge;
    if (i + j == n) return which = 1, along = i, VertexKind::edge;
    if (j == 0) return which = 2, along = n - i, VertexKind::edge;
    return VertexKind::interior;
}

// Runs `work(index)` for index in [0, count) on the TBB pool, reporting progress between chunks.
template <typename Work>
void for_each_chunked(std::size_t count, const Progress& progress, const std::string& stage, Work work)
{
    const std::size_t chunk = 4096;
    for (std::size_t start = 0; start < count; start += chunk) {
        std::size_t end = std::min(count, start + chunk);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(start, end), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t i = r.begin(); i != r.end(); ++i) work(i);
        });
        progress.report(stage, double(end) / double(count));
    }
}

// Hat-weighted sums of sub-ray elevations for every pattern vertex of one face (step 2).
void ring_sums(const Mesh& original, const RayScene& scene, const ControlGeometry& control, std::uint32_t face, int n,
               int rays_per_side, float range, bool cutouts, std::vector<double>& sum_wh, std::vector<double>& sum_w)
{
    const std::uint32_t* corner = &control.indices[3 * std::size_t(face)];
    glm::vec3 p[3], nrm[3];
    for (int k = 0; k < 3; ++k) p[k] = control.positions[corner[k]], nrm[k] = control.normals[corner[k]];
    auto add_triangle = [&](int ia, int ja, int ib, int jb, int ic, int jc) {
        std::size_t va = triangle_index(n, ia, ja), vb = triangle_index(n, ib, jb), vc = triangle_index(n, ic, jc);
        const int r = rays_per_side;
        for (int a = 0; a < r; ++a)
            for (int b = 0; b < r - a; ++b)
                for (int down = 0; down < (b < r - a - 1 ? 2 : 1); ++down) {
                    // centroid of a sub-triangle, as weights on the pattern triangle's corners
                    float x = (float(b) + (down ? 2.0f : 1.0f) / 3.0f) / float(r);
                    float y = (float(a) + (down ? 2.0f : 1.0f) / 3.0f) / float(r);
                    float hat[3] = {1.0f - x - y, x, y};
                    // pattern coordinates of the sub-ray, then face weights (w1 = j / n, w2 = i / n)
                    float i = hat[0] * float(ia) + hat[1] * float(ib) + hat[2] * float(ic);
                    float j = hat[0] * float(ja) + hat[1] * float(jb) + hat[2] * float(jc);
                    float w1 = j / float(n), w2 = i / float(n), w0 = 1.0f - w1 - w2;
                    glm::vec3 origin = w0 * p[0] + w1 * p[1] + w2 * p[2];
                    glm::vec3 direction = unit_direction(w0 * nrm[0] + w1 * nrm[1] + w2 * nrm[2]);
                    float h = 0.0f;
                    bool missed = false, covered = true;
                    if (cutouts)
                        nearest_covered_along(scene, original, origin, direction, range, h, missed, covered);
                    else
                        nearest_along(scene, original, origin, direction, range, h, missed);
                    sum_wh[va] += double(hat[0]) * h, sum_w[va] += hat[0];
                    sum_wh[vb] += double(hat[1]) * h, sum_w[vb] += hat[1];
                    sum_wh[vc] += double(hat[2]) * h, sum_w[vc] += hat[2];
                }
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n - i; ++j) {
            add_triangle(i, j, i, j + 1, i + 1, j);
            if (j < n - i - 1) add_triangle(i, j + 1, i + 1, j + 1, i + 1, j);
        }
}

// Whether any face reads a base-colour texture: the models whose samples' colours are prefiltered.
bool has_base_colour_textures(const Mesh& mesh)
{
    if (!mesh.has_texture_coordinates()) return false;
    for (const Material& material : mesh.materials)
        if (material.base_color_texture >= 0) return true;
    return false;
}

// The world length of a texel of a triangle's base-colour texture; infinite without a texture or
// with degenerate texture coordinates.
float triangle_texel_length(const Mesh& mesh, std::uint32_t triangle)
{
    const int texture = mesh.materials[mesh.face_materials[triangle]].base_color_texture;
    const double texels = texture >= 0 && mesh.has_texture_coordinates() ? triangle_texel_area(mesh, triangle, texture) : 0.0;
    return texels > 0.0 ? float(std::sqrt(mesh.triangle_area(triangle) / texels)) : std::numeric_limits<float>::infinity();
}

// Sub-points per side of a sample's cell whose colours are averaged (step 3, prefiltering).
constexpr int k_colour_subsamples = 3;

// The albedo of samples that lie on the original (a leaf card kept whole in the control mesh; any
// textured face of a small model, which keeps every face: bake.cpp default_control_plan),
// averaged over the sample's cell: k x k points spread over one pattern step around it, each the
// point of the original it lies on, weighted by whether it survives the alpha test. A point
// sample of the texture aliases once a face holds more texels than samples (a 256-texel leaf
// texture on a card of 33 samples a side), while the truth reads coverage-weighted mips: this is
// the box filter a mip level applies, at the sample spacing. Samples off the surface (rays that
// travelled) keep their point sample. Returns per sample whether it holds a covered colour.
// `where_texels_finer`: only samples whose triangle's texels are finer than the sample step (a
// textured model's), where a point sample aliases; coarser texels keep the bilinear point sample,
// which is what the truth's level 0 shows magnified (averaged anyway, the bundled box's 64 samples a
// face over about 100 texels came out blurred: Luv 0.77 -> 1.06).
std::vector<std::uint8_t> prefilter_surface_colour(const Mesh& original, const RayScene& scene, const ControlGeometry& control,
                                                   int n, std::size_t per_face, float range, bool where_texels_finer, SampledSurface& out)
{
    const std::size_t faces = control.face_count();
    std::vector<std::uint8_t> has_colour(out.coverage.begin(), out.coverage.end());
    if (out.coverage.empty()) has_colour.assign(faces * per_face, 0); // an opaque model: every point counts
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t face = r.begin(); face != r.end(); ++face) {
            const std::uint32_t* corner = &control.indices[3 * face];
            const glm::vec3 p0 = control.positions[corner[0]], p1 = control.positions[corner[1]], p2 = control.positions[corner[2]];
            auto point_at = [&](float i, float j) {
                float w1 = j / float(n), w2 = i / float(n);
                return (1.0f - w1 - w2) * p0 + w1 * p1 + w2 * p2;
            };
            const float step = (glm::length(p1 - p0) + glm::length(p2 - p1) + glm::length(p0 - p2)) / (3.0f * float(n));
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n - i; ++j) {
                    std::size_t at = face * per_face + triangle_index(n, i, j);
                    SurfacePoint centre = scene.closest(point_at(float(i), float(j)), k_on_surface * range);
                    if (!centre.found) continue;
                    if (where_texels_finer && !(triangle_texel_length(original, centre.triangle) < step)) continue;
                    // most sub-points lie on the centre's triangle: a projection finds them without
                    // a scene query
                    const std::uint32_t* t = &original.indices[3 * std::size_t(centre.triangle)];
                    const glm::vec3 a0 = original.positions[t[0]], a1 = original.positions[t[1]], a2 = original.positions[t[2]];
                    auto on_surface = [&](glm::vec3 q) {
                        SurfacePoint on;
                        glm::vec3 nearest = closest_point_in_triangle(q, a0, a1, a2, on.b1, on.b2);
                        if (glm::length(nearest - q) <= k_on_surface * range) {
                            on.found = true, on.triangle = centre.triangle;
                            return on;
                        }
                        return scene.closest(q, k_on_surface * range);
                    };
                    glm::vec3 sum(0.0f);
                    int covered = 0;
                    for (int a = 0; a < k_colour_subsamples; ++a)
                        for (int b = 0; b < k_colour_subsamples; ++b) {
                            float di = (float(a) + 0.5f) / float(k_colour_subsamples) - 0.5f;
                            float dj = (float(b) + 0.5f) / float(k_colour_subsamples) - 0.5f;
                            float si = std::clamp(float(i) + di, 0.0f, float(n)), sj = std::clamp(float(j) + dj, 0.0f, float(n) - si);
                            SurfacePoint on = on_surface(point_at(si, sj));
                            if (!on.found) continue;
                            // one texture lookup gives colour and alpha (Mesh::covered_at's test)
                            glm::vec4 colour = original.albedo_at(on.triangle, on.b1, on.b2);
                            float cutoff = alpha_test_cutoff(original.materials[original.face_materials[on.triangle]]);
                            if (cutoff > 0.0f && colour.w < cutoff) continue;
                            sum += glm::vec3(colour);
                            ++covered;
                        }
                    if (covered == 0) continue;
                    out.albedo[at] = glm::vec4(sum / float(covered), out.albedo[at].w);
                    has_colour[at] = 1;
                }
        }
    });
    return has_colour;
}

// Cut-out samples take the colour of the covered samples around them (issue #14). A sample on a
// kept leaf card takes the albedo of the point it lies on, and a texture's cut-out texels are
// usually black; the renderer interpolates colour and coverage alike between samples, so a pixel
// whose interpolated coverage passes 1/2 next to a cut-out sample came out darkened towards black
// (the tree's leaves were 9% darker than the truth's, whose mips are coverage-weighted for the same
// reason). Each pass gives every still-uncoloured cut-out sample the mean of its coloured pattern
// neighbours in the same face (alpha kept), as texture tools bleed colour into transparent texels;
// per face, so it is independent of the order faces are visited in.
void bleed_into_cutouts(int n, std::size_t per_face, std::size_t face, const std::vector<std::uint8_t>& has_colour,
                        std::vector<glm::vec4>& albedo)
{
    const std::size_t base = face * per_face;
    std::vector<std::uint8_t> coloured(per_face);
    bool any_cut = false, any_covered = false;
    for (std::size_t k = 0; k < per_face; ++k) {
        coloured[k] = has_colour[base + k];
        any_cut |= coloured[k] == 0;
        any_covered |= coloured[k] != 0;
    }
    if (!any_cut || !any_covered) return;
    static constexpr int k_neighbours[6][2] = {{0, 1}, {0, -1}, {1, 0}, {-1, 0}, {1, -1}, {-1, 1}};
    std::vector<std::pair<std::size_t, glm::vec3>> fills;
    for (int pass = 0; pass < 2 * n; ++pass) {
        fills.clear();
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                std::size_t k = triangle_index(n, i, j);
                if (coloured[k]) continue;
                glm::vec3 sum(0.0f);
                int count = 0;
                for (const auto& d : k_neighbours) {
                    int ni = i + d[0], nj = j + d[1];
                    if (ni < 0 || nj < 0 || ni + nj > n) continue;
                    std::size_t m = triangle_index(n, ni, nj);
                    if (coloured[m]) sum += glm::vec3(albedo[base + m]), ++count;
                }
                if (count > 0) fills.emplace_back(k, sum / float(count));
            }
        if (fills.empty()) break;
        for (const auto& [k, colour] : fills) {
            albedo[base + k] = glm::vec4(colour, albedo[base + k].w);
            coloured[k] = 1;
        }
    }
}

// Step 3's departure: a corner or edge sample is shared by the faces that meet there, so its
// elevation is one (no cracks); its shading need not be, and on a crease it cannot be: a cube's
// edge sample lies on both faces and took either face's normal (and colour), so the pattern
// triangles along every edge of the other face were shaded as its neighbour, in notches
// (docs/RESULTS.md "Shading on both sides of a crease"). Each face reads its own copy of the
// shading arrays, so where the surface a hair inside this face (1/32 of a pattern step towards its
// centre) is shaded otherwise (normals over 10 degrees apart, or a colour channel over 8/255), the
// face's copy takes that shading. Smooth, evenly coloured surfaces keep the shared sample's bytes.
void take_own_shading(const Mesh& original, const RayScene& scene, const ControlGeometry& control, const std::uint32_t corner[3],
                      int n, int i, int j, float range, bool cutouts, bool move_out, Sample& shared)
{
    if (shared.missed) return;
    auto toward_centre = [&](int index) { return std::uint32_t(std::lround(toward_centroid(index, n) * double(k_bary_one))); };
    FacePoint inside = face_point(control.positions.data(), control.normals.data(), corner, toward_centre(j), toward_centre(i));
    Sample own = sample_at(original, scene, inside, range, cutouts, move_out);
    if (shared.kept_first && own.hidden.moved) take_hidden(original, own); // a crease's sample stayed on its part
    if (own.missed || (cutouts && !own.covered)) return; // a cut-out's colour is no shading
    const bool creased = glm::dot(glm::normalize(own.normal), glm::normalize(shared.normal)) < std::cos(glm::radians(10.0f));
    const glm::vec4 colour_step = glm::abs(own.albedo - shared.albedo);
    const bool colour_edge = std::max({colour_step.x, colour_step.y, colour_step.z}) > 8.0f / 255.0f;
    if (!creased && !colour_edge) return;
    shared.normal = own.normal;
    shared.albedo = glm::vec4(glm::vec3(own.albedo), shared.albedo.w); // the alpha is the shared coverage's
    shared.pbr = own.pbr;
}

// Departure (session 27) from outermost_visible's moves: a part sunk into another (a small sphere
// half inside a larger one, a bolt through a fin) has its hidden samples moved onto the other
// part's surface, while its neighbours stay on the part where it shows, and the displaced triangle
// between them bridges the concave crease (a fillet). There the other part's own control faces
// already draw the surface the sample moved to, and the depth test cuts the two parts where they
// cross, so the sample goes back to its first hit. A move stays where nothing else draws that
// surface (nested shells, a core inside a casing, an outer face that met an inner part first).
// "Drawn": the sampled surface of the samples that did not move, on control faces that share no
// vertex with the sample's own, passes within half a pattern step of the moved sample's point.
// Decided once over the first pass's samples, so the result is independent of order and threads.
void undo_covered_moves(const Mesh& original, const ControlGeometry& control, int n, std::size_t per_face,
                        std::vector<Sample>& corners, std::vector<Sample>& edge_samples,
                        std::vector<std::vector<std::pair<std::uint32_t, Sample>>>& moved_inside, SampledSurface& out)
{
    const std::size_t faces = control.face_count();
    bool any = std::any_of(corners.begin(), corners.end(), [](const Sample& s) { return s.hidden.moved; }) ||
               std::any_of(edge_samples.begin(), edge_samples.end(), [](const Sample& s) { return s.hidden.moved; }) ||
               std::any_of(moved_inside.begin(), moved_inside.end(), [](const auto& m) { return !m.empty(); });
    if (!any) return;
    const ControlTopology& topology = control.topology;
    // every sample's point and whether it moved, face-major as `out`
    std::vector<glm::vec3> points(faces * per_face);
    std::vector<float> elevations(faces * per_face);
    std::vector<std::uint8_t> moved(faces * per_face, 0);
    double edge_length = 0.0;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const std::uint32_t* corner = &control.indices[3 * f];
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n - i; ++j) {
                    int which = 0, along = 0;
                    const std::size_t at = f * per_face + triangle_index(n, i, j);
                    VertexKind kind = classify(n, i, j, which, along);
                    float elevation = out.elevation[at];
                    if (kind == VertexKind::corner) {
                        const Sample& s = corners[corner[which]];
                        elevation = s.elevation, moved[at] = s.hidden.moved;
                    } else if (kind == VertexKind::edge) {
                        const Sample& s = edge_samples[edge_sample_index(topology, std::uint32_t(f), which, along, n)];
                        elevation = s.elevation, moved[at] = s.hidden.moved;
                    }
                    points[at] = displaced_point(control, corner, bary(j, n), bary(i, n), elevation);
                    elevations[at] = elevation;
                }
        }
    });
    for (std::size_t f = 0; f < faces; ++f) {
        for (const auto& [k, s] : moved_inside[f]) moved[f * per_face + k] = 1;
        const std::uint32_t* c = &control.indices[3 * f];
        edge_length += glm::length(control.positions[c[1]] - control.positions[c[0]]) +
                       glm::length(control.positions[c[2]] - control.positions[c[1]]) +
                       glm::length(control.positions[c[0]] - control.positions[c[2]]);
    }
    const float radius = float(0.5 * edge_length / double(3 * faces) / double(n));
    // a sample that moved less than that onto the surface its face lies on (a face of the part
    // that encloses the sunk one, whose ray met the sunk part first) draws that surface too
    std::vector<std::uint8_t> drawer(faces * per_face);
    for (std::size_t at = 0; at < drawer.size(); ++at) drawer[at] = !moved[at] || std::abs(elevations[at]) < radius;
    // the sampled surface of samples that stayed where their rays met the original first
    std::vector<std::uint32_t> indices, face_of;
    for (std::size_t f = 0; f < faces; ++f) {
        auto v = [&](int i, int j) { return std::uint32_t(f * per_face + triangle_index(n, i, j)); };
        auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
            if (!drawer[a] || !drawer[b] || !drawer[c]) return;
            indices.insert(indices.end(), {a, b, c});
            face_of.push_back(std::uint32_t(f));
        };
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                add(v(i, j), v(i, j + 1), v(i + 1, j));
                if (j < n - i - 1) add(v(i, j + 1), v(i + 1, j + 1), v(i + 1, j));
            }
    }
    if (indices.empty()) return;
    Result<std::unique_ptr<RayScene>> stayed = RayScene::create(points, indices);
    if (!stayed) return; // embree failed: keep every move
    auto drawn_elsewhere = [&](glm::vec3 point, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        // not by its own faces or their neighbours
        const std::function<bool(std::uint32_t)> elsewhere = [&](std::uint32_t triangle) {
            const std::uint32_t* other = &control.indices[3 * std::size_t(face_of[triangle])];
            for (int k = 0; k < 3; ++k)
                if (other[k] == a || other[k] == b || other[k] == c) return false;
            return true;
        };
        return (*stayed)->closest(point, radius, elsewhere).found;
    };
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, corners.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t v = r.begin(); v != r.end(); ++v) {
            Sample& s = corners[v];
            const std::uint32_t vertex = std::uint32_t(v);
            if (s.hidden.moved && drawn_elsewhere(control.positions[v] + s.elevation * unit_direction(control.normals[v]), vertex, vertex, vertex))
                take_hidden(original, s);
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, topology.edges.size()), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t e = r.begin(); e != r.end(); ++e) {
            const ControlEdge& edge = topology.edges[e];
            const std::uint32_t ends[3] = {edge.lo, edge.hi, edge.hi};
            for (int step = 1; step < n; ++step) {
                Sample& s = edge_samples[e * std::size_t(n - 1) + std::size_t(step - 1)];
                if (s.hidden.moved && drawn_elsewhere(displaced_point(control, ends, bary(step, n), 0, s.elevation), edge.lo, edge.hi, edge.hi))
                    take_hidden(original, s);
            }
        }
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            const std::uint32_t* corner = &control.indices[3 * f];
            for (auto& [k, s] : moved_inside[f]) {
                if (!drawn_elsewhere(points[f * per_face + k], corner[0], corner[1], corner[2])) continue;
                take_hidden(original, s);
                store_sample(out, f * per_face + k, s, false); // (no moves on cut-out models: coverage stays)
            }
        }
    });
}

} // namespace

Result<SampledSurface> sample_surface(const Mesh& original, const RayScene& scene, const ControlGeometry& control,
                                      const SampleOptions& options, const Progress& progress)
{
    if (!is_pattern_degree(options.degree))
        return error(StatusCode::invalid_argument, "degree: " + std::to_string(options.degree) + " is not one of 5, 9, 17, 33");
    const PatternLayout layout(options.degree);
    const int n = layout.segments;
    const std::size_t faces = control.face_count(), per_face = layout.finest_samples;
    const ControlTopology& topology = control.topology;
    const float range = options.ray_range;
    const bool cutouts = reps::has_cutouts(original), move_out = options.move_hidden_out;

    // corners and edges, once each
    std::vector<Sample> corners(control.positions.size());
    for_each_chunked(corners.size(), progress, "sampling corners", [&](std::size_t v) {
        corners[v] = sample_at(original, scene, {control.positions[v], control.normals[v]}, range, cutouts, move_out);
    });
    std::vector<Sample> edge_samples(topology.edges.size() * std::size_t(n - 1));
    for_each_chunked(topology.edges.size(), progress, "sampling edges", [&](std::size_t e) {
        const ControlEdge& edge = topology.edges[e];
        const std::uint32_t ends[3] = {edge.lo, edge.hi, edge.hi};
        for (int s = 1; s < n; ++s) {
            FacePoint point = face_point(control.positions.data(), control.normals.data(), ends, bary(s, n), 0);
            edge_samples[e * std::size_t(n - 1) + std::size_t(s - 1)] = sample_at(original, scene, point, range, cutouts, move_out);
        }
    });

    // faces: interior samples, and the shared ones copied in
    SampledSurface out;
    out.elevation.assign(faces * per_face, 0.0f);
    out.normal.assign(faces * per_face, glm::vec3(0.0f));
    out.albedo.assign(faces * per_face, glm::vec4(0.0f));
    if (original.has_pbr_materials()) out.pbr.assign(faces * per_face, PbrSample{});
    if (cutouts) out.coverage.assign(faces * per_face, 0);
    std::vector<std::uint8_t> missed(faces * per_face, 0);
    auto shared_sample = [&](std::uint32_t f, VertexKind kind, int which, int along) -> const Sample& {
        if (kind == VertexKind::corner) return corners[control.indices[3 * std::size_t(f) + std::size_t(which)]];
        return edge_samples[edge_sample_index(topology, f, which, along, n)];
    };
    // interior samples first, the moved ones' first hits kept aside; then the moves that made a
    // fillet are undone (undo_covered_moves); then the shared samples are copied in
    std::vector<std::vector<std::pair<std::uint32_t, Sample>>> moved_inside(faces);
    for_each_chunked(faces, progress, "sampling faces", [&](std::size_t face) {
        const std::uint32_t* corner = &control.indices[3 * face];
        for (int i = 1; i < n; ++i)
            for (int j = 1; j < n - i; ++j) {
                Sample s = sample_at(original, scene,
                                     face_point(control.positions.data(), control.normals.data(), corner, bary(j, n), bary(i, n)),
                                     range, cutouts, move_out);
                std::size_t at = face * per_face + triangle_index(n, i, j);
                store_sample(out, at, s, cutouts);
                missed[at] = s.missed;
                if (s.hidden.moved) moved_inside[face].emplace_back(std::uint32_t(triangle_index(n, i, j)), s);
            }
    });
    undo_covered_moves(original, control, n, per_face, corners, edge_samples, moved_inside, out);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t face = r.begin(); face != r.end(); ++face) {
            std::uint32_t f = std::uint32_t(face);
            const std::uint32_t* corner = &control.indices[3 * face];
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n - i; ++j) {
                    int which = 0, along = 0;
                    VertexKind kind = classify(n, i, j, which, along);
                    if (kind == VertexKind::interior) continue;
                    Sample s = shared_sample(f, kind, which, along);
                    take_own_shading(original, scene, control, corner, n, i, j, range, cutouts, move_out, s);
                    store_sample(out, face * per_face + triangle_index(n, i, j), s, cutouts);
                }
        }
    });
    if (cutouts) {
        std::vector<std::uint8_t> has_colour = prefilter_surface_colour(original, scene, control, n, per_face, range, false, out);
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
            for (std::size_t f = r.begin(); f != r.end(); ++f) bleed_into_cutouts(n, per_face, f, has_colour, out.albedo);
        });
    }
    std::size_t interior_per_face = per_face - 3 * std::size_t(n);
    out.rays = 2 * (corners.size() + edge_samples.size() + faces * interior_per_face);
    for (const Sample& s : corners) out.misses += s.missed;
    for (const Sample& s : edge_samples) out.misses += s.missed;
    for (std::uint8_t m : missed) out.misses += m;

    if (options.sampler == "interpolation") {
        // hat-weighted sums per face, then per edge and per corner in increasing face order
        int r = int(std::lround(std::sqrt(double(options.interpolation_rays))));
        std::vector<double> sum_wh(faces * per_face, 0.0), sum_w(faces * per_face, 0.0);
        for_each_chunked(faces, progress, "interpolation sampling", [&](std::size_t f) {
            std::vector<double> wh(per_face, 0.0), w(per_face, 0.0);
            ring_sums(original, scene, control, std::uint32_t(f), n, r, range, cutouts, wh, w);
            std::copy(wh.begin(), wh.end(), sum_wh.begin() + std::ptrdiff_t(f * per_face));
            std::copy(w.begin(), w.end(), sum_w.begin() + std::ptrdiff_t(f * per_face));
        });
        out.rays += 2 * faces * std::size_t(n) * std::size_t(n) * std::size_t(r) * std::size_t(r);
        auto local_index = [&](std::uint32_t f, int which, int canonical_s) {
            int along = topology.reversed(f, which) ? n - canonical_s : canonical_s;
            int i = 0, j = 0;
            edge_vertex(n, which, along, i, j);
            return std::size_t(f) * per_face + triangle_index(n, i, j);
        };
        std::vector<float> corner_h(control.positions.size()), edge_h(edge_samples.size());
        for (std::size_t v = 0; v < corner_h.size(); ++v) {
            double wh = 0.0, w = 0.0;
            for (std::uint32_t f : topology.vertex_faces[v]) {
                int k = 0;
                while (control.indices[3 * std::size_t(f) + std::size_t(k)] != v) ++k;
                int i = 0, j = 0;
                edge_vertex(n, k, 0, i, j);
                wh += sum_wh[std::size_t(f) * per_face + triangle_index(n, i, j)];
                w += sum_w[std::size_t(f) * per_face + triangle_index(n, i, j)];
            }
            corner_h[v] = w > 0.0 ? float(wh / w) : corners[v].elevation;
        }
        for (std::size_t e = 0; e < topology.edges.size(); ++e)
            for (int s = 1; s < n; ++s) {
                double wh = 0.0, w = 0.0;
                for (std::uint32_t f : topology.edges[e].faces) {
                    int which = 0;
                    while (topology.face_edges[f][std::size_t(which)] != e) ++which;
                    std::size_t at = local_index(f, which, s);
                    wh += sum_wh[at], w += sum_w[at];
                }
                edge_h[e * std::size_t(n - 1) + std::size_t(s - 1)] = float(wh / w);
            }
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& range_f) {
            for (std::size_t f = range_f.begin(); f != range_f.end(); ++f)
                for (int i = 0; i <= n; ++i)
                    for (int j = 0; j <= n - i; ++j) {
                        int which = 0, along = 0;
                        VertexKind kind = classify(n, i, j, which, along);
                        std::size_t at = f * per_face + triangle_index(n, i, j);
                        if (kind == VertexKind::interior) {
                            out.elevation[at] = float(sum_wh[at] / sum_w[at]);
                        } else if (kind == VertexKind::corner) {
                            out.elevation[at] = corner_h[control.indices[3 * f + std::size_t(which)]];
                        } else {
                            out.elevation[at] = edge_h[edge_sample_index(topology, std::uint32_t(f), which, along, n)];
                        }
                    }
        });
    }
    return out;
}

SampledSurface sample_fine_shading(const Mesh& original, const RayScene& scene, const ControlGeometry& control,
                                   const SampledSurface& coarse, int degree, int detail, float range, const Progress& progress)
{
    const PatternLayout layout(degree);
    const int n = layout.segments, fine_n = n * detail;
    const std::size_t faces = control.face_count(), per_coarse = layout.finest_samples, per_fine = triangle_samples(fine_n);
    SampledSurface out;
    out.normal.assign(faces * per_fine, glm::vec3(0.0f));
    out.albedo.assign(faces * per_fine, glm::vec4(0.0f));
    const bool pbr = !coarse.pbr.empty(), cutouts = !coarse.coverage.empty();
    if (pbr) out.pbr.assign(faces * per_fine, PbrSample{});
    if (cutouts) out.coverage.assign(faces * per_fine, 0);
    for_each_chunked(faces, progress, "sampling shading", [&](std::size_t face) {
        const std::uint32_t* corner = &control.indices[3 * face];
        const std::size_t coarse_base = face * per_coarse, fine_base = face * per_fine;
        for (int a = 0; a <= fine_n; ++a)
            for (int b = 0; b <= fine_n - a; ++b) {
                const std::size_t at = fine_base + triangle_index(fine_n, a, b);
                if (a % detail == 0 && b % detail == 0) {
                    const std::size_t from = coarse_base + triangle_index(n, a / detail, b / detail);
                    out.normal[at] = coarse.normal[from], out.albedo[at] = coarse.albedo[from];
                    if (pbr) out.pbr[at] = coarse.pbr[from];
                    if (cutouts) out.coverage[at] = coarse.coverage[from];
                    continue;
                }
                // the fine point's weights on corners 1 and 2, a hair inside the face on its edges
                const bool on_edge = a == 0 || b == 0 || a + b == fine_n;
                const double w1 = on_edge ? toward_centroid(b, fine_n) : double(b) / double(fine_n);
                const double w2 = on_edge ? toward_centroid(a, fine_n) : double(a) / double(fine_n);
                // the finest pattern triangle holding it (the renderer's split), and its weights
                const PatternTriangle cell = pattern_triangle(n, w1 * n, w2 * n);
                const std::size_t* index = cell.index;
                const double* weight = cell.weight;
                double elevation = 0.0;
                for (int k = 0; k < 3; ++k) elevation += weight[k] * coarse.elevation[coarse_base + index[k]];
                const glm::vec3 drawn = displaced_point(control, corner, std::uint32_t(std::lround(w1 * double(k_bary_one))),
                                                        std::uint32_t(std::lround(w2 * double(k_bary_one))), float(elevation));
                // coverage: where the drawn point lies on the original (a leaf card kept whole),
                // the alpha test there; elsewhere (surfaces the rays reached through cut-outs) the
                // pattern's coverage as the renderer interpolates it
                double blended_coverage = 0.0;
                if (cutouts)
                    for (int k = 0; k < 3; ++k) blended_coverage += weight[k] * double(coarse.coverage[coarse_base + index[k]]);
                // first within k_on_surface of the drawn point: on a card kept whole that finds it
                // after a few triangles, where a query as wide as the ray range visits every card
                // whose box it reaches (3/4 of a dense bush's bake). The same point: the closest
                // within the range lies within the small radius whenever anything does.
                SurfacePoint on = scene.closest(drawn, k_on_surface * range);
                if (!on.found) on = scene.closest(drawn, range);
                if (on.found) {
                    Sample s;
                    shade_sample(original, on, s);
                    out.normal[at] = s.normal, out.albedo[at] = s.albedo;
                    if (pbr) out.pbr[at] = s.pbr;
                    if (cutouts)
                        out.coverage[at] = on.distance <= k_on_surface * range ? std::uint8_t(original.covered_at(on.triangle, on.b1, on.b2))
                                                                               : std::uint8_t(blended_coverage >= 0.5);
                    continue;
                }
                if (cutouts) out.coverage[at] = std::uint8_t(blended_coverage >= 0.5);
                // nothing within the ray range (the coarse samples missed too): theirs, blended
                glm::vec3 normal(0.0f);
                glm::vec4 albedo(0.0f);
                for (int k = 0; k < 3; ++k) {
                    normal += float(weight[k]) * coarse.normal[coarse_base + index[k]];
                    albedo += float(weight[k]) * coarse.albedo[coarse_base + index[k]];
                }
                out.normal[at] = unit_direction(normal), out.albedo[at] = albedo;
                if (pbr) out.pbr[at] = coarse.pbr[coarse_base + index[0]];
            }
        // cut-out points read the texture's cut-out colour (black in most files): the covered
        // colours around them are bled in, as on the pattern (bleed_into_cutouts)
        if (cutouts) bleed_into_cutouts(fine_n, per_fine, face, out.coverage, out.albedo);
    });
    return out;
}

double triangle_texel_area(const Mesh& mesh, std::size_t triangle, int texture)
{
    const Texture& t = mesh.textures[std::size_t(texture)];
    const std::uint32_t* v = &mesh.indices[3 * triangle];
    const glm::dvec2 a(mesh.uvs[v[0]]), e1 = glm::dvec2(mesh.uvs[v[1]]) - a, e2 = glm::dvec2(mesh.uvs[v[2]]) - a;
    return 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x) * double(t.width) * double(t.height);
}

void prefilter_texture_colour(const Mesh& original, const RayScene& scene, const ControlGeometry& control, int segments, float range,
                              SampledSurface& shading)
{
    if (reps::has_cutouts(original) || !has_base_colour_textures(original)) return;
    prefilter_surface_colour(original, scene, control, segments, triangle_samples(segments), range, true, shading);
}

Quantisation choose_quantisation(const std::vector<float>& values, float min_step)
{
    Quantisation q;
    if (values.empty()) return q;
    auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    q.minimum = *lo;
    q.step = std::max((*hi - *lo) / 65535.0f, min_step);
    return q;
}

std::vector<std::uint16_t> quantise(const std::vector<float>& values, const Quantisation& q)
{
    std::vector<std::uint16_t> codes(values.size(), 0);
    if (!(q.step > 0.0f)) return codes;
    for (std::size_t i = 0; i < values.size(); ++i) {
        double code = std::round((double(values[i]) - double(q.minimum)) / double(q.step));
        codes[i] = std::uint16_t(std::clamp(code, 0.0, 65535.0));
    }
    return codes;
}

Mesh reconstruct(const ControlGeometry& control, const PatternLayout& layout, const std::vector<float>& finest_elevation)
{
    const int n = layout.segments;
    const std::size_t faces = control.face_count(), per_face = layout.finest_samples;
    Mesh ms;
    ms.positions.resize(faces * per_face);
    ms.indices.reserve(faces * std::size_t(n) * std::size_t(n) * 3);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f)
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n - i; ++j) {
                    std::size_t at = f * per_face + triangle_index(n, i, j);
                    ms.positions[at] = displaced_point(control, &control.indices[3 * f], bary(j, n), bary(i, n), finest_elevation[at]);
                }
    });
    for (std::size_t f = 0; f < faces; ++f) {
        auto v = [&](int i, int j) { return std::uint32_t(f * per_face + triangle_index(n, i, j)); };
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n - i; ++j) {
                ms.indices.insert(ms.indices.end(), {v(i, j), v(i, j + 1), v(i + 1, j)});
                if (j < n - i - 1) ms.indices.insert(ms.indices.end(), {v(i, j + 1), v(i + 1, j + 1), v(i + 1, j)});
            }
    }
    ms.colors.assign(ms.positions.size(), glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
    ms.face_materials.assign(ms.triangle_count(), 0);
    ms.materials.push_back(Material{});
    compute_smooth_normals(ms);
    return ms;
}

Result<SamplingError> measure_sampling_error(const Mesh& original, const RayScene& original_scene, const Mesh& sampled,
                                             std::size_t control_faces, int degree, const Progress& progress)
{
    Result<std::unique_ptr<RayScene>> sampled_scene = RayScene::create(sampled.positions, sampled.indices);
    if (!sampled_scene) return sampled_scene.status();
    const std::size_t triangles_per_face = std::size_t(degree - 1) * std::size_t(degree - 1);
    // both meshes lie within a sampling error of each other: searched that near first
    const float near = 1e-3f * original.bounds().diagonal();

    // original -> Ms: the paper's d, and ∆_f by the face holding each vertex's closest point
    std::vector<float> distance(original.vertex_count());
    std::vector<std::uint32_t> face_of(original.vertex_count());
    for_each_chunked(original.vertex_count(), progress, "measuring the sampled mesh", [&](std::size_t v) {
        SurfacePoint c = (*sampled_scene)->closest_anywhere(original.positions[v], near);
        distance[v] = c.distance;
        face_of[v] = std::uint32_t(c.triangle / triangles_per_face);
    });
    SamplingError out;
    out.face_error.assign(control_faces, 0.0f);
    double sum = 0.0;
    for (std::size_t v = 0; v < distance.size(); ++v) {
        sum += distance[v];
        out.original_to_sampled_max = std::max(out.original_to_sampled_max, double(distance[v]));
        out.face_error[face_of[v]] = std::max(out.face_error[face_of[v]], distance[v]);
    }
    out.original_to_sampled_mean = distance.empty() ? 0.0 : sum / double(distance.size());

    // Ms -> original, over Ms's vertices
    std::vector<float> back(sampled.vertex_count());
    for_each_chunked(sampled.vertex_count(), progress, "measuring the original", [&](std::size_t v) {
        back[v] = original_scene.closest_anywhere(sampled.positions[v], near).distance;
    });
    sum = 0.0;
    for (float d : back) {
        sum += d;
        out.sampled_to_original_max = std::max(out.sampled_to_original_max, double(d));
    }
    out.sampled_to_original_mean = back.empty() ? 0.0 : sum / double(back.size());
    return out;
}

} // namespace standin::displaced_mesh
