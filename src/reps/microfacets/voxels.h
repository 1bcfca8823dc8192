// The microfacets' geometry: a binary voxel grid around the model and the octree of coarser levels
// made by doubling the cell size (Yamazaki et al. 2002 §3.2.2-3.2.3). Voxels are kept as sorted
// Morton codes per level, so an octree level is a list, a parent is `code >> 3` and a level is
// cheap to store (4 bytes a voxel, docs/FORMAT.md "Microfacets").
#pragma once

#include <standin/mesh.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace standin::microfacets {

// 10 bits per axis in a 32-bit code: levels 0..10 (1³ .. 1024³ cells).
constexpr int k_max_grid_level = 10;

// Morton (Z-order) code of cell (x, y, z), each below 2^k_max_grid_level: bit 3i is x's bit i,
// 3i + 1 y's, 3i + 2 z's. Children of a cell at level k are the codes (code << 3) | 0..7 at k + 1.
std::uint32_t morton_encode(glm::uvec3 cell);
glm::uvec3 morton_decode(std::uint32_t code);

// The cube the voxels live in: level k has 2^k cells per side of size `size / 2^k`.
struct Grid {
    glm::vec3 origin{0.0f}; // the cube's minimum corner
    float size = 1.0f;      // the cube's side

    float voxel_size(int level) const { return size / float(1u << level); }
    // centre of the cell with Morton code `code` at `level`
    glm::vec3 center(std::uint32_t code, int level) const
    {
        return origin + (glm::vec3(morton_decode(code)) + 0.5f) * voxel_size(level);
    }
};

// A cube of side max(extent) * (1 + 1e-4) centred on the box (so no surface lies on its faces);
// a flat or degenerate box still gets a cube of positive size.
Grid grid_around(const Bounds& bounds);

// Akenine-Möller's triangle-box overlap test (Akenine-Möller, "Fast 3D Triangle-Box Overlap
// Testing", JGT 2001): separating axes of the box's 3 normals, the triangle's normal and the 9
// edge cross products. Touching counts as overlapping. `half` is the box's half size.
bool triangle_box_overlap(glm::vec3 box_center, glm::vec3 half, const glm::vec3 triangle[3]);

// The cells at `level` that some triangle of `mesh` overlaps (Yamazaki et al. 2002 §3.2.2: a voxel
// is 1 where the surface intersects it), as sorted unique Morton codes. Triangles are voxelised in
// parallel (oneTBB); the sorted result does not depend on the thread count.
std::vector<std::uint32_t> voxelise(const Mesh& mesh, const Grid& grid, int level);

// The next coarser level (§3.2.3, "doubling the sampling interval"): a cell is occupied where one
// of its 8 children is, i.e. the sorted unique `code >> 3` of the finer codes (sorted input).
std::vector<std::uint32_t> coarsen(const std::vector<std::uint32_t>& finer);

// Every level from min_level to max_level, finest voxelised, the others coarsened from it.
struct Octree {
    Grid grid;
    int min_level = 0, max_level = 0;
    std::vector<std::vector<std::uint32_t>> levels; // levels[k - min_level]: sorted codes at level k

    const std::vector<std::uint32_t>& at(int level) const { return levels[std::size_t(level - min_level)]; }
};
Octree build_octree(const Mesh& mesh, const Grid& grid, int min_level, int max_level);

} // namespace standin::microfacets
