// What every subcommand shares: error reporting, view options, progress on stderr.
#pragma once

#include <standin/camera.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/progress.h>
#include <standin/render.h>
#include <standin/status.h>

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>

namespace standin::cli {

constexpr int k_exit_ok = 0;
constexpr int k_exit_failure = 2; // bad input, bad options, or a failure we can name

// Every model the command line reads is parsed in a child process: a crash inside assimp on one
// damaged file becomes that file's error (and a batch goes on with the rest).
inline const ImportOptions k_isolated_import{.isolate_parser = true};

// A model or a package named on the command line (render, eval): read before any GL work, then
// drawn by its renderer (the package's representation's, or the ground truth's for a model).
struct Drawable {
    std::string path;
    std::unique_ptr<Package> package; // null for a model
    std::optional<Mesh> mesh;         // the model's
    std::unique_ptr<Renderer> renderer;
    std::string representation() const;  // the package's, or "mesh"
    BoundingSphere framing_sphere() const; // a package is framed as its source model
};
// A directory is a package, anything else a model (imported in a child process).
Result<Drawable> read_drawable(const std::string& path);
// The renderer, under a current GL context; `options` must have been checked against the
// representations at hand (check_render_options_apply).
Status make_drawable_renderer(Drawable& drawable, const RenderOptions& options);

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

// Progress bar on stderr, throttled, only when stderr is a terminal or STANDIN_PROGRESS=1, and
// never with --quiet.
Progress stderr_progress();

// -v/--verbose and -q/--quiet, accepted before or after the subcommand.
struct Verbosity {
    bool verbose = false;
    bool quiet = false;
};
// Installs a log sink printing warnings (and info with verbose; nothing but errors with quiet) on
// stderr, and remembers quiet for note() and stderr_progress().
void install_log_sink(const Verbosity& verbosity);
// "standin: MESSAGE" on stderr, unless --quiet: what a command did ("wrote ...").
void note(const std::string& message);

} // namespace standin::cli
