// Per-frame uniforms shared by every renderer; layout mirrors standin::gpu::FrameUniforms.
#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/shading_model.h"

layout(std140, binding = BINDING_FRAME_UBO) uniform FrameBlock {
    mat4 clip_from_world;
    mat4 view_from_world;
    mat4 world_from_clip;
    vec4 eye_world;         // xyz: eye position (orthographic: a point behind the near plane)
    vec4 forward_world;     // xyz: view direction; w: 1 for orthographic cameras
    vec4 light_to_world;    // xyz: unit direction towards the light
    vec4 light_terms;       // ambient, diffuse, specular, shininess
    vec4 viewport_size;     // width, height, 1/width, 1/height
    mat4 shadow_from_world; // world -> shadow map u, v, window depth (lighting.glsl)
    vec4 shadow_terms;      // x: 1 with a shadow map, else 0; y: 1/resolution; z: world units per
                            // texel; w: window-depth units per world unit along the light
    vec4 shadow_bias;       // x: constant depth bias, world units; y: shading model
                            // (shading_model.h); zw: unused
    vec4 fade;              // x: cross-fade amount in [0, 1]; y: 1 incoming, 0 outgoing (fade.glsl)
} frame;

layout(std430, binding = BINDING_INSTANCES_SSBO) readonly buffer InstanceBlock {
    mat4 world_from_object[];
} instances;

// The ray through a window-space position, in world space (origin on the near plane).
void camera_ray(vec2 frag_coord, out vec3 origin, out vec3 direction)
{
    vec2 ndc = frag_coord * frame.viewport_size.zw * 2.0 - 1.0;
    vec4 near_point = frame.world_from_clip * vec4(ndc, -1.0, 1.0);
    vec4 far_point = frame.world_from_clip * vec4(ndc, 1.0, 1.0);
    origin = near_point.xyz / near_point.w;
    direction = normalize(far_point.xyz / far_point.w - origin);
}

// Window-space depth of a world-space point, as the fixed pipeline would write it.
float window_depth(vec3 world_position)
{
    vec4 clip = frame.clip_from_world * vec4(world_position, 1.0);
    return clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
}
