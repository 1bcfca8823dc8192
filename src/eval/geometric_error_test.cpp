// One-sided surface distance. MeshLab is not installed here, so the cross-check is analytic:
// between concentric spheres every point of one lies exactly |r1 - r2| from the other (up to the
// faceting of the finer mesh, below 1e-3 of the radius at these triangle counts).
#include <standin/eval.h>

#include <gtest/gtest.h>

namespace standin {
namespace {

Mesh sphere(float radius, std::size_t triangles)
{
    GenerateOptions options;
    options.radius = radius;
    options.target_triangles = triangles;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

TEST(SurfaceDistance, ConcentricSpheresAreTheRadiusDifferenceApart)
{
    Mesh inner = sphere(1.0f, 200000), outer = sphere(1.25f, 20000);
    // outer vertices lie on r = 1.25 and its faces slightly inside; the inner mesh is fine
    Result<SurfaceDistance> d = surface_distance(outer, inner, 20000);
    ASSERT_TRUE(d.is_ok()) << d.status().message();
    EXPECT_EQ(d->samples, 20000u);
    EXPECT_NEAR(d->max, 0.25, 0.002);
    EXPECT_NEAR(d->mean, 0.25, 0.002);
    EXPECT_NEAR(d->max_rel, 0.25 / inner.bounds().diagonal(), 0.002);
}

TEST(SurfaceDistance, MeshToItselfIsZeroAndSamplingIsDeterministic)
{
    Mesh m = sphere(2.0f, 5000);
    Result<SurfaceDistance> d = surface_distance(m, m, 5000, 7);
    ASSERT_TRUE(d.is_ok());
    EXPECT_LT(d->max, 1e-5);
    Result<SurfaceDistance> a = surface_distance(sphere(1.1f, 500), m, 1000, 3);
    Result<SurfaceDistance> b = surface_distance(sphere(1.1f, 500), m, 1000, 3);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    EXPECT_EQ(a->mean, b->mean);
    EXPECT_FALSE(surface_distance(m, m, 0).is_ok());
}

} // namespace
} // namespace standin
