// The protocols' cameras: counts, the 14 directions of Saraiva et al. §3, distances and sizes.
#include <standin/eval.h>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace standin {
namespace {

TEST(Protocols, FourteenDirectionsAreSixMeridiansTwoZonesTwoPoles)
{
    std::vector<glm::vec2> d = fourteen_directions();
    ASSERT_EQ(d.size(), 14u);
    std::set<std::pair<float, float>> unique;
    for (glm::vec2 v : d) unique.insert({v.x, v.y});
    EXPECT_EQ(unique.size(), 14u);
    int north = 0, south = 0, up = 0, down = 0;
    for (glm::vec2 v : d) {
        north += v.y == 30.0f, south += v.y == -30.0f, up += v.y == 90.0f, down += v.y == -90.0f;
        EXPECT_EQ(std::fmod(v.x, 60.0f), 0.0f);
    }
    EXPECT_EQ(north, 6);
    EXPECT_EQ(south, 6);
    EXPECT_EQ(up, 1);
    EXPECT_EQ(down, 1);
}

TEST(Protocols, ThesisIsFourteenViewsAtThreeResolutions)
{
    Result<Protocol> p = make_protocol("thesis");
    ASSERT_TRUE(p.is_ok());
    ASSERT_EQ(p->views.size(), 42u);
    std::set<std::pair<int, int>> sizes;
    for (const EvalView& v : p->views) {
        sizes.insert({v.width, v.height});
        EXPECT_EQ(v.orbit.distance_rel, 1.0f);
        EXPECT_EQ(v.orbit.fov_y_degrees, 40.0f);
    }
    EXPECT_EQ(sizes, (std::set<std::pair<int, int>>{{800, 600}, {400, 300}, {200, 150}}));
}

TEST(Protocols, SaraivaCoversDistancesAndFovs)
{
    Result<Protocol> p = make_protocol("saraiva");
    ASSERT_TRUE(p.is_ok());
    ASSERT_EQ(p->views.size(), 14u * 8u * 3u);
    std::set<float> distances, fovs;
    for (const EvalView& v : p->views) distances.insert(v.orbit.distance_rel), fovs.insert(v.orbit.fov_y_degrees);
    EXPECT_EQ(distances, (std::set<float>{0.5f, 1, 2, 4, 8, 16, 32, 64}));
    EXPECT_EQ(fovs, (std::set<float>{40, 60, 90}));
}

TEST(Protocols, FoliageIsThreeDistancesSupersampledAndTheSeedsOnesAreNot)
{
    Result<Protocol> p = make_protocol("foliage");
    ASSERT_TRUE(p.is_ok());
    ASSERT_EQ(p->views.size(), 42u);
    std::set<float> distances;
    for (const EvalView& v : p->views) distances.insert(v.orbit.distance_rel);
    EXPECT_EQ(distances, (std::set<float>{1, 4, 8}));
    EXPECT_EQ(p->supersample, 4);
    for (const char* seed : {"thesis", "saraiva", "quick"}) EXPECT_EQ(make_protocol(seed)->supersample, 1) << seed;
}

TEST(Protocols, QuickIsSmallAndUnknownNamesAreRefused)
{
    Result<Protocol> p = make_protocol("quick");
    ASSERT_TRUE(p.is_ok());
    EXPECT_LE(p->views.size(), 4u);
    Result<Protocol> bad = make_protocol("nope");
    ASSERT_FALSE(bad.is_ok());
    EXPECT_NE(bad.status().message().find("thesis"), std::string::npos);
}

} // namespace
} // namespace standin
