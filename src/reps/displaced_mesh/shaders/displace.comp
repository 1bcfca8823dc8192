#version 450 core
// After the last bisection pass: the final list's vertices displaced once per frame (three per
// record, displaced_position as draw.vert did), for draw.vert to read. A departure from the paper's
// vertex-stage displacement (§3.3): the cut-out pre-pass draws the list twice, and llvmpipe runs
// vertex shaders on one thread but compute on every core (a 100,000-card tree: docs/RESULTS.md).
// Vertices two triangles share are computed from the same integers by this one program, so they
// stay bit-identical.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

layout(local_size_x = DM_GROUP_SIZE) in;

layout(std430, binding = DM_FINAL_SSBO) readonly buffer FinalBlock { uint final_list[]; };
layout(std430, binding = DM_DISPLACED_SSBO) writeonly buffer DisplacedBlock { vec4 displaced_world[]; };

uniform uint vertex_count; // three per final record

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= vertex_count) return;
    uint base = (v / 3u) * DM_RECORD_UINTS, corner = v % 3u;
    uint face = final_list[base], instance = final_list[base + 1u];
    uint q1 = final_list[base + 2u + 2u * corner], q2 = final_list[base + 3u + 2u * corner];
    mat4 world_from_object = instances.world_from_object[instance];
    vec3 direction;
    vec3 p = displaced_position(face, q1, q2, frame.view_from_world * world_from_object, direction);
    displaced_world[v] = world_from_object * vec4(p, 1.0);
}
