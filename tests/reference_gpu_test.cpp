// The ground-truth renderer against analytic expectations: a sphere's silhouette radius in pixels,
// Lambert intensity at its centre, and byte-identical repeated renders.
#include "test_support.h"

#include "gpu/gl.h"

#include <standin/camera.h>
#include <standin/mesh.h>
#include <standin/render.h>

#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace standin {
namespace {

Mesh unit_sphere()
{
    GenerateOptions options;
    options.shape = GeneratedShape::sphere;
    options.target_triangles = 80000;
    options.radius = 1.0f;
    options.color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok()) << mesh.status().message();
    return std::move(*mesh);
}

double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double linear_to_srgb(double c) { return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

std::size_t covered_pixels(const ImageRGBA8& image)
{
    std::size_t n = 0;
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) n += image.pixels[i] > 0;
    return n;
}

// Every renderer reports a GL error through gl_error_text: the code, and for GL_OUT_OF_MEMORY (a
// package too large for the device, as a 4096-texel foliage bake is for llvmpipe) what to do.
TEST(GlErrors, OutOfMemorySaysWhatToDo)
{
    EXPECT_EQ(gpu::gl_error_text(GL_INVALID_OPERATION), "OpenGL error 1282");
    std::string oom = gpu::gl_error_text(GL_OUT_OF_MEMORY);
    EXPECT_EQ(oom.rfind("OpenGL error 1285 (out of GPU memory", 0), 0u) << oom;
    EXPECT_NE(oom.find("--resolution"), std::string::npos) << oom;
}

TEST(ReferenceRenderer, SphereSilhouetteRadiusMatchesPerspectiveProjection)
{
    test::gpu_context();
    Mesh sphere = unit_sphere();
    auto renderer = make_mesh_renderer(sphere);
    ASSERT_TRUE(renderer.is_ok()) << renderer.status().message();
    const int width = 400, height = 300;
    OrbitView view;
    view.azimuth_degrees = 0;
    view.elevation_degrees = 0;
    view.fov_y_degrees = 40;
    Camera camera = orbit_camera(sphere.bounding_sphere(), view, float(width) / height);
    auto image = render_offscreen(**renderer, camera, default_light(camera), width, height);
    ASSERT_TRUE(image.is_ok()) << image.status().message();

    // A sphere of radius r seen from distance d subtends asin(r/d); its outline is a circle of
    // tan(asin(r/d)) / tan(fov/2) * height/2 pixels.
    double d = glm::length(camera.eye_world - sphere.bounding_sphere().center);
    double expected_radius = std::tan(std::asin(1.0 / d)) / std::tan(glm::radians(20.0)) * height / 2.0;
    double measured_radius = std::sqrt(double(covered_pixels(image->color)) / M_PI);
    EXPECT_NEAR(measured_radius, expected_radius, 0.01 * expected_radius);
}

TEST(ReferenceRenderer, SphereSilhouetteRadiusOrthographic)
{
    test::gpu_context();
    Mesh sphere = unit_sphere();
    auto renderer = make_mesh_renderer(sphere);
    ASSERT_TRUE(renderer.is_ok());
    const int size = 256;
    OrbitView view;
    view.orthographic = true;
    view.elevation_degrees = 35;
    Camera camera = orbit_camera(sphere.bounding_sphere(), view, 1.0f);
    auto image = render_offscreen(**renderer, camera, default_light(camera), size, size);
    ASSERT_TRUE(image.is_ok());
    double expected_radius = 1.0 / camera.ortho_half_height * size / 2.0;
    double measured_radius = std::sqrt(double(covered_pixels(image->color)) / M_PI);
    EXPECT_NEAR(measured_radius, expected_radius, 0.01 * expected_radius);
}

TEST(ReferenceRenderer, LambertIntensityAtSphereCentre)
{
    test::gpu_context();
    Mesh sphere = unit_sphere();
    auto renderer = make_mesh_renderer(sphere);
    ASSERT_TRUE(renderer.is_ok());
    const int size = 201;
    OrbitView view; // from +Z
    Camera camera = orbit_camera(sphere.bounding_sphere(), view, 1.0f);
    for (glm::vec3 to_light : {glm::vec3(0, 0, 1), glm::normalize(glm::vec3(0.5f, 0.3f, 1.0f)), glm::vec3(1, 0, 0)}) {
        Light light;
        light.direction_to_light_world = to_light;
        light.ambient = 0.15f;
        light.diffuse = 0.85f;
        light.shading = ShadingModel::lambert_blinn_phong; // the GGX model: pbr_gpu_test.cpp
        auto image = render_offscreen(**renderer, camera, light, size, size);
        ASSERT_TRUE(image.is_ok());
        // The centre pixel sees the point of the sphere whose normal is +Z.
        double n_dot_l = std::max(0.0, double(to_light.z));
        double expected = linear_to_srgb(srgb_to_linear(0.8) * (0.15 + 0.85 * n_dot_l)) * 255.0;
        const std::uint8_t* centre = image->color.at(size / 2, size / 2);
        EXPECT_NEAR(centre[0], expected, 2.0) << "light " << to_light.x << "," << to_light.y << "," << to_light.z;
        EXPECT_EQ(centre[3], 255);
    }
}

TEST(ReferenceRenderer, RepeatedRendersAreByteIdentical)
{
    test::gpu_context();
    GenerateOptions options;
    options.shape = GeneratedShape::torus;
    options.target_triangles = 20000;
    Result<Mesh> torus = generate_mesh(options);
    ASSERT_TRUE(torus.is_ok());
    auto renderer = make_mesh_renderer(*torus);
    ASSERT_TRUE(renderer.is_ok());
    OrbitView view;
    view.azimuth_degrees = 37;
    view.elevation_degrees = 41;
    Camera camera = orbit_camera(torus->bounding_sphere(), view, 4.0f / 3.0f);
    auto first = render_offscreen(**renderer, camera, default_light(camera), 320, 240);
    auto second = render_offscreen(**renderer, camera, default_light(camera), 320, 240);
    ASSERT_TRUE(first.is_ok() && second.is_ok());
    EXPECT_GT(covered_pixels(first->color), 1000u);
    EXPECT_EQ(first->color.pixels, second->color.pixels);
    EXPECT_EQ(first->depth, second->depth);
}

TEST(ReferenceRenderer, InstancesAreDrawnWhereTheirTransformsPutThem)
{
    test::gpu_context();
    Mesh sphere = unit_sphere();
    auto renderer = make_mesh_renderer(sphere);
    ASSERT_TRUE(renderer.is_ok());
    Camera camera = look_at_camera({0, 0, 10}, {0, 0, 0}, {0, 1, 0}, 40.0f, 2.0f, 1.0f, 20.0f);
    std::vector<glm::mat4> transforms = {glm::translate(glm::mat4(1.0f), glm::vec3(-2.5f, 0, 0)),
                                         glm::translate(glm::mat4(1.0f), glm::vec3(2.5f, 0, 0))};
    auto image = render_offscreen(**renderer, camera, default_light(camera), 200, 100, transforms);
    ASSERT_TRUE(image.is_ok());
    EXPECT_EQ(image->color.at(100, 50)[3], 0) << "nothing at the centre";
    EXPECT_EQ(image->color.at(100 - 36, 50)[3], 255) << "left instance";
    EXPECT_EQ(image->color.at(100 + 36, 50)[3], 255) << "right instance";
}

// A single-sided closed sphere under a mirroring transform looks as it does unmirrored (a sphere is
// its own mirror image): its front faces, whose winding the mirror turns, are the ones drawn, not
// its inside. Culled by winding alone, the mirrored one showed the far half's inside.
TEST(ReferenceRenderer, MirroredInstanceOfASingleSidedMeshShowsItsOutside)
{
    test::gpu_context();
    Mesh sphere = unit_sphere();
    for (Material& m : sphere.materials) m.double_sided = false;
    auto renderer = make_mesh_renderer(sphere);
    ASSERT_TRUE(renderer.is_ok());
    Camera camera = look_at_camera({0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0f, 1.0f, 0.5f, 20.0f);
    Light light = default_light(camera);
    light.direction_to_light_world = glm::normalize(glm::vec3(0.0f, 0.6f, 0.8f)); // in the mirror plane
    const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 1.0f, 1.0f));
    auto plain = render_offscreen(**renderer, camera, light, 128, 128);
    auto mirrored = render_offscreen(**renderer, camera, light, 128, 128, std::span<const glm::mat4>(&mirror, 1));
    ASSERT_TRUE(plain.is_ok() && mirrored.is_ok());
    EXPECT_EQ(covered_pixels(mirrored->color), covered_pixels(plain->color));
    // the near side's depth and shading at the centre
    EXPECT_NEAR(mirrored->depth[64 * 128 + 64], plain->depth[64 * 128 + 64], 1e-4f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(int(mirrored->color.at(64, 64)[c]), int(plain->color.at(64, 64)[c]), 2);
    // and a mirror alongside an unmirrored instance in one draw culls each by its own handedness
    const std::vector<glm::mat4> both = {glm::translate(glm::mat4(1.0f), glm::vec3(-1.1f, 0, 0)),
                                         glm::translate(glm::mat4(1.0f), glm::vec3(1.1f, 0, 0)) * mirror};
    auto pair = render_offscreen(**renderer, camera, light, 128, 128, both);
    ASSERT_TRUE(pair.is_ok());
    const int left = 15, right = 127 - left; // the two centres' pixels (44 px a unit), symmetric about the image's centre
    EXPECT_NEAR(pair->depth[64 * 128 + left], pair->depth[64 * 128 + right], 1e-4f);
}

} // namespace
} // namespace standin
