// GPU frame time of any Renderer: draws into an offscreen framebuffer, warm-up frames first, then
// each frame timed with a GL_TIME_ELAPSED query (GpuTimer); the median is what bench and eval report.
#pragma once

#include <standin/render.h>

#include <cstdint>

namespace standin::gpu {

struct FrameTimes {
    double median_ms = 0.0, min_ms = 0.0, max_ms = 0.0; // GPU timer queries (GL_TIME_ELAPSED)
    // CPU wall time from submission to glFinish. On llvmpipe the timer query does not cover the
    // deferred rasterisation, so this is the figure to compare there.
    double wall_median_ms = 0.0;
    // CPU time of the whole process (every thread) over the same span. A software rasteriser's
    // threads run in this process, so on llvmpipe this is the work a frame costs, whatever else the
    // machine runs at the time (wall time grows with the machine's load; this does not).
    double cpu_median_ms = 0.0;
    DrawStats stats;                 // of the last frame
    std::size_t covered_pixels = 0;  // alpha > 0 after the last frame
    double fetches_per_pixel = -1.0; // -1 when the renderer does not count fetches
    double fragments_per_pixel = -1.0; // fragment-stage runs per covered pixel (overdraw); -1 when not counted
};

// Renders `params` (viewport = framebuffer size) warmup + frames times into an RGBA8 + depth
// framebuffer cleared to transparent each frame. frames >= 1. Needs a current context; gpu_error
// when the framebuffer cannot be made or GL reports an error.
Result<FrameTimes> time_frames(Renderer& renderer, const DrawParams& params, int warmup, int frames);

} // namespace standin::gpu
