// Microfacets as the registry sees them: bake parameters and run-time options (declared once: the
// command line, --help, the viewer, the manifest's "bake" block and its validation all come from
// these tables), debug views, and the summary `standin info` prints.
// Defaults were chosen by measurement (docs/RESULTS.md, "Microfacets"); the paper's own settings
// are one option away: --layout circle --frames 36 (its turntable), --depth-bits 8, --views 1
// --clip seed --coverage any (its nearest view clipped by eq. 1), --level N (its fixed levels).
#include "reps/common/package_cast.h"
#include "reps/microfacets/export.h"
#include "reps/microfacets/microfacets.h"
#include "reps/microfacets/renderer.h"
#include "reps/microfacets/view_lookup.h"

#include <cstdio>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin::microfacets {

namespace {

std::vector<OptionSpec> bake_options()
{
    return {
        integer_option("level", 7, 1, k_max_grid_level,
                       "Finest octree level: 2^level voxels per side (Yamazaki et al. 2002 Table 1: 5..8)"),
        integer_option("min-level", 2, 0, k_max_grid_level, "Coarsest octree level kept, what distant copies draw"),
        choice_option("layout", "icosahedral", {"icosahedral", "octahedral", "hemi-octahedral", "circle"},
                      "Capture directions: the view atlas's sphere layouts, or circle (Yamazaki et al. 2002: a "
                      "turntable of --frames cameras)"),
        integer_option("subdivisions", 1, 0, 5, "Icosahedron subdivisions: 20 x 4^k views (1 = 80, chosen by measurement)"),
        integer_option("frames", 36, 2, 256, "Cameras on the circle (Yamazaki et al. 2002: 36), or per side of the octahedral grids"),
        integer_option("resolution", 512, 16, 4096,
                       "Capture size in pixels (square); unset: 512, or for models with alpha-tested materials up to 1536 "
                       "where their cut-out texture's texels are finer (a texel as fine as the leaf texture's)"),
        integer_option("depth-bits", 16, 8, 16, "Depth precision: 16, or 8 (Yamazaki et al. 2002: 8, which caps it at 256^3)"),
        choice_option("geometry-from", "full", {"full", "simplified", "noisy"},
                      "Voxels and range images from the model, or from a degraded copy (colour always from the model)"),
        number_option("geometry-amount", "0.1", 0.0, 1.0,
                      "Degraded copy: fraction of triangles kept (simplified) or noise amplitude over the radius (noisy)", true),
        flag_option("fill-holes", true, "Fill range-image holes with the 3x3 masked median (Yamazaki et al. 2002 §5.1)"),
        integer_option("page-size", 2048, 256, 16384, "Atlas page size in texels (a multiple of 16)"),
    };
}

std::vector<OptionSpec> render_options()
{
    return {
        choice_option("clip", "ray", {"ray", "seed", "voxel"},
                      "Texturing: ray (the pixel's ray in the voxel against each view's depth), seed (Yamazaki et al. "
                      "2002 eq. 1: texels within W/2 of the facet), voxel (eq. 1 and inside the facet's voxel)"),
        integer_option("views", 4, 1, k_max_blend, "Views blended per facet (1: the paper's nearest view; 4 chosen by measurement)"),
        choice_option("coverage", "vote", {"vote", "any"},
                      "A pixel is covered where the hitting views hold half the weight (vote) or where any view hits"),
        choice_option("facet", "billboard", {"billboard", "fixed", "box"},
                      "Facets: squares of side sqrt(3) W facing the eye (the paper), fixed axis-aligned squares (its "
                      "Fig. 8), or the voxel's own faces (box, with --clip ray)"),
        choice_option("select", "lookup", {"lookup", "cone", "all"},
                      "Per-facet view candidates: a direction lookup, the paper's cone (Table 1 row c), or every view (row a)"),
        choice_option("primitive", "auto", {"auto", "quads", "points"},
                      "Quads, points with one colour each (Table 1 row b), or points where facets are smaller than --point-pixels"),
        integer_option("level", -1, -1, k_max_grid_level,
                       "Draw this octree level everywhere (the paper's fixed levels); -1: per node under --pixel-error"),
        number_option("pixel-error", "0", 0.0, 1000.0,
                      "LOD bound on the eq. 2 error in pixels (0: 1, or 4 with --clip ray, which corrects parallax itself)"),
        number_option("point-pixels", "1", 0.0, 64.0, "With --primitive auto: facets narrower than this many pixels are points"),
    };
}

PackageSummary summarise(const Package& base)
{
    const auto& package = reps::package_cast<MicrofacetsPackage>(base);
    const BakeSettings& s = package.settings;
    nlohmann::json levels = nlohmann::json::object();
    for (int level = s.min_level; level <= s.level; ++level)
        levels[std::to_string(1 << level) + "^3"] = package.octree.at(level).size();
    std::uint64_t texels = 0;
    for (const View& v : package.views) texels += std::uint64_t(v.width) * v.height;
    std::uint64_t page_texels = std::uint64_t(s.page_size) * s.page_size * package.color_pages.size();
    // colour (and ORM + emission for PBR models) RGBA8 with mips, normal-depth RGBA16
    std::uint64_t gpu_bytes = page_texels * 4 * 4 / 3 * (package.has_pbr() ? 3 : 1) + page_texels * 8;
    PackageSummary summary;
    summary.details = {{"source", package.source.file_name},
                       {"facets_per_level", levels},
                       {"layout", s.layout},
                       {"views", package.views.size()},
                       {"resolution", s.resolution},
                       {"depth_bits", s.depth_bits},
                       {"pbr_pages", package.has_pbr()},
                       {"geometry_from", s.geometry_from},
                       {"max_view_angle_degrees", glm::degrees(package.max_view_angle)},
                       {"pages", package.color_pages.size()},
                       {"page_size", s.page_size},
                       {"crop_texels", texels},
                       {"gpu_texture_bytes", gpu_bytes}};
    char line[240];
    std::snprintf(line, sizeof line, "%zu voxels at %d^3 (levels %d^3..%d^3), %zu %s views of %d px in %zu page%s of %d, %.0f MiB on the GPU",
                  package.octree.at(s.level).size(), 1 << s.level, 1 << s.min_level, 1 << s.level, package.views.size(),
                  s.layout.c_str(), s.resolution, package.color_pages.size(), package.color_pages.size() == 1 ? "" : "s",
                  s.page_size, double(gpu_bytes) / (1 << 20));
    summary.headline = line;
    return summary;
}

} // namespace

BakeSettings settings_from(const Options& parameters)
{
    BakeSettings s;
    s.level = parameters.integer("level");
    s.min_level = parameters.integer("min-level");
    s.layout = parameters.choice("layout");
    s.subdivisions = parameters.integer("subdivisions");
    s.frames = parameters.integer("frames");
    s.resolution = parameters.integer("resolution");
    s.depth_bits = parameters.integer("depth-bits");
    s.geometry_from = parameters.choice("geometry-from");
    s.geometry_amount = parameters.number("geometry-amount");
    s.fill_holes = parameters.flag("fill-holes");
    s.page_size = parameters.integer("page-size");
    return s;
}

Status check_settings(const BakeSettings& s)
{
    if (s.min_level > s.level)
        return error(StatusCode::invalid_argument, "--min-level: " + std::to_string(s.min_level) + " is above --level " +
                                                       std::to_string(s.level));
    if (s.depth_bits != 8 && s.depth_bits != 16)
        return error(StatusCode::invalid_argument, "--depth-bits: must be 8 or 16, not " + std::to_string(s.depth_bits));
    if (s.page_size % reps::k_cell != 0)
        return error(StatusCode::invalid_argument, "--page-size: must be a multiple of " + std::to_string(reps::k_cell));
    if (s.resolution + 2 * reps::k_cell > s.page_size)
        return error(StatusCode::invalid_argument, "--page-size: must exceed --resolution by two cells");
    return Status::ok();
}

Representation registration()
{
    return {.name = "microfacets",
            .title = "Microfacets",
            .description = "facets at the occupied voxels of an octree, textured from the nearest captured views where "
                           "their depth says the surface lies",
            .reference = "Yamazaki, Sagawa, Kawasaki, Ikeuchi & Sakauchi 2002",
            .bake_options = bake_options(),
            .render_options = render_options(),
            .debug_views = {DebugView::parts, DebugView::depth, DebugView::normal, DebugView::fetches, DebugView::proxies,
                            DebugView::level},
            .bench_variants = {},
            .bake = bake,
            .write = write,
            .read = read,
            .make_renderer = make_renderer,
            .summarise = summarise,
            .export_options = export_options(),
            .export_scene = export_scene};
}

} // namespace standin::microfacets
