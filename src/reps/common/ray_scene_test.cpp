// The ray scene's closest-point queries: a search that starts near and widens gives the unbounded
// query's answer, point for point, near the surface and far from it.
#include "reps/common/ray_scene.h"

#include <standin/mesh.h>

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>
#include <limits>

namespace standin::reps {
namespace {

TEST(RayScene, TheClosestPointFoundNearFirstIsTheClosestAnywhere)
{
    GenerateOptions shrub;
    shrub.shape = GeneratedShape::shrub; // branches and crossing leaf cards: many triangles near any point
    shrub.target_triangles = 20000;
    Result<Mesh> mesh = generate_mesh(shrub);
    ASSERT_TRUE(mesh.is_ok());
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh->positions, mesh->indices);
    ASSERT_TRUE(scene.is_ok());
    const float diagonal = mesh->bounds().diagonal();
    const glm::vec3 centre = mesh->bounds().center();
    std::size_t near = 0, far = 0;
    for (int k = 0; k < 2000; ++k) {
        // points on a spiral through the crown and out to three diagonals away
        const float t = float(k) / 2000.0f, angle = 2.399963f * float(k);
        const float radius = diagonal * (k % 2 == 0 ? 0.4f * t : 0.5f + 3.0f * t);
        const float height = 2.0f * std::fmod(0.618034f * float(k), 1.0f) - 1.0f, ring = std::sqrt(1.0f - height * height);
        const glm::vec3 point = centre + radius * glm::vec3(ring * std::cos(angle), height, ring * std::sin(angle));
        const SurfacePoint unbounded = (*scene)->closest(point, std::numeric_limits<float>::infinity());
        const SurfacePoint widened = (*scene)->closest_anywhere(point, 1e-3f * diagonal);
        ASSERT_TRUE(unbounded.found && widened.found);
        EXPECT_EQ(widened.triangle, unbounded.triangle) << "point " << k;
        EXPECT_EQ(widened.distance, unbounded.distance) << "point " << k;
        (unbounded.distance < 1e-3f * diagonal ? near : far) += 1;
    }
    EXPECT_GT(far, 1000u); // most found past the first radius: the widening was exercised
    // a first radius of zero or NaN searches everywhere at once
    const SurfacePoint zero = (*scene)->closest_anywhere(centre, 0.0f);
    const SurfacePoint nan = (*scene)->closest_anywhere(centre, std::nanf(""));
    EXPECT_TRUE(zero.found && nan.found);
    EXPECT_EQ(zero.triangle, nan.triangle);
}

} // namespace
} // namespace standin::reps

namespace standin::reps {
namespace {

// A point on an edge of a long thin triangle is on the triangle: its closest point is itself, to
// float rounding. The triangle is one of the generated tree's trunk faces (an edge 0.012 long against
// sides of 0.15), where the normal equations solved in float put 6 of 31 such points 1.1e-5 away,
// past the displaced mesh's on-surface radius (sample.cpp k_on_surface).
TEST(RayScene, APointOnTheEdgeOfASliverIsItsOwnClosestPoint)
{
    const glm::vec3 a(-0.214441f, 0.176804f, -0.0476398f), b(-0.201151f, 0.29306f, -0.142386f), c(-0.207063f, 0.29306f, -0.142765f);
    for (int k = 1; k < 32; ++k) {
        const glm::vec3 q = c + (float(k) / 32.0f) * (b - c);
        float b1 = 0.0f, b2 = 0.0f;
        const glm::vec3 p = closest_point_in_triangle(q, a, b, c, b1, b2);
        EXPECT_LT(glm::length(p - q), 1e-6f) << "point " << k << " of the edge";
        EXPECT_NEAR(b1 + b2, 1.0f, 1e-5f) << "point " << k << " lies on edge bc";
    }
}

} // namespace
} // namespace standin::reps
