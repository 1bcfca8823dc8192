#version 450 core
// One bisection pass (Bauman, Livny & El-Sana §3.3; refine.cpp decide): each record of the current
// list is tested; it bisects the longest of its edges whose own test passes (|e_p| * w_e > tau and
// longer than one pattern grid unit), else it is final: under the error criterion the longest in
// pattern units with the projected length breaking ties (refine.cpp), under the paper's rules the
// longest on screen. Writes the decision and the group
// scan of (splits, finals).
#include "gpu/shaders/common/frame.glsl"
#include "reps/displaced_mesh/shaders/displaced.glsl"
#include "reps/displaced_mesh/shaders/passes.glsl"

uniform uint last_pass; // 1: nothing splits any more (counted as capped)

// A segment's squared length in pattern grid units (the pattern's equilateral metric)
float pattern_units2(uvec2 a, uvec2 b)
{
    float d1 = float(int(a.x - b.x)) / float(BARY_ONE);
    float d2 = float(int(a.y - b.y)) / float(BARY_ONE);
    float d0 = -(d1 + d2);
    float n = float(refine.counts.z);
    precise float units2 = 0.5 * (d0 * d0 + d1 * d1 + d2 * d2) * n * n;
    return units2;
}

// The face edge a segment lies on, 3 inside (refine.cpp segment_edge).
int segment_edge(uvec2 a, uvec2 b)
{
    if (a.y == 0u && b.y == 0u) return 0;
    if (a.x + a.y == BARY_ONE && b.x + b.y == BARY_ONE) return 1;
    if (a.x == 0u && b.x == 0u) return 2;
    return 3;
}

// refine.cpp error_weight: curvature x length x chord factor, times how much of a deviation along
// the normal shows on screen (the sine of the normal's angle to the view direction, at least
// DM_MIN_VISIBLE; the outline weight times near the outline)
float error_weight(float curvature, vec3 a, vec3 b, vec3 na, vec3 nb, float scale)
{
    vec3 normal = unit_direction(na + nb);
    vec3 to_eye = refine.view_terms.w > 0.5 ? vec3(0.0, 0.0, 1.0) : unit_direction(-(a + b));
    float facing = dot(normal, to_eye);
    float visible = max(sqrt(max(1.0 - facing * facing, 0.0)), DM_MIN_VISIBLE);
    if (abs(facing) < DM_SILHOUETTE_COS) visible *= refine.error_terms.z;
    return curvature * length(a - b) / scale * DM_CHORD_ERROR * visible;
}

uint decide(uint face, uint q[6], mat4 view_object)
{
    uvec2 corner[3] = uvec2[3](uvec2(q[0], q[1]), uvec2(q[2], q[3]), uvec2(q[4], q[5]));
    uvec3 c = faces[face].corners.xyz;
    vec4 weights = faces[face].weights, curvature = faces[face].curvature;
    float scale = length(view_object[0].xyz);
    vec3 p[3], normal[3];
    for (int k = 0; k < 3; ++k) {
        FacePoint point = face_point(c, corner[k].x, corner[k].y);
        p[k] = (view_object * vec4(point.position, 1.0)).xyz;
        normal[k] = unit_direction(mat3(view_object) * point.normal);
    }
    float len[3], w[3], units2[3];
    bool can_split[3];
    for (int k = 0; k < 3; ++k) {
        len[k] = projected_length(p[k], p[(k + 1) % 3]);
        int edge = segment_edge(corner[k], corner[(k + 1) % 3]);
        if (refine.options.x == DM_CRITERION_LENGTH) w[k] = 1.0;
        else if (refine.options.x == DM_CRITERION_ERROR) w[k] = error_weight(curvature[edge], p[k], p[(k + 1) % 3], normal[k], normal[(k + 1) % 3], scale);
        else w[k] = weights[edge];
        units2[k] = pattern_units2(corner[k], corner[(k + 1) % 3]);
        can_split[k] = units2[k] > 1.001 * 1.001; // refine.cpp k_segment_min_units
    }
    float tau = refine.view_terms.x;
    int best = -1;
    if (refine.options.x == DM_CRITERION_SEED) {
        for (int k = 0; k < 3; ++k)
            if (can_split[k] && (best < 0 || len[k] > len[best])) best = k;
        if (best >= 0 && !(len[best] * w[best] > tau)) best = -1;
    } else {
        // (the error criterion: longest in pattern units, the projected length breaking ties; the
        // paper's weighted and length rules: longest on screen)
        const bool by_pattern = refine.options.x == DM_CRITERION_ERROR;
        float units[3];
        for (int k = 0; k < 3; ++k) units[k] = by_pattern ? units2[k] : 0.0;
        for (int k = 0; k < 3; ++k)
            if (can_split[k] && len[k] * w[k] > tau && (best < 0 || units[k] > units[best] * 1.0001 || (!(units[best] > units[k] * 1.0001) && len[k] > len[best]))) best = k;
    }
    return best < 0 ? DECIDE_FINAL : uint(best);
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint decision = DECIDE_FINAL;
    uvec2 value = uvec2(0u);
    if (i < current_count()) {
        uint face, instance, depth, q[6];
        load_record(i, face, instance, q, depth);
        decision = decide(face, q, view_from_object(instance));
        if (last_pass != 0u && decision != DECIDE_FINAL) {
            atomicAdd(state[DM_STATE_CAPPED], 1u); // a sum: the same whatever the order
            decision = DECIDE_FINAL;
        }
        value = decision == DECIDE_FINAL ? uvec2(0u, 1u) : uvec2(1u, 0u);
    }
    uvec2 total;
    uvec2 prefix = group_exclusive_scan(value, total);
    if (i < current_count()) scan[i] = uvec4(decision, prefix, 0u);
    if (gl_LocalInvocationID.x == 0u) groups[gl_WorkGroupID.x] = total;
}
