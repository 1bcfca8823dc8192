#version 300 es
// Enhanced billboard, fragment stage (WebGL2 / GLSL ES 3.00): the reference for drawing a
// `role: "billboard"` node of a .glb written by `standin export` (docs/FORMAT.md, "Export" and
// "Geometry of a billboard"; Vichitvejpaisal 2005 §3.3: a ray cast through the billboard's height
// field inside its box), used as is by examples/web. Self-contained: no includes.
//
// Box space: x = dot(p - origin, axis_u) / texel_size (texels), y likewise along axis_v, z =
// dot(p - origin, direction) / depth_range (direction points into the model); texel (i, j) of the
// maps covers [i, i + 1) x [j, j + 1) (row 0 at origin: glTF UVs, three's GLTFLoader, flipY false).
// The surface is the one standin's exact march intersects (src/reps/enhanced_billboards/shaders/
// march.frag, MARCH_EXACT; reps/common/shaders/height_field.{h,glsl}): a covered texel (coverage
// code > 0) is a top at its depth tilted as its linked neighbours' depths say (texel_surface), and
// two neighbouring covered texels whose depth step is within what their normals' slopes allow (the
// shared link rule), or repeats beyond them, are joined by a wall, so thin leaves one texel wide
// and grazing views keep every texel the renderer keeps.
// Steps, per pixel of the box's back faces:
//  1. the eye ray in box space, clipped to the box (slabs);
//  2. a walk (DDA) from the entry through a min/max pyramid as standin's march climbs its own (a
//     cell whose depth range the ray's segment above it misses is skipped whole); in each covered
//     texel whose range (its depth and its linked neighbours') the ray's segment over it meets,
//     the crossing of the wall it was entered through (when that neighbour is linked) or else of
//     its top inside the texel (hf_cross_column), tops tilted as in standin
//     (texel_surface); the first crossing is the hit;
//  3. the hit's depth is written (gl_FragDepth), so boxes resolve by the depth test, and every
//     hit sets a stencil bit the coarse mesh is not drawn through (main.js: standin's coarse mesh
//     fills every pixel without a front hit, coarse.frag); no hit: discard, unless
//     mark_near_misses (main.js coarse=near-misses, standin's --coarse-fill near-misses) and the ray
//     came within a texel of a surface (its segment over a covered texel meets that texel's depth
//     range, its walls to linked neighbours included): then a near miss, drawn with alpha 0
//     (blended away) and far depth, only to set the stencil bit that the coarse mesh is then drawn
//     through;
//  4. shading is standin's: Lambert + ambient, two-sided, linear light, sRGB in and out; the texel
//     is the hit's (nearest, as texelFetch in standin).
// Departures from the standin renderer: one box per billboard, not its sheared per-tile boxes;
// the pyramid's ranges are conservative (links judged by the widest the rule allows, not by the
// normals); no level-of-detail shortcut (it only acts where 4 or more texels share a pixel).
// Textures: color_map (RGB sRGB albedo, A coverage), normal_depth_map (an RGBA16UI integer texture
// of the PNG's 16-bit codes, which main.js decodes itself: RGB object-space normal * 0.5 + 0.5, A
// depth d in [0, 1] of depth_range, as code / 65535), read with texelFetch; the maps may be larger
// than width x height (the export pads them to multiples of 4). Uniforms: the node's extras
// (origin, axis_u, axis_v, direction, texel_size, depth_range, width and height as size_texels),
// depth_quantum, pyramid / levels / pyramid_rows, the camera in object space (eye_object, forward_object, orthographic),
// clip_from_object, the light (to_light_object, unit; light_terms = ambient, diffuse).
precision highp float;
precision highp int;

uniform sampler2D color_map;
uniform highp usampler2D normal_depth_map; // RGBA16UI codes
uniform vec3 origin;
uniform vec3 axis_u;
uniform vec3 axis_v;
uniform vec3 direction;
uniform float texel_size;
uniform float depth_range;
uniform vec2 size_texels;
uniform float depth_quantum; // one step of the depth codes as read, in [0, 1] of depth_range
// min/max pyramid over the texels' depth ranges (each covered texel's depth and those of its
// neighbours a link may join; built by main.js from the maps): level k (1..levels: cells of 2^k
// texels) is the rectangle of rows from pyramid_rows[k], RG = lowest, highest depth (empty: 2, -1)
uniform highp sampler2D pyramid;
uniform int levels;
uniform int mark_near_misses; // 1: near misses set the stencil too (main.js coarse=near-misses)
uniform int pyramid_rows[9];
uniform vec3 eye_object;
uniform vec3 forward_object;
uniform int orthographic;
uniform mat4 clip_from_object;
uniform vec3 to_light_object;
uniform vec2 light_terms;

in vec3 v_position_object;
out vec4 out_color;

// the shared height-field rule (reps/common/shaders/height_field.h, copied: no includes here)
const float k_slope_tolerance = 1.5;
const float k_curvature_texels = 0.5;
const float k_quanta = 2.0;
const float k_max_slope = 8.0;
const float k_top_max_slope = 3.0;     // HF_TOP_MAX_SLOPE
const float k_top_reach_fraction = 0.25; // acceleration.cpp
const float k_miss = 0.0, k_top = 1.0, k_wall = 2.0;
// standin's edge-line codes (docs/FORMAT.md "Sheet edge lines"; billboard_layout.glsl in standin):
// a covered texel whose colour alpha is FIRST..FIRST + ANGLES * OFFSETS - 1 holds the line its
// surface ends at; 255 is a whole texel
const int k_edge_line_first = 128, k_edge_line_angles = 18, k_edge_line_offsets = 7;
const int k_max_iterations = 2048; // cells visited, at all levels (standin's march: 512)

vec4 normal_depth(ivec2 texel) { return vec4(texelFetch(normal_depth_map, texel, 0)) / 65535.0; }

vec3 box_from_object(vec3 p)
{
    vec3 q = p - origin;
    return vec3(dot(q, axis_u) / texel_size, dot(q, axis_v) / texel_size, dot(q, direction) / depth_range);
}

// depth change per texel along `axis` that normal n implies, in texels of depth, capped (hf_slope)
float slope_along(vec3 n, vec3 axis)
{
    float along = abs(dot(n, axis)), across = abs(dot(n, direction));
    return along >= across * k_max_slope ? k_max_slope : along / across;
}

// Whether box-space point p (x, y in texels) is on the surface of covered texel `texel`: everywhere,
// unless the texel holds an edge line (its alpha code), which the surface ends at (standin's
// march.frag on_surface).
bool on_surface(ivec2 texel, vec2 p)
{
    int code = int(texelFetch(color_map, texel, 0).a * 255.0 + 0.5) - k_edge_line_first;
    if (code < 0 || code >= k_edge_line_angles * k_edge_line_offsets) return true;
    float angle = float(code / k_edge_line_offsets) * (6.28318530718 / float(k_edge_line_angles));
    vec2 n = vec2(cos(angle), sin(angle));
    float e = ((float(code % k_edge_line_offsets) + 0.5) / float(k_edge_line_offsets) * 2.0 - 1.0) * 0.5 * (abs(n.x) + abs(n.y));
    return dot(n, p - vec2(texel) - 0.5) <= e;
}

// hf_cross_column (reps/common/shaders/height_field.glsl)
vec2 cross_column(float t_wall, float t_enter, float t_exit, float z_origin, float z_per_t, float top,
                  bool from_linked, float from_top)
{
    if (from_linked) {
        float z_wall = z_origin + t_wall * z_per_t;
        if (z_wall >= min(from_top, top) && z_wall <= max(from_top, top)) return vec2(t_wall, k_wall);
    }
    float z_enter = z_origin + t_enter * z_per_t, z_exit = z_origin + t_exit * z_per_t;
    if (top >= min(z_enter, z_exit) && top <= max(z_enter, z_exit)) {
        float t_top = abs(z_per_t) > 1e-20 ? clamp((top - z_origin) / z_per_t, t_enter, t_exit) : t_enter;
        return vec2(t_top, k_top);
    }
    return vec2(-1.0, k_miss);
}

// whether the step from depth `a` to `b` repeats from the covered texel `beyond` (a plane seen
// steeply: standin's acceleration.cpp texels_continue_plane, whatever the shading normals say)
bool step_repeats(float a, float b, ivec2 beyond, bool beyond_is_after)
{
    if (any(lessThan(beyond, ivec2(0))) || any(greaterThanEqual(beyond, ivec2(size_texels)))) return false;
    if (texelFetch(color_map, beyond, 0).a <= 0.5 / 255.0) return false;
    float d = normal_depth(beyond).a, step = b - a;
    float other_step = beyond_is_after ? d - b : a - d;
    return abs(other_step - step) <= k_curvature_texels * texel_size / depth_range + k_quanta * depth_quantum;
}

// whether covered texel `texel` (normal + depth nd) and its covered neighbour `other` (other_nd)
// continue one surface: the step is within what their normals allow (hf_link_tolerance), or is
// at most k_max_slope texels and repeats on a covered texel before or after them
bool linked(ivec2 texel, vec4 nd, ivec2 other, vec4 other_nd, vec3 axis_vector)
{
    float slope = max(slope_along(nd.rgb * 2.0 - 1.0, axis_vector), slope_along(other_nd.rgb * 2.0 - 1.0, axis_vector));
    float allowed = (k_slope_tolerance * slope + k_curvature_texels) * texel_size / depth_range + k_quanta * depth_quantum;
    float step = abs(nd.a - other_nd.a);
    if (step <= allowed) return true;
    if (step > k_max_slope * texel_size / depth_range) return false;
    ivec2 along = other - texel;
    return step_repeats(nd.a, other_nd.a, texel - along, false) || step_repeats(nd.a, other_nd.a, other + along, true);
}

// A covered texel's links, read once: its depth range (its depth and its linked neighbours', the
// renderer's SurfaceTexel min / max before the tilt's reach: a ray whose segment over the texel
// meets it came within a texel of the surface) and its top's tilt (standin's acceleration.cpp: the
// change of its box depth per texel along x and y from the depths of its linked neighbours,
// central where it has both, one-sided at an edge, flat where it has none, capped at
// k_top_max_slope texels of depth per texel).
vec2 texel_surface(ivec2 texel, vec4 nd, out vec2 range)
{
    range = vec2(nd.a);
    vec2 tilt = vec2(0.0);
    for (int a = 0; a < 2; ++a) {
        ivec2 step = a == 0 ? ivec2(1, 0) : ivec2(0, 1);
        vec3 axis_vector = a == 0 ? axis_u : axis_v;
        bool before = false, after = false;
        float d_before = 0.0, d_after = 0.0;
        for (int side = -1; side <= 1; side += 2) {
            ivec2 other = texel + side * step;
            if (any(lessThan(other, ivec2(0))) || any(greaterThanEqual(other, ivec2(size_texels)))) continue;
            if (texelFetch(color_map, other, 0).a <= 0.5 / 255.0) continue;
            vec4 other_nd = normal_depth(other);
            if (!linked(texel, nd, other, other_nd, axis_vector)) continue;
            range = vec2(min(range.x, other_nd.a), max(range.y, other_nd.a));
            if (side < 0) { before = true; d_before = other_nd.a; }
            else { after = true; d_after = other_nd.a; }
        }
        tilt[a] = before && after ? 0.5 * (d_after - d_before) : after ? d_after - nd.a : before ? nd.a - d_before : 0.0;
    }
    float cap = k_top_max_slope * texel_size / depth_range;
    return clamp(tilt, vec2(-cap), vec2(cap));
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
    vec3 o = box_from_object(start);
    vec3 d = box_from_object(start + ray) - o;
    const float tiny = 1e-20;
    vec3 inv = 1.0 / vec3(abs(d.x) > tiny ? d.x : tiny, abs(d.y) > tiny ? d.y : tiny, abs(d.z) > tiny ? d.z : tiny);
    vec3 box_max = vec3(size_texels, 1.0);
    vec3 ta = (vec3(0.0) - o) * inv, tb = (box_max - o) * inv;
    vec3 t_near = min(ta, tb), t_far = max(ta, tb);
    float t0 = max(max(t_near.x, t_near.y), max(t_near.z, 0.0));
    float t1 = min(min(t_far.x, t_far.y), t_far.z);
    if (t1 <= t0) discard;

    // 2. the walk (Amanatides & Woo 1987) through the min/max pyramid (Tevs et al. 2008) as standin's
    // march climbs it: a cell whose depth range the ray's segment above it misses is skipped whole;
    // in a texel, standin's exact column crossing
    ivec2 size = ivec2(size_texels);
    ivec2 dir = ivec2(d.x >= 0.0 ? 1 : -1, d.y >= 0.0 ? 1 : -1);
    ivec2 ahead = max(dir, ivec2(0)); // 1 where a cell's exit side is its upper one
    float link_scale = texel_size / depth_range; // one texel of depth, in units of depth_range
    // a box as deep as the model: start as high as the ray's path across the plane is long
    float footprint = length(d.xy) * (t1 - t0);
    int level = clamp(int(ceil(log2(footprint + 1.0))), 0, levels);
    float t = t0;
    ivec2 texel = clamp(ivec2(floor(o.xy + t0 * d.xy + vec2(dir) * 1e-3)), ivec2(0), size - 1);
    // the last texel read at level 0: the one a wall crossing comes from, most of the time
    ivec2 last_texel = ivec2(-1);
    bool last_covered = false;
    vec4 last_nd = vec4(0.0);
    bool found = false, near = false;
    float t_hit = 0.0;
    ivec2 hit_texel = texel;
    int iteration = 0;
    for (; iteration < k_max_iterations; ++iteration) {
        ivec2 cell = texel >> level;
        vec2 t_bounds = (vec2((cell + ahead) << level) - o.xy) * inv.xy;
        int axis = t_bounds.x < t_bounds.y ? 0 : 1;
        float t_exit = min(t_bounds[axis], t1);
        float z_a = o.z + t * d.z, z_b = o.z + t_exit * d.z;
        float z_lo = min(z_a, z_b), z_hi = max(z_a, z_b);
        if (level > 0) {
            vec2 range = texelFetch(pyramid, ivec2(cell.x, pyramid_rows[level] + cell.y), 0).rg;
            if (range.x <= z_hi && range.y >= z_lo) {
                --level; // the segment may meet the surface below this cell: look closer
                continue;
            }
        } else {
            bool covered = texelFetch(color_map, texel, 0).a > 0.5 / 255.0; // standin: coverage code != 0
            vec4 nd = vec4(0.0);
            if (covered) {
                nd = normal_depth(texel);
                // the wall to the texel the ray came from, if it continues this surface, then the top
                vec2 t_entries = (vec2(texel + ivec2(1) - ahead) - o.xy) * inv.xy;
                int entry_axis = t_entries.x > t_entries.y ? 0 : 1;
                float t_in = t_entries[entry_axis];
                ivec2 from = texel;
                from[entry_axis] -= dir[entry_axis];
                bool from_linked = false;
                vec4 from_nd = last_nd;
                if (t_in >= t0 && from[entry_axis] >= 0 && from[entry_axis] < size[entry_axis]) {
                    bool from_covered = last_covered;
                    if (from != last_texel) {
                        from_covered = texelFetch(color_map, from, 0).a > 0.5 / 255.0;
                        from_nd = normal_depth(from);
                    }
                    from_linked = from_covered && linked(texel, nd, from, from_nd, entry_axis == 0 ? axis_u : axis_v);
                }
                // standin's tilted tops: each top is the plane through its depth at the texel's
                // centre with its linked neighbours' slope (capped), the ray shifted by the tilt,
                // the wall between the two tilted tops; crossed only where the ray's segment over
                // the texel meets the texel's range (its depth and its linked neighbours'), as in
                // standin
                vec2 links_range;
                vec2 tilt = texel_surface(texel, nd, links_range), centre = vec2(texel) + 0.5;
                float z_origin = o.z - dot(tilt, o.xy - centre), z_per_t = d.z - dot(tilt, d.xy);
                float from_top = from_nd.a;
                if (from_linked) {
                    vec2 wall_point = o.xy + t_in * d.xy;
                    vec2 from_range;
                    from_top += dot(texel_surface(from, from_nd, from_range), wall_point - vec2(from) - 0.5) - dot(tilt, wall_point - centre);
                }
                // (the range holds a quarter of the top's own reach, and the top ends at the range:
                // standin's acceleration.cpp k_top_reach_fraction, march.frag)
                float reach = k_top_reach_fraction * 0.5 * (abs(tilt.x) + abs(tilt.y));
                vec2 own_range = links_range + vec2(-reach, reach);
                vec2 crossing = own_range.x <= z_hi && own_range.y >= z_lo
                                    ? cross_column(t_in, t, t_exit, z_origin, z_per_t, nd.a, from_linked, from_top)
                                    : vec2(-1.0, k_miss);
                float z_cross = o.z + crossing.x * d.z;
                if (z_cross < own_range.x || z_cross > own_range.y) crossing.y = k_miss;
                // standin's edge lines (a sheet's rim, a leaf's cut-out contour): a crossing beyond
                // the line its texel holds is no hit, and the ray walks on
                vec2 p_cross = o.xy + crossing.x * d.xy;
                bool on = crossing.y == k_top ? on_surface(texel, p_cross)
                        : crossing.y == k_wall && on_surface(texel, p_cross) && on_surface(from, p_cross);
                if (crossing.y != k_miss && on) {
                    t_hit = crossing.x;
                    // on a wall, the texel whose top is nearer the crossing
                    float z_in = z_origin + t_in * z_per_t;
                    hit_texel = crossing.y == k_wall && abs(z_in - from_top) < abs(z_in - nd.a) ? from : texel;
                    found = true;
                    break;
                }
                if (!near) {
                    // the renderer's near miss: the segment over the texel meets its range (the widest
                    // a link allows bounds it first, so most texels the ray passes high above cost no more)
                    float widest = (k_slope_tolerance * k_max_slope + k_curvature_texels) * link_scale + k_quanta * depth_quantum;
                    float slack = 0.5 / 65535.0;
                    if (nd.a - widest <= z_hi + slack && nd.a + widest >= z_lo - slack)
                        near = links_range.x <= z_hi + slack && links_range.y >= z_lo - slack;
                }
            }
            last_texel = texel;
            last_covered = covered;
            last_nd = nd;
        }

        // leave the cell: into the neighbouring one, one level up when that is in another parent
        if (t_exit >= t1) break;
        ivec2 next = texel;
        next[axis] = (cell[axis] + dir[axis]) << level;
        if (dir[axis] < 0) next[axis] += (1 << level) - 1;
        int other = 1 - axis;
        float along = o[other] + t_exit * d[other];
        int lo = cell[other] << level, hi = ((cell[other] + 1) << level) - 1;
        next[other] = clamp(int(floor(along + float(dir[other]) * 1e-3)), lo, hi);
        if (next[axis] < 0 || next[axis] >= size[axis]) break;
        if (level < levels && (cell >> 1) != ((next >> level) >> 1)) ++level;
        texel = next;
        t = t_exit;
    }
    if (iteration == k_max_iterations) near = true; // out of iterations: let the coarse mesh decide
    if (!found) {
        // 3. a near miss marks the stencil only (main.js, coarse=near-misses); anything else is no
        // part of the picture
        if (!near || mark_near_misses == 0) discard;
        gl_FragDepth = 1.0;
        out_color = vec4(0.0);
        return;
    }

    // 3. the hit's depth
    vec3 hit_object = start + ray * t_hit;
    vec4 clip = clip_from_object * vec4(hit_object, 1.0);
    gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);

    // 4. standin's shading
    vec3 albedo = texelFetch(color_map, hit_texel, 0).rgb;
    vec3 n = normalize(normal_depth(hit_texel).rgb * 2.0 - 1.0);
    if (dot(n, -ray) < 0.0) n = -n;
    float n_dot_l = max(dot(n, to_light_object), 0.0);
    out_color = vec4(linear_to_srgb(srgb_to_linear(albedo) * (light_terms.x + light_terms.y * n_dot_l)), 1.0);
}
