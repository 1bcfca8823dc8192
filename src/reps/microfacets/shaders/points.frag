#version 450 core
// Microfacets as points: the facet's one colour, lit from its stored normal, at its stored
// surface's depth (points.vert).
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "gpu/shaders/common/counters.glsl"
#include "reps/microfacets/shaders/microfacets_layout.glsl"

flat in vec3 v_color;
flat in vec3 v_orm;
flat in vec3 v_emission;
flat in vec3 v_normal_world;
flat in vec3 v_surface_world;
flat in int v_view;
flat in int v_level;
flat in uint v_fetches;

uniform int debug_view;
uniform int counting;
uniform int min_level, max_level;

layout(location = 0) out vec4 out_color;
layout(depth_greater) out float gl_FragDepth;

void main()
{
    if (fade_discards()) discard; // a cross-fade's other renderer owns this pixel
    if (counting != 0) count_fragment(v_fetches);
    float depth = max(window_depth(v_surface_world), gl_FragCoord.z);
    gl_FragDepth = depth;
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz : normalize(frame.eye_world.xyz - v_surface_world);
    if (debug_view == DEBUG_VIEW_PARTS || debug_view == DEBUG_VIEW_PROXIES) out_color = vec4(index_color(v_view), 1.0);
    else if (debug_view == DEBUG_VIEW_DEPTH) out_color = vec4(vec3(1.0 - depth), 1.0);
    else if (debug_view == DEBUG_VIEW_NORMAL) out_color = vec4(v_normal_world * 0.5 + 0.5, 1.0);
    else if (debug_view == DEBUG_VIEW_FETCHES) out_color = vec4(fetches_color(v_fetches), 1.0);
    else if (debug_view == DEBUG_VIEW_LEVEL) out_color = vec4(heat(float(v_level - min_level) / float(max(max_level - min_level, 1))), 1.0);
    else out_color = vec4(shade_pbr_at(v_color, v_orm, srgb_to_linear(v_emission), v_normal_world, to_eye, v_surface_world), 1.0);
}
