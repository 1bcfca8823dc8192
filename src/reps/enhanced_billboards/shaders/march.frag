#version 450 core
// Enhanced billboards, per fragment: the eye ray is clipped to the proxy box (a tile of the
// billboard, or the whole billboard) and intersected with the billboard's height field (Vichitvejpaisal 2005
// §3.3; Vichitvejpaisal & Kanongchaiyos 2006 Fig. 7). The march stops at the nearest front hit found so far at the pixel (an image
// the shader keeps itself: a fragment whose depth the shader writes is tested late on some GPUs and
// on llvmpipe, and boxes are drawn front to back, so most rays behind a hit never start).
// MARCH_EXACT: the depth map is a sheet of texel-sized columns: a covered texel's top is the plane
// through its depth at its centre, tilted as its linked neighbours' depths say (capped at
// HF_TOP_MAX_SLOPE, ended at the texel's range: acceleration.cpp; the view atlas's tilt by
// normals), and linked neighbours (acceleration.h: same surface, jump within the
// normals' slope, or a step that repeats) are joined by walls between their tilted tops, so a
// surface has no gaps at any view, grazing included, and silhouettes are the covered texels' outline; a texel an outline crosses (a sheet's rim, a surface's silhouette)
// is cut by the outline's line stored with it (on_surface, issue #17). The ray visits texels through a min/max pyramid (Tevs et al., I3D 2008):
// a node whose depth range the ray segment above it misses is skipped whole; at level 0 the
// crossing of the texel's top and of the wall it was entered through is computed exactly.
// Level of detail: where a pyramid node is no wider than half the pixel's footprint on the billboard,
// a node the ray meets is a hit at its covered texel where the ray reaches the node's depth range
// (the texels under one pixel would share it anyway); without a covered texel there it looks closer.
// MARCH_SEED: the paper's linear march, `seed_steps` equal steps over the box diagonal, hit where
// the ray is below the stored depth by less than the hit range e (holes included).
// Every hit writes its true depth; misses are discarded. Its colour is filtered over the pixel's
// footprint within one smooth surface (footprint_color), as the truth's mip-mapped textures are.
#ifndef INSIDE_PASS
layout(depth_greater) out float gl_FragDepth; // the hit is never nearer than the box face
#endif
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "gpu/shaders/common/counters.glsl"
#include "reps/common/shaders/height_field.glsl"
#include "reps/enhanced_billboards/shaders/billboard.glsl"
#include "reps/common/shaders/depth_batches.glsl"

flat in int v_tile;
flat in int v_instance;
flat in mat4 v_box_from_world;
flat in mat4 v_world_from_box;

layout(binding = BINDING_COLOR_MAPS) uniform sampler2DArray color_maps;
layout(binding = BINDING_NORMAL_MAPS) uniform sampler2DArray normal_maps;
layout(binding = BINDING_SURFACE_MAPS) uniform usampler2DArray surface_maps; // depth, range, tilt, flags (acceleration.h pack_surface)
layout(binding = BINDING_MINMAX_MAPS) uniform usampler2DArray minmax_maps;   // level k: cells of 2^(k+1)
layout(binding = BINDING_ORM_MAPS) uniform sampler2DArray orm_maps;           // only when has_pbr_maps
layout(binding = BINDING_EMISSION_MAPS) uniform sampler2DArray emission_maps;
layout(binding = BINDING_COLOR_MIPS) uniform sampler2DArray color_mips; // level k - 1: cells of 2^k texels
layout(binding = IMAGE_PIXEL_FLAGS, r32ui) uniform coherent uimage2D pixel_flags;
layout(binding = IMAGE_PIXEL_DEPTH, r32ui) uniform coherent uimage2D pixel_depth;

// Settings fixed for the renderer's life are compiled in (renderer.cpp, make_march_program), not
// uniforms: llvmpipe runs the branch not taken too, masked, for every fragment (the seed's march
// and the exact one it calls to mark holes cost the exact march about 10% of a frame; the debug
// views, the near-miss marks, the PBR maps' reads and the back-hit switch 5-10%).
#ifndef MARCH_MODE // the build's shader check compiles without the renderer's defines: its defaults
#define MARCH_MODE MARCH_EXACT
#define MARCH_LOD 1
#define MARCH_DEBUG_VIEW DEBUG_VIEW_NONE
#define MARCH_MARK_PIXELS 0
#define MARCH_HAS_PBR_MAPS 0
#define MARCH_COLOR_FOOTPRINT 1
#define MARCH_HIDE_BACK_HITS 0
#endif
const int march_mode = MARCH_MODE;           // --march
const int debug_view = MARCH_DEBUG_VIEW;     // DEBUG_VIEW_*
const int mark_pixels = MARCH_MARK_PIXELS;   // near misses marked for --coarse-fill near-misses
const int has_pbr_maps = MARCH_HAS_PBR_MAPS; // the package has PBR maps (issue #14); otherwise Material's defaults
const int color_footprint = MARCH_COLOR_FOOTPRINT; // colour filtered over the pixel's footprint (--color-filter footprint)
const int hide_back_hits = MARCH_HIDE_BACK_HITS;   // the package's bake.back_hits is "hide" (billboards.h BakeSettings::back_hits)
uniform int seed_steps;
uniform float seed_hit_range;
uniform int counting; // switched per frame (Renderer::set_counting)

layout(location = 0) out vec4 out_color;

// a unit normal from its point on the octahedron folded onto [0, 1]² (reps/common/block_compress.h)
vec3 octahedral_decode(vec2 e)
{
    vec2 f = e * 2.0 - 1.0;
    vec3 n = vec3(f, 1.0 - abs(f.x) - abs(f.y));
    float t = max(-n.z, 0.0);
    n.xy += vec2(n.x >= 0.0 ? -t : t, n.y >= 0.0 ? -t : t);
    return normalize(n);
}

const float k_codes = HF_DEPTH_CODES;
int g_fetches = 0;
// where the billboard's maps lie in their layer (several billboards share one: pack_layers); the
// march works in the billboard's own texels, and every read goes through at()
ivec2 g_offset = ivec2(0);
ivec3 at(ivec2 texel, int layer) { return ivec3(texel + g_offset, layer); }
// a cell of pyramid level `level` (offsets are multiples of the top level's cell)
ivec3 at_level(ivec2 cell, int layer, int level) { return ivec3(cell + (g_offset >> level), layer); }

uvec4 fetch_surface(ivec2 texel, int layer)
{
    ++g_fetches;
    return texelFetch(surface_maps, at(texel, layer), 0);
}

// a surface texel's depth range [min, max] in codes: its depth and its linked neighbours' (the
// walls), stored as whole range units below and above the depth (pack_surface)
float g_range_unit = 1.0;
vec2 surface_range(uvec4 s)
{
    return vec2(float(s.x) - float(s.y & 255u) * g_range_unit, float(s.x) + float(s.y >> 8u) * g_range_unit);
}

// a covered texel's tilt: the change of its top's box depth (z) per texel along x and y
float g_texel_depth = 1.0; // one texel of depth in box z (texel size over depth range)
vec2 surface_tilt(uvec4 s)
{
    vec2 q = vec2(float(s.z & 255u), float(s.z >> 8u)) - 128.0;
    return q * (HF_TOP_MAX_SLOPE / 127.0) * g_texel_depth;
}

// Whether box-space point p (x, y in texels) is on the surface of covered texel `texel` (surface
// map entry s): everywhere, unless the texel holds an edge line (issue #17: a sheet's rim, a leaf's
// contour, a surface's outline; capture.cpp, edge_line_code; the code layout in
// billboard_layout.glsl), which the surface ends at. The line rides in the flags (TEXEL_LINE_*).
bool on_surface(uvec4 s, ivec2 texel, vec2 p)
{
    uint line = ((s.a >> TEXEL_LINE_LOW_BIT) & 1u) | ((s.a >> TEXEL_LINE_HIGH_SHIFT) << 1u);
    if (line == 0u) return true;
    uint code = line - 1u;
    float angle = float(code / uint(EDGE_LINE_OFFSETS)) * (6.28318530718 / float(EDGE_LINE_ANGLES));
    vec2 n = vec2(cos(angle), sin(angle));
    float e = ((float(code % uint(EDGE_LINE_OFFSETS)) + 0.5) / float(EDGE_LINE_OFFSETS) * 2.0 - 1.0) * 0.5 * (abs(n.x) + abs(n.y));
    return dot(n, p - vec2(texel) - 0.5) <= e;
}

// The colour at box point p interpolated bilinearly over the hit texel and the three nearest of its
// neighbours, those that continue its surface without a crease (SMOOTH_* links) only, renormalised:
// the truth interpolates its textures, and a pixel's point sample of the texel grid is noise at
// texel-sized detail (issue #14).
vec3 surface_bilinear_color(ivec2 texel, vec2 p, int layer)
{
    vec2 f = p - vec2(texel) - 0.5;
    ivec2 side = ivec2(f.x >= 0.0 ? 1 : -1, f.y >= 0.0 ? 1 : -1);
    vec2 w = min(abs(f), vec2(0.5));
    uint link_u = side.x > 0 ? SMOOTH_PLUS_U : SMOOTH_MINUS_U, link_v = side.y > 0 ? SMOOTH_PLUS_V : SMOOTH_MINUS_V;
    uint flags = texelFetch(surface_maps, at(texel, layer), 0).a;
    bool along_u = (flags & link_u) != 0u, along_v = (flags & link_v) != 0u, diagonal = false;
    if (along_u)
        diagonal = (texelFetch(surface_maps, at(texel + ivec2(side.x, 0), layer), 0).a & link_v) != 0u;
    if (!diagonal && along_v)
        diagonal = (texelFetch(surface_maps, at(texel + ivec2(0, side.y), layer), 0).a & link_u) != 0u;
    vec4 weights = vec4((1.0 - w.x) * (1.0 - w.y), along_u ? w.x * (1.0 - w.y) : 0.0, along_v ? (1.0 - w.x) * w.y : 0.0,
                        diagonal ? w.x * w.y : 0.0);
    weights = weights / (weights.x + weights.y + weights.z + weights.w);
    vec4 sum = weights.x * texelFetch(color_maps, at(texel, layer), 0);
    if (weights.y > 0.0) sum += weights.y * texelFetch(color_maps, at(texel + ivec2(side.x, 0), layer), 0);
    if (weights.z > 0.0) sum += weights.z * texelFetch(color_maps, at(texel + ivec2(0, side.y), layer), 0);
    if (weights.w > 0.0) sum += weights.w * texelFetch(color_maps, at(texel + side, layer), 0);
    return sum.rgb;
}

vec3 safe_inverse(vec3 d)
{
    const float tiny = 1e-20;
    return 1.0 / vec3(abs(d.x) < tiny ? tiny : d.x, abs(d.y) < tiny ? tiny : d.y, abs(d.z) < tiny ? tiny : d.z);
}

// The exact crossing of ray o + t d (box space) with the column sheet, for t in [t0, t1].
// The ray starts in a texel of start_rect (xy: first texel, zw: past the last) and stops at t1, or where it
// leaves the billboard (size); the pyramid is climbed to top_level at most.
// Two loops: the inner one walks the nodes (a fetch, a depth-range test, the step to the next node)
// until a node needs a closer look (a level-0 texel whose range the ray meets, or a node of the
// pixel's level of detail); the outer one looks closer once per such node, then walks on. A
// software rasteriser runs every branch of a loop body, masked, at every step of every fragment
// (llvmpipe: docs/RESULTS.md "Straight-line code"), so the closer looks, most of the body's code
// and rare against the steps, cost once per node looked at instead of once per step; GPUs run
// the same steps in the same order.
const int MARCH_STEPS = 512; // steps (node visits) per ray; then the coarse mesh decides
bool march_exact(vec3 o, vec3 d, float t0, float t1, int layer, ivec2 size, ivec4 start_rect, int top_level,
                 int pixel_level, int start_level, out float t_hit,
                 out ivec2 hit_texel, inout bool near)
{
    vec3 inv = safe_inverse(d);
    ivec2 dir = ivec2(d.x >= 0.0 ? 1 : -1, d.y >= 0.0 ? 1 : -1);
    ivec2 ahead = max(dir, ivec2(0)); // 1 where the exit boundary of a cell is its upper one
    int level = clamp(start_level, pixel_level, top_level);
    // the last texel read at level 0: the one a wall crossing comes from, most of the time
    ivec2 last_texel = ivec2(-1);
    uvec4 last_surface = uvec4(0u);
    float t = t0;
    vec2 p = o.xy + t * d.xy + vec2(dir) * 1e-3;
    ivec2 texel = clamp(ivec2(floor(p)), start_rect.xy, start_rect.zw - 1);

    // the node of the current step, as the closer looks and the step to the next node read it
    ivec2 cell = ivec2(0);
    int axis = 0;
    float t_exit = t;
    uvec2 node_range = uvec2(0u);                  // level > 0: the node's depth range
    uvec4 s = uvec4(0u), previous_surface = uvec4(0u); // level 0: the texel's surface, the one read before
    ivec2 previous_texel = ivec2(-1);
    int steps = 0;         // steps taken (MARCH_STEPS at most)
    bool advance = false;  // the current step is done but for the move to the next node
    for (int look = 0; look <= MARCH_STEPS; ++look) {
        const int LOOK_NONE = 0, LOOK_CONTACT = 1, LOOK_TEXEL = 2;
        int closer = LOOK_NONE;
        for (;;) {
            if (advance) {
                // leave the node: into the neighbouring one, one level up when that is in another
                // parent (Tevs et al.; climbing as far as the crossing allows costs more on rough
                // surfaces, where the climb is undone at once: 17.4 against 15.8 fetches per covered pixel)
                if (t_exit >= t1) return false;
                ivec2 next = texel;
                next[axis] = (cell[axis] + dir[axis]) << level;
                if (dir[axis] < 0) next[axis] += (1 << level) - 1;
                int other = 1 - axis;
                float along = o[other] + t_exit * d[other];
                int lo = cell[other] << level, hi = ((cell[other] + 1) << level) - 1;
                next[other] = clamp(int(floor(along + float(dir[other]) * 1e-3)), lo, hi);
                if (next[axis] < 0 || next[axis] >= size[axis]) return false;
                ivec2 old_cell = cell, new_cell = next >> level;
                if (level < top_level && (old_cell >> 1) != (new_cell >> 1)) ++level;
                texel = next;
                t = t_exit;
                advance = false;
                if (++steps >= MARCH_STEPS) break;
            }
            cell = texel >> level;
            vec2 exit_bound = vec2((cell + ahead) << level);
            vec2 t_bounds = (exit_bound - o.xy) * inv.xy;
            axis = t_bounds.x < t_bounds.y ? 0 : 1;
            t_exit = min(t_bounds[axis], t1);
            float z_a = o.z + t * d.z, z_b = o.z + t_exit * d.z;
            float z_lo = min(z_a, z_b) * k_codes, z_hi = max(z_a, z_b) * k_codes;

            if (level > 0) {
                ++g_fetches;
                node_range = texelFetch(minmax_maps, at_level(cell, layer, level), level - 1).rg;
                if (float(node_range.x) <= z_hi + 0.5 && float(node_range.y) >= z_lo - 0.5) {
#if MARCH_LOD
                    if (level <= pixel_level) {
                        closer = LOOK_CONTACT;
                        break;
                    }
#endif
                    --level; // the segment may meet the surface below this node: look closer
                    if (++steps >= MARCH_STEPS) break;
                    continue;
                }
            } else {
                s = fetch_surface(texel, layer);
                previous_texel = last_texel;
                previous_surface = last_surface;
                last_texel = texel;
                last_surface = s;
                vec2 range = surface_range(s);
                if ((s.a & TEXEL_COVERED) != 0u && range.x <= z_hi + 0.5 && range.y >= z_lo - 0.5) {
                    closer = LOOK_TEXEL;
                    break;
                }
            }
            advance = true;
        }
        if (closer == LOOK_NONE) break; // out of steps

#if MARCH_LOD
        if (closer == LOOK_CONTACT) {
            // the node is no wider than half the pixel: the ray meets it where it reaches
            // the node's depth range, at the texel there if that texel's range meets the
            // ray too (else look closer)
            float z_contact = (d.z >= 0.0 ? float(node_range.x) : float(node_range.y)) / k_codes;
            float t_contact = abs(d.z) > 1e-20 ? clamp((z_contact - o.z) / d.z, t, t_exit) : t;
            ivec2 first = cell << level;
            ivec2 contact = clamp(ivec2(floor(o.xy + t_contact * d.xy)), first, first + (1 << level) - 1);
            uvec4 c = fetch_surface(contact, layer);
            // the ray's depths over the contact texel's own column, not the node's: over a
            // node it can pass high above a leaf of a few texels and leave it (issue #14:
            // the leaves fattened, spill 3.5% at distance 8)
            vec2 t_a = (vec2(contact) - o.xy) * inv.xy, t_b = (vec2(contact + 1) - o.xy) * inv.xy;
            vec2 t_near = min(t_a, t_b), t_far = max(t_a, t_b);
            float t_in = max(max(t_near.x, t_near.y), t), t_out = min(min(t_far.x, t_far.y), t_exit);
            float zc_a = (o.z + t_in * d.z) * k_codes, zc_b = (o.z + t_out * d.z) * k_codes;
            // and the hit where it reaches that texel's top within the column, so that
            // its depth is the texel's, not the node's nearest
            float t_top = abs(d.z) > 1e-20 ? clamp((float(c.x) / k_codes - o.z) / d.z, t_in, t_out) : t_in;
            if ((c.a & TEXEL_COVERED) != 0u && t_in <= t_out && float(c.x) <= max(zc_a, zc_b) + 0.5 && float(c.x) >= min(zc_a, zc_b) - 0.5 &&
                on_surface(c, contact, o.xy + t_top * d.xy)) {
                near = true;
                t_hit = t_top;
                hit_texel = contact;
                return true;
            }
            --level; // look closer
            if (++steps >= MARCH_STEPS) break;
            continue;
        }
#endif
        {
            near = true;
            vec2 range = surface_range(s);
            // the wall to the texel the ray came from, if it continues this surface, then the top
            vec2 entry_bound = vec2(texel + ivec2(1) - ahead);
            vec2 t_entries = (entry_bound - o.xy) * inv.xy;
            int entry_axis = t_entries.x > t_entries.y ? 0 : 1;
            float t_in = t_entries[entry_axis];
            uint link = entry_axis == 0 ? (dir.x > 0 ? LINK_MINUS_U : LINK_PLUS_U)
                                        : (dir.y > 0 ? LINK_MINUS_V : LINK_PLUS_V);
            bool from_linked = t_in >= t0 && (s.a & link) != 0u;
            ivec2 from = texel;
            from[entry_axis] -= dir[entry_axis];
            uvec4 from_surface = uvec4(0u);
            if (from_linked) from_surface = from == previous_texel ? previous_surface : fetch_surface(from, layer);
            // the tilted tops: the ray is compared with this texel's top as the ray z_origin +
            // t z_per_t against the flat top `top`, shifted by the tilt (the view atlas's
            // walk, atlas.frag), and with the neighbour's tilted top where it crosses the wall
            float top = float(s.x) / k_codes;
            vec2 tilt = surface_tilt(s), centre = vec2(texel) + 0.5;
            float z_origin = o.z - dot(tilt, o.xy - centre), z_per_t = d.z - dot(tilt, d.xy);
            float d_from = 0.0;
            if (from_linked) {
                vec2 wall_point = o.xy + t_in * d.xy;
                d_from = float(from_surface.x) / k_codes + dot(surface_tilt(from_surface), wall_point - vec2(from) - 0.5) -
                         dot(tilt, wall_point - centre);
            }
            vec2 crossing = hf_cross_column(t_in, t, t_exit, z_origin, z_per_t, top, from_linked, d_from);
            // a tilted top ends at the texel's range (its depth and its linked neighbours'),
            // which every proxy box holds: an outline texel's top does not reach past its
            // depth towards the outside, and a box's layers keep the picture (build_tiles)
            float z_cross = (o.z + crossing.x * d.z) * k_codes;
            if (z_cross < range.x - 0.5 || z_cross > range.y + 0.5) crossing.y = HF_MISS;
            // a sheet's edge line ends the top, and a wall, on the texels that hold one
            vec2 p_cross = o.xy + crossing.x * d.xy;
            bool on = crossing.y == HF_TOP ? on_surface(s, texel, p_cross)
                    : crossing.y == HF_WALL && on_surface(s, texel, p_cross) && on_surface(from_surface, from, p_cross);
            if (on) {
                t_hit = crossing.x;
                // on a wall, the texel whose top is nearer the crossing
                float z_in = z_origin + t_in * z_per_t;
                hit_texel = crossing.y == HF_WALL && abs(z_in - d_from) < abs(z_in - top) ? from : texel;
                return true;
            }
            advance = true; // and on to the next node
        }
    }
    near = true; // out of steps: let the coarse mesh decide
    return false;
}

// The seed's linear search (Vichitvejpaisal & Kanongchaiyos 2006 Fig. 7): equal steps over the box diagonal from the entry point.
bool march_seed(vec3 o, vec3 d, float t0, float t1, int layer, ivec2 size, float diagonal_t,
                out float t_hit, out ivec2 hit_texel, inout bool near)
{
    float step = diagonal_t / float(seed_steps);
    for (int i = 0; i < seed_steps; ++i) {
        float t = t0 + float(i) * step;
        if (t > t1) break;
        vec3 p = o + t * d;
        ivec2 texel = clamp(ivec2(floor(p.xy)), ivec2(0), size - 1);
        uvec4 s = fetch_surface(texel, layer);
        if ((s.a & TEXEL_COVERED) == 0u) continue;
        float depth = float(s.x) / k_codes;
        if (p.z > depth && p.z - seed_hit_range < depth) {
            t_hit = t;
            hit_texel = texel;
            return true;
        }
    }
    return false;
}

void finish(bool hit, bool near)
{
    if (counting != 0) {
        count_fragment(uint(g_fetches));
        if (hit) atomicAdd(counters[COUNTER_HITS], 1u);
        if (!hit && near) atomicAdd(counters[COUNTER_NEAR_MISSES], 1u); // back hits count here
    }
    if (mark_pixels != 0 && (hit || near))
        imageAtomicOr(pixel_flags, ivec2(gl_FragCoord.xy), hit ? PIXEL_HIT : PIXEL_NEAR_MISS);
}

// The albedo a pixel shows at hit texel `texel` (issue #14, --color-filter footprint): the truth's
// textures are filtered over the pixel (trilinear mip maps) but never across geometry, where one
// capture texel per pixel is a point sample of them, noise that grows as the stand-in shrinks:
//  1. the pixel's footprint on the billboard in texels (its shorter side), at the hit;
//  2. lambda = log2(footprint) - 1/2: a capture texel is already the mean over its own square, so
//     the mips start half a level late (generated tree, thesis protocol at 800x600 / 400x300 /
//     200x150, before creases stopped the filter: Luv 3.52 / 4.38 / 4.97 at +0, 3.44 / 4.46 / 5.08
//     at -1/2, 3.45 / 4.42 / 5.17 at -1; the texel's own colour 3.89 / 4.75 / 5.63);
//  3. the colour at the two levels around lambda, blended: level 0 interpolated over the hit's
//     texel and its neighbours across smooth links (surface_bilinear_color), level k >= 1 the mean over
//     the cell of 2^k texels holding the hit where that cell is one smooth surface
//     (build_color_pyramid), else the finest level around the hit that is.
// Normals stay the hit texel's: interpolating them too raised the tree's Luv (4.29 -> 4.35).
// Its reads are shading, like the hit's colour and normal, and not counted: the fetch counter is
// the height-field walk's (issue #17's fetches per covered pixel).
const float k_color_level_bias = -0.5;
vec3 footprint_color(ivec2 texel, int layer, int top_level, vec3 p_box, vec3 p_world, float t_hit, vec3 ox, vec3 dx,
                     vec3 oy, vec3 dy)
{
    float across_x = length((mat3(v_box_from_world) * (ox + t_hit * dx - p_world)).xy);
    float across_y = length((mat3(v_box_from_world) * (oy + t_hit * dy - p_world)).xy);
    float footprint = min(across_x, across_y);
    float lambda = footprint > 1.0 ? max(log2(footprint) + k_color_level_bias, 0.0) : 0.0;
    int finer_level = min(int(floor(lambda)), top_level);
    // the coarsest level at or under finer_level + 1 whose cell is one surface (the children of a
    // cell of one surface are of one surface)
    int found = 0;
    vec3 found_color = vec3(0.0);
    for (int level = min(finer_level + 1, top_level); level > 0; --level) {
        vec4 mean = texelFetch(color_mips, at_level(texel >> level, layer, level), level - 1);
        if (mean.a > 0.5) {
            found = level;
            found_color = mean.rgb;
            break;
        }
    }
    if (found > 0 && found <= finer_level) return found_color;
    // level 0 interpolated where no cell around the hit is one surface; under a blend, level 0 or
    // the mean of finer_level's cell (one surface, since its parent is)
    vec3 finer = found == 0 || finer_level == 0
                     ? surface_bilinear_color(texel, p_box.xy, layer)
                     : texelFetch(color_mips, at_level(texel >> finer_level, layer, finer_level), finer_level - 1).rgb;
    return found > finer_level ? mix(finer, found_color, clamp(lambda - float(finer_level), 0.0, 1.0)) : finer;
}

// Whether this fragment is behind a hit already drawn at its pixel: its depth is at or behind its
// box face's (depth_greater), and the depth buffer is at or before every depth this draw wrote, so
// it would fail the depth test whatever its ray meets: it stops before any set-up. The same as the
// ray clipped to the nearest hit (below), sooner. With --coarse-fill near-misses not behind a back
// hit, where the coarse mesh may fill by the near misses these rays mark. On llvmpipe the frame does
// not move (rasterising and starting the fragment is most of a box's cost behind the leaves:
// docs/RESULTS.md); it counts the fragments boxes spend behind the surface (COUNTER_BEHIND_HITS).
// `nearest` is the pixel's record (pixel_depth).
bool behind_drawn_hit(uint nearest)
{
#ifdef INSIDE_PASS
    return false; // the boxes around the eye draw their back faces: no bound from gl_FragCoord.z
#else
    return (mark_pixels == 0 || (nearest & PIXEL_DEPTH_BACK) == 0u) &&
           floatBitsToUint(gl_FragCoord.z) > (nearest | PIXEL_DEPTH_BACK);
#endif
}

void main()
{
    if (fade_discards()) discard; // a cross-fade's other renderer owns this pixel
    // the pixel's nearest hit so far, read once: the stop below and the ray's clip further down
    const uint nearest_record = imageLoad(pixel_depth, ivec2(gl_FragCoord.xy)).r;
    if (behind_drawn_hit(nearest_record)) {
        if (counting != 0) atomicAdd(counters[COUNTER_BEHIND_HITS], 1u);
        finish(false, false);
        discard;
    }
    TileData tile = tiles.items[v_tile];
    int billboard = tile.info.x, top_level = tile.info.y;
    BillboardData data = billboards.items[billboard];
    int layer = data.info.x;
    ivec2 size = data.info.zw;
    g_offset = data.offset.xy;
    g_range_unit = float(data.info.y);
    g_texel_depth = length(mat3(data.object_from_box)[0]) / length(mat3(data.object_from_box)[2]);

    // the eye ray in box space, clipped to the proxy box (and to the near plane: t >= 0); t is the
    // distance along the world ray in both spaces
    vec3 origin_world, direction_world;
    camera_ray(gl_FragCoord.xy, origin_world, direction_world);
    vec3 o = (v_box_from_world * vec4(origin_world, 1.0)).xyz;
    vec3 d = mat3(v_box_from_world) * direction_world;
    // (the slab test in the tile's sheared space, where its box is axis-aligned; widened by a
    // little across tile sides, so that a ray along a side between two tiles meets both)
    vec3 o_tile = tile_from_box(tile, o), inv = safe_inverse(tile_from_box_direction(tile, d));
    const vec3 widen = vec3(5e-4, 5e-4, 0.0);
    vec3 t_a = (tile.box_min.xyz - widen - o_tile) * inv, t_b = (tile.box_max.xyz + widen - o_tile) * inv;
    vec3 t_near = min(t_a, t_b), t_far = max(t_a, t_b);
    float t0 = max(max(t_near.x, t_near.y), max(t_near.z, 0.0));
    float t1 = min(min(t_far.x, t_far.y), t_far.z);

    // and to the nearest hit so far: a hit beyond it would fail the depth test (GL_LESS); the
    // margin keeps rounding of the round trip through window depth on the safe side
    float nearest = uintBitsToFloat(nearest_record & ~PIXEL_DEPTH_BACK);
    if (nearest < 1.0) {
        vec2 ndc = gl_FragCoord.xy * frame.viewport_size.zw * 2.0 - 1.0;
        vec4 p = frame.world_from_clip * vec4(ndc, nearest * 2.0 - 1.0, 1.0);
        float t_limit = dot(p.xyz / p.w - origin_world, direction_world);
        t1 = min(t1, t_limit + 1e-4 * abs(t_limit) + 1e-6);
    }

    // level of detail: pyramid nodes no wider than half the pixel's footprint on the billboard (at
    // the box entry, the nearest point) end the walk: their texels would share the pixel anyway
    vec3 o_x, d_x, o_y, d_y;
    camera_ray(gl_FragCoord.xy + vec2(1.0, 0.0), o_x, d_x);
    camera_ray(gl_FragCoord.xy + vec2(0.0, 1.0), o_y, d_y);
#if MARCH_LOD
    float t_entry = max(t0, 0.0);
    vec3 p_entry = origin_world + t_entry * direction_world;
    float texels_x = length((mat3(v_box_from_world) * (o_x + t_entry * d_x - p_entry)).xy);
    float texels_y = length((mat3(v_box_from_world) * (o_y + t_entry * d_y - p_entry)).xy);
    float texels_per_pixel = min(texels_x, texels_y);
    // nodes of at most half a pixel: with whole pixels the thesis protocol's Luv rose from 0.47 to
    // 0.63 on the noisy sphere (a node's texel is not the exact hit's, and silhouettes spill)
    int pixel_level = texels_per_pixel >= 4.0 ? min(int(floor(log2(texels_per_pixel))) - 1, top_level) : 0;
#else
    const int pixel_level = 0; // no instance of the draw spans 4 texels a pixel (renderer.cpp, k_lod_texels_per_pixel)
#endif

    bool hit = false, near = false;
    float t_hit = 0.0;
    ivec2 texel = ivec2(0);
    if (t0 < t1) {
        if (march_mode == MARCH_SEED) {
            // t is in world units: the box diagonal in world units
            float diagonal_t = length(mat3(v_world_from_box) * vec3(size, 1.0));
            hit = march_seed(o, d, t0, t1, layer, size, diagonal_t, t_hit, texel, near);
            if (!hit && mark_pixels != 0) {
                // a seed hole is where the exact sheet is crossed or nearly so: let the coarse
                // mesh fill those pixels (not counted: it is not the seed's work)
                int seed_fetches = g_fetches;
                float t_exact;
                ivec2 texel_exact;
                near = march_exact(o, d, t0, t1, layer, size, ivec4(0, 0, size), top_level, 0, top_level, t_exact, texel_exact, near) || near;
                g_fetches = seed_fetches;
            }
        } else {
            {
            // a tile's box hugs the surface (it follows its plane), so the ray starts next to it:
            // start at the texel (or the pixel's level), where a coarse node would mostly be entered
            // only to be left again (measured: 15.8 fetches per covered pixel starting at the ray's
            // footprint level, 13.5 at the texel, noisy sphere, 800x600); a whole billboard's box
            // is as deep as the model, and there (and in a coarse tile, a few pixels wide) the
            // footprint level skips the empty space above
            float footprint = length(d.xy) * (t1 - t0);
            int start_level = tile.info.z != 0 ? int(ceil(log2(footprint + 1.0))) : 0;
            hit = march_exact(o, d, t0, t1, layer, size, ivec4(tile.box_min.xy, tile.box_max.xy), top_level, pixel_level,
                              start_level, t_hit, texel, near);
        }
        }
    }
    if (!hit) {
        finish(false, near);
        discard;
    }

    vec3 p_box = o + t_hit * d;
    vec3 p_world = (v_world_from_box * vec4(p_box, 1.0)).xyz;
    mat4 world_from_object = instances.world_from_object[v_instance];
    vec3 normal_object = octahedral_decode(texelFetch(normal_maps, at(texel, layer), 0).rg);
    vec3 normal_world = normalize(mat3(world_from_object) * normal_object);
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz : normalize(frame.eye_world.xyz - p_world);
    // the back of a height field is drawn (open surfaces show both sides, as in the ground truth)
    // but marked a near miss: on a closed surface it shows only through a hole, which the coarse
    // mesh, in front of it, then fills; the back of a sheet is baked from its own side too
    // (bake.cpp, add_back_sides). Its depth is pushed k_back_texels texels behind the hit, so that
    // this front hit of the other side and the coarse mesh, within a texel or two of the same depth
    // (quantised from another direction, decimated), win the depth test instead of z-fighting it
    // in stripes (issue #17). Measured without the push: the 30k sheet assembly from azimuth 120
    // showed the flange's back hits in moire over the casing's inside (Luv 7.3-7.9 against 2.0-2.4
    // with it); on the lead's 126k sheet model the push costs 0.15 Luv (1.47 -> 1.62) and the thick
    // assembly 0.02, where the coarse mesh now wins over back hits that were the right colour
    bool back = dot(normal_world, to_eye) < 0.0;
    // the back of an open single-sided part, which the truth culls: not drawn, but a near miss, so
    // that the coarse mesh (drawn with back faces culled for such packages) shows what the truth
    // shows there
    if (back && hide_back_hits != 0) {
        finish(false, true);
        discard;
    }
    // (the colour only for hits that are drawn)
    vec4 albedo = texelFetch(color_maps, at(texel, layer), 0);
    if (color_footprint != 0 && march_mode == MARCH_EXACT)
        albedo.rgb = footprint_color(texel, layer, top_level, p_box, p_world, t_hit, o_x, d_x, o_y, d_y);
    const float k_back_texels = 2.0;
    float texel_world = length(mat3(v_world_from_box) * vec3(1.0, 0.0, 0.0));
    float depth = window_depth(back ? p_world + direction_world * (k_back_texels * texel_world) : p_world);
#ifndef INSIDE_PASS
    depth = max(depth, gl_FragCoord.z);
#endif
    finish(!back, back);
    const uint record = (floatBitsToUint(depth) & ~PIXEL_DEPTH_BACK) | (back ? PIXEL_DEPTH_BACK : 0u);
    imageAtomicMin(pixel_depth, ivec2(gl_FragCoord.xy), record);
#ifdef DEPTH_BATCHES
    // a depth batch (reps/common/shaders/depth_batches.glsl): the nearest so far is stored below, by
    // the exact depth (the record above drops its lowest bit for the back-hit mark: 88 of 26,000
    // pixels of a sphere then kept a hit one ulp behind the nearest)
    const bool nearest_so_far = depth_batch_nearer(depth);
#else
    gl_FragDepth = depth;
#endif
    vec3 orm = SHADING_DEFAULT_ORM, emissive = vec3(0.0);
    if (has_pbr_maps != 0) {
        orm = texelFetch(orm_maps, at(texel, layer), 0).rgb;
        emissive = srgb_to_linear(texelFetch(emission_maps, at(texel, layer), 0).rgb);
    }
    vec3 color = shade_pbr_at(albedo.rgb, orm, emissive, normal_world, to_eye, p_world);
    if (debug_view == DEBUG_VIEW_PARTS) color = billboard_color(billboard);
    if (debug_view == DEBUG_VIEW_DEPTH) color = vec3(1.0 - clamp(p_box.z, 0.0, 1.0));
    if (debug_view == DEBUG_VIEW_NORMAL) color = normal_world * 0.5 + 0.5;
    if (debug_view == DEBUG_VIEW_FETCHES) color = fetches_color(uint(g_fetches));
    out_color = vec4(color, 1.0);
#ifdef DEPTH_BATCHES
    if (nearest_so_far) depth_batch_store(color, depth);
#endif
}
