// GPU frame timing with timer queries, median of many frames after warm-up (niagara measures its
// frames the same way with timestamp queries).
#include "gpu/frame_timing.h"

#include "gpu/gl.h"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <vector>

namespace standin::gpu {

static const float k_transparent[4] = {0, 0, 0, 0};

static double process_cpu_ms()
{
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

static double frame_median(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

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
    std::vector<double> ms, wall, cpu;
    for (int i = 0; i < frames; ++i) {
        target->clear(k_transparent);
        glFinish();
        auto start = std::chrono::steady_clock::now();
        const double cpu_start = process_cpu_ms();
        timer.begin();
        result.stats = renderer.draw(params);
        timer.end();
        glFinish();
        wall.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        cpu.push_back(process_cpu_ms() - cpu_start);
        ms.push_back(timer.milliseconds());
    }
    result.wall_median_ms = frame_median(wall);
    result.cpu_median_ms = frame_median(cpu);
    result.median_ms = frame_median(ms);
    result.min_ms = *std::min_element(ms.begin(), ms.end());
    result.max_ms = *std::max_element(ms.begin(), ms.end());

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
        return error(StatusCode::gpu_error, "frame timing: " + gpu::gl_error_text(gl_error));
    return result;
}

} // namespace standin::gpu
