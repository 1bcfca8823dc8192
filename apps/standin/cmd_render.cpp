// standin render: one picture of a model with the ground-truth renderer (or of a package with its
// representation's renderer), offscreen, to PNG.
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/files.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <cstdio>
#include <filesystem>
#include <memory>

namespace standin::cli {

struct RenderArgs {
    std::string input;
    std::string output;
    ViewArgs view;
    DeclaredOptions options;
    std::string debug_view;
    ShadowArgs shadows;
};

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

    // a directory is a package, drawn by its representation's renderer; a file is a model
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());
    std::unique_ptr<Renderer> renderer;
    BoundingSphere sphere;
    std::error_code ec;
    if (std::filesystem::is_directory(args.input, ec)) {
        Result<std::unique_ptr<Package>> package = read_package(args.input);
        if (!package) return fail(package.status());
        const Representation* at_hand[] = {&representation_of(**package)};
        if (Status s = check_render_options_apply(options, at_hand); !s) return fail(s);
        Result<std::unique_ptr<Renderer>> made = make_package_renderer(**package, options);
        if (!made) return fail(naming_file(made.status(), args.input));
        renderer = std::move(*made);
        // frame the package as its source model
        sphere = bounding_sphere_of((*package)->source.bounds);
    } else {
        if (Status s = check_render_options_apply(options, {}); !s) return fail(s);
        Result<Mesh> mesh = import_mesh(args.input, nullptr, k_isolated_import);
        if (!mesh) return fail(mesh.status());
        Result<std::unique_ptr<Renderer>> made = make_mesh_renderer(*mesh);
        if (!made) return fail(made.status());
        renderer = std::move(*made);
        sphere = mesh->bounding_sphere();
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
    note("wrote " + args.output + " (" + std::to_string(width) + "x" + std::to_string(height) + ", " +
         (*context)->device_name() + ")");
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
    args->options.add_to(*command, OptionKind::render);
    return [args] { return run_render(*args); };
}

} // namespace standin::cli
