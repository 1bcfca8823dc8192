// The enhanced billboards as the registry sees them: their bake parameters and run-time options
// (declared once: the command line, --help, the viewer, the manifest's "bake" block and its
// validation all come from these tables), debug views, and the summary `standin info` prints.
#include "reps/enhanced_billboards/acceleration.h"
#include "reps/enhanced_billboards/billboards.h"
#include "reps/common/package_cast.h"

#include <algorithm>
#include <cstdio>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin::billboards {

namespace {

std::vector<OptionSpec> bake_options()
{
    return {
        integer_option("resolution", 512, 16, k_max_grid_texels,
                       "Texels along the bounding-box diagonal (Vichitvejpaisal 2005: 512); unset: 512; 1024 for "
                       "models with detail finer than 512 texels resolve (over 22% of the covered texels end a "
                       "surface); for models with alpha-tested materials 1024, or up to 2048 where their cut-out "
                       "texture's texels are finer (a texel as fine as the leaf texture's)"),
        number_option("texel-size", "", 0.0, 3.0e38, "World units per texel, instead of --resolution", true),
        choice_option("directions", "seed", {"seed", "sphere", "axis"},
                      "Candidate directions: seed (36 x 18 around the model), sphere (even Fibonacci set), axis "
                      "(+-X, +-Y, +-Z)"),
        integer_option("direction-count", k_default_direction_count, 6, 100000,
                       "Number of directions of --directions sphere"),
        choice_option("score", "area", {"area", "faces"},
                      "Direction score: area (the area a capture really takes) or faces (the paper: facing faces)"),
        number_option("depth-limit", "1", 0.0, 2.0,
                      "Depth of a billboard as a fraction of the bounding-box diagonal (1: the whole model)", true),
        number_option("grazing-angle", "20", 0.0, 89.0,
                      "Faces within this angle (degrees) of the projection direction are left for another billboard; "
                      "unset: 20, or 30 for models with alpha-tested materials (the seed: 10; chosen by measurement: "
                      "squarer captures, fewer fetches, ~15% more texels)"),
        number_option("partly-hidden", "", 0.0, 1.0,
                      "A face that others hide at some of its texels is captured at the texels where it is in front "
                      "when at least this fraction of them are (0: never, the seed's test, the face waits for a "
                      "direction that sees all of it); unset: 0.5 for models with alpha-tested materials (a dense "
                      "crown hides part of every leaf from every direction), else 0 (solid models lost more by the "
                      "hidden parts than fewer billboards gave them: docs/RESULTS.md \"Partly hidden leaves\")"),
        number_option("split-budget", "", 0.0, 1000.0,
                      "Models with alpha-tested materials: the most faces, in millions, that the cards the greedy "
                      "leaves may be split into for its second round (8-texel edges, else 11.3; 0: no second "
                      "round); unset: 16 for such models, 0 for others. A million faces costs about 0.2 GB of "
                      "bake memory; a 200,000-card tree needs about 33 for 8 texels: 40 baked it in 8.6 GB (docs/RESULTS.md)"),
        integer_option("max-billboards", 64, 1, 4096, "Stop after this many billboards"),
        number_option("min-coverage", "0.001", 0.0, 1.0,
                      "Stop when the next billboard would capture less than this fraction of the surface found so far "
                      "(itself included: what no direction shows, such as a dense crown's inside, does not count)"),
        integer_option("depth-bits", 16, 8, 16,
                       "Depth precision: 16, or 8 (the paper: the alpha channel of an 8-bit image)"),
        choice_option("compression", "bc", {"bc", "none"},
                      "Maps in the package: bc (BC5 octahedral normals in KTX2 files, exact depth as grey PNG, "
                      "colour PNG) or none (PNG only, the seed's images)"),
        number_option("coarse-ratio", "0.1", 0.0, 1.0,
                      "Triangles of the coarse hole-filling mesh relative to the model (0: none), or more where that "
                      "many would stray further than a texel from it; models with alpha-tested materials: of their "
                      "opaque faces only"),
        choice_option("sheet-edges", "auto", {"auto", "centre", "clip", "overlap"},
                      "Texels an outline crosses (a surface's silhouette as the billboard sees it, the edge of an "
                      "open surface, a leaf's cut-out contour): centre (covered where the texel centre is on the "
                      "surface: the seed's), clip (the outline's line is stored in the texel and the march clips "
                      "to it; texels beyond that the surface reaches into are added and clipped the same way), "
                      "overlap (a sheet's every rim texel, unclipped: more spill; elsewhere centre) or auto (clip; "
                      "the package records which)"),
        choice_option("face-assignment", "first", {"first", "squarer"},
                      "Which of the chosen billboards holds a face: first (the first that can: the seed's greedy) or "
                      "squarer (a face the first would see more than 45 degrees off its normal waits for a later "
                      "billboard that sees it more squarely, whose texels rays meet closer to the surface: thesis "
                      "Luv up to 29% lower and 20% fewer fetches, for 9-41% more package bytes and 1.7-3.1x the "
                      "bake time; the detail rule may then pick finer texels, --resolution keeps them; "
                      "docs/RESULTS.md)"),
        choice_option("back-hits", "auto", {"auto", "show", "hide"},
                      "Rays meeting a billboard's surface from behind: show (drawn where nothing nearer is, as the "
                      "back of a double-sided sheet, or the inside of a part through a seam), hide (dropped, and "
                      "the coarse mesh's back faces culled: the truth culls the backs of single-sided faces; for "
                      "scenes with single-sided ground planes or sheets seen from behind) or auto (hide where over "
                      "0.1% of the model's area is single-sided faces whose backs can be seen from outside, "
                      "else show; the package records which)"),
    };
}

std::vector<OptionSpec> render_options()
{
    return {
        choice_option("march", "exact", {"exact", "seed"},
                      "Ray march: exact (height-field crossing, independent of step size) or seed (the paper's "
                      "linear march with a hit range, Vichitvejpaisal 2005 §3.3)"),
        integer_option("steps", 100, 1, 10000, "Seed march: steps along the box diagonal"),
        number_option("hit-range", "0.01", 0.0, 1.0,
                      "Seed march: hit range e as a fraction of the box depth (0.02 fills holes)", true),
        flag_option("coarse", true, "Fill holes with the package's coarse mesh"),
        choice_option("coarse-fill", "empty", {"empty", "near-misses"},
                      "Where the coarse mesh fills: empty (every pixel without a billboard's front hit, as the "
                      "paper draws it, Vichitvejpaisal 2005 §3.4: also surfaces no billboard captured) or "
                      "near-misses (only pixels where a ray came within a texel of a surface and missed: an "
                      "outline that cannot grow where the coarse mesh lies outside the model)"),
        choice_option("cull-back-proxies", "auto", {"auto", "on", "off"},
                      "Leave out proxy boxes whose texels' normals all face away from the eye, which can draw only "
                      "back hits (a scan's stand-in 25-35% and its crowd about 20% less CPU on llvmpipe): auto does "
                      "for packages of one closed surface, whose picture it keeps, and of one part whose backs face "
                      "its own inside (a scan with small openings: +0.004 Luv); on also for others, where open "
                      "sheets and the seams between parts lose the backs that showed (up to +0.3 Luv, docs/RESULTS.md)"),
        choice_option("coarse-lod", "on", {"on", "off"},
                      "The coarse mesh on instances smaller on screen: on draws the coarsest of its levels (a "
                      "quarter of the triangles each) within half a pixel of it (crowds of 1000 copies of a "
                      "252k-face head and of a 110k-face engine 10-20% less CPU on llvmpipe, docs/RESULTS.md); off "
                      "draws the bake's mesh everywhere, as the paper does. Not with --coarse-fill near-misses"),
        choice_option("cull-hidden-proxies", "on", {"on", "off"},
                      "Leave out proxy boxes that hold no nearest hit from the eye's direction: hidden behind "
                      "others from every corner of its cell of view directions (an octahedral grid of 16 x 16), found "
                      "on first need from a depth buffer of the texels (docs/RESULTS.md); the coarse tiles and "
                      "whole boxes of small instances cut to the tiles that show; not with --coarse-fill "
                      "near-misses, and not for an instance the eye is inside the bounding sphere of"),
        choice_option("depth-batches", "auto", {"auto", "off"},
                      "Crowds: instances sorted front to back are drawn in batches (8, then up to 4x more), each "
                      "after the first with its boxes' depth test before the shader, against the batches drawn "
                      "before it (the same picture; 1000 copies of a scan 15-30% less CPU on llvmpipe, "
                      "docs/RESULTS.md): auto does on software rasterisers, which test depth after a shader that "
                      "writes it (GPUs test first already), but not with --coarse-fill near-misses"),
        flag_option("tile-layers", true,
                    "Split a tile's proxy box into one box per depth layer where nested parts lie apart (the same "
                    "picture as one box per tile, with fewer fragments and fetches)"),
        choice_option("color-filter", "footprint", {"footprint", "texel"},
                      "Colour where a pixel covers several texels: footprint (the mean of the texels of one surface "
                      "under the pixel, as the model's textures are filtered by their mip maps) or texel (the hit "
                      "texel's: the paper's, noisier as the stand-in shrinks)"),
    };
}

PackageSummary summarise(const Package& base)
{
    const auto& package = reps::package_cast<EnhancedBillboardsPackage>(base);
    double total = package.area_total > 0.0 ? package.area_total : 1.0;
    nlohmann::json left_fraction = nlohmann::json::object(), left_faces = nlohmann::json::object();
    for (const auto& [reason, what] : package.left) {
        left_fraction[reason] = what.area / total;
        left_faces[reason] = what.faces;
    }
    std::uint64_t texels = 0;
    nlohmann::json sizes = nlohmann::json::array();
    for (const Billboard& b : package.billboards) {
        texels += std::uint64_t(b.width) * b.height;
        sizes.push_back({b.width, b.height});
    }
    double captured = std::min(1.0, package.area_captured / total);
    PackageSummary summary;
    summary.details = {{"source", package.source.file_name},
                       {"billboards", package.billboards.size()},
                       {"billboard_sizes", sizes},
                       {"texels", texels},
                       {"texel_size", package.settings.texel_size},
                       {"depth_bits", package.settings.depth_bits},
                       {"directions", package.settings.directions},
                       {"faces_total", package.faces_total},
                       {"area_total", package.area_total},
                       {"area_captured_fraction", captured},
                       {"area_left_fraction", left_fraction},
                       {"faces_left", left_faces},
                       {"coarse_mesh_triangles", package.coarse_mesh.triangle_count()}};
    char line[160];
    std::snprintf(line, sizeof line, "%zu billboards", package.billboards.size());
    summary.headline = line;
    if (package.coarse_mesh.triangle_count() > 0)
        summary.headline += " + " + std::to_string(package.coarse_mesh.triangle_count()) + "-triangle coarse mesh";
    std::snprintf(line, sizeof line, ", %.2f%% of the area captured", 100.0 * captured);
    summary.headline += line;
    // what the renderer's texture arrays take (acceleration.h gpu_layout: the layers as packed
    // where GL allows 8192-texel layers)
    const std::uint64_t gpu_bytes = gpu_texture_bytes(gpu_layout(package.billboards), has_pbr_maps(package.billboards));
    summary.details["gpu_texture_bytes"] = gpu_bytes;
    std::snprintf(line, sizeof line, ", %.0f MiB on the GPU", double(gpu_bytes) / double(1 << 20));
    summary.headline += line;
    return summary;
}

} // namespace

BakeSettings settings_from(const Options& parameters)
{
    BakeSettings s;
    s.resolution = parameters.integer("resolution");
    s.texel_size = parameters.number("texel-size");
    s.directions = parameters.choice("directions");
    s.direction_count = parameters.integer("direction-count");
    s.score = parameters.choice("score");
    s.depth_limit = parameters.number("depth-limit");
    s.grazing_angle = parameters.number("grazing-angle");
    s.partly_hidden = parameters.number("partly-hidden");
    s.split_budget = parameters.number("split-budget");
    s.max_billboards = parameters.integer("max-billboards");
    s.min_coverage = parameters.number("min-coverage");
    s.depth_bits = parameters.integer("depth-bits");
    s.coarse_ratio = parameters.number("coarse-ratio");
    s.compression = parameters.choice("compression");
    s.sheet_edges = parameters.choice("sheet-edges");
    s.back_hits = parameters.choice("back-hits");
    s.face_assignment = parameters.choice("face-assignment");
    return s;
}

Representation registration()
{
    OptionValues no_coarse;
    no_coarse.set("coarse", "off");
    return {.name = "enhanced-billboards",
            .title = "Enhanced billboards",
            .description = "greedy orthographic billboards with colour, coverage, normal and depth, ray-cast per "
                           "pixel over their boxes, holes filled by a coarse mesh",
            .reference = "Vichitvejpaisal 2005; Vichitvejpaisal & Kanongchaiyos 2006",
            .bake_options = bake_options(),
            .render_options = render_options(),
            .debug_views = {DebugView::parts, DebugView::depth, DebugView::normal, DebugView::fetches, DebugView::proxies},
            .bench_variants = {no_coarse},
            .bake = bake,
            .write = write,
            .read = read,
            .make_renderer = make_renderer,
            .summarise = summarise,
            .export_scene = export_scene};
}

} // namespace standin::billboards
