#version 450 core
// Pass 0: one invocation per control face and instance. A face is kept when its prism (corners
// displaced by its lowest and highest elevation) meets the frustum and is not wholly back-facing
// (Bauman, Livny & El-Sana §3.4; face_visible in displaced.glsl). Writes the decision and the group scan.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint count = refine.counts.x * refine.counts.y;
    uint keep = 0u;
    if (i < count) {
        uint face = i % refine.counts.x, instance = i / refine.counts.x;
        keep = (refine.options.z == 0u || face_visible(face, view_from_object(instance))) ? 1u : 0u;
    }
    uvec2 total;
    uvec2 prefix = group_exclusive_scan(uvec2(keep, 0u), total);
    if (i < count) scan[i] = uvec4(keep, prefix, 0u);
    if (gl_LocalInvocationID.x == 0u) groups[gl_WorkGroupID.x] = total;
}
