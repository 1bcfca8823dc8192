// View-atlas directions and packing: counts, spacing, poles, hemispheres; packed crops stay inside
// their pages, never overlap and do not depend on anything but the input.
#include "reps/common/view_layout.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

namespace standin::reps {
namespace {

float max_cosine_to_others(const std::vector<glm::vec3>& d, std::size_t k)
{
    float best = -1.0f;
    for (std::size_t j = 0; j < d.size(); ++j)
        if (j != k) best = std::max(best, glm::dot(d[k], d[j]));
    return best;
}

TEST(ViewLayout, IcosahedralCountsSpacingAndPoles)
{
    for (int k = 0; k <= 3; ++k) {
        std::vector<glm::vec3> d = layout_directions("icosahedral", k, 0);
        ASSERT_EQ(d.size(), std::size_t(20) << (2 * k));
        for (const glm::vec3& v : d) EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
    }
    // k = 4: the seed's 5120 views, neighbours under 5.5 degrees apart (Saraiva et al. §3)
    std::vector<glm::vec3> d = layout_directions("icosahedral", 4, 0);
    ASSERT_EQ(d.size(), 5120u);
    float widest = 0.0f;
    for (std::size_t k = 0; k < d.size(); k += 7)
        widest = std::max(widest, glm::degrees(std::acos(std::min(1.0f, max_cosine_to_others(d, k)))));
    EXPECT_LT(widest, 5.5f);
    // +Y and -Y are captured views (the protocols' poles)
    float top = -1.0f, bottom = -1.0f;
    for (const glm::vec3& v : d) top = std::max(top, v.y), bottom = std::max(bottom, -v.y);
    EXPECT_GT(top, 1.0f - 1e-5f);
    EXPECT_GT(bottom, 1.0f - 1e-5f);
}

TEST(ViewLayout, OctahedralGrids)
{
    std::vector<glm::vec3> full = layout_directions("octahedral", 0, 16);
    ASSERT_EQ(full.size(), 256u);
    int below = 0, above = 0;
    for (const glm::vec3& v : full) below += v.y < -1e-6f, above += v.y > 1e-6f;
    EXPECT_EQ(below, above); // as many frames look from below as from above
    EXPECT_GE(below, 100);
    std::vector<glm::vec3> hemi = layout_directions("hemi-octahedral", 0, 16);
    ASSERT_EQ(hemi.size(), 256u);
    for (const glm::vec3& v : hemi) {
        EXPECT_GE(v.y, 0.0f);
        EXPECT_NEAR(glm::length(v), 1.0f, 1e-5f);
    }
}

TEST(ViewLayout, PackingStaysInsidePagesWithoutOverlap)
{
    std::vector<View> views;
    for (int k = 0; k < 200; ++k) {
        View v;
        v.width = k_cell * (1 + (k * 7) % 13);
        v.height = k_cell * (1 + (k * 5) % 11);
        if (k % 50 == 3) v.width = v.height = 0; // a view that saw nothing
        views.push_back(v);
    }
    std::vector<View> again = views;
    const int page_size = 512;
    int pages = pack_views(views, page_size);
    EXPECT_EQ(pack_views(again, page_size), pages);
    ASSERT_GE(pages, 2);
    for (std::size_t a = 0; a < views.size(); ++a) {
        const View& v = views[a];
        EXPECT_EQ(v.page, again[a].page);
        EXPECT_EQ(v.atlas_x, again[a].atlas_x);
        EXPECT_EQ(v.atlas_y, again[a].atlas_y);
        if (v.width == 0) continue;
        EXPECT_LT(v.page, pages);
        EXPECT_LE(v.atlas_x + v.width, page_size);
        EXPECT_LE(v.atlas_y + v.height, page_size);
        EXPECT_EQ(v.atlas_x % k_cell, 0);
        EXPECT_EQ(v.atlas_y % k_cell, 0);
        for (std::size_t b = a + 1; b < views.size(); ++b) {
            const View& w = views[b];
            if (w.width == 0 || w.page != v.page) continue;
            bool apart = v.atlas_x + v.width <= w.atlas_x || w.atlas_x + w.width <= v.atlas_x ||
                         v.atlas_y + v.height <= w.atlas_y || w.atlas_y + w.height <= v.atlas_y;
            EXPECT_TRUE(apart) << "views " << a << " and " << b << " overlap";
        }
    }
}

} // namespace
} // namespace standin::reps
