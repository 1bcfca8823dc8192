// Edges and corners of a control mesh, numbered once (Bauman, Livny & El-Sana §3.3: "the edges
// guide the face subdivision in order to avoid T-junctions"). Everything two faces must agree on
// is computed per edge or per corner from this table, in the edge's canonical direction (from the
// lower vertex index to the higher), never per face.
#pragma once

#include <standin/status.h>

#include <array>
#include <cstdint>
#include <vector>

namespace standin::displaced_mesh {

struct ControlEdge {
    std::uint32_t lo = 0, hi = 0;      // vertex indices, lo < hi: the canonical direction
    std::vector<std::uint32_t> faces;  // faces using the edge, increasing (1 on a boundary)
};

struct ControlTopology {
    std::vector<ControlEdge> edges;                       // ordered by (lo, hi)
    std::vector<std::array<std::uint32_t, 3>> face_edges; // edge k of face f runs corner k -> k+1
    // bit k set: face f walks its edge k from the edge's `hi` to its `lo` (against canonical order)
    std::vector<std::uint8_t> face_edge_reversed;
    std::vector<std::vector<std::uint32_t>> vertex_faces; // faces around each vertex, increasing

    bool reversed(std::uint32_t face, int k) const { return (face_edge_reversed[face] >> k) & 1u; }
};

// bad_data when a face repeats a vertex or an index is out of range.
Result<ControlTopology> build_topology(std::size_t vertex_count, const std::vector<std::uint32_t>& indices);

} // namespace standin::displaced_mesh
