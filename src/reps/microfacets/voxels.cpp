// Voxelising the surface and building the octree.
// Yamazaki et al. 2002 §3.2.2 (binary voxels: 1 where the surface intersects the cell) and §3.2.3
// (an octree by repeatedly doubling the sampling interval). The paper does not say how a triangle
// is tested against a cell; here it is Akenine-Möller's exact separating-axis test (JGT 2001).
// Steps:
//  1. place a cube around the model's box (grid_around);
//  2. per triangle (in parallel): split its bounding cell range in halves, keeping only the halves
//     whose box the triangle overlaps, down to single cells, and collect their Morton codes;
//  3. sort and deduplicate (the result is independent of the thread count);
//  4. coarser levels: parent = code >> 3, sorted and deduplicated (a parent is the OR of its
//     children).
#include "reps/microfacets/voxels.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace standin::microfacets {

namespace {

// spreads the low 10 bits of x to every third bit
std::uint32_t spread_bits(std::uint32_t x)
{
    x &= 0x3ffu;
    x = (x | (x << 16)) & 0x030000ffu;
    x = (x | (x << 8)) & 0x0300f00fu;
    x = (x | (x << 4)) & 0x030c30c3u;
    x = (x | (x << 2)) & 0x09249249u;
    return x;
}

std::uint32_t compact_bits(std::uint32_t x)
{
    x &= 0x09249249u;
    x = (x | (x >> 2)) & 0x030c30c3u;
    x = (x | (x >> 4)) & 0x0300f00fu;
    x = (x | (x >> 8)) & 0x030000ffu;
    x = (x | (x >> 16)) & 0x000003ffu;
    return x;
}

// Whether the projections of the triangle (already relative to the box centre) and of the box on
// `axis` are disjoint. A zero axis (parallel edges) never separates.
bool separated_on(glm::vec3 axis, const glm::vec3 v[3], glm::vec3 half)
{
    float p0 = glm::dot(v[0], axis), p1 = glm::dot(v[1], axis), p2 = glm::dot(v[2], axis);
    float r = half.x * std::abs(axis.x) + half.y * std::abs(axis.y) + half.z * std::abs(axis.z);
    return std::min({p0, p1, p2}) > r || std::max({p0, p1, p2}) < -r;
}

// An integer range of cells [lo, hi) per axis.
struct CellRange {
    glm::uvec3 lo, hi;
};

// Step 2 for one triangle: recursive halving of its cell range, pruned by the overlap test.
void voxelise_triangle(const glm::vec3 corners[3], const Grid& grid, int level, std::vector<std::uint32_t>& out)
{
    const std::uint32_t n = 1u << level;
    const float cell = grid.voxel_size(level);
    // the triangle's bounding cells (clamped: the grid holds the model's box)
    glm::vec3 lo_world = glm::min(glm::min(corners[0], corners[1]), corners[2]);
    glm::vec3 hi_world = glm::max(glm::max(corners[0], corners[1]), corners[2]);
    CellRange start;
    for (int a = 0; a < 3; ++a) {
        float lo = std::floor((lo_world[a] - grid.origin[a]) / cell), hi = std::floor((hi_world[a] - grid.origin[a]) / cell);
        start.lo[a] = std::uint32_t(std::clamp(lo, 0.0f, float(n - 1)));
        start.hi[a] = std::uint32_t(std::clamp(hi, 0.0f, float(n - 1))) + 1u;
    }
    // a hair of slack so that rounding never drops a cell the triangle touches
    const float slack = cell * 1e-5f;
    std::vector<CellRange> stack{start};
    while (!stack.empty()) {
        CellRange r = stack.back();
        stack.pop_back();
        glm::vec3 box_lo = grid.origin + glm::vec3(r.lo) * cell, box_hi = grid.origin + glm::vec3(r.hi) * cell;
        if (!triangle_box_overlap(0.5f * (box_lo + box_hi), 0.5f * (box_hi - box_lo) + slack, corners)) continue;
        glm::uvec3 extent = r.hi - r.lo;
        if (extent.x == 1 && extent.y == 1 && extent.z == 1) {
            out.push_back(morton_encode(r.lo));
            continue;
        }
        int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
        std::uint32_t middle = r.lo[axis] + extent[axis] / 2;
        CellRange low = r, high = r;
        low.hi[axis] = middle;
        high.lo[axis] = middle;
        stack.push_back(low);
        stack.push_back(high);
    }
}

void sort_unique(std::vector<std::uint32_t>& codes)
{
    tbb::parallel_sort(codes.begin(), codes.end()); // equal codes are equal values: order-free
    codes.erase(std::unique(codes.begin(), codes.end()), codes.end());
}

} // namespace

std::uint32_t morton_encode(glm::uvec3 cell)
{
    assert(cell.x < (1u << k_max_grid_level) && cell.y < (1u << k_max_grid_level) && cell.z < (1u << k_max_grid_level));
    return spread_bits(cell.x) | (spread_bits(cell.y) << 1) | (spread_bits(cell.z) << 2);
}

glm::uvec3 morton_decode(std::uint32_t code)
{
    return {compact_bits(code), compact_bits(code >> 1), compact_bits(code >> 2)};
}

Grid grid_around(const Bounds& bounds)
{
    glm::vec3 extent = bounds.extent();
    float side = std::max({extent.x, extent.y, extent.z});
    if (!(side > 0.0f)) side = std::max(1e-3f, 1e-3f * glm::length(bounds.center()));
    side *= 1.0f + 1e-4f;
    Grid grid;
    grid.size = side;
    grid.origin = bounds.center() - glm::vec3(0.5f * side);
    return grid;
}

bool triangle_box_overlap(glm::vec3 box_center, glm::vec3 half, const glm::vec3 triangle[3])
{
    const glm::vec3 v[3] = {triangle[0] - box_center, triangle[1] - box_center, triangle[2] - box_center};
    const glm::vec3 edges[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
    // the box's face normals: the triangle's bounding box against the box
    for (int a = 0; a < 3; ++a) {
        glm::vec3 axis(0.0f);
        axis[a] = 1.0f;
        if (separated_on(axis, v, half)) return false;
    }
    // the triangle's plane
    if (separated_on(glm::cross(edges[0], edges[1]), v, half)) return false;
    // the nine cross products of a box axis and a triangle edge
    for (const glm::vec3& e : edges)
        for (int a = 0; a < 3; ++a) {
            glm::vec3 axis(0.0f);
            axis[a] = 1.0f;
            if (separated_on(glm::cross(axis, e), v, half)) return false;
        }
    return true;
}

std::vector<std::uint32_t> voxelise(const Mesh& mesh, const Grid& grid, int level)
{
    assert(level >= 0 && level <= k_max_grid_level);
    tbb::combinable<std::vector<std::uint32_t>> found;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangle_count(), 1024),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                          std::vector<std::uint32_t>& local = found.local();
                          for (std::size_t t = range.begin(); t != range.end(); ++t) {
                              const glm::vec3 corners[3] = {mesh.positions[mesh.indices[3 * t]],
                                                            mesh.positions[mesh.indices[3 * t + 1]],
                                                            mesh.positions[mesh.indices[3 * t + 2]]};
                              voxelise_triangle(corners, grid, level, local);
                          }
                          // keep each thread's list short on large meshes
                          if (local.size() > (1u << 20)) sort_unique(local);
                      });
    std::vector<std::uint32_t> codes;
    found.combine_each([&](const std::vector<std::uint32_t>& local) { codes.insert(codes.end(), local.begin(), local.end()); });
    sort_unique(codes);
    return codes;
}

std::vector<std::uint32_t> coarsen(const std::vector<std::uint32_t>& finer)
{
    assert(std::is_sorted(finer.begin(), finer.end()));
    std::vector<std::uint32_t> coarse;
    coarse.reserve(finer.size() / 4 + 1);
    for (std::uint32_t code : finer) // sorted children give sorted parents: deduplicate in one pass
        if (coarse.empty() || coarse.back() != (code >> 3)) coarse.push_back(code >> 3);
    return coarse;
}

Octree build_octree(const Mesh& mesh, const Grid& grid, int min_level, int max_level)
{
    assert(0 <= min_level && min_level <= max_level && max_level <= k_max_grid_level);
    Octree tree;
    tree.grid = grid;
    tree.min_level = min_level;
    tree.max_level = max_level;
    tree.levels.resize(std::size_t(max_level - min_level + 1));
    tree.levels.back() = voxelise(mesh, grid, max_level);
    for (int level = max_level - 1; level >= min_level; --level)
        tree.levels[std::size_t(level - min_level)] = coarsen(tree.levels[std::size_t(level - min_level + 1)]);
    return tree;
}

} // namespace standin::microfacets
