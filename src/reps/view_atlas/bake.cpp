// Baking a view atlas.
// Saraiva, Oliveira, Pereira & Araújo (§3): render the model from
// the face centres of a subdivided icosahedron, orthographically or with a perspective camera at the
// base distance r / sin(fov/2), lit by the renderer's fixed light; crop every image to its content.
// Steps: choose the directions (layout.cpp); render each view with the ground-truth renderer on the
// GPU (colour, and for "surface" maps the shading normal, from the truth's capture mode, and the
// depth); crop to the covered pixels plus one
// empty texel, padded to whole k_cell cells; pack the crops into pages (layout.cpp); copy them in.
// Differences from the paper:
//  - the icosahedron is turned so that +Y and -Y are face centres (the protocols' pole views);
//  - "surface" maps (default) store albedo, world normal and depth instead of a lit colour, so the
//    renderer can light dynamically and correct parallax (seed §7); "lit" is the paper's image;
//  - PBR models (issue #14, Mesh::has_pbr_materials) also get ORM and emission pages with the same
//    layout, captured from the truth's capture modes (reps/common/material_capture.h), so the
//    renderer relights metals, smooth and occluded surfaces and emission like the truth;
//  - default 320 views (k = 2) of 256² instead of 5120 of 512²: a bunny package stays well under
//    100 MB (docs/RESULTS.md, "View atlas" and "Defaults: views and resolution for the corrected
//    style"); k = 4 and 512 remain options;
//  - models with alpha-tested materials (issue #14) are captured at k_coverage_samples times the
//    resolution per side and box-filtered down (reps/common/coverage_capture.h): a texel's
//    alpha is the fraction of it the alpha-tested surface covers, so that the renderer can place a
//    leaf's cut-out edge inside a texel (atlas.frag, hit_coverage) instead of on texel borders.
//    Other models keep one sample per texel (binary coverage), so their packages do not change.
//    Without --resolution such models are captured at k_alpha_resolution (512) with one sample
//    per texel instead: a leaf's edge, gaps and colour need the texels more than the fractions;
//  - models with detail finer than the default texels (issue #17: nested parts, fins, thin legs) are
//    captured again at k_detail_resolution (512) without --resolution, when over
//    k_detail_edge_fraction of the views' covered texels end their surface (depth_edge_fraction,
//    the billboards' rule): the held-out engine's thesis Luv 4.08 -> 2.37 for 2.8x the package.
#include "reps/view_atlas/view_atlas.h"
#include "reps/view_atlas/hull.h"

#include "gpu/gl.h"
#include "reps/common/coverage_capture.h"
#include "reps/common/material_capture.h"
#include "reps/common/surface_image.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace standin::view_atlas {

namespace {

// The capture camera of a direction: the protocols' orbit camera at distance 1 (so that the view's
// up vector, and with it the camera-relative light, follows the same rule as the evaluation's).
Camera capture_camera(const BoundingSphere& sphere, const BakeSettings& s, glm::vec3 direction)
{
    OrbitView view;
    view.azimuth_degrees = glm::degrees(std::atan2(direction.x, direction.z));
    view.elevation_degrees = glm::degrees(std::asin(std::clamp(direction.y, -1.0f, 1.0f)));
    view.distance_rel = 1.0f;
    view.fov_y_degrees = s.fov;
    view.orthographic = s.projection == "ortho";
    return orbit_camera(sphere, view, 1.0f);
}

// distance along the camera's forward axis of a window depth
float view_depth(const Camera& camera, float window_depth)
{
    float n = camera.near_plane, f = camera.far_plane;
    if (camera.orthographic) return n + window_depth * (f - n);
    float z_ndc = 2.0f * window_depth - 1.0f;
    return 2.0f * n * f / (f + n - z_ndc * (f - n));
}

struct Capture {
    ImageRGBA8 color, normal_depth; // cropped
    std::vector<std::uint16_t> depth; // cropped, row-major: depth codes (depth_bits over 8 only)
    ImageRGBA8 orm, emission;       // cropped, PBR models only
};

// Crops a capture to its covered pixels plus one empty texel, in whole cells.
void crop(const RenderedImage& color, const RenderedImage* normals, const reps::MaterialImages* material,
          const Camera& camera, float eye_distance, const BoundingSphere& sphere, int depth_bits, View& view, Capture& out)
{
    const int n = color.color.width;
    int x0 = n, y0 = n, x1 = -1, y1 = -1;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            if (color.color.at(x, y)[3] != 0) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
    if (x1 < 0) return; // nothing seen
    view.crop_x = x0 - 1;
    view.crop_y = y0 - 1;
    view.width = (x1 - x0 + 3 + k_cell - 1) / k_cell * k_cell;
    view.height = (y1 - y0 + 3 + k_cell - 1) / k_cell * k_cell;
    out.color = ImageRGBA8(view.width, view.height);
    if (normals) out.normal_depth = ImageRGBA8(view.width, view.height);
    const bool depth16 = depth_bits > 8;
    if (normals && depth16) out.depth.assign(std::size_t(view.width) * std::size_t(view.height), 0);
    if (material) out.orm = ImageRGBA8(view.width, view.height), out.emission = ImageRGBA8(view.width, view.height);
    for (int y = 0; y < view.height; ++y) {
        for (int x = 0; x < view.width; ++x) {
            int sx = view.crop_x + x, sy = view.crop_y + y;
            if (sx < 0 || sy < 0 || sx >= n || sy >= n) continue;
            const std::uint8_t* c = color.color.at(sx, sy);
            if (c[3] == 0) continue;
            std::memcpy(out.color.at(x, y), c, 4); // alpha: 255, or the covered fraction (reps::downsample_coverage)
            if (material) reps::copy_material_texel(*material, sx, sy, out.orm, out.emission, x, y);
            if (!normals) continue;
            std::uint8_t* nd = out.normal_depth.at(x, y);
            std::memcpy(nd, normals->color.at(sx, sy), 3);
            // depth: (r - dot(p - centre, direction)) / 2r, 0 nearest the camera
            float along = eye_distance - view_depth(camera, color.depth[std::size_t(sy) * n + sx]);
            float depth = (sphere.radius - along) / (2.0f * sphere.radius);
            if (depth16) { // the 8 bits from the code, as a reader makes them (depth8)
                const std::uint16_t code = depth_code(depth, depth_bits);
                out.depth[std::size_t(y) * std::size_t(view.width) + std::size_t(x)] = code;
                nd[3] = depth8(code, depth_bits);
            } else {
                nd[3] = std::uint8_t(std::lround(std::clamp(depth, 0.0f, 1.0f) * 255.0f));
            }
        }
    }
}

void copy_into_page(const ImageRGBA8& crop, ImageRGBA8& page, int x, int y)
{
    for (int row = 0; row < crop.height; ++row)
        std::memcpy(page.at(x, y + row), crop.at(0, row), std::size_t(crop.width) * 4);
}

} // namespace

// The share of the views' covered texels that end their surface: a 4-neighbour empty, or across a
// depth step the shared link rule (height_field.h) does not join. Such texels are where the views
// meet depth edges finer than their texels (the nested parts of an assembly); a smooth closed
// model has them only along its outline.
double depth_edge_fraction(const ViewAtlasPackage& package)
{
    const int n = package.settings.resolution;
    // a texel is 2r / n wide (orthographic; about that for perspective captures), depth 255 codes over 2r
    const float texel_world = 2.0f * package.radius / float(n), codes_per_world = 255.0f / (2.0f * package.radius);
    std::size_t edges = 0, covered = 0;
    for (const View& v : package.views) {
        if (v.width == 0 || package.normal_depth_pages.empty()) continue;
        const ImageRGBA8& color = package.color_pages[std::size_t(v.page)];
        const ImageRGBA8& nd = package.normal_depth_pages[std::size_t(v.page)];
        auto is_covered = [&](int x, int y) {
            return x >= 0 && y >= 0 && x < v.width && y < v.height && color.at(v.atlas_x + x, v.atlas_y + y)[3] != 0;
        };
        auto normal = [&](int x, int y) {
            const std::uint8_t* t = nd.at(v.atlas_x + x, v.atlas_y + y);
            return glm::vec3(t[0], t[1], t[2]) / 255.0f * 2.0f - 1.0f;
        };
        auto linked = [&](int x, int y, int dx, int dy) {
            if (!is_covered(x + dx, y + dy)) return false;
            float step = float(nd.at(v.atlas_x + x, v.atlas_y + y)[3]) - float(nd.at(v.atlas_x + x + dx, v.atlas_y + y + dy)[3]);
            return reps::hf_linked(step, normal(x, y), normal(x + dx, y + dy), dx != 0 ? v.axis_u : v.axis_v, v.direction,
                                   texel_world, codes_per_world, 1.0f);
        };
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) {
                if (!is_covered(x, y)) continue;
                ++covered;
                edges += !(linked(x, y, 1, 0) && linked(x, y, -1, 0) && linked(x, y, 0, 1) && linked(x, y, 0, -1));
            }
    }
    return covered > 0 ? double(edges) / double(covered) : 0.0;
}

namespace {

// One bake with the resolved parameters (the steps in the comment at the top).
Result<std::unique_ptr<ViewAtlasPackage>> bake_pass(const BakeContext& context, const Options& parameters, bool masked,
                                                    bool alpha_resolution)
{
    const BakeSettings s = settings_from(parameters);
    STANDIN_RETURN_IF_ERROR(check_settings(s));
    STANDIN_RETURN_IF_ERROR(validate_mesh(context.mesh, "view atlas"));

    // the bake renders on the GPU: use the current context or make one for the bake
    std::unique_ptr<GpuContext> own_context;
    if (!gpu::has_current_context()) {
        Result<std::unique_ptr<GpuContext>> made = create_headless_context();
        if (!made) return made.status();
        own_context = std::move(*made);
    }
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(context.mesh);
    if (!truth) return truth.status();
    // surface maps: normals from the truth's capture mode, the very normal it shades each pixel with
    // (normal maps applied, alpha-tested cut-outs cut out), so they line up with the colour capture
    const bool normals = s.maps == "surface";
    // lit maps hold the truth's shading, PBR included; only surface maps are relit
    const bool pbr = normals && context.mesh.has_pbr_materials();
    const bool depth16 = normals && s.depth_bits > 8;
    // STANDIN_ATLAS_COVERAGE_SAMPLES (1..8) overrides k_coverage_samples for measurements
    const int samples = reps::coverage_samples(context.mesh, s.resolution, alpha_resolution ? 1 : k_coverage_samples,
                                               "STANDIN_ATLAS_COVERAGE_SAMPLES");
    const int capture_size = s.resolution * samples;
    std::unique_ptr<RenderTarget> material_target; // one for every view's material capture
    if (pbr) {
        Result<RenderTarget> target = RenderTarget::create(capture_size, capture_size, "view atlas capture");
        if (!target) return target.status();
        material_target = std::make_unique<RenderTarget>(std::move(*target));
    }

    auto package = std::make_unique<ViewAtlasPackage>();
    package->source = context.source;
    package->parameters = parameters;
    package->settings = s;
    package->alpha_tested = masked;
    BoundingSphere sphere = context.mesh.bounding_sphere();
    package->center = sphere.center;
    package->radius = sphere.radius;
    std::vector<glm::vec3> directions = layout_directions(s.layout, s.subdivisions, s.frames);
    // the proxy (hull.h): planes tangent to the model along the views' directions, a millionth of the
    // radius out so that the renderer's floats never cut a vertex
    for (const HalfSpace& h : proxy_planes(context.mesh.positions, directions, source_box(*package), 1e-6 * sphere.radius))
        package->proxy_planes.push_back(glm::vec4(glm::vec3(h.normal), float(h.offset)));

    // render every view and crop it
    std::vector<Capture> captures(directions.size());
    package->views.resize(directions.size());
    for (std::size_t k = 0; k < directions.size(); ++k) {
        Camera camera = capture_camera(sphere, s, directions[k]);
        View& view = package->views[k];
        view.direction = -camera.forward_world;
        const glm::mat4& m = camera.view_from_world; // rows 0 and 1: camera right and up
        view.axis_u = glm::vec3(m[0][0], m[1][0], m[2][0]);
        view.axis_v = -glm::vec3(m[0][1], m[1][1], m[2][1]);
        Light light = default_light(camera);
        if (normals) // albedo: pure ambient under the Lambert model
            light = Light{light.direction_to_light_world, 1.0f, 0.0f, 0.0f, 1.0f, ShadingModel::lambert_blinn_phong};
        Result<RenderedImage> color = render_offscreen(**truth, camera, light, capture_size, capture_size);
        if (!color) return color.status();
        RenderedImage normal;
        if (normals) {
            Light normal_light = light;
            normal_light.shading = ShadingModel::capture_normal;
            Result<RenderedImage> rendered = render_offscreen(**truth, camera, normal_light, capture_size, capture_size);
            if (!rendered) return rendered.status();
            normal = std::move(*rendered);
        }
        reps::MaterialImages material;
        if (pbr) {
            DrawParams params;
            params.camera = camera;
            params.light = light;
            params.viewport = {capture_size, capture_size};
            Result<reps::MaterialImages> captured = reps::capture_material(**truth, *material_target, params);
            if (!captured) return captured.status();
            material = std::move(*captured);
        }
        reps::downsample_coverage(color->color, {normals ? &normal.color : nullptr, pbr ? &material.orm : nullptr, pbr ? &material.emission : nullptr},
                                  &color->depth, samples);
        float eye_distance = glm::dot(camera.eye_world - sphere.center, view.direction);
        crop(*color, normals ? &normal : nullptr, pbr ? &material : nullptr, camera, eye_distance, sphere, s.depth_bits, view,
             captures[k]);
        context.progress.report("view atlas: capturing views", double(k + 1) / double(directions.size()));
    }

    // pack the crops into pages
    int pages = pack_views(package->views, s.page_size);
    package->color_pages.assign(std::size_t(pages), ImageRGBA8(s.page_size, s.page_size));
    if (normals) package->normal_depth_pages.assign(std::size_t(pages), ImageRGBA8(s.page_size, s.page_size));
    if (depth16)
        package->depth_pages.assign(std::size_t(pages), std::vector<std::uint16_t>(std::size_t(s.page_size) * std::size_t(s.page_size), 0));
    if (pbr) {
        package->orm_pages.assign(std::size_t(pages), ImageRGBA8(s.page_size, s.page_size));
        package->emission_pages.assign(std::size_t(pages), ImageRGBA8(s.page_size, s.page_size));
    }
    for (std::size_t k = 0; k < package->views.size(); ++k) {
        const View& v = package->views[k];
        if (v.width == 0) continue;
        copy_into_page(captures[k].color, package->color_pages[std::size_t(v.page)], v.atlas_x, v.atlas_y);
        if (normals) copy_into_page(captures[k].normal_depth, package->normal_depth_pages[std::size_t(v.page)], v.atlas_x, v.atlas_y);
        if (depth16) {
            std::vector<std::uint16_t>& page = package->depth_pages[std::size_t(v.page)];
            for (int row = 0; row < v.height; ++row)
                std::copy_n(&captures[k].depth[std::size_t(row) * std::size_t(v.width)], v.width,
                            &page[std::size_t(v.atlas_y + row) * std::size_t(s.page_size) + std::size_t(v.atlas_x)]);
        }
        if (pbr) {
            copy_into_page(captures[k].orm, package->orm_pages[std::size_t(v.page)], v.atlas_x, v.atlas_y);
            copy_into_page(captures[k].emission, package->emission_pages[std::size_t(v.page)], v.atlas_x, v.atlas_y);
        }
    }
    return package;
}

} // namespace

Result<std::unique_ptr<Package>> bake(const BakeContext& context)
{
    Options parameters = context.parameters;
    const bool masked = reps::has_cutouts(context.mesh);
    // alpha-tested models at the default resolution: more texels rather than more samples per texel
    // (where the pages hold such a view; a smaller --page-size keeps the default's 2 x 2 samples)
    const bool default_resolution = !parameters.given("resolution");
    const bool alpha_resolution = masked && default_resolution &&
                                  k_alpha_resolution + 2 * k_cell <= parameters.integer("page-size");
    if (alpha_resolution) parameters.set_integer("resolution", k_alpha_resolution);
    // --depth-bits 0: chosen by each pass's resolution, and recorded as chosen
    const bool default_depth_bits = parameters.integer("depth-bits") == 0;
    auto choose_depth_bits = [&]() {
        if (default_depth_bits) parameters.set_integer("depth-bits", depth_bits_for(int(parameters.integer("resolution"))));
    };
    choose_depth_bits();
    Result<std::unique_ptr<ViewAtlasPackage>> package = bake_pass(context, parameters, masked, alpha_resolution);
    if (!package) return package.status();
    // models with detail finer than the default texels (nested parts, fins): captured again at
    // k_detail_resolution when over k_detail_edge_fraction of the texels end a surface
    if (default_resolution && !masked && (*package)->has_surface() &&
        k_detail_resolution + 2 * k_cell <= parameters.integer("page-size")) {
        if (depth_edge_fraction(**package) > k_detail_edge_fraction) {
            parameters.set_integer("resolution", k_detail_resolution);
            choose_depth_bits();
            package = bake_pass(context, parameters, masked, false);
            if (!package) return package.status();
        }
    }
    return std::unique_ptr<Package>(std::move(*package));
}

} // namespace standin::view_atlas
