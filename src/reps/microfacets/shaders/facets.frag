#version 450 core
// Microfacets, per fragment of a quad (Yamazaki et al. 2002 §3.3.2-3.3.3): each of the facet's
// views is projected onto the facet point (orthographic captures: the point's plane coordinates),
// clipped by eq. 1, and the passing views are blended by their weights. The seed keeps a pixel
// where its one view passes; with blending (A10 in docs/ARCHITECTURE.md) a pixel is covered where
// any view passes ("any") or where the passing views hold half the weight ("vote"). Colour and
// normal come from the same texels (and, for PBR packages, ORM and emission: issue #14); the stored
// normal is lit by the shared lighting (shade_pbr_at), and the depth
// written is the stored surface point's (the view with the largest weight), so stand-ins composite,
// cast and receive shadows like the mesh.
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "gpu/shaders/common/counters.glsl"
#include "reps/microfacets/shaders/microfacets.glsl"
#include "reps/microfacets/shaders/microfacets_sample.glsl"

in vec3 v_position;
flat in vec3 v_center;
in vec2 v_corner; // position on the facet's square, [-1, 1]^2
flat in uint v_instance;
flat in int v_level;
flat in uvec4 v_views;
flat in vec4 v_weights;
flat in uint v_node; // the facet's node, in the order of `seen` (select.comp)

layout(std430, binding = MF_SEEN_SSBO) readonly buffer SeenBlock {
    uint words[]; // seen_words per node, bit k of word k / 32: view k saw surface in the node (visibility.h)
} seen;

uniform int debug_view;    // DEBUG_VIEW_*
uniform int counting;      // 1: add this fragment and its texture reads to the counters
uniform int coverage_rule; // MF_COVERAGE_*
uniform int min_level, max_level;
uniform uint seen_words;    // words per node in `seen`; 0: no seen bits (clips other than the ray's)
uniform int fallback_views; // views walked, nearest first, where every blended view abstained
uniform int filter_color;   // 1: the ray clip filters colour over the pixel's footprint (renderer.cpp)

// Whether view `view` saw surface in the facet's node.
bool seen_here(uint view) { return (seen.words[v_node * seen_words + view / 32u] & (1u << (view % 32u))) != 0u; }

layout(location = 0) out vec4 out_color;
layout(depth_greater) out float gl_FragDepth;

#define MF_MAX_FALLBACK 8

// The fallback_views (at most MF_MAX_FALLBACK) nearest views to `to_eye` that saw surface in the
// facet's node and are not among its blended views, nearest first (ties to the lower index): one
// pass over the views, an insertion into a short sorted list (select.comp nearest_views' rule).
int fallback_list(vec3 to_eye, out int list[MF_MAX_FALLBACK])
{
    float cosines[MF_MAX_FALLBACK];
    int count = 0, wanted = min(fallback_views, MF_MAX_FALLBACK);
    if (wanted <= 0) return 0;
    for (int v = 0; v < views.items.length(); ++v) {
        if (!seen_here(uint(v))) continue;
        bool blended = false;
        for (int k = 0; k < MF_MAX_BLEND; ++k) blended = blended || (v_weights[k] > 0.0 && int(v_views[k]) == v);
        float c = dot(views.items[v].direction.xyz, to_eye);
        if (blended || c <= 0.05 || (count == wanted && c <= cosines[wanted - 1])) continue; // 0.05: walk_view's edge-on limit
        int slot = min(count, wanted - 1);
        while (slot > 0 && c > cosines[slot - 1]) {
            cosines[slot] = cosines[slot - 1];
            list[slot] = list[slot - 1];
            --slot;
        }
        cosines[slot] = c;
        list[slot] = v;
        count = min(count + 1, wanted);
    }
    return count;
}

void main()
{
    vec3 p = v_position;
    // The ray clip's colour is filtered over the pixel's footprint where the footprint holds one
    // surface (walk_view: the truth filters a face's texture, never across faces; averaging leaves
    // with their neighbours measured worse, shrub thesis Luv 7.22 -> 7.95, 9.8 -> 11.6 at 512^2
    // before). One level under the footprint's: a capture texel already holds the texture filtered
    // over itself. Generated tree, 1536^2 captures, foliage Luv d1 / d4 / d8: 3.25 / 5.72 / 7.12
    // point-sampled, 2.96 / 5.18 / 6.81 filtered (across surfaces too, at the footprint's level: 3.28
    // at d1; docs/RESULTS.md "Microfacets on foliage").
    // The seed and voxel clips read the texel hit, as the paper does.
    float color_level = clip_rule == MF_CLIP_RAY && filter_color != 0 ? color_lod(max(length(dFdx(p)), length(dFdy(p)))) - 1.0 : 0.0;
    float edge = max(abs(v_corner.x), abs(v_corner.y)), edge_width = fwidth(edge);
    // a cross-fade's other renderer owns this pixel; dropped after the derivatives above, which
    // need the whole 2x2 quad alive
    if (fade_discards()) discard;
    float w = voxel_size(v_level);

    vec3 color = vec3(0.0), normal = vec3(0.0), surface = p, orm = vec3(0.0), emission = vec3(0.0);
    float weight = 0.0, best = -1.0, abstained = 0.0;
    int best_view = int(v_views.x);
    InstanceLod lod = lods.items[v_instance];
    vec3 ray_origin = lod.forward_object.w > 0.5 ? p - lod.forward_object.xyz * (4.0 * mf_radius) : lod.eye_object.xyz;
    vec3 ray = lod.forward_object.w > 0.5 ? lod.forward_object.xyz : normalize(p - lod.eye_object.xyz);
    for (int k = 0; k < MF_MAX_BLEND; ++k) {
        float wk = v_weights[k];
        if (wk <= 0.0) continue;
        ViewSample s;
        if (clip_rule == MF_CLIP_RAY) {
            int outcome = walk_view(views.items[v_views[k]], ray_origin, ray, v_center, w, color_level, s);
            if (outcome == RAY_HIDDEN) abstained += wk;
        } else {
            s = sample_view(views.items[v_views[k]], p, v_center, w, color_level);
        }
        if (!s.passed) continue;
        color += wk * s.color;
        normal += wk * facing(s.normal, -ray);
        orm += wk * s.orm;
        emission += wk * s.emission;
        weight += wk;
        if (wk > best) {
            best = wk;
            surface = s.surface;
            best_view = int(v_views[k]);
        }
    }
    // Beyond the paper (issues #14, #16): where every blended view abstained (the pixel's ray passed
    // under surface each of them saw nearer their camera: a leaf or branch inside a crown that the
    // nearest views saw hidden behind others), the views that saw surface in the node are walked
    // nearest first, and the first that can tell decides: its hit is drawn, its miss leaves the pixel
    // empty. The blend's views were picked per node, not per pixel, so a view a little farther off
    // often saw what this pixel's ray meets; eq. 1's clip alone leaves a hole there.
    if (clip_rule == MF_CLIP_RAY && weight <= 0.0 && abstained >= 0.999 && seen_words > 0u) {
        int list[MF_MAX_FALLBACK];
        int count = fallback_list(-ray, list);
        for (int k = 0; k < count; ++k) {
            ViewSample s;
            if (walk_view(views.items[list[k]], ray_origin, ray, v_center, w, color_level, s) == RAY_HIDDEN) continue;
            if (s.passed) {
                color = s.color;
                normal = facing(s.normal, -ray);
                orm = s.orm;
                emission = s.emission;
                weight = 1.0;
                surface = s.surface;
                best_view = list[k];
            }
            break;
        }
    }
    if (counting != 0) count_fragment(g_fetches);
    // "vote": the views that hit hold at least half the weight of those that could tell
    bool covered = coverage_rule == MF_COVERAGE_VOTE ? weight > 0.0 && weight >= 0.5 * (1.0 - abstained) : weight > 0.0;
    // DEBUG_VIEW_PROXIES: every facet's outline (a line a pixel wide) over the picture
    if (debug_view == DEBUG_VIEW_PROXIES && edge > 1.0 - edge_width) {
        out_color = vec4(index_color(int(v_views.x)), 1.0);
        gl_FragDepth = gl_FragCoord.z;
        return;
    }
    if (!covered) discard;
    color /= weight;
    orm /= weight;
    emission /= weight;

    mat4 world_from_object = instances.world_from_object[v_instance];
    vec3 surface_world = (world_from_object * vec4(surface, 1.0)).xyz;
    vec3 normal_world = normalize(mat3(world_from_object) * normal);
    float depth = max(window_depth(surface_world), gl_FragCoord.z);
    gl_FragDepth = depth;
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz : normalize(frame.eye_world.xyz - surface_world);

    if (debug_view == DEBUG_VIEW_PARTS) out_color = vec4(index_color(best_view), 1.0);
    else if (debug_view == DEBUG_VIEW_DEPTH) out_color = vec4(vec3(1.0 - depth), 1.0);
    else if (debug_view == DEBUG_VIEW_NORMAL) out_color = vec4(normal_world * 0.5 + 0.5, 1.0);
    else if (debug_view == DEBUG_VIEW_FETCHES) out_color = vec4(fetches_color(g_fetches), 1.0);
    else if (debug_view == DEBUG_VIEW_LEVEL) out_color = vec4(heat(float(v_level - min_level) / float(max(max_level - min_level, 1))), 1.0);
    else out_color = vec4(shade_pbr_at(color, orm, srgb_to_linear(emission), normal_world, to_eye, surface_world), 1.0);
}
