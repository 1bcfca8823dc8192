// The image units of depth batches (reps/common/depth_batches.h), included by C++ and by GLSL
// (depth_batches.glsl, depth_batch_resolve.frag). Plain #defines only: both languages must parse
// this file. Renderers allocate their own image units from 0 up (gpu/shaders/common/bindings.h);
// these are the last three that GL 4.5 guarantees a fragment stage (8).
#ifndef STANDIN_DEPTH_BATCHES_H
#define STANDIN_DEPTH_BATCHES_H

#define DEPTH_BATCH_NEAREST_IMAGE 5 // R32UI: the nearest depth (its float's bits) of the batches' fragments
#define DEPTH_BATCH_COLOR_IMAGE 6 // RGBA32F: the colour drawn (rgb) and its window depth (a)
#define DEPTH_BATCH_STAMP_IMAGE 7 // R32UI: the batch that drew it

#endif
