#version 450 core
// Microfacets: every kept facet to its place in the quad or point list (group offset + rank in the
// group), so both lists hold the facets in work order.
#include "reps/microfacets/shaders/microfacets.glsl"

layout(local_size_x = MF_GROUP_SIZE) in;

layout(std430, binding = MF_SELECTED_SSBO) readonly buffer SelectedBlock {
    Facet items[];
} selected;

layout(std430, binding = MF_GROUPS_SSBO) readonly buffer GroupBlock {
    uvec2 counts[];
} groups;

layout(std430, binding = MF_QUADS_SSBO) writeonly buffer QuadBlock {
    Facet items[];
} quads;

layout(std430, binding = MF_POINTS_SSBO) writeonly buffer PointBlock {
    Facet items[];
} points;

uniform uint work_total;
uniform uint groups_x;
uniform uint group_count;
uniform uint capacity; // facets each list can hold

void main()
{
    uint group = gl_WorkGroupID.y * groups_x + gl_WorkGroupID.x;
    uint w = group * uint(MF_GROUP_SIZE) + gl_LocalInvocationID.x;
    if (w >= work_total) return;
    Facet f = selected.items[w];
    uint kind = facet_kind(f);
    if (kind == MF_KIND_NONE) return;
    uvec2 offset = groups.counts[group_count + group];
    uint rank = kind == MF_KIND_QUAD ? (f.b.z & 0xffffu) : (f.b.z >> 16);
    f.b.z = 0u;
    if (kind == MF_KIND_QUAD) {
        if (offset.x + rank < capacity) quads.items[offset.x + rank] = f;
    } else {
        if (offset.y + rank < capacity) points.items[offset.y + rank] = f;
    }
}
