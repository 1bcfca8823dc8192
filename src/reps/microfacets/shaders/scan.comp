#version 450 core
// Microfacets: where each work group's kept quads and points go (an exclusive scan over the groups'
// counts, one work group), and how many there are (the indirect draws' counts).
#include "reps/microfacets/shaders/microfacets_layout.glsl"

layout(local_size_x = MF_SCAN_SIZE) in;

// counts[g] for the groups of select.comp, then counts[group_count + g]: their offsets
layout(std430, binding = MF_GROUPS_SSBO) buffer GroupBlock {
    uvec2 counts[];
} groups;

// {count, instanceCount, first, baseInstance} for the quads (vertices_per_facet x quads, 1, 0, 0:
// triangles, not instances, which llvmpipe draws one at a time) and the points (points, 1, 0, 0)
layout(std430, binding = MF_COMMANDS_SSBO) buffer CommandBlock {
    uint commands[8];
};

uniform uint group_count;
uniform uint vertices_per_facet; // 6 (a square: two triangles) or 18 (a box's three faces)

shared uvec2 s_sums[MF_SCAN_SIZE];

void main()
{
    uint lane = gl_LocalInvocationID.x;
    uint per_lane = (group_count + uint(MF_SCAN_SIZE) - 1u) / uint(MF_SCAN_SIZE);
    uint begin = min(lane * per_lane, group_count), end = min(begin + per_lane, group_count);
    uvec2 sum = uvec2(0u);
    for (uint g = begin; g < end; ++g) sum += groups.counts[g];
    s_sums[lane] = sum;
    barrier();
    for (uint offset = 1u; offset < uint(MF_SCAN_SIZE); offset <<= 1u) {
        uvec2 add = lane >= offset ? s_sums[lane - offset] : uvec2(0u);
        barrier();
        s_sums[lane] += add;
        barrier();
    }
    uvec2 running = s_sums[lane] - sum;
    for (uint g = begin; g < end; ++g) {
        uvec2 count = groups.counts[g];
        groups.counts[group_count + g] = running;
        running += count;
    }
    if (lane == uint(MF_SCAN_SIZE) - 1u) {
        commands[0] = vertices_per_facet * s_sums[lane].x;
        commands[4] = s_sums[lane].y; // points: vertices
    }
}
