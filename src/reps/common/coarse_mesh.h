// A coarse version of a model, for stand-ins that need real geometry besides their images: the
// enhanced billboards fill their holes with it (Vichitvejpaisal 2005 §3.4), and any stand-in may use
// it as a proxy surface.
#pragma once

#include <standin/mesh.h>

namespace standin::reps {

// About `ratio` of the triangles of `mesh` (at least k_min_coarse_triangles, or all of them), by
// QEM simplification (meshoptimizer) on the position-welded topology, falling back to sloppy
// simplification when QEM stops early at locked borders. Vertex colours carry the albedo (textures
// sampled at the kept corners); smooth normals. ratio <= 0: an empty mesh. Deterministic.
Mesh make_coarse_mesh(const Mesh& mesh, float ratio);

// Small models keep enough triangles to stay closed: 10% of a 12-triangle box is one triangle,
// which fills no hole at all.
constexpr std::size_t k_min_coarse_triangles = 256;

} // namespace standin::reps
