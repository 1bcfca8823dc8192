// Enhanced-billboards packages on disk: round trip, byte-identical writes, refusal of damaged
// packages with errors naming the file and field, and the `standin bake` / `standin info` commands.
#include "reps/enhanced_billboards/billboards.h"
#include "reps/common/surface_image.h"

#include "../../../tests/test_support.h"

#include <standin/assembly.h>
#include <standin/files.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace standin::billboards {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<EnhancedBillboardsPackage> baked_sphere(const std::map<std::string, std::string>& options = {})
{
    GenerateOptions generate;
    generate.shape = GeneratedShape::noisy_sphere;
    generate.target_triangles = 4000;
    Result<Mesh> mesh = generate_mesh(generate);
    EXPECT_TRUE(mesh);
    Result<SourceInfo> source = describe_source("", *mesh);
    OptionValues parameters;
    parameters.set("compression", "none"); // exact round trips; BcPackagesRoundTrip tests "bc"
    for (const auto& [k, v] : options) parameters.set(k, v);
    Result<std::unique_ptr<Package>> result = bake_package(registration(), *mesh, *source, parameters);
    EXPECT_TRUE(result) << result.status().message();
    return std::unique_ptr<EnhancedBillboardsPackage>(static_cast<EnhancedBillboardsPackage*>(result->release()));
}

std::map<std::string, std::string> directory_bytes(const std::string& directory)
{
    std::map<std::string, std::string> out;
    for (const auto& entry : fs::directory_iterator(directory)) out[entry.path().filename().string()] = *read_file(entry.path().string());
    return out;
}

nlohmann::json read_manifest(const std::string& directory)
{
    return nlohmann::json::parse(*read_file(directory + "/manifest.json"));
}

void write_manifest(const std::string& directory, const nlohmann::json& manifest)
{
    ASSERT_TRUE(write_file_atomic(directory + "/manifest.json", manifest.dump(2)));
}

// Reading fails, with a message containing `needle`.
void expect_refused(const std::string& directory, const std::string& needle)
{
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_FALSE(read);
    EXPECT_NE(read.status().message().find(needle), std::string::npos) << read.status().message();
}

// The generated assembly's default bake (PNG maps): open sheets or closed parts. Null if it fails.
std::unique_ptr<Package> baked_assembly(bool sheets)
{
    Result<Mesh> mesh = generate_assembly(3000, 1.0f, sheets);
    EXPECT_TRUE(mesh) << mesh.status().message();
    if (!mesh) return nullptr;
    Result<SourceInfo> source = describe_source("", *mesh);
    OptionValues parameters;
    parameters.set("compression", "none");
    Result<std::unique_ptr<Package>> baked = bake_package(registration(), *mesh, *source, parameters);
    EXPECT_TRUE(baked) << baked.status().message();
    return baked ? std::move(*baked) : nullptr;
}

TEST(BillboardPackage, RoundTripKeepsEverything)
{
    auto baked = baked_sphere();
    std::string directory = test::fresh_directory("billboard_round_trip") + "/sphere.standin";
    ASSERT_TRUE(write_package(*baked, directory));
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    const auto& p = static_cast<const EnhancedBillboardsPackage&>(**read);
    ASSERT_EQ(p.billboards.size(), baked->billboards.size());
    for (std::size_t k = 0; k < p.billboards.size(); ++k) {
        const Billboard &a = p.billboards[k], &b = baked->billboards[k];
        EXPECT_EQ(a.origin, b.origin);
        EXPECT_EQ(a.axis_u, b.axis_u);
        EXPECT_EQ(a.direction, b.direction);
        EXPECT_EQ(a.texel_size, b.texel_size);
        EXPECT_EQ(a.depth_range, b.depth_range);
        EXPECT_EQ(a.color.pixels, b.color.pixels);
        EXPECT_EQ(a.normal_depth.pixels, b.normal_depth.pixels);
        EXPECT_EQ(a.captured_faces, b.captured_faces);
    }
    EXPECT_EQ(p.area_captured, baked->area_captured);
    EXPECT_EQ(p.faces_total, baked->faces_total);
    EXPECT_EQ(p.coarse_mesh.triangle_count(), baked->coarse_mesh.triangle_count());
    EXPECT_GT(p.package_bytes, 0u);
    nlohmann::json summary = summarise_package(p).details;
    for (const char* key : {"representation", "billboards", "faces_total", "area_captured_fraction", "area_left_fraction", "package_bytes"})
        EXPECT_TRUE(summary.contains(key)) << key;
    EXPECT_EQ(summary["representation"], "enhanced-billboards");
}

// Packages from before --sheet-edges (no bake.sheet_edges) read as centre-covered, from before
// --back-hits (no bake.back_hits) as showing back hits, as they were baked and drawn, and from before
// --face-assignment as the greedy's first billboard.
TEST(BillboardPackage, PackagesFromBeforeSheetEdgesAreRead)
{
    auto baked = baked_sphere();
    std::string directory = test::fresh_directory("billboard_no_sheet_edges") + "/sphere.standin";
    ASSERT_TRUE(write_package(*baked, directory));
    nlohmann::json manifest = read_manifest(directory);
    ASSERT_EQ(manifest["bake"]["sheet_edges"], "clip"); // what auto resolves to
    ASSERT_EQ(manifest["bake"]["back_hits"], "show");
    ASSERT_EQ(manifest["bake"]["face_assignment"], "first");
    manifest["bake"].erase("sheet_edges");
    manifest["bake"].erase("back_hits");
    manifest["bake"].erase("face_assignment");
    write_manifest(directory, manifest);
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    EXPECT_EQ(static_cast<const EnhancedBillboardsPackage&>(**read).settings.sheet_edges, "centre");
    EXPECT_EQ(static_cast<const EnhancedBillboardsPackage&>(**read).settings.back_hits, "show");
    EXPECT_EQ(static_cast<const EnhancedBillboardsPackage&>(**read).settings.face_assignment, "first");
}

// Sheet rims (issue #17): a model with open opaque parts gets coarse_mesh.rims (the renderer fills
// rim holes with the coarse triangles along open boundaries); closed models' manifests do not
// change; the flag survives the round trip, and a flag that is not a boolean is refused.
TEST(BillboardPackage, SheetPackagesMarkTheirCoarseRims)
{
    auto sphere = baked_sphere();
    EXPECT_FALSE(sphere->coarse_rims);
    std::string base = test::fresh_directory("billboard_coarse_rims");
    ASSERT_TRUE(write_package(*sphere, base + "/sphere.standin"));
    EXPECT_FALSE(read_manifest(base + "/sphere.standin")["coarse_mesh"].contains("rims"));

    std::unique_ptr<Package> baked = baked_assembly(true);
    ASSERT_TRUE(baked);
    const auto& sheet = static_cast<const EnhancedBillboardsPackage&>(*baked);
    EXPECT_TRUE(sheet.coarse_rims);
    std::string directory = base + "/sheet.standin";
    ASSERT_TRUE(write_package(sheet, directory));
    nlohmann::json manifest = read_manifest(directory);
    EXPECT_EQ(manifest["coarse_mesh"]["rims"], true);
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    EXPECT_TRUE(static_cast<const EnhancedBillboardsPackage&>(**read).coarse_rims);
    manifest["coarse_mesh"]["rims"] = "yes";
    write_manifest(directory, manifest);
    expect_refused(directory, "coarse_mesh.rims");
}

// One closed surface (--cull-back-proxies auto): the bake marks the noisy sphere, not an assembly
// of closed parts; the mark survives the round trip, is absent where false (other packages keep
// their bytes), and a mark that is not a boolean is refused.
TEST(BillboardPackage, OneClosedSurfaceIsMarkedAndReadBack)
{
    auto sphere = baked_sphere();
    EXPECT_TRUE(sphere->one_closed_surface);
    std::string base = test::fresh_directory("billboard_closed_surface");
    std::string directory = base + "/sphere.standin";
    ASSERT_TRUE(write_package(*sphere, directory));
    nlohmann::json manifest = read_manifest(directory);
    EXPECT_EQ(manifest["one_closed_surface"], true);
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    EXPECT_TRUE(static_cast<const EnhancedBillboardsPackage&>(**read).one_closed_surface);
    manifest.erase("one_closed_surface"); // as written before it
    write_manifest(directory, manifest);
    read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    EXPECT_FALSE(static_cast<const EnhancedBillboardsPackage&>(**read).one_closed_surface);
    manifest["one_closed_surface"] = 1;
    write_manifest(directory, manifest);
    expect_refused(directory, "one_closed_surface");
    // the mark of one part whose backs face its inside (bake.cpp backs_unseen) the same way
    manifest.erase("one_closed_surface");
    manifest["backs_unseen"] = true;
    write_manifest(directory, manifest);
    read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    EXPECT_TRUE(static_cast<const EnhancedBillboardsPackage&>(**read).backs_unseen);
    ASSERT_TRUE(write_package(**read, base + "/again.standin"));
    EXPECT_EQ(read_manifest(base + "/again.standin")["backs_unseen"], true);
    manifest["backs_unseen"] = "yes";
    write_manifest(directory, manifest);
    expect_refused(directory, "backs_unseen");

    std::unique_ptr<Package> assembly = baked_assembly(false); // closed parts
    ASSERT_TRUE(assembly);
    EXPECT_FALSE(static_cast<const EnhancedBillboardsPackage&>(*assembly).one_closed_surface);
    ASSERT_TRUE(write_package(*assembly, base + "/assembly.standin"));
    EXPECT_FALSE(read_manifest(base + "/assembly.standin").contains("one_closed_surface"));
    EXPECT_FALSE(read_manifest(base + "/assembly.standin").contains("backs_unseen"));
}

// Sheet edge lines (issue #17): the default bake of a sheet model records sheet_edges "clip" (as a
// closed model's does since outline lines), its rim texels hold line codes 128-254 in the colour
// alpha, and both packagings give those codes back exactly.
TEST(BillboardPackage, SheetEdgeLinesRoundTripInBothPackagings)
{
    EXPECT_EQ(baked_sphere()->settings.sheet_edges, "clip");
    Result<Mesh> mesh = generate_assembly(3000, 1.0f, true);
    ASSERT_TRUE(mesh) << mesh.status().message();
    Result<SourceInfo> source = describe_source("", *mesh);
    std::string base = test::fresh_directory("billboard_edge_lines");
    for (const char* compression : {"none", "bc"}) {
        OptionValues parameters;
        parameters.set("compression", compression);
        Result<std::unique_ptr<Package>> baked = bake_package(registration(), *mesh, *source, parameters);
        ASSERT_TRUE(baked) << baked.status().message();
        const auto& sheet = static_cast<const EnhancedBillboardsPackage&>(**baked);
        EXPECT_EQ(sheet.settings.sheet_edges, "clip");
        std::size_t lines = 0;
        for (const Billboard& b : sheet.billboards)
            for (std::size_t k = 0; k < b.color.pixels.size(); k += 4) lines += b.color.pixels[k + 3] >= 128 && b.color.pixels[k + 3] < 255;
        EXPECT_GT(lines, 100u);
        std::string directory = base + "/" + compression + ".standin";
        ASSERT_TRUE(write_package(sheet, directory));
        EXPECT_EQ(read_manifest(directory)["bake"]["sheet_edges"], "clip");
        Result<std::unique_ptr<Package>> read = read_package(directory);
        ASSERT_TRUE(read) << read.status().message();
        const auto& back = static_cast<const EnhancedBillboardsPackage&>(**read);
        ASSERT_EQ(back.billboards.size(), sheet.billboards.size());
        for (std::size_t k = 0; k < sheet.billboards.size(); ++k)
            for (std::size_t p = 3; p < sheet.billboards[k].color.pixels.size(); p += 4)
                ASSERT_EQ(back.billboards[k].color.pixels[p], sheet.billboards[k].color.pixels[p]) << compression << " billboard " << k;
    }
}

// --compression bc: KTX2 maps, coverage and depth exact, normals within BC5's error, smaller.
TEST(BillboardPackage, BcPackagesRoundTrip)
{
    for (const char* bits : {"16", "8"}) {
        auto plain = baked_sphere({{"depth-bits", bits}});
        auto baked = baked_sphere({{"compression", "bc"}, {"depth-bits", bits}});
        std::string base = test::fresh_directory(std::string("billboard_bc") + bits);
        ASSERT_TRUE(write_package(*baked, base + "/bc.standin"));
        ASSERT_TRUE(write_package(*plain, base + "/png.standin"));
        EXPECT_TRUE(fs::exists(base + "/bc.standin/billboard_000_normal.ktx2"));
        EXPECT_FALSE(fs::exists(base + "/bc.standin/billboard_000_normal_depth.png"));
        EXPECT_EQ(read_manifest(base + "/bc.standin")["version"], k_package_format_version_exact_depth);
        EXPECT_EQ(read_manifest(base + "/png.standin")["version"], 1); // older standins still read PNG packages
        Result<std::unique_ptr<Package>> read = read_package(base + "/bc.standin");
        ASSERT_TRUE(read) << read.status().message();
        const auto& p = static_cast<const EnhancedBillboardsPackage&>(**read);
        // (sizes: docs/RESULTS.md "Compressed packages"; at 4k faces bc is not always smaller)
        ASSERT_EQ(p.billboards.size(), baked->billboards.size());
        float worst_normal = 0.0f;
        int worst_color = 0;
        for (std::size_t k = 0; k < p.billboards.size(); ++k) {
            const Billboard &a = p.billboards[k], &b = baked->billboards[k];
            for (std::size_t t = 0; t < a.color.pixels.size() / 4; ++t) {
                ASSERT_EQ(a.color.pixels[t * 4 + 3], b.color.pixels[t * 4 + 3]) << "coverage, texel " << t;
                if (b.color.pixels[t * 4 + 3] == 0) continue;
                ASSERT_EQ(a.normal_depth.pixels[t * 4 + 3], b.normal_depth.pixels[t * 4 + 3]) << "depth, texel " << t;
                for (int c = 0; c < 3; ++c)
                    worst_color = std::max(worst_color, std::abs(int(a.color.pixels[t * 4 + c]) - int(b.color.pixels[t * 4 + c])));
                glm::vec3 na = reps::decode_normal(&a.normal_depth.pixels[t * 4]), nb = glm::normalize(reps::decode_normal(&b.normal_depth.pixels[t * 4]));
                worst_normal = std::max(worst_normal, glm::degrees(std::acos(std::min(glm::dot(glm::normalize(na), nb), 1.0f))));
            }
        }
        EXPECT_LT(worst_normal, 12.0f) << bits;
        EXPECT_EQ(worst_color, 0) << bits; // colour stays PNG
    }
}

// --compression bc stores the coarse mesh compactly (coarse.meshopt); none keeps coarse.ply, which
// format version 1 readers know. A damaged compact file is refused naming it, even when the
// manifest's hash was updated to match.
TEST(BillboardPackage, BcPackagesKeepACompactCoarseMesh)
{
    auto plain = baked_sphere();
    auto baked = baked_sphere({{"compression", "bc"}});
    ASSERT_GT(baked->coarse_mesh.triangle_count(), 0u);
    std::string base = test::fresh_directory("billboard_compact_coarse");
    ASSERT_TRUE(write_package(*baked, base + "/bc.standin"));
    ASSERT_TRUE(write_package(*plain, base + "/png.standin"));
    EXPECT_TRUE(fs::exists(base + "/png.standin/coarse.ply"));
    EXPECT_FALSE(fs::exists(base + "/bc.standin/coarse.ply"));
    const std::uint64_t compact = fs::file_size(base + "/bc.standin/coarse.meshopt");
    EXPECT_LT(compact * 4, fs::file_size(base + "/png.standin/coarse.ply"));
    EXPECT_EQ(read_manifest(base + "/bc.standin")["coarse_mesh"]["format"], "meshopt-q16");
    Result<std::unique_ptr<Package>> read = read_package(base + "/bc.standin");
    ASSERT_TRUE(read) << read.status().message();
    const Mesh& coarse = static_cast<const EnhancedBillboardsPackage&>(**read).coarse_mesh;
    EXPECT_EQ(coarse.triangle_count(), baked->coarse_mesh.triangle_count());
    EXPECT_EQ(coarse.vertex_count(), baked->coarse_mesh.vertex_count());
    EXPECT_EQ(coarse.bounds().min, baked->coarse_mesh.bounds().min); // the box's low corner is exact
    EXPECT_LT(glm::length(coarse.bounds().max - baked->coarse_mesh.bounds().max),
              1e-5f * baked->coarse_mesh.bounds().diagonal());

    std::string damaged = base + "/damaged.standin";
    ASSERT_TRUE(write_package(*baked, damaged));
    std::string bytes = *read_file(damaged + "/coarse.meshopt");
    bytes = bytes.substr(0, bytes.size() - 10);
    ASSERT_TRUE(write_file_atomic(damaged + "/coarse.meshopt", bytes));
    nlohmann::json manifest = read_manifest(damaged);
    manifest["files"]["coarse.meshopt"] = {{"bytes", bytes.size()}, {"fnv1a64", hex64(hash_bytes(bytes))}};
    write_manifest(damaged, manifest);
    expect_refused(damaged, "coarse.meshopt: has");

    std::string format = base + "/format.standin";
    ASSERT_TRUE(write_package(*baked, format));
    manifest = read_manifest(format);
    manifest["coarse_mesh"]["format"] = "draco";
    write_manifest(format, manifest);
    expect_refused(format, "coarse_mesh.format");
}

TEST(BillboardPackage, EightBitPackagesRoundTrip)
{
    auto baked = baked_sphere({{"depth-bits", "8"}});
    std::string directory = test::fresh_directory("billboard_8bit") + "/sphere.standin";
    ASSERT_TRUE(write_package(*baked, directory));
    Result<int> bits = png_bit_depth(directory + "/billboard_000_normal_depth.png");
    ASSERT_TRUE(bits);
    EXPECT_EQ(*bits, 8);
    Result<std::unique_ptr<Package>> read = read_package(directory);
    ASSERT_TRUE(read) << read.status().message();
    const auto& p = static_cast<const EnhancedBillboardsPackage&>(**read);
    EXPECT_EQ(p.billboards.at(0).normal_depth.pixels, baked->billboards.at(0).normal_depth.pixels);
}

TEST(BillboardPackage, WritesAreByteIdenticalAcrossThreadCounts)
{
    std::string base = test::fresh_directory("billboard_identical");
    auto a = baked_sphere({{"compression", "bc"}}); // the default, as bake_package below

    ASSERT_TRUE(write_package(*a, base + "/a.standin"));
    std::map<std::string, std::string> first = directory_bytes(base + "/a.standin");
    for (int threads : {1, 2}) {
        GenerateOptions generate;
        generate.shape = GeneratedShape::noisy_sphere;
        generate.target_triangles = 4000;
        Result<Mesh> mesh = generate_mesh(generate);
        Result<SourceInfo> source = describe_source("", *mesh);
        Result<std::unique_ptr<Package>> p = bake_package(registration(), *mesh, *source, {}, {}, threads);
        ASSERT_TRUE(p);
        std::string directory = base + "/t" + std::to_string(threads) + ".standin";
        ASSERT_TRUE(write_package(**p, directory));
        EXPECT_EQ(directory_bytes(directory), first) << threads << " threads";
    }
}

TEST(BillboardPackage, DamagedPackagesAreRefused)
{
    auto baked = baked_sphere({{"coarse-ratio", "0"}});
    std::string base = test::fresh_directory("billboard_damaged");
    auto fresh = [&](const std::string& name) {
        std::string directory = base + "/" + name + ".standin";
        EXPECT_TRUE(write_package(*baked, directory));
        return directory;
    };

    std::string missing = fresh("missing");
    fs::remove(missing + "/billboard_001_color.png");
    expect_refused(missing, "billboard_001_color.png");

    std::string truncated = fresh("truncated");
    std::string bytes = *read_file(truncated + "/billboard_000_normal_depth.png");
    ASSERT_TRUE(write_file_atomic(truncated + "/billboard_000_normal_depth.png", bytes.substr(0, bytes.size() / 2)));
    expect_refused(truncated, "billboard_000_normal_depth.png");

    // a valid PNG of the wrong size, with the manifest's hash updated to match
    std::string resized = fresh("resized");
    ASSERT_TRUE(write_png(ImageRGBA8(3, 3), resized + "/billboard_000_color.png"));
    nlohmann::json manifest = read_manifest(resized);
    std::string png = *read_file(resized + "/billboard_000_color.png");
    manifest["files"]["billboard_000_color.png"] = {{"bytes", png.size()}, {"fnv1a64", hex64(hash_bytes(png))}};
    write_manifest(resized, manifest);
    expect_refused(resized, "3x3");

    std::string bad_json = fresh("bad_json");
    ASSERT_TRUE(write_file_atomic(bad_json + "/manifest.json", "{\"format\": \"standin-package\", "));
    expect_refused(bad_json, "manifest.json");

    std::string future = fresh("future");
    manifest = read_manifest(future);
    manifest["version"] = k_package_format_version + 1;
    write_manifest(future, manifest);
    Result<std::unique_ptr<Package>> read = read_package(future);
    ASSERT_FALSE(read);
    EXPECT_EQ(read.status().code(), StatusCode::unsupported);

    std::string axis = fresh("axis");
    manifest = read_manifest(axis);
    manifest["billboards"][0]["axis_u"] = {2.0, 0.0, 0.0};
    write_manifest(axis, manifest);
    expect_refused(axis, "billboards[0].axis_u");

    std::string field = fresh("field");
    manifest = read_manifest(field);
    manifest["billboards"][1].erase("depth_range");
    write_manifest(field, manifest);
    expect_refused(field, "billboards[1].depth_range");

    std::string nonfinite = fresh("nonfinite");
    manifest = read_manifest(nonfinite);
    manifest["billboards"][0]["texel_size"] = -1.0;
    write_manifest(nonfinite, manifest);
    expect_refused(nonfinite, "billboards[0].texel_size");

    // no billboard and no coarse mesh: a package that draws nothing
    std::string empty = fresh("empty");
    manifest = read_manifest(empty);
    manifest["billboards"] = nlohmann::json::array();
    manifest["coarse_mesh"] = nullptr;
    write_manifest(empty, manifest);
    expect_refused(empty, "draws nothing");
}

TEST(BillboardPackage, BakeAndInfoCommands)
{
    std::string base = test::fresh_directory("billboard_cli");
    ASSERT_EQ(test::run_cli("generate torus -t 5000 -o " + base + "/torus.ply").exit_code, 0);
    test::CommandResult baked = test::run_cli("bake " + base + "/torus.ply -o " + base + "/torus.standin --threads 2");
    ASSERT_EQ(baked.exit_code, 0) << baked.err;
    EXPECT_NE(baked.err.find("billboards"), std::string::npos) << baked.err;
    test::CommandResult info = test::run_cli("info " + base + "/torus.standin --json");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    nlohmann::json summary = nlohmann::json::parse(info.out);
    EXPECT_EQ(summary["representation"], "enhanced-billboards");
    EXPECT_GE(summary["area_captured_fraction"].get<double>(), 0.99);
    EXPECT_GT(summary["package_bytes"].get<std::uint64_t>(), 0u);
    EXPECT_TRUE(summary["area_left_fraction"].is_object());

    // bad options: exit 2, the option named, nothing written
    test::CommandResult bad = test::run_cli("bake " + base + "/torus.ply -o " + base + "/bad.standin --resolution 0");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--resolution"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(base + "/bad.standin"));
    bad = test::run_cli("bake " + base + "/missing.ply -o " + base + "/bad.standin");
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_FALSE(fs::exists(base + "/bad.standin"));
}

} // namespace
} // namespace standin::billboards
