// The command line as a user meets it: help, info on real files, and bad input refused with one
// line naming the file or option, exit status 2, and no output left behind.
#include "test_support.h"

#include <standin/image.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace standin {
namespace {

namespace fs = std::filesystem;

std::string write_text(const std::string& dir, const std::string& name, const std::string& text)
{
    std::string path = dir + "/" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

using test::line_count;

TEST(Cli, HelpListsTheCommands)
{
    test::CommandResult result = test::run_cli("--help");
    EXPECT_EQ(result.exit_code, 0);
    for (const char* command : {"info", "render", "generate"}) EXPECT_NE(result.out.find(command), std::string::npos) << command;
    test::CommandResult render_help = test::run_cli("render --help");
    EXPECT_EQ(render_help.exit_code, 0);
    EXPECT_NE(render_help.out.find("--azimuth"), std::string::npos);
}

TEST(Cli, InfoJsonOnTheBundledModel)
{
    test::CommandResult result = test::run_cli("info --json " + test::source_dir() + "/data/bunny.ply");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    nlohmann::json info = nlohmann::json::parse(result.out);
    EXPECT_GT(info["triangles"].get<int>(), 1000);
    EXPECT_GT(info["vertices"].get<int>(), 500);
    for (const char* key : {"bounds", "materials", "textures", "warnings"}) EXPECT_TRUE(info.contains(key)) << key;
    EXPECT_EQ(info["bounds"]["min"].size(), 3u);
    EXPECT_EQ(info["bounds"]["max"].size(), 3u);
}

struct BadInput {
    const char* name;
    const char* file_name;
    const char* contents;
    const char* expected_in_message;
};

TEST(Cli, BadModelsAreRefusedWithOneLineNamingTheFile)
{
    std::string dir = test::fresh_directory("cli_bad_models");
    const BadInput cases[] = {
        {"missing", "does_not_exist.obj", nullptr, "does_not_exist.obj"},
        {"unknown format", "model.xyz123", "hello", "model.xyz123"},
        {"corrupt", "corrupt.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 99999\n\x01\x02garbage", "corrupt.ply"},
        {"empty", "empty.obj", "# nothing here\n", "empty.obj"},
        {"nan", "nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n", "nan.obj"},
    };
    for (const BadInput& c : cases) {
        std::string path = dir + "/" + c.file_name;
        if (c.contents) write_text(dir, c.file_name, c.contents);
        std::string output = dir + "/out_" + std::string(c.file_name) + ".png";
        for (const std::string& command : {"info " + path, "render " + path + " -o " + output}) {
            test::CommandResult result = test::run_cli(command);
            EXPECT_EQ(result.exit_code, 2) << c.name << ": " << command;
            EXPECT_EQ(line_count(result.err), 1) << c.name << ": " << result.err;
            EXPECT_NE(result.err.find(c.expected_in_message), std::string::npos) << c.name << ": " << result.err;
            EXPECT_FALSE(fs::exists(output)) << c.name;
        }
    }

    // a file that crashes the third-party parser (src/io/import_isolated_test.cpp says which and why)
    std::string crash = test::source_dir() + "/tests/data/assimp_base64_padding_crash.fbx";
    std::string output = dir + "/out_crash.png";
    for (const std::string& command : {"info " + crash, "render " + crash + " -o " + output}) {
        test::CommandResult result = test::run_cli(command);
        EXPECT_EQ(result.exit_code, 2) << command << ": " << result.err;
        EXPECT_NE(result.err.find("assimp_base64_padding_crash.fbx: the model importer"), std::string::npos) << result.err;
        // under the sanitizer lane (STANDIN_CLI set) the crash comes with AddressSanitizer's report
        if (!std::getenv("STANDIN_CLI")) {
            EXPECT_EQ(line_count(result.err), 1) << result.err;
        }
        EXPECT_FALSE(fs::exists(output));
    }
}

TEST(Cli, AbsurdRenderOptionsAreRefused)
{
    std::string dir = test::fresh_directory("cli_bad_options");
    std::string model = test::source_dir() + "/data/bunny.ply";
    std::string output = dir + "/out.png";
    for (const char* options : {"--size 0x10", "--size banana", "--elevation 91", "--distance -1", "--distance nan",
                                "--fov 0", "--fov 180", "--steps 0", "--fov 40 --ortho"}) {
        test::CommandResult result = test::run_cli("render " + model + " -o " + output + " " + options);
        EXPECT_EQ(result.exit_code, 2) << options;
        EXPECT_EQ(line_count(result.err), 1) << options << ": " << result.err;
        EXPECT_FALSE(fs::exists(output)) << options;
    }
}

TEST(Cli, RenderWritesAPngOfTheRequestedSize)
{
    std::string dir = test::fresh_directory("cli_render");
    std::string output = dir + "/bunny.png";
    test::CommandResult result =
        test::run_cli("render " + test::source_dir() + "/data/bunny.ply -o " + output + " --size 160x120 --azimuth 45");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    Result<ImageRGBA8> image = read_png_rgba8(output);
    ASSERT_TRUE(image.is_ok());
    EXPECT_EQ(image->width, 160);
    EXPECT_EQ(image->height, 120);
    std::size_t covered = 0;
    for (std::size_t i = 3; i < image->pixels.size(); i += 4) covered += image->pixels[i] > 0;
    EXPECT_GT(covered, 160u * 120u / 20) << "the bunny fills a fair part of the view";
    EXPECT_EQ(image->at(0, 0)[3], 0) << "transparent background";
}

// `eval MODEL A B`: several stand-ins compared. Here A is the model itself (a mesh stand-in: the
// truth's own picture) and B a torus: A's figures are exact (Luv 0, IoU 1) and B's are not; the
// sheet holds the truth and both in columns (the quick protocol's 4 views at 320x240, labelled T, 1,
// 2), column 1 the truth's pixels outside its label; each stand-in has its own report; the single-
// stand-in JSON format is unchanged.
TEST(Cli, EvalComparesSeveralStandinsSideBySide)
{
    std::string dir = test::fresh_directory("cli_compare");
    const std::string bunny = test::source_dir() + "/data/bunny.ply", torus = dir + "/torus.ply";
    ASSERT_EQ(test::run_cli("generate torus -t 2000 -o " + torus).exit_code, 0);
    test::CommandResult result = test::run_cli("eval " + bunny + " " + bunny + " " + torus + " --frames 0 --report " + dir +
                                               "/report --json " + dir + "/comparison.json");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.out.find("compared 2 stand-ins"), std::string::npos) << result.out;
    std::ifstream json_file(dir + "/comparison.json");
    nlohmann::json comparison = nlohmann::json::parse(json_file);
    EXPECT_EQ(comparison["format"], "standin-eval-comparison");
    ASSERT_EQ(comparison["standins"].size(), 2u);
    const nlohmann::json& itself = comparison["standins"][0]["eval"]["summary"];
    const nlohmann::json& other = comparison["standins"][1]["eval"]["summary"];
    EXPECT_EQ(itself["luv_mean"].get<double>(), 0.0);
    EXPECT_EQ(itself["iou"].get<double>(), 1.0);
    EXPECT_GT(other["luv_mean"].get<double>(), 1.0);
    EXPECT_LT(other["iou"].get<double>(), 0.9);
    EXPECT_EQ(comparison["standins"][1]["representation"], "mesh");
    EXPECT_EQ(comparison["standins"][1]["bytes"].get<std::uint64_t>(), fs::file_size(torus));
    for (const char* file : {"index.html", "sheet.png", "comparison.json", "01-bunny.ply/index.html",
                             "02-torus.ply/images/003_standin.png"})
        EXPECT_TRUE(fs::exists(dir + "/report/" + file)) << file;
    Result<ImageRGBA8> sheet = read_png_rgba8(dir + "/report/sheet.png");
    ASSERT_TRUE(sheet.is_ok());
    EXPECT_EQ(sheet->width, 3 * 320 + 2 * 4);
    EXPECT_EQ(sheet->height, 4 * 240 + 3 * 4);
    std::size_t differ = 0, model = 0;
    for (int y = 30; y < sheet->height; ++y)
        for (int x = 0; x < 320; ++x) {
            const std::uint8_t *truth = sheet->at(x, y), *same = sheet->at(x + 324, y), *torus_pixel = sheet->at(x + 648, y);
            differ += !std::equal(truth, truth + 3, same);
            model += !std::equal(truth, truth + 3, torus_pixel);
        }
    EXPECT_EQ(differ, 0u) << "the model as its own stand-in draws the truth's pixels";
    EXPECT_GT(model, 10000u) << "the torus is not the bunny";
    // one stand-in: the evaluation's own JSON, as before
    test::CommandResult one = test::run_cli("eval " + bunny + " " + torus + " --frames 0 --json " + dir + "/one.json");
    ASSERT_EQ(one.exit_code, 0) << one.err;
    std::ifstream one_file(dir + "/one.json");
    EXPECT_EQ(nlohmann::json::parse(one_file)["format"], "standin-eval");
    // an output among the inputs is refused
    EXPECT_EQ(test::run_cli("eval " + bunny + " " + bunny + " " + torus + " --frames 0 --json " + torus).exit_code, 2);
    // a render option goes to the packages that declare it: refused where none does, else taken
    const std::string package = dir + "/bunny.standin";
    ASSERT_EQ(test::run_cli("bake " + bunny + " -o " + package + " -q --resolution 64").exit_code, 0);
    test::CommandResult none_declares = test::run_cli("eval " + bunny + " " + bunny + " " + torus + " --frames 0 --march seed");
    EXPECT_EQ(none_declares.exit_code, 2);
    EXPECT_EQ(line_count(none_declares.err), 1u) << none_declares.err;
    test::CommandResult seed = test::run_cli("eval " + bunny + " " + package + " " + torus + " --frames 0 --march seed --json " +
                                             dir + "/seed.json");
    ASSERT_EQ(seed.exit_code, 0) << seed.err;
    test::CommandResult exact = test::run_cli("eval " + bunny + " " + package + " " + torus + " --frames 0 --json " + dir + "/exact.json");
    ASSERT_EQ(exact.exit_code, 0) << exact.err;
    std::ifstream seed_file(dir + "/seed.json"), exact_file(dir + "/exact.json");
    const nlohmann::json seed_json = nlohmann::json::parse(seed_file), exact_json = nlohmann::json::parse(exact_file);
    EXPECT_NE(seed_json["standins"][0]["eval"]["summary"]["luv_mean"], exact_json["standins"][0]["eval"]["summary"]["luv_mean"])
        << "the package drew with the seed's march";
    EXPECT_EQ(seed_json["standins"][1]["eval"]["summary"]["luv_mean"], exact_json["standins"][1]["eval"]["summary"]["luv_mean"]);
}

// `render --fade-to`: the screen-door cross-fade an engine's LOD switch shows. At amount 0 it is the
// input's picture byte for byte; at 0.5 every pixel is the input's or the other's (never a mix),
// about half of those that differ taken from each; a band maps --distance to the amount.
TEST(Cli, RenderCrossFadesToASecondSubject)
{
    std::string dir = test::fresh_directory("cli_fade");
    const std::string bunny = test::source_dir() + "/data/bunny.ply", torus = dir + "/torus.ply";
    ASSERT_EQ(test::run_cli("generate torus -t 2000 -o " + torus).exit_code, 0);
    auto render = [&](const std::string& name, const std::string& options) {
        const std::string output = dir + "/" + name + ".png";
        test::CommandResult result = test::run_cli("render " + bunny + " -o " + output + " --size 192x144 " + options);
        EXPECT_EQ(result.exit_code, 0) << options << ": " << result.err;
        Result<ImageRGBA8> image = read_png_rgba8(output);
        EXPECT_TRUE(image.is_ok()) << options;
        return image.is_ok() ? std::move(*image) : ImageRGBA8{};
    };
    const ImageRGBA8 plain = render("plain", "--distance 2.5");
    const ImageRGBA8 none = render("none", "--distance 2.5 --fade-to " + torus + " --fade 0");
    const ImageRGBA8 all = render("all", "--distance 2.5 --fade-to " + torus + " --fade 1");
    const ImageRGBA8 half = render("half", "--distance 2.5 --fade-to " + torus + " --fade 0.5");
    const ImageRGBA8 band = render("band", "--distance 2.5 --fade-to " + torus + " --fade-band 2:3");
    const ImageRGBA8 before_band = render("before", "--distance 2.5 --fade-to " + torus + " --fade-band 3:4");
    ASSERT_FALSE(plain.pixels.empty());
    EXPECT_EQ(none.pixels, plain.pixels) << "amount 0 draws exactly the input";
    EXPECT_EQ(before_band.pixels, plain.pixels) << "a band beyond the distance has not started";
    EXPECT_EQ(band.pixels, half.pixels) << "2.5 is halfway through 2:3";
    ASSERT_EQ(all.pixels.size(), plain.pixels.size());
    std::size_t differ = 0, from_all = 0, neither = 0;
    for (std::size_t i = 0; i < plain.pixels.size(); i += 4) {
        auto same = [&](const ImageRGBA8& a, const ImageRGBA8& b) {
            return std::equal(a.pixels.begin() + long(i), a.pixels.begin() + long(i) + 4, b.pixels.begin() + long(i));
        };
        if (same(plain, all)) continue;
        ++differ;
        if (same(half, all)) ++from_all;
        else if (!same(half, plain)) ++neither;
    }
    ASSERT_GT(differ, 400u) << "the bunny and the torus cover different pixels";
    EXPECT_EQ(neither, 0u) << "each pixel shows one subject, never a blend";
    EXPECT_NEAR(double(from_all) / double(differ), 0.5, 0.1);

    for (const char* options : {"--fade 0.5", "--fade-band 2:3", "--fade-to MISSING.ply", "--fade-to T --fade 0.5 --fade-band 2:3",
                                "--fade-to T --fade 2", "--fade-to T --fade-band 3:2", "--fade-to T --fade-band 0:1",
                                "--fade-to T --fade-band banana"}) {
        std::string command = options;
        if (std::size_t at = command.find(" T "); at != std::string::npos) command.replace(at + 1, 1, torus);
        if (std::size_t at = command.find("MISSING"); at != std::string::npos) command.replace(at, 7, dir + "/missing");
        test::CommandResult result = test::run_cli("render " + bunny + " -o " + dir + "/bad.png " + command);
        EXPECT_EQ(result.exit_code, 2) << options;
        EXPECT_EQ(line_count(result.err), 1) << options << ": " << result.err;
        EXPECT_FALSE(fs::exists(dir + "/bad.png")) << options;
    }
}

TEST(Cli, GenerateWritesAnImportablePly)
{
    std::string dir = test::fresh_directory("cli_generate");
    std::string output = dir + "/torus.ply";
    test::CommandResult result = test::run_cli("generate torus -t 5000 -o " + output);
    ASSERT_EQ(result.exit_code, 0) << result.err;
    test::CommandResult info = test::run_cli("info --json " + output);
    ASSERT_EQ(info.exit_code, 0) << info.err;
    int triangles = nlohmann::json::parse(info.out)["triangles"].get<int>();
    EXPECT_NEAR(triangles, 5000, 1000);
    EXPECT_EQ(test::run_cli("generate cube -o " + dir + "/x.ply").exit_code, 2);
    EXPECT_EQ(test::run_cli("generate sphere -t 0 -o " + dir + "/y.ply").exit_code, 2);
    EXPECT_FALSE(fs::exists(dir + "/y.ply"));
}

} // namespace
} // namespace standin
