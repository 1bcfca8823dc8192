// Fractional coverage at a hit on an image-based stand-in's height field (issue #14), shared by the
// view atlas's corrected walk (atlas.frag hit_coverage) and the microfacets' walk
// (microfacets_sample.glsl hit_coverage). Captures of alpha-tested models store each texel's
// covered fraction (reps/common/coverage_capture.h); the truth's alpha test keeps a point where its
// bilinearly filtered texture alpha reaches the cutoff, so a stand-in keeps a crossing where the
// coverage of the hit's own surface, filtered bilinearly between the four texel centres around it,
// reaches 1/2. The cut-out's edge then falls inside a texel instead of on texel borders.
#ifndef STANDIN_COVERAGE_GLSL
#define STANDIN_COVERAGE_GLSL

#include "reps/common/shaders/height_field.glsl"

// How far a neighbour's stored height may lie from the hit's and still count as the hit's surface:
// the link rule's step for the neighbour's slopes along the two plane axes, and a texel.
float hf_coverage_tolerance(float slope_u, float slope_v, float texel, float quantum)
{
    return hf_link_tolerance(slope_u, slope_v, texel, quantum) + texel;
}

// The filtered coverage of the surface at height `height` (larger = nearer the capture camera) at a
// point whose position among the four texel centres around it is `f` ([0, 1]^2; corner k is
// (k & 1, k >> 1)). Per corner: `covered` (the texel holds a surface), its stored `heights`, the
// `tolerances` (hf_coverage_tolerance) and coverage `alphas` (in [0, 1]). A corner of the same
// surface adds its alpha; an empty corner, or one holding a surface behind, adds none (the front
// surface would have been stored there); one holding a nearer surface tells nothing about this one
// and is left out of the weights. 1 when every corner is left out.
// `presence`: the same filter with a corner holding a surface behind adding its alpha too: how sure
// the capture is that some surface lies along the ray here (one that passes beside this surface's
// edge meets the one behind), where the coverage says how sure it is of this surface.
float hf_filtered_coverage(vec2 f, float height, bvec4 covered, vec4 heights, vec4 tolerances, vec4 alphas, out float presence)
{
    float coverage = 0.0, weight_sum = 0.0;
    presence = 0.0;
    for (int k = 0; k < 4; ++k) {
        ivec2 corner = ivec2(k & 1, k >> 1);
        float w = (corner.x == 1 ? f.x : 1.0 - f.x) * (corner.y == 1 ? f.y : 1.0 - f.y);
        if (covered[k]) {
            if (heights[k] > height + tolerances[k]) continue;
            if (heights[k] >= height - tolerances[k]) coverage += w * alphas[k];
            presence += w * alphas[k];
        }
        weight_sum += w;
    }
    presence = weight_sum > 0.0 ? presence / weight_sum : 1.0;
    return weight_sum > 0.0 ? coverage / weight_sum : 1.0;
}

float hf_filtered_coverage(vec2 f, float height, bvec4 covered, vec4 heights, vec4 tolerances, vec4 alphas)
{
    float presence;
    return hf_filtered_coverage(f, height, covered, heights, tolerances, alphas, presence);
}

#endif
