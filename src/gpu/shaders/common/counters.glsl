// The counters block (gpu/counters.h) and the shared debug views' colours, for any fragment stage
// that counts and draws debug views. The including shader declares `uniform int counting;`.
#ifndef STANDIN_COUNTERS_GLSL
#define STANDIN_COUNTERS_GLSL

#include "gpu/shaders/common/bindings.h"
#include "gpu/shaders/common/debug_views.h"
#include "gpu/shaders/common/debug_colors.glsl"

layout(std430, binding = BINDING_COUNTERS_SSBO) buffer Counters {
    uint counters[];
};

// One fragment and its texture reads, counted when the renderer counts.
void count_fragment(uint fetches)
{
    atomicAdd(counters[COUNTER_FRAGMENTS], 1u);
    atomicAdd(counters[COUNTER_FETCHES], fetches);
}

// The colour of DEBUG_VIEW_FETCHES, one scale for every renderer.
vec3 fetches_color(uint fetches) { return heat(float(fetches) / FETCHES_HEAT_MAX); }

#endif
