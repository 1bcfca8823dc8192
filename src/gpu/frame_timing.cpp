// GPU frame timing with timer queries, median of many frames after warm-up (niagara measures its
// frames the same way with timestamp queries).
#include "gpu/frame_timing.h"

#include "gpu/gl.h"

#include <algorithm>
#include <chrono>
#include <vector>

namespace standin::gpu {

static const float k_transparent[4] = {0, 0, 0, 0};

Result<FrameTimes> time_frames(Renderer& renderer, const DrawParams& params, int warmup, int frames)
{
    if (!has_current_context()) return error(StatusCode::gpu_error, "frame timing: no current OpenGL context");
    const int width = params.viewport.x, height = params.viewport.y;
    if (width < 1 || height < 1 || frames < 1)
        return error(StatusCode::invalid_argument, "frame timing: empty viewport or no frames");

    // the offscreen target
    Result<RenderTarget> target = RenderTarget::create(width, height);
    if (!target) return target.status();
    target->bind();

    // warm up (shader compilation, uploads, caches), then time each frame
    FrameTimes result;
    for (int i = 0; i < warmup; ++i) {
        target->clear(k_transparent);
        renderer.draw(params);
    }
    glFinish();
    GpuTimer timer;
    std::vector<double> ms, wall;
    for (int i = 0; i < frames; ++i) {
        target->clear(k_transparent);
        glFinish();
        auto start = std::chrono::steady_clock::now();
        timer.begin();
        result.stats = renderer.draw(params);
        timer.end();
        glFinish();
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        ms.push_back(timer.milliseconds());
    }
    std::sort(wall.begin(), wall.end());
    result.wall_median_ms = wall.size() % 2 ? wall[wall.size() / 2] : 0.5 * (wall[wall.size() / 2 - 1] + wall[wall.size() / 2]);
    std::sort(ms.begin(), ms.end());
    result.median_ms = ms[ms.size() / 2];
    if (ms.size() % 2 == 0) result.median_ms = 0.5 * (ms[ms.size() / 2 - 1] + ms[ms.size() / 2]);
    result.min_ms = ms.front();
    result.max_ms = ms.back();

    // coverage of the last frame, then one counted frame where the renderer counts fetches
    ImageRGBA8 pixels = target->read_color();
    for (std::size_t i = 3; i < pixels.pixels.size(); i += 4) result.covered_pixels += pixels.pixels[i] > 0;
    renderer.set_counting(true);
    target->clear(k_transparent);
    renderer.draw(params);
    std::uint64_t fetches = renderer.read_counter(Counter::fetches);
    std::uint64_t fragments = renderer.read_counter(Counter::fragments);
    renderer.set_counting(false);
    if (fetches > 0 && result.covered_pixels > 0) result.fetches_per_pixel = double(fetches) / double(result.covered_pixels);
    if (fragments > 0 && result.covered_pixels > 0)
        result.fragments_per_pixel = double(fragments) / double(result.covered_pixels);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "frame timing: OpenGL error " + std::to_string(gl_error));
    return result;
}

} // namespace standin::gpu
