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

#include <cctype>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

namespace standin::cli {

struct EvalArgs {
    std::string model;
    std::vector<std::string> standins; // package directories, or model files (mesh stand-ins)
    std::string protocol = "quick";
    std::string json;
    std::string report;
    int frames = 3;
    int supersample = 0; // 0: the protocol's
    std::size_t samples = 100000;
    DeclaredOptions options;
    ShadowArgs shadows;
    std::string shading = "ggx";
};

// The stand-ins to evaluate: packages, or meshes (then also their surfaces), read before any is
// drawn so that the render options are checked against them all: each option must apply to one of
// them, and each package takes those its representation declares (as standin bench does).
static Result<std::vector<Drawable>> load_subjects(const EvalArgs& args, RenderOptions& options)
{
    options.values = args.options.given();
    std::vector<Drawable> subjects;
    std::vector<const Representation*> at_hand;
    for (const std::string& path : args.standins) {
        Result<Drawable> subject = read_drawable(path);
        if (!subject) return subject.status();
        if (subject->package) at_hand.push_back(&representation_of(*subject->package));
        subjects.push_back(std::move(*subject));
    }
    STANDIN_RETURN_IF_ERROR(check_render_options_apply(options, at_hand));
    return subjects;
}

static std::string command_line(const EvalArgs& args)
{
    std::string line = "standin eval " + args.model;
    for (const std::string& standin : args.standins) line += " " + standin;
    line += " --protocol " + args.protocol;
    if (args.supersample > 0) line += " --supersample " + std::to_string(args.supersample);
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
    std::printf("eval %s: %zu views, protocol %s, %d x %d samples a pixel, device %s\n", json.value("package", "").c_str(),
                result.views.size(), result.protocol.c_str(), result.supersample, result.supersample, result.device.c_str());
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

// One stand-in evaluated against the truth: its figures, its report in `report_directory` when
// given, and the sheet's pictures when `sheet` (the truth's too when `truth_pictures`). The truth's
// images and times are kept in `truth_views` for the next stand-in of a comparison.
static Result<ComparedStandin> evaluate_standin(const EvalArgs& args, Drawable& subject, const RenderOptions& render_options,
                                                const Mesh& mesh, Renderer& truth, const Protocol& protocol,
                                                const std::string& device, const std::string& report_directory, bool sheet,
                                                std::vector<ImageRGBA8>* truth_pictures, TruthViews* truth_views)
{
    const std::string& path = subject.path;
    RenderOptions own_options = render_options;
    if (subject.package) own_options.values = render_options.values.only(representation_of(*subject.package).render_options);
    if (Status made = make_drawable_renderer(subject, own_options); !made) return made;
    if (subject.package) {
        Result<SourceInfo> source = describe_source(args.model, mesh);
        if (source && !subject.package->source.content_hash.empty() &&
            source->content_hash != subject.package->source.content_hash)
            log_message(LogLevel::warning, path + " was baked from " + subject.package->source.file_name + ", not from " +
                                               args.model + " (content hash differs)");
    }

    // render, compare, and write the report's images as we go
    std::optional<ReportWriter> report;
    if (!report_directory.empty()) {
        Result<ReportWriter> writer = ReportWriter::begin(report_directory);
        if (!writer) return writer.status();
        report.emplace(std::move(*writer));
    }
    ComparedStandin compared;
    ViewSink sink = [&](std::size_t i, const ViewResult& r, const RenderedImage& t, const RenderedImage& s) {
        if (sheet && i < k_comparison_sheet_views) {
            compared.pictures.push_back(comparison_picture(s.color));
            if (truth_pictures) truth_pictures->push_back(comparison_picture(t.color));
        }
        return report ? report->add_view(i, r, t, s) : Status::ok();
    };
    EvalOptions options;
    options.timed_frames = args.frames;
    options.supersample = args.supersample > 0 ? args.supersample : protocol.supersample;
    options.shadows = args.shadows.enabled;
    options.shadow_resolution = args.shadows.resolution;
    options.shading = args.shading == "lambert" ? ShadingModel::lambert_blinn_phong : ShadingModel::ggx;
    Result<EvalResult> result =
        evaluate(truth, *subject.renderer, mesh.bounding_sphere(), protocol, options, stderr_progress(), sink, truth_views);
    if (!result) return result.status();
    result->device = device;
    if (subject.mesh) {
        Result<SurfaceDistance> surface = surface_distance(*subject.mesh, mesh, args.samples);
        if (!surface) return surface.status();
        result->surface = *surface;
    }

    nlohmann::json identity = {{"model", args.model},
                               {"package", path},
                               {"representation", subject.representation()},
                               {"shadows", args.shadows.enabled},
                               {"shading", args.shading},
                               {"command", command_line(args)}};
    compared.package = path;
    compared.representation = subject.representation();
    compared.json = eval_to_json(*result, identity);
    if (subject.package) {
        if (Result<std::uint64_t> bytes = package_bytes(path)) compared.bytes = *bytes;
    } else {
        std::error_code ec;
        const std::uintmax_t bytes = std::filesystem::file_size(path, ec);
        if (!ec) compared.bytes = bytes;
    }
    if (report) {
        if (Status s = report->finish(*result, compared.json); !s) return s;
        compared.report = std::filesystem::path(report->directory()).filename().string();
    }
    print_summary(*result, compared.json);
    subject.renderer.reset(); // the next stand-in's maps take its place on the GPU
    return compared;
}

// The folder of stand-in k's own report inside a comparison: its number and its file name.
static std::string standin_report_name(std::size_t k, const std::string& path)
{
    std::string name = std::filesystem::path(path).filename().string();
    if (name.empty()) name = std::filesystem::path(path).parent_path().filename().string();
    for (char& c : name)
        if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '_')) c = '_';
    char number[32];
    std::snprintf(number, sizeof number, "%02zu-", k + 1);
    return number + name;
}

static int run_eval(EvalArgs& args)
{
    if (Status s = check_shadow_options(args.shadows); !s) return fail(s);
    if (args.frames < 0 || args.frames > 1000) return fail("--frames: must be within 0..1000");
    if (args.samples < 1 || args.samples > k_max_surface_samples)
        return fail("--samples: must be within 1.." + std::to_string(k_max_surface_samples));
    std::vector<std::string> inputs = {args.model};
    inputs.insert(inputs.end(), args.standins.begin(), args.standins.end());
    for (const std::string& output : {args.json, args.report})
        if (!output.empty())
            if (Status s = check_output_is_not_input(output, inputs); !s) return fail(s);
    Result<Protocol> protocol = make_protocol(args.protocol);
    if (!protocol) return fail(protocol.status());

    // load the truth
    Result<Mesh> mesh = import_mesh(args.model, nullptr, k_isolated_import);
    if (!mesh) return fail(mesh.status());
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return fail(truth.status());
    const std::string device = (*context)->device_name();
    RenderOptions render_options;
    Result<std::vector<Drawable>> subjects = load_subjects(args, render_options);
    if (!subjects) return fail(subjects.status());

    // one stand-in: its report and JSON as they always were
    if (args.standins.size() == 1) {
        Result<ComparedStandin> one = evaluate_standin(args, subjects->front(), render_options, *mesh, **truth, *protocol,
                                                       device, args.report, false, nullptr, nullptr);
        if (!one) return fail(one.status());
        if (!args.json.empty())
            if (Status s = write_file_atomic(args.json, one->json.dump(2) + "\n"); !s) return fail(s);
        if (!args.report.empty())
            std::printf("report: %s\n", (std::filesystem::path(args.report) / "index.html").c_str());
        return k_exit_ok;
    }

    // several: each evaluated in turn (its own report inside the comparison's), then the comparison
    std::string report_final, report_temporary;
    if (!args.report.empty()) {
        Result<std::string> final_path = report_directory_path(args.report);
        if (!final_path) return fail(final_path.status());
        report_final = *final_path;
        std::error_code ec;
        report_temporary = temporary_path_for(report_final);
        std::filesystem::create_directories(report_temporary, ec);
        if (ec) return fail(report_temporary + ": cannot create directory: " + ec.message());
    }
    struct RemoveUnlessCommitted {
        std::string path;
        ~RemoveUnlessCommitted()
        {
            std::error_code ec;
            if (!path.empty()) std::filesystem::remove_all(path, ec);
        }
    } cleanup{report_temporary};
    std::vector<ComparedStandin> compared;
    std::vector<ImageRGBA8> truth_pictures;
    TruthViews truth_views; // the mesh drawn and timed once for every stand-in
    for (std::size_t k = 0; k < args.standins.size(); ++k) {
        const std::string report_directory =
            report_temporary.empty() ? std::string()
                                     : (std::filesystem::path(report_temporary) / standin_report_name(k, args.standins[k])).string();
        Result<ComparedStandin> one = evaluate_standin(args, (*subjects)[k], render_options, *mesh, **truth, *protocol, device,
                                                       report_directory, !report_temporary.empty(),
                                                       k == 0 ? &truth_pictures : nullptr, &truth_views);
        if (!one) return fail(one.status());
        compared.push_back(std::move(*one));
    }
    const nlohmann::json comparison = comparison_to_json(args.model, args.protocol, device, command_line(args), compared);
    std::printf("compared %zu stand-ins of %s (protocol %s; means over views):\n", compared.size(), args.model.c_str(),
                args.protocol.c_str());
    std::printf("  %-3s %-22s %12s %8s %8s %8s %9s %9s %19s  %s\n", "#", "representation", "bytes", "Luv", "dE2000", "IoU",
                "holes %", "spill %", "ms stand-in / mesh", "stand-in");
    for (std::size_t k = 0; k < compared.size(); ++k) {
        const nlohmann::json& s = compared[k].json["summary"];
        char frame[64] = "not timed";
        if (const auto ms = comparison_frame_ms(compared[k].json)) std::snprintf(frame, sizeof frame, "%.2f / %.2f", ms->first, ms->second);
        std::printf("  %-3zu %-22s %12llu %8.3f %8.3f %8.4f %9.4f %9.4f %19s  %s\n", k + 1, compared[k].representation.c_str(),
                    static_cast<unsigned long long>(compared[k].bytes), s["luv_mean"].get<double>(),
                    s["de2000_mean"].get<double>(), s["iou"].get<double>(), 100.0 * s["hole_fraction"].get<double>(),
                    100.0 * s["spill_fraction"].get<double>(), frame, compared[k].package.c_str());
    }
    if (!args.json.empty())
        if (Status s = write_file_atomic(args.json, comparison.dump(2) + "\n"); !s) return fail(s);
    if (!report_temporary.empty()) {
        if (Status s = write_comparison_page(report_temporary, comparison, truth_pictures, compared); !s) return fail(s);
        if (Status s = commit_path(report_temporary, report_final); !s) return fail(s);
        cleanup.path.clear();
        std::printf("report: %s\n", (std::filesystem::path(report_final) / "index.html").c_str());
    }
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
    command->add_option("packages", args->standins,
                        "A NAME.standin package directory, or another model file (a mesh stand-in: its surface "
                        "distance to the original is measured too); several are compared side by side (a table of "
                        "their figures and sizes, a contact sheet of the truth and each, and each one's own report)")
        ->required();
    std::string names;
    for (const std::string& p : protocol_names()) names += (names.empty() ? "" : " | ") + p;
    command->add_option("--protocol", args->protocol,
                        names + ": quick = 4 views at 320x240; thesis = Vichitvejpaisal 2005 appendix A (14 views x "
                                "3 resolutions); saraiva = Saraiva et al. §3 (14 views x 8 distances x 3 fovs); "
                                "foliage = 14 views x distances 1, 4, 8 (alpha-masked leaves), 4 x 4 samples a pixel")
        ->capture_default_str();
    command->add_option("--json", args->json, "Write every figure as JSON to this file");
    command->add_option("--report", args->report,
                        "Write an HTML report (index.html, CSV tables, SVG charts, image triplets) into this directory");
    command->add_option("--supersample", args->supersample,
                        "Samples a pixel along each axis, for truth and stand-in alike: both are rendered at N times "
                        "the view's size and box-filtered in linear light, as an anti-aliased display shows them; "
                        "colour figures compare the pixels, silhouette figures (IoU, holes, spill, pixels) the "
                        "samples. 0: the protocol's (4 for foliage, whose alpha-tested leaves alias at one sample; "
                        "1 for the others, as the seeds measured)")
        ->check(CLI::Range(0, k_max_supersample))
        ->capture_default_str();
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
