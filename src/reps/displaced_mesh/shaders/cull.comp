#version 450 core
// Pass 0: one invocation per control face and instance. A face is kept when its prism (corners
// displaced by its lowest and highest elevation) meets the frustum and is not wholly back-facing
// (Bauman, Livny & El-Sana §3.4; refine.cpp face_visible). Writes the decision and the group scan.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

#define PI 3.14159265358979

bool face_visible(uint face, mat4 view_object)
{
    FaceData d = faces[face];
    vec3 corners[6];
    for (int k = 0; k < 3; ++k) {
        vec3 p = control_position(d.corners[k]), n = control_normal(d.corners[k]);
        corners[k] = (view_object * vec4(p + d.range.x * n, 1.0)).xyz;
        corners[k + 3] = (view_object * vec4(p + d.range.y * n, 1.0)).xyz;
    }
    vec3 centre = vec3(0.0);
    for (int k = 0; k < 6; ++k) centre += corners[k] / 6.0;
    float radius = 0.0, longest = 0.0;
    for (int k = 0; k < 6; ++k) radius = max(radius, length(corners[k] - centre));
    for (int k = 0; k < 3; ++k) longest = max(longest, length(corners[k] - corners[(k + 1) % 3]));
    float scale = length(view_object[0].xyz);
    radius += 0.01 * longest + scale * max(abs(d.range.x), abs(d.range.y)) * d.range.w;

    // frustum (Gribb & Hartmann 2001) in view space
    mat4 m = refine.clip_from_view;
    for (int plane = 0; plane < 6; ++plane) {
        vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
        int axis = plane / 2;
        vec4 ra = vec4(m[0][axis], m[1][axis], m[2][axis], m[3][axis]);
        vec4 e = r3 + ((plane % 2) == 1 ? -1.0 : 1.0) * ra;
        if (dot(e.xyz, centre) + e.w < -radius * length(e.xyz)) return false;
    }

    // back faces
    if (d.range.z >= 0.5 * PI) return true;
    vec3 p0 = (view_object * vec4(control_position(d.corners.x), 1.0)).xyz;
    vec3 p1 = (view_object * vec4(control_position(d.corners.y), 1.0)).xyz;
    vec3 p2 = (view_object * vec4(control_position(d.corners.z), 1.0)).xyz;
    vec3 axis = cross(p1 - p0, p2 - p0);
    if (!(length(axis) > 0.0)) return true;
    axis = normalize(axis);
    float sin_cone = sin(d.range.z);
    if (refine.view_terms.w > 0.5) return dot(vec3(0.0, 0.0, -1.0), axis) < sin_cone;
    float distance_c = length(centre);
    if (distance_c <= radius) return true;
    return dot(centre / distance_c, axis) < sin_cone + radius / distance_c;
}

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
