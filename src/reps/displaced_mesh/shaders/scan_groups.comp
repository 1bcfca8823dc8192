#version 450 core
// One workgroup: the exclusive prefix of the group sums of the pass that just ran, then the
// bookkeeping for the next pass (its list size and dispatch arguments, in the other parity slot),
// the final list's size and the draw arguments. When the children would not fit the list, every
// record of this pass becomes final instead (counted as capped); finals past the final list's
// capacity are dropped (counted).
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

uniform uint after_cull; // 1: the pass was culling (roots), 0: a bisection pass

void main()
{
    uint n = after_cull != 0u ? refine.counts.x * refine.counts.y : current_count();
    uint group_count = (n + DM_GROUP_SIZE - 1u) / DM_GROUP_SIZE;
    uvec2 carry = uvec2(0u);
    for (uint start = 0u; start < group_count; start += DM_GROUP_SIZE) {
        uint g = start + gl_LocalInvocationID.x;
        uvec2 total;
        uvec2 prefix = group_exclusive_scan(g < group_count ? groups[g] : uvec2(0u), total);
        if (g < group_count) groups[g] = carry + prefix;
        carry += total;
        barrier();
    }
    if (gl_LocalInvocationID.x != 0u) return;
    uint next = 1u - parity;
    uint list_capacity = refine.capacities.x, final_capacity = refine.capacities.y;
    uint next_count;
    if (after_cull != 0u) {
        state[DM_STATE_VISIBLE] = carry.x;
        next_count = min(carry.x, list_capacity);
        state[DM_STATE_OVERFLOWED] += carry.x - next_count;
    } else {
        uint splits = carry.x, finals = carry.y;
        state[DM_STATE_PROCESSED] += n;
        uint overflow = 2u * splits > list_capacity ? 1u : 0u;
        if (overflow != 0u) {
            state[DM_STATE_OVERFLOWED] += splits;
            splits = 0u;
            finals = n;
        }
        uint base = state[DM_STATE_FINAL];
        uint final_count = min(base + finals, final_capacity);
        state[DM_STATE_DROPPED] += base + finals - final_count;
        state[DM_STATE_FINAL_BASE] = base;
        state[DM_STATE_FINAL] = final_count;
        state[DM_STATE_OVERFLOW] = overflow;
        next_count = 2u * splits;
    }
    state[DM_STATE_COUNT + next] = next_count;
    state[DM_STATE_DISPATCH + 3u * next] = (next_count + DM_GROUP_SIZE - 1u) / DM_GROUP_SIZE;
    state[DM_STATE_DISPATCH + 3u * next + 1u] = 1u;
    state[DM_STATE_DISPATCH + 3u * next + 2u] = 1u;
    state[DM_STATE_DRAW] = 3u * state[DM_STATE_FINAL];
    state[DM_STATE_DRAW + 1u] = 1u;
    state[DM_STATE_DRAW + 2u] = 0u;
    state[DM_STATE_DRAW + 3u] = 0u;
}
