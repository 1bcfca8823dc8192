// Offscreen targets and GPU timers (include/standin/render.h).
#include "gpu/gl.h"

#include <standin/render.h>

#include <cstring>

namespace standin {

struct RenderTarget::State {
    gpu::Texture color, depth;
    gpu::Framebuffer fbo;
    int width = 0, height = 0;
};

RenderTarget::RenderTarget() : state_(std::make_unique<State>()) {}
RenderTarget::RenderTarget(RenderTarget&&) noexcept = default;
RenderTarget& RenderTarget::operator=(RenderTarget&&) noexcept = default;
RenderTarget::~RenderTarget() = default;

Result<RenderTarget> RenderTarget::create(int width, int height, const std::string& what)
{
    STANDIN_RETURN_IF_ERROR(check_render_target(width, height, what));
    RenderTarget target;
    State& s = *target.state_;
    s.width = width;
    s.height = height;
    s.color = gpu::make_texture_2d(GL_RGBA8, width, height);
    s.depth = gpu::make_texture_2d(GL_DEPTH_COMPONENT32F, width, height);
    s.fbo = gpu::make_framebuffer();
    glNamedFramebufferTexture(s.fbo.get(), GL_COLOR_ATTACHMENT0, s.color.get(), 0);
    glNamedFramebufferTexture(s.fbo.get(), GL_DEPTH_ATTACHMENT, s.depth.get(), 0);
    if (glCheckNamedFramebufferStatus(s.fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return error(StatusCode::gpu_error, "render: offscreen framebuffer of " + std::to_string(width) + "x" +
                                                std::to_string(height) + " incomplete (out of GPU memory?)");
    return target;
}

void RenderTarget::bind() const
{
    glBindFramebuffer(GL_FRAMEBUFFER, state_->fbo.get());
    glViewport(0, 0, state_->width, state_->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
}

void RenderTarget::clear(const float rgba[4]) const
{
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(state_->fbo.get(), GL_COLOR, 0, rgba);
    glClearNamedFramebufferfv(state_->fbo.get(), GL_DEPTH, 0, &far_depth);
}

int RenderTarget::width() const { return state_->width; }
int RenderTarget::height() const { return state_->height; }
unsigned RenderTarget::framebuffer() const { return state_->fbo.get(); }
unsigned RenderTarget::color_texture() const { return state_->color.get(); }

ImageRGBA8 RenderTarget::read_color() const
{
    const int w = state_->width, h = state_->height;
    ImageRGBA8 image(w, h);
    std::vector<std::uint8_t> rows(image.pixels.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(state_->color.get(), 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rows.size()), rows.data());
    // GL's row 0 is the bottom row; images are stored top row first
    const std::size_t stride = std::size_t(w) * 4;
    for (int y = 0; y < h; ++y) std::memcpy(&image.pixels[std::size_t(y) * stride], &rows[std::size_t(h - 1 - y) * stride], stride);
    return image;
}

std::vector<float> RenderTarget::read_depth() const
{
    const int w = state_->width, h = state_->height;
    std::vector<float> rows(std::size_t(w) * h), depth(rows.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(state_->depth.get(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(rows.size() * sizeof(float)), rows.data());
    for (int y = 0; y < h; ++y)
        std::memcpy(&depth[std::size_t(y) * w], &rows[std::size_t(h - 1 - y) * w], std::size_t(w) * sizeof(float));
    return depth;
}

GpuTimer::GpuTimer() { glCreateQueries(GL_TIME_ELAPSED, 1, &query_); }
GpuTimer::~GpuTimer() { glDeleteQueries(1, &query_); }
void GpuTimer::begin() { glBeginQuery(GL_TIME_ELAPSED, query_); }
void GpuTimer::end() { glEndQuery(GL_TIME_ELAPSED); }
double GpuTimer::milliseconds()
{
    GLuint64 ns = 0;
    glGetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
    return double(ns) * 1e-6;
}

void set_shader_source_directory(const std::string& src_root) { gpu::set_shader_source_directory(src_root); }

} // namespace standin
