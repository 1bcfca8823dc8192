// What every refinement pass shares (renderer.cpp runs them): the work lists, the per-element
// scan records, the per-group sums and the state block, and a deterministic workgroup scan. Lists
// are compacted with prefix sums (count, scan, scatter), never with atomic appends, so the order
// of the final triangles, and so the picture, is a function of the input alone.
// Include after displaced.glsl.

layout(local_size_x = DM_GROUP_SIZE) in;

layout(std430, binding = DM_LIST_IN_SSBO) buffer ListInBlock { uint list_in[]; };
layout(std430, binding = DM_LIST_OUT_SSBO) buffer ListOutBlock { uint list_out[]; };
layout(std430, binding = DM_FINAL_SSBO) buffer FinalBlock { uint final_list[]; };
// per element: x decision (DECIDE_* below), y / z exclusive prefix of the two counts in its group
layout(std430, binding = DM_SCAN_SSBO) buffer ScanBlock { uvec4 scan[]; };
// per group: its two sums, turned into their exclusive prefix by scan_groups.comp
layout(std430, binding = DM_GROUPS_SSBO) buffer GroupBlock { uvec2 groups[]; };
layout(std430, binding = DM_STATE_SSBO) buffer StateBlock { uint state[]; };

uniform uint parity; // pass p reads state slot p % 2 and writes (p + 1) % 2

#define DECIDE_FINAL 3u // 0, 1, 2: bisect that edge

shared uvec2 scan_shared[DM_GROUP_SIZE];

// The exclusive prefix of `value` over the workgroup (Hillis & Steele), and the group's sum.
// Every invocation of the group must call it.
uvec2 group_exclusive_scan(uvec2 value, out uvec2 total)
{
    uint i = gl_LocalInvocationID.x;
    scan_shared[i] = value;
    barrier();
    for (uint offset = 1u; offset < DM_GROUP_SIZE; offset <<= 1) {
        uvec2 add = i >= offset ? scan_shared[i - offset] : uvec2(0u);
        barrier();
        scan_shared[i] += add;
        barrier();
    }
    total = scan_shared[DM_GROUP_SIZE - 1];
    return scan_shared[i] - value;
}

uint current_count() { return state[DM_STATE_COUNT + parity]; }

void load_record(uint index, out uint face, out uint instance, out uint q[6], out uint depth)
{
    uint base = index * DM_RECORD_UINTS;
    face = list_in[base];
    instance = list_in[base + 1u];
    for (uint k = 0u; k < 6u; ++k) q[k] = list_in[base + 2u + k];
    depth = list_in[base + 8u];
}
