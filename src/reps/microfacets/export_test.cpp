// The exported voxel surface (export.h exposed_faces) on hand-made octrees with known face counts:
// a lone voxel, a solid block, a hollow shell whose cavity faces are culled, a shell with a hole
// (the cavity is then outside and its faces kept), and two voxels touching along an edge only.
// The export of a baked package (closed mesh, bounds, colours) is tests/export_gpu_test.cpp.
#include "reps/microfacets/export.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace standin::microfacets {
namespace {

Octree export_octree_of(std::vector<glm::uvec3> cells, int level)
{
    Octree tree;
    tree.grid.origin = glm::vec3(0.0f);
    tree.grid.size = 1.0f;
    tree.min_level = tree.max_level = level;
    std::vector<std::uint32_t> codes;
    for (glm::uvec3 c : cells) codes.push_back(morton_encode(c));
    std::sort(codes.begin(), codes.end());
    tree.levels = {codes};
    return tree;
}

std::vector<glm::uvec3> export_block(glm::uvec3 lo, glm::uvec3 hi, bool hollow)
{
    std::vector<glm::uvec3> cells;
    for (unsigned z = lo.z; z <= hi.z; ++z)
        for (unsigned y = lo.y; y <= hi.y; ++y)
            for (unsigned x = lo.x; x <= hi.x; ++x) {
                bool surface = x == lo.x || x == hi.x || y == lo.y || y == hi.y || z == lo.z || z == hi.z;
                if (!hollow || surface) cells.push_back({x, y, z});
            }
    return cells;
}

TEST(MicrofacetsExport, LoneVoxelShowsSixFaces)
{
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 2, 3}}, 3), 3).size(), 6u);
    // at the grid's border too: outside the grid is outside
    EXPECT_EQ(exposed_faces(export_octree_of({{0, 0, 0}}, 2), 2).size(), 6u);
}

TEST(MicrofacetsExport, SolidBlockShowsOnlyItsOuterFaces)
{
    // a 3 x 4 x 5 block: 2 (3*4 + 4*5 + 3*5) faces, none between two voxels
    EXPECT_EQ(exposed_faces(export_octree_of(export_block({1, 1, 1}, {3, 4, 5}, false), 3), 3).size(), 2u * (12 + 20 + 15));
    // filling the grid: the faces on the grid's border
    EXPECT_EQ(exposed_faces(export_octree_of(export_block({0, 0, 0}, {3, 3, 3}, false), 2), 2).size(), 6u * 16);
}

TEST(MicrofacetsExport, EnclosedCavitiesAreCulled)
{
    // a hollow 5^3 shell (a voxelised closed surface): only its outside, as if solid
    auto shell = export_block({1, 1, 1}, {5, 5, 5}, true);
    EXPECT_EQ(exposed_faces(export_octree_of(shell, 3), 3).size(), 6u * 25);
    // a hole through one wall lets the outside in: the hole's 4 walls and the 3^3 cavity's
    // faces show (54 less the removed voxel's), the removed voxel's outer face is gone
    shell.erase(std::find(shell.begin(), shell.end(), glm::uvec3(3, 3, 1)));
    EXPECT_EQ(exposed_faces(export_octree_of(shell, 3), 3).size(), 6u * 25 - 1 + 4 + 53);
}

TEST(MicrofacetsExport, VoxelsTouchingAlongAnEdgeKeepAllFaces)
{
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 1, 1}, {2, 2, 1}}, 2), 2).size(), 12u);
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 1, 1}, {2, 1, 1}}, 2), 2).size(), 10u);
}

} // namespace
} // namespace standin::microfacets
