#version 450 core
// Depth batches' resolve (reps/common/depth_batches.h): the pixels a batch drew, with the colour and
// depth its nearest fragment stored, through the ordinary depth test; every other pixel is left.
#include "reps/common/shaders/depth_batches.h"

layout(binding = DEPTH_BATCH_COLOR_IMAGE, rgba32f) uniform readonly image2D depth_batch_color;
layout(binding = DEPTH_BATCH_STAMP_IMAGE, r32ui) uniform readonly uimage2D depth_batch_stamp;
uniform uint depth_batch;

layout(location = 0) out vec4 out_color;

void main()
{
    const ivec2 pixel = ivec2(gl_FragCoord.xy);
    if (imageLoad(depth_batch_stamp, pixel).r != depth_batch) discard;
    const vec4 stored = imageLoad(depth_batch_color, pixel);
    gl_FragDepth = stored.a;
    out_color = vec4(stored.rgb, 1.0);
}
