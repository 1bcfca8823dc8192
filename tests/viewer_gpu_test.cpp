// `standin view` as a person starts it, under Xvfb, driven by a script: its screenshots show the
// model, the stand-in, the split view and the debug views; the overlay shows frame times; the
// window resizes; bad packages, bad scripts and a missing display are refused with one line.
#include "test_support.h"

#include <standin/image.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace standin {
namespace {

namespace fs = std::filesystem;

bool have_xvfb() { return test::run_command("command -v xvfb-run").exit_code == 0; }

std::string write_text(const std::string& path, const std::string& text)
{
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

using test::line_count;

// `standin view ARGS` in a fresh virtual X server (llvmpipe: keep windows small). xvfb-run -a
// starts its search for a free display at 99 in every process, so two test processes started
// together (ctest -j) can race for the same one: each process starts from its own number. The
// X authority file is the test's own (-f): xvfb-run's temporary folder for it once failed to be
// removed under a parallel run, and xvfb-run then exits 5 whatever the viewer returned.
test::CommandResult run_view_under_xvfb(const std::string& arguments)
{
    static int calls = 0;
    std::string first_display = std::to_string(100 + ::getpid() % 800);
    std::string authority = test::fresh_directory("xauth_" + std::to_string(calls++)) + "/Xauthority";
    return test::run_command("xvfb-run -a -n " + first_display + " -f " + authority + " -s '-screen 0 1024x768x24' " +
                             test::cli_path() + " view " + arguments);
}

ImageRGBA8 load(const std::string& path)
{
    Result<ImageRGBA8> image = read_png_rgba8(path);
    EXPECT_TRUE(image.is_ok()) << path << ": " << image.status().message();
    return image ? *image : ImageRGBA8();
}

// pixels whose colour differs clearly from the top-left corner (the background)
double foreground_fraction(const ImageRGBA8& image, int x0, int x1)
{
    if (image.empty()) return 0.0;
    const std::uint8_t* background = image.at(0, 0);
    std::size_t count = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* p = image.at(x, y);
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(p[c]) - int(background[c])) > 24) {
                    ++count;
                    break;
                }
        }
    return double(count) / (double(x1 - x0) * image.height);
}

// mean absolute difference per channel over columns [x0, x1)
double mean_difference(const ImageRGBA8& a, const ImageRGBA8& b, int x0, int x1)
{
    if (a.empty() || a.width != b.width || a.height != b.height) return 1e9;
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = x0; x < x1; ++x)
            for (int c = 0; c < 3; ++c) sum += std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c]));
    return sum / (double(x1 - x0) * a.height * 3);
}

class ViewerUnderXvfb : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        if (!have_xvfb()) return;
        directory_ = test::fresh_directory("viewer_gpu");
        package_ = directory_ + "/bunny.standin";
        test::CommandResult baked = test::run_cli("bake " + model() + " -o " + package_);
        ASSERT_EQ(baked.exit_code, 0) << baked.err;
    }
    void SetUp() override
    {
        if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    }
    static std::string model() { return test::source_dir() + "/data/bunny.ply"; }
    static std::string directory_, package_;
};
std::string ViewerUnderXvfb::directory_, ViewerUnderXvfb::package_;

TEST_F(ViewerUnderXvfb, ScriptedScreenshotsShowModelStandInSplitAndDebugViews)
{
    const std::string d = directory_ + "/";
    std::string script = write_text(d + "views.txt",
                                    "panels off\n"
                                    "overlay off\n"
                                    "camera 30 20 1\n"
                                    "screenshot " + d + "original.png\n"
                                    "show package 1\n"
                                    "screenshot " + d + "package.png\n"
                                    "light 60 25\n"
                                    "screenshot " + d + "lit.png\n"
                                    "shadows on\n"
                                    "screenshot " + d + "shadows.png\n"
                                    "shadows off\n"
                                    "light camera\n"
                                    "split on\n"
                                    "screenshot " + d + "split.png\n"
                                    "split off\n"
                                    "debug normal\n"
                                    "screenshot " + d + "normal.png\n"
                                    "debug parts\n"
                                    "screenshot " + d + "parts.png\n"
                                    "debug fetches\n"
                                    "screenshot " + d + "fetches.png\n"
                                    "debug proxies\n"
                                    "screenshot " + d + "proxies.png\n"
                                    "debug holes\n"
                                    "screenshot " + d + "holes.png\n"
                                    "debug off\n"
                                    "overlay on\n"
                                    "screenshot " + d + "overlay.png\n"
                                    "resolution 200x150\n"
                                    "light 90 10\n"
                                    "screenshot " + d + "low.png\n"
                                    "window 320x240\n"
                                    "wait 1\n"
                                    "screenshot " + d + "resized.png\n"
                                    "quit\n");
    test::CommandResult result =
        run_view_under_xvfb(model() + " " + package_ + " --size 400x300 --script " + script);
    ASSERT_EQ(result.exit_code, 0) << result.err;
    // the log names every screenshot with the frame time (GPU timer query) of what it shows
    EXPECT_NE(result.err.find("overlay.png (400x300, render 400x300; package 1"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("ms GPU"), std::string::npos) << result.err;

    ImageRGBA8 original = load(d + "original.png"), package = load(d + "package.png");
    ASSERT_EQ(original.width, 400);
    ASSERT_EQ(original.height, 300);
    const int w = original.width, half = w / 2;
    // the model and the stand-in both cover a good part of the window, about equally
    double covered_original = foreground_fraction(original, 0, w), covered_package = foreground_fraction(package, 0, w);
    EXPECT_GT(covered_original, 0.05);
    EXPECT_NEAR(covered_package / covered_original, 1.0, 0.25);

    // split: the original on the left, the stand-in on the right (columns near the divider left out)
    ImageRGBA8 split = load(d + "split.png");
    EXPECT_LT(mean_difference(split, original, 0, half - 3), 1.0);
    EXPECT_LT(mean_difference(split, package, half + 3, w), 1.0);
    EXPECT_GT(foreground_fraction(split, 0, half - 3), 0.02);
    EXPECT_GT(foreground_fraction(split, half + 3, w), 0.02);
    EXPECT_GT(mean_difference(original, package, 0, w), 0.01); // two renderers, two pictures

    // shadows darken parts of the stand-in, and cover the same pixels
    ImageRGBA8 lit = load(d + "lit.png"), shadowed = load(d + "shadows.png");
    EXPECT_GT(mean_difference(lit, shadowed, 0, w), 0.1);
    EXPECT_NEAR(foreground_fraction(shadowed, 0, w), foreground_fraction(lit, 0, w), 0.01);

    // debug views differ from the normal picture, and from one another
    const char* views[] = {"normal", "parts", "fetches", "proxies", "holes"};
    std::vector<ImageRGBA8> debug;
    for (const char* view : views) {
        debug.push_back(load(d + view + ".png"));
        EXPECT_GT(mean_difference(debug.back(), package, 0, w), 2.0) << view;
        EXPECT_GT(foreground_fraction(debug.back(), 0, w), 0.02) << view;
    }
    for (std::size_t i = 0; i < debug.size(); ++i)
        for (std::size_t j = i + 1; j < debug.size(); ++j)
            EXPECT_GT(mean_difference(debug[i], debug[j], 0, w), 1.0) << views[i] << " vs " << views[j];

    // the overlay (frame times) is drawn over the picture
    EXPECT_GT(mean_difference(load(d + "overlay.png"), package, 0, w), 1.0);
    // a lower render resolution, scaled up, still shows the stand-in
    EXPECT_GT(foreground_fraction(load(d + "low.png"), 0, w), 0.05);
    // the window resized
    ImageRGBA8 resized = load(d + "resized.png");
    EXPECT_EQ(resized.width, 320);
    EXPECT_EQ(resized.height, 240);
}

TEST_F(ViewerUnderXvfb, ImpossibleScriptCommandStopsNamingItsLine)
{
    std::string script = write_text(directory_ + "/bad_show.txt", "wait 1\nshow package 3\nquit\n");
    test::CommandResult result = run_view_under_xvfb(model() + " " + package_ + " --size 160x120 --script " + script);
    EXPECT_EQ(result.exit_code, 2);
    EXPECT_NE(result.err.find("bad_show.txt line 2"), std::string::npos) << result.err;
    EXPECT_NE(result.err.find("1 package(s) given"), std::string::npos) << result.err;
}

// these are refused before a window opens, so they need no display
TEST(Viewer, UnknownScriptCommandIsRefusedNamingTheLine)
{
    std::string dir = test::fresh_directory("viewer_bad_script");
    std::string script = write_text(dir + "/s.txt", "camera 0 0 1\n# fine so far\nexplode\n");
    test::CommandResult result = test::run_cli("view " + test::source_dir() + "/data/bunny.ply --script " + script);
    EXPECT_EQ(result.exit_code, 2);
    EXPECT_EQ(line_count(result.err), 1) << result.err;
    EXPECT_NE(result.err.find("s.txt line 3: unknown command 'explode'"), std::string::npos) << result.err;
}

TEST(Viewer, BadPackageIsRefusedWithOneLine)
{
    std::string dir = test::fresh_directory("viewer_bad_package");
    fs::create_directories(dir + "/broken.standin");
    write_text(dir + "/broken.standin/manifest.json", "{\"format\": \"standin-package\", \"version\": 1, ");
    fs::create_directories(dir + "/empty.standin");
    for (const std::string& package : {dir + "/broken.standin", dir + "/empty.standin"}) {
        test::CommandResult result = test::run_cli("view " + test::source_dir() + "/data/bunny.ply " + package);
        EXPECT_EQ(result.exit_code, 2) << package;
        EXPECT_EQ(line_count(result.err), 1) << result.err;
        EXPECT_NE(result.err.find(package), std::string::npos) << result.err;
    }
}

TEST(Viewer, PackageWhoseRendererFailsEndsCleanlyAfterTheWindowCloses)
{
    // issue #15: a lit-only view atlas cannot be drawn with the default style; the early return
    // left the renderers alive after the GL context was gone and libepoxy aborted
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is not installed";
    std::string dir = test::fresh_directory("viewer_lit_atlas");
    test::CommandResult bake = test::run_cli("bake " + test::source_dir() + "/data/bunny.ply -r view-atlas --maps lit "
                                             "--resolution 16 --subdivisions 0 --page-size 256 -o " + dir + "/lit.standin");
    ASSERT_EQ(bake.exit_code, 0) << bake.err;
    std::string script = write_text(dir + "/s.txt", "wait 2\nquit\n");
    test::CommandResult result = run_view_under_xvfb(test::source_dir() + "/data/bunny.ply " + dir + "/lit.standin --script " +
                                                     script + " --size 160x120");
    EXPECT_TRUE(result.exit_code == 0 || result.exit_code == 2) << result.exit_code << ": " << result.err;
    if (result.exit_code == 2) {
        EXPECT_EQ(line_count(result.err), 1) << result.err;
        EXPECT_NE(result.err.find("lit.standin"), std::string::npos) << result.err;
    }
}

TEST(Viewer, MissingDisplaySuggestsRender)
{
    test::CommandResult result =
        test::run_command("env -u DISPLAY " + test::cli_path() + " view " + test::source_dir() + "/data/bunny.ply");
    EXPECT_EQ(result.exit_code, 2);
    EXPECT_EQ(result.err,
              "standin: no display for the viewer (DISPLAY is not set); use 'standin render' for offscreen pictures\n");
}

} // namespace
} // namespace standin
