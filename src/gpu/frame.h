// The per-frame uniform block every renderer shares (GLSL side: shaders/common/frame.glsl), and
// the instance buffer of object-to-world transforms.
#pragma once

#include "gpu/gl.h"
#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/shading_model.h"

#include <standin/render.h>

#include <span>

namespace standin::gpu {

struct FrameUniforms {
    glm::mat4 clip_from_world;
    glm::mat4 view_from_world;
    glm::mat4 world_from_clip;
    glm::vec4 eye_world;
    glm::vec4 forward_world;  // w = 1 for orthographic
    glm::vec4 light_to_world;
    glm::vec4 light_terms;    // ambient, diffuse, specular, shininess
    glm::vec4 viewport_size;  // w, h, 1/w, 1/h
    glm::mat4 shadow_from_world{1.0f}; // world -> shadow map u, v, depth (ShadowMap)
    glm::vec4 shadow_terms{0.0f};      // on (1) or off (0), 1/resolution, texel_world, depth_per_world
    glm::vec4 shadow_bias{0.0f};       // bias_world, shading model (shading_model.h), unused x 2
    glm::vec4 fade{0.0f};              // DrawParams::fade: amount, incoming (1) or outgoing (0), unused x 2
};
static_assert(sizeof(FrameUniforms) == 4 * 64 + 8 * 16, "std140 layout of FrameBlock");

// The shading_model.h code of a model (FrameUniforms::shadow_bias.y).
int shading_model_code(ShadingModel model);

// shadow_map may be null (no shadows)
FrameUniforms make_frame_uniforms(const Camera& camera, const Light& light, glm::ivec2 viewport,
                                  const ShadowMap* shadow_map = nullptr);

// Owns the frame UBO and the instance SSBO and binds them; renderers keep one each.
class FrameResources {
public:
    // Uploads uniforms and instances (identity when empty) and binds both, and the shadow map's
    // texture when params has one (otherwise unbinds that unit: a map being drawn is never read).
    void bind(const DrawParams& params);
    std::size_t instance_count() const { return instance_count_; }
    // Whether an instance bound last mirrors (negative determinant): one instanced draw applies GL's
    // winding cull to every instance alike, so where any mirrors, renderers cull in the shader
    bool any_instance_mirrors() const { return any_instance_mirrors_; }

private:
    Buffer frame_buffer_;
    Buffer instance_buffer_;
    std::size_t instance_capacity_ = 0;
    std::size_t instance_count_ = 0;
    bool any_instance_mirrors_ = false;
};

} // namespace standin::gpu
