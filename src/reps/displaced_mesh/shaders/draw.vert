#version 450 core
// Draws the final list (Bauman, Livny & El-Sana §3.3, last step: "the GPU displaces each vertex
// according to its assigned elevation value"): three vertices per record, pulled by gl_VertexID,
// their positions displaced along the normalised interpolated normal by displace.comp just before
// (refine.cpp displaced_position), once for the pre-pass and the shading pass.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

layout(std430, binding = DM_FINAL_SSBO) readonly buffer FinalBlock { uint final_list[]; };
layout(std430, binding = DM_DISPLACED_SSBO) readonly buffer DisplacedBlock { vec4 displaced_world[]; };

out vec3 v_position_world;
out vec2 v_face_bary;     // weights of the face's corners 1 and 2: where to read the shading samples
flat out uint v_face;
flat out uint v_instance;
flat out uint v_depth;
// the cut-out pre-pass and the shading pass after it (renderer.cpp draw) run this shader in two
// programs, and the second tests depth for equality with the first's
invariant gl_Position;

void main()
{
    uint base = uint(gl_VertexID / 3) * DM_RECORD_UINTS;
    uint corner = uint(gl_VertexID % 3);
    uint face = final_list[base], instance = final_list[base + 1u];
    uint q1 = final_list[base + 2u + 2u * corner], q2 = final_list[base + 3u + 2u * corner];
    vec4 world = displaced_world[gl_VertexID];
    v_position_world = world.xyz;
    v_face_bary = vec2(float(q1), float(q2)) / float(BARY_ONE);
    v_face = face;
    v_instance = instance;
    v_depth = final_list[base + 8u];
    gl_Position = frame.clip_from_world * world;
}
