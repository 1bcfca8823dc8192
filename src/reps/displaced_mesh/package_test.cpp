// The displaced-mesh package through the registry: a bake is byte-identical at 1 and 2 threads,
// round-trips through write and read, refuses damaged or inconsistent packages naming file and
// field, and its declared options refuse what the baker cannot take.
#include "test_support.h"

#include "reps/common/package_codec.h"
#include "reps/displaced_mesh/displaced_mesh.h"

#include <standin/files.h>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace standin::displaced_mesh {
namespace {

namespace fs = std::filesystem;

// A displaced-mesh package of `mesh` baked on 2 threads with `values` (the bounds its source).
Result<std::unique_ptr<Package>> bake_on_two_threads(const Mesh& mesh, const OptionValues& values)
{
    SourceInfo source;
    source.bounds = mesh.bounds();
    return bake_package(*find_representation("displaced-mesh"), mesh, source, values, {}, 2);
}

Mesh small_sphere()
{
    GenerateOptions options;
    options.shape = GeneratedShape::noisy_sphere;
    options.target_triangles = 6000;
    options.noise_amplitude = 0.1f;
    return std::move(*generate_mesh(options));
}

// a file the test expects to exist (an empty string for a missing one would compare equal)
std::string file_text(const std::string& path)
{
    Result<std::string> text = read_file(path);
    EXPECT_TRUE(text.is_ok()) << path;
    return text ? *text : std::string();
}

TEST(DisplacedMeshPackage, ByteIdenticalAtOneAndTwoThreadsAndRoundTrips)
{
    Mesh mesh = small_sphere();
    SourceInfo source;
    source.bounds = mesh.bounds();
    OptionValues values;
    values.set("degree", "9");
    const Representation& r = *find_representation("displaced-mesh");
    Result<std::unique_ptr<Package>> one = bake_package(r, mesh, source, values, {}, 1);
    Result<std::unique_ptr<Package>> two = bake_package(r, mesh, source, values, {}, 2);
    ASSERT_TRUE(one.is_ok() && two.is_ok()) << one.status().message();
    std::string dir = test::fresh_directory("displaced_roundtrip");
    ASSERT_TRUE(write_package(**one, dir + "/a.standin").is_ok());
    ASSERT_TRUE(write_package(**two, dir + "/b.standin").is_ok());
    for (const char* name : {"manifest.json", "control.ply", "elevation.bin.gz", "face_error.bin.gz", "normal.bin.gz", "albedo.bin.gz"})
        EXPECT_EQ(file_text(dir + "/a.standin/" + name), file_text(dir + "/b.standin/" + name)) << name;

    Result<std::unique_ptr<Package>> back = read_package(dir + "/a.standin");
    ASSERT_TRUE(back.is_ok()) << back.status().message();
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(**one);
    const auto& q = dynamic_cast<const DisplacedMeshPackage&>(**back);
    EXPECT_EQ(q.positions, p.positions);
    EXPECT_EQ(q.normals, p.normals);
    EXPECT_EQ(q.indices, p.indices);
    EXPECT_EQ(q.elevations, p.elevations);
    EXPECT_EQ(q.shading_normals, p.shading_normals);
    EXPECT_EQ(q.albedo, p.albedo);
    EXPECT_EQ(q.face_error, p.face_error);
    EXPECT_EQ(q.settings.degree, 9);
    EXPECT_EQ(q.topology.edges.size(), p.topology.edges.size());
    EXPECT_EQ(summarise_package(q).details["control_faces"], p.face_count());

    // a package baked with 32-bit elevations round-trips too
    values.set("elevation-bits", "32");
    Result<std::unique_ptr<Package>> floats = bake_package(r, mesh, source, values, {}, 1);
    ASSERT_TRUE(floats.is_ok());
    ASSERT_TRUE(write_package(**floats, dir + "/c.standin").is_ok());
    Result<std::unique_ptr<Package>> floats_back = read_package(dir + "/c.standin");
    ASSERT_TRUE(floats_back.is_ok()) << floats_back.status().message();
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(**floats_back).elevations,
              dynamic_cast<const DisplacedMeshPackage&>(**floats).elevations);
}

// Shading finer than the pattern (a textured low-poly model drawn from its samples, auto resolves to
// 4): the arrays hold (k - 1) x 4 segments per face, the manifest records the detail, the bytes are
// the same at 1 and 2 threads, and the package reads back; an alpha-masked model refuses a detail
// above 1. (With the source's texture, the default, the box's faces draw it and take detail 1.)
TEST(DisplacedMeshPackage, FinerShadingRoundTripsAndIsRecorded)
{
    Result<Mesh> box = import_mesh(test::source_dir() + "/data/box_textured.glb");
    ASSERT_TRUE(box.is_ok());
    SourceInfo source;
    source.bounds = box->bounds();
    const Representation& r = *find_representation("displaced-mesh");
    OptionValues sampled;
    sampled.set("source-textures", "off");
    Result<std::unique_ptr<Package>> one = bake_package(r, *box, source, sampled, {}, 1);
    Result<std::unique_ptr<Package>> two = bake_package(r, *box, source, sampled, {}, 2);
    ASSERT_TRUE(one.is_ok() && two.is_ok()) << one.status().message();
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(**one);
    EXPECT_EQ(p.settings.degree, 33); // 12 faces, every one a control face (default_control_plan)
    EXPECT_EQ(p.settings.shading_detail, 4);
    EXPECT_EQ(p.shading_segments(), 128);
    EXPECT_EQ(p.shading_normals.size(), p.face_count() * triangle_samples(128));
    std::string dir = test::fresh_directory("displaced_fine_shading");
    ASSERT_TRUE(write_package(**one, dir + "/a.standin").is_ok());
    ASSERT_TRUE(write_package(**two, dir + "/b.standin").is_ok());
    for (const char* name : {"manifest.json", "normal.bin.gz", "albedo.bin.gz"})
        EXPECT_EQ(file_text(dir + "/a.standin/" + name), file_text(dir + "/b.standin/" + name)) << name;
    EXPECT_NE(file_text(dir + "/a.standin/manifest.json").find("\"shading_detail\": \"4\""), std::string::npos);
    Result<std::unique_ptr<Package>> back = read_package(dir + "/a.standin");
    ASSERT_TRUE(back.is_ok()) << back.status().message();
    const auto& q = dynamic_cast<const DisplacedMeshPackage&>(**back);
    EXPECT_EQ(q.settings.shading_detail, 4);
    EXPECT_EQ(q.shading_normals, p.shading_normals);
    // `standin info` reports the detail, the samples and what they take on the GPU (8 bytes each
    // and the elevations at 4 bytes, at least)
    const nlohmann::json details = summarise_package(q).details;
    EXPECT_EQ(details["shading_detail"], 4);
    EXPECT_EQ(details["shading_samples"], q.shading_normals.size());
    EXPECT_GE(details["gpu_buffer_bytes"].get<std::uint64_t>(), 8 * q.shading_normals.size() + 4 * q.elevations.size());
    EXPECT_EQ(q.albedo, p.albedo);

    // an alpha-masked model's coverage is sampled with its shading, and round-trips with it
    OptionValues finer;
    finer.set("shading-detail", "2");
    finer.set("degree", "9");
    Result<std::unique_ptr<Package>> masked = bake_package(r, test::alpha_quad(AlphaMode::mask, 0.5f, true), source, finer, {}, 1);
    ASSERT_TRUE(masked.is_ok()) << masked.status().message();
    const auto& m = dynamic_cast<const DisplacedMeshPackage&>(**masked);
    EXPECT_EQ(m.coverage.size(), m.face_count() * triangle_samples(16));
    ASSERT_TRUE(write_package(**masked, dir + "/masked.standin").is_ok());
    Result<std::unique_ptr<Package>> masked_back = read_package(dir + "/masked.standin");
    ASSERT_TRUE(masked_back.is_ok()) << masked_back.status().message();
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(**masked_back).coverage, m.coverage);
}

// Issue #14: a model with alpha-masked materials gets coverage (the disc the alpha test keeps of
// the quad, and nothing of its cut-out corners), written as coverage.bin and read back; a model
// without gets neither the array nor the file, so its package is what it was before.
TEST(DisplacedMeshPackage, CoverageOnlyForAlphaMaskedModelsAndRoundTrips)
{
    std::string dir = test::fresh_directory("displaced_coverage");
    std::unique_ptr<Package> masked = test::bake(test::alpha_quad(AlphaMode::mask, 0.5f, true), "displaced-mesh", {{"degree", "9"}});
    ASSERT_TRUE(masked);
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(*masked);
    ASSERT_EQ(p.coverage.size(), p.face_count() * p.shading_samples_per_face()); // sampled with the shading
    std::size_t covered = 0;
    for (std::uint8_t c : p.coverage) {
        EXPECT_TRUE(c == 0 || c == 255);
        covered += c == 255;
    }
    // the kept disc is pi / 16 of the quad; the samples on the pattern see about as much
    double share = double(covered) / double(p.coverage.size());
    EXPECT_GT(share, 0.10);
    EXPECT_LT(share, 0.32);
    ASSERT_TRUE(write_package(*masked, dir + "/masked.standin").is_ok());
    EXPECT_TRUE(fs::exists(dir + "/masked.standin/coverage.bin.gz"));
    Result<std::unique_ptr<Package>> back = read_package(dir + "/masked.standin");
    ASSERT_TRUE(back.is_ok()) << back.status().message();
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(**back).coverage, p.coverage);

    std::unique_ptr<Package> opaque = test::bake(test::alpha_quad(AlphaMode::opaque, 0.5f, true), "displaced-mesh", {{"degree", "9"}});
    ASSERT_TRUE(opaque);
    EXPECT_TRUE(dynamic_cast<const DisplacedMeshPackage&>(*opaque).coverage.empty());
    ASSERT_TRUE(write_package(*opaque, dir + "/opaque.standin").is_ok());
    EXPECT_FALSE(fs::exists(dir + "/opaque.standin/coverage.bin.gz"));
    EXPECT_EQ(file_text(dir + "/opaque.standin/manifest.json").find("coverage"), std::string::npos);
}

// Issue #14: control faces that are source triangles keep the source's texture, corner for corner:
// the alpha-masked card's two faces always, the opaque card's because the control mesh kept every
// face; records and texture round-trip, `off` and untextured models store none, and a record naming
// a layer the package lacks is refused naming the field.
TEST(DisplacedMeshPackage, SourceTrianglesKeepTheirTextureCornerForCorner)
{
    std::string dir = test::fresh_directory("displaced_source_textures");
    for (AlphaMode mode : {AlphaMode::mask, AlphaMode::opaque}) {
        const Mesh card = test::alpha_quad(mode, 0.5f, true);
        std::unique_ptr<Package> baked = test::bake(card, "displaced-mesh", {{"degree", "9"}});
        ASSERT_TRUE(baked);
        auto& p = dynamic_cast<DisplacedMeshPackage&>(*baked);
        const SourceTextures& t = p.source_textures;
        ASSERT_EQ(t.faces.size(), p.face_count());
        EXPECT_EQ(t.matched_faces(), card.triangle_count());
        ASSERT_EQ(t.layers.size(), 1u);
        EXPECT_EQ(t.layers[0].width, card.textures[0].width);
        EXPECT_EQ(t.layers[0].rgba, card.textures[0].rgba);
        for (std::size_t f = 0; f < p.face_count(); ++f) {
            EXPECT_EQ(t.faces[f].layer, 0u);
            EXPECT_EQ(t.faces[f].cutoff, alpha_test_cutoff(card.materials[0]));
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 corner = p.positions[p.indices[3 * f + std::size_t(k)]];
                std::size_t v = 0;
                while (v < card.positions.size() && card.positions[v] != corner) ++v;
                ASSERT_LT(v, card.positions.size());
                EXPECT_EQ(t.faces[f].uv[k], card.uvs[v]) << "face " << f << " corner " << k;
                EXPECT_EQ(t.faces[f].color[k], pack_rgba8(card.colors[v]));
            }
        }
        const std::string path = dir + (mode == AlphaMode::mask ? "/mask.standin" : "/opaque.standin");
        ASSERT_TRUE(write_package(p, path).is_ok());
        Result<std::unique_ptr<Package>> back = read_package(path);
        ASSERT_TRUE(back.is_ok()) << back.status().message();
        const SourceTextures& read = dynamic_cast<const DisplacedMeshPackage&>(**back).source_textures;
        ASSERT_EQ(read.faces.size(), t.faces.size());
        EXPECT_EQ(std::memcmp(read.faces.data(), t.faces.data(), t.faces.size() * sizeof(FaceTexture)), 0);
        ASSERT_EQ(read.layers.size(), 1u);
        EXPECT_EQ(read.layers[0].rgba, t.layers[0].rgba);

        if (mode == AlphaMode::mask) {
            p.source_textures.faces[1].layer = 3; // a layer the package does not hold
            ASSERT_TRUE(write_package(p, dir + "/bad_layer.standin").is_ok());
            Result<std::unique_ptr<Package>> bad = read_package(dir + "/bad_layer.standin");
            ASSERT_FALSE(bad.is_ok());
            EXPECT_NE(bad.status().message().find("source_textures"), std::string::npos) << bad.status().message();
            // layers asking for more texels than standin reads (a memory bomb of well-compressed PNGs)
            p.source_textures.faces[1].layer = 0;
            ASSERT_TRUE(write_package(p, dir + "/huge.standin").is_ok());
            std::string manifest = file_text(dir + "/huge.standin/manifest.json");
            const std::string width = "\"width\": " + std::to_string(card.textures[0].width);
            ASSERT_NE(manifest.find(width), std::string::npos);
            manifest.replace(manifest.find(width), width.size(), "\"width\": 16384");
            const std::string height = "\"height\": " + std::to_string(card.textures[0].height);
            ASSERT_NE(manifest.find(height), std::string::npos);
            manifest.replace(manifest.find(height), height.size(), "\"height\": 16384");
            std::size_t at = manifest.find("\"layers\": [");
            ASSERT_NE(at, std::string::npos);
            std::size_t end = manifest.find(']', at);
            const std::string one = manifest.substr(manifest.find('{', at), manifest.rfind('}', end) - manifest.find('{', at) + 1);
            manifest.insert(end, ", " + one + ", " + one); // three layers of 16384²: 805 million texels
            ASSERT_TRUE(write_file_atomic(dir + "/huge.standin/manifest.json", manifest).is_ok());
            Result<std::unique_ptr<Package>> huge = read_package(dir + "/huge.standin");
            ASSERT_FALSE(huge.is_ok());
            EXPECT_NE(huge.status().message().find("source_textures.layers"), std::string::npos) << huge.status().message();
        }
    }
    std::unique_ptr<Package> off =
        test::bake(test::alpha_quad(AlphaMode::mask, 0.5f, true), "displaced-mesh", {{"degree", "9"}, {"source-textures", "off"}});
    ASSERT_TRUE(off);
    EXPECT_TRUE(dynamic_cast<const DisplacedMeshPackage&>(*off).source_textures.faces.empty());
    ASSERT_TRUE(write_package(*off, dir + "/off.standin").is_ok());
    EXPECT_EQ(file_text(dir + "/off.standin/manifest.json").find("\"source_textures\": {"), std::string::npos);
    std::unique_ptr<Package> untextured = test::bake(small_sphere(), "displaced-mesh", {{"degree", "5"}});
    ASSERT_TRUE(untextured);
    EXPECT_TRUE(dynamic_cast<const DisplacedMeshPackage&>(*untextured).source_textures.faces.empty());
}

// Issue #14: the cut-out texels of most leaf textures are black. Samples on the cut-out take their
// covered neighbours' colour, and covered samples average only covered texels of their cell, so the
// interpolated colour never darkens towards the cut-out: every sample of the disc quad keeps the
// disc's green. An alpha-masked card filling the view defaults to degree 33 (k_alpha_degree); an
// opaque one keeps its 2 faces, at 33 too (default_control_plan).
TEST(DisplacedMeshPackage, CutOutSamplesTakeTheCoveredColourAndMaskedModelsSampleFiner)
{
    Mesh leaf = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    for (std::size_t t = 0; t < leaf.textures[0].rgba.size(); t += 4)
        if (leaf.textures[0].rgba[t + 3] < 128) leaf.textures[0].rgba[t] = leaf.textures[0].rgba[t + 1] = leaf.textures[0].rgba[t + 2] = 0;
    std::unique_ptr<Package> masked = test::bake(leaf, "displaced-mesh", {{"degree", "9"}});
    ASSERT_TRUE(masked);
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(*masked);
    ASSERT_EQ(p.albedo.size(), p.coverage.size());
    const glm::vec3 green(40.0f / 255.0f, 200.0f / 255.0f, 60.0f / 255.0f);
    // black is 0.84 from the green; a covered point on the disc's rim reads a bilinear mix of its
    // texels (as the truth does there), at most half black
    float worst = 0.0f, sum = 0.0f;
    for (std::uint32_t packed : p.albedo) {
        glm::vec3 rgb = glm::vec3(packed & 255u, (packed >> 8) & 255u, (packed >> 16) & 255u) / 255.0f;
        worst = std::max(worst, glm::length(rgb - green));
        sum += glm::length(rgb - green);
    }
    EXPECT_LT(worst, 0.3f) << "a sample's colour is the cut-out's black";
    EXPECT_LT(sum / float(p.albedo.size()), 0.02f) << "the samples' colours are darkened towards the cut-out's black";

    std::unique_ptr<Package> masked_default = test::bake(leaf, "displaced-mesh", {});
    ASSERT_TRUE(masked_default);
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(*masked_default).settings.degree, k_alpha_degree);
    std::unique_ptr<Package> opaque_default = test::bake(test::alpha_quad(AlphaMode::opaque, 0.5f, true), "displaced-mesh", {});
    ASSERT_TRUE(opaque_default);
    // (an opaque quad: its 2 faces kept at 33 by default_control_plan, not by k_alpha_degree)
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(*opaque_default).settings.degree, 33);
}

// n x n disc cards (test::alpha_quad: 2 faces, a 256-texel texture) tiling the unit square
Mesh tiled_cards(int n)
{
    const Mesh card = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    Mesh mesh = card;
    mesh.positions.clear(), mesh.normals.clear(), mesh.colors.clear(), mesh.uvs.clear(), mesh.indices.clear(), mesh.face_materials.clear();
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const auto base = std::uint32_t(mesh.positions.size());
            for (std::size_t v = 0; v < card.positions.size(); ++v) {
                mesh.positions.push_back((card.positions[v] + glm::vec3(0.5f + float(x), 0.5f + float(y), 0.0f)) / float(n));
                mesh.normals.push_back(card.normals[v]);
                mesh.colors.push_back(card.colors[v]);
                mesh.uvs.push_back(card.uvs[v]);
            }
            for (std::uint32_t i : card.indices) mesh.indices.push_back(base + i);
            mesh.face_materials.insert(mesh.face_materials.end(), card.face_materials.begin(), card.face_materials.end());
        }
    return mesh;
}

// Issue #14: a leaf card keeps its vertices in the control mesh, so each card holds a whole pattern:
// the default degree (33) goes coarser only where the cut-out faces would hold over
// k_max_cutout_samples finest samples.
TEST(DisplacedMeshPackage, TheDefaultDegreeOfManyCardsStaysWithinASampleBudget)
{
    EXPECT_EQ(cutout_degree(tiled_cards(1)), 33);
    EXPECT_EQ(cutout_degree(tiled_cards(80)), 33);  // 12,800 cut-out faces x 561 samples: 7.2 million
    EXPECT_EQ(cutout_degree(tiled_cards(100)), 17); // 20,000 x 561 is over 8 million, x 153 not
    EXPECT_EQ(cutout_degree(tiled_cards(250)), 9);  // 125,000 x 153 is over, x 45 not
    EXPECT_EQ(cutout_degree(tiled_cards(300)), 5);  // 180,000 x 45 is over too
    Mesh opaque = tiled_cards(100);
    opaque.materials[0].alpha_mode = AlphaMode::opaque;
    EXPECT_EQ(cutout_degree(opaque), k_alpha_degree); // no cut-out faces: not asked (the bake plans their degree: default_control_plan)
}

// With the degree chosen and no --control-faces, the paper's target (input faces over (k - 1)^2 at
// 17) holds from 65,536 faces; smaller inputs spend its floor's 65,536 finest triangles on 4,096
// control faces at degree 5, and inputs of 4,096 faces or fewer keep every face at the finest
// degree within them, where the displaced surface is the input's own (each sample lies on its
// face: elevations zero).
TEST(DisplacedMeshPackage, SmallInputsTakeACoarserDegreeOrKeepEveryFace)
{
    const auto plan = [](std::size_t faces) {
        ControlPlan p = default_control_plan(faces);
        return std::pair<int, std::size_t>(p.degree, p.target_faces);
    };
    EXPECT_EQ(plan(1'000'000), std::make_pair(17, std::size_t(3906)));
    EXPECT_EQ(plan(65'536), std::make_pair(17, std::size_t(256)));
    EXPECT_EQ(plan(60'000), std::make_pair(5, std::size_t(4096)));
    EXPECT_EQ(plan(4'097), std::make_pair(5, std::size_t(4096)));
    EXPECT_EQ(plan(4'096), std::make_pair(5, std::size_t(4096)));  // 65,536 finest triangles
    EXPECT_EQ(plan(3'000), std::make_pair(5, std::size_t(3000)));  // 48,000 at 5; 192,000 at 9
    EXPECT_EQ(plan(576), std::make_pair(9, std::size_t(576)));     // 36,864 at 9
    EXPECT_EQ(plan(256), std::make_pair(17, std::size_t(256)));
    EXPECT_EQ(plan(12), std::make_pair(33, std::size_t(12)));

    Result<Mesh> bunny = import_mesh(test::source_dir() + "/data/bunny.ply");
    ASSERT_TRUE(bunny.is_ok());
    Result<std::unique_ptr<Package>> baked = bake_on_two_threads(*bunny, {});
    ASSERT_TRUE(baked.is_ok()) << baked.status().message();
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(**baked);
    EXPECT_EQ(p.face_count(), bunny->triangle_count());
    EXPECT_EQ(p.settings.degree, 5);
    EXPECT_TRUE(p.parameters.requested().empty()) << "a re-bake with the defaults takes the same plan";
    float largest = 0.0f;
    for (float h : p.elevations) largest = std::max(largest, std::abs(h));
    EXPECT_LT(largest, 1e-4f * bunny->bounds().diagonal()) << "the samples lie on the input's faces";
    // a given degree takes the paper's target (at least 256 faces) as before
    OptionValues given;
    given.set("degree", "17");
    Result<std::unique_ptr<Package>> paper = bake_on_two_threads(*bunny, given);
    ASSERT_TRUE(paper.is_ok()) << paper.status().message();
    EXPECT_LT(dynamic_cast<const DisplacedMeshPackage&>(**paper).face_count(), bunny->triangle_count() / 4);
}

// A model kept whole (default_control_plan) samples every part on its own faces, a part half inside
// another included: a ball of about 1,000 faces whose centre lies on the surface of one 2.5 times
// its size, every elevation zero. (Samples hidden inside the larger ball are not moved out to it,
// SampleOptions::move_hidden_out; here undo_covered_moves would put them back anyway, so this holds
// either way: the flag's effect was measured on assimp's minigun, docs/RESULTS.md.)
TEST(DisplacedMeshPackage, AModelKeptWholeSamplesEveryPartOnItsOwnFaces)
{
    GenerateOptions options;
    options.shape = GeneratedShape::noisy_sphere;
    options.target_triangles = 1000;
    options.noise_amplitude = 0.05f;
    Mesh balls = std::move(*generate_mesh(options));
    const std::size_t outer_vertices = balls.positions.size(), outer_faces = balls.triangle_count();
    for (std::size_t v = 0; v < outer_vertices; ++v) {
        balls.positions.push_back(glm::vec3(1.0f, 0.0f, 0.0f) + 0.4f * balls.positions[v]);
        balls.normals.push_back(balls.normals[v]);
        balls.colors.push_back(balls.colors[v]);
    }
    for (std::size_t k = 0, count = balls.indices.size(); k < count; ++k) balls.indices.push_back(balls.indices[k] + std::uint32_t(outer_vertices));
    balls.face_materials.resize(2 * outer_faces, balls.face_materials.front());
    Result<std::unique_ptr<Package>> baked = bake_on_two_threads(balls, {});
    ASSERT_TRUE(baked.is_ok()) << baked.status().message();
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(**baked);
    ASSERT_EQ(p.face_count(), balls.triangle_count());
    float largest = 0.0f;
    for (float h : p.elevations) largest = std::max(largest, std::abs(h));
    EXPECT_LT(largest, 1e-4f * balls.bounds().diagonal());
}

// A texture finer than the shading samples is averaged over each sample's cell, as the truth's mip
// level averages it, not point-sampled: a checker of 48 texels a side on a quad kept whole (2 faces
// at degree 33, 32 steps a side, detail 1) puts every other sample on a texel's centre, where a
// point sample reads pure black or white; averaged over its cell (1.5 texels) none is within a
// tenth of either (the quad's rim, whose cells are cut by the face, 0.28 at the least).
TEST(DisplacedMeshPackage, TexturesFinerThanTheSamplesAreAveragedOverTheirCells)
{
    Mesh quad = test::alpha_quad(AlphaMode::opaque, 0.5f, true);
    quad.textures[0] = test::painted_texture("checker", 48, [](int x, int y, std::uint8_t* t) {
        t[0] = t[1] = t[2] = (x + y) % 2 ? 255 : 0;
        t[3] = 255;
    });
    OptionValues values;
    values.set("shading-detail", "1");
    Result<std::unique_ptr<Package>> baked = bake_on_two_threads(quad, values);
    ASSERT_TRUE(baked.is_ok()) << baked.status().message();
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(**baked);
    ASSERT_EQ(p.settings.degree, 33);
    std::size_t pure = 0;
    for (std::uint32_t rgba : p.albedo) {
        const std::uint32_t red = rgba & 0xffu;
        pure += red < 26 || red > 229;
    }
    EXPECT_EQ(pure, 0u) << "of " << p.albedo.size() << " samples, some read the checker's texels point-sampled";
}

// A control mesh that stops far above its target (the boundary loops of many open parts keep their
// vertices) takes a coarser default degree: its finest pattern within k_max_pattern_growth (4) times
// what the target's faces would hold at the given degree (153 samples a face at 17, 45 at 9, 15 at 5).
TEST(DisplacedMeshPackage, AControlMeshFarAboveItsTargetTakesACoarserDefaultDegree)
{
    EXPECT_EQ(control_degree(256, 256, 17), 17);
    EXPECT_EQ(control_degree(1018, 424, 17), 17);  // the generated assembly: 2.4 times its target
    EXPECT_EQ(control_degree(1000, 100, 17), 9);   // 153,000 over 61,200; 45,000 not
    EXPECT_EQ(control_degree(17197, 431, 17), 5);  // the held-out engine: over at 9 (773,865 > 263,772)
    EXPECT_EQ(control_degree(100000, 10, 17), 5);  // 5 at most coarse

    // 1,600 separate opaque cards (3,200 faces, each card's 4-vertex loop kept whole) against the
    // given target of 256 faces: degree 9 (without it every face is kept, at 5: default_control_plan);
    // a given degree kept
    Mesh cards = tiled_cards(40);
    cards.materials[0].alpha_mode = AlphaMode::opaque;
    const std::size_t per_card = cards.positions.size() / 1600; // each card shrunk about its centre: apart
    for (std::size_t first = 0; first < cards.positions.size(); first += per_card) {
        glm::vec3 centre(0.0f);
        for (std::size_t v = first; v < first + per_card; ++v) centre += cards.positions[v] / float(per_card);
        for (std::size_t v = first; v < first + per_card; ++v) cards.positions[v] = centre + 0.8f * (cards.positions[v] - centre);
    }
    SourceInfo source;
    source.bounds = cards.bounds();
    const Representation& r = *find_representation("displaced-mesh");
    OptionValues target_given;
    target_given.set("control-faces", "256");
    Result<std::unique_ptr<Package>> by_default = bake_package(r, cards, source, target_given, {}, 2);
    ASSERT_TRUE(by_default.is_ok()) << by_default.status().message();
    const auto& coarse = dynamic_cast<const DisplacedMeshPackage&>(**by_default);
    EXPECT_EQ(coarse.face_count(), 3200u);
    EXPECT_EQ(coarse.settings.degree, 9);
    EXPECT_EQ(coarse.parameters.integer("degree"), 9) << "the package records the degree it was baked at";
    Result<std::unique_ptr<Package>> whole = bake_package(r, cards, source, {}, {}, 2);
    ASSERT_TRUE(whole.is_ok()) << whole.status().message();
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(**whole).settings.degree, 5);
    OptionValues given;
    given.set("degree", "17");
    Result<std::unique_ptr<Package>> kept = bake_package(r, cards, source, given, {}, 2);
    ASSERT_TRUE(kept.is_ok()) << kept.status().message();
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(**kept).settings.degree, 17);
}

// Cut-out cards ask for finer coverage than colour does: a leaf's outline a pixel off shows where a
// colour blur of 4 pixels does not. The tiled cards' pattern step at degree 33 (cards kept whole) is
// 1.138 / 32 / n of the unit square, a reference pixel sqrt(2) / 564.
TEST(DisplacedMeshPackage, CutOutCardsAreShadedFinerWhileTheirStepIsOverAPixel)
{
    const auto detail = [](const Mesh& mesh) { return finest_useful_detail(mesh, mesh.positions, mesh.indices, 33); };
    EXPECT_EQ(detail(tiled_cards(20)), 1); // 0.71 px
    EXPECT_EQ(detail(tiled_cards(10)), 2); // 1.42 px: 0.71 at 2 (colour alone: 1, under 4 px)
    EXPECT_EQ(detail(tiled_cards(3)), 4);  // 4.7 px: colour alone 2, outlines 4
    Mesh opaque = tiled_cards(10);
    opaque.materials[0].alpha_mode = AlphaMode::opaque;
    EXPECT_EQ(detail(opaque), 1);
    opaque = tiled_cards(3);
    opaque.materials[0].alpha_mode = AlphaMode::opaque;
    EXPECT_EQ(detail(opaque), 2);
    // not finer than two of the texture's texels: at 64 a card (n = 3), a step at 4 would be 1.1
    Mesh coarse_texture = tiled_cards(3);
    Texture& t = coarse_texture.textures[0];
    t.width = t.height = 64;
    t.rgba.assign(64 * 64 * 4, 255);
    EXPECT_EQ(detail(coarse_texture), 2);

    // The budgets: at degree 17 the n = 3 cards' step is 9.5 px, so colour and outlines both want 4.
    // A control mesh of 20,016 faces as large (the 18 repeated) holds 42.9 million shading samples
    // at 4 and 11.2 million at 2 (561 a face): over the 8 million of opaque textured models (they get
    // 1) and within the 16 million of models with cut-out faces (2).
    Mesh cards = tiled_cards(3);
    std::vector<std::uint32_t> control;
    for (int copy = 0; copy < 1112; ++copy) control.insert(control.end(), cards.indices.begin(), cards.indices.end());
    ASSERT_EQ(control.size() / 3, 20'016u);
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, cards.indices, 17), 4);
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, control, 17), 2);
    cards.materials[0].alpha_mode = AlphaMode::opaque;
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, cards.indices, 17), 4);
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, control, 17), 1);
}

// Cards drawn with the source's own texture (session 46) show neither their samples' colour nor
// their coverage: they ask for no shading detail (the 2,000-face bush took 2 for its cards'
// outlines), while faces drawn from samples still do, and --source-textures off keeps the old rule.
TEST(DisplacedMeshPackage, CardsDrawnWithTheSourceTextureAskForNoShadingDetail)
{
    const Mesh cards = tiled_cards(3); // 4.7 px a step at degree 33: detail 4 from samples
    const std::size_t faces = cards.triangle_count();
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, cards.indices, 33, std::vector<std::uint8_t>(faces, k_drawn_from_source_cut_out)), 1);
    // half the cards drawn from samples: their step and outlines still ask for 4
    std::vector<std::uint8_t> half(faces, 0);
    for (std::size_t f = 0; f < faces / 2; ++f) half[f] = k_drawn_from_source_cut_out;
    EXPECT_EQ(finest_useful_detail(cards, cards.positions, cards.indices, 33, half), 4);

    std::unique_ptr<Package> textured = test::bake(cards, "displaced-mesh", {{"degree", "33"}});
    std::unique_ptr<Package> sampled = test::bake(cards, "displaced-mesh", {{"degree", "33"}, {"source-textures", "off"}});
    ASSERT_TRUE(textured && sampled);
    const auto& t = dynamic_cast<const DisplacedMeshPackage&>(*textured);
    const auto& s = dynamic_cast<const DisplacedMeshPackage&>(*sampled);
    EXPECT_EQ(t.source_textures.matched_faces(), faces);
    EXPECT_EQ(t.settings.shading_detail, 1);
    EXPECT_GT(s.settings.shading_detail, 1);
    EXPECT_LT(t.shading_samples_per_face(), s.shading_samples_per_face());
}

TEST(DisplacedMeshPackage, DamagedPackagesAreRefusedNamingTheFile)
{
    Mesh mesh = small_sphere();
    std::unique_ptr<Package> package = test::bake(mesh, "displaced-mesh", {{"degree", "5"}});
    ASSERT_TRUE(package);
    std::string dir = test::fresh_directory("displaced_damaged");
    auto fresh = [&](const std::string& name) {
        std::string path = dir + "/" + name + ".standin";
        EXPECT_TRUE(write_package(*package, path).is_ok());
        return path;
    };
    // a flipped byte
    std::string flipped = fresh("flipped");
    {
        std::fstream f(flipped + "/elevation.bin.gz", std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(10);
        f.put(char(0x5a));
    }
    Result<std::unique_ptr<Package>> a = read_package(flipped);
    ASSERT_FALSE(a.is_ok());
    EXPECT_NE(a.status().message().find("elevation.bin"), std::string::npos) << a.status().message();

    // a manifest that disagrees with the control mesh, or with the declared options
    auto edit_manifest = [&](const std::string& path, const std::string& from, const std::string& to) {
        std::string text = file_text(path + "/manifest.json");
        std::size_t at = text.find(from);
        ASSERT_NE(at, std::string::npos) << from;
        text.replace(at, from.size(), to);
        ASSERT_TRUE(write_file_atomic(path + "/manifest.json", text).is_ok());
    };
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(*package);
    std::string faces = fresh("faces");
    edit_manifest(faces, "\"faces\": " + std::to_string(p.face_count()), "\"faces\": " + std::to_string(p.face_count() + 1));
    Result<std::unique_ptr<Package>> b = read_package(faces);
    ASSERT_FALSE(b.is_ok());
    EXPECT_NE(b.status().message().find("control.faces"), std::string::npos) << b.status().message();
    std::string sampler = fresh("sampler");
    edit_manifest(sampler, "\"sampler\": \"intersection\"", "\"sampler\": \"guesswork\"");
    Result<std::unique_ptr<Package>> c = read_package(sampler);
    ASSERT_FALSE(c.is_ok());
    EXPECT_NE(c.status().message().find("sampler"), std::string::npos) << c.status().message();
    std::string degree = fresh("degree");
    edit_manifest(degree, "\"degree\": 5", "\"degree\": 7");
    EXPECT_FALSE(read_package(degree).is_ok());
}

// Arrays are gzip members by default (format version 7) and raw with --compression none (version
// 1, for older readers); both read back to the same package, packages from before the option read
// as raw, and a .gz that does not inflate to exactly the manifest's size is refused naming it.
TEST(DisplacedMeshPackage, ArraysAreGzipMembersAndRefuseAnyOtherSize)
{
    Mesh mesh = small_sphere();
    std::unique_ptr<Package> gz = test::bake(mesh, "displaced-mesh", {{"degree", "5"}});
    std::unique_ptr<Package> raw = test::bake(mesh, "displaced-mesh", {{"degree", "5"}, {"compression", "none"}});
    ASSERT_TRUE(gz && raw);
    std::string dir = test::fresh_directory("displaced_gzip");
    ASSERT_TRUE(write_package(*gz, dir + "/gz.standin").is_ok());
    ASSERT_TRUE(write_package(*raw, dir + "/raw.standin").is_ok());
    nlohmann::json gz_manifest = nlohmann::json::parse(file_text(dir + "/gz.standin/manifest.json"));
    EXPECT_EQ(gz_manifest["version"], k_package_format_version_gzip_arrays);
    EXPECT_EQ(nlohmann::json::parse(file_text(dir + "/raw.standin/manifest.json"))["version"], 1);
    const auto& p = dynamic_cast<const DisplacedMeshPackage&>(*raw);
    for (const char* name : {"elevation.bin", "face_error.bin", "normal.bin", "albedo.bin"}) {
        EXPECT_FALSE(fs::exists(dir + "/gz.standin/" + name)) << name;
        std::string member = file_text(dir + "/gz.standin/" + name + ".gz");
        ASSERT_GE(member.size(), 18u) << name;
        // RFC 1952: magic, deflate, no flags, mtime 0 (the bytes depend on the arrays alone)
        EXPECT_EQ(member.substr(0, 8), std::string("\x1f\x8b\x08\x00\x00\x00\x00\x00", 8)) << name;
        // ISIZE, the member's last 4 bytes: the raw array's size
        std::uint32_t size = 0;
        std::memcpy(&size, member.data() + member.size() - 4, 4);
        EXPECT_EQ(size, file_text(dir + "/raw.standin/" + name).size()) << name;
    }
    EXPECT_LT(fs::file_size(dir + "/gz.standin/albedo.bin.gz") * 20, fs::file_size(dir + "/raw.standin/albedo.bin")); // one colour
    for (const char* name : {"gz", "raw"}) {
        Result<std::unique_ptr<Package>> back = read_package(dir + "/" + name + ".standin");
        ASSERT_TRUE(back.is_ok()) << back.status().message();
        const auto& q = dynamic_cast<const DisplacedMeshPackage&>(**back);
        EXPECT_EQ(q.elevations, p.elevations) << name;
        EXPECT_EQ(q.elevation_codes, p.elevation_codes) << name;
        EXPECT_EQ(q.face_error, p.face_error) << name;
        EXPECT_EQ(q.shading_normals, p.shading_normals) << name;
        EXPECT_EQ(q.albedo, p.albedo) << name;
    }
    // a package written before the option: no "compression" in its bake block, raw arrays
    nlohmann::json old = nlohmann::json::parse(file_text(dir + "/raw.standin/manifest.json"));
    old["bake"].erase("compression");
    ASSERT_TRUE(write_file_atomic(dir + "/raw.standin/manifest.json", old.dump(1)).is_ok());
    EXPECT_TRUE(read_package(dir + "/raw.standin").is_ok());

    const std::string path = dir + "/damaged.standin";
    const std::string normals(reinterpret_cast<const char*>(p.shading_normals.data()), p.shading_normals.size() * 4);
    auto expect_refused = [&](const std::string& bytes, const std::string& problem) {
        fs::remove_all(path);
        ASSERT_TRUE(write_package(*gz, path).is_ok());
        ASSERT_TRUE(write_file_atomic(path + "/normal.bin.gz", bytes).is_ok());
        nlohmann::json m = gz_manifest;
        m["files"]["normal.bin.gz"] = {{"bytes", bytes.size()}, {"fnv1a64", hex64(hash_bytes(bytes))}};
        ASSERT_TRUE(write_file_atomic(path + "/manifest.json", m.dump(1)).is_ok());
        Result<std::unique_ptr<Package>> bad = read_package(path);
        ASSERT_FALSE(bad.is_ok()) << problem;
        EXPECT_EQ(bad.status().code(), StatusCode::bad_data);
        EXPECT_NE(bad.status().message().find("normal.bin.gz"), std::string::npos) << bad.status().message();
        EXPECT_NE(bad.status().message().find(problem), std::string::npos) << bad.status().message();
    };
    const std::string whole = manifest_io::gzip_bytes(normals);
    expect_refused(manifest_io::gzip_bytes(normals.substr(4)), "inflates to " + std::to_string(normals.size() - 4));
    expect_refused(manifest_io::gzip_bytes(normals + "more"), "more than the " + std::to_string(normals.size()));
    expect_refused(whole.substr(0, whole.size() / 2), "not a complete gzip stream");
    expect_refused(whole + whole, "bytes after its gzip stream");
    expect_refused(normals, "not a complete gzip stream"); // raw bytes under a .gz name
}

TEST(DisplacedMeshPackage, OptionsTheBakerCannotTakeAreRefused)
{
    Mesh mesh = small_sphere();
    SourceInfo source;
    const Representation& r = *find_representation("displaced-mesh");
    for (auto [name, value] : std::vector<std::pair<std::string, std::string>>{
             {"degree", "12"}, {"degree", "65"}, {"interpolation-rays", "5"}, {"elevation-bits", "24"},
             {"cone-angle", "0"}, {"sampler", "nearest"}, {"resolution", "512"}}) {
        OptionValues values;
        values.set(name, value);
        Result<std::unique_ptr<Package>> baked = bake_package(r, mesh, source, values, {}, 1);
        ASSERT_FALSE(baked.is_ok()) << name << " " << value;
        EXPECT_EQ(baked.status().code(), StatusCode::invalid_argument);
        EXPECT_NE(baked.status().message().find(name), std::string::npos) << baked.status().message();
    }
}

} // namespace
} // namespace standin::displaced_mesh
