// glTF metallic-roughness through the importer (issue #14): factors, the metallic-roughness,
// occlusion and emissive maps, and Mesh::pbr_at sampling them, on the test-written four-sphere
// model of tests/pbr_fixture.h; formats without PBR materials keep the defaults.
#include <standin/mesh.h>

#include "pbr_fixture.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace standin {
namespace {

// The triangle of material `material` whose first corner is nearest `latitude_y` on its sphere.
std::size_t pbr_triangle_near(const Mesh& mesh, std::uint32_t material, float latitude_y)
{
    std::size_t best = 0;
    float best_distance = 1e30f;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        if (mesh.face_materials[t] != material) continue;
        float d = std::abs(mesh.positions[mesh.indices[t * 3]].y - latitude_y);
        if (d < best_distance) best_distance = d, best = t;
    }
    return best;
}

TEST(ImportPbr, GltfFactorsAndMapsAreRead)
{
    std::string dir = test::fresh_directory("import_pbr");
    std::string path = test::write_pbr_spheres_gltf(dir, 800);
    ASSERT_FALSE(path.empty());
    ImportReport report;
    Result<Mesh> imported = import_mesh(path, &report);
    ASSERT_TRUE(imported.is_ok()) << imported.status().message();
    const Mesh& mesh = *imported;
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(mesh.materials.size(), 4u);
    EXPECT_TRUE(mesh.has_pbr_materials());

    const Material& gold = mesh.materials[0];
    EXPECT_FLOAT_EQ(gold.metallic, 1.0f);
    EXPECT_FLOAT_EQ(gold.roughness, 0.3f);
    EXPECT_EQ(gold.metallic_roughness_texture, -1);
    const Material& plastic = mesh.materials[1];
    EXPECT_FLOAT_EQ(plastic.metallic, 0.0f);
    EXPECT_FLOAT_EQ(plastic.roughness, 0.2f);
    EXPECT_EQ(plastic.emissive, glm::vec3(0.0f));

    const Material& mapped = mesh.materials[3];
    ASSERT_GE(mapped.metallic_roughness_texture, 0);
    ASSERT_GE(mapped.occlusion_texture, 0);
    ASSERT_GE(mapped.emissive_texture, 0);
    EXPECT_EQ(mapped.normal_texture, -1);
    EXPECT_NEAR(mapped.emissive.z, 1.0f, 1e-6f);
    ASSERT_TRUE(mesh.has_texture_coordinates());

    // near the north pole: smooth metal (G 40, B 255), unoccluded, emitting blue
    PbrSample north = mesh.pbr_at(pbr_triangle_near(mesh, 3, 1.0f), 1.0f / 3, 1.0f / 3);
    EXPECT_NEAR(north.metallic, 1.0f, 0.02f);
    EXPECT_NEAR(north.roughness, 40.0f / 255.0f, 0.03f);
    EXPECT_NEAR(north.occlusion, 1.0f, 0.02f);
    EXPECT_NEAR(north.emissive.z, 1.0f, 0.05f);
    EXPECT_NEAR(north.emissive.x, 0.1f, 0.02f);
    // near the south pole: rough dielectric (G 230, B 0), occluded to 90/255, no emission
    PbrSample south = mesh.pbr_at(pbr_triangle_near(mesh, 3, -1.0f), 1.0f / 3, 1.0f / 3);
    EXPECT_NEAR(south.metallic, 0.0f, 0.02f);
    EXPECT_NEAR(south.roughness, 230.0f / 255.0f, 0.03f);
    EXPECT_NEAR(south.occlusion, 90.0f / 255.0f, 0.03f);
    EXPECT_NEAR(south.emissive.z, 0.0f, 0.02f);
    // factors alone elsewhere
    PbrSample on_gold = mesh.pbr_at(pbr_triangle_near(mesh, 0, 0.0f), 0.2f, 0.3f);
    EXPECT_FLOAT_EQ(on_gold.metallic, 1.0f);
    EXPECT_FLOAT_EQ(on_gold.roughness, 0.3f);
    EXPECT_FLOAT_EQ(on_gold.occlusion, 1.0f);
}

TEST(ImportPbr, FormatsWithoutPbrKeepTheDefaults)
{
    std::string dir = test::fresh_directory("import_pbr_obj");
    std::ofstream(dir + "/m.mtl") << "newmtl m\nKd 0.5 0.25 1\n";
    std::ofstream(dir + "/m.obj") << "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n";
    Result<Mesh> mesh = import_mesh(dir + "/m.obj");
    ASSERT_TRUE(mesh.is_ok()) << mesh.status().message();
    EXPECT_FALSE(mesh->has_pbr_materials());
    PbrSample sample = mesh->pbr_at(0, 0.3f, 0.3f);
    EXPECT_EQ(sample.metallic, 0.0f);
    EXPECT_EQ(sample.roughness, 1.0f);
    EXPECT_EQ(sample.occlusion, 1.0f);
    EXPECT_EQ(sample.emissive, glm::vec3(0.0f));

    Result<Mesh> bunny = import_mesh(test::source_dir() + "/data/bunny.ply");
    ASSERT_TRUE(bunny.is_ok());
    EXPECT_FALSE(bunny->has_pbr_materials());
}

TEST(ImportPbr, NormalMapBendsTheShadingNormal)
{
    // one triangle in the xy plane, UVs along x and y, a normal map tilting every normal towards +u
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.colors.assign(3, glm::vec4(1.0f));
    mesh.uvs = {{0, 0}, {1, 0}, {0, 1}};
    mesh.indices = {0, 1, 2};
    mesh.face_materials = {0};
    Texture map;
    map.width = map.height = 1;
    glm::vec3 tilted = glm::normalize(glm::vec3(1, 0, 1));
    glm::u8vec3 encoded(glm::round((tilted * 0.5f + 0.5f) * 255.0f));
    map.rgba = {encoded.x, encoded.y, encoded.z, 255};
    mesh.textures.push_back(map);
    Material material;
    material.normal_texture = 0;
    mesh.materials.push_back(material);
    ASSERT_TRUE(validate_mesh(mesh, "normal-mapped triangle").is_ok());
    glm::vec3 n = mesh.shading_normal_at(0, 0.3f, 0.3f);
    EXPECT_NEAR(glm::length(n - tilted), 0.0f, 0.02f);
    // the material without its map: the interpolated normal
    mesh.materials[0].normal_texture = -1;
    EXPECT_NEAR(glm::length(mesh.shading_normal_at(0, 0.3f, 0.3f) - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

TEST(ImportPbr, OutOfRangeMapIsBadData)
{
    Mesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
    mesh.colors.assign(3, glm::vec4(1.0f));
    mesh.indices = {0, 1, 2};
    mesh.face_materials = {0};
    Material material;
    material.metallic_roughness_texture = 3;
    mesh.materials.push_back(material);
    Status status = validate_mesh(mesh, "m");
    EXPECT_EQ(status.code(), StatusCode::bad_data);
    EXPECT_NE(status.message().find("metallic_roughness_texture"), std::string::npos) << status.message();
}

// Not a test: writes the four-sphere model for the docs/RESULTS.md "PBR materials" measurements
// into $STANDIN_PBR_MODEL_DIR (run with --gtest_also_run_disabled_tests).
TEST(ImportPbr, DISABLED_WriteMeasurementModel)
{
    const char* dir = std::getenv("STANDIN_PBR_MODEL_DIR");
    ASSERT_NE(dir, nullptr) << "set STANDIN_PBR_MODEL_DIR";
    std::string path = test::write_pbr_spheres_gltf(dir, 20000);
    ASSERT_FALSE(path.empty());
    std::printf("wrote %s\n", path.c_str());
}

} // namespace
} // namespace standin
