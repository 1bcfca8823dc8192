// Cameras, the orbit parametrisation the papers' protocols use, and the one directional light.
#pragma once

#include <standin/mesh.h>

#include <glm/glm.hpp>

namespace standin {

struct Camera {
    glm::mat4 view_from_world{1.0f};
    glm::mat4 clip_from_view{1.0f};
    glm::vec3 eye_world{0.0f};      // for orthographic cameras: a point behind the near plane
    glm::vec3 forward_world{0.0f, 0.0f, -1.0f};
    bool orthographic = false;
    float fov_y_degrees = 40.0f;    // perspective only
    float ortho_half_height = 1.0f; // orthographic only
    float near_plane = 0.1f, far_plane = 100.0f;

    glm::mat4 clip_from_world() const { return clip_from_view * view_from_world; }
};

// A camera on a sphere around the model, looking at its centre, +Y up.
// Azimuth 0 looks from +Z towards -Z; azimuth 90 from +X; elevation 90 from +Y (the top).
struct OrbitView {
    float azimuth_degrees = 0.0f;
    float elevation_degrees = 0.0f;
    // In units of the base distance radius / sin(fov/2), at which the bounding sphere just fits the
    // vertical field of view (Saraiva et al. §3). For orthographic cameras, 1 frames the sphere the same way.
    float distance_rel = 1.0f;
    float fov_y_degrees = 40.0f;
    bool orthographic = false;
};

float base_distance(float radius, float fov_y_degrees);
glm::vec3 direction_from_angles(float azimuth_degrees, float elevation_degrees);
Camera orbit_camera(const BoundingSphere& sphere, const OrbitView& view, float aspect);
// A perspective camera from an eye, a target and an up vector (viewer, crowds).
Camera look_at_camera(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float fov_y_degrees, float aspect,
                      float near_plane, float far_plane);

// How surfaces reflect light (src/gpu/shaders/common/lighting.glsl). ggx: glTF 2.0's metallic-
// roughness BRDF (GGX distribution, height-correlated Smith visibility, Schlick Fresnel, Lambert
// diffuse) under the directional light plus a uniform white environment of radiance `ambient`.
// lambert_blinn_phong: standin's model before issue #14 (Lambert + ambient + optional Blinn-Phong
// with `specular` and `shininess`); it ignores metallic, roughness, occlusion and emission, and under
// a pure ambient light (ambient 1, diffuse 0) returns the albedo, which bakers capture with it.
// capture_orm, capture_emission and capture_normal are bakers' capture modes: renderers write the
// surface's occlusion, roughness, metallic (linear, in r, g, b), its emission (sRGB-encoded,
// clamped to 1) or the normal it is shaded with (world space, normal map applied, turned towards
// the eye, n * 0.5 + 0.5) instead of a colour; renderers of stand-ins without PBR maps write the
// defaults (1, 1, 0; black).
enum class ShadingModel { ggx, lambert_blinn_phong, capture_orm, capture_emission, capture_normal };

// One directional light; shading is computed by the shared include
// src/gpu/shaders/common/lighting.glsl. `diffuse` scales the light so that a white Lambert surface
// facing it reflects `diffuse` (its irradiance is pi x diffuse).
struct Light {
    glm::vec3 direction_to_light_world{0.0f, 0.0f, 1.0f}; // unit
    float ambient = 0.2f;
    float diffuse = 0.8f;
    float specular = 0.0f;
    float shininess = 32.0f;
    ShadingModel shading = ShadingModel::ggx;
};

// The default light of standin's protocols: from above-left of the camera, so that both the front
// and the silhouette are shaded and the same light gives the same picture to every representation.
Light default_light(const Camera& camera);
Light light_from_angles(float azimuth_degrees, float elevation_degrees);

} // namespace standin
