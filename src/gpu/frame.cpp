#include "gpu/frame.h"

#include <glm/glm.hpp>

#include <algorithm>

namespace standin::gpu {

int shading_model_code(ShadingModel model)
{
    switch (model) {
    case ShadingModel::ggx: return SHADING_GGX;
    case ShadingModel::lambert_blinn_phong: return SHADING_LAMBERT_BLINN_PHONG;
    case ShadingModel::capture_orm: return SHADING_CAPTURE_ORM;
    case ShadingModel::capture_emission: return SHADING_CAPTURE_EMISSION;
    case ShadingModel::capture_normal: return SHADING_CAPTURE_NORMAL;
    }
    return SHADING_GGX;
}

FrameUniforms make_frame_uniforms(const Camera& camera, const Light& light, glm::ivec2 viewport,
                                  const ShadowMap* shadow_map)
{
    FrameUniforms u;
    u.clip_from_world = camera.clip_from_world();
    u.view_from_world = camera.view_from_world;
    u.world_from_clip = glm::inverse(u.clip_from_world);
    u.eye_world = glm::vec4(camera.eye_world, 1.0f);
    u.forward_world = glm::vec4(camera.forward_world, camera.orthographic ? 1.0f : 0.0f);
    u.light_to_world = glm::vec4(glm::normalize(light.direction_to_light_world), 0.0f);
    u.light_terms = glm::vec4(light.ambient, light.diffuse, light.specular, light.shininess);
    u.viewport_size = glm::vec4(float(viewport.x), float(viewport.y), 1.0f / float(viewport.x), 1.0f / float(viewport.y));
    u.shadow_bias.y = float(shading_model_code(light.shading));
    if (shadow_map) {
        u.shadow_from_world = shadow_map->shadow_from_world();
        u.shadow_terms = glm::vec4(1.0f, 1.0f / float(shadow_map->resolution()), shadow_map->texel_world(),
                                   shadow_map->depth_per_world());
        u.shadow_bias.x = shadow_map->bias_world();
    }
    return u;
}

void FrameResources::bind(const DrawParams& params)
{
    FrameUniforms uniforms = make_frame_uniforms(params.camera, params.light, params.viewport, params.shadow_map);
    float amount = params.fade.amount > 0.0f ? std::min(params.fade.amount, 1.0f) : 0.0f; // NaN: no fade
    uniforms.fade = glm::vec4(amount, params.fade.incoming ? 1.0f : 0.0f, 0.0f, 0.0f);
    if (!frame_buffer_) frame_buffer_ = make_buffer(nullptr, sizeof(FrameUniforms), GL_DYNAMIC_STORAGE_BIT);
    glNamedBufferSubData(frame_buffer_.get(), 0, sizeof uniforms, &uniforms);

    static const glm::mat4 identity(1.0f);
    std::span<const glm::mat4> transforms = params.world_from_object;
    if (transforms.empty()) transforms = std::span<const glm::mat4>(&identity, 1);
    if (transforms.size() > instance_capacity_) {
        instance_capacity_ = std::max<std::size_t>(transforms.size(), 2 * instance_capacity_);
        instance_buffer_ = make_buffer(nullptr, instance_capacity_ * sizeof(glm::mat4), GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(instance_buffer_.get(), 0, GLsizeiptr(transforms.size() * sizeof(glm::mat4)), transforms.data());
    instance_count_ = transforms.size();
    any_instance_mirrors_ = std::any_of(transforms.begin(), transforms.end(),
                                        [](const glm::mat4& m) { return glm::determinant(glm::mat3(m)) < 0.0f; });
    glBindBufferBase(GL_UNIFORM_BUFFER, BINDING_FRAME_UBO, frame_buffer_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_INSTANCES_SSBO, instance_buffer_.get());
    glBindTextureUnit(BINDING_SHADOW_TEXTURE, params.shadow_map ? GLuint(params.shadow_map->texture()) : 0u);
}

} // namespace standin::gpu
