// The experiments of Bauman, Livny & El-Sana (Tables 1-4, Fig. 10, Fig. 11c, §5.3, §5.4) on the
// displaced control mesh. Not a test: prints Markdown tables (docs/RESULTS.md, "Displaced control
// mesh", says which command gave which table).
//   displaced_mesh_tables bake MODEL [--degree 17] [--sampler intersection] [--bits 16] [--control-faces N]
//                              [--threads N] [--write PACKAGE]                        (Tables 1-3: one row)
//   displaced_mesh_tables runtime MODEL PACKAGE [--tau 1,2] [--criterion error] [--size 800x600]
//                              [--frames 3] [--views 14] [--subdivision leb]          (Table 4)
//   displaced_mesh_tables mips MODEL PACKAGE [--distance 2] [--size 400x300]          (Fig. 10)
//   displaced_mesh_tables bend MODEL PACKAGE [--angle 40] [--size 800x600]            (§5.3)
//   displaced_mesh_tables lod MODEL PACKAGE [--tau 1,2] [--size 800x600] [--views 4]  (§5.4)
//   displaced_mesh_tables picture MODEL PACKAGE --out PNG [--debug-view error] [--tau 1] (Fig. 11c)
// Frame times are wall times to glFinish (on llvmpipe only their ratios mean anything); the
// stand-in's counters come from its GPU refinement (one small read-back per draw).
#include "gpu/frame_timing.h"
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/refine.h"
#include "reps/displaced_mesh/renderer.h"
#include "reps/common/ray_scene.h"
#include "reps/displaced_mesh/sample.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <meshoptimizer.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

using namespace standin;
using namespace standin::displaced_mesh;

namespace {

[[noreturn]] void fail(const std::string& message)
{
    std::fprintf(stderr, "displaced_mesh_tables: %s\n", message.c_str());
    std::exit(2);
}

template <typename T>
T take(Result<T> result)
{
    if (!result) fail(result.status().message());
    return std::move(*result);
}

struct Args {
    std::vector<std::string> positional;
    std::map<std::string, std::string> named;
    std::string get(const std::string& name, const std::string& fallback) const
    {
        auto it = named.find(name);
        return it == named.end() ? fallback : it->second;
    }
};

Args parse(int argc, char** argv)
{
    Args args;
    for (int i = 2; i < argc; ++i) {
        std::string a = argv[i];
        if (a.rfind("--", 0) == 0) {
            if (i + 1 >= argc) fail(a + ": needs a value");
            args.named[a.substr(2)] = argv[++i];
        } else {
            args.positional.push_back(a);
        }
    }
    return args;
}

std::vector<float> floats(const std::string& list)
{
    std::vector<float> out;
    std::stringstream in(list);
    std::string item;
    while (std::getline(in, item, ',')) out.push_back(std::stof(item));
    return out;
}

glm::ivec2 size_of(const std::string& text)
{
    int w = 0, h = 0;
    if (std::sscanf(text.c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0) fail("--size: WIDTHxHEIGHT");
    return {w, h};
}

long peak_rss_kib()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::atol(line.c_str() + 6);
    return 0;
}

Mesh load(const std::string& path) { return take(import_mesh(path)); }

const DisplacedMeshPackage& as_displaced(const Package& package)
{
    const auto* p = dynamic_cast<const DisplacedMeshPackage*>(&package);
    if (!p) fail("not a displaced-mesh package");
    return *p;
}

// What most commands open: the model, a GL context and the package.
struct Subject {
    Mesh mesh;
    std::unique_ptr<GpuContext> context;
    std::unique_ptr<Package> loaded;
    const DisplacedMeshPackage* package = nullptr;
};

Subject open_subject(const Args& args, const char* usage, bool gpu = true)
{
    if (args.positional.size() != 2) fail(usage);
    Subject s;
    s.mesh = load(args.positional[0]);
    if (gpu) s.context = take(create_headless_context());
    s.loaded = take(read_package(args.positional[1]));
    s.package = &as_displaced(*s.loaded);
    return s;
}

double wall_ms(Renderer& renderer, const DrawParams& params, int frames)
{
    gpu::FrameTimes times = take(gpu::time_frames(renderer, params, 1, frames));
    return times.wall_median_ms;
}

DrawParams params_for(const Camera& camera, glm::ivec2 size)
{
    DrawParams params;
    params.camera = camera;
    params.light = default_light(camera);
    params.viewport = size;
    return params;
}

Camera view_camera(const Mesh& mesh, glm::vec2 direction, float distance, glm::ivec2 size)
{
    OrbitView view;
    view.azimuth_degrees = direction.x;
    view.elevation_degrees = direction.y;
    view.distance_rel = distance;
    return orbit_camera(mesh.bounding_sphere(), view, float(size.x) / float(size.y));
}

std::vector<glm::vec2> directions(int count)
{
    std::vector<glm::vec2> all = fourteen_directions();
    if (count < int(all.size())) all.resize(std::size_t(std::max(count, 1)));
    return all;
}

RendererSettings render_settings(const Args& args, float tau)
{
    RendererSettings s;
    s.tau = tau;
    if (!parse_criterion(args.get("criterion", "error"), s.criterion)) fail("--criterion: error, weighted, length or seed");
    s.subdivision = args.get("subdivision", "leb");
    s.mip = args.get("mip", "on") == "on";
    s.outline = std::stof(args.get("outline", "2"));
    return s;
}

// ---------------------------------------------------------------------------------------------
// Tables 1-3: one bake, its time, memory, size and distances

int command_bake(const Args& args)
{
    if (args.positional.size() != 1) fail("bake MODEL");
    const std::string model = args.positional[0];
    Options parameters = take(bake_parameters({{"degree", args.get("degree", "17")},
                                               {"sampler", args.get("sampler", "intersection")},
                                               {"elevation-bits", args.get("bits", "16")},
                                               {"control-faces", args.get("control-faces", "0")},
                                               {"interpolation-rays", args.get("interpolation-rays", "16")}}));
    const BakeSettings settings = settings_from(parameters);
    int threads = std::stoi(args.get("threads", "0"));
    std::optional<tbb::global_control> limit;
    if (threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads));

    auto start = std::chrono::steady_clock::now();
    Mesh mesh = load(model);
    double import_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    SourceInfo source = take(describe_source(model, mesh));
    start = std::chrono::steady_clock::now();
    std::unique_ptr<DisplacedMeshPackage> package = take(bake_displaced(mesh, source, parameters, Progress()));
    double bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::uint64_t bytes = 0;
    std::string out = args.get("write", "");
    if (!out.empty()) {
        Status written = write_package(*package, out);
        if (!written) fail(written.message());
        bytes = take(package_bytes(out));
    }
    const SamplingStats& s = package->sampling;
    double diagonal = mesh.bounds().diagonal();
    double edge = 0.0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) edge += std::sqrt(4.0 * mesh.triangle_area(t) / std::sqrt(3.0));
    edge /= double(mesh.triangle_count()); // the mean edge of an equilateral triangle of the mean area
    std::printf("| model | faces | degree | sampler | bits | control faces | reached | import s | bake s | s per M faces | "
                "peak RSS MB | model file MB | package MB | d mean | d mean / diag | d mean / edge | d max / diag | "
                "Ms->M mean / diag | misses |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    std::printf("| %s | %zu | %d | %s | %d | %zu | %s | %.1f | %.1f | %.1f | %.0f | %.1f | %.2f | %.3g | %.3g | %.3f | %.3g | %.3g | %zu |\n",
                std::filesystem::path(model).filename().c_str(), mesh.triangle_count(), settings.degree, settings.sampler.c_str(),
                settings.elevation_bits, package->face_count(), package->control.reached_target ? "yes" : "no", import_s, bake_s,
                bake_s / (double(mesh.triangle_count()) * 1e-6), double(peak_rss_kib()) / 1024.0, double(source.file_bytes) / 1048576.0,
                double(bytes) / 1048576.0, s.original_to_sampled_mean, s.original_to_sampled_mean / diagonal,
                s.original_to_sampled_mean / edge, s.original_to_sampled_max / diagonal, s.sampled_to_original_mean / diagonal,
                s.misses);
    return 0;
}

// ---------------------------------------------------------------------------------------------
// Table 4: tau, measured error, processed and rendered triangles, frame time, culling on and off

int command_runtime(const Args& args)
{
    Subject subject = open_subject(args, "runtime MODEL PACKAGE");
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "800x600"));
    int frames = std::stoi(args.get("frames", "3"));
    std::vector<glm::vec2> views = directions(std::stoi(args.get("views", "14")));
    float distance = std::stof(args.get("distance", "1"));
    std::unique_ptr<Renderer> truth = take(make_mesh_renderer(mesh));

    double truth_ms = 0.0;
    for (glm::vec2 d : views) truth_ms += wall_ms(*truth, params_for(view_camera(mesh, d, distance, size), size), frames) / double(views.size());
    std::printf("%s, %zu control faces, degree %d, %dx%d, distance %.2f, %zu views, mesh: %.1f ms\n\n", package.source.file_name.c_str(),
                package.face_count(), package.settings.degree, size.x, size.y, distance, views.size(), truth_ms);
    std::printf("| tau px | criterion | culling | eps mean px | eps max px | faces visible | processed | rendered | proc/rend | "
                "frame ms | mesh/standin | Luv | IoU | holes |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (float tau : floats(args.get("tau", "1,2")))
        for (bool cull : {true, false}) {
            RendererSettings settings = render_settings(args, tau);
            settings.cull = cull;
            std::unique_ptr<DisplacedRenderer> renderer = take(DisplacedRenderer::create(package, settings));
            double ms = 0.0, eps_mean = 0.0, eps_max = 0.0, luv = 0.0, iou = 0.0, holes = 0.0;
            double visible = 0.0, processed = 0.0, rendered = 0.0;
            for (glm::vec2 d : views) {
                Camera camera = view_camera(mesh, d, distance, size);
                DrawParams params = params_for(camera, size);
                ms += wall_ms(*renderer, params, frames) / double(views.size());
                RefineCounters c = renderer->last_counters();
                visible += double(c.faces_visible) / double(views.size());
                processed += double(c.processed) / double(views.size());
                rendered += double(c.rendered) / double(views.size());
                renderer->set_counting(true);
                RenderedImage image = take(render_offscreen(*renderer, camera, params.light, size.x, size.y));
                ErrorCounters e = renderer->read_error_counters();
                renderer->set_counting(false);
                eps_mean += e.error_mean_px / double(views.size());
                eps_max = std::max(eps_max, e.error_max_px);
                RenderedImage reference = take(render_offscreen(*truth, camera, params.light, size.x, size.y));
                ImageMetrics m = compare_images(reference.color, image.color);
                luv += m.luv_mean / double(views.size());
                iou += m.iou / double(views.size());
                holes += m.hole_fraction / double(views.size());
            }
            std::printf("| %.2g | %s | %s | %.3f | %.2f | %.0f | %.0f | %.0f | %.2f | %.1f | %.2f | %.3f | %.4f | %.4f |\n", tau,
                        (args.get("criterion", "error") + (args.get("criterion", "error") == "error" ? ", outline " + args.get("outline", "2") : "")).c_str(), cull ? "on" : "off", eps_mean, eps_max, visible, processed, rendered,
                        processed / std::max(rendered, 1.0), ms, truth_ms / ms, luv, iou, holes);
        }
    return 0;
}

// ---------------------------------------------------------------------------------------------
// Fig. 10: mip maps on and off: error against the truth and frame-to-frame flicker in an orbit

int command_mips(const Args& args)
{
    Subject subject = open_subject(args, "mips MODEL PACKAGE");
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "400x300"));
    float step = std::stof(args.get("step", "0.5")), span = std::stof(args.get("span", "20"));
    std::unique_ptr<Renderer> truth = take(make_mesh_renderer(mesh));
    std::printf("| distance | tau | mip | Luv vs mesh | PSNR dB | flicker (mean frame-to-frame rgb change) | mesh flicker | excess |\n"
                "|---|---|---|---|---|---|---|---|\n");
    for (float distance : floats(args.get("distance", "1,2,4")))
        for (bool mip : {false, true}) {
            RendererSettings settings = render_settings(args, std::stof(args.get("tau", "1")));
            settings.mip = mip;
            std::unique_ptr<DisplacedRenderer> renderer = take(DisplacedRenderer::create(package, settings));
            ImageRGBA8 previous, previous_truth;
            double change = 0.0, truth_change = 0.0, luv = 0.0, psnr = 0.0;
            int frames = 0, pairs = 0;
            for (float azimuth = 0.0f; azimuth <= span + 1e-3f; azimuth += step, ++frames) {
                Camera camera = view_camera(mesh, {azimuth, 20.0f}, distance, size);
                Light light = default_light(view_camera(mesh, {0.0f, 20.0f}, distance, size)); // fixed light
                RenderedImage a = take(render_offscreen(*renderer, camera, light, size.x, size.y));
                RenderedImage t = take(render_offscreen(*truth, camera, light, size.x, size.y));
                ImageMetrics m = compare_images(t.color, a.color);
                luv += m.luv_mean, psnr += m.psnr;
                if (!previous.empty()) {
                    change += compare_images(previous, a.color).rgb_avg;
                    truth_change += compare_images(previous_truth, t.color).rgb_avg;
                    ++pairs;
                }
                previous = std::move(a.color);
                previous_truth = std::move(t.color);
            }
            std::printf("| %.1f | %s | %s | %.3f | %.2f | %.3f | %.3f | %.3f |\n", distance, args.get("tau", "1").c_str(), mip ? "on" : "off",
                        luv / frames, psnr / frames, change / pairs, truth_change / pairs, change / pairs - truth_change / pairs);
        }
    return 0;
}

// ---------------------------------------------------------------------------------------------
// §5.3: bend the control mesh and the original by the same field

// A bend about the z axis through the bottom of the box: a point turns by `angle` x its height
// fraction (a classic bend deformer); normals are recomputed from the bent faces.
glm::vec3 bend(glm::vec3 p, const Bounds& box, float angle_radians)
{
    float h = std::max(box.extent().y, 1e-6f);
    float t = (p.y - box.min.y) / h;
    float a = angle_radians * t;
    glm::vec2 pivot(box.center().x, box.min.y);
    glm::vec2 d(p.x - pivot.x, p.y - pivot.y);
    glm::vec2 r(std::cos(a) * d.x - std::sin(a) * d.y, std::sin(a) * d.x + std::cos(a) * d.y);
    return {pivot.x + r.x, pivot.y + r.y, p.z};
}

std::vector<glm::vec3> face_normals_mean(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices)
{
    std::vector<glm::dvec3> sum(positions.size(), glm::dvec3(0.0));
    for (std::size_t f = 0; f + 2 < indices.size(); f += 3) {
        glm::dvec3 a(positions[indices[f]]), b(positions[indices[f + 1]]), c(positions[indices[f + 2]]);
        glm::dvec3 n = glm::cross(b - a, c - a);
        for (int k = 0; k < 3; ++k) sum[indices[f + std::size_t(k)]] += n;
    }
    std::vector<glm::vec3> out(positions.size());
    for (std::size_t v = 0; v < out.size(); ++v) out[v] = glm::vec3(glm::normalize(sum[v]));
    return out;
}

int command_bend(const Args& args)
{
    Subject subject = open_subject(args, "bend MODEL PACKAGE");
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "800x600"));
    int frames = std::stoi(args.get("frames", "5"));
    Bounds box = mesh.bounds();
    std::printf("| bend degrees | d(Ms, M) mean / diag | d(Ms, M) max / diag | Luv | IoU | holes | static ms | animated ms | CPU bend ms |\n"
                "|---|---|---|---|---|---|---|---|---|\n");
    for (float degrees : floats(args.get("angle", "0,20,40"))) {
        float angle = glm::radians(degrees);
        // the bent original, and the package's control mesh bent by the same field
        Mesh bent = mesh;
        for (glm::vec3& p : bent.positions) p = bend(p, box, angle);
        compute_smooth_normals(bent);
        std::vector<glm::vec3> control = package.positions;
        for (glm::vec3& p : control) p = bend(p, box, angle);
        std::vector<glm::vec3> normals = face_normals_mean(control, package.indices);

        // geometry: Ms rebuilt over the bent control mesh, against the bent original
        DisplacedMeshPackage copy;
        copy.settings = package.settings;
        copy.positions = control;
        copy.normals = normals;
        copy.indices = package.indices;
        copy.topology = package.topology;
        copy.elevations = package.elevations;
        Mesh ms = sampled_mesh(copy);
        SurfaceDistance d = take(surface_distance(ms, bent, 200000));

        // pictures and frame times, the renderer fed the bent control mesh every frame
        std::unique_ptr<DisplacedRenderer> renderer = take(DisplacedRenderer::create(package, RendererSettings{}));
        std::unique_ptr<Renderer> truth = take(make_mesh_renderer(bent));
        Camera camera = view_camera(mesh, {30.0f, 20.0f}, 1.2f, size);
        DrawParams params = params_for(camera, size);
        double static_ms = wall_ms(*renderer, params, frames);
        Status updated = renderer->update_control(control, normals);
        if (!updated) fail(updated.message());
        RenderedImage a = take(render_offscreen(*renderer, camera, params.light, size.x, size.y));
        RenderedImage t = take(render_offscreen(*truth, camera, params.light, size.x, size.y));
        ImageMetrics m = compare_images(t.color, a.color);
        // animated: every frame bends the rest pose on the CPU, uploads it and draws (§5.3)
        double animated_ms = 0.0, cpu_ms = 0.0;
        for (int f = 0; f < frames; ++f) {
            auto t0 = std::chrono::steady_clock::now();
            std::vector<glm::vec3> moving = package.positions;
            float a = angle * float(f + 1) / float(frames);
            for (glm::vec3& p : moving) p = bend(p, box, a);
            std::vector<glm::vec3> moving_normals = face_normals_mean(moving, package.indices);
            cpu_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() / frames;
            (void)renderer->update_control(moving, moving_normals);
            gpu::FrameTimes times = take(gpu::time_frames(*renderer, params, 0, 1));
            animated_ms += times.wall_median_ms / frames;
        }
        std::printf("| %.0f | %.3g | %.3g | %.3f | %.4f | %.4f | %.1f | %.1f | %.2f |\n", degrees, d.mean_rel, d.max_rel, m.luv_mean, m.iou,
                    m.hole_fraction, static_ms, animated_ms + cpu_ms, cpu_ms);
        if (!args.get("out", "").empty() && degrees > 0.0f) {
            Status w = write_png(a.color, args.get("out", "") + "_" + std::to_string(int(degrees)) + ".png");
            if (!w) fail(w.message());
        }
    }
    return 0;
}

// ---------------------------------------------------------------------------------------------
// §5.4: triangles needed at an equal screen-space error, against a static meshoptimizer LOD

Mesh refined_mesh(const DisplacedMeshPackage& package, const std::vector<FaceRefineData>& faces, const RefineView& view,
                  const RefineOptions& options, RefineStats& stats)
{
    RefineSurface surface{&package.positions, &package.normals, &package.indices, &package.topology, &package.elevations, &faces,
                          package.settings.degree};
    std::vector<RefinedTriangle> triangles = refine(surface, view, options, stats);
    Mesh out;
    for (const RefinedTriangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            out.positions.push_back(displaced_position(surface, t.face, t.q[k][0], t.q[k][1], view, options));
            out.indices.push_back(std::uint32_t(out.positions.size() - 1));
        }
    out.normals.assign(out.positions.size(), glm::vec3(0, 0, 1));
    out.colors.assign(out.positions.size(), glm::vec4(1.0f));
    out.face_materials.assign(out.triangle_count(), 0);
    out.materials.push_back(Material{});
    return out;
}

// The triangles of a mesh facing the eye, as a mesh (what a view shows of a static LOD).
Mesh facing_part(const Mesh& mesh, glm::vec3 eye)
{
    Mesh out = mesh;
    out.indices.clear();
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const std::uint32_t* v = &mesh.indices[3 * t];
        glm::vec3 a = mesh.positions[v[0]], b = mesh.positions[v[1]], c = mesh.positions[v[2]];
        if (glm::dot(glm::cross(b - a, c - a), eye - a) > 0.0f) out.indices.insert(out.indices.end(), {v[0], v[1], v[2]});
    }
    out.face_materials.assign(out.triangle_count(), 0);
    return out;
}

// Screen-space error of a mesh against the original seen by `camera`: points placed on the mesh by
// area (stratified, deterministic), each moved to its closest point on the original; the part of
// that offset across the view direction, in pixels at the point's depth (what shows on screen: an
// offset along the line of sight does not). Mean, 99th percentile and max.
struct ScreenError {
    double mean = 0.0, p99 = 0.0, max = 0.0;
};

ScreenError screen_error(const Mesh& mesh, const RayScene& original, const Camera& camera, int height, std::size_t samples)
{
    std::vector<double> cumulative(mesh.triangle_count());
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) cumulative[t] = total += mesh.triangle_area(t);
    const float pixels_per_unit = float(height) / (2.0f * std::tan(glm::radians(camera.fov_y_degrees) * 0.5f));
    std::vector<double> errors(samples);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
            // a fixed low-discrepancy pattern: the i-th stratum of the area, then (u, v) from i
            double target = (double(i) + 0.5) / double(samples) * total;
            std::size_t t = std::min<std::size_t>(std::size_t(std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin()),
                                                  cumulative.size() - 1);
            float u = float(std::fmod(double(i) * 0.7548776662466927, 1.0)), v = float(std::fmod(double(i) * 0.5698402909980532, 1.0));
            if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
            const std::uint32_t* tri = &mesh.indices[3 * t];
            glm::vec3 p = (1.0f - u - v) * mesh.positions[tri[0]] + u * mesh.positions[tri[1]] + v * mesh.positions[tri[2]];
            glm::vec3 q = original.closest(p, std::numeric_limits<float>::infinity()).position;
            glm::vec3 sight = glm::normalize(p - camera.eye_world);
            glm::vec3 offset = q - p;
            offset -= glm::dot(offset, sight) * sight;
            float depth = glm::dot(p - camera.eye_world, camera.forward_world);
            errors[i] = double(glm::length(offset)) * pixels_per_unit / std::max(depth, camera.near_plane);
        }
    });
    ScreenError out;
    for (double e : errors) out.mean += e / double(samples), out.max = std::max(out.max, e);
    std::sort(errors.begin(), errors.end());
    out.p99 = errors[std::size_t(0.99 * double(samples - 1))];
    return out;
}

// The triangle count at which a sweep of (count, error) pairs reaches `error`, interpolated in
// log-log; -1 when the error lies outside the sweep.
double count_at_error(const std::vector<std::pair<double, double>>& sweep, double error)
{
    for (std::size_t i = 0; i + 1 < sweep.size(); ++i) {
        auto [n0, e0] = sweep[i];
        auto [n1, e1] = sweep[i + 1];
        if (error <= e0 && error >= e1 && e0 > e1) {
            double t = (std::log(e0) - std::log(error)) / (std::log(e0) - std::log(e1));
            return std::exp(std::log(n0) + t * (std::log(n1) - std::log(n0)));
        }
    }
    return -1.0;
}

int command_lod(const Args& args)
{
    Subject subject = open_subject(args, "lod MODEL PACKAGE", false);
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "800x600"));
    std::vector<glm::vec2> views = directions(std::stoi(args.get("views", "4")));
    float distance = std::stof(args.get("distance", "1"));
    std::size_t samples = std::size_t(std::stoul(args.get("samples", "200000")));
    std::vector<FaceRefineData> faces = prepare_faces(package.positions, package.normals, package.indices, package.topology,
                                                      package.layout(), package.elevations, package.face_error);
    const BoundingSphere sphere = mesh.bounding_sphere();
    std::vector<Camera> cameras;
    for (glm::vec2 d : views) cameras.push_back(view_camera(mesh, d, distance, size));
    // pixels per world unit at the model's centre (all views stand at the same distance)
    const float pixels_per_unit = float(size.y) / (2.0f * std::tan(glm::radians(cameras[0].fov_y_degrees) * 0.5f)) /
                                  glm::length(cameras[0].eye_world - sphere.center);

    // the static LODs: meshoptimizer's simplifier at a sweep of targets; per view, the screen-space
    // error of the part facing the eye (what the view shows), mean and 99th percentile, averaged
    std::unique_ptr<RayScene> scene = take(RayScene::create(mesh.positions, mesh.indices));
    std::vector<std::uint32_t> welded(mesh.indices.size());
    meshopt_generateShadowIndexBuffer(welded.data(), mesh.indices.data(), mesh.indices.size(), mesh.positions.data(),
                                      mesh.vertex_count(), sizeof(glm::vec3), sizeof(glm::vec3));
    std::vector<std::pair<double, double>> by_mean, by_max, facing_by_mean, facing_by_max;
    std::printf("%s: %zu faces, %dx%d, distance %.2f (%.0f px per unit at the centre), %zu views\n\nmeshoptimizer LODs "
                "(screen-space error of the part facing the eye, px, averaged over the views):\n\n| triangles | facing the eye | mean error px "
                "| 99th percentile px |\n|---|---|---|---|\n",
                package.source.file_name.c_str(), mesh.triangle_count(), size.x, size.y, distance, pixels_per_unit, views.size());
    for (double fraction : {0.0025, 0.005, 0.01, 0.02, 0.04, 0.08, 0.16, 0.32}) {
        std::vector<std::uint32_t> simplified(welded.size());
        std::size_t count = meshopt_simplify(simplified.data(), welded.data(), welded.size(), &mesh.positions[0].x, mesh.vertex_count(),
                                             sizeof(glm::vec3), std::size_t(double(welded.size()) * fraction) / 3 * 3, 1.0f, 0, nullptr);
        simplified.resize(count);
        Mesh lod = mesh;
        lod.indices = simplified;
        lod.face_materials.assign(lod.triangle_count(), 0);
        double mean = 0.0, max = 0.0, facing = 0.0;
        for (const Camera& camera : cameras) {
            Mesh part = facing_part(lod, camera.eye_world);
            ScreenError e = screen_error(part, *scene, camera, size.y, samples);
            mean += e.mean / double(cameras.size());
            max += e.p99 / double(cameras.size());
            facing += double(part.triangle_count()) / double(cameras.size());
        }
        by_mean.push_back({double(lod.triangle_count()), mean});
        by_max.push_back({double(lod.triangle_count()), max});
        facing_by_mean.push_back({facing, mean});
        facing_by_max.push_back({facing, max});
        std::printf("| %zu | %.0f | %.3f | %.2f |\n", lod.triangle_count(), facing, mean, max);
    }

    std::printf("\nThe displaced mesh (CPU reference of the GPU refinement), and the LOD of equal error:\n\n| tau | rendered | "
                "mean error px | 99th percentile px | LOD at that mean (facing) | LOD at that 99th percentile (facing) | "
                "rendered / LOD by 99th percentile | "
                "rendered / original |\n|---|---|---|---|---|---|---|---|\n");
    auto shown = [](double n) { return n < 0.0 ? std::string("outside the sweep") : std::to_string(std::llround(n)); };
    for (float tau : floats(args.get("tau", "1,2"))) {
        RefineOptions options;
        options.tau = tau;
        options.outline = std::stof(args.get("outline", "2"));
        if (!parse_criterion(args.get("criterion", "error"), options.criterion)) fail("--criterion");
        double rendered = 0.0, mean = 0.0, max = 0.0;
        for (const Camera& camera : cameras) {
            RefineStats stats;
            Mesh ours = refined_mesh(package, faces, make_refine_view(camera, size.y, glm::mat4(1.0f)), options, stats);
            ScreenError e = screen_error(ours, *scene, camera, size.y, samples);
            rendered += double(stats.rendered) / double(cameras.size());
            mean += e.mean / double(cameras.size());
            max += e.p99 / double(cameras.size());
        }
        double lod_mean = count_at_error(by_mean, mean), lod_max = count_at_error(by_max, max);
        double facing_mean = count_at_error(facing_by_mean, mean), facing_max = count_at_error(facing_by_max, max);
        std::printf("| %.2g | %.0f | %.3f | %.2f | %s (%s) | %s (%s) | %s | %.4f |\n", tau, rendered, mean, max, shown(lod_mean).c_str(),
                    shown(facing_mean).c_str(), shown(lod_max).c_str(), shown(facing_max).c_str(),
                    lod_max < 0.0 ? "-" : std::to_string(rendered / lod_max).substr(0, 5).c_str(), rendered / double(mesh.triangle_count()));
    }
    return 0;
}

// ---------------------------------------------------------------------------------------------
// Fig. 11c and friends: one picture with a debug view

int command_picture(const Args& args)
{
    Subject subject = open_subject(args, "picture MODEL PACKAGE --out PNG");
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "800x600"));
    RendererSettings settings = render_settings(args, std::stof(args.get("tau", "1")));
    settings.debug_view = take(parse_debug_view(args.get("debug-view", "")));
    settings.error_scale = std::stof(args.get("error-scale", "0"));
    std::unique_ptr<DisplacedRenderer> renderer = take(DisplacedRenderer::create(package, settings));
    Camera camera = view_camera(mesh, {std::stof(args.get("azimuth", "30")), std::stof(args.get("elevation", "20"))},
                                std::stof(args.get("distance", "1")), size);
    RenderedImage image = take(render_offscreen(*renderer, camera, default_light(camera), size.x, size.y));
    Status written = write_png(image.color, args.get("out", "picture.png"));
    if (!written) fail(written.message());
    RefineCounters c = renderer->last_counters();
    std::printf("%s: %llu rendered, %llu processed, %llu faces visible\n", args.get("out", "picture.png").c_str(),
                (unsigned long long)c.rendered, (unsigned long long)c.processed, (unsigned long long)c.faces_visible);
    return 0;
}

// Frame time of one view, for profiling: the stand-in alone, N frames.
int command_frames(const Args& args)
{
    Subject subject = open_subject(args, "frames MODEL PACKAGE");
    const Mesh& mesh = subject.mesh;
    const DisplacedMeshPackage& package = *subject.package;
    glm::ivec2 size = size_of(args.get("size", "800x600"));
    RendererSettings settings = render_settings(args, std::stof(args.get("tau", "1")));
    settings.debug_view = take(parse_debug_view(args.get("debug-view", "")));
    std::unique_ptr<DisplacedRenderer> renderer = take(DisplacedRenderer::create(package, settings));
    Camera camera = view_camera(mesh, {30.0f, 20.0f}, std::stof(args.get("distance", "1")), size);
    gpu::FrameTimes times = take(gpu::time_frames(*renderer, params_for(camera, size), 2, std::stoi(args.get("frames", "10"))));
    std::printf("wall %.2f ms, gpu %.2f ms, rendered %llu\n", times.wall_median_ms, times.median_ms,
                (unsigned long long)renderer->last_counters().rendered);
    return 0;
}

} // namespace

int main(int argc, char** argv)
{
    if (argc < 2) fail("bake | runtime | mips | bend | lod | picture (see the comment at the top of bench/displaced_mesh_tables.cpp)");
    std::string command = argv[1];
    Args args = parse(argc, argv);
    if (command == "bake") return command_bake(args);
    if (command == "runtime") return command_runtime(args);
    if (command == "mips") return command_mips(args);
    if (command == "bend") return command_bend(args);
    if (command == "lod") return command_lod(args);
    if (command == "picture") return command_picture(args);
    if (command == "frames") return command_frames(args);
    fail("unknown command " + command);
}
