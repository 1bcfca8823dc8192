// standin export: every exportable representation's .glb parses back as glTF 2.0 (GLB header and
// chunks, accessors inside the binary chunk, positions within the source's bounds, the extras a
// shader needs), the same package exports byte-identical files, and bad input is refused with
// nothing written. The Khronos validator runs on the CLI's exports in tests/export_validator.sh.
#include "test_support.h"

#include <standin/export.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>

namespace standin {
namespace {

Mesh export_torus()
{
    return test::generated(GeneratedShape::torus, 2000);
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

// The values of an accessor (float vectors or 32-bit indices), tightly packed.
template <typename T>
std::vector<T> read_accessor(const ParsedGlb& glb, int accessor_index)
{
    const auto& accessor = glb.json["accessors"][std::size_t(accessor_index)];
    const auto& view = glb.json["bufferViews"][accessor["bufferView"].get<std::size_t>()];
    const std::size_t offset = view["byteOffset"].get<std::size_t>() + accessor.value("byteOffset", std::size_t(0));
    std::vector<T> out(accessor["count"].get<std::size_t>());
    EXPECT_LE(offset + out.size() * sizeof(T), glb.bin.size());
    if (offset + out.size() * sizeof(T) <= glb.bin.size()) std::memcpy(out.data(), glb.bin.data() + offset, out.size() * sizeof(T));
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
    ASSERT_EQ(glb.json["meshes"].size(), 2u); // the quad and the atlas hull
    ASSERT_EQ(glb.json["images"].size(), 2u);
    const auto& extras = glb.json["nodes"][1]["extras"]["standin"];
    EXPECT_EQ(extras["role"], "grid-impostor");
    EXPECT_EQ(extras["frames"], 4);
    EXPECT_EQ(extras["atlas_size"], 256);
    EXPECT_EQ(extras["frame_axes"].size(), 16u);
    EXPECT_NEAR(extras["radius"].get<float>(), mesh.bounding_sphere().radius, 1e-5f);
    // the atlas hull: the quad's extras under its own role, a closed convex mesh holding every
    // vertex of the model (within a capture texel: the sampling margin), smaller than the quad
    const auto& hull_extras = glb.json["nodes"][2]["extras"]["standin"];
    EXPECT_EQ(hull_extras["role"], "grid-impostor-hull");
    EXPECT_EQ(hull_extras["quad_node"], "impostor");
    EXPECT_EQ(hull_extras["frame_axes"], extras["frame_axes"]);
    EXPECT_EQ(hull_extras["color_texture"], extras["color_texture"]);
    EXPECT_EQ(glb.json["nodes"][2]["name"], "hull");
    {
        const auto& primitive = glb.json["meshes"][1]["primitives"][0];
        std::vector<glm::vec3> positions = read_accessor<glm::vec3>(glb, primitive["attributes"]["POSITION"]);
        std::vector<std::uint32_t> indices = read_accessor<std::uint32_t>(glb, primitive["indices"]);
        ASSERT_GE(indices.size(), 12u);
        EXPECT_LT(indices.size() / 3, 2000u);
        const float texel = 2.0f * mesh.bounding_sphere().radius / 64.0f;
        std::size_t outside = 0;
        double area = 0.0; // seen along +Z: half the sum of |projected triangle areas|
        for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
            const glm::vec3 a = positions[indices[t]], b = positions[indices[t + 1]], c = positions[indices[t + 2]];
            const glm::vec3 n = glm::cross(b - a, c - a);
            area += 0.25 * std::abs(double(n.z));
            if (glm::length(n) < 1e-12f) continue;
            for (const glm::vec3& p : mesh.positions)
                if (glm::dot(glm::normalize(n), p - a) > texel) ++outside;
        }
        EXPECT_EQ(outside, 0u);
        const double h = extras["half_extent"].get<double>();
        EXPECT_LT(area, 0.8 * 4.0 * h * h);
    }
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

// An alpha-masked model's displaced mesh (issue #14) keeps its cut-outs in the export: its shading
// samples as a texture whose alpha is their coverage, on a MASK material; the flat card stays its
// two control triangles (no vertex per sample), and the texture read at the card's corners is cut
// out (the disc's outside) and at its centre kept, as the renderer discards them.
TEST(Export, DisplacedMeshKeepsCutOutsAsAMaskTexture)
{
    Mesh card = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    // the samples' path: with the source's texture (the default) the card is exported as the
    // source triangles it is (the next test)
    auto package = bake_small(card, "displaced-mesh", {{"degree", "17"}, {"source-textures", "off"}});
    ASSERT_TRUE(package);
    const nlohmann::json faces = summarise_package(*package).details;
    std::string dir = test::fresh_directory("export_displaced_alpha");
    ExportScene scene;
    ParsedGlb glb = export_and_parse(*package, {}, dir + "/card.glb", 0.05f, &scene);
    ASSERT_EQ(glb.json["meshes"].size(), 1u);
    const auto& primitive = glb.json["meshes"][0]["primitives"][0];
    const auto& material = glb.json["materials"][primitive["material"].get<std::size_t>()];
    EXPECT_EQ(material["alphaMode"], "MASK");
    EXPECT_EQ(material["alphaCutoff"], 0.5);
    EXPECT_EQ(material["doubleSided"], true);
    ASSERT_TRUE(material["pbrMetallicRoughness"].contains("baseColorTexture"));
    EXPECT_FALSE(primitive["attributes"].contains("COLOR_0"));
    const int index_accessor = primitive["indices"];
    EXPECT_EQ(glb.json["accessors"][std::size_t(index_accessor)]["count"].get<std::size_t>(), 3 * faces["control_faces"].get<std::size_t>())
        << "a flat card is its control triangles";
    ASSERT_EQ(scene.textures.size(), 1u);
    ASSERT_TRUE(write_file_atomic(dir + "/atlas.png", scene.textures[0].png).is_ok());
    Result<ImageRGBA8> atlas = read_png_rgba8(dir + "/atlas.png");
    ASSERT_TRUE(atlas.is_ok());
    std::vector<glm::vec3> positions = read_accessor<glm::vec3>(glb, primitive["attributes"]["POSITION"].get<int>());
    std::vector<glm::vec2> uvs = read_accessor<glm::vec2>(glb, primitive["attributes"]["TEXCOORD_0"].get<int>());
    ASSERT_EQ(uvs.size(), positions.size());
    auto alpha_at = [&](glm::vec2 uv) {
        const int x = std::clamp(int(uv.x * float(atlas->width)), 0, atlas->width - 1);
        const int y = std::clamp(int(uv.y * float(atlas->height)), 0, atlas->height - 1);
        return atlas->at(x, y)[3];
    };
    std::vector<std::uint32_t> indices = read_accessor<std::uint32_t>(glb, index_accessor);
    int centres = 0;
    for (std::size_t v = 0; v < positions.size(); ++v) EXPECT_EQ(alpha_at(uvs[v]), 0) << "card corner " << v;
    for (std::size_t t = 0; t < indices.size(); t += 3) {
        // the midpoint of the edge opposite the triangle's right-angled corner: the card's centre
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = indices[t + std::size_t(k)], b = indices[t + std::size_t((k + 1) % 3)];
            if (glm::length(0.5f * (positions[a] + positions[b])) < 1e-4f) {
                EXPECT_EQ(alpha_at(0.5f * (uvs[a] + uvs[b])), 255);
                ++centres;
            }
        }
    }
    EXPECT_EQ(centres, 2) << "each triangle's diagonal passes through the card's centre";
    // an opaque model's export keeps its vertex colours and stays opaque
    ParsedGlb torus = export_and_parse(*bake_small(export_torus(), "displaced-mesh", {{"degree", "5"}}), {}, dir + "/torus.glb", 0.05f);
    EXPECT_EQ(torus.json["materials"][0]["alphaMode"], "OPAQUE");
    EXPECT_TRUE(torus.json["meshes"][0]["primitives"][0]["attributes"].contains("COLOR_0"));
}

// Faces drawn with the source's own texture (session 46) export as the source triangles they are:
// the texture itself (repeated: the card's UVs run to 2), the corners' UVs and colours (linear in
// COLOR_0; left out when all white), the material's own alpha cutoff. Read back as a model, the
// card draws what the source does, cut-outs and tints.
TEST(Export, DisplacedMeshExportsSourceTrianglesWithTheSourceTexture)
{
    std::string dir = test::fresh_directory("export_displaced_source");
    for (AlphaMode mode : {AlphaMode::mask, AlphaMode::opaque}) {
        Mesh card = test::alpha_quad(mode, 0.3f, true);
        for (glm::vec2& uv : card.uvs) uv *= 2.0f; // the disc tiled 2 x 2
        const bool tinted = mode == AlphaMode::opaque;
        if (tinted) card.colors = {{1.0f, 0.8f, 0.6f, 1.0f}, {0.6f, 1.0f, 0.8f, 1.0f}, {0.8f, 0.6f, 1.0f, 1.0f}, {1.0f, 1.0f, 1.0f, 1.0f}};
        auto package = bake_small(card, "displaced-mesh", {{"degree", "17"}});
        ASSERT_TRUE(package);
        const std::string path = dir + (mode == AlphaMode::mask ? "/mask.glb" : "/opaque.glb");
        ExportScene scene;
        ParsedGlb glb = export_and_parse(*package, {}, path, 0.05f, &scene);
        ASSERT_EQ(glb.json["meshes"].size(), 1u) << "no samples' mesh: every face is a source triangle";
        ASSERT_EQ(scene.textures.size(), 1u) << "no samples' atlas";
        const auto& primitive = glb.json["meshes"][0]["primitives"][0];
        const auto& material = glb.json["materials"][primitive["material"].get<std::size_t>()];
        if (mode == AlphaMode::mask) {
            EXPECT_EQ(material["alphaMode"], "MASK");
            EXPECT_EQ(material["alphaCutoff"], 0.3) << "the material's own cutoff";
        } else {
            EXPECT_EQ(material["alphaMode"], "OPAQUE");
        }
        const int texture = material["pbrMetallicRoughness"]["baseColorTexture"]["index"];
        const auto& sampler = glb.json["samplers"][glb.json["textures"][std::size_t(texture)]["sampler"].get<std::size_t>()];
        EXPECT_EQ(sampler["wrapS"], 10497) << "repeated, as the truth reads it";
        EXPECT_EQ(sampler["wrapT"], 10497);
        ASSERT_TRUE(write_file_atomic(dir + "/texture.png", scene.textures[0].png).is_ok());
        Result<ImageRGBA8> image = read_png_rgba8(dir + "/texture.png");
        ASSERT_TRUE(image.is_ok());
        EXPECT_EQ(image->pixels, card.textures[0].rgba) << "the source's texture, row 0 on top";

        std::vector<glm::vec3> positions = read_accessor<glm::vec3>(glb, primitive["attributes"]["POSITION"].get<int>());
        std::vector<glm::vec2> uvs = read_accessor<glm::vec2>(glb, primitive["attributes"]["TEXCOORD_0"].get<int>());
        ASSERT_EQ(uvs.size(), positions.size());
        ASSERT_EQ(primitive["attributes"].contains("COLOR_0"), tinted);
        std::vector<glm::vec4> colors;
        if (tinted) colors = read_accessor<glm::vec4>(glb, primitive["attributes"]["COLOR_0"].get<int>());
        EXPECT_EQ(read_accessor<std::uint32_t>(glb, primitive["indices"].get<int>()).size(), 6u) << "the card's two triangles";
        for (std::size_t v = 0; v < positions.size(); ++v) {
            std::size_t corner = 0;
            while (corner < card.positions.size() && glm::length(card.positions[corner] - positions[v]) > 1e-6f) ++corner;
            ASSERT_LT(corner, card.positions.size()) << "vertex " << v << " is a corner of the card";
            EXPECT_EQ(uvs[v], card.uvs[corner]);
            for (int c = 0; c < 3 && tinted; ++c) {
                const float srgb = float(std::lround(card.colors[corner][c] * 255.0f)) / 255.0f;
                const float linear = srgb <= 0.04045f ? srgb / 12.92f : std::pow((srgb + 0.055f) / 1.055f, 2.4f);
                EXPECT_NEAR(colors[v][c], linear, 1e-5f) << "vertex " << v << " channel " << c;
            }
        }
        // read back as a model: the cut-outs, tiled 2 x 2, and the colours as the source's
        Result<Mesh> back = import_mesh(path);
        ASSERT_TRUE(back.is_ok()) << back.status().message();
        auto truth = make_mesh_renderer(card);
        auto exported = make_mesh_renderer(*back);
        ASSERT_TRUE(truth.is_ok() && exported.is_ok());
        Result<EvalResult> result = test::evaluate_views(**truth, **exported, card, {0.0f, 200.0f}, {20.0f}, 320, 240);
        ASSERT_TRUE(result.is_ok());
        for (const ViewResult& v : result->views) {
            EXPECT_GE(v.metrics.iou, 0.99) << "azimuth " << v.view.orbit.azimuth_degrees;
            EXPECT_LE(v.metrics.luv_mean, 0.5) << "azimuth " << v.view.orbit.azimuth_degrees;
        }
    }
}

// A model kept whole exports as its own triangles with their own normals: the bundled textured box's
// corners are welded only where the stored normal agrees too, so its edges stay hard (welded by
// position and UV alone, 21 vertices and rounded edges, Luv 3.6 against the box); and so does the
// same box untextured, whose flat sides of one colour are not refined.
TEST(Export, DisplacedMeshKeepsHardEdgesHard)
{
    Result<Mesh> box = import_mesh(test::source_dir() + "/data/box_textured.glb");
    ASSERT_TRUE(box.is_ok());
    auto package = bake_small(*box, "displaced-mesh", {});
    ASSERT_TRUE(package);
    ParsedGlb glb = export_and_parse(*package, {}, test::fresh_directory("export_displaced_box") + "/box.glb", 0.05f);
    ASSERT_EQ(glb.json["meshes"].size(), 1u);
    const auto& attributes = glb.json["meshes"][0]["primitives"][0]["attributes"];
    std::vector<glm::vec3> normals = read_accessor<glm::vec3>(glb, attributes["NORMAL"].get<int>());
    EXPECT_EQ(normals.size(), 24u) << "four corners a side";
    for (const glm::vec3& n : normals) {
        const glm::vec3 a = glm::abs(n);
        EXPECT_NEAR(std::max({a.x, a.y, a.z}), 1.0f, 1e-3f) << "a side's normal, not a blend of sides";
    }

    // untextured, drawn from its samples: flat sides of one colour stay whole too (the vertex
    // colours need no vertex per sample; refined, the 12 faces were 18,432 triangles)
    Mesh plain = *box;
    for (Material& m : plain.materials) m.base_color_texture = -1;
    plain.textures.clear();
    auto untextured = bake_small(plain, "displaced-mesh", {});
    ASSERT_TRUE(untextured);
    ParsedGlb flat = export_and_parse(*untextured, {}, test::fresh_directory("export_displaced_plain_box") + "/box.glb", 0.05f);
    const auto& primitive = flat.json["meshes"][0]["primitives"][0];
    EXPECT_EQ(flat.json["accessors"][primitive["indices"].get<std::size_t>()]["count"].get<std::size_t>(), 36u) << "the box's 12 triangles";
    EXPECT_EQ(read_accessor<glm::vec3>(flat, primitive["attributes"]["NORMAL"].get<int>()).size(), 24u);
}

// A PBR package's displaced mesh exports its material's factors (the mean of its samples, one per
// mesh as glTF has them): metallic, roughness and emission as baked, which a rough dielectric
// without emission (the old export, whatever the model) is far from.
TEST(Export, DisplacedMeshCarriesItsMaterialsFactors)
{
    Mesh torus = export_torus();
    for (Material& m : torus.materials) m.metallic = 0.7f, m.roughness = 0.4f, m.emissive = glm::vec3(0.2f, 0.1f, 0.0f);
    auto package = bake_small(torus, "displaced-mesh", {{"degree", "5"}});
    ASSERT_TRUE(package);
    ParsedGlb glb = export_and_parse(*package, {}, test::fresh_directory("export_displaced_pbr") + "/torus.glb", 0.05f);
    ASSERT_EQ(glb.json["materials"].size(), 1u);
    const auto& material = glb.json["materials"][0];
    EXPECT_NEAR(material["pbrMetallicRoughness"]["metallicFactor"].get<double>(), 0.7, 1.0 / 255.0);
    EXPECT_NEAR(material["pbrMetallicRoughness"]["roughnessFactor"].get<double>(), 0.4, 1.0 / 255.0);
    ASSERT_TRUE(material.contains("emissiveFactor"));
    // (emission is stored sRGB-encoded in 8 bits: 0.1 comes back within a code's step)
    EXPECT_NEAR(material["emissiveFactor"][0].get<double>(), 0.2, 0.01);
    EXPECT_NEAR(material["emissiveFactor"][1].get<double>(), 0.1, 0.01);
    EXPECT_NEAR(material["emissiveFactor"][2].get<double>(), 0.0, 0.01);
}

// glTF's COLOR_0 and baseColorFactor are linear: an export's vertex colours (linear, as written
// from standin's sRGB-encoded albedo) read back as the albedo they came from, the factor too.
TEST(Export, LinearColoursReadBackAsTheAlbedoTheyCameFrom)
{
    ExportScene scene;
    ExportMesh mesh;
    mesh.name = "triangle";
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.normals.assign(3, glm::vec3(0, 0, 1));
    mesh.colors = {{0.2140f, 0.2140f, 0.2140f, 1.0f}, {1.0f, 0.0f, 0.0508f, 1.0f}, {1.0f, 1.0f, 1.0f, 1.0f}}; // sRGB 0.5, (1, 0, 0.25), 1
    mesh.base_color = glm::vec4(0.2140f, 1.0f, 1.0f, 1.0f);
    mesh.indices = {0, 1, 2};
    scene.meshes.push_back(mesh);
    Result<std::string> glb = encode_glb(scene, "test");
    ASSERT_TRUE(glb.is_ok());
    const std::string path = test::fresh_directory("export_linear_colours") + "/triangle.glb";
    ASSERT_TRUE(write_file_atomic(path, *glb).is_ok());
    Result<Mesh> back = import_mesh(path);
    ASSERT_TRUE(back.is_ok()) << back.status().message();
    ASSERT_EQ(back->vertex_count(), 3u);
    const glm::vec4 expected[3] = {{0.25f, 0.5f, 0.5f, 1.0f}, {0.5f, 0.0f, 0.25f, 1.0f}, {0.5f, 1.0f, 1.0f, 1.0f}}; // factor x colour
    for (std::size_t v = 0; v < 3; ++v) {
        std::size_t k = 0;
        while (k < 3 && glm::length(back->positions[v] - mesh.positions[k]) > 1e-6f) ++k;
        ASSERT_LT(k, 3u);
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(back->colors[v][c], expected[k][c], 2e-3f) << "vertex " << k << " channel " << c;
    }
}

// A PBR package's billboards, view atlas and microfacets export their ORM and emission maps as
// glTF's metallicRoughnessTexture, occlusionTexture and emissiveTexture (factors 1: the maps as they
// are), so an engine relights them as the model's metal; covered texels hold the model's metallic
// 0.7, roughness 0.4 and emission (microfacets: each plane's mean, in tiles laid out as its
// coverage's). Without PBR maps, the materials stay rough dielectrics.
TEST(Export, ImageBasedStandinsCarryTheirPbrMaps)
{
    Mesh torus = export_torus();
    for (Material& m : torus.materials) m.metallic = 0.7f, m.roughness = 0.4f, m.emissive = glm::vec3(0.2f, 0.1f, 0.0f);
    const std::string dir = test::fresh_directory("export_pbr_maps");
    const std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> bakes = {
        {"enhanced-billboards", {{"resolution", "128"}}},
        {"view-atlas", {{"layout", "octahedral"}, {"frames", "4"}, {"resolution", "64"}, {"page-size", "512"}}},
        {"microfacets", {{"level", "5"}, {"min-level", "3"}, {"subdivisions", "0"}, {"resolution", "128"}, {"page-size", "1024"}}}};
    for (const auto& [representation, values] : bakes) {
        SCOPED_TRACE(representation);
        auto package = bake_small(torus, representation, values);
        ASSERT_TRUE(package);
        ExportScene scene;
        ParsedGlb glb = export_and_parse(*package, {}, dir + "/" + representation + ".glb", 0.8f, &scene);
        std::size_t checked = 0;
        for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
            const ExportMesh& mesh = scene.meshes[m];
            if (mesh.base_color_texture < 0) continue; // the billboards' coarse mesh: vertex colours
            ASSERT_GE(mesh.orm_texture, 0) << mesh.name;
            ASSERT_GE(mesh.emissive_texture, 0) << mesh.name;
            const auto& material = glb.json["materials"][glb.json["meshes"][m]["primitives"][0]["material"].get<std::size_t>()];
            EXPECT_EQ(material["pbrMetallicRoughness"]["metallicRoughnessTexture"]["index"], mesh.orm_texture);
            EXPECT_EQ(material["occlusionTexture"]["index"], mesh.orm_texture);
            EXPECT_EQ(material["emissiveTexture"]["index"], mesh.emissive_texture);
            EXPECT_EQ(material["pbrMetallicRoughness"]["metallicFactor"].get<double>(), 1.0);
            EXPECT_EQ(material["pbrMetallicRoughness"]["roughnessFactor"].get<double>(), 1.0);
            EXPECT_EQ(material["emissiveFactor"], nlohmann::json::array({1, 1, 1}));
            // the maps' texels where the colour is covered
            auto decoded = [&](int texture) {
                const std::string path = dir + "/" + scene.textures[std::size_t(texture)].name + ".png";
                EXPECT_TRUE(write_file_atomic(path, scene.textures[std::size_t(texture)].png).is_ok());
                Result<ImageRGBA8> image = read_png_rgba8(path);
                EXPECT_TRUE(image.is_ok());
                return image.is_ok() ? *image : ImageRGBA8{};
            };
            const ImageRGBA8 color = decoded(mesh.base_color_texture), orm = decoded(mesh.orm_texture),
                             emission = decoded(mesh.emissive_texture);
            ASSERT_EQ(orm.pixels.size(), color.pixels.size());
            ASSERT_EQ(emission.pixels.size(), color.pixels.size());
            double roughness = 0.0, metallic = 0.0, red = 0.0;
            std::size_t covered = 0;
            for (std::size_t i = 0; i < color.pixels.size(); i += 4) {
                if (color.pixels[i + 3] < 255) continue;
                roughness += orm.pixels[i + 1] / 255.0, metallic += orm.pixels[i + 2] / 255.0;
                red += srgb_to_linear(emission.pixels[i] / 255.0f);
                ++covered;
            }
            ASSERT_GT(covered, 100u) << mesh.name;
            EXPECT_NEAR(roughness / double(covered), 0.4, 0.01) << mesh.name;
            EXPECT_NEAR(metallic / double(covered), 0.7, 0.01) << mesh.name;
            EXPECT_NEAR(red / double(covered), 0.2, 0.01) << mesh.name;
            ++checked;
        }
        EXPECT_GT(checked, 0u);
    }
    // the same torus without PBR materials: no maps, the default material
    auto plain = bake_small(export_torus(), "enhanced-billboards", {{"resolution", "128"}});
    ASSERT_TRUE(plain);
    ParsedGlb glb = export_and_parse(*plain, {}, dir + "/plain.glb", 0.25f);
    for (const auto& material : glb.json["materials"]) {
        EXPECT_FALSE(material["pbrMetallicRoughness"].contains("metallicRoughnessTexture"));
        EXPECT_FALSE(material.contains("emissiveTexture"));
    }
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
    // maps padded to multiples of 4 (KTX2 blocks), the billboard's texels top-left, the padding
    // uncovered, and the box's UVs reaching only the billboard's texels
    std::size_t covered = 0;
    for (const ExportMesh& mesh : scene.meshes) {
        if (mesh.extras["standin"]["role"] != "billboard") continue;
        const int width = mesh.extras["standin"]["width"], height = mesh.extras["standin"]["height"];
        const ExportTexture& color = scene.textures[std::size_t(mesh.base_color_texture)];
        const ExportTexture& normal_depth = scene.textures[std::size_t(mesh.base_color_texture) + 1];
        for (const ExportTexture* t : {&color, &normal_depth}) {
            EXPECT_EQ(t->width % 4, 0) << t->name;
            EXPECT_EQ(t->height % 4, 0) << t->name;
            EXPECT_GE(t->width, width);
            EXPECT_LT(t->width, width + 4);
            EXPECT_GE(t->height, height);
            EXPECT_LT(t->height, height + 4);
        }
        ASSERT_TRUE(write_file_atomic(dir + "/map.png", color.png));
        Result<ImageRGBA8> map = read_png_rgba8(dir + "/map.png");
        ASSERT_TRUE(map);
        for (int y = 0; y < map->height; ++y)
            for (int x = 0; x < map->width; ++x) {
                if (x < width && y < height) covered += map->at(x, y)[3] != 0;
                else ASSERT_EQ(map->at(x, y)[3], 0) << color.name << " " << x << ", " << y;
            }
        glm::vec2 uv_max{0.0f};
        for (glm::vec2 uv : mesh.uvs) uv_max = glm::max(uv_max, uv);
        EXPECT_FLOAT_EQ(uv_max.x, float(width) / float(color.width));
        EXPECT_FLOAT_EQ(uv_max.y, float(height) / float(color.height));
    }
    EXPECT_GT(covered, 0u);
}

// Every directed edge of a triangle mesh (vertices welded by exact position) is matched by one in
// the opposite direction: the surface is closed and consistently wound (non-manifold edges, where
// voxels touch along an edge, are used twice in each direction).
bool closed_surface(const ExportMesh& mesh)
{
    std::map<std::array<std::uint32_t, 3>, std::uint32_t> welded;
    std::vector<std::uint32_t> id(mesh.positions.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        std::array<std::uint32_t, 3> bits;
        std::memcpy(bits.data(), &mesh.positions[i], sizeof bits);
        id[i] = welded.try_emplace(bits, std::uint32_t(welded.size())).first->second;
    }
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) ++edges[{id[mesh.indices[t + k]], id[mesh.indices[t + (k + 1) % 3]]}];
    for (const auto& [edge, count] : edges) {
        auto reverse = edges.find({edge.second, edge.first});
        if (reverse == edges.end() || reverse->second != count) return false;
    }
    return !edges.empty();
}

TEST(Export, MicrofacetsExportAClosedVoxelSurface)
{
    Mesh mesh = export_torus();
    auto package = bake_small(mesh, "microfacets", {{"level", "6"}, {"min-level", "3"}, {"subdivisions", "0"},
                                                    {"resolution", "128"}, {"page-size", "1024"}});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("export_microfacets");
    const Bounds& b = package->source.bounds;
    std::size_t previous_triangles = 0;
    // unsnapped (the voxels' own faces) and snapped (corners moved onto the captured surface)
    for (int level = 3; level <= 6; ++level)
    for (bool snap : {false, true}) {
        OptionValues options;
        options.set("planes", "false"); // the closed voxel faces, not the default planes
        options.set("level", std::to_string(level));
        options.set("snap", snap ? "true" : "false");
        ExportScene scene;
        std::string path = dir + "/level" + std::to_string(level) + (snap ? "s" : "") + ".glb";
        ParsedGlb glb = export_and_parse(*package, options, path, 0.6f, &scene);
        ASSERT_EQ(scene.meshes.size(), 1u);
        const ExportMesh& m = scene.meshes[0];
        const auto& extras = glb.json["nodes"][1]["extras"]["standin"];
        EXPECT_EQ(extras["role"], "mesh");
        EXPECT_EQ(extras["level"], level);
        EXPECT_TRUE(closed_surface(m)) << "level " << level << " snap " << snap;
        // two triangles per exposed face, and about four times the faces per level (the surface's
        // area over a voxel face's, which shrinks 4x)
        std::size_t triangles = m.indices.size() / 3;
        EXPECT_EQ(triangles, 2 * extras["faces"].get<std::size_t>());
        if (previous_triangles > 0 && !snap) {
            EXPECT_GT(double(triangles), 2.5 * double(previous_triangles)) << "level " << level;
            EXPECT_LT(double(triangles), 6.0 * double(previous_triangles)) << "level " << level;
        }
        if (!snap) previous_triangles = triangles;
        // the voxels enclose the model and stand at most one voxel beyond its box; snapped, the
        // box is the model's within a voxel
        float voxel = extras["voxel_size"].get<float>();
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : m.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        for (int k = 0; k < 3; ++k) {
            if (!snap) {
                EXPECT_LE(lo[k], b.min[k] + 1e-5f) << "level " << level;
                EXPECT_GE(hi[k], b.max[k] - 1e-5f) << "level " << level;
            }
            EXPECT_NEAR(lo[k], b.min[k], 1.001f * voxel) << "level " << level << " snap " << snap;
            EXPECT_NEAR(hi[k], b.max[k], 1.001f * voxel) << "level " << level << " snap " << snap;
        }
        // colours in range, and the captured normals face out of their faces
        std::size_t outward = 0;
        for (std::size_t f = 0; f < m.positions.size(); f += 4) {
            // the face's first triangle, as wound (counter-clockwise from outside)
            const std::uint32_t* t = &m.indices[f / 4 * 6];
            glm::vec3 face_normal = glm::cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
            outward += glm::dot(face_normal, m.normals[f]) > 0.0f;
            for (int c = 0; c < 4; ++c) {
                EXPECT_GE(m.colors[f][c], 0.0f);
                EXPECT_LE(m.colors[f][c], 1.0f);
            }
        }
        EXPECT_GT(double(outward), (snap ? 0.8 : 0.9) * double(m.positions.size() / 4)) << "level " << level << " snap " << snap;
        EXPECT_TRUE(glb.json["meshes"][0]["primitives"][0]["attributes"].contains("COLOR_0"));
        EXPECT_TRUE(glb.json["meshes"][0]["primitives"][0]["attributes"].contains("NORMAL"));
    }
    // the same package exports the same bytes
    OptionValues six;
    six.set("planes", "false");
    six.set("level", "6");
    ASSERT_TRUE(export_package(*package, six, dir + "/again.glb"));
    EXPECT_EQ(*read_file(dir + "/level6s.glb"), *read_file(dir + "/again.glb"));
    // the default: one cut-out square per seen voxel in its surface's plane, the same bytes again
    OptionValues plain;
    plain.set("level", "6");
    ExportScene planes_scene;
    ParsedGlb planes_glb = export_and_parse(*package, plain, dir + "/planes.glb", 0.6f, &planes_scene);
    ASSERT_EQ(planes_scene.meshes.size(), 1u);
    const auto& planes_extras = planes_glb.json["nodes"][1]["extras"]["standin"];
    EXPECT_GT(planes_extras["planes"].get<std::size_t>(), 0u);
    EXPECT_EQ(planes_scene.meshes[0].indices.size(), 6 * planes_extras["planes"].get<std::size_t>());
    EXPECT_EQ(planes_scene.meshes[0].alpha_mode, "MASK");
    ASSERT_TRUE(export_package(*package, plain, dir + "/planes_again.glb"));
    EXPECT_EQ(*read_file(dir + "/planes.glb"), *read_file(dir + "/planes_again.glb"));
    // --pixels: a small screen takes a coarse level, a large one the finest
    auto level_at = [&](int pixels) {
        OptionValues options;
        options.set("pixels", std::to_string(pixels));
        ExportScene scene;
        EXPECT_TRUE(export_package(*package, options, dir + "/pixels.glb", &scene));
        return scene.meshes.empty() ? -1 : scene.meshes[0].extras["standin"]["level"].get<int>();
    };
    const int small = level_at(16), medium = level_at(128);
    EXPECT_GE(small, 3);
    EXPECT_LT(small, medium);
    EXPECT_EQ(level_at(60000), 6);
    // bad input: one line, nothing written
    for (auto [option, value] : {std::pair{"level", "8"}, std::pair{"level", "2"}, std::pair{"level", "99"}, std::pair{"pixels", "-3"}}) {
        OptionValues bad;
        bad.set(option, value);
        Status s = export_package(*package, bad, dir + "/bad.glb");
        EXPECT_EQ(s.code(), StatusCode::invalid_argument) << option << " " << value;
        EXPECT_EQ(s.message().find('\n'), std::string::npos);
    }
    OptionValues both;
    both.set("level", "5");
    both.set("pixels", "500");
    EXPECT_EQ(export_package(*package, both, dir + "/bad.glb").code(), StatusCode::invalid_argument);
    EXPECT_FALSE(std::filesystem::exists(dir + "/bad.glb"));
}

} // namespace
} // namespace standin
