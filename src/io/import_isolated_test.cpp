// Importing in a child process (ImportOptions::isolate_parser, import_isolated.cpp): the mesh that
// comes back is the one an in-process import gives, every field of it, and a file that crashes
// assimp is refused in one line naming it while this process goes on.
#include <standin/mesh.h>

#include "pbr_fixture.h"
#include "test_support.h"

#include <gtest/gtest.h>

namespace standin {
namespace {

const ImportOptions k_isolated{.isolate_parser = true};

void expect_same_material(const Material& a, const Material& b)
{
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.base_color, b.base_color);
    EXPECT_EQ(a.base_color_texture, b.base_color_texture);
    EXPECT_EQ(a.alpha_mode, b.alpha_mode);
    EXPECT_EQ(a.alpha_cutoff, b.alpha_cutoff);
    EXPECT_EQ(a.double_sided, b.double_sided);
    EXPECT_EQ(a.metallic, b.metallic);
    EXPECT_EQ(a.roughness, b.roughness);
    EXPECT_EQ(a.emissive, b.emissive);
    EXPECT_EQ(a.occlusion_strength, b.occlusion_strength);
    EXPECT_EQ(a.normal_scale, b.normal_scale);
    EXPECT_EQ(a.metallic_roughness_texture, b.metallic_roughness_texture);
    EXPECT_EQ(a.occlusion_texture, b.occlusion_texture);
    EXPECT_EQ(a.emissive_texture, b.emissive_texture);
    EXPECT_EQ(a.normal_texture, b.normal_texture);
}

void expect_same_import(const std::string& path)
{
    ImportReport in_report, out_report;
    Result<Mesh> in_process = import_mesh(path, &in_report);
    Result<Mesh> isolated = import_mesh(path, &out_report, k_isolated);
    ASSERT_TRUE(in_process.is_ok()) << in_process.status().message();
    ASSERT_TRUE(isolated.is_ok()) << isolated.status().message();
    const Mesh &a = *in_process, &b = *isolated;
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.colors, b.colors);
    EXPECT_EQ(a.uvs, b.uvs);
    EXPECT_EQ(a.indices, b.indices);
    EXPECT_EQ(a.face_materials, b.face_materials);
    ASSERT_EQ(a.materials.size(), b.materials.size());
    for (std::size_t i = 0; i < a.materials.size(); ++i) expect_same_material(a.materials[i], b.materials[i]);
    ASSERT_EQ(a.textures.size(), b.textures.size());
    for (std::size_t i = 0; i < a.textures.size(); ++i) {
        EXPECT_EQ(a.textures[i].name, b.textures[i].name);
        EXPECT_EQ(a.textures[i].width, b.textures[i].width);
        EXPECT_EQ(a.textures[i].height, b.textures[i].height);
        EXPECT_EQ(a.textures[i].rgba, b.textures[i].rgba);
    }
    EXPECT_EQ(in_report.source_path, out_report.source_path);
    EXPECT_EQ(in_report.format, out_report.format);
    EXPECT_EQ(in_report.degenerate_dropped, out_report.degenerate_dropped);
    EXPECT_EQ(in_report.meshes_in_scene, out_report.meshes_in_scene);
    EXPECT_EQ(in_report.warnings, out_report.warnings);
}

TEST(IsolatedImport, GivesWhatAnInProcessImportGives)
{
    expect_same_import(test::source_dir() + "/data/bunny.ply");
    expect_same_import(test::source_dir() + "/data/box_textured.glb"); // a texture
    // every PBR field and four maps
    expect_same_import(test::write_pbr_spheres_gltf(test::fresh_directory("isolated_import_pbr"), 200));
}

TEST(IsolatedImport, ErrorsComeBackAsTheyAre)
{
    std::string missing = test::fresh_directory("isolated_import_missing") + "/none.obj";
    Result<Mesh> in_process = import_mesh(missing);
    Result<Mesh> isolated = import_mesh(missing, nullptr, k_isolated);
    ASSERT_FALSE(isolated.is_ok());
    EXPECT_EQ(isolated.status().code(), in_process.status().code());
    EXPECT_EQ(isolated.status().message(), in_process.status().message());
}

// A 2 kB ASCII FBX, cut down from what assimp 5.2's own exporter writes for data/box_textured.glb:
// an embedded texture whose base64 ends in four '=' makes Debian 12's assimp (5.2.5) read out of
// bounds and die with SIGSEGV (under AddressSanitizer, its report and exit status 1). Importing it
// in process would end this test program.
TEST(IsolatedImport, AParserCrashIsOneLineNamingTheFile)
{
    std::string path = test::source_dir() + "/tests/data/assimp_base64_padding_crash.fbx";
    Result<Mesh> mesh = import_mesh(path, nullptr, k_isolated);
    ASSERT_FALSE(mesh.is_ok()) << "assimp no longer crashes on this file: find another for this test";
    EXPECT_EQ(mesh.status().code(), StatusCode::bad_data);
    const std::string& message = mesh.status().message();
    EXPECT_NE(message.find("assimp_base64_padding_crash.fbx"), std::string::npos) << message;
    EXPECT_NE(message.find("importer"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;

    // and this process goes on importing
    expect_same_import(test::source_dir() + "/data/teapot.ply");
}

} // namespace
} // namespace standin
