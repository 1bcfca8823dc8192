// Tests of the procedural meshes: triangle counts near the target, exact geometry (radius, area),
// closed and consistently oriented surfaces, determinism, the intricate shapes (shrub, fur ball),
// and option validation.
#include <standin/mesh.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <tuple>

namespace standin {
namespace {

Mesh generate_ok(const GenerateOptions& options)
{
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok()) << mesh.status().message();
    if (!mesh) return {};
    Status valid = validate_mesh(*mesh, "generated");
    EXPECT_TRUE(valid.is_ok()) << valid.message();
    return std::move(*mesh);
}

GenerateOptions shape(GeneratedShape s, std::size_t triangles)
{
    GenerateOptions options;
    options.shape = s;
    options.target_triangles = triangles;
    return options;
}

// Closed 2-manifold with consistent winding: every directed edge once, and its reverse once.
void expect_closed_and_oriented(const Mesh& mesh)
{
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) ++directed[{mesh.indices[t * 3 + k], mesh.indices[t * 3 + (k + 1) % 3]}];
    for (const auto& [edge, count] : directed) {
        ASSERT_EQ(count, 1) << edge.first << " -> " << edge.second;
        auto reverse = directed.find({edge.second, edge.first});
        ASSERT_NE(reverse, directed.end()) << "open edge " << edge.first << " -> " << edge.second;
    }
}

// Winding agrees with the vertex normals (faces point outwards).
void expect_normals_match_winding(const Mesh& mesh)
{
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        glm::vec3 p0 = mesh.positions[mesh.indices[t * 3]], p1 = mesh.positions[mesh.indices[t * 3 + 1]],
                  p2 = mesh.positions[mesh.indices[t * 3 + 2]];
        glm::vec3 face = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        for (int k = 0; k < 3; ++k)
            ASSERT_GT(glm::dot(face, mesh.normals[mesh.indices[t * 3 + k]]), 0.5f) << "triangle " << t;
    }
}

TEST(GenerateMesh, TriangleCountsNearTarget)
{
    for (GeneratedShape s : {GeneratedShape::sphere, GeneratedShape::torus, GeneratedShape::noisy_sphere})
        for (std::size_t target : {1000u, 20000u, 150000u}) {
            Mesh mesh = generate_ok(shape(s, target));
            double ratio = double(mesh.triangle_count()) / double(target);
            EXPECT_NEAR(ratio, 1.0, 0.05) << "shape " << int(s) << " target " << target;
        }
    // the smallest allowed target still gives a closed surface
    Mesh tiny = generate_ok(shape(GeneratedShape::sphere, 8));
    EXPECT_EQ(tiny.triangle_count(), 12u);
    expect_closed_and_oriented(tiny);
}

TEST(GenerateMesh, SphereVerticesLieOnTheRadius)
{
    GenerateOptions options = shape(GeneratedShape::sphere, 5000);
    options.radius = 2.5f;
    Mesh mesh = generate_ok(options);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
        ASSERT_NEAR(glm::length(mesh.positions[v]), 2.5f, 2.5e-6f);
        ASSERT_NEAR(glm::length(mesh.normals[v] - mesh.positions[v] / 2.5f), 0.0f, 1e-5f);
    }
    expect_closed_and_oriented(mesh);
    expect_normals_match_winding(mesh);
}

TEST(GenerateMesh, SurfaceAreasMatchTheAnalyticShapes)
{
    GenerateOptions sphere = shape(GeneratedShape::sphere, 20000);
    sphere.radius = 3.0f;
    EXPECT_NEAR(generate_ok(sphere).surface_area() / (4.0 * std::numbers::pi * 9.0), 1.0, 0.01);

    GenerateOptions torus = shape(GeneratedShape::torus, 20000);
    torus.radius = 2.0f;
    torus.minor_radius = 0.5f;
    Mesh mesh = generate_ok(torus);
    EXPECT_NEAR(mesh.surface_area() / (4.0 * std::numbers::pi * std::numbers::pi * 2.0 * 0.5), 1.0, 0.01);
    expect_closed_and_oriented(mesh);
    expect_normals_match_winding(mesh);
}

TEST(GenerateMesh, NoisySphereStaysWithinItsAmplitude)
{
    GenerateOptions options = shape(GeneratedShape::noisy_sphere, 20000);
    options.radius = 2.0f;
    options.noise_amplitude = 0.1f;
    Mesh mesh = generate_ok(options);
    float lowest = 1e9f, highest = 0.0f;
    for (glm::vec3 p : mesh.positions) {
        lowest = std::min(lowest, glm::length(p));
        highest = std::max(highest, glm::length(p));
    }
    EXPECT_GE(lowest, 2.0f * 0.9f - 1e-5f);
    EXPECT_LE(highest, 2.0f * 1.1f + 1e-5f);
    EXPECT_GT(highest - lowest, 0.05f); // it is really displaced
    expect_closed_and_oriented(mesh);
    expect_normals_match_winding(mesh);
}

TEST(GenerateMesh, Deterministic)
{
    for (GeneratedShape s : {GeneratedShape::sphere, GeneratedShape::torus, GeneratedShape::noisy_sphere}) {
        GenerateOptions options = shape(s, 30000);
        options.seed = 7;
        Mesh a = generate_ok(options), b = generate_ok(options);
        EXPECT_EQ(a.positions, b.positions);
        EXPECT_EQ(a.normals, b.normals);
        EXPECT_EQ(a.indices, b.indices);
    }
    GenerateOptions seeded = shape(GeneratedShape::noisy_sphere, 2000);
    seeded.seed = 1;
    Mesh one = generate_ok(seeded);
    seeded.seed = 2;
    EXPECT_NE(one.positions, generate_ok(seeded).positions);
}

TEST(GenerateMesh, ColourComesFromOptions)
{
    GenerateOptions options = shape(GeneratedShape::torus, 500);
    options.color = {0.1f, 0.2f, 0.3f, 1.0f};
    Mesh mesh = generate_ok(options);
    ASSERT_EQ(mesh.materials.size(), 1u);
    for (glm::vec4 c : mesh.colors) EXPECT_EQ(c, options.color);
    EXPECT_EQ(mesh.albedo_at(0, 0.3f, 0.3f), options.color);
}

TEST(GenerateMesh, ShrubAndFurBall)
{
    for (GeneratedShape s : {GeneratedShape::shrub, GeneratedShape::fur_ball}) {
        for (std::size_t target : {std::size_t(200), std::size_t(5000), std::size_t(25000)}) {
            GenerateOptions options = shape(s, target);
            options.radius = 2.0f;
            Mesh a = generate_ok(options), b = generate_ok(options);
            double ratio = double(a.triangle_count()) / double(target);
            EXPECT_NEAR(ratio, 1.0, 0.1) << "shape " << int(s) << " target " << target;
            // repeatable, fitted into the sphere of the radius, coloured per part
            EXPECT_EQ(a.positions, b.positions);
            EXPECT_EQ(a.colors, b.colors);
            EXPECT_NEAR(a.bounding_sphere().radius, 2.0f, 1e-3f);
            EXPECT_NEAR(glm::length(a.bounding_sphere().center), 0.0f, 1e-3f);
            std::set<std::tuple<float, float, float>> colours;
            for (const glm::vec4& c : a.colors) colours.insert({c.x, c.y, c.z});
            EXPECT_GT(colours.size(), 10u);
        }
        GenerateOptions seeded = shape(s, 3000);
        seeded.seed = 2;
        EXPECT_NE(generate_ok(shape(s, 3000)).positions, generate_ok(seeded).positions);
    }
}

TEST(GenerateMesh, RejectsBadOptions)
{
    auto expect_invalid = [](GenerateOptions options, const char* field) {
        Result<Mesh> mesh = generate_mesh(options);
        ASSERT_FALSE(mesh.is_ok()) << field;
        EXPECT_EQ(mesh.status().code(), StatusCode::invalid_argument);
        EXPECT_NE(mesh.status().message().find(field), std::string::npos) << mesh.status().message();
    };
    GenerateOptions base;
    GenerateOptions o = base;
    o.target_triangles = 7;
    expect_invalid(o, "target_triangles");
    o.target_triangles = 50'000'001;
    expect_invalid(o, "target_triangles");
    for (float radius : {0.0f, -1.0f, NAN, INFINITY}) {
        o = base;
        o.radius = radius;
        expect_invalid(o, "radius");
    }
    o = shape(GeneratedShape::torus, 1000);
    o.minor_radius = 1.5f;
    expect_invalid(o, "minor_radius");
    o = shape(GeneratedShape::noisy_sphere, 1000);
    o.noise_amplitude = 1.5f;
    expect_invalid(o, "noise_amplitude");
}

} // namespace
} // namespace standin
