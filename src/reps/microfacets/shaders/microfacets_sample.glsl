// Microfacets: reading a captured view at a point of a facet, with the clipping rule of Yamazaki et
// al. 2002 eq. 1 (a texel is kept where the view's stored surface lies within W/2 of the facet,
// measured along the view, §3.3.3). Beyond the paper: packages of alpha-tested models store each
// texel's covered fraction, and a surface point is kept where that coverage, filtered bilinearly,
// reaches 1/2 (hit_coverage, issue #14), so cut-out edges fall inside texels. Shared by the quads' fragment stage and the points' vertex
// stage. Include after microfacets.glsl.
#include "reps/common/shaders/height_field.glsl"
#include "reps/common/shaders/coverage.glsl"

layout(binding = MF_COLOR_TEXTURE) uniform sampler2DArray color_pages;
layout(binding = MF_NORMAL_DEPTH_TEXTURE) uniform sampler2DArray normal_depth_pages;
#ifndef MF_PBR
#define MF_PBR 0 // 1: the package has ORM and emission pages (issue #14; renderer.cpp defines it)
#endif
#if MF_PBR
layout(binding = MF_ORM_TEXTURE) uniform sampler2DArray orm_pages;
layout(binding = MF_EMISSION_TEXTURE) uniform sampler2DArray emission_pages;
#endif

uniform float page_size;  // texels per page side
uniform int max_color_lod; // mip levels of the colour pages that never mix two crops
// MF_CLIP_*: renderer.cpp compiles it into the fragment programs (MF_CLIP_RULE), since llvmpipe
// runs every branch for every fragment, masked (the ray clip paid for eq. 1's sampling of each view
// too); without the define, a uniform.
#ifdef MF_CLIP_RULE
const int clip_rule = MF_CLIP_RULE;
#else
uniform int clip_rule;
#endif
// 1 (the default, binary pages too): a surface is kept where the colour pages' coverage (alpha),
// filtered at the hit, reaches 1/2 (hit_coverage, issue #14); 0: every covered texel is surface
// (renderer.cpp: STANDIN_MICROFACETS_FILTER_BINARY=0, for measurements)
uniform int fractional_coverage;

uint g_fetches = 0u;

// normals are n * 0.5 + 0.5 in unsigned normalised channels (microfacets.h)
vec3 decode_normal(vec3 stored) { return stored * 2.0 - 1.0; }

struct ViewSample {
    bool passed;    // covered and within W/2 (eq. 1)
    vec3 color;     // albedo, sRGB-encoded
    vec3 orm;       // occlusion, roughness, metallic (Material's defaults without MF_PBR)
    vec3 emission;  // sRGB-encoded (black without MF_PBR)
    vec3 normal;    // object space, unnormalised
    vec3 surface;   // the stored surface point: the facet point moved along the view to its depth
};

// A view's stored normal turned towards `to_eye` (object space) before it is blended: captures turn
// each normal towards their own camera (capture.cpp step 3), so two views on either side of a
// double-sided leaf card store opposite normals, whose sum cancels into whatever the views' other
// differences leave. The truth turns a double-sided face's normal towards the eye (lighting.glsl
// shade_pbr), so each view's normal is turned the same way before the blend; for a surface every
// view sees from its front the turn changes nothing.
vec3 facing(vec3 normal, vec3 to_eye) { return dot(normal, to_eye) < 0.0 ? -normal : normal; }

// The colour of a view at capture pixel position `position` (a float position inside the view's
// crop), straight (not premultiplied): filtered bilinearly at level 0, and at lod > 0 over the
// footprint, kept inside the crop (crops sit on cells of 2^max_color_lod texels).
vec3 view_page(sampler2DArray pages, ViewData view, vec2 position, float lod)
{
    lod = clamp(lod, 0.0, float(max_color_lod));
    float margin = 0.5 * exp2(ceil(lod));
    vec2 page = clamp(vec2(view.atlas.yz) + position - vec2(view.crop.xy), vec2(view.atlas.yz) + margin,
                      vec2(view.atlas.yz + view.crop.zw) - margin);
    vec4 c = textureLod(pages, vec3(page / page_size, float(view.atlas.x)), lod);
    g_fetches += 1u;
    return c.a > 0.0 ? c.rgb / c.a : c.rgb;
}

vec3 view_color(ViewData view, vec2 position, float lod) { return view_page(color_pages, view, position, lod); }

// Whether the texels at the corners of a footprint of 2^lod texels around capture position `position`
// all hold the surface of the hit (height `height` along the view, normal `normal`): then a colour
// filtered over that footprint mixes only that surface's texels, as the truth's texture filter does
// within a face; else the filter would mix leaves, or a leaf and the one behind it.
bool one_surface_around(ViewData view, vec2 position, float lod, float height, vec3 normal)
{
    const float texel = 2.0 * mf_radius / capture_resolution;
    float r = 0.5 * exp2(lod);
    for (int k = 0; k < 4; ++k) {
        ivec2 cell = ivec2(floor(position + vec2((k & 1) != 0 ? r : -r, (k & 2) != 0 ? r : -r)));
        if (any(lessThan(cell, view.crop.xy)) || any(greaterThanEqual(cell, view.crop.xy + view.crop.zw))) return false;
        vec4 nd = texelFetch(normal_depth_pages, ivec3(view.atlas.yz + cell - view.crop.xy, view.atlas.x), 0);
        g_fetches += 1u;
        if (nd.r + nd.g + nd.b == 0.0) return false;
        // within two texels of height per texel of distance (slopes up to ~63 degrees), normals within ~25 degrees
        if (abs(stored_height(nd.a) - height) > 2.0 * (2.0 * r + 1.0) * texel) return false;
        if (dot(decode_normal(nd.rgb), normal) < 0.9) return false;
    }
    return true;
}

// The PBR inputs of the same texel as view_color (the pages share its layout and coverage).
void view_material(ViewData view, vec2 position, float lod, inout ViewSample s)
{
#if MF_PBR
    s.orm = view_page(orm_pages, view, position, lod);
    s.emission = view_page(emission_pages, view, position, lod);
#else
    s.orm = vec3(1.0, 1.0, 0.0); // lighting.glsl SHADING_DEFAULT_ORM (this file is also a vertex stage's)
    s.emission = vec3(0.0);
#endif
}


// The coverage of the view's surface at object-space point `surface` (issue #14): the colour pages'
// alpha (the covered fraction of each texel, capture.h) of the four texels around the point,
// filtered bilinearly among those holding the same surface (reps/common/shaders/coverage.glsl).
float hit_coverage(ViewData view, vec3 surface)
{
    const float texel = 2.0 * mf_radius / capture_resolution, quantum = 2.0 * mf_radius / HF_DEPTH_CODES;
    vec3 dir = view.direction.xyz;
    vec2 p = capture_pixel(view, surface) - 0.5;
    ivec2 base = ivec2(floor(p));
    bvec4 covered = bvec4(false);
    vec4 heights = vec4(0.0), tolerances = vec4(0.0), alphas = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        ivec2 cell = base + ivec2(k & 1, k >> 1);
        if (any(lessThan(cell, view.crop.xy)) || any(greaterThanEqual(cell, view.crop.xy + view.crop.zw))) continue;
        ivec3 at = ivec3(view.atlas.yz + cell - view.crop.xy, view.atlas.x);
        vec4 nd = texelFetch(normal_depth_pages, at, 0);
        g_fetches += 2u;
        if (nd.r + nd.g + nd.b == 0.0) continue;
        vec3 normal = decode_normal(nd.rgb);
        covered[k] = true;
        heights[k] = stored_height(nd.a);
        tolerances[k] = hf_coverage_tolerance(hf_slope(dot(normal, view.axis_u.xyz), dot(normal, dir)),
                                              hf_slope(dot(normal, view.axis_v.xyz), dot(normal, dir)), texel, quantum);
        alphas[k] = texelFetch(color_pages, at, 0).a;
    }
    return hf_filtered_coverage(p - vec2(base), dot(surface - mf_center, dir), covered, heights, tolerances, alphas);
}

// Whether a surface point a view stored counts as surface: always with binary coverage, else where
// its filtered coverage reaches 1/2, the truth's alpha-test rule.
bool covered_enough(ViewData view, vec3 surface)
{
    return fractional_coverage == 0 || hit_coverage(view, surface) >= 0.5;
}

// The view's sample at facet point p (object space) for the facet of the voxel at `center` of size
// w; `lod` is the colour's mip level (<= 0: the exact texel; above: the covered texels around it,
// averaged through the pages' coverage-premultiplied mips).
ViewSample sample_view(ViewData view, vec3 p, vec3 center, float w, float lod)
{
    ViewSample s;
    s.passed = false;
    ivec2 texel = ivec2(floor(capture_pixel(view, p)));
    if (any(lessThan(texel, view.crop.xy)) || any(greaterThanEqual(texel, view.crop.xy + view.crop.zw))) return s;
    ivec2 at = view.atlas.yz + texel - view.crop.xy;
    vec4 nd = texelFetch(normal_depth_pages, ivec3(at, view.atlas.x), 0);
    g_fetches += 1u;
    if (nd.r + nd.g + nd.b == 0.0) return s; // empty texel
    float stored = stored_height(nd.a), here = dot(p - mf_center, view.direction.xyz);
    if (abs(stored - here) >= 0.5 * w) return s; // eq. 1
    s.surface = p + (stored - here) * view.direction.xyz;
    // MF_CLIP_VOXEL: the surface point must lie in the facet's own voxel (grown by a texel), so a
    // surface point is drawn by one facet, not by every facet whose square reaches over it
    if (clip_rule == MF_CLIP_VOXEL && any(greaterThan(abs(s.surface - center), vec3(0.5 * w + 2.0 * mf_radius / capture_resolution))))
        return s;
    if (lod <= 0.0 && !covered_enough(view, s.surface)) return s; // beside a cut-out's edge
    s.passed = true;
    s.normal = decode_normal(nd.rgb);
    s.color = view_color(view, vec2(texel) + 0.5, lod);
    view_material(view, vec2(texel) + 0.5, lod, s);
    return s;
}

// The colour mip level at which one texel of the capture spans `span` object units.
float color_lod(float span) { return log2(max(span * capture_resolution / (2.0 * mf_radius), 1e-6)); }

// --- MF_CLIP_RAY: the pixel's ray inside the facet's voxel against the view's depth -------------
// Beyond the paper: instead of showing a view's texel where its ray meets the facet's plane (eq. 1,
// which misplaces the surface by up to W/2 tan(delta) on screen, eq. 2), walk the part of the
// pixel's ray inside the facet's voxel across the view's texel columns with the image-based
// stand-ins' one height-field rule (reps/common/shaders/height_field.glsl: texel tops, walls to
// neighbours of the same surface, space under a surface unseen) and stop at the first crossing.
// Every view then places the surface where it is, the blended views agree, and the depth written is
// the surface's. Inside a voxel the ray moves up to sqrt(3) W sin(delta) across the view: a few
// texels at the finest levels, more at coarse ones.
#define RAY_MISS 0   // the ray crossed the voxel without meeting the view's surface
#define RAY_HIT 1
#define RAY_HIDDEN 2 // the ray passed under a surface the view saw: it cannot tell what is there

// The ray o + t d (object space, d unit) inside the box of the voxel at `center` (size w, grown by
// `grow`): [t0, t1], empty when t0 > t1.
vec2 voxel_span(vec3 o, vec3 d, vec3 center, float w, float grow)
{
    vec3 inverse = 1.0 / d;
    vec3 a = (center - (0.5 * w + grow) - o) * inverse, b = (center + (0.5 * w + grow) - o) * inverse;
    vec3 near = min(a, b), far = max(a, b);
    return vec2(max(max(near.x, near.y), max(near.z, 0.0)), min(min(far.x, far.y), far.z));
}

// Texels a walk visits at most (walk_view); a longer segment walks every 2^k-th column instead.
#define MF_WALK_STEPS 64

int walk_view(ViewData view, vec3 o, vec3 d, vec3 center, float w, float lod, out ViewSample s)
{
    s.passed = false;
    const float quantum = 2.0 * mf_radius / HF_DEPTH_CODES;
    float texel = 2.0 * mf_radius / capture_resolution;
    vec2 span = voxel_span(o, d, center, w, 0.5 * texel);
    if (span.x > span.y) return RAY_MISS;
    vec3 dir = view.direction.xyz;
    if (dot(d, dir) > -0.05) return RAY_HIDDEN; // seen from behind or edge-on: the view knows nothing here
    // the segment in the voxel, s in [0, 1]; depth below the capture plane's top, growing along it
    vec3 p0 = o + span.x * d, p1 = o + span.y * d;
    float z0 = -dot(p0 - mf_center, dir), z1 = -dot(p1 - mf_center, dir);
    vec2 a = capture_pixel(view, p0), b = capture_pixel(view, p1);
    // A segment across more texels than MF_WALK_STEPS (a coarse voxel of a fine capture: at 1536 px
    // a level-4 voxel spans ~100 texels) walks a grid of 2^k x 2^k blocks instead, each read at its
    // centre texel: the walk ends inside the voxel, where one that ran out of steps left a hole
    // (foliage at distance 8: holes 0.7% -> 5.4% from 1024 to 1536 px captures). The LOD cut keeps
    // such voxels under a few pixels, so a block is about a pixel's size there.
    float block = exp2(max(ceil(log2((abs(b.x - a.x) + abs(b.y - a.y) + 1.0) / float(MF_WALK_STEPS - 1))), 0.0));
    int block_texels = int(block);
    texel *= block;
    a /= block;
    b /= block;
    // blocks under the segment, in order (Amanatides & Woo)
    ivec2 cell = ivec2(floor(a)), last = ivec2(floor(b));
    vec2 delta = b - a;
    ivec2 stride = ivec2(sign(delta));
    vec2 inverse = vec2(abs(delta.x) > 1e-9 ? 1.0 / abs(delta.x) : 1e30, abs(delta.y) > 1e-9 ? 1.0 / abs(delta.y) : 1e30);
    vec2 next = vec2(delta.x >= 0.0 ? float(cell.x + 1) - a.x : a.x - float(cell.x),
                     delta.y >= 0.0 ? float(cell.y + 1) - a.y : a.y - float(cell.y)) * inverse;
    float s_in = 0.0;
    bool previous_covered = false, crossed_u = true; // crossed_u: the last step crossed a column side along axis_u
    float previous_top = 0.0;
    vec3 previous_normal = vec3(0.0);
    for (int step = 0; step < MF_WALK_STEPS; ++step) { // at most |dx| + |dy| + 1 blocks
        float s_out = min(min(next.x, next.y), 1.0);
        bool covered = false;
        ivec2 read = cell * block_texels + block_texels / 2;
        if (all(greaterThanEqual(read, view.crop.xy)) && all(lessThan(read, view.crop.xy + view.crop.zw))) {
            ivec2 at = view.atlas.yz + read - view.crop.xy;
            vec4 nd = texelFetch(normal_depth_pages, ivec3(at, view.atlas.x), 0);
            g_fetches += 1u;
            covered = nd.r + nd.g + nd.b > 0.0;
            if (covered) {
                float top = mf_radius - stored_height(nd.a); // the column's top, as a depth
                vec3 normal = decode_normal(nd.rgb);
                // linked to the column before: one surface when their step is within the shared tolerance
                bool linked = false;
                if (step > 0 && previous_covered) {
                    vec3 axis = crossed_u ? view.axis_u.xyz : view.axis_v.xyz;
                    float slope_a = hf_slope(dot(normal, axis), dot(normal, dir)), slope_b = hf_slope(dot(previous_normal, axis), dot(previous_normal, dir));
                    linked = abs(top - previous_top) <= hf_link_tolerance(slope_a, slope_b, texel, quantum);
                }
                vec2 crossing = hf_cross_column(s_in, s_in, s_out, z0 + mf_radius, z1 - z0, top, linked, previous_top);
                if (crossing.y == HF_UNDER) return RAY_HIDDEN;
                // a crossing where the surface's filtered coverage is under 1/2 is no hit: the ray
                // passes beside a cut-out's edge there and walks on
                if ((crossing.y == HF_TOP || crossing.y == HF_WALL) && covered_enough(view, mix(p0, p1, crossing.x))) {
                    s.passed = true;
                    s.surface = mix(p0, p1, crossing.x);
                    s.normal = normal;
                    // the texel's own colour, or filtered over the pixel's footprint where that holds one surface
                    vec2 position = vec2(read) + 0.5, hit = capture_pixel(view, s.surface);
                    float level = 0.0;
                    if (lod > 0.0 && one_surface_around(view, hit, lod, dot(s.surface - mf_center, dir), normal)) {
                        position = hit;
                        level = lod;
                    }
                    s.color = view_color(view, position, level);
                    view_material(view, position, level, s);
                    return RAY_HIT;
                }
                previous_top = top;
                previous_normal = normal;
            }
        }
        previous_covered = covered;
        if (cell == last || s_out >= 1.0) break;
        crossed_u = next.x < next.y;
        if (crossed_u) {
            cell.x += stride.x;
            next.x += inverse.x;
        } else {
            cell.y += stride.y;
            next.y += inverse.y;
        }
        s_in = s_out;
    }
    return RAY_MISS;
}
