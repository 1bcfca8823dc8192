// standin bench: bake time and peak memory, package size vs. the source file (Vichitvejpaisal 2005
// Fig. 4-3), GPU frame times of package and original mesh at its resolutions (Table A-1), vs. screen
// coverage, and in a crowd of N instances (docs/EVAL.md).
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>

namespace standin::cli {

namespace fs = std::filesystem;

struct BenchArgs {
    std::string model;
    std::vector<std::string> packages;
    std::string json;
    std::string keep; // where to keep the package baked with the defaults
    std::string representation = representations().front().name; // the registry's first is the default
    std::vector<std::string> parameters; // NAME=VALUE for the bake
    int frames = 15;
    int warmup = 3;
    std::size_t crowd = 0;
    bool no_coverage = false;
    bool no_mesh = false;
    bool no_variants = false;
    DeclaredOptions render; // the representations' run-time options, as for render and eval
};

struct Measured {
    std::string path;
    std::string representation;
    std::uint64_t bytes = 0;
    std::unique_ptr<Package> package;
};

// Bakes with the given representation's defaults (and --param overrides), measuring time and
// peak memory, and writes the package to measure its size on disk.
static Result<Measured> bake_default(const BenchArgs& args, const Mesh& mesh, const SourceInfo& source,
                                     nlohmann::json& json)
{
    const Representation* representation = find_representation(args.representation);
    if (!representation) return error(StatusCode::invalid_argument, "--representation: unknown '" + args.representation + "'");
    OptionValues parameters;
    for (const std::string& p : args.parameters) {
        std::size_t eq = p.find('=');
        if (eq == std::string::npos || eq == 0)
            return error(StatusCode::invalid_argument, "--param: expected NAME=VALUE, got '" + p + "'");
        parameters.set(p.substr(0, eq), p.substr(eq + 1));
    }
    bool rss_reset = reset_peak_rss();
    double rss_before = peak_rss_mb();
    auto start = std::chrono::steady_clock::now();
    Result<std::unique_ptr<Package>> package = bake_package(*representation, mesh, source, parameters, stderr_progress());
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!package) return package.status();
    json["bake_seconds"] = seconds;
    json["bake_peak_rss_mb"] = peak_rss_mb();
    json["bake_peak_rss_note"] = rss_reset ? "VmHWM reset before the bake" : "process peak (VmHWM could not be reset)";
    json["rss_before_bake_mb"] = rss_before;

    Measured measured;
    measured.representation = args.representation;
    std::string directory = args.keep;
    bool temporary = directory.empty();
    if (temporary) directory = temporary_path_for((fs::temp_directory_path() / "standin-bench.standin").string());
    STANDIN_RETURN_IF_ERROR(write_package(**package, directory));
    Result<std::uint64_t> bytes = package_bytes(directory);
    std::error_code ec;
    if (temporary) fs::remove_all(directory, ec);
    if (!bytes) return bytes.status();
    measured.bytes = *bytes;
    measured.path = temporary ? "(baked with defaults)" : directory;
    measured.package = std::move(*package);
    return measured;
}

static nlohmann::json frame_json(const FrameRecord& r, const std::string& package)
{
    nlohmann::json j = {{"width", r.width},
                        {"height", r.height},
                        {"subject", r.subject},
                        {"scene", r.scene},
                        {"instances", r.instances},
                        {"distance", r.distance_rel},
                        {"ms_median", r.ms_median},
                        {"ms_min", r.ms_min},
                        {"ms_max", r.ms_max},
                        {"wall_ms_median", r.wall_ms_median},
                        {"cpu_ms_median", r.cpu_ms_median},
                        {"covered_pixels", r.covered_pixels},
                        {"primitives", r.primitives}};
    j["fetches_per_pixel"] = r.fetches_per_pixel >= 0.0 ? nlohmann::json(r.fetches_per_pixel) : nlohmann::json(nullptr);
    j["overdraw"] = r.fragments_per_pixel >= 0.0 ? nlohmann::json(r.fragments_per_pixel) : nlohmann::json(nullptr);
    if (r.subject != "mesh") j["package"] = package;
    return j;
}

static void print_frames(const std::vector<FrameRecord>& records)
{
    std::printf("%-8s %-10s %-18s %9s %8s %10s %10s %10s %12s %10s %9s\n", "scene", "size", "subject", "instances", "distance",
                "gpu ms", "wall ms", "cpu ms", "covered px", "fetch/px", "overdraw");
    for (const FrameRecord& r : records) {
        char size[32], fetch[32] = "-", overdraw[32] = "-";
        std::snprintf(size, sizeof size, "%dx%d", r.width, r.height);
        if (r.fetches_per_pixel >= 0.0) std::snprintf(fetch, sizeof fetch, "%.2f", r.fetches_per_pixel);
        if (r.fragments_per_pixel >= 0.0) std::snprintf(overdraw, sizeof overdraw, "%.2f", r.fragments_per_pixel);
        std::printf("%-8s %-10s %-18s %9zu %8g %10.3f %10.3f %10.3f %12zu %10s %9s\n", r.scene.c_str(), size,
                    r.subject.c_str(), r.instances, r.distance_rel, r.ms_median, r.wall_ms_median, r.cpu_ms_median,
                    r.covered_pixels, fetch, overdraw);
    }
}

static int run_bench(BenchArgs& args)
{
    if (args.frames < 1 || args.frames > 10000) return fail("--frames: must be within 1..10000");
    if (args.warmup < 0 || args.warmup > 1000) return fail("--warmup: must be within 0..1000");
    if (args.crowd > 1000000) return fail("--crowd: at most 1000000 instances");

    // the model and the context
    Result<Mesh> mesh = import_mesh(args.model, nullptr, k_isolated_import);
    if (!mesh) return fail(mesh.status());
    Result<SourceInfo> source = describe_source(args.model, *mesh);
    if (!source) return fail(source.status());
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());
    nlohmann::json json = {{"format", "standin-bench"},
                           {"version", 1},
                           {"device", (*context)->device_name()},
                           {"gl_version", (*context)->version()},
                           {"model", args.model},
                           {"source_bytes", source->file_bytes},
                           {"triangles", mesh->triangle_count()},
                           {"bake_seconds", nullptr},
                           {"bake_peak_rss_mb", nullptr}};
    std::printf("device: %s\n", (*context)->device_name().c_str());

    // the packages: baked here with the defaults, or read
    std::vector<Measured> measured;
    if (args.packages.empty()) {
        Result<Measured> baked = bake_default(args, *mesh, *source, json);
        if (!baked) return fail(baked.status());
        measured.push_back(std::move(*baked));
        std::printf("bake: %.2f s, peak RSS %.1f MiB\n", json["bake_seconds"].get<double>(),
                    json["bake_peak_rss_mb"].get<double>());
    }
    for (const std::string& path : args.packages) {
        Result<std::unique_ptr<Package>> package = read_package(path);
        if (!package) return fail(package.status());
        Result<std::uint64_t> bytes = package_bytes(path);
        if (!bytes) return fail(bytes.status());
        Measured m;
        m.path = path;
        m.representation = (*package)->representation();
        m.bytes = *bytes;
        m.package = std::move(*package);
        measured.push_back(std::move(m));
    }

    // the run-time options must apply to some package; each package takes those it declares
    RenderOptions render;
    render.values = args.render.given();
    std::vector<const Representation*> at_hand;
    for (const Measured& m : measured) at_hand.push_back(find_representation(m.representation));
    if (Status s = check_render_options_apply(render, at_hand); !s) return fail(s);

    // frame times: the mesh once, each package with its options and its representation's variants
    Result<std::unique_ptr<Renderer>> mesh_renderer = make_mesh_renderer(*mesh);
    if (!mesh_renderer) return fail(mesh_renderer.status());
    BenchOptions options;
    options.frames = args.frames;
    options.warmup_frames = args.warmup;
    if (args.no_coverage) options.coverage_distances.clear();
    for (std::size_t n : {std::size_t(1), std::size_t(100), std::size_t(1000), std::size_t(10000)})
        if (args.crowd > 0 && n < args.crowd) options.crowd_counts.push_back(n);
    if (args.crowd > 0) options.crowd_counts.push_back(args.crowd);
    nlohmann::json packages = nlohmann::json::array(), frames = nlohmann::json::array();
    std::vector<FrameRecord> all;
    for (std::size_t i = 0; i < measured.size(); ++i) {
        const Measured& m = measured[i];
        const Representation& representation = representation_of(*m.package);
        RenderOptions package_options;
        package_options.values = render.values.only(representation.render_options);
        Result<std::unique_ptr<Renderer>> drawn = make_package_renderer(*m.package, package_options);
        if (!drawn) return fail(drawn.status());
        BenchSubjects subjects;
        subjects.package = drawn->get();
        std::vector<std::unique_ptr<Renderer>> variants;
        static const std::vector<OptionValues> no_variants;
        for (const OptionValues& variant : args.no_variants ? no_variants : representation.bench_variants) {
            RenderOptions varied = package_options;
            std::string label = "package";
            for (const auto& [name, value] : variant.items()) {
                varied.values.set(name, value);
                label += " " + name + "=" + value;
            }
            Result<std::unique_ptr<Renderer>> made = make_package_renderer(*m.package, varied);
            if (!made) return fail(made.status());
            variants.push_back(std::move(*made));
            subjects.package_variants.push_back({label, variants.back().get()});
        }
        subjects.mesh = i == 0 && !args.no_mesh ? mesh_renderer->get() : nullptr;
        Result<std::vector<FrameRecord>> records = benchmark_frames(subjects, *mesh, options, stderr_progress());
        if (!records) return fail(records.status());
        for (const FrameRecord& r : *records) frames.push_back(frame_json(r, m.path));
        packages.push_back({{"path", m.path},
                            {"representation", m.representation},
                            {"package_bytes", m.bytes},
                            {"size_ratio", double(m.bytes) / double(std::max<std::uint64_t>(source->file_bytes, 1))}});
        std::printf("package %s (%s): %llu bytes, %.3f x the source file (%llu bytes)\n", m.path.c_str(),
                    m.representation.c_str(), (unsigned long long)m.bytes,
                    double(m.bytes) / double(std::max<std::uint64_t>(source->file_bytes, 1)),
                    (unsigned long long)source->file_bytes);
        all.insert(all.end(), records->begin(), records->end());
    }
    json["package_bytes"] = measured.front().bytes;
    json["packages"] = packages;
    json["frames"] = frames;

    // the crowd ratios: mesh ms / package ms at the same N (first package)
    nlohmann::json crowd = nlohmann::json::array();
    std::map<std::size_t, std::map<std::string, const FrameRecord*>> by_count;
    for (const FrameRecord& r : all)
        if (r.scene == "crowd" && !by_count[r.instances].count(r.subject)) by_count[r.instances][r.subject] = &r;
    auto ratio = [](double a, double b) { return b > 0.0 ? a / b : 0.0; };
    for (const auto& [count, subject] : by_count)
        if (subject.count("mesh") && subject.count("package")) {
            const FrameRecord& p = *subject.at("package");
            const FrameRecord& m = *subject.at("mesh");
            crowd.push_back({{"instances", count},
                             {"package_ms", p.ms_median},
                             {"mesh_ms", m.ms_median},
                             {"mesh_over_package", ratio(m.ms_median, p.ms_median)},
                             {"package_wall_ms", p.wall_ms_median},
                             {"mesh_wall_ms", m.wall_ms_median},
                             {"mesh_over_package_wall", ratio(m.wall_ms_median, p.wall_ms_median)},
                             {"package_cpu_ms", p.cpu_ms_median},
                             {"mesh_cpu_ms", m.cpu_ms_median},
                             {"mesh_over_package_cpu", ratio(m.cpu_ms_median, p.cpu_ms_median)}});
        }
    json["crowd"] = crowd;

    print_frames(all);
    for (const auto& c : crowd)
        std::printf("crowd %6zu: package %.3f ms, mesh %.3f ms, mesh/package %.2f (wall: %.3f / %.3f ms, %.2f; cpu: %.3f / "
                    "%.3f ms, %.2f)\n",
                    c["instances"].get<std::size_t>(), c["package_ms"].get<double>(), c["mesh_ms"].get<double>(),
                    c["mesh_over_package"].get<double>(), c["package_wall_ms"].get<double>(),
                    c["mesh_wall_ms"].get<double>(), c["mesh_over_package_wall"].get<double>(),
                    c["package_cpu_ms"].get<double>(), c["mesh_cpu_ms"].get<double>(),
                    c["mesh_over_package_cpu"].get<double>());
    if ((*context)->device_name().find("llvmpipe") != std::string::npos)
        std::printf("note: llvmpipe (software rendering): compare these figures as ratios only; cpu ms (the process's CPU "
                    "time, rasteriser threads included) does not grow with other load on the machine, wall ms does\n");
    if (!args.json.empty())
        if (Status s = write_file_atomic(args.json, json.dump(2) + "\n"); !s) return fail(s);
    return k_exit_ok;
}

CommandRun add_bench_command(CLI::App& root)
{
    auto args = std::make_shared<BenchArgs>();
    CLI::App* command = root.add_subcommand(
        "bench", "Measure bake time and peak memory, package size vs. the source file, and GPU frame times of "
                 "stand-in and original mesh at 800x600/400x300/200x150, vs. coverage, and in a crowd");
    command->add_option("model", args->model, "The original model file")->required();
    command->add_option("packages", args->packages,
                        "Package directories to measure; none: bake the model with the defaults and measure that");
    command->add_option("--json", args->json, "Write every figure as JSON to this file");
    command->add_option("--frames", args->frames, "Timed frames per measurement (median reported)")->capture_default_str();
    command->add_option("--warmup", args->warmup, "Untimed frames before each measurement")->capture_default_str();
    command->add_option("--crowd", args->crowd,
                        "Also draw crowds of 1, 100, 1000, 10000 instances up to N on a ground grid (0: no crowd)")
        ->capture_default_str();
    command->add_flag("--no-coverage", args->no_coverage, "Skip the frame time vs. distance (coverage) series");
    command->add_flag("--no-mesh", args->no_mesh,
                      "Time the packages only, not the mesh (no mesh/package ratios): to compare packages or render "
                      "options quickly (a crowd of 1000 meshes takes a minute on llvmpipe)");
    std::string variants; // the registry's, as the frames label them
    for (const Representation& r : representations())
        for (const OptionValues& variant : r.bench_variants) {
            variants += (variants.empty() ? "" : "; ") + r.name + ":";
            for (const auto& [name, value] : variant.items()) variants += " " + name + "=" + value;
        }
    command->add_flag("--no-variants", args->no_variants,
                      "Time each package as drawn, not also its representation's comparison variants (" + variants +
                          "), which on a large package can take minutes on llvmpipe");
    command->add_option("--representation", args->representation, "Representation to bake when no package is given")
        ->capture_default_str();
    command->add_option("--param", args->parameters,
                        "Bake parameter NAME=VALUE (repeatable), as 'standin bake --NAME VALUE' takes it");
    command->add_option("--keep", args->keep, "Keep the package baked with the defaults in this directory");
    args->render.add_to(*command, OptionKind::render);
    return [args] { return run_bench(*args); };
}

} // namespace standin::cli
