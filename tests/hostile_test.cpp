// Hostile input as issue #15 found it: files and packages from strangers, absurd options, outputs
// aimed at inputs. Each case is made here (no large files in the repository) and must end the way
// the CLI promises: one line naming the file, exit status 2, nothing written, within 5 seconds.
// Cases that must be accepted (valid but unusual files) are in the second table.
#include "test_support.h"

#include <standin/files.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sys/stat.h>

namespace standin {
namespace {

namespace fs = std::filesystem;

void write_bytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

using test::line_count;

// The promise is 5 seconds for a Release build; the sanitizer lane (2-4x slower) scales it with
// STANDIN_TEST_TIME_SCALE.
double seconds_allowed()
{
    const char* scale = std::getenv("STANDIN_TEST_TIME_SCALE");
    double factor = scale ? std::atof(scale) : 1.0;
    return 5.0 * (factor >= 1.0 ? factor : 1.0);
}

// A small enhanced-billboards package made through the CLI once per test process (CPU only).
std::string base_package()
{
    static const std::string package = [] {
        std::string dir = test::fresh_directory("hostile_base");
        EXPECT_EQ(test::run_cli("generate sphere -t 300 -o " + dir + "/sphere.ply").exit_code, 0);
        test::CommandResult bake =
            test::run_cli("bake " + dir + "/sphere.ply -o " + dir + "/sphere.standin --resolution 32 --max-billboards 2");
        EXPECT_EQ(bake.exit_code, 0) << bake.err;
        return dir + "/sphere.standin";
    }();
    return package;
}

std::string copy_package(const std::string& dir, const std::string& name)
{
    std::string copy = dir + "/" + name;
    fs::copy(base_package(), copy, fs::copy_options::recursive);
    return copy;
}

nlohmann::json read_manifest(const std::string& package) { return nlohmann::json::parse(*read_file(package + "/manifest.json")); }
void write_manifest(const std::string& package, const nlohmann::json& manifest)
{
    write_bytes(package + "/manifest.json", manifest.dump(2));
}

// A binary PLY: `faces` polygons of `corners` corners each over a ring of `corners` vertices.
std::string polygon_ply(int faces, int corners)
{
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(corners) +
                       "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
                       "\nproperty list ushort uint vertex_indices\nend_header\n";
    for (int i = 0; i < corners; ++i) {
        float p[3] = {std::cos(6.2831853f * float(i) / float(corners)), std::sin(6.2831853f * float(i) / float(corners)), 0.0f};
        text.append(reinterpret_cast<const char*>(p), sizeof p);
    }
    for (int f = 0; f < faces; ++f) {
        std::uint16_t n = std::uint16_t(corners);
        text.append(reinterpret_cast<const char*>(&n), 2);
        for (std::uint32_t i = 0; i < std::uint32_t(corners); ++i) text.append(reinterpret_cast<const char*>(&i), 4);
    }
    return text;
}

// A cone: `n` triangles around one apex (the quadratic-normals case of issue #15).
std::string cone_ply(int n)
{
    std::string text = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n + 1) +
                       "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(n) +
                       "\nproperty list uchar uint vertex_indices\nend_header\n";
    float apex[3] = {0.0f, 1.0f, 0.0f};
    text.append(reinterpret_cast<const char*>(apex), sizeof apex);
    for (int i = 0; i < n; ++i) {
        float p[3] = {std::cos(6.2831853f * float(i) / float(n)), 0.0f, std::sin(6.2831853f * float(i) / float(n))};
        text.append(reinterpret_cast<const char*>(p), sizeof p);
    }
    for (int i = 0; i < n; ++i) {
        std::uint8_t three = 3;
        std::uint32_t corner[3] = {0, std::uint32_t(1 + (i + 1) % n), std::uint32_t(1 + i)};
        text.append(reinterpret_cast<const char*>(&three), 1);
        text.append(reinterpret_cast<const char*>(corner), sizeof corner);
    }
    return text;
}

std::string gltf_with_normals(int positions, int normals)
{
    // the buffer is never read: the accessor counts alone must refuse it
    nlohmann::json doc = {
        {"asset", {{"version", "2.0"}}}, {"scene", 0}, {"scenes", {{{"nodes", {0}}}}}, {"nodes", {{{"mesh", 0}}}},
        {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}, {"NORMAL", 1}}}}}}}}},
        {"buffers", {{{"byteLength", 1024}, {"uri", "missing.bin"}}}},
        {"bufferViews", {{{"buffer", 0}, {"byteLength", 512}}, {{"buffer", 0}, {"byteOffset", 512}, {"byteLength", 512}}}},
        {"accessors",
         {{{"bufferView", 0}, {"componentType", 5126}, {"count", positions}, {"type", "VEC3"}, {"min", {0, 0, 0}}, {"max", {1, 1, 1}}},
          {{"bufferView", 1}, {"componentType", 5126}, {"count", normals}, {"type", "VEC3"}}}}};
    return doc.dump();
}

const char* const k_triangle_obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

struct HostileCase {
    const char* name;
    // makes the files in `dir`; returns the arguments of `standin` and the text the message must hold
    std::function<std::pair<std::string, std::string>(const std::string& dir)> setup;
    const char* environment = ""; // VAR=VALUE prefix
};

const HostileCase k_refused[] = {
    {"FIFO as the model",
     [](const std::string& d) { ::mkfifo((d + "/pipe.ply").c_str(), 0600); return std::pair{"info " + d + "/pipe.ply", std::string("pipe.ply")}; }},
    {"FIFO as an OBJ model (assimp's path)",
     [](const std::string& d) { ::mkfifo((d + "/pipe.obj").c_str(), 0600); return std::pair{"info " + d + "/pipe.obj", std::string("pipe.obj")}; }},
    {"FIFO as a package's manifest",
     [](const std::string& d) {
         std::string p = copy_package(d, "fifo_manifest.standin");
         fs::remove(p + "/manifest.json");
         ::mkfifo((p + "/manifest.json").c_str(), 0600);
         return std::pair{"info " + p, std::string("manifest.json")};
     }},
    {"FIFO as a package's image",
     [](const std::string& d) {
         std::string p = copy_package(d, "fifo_image.standin");
         fs::remove(p + "/billboard_000_color.png");
         ::mkfifo((p + "/billboard_000_color.png").c_str(), 0600);
         return std::pair{"info " + p, std::string("billboard_000_color.png")};
     }},
    {"a folder of packages (a batch bake's output) as the package",
     [](const std::string& d) {
         fs::create_directories(d + "/batch");
         copy_package(d + "/batch", "a.standin");
         copy_package(d + "/batch", "b.standin");
         return std::pair{"render " + d + "/batch -o " + d + "/out.png", std::string("a folder of 2 (a batch bake's output)")};
     }},
    {"an empty folder as the package",
     [](const std::string& d) {
         fs::create_directories(d + "/empty.standin");
         return std::pair{"info " + d + "/empty.standin", std::string("not a package (no manifest.json)")};
     }},
    {"/dev/zero as the model",
     [](const std::string& d) { fs::create_symlink("/dev/zero", d + "/zero.ply"); return std::pair{"info " + d + "/zero.ply", std::string("zero.ply")}; }},
    {"/dev/zero as a manifest",
     [](const std::string& d) {
         std::string p = copy_package(d, "zero.standin");
         fs::remove(p + "/manifest.json");
         fs::create_symlink("/dev/zero", p + "/manifest.json");
         return std::pair{"info " + p, std::string("manifest.json")};
     }},
    {"symlink loop as the model",
     [](const std::string& d) { fs::create_symlink(d + "/loop.obj", d + "/loop.obj"); return std::pair{"render " + d + "/loop.obj -o " + d + "/out.png", std::string("loop.obj")}; }},
    {"symlink loop inside a package",
     [](const std::string& d) {
         std::string p = copy_package(d, "loop.standin");
         fs::remove(p + "/billboard_000_color.png");
         fs::create_symlink("billboard_000_color.png", p + "/billboard_000_color.png");
         return std::pair{"info " + p, std::string("billboard_000_color.png")};
     }},
    {"a file name longer than the system allows",
     [](const std::string& d) { return std::pair{"render " + d + "/" + std::string(300, 'a') + ".obj -o " + d + "/out.png", std::string("aaaa")}; }},
    {"a package name longer than the system allows",
     [](const std::string& d) { return std::pair{"info " + d + "/" + std::string(300, 'b') + ".standin", std::string("bbbb")}; }},
    {"OFF declaring 353 billion vertices (assimp's OutOfMemory.off)",
     [](const std::string& d) {
         write_bytes(d + "/oom.off", "OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n0.5 -0.5 0.5\n-0.5 0.5 0.5\n3 0 1 2\n");
         return std::pair{"info " + d + "/oom.off", std::string("oom.off")};
     }},
    {"PLY faces fanned beyond the triangle budget",
     [](const std::string& d) {
         write_bytes(d + "/fans.ply", polygon_ply(8, 65535));
         return std::pair{"info " + d + "/fans.ply", std::string("STANDIN_MAX_TRIANGLES")};
     },
     "STANDIN_MAX_TRIANGLES=100000"},
    {"a model beyond the memory budget, refused before conversion",
     [](const std::string& d) {
         write_bytes(d + "/cone.ply", cone_ply(20000));
         return std::pair{"bake " + d + "/cone.ply -o " + d + "/cone.standin", std::string("memory budget")};
     },
     "STANDIN_MEMORY_LIMIT=1M"},
    {"PLY element with a huge count and no properties",
     [](const std::string& d) {
         write_bytes(d + "/count.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                       "element junk 999999999999\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
         return std::pair{"info " + d + "/count.ply", std::string("count.ply")};
     }},
    {"glTF whose normals do not match its positions",
     [](const std::string& d) {
         write_bytes(d + "/mismatch.gltf", gltf_with_normals(3, 2));
         return std::pair{"info " + d + "/mismatch.gltf", std::string("mismatch.gltf")};
     }},
    {"huge coordinates",
     [](const std::string& d) {
         write_bytes(d + "/huge.obj", "v 0 0 0\nv 1e30 0 0\nv 0 1e30 0\nf 1 2 3\n");
         return std::pair{"render " + d + "/huge.obj -o " + d + "/out.png", std::string("huge.obj")};
     }},
    {"package bounds with min above max",
     [](const std::string& d) {
         std::string p = copy_package(d, "bounds.standin");
         nlohmann::json m = read_manifest(p);
         m["source"]["bounds"]["min"] = {1, 1, 1};
         m["source"]["bounds"]["max"] = {0, 0, 0};
         write_manifest(p, m);
         return std::pair{"info " + p, std::string("bounds")};
     }},
    {"manifest files key with a path-traversal name, unused",
     [](const std::string& d) {
         std::string p = copy_package(d, "traversal.standin");
         nlohmann::json m = read_manifest(p);
         m["files"]["../../etc/passwd"] = {{"bytes", 1}, {"fnv1a64", "0000000000000000"}};
         write_manifest(p, m);
         return std::pair{"info " + p, std::string("etc/passwd")};
     }},
    {"manifest files key naming a symlink out of the package",
     [](const std::string& d) {
         std::string p = copy_package(d, "link_out.standin");
         fs::create_symlink("/etc/hostname", p + "/extra.txt");
         nlohmann::json m = read_manifest(p);
         m["files"]["extra.txt"] = {{"bytes", 1}, {"fnv1a64", "0000000000000000"}};
         write_manifest(p, m);
         return std::pair{"info " + p, std::string("extra.txt")};
     }},
    {"grey PNG where RGBA is declared (size and hash updated)",
     [](const std::string& d) {
         std::string p = copy_package(d, "grey.standin");
         // a 1x1 8-bit grey PNG
         static const unsigned char grey[] = {0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44, 0x52,
                                              0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x00, 0x00, 0x00, 0x3a, 0x7e, 0x9b,
                                              0x55, 0x00, 0x00, 0x00, 0x0a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60, 0x00, 0x00, 0x00,
                                              0x02, 0x00, 0x01, 0x48, 0xaf, 0xa4, 0x71, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae,
                                              0x42, 0x60, 0x82};
         std::string bytes(reinterpret_cast<const char*>(grey), sizeof grey);
         write_bytes(p + "/billboard_000_color.png", bytes);
         nlohmann::json m = read_manifest(p);
         m["files"]["billboard_000_color.png"] = {{"bytes", bytes.size()}, {"fnv1a64", hex64(hash_bytes(bytes))}};
         write_manifest(p, m);
         return std::pair{"info " + p, std::string("billboard_000_color.png")};
     }},
    {"eval --json over the model",
     [](const std::string& d) {
         write_bytes(d + "/model.obj", k_triangle_obj);
         return std::pair{"eval " + d + "/model.obj " + base_package() + " --json " + d + "/model.obj", std::string("model.obj")};
     }},
    {"eval --json over a package's manifest",
     [](const std::string& d) {
         std::string p = copy_package(d, "json.standin");
         return std::pair{"eval " + test::source_dir() + "/data/bunny.ply " + p + " --json " + p + "/manifest.json", std::string("manifest.json")};
     }},
    {"eval --report into a package",
     [](const std::string& d) {
         std::string p = copy_package(d, "report.standin");
         return std::pair{"eval " + test::source_dir() + "/data/bunny.ply " + p + " --report " + p + "/report", std::string("report.standin")};
     }},
    {"render -o over a package's image",
     [](const std::string& d) {
         std::string p = copy_package(d, "image.standin");
         return std::pair{"render " + p + " -o " + p + "/billboard_000_color.png", std::string("billboard_000_color.png")};
     }},
    {"render -o through a link to the model",
     [](const std::string& d) {
         write_bytes(d + "/linked.obj", k_triangle_obj);
         fs::create_symlink(d + "/linked.obj", d + "/alias.png");
         return std::pair{"render " + d + "/linked.obj -o " + d + "/alias.png", std::string("alias.png")};
     }},
    {"bake -o into a folder that does not exist",
     [](const std::string& d) {
         write_bytes(d + "/model.obj", k_triangle_obj);
         return std::pair{"bake " + d + "/model.obj -o " + d + "/missing/dir/k.standin", std::string("missing")};
     }},
    {"bake -o over the package holding the model",
     [](const std::string& d) {
         std::string p = copy_package(d, "holder.standin");
         write_bytes(p + "/model.obj", k_triangle_obj); // (a bc package's coarse mesh is no model file)
         return std::pair{"bake " + p + "/model.obj -o " + p, std::string("holder.standin")};
     }},
    {"eval --samples -1",
     [](const std::string& d) {
         write_bytes(d + "/model.obj", k_triangle_obj);
         return std::pair{"eval " + d + "/model.obj " + d + "/model.obj --samples -1", std::string("samples")};
     }},
    {"render --size 16384x16384 beyond the memory budget",
     [](const std::string& d) {
         return std::pair{"render " + test::source_dir() + "/data/bunny.ply -o " + d + "/big.png --size 16384x16384", std::string("memory budget")};
     },
     "STANDIN_MEMORY_LIMIT=2G"},
    {"viewer script read from /dev/zero",
     [](const std::string& d) {
         fs::create_symlink("/dev/zero", d + "/zero.script");
         return std::pair{"view " + test::source_dir() + "/data/bunny.ply --script " + d + "/zero.script", std::string("zero.script")};
     }},
    {"a file name holding a newline",
     [](const std::string& d) {
         return std::pair{"info '" + d + "/new\nline.obj'", std::string("new\\nline.obj")};
     }},
};

class Hostile : public ::testing::TestWithParam<int> {};

TEST_P(Hostile, RefusedInOneLineNamingTheFileExitTwoNothingWrittenWithinFiveSeconds)
{
    const HostileCase& c = k_refused[GetParam()];
    std::string dir = test::fresh_directory("hostile_" + std::to_string(GetParam()));
    auto [arguments, expected] = c.setup(dir);
    std::set<std::string> before;
    for (const auto& e : fs::recursive_directory_iterator(dir)) before.insert(e.path().string());

    auto start = std::chrono::steady_clock::now();
    test::CommandResult result = test::run_command(std::string(c.environment) + " timeout 30 " + test::cli_path() + " " + arguments);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    EXPECT_EQ(result.exit_code, 2) << c.name << "\n" << result.err;
    EXPECT_EQ(line_count(result.err), 1) << c.name << ": " << result.err;
    EXPECT_NE(result.err.find(expected), std::string::npos) << c.name << ": " << result.err;
    EXPECT_EQ(result.err.rfind("standin: ", 0), 0u) << c.name << ": " << result.err;
    EXPECT_LT(seconds, seconds_allowed()) << c.name;
    std::set<std::string> after;
    for (const auto& e : fs::recursive_directory_iterator(dir)) after.insert(e.path().string());
    EXPECT_EQ(before, after) << c.name << ": something was written or removed";
}

INSTANTIATE_TEST_SUITE_P(Cases, Hostile, ::testing::Range(0, int(std::size(k_refused))),
                         [](const ::testing::TestParamInfo<int>& info) {
                             std::string name;
                             for (const char* p = k_refused[info.param].name; *p; ++p)
                                 name += std::isalnum(static_cast<unsigned char>(*p)) ? *p : '_';
                             return std::to_string(info.param) + "_" + name.substr(0, 60);
                         });

// Unusual but valid files: accepted, with warnings at most.
TEST(HostileAccepted, UnusualValidFilesAreRead)
{
    std::string dir = test::fresh_directory("hostile_accepted");
    const std::pair<const char*, std::string> cases[] = {
        // Blender 2.4's header line without "comment" (assimp-testmodels' Wuson.ply)
        {"blender.ply", "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: \nelement vertex 3\n"
                        "property float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                        "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"},
        {"float_colours.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "property float red\nproperty float green\nproperty float blue\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n0 0 0 0.5 0.2 1\n1 0 0 1 1 1\n0 1 0 0 0 0\n3 0 1 2\n"},
        {"double_colours_255.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                   "property double red\nproperty double green\nproperty double blue\nproperty int alpha\nelement face 1\n"
                                   "property list uchar int vertex_indices\nend_header\n0 0 0 128 20 255 2147483647\n1 0 0 1 1 1 0\n"
                                   "0 1 0 0 0 0 7\n3 0 1 2\n"},
        {"short_colours.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                              "property ushort red\nproperty ushort green\nproperty ushort blue\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n0 0 0 65535 0 0\n1 0 0 0 65535 0\n0 1 0 0 0 1\n3 0 1 2\n"},
    };
    for (const auto& [name, text] : cases) {
        write_bytes(dir + "/" + name, text);
        test::CommandResult result = test::run_cli("info --json " + dir + "/" + name);
        EXPECT_EQ(result.exit_code, 0) << name << ": " << result.err;
    }
}

TEST(HostileAccepted, VertexNormalsAreLinearInTheMeshSize)
{
    // 200k triangles around one apex took over a minute (quadratic smoothing at one position)
    std::string dir = test::fresh_directory("hostile_cone");
    write_bytes(dir + "/cone.ply", cone_ply(200000));
    auto start = std::chrono::steady_clock::now();
    test::CommandResult result = test::run_cli("info " + dir + "/cone.ply");
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_LT(seconds, seconds_allowed());
}

TEST(HostileAccepted, PolygonsOfManyCornersFinish)
{
    // faces of 65,535 corners fan into 65,533 triangles each: within the default budget, read in time
    std::string dir = test::fresh_directory("hostile_fans");
    write_bytes(dir + "/fans.ply", polygon_ply(4, 65535));
    auto start = std::chrono::steady_clock::now();
    test::CommandResult result = test::run_cli("info " + dir + "/fans.ply");
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_LT(seconds, seconds_allowed());
}

TEST(HostileAccepted, RebakeRemovesTemporariesOfDeadProcessesOnly)
{
    std::string dir = test::fresh_directory("hostile_stale");
    write_bytes(dir + "/model.obj", k_triangle_obj);
    std::string output = dir + "/k.standin";
    // pid 4194303 is above every pid_max Linux allows by default; pid 1 always runs
    fs::create_directories(output + ".tmp4194303_0/inner");
    fs::create_directories(output + ".tmp1_0");
    test::CommandResult result = test::run_cli("bake " + dir + "/model.obj -o " + output + " --resolution 16 --max-billboards 1");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_FALSE(fs::exists(output + ".tmp4194303_0"));
    EXPECT_TRUE(fs::exists(output + ".tmp1_0"));
    EXPECT_TRUE(fs::exists(output + "/manifest.json"));
}

} // namespace
} // namespace standin
