// Baking microfacets.
// Yamazaki et al. 2002 §3.1 ModelingProcess: approximate the geometry by voxels (§3.2.2), build the
// multiresolution octree (§3.2.3), and generate the texture images: colour and a range image per
// camera (§3.2.4), with the range images' holes filled (§5.1).
// Steps:
//  1. read the settings (alpha-tested models without --resolution: captures as fine as their leaf
//     texture, up to k_alpha_max_resolution); with `geometry-from` the voxels and range images come
//     from a degraded copy of the model (sloppy-simplified, or displaced by noise), colour from the
//     full model: the paper's premise (a scan worse than its photographs), which standin's exact
//     meshes lack;
//  2. voxelise the finest level, coarsen to min_level (voxels.cpp);
//  3. per capture direction (the view atlas's sphere layouts, or the seed's turntable circle):
//     colour, normal and range images (capture.cpp); fill the range image's holes where the colour
//     saw surface; quantise depth to 16 (or 8) bits; crop to the covered texels in whole cells;
//     PBR models (issue #14) also get the ORM and emission of the same texels; alpha-tested models
//     (issue #14) may be captured at k_coverage_samples^2 samples per texel, so a texel's alpha is
//     the fraction of it covered (reps/common/coverage_capture.h; 1 by default, microfacets.h);
//  4. pack the crops into pages (reps::pack_views) and copy them in.
// Differences from the paper: no alpha matting (§5.2: synthetic captures have exact coverage; the
// supersampled coverage of alpha-tested models stands for the paper's matted alpha at edges);
// orthographic cameras (depth along the view is then affine over a facet, so eq. 1 is exact per
// texel); 16-bit depth by default (the paper's 8 bits cap it at 256^3, §6.2).
#include "reps/microfacets/capture.h"
#include "reps/microfacets/lod.h"
#include "reps/microfacets/microfacets.h"

#include "gpu/gl.h"
#include "reps/common/coverage_capture.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace standin::microfacets {

namespace {

// A hash of a vertex index in [-1, 1], the same on every run.
float vertex_noise(std::uint32_t index)
{
    std::uint32_t h = index * 0x9E3779B1u;
    h ^= h >> 15;
    h *= 0x85EBCA77u;
    h ^= h >> 13;
    h *= 0xC2B2AE3Du;
    h ^= h >> 16;
    return float(h >> 8) * (2.0f / 16777215.0f) - 1.0f;
}

// Step 1: the incomplete scan of the experiment. "simplified" keeps geometry_amount of the
// triangles with meshoptimizer's sloppy simplifier, which leaves gaps; "noisy" moves every vertex
// along its normal by up to geometry_amount * radius.
Mesh degraded_geometry(const Mesh& mesh, const BakeSettings& s)
{
    Mesh copy = mesh;
    if (s.geometry_from == "simplified") {
        std::size_t target = std::max<std::size_t>(3, std::size_t(double(mesh.indices.size()) * s.geometry_amount) / 3 * 3);
        std::vector<std::uint32_t> kept(mesh.indices.size());
        std::size_t count = meshopt_simplifySloppy(kept.data(), mesh.indices.data(), mesh.indices.size(),
                                                   &mesh.positions[0].x, mesh.vertex_count(), sizeof(glm::vec3), target, 1.0f);
        kept.resize(count);
        copy.indices = std::move(kept);
        copy.face_materials.assign(copy.indices.size() / 3, 0u);
        copy.materials.resize(1);
        copy.uvs.clear();
        copy.textures.clear();
        for (Material& m : copy.materials) m.base_color_texture = -1;
    } else if (s.geometry_from == "noisy") {
        float amplitude = s.geometry_amount * mesh.bounding_sphere().radius;
        for (std::size_t v = 0; v < copy.positions.size(); ++v)
            copy.positions[v] += copy.normals[v] * (amplitude * vertex_noise(std::uint32_t(v)));
    }
    return copy;
}

// A view's images after step 3, cropped.
struct Crop {
    ImageRGBA8 color;
    ImageRGBA8 orm, emission; // PBR models only
    ImageRGBA16 normal_depth;
};

// Step 3 for one capture: fill holes, quantise, crop. A texel is covered where the colour saw
// surface and the range image has a depth (after filling); elsewhere every channel is 0.
Crop encode_and_crop(SurfaceCapture& capture, const BakeSettings& s, float radius, bool degraded, bool fractional, View& view)
{
    const int n = capture.albedo.width;
    if (degraded && s.fill_holes) {
        std::vector<std::uint8_t> fillable(std::size_t(n) * n);
        for (std::size_t p = 0; p < fillable.size(); ++p) fillable[p] = capture.albedo.pixels[4 * p + 3] != 0;
        fill_range_holes(capture.range, fillable);
    }
    auto covered = [&](int x, int y) {
        std::size_t p = std::size_t(y) * n + x;
        return capture.albedo.pixels[4 * p + 3] != 0 && capture.range.valid[p];
    };
    int x0 = n, y0 = n, x1 = -1, y1 = -1;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if (covered(x, y)) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    view.direction = capture.direction;
    view.axis_u = capture.axis_u;
    view.axis_v = capture.axis_v;
    Crop crop;
    if (x1 < 0) return crop; // nothing seen: width 0
    const int cell = reps::k_cell;
    view.crop_x = x0 - 1;
    view.crop_y = y0 - 1;
    view.width = (x1 - x0 + 3 + cell - 1) / cell * cell;
    view.height = (y1 - y0 + 3 + cell - 1) / cell * cell;
    crop.color = ImageRGBA8(view.width, view.height);
    crop.normal_depth = ImageRGBA16(view.width, view.height);
    const bool pbr = !capture.material.orm.empty();
    if (pbr) crop.orm = ImageRGBA8(view.width, view.height), crop.emission = ImageRGBA8(view.width, view.height);
    const float depth_levels = s.depth_bits == 8 ? 255.0f : 65535.0f;
    const std::uint16_t depth_scale = s.depth_bits == 8 ? 257 : 1; // 8-bit codes stored as 16-bit
    for (int y = 0; y < view.height; ++y)
        for (int x = 0; x < view.width; ++x) {
            int sx = view.crop_x + x, sy = view.crop_y + y;
            if (sx < 0 || sy < 0 || sx >= n || sy >= n || !covered(sx, sy)) continue;
            std::size_t p = std::size_t(sy) * n + sx;
            std::memcpy(crop.color.at(x, y), capture.albedo.at(sx, sy), 3);
            // alpha: 255, or with coverage samples (alpha-tested models) the covered fraction
            crop.color.at(x, y)[3] = fractional ? capture.albedo.at(sx, sy)[3] : std::uint8_t(255);
            if (pbr) reps::copy_material_texel(capture.material, sx, sy, crop.orm, crop.emission, x, y);
            std::uint16_t* nd = crop.normal_depth.at(x, y);
            // the capture's 8-bit normal expanded to 16 bits (reps::SurfaceImage's encoding, n * 0.5 +
            // 0.5); never 0: a zero normal means "empty"
            for (int c = 0; c < 3; ++c) nd[c] = std::uint16_t(std::max<int>(capture.normal.at(sx, sy)[c], 1) * 257);
            float depth = (radius - capture.range.depth[p]) / (2.0f * radius); // 0 nearest the camera
            nd[3] = std::uint16_t(std::lround(std::clamp(depth, 0.0f, 1.0f) * depth_levels) * depth_scale);
        }
    return crop;
}

template <typename Image>
void copy_into_page(const Image& crop, Image& page, int x, int y)
{
    for (int row = 0; row < crop.height; ++row)
        std::copy_n(crop.at(0, row), std::size_t(crop.width) * 4, page.at(x, y + row));
}

} // namespace

std::vector<glm::vec3> capture_directions(const BakeSettings& settings)
{
    if (settings.layout != "circle") return reps::layout_directions(settings.layout, settings.subdivisions, settings.frames);
    std::vector<glm::vec3> directions;
    for (int k = 0; k < settings.frames; ++k) directions.push_back(direction_from_angles(360.0f * float(k) / float(settings.frames), 0.0f));
    return directions;
}

// Step 1 for alpha-tested models without --resolution (issue #14): captures whose texel is as fine
// as a texel of the leaf texture (reps::cutout_texel_size), between the default and
// k_alpha_max_resolution, within the page. Leaf-over-leaf edges need it: the generated tree's
// foliage Luv at distance 1 falls 5.07 -> 3.52 -> 3.25 from 512 to 1024 to 1536 (docs/RESULTS.md).
Options with_cutout_resolution(const Mesh& mesh, float radius, Options parameters)
{
    const double texel = reps::cutout_texel_size(mesh); // 0 without textured cut-outs
    if (parameters.given("resolution") || !(texel > 0.0)) return parameters;
    const int largest = std::min(k_alpha_max_resolution, parameters.integer("page-size") - 2 * reps::k_cell);
    const int fine = int(std::min(std::ceil(2.0 * double(radius) / texel), double(largest)));
    if (fine > parameters.integer("resolution")) parameters.set_integer("resolution", fine);
    return parameters;
}

namespace {

// Each view's extent on its capture plane (u min, u max, v min, v max, object units from the
// centre): the model's vertices projected, which bound every texel the capture can cover.
std::vector<glm::vec4> view_extents(const Mesh& mesh, const BoundingSphere& sphere, const std::vector<glm::vec3>& directions)
{
    std::vector<glm::vec4> extents;
    for (glm::vec3 direction : directions) {
        glm::vec3 axis_u, axis_v;
        capture_axes(sphere, direction, axis_u, axis_v);
        glm::vec4 e(std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
                    -std::numeric_limits<float>::max());
        for (const glm::vec3& p : mesh.positions) {
            const float u = glm::dot(p - sphere.center, axis_u), v = glm::dot(p - sphere.center, axis_v);
            e = glm::vec4(std::min(e.x, u), std::max(e.y, u), std::min(e.z, v), std::max(e.w, v));
        }
        extents.push_back(e);
    }
    return extents;
}

// The crops' sizes at `resolution` from their extents, with encode_and_crop's margin and cells.
std::vector<View> crops_of(const std::vector<glm::vec4>& extents, float radius, int resolution, int page_size)
{
    const int cell = reps::k_cell;
    auto pixel = [&](float plane) {
        return std::clamp(int(std::floor((plane + radius) / (2.0f * radius) * float(resolution))), 0, resolution - 1);
    };
    std::vector<View> views(extents.size());
    for (std::size_t k = 0; k < extents.size(); ++k) {
        const glm::vec4& e = extents[k];
        views[k].width = std::min((pixel(e.y) - pixel(e.x) + 3 + cell - 1) / cell * cell, page_size);
        views[k].height = std::min((pixel(e.w) - pixel(e.z) + 3 + cell - 1) / cell * cell, page_size);
    }
    return views;
}

} // namespace

std::vector<View> estimated_crops(const Mesh& mesh, const BoundingSphere& sphere, const std::vector<glm::vec3>& directions,
                                  int resolution, int page_size)
{
    return crops_of(view_extents(mesh, sphere, directions), sphere.radius, resolution, page_size);
}

// Step 1 (continued): a model whose views its cut-out texture's rule fills (a textured box with
// cut-outs) needed 67 pages of 2048^2 at 1536 px, twice what the renderer takes: the package was
// written and could not be drawn. The estimate packs crops no smaller than the real ones as
// reps::pack_views packs those (shelf packing is not strictly monotone in the crops' sizes, so the
// bake checks the real pages again and refuses, rather than writes, a package over the budget).
int fitting_resolution(const Mesh& mesh, const BoundingSphere& sphere, const std::vector<glm::vec3>& directions,
                       int resolution, int floor_resolution, int page_size)
{
    const int budget = budget_pages(page_size);
    const std::vector<glm::vec4> extents = view_extents(mesh, sphere, directions);
    auto pages = [&](int r) {
        std::vector<View> views = crops_of(extents, sphere.radius, r, page_size);
        return reps::pack_views(views, page_size);
    };
    while (resolution > floor_resolution && pages(resolution) > budget)
        resolution = std::max(floor_resolution, resolution * 15 / 16);
    return resolution;
}

Result<std::unique_ptr<Package>> bake(const BakeContext& context)
{
    const BoundingSphere sphere = context.mesh.bounding_sphere();
    Options parameters = with_cutout_resolution(context.mesh, sphere.radius, context.parameters);
    BakeSettings s = settings_from(parameters);
    if (s.resolution > context.parameters.integer("resolution") && context.mesh.positions.size() > 0) {
        const int fitting = fitting_resolution(context.mesh, sphere, capture_directions(s), s.resolution,
                                               context.parameters.integer("resolution"), s.page_size);
        if (fitting != s.resolution) {
            parameters.set_integer("resolution", fitting);
            s = settings_from(parameters);
        }
    }
    STANDIN_RETURN_IF_ERROR(check_settings(s));
    STANDIN_RETURN_IF_ERROR(validate_mesh(context.mesh, "microfacets"));
    const bool degraded = s.geometry_from != "full";
    Mesh geometry = degraded ? degraded_geometry(context.mesh, s) : Mesh{};
    const Mesh& voxel_source = degraded ? geometry : context.mesh;

    auto package = std::make_unique<MicrofacetsPackage>();
    package->source = context.source;
    package->parameters = parameters;
    package->settings = s;
    package->center = sphere.center;
    package->radius = sphere.radius;

    // voxels: the finest level, then the coarser ones
    context.progress.report("microfacets: voxelising", 0.0);
    package->octree = build_octree(voxel_source, grid_around(context.mesh.bounds()), s.min_level, s.level);
    context.progress.report("microfacets: voxelising", 1.0);

    // the bake renders on the GPU: use the current context or make one for the bake
    std::unique_ptr<GpuContext> own_context;
    if (!gpu::has_current_context()) {
        Result<std::unique_ptr<GpuContext>> made = create_headless_context();
        if (!made) return made.status();
        own_context = std::move(*made);
    }
    const int samples = reps::coverage_samples(context.mesh, s.resolution, k_coverage_samples, "STANDIN_MICROFACETS_COVERAGE_SAMPLES");
    Result<std::unique_ptr<SurfaceCapturer>> capturer =
        SurfaceCapturer::create(context.mesh, degraded ? &geometry : nullptr, sphere, s.resolution, samples);
    if (!capturer) return capturer.status();

    // capture, fill, quantise and crop every view
    std::vector<glm::vec3> directions = capture_directions(s);
    package->max_view_angle = max_view_angle(directions, s.layout == "circle");
    std::vector<Crop> crops(directions.size());
    package->views.resize(directions.size());
    for (std::size_t k = 0; k < directions.size(); ++k) {
        Result<SurfaceCapture> capture = (*capturer)->capture(directions[k]);
        if (!capture) return capture.status();
        crops[k] = encode_and_crop(*capture, s, sphere.radius, degraded, samples > 1, package->views[k]);
        context.progress.report("microfacets: capturing views", double(k + 1) / double(directions.size()));
    }

    // pack the crops into pages, a page at a time, each crop freed once copied: the bake's peak is the
    // crops and one page, not the crops and every page (1536^2 captures of a tree: 1.86 -> 1.35 GB)
    int pages = reps::pack_views(package->views, s.page_size);
    // a package the renderer would refuse is not written (an explicit --resolution or view count)
    if (pages > budget_pages(s.page_size))
        return error(StatusCode::invalid_argument,
                     "microfacets: " + std::to_string(directions.size()) + " views of " + std::to_string(s.resolution) +
                         " px need " + std::to_string(pages) + " pages of " + std::to_string(s.page_size) + "^2, more than the " +
                         std::to_string(budget_pages(s.page_size)) +
                         " one texture array holds: bake with a lower --resolution or fewer views (--subdivisions)");
    const bool pbr = context.mesh.has_pbr_materials();
    package->color_pages.resize(std::size_t(pages));
    package->normal_depth_pages.resize(std::size_t(pages));
    if (pbr) {
        package->orm_pages.resize(std::size_t(pages));
        package->emission_pages.resize(std::size_t(pages));
    }
    for (int page = 0; page < pages; ++page) {
        const auto p = std::size_t(page);
        package->color_pages[p] = ImageRGBA8(s.page_size, s.page_size);
        package->normal_depth_pages[p] = ImageRGBA16(s.page_size, s.page_size);
        if (pbr) {
            package->orm_pages[p] = ImageRGBA8(s.page_size, s.page_size);
            package->emission_pages[p] = ImageRGBA8(s.page_size, s.page_size);
        }
        for (std::size_t k = 0; k < package->views.size(); ++k) {
            const View& v = package->views[k];
            if (v.width == 0 || v.page != page) continue;
            copy_into_page(crops[k].color, package->color_pages[p], v.atlas_x, v.atlas_y);
            copy_into_page(crops[k].normal_depth, package->normal_depth_pages[p], v.atlas_x, v.atlas_y);
            if (pbr) {
                copy_into_page(crops[k].orm, package->orm_pages[p], v.atlas_x, v.atlas_y);
                copy_into_page(crops[k].emission, package->emission_pages[p], v.atlas_x, v.atlas_y);
            }
            crops[k] = Crop{};
        }
    }
    return std::unique_ptr<Package>(std::move(package));
}

} // namespace standin::microfacets
