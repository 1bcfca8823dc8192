#version 450 core
// Tessellation baseline (the hardware path the paper's era lacked): each control face is one
// patch; an edge's level is a power of two from the edge alone (its projected length times its
// weight over tau, at most the pattern's segments), so both faces of an edge agree and the
// tessellator leaves no crack; the inside takes the largest. Faces culled on their prism get 0.
// With the error criterion the level is the square root of the edge's chord error over tau (the
// error falls with the square of the segment count), without the bisection path's view-angle and
// outline factors: a patch's levels cannot vary along an edge.
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"

layout(vertices = 3) out;

flat in uint vc_face[];
flat in uint vc_instance[];
flat out uint tc_face[];
flat out uint tc_instance[];

float edge_level(uint face, int edge, mat4 view_object)
{
    uvec3 corner = faces[face].corners.xyz;
    uint a = corner[edge], b = corner[(edge + 1) % 3];
    vec3 lo = (view_object * vec4(control_position(min(a, b)), 1.0)).xyz;
    vec3 hi = (view_object * vec4(control_position(max(a, b)), 1.0)).xyz;
    float projected = projected_length(lo, hi), segments;
    if (refine.options.x == DM_CRITERION_ERROR) {
        // the chord error falls with the square of the segment count
        float scale = length(view_object[0].xyz);
        float error_px = faces[face].curvature[edge] * length(hi - lo) / scale * DM_CHORD_ERROR * projected;
        segments = sqrt(error_px / refine.view_terms.x);
    } else {
        float weight = refine.options.x == DM_CRITERION_LENGTH ? 1.0 : faces[face].weights[edge];
        segments = projected * weight / refine.view_terms.x;
    }
    float level = exp2(ceil(log2(max(segments, 1.0))));
    return min(level, float(refine.counts.z));
}

void main()
{
    tc_face[gl_InvocationID] = vc_face[gl_InvocationID];
    tc_instance[gl_InvocationID] = vc_instance[gl_InvocationID];
    if (gl_InvocationID != 0) return;
    uint face = vc_face[0];
    mat4 view_object = view_from_object(vc_instance[0]);
    if (refine.options.z != 0u && !face_visible(face, view_object)) {
        gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
    // outer[i] is the edge opposite patch vertex i: face edge 1 (c1 -> c2), 2 (c2 -> c0), 0 (c0 -> c1)
    float e0 = edge_level(face, 0, view_object), e1 = edge_level(face, 1, view_object), e2 = edge_level(face, 2, view_object);
    gl_TessLevelOuter[0] = e1;
    gl_TessLevelOuter[1] = e2;
    gl_TessLevelOuter[2] = e0;
    gl_TessLevelInner[0] = max(e0, max(e1, e2));
}
