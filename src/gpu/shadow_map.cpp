// Shadow maps of the one directional light (issue #6; Saraiva et al. §7: "cast shadows from the
// depth-correct surface"). Williams, "Casting curved shadows on curved surfaces", SIGGRAPH 1978,
// filtered by percentage-closer taps (Reeves, Salesin & Cook, SIGGRAPH 1987) in lighting.glsl.
// Steps: fit an orthographic camera along the light to the scene's sphere; draw the casters with
// their own renderers into a depth-only target (their fragment stages run: ray hits and atlas
// intersections write their true depth); hand the texture, compare mode on, to the frame block.
#include "gpu/gl.h"

#include <standin/render.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>

namespace standin {

struct ShadowMap::State {
    gpu::Texture depth;
    gpu::Framebuffer fbo;
    int resolution = 0;
    Camera camera;
    float texel_world = 0.0f, depth_per_world = 0.0f, bias_world = 0.0f;
};

// the constant depth bias, relative to the scene's radius (ShadowMap::bias_world)
constexpr float k_bias_rel = 0.006f;

ShadowMap::ShadowMap() : state_(std::make_unique<State>()) {}
ShadowMap::~ShadowMap() = default;

Result<std::unique_ptr<ShadowMap>> ShadowMap::create(int resolution)
{
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (resolution < 1 || resolution > max_size)
        return error(StatusCode::invalid_argument, "shadow map: resolution " + std::to_string(resolution) +
                                                       " out of range 1.." + std::to_string(max_size));
    std::unique_ptr<ShadowMap> map(new ShadowMap());
    State& s = *map->state_;
    s.resolution = resolution;
    s.depth = gpu::make_texture_2d(GL_DEPTH_COMPONENT32F, resolution, resolution);
    GLuint t = s.depth.get();
    glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(t, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTextureParameteri(t, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL); // 1 where the point is not behind the map
    s.fbo = gpu::make_framebuffer();
    glNamedFramebufferTexture(s.fbo.get(), GL_DEPTH_ATTACHMENT, t, 0);
    glNamedFramebufferDrawBuffer(s.fbo.get(), GL_NONE);
    glNamedFramebufferReadBuffer(s.fbo.get(), GL_NONE);
    if (glCheckNamedFramebufferStatus(s.fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return error(StatusCode::gpu_error, "shadow map: depth framebuffer incomplete");
    return map;
}

// An orthographic camera looking along the light onto the sphere, which just fits its square
// view and its depth range.
static Camera light_camera(const Light& light, const BoundingSphere& scene)
{
    const float r = std::max(scene.radius, 1e-12f) * 1.01f;
    glm::vec3 to_light = glm::normalize(light.direction_to_light_world);
    glm::vec3 up = std::abs(to_light.y) > 0.999f ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(0.0f, 1.0f, 0.0f);
    Camera camera;
    camera.orthographic = true;
    camera.ortho_half_height = r;
    camera.near_plane = r;
    camera.far_plane = 3.0f * r;
    camera.eye_world = scene.center + 2.0f * r * to_light;
    camera.forward_world = -to_light;
    camera.view_from_world = glm::lookAt(camera.eye_world, scene.center, up);
    camera.clip_from_view = glm::ortho(-r, r, -r, r, camera.near_plane, camera.far_plane);
    return camera;
}

Status ShadowMap::render(Renderer& casters, const Light& light, const BoundingSphere& scene,
                         std::span<const glm::mat4> world_from_object)
{
    State& s = *state_;
    s.camera = light_camera(light, scene);
    s.texel_world = 2.0f * s.camera.ortho_half_height / float(s.resolution);
    s.depth_per_world = 1.0f / (s.camera.far_plane - s.camera.near_plane);
    s.bias_world = std::max(k_bias_rel * std::max(scene.radius, 0.0f), 1.5f * s.texel_world);

    // draw the casters into the depth target, then restore what was bound
    GLint previous_fbo = 0, previous_viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_fbo);
    glGetIntegerv(GL_VIEWPORT, previous_viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, s.fbo.get());
    glViewport(0, 0, s.resolution, s.resolution);
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(s.fbo.get(), GL_DEPTH, 0, &far_depth);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);

    DrawParams params;
    params.camera = s.camera;
    params.light = light;
    params.viewport = {s.resolution, s.resolution};
    params.world_from_object = world_from_object;
    casters.draw(params); // no shadow map: the casters never read the map they draw into

    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previous_fbo));
    glViewport(previous_viewport[0], previous_viewport[1], previous_viewport[2], previous_viewport[3]);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "shadow map: " + gpu::gl_error_text(e));
    return Status::ok();
}

const Camera& ShadowMap::camera() const { return state_->camera; }

glm::mat4 ShadowMap::shadow_from_world() const
{
    // clip [-1, 1]^3 to [0, 1]^3
    glm::mat4 unit_from_clip = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
    return unit_from_clip * state_->camera.clip_from_world();
}

float ShadowMap::texel_world() const { return state_->texel_world; }
float ShadowMap::depth_per_world() const { return state_->depth_per_world; }
float ShadowMap::bias_world() const { return state_->bias_world; }
int ShadowMap::resolution() const { return state_->resolution; }
unsigned ShadowMap::texture() const { return state_->depth.get(); }

} // namespace standin
