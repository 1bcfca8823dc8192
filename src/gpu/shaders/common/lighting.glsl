// The one shading model of standin (seed 000 §5.1 lost accuracy to a shading mismatch between the
// original and the billboards: every renderer includes this file, so differences measure the
// representation, not the lighting). Albedo arrives sRGB-encoded; lighting is done in linear space;
// the result is sRGB-encoded again for an RGBA8 target.

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
