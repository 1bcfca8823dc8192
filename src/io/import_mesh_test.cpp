// Tests of import_mesh on files written here (OBJ/MTL with PNG textures, glTF with a node
// hierarchy, OFF, PLY from write_ply), on the bundled models in data/, and on bad inputs: each
// error must come back as a Status with the right code and the file's path in the message.
#include <standin/image.h>
#include <standin/mesh.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <random>
#include <sstream>

namespace standin {
namespace {

namespace fs = std::filesystem;

std::string import_test_dir(const std::string& name)
{
    fs::path dir = fs::path(::testing::TempDir()) / ("standin_import_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

std::string write_text(const std::string& dir, const std::string& name, const std::string& contents)
{
    std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << contents;
    return path;
}

// test::source_dir(), not __FILE__: a compiler cache with a base directory (ccache's
// CCACHE_BASEDIR) makes __FILE__ relative to the build folder.
std::string data_path(const std::string& name) { return test::source_dir() + "/data/" + name; }

Mesh import_ok(const std::string& path, ImportReport* report = nullptr, const ImportOptions& options = {})
{
    Result<Mesh> mesh = import_mesh(path, report, options);
    EXPECT_TRUE(mesh.is_ok()) << mesh.status().message();
    if (!mesh) return {};
    Status valid = validate_mesh(*mesh, path);
    EXPECT_TRUE(valid.is_ok()) << valid.message();
    return std::move(*mesh);
}

void expect_error(const std::string& path, StatusCode code, const std::string& fragment = "")
{
    Result<Mesh> mesh = import_mesh(path);
    ASSERT_FALSE(mesh.is_ok()) << path;
    EXPECT_EQ(mesh.status().code(), code) << mesh.status().message();
    EXPECT_NE(mesh.status().message().find(path), std::string::npos) << mesh.status().message();
    EXPECT_NE(mesh.status().message().find(fragment), std::string::npos) << mesh.status().message();
    EXPECT_EQ(mesh.status().message().find('\n'), std::string::npos) << mesh.status().message();
}

using test::expect_near;

glm::vec3 corner(const Mesh& mesh, std::size_t triangle, int k) { return mesh.positions[mesh.indices[triangle * 3 + k]]; }

// The normal the winding implies, to check that it agrees with the vertex normals.
glm::vec3 geometric_normal(const Mesh& mesh, std::size_t t)
{
    return glm::normalize(glm::cross(corner(mesh, t, 1) - corner(mesh, t, 0), corner(mesh, t, 2) - corner(mesh, t, 0)));
}

// ---------------------------------------------------------------------------------------------
// Round trips and formats

TEST(ImportMesh, PlyRoundTrip)
{
    GenerateOptions options;
    options.target_triangles = 600;
    options.color = {0.2f, 0.4f, 0.6f, 1.0f};
    Result<Mesh> original = generate_mesh(options);
    ASSERT_TRUE(original.is_ok());
    std::string path = import_test_dir("ply_round_trip") + "/sphere.ply";
    ASSERT_TRUE(write_ply(*original, path).is_ok());

    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_EQ(report.format, "ply");
    EXPECT_EQ(report.degenerate_dropped, 0u);
    ASSERT_EQ(mesh.triangle_count(), original->triangle_count());
    EXPECT_EQ(mesh.vertex_count(), original->vertex_count());
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = mesh.indices[t * 3 + k], b = original->indices[t * 3 + k];
            ASSERT_EQ(mesh.positions[a], original->positions[b]) << "triangle " << t;
            EXPECT_NEAR(glm::length(mesh.normals[a] - original->normals[b]), 0.0f, 1e-6f);
            expect_near(mesh.colors[a], original->colors[b], 0.5f / 255.0f);
        }
}

TEST(ImportMesh, PlyBodyStartingWithANewlineByte)
{
    // assimp 5.2.5 skips a '\n' right after end_header and misreads the rest; our reader must not
    std::uint32_t bits = 0x3F80000Au; // 1.0000012f, whose first little-endian byte is '\n'
    float x;
    std::memcpy(&x, &bits, sizeof x);
    Mesh original;
    original.positions = {{x, 0, 0}, {2, 0, 0}, {0, 1, 0}};
    original.normals.assign(3, glm::vec3(0, 0, 1));
    original.colors.assign(3, glm::vec4(1));
    original.indices = {0, 1, 2};
    original.face_materials = {0};
    original.materials.resize(1);
    std::string path = import_test_dir("ply_newline") + "/newline.ply";
    ASSERT_TRUE(write_ply(original, path).is_ok());
    Mesh mesh = import_ok(path);
    ASSERT_EQ(mesh.triangle_count(), 1u);
    EXPECT_EQ(corner(mesh, 0, 0), original.positions[0]);
    EXPECT_EQ(corner(mesh, 0, 2), original.positions[2]);
}

TEST(ImportMesh, AsciiPlyWithPolygonsColoursAndCrlf)
{
    std::string header =
        "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 4\r\n"
        "property float x\r\nproperty float y\r\nproperty float z\r\n"
        "property uchar red\r\nproperty uchar green\r\nproperty uchar blue\r\n"
        "element face 2\r\nproperty list uchar int vertex_indices\r\nelement edge 1\r\n"
        "property int vertex1\r\nproperty int vertex2\r\nend_header\r\n";
    std::string body = "0 0 0 255 0 0\r\n1 0 0 255 0 0\r\n1 1 0 0 0 255\r\n+0 1 0 0 0 255\r\n4 0 1 2 3\r\n2 0 1\r\n0 1\r\n";
    std::string path = write_text(import_test_dir("ply_ascii"), "quad.ply", header + body);
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_EQ(mesh.triangle_count(), 2u);
    EXPECT_DOUBLE_EQ(mesh.surface_area(), 1.0);
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        expect_near(mesh.colors[v], mesh.positions[v].y < 0.5f ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 0, 1, 1), 1e-6f);
    for (glm::vec3 n : mesh.normals) EXPECT_NEAR(glm::length(n - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    ASSERT_EQ(report.warnings.size(), 1u); // the two-corner face
    EXPECT_NE(report.warnings[0].find("fewer than 3"), std::string::npos) << report.warnings[0];
}

// A vertex colour set with no positive component paints nothing (assimp's Blender loader gives
// Blender's grey default cube one of (-1, -1, -1, -1)): the material's colour stays, not black.
// A negative channel among painted ones reflects no light rather than less than none.
TEST(ImportMesh, VertexColoursWithNothingPositiveAreNotPaint)
{
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float red\nproperty float green\nproperty float blue\nproperty float alpha\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const std::string dir = import_test_dir("ply_unset_colours");
    Mesh unset = import_ok(write_text(dir, "unset.ply", header + "0 0 0 -1 -1 -1 -1\n1 0 0 -1 -1 -1 -1\n0 1 0 0 0 0 0\n3 0 1 2\n"));
    for (const glm::vec4& c : unset.colors) expect_near(c, glm::vec4(0.8f, 0.8f, 0.8f, 1.0f), 1e-6f); // the default material's
    Mesh painted = import_ok(write_text(dir, "painted.ply", header + "0 0 0 0.5 -1 0.25 1\n1 0 0 0.5 -1 0.25 1\n0 1 0 0.5 -1 0.25 1\n3 0 1 2\n"));
    for (const glm::vec4& c : painted.colors) expect_near(c, glm::vec4(0.5f, 0.0f, 0.25f, 1.0f), 1e-6f);
}

TEST(ImportMesh, BigEndianPly)
{
    std::string bytes =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
        "element face 1\nproperty list uchar ushort vertex_indices\nend_header\n";
    auto put_be = [&](const void* data, std::size_t size) {
        for (std::size_t i = size; i-- > 0;) bytes += static_cast<const char*>(data)[i];
    };
    for (double value : {0.0, 0.0, 0.0, 3.0, 0.0, 0.0, 0.0, 2.0, 0.0}) put_be(&value, sizeof value);
    bytes += char(3);
    for (std::uint16_t index : {0, 1, 2}) put_be(&index, sizeof index);
    std::string path = write_text(import_test_dir("ply_big_endian"), "big.ply", bytes);
    Mesh mesh = import_ok(path);
    ASSERT_EQ(mesh.triangle_count(), 1u);
    EXPECT_DOUBLE_EQ(mesh.surface_area(), 3.0);
    EXPECT_EQ(mesh.bounds().max, glm::vec3(3, 2, 0));
}

TEST(ImportMesh, MalformedPlyIsBadData)
{
    std::string dir = import_test_dir("ply_malformed");
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                               "element face 1\nproperty list uchar int vertex_indices\n";
    // assimp 5.2.5 loops forever on this one
    expect_error(write_text(dir, "no_end.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 99999\n\x01\x02garbage"),
                 StatusCode::bad_data, "end_header");
    expect_error(write_text(dir, "index.ply", header + "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"), StatusCode::bad_data, "vertex 7");
    expect_error(write_text(dir, "short.ply", header + "end_header\n0 0 0\n1 0 0\n"), StatusCode::bad_data);
    expect_error(write_text(dir, "words.ply", header + "end_header\n0 0 zero\n1 0 0\n0 1 0\n3 0 1 2\n"), StatusCode::bad_data);
    expect_error(write_text(dir, "huge.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
                                             "property float y\nproperty float z\nend_header\n\x01\x02\x03\x04"),
                 StatusCode::bad_data, "4000000000");
    expect_error(write_text(dir, "points.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                               "property float z\nend_header\n0 0 0\n"),
                 StatusCode::bad_data, "contains no triangles");
    expect_error(write_text(dir, "type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n"),
                 StatusCode::bad_data, "quaternion");
}

TEST(ImportMesh, ObjQuadIsTriangulatedAndKeepsNormals)
{
    std::string dir = import_test_dir("obj_quad");
    std::string path = write_text(dir, "quad.obj",
                                  "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                  "vn 0.6 0 0.8\n"
                                  "f 1//1 2//1 3//1 4//1\n");
    Mesh mesh = import_ok(path);
    EXPECT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.vertex_count(), 4u);
    EXPECT_DOUBLE_EQ(mesh.surface_area(), 1.0);
    for (glm::vec3 n : mesh.normals) EXPECT_NEAR(glm::length(n - glm::vec3(0.6f, 0, 0.8f)), 0.0f, 1e-6f);
    // no MTL: the neutral grey, not assimp's default material colour
    for (glm::vec4 c : mesh.colors) expect_near(c, {0.8f, 0.8f, 0.8f, 1.0f}, 1e-6f);
    EXPECT_FALSE(mesh.has_texture_coordinates());
}

TEST(ImportMesh, ObjMaterialColoursBecomeVertexColours)
{
    std::string dir = import_test_dir("obj_mtl");
    write_text(dir, "colours.mtl",
               "newmtl red\nKd 0.9 0.1 0.1\n"
               "newmtl blue\nKd 0.2 0.4 0.6\nd 0.5\n");
    std::string path = write_text(dir, "colours.obj",
                                  "mtllib colours.mtl\n"
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\n"
                                  "usemtl red\nf 1 2 3\n"
                                  "usemtl blue\nf 4 5 6\n");
    Mesh mesh = import_ok(path);
    ASSERT_EQ(mesh.triangle_count(), 2u);
    EXPECT_EQ(mesh.materials.size(), 2u);
    for (std::size_t t = 0; t < 2; ++t) {
        bool left = corner(mesh, t, 0).x < 2.0f;
        glm::vec4 expected = left ? glm::vec4(0.9f, 0.1f, 0.1f, 1.0f) : glm::vec4(0.2f, 0.4f, 0.6f, 0.5f);
        for (int k = 0; k < 3; ++k) expect_near(mesh.colors[mesh.indices[t * 3 + k]], expected, 1e-6f);
        expect_near(mesh.albedo_at(t, 0.3f, 0.3f), expected, 1e-6f);
        EXPECT_EQ(mesh.materials[mesh.face_materials[t]].name, left ? "red" : "blue");
    }
}

// A 2x2 PNG whose top row (v = 1 in OBJ) is red, green and bottom row blue, white.
void write_checker_png(const std::string& path)
{
    ImageRGBA8 image(2, 2);
    const std::uint8_t texels[4][4] = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}, {255, 255, 255, 255}};
    for (int i = 0; i < 4; ++i) std::memcpy(image.at(i % 2, i / 2), texels[i], 4);
    ASSERT_TRUE(write_png(image, path).is_ok());
}

TEST(ImportMesh, ObjTextureIsSampledAndKept)
{
    std::string dir = import_test_dir("obj_texture");
    write_checker_png(dir + "/checker.png");
    write_text(dir, "textured.mtl", "newmtl checker\nKd 1 1 1\nmap_Kd checker.png\n");
    // each corner's UV is the centre of one texel
    std::string path = write_text(dir, "textured.obj",
                                  "mtllib textured.mtl\n"
                                  "v 0 1 0\nv 1 1 0\nv 1 0 0\nv 0 0 0\n"
                                  "vt 0.25 0.75\nvt 0.75 0.75\nvt 0.75 0.25\nvt 0.25 0.25\n"
                                  "usemtl checker\nf 4/4 3/3 2/2 1/1\n");
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(mesh.textures.size(), 1u);
    EXPECT_EQ(mesh.textures[0].width, 2);
    EXPECT_EQ(mesh.textures[0].height, 2);
    ASSERT_TRUE(mesh.has_texture_coordinates());
    ASSERT_EQ(mesh.triangle_count(), 2u);

    auto texel_for = [](glm::vec3 p) {
        if (p.y > 0.5f) return p.x < 0.5f ? glm::vec4(1, 0, 0, 1) : glm::vec4(0, 1, 0, 1);
        return p.x < 0.5f ? glm::vec4(0, 0, 1, 1) : glm::vec4(1, 1, 1, 1);
    };
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        EXPECT_EQ(mesh.materials[mesh.face_materials[t]].base_color_texture, 0);
        expect_near(mesh.albedo_at(t, 0, 0), texel_for(corner(mesh, t, 0)), 1e-5f);
        expect_near(mesh.albedo_at(t, 1, 0), texel_for(corner(mesh, t, 1)), 1e-5f);
        expect_near(mesh.albedo_at(t, 0, 1), texel_for(corner(mesh, t, 2)), 1e-5f);
    }

    // write_ply folds the texture into the vertex colours; importing that gives the same albedo
    ASSERT_TRUE(write_ply(mesh, dir + "/flattened.ply").is_ok());
    Mesh flattened = import_ok(dir + "/flattened.ply");
    EXPECT_TRUE(flattened.textures.empty());
    for (std::size_t v = 0; v < flattened.vertex_count(); ++v)
        expect_near(flattened.colors[v], texel_for(flattened.positions[v]), 1e-6f);
}

TEST(ImportMesh, TexturePathsWithBackslashesAndSpaces)
{
    std::string dir = import_test_dir("obj_texture_paths");
    fs::create_directories(dir + "/my textures");
    write_checker_png(dir + "/my textures/checker 1.png");
    write_text(dir, "m.mtl", "newmtl m\nKd 1 1 1\nmap_Kd my textures\\checker 1.png\n");
    std::string path = write_text(dir, "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvt 0.25 0.75\nvt 0.25 0.75\n"
                                                "usemtl m\nf 1/1 2/2 3/3\n");
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
    ASSERT_EQ(mesh.textures.size(), 1u);
    expect_near(mesh.albedo_at(0, 0.3f, 0.3f), {1, 0, 0, 1}, 1e-5f);
}

TEST(ImportMesh, MissingTextureFallsBackToMaterialColourWithWarning)
{
    std::string dir = import_test_dir("obj_missing_texture");
    write_text(dir, "m.mtl", "newmtl m\nKd 0.5 0.25 1\nmap_Kd nowhere.png\n");
    std::string path = write_text(dir, "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n");
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_TRUE(mesh.textures.empty());
    EXPECT_FALSE(mesh.has_texture_coordinates());
    expect_near(mesh.albedo_at(0, 0.2f, 0.2f), {0.5f, 0.25f, 1.0f, 1.0f}, 1e-6f);
    ASSERT_EQ(report.warnings.size(), 1u);
    EXPECT_NE(report.warnings[0].find("nowhere.png"), std::string::npos) << report.warnings[0];
}

// A glTF file whose one mesh is a triangle with per-vertex normals, placed by `nodes`.
std::string triangle_gltf(const std::array<float, 9>& positions, const std::array<float, 9>& normals,
                          const std::string& scene_nodes, const std::string& nodes)
{
    std::string bytes(reinterpret_cast<const char*>(positions.data()), 36);
    bytes.append(reinterpret_cast<const char*>(normals.data()), 36);
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int v = 0; v < 3; ++v) {
        glm::vec3 p(positions[v * 3], positions[v * 3 + 1], positions[v * 3 + 2]);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    auto list = [](glm::vec3 v) {
        std::ostringstream text; // not string concatenation: GCC 12 -O3 gives a false -Wrestrict there
        text << '[' << v.x << ", " << v.y << ", " << v.z << ']';
        return text.str();
    };
    return R"({
  "asset": {"version": "2.0"},
  "scene": 0,
  "scenes": [{"nodes": )" + scene_nodes + R"(}],
  "nodes": )" + nodes + R"(,
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
  "buffers": [{"byteLength": 72, "uri": "data:application/octet-stream;base64,)" + test::base64(bytes) + R"("}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
  "accessors": [
    {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": )" + list(lo) + R"(, "max": )" + list(hi) + R"(},
    {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}
  ]
})";
}

TEST(ImportMesh, GltfNodeTransformsAreFlattened)
{
    // one triangle (0,0,0) (1,0,0) (0,1,0) with normal +z, placed three times: translated, inside a
    // translated parent with its own scale, and mirrored
    std::string gltf = triangle_gltf({0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 1, 0, 0, 1, 0, 0, 1}, "[0, 1, 2]", R"([
    {"mesh": 0, "translation": [10, 0, 0]},
    {"translation": [0, 0, -5], "children": [3]},
    {"mesh": 0, "translation": [0, 3, 0], "scale": [-1, 1, 1]},
    {"mesh": 0, "scale": [2, 2, 2]}
  ])");
    std::string path = write_text(import_test_dir("gltf_nodes"), "nodes.gltf", gltf);
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_EQ(report.format, "gltf");
    EXPECT_EQ(report.meshes_in_scene, 3u);
    ASSERT_EQ(mesh.triangle_count(), 3u);
    Bounds b = mesh.bounds();
    EXPECT_NEAR(glm::length(b.min - glm::vec3(-1, 0, -5)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(b.max - glm::vec3(11, 4, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(mesh.surface_area(), 0.5 + 0.5 + 2.0, 1e-6);
    // the mirrored instance keeps its winding consistent with its normals
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        glm::vec3 n = mesh.normals[mesh.indices[t * 3]];
        EXPECT_NEAR(glm::length(n - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
        EXPECT_GT(glm::dot(geometric_normal(mesh, t), n), 0.99f) << "triangle " << t;
    }
}

TEST(ImportMesh, NormalsFollowNonUniformScale)
{
    // the plane x + y + z = 1 stretched along x: normals transform with the inverse transpose
    float n = 1.0f / std::sqrt(3.0f);
    std::string gltf = triangle_gltf({1, 0, 0, 0, 1, 0, 0, 0, 1}, {n, n, n, n, n, n, n, n, n}, "[0]",
                                     R"([{"mesh": 0, "scale": [2, 1, 1]}])");
    Mesh mesh = import_ok(write_text(import_test_dir("gltf_scale"), "scaled.gltf", gltf));
    ASSERT_EQ(mesh.triangle_count(), 1u);
    glm::vec3 expected = glm::vec3(1, 2, 2) / 3.0f;
    EXPECT_NEAR(glm::length(geometric_normal(mesh, 0) - expected), 0.0f, 1e-6f);
    for (glm::vec3 normal : mesh.normals) EXPECT_NEAR(glm::length(normal - expected), 0.0f, 1e-6f);
}

TEST(ImportMesh, OffFile)
{
    std::string path = write_text(import_test_dir("off"), "square.off", "OFF\n4 1 0\n0 0 0\n2 0 0\n2 2 0\n0 2 0\n4 0 1 2 3\n");
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_EQ(report.format, "off");
    EXPECT_EQ(mesh.triangle_count(), 2u);
    EXPECT_DOUBLE_EQ(mesh.surface_area(), 4.0);
    for (glm::vec3 n : mesh.normals) EXPECT_NEAR(glm::length(n - glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
}

const char* k_cube_obj =
    "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 3 4 8 7\nf 2 3 7 6\nf 1 5 8 4\n";

TEST(ImportMesh, MissingNormalsAreSplitAtCreases)
{
    std::string path = write_text(import_test_dir("crease"), "cube.obj", k_cube_obj);
    // 90 degree edges are creases at the default 80 degrees: four vertices per face, flat normals
    Mesh sharp = import_ok(path);
    ASSERT_EQ(sharp.triangle_count(), 12u);
    EXPECT_EQ(sharp.vertex_count(), 24u);
    for (std::size_t t = 0; t < sharp.triangle_count(); ++t)
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(glm::dot(sharp.normals[sharp.indices[t * 3 + k]], geometric_normal(sharp, t)), 1.0f, 1e-6f);

    // above 90 degrees the cube is smoothed into one vertex per corner, normals pointing outwards
    ImportOptions smooth_options;
    smooth_options.crease_angle_degrees = 100.0f;
    Mesh smooth = import_ok(path, nullptr, smooth_options);
    EXPECT_EQ(smooth.vertex_count(), 8u);
    for (std::size_t v = 0; v < smooth.vertex_count(); ++v)
        EXPECT_GT(glm::dot(smooth.normals[v], glm::normalize(smooth.positions[v])), 0.9f);
}

// ---------------------------------------------------------------------------------------------
// Bundled models

TEST(ImportMesh, BundledBunny)
{
    ImportReport report;
    Mesh mesh = import_ok(data_path("bunny.ply"), &report);
    EXPECT_EQ(mesh.triangle_count() + report.degenerate_dropped, 3674u);
    EXPECT_GT(mesh.triangle_count(), 3600u);
    Bounds b = mesh.bounds();
    EXPECT_NEAR(b.min.y, 0.0f, 0.01f);
    EXPECT_NEAR(b.max.y, 9.65f, 0.01f);
    for (glm::vec3 n : mesh.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(ImportMesh, BundledTexturedBoxHasItsEmbeddedTexture)
{
    ImportReport report;
    Mesh mesh = import_ok(data_path("box_textured.glb"), &report);
    EXPECT_EQ(report.format, "glb");
    EXPECT_EQ(mesh.triangle_count(), 12u);
    ASSERT_EQ(mesh.textures.size(), 1u);
    EXPECT_EQ(mesh.textures[0].width, 211);
    EXPECT_EQ(mesh.textures[0].height, 211);
    EXPECT_TRUE(mesh.has_texture_coordinates());
    EXPECT_NEAR(mesh.bounding_sphere().radius, std::sqrt(3.0f) / 2.0f, 1e-5f);
    // the logo has sky at the top of the image (v near 1) and grass at the bottom
    glm::vec4 sky = mesh.textures[0].sample({0.5f, 0.8f});
    glm::vec4 grass = mesh.textures[0].sample({0.5f, 0.15f});
    EXPECT_GT(sky.z, sky.y);
    EXPECT_GT(sky.z, sky.x);
    EXPECT_GT(grass.y, grass.z);
    EXPECT_GT(grass.y, grass.x);
}

// ---------------------------------------------------------------------------------------------
// Bad inputs

TEST(ImportMesh, MissingFileIsNotFound)
{
    expect_error(import_test_dir("missing") + "/nothing_here.obj", StatusCode::not_found);
}

TEST(ImportMesh, UnknownExtensionIsUnsupported)
{
    std::string path = write_text(import_test_dir("unknown"), "model.xyz123", "v 0 0 0\n");
    expect_error(path, StatusCode::unsupported, ".xyz123");
}

// The format is told by the extension; without one the message says how to give it.
TEST(ImportMesh, NoExtensionIsUnsupportedAndSaysWhatToDo)
{
    std::string path = write_text(import_test_dir("no_extension"), "model", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error(path, StatusCode::unsupported, "rename it with its format's extension");
}

TEST(ImportMesh, CorruptFilesAreBadData)
{
    std::string dir = import_test_dir("corrupt");
    std::mt19937 random(12345);
    for (const char* name : {"random.ply", "random.obj", "random.glb", "random.stl", "random.off", "random.gltf"}) {
        std::string bytes(4096, '\0');
        for (char& c : bytes) c = char(random() & 0xff);
        std::string path = write_text(dir, name, bytes);
        ::testing::internal::CaptureStdout();
        expect_error(path, StatusCode::bad_data);
        // assimp must not print: the CLI's stdout may carry machine-readable output
        EXPECT_EQ(::testing::internal::GetCapturedStdout(), "") << name;
    }
}

TEST(ImportMesh, TruncatedPlyIsBadData)
{
    std::string dir = import_test_dir("truncated");
    GenerateOptions options;
    options.target_triangles = 200;
    ASSERT_TRUE(write_ply(*generate_mesh(options), dir + "/whole.ply").is_ok());
    std::ifstream in(dir + "/whole.ply", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::string path = write_text(dir, "truncated.ply", bytes.substr(0, bytes.size() / 2));
    expect_error(path, StatusCode::bad_data);
}

TEST(ImportMesh, EmptyFilesAreBadData)
{
    std::string dir = import_test_dir("empty");
    expect_error(write_text(dir, "empty.obj", ""), StatusCode::bad_data);
    expect_error(write_text(dir, "comments.obj", "# nothing but a comment, long enough for assimp to parse it\n"),
                 StatusCode::bad_data);
    expect_error(write_text(dir, "lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n"), StatusCode::bad_data,
                 "contains no triangles");
}

// assimp's validation refuses a whole file for what standin does not draw: a light or camera its
// importer left without a node (Blender's default scene as OpenGEX), an empty solid beside the
// model in an STL. They are dropped before validation, so the triangles are read; a file with
// nothing else is still "contains no triangles".
TEST(ImportMesh, LightsCamerasAndEmptyMeshesDoNotRefuseTheFile)
{
    std::string dir = import_test_dir("not_drawn");
    const std::string ogex = R"(Metric (key = "distance") {float {1.0}}
Metric (key = "up") {string {"z"}}
GeometryNode $node1 { Name {string {"Triangle"}} ObjectRef {ref {$geometry1}} MaterialRef (index = 0) {ref {$material1}} }
LightNode $node2 { Name {string {"Lamp"}} ObjectRef {ref {$light1}} }
CameraNode $node3 { Name {string {"Camera"}} ObjectRef {ref {$camera1}} }
GeometryObject $geometry1 {
  Mesh (primitive = "triangles") {
    VertexArray (attrib = "position") { float[3] { {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0} } }
    IndexArray { unsigned_int32[3] { {0, 1, 2} } }
  }
}
LightObject $light1 (type = "point") { Color (attrib = "light") {float[3] {{1.0, 1.0, 1.0}}} }
CameraObject $camera1 { Param (attrib = "fov") {float {0.85}} Param (attrib = "near") {float {0.1}} Param (attrib = "far") {float {100.0}} }
Material $material1 { Name {string {"Material"}} Color (attrib = "diffuse") {float[3] {{0.64, 0.64, 0.64}}} }
)";
    Mesh lit = import_ok(write_text(dir, "lamp.ogex", ogex));
    EXPECT_EQ(lit.triangle_count(), 1u);

    const std::string triangle = "solid triangle\n facet normal 0 0 1\n  outer loop\n   vertex 1 1 0\n   vertex -1 1 0\n"
                                 "   vertex 0 -1 0\n  endloop\n endfacet\nendsolid\n";
    ImportReport report;
    Mesh stl = import_ok(write_text(dir, "empty_solid.stl", triangle + "solid emptySolid\nendsolid\n"), &report);
    EXPECT_EQ(stl.triangle_count(), 1u);
    ASSERT_FALSE(report.warnings.empty());
    EXPECT_NE(report.warnings.back().find("skipped 1 mesh without faces"), std::string::npos) << report.warnings.back();

    expect_error(write_text(dir, "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\np 1\np 2\np 3\n"), StatusCode::bad_data,
                 "contains no triangles");
}

TEST(ImportMesh, NonFiniteCoordinatesAreBadData)
{
    std::string dir = import_test_dir("non_finite");
    expect_error(write_text(dir, "nan.obj", "v 0 0 0\nv nan 0 0\nv 1 1 0\nf 1 2 3\n"), StatusCode::bad_data, "non-finite");
    expect_error(write_text(dir, "inf.obj", "v 0 0 0\nv 1e40 0 0\nv 1 1 0\nf 1 2 3\n"), StatusCode::bad_data, "non-finite");
    expect_error(write_text(dir, "nan.ply",
                            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                            "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                            "0 0 0\n1 nan 0\n1 1 0\n3 0 1 2\n"),
                 StatusCode::bad_data, "non-finite");
}

TEST(ImportMesh, DegenerateTrianglesAreDroppedAndCounted)
{
    std::string dir = import_test_dir("degenerate");
    std::string path = write_text(dir, "degenerate.obj",
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\n"
                                  "f 1 2 3\n"   // fine
                                  "f 1 2 4\n"   // collinear: zero area
                                  "f 1 1 3\n"); // repeated corner
    ImportReport report;
    Mesh mesh = import_ok(path, &report);
    EXPECT_EQ(mesh.triangle_count(), 1u);
    EXPECT_EQ(report.degenerate_dropped, 2u);
    EXPECT_EQ(mesh.vertex_count(), 3u); // the vertex only the dropped triangle used is gone
    ASSERT_FALSE(report.warnings.empty());
    EXPECT_NE(report.warnings[0].find("2 degenerate"), std::string::npos) << report.warnings[0];

    expect_error(write_text(dir, "all_degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n"), StatusCode::bad_data,
                 "contains no triangles");
}

} // namespace
} // namespace standin
