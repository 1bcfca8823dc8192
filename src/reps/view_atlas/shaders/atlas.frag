#version 450 core
// View atlas, per fragment.
// STYLE_SEED: the nearest view's texel (Saraiva et al. §3), lit colour as baked or, with surface maps,
// albedo lit from the stored normal.
// STYLE_BASELINE: the way impostor bakers draw: the three views around the viewing direction, each
// read where the eye ray crosses the centre plane moved by one parallax step along its depth,
// blended by weight.
// STYLE_CORRECTED: the three views around each pixel's ray direction are intersected with the ray as
// height fields (an exact walk over their texels that does not take depth edges for surfaces, and
// that keeps a crossing only where the coverage filtered around it reaches 1/2, issue #14), hits on
// the nearest surface are blended, the true depth is written and the stored normal is lit.
// Every style that lights stored normals (surface maps) lights them with shade_pbr_at: with the
// ORM and emission pages of a PBR package (ATLAS_PBR, issue #14) read where the colour is read,
// otherwise with Material's defaults. Lit-colour packages (lit_maps) show the truth's own shading,
// PBR included, as captured under the capture light: nothing is relit, so they have no PBR pages.
// Filtering never bleeds the background: pages hold colour premultiplied by coverage, are mip-mapped
// as such, and are divided by the filtered coverage; levels stop where two crops would mix.
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "gpu/shaders/common/counters.glsl"
#include "reps/common/shaders/height_field.glsl"
#include "reps/common/shaders/coverage.glsl"
#include "reps/view_atlas/shaders/atlas.glsl"
#include "reps/common/shaders/depth_batches.glsl"

flat in ivec3 v_views;
flat in vec3 v_weights;
flat in int v_instance;
flat in int v_lod; // atlas.vert: ATLAS_LOD_*, the level a corrected-style instance is shaded at
// The one path this program shades, ATLAS_LOD_* (renderer.cpp compiles one program per path it
// draws, and draws each level's instances apart): llvmpipe runs the whole of main() for every
// fragment, the other paths' code included, masked, so the seed's quad cost as much as the walk's
// set-up (a crowd's frame at 1000 copies: docs/RESULTS.md "One fragment program per level").
// Without it, the path is chosen per fragment from the style and v_lod (one program for all).
#ifndef ATLAS_PATH
#define ATLAS_PATH -1
#endif
in vec2 v_atlas_texel;

#ifndef ATLAS_ARRAYS
#define ATLAS_ARRAYS 1 // texture arrays per map, 1..ATLAS_MAX_ARRAYS (renderer.cpp defines it)
#endif
layout(binding = ATLAS_COLOR_TEXTURE) uniform sampler2DArray color_pages[ATLAS_ARRAYS];
layout(binding = ATLAS_NORMAL_DEPTH_TEXTURE) uniform sampler2DArray normal_depth_pages[ATLAS_ARRAYS];
#ifndef ATLAS_PBR
#define ATLAS_PBR 0 // 1: the package has ORM and emission pages (renderer.cpp defines it)
#endif
#if ATLAS_PBR
layout(binding = ATLAS_ORM_TEXTURE) uniform sampler2DArray orm_pages[ATLAS_ARRAYS];
layout(binding = ATLAS_EMISSION_TEXTURE) uniform sampler2DArray emission_pages[ATLAS_ARRAYS];
#endif
#define MAP_COLOR 0
#define MAP_NORMAL_DEPTH 1
#define MAP_ORM 2      // ATLAS_PBR only
#define MAP_EMISSION 3 // ATLAS_PBR only
// One map of texture array i: read (uvw, lod) or fetched (texel).
#if ATLAS_PBR
#define ATLAS_MAP_READ(i) (map == MAP_COLOR ? textureLod(color_pages[i], uvw, lod) : map == MAP_NORMAL_DEPTH ? textureLod(normal_depth_pages[i], uvw, lod) : map == MAP_ORM ? textureLod(orm_pages[i], uvw, lod) : textureLod(emission_pages[i], uvw, lod))
#define ATLAS_MAP_FETCH(i) (map == MAP_COLOR ? texelFetch(color_pages[i], texel, 0) : map == MAP_NORMAL_DEPTH ? texelFetch(normal_depth_pages[i], texel, 0) : map == MAP_ORM ? texelFetch(orm_pages[i], texel, 0) : texelFetch(emission_pages[i], texel, 0))
#else
#define ATLAS_MAP_READ(i) (map == MAP_COLOR ? textureLod(color_pages[i], uvw, lod) : textureLod(normal_depth_pages[i], uvw, lod))
#define ATLAS_MAP_FETCH(i) (map == MAP_COLOR ? texelFetch(color_pages[i], texel, 0) : texelFetch(normal_depth_pages[i], texel, 0))
#endif

uniform int style;
uniform int debug_view; // DEBUG_VIEW_*
uniform int counting; // 1: add this fragment and its texture reads to the counters
uniform int lit_maps; // 1: colour pages hold the baked lit colour (no normals)
// 1: the corrected style reads colour and normals from level 0 at every distance (--color-level,
// issue #14). An alpha-tested truth draws one leaf per pixel, lit from its own normal, with the leaf's
// texture filtered but its outline not; the filtered levels average the image across leaves and
// depths (and light the mean normal), which is far from that picture: on the foliage tree Luv at
// distance 4 / 8 is 6.2 / 7.2 from level 0 against 9.0 / 11.6 from the footprint's level
// (docs/RESULTS.md "View atlas on foliage: colour level and capture resolution"). The truth is
// point-sampled for every model, so level 0 is nearer it for opaque models too, and does not shimmer
// more than it under motion (docs/RESULTS.md "Colour from level 0 for every model"): the host sets it
// unless --color-level mips.
// renderer.cpp compiles it in (ATLAS_FINEST_COLOR): llvmpipe runs the filtered levels' reads
// masked in every fragment otherwise.
#ifdef ATLAS_FINEST_COLOR
const int finest_color = ATLAS_FINEST_COLOR;
#else
uniform int finest_color;
#endif
// The octahedral baseline's parallax steps (style or level; --parallax-steps; 1: impostor bakers')
uniform int parallax_steps;
// The stored depth: 2^bits - 1 steps over the bounding sphere's diameter, and the factor from the
// normal-depth pages' A to the fraction of the diameter (renderer.cpp; 1 for 8-bit depth).
uniform float depth_codes;
uniform float depth_scale;

layout(location = 0) out vec4 out_color;
// Every style writes a depth at or behind its proxy's (corrected: the hit, clamped to the hull's
// face, which it can pass only by a texel of another view's height field), so early depth tests
// can reject fragments behind what is drawn (crowds).
layout(depth_greater) out float gl_FragDepth;

// Early rejection (issue #17, crowds): llvmpipe runs this stage before the depth test, since it
// writes gl_FragDepth, so a fragment behind what is already drawn still walked and shaded (5.85
// fragments per covered pixel at 1000 copies). Every fragment that is drawn records its depth in
// nearest_depth (atomic minimum of the float's bits: depths are non-negative, so the bits order as
// the values), and every style's depth is at or behind its proxy's, so a fragment whose proxy depth
// is already behind that record would fail the draw's GL_LESS test whatever it computes: it stops
// at once, and after the walk, a fragment whose nearest hit is behind it stops before shading. The
// record only holds depths this draw wrote, so it is never nearer than the depth buffer: the picture
// is exactly the one without it. llvmpipe shades each screen tile's fragments on one thread in
// draw order, so the record and the counters are deterministic there; on a GPU the record may lag
// (fewer rejections, same picture). renderer.cpp turns it on (early_reject) only for a GL_LESS test
// with depth writes into a single-sampled target.
uniform int early_reject; // 1: nearest_depth is bound, cleared for this draw
layout(binding = ATLAS_NEAREST_IMAGE, r32ui) uniform coherent uimage2D nearest_depth;

// Whether a fragment at window depth z would fail the depth test against what this draw drew.
bool behind_drawn(float z)
{
    return early_reject != 0 && floatBitsToUint(z) > imageLoad(nearest_depth, ivec2(gl_FragCoord.xy)).r;
}

// The fragment's colour and depth: gl_FragDepth, and its record for behind_drawn; in a depth
// batch (reps/common/shaders/depth_batches.glsl, where renderer.cpp keeps early_reject on) the
// record decides whether it is the nearest so far, which the batch's resolve then draws.
void write_fragment(vec3 color, float z)
{
    out_color = vec4(color, 1.0);
#ifdef DEPTH_BATCHES
    if (floatBitsToUint(z) < imageAtomicMin(nearest_depth, ivec2(gl_FragCoord.xy), floatBitsToUint(z)))
        depth_batch_store(color, z);
#else
    gl_FragDepth = z;
    if (early_reject != 0) imageAtomicMin(nearest_depth, ivec2(gl_FragCoord.xy), floatBitsToUint(z));
#endif
}

// A read of one map's texture array `array`. Views of one draw lie in different arrays, so the
// sampler is chosen by branching (indices into sampler arrays must be dynamically uniform).
#define ATLAS_READ(i) if (array == i) return ATLAS_MAP_READ(i);
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
    return ATLAS_MAP_READ(0);
}

// A page sample of map MAP_* at an atlas texel position: empty outside the
// view's crop, clamped inside it at that level (so that filtering never reads a neighbouring crop).
vec4 sample_page(int map, ViewData view, vec2 texel, float lod)
{
    if (any(lessThan(texel, vec2(view.atlas.yz))) || any(greaterThan(texel, vec2(view.atlas.yz + view.crop.zw))))
        return vec4(0.0); // clamping would repeat the crop's border texels outwards as streaks
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

// --- the corrected style's height-field intersection ---------------------------------------------
// A view is a height field over its capture plane: texel (i, j) holds a top through its stored
// height (object units above the centre plane, towards the capture camera) at its centre, tilted by
// its stored normal (texel_gradient, below; the enhanced billboards' tops tilt by their depths). As in the
// enhanced billboards' march (reps/enhanced_billboards/acceleration.h), the surface is the texel tops plus
// the walls between neighbours that continue one surface (height step within what their normals'
// slope allows); a larger step is a depth edge, where the view saw one surface in front of another
// and knows nothing of the gap between them. A ray that enters a column below its top through such
// an edge is in space the view did not see: no hit, and the view abstains instead of voting "empty".
#define RAY_MISS 0   // passed through the view's box without meeting or passing under a surface
#define RAY_HIT 1
#define RAY_HIDDEN 2 // passed under a surface the view saw: it cannot tell what is there

uint g_fetches = 0u;

void count_this_fragment()
{
    if (counting != 0) count_fragment(g_fetches);
}

vec4 fetch_array(int map, int array, ivec3 texel)
{
    g_fetches += 1u;
#define ATLAS_FETCH(i) if (array == i) return ATLAS_MAP_FETCH(i);
#if ATLAS_ARRAYS > 1
    ATLAS_FETCH(1)
#endif
#if ATLAS_ARRAYS > 2
    ATLAS_FETCH(2)
#endif
#if ATLAS_ARRAYS > 3
    ATLAS_FETCH(3)
#endif
#if ATLAS_ARRAYS > 4
    ATLAS_FETCH(4)
#endif
#if ATLAS_ARRAYS > 5
    ATLAS_FETCH(5)
#endif
#if ATLAS_ARRAYS > 6
    ATLAS_FETCH(6)
#endif
#if ATLAS_ARRAYS > 7
    ATLAS_FETCH(7)
#endif
    return ATLAS_MAP_FETCH(0);
}

// One texel of a view's height field at level 0: x: covered (0/1), y: height, zw: the normal's
// slope along axis_u and axis_v (height per unit of plane distance, capped).
// nd: the texel as read (zero where none was read), for callers that need it too.
vec4 height_texel(ViewData view, ivec2 capture_texel, out vec4 nd)
{
    nd = vec4(0.0);
    ivec2 local = capture_texel - view.crop.xy;
    if (any(lessThan(local, ivec2(0))) || any(greaterThanEqual(local, view.crop.zw))) return vec4(0.0);
    // one read: level 0 of the normal-depth pages holds the stored values on every covered texel
    // (however little covered) and zero on empty ones (renderer.cpp, upload_pages), while a unit
    // normal encoded as n * 0.5 + 0.5 has a component of at least 0.21
    nd = fetch_array(MAP_NORMAL_DEPTH, view.atlas.w, ivec3(view.atlas.yz + local, view.atlas.x));
    if (max(nd.r, max(nd.g, nd.b)) < 0.1) return vec4(0.0);
    vec3 n = nd.rgb * 2.0 - 1.0;
    vec3 n_view = vec3(dot(n, view.axis_u.xyz), dot(n, view.axis_v.xyz), dot(n, view.direction.xyz));
    vec2 slope = vec2(hf_slope(n_view.x, n_view.z), hf_slope(n_view.y, n_view.z));
    return vec4(1.0, atlas_radius - 2.0 * atlas_radius * nd.a * depth_scale, slope);
}

vec4 height_texel(ViewData view, ivec2 capture_texel)
{
    vec4 nd;
    return height_texel(view, capture_texel, nd);
}

layout(binding = ATLAS_CELL_TEXTURE) uniform sampler2DArray cell_tops;
uniform int pages_per_array; // a view's page is atlas.w * pages_per_array + atlas.x

// The height of the highest surface in the ATLAS_CELL cell holding a view's capture texel (-r when
// the cell is empty).
float cell_top(ViewData view, ivec2 capture_texel)
{
    g_fetches += 1u;
    ivec2 atlas_cell = (view.atlas.yz + capture_texel - view.crop.xy) / ATLAS_CELL;
    float code = texelFetch(cell_tops, ivec3(atlas_cell, view.atlas.w * pages_per_array + view.atlas.x), 0).r;
    return atlas_radius - 2.0 * atlas_radius * code;
}

// One step of the stored depth (bake.depth_bits: renderer.cpp), in object units.
float depth_quantum() { return 2.0 * atlas_radius / depth_codes; }

// Whether neighbouring covered texels a and b (across axis 0: u, 1: v) continue one surface
// (height_field.h).
bool linked(vec4 a, vec4 b, int axis, float texel)
{
    return abs(a.y - b.y) <= hf_link_tolerance(a[2 + axis], b[2 + axis], texel, depth_quantum());
}

// The coverage of the surface at height `height` at plane point `plane` of a view (issue #14): the
// colour pages' alpha (for alpha-tested models the covered fraction of each texel, bake.cpp) of the
// four texels around the point, filtered bilinearly among those of the same surface as the truth's
// alpha test filters its texture (reps/common/shaders/coverage.glsl, shared with microfacets), so
// that a cut-out's edge falls where the filtered coverage crosses 1/2, inside a texel, instead of on
// texel borders. Binary packages get the contour half-way between covered and empty texel centres
// (their old edge on texel borders, with corners cut).
uniform int binary_coverage; // 1: every colour alpha is 0 or 1 (renderer.cpp, cell_depths): no alpha to read
uniform int alpha_tested;    // 1: the model has alpha-tested materials (foliage)

float hit_coverage(ViewData view, vec2 plane, float height, out float presence)
{
    float texel = 2.0 * half_extent / resolution;
    vec2 p = capture_from_plane(plane) - 0.5;
    ivec2 base = ivec2(floor(p));
    bvec4 covered = bvec4(false);
    vec4 heights = vec4(0.0), tolerances = vec4(0.0), alphas = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        ivec2 corner = ivec2(k & 1, k >> 1);
        vec4 t = height_texel(view, base + corner);
        if (t.x <= 0.5) continue;
        covered[k] = true;
        heights[k] = t.y;
        tolerances[k] = hf_coverage_tolerance(t.z, t.w, texel, depth_quantum());
        alphas[k] = binary_coverage != 0 ? 1.0
                                         : fetch_array(MAP_COLOR, view.atlas.w, ivec3(view.atlas.yz + base + corner - view.crop.xy, view.atlas.x)).a;
    }
    return hf_filtered_coverage(p - vec2(base), height, covered, heights, tolerances, alphas, presence);
}

// The slope of a covered texel's top: its height change per plane unit along axis_u and axis_v,
// from its stored normal nd (as read), capped at ATLAS_TOP_MAX_SLOPE (renderer.cpp's top_slope
// bounds the cell tops with it). A top is the plane through the stored height at the texel's
// centre with this slope, not a flat step: flat steps stand out of a curved or slanted surface by
// up to half a texel's rise, and near an outline a ray that passes beside the model meets them (a
// side view's hit outside the silhouette: spill). Capped because a steeper top would reach many
// texels past the depth stored at its centre: the cap measured best between 1 and 8
// (docs/RESULTS.md "Tilted texel tops").
vec2 texel_gradient(ViewData view, vec4 nd)
{
    vec3 n = nd.rgb * 2.0 - 1.0;
    float across = max(dot(n, view.direction.xyz), 1e-6);
    vec2 g = -vec2(dot(n, view.axis_u.xyz), dot(n, view.axis_v.xyz)) / across;
    return clamp(g, -ATLAS_TOP_MAX_SLOPE, ATLAS_TOP_MAX_SLOPE);
}

// Intersects ray o + t d (object space) with one view's height field: a digital walk over the
// texels under the ray between the view's nearest and farthest stored heights. A crossing where
// the surface's filtered coverage is under 1/2 (hit_coverage) is no hit: the ray passes beside the
// edge there and walks on. Returns (t, result); `coverage`: a hit's filtered coverage; `presence`:
// the same counting surfaces behind it too (hf_filtered_coverage).
vec2 intersect_view(ViewData view, vec3 o, vec3 d, out float coverage, out float presence)
{
    coverage = 0.0;
    presence = 0.0;
    vec3 u = view.axis_u.xyz, v = view.axis_v.xyz, w = view.direction.xyz;
    vec3 ro = vec3(dot(o - atlas_center, u), dot(o - atlas_center, v), dot(o - atlas_center, w));
    vec3 rd = vec3(dot(d, u), dot(d, v), dot(d, w));
    if (rd.z > -1e-4 || view.depth_range.x < view.depth_range.y) return vec2(-1.0, RAY_MISS);
    float texel = 2.0 * half_extent / resolution;
    // the slab between the stored heights, and the crop's rectangle
    float t0 = (view.depth_range.x + 1e-4 * atlas_radius - ro.z) / rd.z; // reaches the nearest height
    float t1 = (view.depth_range.y - 1e-4 * atlas_radius - ro.z) / rd.z; // passes the farthest
    vec2 lo = plane_from_capture(vec2(view.crop.xy)), hi = plane_from_capture(vec2(view.crop.xy + view.crop.zw));
    for (int a = 0; a < 2; ++a) {
        if (abs(rd[a]) < 1e-9) {
            if (ro[a] < lo[a] || ro[a] > hi[a]) return vec2(-1.0, RAY_MISS);
            continue;
        }
        float ta = (lo[a] - ro[a]) / rd[a], tb = (hi[a] - ro[a]) / rd[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    t0 = max(t0, 0.0);
    if (t0 >= t1) return vec2(-1.0, RAY_MISS);

    // digital walk in capture pixels (Amanatides & Woo), skipping whole ATLAS_CELL cells the ray
    // passes above (their highest surface is below where the ray leaves them); crossings are
    // computed from the start point so that skips and steps agree exactly
    float scale = resolution / (2.0 * half_extent);
    vec2 p0 = capture_from_plane((ro + t0 * rd).xy);
    vec2 dp = rd.xy * scale; // capture pixels per unit t
    ivec2 step_dir = ivec2(dp.x >= 0.0 ? 1 : -1, dp.y >= 0.0 ? 1 : -1);
    vec2 inv = vec2(abs(dp.x) > 1e-9 ? 1.0 / abs(dp.x) : 1e30, abs(dp.y) > 1e-9 ? 1.0 / abs(dp.y) : 1e30);
    ivec2 crop_lo = view.crop.xy, crop_hi = view.crop.xy + view.crop.zw - 1;
    ivec2 cell = clamp(ivec2(floor(p0)), crop_lo, crop_hi);
    // where the ray crosses the vertical and horizontal line x = X / y = Y (capture pixels)
    #define CROSSING(axis, line) (t0 + abs(float(line) - p0[axis]) * inv[axis])
    vec2 t_next = vec2(CROSSING(0, cell.x + max(step_dir.x, 0)), CROSSING(1, cell.y + max(step_dir.y, 0)));

    float t_enter = t0;
    int entered_across = -1; // axis crossed into the current texel, -1 at the start
    vec4 previous = vec4(0.0);
    vec2 previous_gradient = vec2(0.0); // the previous texel's tilt (texel_gradient)
    ivec2 previous_cell = cell;
    bool previous_unread = false; // the previous texel lies in a skipped cell: read it if needed
    bool read_previous = false;   // this step reads the previous texel, then the current one again
    bool previous_above = true;   // the ray left the previous texel above its top (or it was empty)
    bool hidden = false;
    ivec2 block = ivec2(-1);
    vec2 p1 = capture_from_plane((ro + t1 * rd).xy);
    int steps = min(int(abs(p0.x - p1.x) + abs(p0.y - p1.y)) + 5, 1024); // 2 more: a wall after a skip
    // The walk stops at each crossing of a top or wall (a candidate) and tests the candidate's
    // coverage outside its loop, resuming where it stopped when the coverage is under 1/2: the same
    // pictures, 10-15% faster on llvmpipe, whose SIMD lanes step through a loop's body together
    // (docs/RESULTS.md "The walk's loop body").
    int i = 0;
    bool walk_ended = false;
    for (;;) {
        float t_candidate = -1.0;
        for (; i < steps; ++i) {
            if (any(lessThan(cell, crop_lo)) || any(greaterThan(cell, crop_hi))) { // left the crop
                walk_ended = true;
                break;
            }
            ivec2 cell_block = (cell - view.crop.xy) / ATLAS_CELL;
            if (cell_block != block) {
                block = cell_block;
                ivec2 block_lo = view.crop.xy + block * ATLAS_CELL;
                float t_leave = min(min(CROSSING(0, block_lo.x + (step_dir.x > 0 ? ATLAS_CELL : 0)),
                                        CROSSING(1, block_lo.y + (step_dir.y > 0 ? ATLAS_CELL : 0))), t1);
                if (ro.z + t_leave * rd.z > cell_top(view, cell)) {
                    if (t_leave >= t1) {
                        walk_ended = true;
                        break;
                    }
                    // jump to the texel after the cell's exit
                    int axis = CROSSING(0, block_lo.x + (step_dir.x > 0 ? ATLAS_CELL : 0)) <
                                       CROSSING(1, block_lo.y + (step_dir.y > 0 ? ATLAS_CELL : 0)) ? 0 : 1;
                    vec2 p = p0 + (t_leave - t0) * dp;
                    ivec2 next = ivec2(floor(p));
                    next[axis] = block_lo[axis] + (step_dir[axis] > 0 ? ATLAS_CELL : -1);
                    previous_cell = next;
                    previous_cell[axis] -= step_dir[axis];
                    previous_unread = true;
                    previous_above = true;
                    entered_across = axis;
                    cell = next;
                    t_next = vec2(CROSSING(0, cell.x + max(step_dir.x, 0)), CROSSING(1, cell.y + max(step_dir.y, 0)));
                    t_enter = t_leave;
                    continue;
                }
            }
            // one read per step: this texel's, or the previous one's when a wall needs it (below;
            // a second read site in the loop's body cost llvmpipe 3-5% more)
            vec4 current_nd;
            vec4 current = height_texel(view, read_previous ? previous_cell : cell, current_nd);
            // the tilted top: height current.y + g . (p - centre); the ray is compared with it as a
            // ray (z_origin + t z_per_t) against the flat top current.y, shifted by the tilt
            vec2 gradient = current.x > 0.5 ? texel_gradient(view, current_nd) : vec2(0.0);
            if (read_previous) {
                previous = current;
                previous_gradient = gradient;
                previous_unread = false;
                read_previous = false;
                continue;
            }
            float t_exit = min(min(t_next.x, t_next.y), t1);
            vec2 centre = plane_from_capture(vec2(cell) + 0.5);
            float z_origin = ro.z - dot(gradient, ro.xy - centre), z_per_t = rd.z - dot(gradient, rd.xy);
            if (current.x > 0.5) {
                // depth grows away from the view's camera: the negated height
                bool below = z_origin + t_enter * z_per_t <= current.y;
                if (below && entered_across >= 0 && previous_above && previous_unread) {
                    // a wall just past a skipped cell: the texel before it, in that cell, is read at
                    // the next step, and this one again at the step after
                    read_previous = true;
                    continue;
                }
                bool from_linked = below && entered_across >= 0 && previous.x > 0.5 && previous_above &&
                                   linked(previous, current, entered_across, texel);
                // the neighbour's tilted top where the ray crosses the wall, in the shifted frame
                float previous_top = 0.0;
                if (from_linked) {
                    vec2 wall_point = ro.xy + t_enter * rd.xy;
                    previous_top = previous.y + dot(previous_gradient, wall_point - plane_from_capture(vec2(previous_cell) + 0.5)) -
                                   dot(gradient, wall_point - centre);
                }
                vec2 crossing = hf_cross_column(t_enter, t_enter, t_exit, -z_origin, -z_per_t, -current.y, from_linked, -previous_top);
                if (crossing.y == HF_TOP || crossing.y == HF_WALL) t_candidate = crossing.x;
                hidden = hidden || crossing.y == HF_UNDER;
            }
            previous = current;
            previous_gradient = gradient;
            previous_cell = cell;
            previous_unread = false;
            previous_above = current.x < 0.5 || z_origin + t_exit * z_per_t > current.y;
            if (t_exit >= t1) {
                walk_ended = true;
                break;
            }
            if (t_next.x < t_next.y) {
                cell.x += step_dir.x;
                t_next.x = CROSSING(0, cell.x + max(step_dir.x, 0));
                entered_across = 0;
            } else {
                cell.y += step_dir.y;
                t_next.y = CROSSING(1, cell.y + max(step_dir.y, 0));
                entered_across = 1;
            }
            t_enter = t_exit;
            if (t_candidate >= 0.0) {
                ++i;
                break;
            }
        }
        if (t_candidate < 0.0) break;
        vec3 hit = ro + t_candidate * rd; // plane coordinates and height
        coverage = hit_coverage(view, hit.xy, hit.z, presence);
        if (coverage >= 0.5) return vec2(t_candidate, RAY_HIT);
        if (walk_ended || i >= steps) break;
    }
    #undef CROSSING
    return vec2(-1.0, hidden ? RAY_HIDDEN : RAY_MISS);
}

// A view's colour (premultiplied, alpha 1) and normal-depth at a hit at plane point `plane` and
// height `height`: bilinear over the level-0 texels of the hit's own surface only (height within
// what their normals' slope allows), so that colour does not leak across a depth edge (plain
// filtering would ring the front object with its colour on the surface behind it); from level 1 on
// the coverage-respecting mip levels, blended in over the first level. orm and emission: the PBR
// pages likewise (premultiplied; zero without ATLAS_PBR).
void surface_sample(ViewData view, vec2 plane, float height, float lod, out vec4 color, out vec4 normal_depth,
                    out vec4 orm, out vec4 emission)
{
    float texel = 2.0 * half_extent / resolution;
    vec2 p = capture_from_plane(plane) - 0.5;
    ivec2 base = ivec2(floor(p));
    vec2 f = p - vec2(base);
    color = vec4(0.0);
    normal_depth = vec4(0.0);
    orm = vec4(0.0);
    emission = vec4(0.0);
    float weight_sum = 0.0;
    if (lod < 1.0) {
        for (int k = 0; k < 4; ++k) {
            ivec2 corner = ivec2(k & 1, k >> 1);
            vec4 texel_nd; // the normal-depth texel, read once for the height and the blend
            vec4 t = height_texel(view, base + corner, texel_nd);
            if (t.x < 0.5) continue;
            // the link rule's step, and a texel more: the hit may lie anywhere on its texel
            float tolerance = hf_link_tolerance(t.z, t.w, texel, depth_quantum()) + texel;
            if (abs(t.y - height) > tolerance) continue;
            float w = (corner.x == 1 ? f.x : 1.0 - f.x) * (corner.y == 1 ? f.y : 1.0 - f.y) + 1e-6;
            ivec3 at = ivec3(view.atlas.yz + base + corner - view.crop.xy, view.atlas.x);
            vec4 texel_color = fetch_array(MAP_COLOR, view.atlas.w, at);
            color += w * texel_color;
            // level 0 of the normal-depth pages is not premultiplied (renderer.cpp, upload_pages):
            // weight it by the colour's coverage like the other maps
            normal_depth += w * texel_color.a * texel_nd;
#if ATLAS_PBR
            orm += w * fetch_array(MAP_ORM, view.atlas.w, at);
            emission += w * fetch_array(MAP_EMISSION, view.atlas.w, at);
#endif
            weight_sum += w;
        }
    }
    vec2 texel_position = atlas_texel(view, plane);
    if (weight_sum <= 0.0) { // far away, or no texel of the surface around: the filtered maps
        color = sample_page(MAP_COLOR, view, texel_position, max(lod, 0.0));
        normal_depth = sample_page(MAP_NORMAL_DEPTH, view, texel_position, max(lod, 0.0));
#if ATLAS_PBR
        orm = sample_page(MAP_ORM, view, texel_position, max(lod, 0.0));
        emission = sample_page(MAP_EMISSION, view, texel_position, max(lod, 0.0));
#endif
        return;
    }
    color /= weight_sum;
    normal_depth /= weight_sum;
    orm /= weight_sum;
    emission /= weight_sum;
    if (finest_color == 0 && lod > 0.0) { // (finest colour: lod <= 0 here)
        color = mix(color, sample_page(MAP_COLOR, view, texel_position, lod), lod);
        normal_depth = mix(normal_depth, sample_page(MAP_NORMAL_DEPTH, view, texel_position, lod), lod);
#if ATLAS_PBR
        orm = mix(orm, sample_page(MAP_ORM, view, texel_position, lod), lod);
        emission = mix(emission, sample_page(MAP_EMISSION, view, texel_position, lod), lod);
#endif
    }
}

// The coverage a filtered texel needs to be drawn (issue #14). At level 0 and closer, 0.5: the cut-out's
// edge where its coverage crosses half. Minified, a filtered texel's coverage is the fraction of it
// covered, and a fixed 0.5 would drop every texel under half covered (distant leaves vanish) and keep
// every one over it whole (dense foliage fattens); a per-pixel threshold spread evenly over (0, 1) (a
// 4 x 4 ordered dither) keeps a pixel with the probability of its coverage, so the area is kept, as
// alpha-to-coverage does (Castano 2010 keeps it by rescaling mip alpha instead; one threshold per
// pixel needs no change to the pages). Solid models keep 0.5: their minified coverage is a
// silhouette's, which the truth draws where a pixel's centre is inside, not a leaf's area, and the
// dither frayed it by a pixel (the baseline level at 24 px: Luv 4.9-6.0, IoU 0.90-0.92
// against the walk, 1.7-2.4 and 0.97 cut at 1/2; docs/RESULTS.md "The cheap levels' silhouettes").
float coverage_threshold(float lod)
{
    const float bayer[16] = float[16](0.0, 8.0, 2.0, 10.0, 12.0, 4.0, 14.0, 6.0, 3.0, 11.0, 1.0, 9.0, 15.0, 7.0, 13.0, 5.0);
    ivec2 p = ivec2(gl_FragCoord.xy) & 3;
    if (alpha_tested == 0) return 0.5;
    float dither = (bayer[p.y * 4 + p.x] + 0.5) / 16.0;
    return mix(0.5, dither, clamp(lod, 0.0, 1.0));
}

// orm: occlusion, roughness, metallic; emission: sRGB-encoded (the pages' encodings).
vec3 shade_surface(vec3 albedo, vec3 orm, vec3 emission, vec3 normal_object, vec3 direction_world, vec3 position_world)
{
    mat4 world_from_object = instances.world_from_object[v_instance];
    vec3 normal_world = normalize(mat3(world_from_object) * normal_object);
    return shade_pbr_at(albedo, orm, srgb_to_linear(emission), normal_world, -direction_world, position_world);
}

// A PBR page at a texel position of one view divided by the colour's coverage `a` (pages are
// premultiplied by it); Material's defaults without ATLAS_PBR.
vec3 pbr_sample(int map, ViewData view, vec2 texel, float lod, float a)
{
#if ATLAS_PBR
    return sample_page(map, view, texel, lod).rgb / a;
#else
    return map == MAP_ORM ? SHADING_DEFAULT_ORM : vec3(0.0);
#endif
}

// The picture of a debug view in place of the shaded colour.
vec3 debug_color(vec3 shaded, int view, vec3 normal_world, float window_z)
{
    if (debug_view == DEBUG_VIEW_PARTS) return index_color(view);
    if (debug_view == DEBUG_VIEW_DEPTH) return vec3(1.0 - window_z);
    if (debug_view == DEBUG_VIEW_NORMAL) return normalize(normal_world) * 0.5 + 0.5;
    if (debug_view == DEBUG_VIEW_FETCHES) return fetches_color(g_fetches);
    return shaded;
}

void main()
{
    // a whole 2x2 quad behind what is drawn stops before any work (behind_drawn); a quad only partly
    // behind goes on to its derivatives, which need every lane (below). The quad test reads the
    // neighbours' flags by fine derivatives, in uniform control flow: the row pair's, then the column's.
    if (early_reject != 0) {
        float behind = behind_drawn(gl_FragCoord.z) ? 1.0 : 0.0;
        float pair = behind > 0.5 && dFdxFine(behind) == 0.0 ? 1.0 : 0.0;
        if (pair > 0.5 && dFdyFine(pair) == 0.0) {
            count_this_fragment();
            discard;
        }
    }
    mat4 world_from_object = instances.world_from_object[v_instance];
    mat4 object_from_world = inverse(world_from_object);
    vec3 origin_world, direction_world;
    camera_ray(gl_FragCoord.xy, origin_world, direction_world);
    vec3 o = (object_from_world * vec4(origin_world, 1.0)).xyz;
    vec3 d = normalize(mat3(object_from_world) * direction_world);

    if (ATLAS_PATH == -1 ? style == STYLE_SEED || v_lod == ATLAS_LOD_SEED : ATLAS_PATH == ATLAS_LOD_SEED) {
        ViewData view = views.items[v_views.x];
        vec2 dx = dFdx(v_atlas_texel), dy = dFdy(v_atlas_texel);
        float lod = log2(max(max(length(dx), length(dy)), 1e-8));
        if (fade_discards()) discard; // after the derivatives, as below
        if (behind_drawn(gl_FragCoord.z)) {
            count_this_fragment();
            discard;
        }
        vec4 c = sample_page(MAP_COLOR, view, v_atlas_texel, lod);
        g_fetches = lit_maps != 0 ? 1u : (ATLAS_PBR != 0 ? 4u : 2u);
        count_this_fragment();
        if (c.a < coverage_threshold(lod)) discard;
        vec3 color = c.rgb / c.a, n = -d; // lit-only packages have no normals
        if (lit_maps == 0) {
            n = sample_page(MAP_NORMAL_DEPTH, view, v_atlas_texel, lod).rgb / c.a * 2.0 - 1.0;
            vec3 orm = pbr_sample(MAP_ORM, view, v_atlas_texel, lod, c.a);
            vec3 emission = pbr_sample(MAP_EMISSION, view, v_atlas_texel, lod, c.a);
            color = shade_surface(color, orm, emission, n, direction_world, fragment_world_position());
        }
        write_fragment(debug_color(color, v_views.x, mat3(world_from_object) * n, gl_FragCoord.z), gl_FragCoord.z);
        return;
    }

    // the level of detail from the centre plane's texel footprint (uniform control flow)
    ViewData first = views.items[v_views.x];
    float t_plane = -dot(o - atlas_center, first.direction.xyz) / dot(d, first.direction.xyz);
    vec3 on_plane = o + t_plane * d - atlas_center;
    vec2 plane_texel = capture_from_plane(vec2(dot(on_plane, first.axis_u.xyz), dot(on_plane, first.axis_v.xyz)));
    float lod = log2(max(max(length(dFdx(plane_texel)), length(dFdy(plane_texel))), 1e-8));
    // a cross-fade's other renderer owns this pixel; dropped after the derivatives above, which
    // need the whole 2x2 quad alive; so is a fragment behind what this draw drew
    if (fade_discards()) discard;
    if (behind_drawn(gl_FragCoord.z)) {
        count_this_fragment();
        discard;
    }

    vec4 color_sum = vec4(0.0), normal_sum = vec4(0.0);
    vec3 orm_sum = vec3(0.0), emission_sum = vec3(0.0); // premultiplied (baseline) or weighted (corrected)
    float t_sum = 0.0, t_weight = 0.0;
    if (ATLAS_PATH == -1 ? style == STYLE_BASELINE || v_lod == ATLAS_LOD_BASELINE : ATLAS_PATH == ATLAS_LOD_BASELINE) {
        for (int k = 0; k < 3; ++k) {
            if (v_weights[k] <= 0.0) continue;
            ViewData view = views.items[v_views[k]];
            vec3 w = view.direction.xyz;
            float dw = dot(d, w);
            if (abs(dw) < 1e-6) continue;
            float t = -dot(o - atlas_center, w) / dw; // the centre plane
            vec3 p = o + t * d - atlas_center;
            vec2 texel = atlas_texel(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)));
            // parallax steps: the ray's point whose height over the centre plane is the depth read at
            // the last point (1: the impostor bakers' one step; more: iterative parallax mapping, which
            // converges where the surface under the ray is less steep than the ray)
            const float t_plane = t;
            for (int step = 0; step < parallax_steps; ++step) {
                vec4 nd = sample_page(MAP_NORMAL_DEPTH, view, texel, lod);
                float coverage = sample_page(MAP_COLOR, view, texel, lod).a;
                g_fetches += 2u;
                if (coverage <= 0.0) break;
                float height = atlas_radius - 2.0 * atlas_radius * nd.a * depth_scale / coverage;
                t = t_plane + height / dw;
                p = o + t * d - atlas_center;
                texel = atlas_texel(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)));
            }
            color_sum += v_weights[k] * sample_page(MAP_COLOR, view, texel, lod);
            normal_sum += v_weights[k] * sample_page(MAP_NORMAL_DEPTH, view, texel, lod);
            g_fetches += 4u;
#if ATLAS_PBR
            g_fetches += 2u;
            orm_sum += v_weights[k] * pbr_sample(MAP_ORM, view, texel, lod, 1.0);
            emission_sum += v_weights[k] * pbr_sample(MAP_EMISSION, view, texel, lod, 1.0);
#endif
        }
        count_this_fragment();
        if (color_sum.a < coverage_threshold(lod)) discard;
        vec3 albedo = color_sum.rgb / color_sum.a;
        vec3 n = normal_sum.rgb / color_sum.a * 2.0 - 1.0;
        vec3 orm = ATLAS_PBR != 0 ? orm_sum / color_sum.a : SHADING_DEFAULT_ORM;
        vec3 emission = emission_sum / color_sum.a;
        vec3 shaded = lit_maps != 0 ? albedo : shade_surface(albedo, orm, emission, n, direction_world, fragment_world_position());
        write_fragment(debug_color(shaded, v_views.x, mat3(world_from_object) * n, gl_FragCoord.z), gl_FragCoord.z);
        return;
    }

    // corrected: the views around this pixel's own ray direction (not the instance's: near the model
    // a perspective camera's rays spread by the field of view, and each ray is best served by the
    // views taken along it), each intersected exactly; a view that sees no surface along the ray
    // votes "empty", one whose ray went under a surface it saw abstains, and the hits on the
    // nearest surface are blended by weight.
    ivec3 ids;
    vec3 weights;
    blend_views(-d, ids, weights);
    vec2 hits[3];
    float t_min = 1e30, hit_vote = 0.0, miss_vote = 0.0;
    for (int k = 0; k < 3; ++k) {
        hits[k] = vec2(-1.0, RAY_MISS);
        if (weights[k] <= 0.0) continue;
        float coverage, presence;
        hits[k] = intersect_view(views.items[ids[k]], o, d, coverage, presence);
        if (hits[k].y == RAY_HIT) {
            t_min = min(t_min, hits[k].x);
            // a hit counts by how sure its view is of it: one within half a texel of that view's
            // cut-out or outline (filtered coverage 1/2..1) may be the view's sampling of the edge,
            // or a side view meeting its own outline's texels, which stand out past the model as
            // columns along that view (three views' columns intersect to more than the model: spill
            // around every outline). Misses keep their weight. Thesis Luv / IoU: bunny 0.899 /
            // 0.9900 -> 0.846 / 0.9908, the assembly 2.105 / 0.9932 -> 2.040 / 0.9936, the four assimp
            // models under 0.98 each +0.0015-0.002 IoU; the tree at distance 1 5.453 -> 5.381
            // (docs/RESULTS.md "Depth bits and the front-surface vote").
            // Whether anything is there is voted by the presence instead: near an edge over a surface
            // behind, the hit is unsure of its own surface but not that the ray meets one (else a
            // weak front hit lost to the misses and abstentions left pinholes inside the picture;
            // the engine 2.034 / 0.9935 -> 1.978 / 0.9946, docs/RESULTS.md "Tilted texel tops").
            hit_vote += weights[k] * (smoothstep(0.5, 1.0, presence) * 0.999 + 0.001);
            weights[k] *= smoothstep(0.5, 1.0, coverage) * 0.999 + 0.001;
        } else if (hits[k].y == RAY_MISS) {
            miss_vote += weights[k];
        } else if (alpha_tested == 0) {
            // a solid model's view that passed under its surface abstains, but not wholly: else a
            // lone hit within its view's outline, down-weighted above, is drawn wherever the other
            // two views passed under a surface, which around every outline they do (half the spill
            // of solid models). Foliage keeps the abstention whole: rays pass under other leaves
            // in most views, and thin leaves are often met by one view only (docs/RESULTS.md
            // "Tilted texel tops").
            miss_vote += 0.05 * weights[k];
        }
    }
    if (hit_vote <= 0.0 || hit_vote < miss_vote) {
        count_this_fragment();
        discard;
    }
    // The surface drawn is voted for like the background is: each view places a surface's edge
    // within its own texels, so the nearest hit of any view would grow every front surface by the
    // worst of three views' errors over what lies behind it (leaf over leaf, part over part). A
    // surface is kept where the views that meet it weigh at least as much as those that see past it
    // (a farther hit, or nothing); else the next one is voted on. A view that passed under a surface
    // it saw abstains, as above. (Thesis Luv of the assembly 2.17 -> 2.11, foliage at distance 1
    // 5.51 -> 5.45; docs/RESULTS.md "Depth bits and the front-surface vote".)
    float texel_size = 2.0 * half_extent / resolution;
    for (int pass = 0; pass < 2; ++pass) {
        float front = 0.0, past = miss_vote, t_next = 1e30;
        for (int k = 0; k < 3; ++k) {
            if (hits[k].y != RAY_HIT || hits[k].x < t_min) continue;
            if (hits[k].x - t_min <= 2.0 * texel_size) {
                front += weights[k];
            } else {
                past += weights[k];
                t_next = min(t_next, hits[k].x);
            }
        }
        if (front >= past || t_next >= 1e30) break;
        t_min = t_next;
    }
    // the depth written is the blend's, at or behind the voted surface's nearest hit
    if (behind_drawn(max(window_depth((world_from_object * vec4(o + t_min * d, 1.0)).xyz), gl_FragCoord.z))) {
        count_this_fragment();
        discard;
    }
    // hits within two texels of the surface voted for are that surface; weight fades out to four
    // texels so that a view's hit does not enter or leave the blend abruptly as the camera moves
    // (hits in front of it were voted down)
    int main_view = ids.x;
    float main_weight = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (hits[k].y != RAY_HIT || hits[k].x < t_min - 2.0 * texel_size) continue;
        float weight = weights[k] * clamp(2.0 - (hits[k].x - t_min) / (2.0 * texel_size), 0.0, 1.0);
        if (weight <= 0.0) continue;
        ViewData view = views.items[ids[k]];
        vec3 p = o + hits[k].x * d - atlas_center;
        vec4 c, nd, orm, emission;
        surface_sample(view, vec2(dot(p, view.axis_u.xyz), dot(p, view.axis_v.xyz)), dot(p, view.direction.xyz),
                       finest_color != 0 ? min(lod, 0.0) : lod, c, nd, orm, emission);
        if (c.a <= 0.0) continue;
        color_sum += weight * vec4(c.rgb / c.a, 1.0);
        normal_sum += weight * vec4(nd.rgb / c.a * 2.0 - 1.0, 0.0);
        orm_sum += weight * orm.rgb / c.a;
        emission_sum += weight * emission.rgb / c.a;
        t_sum += weight * hits[k].x;
        t_weight += weight;
        if (weight > main_weight) {
            main_weight = weight;
            main_view = ids[k];
        }
    }
    count_this_fragment();
    if (t_weight <= 0.0) discard;
    vec3 p_object = o + (t_sum / t_weight) * d;
    vec3 p_world = (world_from_object * vec4(p_object, 1.0)).xyz;
    vec3 albedo = color_sum.rgb / t_weight;
    vec3 orm = ATLAS_PBR != 0 ? orm_sum / t_weight : SHADING_DEFAULT_ORM;
    vec3 shaded = lit_maps != 0 ? albedo : shade_surface(albedo, orm, emission_sum / t_weight, normal_sum.xyz, direction_world, p_world);
    float z = max(window_depth(p_world), gl_FragCoord.z);
    write_fragment(debug_color(shaded, main_view, mat3(world_from_object) * normal_sum.xyz, z), z);
}
