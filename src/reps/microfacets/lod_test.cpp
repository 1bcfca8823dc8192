// Level of detail (eq. 2 and the per-node cut), the cone of candidate views, and the direction
// lookup of candidate views against a brute-force search.
#include "reps/microfacets/lod.h"
#include "reps/microfacets/view_lookup.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

namespace standin::microfacets {
namespace {

Mesh torus()
{
    return test::generated(GeneratedShape::torus, 3000);
}

// n directions spread over the sphere (a Fibonacci spiral)
std::vector<glm::vec3> spiral(int n)
{
    std::vector<glm::vec3> d;
    const float golden = std::numbers::pi_v<float> * (3.0f - std::sqrt(5.0f));
    for (int i = 0; i < n; ++i) {
        float y = 1.0f - 2.0f * (float(i) + 0.5f) / float(n), r = std::sqrt(1.0f - y * y);
        d.push_back(glm::normalize(glm::vec3(r * std::cos(golden * float(i)), y, r * std::sin(golden * float(i)))));
    }
    return d;
}

TEST(MicrofacetLod, ParallaxErrorIsIntervalTimesTanDelta)
{
    EXPECT_FLOAT_EQ(parallax_error(2.0f, 1.0f), 2.0f);
    EXPECT_NEAR(parallax_error(0.5f, std::tan(glm::radians(5.0f))), 0.5f * 0.0874887f, 1e-6f);
    // the derived bound of 36 cameras on a circle: facets under 11.4 px keep the error under a pixel
    EXPECT_LT(parallax_error(11.4f, std::tan(std::numbers::pi_v<float> / 36.0f)), 1.0f);
    EXPECT_GT(parallax_error(11.5f, std::tan(std::numbers::pi_v<float> / 36.0f)), 1.0f);
}

TEST(MicrofacetLod, ScreenScaleOfPerspectiveAndOrthographicCameras)
{
    BoundingSphere sphere{{0, 0, 0}, 1.0f};
    OrbitView view;
    Camera perspective = orbit_camera(sphere, view, 1.0f);
    ScreenScale s = screen_scale(perspective, 600);
    EXPECT_NEAR(s.at(2.0f), 300.0f / std::tan(glm::radians(20.0f)) / 2.0f, 1e-2f);
    view.orthographic = true;
    view.distance_rel = 2.0f; // half height 2
    ScreenScale o = screen_scale(orbit_camera(sphere, view, 1.0f), 600);
    EXPECT_NEAR(o.at(1.0f), 150.0f, 1e-3f);
    EXPECT_NEAR(o.at(50.0f), 150.0f, 1e-3f);
}

TEST(MicrofacetLod, CutDrawsEveryVoxelOnce)
{
    Mesh mesh = torus();
    Octree tree = build_octree(mesh, grid_around(mesh.bounds()), 2, 6);
    LodRule rule;
    rule.min_level = 2;
    rule.max_level = 6;
    rule.tan_delta = 0.12f;
    BoundingSphere sphere = mesh.bounding_sphere();
    std::set<int> levels_seen;
    for (float distance : {0.3f, 1.0f, 3.0f, 30.0f}) {
        OrbitView view;
        view.distance_rel = distance;
        view.azimuth_degrees = 30.0f;
        view.elevation_degrees = 20.0f;
        Camera camera = orbit_camera(sphere, view, 1.0f);
        ScreenScale scale = screen_scale(camera, 400);
        int finest = finest_level(rule, scale, tree.grid.size, glm::length(camera.eye_world - sphere.center), sphere.radius);
        std::vector<NodeRef> cut = select_cut(tree, rule, scale, camera.eye_world, 1.0f, finest);
        std::set<std::pair<int, std::uint32_t>> in_cut;
        for (const NodeRef& n : cut) in_cut.insert({n.level, n.code}), levels_seen.insert(n.level);
        EXPECT_LE(cut.size(), tree.at(finest).size()); // the renderer's buffer bound
        // every voxel of the finest level has exactly one ancestor (or itself) in the cut
        for (std::uint32_t code : tree.at(finest)) {
            int found = 0;
            for (int level = finest; level >= 2; --level) found += int(in_cut.count({level, code >> (3 * (finest - level))}));
            ASSERT_EQ(found, 1) << "distance " << distance;
        }
        if (distance == 30.0f) {
            EXPECT_EQ(finest, 2);
        }
        if (distance == 0.3f) {
            EXPECT_EQ(finest, 6);
        }
    }
    // close views mix levels: the near side finer than the far side
    EXPECT_GE(levels_seen.size(), 3u);

    // a forced level is that level, whole
    rule.forced_level = 4;
    ScreenScale any;
    EXPECT_EQ(select_cut(tree, rule, any, glm::vec3(5.0f), 1.0f, 4).size(), tree.at(4).size());
}

TEST(MicrofacetLod, ErrorHalvesWithTheVoxelAndGrowsNear)
{
    LodRule rule;
    rule.tan_delta = 0.1f;
    ScreenScale scale{false, 500.0f};
    EXPECT_FLOAT_EQ(node_error_pixels(rule, scale, 0.02f, 1.0f), 1.0f);
    EXPECT_FLOAT_EQ(node_error_pixels(rule, scale, 0.01f, 1.0f), 0.5f);
    EXPECT_FLOAT_EQ(node_error_pixels(rule, scale, 0.02f, 2.0f), 0.5f);
}

TEST(MicrofacetLod, WorstNearestViewAngle)
{
    std::vector<glm::vec3> axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    // the cube's corner directions are the farthest from the six axes: acos(1/sqrt(3)) = 54.7 degrees
    float worst = glm::degrees(max_view_angle(axes, false));
    EXPECT_GT(worst, 52.5f);
    EXPECT_LE(worst, 54.75f);
    EXPECT_NEAR(glm::degrees(max_view_angle(std::vector<glm::vec3>(36, glm::vec3(1, 0, 0)), true)), 5.0f, 1e-4f);
    EXPECT_NEAR(glm::degrees(max_view_angle(std::vector<glm::vec3>(36, glm::vec3(1, 0, 0)), true, 3)), 15.0f, 1e-4f);
    // more views, smaller angles
    EXPECT_LT(max_view_angle(spiral(320), false), max_view_angle(spiral(80), false));
}

TEST(MicrofacetLod, ConeKeepsOnlyViewsThatCanBeNearest)
{
    std::vector<glm::vec3> axes = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    EXPECT_EQ(cone_candidates(axes, {0, 0, 100}, {0, 0, 0}, 1.0f, 0.1f), std::vector<std::uint32_t>{4});
    EXPECT_EQ(cone_candidates(axes, {0, 0, 0.5f}, {0, 0, 0}, 1.0f, 0.1f).size(), 6u);
    // near the sphere the cone opens: asin(1/1.05) = 72 degrees plus the slack reaches the side views
    EXPECT_EQ(cone_candidates(axes, {0, 0, 1.05f}, {0, 0, 0}, 1.0f, glm::radians(20.0f)).size(), 5u);

    // every view some facet of the sphere sees as its nearest is a candidate
    std::vector<glm::vec3> views = spiral(200);
    float slack = max_view_angle(views, false);
    glm::vec3 eye(0.3f, 2.0f, 2.5f);
    std::vector<std::uint32_t> cone = cone_candidates(views, eye, glm::vec3(0.0f), 1.0f, slack);
    EXPECT_LT(cone.size(), views.size() / 2);
    std::vector<glm::vec3> points = spiral(2000);
    for (std::size_t i = 0; i < points.size(); ++i) {
        glm::vec3 p = points[i] * 0.9f;
        glm::vec3 e = glm::normalize(eye - p);
        std::uint32_t best = 0;
        for (std::uint32_t k = 1; k < views.size(); ++k)
            if (glm::dot(views[k], e) > glm::dot(views[best], e)) best = k;
        ASSERT_TRUE(std::binary_search(cone.begin(), cone.end(), best)) << i;
    }
}

TEST(MicrofacetViewLookup, SameViewsAndWeightsAsBruteForce)
{
    for (int n : {6, 36, 320}) {
        std::vector<glm::vec3> views = spiral(n);
        ViewLookup lookup = build_view_lookup(views);
        ASSERT_EQ(lookup.cells.size(), std::size_t(6 * k_lookup_side * k_lookup_side));
        std::vector<glm::vec3> probes = spiral(4001);
        for (const glm::vec3& e : probes) {
            // brute force: views by cosine, ties to the lower index
            std::vector<int> order(views.size());
            for (std::size_t k = 0; k < order.size(); ++k) order[k] = int(k);
            std::sort(order.begin(), order.end(), [&](int a, int b) {
                float ca = glm::dot(views[std::size_t(a)], e), cb = glm::dot(views[std::size_t(b)], e);
                return ca != cb ? ca > cb : a < b;
            });
            for (int count = 1; count <= std::min(4, n - 1); ++count) {
                ViewBlend blend = select_views(views, lookup, e, count);
                float floor_cosine = glm::dot(views[std::size_t(order[std::size_t(count)])], e);
                float sum = 0.0f;
                for (int k = 0; k < count; ++k) sum += glm::dot(views[std::size_t(order[std::size_t(k)])], e) - floor_cosine;
                for (int k = 0; k < count; ++k) {
                    ASSERT_EQ(blend.ids[k], order[std::size_t(k)]) << "n " << n << " count " << count;
                    float expected = count == 1 ? 1.0f : (glm::dot(views[std::size_t(order[std::size_t(k)])], e) - floor_cosine) / sum;
                    if (count > 1 && sum <= 0.0f) expected = k == 0 ? 1.0f : 0.0f;
                    ASSERT_NEAR(blend.weights[k], expected, 1e-5f);
                }
            }
        }
        // a cell lists a handful of views, not all of them
        std::size_t most = 0;
        for (std::uint32_t cell : lookup.cells) most = std::max<std::size_t>(most, cell & 255u);
        if (n == 320) {
            EXPECT_LT(most, 40u);
        }
    }
}

} // namespace
} // namespace standin::microfacets
