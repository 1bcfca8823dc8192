// standin export: every exportable representation's .glb parses back as glTF 2.0 (GLB header and
// chunks, accessors inside the binary chunk, positions within the source's bounds, the extras a
// shader needs), the same package exports byte-identical files, and bad input is refused with
// nothing written. The Khronos validator runs on the CLI's exports in tests/export_validator.sh.
#include "test_support.h"

#include <standin/export.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

namespace standin {
namespace {

Mesh export_torus()
{
    GenerateOptions options;
    options.shape = GeneratedShape::torus;
    options.target_triangles = 2000;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

std::unique_ptr<Package> bake_small(const Mesh& mesh, const std::string& representation,
                                    const std::vector<std::pair<std::string, std::string>>& values)
{
    test::gpu_context();
    return test::bake(mesh, representation, values); // source.bounds: the mesh's
}

struct ParsedGlb {
    nlohmann::json json;
    std::string bin;
};

// Parses a .glb as a loader would, failing the test on anything malformed.
ParsedGlb parse_glb(const std::string& bytes)
{
    ParsedGlb out;
    auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    EXPECT_GE(bytes.size(), 28u);
    if (bytes.size() < 28) return out;
    EXPECT_EQ(bytes.substr(0, 4), "glTF");
    EXPECT_EQ(u32(4), 2u);
    EXPECT_EQ(u32(8), bytes.size());
    std::uint32_t json_length = u32(12);
    EXPECT_EQ(bytes.substr(16, 4), "JSON");
    EXPECT_EQ(json_length % 4, 0u);
    out.json = nlohmann::json::parse(bytes.substr(20, json_length));
    std::size_t bin_at = 20 + json_length;
    std::uint32_t bin_length = u32(bin_at);
    EXPECT_EQ(bytes.substr(bin_at + 4, 4), std::string("BIN\0", 4));
    EXPECT_EQ(bin_at + 8 + bin_length, bytes.size());
    out.bin = bytes.substr(bin_at + 8, bin_length);
    EXPECT_EQ(out.json["buffers"][0]["byteLength"], bin_length);
    for (const auto& view : out.json["bufferViews"])
        EXPECT_LE(view["byteOffset"].get<std::size_t>() + view["byteLength"].get<std::size_t>(), bin_length);
    return out;
}

// Exports to a fresh file and parses it back; checks every mesh's POSITION bounds lie within the
// source's box grown by `margin` (a fraction of its diagonal).
ParsedGlb export_and_parse(const Package& package, const OptionValues& options, const std::string& path, float margin,
                           ExportScene* scene = nullptr)
{
    Status s = export_package(package, options, path, scene);
    EXPECT_TRUE(s) << s.message();
    Result<std::string> bytes = read_file(path);
    EXPECT_TRUE(bytes);
    if (!bytes) return {};
    ParsedGlb glb = parse_glb(*bytes);
    const Bounds& b = package.source.bounds;
    float grow = margin * glm::length(b.max - b.min);
    for (const auto& mesh : glb.json["meshes"]) {
        int position = mesh["primitives"][0]["attributes"]["POSITION"];
        const auto& accessor = glb.json["accessors"][std::size_t(position)];
        for (int k = 0; k < 3; ++k) {
            EXPECT_GE(accessor["min"][k].get<float>(), b.min[k] - grow) << mesh["name"];
            EXPECT_LE(accessor["max"][k].get<float>(), b.max[k] + grow) << mesh["name"];
        }
    }
    EXPECT_EQ(glb.json["nodes"][0]["extras"]["standin"]["representation"], package.representation());
    return glb;
}

TEST(Export, ViewAtlasGridAtlasHasTheFramesAndTheQuad)
{
    Mesh mesh = export_torus();
    auto package = bake_small(mesh, "view-atlas", {{"layout", "octahedral"}, {"frames", "4"}, {"resolution", "64"}, {"page-size", "512"}});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("export_view_atlas");
    OptionValues options;
    options.set("atlas-size", "256");
    ExportScene scene;
    ParsedGlb glb = export_and_parse(*package, options, dir + "/a.glb", 0.8f, &scene);
    ASSERT_EQ(glb.json["meshes"].size(), 1u);
    ASSERT_EQ(glb.json["images"].size(), 2u);
    const auto& extras = glb.json["nodes"][1]["extras"]["standin"];
    EXPECT_EQ(extras["role"], "grid-impostor");
    EXPECT_EQ(extras["frames"], 4);
    EXPECT_EQ(extras["atlas_size"], 256);
    EXPECT_EQ(extras["frame_axes"].size(), 16u);
    EXPECT_NEAR(extras["radius"].get<float>(), mesh.bounding_sphere().radius, 1e-5f);
    // the textures are the atlas size, colour with coverage somewhere and transparency somewhere
    ASSERT_EQ(scene.textures.size(), 2u);
    EXPECT_EQ(scene.textures[0].width, 256);
    EXPECT_GT(scene.gpu_bytes, 2u * 256 * 256 * 4);
    // the same package exports the same bytes
    ASSERT_TRUE(export_package(*package, options, dir + "/b.glb"));
    EXPECT_EQ(*read_file(dir + "/a.glb"), *read_file(dir + "/b.glb"));
    // --frames must match the bake; an icosahedral atlas has no grid; options of others are refused
    OptionValues wrong_frames;
    wrong_frames.set("frames", "8");
    Status s = export_package(*package, wrong_frames, dir + "/c.glb");
    EXPECT_EQ(s.code(), StatusCode::invalid_argument);
    EXPECT_NE(s.message().find("--frames"), std::string::npos) << s.message();
    OptionValues tau;
    tau.set("tau", "2");
    EXPECT_EQ(export_package(*package, tau, dir + "/c.glb").code(), StatusCode::invalid_argument);
    OptionValues absurd;
    absurd.set("atlas-size", "100000");
    EXPECT_EQ(export_package(*package, absurd, dir + "/c.glb").code(), StatusCode::invalid_argument);
    EXPECT_FALSE(export_package(*package, options, dir + "/no/such/dir/c.glb"));
    EXPECT_FALSE(std::filesystem::exists(dir + "/c.glb"));
    auto icosahedral = bake_small(mesh, "view-atlas", {{"subdivisions", "0"}, {"resolution", "32"}, {"page-size", "512"}});
    ASSERT_TRUE(icosahedral);
    EXPECT_EQ(export_package(*icosahedral, {}, dir + "/c.glb").code(), StatusCode::unsupported);
    EXPECT_FALSE(std::filesystem::exists(dir + "/c.glb"));
}

TEST(Export, DisplacedMeshRefinesWithTau)
{
    Mesh mesh = export_torus();
    auto package = bake_small(mesh, "displaced-mesh", {{"degree", "5"}});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("export_displaced");
    OptionValues coarse, fine;
    coarse.set("tau", "8");
    fine.set("tau", "0.5");
    ParsedGlb a = export_and_parse(*package, coarse, dir + "/coarse.glb", 0.05f);
    ParsedGlb b = export_and_parse(*package, fine, dir + "/fine.glb", 0.05f);
    ASSERT_EQ(a.json["meshes"].size(), 1u);
    ASSERT_EQ(b.json["meshes"].size(), 1u);
    auto triangles = [](const ParsedGlb& g) {
        int indices = g.json["meshes"][0]["primitives"][0]["indices"];
        return g.json["accessors"][std::size_t(indices)]["count"].get<std::size_t>() / 3;
    };
    // a smaller tolerance refines more
    EXPECT_GT(triangles(b), triangles(a));
    EXPECT_TRUE(b.json["meshes"][0]["primitives"][0]["attributes"].contains("COLOR_0"));
    EXPECT_TRUE(export_package(*package, fine, dir + "/again.glb"));
    EXPECT_EQ(*read_file(dir + "/fine.glb"), *read_file(dir + "/again.glb"));
}

TEST(Export, BillboardsExportTheirBoxesAndCoarseMesh)
{
    Mesh mesh = export_torus();
    auto package = bake_small(mesh, "enhanced-billboards", {{"resolution", "128"}});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("export_billboards");
    ExportScene scene;
    ParsedGlb glb = export_and_parse(*package, {}, dir + "/b.glb", 0.25f, &scene);
    std::size_t boxes = 0, coarse = 0;
    for (std::size_t k = 1; k < glb.json["nodes"].size(); ++k) {
        std::string role = glb.json["nodes"][k]["extras"]["standin"]["role"];
        boxes += role == "billboard";
        coarse += role == "coarse-mesh";
    }
    EXPECT_GT(boxes, 0u);
    EXPECT_EQ(glb.json["images"].size(), 2 * boxes);
    EXPECT_LE(coarse, 1u);
}

TEST(Export, MicrofacetsAreRefusedInOneLine)
{
    Mesh mesh = export_torus();
    auto package = bake_small(mesh, "microfacets", {});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("export_microfacets");
    Status s = export_package(*package, {}, dir + "/m.glb");
    EXPECT_EQ(s.code(), StatusCode::unsupported);
    EXPECT_EQ(s.message().find('\n'), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir + "/m.glb"));
}

} // namespace
} // namespace standin
