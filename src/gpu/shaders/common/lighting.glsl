// The one shading model of standin (Vichitvejpaisal 2005 §5.1 lost accuracy to a shading mismatch between the
// original and the billboards: every renderer includes this file, so differences measure the
// representation, not the lighting). Albedo arrives sRGB-encoded; lighting is done in linear space;
// the result is sRGB-encoded again for an RGBA8 target.
// Fragment stages only; include after frame.glsl (shade_at reads the frame's light and shadow map).

vec3 srgb_to_linear(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec3 linear_to_srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

// Lambert diffuse with ambient, optional Blinn-Phong specular, two-sided (a normal facing away from
// the viewer is flipped, so open meshes and thin sheets shade the same from both sides).
vec3 shade(vec3 albedo_srgb, vec3 normal_world, vec3 to_eye_world, vec3 to_light_world, vec4 terms)
{
    vec3 n = normalize(normal_world);
    if (dot(n, to_eye_world) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_world), 0.0);
    vec3 color = srgb_to_linear(albedo_srgb) * (terms.x + terms.y * n_dot_l);
    if (terms.z > 0.0 && n_dot_l > 0.0) {
        vec3 h = normalize(to_light_world + to_eye_world);
        color += vec3(terms.z * pow(max(dot(n, h), 0.0), terms.w));
    }
    return linear_to_srgb(color);
}

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

// shade() with the frame's light at a world-space point, in the shadows of the frame's shadow map
// when it has one (the direct term, diffuse and specular, times the light's visibility). Without a
// map it is shade() itself, so pictures without shadows do not change.
vec3 shade_at(vec3 albedo_srgb, vec3 normal_world, vec3 to_eye_world, vec3 position_world)
{
    vec3 to_light = frame.light_to_world.xyz;
    if (frame.shadow_terms.x == 0.0) return shade(albedo_srgb, normal_world, to_eye_world, to_light, frame.light_terms);
    vec3 n = normalize(normal_world);
    if (dot(n, to_eye_world) < 0.0) n = -n;
    float n_dot_l = dot(n, to_light);
    vec4 terms = frame.light_terms;
    if (n_dot_l > 0.0) terms.yz *= light_visibility(position_world, n, n_dot_l);
    return shade(albedo_srgb, normal_world, to_eye_world, to_light, terms);
}

// The world-space point a fragment lies at (its window position and rasterised depth).
vec3 fragment_world_position()
{
    vec3 ndc = vec3(gl_FragCoord.xy * frame.viewport_size.zw, gl_FragCoord.z) * 2.0 - 1.0;
    vec4 world = frame.world_from_clip * vec4(ndc, 1.0);
    return world.xyz / world.w;
}
