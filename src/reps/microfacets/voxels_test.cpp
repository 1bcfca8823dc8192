// The voxeliser on hand-made cases with known cells, the separating-axis test on the cases that need
// each kind of axis, coarse levels equal to the OR of their children, and thread-count independence.
#include "reps/microfacets/voxels.h"

#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <algorithm>
#include <set>

namespace standin::microfacets {
namespace {

Mesh one_triangle(glm::vec3 a, glm::vec3 b, glm::vec3 c)
{
    Mesh mesh;
    mesh.positions = {a, b, c};
    mesh.normals.assign(3, glm::normalize(glm::cross(b - a, c - a)));
    mesh.colors.assign(3, glm::vec4(1.0f));
    mesh.indices = {0, 1, 2};
    mesh.face_materials = {0};
    mesh.materials.resize(1);
    return mesh;
}

Mesh generated(GeneratedShape shape, std::size_t triangles)
{
    GenerateOptions options;
    options.shape = shape;
    options.target_triangles = triangles;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

TEST(MicrofacetVoxels, MortonCodesInterleaveXYZ)
{
    EXPECT_EQ(morton_encode({1, 0, 0}), 1u);
    EXPECT_EQ(morton_encode({0, 1, 0}), 2u);
    EXPECT_EQ(morton_encode({0, 0, 1}), 4u);
    EXPECT_EQ(morton_encode({3, 0, 0}), 9u);
    EXPECT_EQ(morton_encode({1023, 1023, 1023}), (1u << 30) - 1u);
    for (glm::uvec3 cell : {glm::uvec3(5, 700, 33), glm::uvec3(1023, 0, 512), glm::uvec3(0, 0, 0)})
        EXPECT_EQ(morton_decode(morton_encode(cell)), cell);
    // the parent of a cell is the code shifted by 3
    EXPECT_EQ(morton_encode({6, 9, 3}) >> 3, morton_encode({3, 4, 1}));
}

TEST(MicrofacetVoxels, SeparatingAxes)
{
    const glm::vec3 center(0.5f), half(0.5f);
    // box axis: beside the box
    glm::vec3 beside[3] = {{1.5f, 0.2f, 0.2f}, {2.0f, 0.8f, 0.2f}, {1.6f, 0.5f, 0.9f}};
    EXPECT_FALSE(triangle_box_overlap(center, half, beside));
    // the triangle's plane: a plane cutting the bounding box but passing beyond the corner (1,1,1)
    glm::vec3 beyond_corner[3] = {{3.1f, 0.0f, 0.0f}, {0.0f, 3.1f, 0.0f}, {0.0f, 0.0f, 3.1f}};
    glm::vec3 through_corner[3] = {{3.1f, 0.0f, 0.0f}, {0.0f, 3.1f, 0.0f}, {0.0f, 0.0f, 2.5f}};
    EXPECT_FALSE(triangle_box_overlap(center, half, beyond_corner));
    // (x + y) / 3.1 + z / 2.5 = 1 passes through the box near (1, 1, 0.89)
    EXPECT_TRUE(triangle_box_overlap(center, half, through_corner));
    // an edge axis: the triangle's box overlaps, its plane cuts the box, but its hypotenuse
    // (x + y = 2.6) passes outside the corner (1, 1)
    glm::vec3 past_edge[3] = {{0.6f, 2.0f, 0.5f}, {2.0f, 0.6f, 0.5f}, {2.0f, 2.0f, 0.5f}};
    EXPECT_FALSE(triangle_box_overlap(center, half, past_edge));
    glm::vec3 over_edge[3] = {{0.4f, 1.5f, 0.5f}, {1.5f, 0.4f, 0.5f}, {2.0f, 2.0f, 0.5f}};
    EXPECT_TRUE(triangle_box_overlap(center, half, over_edge));
    // a triangle holding the box's centre, and one touching a face
    glm::vec3 inside[3] = {{0.4f, 0.4f, 0.5f}, {0.6f, 0.4f, 0.5f}, {0.5f, 0.6f, 0.5f}};
    EXPECT_TRUE(triangle_box_overlap(center, half, inside));
    glm::vec3 touching[3] = {{1.0f, 0.2f, 0.2f}, {1.0f, 0.8f, 0.2f}, {1.0f, 0.5f, 0.9f}};
    EXPECT_TRUE(triangle_box_overlap(center, half, touching));
}

TEST(MicrofacetVoxels, OneTriangleGivesItsCells)
{
    // a grid of 4^3 unit cells from the origin; a right triangle in the middle of layer z = 0 with
    // legs of 2.2 from (0.2, 0.2): it reaches the cells with i + j <= 2 (x + y <= 2.6)
    Grid grid;
    grid.origin = glm::vec3(0.0f);
    grid.size = 4.0f;
    Mesh mesh = one_triangle({0.2f, 0.2f, 0.5f}, {2.4f, 0.2f, 0.5f}, {0.2f, 2.4f, 0.5f});
    std::vector<std::uint32_t> codes = voxelise(mesh, grid, 2);
    std::set<std::uint32_t> expected;
    for (std::uint32_t j = 0; j < 4; ++j)
        for (std::uint32_t i = 0; i < 4; ++i)
            if (i + j <= 2) expected.insert(morton_encode({i, j, 0}));
    EXPECT_EQ(std::set<std::uint32_t>(codes.begin(), codes.end()), expected);
    EXPECT_TRUE(std::is_sorted(codes.begin(), codes.end()));

    // a tilted triangle from cell (0,0,0) to cell (3,3,3) along the diagonal: the cells on its way,
    // each cell of the diagonal and none far from it
    Mesh diagonal = one_triangle({0.5f, 0.5f, 0.5f}, {3.5f, 3.5f, 3.5f}, {3.4f, 3.6f, 3.5f});
    std::vector<std::uint32_t> along = voxelise(diagonal, grid, 2);
    for (std::uint32_t k = 0; k < 4; ++k)
        EXPECT_TRUE(std::binary_search(along.begin(), along.end(), morton_encode({k, k, k}))) << k;
    EXPECT_FALSE(std::binary_search(along.begin(), along.end(), morton_encode({3, 0, 0})));
    EXPECT_FALSE(std::binary_search(along.begin(), along.end(), morton_encode({0, 3, 3})));
    // every cell found really overlaps the triangle
    const glm::vec3 corners[3] = {diagonal.positions[0], diagonal.positions[1], diagonal.positions[2]};
    for (std::uint32_t code : along) EXPECT_TRUE(triangle_box_overlap(grid.center(code, 2), glm::vec3(0.5f), corners));
}

TEST(MicrofacetVoxels, GridHoldsTheBox)
{
    Bounds box{{-1.0f, 0.0f, 2.0f}, {3.0f, 1.0f, 2.5f}};
    Grid grid = grid_around(box);
    EXPECT_GE(grid.size, 4.0f);
    for (int a = 0; a < 3; ++a) {
        EXPECT_LT(grid.origin[a], box.min[a]);
        EXPECT_GT(grid.origin[a] + grid.size, box.max[a]);
    }
    Grid flat = grid_around(Bounds{{1.0f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f}});
    EXPECT_GT(flat.size, 0.0f);
}

TEST(MicrofacetVoxels, CoarseLevelIsTheOrOfItsChildren)
{
    Mesh mesh = generated(GeneratedShape::torus, 3000);
    Grid grid = grid_around(mesh.bounds());
    Octree tree = build_octree(mesh, grid, 2, 5);
    ASSERT_EQ(tree.levels.size(), 4u);
    for (int level = 2; level < 5; ++level) {
        const std::vector<std::uint32_t>& coarse = tree.at(level);
        const std::vector<std::uint32_t>& fine = tree.at(level + 1);
        // exhaustively: a coarse cell is set exactly where one of its 8 children is
        const std::uint32_t cells = 1u << (3 * level);
        for (std::uint32_t code = 0; code < cells; ++code) {
            bool child = false;
            for (std::uint32_t c = 0; c < 8; ++c) child = child || std::binary_search(fine.begin(), fine.end(), (code << 3) | c);
            EXPECT_EQ(std::binary_search(coarse.begin(), coarse.end(), code), child) << "level " << level << " code " << code;
        }
        // and a triangle overlaps a parent box exactly when it overlaps a child box: voxelising the
        // coarse level directly gives the same cells
        EXPECT_EQ(voxelise(mesh, grid, level), coarse) << level;
    }
    // a surface: about four times the cells per level
    double growth = double(tree.at(5).size()) / double(tree.at(4).size());
    EXPECT_GT(growth, 3.0);
    EXPECT_LT(growth, 5.0);
}

TEST(MicrofacetVoxels, IndependentOfThreadCount)
{
    Mesh mesh = generated(GeneratedShape::noisy_sphere, 20000);
    Grid grid = grid_around(mesh.bounds());
    std::vector<std::uint32_t> one, two;
    tbb::task_arena(1).execute([&] { one = voxelise(mesh, grid, 7); });
    tbb::task_arena(2).execute([&] { two = voxelise(mesh, grid, 7); });
    EXPECT_EQ(one, two);
    EXPECT_GT(one.size(), 10000u);
}

} // namespace
} // namespace standin::microfacets
