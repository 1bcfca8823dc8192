#version 450 core
// After a bisection pass: each record goes to the final list, or its two halves to the next list,
// at the places the scan gave them (refine.cpp refine: (k, m, k + 2) and (m, k + 1, k + 2), m the
// midpoint of edge k).
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

void write_record(bool to_final, uint slot, uint face, uint instance, uvec2 a, uvec2 b, uvec2 c, uint depth)
{
    uint base = slot * DM_RECORD_UINTS;
    uint values[DM_RECORD_UINTS] = uint[DM_RECORD_UINTS](face, instance, a.x, a.y, b.x, b.y, c.x, c.y, depth);
    for (uint k = 0u; k < DM_RECORD_UINTS; ++k) {
        if (to_final) final_list[base + k] = values[k];
        else list_out[base + k] = values[k];
    }
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= current_count()) return;
    uvec4 s = scan[i];
    uvec2 group_base = groups[i / DM_GROUP_SIZE];
    uint face, instance, depth, q[6];
    load_record(i, face, instance, q, depth);
    uvec2 corner[3] = uvec2[3](uvec2(q[0], q[1]), uvec2(q[2], q[3]), uvec2(q[4], q[5]));
    bool overflow = state[DM_STATE_OVERFLOW] != 0u;
    if (overflow || s.x == DECIDE_FINAL) {
        uint slot = state[DM_STATE_FINAL_BASE] + (overflow ? i : group_base.y + s.z);
        if (slot < refine.capacities.y) write_record(true, slot, face, instance, corner[0], corner[1], corner[2], depth);
        return;
    }
    int k = int(s.x), k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    uvec2 a = corner[k], b = corner[k1];
    uvec2 m = (a >> 1u) + (b >> 1u) + (a & b & uvec2(1u));
    uint child = 2u * (group_base.x + s.y);
    write_record(false, child, face, instance, a, m, corner[k2], depth + 1u);
    write_record(false, child + 1u, face, instance, m, b, corner[k2], depth + 1u);
}
