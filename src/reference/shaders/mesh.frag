#version 450 core
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"

in vec3 v_position_world;
in vec3 v_normal_world;
in vec4 v_color;
in vec2 v_uv;

layout(binding = BINDING_FIRST_RENDERER_TEXTURE) uniform sampler2D albedo_texture; // the ground truth's one texture unit
// Albedo = vertex colour (material colour folded in at import) x texture where the material has
// one: the same rule as Mesh::albedo_at, which bakers sample per texel.
uniform int has_texture;

layout(location = 0) out vec4 out_color;

void main()
{
    vec4 albedo = v_color;
    if (has_texture != 0) albedo *= texture(albedo_texture, v_uv);
    // a cross-fade's other renderer owns this pixel; dropped after the derivatives above, which
    // need the whole 2x2 quad alive
    if (fade_discards()) discard;
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz
                                              : normalize(frame.eye_world.xyz - v_position_world);
    out_color = vec4(shade_at(albedo.rgb, v_normal_world, to_eye, v_position_world), 1.0);
}
