// Evaluation end to end on the GPU (llvmpipe here): the truth against itself scores zero, a
// coarser mesh scores worse than a finer one, a worse package scores worse, the JSON of `standin
// eval` matches a recomputation from the report's saved images, and bench writes its schema.
#include "../../tests/test_support.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/render.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <set>

namespace standin {
namespace {

namespace fs = std::filesystem;

Mesh make_sphere(std::size_t triangles)
{
    GenerateOptions options;
    options.shape = GeneratedShape::noisy_sphere;
    options.target_triangles = triangles;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

Result<EvalResult> run_quick(const Mesh& truth, const Mesh& standin)
{
    auto truth_renderer = make_mesh_renderer(truth);
    auto standin_renderer = make_mesh_renderer(standin);
    EXPECT_TRUE(truth_renderer.is_ok() && standin_renderer.is_ok());
    EvalOptions options;
    options.timed_frames = 1;
    return evaluate(**truth_renderer, **standin_renderer, truth.bounding_sphere(), *make_protocol("quick"), options, {});
}

using test::read_json;

TEST(Evaluate, TruthAgainstItselfHasNoError)
{
    test::gpu_context();
    Mesh mesh = make_sphere(20000);
    Result<EvalResult> result = run_quick(mesh, mesh);
    ASSERT_TRUE(result.is_ok()) << result.status().message();
    ASSERT_EQ(result->views.size(), 4u);
    for (const ViewResult& v : result->views) {
        EXPECT_GT(v.metrics.truth_pixels, 1000u);
        EXPECT_EQ(v.metrics.luv_mean, 0.0);
        EXPECT_EQ(v.metrics.rgb_total, 0.0);
        EXPECT_EQ(v.metrics.iou, 1.0);
        EXPECT_GE(v.standin_wall_ms, 0.0);
    }
}

// Supersampled: pictures at the view's size, silhouettes over samples; the truth still scores zero
// against itself, a mesh a quarter of a pixel off loses about its shifted area, and a truth kept
// for a second stand-in keeps its sample masks.
TEST(Evaluate, SupersampledViewsResolveToTheViewSize)
{
    test::gpu_context();
    Mesh mesh = make_sphere(20000);
    auto truth_renderer = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth_renderer.is_ok());
    EvalOptions options;
    options.timed_frames = 0;
    options.supersample = 4;
    Protocol quick = *make_protocol("quick");
    quick.views.resize(1);
    TruthViews kept;
    std::vector<std::pair<int, int>> sizes;
    ViewSink sink = [&](std::size_t, const ViewResult&, const RenderedImage& t, const RenderedImage& s) {
        sizes.push_back({t.color.width, s.color.height});
        return Status::ok();
    };
    Result<EvalResult> same = evaluate(**truth_renderer, **truth_renderer, mesh.bounding_sphere(), quick, options, {}, sink, &kept);
    ASSERT_TRUE(same.is_ok()) << same.status().message();
    EXPECT_EQ(same->supersample, 4);
    EXPECT_EQ(same->views[0].metrics.luv_mean, 0.0);
    EXPECT_EQ(same->views[0].metrics.iou, 1.0);
    ASSERT_EQ(sizes.size(), 1u);
    EXPECT_EQ(sizes[0], std::make_pair(320, 240));
    ASSERT_EQ(kept.sample_coverage.size(), 1u);
    EXPECT_EQ(kept.sample_coverage[0].size(), 320u * 240u);

    // the sphere moved right by a quarter of a pixel at its centre's depth: each side loses or
    // gains a crescent of about 2 r s pixels, r its radius on screen and s the shift
    const BoundingSphere sphere = mesh.bounding_sphere();
    const double fov = glm::radians(double(quick.views[0].orbit.fov_y_degrees));
    const double distance = sphere.radius / std::sin(fov / 2);
    const double pixel = 2.0 * distance * std::tan(fov / 2) / 240.0;
    Mesh moved = mesh;
    for (glm::vec3& p : moved.positions) p.x += float(0.25 * pixel);
    auto moved_renderer = make_mesh_renderer(moved);
    ASSERT_TRUE(moved_renderer.is_ok());
    Result<EvalResult> shifted = evaluate(**truth_renderer, **moved_renderer, sphere, quick, options, {}, {}, &kept);
    ASSERT_TRUE(shifted.is_ok()) << shifted.status().message();
    const ImageMetrics& m = shifted->views[0].metrics;
    const double radius_px = std::sqrt(double(m.truth_pixels) / 3.14159265);
    const double expected = 2.0 * radius_px * 0.25 / double(m.truth_pixels);
    EXPECT_NEAR(m.hole_fraction, expected, 0.3 * expected) << "radius " << radius_px << " px";
    EXPECT_NEAR(m.spill_fraction, expected, 0.3 * expected);

    // a kept truth serves evaluations of its own samples a pixel only
    TruthViews plain;
    options.supersample = 1;
    ASSERT_TRUE(evaluate(**truth_renderer, **truth_renderer, sphere, quick, options, {}, {}, &plain).is_ok());
    options.supersample = 2;
    EXPECT_FALSE(evaluate(**truth_renderer, **moved_renderer, sphere, quick, options, {}, {}, &plain).is_ok());
    options.supersample = 1;
    EXPECT_FALSE(evaluate(**truth_renderer, **moved_renderer, sphere, quick, options, {}, {}, &kept).is_ok());
    options.supersample = 4;
    EXPECT_TRUE(evaluate(**truth_renderer, **moved_renderer, sphere, quick, options, {}, {}, &kept).is_ok());
    options.supersample = k_max_supersample + 1;
    EXPECT_FALSE(evaluate(**truth_renderer, **moved_renderer, sphere, quick, options, {}).is_ok());
}

// A renderer that counts its draws, to see what an evaluation draws.
class CountingRenderer final : public Renderer {
public:
    explicit CountingRenderer(Renderer& inner) : inner_(inner) {}
    DrawStats draw(const DrawParams& params) override
    {
        ++draws;
        return inner_.draw(params);
    }
    int draws = 0;

private:
    Renderer& inner_;
};

// `standin eval MODEL A B`: the truth's images and times kept (TruthViews) are drawn once, and each
// stand-in scores exactly what it scores alone.
TEST(Evaluate, TruthKeptForSeveralStandinsIsDrawnOnce)
{
    test::gpu_context();
    Mesh truth = make_sphere(20000), finer = make_sphere(5000), coarser = make_sphere(300);
    auto truth_renderer = make_mesh_renderer(truth);
    auto finer_renderer = make_mesh_renderer(finer);
    auto coarser_renderer = make_mesh_renderer(coarser);
    ASSERT_TRUE(truth_renderer.is_ok() && finer_renderer.is_ok() && coarser_renderer.is_ok());
    CountingRenderer counted(**truth_renderer);
    EvalOptions options;
    options.timed_frames = 1;
    const Protocol protocol = *make_protocol("quick");
    TruthViews kept;
    Result<EvalResult> first = evaluate(counted, **finer_renderer, truth.bounding_sphere(), protocol, options, {}, {}, &kept);
    ASSERT_TRUE(first.is_ok()) << first.status().message();
    const int draws = counted.draws;
    EXPECT_GE(draws, 2 * int(protocol.views.size())); // a picture and a timed frame each
    EXPECT_EQ(kept.images.size(), protocol.views.size());
    Result<EvalResult> second = evaluate(counted, **coarser_renderer, truth.bounding_sphere(), protocol, options, {}, {}, &kept);
    ASSERT_TRUE(second.is_ok()) << second.status().message();
    EXPECT_EQ(counted.draws, draws) << "the kept truth is not drawn again";
    Result<EvalResult> alone = evaluate(**truth_renderer, **coarser_renderer, truth.bounding_sphere(), protocol, options, {});
    ASSERT_TRUE(alone.is_ok());
    for (std::size_t i = 0; i < protocol.views.size(); ++i) {
        EXPECT_EQ(second->views[i].metrics.luv_mean, alone->views[i].metrics.luv_mean) << "view " << i;
        EXPECT_EQ(second->views[i].metrics.iou, alone->views[i].metrics.iou) << "view " << i;
        EXPECT_EQ(second->views[i].truth_wall_ms, first->views[i].truth_wall_ms) << "view " << i;
        EXPECT_GT(second->views[i].metrics.luv_mean, first->views[i].metrics.luv_mean) << "view " << i;
    }
}

TEST(Evaluate, CoarserMeshScoresWorse)
{
    test::gpu_context();
    Mesh truth = make_sphere(40000);
    Result<EvalResult> fine = run_quick(truth, make_sphere(5000));
    Result<EvalResult> coarse = run_quick(truth, make_sphere(300));
    ASSERT_TRUE(fine.is_ok() && coarse.is_ok());
    auto luv = [](const ViewResult& v) { return v.metrics.luv_mean; };
    auto iou = [](const ViewResult& v) { return v.metrics.iou; };
    double luv_fine = stats_over_views(*fine, luv).mean, luv_coarse = stats_over_views(*coarse, luv).mean;
    EXPECT_GT(luv_fine, 0.0);
    EXPECT_GT(luv_coarse, luv_fine);
    EXPECT_LT(stats_over_views(*coarse, iou).mean, stats_over_views(*fine, iou).mean);
}

TEST(Evaluate, CliJsonMatchesRecomputationFromSavedImages)
{
    std::string dir = test::fresh_directory("eval_cli");
    ASSERT_TRUE(write_ply(make_sphere(20000), dir + "/truth.ply").is_ok());
    ASSERT_TRUE(write_ply(make_sphere(600), dir + "/coarse.ply").is_ok());
    test::CommandResult r = test::run_cli("eval " + dir + "/truth.ply " + dir + "/coarse.ply --protocol quick --frames 1 --json " +
                                          dir + "/eval.json --report " + dir + "/report");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("report: "), std::string::npos);
    nlohmann::json json = read_json(dir + "/eval.json");
    for (const char* key : {"luv_mean", "luv_max", "de2000_mean", "de2000_p95", "rgb_avg", "rgb_total", "hole_fraction",
                            "spill_fraction", "iou", "psnr"})
        EXPECT_TRUE(json["summary"].contains(key)) << key;
    ASSERT_EQ(json["views"].size(), 4u);
    EXPECT_GT(json["surface"]["mean_rel"].get<double>(), 0.0);

    // every figure again from the PNGs the report saved
    for (std::size_t i = 0; i < 4; ++i) {
        char stem[64];
        std::snprintf(stem, sizeof stem, "/report/images/%03zu", i);
        Result<ImageRGBA8> truth = read_png_rgba8(dir + stem + "_truth.png");
        Result<ImageRGBA8> standin = read_png_rgba8(dir + stem + "_standin.png");
        ASSERT_TRUE(truth.is_ok() && standin.is_ok());
        ImageMetrics m = compare_images(*truth, *standin);
        const nlohmann::json& v = json["views"][i];
        EXPECT_DOUBLE_EQ(v["luv_mean"].get<double>(), m.luv_mean);
        EXPECT_DOUBLE_EQ(v["rgb_total"].get<double>(), m.rgb_total);
        EXPECT_DOUBLE_EQ(v["rgb_avg"].get<double>(), m.rgb_avg);
        EXPECT_DOUBLE_EQ(v["de2000_p95"].get<double>(), m.de2000_p95);
        EXPECT_DOUBLE_EQ(v["iou"].get<double>(), m.iou);
        EXPECT_DOUBLE_EQ(v["psnr"].get<double>(), m.psnr);
        EXPECT_TRUE(fs::exists(dir + stem + "_diff.png"));
    }

    // the page has its tables, charts and triplets; the CSVs are there
    Result<std::string> html = read_file(dir + "/report/index.html");
    ASSERT_TRUE(html.is_ok());
    EXPECT_NE(html->find("<table>"), std::string::npos);
    EXPECT_NE(html->find("images/003_diff.png"), std::string::npos);
    for (const char* csv : {"views.csv", "table_a2.csv", "table_saraiva.csv", "frame_times.csv"})
        EXPECT_TRUE(fs::exists(dir + "/report/" + csv)) << csv;
    // the quick protocol has one image size: its frame times are a table, not a one-point chart
    EXPECT_FALSE(fs::exists(dir + "/report/chart_fps.svg"));
    // the verdict, in the page, the JSON and on the terminal; llvmpipe's times are wall times
    std::string line = json["verdict"]["line"].get<std::string>();
    EXPECT_NE(html->find("<h2>Verdict</h2>"), std::string::npos);
    EXPECT_NE(line.find("at 1x the base distance"), std::string::npos) << line;
    if (json["device"].get<std::string>().find("llvmpipe") != std::string::npos) {
        EXPECT_EQ(json["verdict"]["timing"], "wall");
    }
}

TEST(Evaluate, WorsePackageScoresWorse)
{
    std::string dir = test::fresh_directory("eval_worse");
    std::string bunny = test::source_dir() + "/data/bunny.ply";
    ASSERT_EQ(test::run_cli("bake " + bunny + " -o " + dir + "/good.standin").exit_code, 0);
    ASSERT_EQ(test::run_cli("bake " + bunny + " -o " + dir + "/low.standin --resolution 64").exit_code, 0);
    test::CommandResult good = test::run_cli("eval " + bunny + " " + dir + "/good.standin --frames 0 --json " + dir + "/good.json");
    test::CommandResult bad = test::run_cli("eval " + bunny + " " + dir + "/low.standin --march seed --frames 0 --json " + dir + "/bad.json");
    ASSERT_EQ(good.exit_code, 0) << good.err;
    ASSERT_EQ(bad.exit_code, 0) << bad.err;
    nlohmann::json g = read_json(dir + "/good.json")["summary"], b = read_json(dir + "/bad.json")["summary"];
    EXPECT_GT(b["luv_mean"].get<double>(), g["luv_mean"].get<double>());
    EXPECT_GT(b["de2000_mean"].get<double>(), g["de2000_mean"].get<double>());
    EXPECT_GT(b["rgb_avg"].get<double>(), g["rgb_avg"].get<double>());
    EXPECT_LT(b["psnr"].get<double>(), g["psnr"].get<double>());
}

TEST(Evaluate, CliRefusesBadArguments)
{
    std::string bunny = test::source_dir() + "/data/bunny.ply";
    test::CommandResult r = test::run_cli("eval " + bunny + " " + bunny + " --protocol nope");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("unknown protocol"), std::string::npos);
    EXPECT_EQ(test::run_cli("eval " + bunny + " /no/such.standin").exit_code, 2);
    r = test::run_cli("eval " + bunny + " " + bunny + " --supersample 9");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--supersample"), std::string::npos) << r.err;
}

TEST(Bench, MeshFramesAndCrowd)
{
    test::gpu_context();
    Mesh mesh = make_sphere(2000);
    auto renderer = make_mesh_renderer(mesh);
    ASSERT_TRUE(renderer.is_ok());
    BenchSubjects subjects;
    subjects.mesh = renderer->get();
    BenchOptions options;
    options.frames = 2;
    options.warmup_frames = 1;
    options.resolutions = {{200, 150}};
    options.coverage_distances = {1.0f, 4.0f};
    options.crowd_counts = {1, 16};
    options.crowd_resolution = {200, 150};
    Result<std::vector<FrameRecord>> records = benchmark_frames(subjects, mesh, options, {});
    ASSERT_TRUE(records.is_ok()) << records.status().message();
    ASSERT_EQ(records->size(), 5u);
    EXPECT_GT((*records)[1].covered_pixels, (*records)[2].covered_pixels); // further away covers less
    EXPECT_EQ((*records)[4].instances, 16u);
    EXPECT_GT((*records)[4].primitives, (*records)[3].primitives);
    EXPECT_GT((*records)[4].covered_pixels, 0u);
}

TEST(Bench, CliWritesSchemaForPackages)
{
    std::string dir = test::fresh_directory("bench_cli");
    std::string bunny = test::source_dir() + "/data/bunny.ply";
    ASSERT_EQ(test::run_cli("bake " + bunny + " -o " + dir + "/b.standin --resolution 128").exit_code, 0);
    test::CommandResult r = test::run_cli("bench " + bunny + " " + dir + "/b.standin --frames 1 --warmup 0 --no-coverage "
                                          "--crowd 4 --json " + dir + "/bench.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("device: "), std::string::npos);
    nlohmann::json json = read_json(dir + "/bench.json");
    for (const char* key : {"device", "bake_seconds", "bake_peak_rss_mb", "package_bytes", "source_bytes", "frames", "crowd"})
        EXPECT_TRUE(json.contains(key)) << key;
    EXPECT_GT(json["package_bytes"].get<std::uint64_t>(), 0u);
    std::set<std::string> subjects;
    for (const auto& f : json["frames"]) {
        for (const char* key : {"width", "height", "subject", "instances", "ms_median", "covered_pixels", "fetches_per_pixel"})
            EXPECT_TRUE(f.contains(key)) << key;
        subjects.insert(f["subject"].get<std::string>());
    }
    EXPECT_EQ(subjects, (std::set<std::string>{"package", "package coarse=off", "mesh"}));
    ASSERT_EQ(json["crowd"].size(), 2u); // N = 1 and 4

    // --no-mesh --no-variants: the package's rows alone, so no ratios
    r = test::run_cli("bench " + bunny + " " + dir + "/b.standin --frames 1 --warmup 0 --no-coverage --crowd 4 --no-mesh "
                      "--no-variants --json " + dir + "/bench_no_mesh.json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    json = read_json(dir + "/bench_no_mesh.json");
    subjects.clear();
    for (const auto& f : json["frames"]) subjects.insert(f["subject"].get<std::string>());
    EXPECT_EQ(subjects, (std::set<std::string>{"package"})); // --no-variants: not the billboards without coarse mesh
    EXPECT_TRUE(json["crowd"].empty());
}

} // namespace
} // namespace standin
