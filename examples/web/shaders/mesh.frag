#version 300 es
// Plain meshes in the web viewer: albedo = base colour x vertex colour x texture (linear; the
// texture is uploaded as sRGB, so the sampler returns linear), alpha-tested when alpha_cutoff > 0,
// then standin's two-sided Lambert + ambient (lighting.glsl) in linear light, sRGB out.
// HAS_MAP: base_color_map is bound.
precision highp float;

uniform vec4 base_color;       // linear
uniform float alpha_cutoff;    // 0: opaque
uniform vec3 to_light_world;   // unit
uniform vec2 light_terms;      // ambient, diffuse
uniform vec3 cameraPosition;
#ifdef HAS_MAP
uniform sampler2D base_color_map;
#endif

in vec3 v_normal_world;
in vec3 v_position_world;
in vec4 v_color;
in vec2 v_uv;
out vec4 out_color;

vec3 linear_to_srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

void main()
{
    vec4 albedo = base_color * v_color;
#ifdef HAS_MAP
    albedo *= texture(base_color_map, v_uv);
#endif
    if (alpha_cutoff > 0.0 && albedo.a < alpha_cutoff) discard;
    vec3 n = normalize(v_normal_world);
    vec3 to_eye = normalize(cameraPosition - v_position_world);
    if (dot(n, to_eye) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_world), 0.0);
    out_color = vec4(linear_to_srgb(albedo.rgb * (light_terms.x + light_terms.y * n_dot_l)), 1.0);
}
