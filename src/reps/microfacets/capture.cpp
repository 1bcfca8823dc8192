// Orthographic reference images of a mesh on the GPU (capture.h).
// Yamazaki et al. 2002 §3.2.4: for each colour image, a range image of the model from the same
// camera at the same resolution. Steps per direction:
//  1. the orbit camera of that direction at distance 1, orthographic (the protocols' cameras, so
//     image axes follow the same up-vector rule as the evaluation's);
//  2. albedo: the ground-truth renderer under a light that is pure ambient (1, no diffuse), so the
//     shaded colour is the albedo, coverage from alpha;
//  3. normals: the same renderer in its capture_normal mode, the normal it shades each pixel with
//     (normal maps applied, turned towards the camera, n * 0.5 + 0.5), alpha-tested cut-outs cut
//     out as in the albedo;
//  4. PBR models (issue #14): ORM and emission from the truth's capture modes
//     (reps/common/material_capture.h), pixel for pixel the albedo's surface;
//  5. range: the depth buffer of the geometry mesh (the colour mesh unless a degraded one is given),
//     turned into heights along the direction;
//  6. alpha-tested models (issue #14): steps 2-5 render f x f samples per pixel, box-filtered down
//     before step 5's heights (reps::downsample_coverage): the albedo's alpha is the pixel's
//     covered fraction, so the renderer can put a cut-out's edge inside a texel
//     (microfacets_sample.glsl, hit_coverage), and the range is the nearest covered sample's.
#include "reps/microfacets/capture.h"

#include "gpu/gl.h"
#include "reps/common/coverage_capture.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace standin::microfacets {

namespace {

// The depth range, in capture texels, of the samples a supersampled texel keeps (step 6): all of
// them (negative) unless the environment variable STANDIN_MICROFACETS_FRONT_TEXELS says otherwise.
// Keeping only the front surface's samples measured worse on the foliage tree (IoU 0.925 within 2
// texels, 0.940 within 8, against 0.945 with all: docs/RESULTS.md "Fractional coverage in
// microfacets"); it stays for measurements.
float front_tolerance_from_environment()
{
    if (const char* text = std::getenv("STANDIN_MICROFACETS_FRONT_TEXELS")) return float(std::atof(text));
    return -1.0f;
}
const float front_tolerance_texels = front_tolerance_from_environment();

Camera capture_camera(const BoundingSphere& sphere, glm::vec3 direction)
{
    OrbitView view;
    view.azimuth_degrees = glm::degrees(std::atan2(direction.x, direction.z));
    view.elevation_degrees = glm::degrees(std::asin(std::clamp(direction.y, -1.0f, 1.0f)));
    view.distance_rel = 1.0f;
    view.orthographic = true;
    return orbit_camera(sphere, view, 1.0f);
}

} // namespace

void capture_axes(const BoundingSphere& sphere, glm::vec3 direction, glm::vec3& axis_u, glm::vec3& axis_v)
{
    const glm::mat4& m = capture_camera(sphere, direction).view_from_world; // rows 0 and 1: camera right and up
    axis_u = glm::vec3(m[0][0], m[1][0], m[2][0]);
    axis_v = -glm::vec3(m[0][1], m[1][1], m[2][1]);
}

Result<std::unique_ptr<SurfaceCapturer>> SurfaceCapturer::create(const Mesh& color_mesh, const Mesh* geometry,
                                                                  const BoundingSphere& sphere, int resolution,
                                                                  int coverage_samples)
{
    auto capturer = std::make_unique<SurfaceCapturer>();
    capturer->sphere_ = sphere;
    capturer->resolution_ = resolution;
    capturer->samples_ = coverage_samples;
    capturer->pbr_ = color_mesh.has_pbr_materials();
    Result<std::unique_ptr<Renderer>> albedo = make_mesh_renderer(color_mesh);
    if (!albedo) return albedo.status();
    capturer->albedo_ = std::move(*albedo);
    if (geometry) {
        Result<std::unique_ptr<Renderer>> made = make_mesh_renderer(*geometry);
        if (!made) return made.status();
        capturer->geometry_ = std::move(*made);
    }
    Result<RenderTarget> target = RenderTarget::create(resolution * coverage_samples, resolution * coverage_samples);
    if (!target) return target.status();
    capturer->target_ = std::make_unique<RenderTarget>(std::move(*target));
    return capturer;
}

Result<SurfaceCapture> SurfaceCapturer::capture(glm::vec3 direction) const
{
    const int n = resolution_;
    Camera camera = capture_camera(sphere_, direction);
    SurfaceCapture out;
    out.direction = -camera.forward_world;
    capture_axes(sphere_, direction, out.axis_u, out.axis_v);
    // pure ambient under the Lambert model: the renderer's shading returns the albedo
    const Light albedo_light{out.direction, 1.0f, 0.0f, 0.0f, 1.0f, ShadingModel::lambert_blinn_phong};

    // one pass per image into the same target, reading back only what each pass gives
    DrawParams params;
    params.camera = camera;
    params.light = albedo_light;
    params.viewport = {n * samples_, n * samples_};
    const float transparent[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    auto draw = [&](Renderer& renderer) {
        target_->bind();
        target_->clear(transparent);
        renderer.draw(params);
    };
    draw(*albedo_);
    out.albedo = target_->read_color();
    std::vector<float> depth;
    if (!geometry_) depth = target_->read_depth();
    params.light.shading = ShadingModel::capture_normal; // step 3
    draw(*albedo_);
    out.normal = target_->read_color();
    params.light = albedo_light;
    if (pbr_) {
        Result<reps::MaterialImages> material = reps::capture_material(*albedo_, *target_, params);
        if (!material) return material.status();
        out.material = std::move(*material);
    }
    if (geometry_) {
        draw(*geometry_);
        depth = target_->read_depth();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "microfacets: " + gpu::gl_error_text(e) + " capturing a view");
    if (samples_ > 1) { // step 6
        const float texel = 2.0f * sphere_.radius / float(n);
        reps::downsample_coverage(out.albedo, {&out.normal, pbr_ ? &out.material.orm : nullptr, pbr_ ? &out.material.emission : nullptr},
                                  &depth, samples_, front_tolerance_texels * texel / (camera.far_plane - camera.near_plane));
    }

    // heights: orthographic window depth is linear between the planes
    const float eye_distance = glm::dot(camera.eye_world - sphere_.center, out.direction);
    out.range.width = out.range.height = n;
    out.range.depth.assign(std::size_t(n) * n, 0.0f);
    out.range.valid.assign(std::size_t(n) * n, 0);
    for (std::size_t p = 0; p < out.range.depth.size(); ++p) {
        float window = depth[p];
        if (window >= 1.0f) continue; // nothing drawn
        float view_depth = camera.near_plane + window * (camera.far_plane - camera.near_plane);
        out.range.depth[p] = eye_distance - view_depth;
        out.range.valid[p] = 1;
    }
    return out;
}

} // namespace standin::microfacets
