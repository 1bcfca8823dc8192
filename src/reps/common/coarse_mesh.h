// A coarse version of a model, for stand-ins that need real geometry besides their images: the
// enhanced billboards fill their holes with it (Vichitvejpaisal 2005 §3.4), and any stand-in may use
// it as a proxy surface.
#pragma once

#include <standin/mesh.h>
#include <standin/status.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace standin::reps {

// About `ratio` of the triangles of `mesh` (at least k_min_coarse_triangles, or all of them), by
// QEM simplification (meshoptimizer) on the position-welded topology, falling back to sloppy
// simplification when QEM stops early at locked borders. Vertex colours carry the albedo (textures
// sampled at the kept corners); smooth normals. ratio <= 0: an empty mesh. Deterministic.
// lock_borders (issue #17): open boundaries keep every vertex, so the outline of a sheet stays
// where it is (closed meshes have none: the result is the same either way).
// max_error > 0 (issue #17, model units): when the ratio's mesh strays further than this from the
// model (meshoptimizer's error estimate), the simplification stops where it would exceed it
// instead, keeping more triangles (at most all of them); 0: the ratio alone decides.
Mesh make_coarse_mesh(const Mesh& mesh, float ratio, bool lock_borders = false, float max_error = 0.0f);

// Coarser levels of a coarse mesh, for instances small on screen (issue #17: in a crowd of 1,000
// copies of a 252k-face head the coarse mesh of the few near instances, 25k triangles each over a
// few thousand pixels, took a third of the frame): each level about a quarter of the triangles of
// the one before (meshopt_simplify on the position-welded topology, borders locked: a sheet's
// outline stays where it is), down to k_min_coarse_triangles / 4 or where simplification stalls.
// `indices` gets the mesh's own indices (level 0) followed by each level's; `error` is how far (model
// units) a level may stray from the mesh, meshoptimizer's estimates summed down the levels.
// Deterministic.
struct CoarseLevel {
    std::uint32_t first_index = 0, index_count = 0;
    float error = 0.0f;
};
std::vector<CoarseLevel> coarse_mesh_levels(const Mesh& coarse, std::vector<std::uint32_t>& indices);

// Small models keep enough triangles to stay closed: 10% of a 12-triangle box is one triangle,
// which fills no hole at all.
constexpr std::size_t k_min_coarse_triangles = 256;

// ------------------------------------------------------------------------------------------------
// The compact coarse-mesh file of compressed packages (docs/FORMAT.md, "Compact coarse mesh"):
// positions quantised to 16 bits per axis over the mesh's bounding box, 8-bit colours, no normals
// (smooth normals are recomputed on decode, as make_coarse_mesh computes them), vertices and
// triangles reordered for the vertex cache and fetch, then meshoptimizer's vertex and index codecs
// under zlib. Deterministic. Colours are Mesh::colors (the coarse mesh's one material is white).
std::string encode_coarse_mesh(const Mesh& mesh);

// Decodes a file of `bytes` (named `path` in refusals, one line each): the header, the counts
// (against `triangles` and `vertices`, the manifest's, and the triangle and memory budgets), the
// streams' sizes and codecs, every index below the vertex count. The mesh has one white material
// and smooth normals.
Result<Mesh> decode_coarse_mesh(std::string_view bytes, const std::string& path, std::uint64_t triangles,
                                std::uint64_t vertices);

} // namespace standin::reps
