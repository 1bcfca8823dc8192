// The view atlas as the registry sees it: its bake parameters and run-time options (declared once:
// the command line, --help, the viewer, the manifest's "bake" block and its validation all come
// from these tables), debug views, and the summary `standin info` prints.
#include "reps/view_atlas/view_atlas.h"
#include "reps/common/package_cast.h"

#include <cstdio>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin::view_atlas {

namespace {

std::vector<OptionSpec> bake_options()
{
    return {
        choice_option("layout", "icosahedral", {"icosahedral", "octahedral", "hemi-octahedral"},
                      "View directions: icosahedral (Saraiva et al.: face centres of a subdivided icosahedron), "
                      "octahedral or hemi-octahedral grids (impostor bakers)"),
        integer_option("subdivisions", 2, 0, 5,
                       "Icosahedron subdivisions: 20 x 4^k views (2 = 320, chosen by measurement; Saraiva et al.: 4)"),
        integer_option("frames", 16, 2, 64, "Frames per side of the (hemi-)octahedral grid"),
        choice_option("projection", "ortho", {"ortho", "perspective"},
                      "Capture projection: ortho, or perspective from the base distance"),
        number_option("fov", "40", 1.0, 170.0, "Field of view of perspective captures, degrees"),
        integer_option("resolution", 256, 16, 4096,
                       "Capture size in pixels (square); unset: 256, or 512 for models with alpha-tested materials or with "
                       "detail finer than 256 px captures resolve (over 15% of the captured texels end a surface)"),
        choice_option("maps", "surface", {"surface", "lit"},
                      "surface: albedo, normal and depth, lit at run time; lit: shaded colour only (the paper)"),
        integer_option("page-size", 2048, 256, 16384, "Atlas page size in texels (a multiple of 16)"),
        choice_option("compression", "bc", {"bc", "none", "bc-color"},
                      "Pages in the package: bc (BC5 octahedral normals in KTX2 files, exact depth as grey PNG, "
                      "colour PNG; -29% bytes, +0.05-0.09 Luv, docs/RESULTS.md), none (PNG), bc-color (bc, colour "
                      "as the DXT5 blocks --texture-format bc3 uploads, mip levels included)"),
        integer_option("depth-bits", 0, 0, 16,
                       "Depth precision (surface maps), bits over the model's diameter, 8..16; 0: 10 for captures of "
                       "512 px or more (a step of half their texel: closer surfaces stay apart), 8 under (a step of "
                       "one 256 px texel; packages before it: 8). Each 2 bits: about +25% package, and over 8 the "
                       "normal-depth pages take twice the GPU memory (docs/RESULTS.md)"),
    };
}

std::vector<OptionSpec> render_options()
{
    return {
        choice_option("style", "corrected", {"corrected", "octahedral-baseline", "seed"},
                      "corrected: 3 views blended, each intersected per pixel with its depth; octahedral-baseline: "
                      "3 views, one parallax step (impostor bakers); seed: the nearest view, no correction"),
        number_option("seed-below", "8", 0.0, 1.0e6,
                      "Corrected style, level of detail: an instance whose bounding sphere is under this many "
                      "pixels in radius is drawn as the seed's nearest view (one quad, no walk; 0: never)"),
        number_option("baseline-below", "0", 0.0, 1.0e6,
                      "Corrected style, level of detail: an instance under this many pixels in radius (and not "
                      "under --seed-below) keeps its hull but is shaded as the octahedral baseline (three views, "
                      "--parallax-steps, no walk; 0: never; 48 for crowds of solid models, docs/RESULTS.md)"),
        integer_option("parallax-steps", 0, 0, 16,
                       "Octahedral baseline (the style, or the corrected style's level under --baseline-below): steps "
                       "from the centre plane to the depth read where the ray met it, then to the depth read there, ... "
                       "(1: the impostor bakers' one step; more: iterative parallax mapping, 2 texture reads per step; "
                       "0: 1 for the style, 3 for the level: nearer the walk it stands for, docs/RESULTS.md)"),
        number_option("hull-above", "80", 0.0, 1.0e6,
                      "Corrected style: an instance at least this many pixels in radius is drawn on the package's "
                      "proxy hull (planes tangent to the model: the fewest fragments), a smaller one on its nearest "
                      "view's crop prism (fewer, larger triangles; llvmpipe shades 4x4 blocks along every edge). 0: "
                      "the hull at every size; 1e6: always the prism (packages baked before the hull have none)"),
        flag_option("early-reject", true,
                    "Stop a fragment before its walk when it lies behind a depth this draw already wrote (the "
                    "picture is the same; llvmpipe runs the shader before its depth test, issue #17)"),
        choice_option("depth-batches", "auto", {"auto", "off"},
                      "Crowds: instances sorted front to back are drawn in batches (8, then up to 4x more), each "
                      "after the first with its depth test before the shader, against the batches drawn before it "
                      "(the same picture; 1000 copies of a scan 20-25% less CPU on llvmpipe, docs/RESULTS.md): auto "
                      "does on software rasterisers, which test depth after a shader that writes it (GPUs test "
                      "first already); needs --early-reject"),
        choice_option("color-level", "auto", {"auto", "mips", "finest"},
                      "Corrected style, colour (and normals) away from the model: mips reads the coverage-respecting "
                      "mip level of the pixel's footprint (filtered: the paper's way); finest reads level 0 at every "
                      "distance, over the hit's own surface (what an alpha-tested truth shows: one leaf per pixel); "
                      "auto: finest for every package (nearer the truth at a distance, and no more flicker under motion "
                      "relative to the truth's than at distance 1; docs/RESULTS.md)"),
        choice_option("texture-format", "rgba8", {"rgba8", "bc3"},
                      "Colour pages on the GPU: rgba8, or bc3 (DXT5 compressed at load: a quarter of the colour "
                      "memory, 5/8 of the total)"),
    };
}

PackageSummary summarise(const Package& base)
{
    const auto& package = reps::package_cast<ViewAtlasPackage>(base);
    const BakeSettings& settings = package.settings;
    std::uint64_t texels = 0;
    for (const View& v : package.views) texels += std::uint64_t(v.width) * v.height;
    std::uint64_t page_texels = std::uint64_t(settings.page_size) * settings.page_size * package.color_pages.size();
    // pages with mips: colour, normal-depth (surface: RGBA16 with 16-bit depth), ORM and emission
    // (PBR models), 4 bytes per texel but the normal-depth pages' 8 with 16-bit depth
    const std::uint64_t normal_depth_bytes = package.has_surface() ? (package.has_fine_depth() ? 8 : 4) : 0;
    const std::uint64_t other_bytes = normal_depth_bytes + (package.has_pbr() ? 8 : 0);
    std::uint64_t gpu_bytes = page_texels * (4 + other_bytes) * 4 / 3;
    // --texture-format bc3: colour pages at one byte per texel (DXT5), the other maps as they were
    std::uint64_t gpu_bytes_bc3 = page_texels * (1 + other_bytes) * 4 / 3;
    PackageSummary summary;
    summary.details = {{"source", package.source.file_name},
                       {"layout", settings.layout},
                       {"views", package.views.size()},
                       {"projection", settings.projection},
                       {"fov", settings.fov},
                       {"resolution", settings.resolution},
                       {"maps", settings.maps},
                       {"compression", settings.compression},
                       {"depth_bits", package.has_surface() ? settings.depth_bits : 0},
                       {"pbr_pages", package.has_pbr()},
                       {"pages", package.color_pages.size()},
                       {"page_size", settings.page_size},
                       {"crop_texels", texels},
                       {"uncropped_texels", std::uint64_t(settings.resolution) * settings.resolution * package.views.size()},
                       {"gpu_texture_bytes", gpu_bytes},
                       {"gpu_texture_bytes_bc3", gpu_bytes_bc3}};
    char line[200];
    std::snprintf(line, sizeof line, "%zu %s views of %d px (%s maps) in %zu page%s of %d, %.0f MiB on the GPU",
                  package.views.size(), settings.layout.c_str(), settings.resolution, settings.maps.c_str(),
                  package.color_pages.size(), package.color_pages.size() == 1 ? "" : "s", settings.page_size,
                  double(gpu_bytes) / (1 << 20));
    summary.headline = line;
    return summary;
}

} // namespace

BakeSettings settings_from(const Options& parameters)
{
    BakeSettings s;
    s.layout = parameters.choice("layout");
    s.subdivisions = parameters.integer("subdivisions");
    s.frames = parameters.integer("frames");
    s.projection = parameters.choice("projection");
    s.fov = parameters.number("fov");
    s.resolution = parameters.integer("resolution");
    s.maps = parameters.choice("maps");
    s.page_size = parameters.integer("page-size");
    s.compression = parameters.choice("compression");
    s.depth_bits = parameters.integer("depth-bits");
    return s;
}

Status check_settings(const BakeSettings& s)
{
    if (s.page_size % k_cell != 0)
        return error(StatusCode::invalid_argument, "--page-size: must be a multiple of " + std::to_string(k_cell));
    if (s.resolution + 2 * k_cell > s.page_size)
        return error(StatusCode::invalid_argument, "--page-size: must exceed --resolution by two cells");
    if (s.depth_bits != 0 && s.depth_bits < 8)
        return error(StatusCode::invalid_argument, "--depth-bits: must be 0 (chosen by the resolution) or 8..16, not " +
                                                       std::to_string(s.depth_bits));
    return Status::ok();
}

Representation registration()
{
    return {.name = "view-atlas",
            .title = "View atlas",
            .description = "a camera-facing proxy textured from many pre-rendered views: the nearest, or three "
                           "blended and intersected per pixel with their depth",
            .reference = "Saraiva, Oliveira, Pereira & Araújo",
            .bake_options = bake_options(),
            .render_options = render_options(),
            .debug_views = {DebugView::parts, DebugView::depth, DebugView::normal, DebugView::fetches},
            .bench_variants = {},
            .bake = bake,
            .write = write,
            .read = read,
            .make_renderer = make_renderer,
            .summarise = summarise,
            .export_options = export_options(),
            .export_scene = export_scene};
}

} // namespace standin::view_atlas
