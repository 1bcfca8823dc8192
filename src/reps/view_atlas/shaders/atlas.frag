#version 450 core
// View atlas, per fragment.
// STYLE_SEED: the nearest view's texel (seed 003 §3), lit colour as baked or, with surface maps,
// albedo lit from the stored normal.
// STYLE_BASELINE: the way impostor bakers draw: the three views around the viewing direction, each
// read where the eye ray crosses the centre plane moved by one parallax step along its depth,
// blended by weight.
// STYLE_CORRECTED: each of the three views is intersected with the eye ray as a height field
// (linear search over its texels, then bisection: the surface point the view really holds), hits on
// the same surface are blended, the true depth is written and the stored normal is lit.
// Filtering never bleeds the background: pages hold colour premultiplied by coverage, are mip-mapped
// as such, and are divided by the filtered coverage; levels stop where two crops would mix.
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "reps/view_atlas/shaders/atlas.glsl"

flat in ivec3 v_views;
flat in vec3 v_weights;
flat in int v_instance;
in vec2 v_atlas_texel;

#ifndef ATLAS_ARRAYS
#define ATLAS_ARRAYS 1 // texture arrays per map, 1..ATLAS_MAX_ARRAYS (renderer.cpp defines it)
#endif
layout(binding = ATLAS_COLOR_TEXTURE) uniform sampler2DArray color_pages[ATLAS_ARRAYS];
layout(binding = ATLAS_NORMAL_DEPTH_TEXTURE) uniform sampler2DArray normal_depth_pages[ATLAS_ARRAYS];
#define MAP_COLOR 0
#define MAP_NORMAL_DEPTH 1

uniform int style;
uniform int lit_maps; // 1: colour pages hold the baked lit colour (no normals)

layout(location = 0) out vec4 out_color;

// A read of one map's texture array `array`. Views of one draw lie in different arrays, so the
// sampler is chosen by branching (indices into sampler arrays must be dynamically uniform).
#define ATLAS_READ(i) if (array == i) return map == MAP_COLOR ? textureLod(color_pages[i], uvw, lod) : textureLod(normal_depth_pages[i], uvw, lod);
vec4 read_array(int map, int array, vec3 uvw, float lod)
{
#if ATLAS_ARRAYS > 1
    ATLAS_READ(1)
#endif
#if ATLAS_ARRAYS > 2
    ATLAS_READ(2)
#endif
#if ATLAS_ARRAYS > 3
    ATLAS_READ(3)
#endif
#if ATLAS_ARRAYS > 4
    ATLAS_READ(4)
#endif
#if ATLAS_ARRAYS > 5
    ATLAS_READ(5)
#endif
#if ATLAS_ARRAYS > 6
    ATLAS_READ(6)
#endif
#if ATLAS_ARRAYS > 7
    ATLAS_READ(7)
#endif
#if ATLAS_ARRAYS > 8
#error "atlas.frag reads at most 8 texture arrays per map (ATLAS_MAX_ARRAYS)"
#endif
    return map == MAP_COLOR ? textureLod(color_pages[0], uvw, lod) : textureLod(normal_depth_pages[0], uvw, lod);
}

// A page sample of map MAP_COLOR or MAP_NORMAL_DEPTH at an atlas texel position, clamped inside
// the view's crop at that level.
vec4 sample_page(int map, ViewData view, vec2 texel, float lod)
{
    lod = clamp(lod, 0.0, float(MAX_LOD));
    float margin = 0.5 * exp2(ceil(lod));
    vec2 lo = vec2(view.atlas.yz) + margin, hi = vec2(view.atlas.yz + view.crop.zw) - margin;
    texel = clamp(texel, lo, hi);
    return read_array(map, view.atlas.w, vec3(texel / page_size, float(view.atlas.x)), lod);
}

// atlas texel position of a point given in view-plane coordinates
vec2 atlas_texel(ViewData view, vec2 plane)
{
    return vec2(view.atlas.yz) + capture_from_plane(plane) - vec2(view.crop.xy);
}

// A view's surface depth along its direction (object units from the centre plane, towards the
// capture camera positive) and coverage at a view-plane point.
vec2 surface_at(ViewData view, vec2 plane)
{
    vec2 texel = atlas_texel(view, plane);
    float coverage = sample_page(MAP_COLOR, view, texel, 0.0).a;
    float depth = sample_page(MAP_NORMAL_DEPTH, view, texel, 0.0).a;
    depth = coverage > 0.0 ? depth / coverage : 1.0;
    return vec2(atlas_radius - 2.0 * atlas_radius * depth, coverage);
}

// Intersects ray o + t d (object space) with one view's height field. Returns t or -1.
float intersect_view(ViewData view, vec3 o, vec3 d)
{
    vec3 u = view.axis_u.xyz, v = view.axis_v.xyz, w = view.direction.xyz;
    vec3 ro = vec3(dot(o - atlas_center, u), dot(o - atlas_center, v), dot(o - atlas_center, w));
    vec3 rd = vec3(dot(d, u), dot(d, v), dot(d, w));
    // the crop's box: plane rectangle x depth [-r, r]
    vec2 lo = plane_from_capture(vec2(view.crop.xy)), hi = plane_from_capture(vec2(view.crop.xy + view.crop.zw));
    vec3 box_lo = vec3(lo, -atlas_radius), box_hi = vec3(hi, atlas_radius);
    vec3 inv = 1.0 / vec3(abs(rd.x) < 1e-12 ? 1e-12 : rd.x, abs(rd.y) < 1e-12 ? 1e-12 : rd.y,
                          abs(rd.z) < 1e-12 ? 1e-12 : rd.z);
    vec3 ta = (box_lo - ro) * inv, tb = (box_hi - ro) * inv;
    vec3 tn = min(ta, tb), tf = max(ta, tb);
    float t0 = max(max(tn.x, tn.y), max(tn.z, 0.0)), t1 = min(min(tf.x, tf.y), tf.z);
    if (t0 >= t1) return -1.0;
    // linear search, about one and a half texels per step, then bisection
    float texel = 2.0 * half_extent / resolution;
    float travel = length(rd.xy) * (t1 - t0) / texel;
    int steps = clamp(int(ceil(travel / 1.5)) + 4, 8, 160);
    float dt = (t1 - t0) / float(steps);
    float t_prev = t0;
    bool above = false; // a hit is a crossing from above the surface to below it: a ray that
                        // enters the box below the surface is where this view saw nothing
    for (int i = 0; i <= steps; ++i) {
        float t = t0 + dt * float(i);
        vec3 p = ro + t * rd;
        vec2 s = surface_at(view, p.xy);
        bool below = s.y >= 0.5 && p.z <= s.x;
        if (!below) {
            above = true;
        } else if (above) {
            float a = t_prev, b = t;
            for (int j = 0; j < 6; ++j) {
                float m = 0.5 * (a + b);
                vec3 q = ro + m * rd;
                vec2 sm = surface_at(view, q.xy);
                if (sm.y >= 0.5 && q.z <= sm.x) b = m; else a = m;
            }
            return b;
        }
        t_prev = t;
    }
    return -1.0;
}

vec3 shade_surface(vec3 albedo, vec3 normal_object, vec3 direction_world, vec3 position_world)
{
    mat4 world_from_object = instances.world_from_object[v_instance];
    vec3 normal_world = normalize(mat3(world_from_object) * normal_object);
    return shade_at(albedo, normal_world, -direction_world, position_world);
}

void main()
{
    mat4 world_from_object = instances.world_from_object[v_instance];
    mat4 object_from_world = inverse(world_from_object);
    vec3 origin_world, direction_world;
    camera_ray(gl_FragCoord.xy, origin_world, direction_world);
    vec3 o = (object_from_world * vec4(origin_world, 1.0)).xyz;
    vec3 d = normalize(mat3(object_from_world) * direction_world);

    if (style == STYLE_SEED) {
        ViewData view = views.items[v_views.x];
        vec2 dx = dFdx(v_atlas_texel), dy = dFdy(v_atlas_texel);
        float lod = log2(max(max(length(dx), length(dy)), 1e-8));
        vec4 c = sample_page(MAP_COLOR, view, v_atlas_texel, lod);
        if (c.a < 0.5) discard;
        vec3 color = c.rgb / c.a;
        if (lit_maps == 0) {
            vec3 n = sample_page(MAP_NORMAL_DEPTH, view, v_atlas_texel, lod).rgb / c.a * 2.0 - 1.0;
            color = shade_surface(color, n, direction_world, fragment_world_position());
        }
        out_color = vec4(color, 1.0);
        gl_FragDepth = gl_FragCoord.z;
        return;
    }

    // the level of detail from the centre plane's texel footprint (uniform control flow)
    ViewData first = views.items[v_views.x];
    float t_plane = -dot(o - atlas_center, first.direction.xyz) / dot(d, first.direction.xyz);
    vec3 on_plane = o + t_plane * d - atlas_center;
    vec2 plane_texel = capture_from_plane(vec2(dot(on_plane, first.axis_u.xyz), dot(on_plane, first.axis_v.xyz)));
    float lod = log2(max(max(length(dFdx(plane_texel)), length(dFdy(plane_texel))), 1e-8));

    vec4 color_sum = vec4(0.0), normal_sum = vec4(0.0);
    float t_sum = 0.0, t_weight = 0.0;
    if (style == STYLE_BASELINE) {
        for (int k = 0; k < 3; ++k) {
            if (v_weights[k] <= 0.0) continue;
            ViewData view = views.items[v_views[k]];
            vec3 w = view.direction.xyz;
            float dw = dot(d, w);
            if (abs(dw) < 1e-6) continue;
            float t = -dot(o - atlas_center, w) / dw; // the centre plane
            vec3 p = o + t * d - atlas_center;
            vec2 texel = atlas_texel(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)));
            vec4 nd = sample_page(MAP_NORMAL_DEPTH, view, texel, lod);
            float coverage = sample_page(MAP_COLOR, view, texel, lod).a;
            if (coverage > 0.0) { // one parallax step to the depth read there
                float height = atlas_radius - 2.0 * atlas_radius * nd.a / coverage;
                t += height / dw;
                p = o + t * d - atlas_center;
                texel = atlas_texel(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)));
            }
            color_sum += v_weights[k] * sample_page(MAP_COLOR, view, texel, lod);
            normal_sum += v_weights[k] * sample_page(MAP_NORMAL_DEPTH, view, texel, lod);
        }
        if (color_sum.a < 0.5) discard;
        vec3 albedo = color_sum.rgb / color_sum.a;
        vec3 n = normal_sum.rgb / color_sum.a * 2.0 - 1.0;
        out_color = vec4(lit_maps != 0 ? albedo : shade_surface(albedo, n, direction_world, fragment_world_position()), 1.0);
        gl_FragDepth = gl_FragCoord.z;
        return;
    }

    // corrected: every view's own intersection; the nearest hits (one surface) are blended
    float hits[3] = float[3](-1.0, -1.0, -1.0);
    float t_min = 1e30, hit_weight = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (v_weights[k] <= 0.0) continue;
        hits[k] = intersect_view(views.items[v_views[k]], o, d);
        if (hits[k] >= 0.0) {
            t_min = min(t_min, hits[k]);
            hit_weight += v_weights[k];
        }
    }
    if (hit_weight < 0.5) discard;
    float same_surface = 4.0 * (2.0 * half_extent / resolution); // four texels
    for (int k = 0; k < 3; ++k) {
        if (hits[k] < 0.0 || hits[k] > t_min + same_surface) continue;
        ViewData view = views.items[v_views[k]];
        vec3 p = o + hits[k] * d - atlas_center;
        vec2 texel = atlas_texel(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)));
        float level = lod;
        vec4 c = sample_page(MAP_COLOR, view, texel, level);
        if (c.a <= 0.0) {
            level = 0.0;
            c = sample_page(MAP_COLOR, view, texel, level);
        }
        if (c.a <= 0.0) continue;
        vec4 nd = sample_page(MAP_NORMAL_DEPTH, view, texel, level);
        color_sum += v_weights[k] * vec4(c.rgb / c.a, 1.0);
        normal_sum += v_weights[k] * vec4(nd.rgb / max(c.a, 1e-6) * 2.0 - 1.0, 0.0);
        t_sum += v_weights[k] * hits[k];
        t_weight += v_weights[k];
    }
    if (t_weight <= 0.0) discard;
    vec3 p_object = o + (t_sum / t_weight) * d;
    vec3 p_world = (world_from_object * vec4(p_object, 1.0)).xyz;
    vec3 albedo = color_sum.rgb / t_weight;
    out_color = vec4(lit_maps != 0 ? albedo : shade_surface(albedo, normal_sum.xyz, direction_world, p_world), 1.0);
    gl_FragDepth = window_depth(p_world);
}
