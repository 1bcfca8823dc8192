#version 300 es
// Grid-atlas impostor, fragment stage (WebGL2 / GLSL ES 3.00): the reference for drawing the
// `grid-impostor` node of a .glb written by `standin export` (docs/FORMAT.md, "Export": "Frame <->
// direction", "Inside a frame"), used as is by examples/web. Self-contained: no includes.
//
// Steps, per pixel of the camera-facing square (grid_impostor.vert):
//  1. the eye ray in object space, clipped to the bounding sphere;
//  2. the frames around the view direction: the octahedral (or hemi-octahedral) encoding of the
//     direction from the centre towards the eye gives a position g on the frame grid (frame
//     centres at integer g); `blend_frames` 3 takes the three frames of the grid triangle holding g
//     with barycentric weights (the bakers' 3-frame blend), 1 the nearest frame alone;
//  3. each frame is an orthographic view along `direction` whose texels say "the surface lies at
//     signed distance depth_near - d * depth_scale from the centre along direction, where alpha
//     (coverage) >= 0.5": a point behind that surface (seen from the frame's camera) on a covered
//     texel is held by the frame. Each frame's solid extends behind its surface to the sphere, so
//     one frame alone widens thin parts seen obliquely; the point must be held by frames of summed
//     weight >= vote_threshold (default all of them: the intersection of their solids, as
//     space carving does). The walk takes `steps` points between the sphere's entry and exit,
//     stops at the first held one and refines between it and the previous one by bisection; no
//     held point: discard (the alpha test). The hit's depth is written as gl_FragDepth;
//  4. colour and normal are the frames' texels at the hit, weighted by frame weight x coverage;
//  5. shading is standin's (src/gpu/shaders/common/lighting.glsl): Lambert + ambient, two-sided, in
//     linear light, from sRGB albedo to sRGB output; a `lit` atlas is shown as stored.
// Departures from the standin renderer (src/reps/view_atlas): the exported grid has frames on a
// regular octahedral grid instead of the package's views, its texels are box-filtered from the
// captures, and the walk is a fixed-step march rather than the exact texel walk; frame axes are
// rederived from the frame index by the documented lookAt rule (the viewer checks them against
// the file's frame_axes).
//
// Textures (both sampled at level 0, bilinear, clamped inside each frame so that no filter reads
// the neighbouring frame; v runs down the image, as glTF's UVs and three's GLTFLoader, flipY false):
//   color_atlas: RGB albedo, sRGB-encoded (or the shaded colour when lit_color == 1), A coverage
//   normal_depth_atlas: RGB object-space unit normal * 0.5 + 0.5, A depth code d (linear codes)
// Uniforms: the node's extras (frames, hemi = layout "hemi-octahedral", center, radius,
// half_extent, depth_near, depth_scale), the camera in object space (eye_object, forward_object,
// orthographic), clip_from_object (for the depth written), the light (to_light_object, unit;
// light_terms = ambient, diffuse), and the walk's knobs (blend_frames 1 or 3, steps <= 256,
// vote_threshold, depth_tolerance: about 1.5 depth codes, depth_scale * 1.5 / 255 for 8-bit maps).
// Perspective captures (extras projection "perspective") are not handled: the export's default is
// ortho.
precision highp float;
precision highp int;

uniform sampler2D color_atlas;
uniform sampler2D normal_depth_atlas;
uniform int has_normal_depth;
uniform int lit_color;
uniform int frames;
uniform int hemi;
uniform vec3 center;
uniform float radius;
uniform float half_extent;
uniform float depth_near;
uniform float depth_scale;
uniform vec3 eye_object;
uniform vec3 forward_object;
uniform int orthographic;
uniform mat4 clip_from_object;
uniform vec3 to_light_object;
uniform vec2 light_terms;
uniform int blend_frames;
uniform int steps;
uniform float vote_threshold;  // weight of the frames that must hold a point: 1 = all (default), 0.5 = a majority
uniform float depth_tolerance; // object units a point may lie in front of a frame's surface and still be held (quantisation)

in vec3 v_position_object;
out vec4 out_color;

vec3 octahedral_decode(vec2 e)
{
    vec3 n = vec3(e.x, 1.0 - abs(e.x) - abs(e.y), e.y);
    if (n.y < 0.0) n.xz = (1.0 - abs(n.zx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.z >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

vec3 hemi_octahedral_decode(vec2 e)
{
    float a = 0.5 * (e.x + e.y), b = 0.5 * (e.y - e.x);
    return normalize(vec3(a, 1.0 - abs(a) - abs(b), b));
}

vec2 octahedral_encode(vec3 d)
{
    vec3 p = d / (abs(d.x) + abs(d.y) + abs(d.z));
    if (p.y >= 0.0) return p.xz;
    return (1.0 - abs(p.zx)) * vec2(p.x >= 0.0 ? 1.0 : -1.0, p.z >= 0.0 ? 1.0 : -1.0);
}

vec2 hemi_octahedral_encode(vec3 d)
{
    d.y = max(d.y, 0.0);
    vec3 p = d / (abs(d.x) + abs(d.y) + abs(d.z));
    return vec2(p.x - p.z, p.x + p.z);
}

// the frame's camera: direction (centre -> camera), axis_u (image right), axis_v (image down)
void frame_axes(ivec2 frame, out vec3 direction, out vec3 axis_u, out vec3 axis_v)
{
    vec2 e = (vec2(frame) + 0.5) / float(frames) * 2.0 - 1.0;
    direction = hemi == 1 ? hemi_octahedral_decode(e) : octahedral_decode(e);
    vec3 up = direction.y > 0.999 ? vec3(0.0, 0.0, -1.0) : direction.y < -0.999 ? vec3(0.0, 0.0, 1.0) : vec3(0.0, 1.0, 0.0);
    axis_u = normalize(cross(-direction, up));
    axis_v = cross(axis_u, direction);
}

struct Frame {
    ivec2 cell;
    vec3 direction, axis_u, axis_v;
    float weight;
};

// the atlas coordinates of frame point st (in [0, 1]^2), kept half a texel inside the frame
vec2 atlas_uv(ivec2 cell, vec2 st)
{
    float texels = float(textureSize(color_atlas, 0).x) / float(frames);
    st = clamp(st, 0.5 / texels, 1.0 - 0.5 / texels);
    return (vec2(cell) + st) / float(frames);
}

vec2 frame_st(Frame f, vec3 p)
{
    vec3 q = p - center;
    return vec2(dot(q, f.axis_u), dot(q, f.axis_v)) / half_extent * 0.5 + 0.5;
}

// covered and behind the frame's surface (seen from its camera): the frame's height field holds p.
// Without depth the frame's plane through the centre is the surface.
bool inside(Frame f, vec3 p)
{
    vec2 st = frame_st(f, p);
    if (any(lessThan(st, vec2(0.0))) || any(greaterThan(st, vec2(1.0)))) return false;
    vec2 uv = atlas_uv(f.cell, st);
    if (textureLod(color_atlas, uv, 0.0).a < 0.5) return false;
    float surface = has_normal_depth == 1 ? depth_near - textureLod(normal_depth_atlas, uv, 0.0).a * depth_scale : 0.0;
    return dot(p - center, f.direction) <= surface + depth_tolerance;
}

// the weight of the frames that hold p
float vote(Frame f[3], vec3 p)
{
    float held = 0.0;
    for (int k = 0; k < 3; ++k)
        if (f[k].weight > 0.0 && inside(f[k], p)) held += f[k].weight;
    return held;
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
    // 1. the eye ray, clipped to the bounding sphere
    vec3 ray = orthographic == 1 ? normalize(forward_object) : normalize(v_position_object - eye_object);
    vec3 origin = orthographic == 1 ? v_position_object - ray * 2.0 * radius : eye_object;
    vec3 oc = origin - center;
    float b = dot(oc, ray), c = dot(oc, oc) - radius * radius;
    float disc = b * b - c;
    if (disc <= 0.0) discard;
    float t0 = max(-b - sqrt(disc), 0.0), t1 = -b + sqrt(disc);
    if (t1 <= t0) discard;

    // 2. the frames around the direction towards the eye
    vec3 to_eye = orthographic == 1 ? -ray : normalize(eye_object - center);
    vec2 e = hemi == 1 ? hemi_octahedral_encode(to_eye) : octahedral_encode(to_eye);
    vec2 g = (e * 0.5 + 0.5) * float(frames) - 0.5;
    ivec2 cells[3];
    vec3 weights;
    if (blend_frames == 1) {
        cells[0] = ivec2(floor(g + 0.5));
        cells[1] = cells[0];
        cells[2] = cells[0];
        weights = vec3(1.0, 0.0, 0.0);
    } else {
        ivec2 base = ivec2(floor(g));
        vec2 f = g - floor(g);
        if (f.x + f.y < 1.0) {
            cells[0] = base; cells[1] = base + ivec2(1, 0); cells[2] = base + ivec2(0, 1);
            weights = vec3(1.0 - f.x - f.y, f.x, f.y);
        } else {
            cells[0] = base + ivec2(1, 1); cells[1] = base + ivec2(0, 1); cells[2] = base + ivec2(1, 0);
            weights = vec3(f.x + f.y - 1.0, 1.0 - f.x, 1.0 - f.y);
        }
    }

    Frame f[3];
    for (int k = 0; k < 3; ++k) {
        f[k].cell = clamp(cells[k], ivec2(0), ivec2(frames - 1));
        frame_axes(f[k].cell, f[k].direction, f[k].axis_u, f[k].axis_v);
        f[k].weight = weights[k];
    }

    // 3. the first point along the ray that the frames' height fields hold by vote (each frame's
    // solid extends behind its surface: one frame alone would widen thin parts seen obliquely)
    float dt = (t1 - t0) / float(steps);
    float t_out = t0, t_in = t1;
    bool found = false;
    for (int i = 0; i < 256; ++i) {
        if (i >= steps) break;
        float t = t0 + (float(i) + 0.5) * dt;
        if (vote(f, origin + ray * t) >= vote_threshold) {
            t_in = t;
            found = true;
            break;
        }
        t_out = t;
    }
    if (!found) discard;
    for (int i = 0; i < 6; ++i) {
        float t = 0.5 * (t_out + t_in);
        if (vote(f, origin + ray * t) >= vote_threshold) t_in = t; else t_out = t;
    }
    vec3 hit = origin + ray * t_in;
    vec4 clip = clip_from_object * vec4(hit, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);

    // 4. colour and normal: the frames' texels at the hit, by weight over the covered ones
    vec4 color = vec4(0.0);
    vec3 normal = vec3(0.0);
    float coverage = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (f[k].weight <= 0.0) continue;
        vec2 uv = atlas_uv(f[k].cell, frame_st(f[k], hit));
        vec4 c = textureLod(color_atlas, uv, 0.0);
        float w = f[k].weight * c.a;
        color += w * c;
        if (has_normal_depth == 1) normal += w * (textureLod(normal_depth_atlas, uv, 0.0).rgb * 2.0 - 1.0);
        coverage += w;
    }
    color /= max(coverage, 1e-6);
    if (has_normal_depth == 0) normal = -ray;

    // 5. standin's shading
    if (lit_color == 1) {
        out_color = vec4(color.rgb, 1.0);
        return;
    }
    vec3 n = normalize(normal);
    if (dot(n, -ray) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_object), 0.0);
    out_color = vec4(linear_to_srgb(srgb_to_linear(color.rgb) * (light_terms.x + light_terms.y * n_dot_l)), 1.0);
}
