// The one shading model of standin (Vichitvejpaisal 2005 §5.1 lost accuracy to a shading mismatch between the
// original and the billboards: every renderer includes this file, so differences measure the
// representation, not the lighting). Albedo arrives sRGB-encoded; lighting is done in linear space;
// the result is sRGB-encoded again for an RGBA8 target.
// The model (issue #14) is glTF 2.0's metallic-roughness BRDF (Khronos, glTF 2.0 specification,
// Appendix B, 2021): GGX normal distribution (Walter et al. 2007), height-correlated Smith
// visibility (Heitz 2014), Schlick Fresnel with F0 = mix(0.04, base, metallic), Lambert diffuse of
// base x (1 - metallic) weighted by 1 - the specular lobe's directional albedo (energy-conserving
// "albedo scaling", as Kulla & Conty 2017 scale their layers; glTF's own 1 - F(v.h) reflects up to
// 35 % more than it receives at grazing angles on smooth dielectrics). Light: the frame's directional light, scaled so that a
// white Lambert surface facing it reflects light_terms.y (as the old model did), plus a uniform
// white environment of radiance light_terms.x ("image-based" with a constant image), integrated by
// the split-sum approximation (Karis 2013) with the exact directional albedo of the specular lobe
// (a 16 x 16 table, specular_albedo_table.h), scaled by the material's occlusion; emission last.
// Departures: single scattering only (rough metals lose energy, as in the glTF sample viewer);
// perceptual roughness is clamped at 0.05 so a point light does not vanish on mirror surfaces.
// src/core/shading.cpp evaluates the same BRDF on the CPU for the white-furnace test; keep them equal.
// The old Lambert + ambient + Blinn-Phong model stays reachable (Light::shading).
// Fragment stages only; include after frame.glsl (the frame's light, model and shadow map).

#include "gpu/shaders/common/specular_albedo_table.h"

#define SHADING_PI 3.14159265358979
#define SHADING_MIN_ROUGHNESS 0.05
#define SHADING_DIELECTRIC_F0 0.04 // glTF: ior 1.5

vec3 srgb_to_linear(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec3 linear_to_srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

// Trowbridge-Reitz (GGX) distribution of microfacet normals; alpha = roughness^2.
float ggx_distribution(float n_dot_h, float alpha)
{
    float a2 = alpha * alpha;
    float d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (SHADING_PI * d * d);
}

// Height-correlated Smith masking-shadowing divided by 4 n.l n.v (glTF's V).
float smith_visibility(float n_dot_l, float n_dot_v, float alpha)
{
    float a2 = alpha * alpha;
    float gv = n_dot_l * sqrt(n_dot_v * n_dot_v * (1.0 - a2) + a2);
    float gl = n_dot_v * sqrt(n_dot_l * n_dot_l * (1.0 - a2) + a2);
    float g = gv + gl;
    return g > 0.0 ? 0.5 / g : 0.0;
}

vec3 fresnel_schlick(vec3 f0, float v_dot_h)
{
    float m = 1.0 - clamp(v_dot_h, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// The specular lobe's directional albedo as scale and bias to F0 (specular_albedo_table.h),
// bilinear in perceptual roughness and n.v.
const float SPECULAR_ALBEDO[SHADING_TABLE_SIZE * SHADING_TABLE_SIZE * 2] = float[](SHADING_SPECULAR_ALBEDO_TABLE);

vec2 specular_albedo_terms(float n_dot_v, float roughness)
{
    const float last = float(SHADING_TABLE_SIZE - 1);
    vec2 p = clamp(vec2(n_dot_v, roughness), 0.0, 1.0) * last;
    ivec2 i0 = min(ivec2(p), ivec2(SHADING_TABLE_SIZE - 2));
    vec2 t = p - vec2(i0);
    int k00 = 2 * (i0.y * SHADING_TABLE_SIZE + i0.x), k01 = k00 + 2 * SHADING_TABLE_SIZE;
    vec2 a = mix(vec2(SPECULAR_ALBEDO[k00], SPECULAR_ALBEDO[k00 + 1]), vec2(SPECULAR_ALBEDO[k00 + 2], SPECULAR_ALBEDO[k00 + 3]), t.x);
    vec2 b = mix(vec2(SPECULAR_ALBEDO[k01], SPECULAR_ALBEDO[k01 + 1]), vec2(SPECULAR_ALBEDO[k01 + 2], SPECULAR_ALBEDO[k01 + 3]), t.x);
    return mix(a, b, t.y);
}

// The frame's shading model (shading_model.h).
int shading_model() { return int(frame.shadow_bias.y + 0.5); }

// Lambert diffuse with ambient, optional Blinn-Phong specular: standin's model before issue #14.
vec3 shade_lambert_blinn_phong(vec3 albedo_srgb, vec3 n, vec3 to_eye_world, vec3 to_light_world, vec4 terms)
{
    float n_dot_l = max(dot(n, to_light_world), 0.0);
    vec3 color = srgb_to_linear(albedo_srgb) * (terms.x + terms.y * n_dot_l);
    if (terms.z > 0.0 && n_dot_l > 0.0) {
        vec3 h = normalize(to_light_world + to_eye_world);
        color += vec3(terms.z * pow(max(dot(n, h), 0.0), terms.w));
    }
    return linear_to_srgb(color);
}

// The surface's reflected and emitted light, sRGB-encoded; two-sided (a normal facing away from the
// viewer is flipped, so open meshes and thin sheets shade the same from both sides). orm: occlusion,
// perceptual roughness, metallic (linear); emissive: linear RGB; visibility: the fraction of the
// directional light reaching the point (shadows). Capture models return the inputs instead.
vec3 shade_pbr(vec3 albedo_srgb, vec3 orm, vec3 emissive, vec3 normal_world, vec3 to_eye_world,
               vec3 to_light_world, vec4 terms, float visibility)
{
    int model = shading_model();
    if (model == SHADING_CAPTURE_ORM) return clamp(orm, 0.0, 1.0);
    if (model == SHADING_CAPTURE_EMISSION) return linear_to_srgb(emissive);
    vec3 n = normalize(normal_world);
    if (dot(n, to_eye_world) < 0.0) n = -n;
    if (model == SHADING_CAPTURE_NORMAL) return n * 0.5 + 0.5;
    if (model == SHADING_LAMBERT_BLINN_PHONG)
        return shade_lambert_blinn_phong(albedo_srgb, n, to_eye_world, to_light_world, terms * vec4(1.0, visibility, visibility, 1.0));

    vec3 base = srgb_to_linear(albedo_srgb);
    float roughness = clamp(orm.y, SHADING_MIN_ROUGHNESS, 1.0);
    float metallic = clamp(orm.z, 0.0, 1.0);
    float alpha = roughness * roughness;
    vec3 f0 = mix(vec3(SHADING_DIELECTRIC_F0), base, metallic);
    vec3 diffuse = base * (1.0 - metallic);
    float n_dot_v = clamp(dot(n, to_eye_world), 1e-4, 1.0);
    // the specular lobe's albedo seen from here; the diffuse lobe gets what it leaves, so a white
    // dielectric reflects all it receives (single scattering loses only what rough metals lose)
    vec2 ab = specular_albedo_terms(n_dot_v, roughness);
    vec3 specular_albedo = f0 * ab.x + ab.y;
    vec3 diffuse_weight = 1.0 - specular_albedo;

    vec3 color = vec3(0.0);
    float n_dot_l = dot(n, to_light_world);
    if (n_dot_l > 0.0 && terms.y * visibility > 0.0) {
        vec3 h = normalize(to_light_world + to_eye_world);
        vec3 f = fresnel_schlick(f0, dot(to_eye_world, h));
        float specular = ggx_distribution(max(dot(n, h), 0.0), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
        vec3 brdf = diffuse_weight * diffuse / SHADING_PI + f * specular;
        color += brdf * (SHADING_PI * terms.y * visibility * n_dot_l);
    }
    color += terms.x * clamp(orm.x, 0.0, 1.0) * (diffuse * diffuse_weight + specular_albedo);
    color += max(emissive, vec3(0.0));
    return linear_to_srgb(color);
}

// What a surface without PBR inputs has (Material's defaults): unoccluded, fully rough dielectric.
const vec3 SHADING_DEFAULT_ORM = vec3(1.0, 1.0, 0.0);

// Shadows (issue #6): the frame's shadow map, a depth map of the scene seen from the light along
// an orthographic camera (src/gpu/shadow_map.cpp), read with depth compares.
layout(binding = BINDING_SHADOW_TEXTURE) uniform sampler2DShadow shadow_map;

#define SHADOW_PCF_RADIUS 2      // 5 x 5 taps, each a bilinear compare of 2 x 2 texels
#define SHADOW_SLOPE_TEXELS 3.0  // per unit of tan(angle to the light): the kernel's half width + 1
#define SHADOW_MAX_TAN 8.0

// The fraction of the light reaching a world-space point with unit normal n (facing the light:
// n_dot_l > 0): 1 lit, 0 in shadow. The depth bias is the map's constant one (ShadowMap::
// bias_world) plus a slope term, since the receiver's depth changes by tan(angle) texels per texel
// across the taps; the point also moves one texel along its normal, off the surface that casts
// onto itself.
float light_visibility(vec3 position_world, vec3 n, float n_dot_l)
{
    float texel_world = frame.shadow_terms.z;
    float tan_angle = min(sqrt(max(1.0 - n_dot_l * n_dot_l, 0.0)) / n_dot_l, SHADOW_MAX_TAN);
    float bias_world = frame.shadow_bias.x + texel_world * SHADOW_SLOPE_TEXELS * tan_angle;
    vec4 s = frame.shadow_from_world * vec4(position_world + n * texel_world, 1.0);
    vec3 p = s.xyz / s.w;
    if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) return 1.0; // outside the map
    float depth = p.z - bias_world * frame.shadow_terms.w;
    float lit = 0.0;
    for (int j = -SHADOW_PCF_RADIUS; j <= SHADOW_PCF_RADIUS; ++j)
        for (int i = -SHADOW_PCF_RADIUS; i <= SHADOW_PCF_RADIUS; ++i)
            lit += textureLod(shadow_map, vec3(p.xy + vec2(i, j) * frame.shadow_terms.y, depth), 0.0);
    return lit / float((2 * SHADOW_PCF_RADIUS + 1) * (2 * SHADOW_PCF_RADIUS + 1));
}

// shade_pbr() with the frame's light at a world-space point, in the shadows of the frame's shadow
// map when it has one (the direct term times the light's visibility). Without a map the light is
// unshadowed, so pictures without shadows do not change.
vec3 shade_pbr_at(vec3 albedo_srgb, vec3 orm, vec3 emissive, vec3 normal_world, vec3 to_eye_world, vec3 position_world)
{
    vec3 to_light = frame.light_to_world.xyz;
    float visibility = 1.0;
    if (frame.shadow_terms.x != 0.0) {
        vec3 n = normalize(normal_world);
        if (dot(n, to_eye_world) < 0.0) n = -n;
        float n_dot_l = dot(n, to_light);
        if (n_dot_l > 0.0) visibility = light_visibility(position_world, n, n_dot_l);
    }
    return shade_pbr(albedo_srgb, orm, emissive, normal_world, to_eye_world, to_light, frame.light_terms, visibility);
}

// shade_pbr_at() for a surface with the default material (stand-ins without PBR maps).
vec3 shade_at(vec3 albedo_srgb, vec3 normal_world, vec3 to_eye_world, vec3 position_world)
{
    return shade_pbr_at(albedo_srgb, SHADING_DEFAULT_ORM, vec3(0.0), normal_world, to_eye_world, position_world);
}

// The world-space point a fragment lies at (its window position and rasterised depth).
vec3 fragment_world_position()
{
    vec3 ndc = vec3(gl_FragCoord.xy * frame.viewport_size.zw, gl_FragCoord.z) * 2.0 - 1.0;
    vec4 world = frame.world_from_clip * vec4(ndc, 1.0);
    return world.xyz / world.w;
}
