#version 300 es
// Grid-atlas impostor, fragment stage (WebGL2 / GLSL ES 3.00): the reference for drawing the
// `grid-impostor` node of a .glb written by `standin export` (docs/FORMAT.md, "Export": "Frame <->
// direction", "Inside a frame"), used as is by examples/web. Self-contained: no includes.
//
// Steps, per pixel of the hull (or the camera-facing square; grid_impostor.vert):
//  1. the eye ray in object space;
//  2. the frames around the view direction: the octahedral (or hemi-octahedral) encoding of the
//     direction from the centre towards the eye gives a position g on the frame grid (frame
//     centres at integer g); `blend_frames` 3 takes the three frames of the grid triangle holding g
//     with barycentric weights (the bakers' 3-frame blend), 1 the nearest frame alone;
//  3. each frame is a height field over its plane (an orthographic view along `direction`): texel
//     (x, y) with coverage a > 0 holds a top through height depth_near - d * depth_scale (towards
//     the frame's camera) at its centre, tilted by its normal (slope capped at 3 heights per plane
//     unit, atlas.frag `texel_gradient`). The ray is intersected with each frame exactly, as standin's own
//     corrected walk does (src/reps/view_atlas/shaders/atlas.frag, `intersect_view`): a digital walk
//     (Amanatides & Woo 1987) over the frame's texels under the ray, the surface being the tops and
//     the walls between neighbours of one surface (a height step within what their normals' slope
//     allows, the rule of src/reps/common/shaders/height_field.glsl); a ray that enters a column
//     below its top through a depth edge is in space the frame did not see (it abstains). A crossing
//     counts only where the coverage, filtered bilinearly over the four texels of the crossed
//     surface, reaches 1/2 (atlas.frag `hit_coverage`, issue #14): a cut-out's edge then falls inside
//     texels, where the truth's alpha test puts it; below 1/2 the ray passes beside the edge and
//     walks on;
//  4. the vote: the pixel is drawn where the frames that hit weigh at least as much as those whose
//     walk found nothing (abstaining frames do not count, but for models without alpha-tested
//     materials, `alpha_tested` 0, a twentieth of their weight), as standin's renderer decides; hits
//     within two texels of the nearest are the same surface and are blended by weight (fading out
//     to four texels); the blended hit's depth is written as gl_FragDepth;
//  5. colour and normal: each hitting frame's texels around its hit, bilinear over those of the
//     hit's own surface, weighted by coverage (colour does not leak across depth edges);
//  6. shading is standin's (src/gpu/shaders/common/lighting.glsl): Lambert + ambient, two-sided, in
//     linear light, from sRGB albedo to sRGB output; a `lit` atlas is shown as stored.
// Until issue #16 this shader marched the ray in fixed steps through the intersection of the
// frames' solids and read coverage as binary (alpha >= 1/2, depth filtered across edges): on
// foliage it rounded leaves off and filled the gaps between them (docs/RESULTS.md "Foliage in the
// web viewer").
// Departures from the standin renderer (src/reps/view_atlas): the exported grid has frames on a
// regular octahedral grid instead of the package's views, its texels are box-filtered from the
// captures (exported by default at frames x capture resolution, one texel per capture pixel),
// its depth has 8 bits instead of 16 (the link rule's two quanta are 8-bit ones), the frames are
// the grid triangle's instead of the 3 nearest views, the walk does not skip empty cells (there
// is no cell-top map), and only level 0 is read (cut-outs alias where a texel is under a pixel).
// Frame axes are rederived from the frame index by the documented lookAt rule (the viewer checks
// them against the file's frame_axes). The atlas side must be a multiple of `frames` (the
// export's default is): other sizes put frame borders inside texels, which the walk ignores.
//
// Textures (read texel by texel with texelFetch, level 0; v runs down the image, as glTF's UVs and
// three's GLTFLoader, flipY false):
//   color_atlas: RGB albedo, sRGB-encoded (or the shaded colour when lit_color == 1), A coverage
//     (the covered fraction of the texel; > 0: the texel holds a surface)
//   normal_depth_atlas: RGB object-space unit normal * 0.5 + 0.5, A depth code d (linear codes)
// Uniforms: the node's extras (frames, hemi = layout "hemi-octahedral", center, radius,
// half_extent, depth_near, depth_scale, alpha_tested), the camera in object space (eye_object, forward_object,
// orthographic), clip_from_object (for the depth written), the light (to_light_object, unit;
// light_terms = ambient, diffuse), and the walk's knobs (blend_frames 1 or 3, steps: the most
// texels walked per frame, <= 1024).
// Perspective captures (extras projection "perspective") are not handled: the export's default is
// ortho. Without a normal + depth texture (`lit` packages) each frame is its plane through the
// centre.
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
uniform int alpha_tested; // extras alpha_tested: the model has alpha-tested materials (foliage)
uniform vec3 eye_object;
uniform vec3 forward_object;
uniform int orthographic;
uniform mat4 clip_from_object;
uniform vec3 to_light_object;
uniform vec2 light_terms;
uniform int blend_frames;
uniform int steps; // the most texels walked per frame

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

// the constants of standin's height-field rule (src/reps/common/shaders/height_field.h)
const float k_slope_tolerance = 1.5;  // normals are sampled at texel centres: allow half as much again
const float k_curvature_texels = 0.5; // a curved surface turns between two normals: half a texel
const float k_quanta = 2.0;           // a step of two depth codes is rounding, not an edge
const float k_max_slope = 8.0;        // texels of depth per texel: steeper is a wall
const float k_top_max_slope = 3.0;    // a top's tilt, height per plane unit (atlas_layout.glsl ATLAS_TOP_MAX_SLOPE)

const int k_hit = 0, k_miss = 1, k_hidden = 2;

int g_texels; // texels per frame side (the atlas side / frames)

float texel_side() { return 2.0 * half_extent / float(g_texels); }
float depth_quantum() { return depth_scale / 255.0; }

// frame texel position (texel units, texel x spans [x, x + 1)) of plane coordinates
vec2 texel_from_plane(vec2 plane) { return (plane / half_extent * 0.5 + 0.5) * float(g_texels); }

float slope_of(float along, float across)
{
    along = abs(along);
    across = abs(across);
    return along >= across * k_max_slope ? k_max_slope : along / across;
}

// One texel of a frame's height field: x: covered (0/1), y: height (towards the frame's camera),
// zw: the normal's slope along axis_u and axis_v (height per unit of plane distance, capped);
// `coverage`: the texel's covered fraction; `gradient`: the top's tilt, its height change per
// plane unit along axis_u and axis_v (signed, capped at k_top_max_slope). Outside the frame: empty.
vec4 height_texel(Frame f, ivec2 texel, out float coverage, out vec2 gradient)
{
    coverage = 0.0;
    gradient = vec2(0.0);
    if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, ivec2(g_texels)))) return vec4(0.0);
    ivec2 at = f.cell * g_texels + texel;
    coverage = texelFetch(color_atlas, at, 0).a;
    if (coverage <= 0.0) return vec4(0.0);
    if (has_normal_depth == 0) return vec4(1.0, 0.0, 0.0, 0.0);
    vec4 nd = texelFetch(normal_depth_atlas, at, 0);
    vec3 n = nd.rgb * 2.0 - 1.0;
    vec3 n_frame = vec3(dot(n, f.axis_u), dot(n, f.axis_v), dot(n, f.direction));
    gradient = clamp(-n_frame.xy / max(n_frame.z, 1e-6), -k_top_max_slope, k_top_max_slope);
    return vec4(1.0, depth_near - nd.a * depth_scale, slope_of(n_frame.x, n_frame.z), slope_of(n_frame.y, n_frame.z));
}

vec4 height_texel(Frame f, ivec2 texel, out float coverage)
{
    vec2 gradient;
    return height_texel(f, texel, coverage, gradient);
}

// the largest height step between two neighbouring texels of one surface
float link_tolerance(vec4 a, vec4 b, int axis)
{
    return (k_slope_tolerance * max(a[2 + axis], b[2 + axis]) + k_curvature_texels) * texel_side() +
           k_quanta * depth_quantum();
}

// The coverage of the surface at `height` at frame plane point `plane` (atlas.frag `hit_coverage`):
// the coverage of the four texels around it, filtered bilinearly; a neighbour of the same surface
// adds its coverage, an empty one or one holding a surface behind adds none (the front surface
// would have been stored there), one holding a nearer surface tells nothing about this one and is
// left out of the weights. `presence`: the same with a neighbour holding a surface behind adding its
// coverage too (atlas.frag: whether the ray meets any surface here, which the vote on the background
// uses).
float hit_coverage(Frame f, vec2 plane, float height, out float presence)
{
    vec2 p = texel_from_plane(plane) - 0.5;
    ivec2 base = ivec2(floor(p));
    vec2 fr = p - vec2(base);
    float coverage = 0.0, weight_sum = 0.0;
    presence = 0.0;
    for (int k = 0; k < 4; ++k) {
        ivec2 corner = ivec2(k & 1, k >> 1);
        float w = (corner.x == 1 ? fr.x : 1.0 - fr.x) * (corner.y == 1 ? fr.y : 1.0 - fr.y);
        float a;
        vec4 t = height_texel(f, base + corner, a);
        if (t.x > 0.5) {
            float tolerance = (k_slope_tolerance * max(t.z, t.w) + k_curvature_texels + 1.0) * texel_side() +
                              k_quanta * depth_quantum();
            if (t.y > height + tolerance) continue;
            if (t.y >= height - tolerance) coverage += w * a;
            presence += w * a;
        }
        weight_sum += w;
    }
    presence = weight_sum > 0.0 ? presence / weight_sum : 1.0;
    return weight_sum > 0.0 ? coverage / weight_sum : 1.0;
}

// Intersects ray o + t d (object space) with one frame's height field (atlas.frag
// `intersect_view`, without its empty-cell skipping): returns (t, k_hit / k_miss / k_hidden);
// `coverage`: a hit's filtered coverage; `presence`: counting surfaces behind it too.
vec2 intersect_frame(Frame f, vec3 o, vec3 d, out float coverage, out float presence)
{
    coverage = 0.0;
    presence = 0.0;
    vec3 q = o - center;
    vec3 ro = vec3(dot(q, f.axis_u), dot(q, f.axis_v), dot(q, f.direction));
    vec3 rd = vec3(dot(d, f.axis_u), dot(d, f.axis_v), dot(d, f.direction));
    if (rd.z > -1e-4) return vec2(-1.0, float(k_miss));
    // the slab of heights the depth codes span, and the frame's square
    float top = depth_near, bottom = depth_near - depth_scale;
    if (has_normal_depth == 0) top = bottom = 0.0;
    float tilt = k_top_max_slope * texel_side(); // the most a tilted top rises or falls from its centre
    float t0 = (top + tilt + 1e-4 * radius - ro.z) / rd.z;
    float t1 = (bottom - tilt - 1e-4 * radius - ro.z) / rd.z;
    for (int a = 0; a < 2; ++a) {
        if (abs(rd[a]) < 1e-9) {
            if (abs(ro[a]) > half_extent) return vec2(-1.0, float(k_miss));
            continue;
        }
        float ta = (-half_extent - ro[a]) / rd[a], tb = (half_extent - ro[a]) / rd[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    t0 = max(t0, 0.0);
    if (t0 >= t1) return vec2(-1.0, float(k_miss));

    vec2 p0 = texel_from_plane((ro + t0 * rd).xy);
    vec2 dp = rd.xy * (float(g_texels) / (2.0 * half_extent)); // texels per unit t
    ivec2 step_dir = ivec2(dp.x >= 0.0 ? 1 : -1, dp.y >= 0.0 ? 1 : -1);
    vec2 inv = vec2(abs(dp.x) > 1e-9 ? 1.0 / abs(dp.x) : 1e30, abs(dp.y) > 1e-9 ? 1.0 / abs(dp.y) : 1e30);
    ivec2 cell = clamp(ivec2(floor(p0)), ivec2(0), ivec2(g_texels - 1));
    // where the ray crosses the lines x = X and y = Y (texels), from the start point so that every
    // step agrees
    vec2 t_next = vec2(t0 + abs(float(cell.x + max(step_dir.x, 0)) - p0.x) * inv.x,
                       t0 + abs(float(cell.y + max(step_dir.y, 0)) - p0.y) * inv.y);
    float t_enter = t0;
    int entered_across = -1; // axis crossed into the current texel, -1 at the start
    vec4 previous = vec4(0.0);
    vec2 previous_gradient = vec2(0.0);
    ivec2 previous_cell = cell;
    bool previous_above = true; // the ray left the previous texel above its top (or it was empty)
    bool hidden = false;
    vec2 p1 = texel_from_plane((ro + t1 * rd).xy);
    int count = min(int(abs(p0.x - p1.x) + abs(p0.y - p1.y)) + 3, steps);
    for (int i = 0; i < 1024; ++i) {
        if (i >= count) break;
        if (any(lessThan(cell, ivec2(0))) || any(greaterThanEqual(cell, ivec2(g_texels)))) break;
        float a;
        vec2 gradient;
        vec4 current = height_texel(f, cell, a, gradient);
        float t_exit = min(min(t_next.x, t_next.y), t1);
        // the tilted top, height current.y + gradient . (p - centre): the ray is compared with the
        // flat current.y as the ray z_origin + t z_per_t, shifted by the tilt (atlas.frag)
        vec2 centre = (vec2(cell) + 0.5) * texel_side() - half_extent;
        float z_origin = ro.z - dot(gradient, ro.xy - centre), z_per_t = rd.z - dot(gradient, rd.xy);
        if (current.x > 0.5) {
            // the crossing of this column (height_field.glsl `hf_cross_column`, in heights)
            float z_enter = z_origin + t_enter * z_per_t, z_exit = z_origin + t_exit * z_per_t;
            bool below = z_enter <= current.y;
            bool from_linked = below && entered_across >= 0 && previous.x > 0.5 && previous_above &&
                               abs(previous.y - current.y) <= link_tolerance(previous, current, entered_across);
            // the neighbour's tilted top where the ray crosses the wall, in the shifted frame
            float previous_top = 0.0;
            if (from_linked) {
                vec2 wall_point = ro.xy + t_enter * rd.xy;
                previous_top = previous.y + dot(previous_gradient, wall_point - ((vec2(previous_cell) + 0.5) * texel_side() - half_extent)) -
                               dot(gradient, wall_point - centre);
            }
            float t_hit = -1.0;
            if (from_linked && z_enter <= max(previous_top, current.y) && z_enter >= min(previous_top, current.y))
                t_hit = t_enter; // the wall between two texels of one surface
            else if (current.y <= z_enter && current.y >= z_exit)
                t_hit = abs(z_per_t) > 1e-20 ? clamp((current.y - z_origin) / z_per_t, t_enter, t_exit) : t_enter; // the top
            if (t_hit >= 0.0) {
                vec3 hit = ro + t_hit * rd; // plane coordinates and height
                coverage = hit_coverage(f, hit.xy, hit.z, presence);
                if (coverage >= 0.5) return vec2(t_hit, float(k_hit));
            } else if (below) {
                hidden = true; // entered under the top through a depth edge: space the frame did not see
            }
        }
        previous = current;
        previous_gradient = gradient;
        previous_cell = cell;
        previous_above = current.x < 0.5 || z_origin + t_exit * z_per_t > current.y;
        if (t_exit >= t1) break;
        if (t_next.x < t_next.y) {
            cell.x += step_dir.x;
            t_next.x = t0 + abs(float(cell.x + max(step_dir.x, 0)) - p0.x) * inv.x;
            entered_across = 0;
        } else {
            cell.y += step_dir.y;
            t_next.y = t0 + abs(float(cell.y + max(step_dir.y, 0)) - p0.y) * inv.y;
            entered_across = 1;
        }
        t_enter = t_exit;
    }
    return vec2(-1.0, float(hidden ? k_hidden : k_miss));
}

// A frame's colour (alpha: the summed weight) and normal at a hit: bilinear over the texels of the
// hit's own surface (height within the link rule's step and a texel), weighted by coverage.
void surface_sample(Frame f, vec2 plane, float height, out vec4 color, out vec3 normal)
{
    vec2 p = texel_from_plane(plane) - 0.5;
    ivec2 base = ivec2(floor(p));
    vec2 fr = p - vec2(base);
    color = vec4(0.0);
    normal = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
        ivec2 corner = ivec2(k & 1, k >> 1);
        float a;
        vec4 t = height_texel(f, base + corner, a);
        if (t.x < 0.5) continue;
        float tolerance = (k_slope_tolerance * max(t.z, t.w) + k_curvature_texels + 1.0) * texel_side() +
                          k_quanta * depth_quantum();
        if (abs(t.y - height) > tolerance) continue;
        float w = ((corner.x == 1 ? fr.x : 1.0 - fr.x) * (corner.y == 1 ? fr.y : 1.0 - fr.y) + 1e-6) * a;
        ivec2 at = f.cell * g_texels + base + corner;
        color += w * vec4(texelFetch(color_atlas, at, 0).rgb, 1.0);
        if (has_normal_depth == 1) normal += w * (texelFetch(normal_depth_atlas, at, 0).rgb * 2.0 - 1.0);
    }
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
    g_texels = max(textureSize(color_atlas, 0).x / frames, 1);

    // 1. the eye ray (for parallel projection from in front of the bounding sphere)
    vec3 ray = orthographic == 1 ? normalize(forward_object) : normalize(v_position_object - eye_object);
    vec3 origin = orthographic == 1 ? v_position_object - ray * 2.0 * radius : eye_object;

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

    // 3.-4. each frame intersected exactly; drawn where the frames that hit outweigh those that
    // saw nothing along the ray
    vec2 hits[3];
    float t_min = 1e30, hit_vote = 0.0, miss_vote = 0.0;
    for (int k = 0; k < 3; ++k) {
        hits[k] = vec2(-1.0, float(k_miss));
        if (f[k].weight <= 0.0) continue;
        float coverage, presence;
        hits[k] = intersect_frame(f[k], origin, ray, coverage, presence);
        if (int(hits[k].y) == k_hit) {
            t_min = min(t_min, hits[k].x);
            // a hit counts by how sure its frame is of it (within half a texel of its outline: less),
            // of any surface for the vote on the background, of its own for the vote on the surface
            hit_vote += f[k].weight * (smoothstep(0.5, 1.0, presence) * 0.999 + 0.001);
            f[k].weight *= smoothstep(0.5, 1.0, coverage) * 0.999 + 0.001;
        } else if (int(hits[k].y) == k_miss) {
            miss_vote += f[k].weight;
        } else if (alpha_tested == 0) {
            miss_vote += 0.05 * f[k].weight; // a solid model's abstaining frame, a little (atlas.frag)
        }
    }
    if (hit_vote <= 0.0 || hit_vote < miss_vote) discard;
    // and the surface voted on likewise: the nearest hit is kept where the frames meeting it weigh
    // at least as much as those seeing past it (a farther hit, or nothing), else the next
    for (int pass = 0; pass < 2; ++pass) {
        float front = 0.0, past = miss_vote, t_next = 1e30;
        for (int k = 0; k < 3; ++k) {
            if (int(hits[k].y) != k_hit || hits[k].x < t_min) continue;
            if (hits[k].x - t_min <= 2.0 * texel_side()) {
                front += f[k].weight;
            } else {
                past += f[k].weight;
                t_next = min(t_next, hits[k].x);
            }
        }
        if (front >= past || t_next >= 1e30) break;
        t_min = t_next;
    }

    // 5. hits within two texels of the surface voted for are one surface, fading out to four texels
    vec4 color_sum = vec4(0.0);
    vec3 normal_sum = vec3(0.0);
    float t_sum = 0.0, t_weight = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (int(hits[k].y) != k_hit || hits[k].x < t_min - 2.0 * texel_side()) continue;
        float weight = f[k].weight * clamp(2.0 - (hits[k].x - t_min) / (2.0 * texel_side()), 0.0, 1.0);
        if (weight <= 0.0) continue;
        vec3 q = origin + hits[k].x * ray - center;
        vec4 c;
        vec3 n;
        surface_sample(f[k], vec2(dot(q, f[k].axis_u), dot(q, f[k].axis_v)), dot(q, f[k].direction), c, n);
        if (c.a <= 0.0) continue;
        color_sum += weight * vec4(c.rgb / c.a, 1.0);
        normal_sum += weight * n / c.a;
        t_sum += weight * hits[k].x;
        t_weight += weight;
    }
    if (t_weight <= 0.0) discard;
    vec3 hit = origin + (t_sum / t_weight) * ray;
    vec4 clip = clip_from_object * vec4(hit, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
    vec3 albedo = color_sum.rgb / t_weight;

    // 6. standin's shading
    if (lit_color == 1) {
        out_color = vec4(albedo, 1.0);
        return;
    }
    vec3 n = has_normal_depth == 1 && dot(normal_sum, normal_sum) > 1e-12 ? normalize(normal_sum) : -ray;
    if (dot(n, -ray) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_object), 0.0);
    out_color = vec4(linear_to_srgb(srgb_to_linear(albedo) * (light_terms.x + light_terms.y * n_dot_l)), 1.0);
}
