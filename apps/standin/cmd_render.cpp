// standin render: one picture of a model with the ground-truth renderer (or of a package with its
// representation's renderer), offscreen, to PNG. With --fade-to, the picture is the screen-door
// cross-fade an engine's level-of-detail switch would show (CrossFade, issue #14) from the input to
// a second model or package, at an amount given directly or by where --distance falls in a band.
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/files.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

namespace standin::cli {

struct RenderArgs {
    std::string input;
    std::string output;
    ViewArgs view;
    DeclaredOptions options;
    std::string debug_view;
    ShadowArgs shadows;
    std::string fade_to;   // a second model or package: cross-fade to it
    std::string fade_band; // NEAR:FAR, relative distances: the amount follows --distance through the band
    float fade_amount = NAN;
};

namespace {

// The cross-fade amount of --fade or --fade-band at the view's distance; NaN when no fade is asked.
Result<float> fade_amount(const RenderArgs& args)
{
    const bool band = !args.fade_band.empty(), amount = !std::isnan(args.fade_amount);
    if (args.fade_to.empty()) {
        if (band || amount) return error(StatusCode::invalid_argument, "--fade and --fade-band need --fade-to MODEL_OR_PACKAGE");
        return NAN;
    }
    if (band == amount)
        return error(StatusCode::invalid_argument,
                     "--fade-to needs exactly one of --fade AMOUNT (0: the input, 1: the --fade-to subject) or "
                     "--fade-band NEAR:FAR (relative distances, like --distance)");
    if (amount) {
        if (!(args.fade_amount >= 0.0f && args.fade_amount <= 1.0f))
            return error(StatusCode::invalid_argument, "--fade " + std::to_string(args.fade_amount) + ": must be in [0, 1]");
        return args.fade_amount;
    }
    float near = NAN, far = NAN;
    char tail = 0;
    if (std::sscanf(args.fade_band.c_str(), "%f:%f%c", &near, &far, &tail) != 2 || !(near > 0.0f) || !(far >= near) ||
        !std::isfinite(far))
        return error(StatusCode::invalid_argument, "--fade-band " + args.fade_band +
                                                       ": expected NEAR:FAR, relative distances with 0 < NEAR <= FAR (e.g. 2:3)");
    return transition_amount(args.view.distance, near, far);
}

} // namespace

static int run_render(RenderArgs& args)
{
    int width = 0, height = 0;
    OrbitView view;
    if (Status s = parse_view(args.view, width, height, view); !s) return fail(s);
    RenderOptions options;
    options.values = args.options.given();
    Result<DebugView> debug_view = parse_debug_view(args.debug_view == "off" ? "" : args.debug_view);
    if (!debug_view) return fail(debug_view.status());
    options.debug_view = *debug_view;
    if (Status s = check_shadow_options(args.shadows); !s) return fail(s);
    if (args.output.size() < 4 || args.output.substr(args.output.size() - 4) != ".png")
        return fail(args.output + ": output must be a .png file");
    if (Status s = check_output_path(args.output); !s) return fail(s);
    if (Status s = check_output_is_not_input(args.output, {args.input}); !s) return fail(s);

    Result<float> fade = fade_amount(args);
    if (!fade) return fail(fade.status());
    if (!args.fade_to.empty()) {
        if (Status s = check_output_is_not_input(args.output, {args.fade_to}); !s) return fail(s);
    }
    std::unique_ptr<GpuContext> context; // declared first: the renderers must go before it
    std::vector<Drawable> subjects; // the input, then the --fade-to subject
    std::vector<const Representation*> at_hand;
    for (const std::string& path : {args.input, args.fade_to}) {
        if (path.empty()) continue;
        Result<Drawable> subject = read_drawable(path);
        if (!subject) return fail(subject.status());
        if (subject->package) at_hand.push_back(&representation_of(*subject->package));
        subjects.push_back(std::move(*subject));
    }
    if (Status s = check_render_options_apply(options, at_hand); !s) return fail(s);

    Result<std::unique_ptr<GpuContext>> created = create_headless_context();
    if (!created) return fail(created.status());
    context = std::move(*created);
    for (Drawable& subject : subjects)
        if (Status s = make_drawable_renderer(subject, options); !s) return fail(s);
    Renderer* renderer = subjects[0].renderer.get();
    const BoundingSphere sphere = subjects[0].framing_sphere();
    std::unique_ptr<CrossFade> cross_fade;
    if (subjects.size() == 2) {
        cross_fade = std::make_unique<CrossFade>(*subjects[0].renderer, *subjects[1].renderer);
        cross_fade->set_amount(*fade);
        renderer = cross_fade.get();
    }

    Camera camera = orbit_camera(sphere, view, float(width) / float(height));
    ShadowOptions shadows;
    shadows.enabled = args.shadows.enabled;
    shadows.scene = sphere;
    shadows.resolution = args.shadows.resolution;
    Result<RenderedImage> image =
        render_offscreen(*renderer, camera, light_for(args.view, camera), width, height, {}, shadows);
    if (!image) return fail(image.status());
    if (Status s = write_png(image->color, args.output); !s) return fail(s);
    std::string fade_note;
    if (cross_fade) {
        char amount[32];
        std::snprintf(amount, sizeof amount, "%.3f", double(*fade));
        fade_note = ", cross-fade " + std::string(amount) + " of the way to " + args.fade_to;
    }
    note("wrote " + args.output + " (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
         context->device_name() + fade_note + ")");
    return k_exit_ok;
}

CommandRun add_render_command(CLI::App& root)
{
    auto args = std::make_shared<RenderArgs>();
    CLI::App* command = root.add_subcommand(
        "render", "Render a model (ground truth) or a .standin package to a PNG with a transparent background, "
                  "from an orbit camera around the bounding sphere, lit by one directional light");
    command->add_option("input", args->input, "Model file, or a NAME.standin package directory")->required();
    command->add_option("-o,--output", args->output, "Output PNG")->required();
    add_view_options(*command, args->view);
    add_shadow_options(*command, args->shadows);
    add_debug_view_option(*command, args->debug_view);
    command->add_option("--fade-to", args->fade_to,
                        "A second model or package: draw the screen-door cross-fade (dithered, 1/64 steps) from the input "
                        "to it, as a level-of-detail switch over a distance band shows it (no pop); needs --fade or --fade-band");
    command->add_option("--fade", args->fade_amount, "Cross-fade amount, 0 (all input) to 1 (all --fade-to)");
    command->add_option("--fade-band", args->fade_band,
                        "NEAR:FAR relative distances of the switch: the amount runs from 0 at NEAR to 1 at FAR, "
                        "taken at --distance (e.g. --fade-band 2:3 --distance 2.5 is halfway)");
    args->options.add_to(*command, OptionKind::render);
    return [args] { return run_render(*args); };
}

} // namespace standin::cli
