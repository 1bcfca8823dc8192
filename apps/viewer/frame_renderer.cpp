// One frame of the viewer: subjects into offscreen targets at the render resolution, then scaled
// into the window (nearest texel, so that a low render resolution looks like one). The holes view
// compares the stand-in's coverage with the original's, pixel by pixel, at the same camera.
#include "frame_renderer.h"

#include <standin/log.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cstring>

namespace standin::viewer {

namespace {

const float k_window_background[4] = {0.08f, 0.08f, 0.09f, 1.0f};
// the render targets' background: visible in the window, alpha 0 so that coverage can be counted
const float k_target_background[4] = {0.20f, 0.21f, 0.24f, 0.0f};

// the largest rectangle of `aspect` centred in a region (GL window coordinates: x0, y0, x1, y1)
glm::ivec4 fit(float aspect, glm::ivec4 region)
{
    float w = float(region.z - region.x), h = float(region.w - region.y);
    float fw = std::min(w, h * aspect), fh = std::min(h, w / aspect);
    int x0 = region.x + int((w - fw) * 0.5f), y0 = region.y + int((h - fh) * 0.5f);
    return {x0, y0, x0 + int(fw), y0 + int(fh)};
}

// GL rectangle (bottom-left origin) to window pixels from the top left
glm::vec4 to_window(glm::ivec4 r, glm::ivec2 framebuffer_size)
{
    return {float(r.x), float(framebuffer_size.y - r.w), float(r.z), float(framebuffer_size.y - r.y)};
}

void blit(GLuint fbo, glm::ivec4 source, glm::ivec4 destination)
{
    if (fbo == 0) return; // no target (its creation failed and was logged)
    glBlitNamedFramebuffer(fbo, 0, source.x, source.y, source.z, source.w, destination.x, destination.y,
                           destination.z, destination.w, GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

} // namespace

FrameRenderer::FrameRenderer() = default;

void FrameRenderer::ensure(Target& target, glm::ivec2 size)
{
    if (target.target && target.size == size) return;
    Result<RenderTarget> made = RenderTarget::create(size.x, size.y, "viewer"); // the viewer keeps sizes within range
    if (!made) {
        log_message(LogLevel::error, made.status().message());
        return;
    }
    target.target.emplace(std::move(*made));
    target.size = size;
}

SubjectStats FrameRenderer::render_subject(ViewerState& state, int index, Target& target, float aspect)
{
    Subject& subject = state.subjects[index];
    SubjectStats stats;
    stats.subject = index;
    if (!target.target) return stats;
    target.target->bind();
    target.target->clear(k_target_background);
    if (!subject.renderer) return stats;

    // draw, timed by a GPU timer query and by the CPU up to glFinish (shadow map included)
    DrawParams params;
    params.camera = current_camera(state, aspect);
    params.light = current_light(state, params.camera);
    params.viewport = target.size;
    if (state.shadows && !shadow_map_) {
        Result<std::unique_ptr<ShadowMap>> made = ShadowMap::create();
        if (made) shadow_map_ = std::move(*made);
        else log_message(LogLevel::warning, made.status().message());
        if (!made) state.shadows = false;
    }
    bool counting = !subject.is_original() && (state.count_fetches || state.debug_view == "fetches");
    subject.renderer->set_counting(counting);
    glFinish();
    auto start = std::chrono::steady_clock::now();
    timer_.begin();
    if (state.shadows && shadow_map_) {
        Status drawn = shadow_map_->render(*subject.renderer, params.light, state.sphere);
        if (drawn) params.shadow_map = shadow_map_.get();
        else log_message(LogLevel::warning, drawn.message());
    }
    stats.draw = subject.renderer->draw(params);
    timer_.end();
    glFinish();
    stats.wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    stats.gpu_ms = timer_.milliseconds();

    // pixels covered: alpha > 0
    target.pixels.resize(std::size_t(target.size.x) * target.size.y * 4);
    glGetTextureImage(target.target->color_texture(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(target.pixels.size()),
                      target.pixels.data());
    for (std::size_t i = 3; i < target.pixels.size(); i += 4) stats.covered_pixels += target.pixels[i] != 0;
    if (counting) {
        std::uint64_t fetches = subject.renderer->read_counter(Counter::fetches);
        stats.fetches_per_pixel = stats.covered_pixels ? double(fetches) / double(stats.covered_pixels) : 0.0;
        subject.renderer->set_counting(false);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return stats;
}

void FrameRenderer::compose_holes(ViewerState& state)
{
    // red: the original covers the pixel and the stand-in does not (a hole); blue: the reverse;
    // both: the stand-in, dimmed
    const Target& original = targets_[0];
    const Target& stand_in = targets_[1];
    Target& out = targets_[2];
    ensure(out, original.size);
    out.pixels.assign(original.pixels.size(), 0);
    state.stats.hole_pixels = state.stats.excess_pixels = 0;
    for (std::size_t i = 0; i < out.pixels.size(); i += 4) {
        bool o = original.pixels[i + 3] != 0, s = stand_in.pixels[i + 3] != 0;
        std::uint8_t* p = &out.pixels[i];
        if (o && !s) {
            p[0] = 255, p[1] = 40, p[2] = 40, p[3] = 255;
            ++state.stats.hole_pixels;
        } else if (s && !o) {
            p[0] = 40, p[1] = 140, p[2] = 255, p[3] = 255;
            ++state.stats.excess_pixels;
        } else if (s) {
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(40 + stand_in.pixels[i + c] * 2 / 5);
            p[3] = 255;
        } else {
            for (int c = 0; c < 3; ++c) p[c] = std::uint8_t(k_target_background[c] * 255.0f);
        }
    }
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (!out.target) return;
    glTextureSubImage2D(out.target->color_texture(), 0, 0, 0, out.size.x, out.size.y, GL_RGBA, GL_UNSIGNED_BYTE, out.pixels.data());
}

FrameLayout FrameRenderer::draw(ViewerState& state, glm::ivec2 framebuffer_size)
{
    FrameLayout layout;
    framebuffer_size = glm::max(framebuffer_size, glm::ivec2(1));
    const bool can_compare = state.original >= 0 && state.stand_in >= 0;
    const bool holes = can_compare && state.debug_view == "holes";
    const Layout mode = holes || !can_compare ? Layout::single : state.layout;

    // the render resolution: fixed, or the window's (halved side by side, keeping the window's
    // aspect so that both images are framed as the single one)
    glm::ivec2 size = state.render_size;
    if (state.render_follows_window) size = mode == Layout::side_by_side ? framebuffer_size / 2 : framebuffer_size;
    size = glm::max(size, glm::ivec2(1));
    // a size beyond the GL limits or the memory budget is halved until it fits, and said so
    for (Status s = check_render_target(size.x, size.y, "view: render size"); !s && size != glm::ivec2(1);
         s = check_render_target(size.x, size.y, "view: render size")) {
        state.message = s.message() + "; halved";
        size = glm::max(size / 2, glm::ivec2(1));
    }
    const float aspect = float(size.x) / float(size.y);
    state.stats = FrameStats();
    state.stats.render_size = size;

    // render: one subject, or the original (left) and the stand-in (right)
    for (Target& target : targets_) ensure(target, size);
    if (mode == Layout::single && !holes) {
        state.stats.subjects.push_back(render_subject(state, state.shown, targets_[0], aspect));
    } else {
        state.stats.subjects.push_back(render_subject(state, state.original, targets_[0], aspect));
        state.stats.subjects.push_back(render_subject(state, state.stand_in, targets_[1], aspect));
    }
    if (holes) compose_holes(state);

    // compose into the window
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, framebuffer_size.x, framebuffer_size.y);
    glDisable(GL_SCISSOR_TEST);
    glClearNamedFramebufferfv(0, GL_COLOR, 0, k_window_background);
    const glm::ivec4 whole{0, 0, framebuffer_size.x, framebuffer_size.y};
    const glm::ivec4 source{0, 0, size.x, size.y};
    if (mode == Layout::single) {
        glm::ivec4 r = fit(aspect, whole);
        blit(targets_[holes ? 2 : 0].framebuffer(), source, r);
        layout.left = to_window(r, framebuffer_size);
        layout.left_label = holes ? "holes: red = original only, blue = stand-in only"
                                  : state.subjects[state.shown].label;
    } else if (mode == Layout::split) {
        glm::ivec4 r = fit(aspect, whole);
        int source_x = int(state.split_position * float(size.x) + 0.5f);
        int window_x = r.x + int(float(source_x) / float(size.x) * float(r.z - r.x) + 0.5f);
        if (source_x > 0) blit(targets_[0].framebuffer(), {0, 0, source_x, size.y}, {r.x, r.y, window_x, r.w});
        if (source_x < size.x) blit(targets_[1].framebuffer(), {source_x, 0, size.x, size.y}, {window_x, r.y, r.z, r.w});
        layout.left = to_window(r, framebuffer_size);
        layout.split_x = float(window_x);
        layout.left_label = state.subjects[state.original].label;
        layout.right_label = state.subjects[state.stand_in].label;
    } else {
        int half = framebuffer_size.x / 2;
        glm::ivec4 left = fit(aspect, {0, 0, half, framebuffer_size.y});
        glm::ivec4 right = fit(aspect, {half, 0, framebuffer_size.x, framebuffer_size.y});
        blit(targets_[0].framebuffer(), source, left);
        blit(targets_[1].framebuffer(), source, right);
        layout.left = to_window(left, framebuffer_size);
        layout.right = to_window(right, framebuffer_size);
        layout.left_label = state.subjects[state.original].label;
        layout.right_label = state.subjects[state.stand_in].label;
    }
    return layout;
}

ImageRGBA8 read_window(glm::ivec2 framebuffer_size)
{
    ImageRGBA8 image(framebuffer_size.x, framebuffer_size.y);
    std::vector<std::uint8_t> rows(image.pixels.size());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    // GL's row 0 is the bottom row; images are stored top row first
    const std::size_t stride = std::size_t(image.width) * 4;
    for (int y = 0; y < image.height; ++y)
        std::memcpy(image.at(0, y), &rows[std::size_t(image.height - 1 - y) * stride], stride);
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) image.pixels[i] = 255;
    return image;
}

} // namespace standin::viewer
