// Edge table of a control mesh (see topology.h). Steps: list every face edge as (lo, hi, face, k);
// sort; give each distinct (lo, hi) an index; record per face which edge and in which direction.
#include "reps/displaced_mesh/topology.h"

#include <algorithm>
#include <string>

namespace standin::displaced_mesh {

Result<ControlTopology> build_topology(std::size_t vertex_count, const std::vector<std::uint32_t>& indices)
{
    std::size_t face_count = indices.size() / 3;
    struct HalfEdge {
        std::uint32_t lo, hi, face;
        std::uint8_t k;
    };
    std::vector<HalfEdge> half_edges;
    half_edges.reserve(indices.size());
    ControlTopology out;
    out.face_edges.resize(face_count);
    out.face_edge_reversed.assign(face_count, 0);
    out.vertex_faces.resize(vertex_count);
    for (std::uint32_t f = 0; f < face_count; ++f) {
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = indices[3 * std::size_t(f) + k], b = indices[3 * std::size_t(f) + (k + 1) % 3];
            if (a >= vertex_count || b >= vertex_count)
                return error(StatusCode::bad_data, "control mesh: face " + std::to_string(f) + " has an index out of range");
            if (a == b) return error(StatusCode::bad_data, "control mesh: face " + std::to_string(f) + " repeats a vertex");
            half_edges.push_back({std::min(a, b), std::max(a, b), f, std::uint8_t(k)});
            if (a > b) out.face_edge_reversed[f] |= std::uint8_t(1u << k);
            out.vertex_faces[a].push_back(f);
        }
    }
    std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
        if (x.lo != y.lo) return x.lo < y.lo;
        if (x.hi != y.hi) return x.hi < y.hi;
        return x.face < y.face;
    });
    for (std::size_t i = 0; i < half_edges.size(); ++i) {
        const HalfEdge& h = half_edges[i];
        if (i == 0 || h.lo != half_edges[i - 1].lo || h.hi != half_edges[i - 1].hi) out.edges.push_back({h.lo, h.hi, {}});
        ControlEdge& edge = out.edges.back();
        edge.faces.push_back(h.face);
        out.face_edges[h.face][h.k] = std::uint32_t(out.edges.size() - 1);
    }
    return out;
}

} // namespace standin::displaced_mesh
