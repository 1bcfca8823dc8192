// standin eval: renders the original model (ground truth) and a stand-in from the same cameras and
// light, compares the images (and, for mesh stand-ins, the surfaces), writes JSON, CSV tables and
// an HTML report (docs/EVAL.md).
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/log.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace standin::cli {

struct EvalArgs {
    std::string model;
    std::string standin; // package directory, or a model file (a mesh stand-in)
    std::string protocol = "quick";
    std::string json;
    std::string report;
    int frames = 3;
    std::size_t samples = 100000;
    DeclaredOptions options;
    ShadowArgs shadows;
    std::string shading = "ggx";
};

// The stand-in to evaluate: a package, or a mesh (then also its surface).
static Result<Drawable> load_subject(const EvalArgs& args)
{
    RenderOptions options;
    options.values = args.options.given();
    Result<Drawable> subject = read_drawable(args.standin);
    if (!subject) return subject.status();
    std::vector<const Representation*> at_hand;
    if (subject->package) at_hand.push_back(&representation_of(*subject->package));
    STANDIN_RETURN_IF_ERROR(check_render_options_apply(options, at_hand));
    STANDIN_RETURN_IF_ERROR(make_drawable_renderer(*subject, options));
    return subject;
}

static std::string command_line(const EvalArgs& args)
{
    std::string line = "standin eval " + args.model + " " + args.standin + " --protocol " + args.protocol;
    // every option that changes a figure, so the JSON says how to reproduce it
    line += args.options.command_line();
    if (args.shadows.enabled) line += " --shadows --shadow-resolution " + std::to_string(args.shadows.resolution);
    if (args.shading != "ggx") line += " --shading " + args.shading;
    line += " --frames " + std::to_string(args.frames);
    if (!args.json.empty()) line += " --json " + args.json;
    if (!args.report.empty()) line += " --report " + args.report;
    return line;
}

static void print_summary(const EvalResult& result, const nlohmann::json& json)
{
    const nlohmann::json& s = json["summary"];
    std::printf("eval %s: %zu views, protocol %s, device %s\n", json.value("package", "").c_str(), result.views.size(),
                result.protocol.c_str(), result.device.c_str());
    std::printf("  Luv (eq. 2.2)   mean %.3f  median %.3f  max %.3f\n", s["luv_mean"].get<double>(),
                s["luv_median"].get<double>(), s["luv_max"].get<double>());
    std::printf("  CIEDE2000       mean %.3f  p95 %.3f\n", s["de2000_mean"].get<double>(), s["de2000_p95"].get<double>());
    std::printf("  RGB error       avg %.3f  total %.4g\n", s["rgb_avg"].get<double>(), s["rgb_total"].get<double>());
    std::printf("  coverage        holes %.4f  spill %.4f  IoU %.4f\n", s["hole_fraction"].get<double>(),
                s["spill_fraction"].get<double>(), s["iou"].get<double>());
    std::printf("  PSNR            %.2f dB\n", s["psnr"].get<double>());
    if (result.surface)
        std::printf("  surface         mean %.3g  max %.3g (of the bounding-box diagonal)\n", result.surface->mean_rel,
                    result.surface->max_rel);
    std::printf("  verdict         %s\n", json["verdict"]["line"].get<std::string>().c_str());
}

static int run_eval(EvalArgs& args)
{
    if (Status s = check_shadow_options(args.shadows); !s) return fail(s);
    if (args.frames < 0 || args.frames > 1000) return fail("--frames: must be within 0..1000");
    if (args.samples < 1 || args.samples > k_max_surface_samples)
        return fail("--samples: must be within 1.." + std::to_string(k_max_surface_samples));
    for (const std::string& output : {args.json, args.report})
        if (!output.empty())
            if (Status s = check_output_is_not_input(output, {args.model, args.standin}); !s) return fail(s);
    Result<Protocol> protocol = make_protocol(args.protocol);
    if (!protocol) return fail(protocol.status());

    // load the truth and the stand-in
    Result<Mesh> mesh = import_mesh(args.model, nullptr, k_isolated_import);
    if (!mesh) return fail(mesh.status());
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return fail(truth.status());
    Result<Drawable> subject = load_subject(args);
    if (!subject) return fail(subject.status());
    if (subject->package) {
        Result<SourceInfo> source = describe_source(args.model, *mesh);
        if (source && !subject->package->source.content_hash.empty() &&
            source->content_hash != subject->package->source.content_hash)
            log_message(LogLevel::warning, args.standin + " was baked from " + subject->package->source.file_name + ", not from " +
                                       args.model + " (content hash differs)");
    }

    // render, compare, and write the report's images as we go
    std::optional<ReportWriter> report;
    if (!args.report.empty()) {
        Result<ReportWriter> writer = ReportWriter::begin(args.report);
        if (!writer) return fail(writer.status());
        report.emplace(std::move(*writer));
    }
    ViewSink sink;
    if (report)
        sink = [&](std::size_t i, const ViewResult& r, const RenderedImage& t, const RenderedImage& s) {
            return report->add_view(i, r, t, s);
        };
    EvalOptions options;
    options.timed_frames = args.frames;
    options.shadows = args.shadows.enabled;
    options.shadow_resolution = args.shadows.resolution;
    options.shading = args.shading == "lambert" ? ShadingModel::lambert_blinn_phong : ShadingModel::ggx;
    Result<EvalResult> result =
        evaluate(**truth, *subject->renderer, mesh->bounding_sphere(), *protocol, options, stderr_progress(), sink);
    if (!result) return fail(result.status());
    result->device = (*context)->device_name();
    if (subject->mesh) {
        Result<SurfaceDistance> surface = surface_distance(*subject->mesh, *mesh, args.samples);
        if (!surface) return fail(surface.status());
        result->surface = *surface;
    }

    // outputs
    nlohmann::json identity = {{"model", args.model},
                               {"package", args.standin},
                               {"representation", subject->representation()},
                               {"shadows", args.shadows.enabled},
                               {"shading", args.shading},
                               {"command", command_line(args)}};
    nlohmann::json json = eval_to_json(*result, identity);
    if (!args.json.empty())
        if (Status s = write_file_atomic(args.json, json.dump(2) + "\n"); !s) return fail(s);
    if (report) {
        if (Status s = report->finish(*result, json); !s) return fail(s);
    }
    print_summary(*result, json);
    if (report) std::printf("report: %s\n", (std::filesystem::path(report->directory()) / "index.html").c_str());
    return k_exit_ok;
}

CommandRun add_eval_command(CLI::App& root)
{
    auto args = std::make_shared<EvalArgs>();
    CLI::App* command = root.add_subcommand(
        "eval", "Compare a stand-in with the original model: render both from a protocol's cameras with the same "
                "light, and report the CIE Luv difference (Vichitvejpaisal 2005 eq. 2.2), the per-pixel RGB error "
                "(Saraiva et al.), "
                "CIEDE2000, holes, spill, IoU and PSNR (docs/EVAL.md)");
    command->add_option("model", args->model, "The original model file (ground truth)")->required();
    command->add_option("package", args->standin,
                        "A NAME.standin package directory, or another model file (a mesh stand-in: its surface "
                        "distance to the original is measured too)")
        ->required();
    std::string names;
    for (const std::string& p : protocol_names()) names += (names.empty() ? "" : " | ") + p;
    command->add_option("--protocol", args->protocol,
                        names + ": quick = 4 views at 320x240; thesis = Vichitvejpaisal 2005 appendix A (14 views x "
                                "3 resolutions); saraiva = Saraiva et al. §3 (14 views x 8 distances x 3 fovs); "
                                "foliage = 14 views x distances 1, 4, 8 (alpha-masked leaves)")
        ->capture_default_str();
    command->add_option("--json", args->json, "Write every figure as JSON to this file");
    command->add_option("--report", args->report,
                        "Write an HTML report (index.html, CSV tables, SVG charts, image triplets) into this directory");
    command->add_option("--frames", args->frames, "Frames timed per view and subject (0: no timing)")->capture_default_str();
    command->add_option("--samples", args->samples, "Mesh stand-ins: surface samples for the distance")
        ->capture_default_str();
    add_shadow_options(*command, args->shadows);
    command->add_option("--shading", args->shading,
                        "Shading model of truth and stand-in: ggx (glTF metallic-roughness, the default) or lambert "
                        "(Lambert + ambient, standin's model before issue #14)")
        ->check(CLI::IsMember({"ggx", "lambert"}))
        ->capture_default_str();
    args->options.add_to(*command, OptionKind::render);
    return [args] { return run_eval(*args); };
}

} // namespace standin::cli
