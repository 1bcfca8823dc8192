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
