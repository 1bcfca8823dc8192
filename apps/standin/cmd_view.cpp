// standin view: the interactive viewer (apps/viewer/): the model and its packages in a window,
// side by side or split, with their run-time knobs, debug views and timings; --script drives it
// unattended.
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include "viewer/script.h"
#include "viewer/viewer.h"

#include <memory>

namespace standin::cli {

struct ViewCommandArgs {
    std::vector<std::string> inputs;
    std::string script;
    std::string render_size;
    ViewArgs view;
    DeclaredOptions options;
    std::string debug_view;
};

static int run_view(ViewCommandArgs& args)
{
    viewer::ViewerArgs viewer_args;
    if (Status s = parse_view(args.view, viewer_args.window_width, viewer_args.window_height, viewer_args.view); !s)
        return fail(s);
    if (!args.render_size.empty() && args.render_size != "window" &&
        !viewer::parse_size(args.render_size, viewer_args.render_width, viewer_args.render_height))
        return fail("--render-size: expected WIDTHxHEIGHT within 1x1..16384x16384 or 'window', got '" +
                    args.render_size + "'");
    viewer_args.options = args.options.given();
    viewer_args.debug_view = args.debug_view == "off" ? "" : args.debug_view;
    viewer_args.inputs = args.inputs;
    viewer_args.script_path = args.script;
    viewer_args.light_azimuth = args.view.light_azimuth;
    viewer_args.light_elevation = args.view.light_elevation;
    if (Status s = viewer::run_viewer(viewer_args); !s) return fail(s);
    return k_exit_ok;
}

CommandRun add_view_command(CLI::App& root)
{
    auto args = std::make_shared<ViewCommandArgs>();
    CLI::App* command = root.add_subcommand(
        "view", "Open an interactive window (OpenGL 4.5) showing a model and its .standin packages, one at a time, "
                "split or side by side, with run-time knobs, debug views and frame timings. Needs a display; "
                "'standin render' draws offscreen");
    command->add_option("inputs", args->inputs, "A model file and/or NAME.standin package directories")->required();
    command->add_option("--script", args->script,
                        "Run the commands in FILE (camera, show, split, debug, resolution, light, screenshot, wait, "
                        "quit, ...; see apps/viewer/script.h), then exit");
    command->add_option("--render-size", args->render_size,
                        "Render resolution WIDTHxHEIGHT, independent of the window (default: the window's)");
    add_view_options(*command, args->view);
    command->get_option("--size")->description("Window size WIDTHxHEIGHT");
    add_debug_view_option(*command, args->debug_view, true);
    args->options.add_to(*command, OptionKind::render);
    return [args] { return run_view(*args); };
}

} // namespace standin::cli
