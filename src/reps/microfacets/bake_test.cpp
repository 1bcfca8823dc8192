// The bake's resolution for alpha-tested models: raised towards the leaf texture's texel, then
// lowered until the views' crops fit the pages one texture array of the renderer holds.
#include "reps/microfacets/microfacets.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace standin::microfacets {
namespace {

int pages_at(const Mesh& mesh, int resolution, int page_size)
{
    std::vector<View> crops = estimated_crops(mesh, mesh.bounding_sphere(), capture_directions(BakeSettings{}), resolution, page_size);
    return reps::pack_views(crops, page_size);
}

// A cube of half side 1: its bounding sphere (the box's, radius sqrt 3) is what the captures frame,
// and the cube fills 58-82% of each view's width.
Mesh cube()
{
    Mesh mesh;
    for (int i = 0; i < 8; ++i) mesh.positions.push_back(glm::vec3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
    mesh.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    return mesh;
}

constexpr int k_page = 2048;
const int k_budget_pages = budget_pages(k_page);

// A cube fills most of every view: at 1536 px most crops take a page of their own, more pages than
// the 30 one texture array holds, so the resolution comes down until they fit, and no further than
// a sixteenth past that (the textured box with cut-outs of assimp's FBX samples took 67 pages).
TEST(MicrofacetsBake, RaisedResolutionComesDownUntilThePagesFit)
{
    Mesh box = cube();
    const std::vector<glm::vec3> directions = capture_directions(BakeSettings{});
    ASSERT_EQ(directions.size(), 80u);
    EXPECT_GT(pages_at(box, 1536, k_page), k_budget_pages);
    const int fitting = fitting_resolution(box, box.bounding_sphere(), directions, 1536, 512, k_page);
    EXPECT_LT(fitting, 1536);
    EXPECT_GE(fitting, 512);
    EXPECT_LE(pages_at(box, fitting, k_page), k_budget_pages);
    EXPECT_GT(pages_at(box, fitting * 16 / 15 + 1, k_page), k_budget_pages) << "lowered further than it had to";
    // a crop spans the cube's outline (58-82% of the capture) and the margin, in whole cells
    std::vector<View> crops = estimated_crops(box, box.bounding_sphere(), directions, 1024, k_page);
    for (const View& v : crops) {
        EXPECT_EQ(v.width % reps::k_cell, 0);
        EXPECT_GE(v.width, int(0.577 * 1024));
        EXPECT_LE(v.width, int(0.817 * 1024) + 3 + reps::k_cell);
    }
}

// What fits stays, and the floor (the resolution asked for) is never crossed.
TEST(MicrofacetsBake, FittingResolutionKeepsWhatFitsAndTheFloor)
{
    Mesh box = cube();
    const std::vector<glm::vec3> directions = capture_directions(BakeSettings{});
    EXPECT_EQ(fitting_resolution(box, box.bounding_sphere(), directions, 512, 512, k_page), 512);
    EXPECT_EQ(fitting_resolution(box, box.bounding_sphere(), directions, 1536, 1400, k_page), 1400);
}

// Foliage keeps the fine captures the leaf texture asks for: the generated tree's crowns leave room
// on every view, and its 1536 px fit (docs/RESULTS.md "Microfacets on foliage").
TEST(MicrofacetsBake, TheGeneratedTreeKeepsItsFineCaptures)
{
    Mesh tree = test::generated(GeneratedShape::tree, 4000, 1);
    EXPECT_LE(pages_at(tree, k_alpha_max_resolution, k_page), k_budget_pages);
    EXPECT_EQ(fitting_resolution(tree, tree.bounding_sphere(), capture_directions(BakeSettings{}), k_alpha_max_resolution, 512, k_page),
              k_alpha_max_resolution);
}

} // namespace
} // namespace standin::microfacets
