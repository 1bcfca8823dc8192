// The displaced control mesh as the registry sees it: its bake parameters and run-time options
// (declared once: the command line, --help, the viewer, the manifest's "bake" block and its
// validation all come from these tables), debug views, and the summary `standin info` prints.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/renderer.h"

#include "reps/common/package_cast.h"

#include <cmath>
#include <cstdio>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin::displaced_mesh {

namespace {

std::vector<OptionSpec> bake_options()
{
    return {
        integer_option("degree", 0, 0, 33,
                       "Sampling-pattern degree k: 5, 9, 17 or 33 vertices per edge, (k-1)^2 triangles per control "
                       "face; 0: chosen (Bauman et al.'s 17, which they measured better than 33, for models of 65,536 "
                       "faces or more; smaller ones 5 over up to 4,096 control faces, and under 4,096 faces every face kept "
                       "at the finest degree whose pattern stays within 65,536 triangles; models with alpha-masked "
                       "materials 33, whose colours then hold the leaf texture's detail, coarser where their cut-out faces "
                       "would hold over 8 million samples; where the control mesh stops over 4x its target's samples, as on "
                       "assemblies of many small parts, 9 or 5, so that the refined mesh stays near the model's size)"),
        integer_option("control-faces", 0, 0, 50'000'000,
                       "Control faces wanted (0: the model's faces / (k-1)^2, at least 256 or all of them; with the degree "
                       "chosen, see --degree; given, the degree chosen is 17)"),
        number_option("cone-angle", "90", 0.0, 180.0,
                      "No vertex's normal cone may reach this half-angle, degrees (90: a half-sphere, the paper)", true),
        choice_option("sampler", "intersection", {"intersection", "interpolation"},
                      "Elevations: intersection (where the vertex's ray meets the surface) or interpolation (the "
                      "paper's neighbourhood sampler: hat-weighted mean of sub-ray elevations)"),
        integer_option("interpolation-rays", 16, 1, 64, "Sub-rays per pattern triangle of the interpolation sampler (a square)"),
        number_option("ray-range", "0.05", 0.0, 10.0,
                      "How far rays look each way along the normal, fraction of the bounding-box diagonal", true),
        integer_option("elevation-bits", 16, 16, 32, "Elevation storage: 16 (unorm over the package's range) or 32 (float)"),
        choice_option("back-faces", "auto", {"auto", "show", "cull"},
                      "Back faces of the displaced surface: show (both sides drawn, as double-sided materials "
                      "are), cull (as the truth culls single-sided materials: for sheets and ground planes seen "
                      "from behind) or auto (cull where over 0.1% of the model's area is single-sided faces "
                      "whose backs can be seen from outside, else show; the package records which)"),
        choice_option("shading-detail", "auto", {"auto", "1", "2", "4"},
                      "Shading (normal, colour, PBR, and the coverage of alpha-masked materials) samples per "
                      "pattern step along an edge: 1 (one per pattern vertex, the paper's), 2 or 4 (a textured "
                      "model's colour detail and cut-out outlines, 4x or 16x the shading bytes), or auto (finer "
                      "only where a pattern step spans over 4 pixels of an 800x600 view and 2 texels, or a cut-out face's step "
                      "over 1 pixel, within 8M shading samples (16M with cut-out faces), and the coarsest whose colours and outlines stay within 1% of the finest; "
                      "1 without textures)"),
        choice_option("compression", "gzip", {"gzip", "none"},
                      "Arrays in the package: gzip (each .bin as a .bin.gz: foliage's shading arrays shrink 20-50x, "
                      "a scan's elevations and normals 4-10%) or none (raw little-endian arrays, read by standin before "
                      "format version 7)"),
        choice_option("source-textures", "auto", {"auto", "off"},
                      "Control faces that are the model's own textured triangles (every leaf card of an alpha-masked "
                      "material, and every face of a model kept whole) draw its base-colour texture at the pixel, "
                      "filtered and alpha-tested as the mesh draws it (auto; the package keeps those textures), or "
                      "only the sampled colour and coverage, as the paper's maps (off)"),
    };
}

std::vector<OptionSpec> render_options()
{
    return {
        number_option("tau", "1", 0.0, 1000.0, "Screen-space tolerance, pixels (the paper's tau)", true),
        choice_option("criterion", "error", {"error", "weighted", "length", "seed"},
                      "Split test: error (a segment's chord error in pixels), weighted (length x edge curvature, "
                      "conforming), length (projected length), seed (the paper's literal rule, leaves T-junctions)"),
        number_option("outline", "2", 1.0, 64.0,
                      "Error criterion: how much more error counts near the silhouette (chords there leave hole pixels)"),
        flag_option("cull", true, "Cull control faces on their displaced prisms (outside the frustum or facing away)"),
        flag_option("mip", true, "Read elevations from the mip level whose spacing projects to about tau pixels"),
        choice_option("subdivision", "leb", {"leb", "tess"},
                      "leb: longest-edge bisection in compute passes; tess: tessellation shaders (a baseline)"),
        flag_option("cut-out-pre-pass", true,
                    "Draw packages with cut-outs (alpha-masked leaves) in two passes: depth through the cut-out test, "
                    "then shading of the nearest fragments alone, once per pixel (the same picture; dense foliage "
                    "25-30% faster on llvmpipe, sparse crowns and cards a pixel or two across within the noise: "
                    "docs/RESULTS.md; --subdivision tess draws one pass)"),
    };
}

PackageSummary summarise(const Package& base)
{
    const auto& p = reps::package_cast<DisplacedMeshPackage>(base);
    const PatternLayout l = p.layout();
    std::uint64_t refined = std::uint64_t(p.face_count()) * std::uint64_t(l.segments) * std::uint64_t(l.segments);
    PackageSummary summary;
    const std::uint64_t gpu_bytes = package_buffer_bytes(p);
    summary.details = {{"source", p.source.file_name},
                       {"control_faces", p.face_count()},
                       {"control_vertices", p.positions.size()},
                       {"control_target_faces", p.control.target_faces},
                       {"control_reached_target", p.control.reached_target},
                       {"degree", p.settings.degree},
                       {"refined_triangles", refined},
                       {"sampler", p.settings.sampler},
                       {"elevation_bits", p.settings.elevation_bits},
                       {"misses", p.sampling.misses},
                       {"d_mean", p.sampling.original_to_sampled_mean},
                       {"d_max", p.sampling.original_to_sampled_max},
                       {"shading_detail", p.settings.shading_detail},
                       {"shading_samples", p.shading_normals.size()},
                       {"compression", p.settings.compressed ? "gzip" : "none"},
                       {"source_textured_faces", p.source_textures.matched_faces()},
                       {"source_texture_layers", p.source_textures.layers.size()},
                       {"gpu_buffer_bytes", gpu_bytes}};
    char line[320];
    std::snprintf(line, sizeof line,
                  "%zu control faces x %d^2 pattern (%llu triangles at full detail), %d-bit elevations, shading detail %d "
                  "(%llu samples), %.1f MiB of GPU buffers%s",
                  p.face_count(), l.segments, (unsigned long long)refined, p.settings.elevation_bits, p.settings.shading_detail,
                  (unsigned long long)p.shading_normals.size(), double(gpu_bytes) / double(1 << 20),
                  p.control.reached_target ? "" : "; the cones or boundary loops stopped simplification early");
    summary.headline = line;
    return summary;
}

} // namespace

BakeSettings settings_from(const Options& parameters)
{
    BakeSettings s;
    s.degree = parameters.integer("degree");
    s.control_faces = parameters.integer("control-faces");
    s.cone_angle = parameters.number("cone-angle");
    s.sampler = parameters.choice("sampler");
    s.interpolation_rays = parameters.integer("interpolation-rays");
    s.ray_range = parameters.number("ray-range");
    s.elevation_bits = parameters.integer("elevation-bits");
    s.back_faces = parameters.choice("back-faces");
    const std::string detail = parameters.choice("shading-detail");
    s.shading_detail = detail == "auto" ? 0 : std::stoi(detail); // 0: not resolved yet (the bake resolves it)
    s.compressed = parameters.choice("compression") == "gzip";
    s.source_textures = parameters.choice("source-textures");
    return s;
}

Status check_settings(const BakeSettings& s)
{
    if (!is_pattern_degree(s.degree)) return error(StatusCode::invalid_argument, "--degree: must be 5, 9, 17 or 33 (or 0: chosen by the bake)");
    int root = int(std::lround(std::sqrt(double(s.interpolation_rays))));
    if (root * root != s.interpolation_rays)
        return error(StatusCode::invalid_argument, "--interpolation-rays: must be a square number (1, 4, 9, ..., 64)");
    if (s.elevation_bits != 16 && s.elevation_bits != 32)
        return error(StatusCode::invalid_argument, "--elevation-bits: must be 16 or 32");
    return Status::ok();
}

Result<Options> bake_parameters(const std::vector<std::pair<std::string, std::string>>& values)
{
    OptionValues given;
    for (const auto& [name, value] : values) given.set(name, value);
    std::vector<OptionSpec> specs = bake_options();
    return Options::parse(specs, given, "displaced-mesh");
}

Representation registration()
{
    Representation r;
    r.name = "displaced-mesh";
    r.title = "Displaced control mesh";
    r.description = "a coarse control mesh with a displacement map per face, culled and bisected on the GPU every "
                    "frame to a screen-space tolerance: real geometry, crack-free";
    r.reference = "Bauman, Livny & El-Sana";
    r.bake_options = bake_options();
    r.render_options = render_options();
    r.debug_views = {DebugView::parts, DebugView::depth, DebugView::normal, DebugView::level, DebugView::error};
    OptionValues tessellation;
    tessellation.set("subdivision", "tess");
    r.bench_variants = {tessellation};
    r.bake = bake;
    r.write = write;
    r.read = read;
    r.make_renderer = make_renderer;
    r.summarise = summarise;
    r.export_options = export_options();
    r.export_scene = export_scene;
    return r;
}

} // namespace standin::displaced_mesh
