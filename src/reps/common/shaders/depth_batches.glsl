// Depth batches (reps/common/depth_batches.h), the fragment stage's side. A renderer compiles its
// program with DEPTH_BATCHES defined for the batches after the first: the depth test then runs
// before the shader (early_fragment_tests), against the depths of the batches already resolved,
// with depth and colour writes off; a fragment that is the nearest drawn so far at its pixel
// (the renderer's own record of the nearest depth, an atomic minimum) stores its colour and depth
// here, and the batch's resolve pass writes them through the ordinary depth test. Without the
// define, nothing here is compiled and the program writes gl_FragDepth as before.
#include "reps/common/shaders/depth_batches.h"

#ifdef DEPTH_BATCHES
layout(early_fragment_tests) in;
layout(binding = DEPTH_BATCH_COLOR_IMAGE, rgba32f) uniform writeonly image2D depth_batch_color;
layout(binding = DEPTH_BATCH_STAMP_IMAGE, r32ui) uniform writeonly uimage2D depth_batch_stamp;
layout(binding = DEPTH_BATCH_NEAREST_IMAGE, r32ui) uniform coherent uimage2D depth_batch_nearest;
uniform uint depth_batch; // this batch's stamp (DepthBatches::begin_batch)

// Whether window depth `depth` is nearer than every depth a batch's fragment gave at this pixel this
// frame (an atomic minimum of the float's bits: depths are non-negative, so the bits order as the
// values). For renderers whose own record of the nearest depth is not exact (the enhanced
// billboards' marks back hits in its lowest bit); the resolve's depth test decides against the
// first batch and everything else drawn.
bool depth_batch_nearer(float depth)
{
    const uint bits = floatBitsToUint(depth);
    return bits < imageAtomicMin(depth_batch_nearest, ivec2(gl_FragCoord.xy), bits);
}

// The colour and window depth of a fragment that is the nearest at its pixel so far.
void depth_batch_store(vec3 color, float depth)
{
    const ivec2 pixel = ivec2(gl_FragCoord.xy);
    imageStore(depth_batch_color, pixel, vec4(color, depth));
    imageStore(depth_batch_stamp, pixel, uvec4(depth_batch));
}
#endif
