#version 450 core
// After culling: every kept face of every instance becomes a root record of the first list, in
// (instance, face) order.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint count = refine.counts.x * refine.counts.y;
    if (i >= count) return;
    uvec4 s = scan[i];
    if (s.x == 0u) return;
    uint slot = groups[i / DM_GROUP_SIZE].x + s.y;
    if (slot >= refine.capacities.x) return; // the list is full: scan_groups counted it as capped
    uint base = slot * DM_RECORD_UINTS;
    list_out[base] = i % refine.counts.x;
    list_out[base + 1u] = i / refine.counts.x;
    // corners 0, 1, 2 of the face: (q1, q2) = (0, 0), (one, 0), (0, one)
    list_out[base + 2u] = 0u, list_out[base + 3u] = 0u;
    list_out[base + 4u] = BARY_ONE, list_out[base + 5u] = 0u;
    list_out[base + 6u] = 0u, list_out[base + 7u] = BARY_ONE;
    list_out[base + 8u] = 0u;
}
