// Reference images of a mesh: orthographic colour (albedo + coverage), world normal and depth from a
// direction, rendered on the GPU by the ground-truth renderer. These are the seed's photographs and
// range images (Yamazaki et al. 2002 §3.2.4), made from the mesh itself; alpha-tested models are
// captured with fractional coverage (reps/common/coverage_capture.h). The geometry the range
// image comes from may be a different (degraded) mesh than the colour's, as a scan is worse than
// photographs (§3.2.1).
// Written for microfacets while src/reps/common/ does not yet hold a shared multi-view capture
// (issue #11); the view atlas's bake has its own. One of them should go.
#pragma once

#include "reps/common/material_capture.h"
#include "reps/microfacets/range_holes.h"

#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/render.h>

#include <glm/glm.hpp>

#include <memory>

namespace standin::microfacets {

struct SurfaceCapture {
    glm::vec3 direction{0, 0, 1}; // from the centre towards the camera
    glm::vec3 axis_u{1, 0, 0};    // image columns (camera right)
    glm::vec3 axis_v{0, -1, 0};   // image rows (camera down)
    // sRGB albedo; A: coverage 0 / 255, or with coverage samples the covered fraction (1..255 where
    // any sample is covered)
    ImageRGBA8 albedo;
    ImageRGBA8 normal;            // world shading normal * 0.5 + 0.5 where covered
    // Height of the geometry's surface above the centre plane along `direction` (object units),
    // valid where the geometry mesh covers the pixel.
    RangeImage range;
    // models with PBR materials only (issue #14): ORM and emission, aligned with `albedo`
    reps::MaterialImages material;
};

// The image axes of the capture along `direction` (towards the camera): columns and rows, as
// SurfaceCapture::axis_u / axis_v.
void capture_axes(const BoundingSphere& sphere, glm::vec3 direction, glm::vec3& axis_u, glm::vec3& axis_v);

// Captures views of a sphere's content: the pixel (x, y) of a resolution^2 capture (continuous, y
// down) lies on the plane through the centre at centre + (-r + x 2r / res) axis_u + (-r + y 2r /
// res) axis_v. Needs a current GL context; holds the meshes' GPU copies. With `coverage_samples` f
// > 1 (alpha-tested models, issue #14: reps::coverage_samples) every image is rendered at f x f
// samples per pixel and box-filtered down (reps::downsample_coverage): the albedo's alpha is the
// covered fraction, the normal and material the covered samples' mean, the range the nearest
// covered sample's.
class SurfaceCapturer {
public:
    // `geometry` may be null (the range images come from `color_mesh` itself). Captures include the
    // material channels when `color_mesh` has PBR materials.
    static Result<std::unique_ptr<SurfaceCapturer>> create(const Mesh& color_mesh, const Mesh* geometry,
                                                           const BoundingSphere& sphere, int resolution,
                                                           int coverage_samples = 1);
    Result<SurfaceCapture> capture(glm::vec3 direction) const;

private:
    std::unique_ptr<Renderer> albedo_, geometry_;
    std::unique_ptr<RenderTarget> target_; // one target for every capture: no allocation per view
    BoundingSphere sphere_;
    bool pbr_ = false;
    int resolution_ = 0;
    int samples_ = 1; // capture samples per pixel side
};

} // namespace standin::microfacets
