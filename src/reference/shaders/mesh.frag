#version 450 core
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"

in vec3 v_position_world;
in vec3 v_normal_world;
in vec4 v_color;
in vec2 v_uv;
flat in float v_handedness; // -1 for a mirroring instance transform

layout(binding = BINDING_FIRST_RENDERER_TEXTURE) uniform sampler2D albedo_texture; // the ground truth's one texture unit
// Albedo = vertex colour (material colour folded in at import) x texture where the material has
// one: the same rule as Mesh::albedo_at, which bakers sample per texel.
uniform int has_texture;
// Alpha test (issue #14): fragments whose alpha is under this are cut out; 0 for opaque materials.
// The alpha is read from the texture's level 0 (mesh_renderer.cpp says why).
uniform float alpha_cutoff;
// a single-sided material drawn with instances that mirror (mesh_renderer.cpp): back faces are
// culled here, a face being a front face when its winding seen on screen, turned by a mirror, is
// counter-clockwise
uniform int cull_in_shader;

// glTF metallic-roughness inputs of the material being drawn (issue #14): factors times maps, as
// Mesh::pbr_at and Mesh::shading_normal_at compute them for the bakers.
layout(binding = BINDING_FIRST_RENDERER_TEXTURE + 1) uniform sampler2D metallic_roughness_texture; // G rough, B metal
layout(binding = BINDING_FIRST_RENDERER_TEXTURE + 2) uniform sampler2D occlusion_texture;          // R
layout(binding = BINDING_FIRST_RENDERER_TEXTURE + 3) uniform sampler2D emissive_texture;           // sRGB
layout(binding = BINDING_FIRST_RENDERER_TEXTURE + 4) uniform sampler2D normal_texture;             // tangent space
uniform vec4 pbr_factors = vec4(0.0, 1.0, 1.0, 1.0); // metallic, roughness, occlusion strength, normal scale
uniform vec3 emissive_factor = vec3(0.0);             // linear
uniform ivec4 pbr_maps = ivec4(0);                    // has: metallic-roughness, occlusion, emissive, normal map

// The normal bent by the normal map in the cotangent frame of the UVs at this pixel (Schüler 2006,
// "Normal mapping without precomputed tangents"): no tangent attribute needed.
vec3 mapped_normal(vec3 n, vec3 position_world, vec2 uv)
{
    n = normalize(n);
    vec3 dp1 = dFdx(position_world), dp2 = dFdy(position_world);
    vec2 duv1 = dFdx(uv), duv2 = dFdy(uv);
    vec3 dp2_perp = cross(dp2, n), dp1_perp = cross(n, dp1);
    // (a mirror turns the cross products, and with them the frame's handedness: turned back, the
    // bumps of a mirrored instance are the mirror image of the unmirrored one's)
    vec3 t = (dp2_perp * duv1.x + dp1_perp * duv2.x) * v_handedness;
    vec3 b = (dp2_perp * duv1.y + dp1_perp * duv2.y) * v_handedness;
    float scale = max(dot(t, t), dot(b, b));
    if (!(scale > 0.0)) return n;
    vec3 m = texture(normal_texture, uv).xyz * 2.0 - 1.0;
    m.xy *= pbr_factors.w;
    vec3 bent = mat3(t * inversesqrt(scale), b * inversesqrt(scale), n) * m;
    return dot(bent, bent) > 0.0 ? normalize(bent) : n;
}

layout(location = 0) out vec4 out_color;

void main()
{
    vec4 albedo = v_color;
    if (has_texture != 0) albedo *= texture(albedo_texture, v_uv);
    // the alpha test and a cross-fade's other renderer drop the pixel only after every derivative
    // below (implicit texture derivatives, the normal map's frame), which need the 2x2 quad alive
    bool cut_out = cull_in_shader != 0 && gl_FrontFacing == (v_handedness < 0.0);
    if (alpha_cutoff > 0.0) {
        float alpha = v_color.a * (has_texture != 0 ? textureLod(albedo_texture, v_uv, 0.0).a : 1.0);
        cut_out = cut_out || alpha < alpha_cutoff;
    }
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz
                                              : normalize(frame.eye_world.xyz - v_position_world);
    vec3 orm = vec3(1.0, pbr_factors.y, pbr_factors.x);
    if (pbr_maps.x != 0) orm.yz *= texture(metallic_roughness_texture, v_uv).gb;
    if (pbr_maps.y != 0) orm.x = 1.0 + pbr_factors.z * (texture(occlusion_texture, v_uv).r - 1.0);
    vec3 emissive = emissive_factor;
    if (pbr_maps.z != 0) emissive *= srgb_to_linear(texture(emissive_texture, v_uv).rgb);
    vec3 normal_world = pbr_maps.w != 0 ? mapped_normal(v_normal_world, v_position_world, v_uv) : v_normal_world;
    if (cut_out || fade_discards()) discard;
    out_color = vec4(shade_pbr_at(albedo.rgb, orm, emissive, normal_world, to_eye, v_position_world), 1.0);
}
