#version 450 core
// Microfacets, the per-frame selection (Yamazaki et al. 2002 §3.3, §5.4, §6.2), one invocation per
// work item = (instance, octree node of a level the instance may draw):
//  1. the node's centre and size, the instance's view of it (InstanceLod, from the CPU);
//  2. viewport culling of the facet's extent (§5.4 "viewport clipping");
//  3. the LOD cut: drawn when its eq. 2 error is within the bound and its parent's is not (lod.h);
//  4. the views for its texture: the blend_count nearest to the direction towards the eye, from the
//     lookup cell's candidates, or from the per-draw list (the seed's cone, or every view), with
//     weights that change continuously (view_lookup.h select_views is the CPU reference); with the
//     ray clip (beyond the paper, issue #14), the nearest of those that saw surface in the node
//     (visibility.h), and a node none of them saw surface in is dropped;
//  5. quad or point by its size on screen;
//  6. its rank among its group's quads and points (a scan in shared memory), so that scatter.comp
//     writes the kept facets in work order: draws do not depend on thread timing.
#include "gpu/shaders/common/frame.glsl"
#include "reps/microfacets/shaders/microfacets.glsl"

layout(local_size_x = MF_GROUP_SIZE) in;

layout(std430, binding = MF_LOOKUP_SSBO) readonly buffer LookupBlock {
    uint entries[];
} lookup;

layout(std430, binding = MF_NODES_SSBO) readonly buffer NodeBlock {
    uint codes[];
} nodes;

layout(std430, binding = MF_SEEN_SSBO) readonly buffer SeenBlock {
    uint words[]; // seen_words per node, bit k of word k / 32: view k saw surface in the node
} seen;

layout(std430, binding = MF_SELECTED_SSBO) writeonly buffer SelectedBlock {
    Facet items[];
} selected;

layout(std430, binding = MF_GROUPS_SSBO) writeonly buffer GroupBlock {
    uvec2 counts[];
} groups;

uniform uint level_first[MF_MAX_LEVELS + 1]; // index in `nodes` of each level's first code (by level)
uniform uint work_total;
uniform uint instance_count;
uniform uint groups_x;          // work groups per row of the dispatch
uniform float max_error_pixels; // the LOD bound
uniform float tan_delta;        // tan of the layout's largest angle to the nearest view
uniform float screen_pixels;    // pixels per world unit (at distance 1 for perspective cameras)
uniform vec4 frustum[6];        // world-space planes, inside where dot(xyz, p) + w >= 0
uniform int forced_level;       // >= 0: every node of that level, no cut
uniform int select_mode;        // MF_SELECT_*
uniform int blend_count;        // 1..MF_MAX_BLEND
uniform int primitive;          // MF_PRIMITIVE_*
uniform float point_pixels;     // auto: facets narrower than this many pixels are points
uniform uint lookup_list;       // index in `lookup` of the per-draw list (count, then views)
uniform uint seen_words;        // words per node in `seen`; 0: no culling of unseen nodes
uniform int clip_rule;          // MF_CLIP_*: far facets of the ray clip walk one view
uniform int prefer_seen;        // 1: blend the nearest views that saw surface in the node (step 4)
uniform float far_error_pixels; // the ray clip walks one view under this eq. 2 error (renderer.cpp)

shared uint s_ranks[MF_GROUP_SIZE];

// the instance whose work range holds w (the last one starting at or before it)
uint find_instance(uint w)
{
    uint lo = 0u, hi = instance_count - 1u;
    while (lo < hi) {
        uint mid = (lo + hi + 1u) / 2u;
        if (lods.items[mid].work.x <= w) lo = mid;
        else hi = mid - 1u;
    }
    return lo;
}

// eq. 2 in pixels for a node, at the nearest point of its bounding sphere (lod.cpp)
float node_error(InstanceLod lod, vec3 center, int level)
{
    float scale = lod.eye_object.w, w = voxel_size(level) * scale;
    float pixels = screen_pixels;
    if (lod.forward_object.w < 0.5) {
        float d = length(lod.eye_object.xyz - center) * scale - 0.8660254 * w;
        pixels /= max(d, 1e-6 * grid_size * scale);
    }
    return w * tan_delta * pixels;
}

int lookup_cell(vec3 d)
{
    vec3 a = abs(d);
    int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    int face = 2 * major + (d[major] < 0.0 ? 1 : 0);
    vec2 st = vec2(d[(major + 1) % 3], d[(major + 2) % 3]) / a[major];
    ivec2 cell = clamp(ivec2(floor((st * 0.5 + 0.5) * float(MF_LOOKUP_SIDE))), ivec2(0), ivec2(MF_LOOKUP_SIDE - 1));
    return (face * MF_LOOKUP_SIDE + cell.y) * MF_LOOKUP_SIDE + cell.x;
}

bool node_seen_by(uint index, uint view)
{
    return (seen.words[index * seen_words + view / 32u] & (1u << (view % 32u))) != 0u;
}

// The blend_count + 1 nearest views to e among `count` candidates from lookup.entries[first], by
// cosine (ties to the lower index: candidates ascend); with `only_seen`, views that saw no surface
// in node `index` are skipped.
void nearest_views(vec3 e, uint first, uint count, bool only_seen, uint index, inout int best[MF_MAX_BLEND + 1],
                  inout float cosines[MF_MAX_BLEND + 1])
{
    for (uint i = 0u; i < count; ++i) {
        int view = int(lookup.entries[first + i]);
        if (only_seen && !node_seen_by(index, uint(view))) continue;
        float c = dot(views.items[view].direction.xyz, e);
        for (int slot = 0; slot <= blend_count; ++slot) {
            if (c > cosines[slot]) {
                for (int m = blend_count; m > slot; --m) {
                    cosines[m] = cosines[m - 1];
                    best[m] = best[m - 1];
                }
                cosines[slot] = c;
                best[slot] = view;
                break;
            }
        }
    }
}

// step 4: the blend_count nearest views by cosine and weights cos_k - cos_(blend_count + 1),
// normalised; the nearest alone gets 1. With the ray clip's seen bits (seen_views > 0 and
// prefer_seen), the nearest views that saw surface in node `index`: a view that saw none there
// can only abstain or miss (its walk passes under nearer leaves), so in a crown a leaf the four
// nearest views all had hidden behind others was a hole, though a view a little farther saw it.
// The candidates' nearest views are found first; when one of the blend_count + 1 nearest (the
// blend and its floor) did not see the node, the nearest seen views are searched again among every
// view in lookup mode (the per-draw list holds them all: the cell's candidates are exact only for
// the 5 nearest views), else among the per-draw list, so lookup and "all" still pick the same.
void select_views(vec3 e, uint index, out uvec4 ids, out vec4 weights)
{
    int best[MF_MAX_BLEND + 1] = int[](-1, -1, -1, -1, -1);
    float cosines[MF_MAX_BLEND + 1] = float[](-2.0, -2.0, -2.0, -2.0, -2.0);
    uint first, count;
    if (select_mode == MF_SELECT_LOOKUP) {
        uint cell = lookup.entries[lookup_cell(e)];
        first = cell >> 8;
        count = cell & 255u;
    } else {
        first = lookup_list + 1u;
        count = lookup.entries[lookup_list];
    }
    nearest_views(e, first, count, false, index, best, cosines);
    bool all_seen = true;
    if (seen_words > 0u && prefer_seen != 0)
        for (int k = 0; k <= blend_count; ++k) all_seen = all_seen && (best[k] < 0 || node_seen_by(index, uint(best[k])));
    if (!all_seen) {
        for (int k = 0; k <= MF_MAX_BLEND; ++k) {
            best[k] = -1;
            cosines[k] = -2.0;
        }
        if (select_mode == MF_SELECT_LOOKUP) {
            first = lookup_list + 1u;
            count = lookup.entries[lookup_list];
        }
        nearest_views(e, first, count, true, index, best, cosines);
    }
    float floor_cosine = best[blend_count] >= 0 ? cosines[blend_count] : -1.0;
    weights = vec4(0.0);
    ids = uvec4(0u);
    float sum = 0.0;
    for (int k = 0; k < blend_count; ++k) {
        ids[k] = uint(max(best[k], 0));
        weights[k] = best[k] >= 0 ? max(cosines[k] - floor_cosine, 0.0) : 0.0;
        sum += weights[k];
    }
    if (blend_count == 1 || sum <= 0.0) weights = vec4(1.0, 0.0, 0.0, 0.0);
    else weights /= sum;
}

uint select_facet(uint w, out Facet f)
{
    f = Facet(uvec4(0u), uvec4(0u));
    // step 1
    uint i = find_instance(w);
    InstanceLod lod = lods.items[i];
    int first = int(lod.work.z), finest = int(lod.work.w);
    uint index = level_first[first] + (w - lod.work.x);
    int level = first;
    while (level < finest && index >= level_first[level + 1]) ++level;
    uint code = nodes.codes[index];
    vec3 c = voxel_center(code, level);
    float scale = lod.eye_object.w, w_world = voxel_size(level) * scale;
    // step 2: the facet reaches sqrt(3/2) W from the centre (a corner of its square)
    vec3 c_world = (instances.world_from_object[i] * vec4(c, 1.0)).xyz;
    for (int k = 0; k < 6; ++k)
        if (dot(frustum[k].xyz, c_world) + frustum[k].w < -1.2248 * w_world) return MF_KIND_NONE;
    // step 3
    if (forced_level < 0) {
        bool fine = level == finest || node_error(lod, c, level) <= max_error_pixels;
        bool parent_fine = level > first && node_error(lod, voxel_center(code >> 3, level - 1), level - 1) <= max_error_pixels;
        if (!fine || parent_fine) return MF_KIND_NONE;
    }
    // step 4
    uvec4 ids;
    vec4 weights;
    select_views(to_eye_object(lod, c), index, ids, weights);
    // a facet whose eq. 2 error is under a pixel needs no blend: its nearest view alone is walked
    // (far facets, most of a crowd). Projecting that view instead (eq. 1) was cheaper still but
    // brought back eq. 1's slab holes: Luv 3.2 against 0.6 at a fixed 128^3 (docs/failure_cases.md)
    bool far = clip_rule == MF_CLIP_RAY && node_error(lod, c, level) <= far_error_pixels;
    if (far) weights = vec4(1.0, 0.0, 0.0, 0.0);
    // step 4b (--clip ray): a node none of its views saw surface in draws nothing (every walk misses
    // or is hidden), so it is not drawn at all: the far side of closed surfaces, the inside of a crown
    if (seen_words > 0u) {
        bool any_seen = false;
        for (int k = 0; k < blend_count; ++k) {
            uint view = ids[k];
            any_seen = any_seen || (weights[k] > 0.0 && node_seen_by(index, view));
        }
        if (!any_seen) return MF_KIND_NONE;
    }
    f.a = uvec4(i | (uint(level) << 24), code, ids.x | (ids.y << 16), ids.z | (ids.w << 16));
    // b.w: the node, whose seen bits the fragment stage reads for its fallback views (facets.frag)
    f.b = uvec4(packUnorm2x16(weights.xy), packUnorm2x16(weights.zw), 0u, index);
    // step 5
    if (primitive == MF_PRIMITIVE_POINTS) return MF_KIND_POINT;
    if (primitive == MF_PRIMITIVE_QUADS) return MF_KIND_QUAD;
    float pixels = screen_pixels;
    if (lod.forward_object.w < 0.5) pixels /= max(distance(frame.eye_world.xyz, c_world), 1e-6 * grid_size * scale);
    return 1.7320508 * w_world * pixels < point_pixels ? MF_KIND_POINT : MF_KIND_QUAD;
}

void main()
{
    uint lane = gl_LocalInvocationID.x;
    uint group = gl_WorkGroupID.y * groups_x + gl_WorkGroupID.x;
    uint w = group * uint(MF_GROUP_SIZE) + lane;
    Facet f = Facet(uvec4(0u), uvec4(0u));
    uint kind = w < work_total ? select_facet(w, f) : MF_KIND_NONE;

    // step 6: inclusive scan of (quad, point << 16) over the group
    uint flag = kind == MF_KIND_QUAD ? 1u : (kind == MF_KIND_POINT ? 0x10000u : 0u);
    s_ranks[lane] = flag;
    barrier();
    for (uint offset = 1u; offset < uint(MF_GROUP_SIZE); offset <<= 1u) {
        uint add = lane >= offset ? s_ranks[lane - offset] : 0u;
        barrier();
        s_ranks[lane] += add;
        barrier();
    }
    if (w < work_total) {
        f.a.x |= kind << 28;
        f.b.z = s_ranks[lane] - flag;
        selected.items[w] = f;
    }
    if (lane == uint(MF_GROUP_SIZE) - 1u) groups.counts[group] = uvec2(s_ranks[lane] & 0xffffu, s_ranks[lane] >> 16);
}
