// The control mesh: cone merging, the cone invariant after every collapse, reaching the target,
// stopping early (reported) when the cones allow no coarser mesh, determinism, boundary loops
// keeping their floor of vertices.
#include "reps/displaced_mesh/control_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <vector>

namespace standin::displaced_mesh {
namespace {

Mesh noisy_sphere(std::size_t triangles, float amplitude = 0.08f)
{
    GenerateOptions options;
    options.shape = GeneratedShape::noisy_sphere;
    options.target_triangles = triangles;
    options.noise_amplitude = amplitude;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

TEST(DisplacedMeshControl, ConesMergeToTheSmallestHoldingBoth)
{
    NormalCone a = merge_direction({}, {1, 0, 0});
    EXPECT_FLOAT_EQ(a.half_angle, 0.0f);
    NormalCone b = merge_direction(a, {0, 1, 0});
    EXPECT_NEAR(b.half_angle, std::numbers::pi_v<float> / 4.0f, 1e-6f);
    EXPECT_NEAR(glm::dot(b.axis, glm::normalize(glm::vec3(1, 1, 0))), 1.0f, 1e-6f);
    EXPECT_TRUE(b.contains({1, 0, 0}));
    EXPECT_TRUE(b.contains({0, 1, 0}));
    EXPECT_FALSE(b.contains({0, 0, 1}));
    // a cone inside another changes nothing; opposite directions fill a half-sphere exactly
    EXPECT_EQ(merge_cones(b, merge_direction({}, glm::normalize(glm::vec3(1, 1, 0)))).half_angle, b.half_angle);
    EXPECT_GE(merge_direction(a, {-1, 0, 0}).half_angle, std::numbers::pi_v<float> / 2.0f - 1e-6f);
}

TEST(DisplacedMeshControl, ConeInvariantHoldsAfterEveryCollapse)
{
    Mesh mesh = noisy_sphere(3000, 0.3f);
    ControlMeshOptions options;
    options.target_faces = 40;
    options.cone_angle_degrees = 90.0f;
    std::size_t collapses = 0, violations = 0;
    const float limit = glm::radians(options.cone_angle_degrees);
    options.observer = [&](const CollapseView& view) {
        ++collapses;
        for (std::uint32_t v : view.affected_vertices()) {
            NormalCone cone = view.cone(v);
            if (!(cone.half_angle < limit)) ++violations;
            for (glm::vec3 n : view.face_normals_around(v))
                if (!cone.contains(n, 1e-3f)) ++violations;
        }
    };
    Result<ControlMesh> control = build_control_mesh(mesh, options);
    ASSERT_TRUE(control.is_ok()) << control.status().message();
    EXPECT_EQ(collapses, control->collapses);
    EXPECT_GT(collapses, 1000u);
    EXPECT_EQ(violations, 0u);
    for (const NormalCone& cone : control->cones) EXPECT_LT(cone.half_angle, limit);
}

TEST(DisplacedMeshControl, SphereReachesTheTargetWithInputVertices)
{
    Mesh mesh = noisy_sphere(8000);
    ControlMeshOptions options;
    options.target_faces = 200;
    Result<ControlMesh> control = build_control_mesh(mesh, options);
    ASSERT_TRUE(control.is_ok());
    EXPECT_TRUE(control->reached_target);
    EXPECT_EQ(control->stopped_by, "target");
    EXPECT_LE(control->face_count(), 200u);
    EXPECT_GE(control->face_count(), 196u);
    // half-edge collapses keep input positions; a closed sphere stays closed (V - E + F = 2)
    std::set<std::tuple<float, float, float>> input;
    for (glm::vec3 p : mesh.positions) input.insert({p.x, p.y, p.z});
    for (glm::vec3 p : control->positions) EXPECT_TRUE(input.count({p.x, p.y, p.z}));
    EXPECT_EQ(control->positions.size() + control->face_count() - 3 * control->face_count() / 2, 2u);
    for (glm::vec3 n : control->normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(DisplacedMeshControl, ConesStopSimplificationEarlyAndSayWhy)
{
    // a sphere cannot become 4 faces without a vertex's cone passing a half-sphere
    Mesh mesh = noisy_sphere(2000, 0.0f);
    ControlMeshOptions options;
    options.target_faces = 4;
    Result<ControlMesh> control = build_control_mesh(mesh, options);
    ASSERT_TRUE(control.is_ok());
    EXPECT_FALSE(control->reached_target);
    EXPECT_EQ(control->stopped_by, "no valid collapse");
    EXPECT_GT(control->face_count(), 4u);
    EXPECT_GT(control->refused_cone, 0u);
    // a narrower cone stops it earlier
    options.cone_angle_degrees = 45.0f;
    Result<ControlMesh> narrow = build_control_mesh(mesh, options);
    ASSERT_TRUE(narrow.is_ok());
    EXPECT_GT(narrow->face_count(), control->face_count());
}

TEST(DisplacedMeshControl, DeterministicAndRefusesBadOptions)
{
    Mesh mesh = noisy_sphere(4000, 0.2f);
    ControlMeshOptions options;
    options.target_faces = 100;
    Result<ControlMesh> a = build_control_mesh(mesh, options), b = build_control_mesh(mesh, options);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    EXPECT_EQ(a->indices, b->indices);
    EXPECT_EQ(a->positions, b->positions);
    options.target_faces = 0;
    EXPECT_EQ(build_control_mesh(mesh, options).status().code(), StatusCode::invalid_argument);
    options.target_faces = 10;
    options.cone_angle_degrees = 0.0f;
    EXPECT_EQ(build_control_mesh(mesh, options).status().code(), StatusCode::invalid_argument);
}

// Issue #14: with keep_cutout_faces every face of an alpha-masked material (the generated tree's
// leaf cards) survives as it was, corners and all; without, the simplifier halves the cards.
TEST(DisplacedMeshControl, KeepCutoutFacesKeepsEveryLeafCardWhole)
{
    GenerateOptions generate;
    generate.shape = GeneratedShape::tree;
    generate.target_triangles = 2000;
    generate.seed = 3;
    Result<Mesh> tree = generate_mesh(generate);
    ASSERT_TRUE(tree.is_ok());
    auto key = [](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        std::vector<float> k{a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
        return k;
    };
    auto leaf_faces_kept = [&](const ControlMesh& control) {
        std::set<std::vector<float>> faces;
        for (std::size_t f = 0; f < control.face_count(); ++f) {
            glm::vec3 p[3];
            for (int k = 0; k < 3; ++k) p[k] = control.positions[control.indices[3 * f + std::size_t(k)]] + glm::vec3(0.0f);
            // any rotation of the corners
            for (int r = 0; r < 3; ++r) faces.insert(key(p[r], p[(r + 1) % 3], p[(r + 2) % 3]));
        }
        std::size_t leaves = 0, kept = 0;
        for (std::size_t t = 0; t < tree->triangle_count(); ++t) {
            if (alpha_test_cutoff(tree->materials[tree->face_materials[t]]) <= 0.0f) continue;
            ++leaves;
            const std::uint32_t* i = &tree->indices[3 * t];
            kept += faces.count(key(tree->positions[i[0]] + glm::vec3(0.0f), tree->positions[i[1]] + glm::vec3(0.0f),
                                    tree->positions[i[2]] + glm::vec3(0.0f)));
        }
        EXPECT_GT(leaves, 500u);
        return double(kept) / double(leaves);
    };
    ControlMeshOptions options;
    options.target_faces = 256;
    Result<ControlMesh> plain = build_control_mesh(*tree, options);
    options.keep_cutout_faces = true;
    Result<ControlMesh> kept = build_control_mesh(*tree, options);
    ASSERT_TRUE(plain.is_ok() && kept.is_ok());
    EXPECT_EQ(leaf_faces_kept(*kept), 1.0);
    EXPECT_LT(leaf_faces_kept(*plain), 0.6);
    EXPECT_GT(kept->face_count(), plain->face_count());
}

// A flat annulus (a flange: one open sheet with two boundary loops), `segments` around, `rings`
// across, radii 0.5 and 1.
Mesh annulus(int segments, int rings)
{
    Mesh mesh;
    for (int r = 0; r <= rings; ++r)
        for (int s = 0; s < segments; ++s) {
            float radius = 0.5f + 0.5f * float(r) / float(rings), a = 2.0f * std::numbers::pi_v<float> * float(s) / float(segments);
            mesh.positions.push_back({radius * std::cos(a), radius * std::sin(a), 0.0f});
            mesh.colors.push_back({0.8f, 0.8f, 0.8f, 1.0f});
        }
    auto at = [&](int r, int s) { return std::uint32_t(r * segments + (s % segments)); };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s)
            mesh.indices.insert(mesh.indices.end(), {at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s), at(r + 1, s + 1), at(r, s + 1)});
    mesh.materials.push_back(Material{});
    mesh.face_materials.assign(mesh.triangle_count(), 0);
    compute_smooth_normals(mesh);
    return mesh;
}

// A flat sheet's outline is its boundary loops' polygon (displacement moves along the normal
// only): without a floor the quadrics take an annulus's round hole down to a triangle; with
// min_loop_vertices each loop keeps that many vertices, and the mesh still ends on input vertices.
TEST(DisplacedMeshControl, BoundaryLoopsKeepTheirFloorOfVertices)
{
    Mesh mesh = annulus(48, 6);
    auto loop_vertices = [](const ControlMesh& control, bool inner) {
        std::size_t count = 0;
        for (glm::vec3 p : control.positions) {
            float radius = glm::length(p);
            count += inner ? std::abs(radius - 0.5f) < 1e-4f : std::abs(radius - 1.0f) < 1e-4f;
        }
        return count;
    };
    ControlMeshOptions options;
    options.target_faces = 4;
    Result<ControlMesh> free = build_control_mesh(mesh, options);
    ASSERT_TRUE(free.is_ok());
    EXPECT_LE(loop_vertices(*free, true), 6u);
    options.min_loop_vertices = 12;
    Result<ControlMesh> kept = build_control_mesh(mesh, options);
    ASSERT_TRUE(kept.is_ok());
    EXPECT_EQ(loop_vertices(*kept, true), 12u);
    EXPECT_EQ(loop_vertices(*kept, false), 12u);
    EXPECT_FALSE(kept->reached_target);
    // a loop with fewer vertices than the floor keeps them all
    options.min_loop_vertices = 100;
    Result<ControlMesh> all = build_control_mesh(mesh, options);
    ASSERT_TRUE(all.is_ok());
    EXPECT_EQ(loop_vertices(*all, true), 48u);
    EXPECT_EQ(loop_vertices(*all, false), 48u);
}

} // namespace
} // namespace standin::displaced_mesh
