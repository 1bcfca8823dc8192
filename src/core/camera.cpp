// Orbit cameras of the papers' protocols (Saraiva et al. §3: base distance = radius / sin(fov/2)) and the
// default light shared by every renderer.
#include <standin/camera.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace standin {

float base_distance(float radius, float fov_y_degrees)
{
    return radius / std::sin(glm::radians(fov_y_degrees) * 0.5f);
}

glm::vec3 direction_from_angles(float azimuth_degrees, float elevation_degrees)
{
    float az = glm::radians(azimuth_degrees), el = glm::radians(elevation_degrees);
    return {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
}

static glm::vec3 up_vector_for(glm::vec3 eye_direction)
{
    // Looking straight down or up, +Y is parallel to the view: use the horizontal axis that keeps
    // azimuth 0 "in front", so that the top view is not mirrored.
    if (std::abs(eye_direction.y) > 0.999f) return eye_direction.y > 0.0f ? glm::vec3(0, 0, -1) : glm::vec3(0, 0, 1);
    return {0.0f, 1.0f, 0.0f};
}

Camera orbit_camera(const BoundingSphere& sphere, const OrbitView& view, float aspect)
{
    const float r = std::max(sphere.radius, 1e-12f);
    glm::vec3 eye_direction = direction_from_angles(view.azimuth_degrees, view.elevation_degrees);
    Camera camera;
    camera.orthographic = view.orthographic;
    camera.fov_y_degrees = view.fov_y_degrees;
    float eye_distance;
    if (view.orthographic) {
        eye_distance = 3.0f * r;
        camera.ortho_half_height = r * view.distance_rel;
        camera.near_plane = eye_distance - 1.05f * r;
        camera.far_plane = eye_distance + 1.05f * r;
        float hh = camera.ortho_half_height, hw = hh * aspect;
        camera.clip_from_view = glm::ortho(-hw, hw, -hh, hh, camera.near_plane, camera.far_plane);
    } else {
        eye_distance = base_distance(r, view.fov_y_degrees) * view.distance_rel;
        camera.near_plane = std::max(eye_distance - 1.05f * r, 0.01f * r);
        camera.far_plane = eye_distance + 1.05f * r;
        camera.clip_from_view = glm::perspective(glm::radians(view.fov_y_degrees), aspect, camera.near_plane,
                                                 camera.far_plane);
    }
    camera.eye_world = sphere.center + eye_direction * eye_distance;
    camera.forward_world = -eye_direction;
    camera.view_from_world = glm::lookAt(camera.eye_world, sphere.center, up_vector_for(eye_direction));
    return camera;
}

Camera look_at_camera(glm::vec3 eye, glm::vec3 target, glm::vec3 up, float fov_y_degrees, float aspect,
                      float near_plane, float far_plane)
{
    Camera camera;
    camera.eye_world = eye;
    camera.forward_world = glm::normalize(target - eye);
    camera.fov_y_degrees = fov_y_degrees;
    camera.near_plane = near_plane;
    camera.far_plane = far_plane;
    camera.view_from_world = glm::lookAt(eye, target, up);
    camera.clip_from_view = glm::perspective(glm::radians(fov_y_degrees), aspect, near_plane, far_plane);
    return camera;
}

Light default_light(const Camera& camera)
{
    const glm::vec3 to_light_view = glm::normalize(glm::vec3(-0.4f, 0.6f, 1.0f));
    glm::mat3 world_from_view = glm::transpose(glm::mat3(camera.view_from_world));
    Light light;
    light.direction_to_light_world = glm::normalize(world_from_view * to_light_view);
    return light;
}

Light light_from_angles(float azimuth_degrees, float elevation_degrees)
{
    Light light;
    light.direction_to_light_world = direction_from_angles(azimuth_degrees, elevation_degrees);
    return light;
}

} // namespace standin
