#version 450 core
// View-atlas bake: the shading normal of the surface seen, world space, turned towards the camera
// (shading is two-sided), encoded n * 0.5 + 0.5. The vertex stage is the ground-truth renderer's.
#include "gpu/shaders/common/frame.glsl"

in vec3 v_position_world;
in vec3 v_normal_world;
in vec4 v_color;
in vec2 v_uv;

layout(binding = BINDING_FIRST_RENDERER_TEXTURE) uniform sampler2D albedo_texture;
uniform int has_texture;
uniform float alpha_cutoff; // the ground truth's alpha test (mesh.frag), 0: none

layout(location = 0) out vec4 out_normal;

void main()
{
    if (alpha_cutoff > 0.0) {
        float alpha = v_color.a * (has_texture != 0 ? textureLod(albedo_texture, v_uv, 0.0).a : 1.0);
        if (alpha < alpha_cutoff) discard;
    }
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz
                                              : normalize(frame.eye_world.xyz - v_position_world);
    vec3 n = normalize(v_normal_world);
    if (dot(n, to_eye) < 0.0) n = -n;
    out_normal = vec4(n * 0.5 + 0.5, 1.0);
}
