// What every subcommand shares: error reporting, view options, progress on stderr.
#pragma once

#include <standin/camera.h>
#include <standin/progress.h>
#include <standin/render.h>
#include <standin/status.h>

#include <CLI/CLI.hpp>

#include <string>

namespace standin::cli {

constexpr int k_exit_ok = 0;
constexpr int k_exit_failure = 2; // bad input, bad options, or a failure we can name

// Prints "standin: MESSAGE" on stderr and returns the failure exit code.
int fail(const Status& status);
int fail(const std::string& message);

// --size WxH, --azimuth, --elevation, --distance, --fov | --ortho
struct ViewArgs {
    std::string size = "800x600";
    float azimuth = 30.0f;
    float elevation = 20.0f;
    float distance = 1.0f;
    float fov = 40.0f;
    bool ortho = false;
    float light_azimuth = NAN, light_elevation = NAN; // default: the protocol light, from the camera
};
void add_view_options(CLI::App& command, ViewArgs& args);
// Checks ranges and parses the size; fills width, height and the orbit view.
Status parse_view(const ViewArgs& args, int& width, int& height, OrbitView& view);
Light light_for(const ViewArgs& args, const Camera& camera);

// --shadows, --shadow-resolution (render and eval)
struct ShadowArgs {
    bool enabled = false;
    int resolution = 2048;
};
void add_shadow_options(CLI::App& command, ShadowArgs& args);
Status check_shadow_options(const ShadowArgs& args);

// --march, --steps, --hit-range, --no-coarse (accepted by render, eval and bench alike)
void add_render_options(CLI::App& command, RenderOptions& options, bool& no_coarse);
Status check_render_options(const RenderOptions& options);

// Progress bar on stderr, throttled, only when stderr is a terminal or STANDIN_PROGRESS=1.
Progress stderr_progress();

// Installs a log sink printing warnings (and info with verbose) on stderr.
void install_log_sink(bool verbose);

} // namespace standin::cli
