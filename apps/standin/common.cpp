#include "common.h"

#include <standin/files.h>
#include <standin/log.h>

#include <chrono>
#include <filesystem>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <unistd.h>

namespace standin::cli {

int fail(const Status& status) { return fail(status.message()); }

int fail(const std::string& message)
{
    // one line whatever the message holds (a file name with a newline, a library's text)
    std::fprintf(stderr, "standin: %s\n", one_line(message).c_str());
    return k_exit_failure;
}

void add_view_options(CLI::App& command, ViewArgs& args)
{
    command.add_option("--size", args.size, "Image size WIDTHxHEIGHT")->capture_default_str();
    command.add_option("--azimuth", args.azimuth, "Camera azimuth in degrees around +Y (0 looks from +Z)")
        ->capture_default_str();
    command.add_option("--elevation", args.elevation, "Camera elevation in degrees, -90..90")->capture_default_str();
    command.add_option("--distance", args.distance,
                       "Camera distance relative to the base distance radius/sin(fov/2), where the bounding "
                       "sphere just fills the view (Saraiva et al.)")
        ->capture_default_str();
    auto* fov = command.add_option("--fov", args.fov, "Vertical field of view in degrees (perspective)")
                    ->capture_default_str();
    command.add_flag("--ortho", args.ortho, "Orthographic projection instead of perspective")->excludes(fov);
    command.add_option("--light-azimuth", args.light_azimuth,
                       "Light direction azimuth in degrees (default: above-left of the camera)");
    command.add_option("--light-elevation", args.light_elevation, "Light direction elevation in degrees");
}

Status parse_view(const ViewArgs& args, int& width, int& height, OrbitView& view)
{
    char x = 0;
    char rest = 0;
    if (std::sscanf(args.size.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || (x != 'x' && x != 'X'))
        return error(StatusCode::invalid_argument, "--size: expected WIDTHxHEIGHT, got '" + args.size + "'");
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return error(StatusCode::invalid_argument, "--size: " + args.size + " out of range 1x1..16384x16384");
    if (!std::isfinite(args.azimuth)) return error(StatusCode::invalid_argument, "--azimuth: must be a finite number");
    if (!(args.elevation >= -90.0f && args.elevation <= 90.0f))
        return error(StatusCode::invalid_argument, "--elevation: must be within -90..90 degrees");
    if (!(args.distance > 0.0f && args.distance <= 1e4f))
        return error(StatusCode::invalid_argument, "--distance: must be within (0, 10000]");
    if (!(args.fov > 0.5f && args.fov < 179.0f))
        return error(StatusCode::invalid_argument, "--fov: must be within (0.5, 179) degrees");
    bool has_light_az = !std::isnan(args.light_azimuth), has_light_el = !std::isnan(args.light_elevation);
    if (has_light_az != has_light_el)
        return error(StatusCode::invalid_argument, "--light-azimuth and --light-elevation go together");
    if (has_light_az && (!std::isfinite(args.light_azimuth) || !(std::abs(args.light_elevation) <= 90.0f)))
        return error(StatusCode::invalid_argument, "--light-azimuth/--light-elevation: out of range");
    view.azimuth_degrees = args.azimuth;
    view.elevation_degrees = args.elevation;
    view.distance_rel = args.distance;
    view.fov_y_degrees = args.fov;
    view.orthographic = args.ortho;
    return Status::ok();
}

Light light_for(const ViewArgs& args, const Camera& camera)
{
    if (!std::isnan(args.light_azimuth)) return light_from_angles(args.light_azimuth, args.light_elevation);
    return default_light(camera);
}

void add_shadow_options(CLI::App& command, ShadowArgs& args)
{
    command.add_flag("--shadows", args.enabled,
                     "Cast shadows: the same renderer first draws the scene from the light into a depth map "
                     "(orthographic, fitted to the bounding sphere), then shading dims the light where that map "
                     "sees something nearer (5x5 filtered taps)");
    command.add_option("--shadow-resolution", args.resolution, "Shadow map size in texels (square)")
        ->capture_default_str();
}

Status check_shadow_options(const ShadowArgs& args)
{
    if (args.resolution < 16 || args.resolution > 16384)
        return error(StatusCode::invalid_argument, "--shadow-resolution: must be within 16..16384");
    return Status::ok();
}

static bool g_quiet = false;

void note(const std::string& message)
{
    if (!g_quiet) std::fprintf(stderr, "standin: %s\n", message.c_str());
}

Progress stderr_progress()
{
    if (g_quiet) return Progress();
    const char* forced = std::getenv("STANDIN_PROGRESS");
    bool show = forced ? std::string(forced) == "1" : ::isatty(2) != 0;
    if (!show) return Progress();
    struct State {
        std::mutex mutex;
        std::chrono::steady_clock::time_point last{};
        std::string stage;
    };
    auto state = std::make_shared<State>();
    return Progress([state](const std::string& stage, double fraction) {
        std::lock_guard lock(state->mutex);
        auto now = std::chrono::steady_clock::now();
        bool done = fraction >= 1.0;
        if (!done && stage == state->stage && now - state->last < std::chrono::milliseconds(100)) return;
        state->last = now;
        state->stage = stage;
        std::fprintf(stderr, "\r%-40s %5.1f%%%s", stage.c_str(), 100.0 * fraction, done ? "\n" : "");
        std::fflush(stderr);
    });
}

void install_log_sink(const Verbosity& verbosity)
{
    g_quiet = verbosity.quiet;
    bool verbose = verbosity.verbose && !verbosity.quiet;
    set_log_sink([verbose, quiet = verbosity.quiet](LogLevel level, const std::string& message) {
        if (level == LogLevel::debug && !verbose) return;
        if (level == LogLevel::info && !verbose) return;
        if (level == LogLevel::warning && quiet) return;
        const char* prefix = level == LogLevel::warning ? "warning: " : level == LogLevel::error ? "error: " : "";
        std::fprintf(stderr, "standin: %s%s\n", prefix, message.c_str());
    });
}

std::string Drawable::representation() const { return package ? package->representation() : "mesh"; }

BoundingSphere Drawable::framing_sphere() const
{
    return package ? bounding_sphere_of(package->source.bounds) : mesh->bounding_sphere();
}

Result<Drawable> read_drawable(const std::string& path)
{
    Drawable drawable;
    drawable.path = path;
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec)) {
        Result<std::unique_ptr<Package>> package = read_package(path);
        if (!package) return package.status();
        drawable.package = std::move(*package);
        return drawable;
    }
    Result<Mesh> mesh = import_mesh(path, nullptr, k_isolated_import);
    if (!mesh) return mesh.status();
    drawable.mesh = std::move(*mesh);
    return drawable;
}

Status make_drawable_renderer(Drawable& drawable, const RenderOptions& options)
{
    Result<std::unique_ptr<Renderer>> made =
        drawable.package ? make_package_renderer(*drawable.package, options) : make_mesh_renderer(*drawable.mesh);
    if (!made) return drawable.package ? naming_file(made.status(), drawable.path) : made.status();
    drawable.renderer = std::move(*made);
    return {};
}

} // namespace standin::cli
