#version 300 es
// Enhanced billboard, fragment stage (WebGL2 / GLSL ES 3.00): the reference for drawing a
// `role: "billboard"` node of a .glb written by `standin export` (docs/FORMAT.md, "Export" and
// "Geometry of a billboard"; Vichitvejpaisal 2005 §3.3: a ray cast through the billboard's height
// field inside its box), used as is by examples/web. Self-contained: no includes.
//
// Box space: x = dot(p - origin, axis_u) / (width * texel_size), y likewise along axis_v with
// height, z = dot(p - origin, direction) / depth_range (direction points into the model); the maps
// are read at uv = (x, y) (row 0 at origin: glTF UVs, three's GLTFLoader with flipY false).
// Steps, per pixel of the box's back faces:
//  1. the eye ray in object space, clipped to the box [0, 1]^3 (slabs);
//  2. `steps` samples along it; a sample is on a covered texel (colour alpha >= 0.5) with signed
//     height f = z - d (d: the depth code in the normal + depth map's alpha). The ray hits where f
//     changes sign between two successive covered samples (the surface as a sheet, seen from the
//     front or the back) whose depths d differ by no more than the ray's z moved or wall_depth
//     (else the sign change is the wall at a depth edge between two surfaces), refined by bisection;
//  3. the hit's depth is written (gl_FragDepth), so boxes and the coarse mesh resolve by the depth
//     test; no hit: discard;
//  4. shading is standin's: Lambert + ambient, two-sided, linear light, sRGB in and out.
// Departures from the standin renderer (src/reps/enhanced_billboards): a fixed-step march (its
// exact march walks texel columns and the walls between neighbours of one surface through a min/max
// pyramid), bilinear reads of 8-bit codes (browsers decode the 16-bit PNG to 8 bits), and the
// coarse mesh is drawn everywhere rather than only where rays came near a surface and missed.
// Textures: color_map (RGB sRGB albedo, A coverage), normal_depth_map (RGB object-space normal *
// 0.5 + 0.5, A depth d in [0, 1] of depth_range). Uniforms: the node's extras (origin, axis_u,
// axis_v, direction, texel_size, depth_range, width, height), the camera in object space
// (eye_object, forward_object, orthographic), clip_from_object, the light (to_light_object, unit;
// light_terms = ambient, diffuse), steps (<= 256).
precision highp float;
precision highp int;

uniform sampler2D color_map;
uniform sampler2D normal_depth_map;
uniform vec3 origin;
uniform vec3 axis_u;
uniform vec3 axis_v;
uniform vec3 direction;
uniform float texel_size;
uniform float depth_range;
uniform vec2 size_texels;
uniform vec3 eye_object;
uniform vec3 forward_object;
uniform int orthographic;
uniform mat4 clip_from_object;
uniform vec3 to_light_object;
uniform vec2 light_terms;
uniform int steps;
uniform float wall_depth; // depth (in units of depth_range) two neighbouring samples of one surface may differ by

in vec3 v_position_object;
out vec4 out_color;

vec3 box_from_object(vec3 p)
{
    vec3 q = p - origin;
    return vec3(dot(q, axis_u) / (size_texels.x * texel_size), dot(q, axis_v) / (size_texels.y * texel_size),
                dot(q, direction) / depth_range);
}

// signed height above the sheet of the box point b, and whether its texel is covered
float height(vec3 b, out bool covered)
{
    vec2 uv = clamp(b.xy, 0.5 / size_texels, 1.0 - 0.5 / size_texels);
    covered = textureLod(color_map, uv, 0.0).a >= 0.5;
    return b.z - textureLod(normal_depth_map, uv, 0.0).a;
}

vec3 srgb_to_linear(vec3 c)
{
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec3 linear_to_srgb(vec3 c)
{
    c = clamp(c, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, greaterThan(c, vec3(0.0031308)));
}

void main()
{
    // 1. the ray in box space (an affine map: the ray stays a line, t is shared)
    vec3 ray = orthographic == 1 ? normalize(forward_object) : normalize(v_position_object - eye_object);
    vec3 start = orthographic == 1 ? v_position_object - ray * 4.0 * length(size_texels * texel_size) : eye_object;
    vec3 b0 = box_from_object(start);
    vec3 db = box_from_object(start + ray) - b0;
    vec3 inv = 1.0 / vec3(abs(db.x) > 1e-12 ? db.x : 1e-12, abs(db.y) > 1e-12 ? db.y : 1e-12, abs(db.z) > 1e-12 ? db.z : 1e-12);
    vec3 ta = (vec3(0.0) - b0) * inv, tb = (vec3(1.0) - b0) * inv;
    vec3 t_near = min(ta, tb), t_far = max(ta, tb);
    float t0 = max(max(t_near.x, t_near.y), max(t_near.z, 0.0));
    float t1 = min(min(t_far.x, t_far.y), t_far.z);
    if (t1 <= t0) discard;

    // 2. the first sign change of the height between covered samples
    float dt = (t1 - t0) / float(steps);
    bool previous_covered;
    float previous_t = t0;
    float previous_f = height(b0 + db * t0, previous_covered);
    bool found = false;
    float ta_hit = 0.0, tb_hit = 0.0;
    for (int i = 1; i <= 256; ++i) {
        if (i > steps) break;
        float t = t0 + float(i) * dt;
        bool covered;
        float f = height(b0 + db * t, covered);
        // a crossing between texels of one surface, not the wall between two surfaces at a depth edge
        // (the sheet's depth jumps there by more than the ray moved and more than wall_texels allow)
        float jump = abs((f - previous_f) - (b0.z + db.z * t - (b0.z + db.z * previous_t)));
        bool same_surface = jump <= max(2.0 * abs(db.z) * dt, wall_depth);
        if (covered && previous_covered && same_surface && (f >= 0.0) != (previous_f >= 0.0)) {
            ta_hit = previous_t;
            tb_hit = t;
            found = true;
            break;
        }
        previous_covered = covered;
        previous_f = f;
        previous_t = t;
    }
    if (!found) discard;
    bool covered;
    float fa = height(b0 + db * ta_hit, covered);
    for (int i = 0; i < 6; ++i) {
        float t = 0.5 * (ta_hit + tb_hit);
        float f = height(b0 + db * t, covered);
        if ((f >= 0.0) == (fa >= 0.0)) ta_hit = t; else tb_hit = t;
    }
    float t_hit = 0.5 * (ta_hit + tb_hit);

    // 3. the hit's depth
    vec3 hit_object = start + ray * t_hit;
    vec4 clip = clip_from_object * vec4(hit_object, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);

    // 4. standin's shading
    vec2 uv = clamp((b0 + db * t_hit).xy, 0.5 / size_texels, 1.0 - 0.5 / size_texels);
    vec3 albedo = textureLod(color_map, uv, 0.0).rgb;
    vec3 n = normalize(textureLod(normal_depth_map, uv, 0.0).rgb * 2.0 - 1.0);
    if (dot(n, -ray) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_object), 0.0);
    out_color = vec4(linear_to_srgb(srgb_to_linear(albedo) * (light_terms.x + light_terms.y * n_dot_l)), 1.0);
}
