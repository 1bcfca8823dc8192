// Control mesh by quadric edge collapse under a per-vertex normal-cone constraint.
// Bauman, Livny & El-Sana, "GPU-Based Adaptive-Subdivision for View-Dependent Rendering", §3
// (x~y~-monotone patches, the normal-cone validity rule) and §4 (Garland & Heckbert 1997 quadrics).
//
// Steps:
//  1. weld vertices by exact position and drop faces that collapse to an edge; with
//     keep_cutout_faces, lock the vertices of faces of alpha-masked materials (departure, issue
//     #14: leaf cards are the surface the cut-outs live on, and a card collapsed to one triangle
//     loses half its leaves; the rest of the model is simplified as before);
//  2. find boundary and non-manifold edges (vertices on non-manifold edges never move), and the
//     boundary loops the boundary edges form;
//  3. one quadric per vertex: area-weighted face planes plus a perpendicular plane per boundary
//     edge (Garland & Heckbert 1997);
//  4. one normal cone per vertex holding the normals of its faces;
//  5. repeatedly collapse the cheapest edge (half-edge collapse: the endpoint of lower quadric error
//     is kept, so control vertices lie on the input) if it is valid: topology (link condition, no
//     boundary pinching), no face turning by more than 90 degrees, and no cone of the kept vertex or
//     of its neighbours reaching the cone angle (the paper: "exceeds a half-sphere"), and no
//     boundary loop falling below min_loop_vertices (departure: on a model of many small open
//     sheets, a flange, a tube rim, the quadrics alone took round holes and outlines down to
//     triangles, which no displacement along the normal can bring back; the paper's models are
//     closed);
//  6. stop at the target face count or when no valid collapse remains (reported);
//  7. compact, and give every control vertex the area-weighted normal of its faces.
//
// Choices where the paper is silent (docs/ARCHITECTURE.md, "Displaced control mesh"):
// - Half-edge collapse rather than the optimal quadric position: corners then lie on the input
//   (elevation 0 there), the result is a subset of the input's vertices and needs no solve.
// - Cones are per vertex as the paper writes (OpenMesh's ModNormalDeviationT keeps them per face):
//   the kept vertex's cone absorbs the removed vertex's cone and the new normals of the faces that
//   moved; every vertex of a face whose normal changed absorbs the new normal. Cones only grow, so
//   a cone always holds every normal its vertex's faces ever had, the collapsed ones included.
// - meshoptimizer's simplifier has no hook for a per-collapse constraint, hence this file.
// - Deterministic: one thread, a heap ordered by (error, vertex, vertex), lazy invalidation by a
//   per-vertex version. An edge refused now is looked at again when a neighbour of it changes.
#include "reps/displaced_mesh/control_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <queue>
#include <unordered_map>

namespace standin::displaced_mesh {

bool NormalCone::contains(glm::vec3 direction, float slack) const
{
    if (empty()) return false;
    float angle = std::acos(std::clamp(glm::dot(axis, direction), -1.0f, 1.0f));
    return angle <= half_angle + slack;
}

NormalCone merge_cones(const NormalCone& a, const NormalCone& b)
{
    if (a.empty()) return b;
    if (b.empty()) return a;
    float phi = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
    if (phi + b.half_angle <= a.half_angle) return a;
    if (phi + a.half_angle <= b.half_angle) return b;
    NormalCone out;
    out.half_angle = 0.5f * (phi + a.half_angle + b.half_angle);
    if (out.half_angle >= 0.5f * std::numbers::pi_v<float> || phi < 1e-6f) {
        out.axis = a.axis;
        return out;
    }
    // turn a's axis towards b's by the growth of the half-angle (slerp on the great circle)
    float turn = out.half_angle - a.half_angle;
    glm::vec3 axis = (std::sin(phi - turn) * a.axis + std::sin(turn) * b.axis) / std::sin(phi);
    out.axis = glm::normalize(axis);
    return out;
}

NormalCone merge_direction(const NormalCone& a, glm::vec3 unit_direction) { return merge_cones(a, {unit_direction, 0.0f}); }

namespace {

constexpr double k_boundary_weight = 10.0; // boundary planes weigh ten times a face of the same size

struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0;

    void add_plane(glm::dvec3 n, double d, double weight)
    {
        a00 += weight * n.x * n.x, a01 += weight * n.x * n.y, a02 += weight * n.x * n.z;
        a11 += weight * n.y * n.y, a12 += weight * n.y * n.z, a22 += weight * n.z * n.z;
        b0 += weight * n.x * d, b1 += weight * n.y * d, b2 += weight * n.z * d;
        c += weight * d * d;
    }
    void add(const Quadric& q)
    {
        a00 += q.a00, a01 += q.a01, a02 += q.a02, a11 += q.a11, a12 += q.a12, a22 += q.a22;
        b0 += q.b0, b1 += q.b1, b2 += q.b2, c += q.c;
    }
    double error(glm::dvec3 p) const
    {
        double e = a00 * p.x * p.x + a11 * p.y * p.y + a22 * p.z * p.z +
                   2.0 * (a01 * p.x * p.y + a02 * p.x * p.z + a12 * p.y * p.z) +
                   2.0 * (b0 * p.x + b1 * p.y + b2 * p.z) + c;
        return std::max(e, 0.0);
    }
};

struct Candidate {
    double cost;
    std::uint32_t from, to;           // collapse `from` onto `to`
    std::uint32_t from_version, to_version;
    bool reverse_tried;               // the other direction was refused already
};

struct CostOrder {
    bool operator()(const Candidate& a, const Candidate& b) const
    {
        // std::priority_queue pops the largest: "larger" = costlier, then higher indices
        if (a.cost != b.cost) return a.cost > b.cost;
        if (a.from != b.from) return a.from > b.from;
        return a.to > b.to;
    }
};

enum class Refusal { none, stale, topology, flip, cone };

class Simplifier final : public CollapseView {
public:
    Simplifier(const Mesh& mesh, const ControlMeshOptions& options);
    ControlMesh run();

    // CollapseView
    std::uint32_t kept_vertex() const override { return kept_; }
    const std::vector<std::uint32_t>& affected_vertices() const override { return affected_; }
    NormalCone cone(std::uint32_t vertex) const override { return cones_[vertex]; }
    std::vector<glm::vec3> face_normals_around(std::uint32_t vertex) const override
    {
        std::vector<glm::vec3> out;
        for (std::uint32_t f : faces_of_[vertex])
            if (glm::vec3 n = face_normal(f); n != glm::vec3(0.0f)) out.push_back(n);
        return out;
    }

private:
    void weld(const Mesh& mesh);
    void classify_edges();
    void build_quadrics_and_cones();
    void push_edges_of(std::uint32_t vertex);
    void push_candidate(std::uint32_t a, std::uint32_t b, bool reverse_tried);
    Refusal try_collapse(std::uint32_t from, std::uint32_t to, bool commit);
    ControlMesh compact() const;

    glm::vec3 face_normal(std::uint32_t f) const
    {
        const std::uint32_t* t = &faces_[3 * std::size_t(f)];
        glm::vec3 n = glm::cross(positions_[t[1]] - positions_[t[0]], positions_[t[2]] - positions_[t[0]]);
        float length = glm::length(n);
        return length > 0.0f ? n / length : glm::vec3(0.0f);
    }

    const ControlMeshOptions& options_;
    float cone_limit_ = 0.0f; // radians
    std::vector<glm::vec3> positions_;
    std::vector<std::uint32_t> faces_;
    std::vector<bool> face_alive_;
    std::vector<std::vector<std::uint32_t>> faces_of_;
    std::vector<Quadric> quadrics_;
    std::vector<NormalCone> cones_;
    std::vector<std::uint32_t> version_;
    std::vector<bool> vertex_alive_, locked_, boundary_, waiting_;
    // boundary loops: each boundary vertex's loop (joined through boundary edges) and how many
    // live vertices each loop has
    std::vector<std::uint32_t> loop_of_, loop_size_;
    std::priority_queue<Candidate, std::vector<Candidate>, CostOrder> heap_;
    std::size_t live_faces_ = 0;
    ControlMesh stats_;
    // the last collapse, for the observer
    std::uint32_t kept_ = 0;
    std::vector<std::uint32_t> affected_;
};

Simplifier::Simplifier(const Mesh& mesh, const ControlMeshOptions& options) : options_(options)
{
    cone_limit_ = glm::radians(options.cone_angle_degrees);
    weld(mesh);
    classify_edges();
    build_quadrics_and_cones();
}

void Simplifier::weld(const Mesh& mesh)
{
    struct Key {
        std::uint32_t x, y, z;
        bool operator==(const Key&) const = default;
    };
    struct KeyHash {
        std::size_t operator()(const Key& k) const
        {
            return std::size_t(k.x) * 73856093u ^ std::size_t(k.y) * 19349663u ^ std::size_t(k.z) * 83492791u;
        }
    };
    std::unordered_map<Key, std::uint32_t, KeyHash> index_of;
    index_of.reserve(mesh.vertex_count());
    std::vector<std::uint32_t> remap(mesh.vertex_count());
    for (std::size_t i = 0; i < mesh.vertex_count(); ++i) {
        glm::vec3 p = mesh.positions[i] + glm::vec3(0.0f); // -0 and +0 weld
        Key key;
        std::memcpy(&key.x, &p.x, 4), std::memcpy(&key.y, &p.y, 4), std::memcpy(&key.z, &p.z, 4);
        auto [it, inserted] = index_of.try_emplace(key, std::uint32_t(positions_.size()));
        if (inserted) positions_.push_back(p);
        remap[i] = it->second;
    }
    faces_.reserve(mesh.indices.size());
    std::vector<std::uint32_t> cutout_vertices;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        std::uint32_t a = remap[mesh.indices[3 * t]], b = remap[mesh.indices[3 * t + 1]], c = remap[mesh.indices[3 * t + 2]];
        if (a == b || b == c || a == c) continue;
        faces_.insert(faces_.end(), {a, b, c});
        if (options_.keep_cutout_faces && alpha_test_cutoff(mesh.materials[mesh.face_materials[t]]) > 0.0f)
            cutout_vertices.insert(cutout_vertices.end(), {a, b, c});
    }
    std::size_t face_count = faces_.size() / 3;
    face_alive_.assign(face_count, true);
    live_faces_ = face_count;
    stats_.input_faces = face_count;
    faces_of_.assign(positions_.size(), {});
    for (std::uint32_t f = 0; f < face_count; ++f)
        for (int k = 0; k < 3; ++k) faces_of_[faces_[3 * std::size_t(f) + k]].push_back(f);
    vertex_alive_.assign(positions_.size(), true);
    version_.assign(positions_.size(), 0);
    locked_.assign(positions_.size(), false);
    boundary_.assign(positions_.size(), false);
    waiting_.assign(positions_.size(), false);
    for (std::uint32_t v : cutout_vertices) locked_[v] = true;
}

// Boundary edges (one face) get quadric planes; vertices of non-manifold edges (three or more
// faces) are locked, since a collapse around them has no well-defined link.
void Simplifier::classify_edges()
{
    struct Edge {
        std::uint32_t lo, hi;
        bool operator<(const Edge& o) const { return lo != o.lo ? lo < o.lo : hi < o.hi; }
        bool operator==(const Edge& o) const { return lo == o.lo && hi == o.hi; }
    };
    std::vector<Edge> edges;
    edges.reserve(faces_.size());
    for (std::size_t f = 0; f < faces_.size() / 3; ++f)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = faces_[3 * f + k], b = faces_[3 * f + (k + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    std::sort(edges.begin(), edges.end());
    // boundary loops by union-find over boundary edges (a vertex where two loops touch joins them)
    std::vector<std::uint32_t> parent(positions_.size());
    for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = v;
    auto root = [&](std::uint32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
    };
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) {
            boundary_[edges[i].lo] = boundary_[edges[i].hi] = true;
            std::uint32_t a = root(edges[i].lo), b = root(edges[i].hi);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
        if (j - i > 2) locked_[edges[i].lo] = locked_[edges[i].hi] = true;
        i = j;
    }
    loop_of_.assign(positions_.size(), UINT32_MAX);
    loop_size_.assign(positions_.size(), 0);
    for (std::uint32_t v = 0; v < positions_.size(); ++v)
        if (boundary_[v]) ++loop_size_[loop_of_[v] = root(v)];
}

void Simplifier::build_quadrics_and_cones()
{
    quadrics_.assign(positions_.size(), {});
    cones_.assign(positions_.size(), {});
    for (std::uint32_t f = 0; f < face_alive_.size(); ++f) {
        const std::uint32_t* t = &faces_[3 * std::size_t(f)];
        glm::dvec3 p0(positions_[t[0]]), p1(positions_[t[1]]), p2(positions_[t[2]]);
        glm::dvec3 n = glm::cross(p1 - p0, p2 - p0);
        double twice_area = glm::length(n);
        if (twice_area <= 0.0) continue;
        n /= twice_area;
        Quadric q;
        q.add_plane(n, -glm::dot(n, p0), 0.5 * twice_area);
        glm::vec3 normal(n);
        for (int k = 0; k < 3; ++k) {
            quadrics_[t[k]].add(q);
            cones_[t[k]] = merge_direction(cones_[t[k]], normal);
        }
        // boundary edges: a plane through the edge, perpendicular to the face
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = t[k], b = t[(k + 1) % 3];
            if (!boundary_[a] || !boundary_[b]) continue;
            int shared = 0;
            for (std::uint32_t g : faces_of_[a]) {
                const std::uint32_t* s = &faces_[3 * std::size_t(g)];
                shared += (s[0] == b || s[1] == b || s[2] == b);
            }
            if (shared != 1) continue;
            glm::dvec3 pa(positions_[a]), pb(positions_[b]);
            glm::dvec3 edge = pb - pa;
            glm::dvec3 m = glm::cross(edge, n);
            double length = glm::length(m);
            if (length <= 0.0) continue;
            m /= length;
            Quadric e;
            e.add_plane(m, -glm::dot(m, pa), k_boundary_weight * glm::dot(edge, edge));
            quadrics_[a].add(e);
            quadrics_[b].add(e);
        }
    }
}

void Simplifier::push_candidate(std::uint32_t a, std::uint32_t b, bool reverse_tried)
{
    Quadric q = quadrics_[a];
    q.add(quadrics_[b]);
    double cost_ab = q.error(glm::dvec3(positions_[b])); // a moves onto b
    double cost_ba = q.error(glm::dvec3(positions_[a]));
    bool a_moves = cost_ab < cost_ba || (cost_ab == cost_ba && a > b);
    if (locked_[a] || locked_[b]) return;
    std::uint32_t from = a_moves ? a : b, to = a_moves ? b : a;
    heap_.push({a_moves ? cost_ab : cost_ba, from, to, version_[from], version_[to], reverse_tried});
}

void Simplifier::push_edges_of(std::uint32_t vertex)
{
    std::vector<std::uint32_t> ring;
    for (std::uint32_t f : faces_of_[vertex])
        for (int k = 0; k < 3; ++k)
            if (std::uint32_t w = faces_[3 * std::size_t(f) + k]; w != vertex) ring.push_back(w);
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (std::uint32_t w : ring) push_candidate(vertex, w, false);
}

Refusal Simplifier::try_collapse(std::uint32_t from, std::uint32_t to, bool commit)
{
    if (!vertex_alive_[from] || !vertex_alive_[to] || locked_[from] || locked_[to]) return Refusal::stale;
    const std::vector<std::uint32_t>& faces_from = faces_of_[from];

    // the faces on the edge, and the link condition: the common neighbours of both endpoints must be
    // exactly the third vertices of those faces (else the collapse pinches the surface)
    std::vector<std::uint32_t> shared, opposite, ring_from, ring_to;
    for (std::uint32_t f : faces_from) {
        const std::uint32_t* t = &faces_[3 * std::size_t(f)];
        bool has_to = t[0] == to || t[1] == to || t[2] == to;
        for (int k = 0; k < 3; ++k) {
            if (t[k] == from) continue;
            ring_from.push_back(t[k]);
            if (has_to && t[k] != to) opposite.push_back(t[k]);
        }
        if (has_to) shared.push_back(f);
    }
    if (shared.empty()) return Refusal::stale; // the edge is gone
    if (shared.size() > 2) return Refusal::topology;
    if (boundary_[from] && shared.size() != 1) return Refusal::topology; // would pull the boundary inside
    // a loop at its floor keeps its outline (a collapse along the boundary removes one of its vertices)
    if (boundary_[from] && loop_size_[loop_of_[from]] <= options_.min_loop_vertices) return Refusal::topology;
    for (std::uint32_t f : faces_of_[to])
        for (int k = 0; k < 3; ++k)
            if (std::uint32_t w = faces_[3 * std::size_t(f) + k]; w != to) ring_to.push_back(w);
    std::sort(ring_from.begin(), ring_from.end());
    ring_from.erase(std::unique(ring_from.begin(), ring_from.end()), ring_from.end());
    std::sort(ring_to.begin(), ring_to.end());
    ring_to.erase(std::unique(ring_to.begin(), ring_to.end()), ring_to.end());
    std::sort(opposite.begin(), opposite.end());
    std::vector<std::uint32_t> common;
    std::set_intersection(ring_from.begin(), ring_from.end(), ring_to.begin(), ring_to.end(), std::back_inserter(common));
    if (common != opposite) return Refusal::topology;
    // no vertex may be left with fewer faces than a fan needs (valence-2 vertices fold over)
    std::size_t kept_faces = faces_from.size() + faces_of_[to].size() - 2 * shared.size();
    if (kept_faces < (boundary_[to] ? 1u : 3u)) return Refusal::topology;
    for (std::uint32_t o : opposite)
        if (faces_of_[o].size() - 1 < (boundary_[o] ? 1u : 3u)) return Refusal::topology;

    // the faces that move with `from`: no flip beyond 90 degrees, no degenerate result
    glm::vec3 p_to = positions_[to];
    std::vector<std::pair<std::uint32_t, glm::vec3>> moved; // face, its new unit normal
    for (std::uint32_t f : faces_from) {
        if (std::find(shared.begin(), shared.end(), f) != shared.end()) continue;
        const std::uint32_t* t = &faces_[3 * std::size_t(f)];
        glm::vec3 p[3];
        for (int k = 0; k < 3; ++k) p[k] = t[k] == from ? p_to : positions_[t[k]];
        glm::vec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
        float length = glm::length(n);
        if (!(length > 0.0f)) return Refusal::flip;
        n /= length;
        glm::vec3 old_normal = face_normal(f);
        if (old_normal != glm::vec3(0.0f) && glm::dot(n, old_normal) <= 0.0f) return Refusal::flip;
        moved.push_back({f, n});
    }

    // the cones: the kept vertex absorbs the removed one and the moved faces; every other vertex of
    // a moved face absorbs its new normal
    NormalCone kept = merge_cones(cones_[to], cones_[from]);
    for (const auto& [f, n] : moved) kept = merge_direction(kept, n);
    if (kept.half_angle >= cone_limit_) return Refusal::cone;
    std::vector<std::pair<std::uint32_t, NormalCone>> neighbours; // vertex, its new cone
    for (const auto& [f, n] : moved) {
        const std::uint32_t* t = &faces_[3 * std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            std::uint32_t w = t[k];
            if (w == from || w == to) continue;
            auto it = std::find_if(neighbours.begin(), neighbours.end(), [&](const auto& e) { return e.first == w; });
            if (it == neighbours.end()) {
                neighbours.push_back({w, cones_[w]});
                it = neighbours.end() - 1;
            }
            it->second = merge_direction(it->second, n);
            if (it->second.half_angle >= cone_limit_) return Refusal::cone;
        }
    }
    if (!commit) return Refusal::none;

    // execute: remove the faces on the edge, move the others, merge adjacency, quadric and cone
    for (std::uint32_t f : shared) {
        face_alive_[f] = false;
        --live_faces_;
        for (int k = 0; k < 3; ++k) {
            std::vector<std::uint32_t>& list = faces_of_[faces_[3 * std::size_t(f) + k]];
            list.erase(std::remove(list.begin(), list.end(), f), list.end());
        }
    }
    for (const auto& [f, n] : moved)
        for (int k = 0; k < 3; ++k)
            if (faces_[3 * std::size_t(f) + k] == from) faces_[3 * std::size_t(f) + k] = to;
    std::vector<std::uint32_t>& faces_to = faces_of_[to];
    for (const auto& [f, n] : moved) faces_to.push_back(f);
    std::sort(faces_to.begin(), faces_to.end());
    faces_of_[from].clear();
    faces_of_[from].shrink_to_fit();
    quadrics_[to].add(quadrics_[from]);
    cones_[to] = kept;
    for (const auto& [w, c] : neighbours) cones_[w] = c;
    vertex_alive_[from] = false;
    if (boundary_[from]) --loop_size_[loop_of_[from]];
    boundary_[to] = boundary_[to] || boundary_[from];
    ++version_[to];
    kept_ = to;
    affected_ = ring_to;
    affected_.insert(affected_.end(), ring_from.begin(), ring_from.end());
    std::sort(affected_.begin(), affected_.end());
    affected_.erase(std::unique(affected_.begin(), affected_.end()), affected_.end());
    affected_.erase(std::remove(affected_.begin(), affected_.end(), from), affected_.end());
    affected_.insert(affected_.begin(), to);
    return Refusal::none;
}

ControlMesh Simplifier::run()
{
    std::size_t target = options_.target_faces;
    stats_.target_faces = target;

    // every edge once, in the direction of lower error
    for (std::uint32_t v = 0; v < positions_.size(); ++v) {
        std::vector<std::uint32_t> ring;
        for (std::uint32_t f : faces_of_[v])
            for (int k = 0; k < 3; ++k)
                if (std::uint32_t w = faces_[3 * std::size_t(f) + k]; w > v) ring.push_back(w);
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        for (std::uint32_t w : ring) push_candidate(v, w, false);
    }

    // collapse the cheapest valid edge until the target is reached
    while (live_faces_ > target && !heap_.empty()) {
        Candidate c = heap_.top();
        heap_.pop();
        if (!vertex_alive_[c.from] || !vertex_alive_[c.to] || version_[c.from] != c.from_version ||
            version_[c.to] != c.to_version)
            continue;
        Refusal refusal = try_collapse(c.from, c.to, true);
        if (refusal == Refusal::stale) continue;
        if (refusal != Refusal::none) {
            if (refusal == Refusal::cone) ++stats_.refused_cone;
            if (refusal == Refusal::flip) ++stats_.refused_flip;
            if (refusal == Refusal::topology) ++stats_.refused_topology;
            waiting_[c.from] = waiting_[c.to] = true;
            if (!c.reverse_tried) {
                Quadric q = quadrics_[c.from];
                q.add(quadrics_[c.to]);
                heap_.push({q.error(glm::dvec3(positions_[c.from])), c.to, c.from, version_[c.to], version_[c.from], true});
            }
            continue;
        }
        ++stats_.collapses;
        // new costs around the kept vertex; edges refused before get another look when their
        // neighbourhood changed
        push_edges_of(c.to);
        for (std::size_t i = 1; i < affected_.size(); ++i) {
            std::uint32_t w = affected_[i];
            if (!waiting_[w]) continue;
            waiting_[w] = false;
            push_edges_of(w);
        }
        if (options_.observer) options_.observer(*this);
    }
    stats_.reached_target = live_faces_ <= target;
    stats_.stopped_by = stats_.reached_target ? "target" : "no valid collapse";
    return compact();
}

ControlMesh Simplifier::compact() const
{
    ControlMesh out = stats_;
    std::vector<std::uint32_t> new_index(positions_.size(), UINT32_MAX);
    for (std::uint32_t f = 0; f < face_alive_.size(); ++f)
        if (face_alive_[f])
            for (int k = 0; k < 3; ++k) new_index[faces_[3 * std::size_t(f) + k]] = 0;
    for (std::uint32_t v = 0; v < positions_.size(); ++v)
        if (new_index[v] == 0) {
            new_index[v] = std::uint32_t(out.positions.size());
            out.positions.push_back(positions_[v]);
            out.cones.push_back(cones_[v]);
        }
    std::vector<glm::dvec3> normals(out.positions.size(), glm::dvec3(0.0));
    for (std::uint32_t f = 0; f < face_alive_.size(); ++f) {
        if (!face_alive_[f]) continue;
        std::uint32_t t[3];
        for (int k = 0; k < 3; ++k) t[k] = new_index[faces_[3 * std::size_t(f) + k]];
        out.indices.insert(out.indices.end(), {t[0], t[1], t[2]});
        glm::dvec3 p0(out.positions[t[0]]), p1(out.positions[t[1]]), p2(out.positions[t[2]]);
        glm::dvec3 n = glm::cross(p1 - p0, p2 - p0); // area-weighted
        for (int k = 0; k < 3; ++k) normals[t[k]] += n;
    }
    out.normals.resize(normals.size());
    for (std::size_t v = 0; v < normals.size(); ++v) {
        double length = glm::length(normals[v]);
        out.normals[v] = length > 0.0 ? glm::vec3(normals[v] / length) : out.cones[v].axis;
    }
    return out;
}

} // namespace

Result<ControlMesh> build_control_mesh(const Mesh& mesh, const ControlMeshOptions& options)
{
    if (options.target_faces == 0) return error(StatusCode::invalid_argument, "control mesh: target face count must be positive");
    if (!(options.cone_angle_degrees > 0.0f && options.cone_angle_degrees <= 180.0f))
        return error(StatusCode::invalid_argument, "control mesh: cone angle must lie in (0, 180] degrees");
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, "control mesh"));
    Simplifier simplifier(mesh, options);
    return simplifier.run();
}

} // namespace standin::displaced_mesh
