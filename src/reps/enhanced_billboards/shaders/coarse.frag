#version 450 core
// Hole filling with the coarse mesh (Vichitvejpaisal 2005 §3.4): it fills the pixels the billboards
// leave empty, as the paper draws it, but never where the nearest billboard hit is a front one,
// whatever the depths (the coarse mesh lies within a texel of the surface, in front of it as often
// as behind). fill_near_misses_only (--coarse-fill near-misses) restricts it further to pixels
// where a billboard ray came within a texel of a surface and missed or saw the back of a sheet
// (march.frag marks them): the outline cannot grow then, but surfaces no billboard captured (seen
// from where the bake's directions saw them edge-on) stay holes, since no ray comes near them.
#include "gpu/shaders/common/frame.glsl"
#include "gpu/shaders/common/fade.glsl"
#include "gpu/shaders/common/lighting.glsl"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

in vec3 v_position_world;
in vec3 v_normal_world;
in vec4 v_color;
flat in float v_handedness;

layout(binding = IMAGE_PIXEL_FLAGS, r32ui) uniform coherent uimage2D pixel_flags;
layout(binding = IMAGE_PIXEL_DEPTH, r32ui) uniform coherent uimage2D pixel_depth;
uniform int fill_near_misses_only;
uniform int debug_view;
// back faces culled here, not by GL (renderer.cpp: where an instance mirrors, which turns its
// faces' winding): a front face's winding on screen, turned by its mirror, is counter-clockwise
uniform int cull_in_shader;

layout(location = 0) out vec4 out_color;

void main()
{
    if (fade_discards()) discard; // a cross-fade's other renderer owns this pixel
    if (cull_in_shader != 0 && gl_FrontFacing == (v_handedness < 0.0)) discard;
    uint nearest = imageLoad(pixel_depth, ivec2(gl_FragCoord.xy)).r;
    bool front_hit = uintBitsToFloat(nearest & ~PIXEL_DEPTH_BACK) < 1.0 && (nearest & PIXEL_DEPTH_BACK) == 0u;
    if (front_hit) discard;
    // (the flags are written and cleared only for this rule: renderer.cpp marks_near_misses)
    if (fill_near_misses_only != 0 && (imageLoad(pixel_flags, ivec2(gl_FragCoord.xy)).r & PIXEL_NEAR_MISS) == 0u) discard;
    vec3 to_eye = frame.forward_world.w > 0.5 ? -frame.forward_world.xyz
                                              : normalize(frame.eye_world.xyz - v_position_world);
    vec3 color = shade_at(v_color.rgb, v_normal_world, to_eye, v_position_world);
    if (debug_view != DEBUG_VIEW_NONE) color = vec3(1.0, 0.0, 1.0); // coarse pixels stand out in debug views
    out_color = vec4(color, 1.0);
}
