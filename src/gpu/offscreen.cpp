// Offscreen rendering for tests, eval and the CLI: one frame into an RGBA8 + 32-bit float depth
// framebuffer without multisampling (exact, repeatable pixels), read back top row first; with
// shadows, after a shadow map drawn by the same renderer (shadow_map.cpp).
#include "gpu/gl.h"

#include <standin/limits.h>
#include <standin/render.h>

#include <algorithm>
#include <cstring>

namespace standin {

// Bytes per pixel of one offscreen frame at its peak (measured: 6.4 GB for 16384 x 16384).
constexpr std::uint64_t k_render_bytes_per_pixel = 24;

Status check_render_target(int width, int height, const std::string& what)
{
    // any current context: EGL (render_offscreen) or the viewer's GLFW window
    GLint max_renderbuffer = 0, max_texture = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
    GLint max_size = std::min(max_renderbuffer, max_texture);
    std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (width < 1 || height < 1 || width > max_size || height > max_size)
        return error(StatusCode::invalid_argument, what + ": size " + size + " out of range 1.." + std::to_string(max_size) +
                                                       " (GL_MAX_RENDERBUFFER_SIZE, GL_MAX_TEXTURE_SIZE)");
    // before anything is allocated: the driver's colour and depth targets, the read-back rows and
    // the result (colour and depth), and the PNG rows of the caller
    return check_memory(std::uint64_t(width) * std::uint64_t(height) * k_render_bytes_per_pixel, what + ": a " + size + " image");
}

Result<RenderedImage> render_offscreen(Renderer& renderer, const Camera& camera, const Light& light, int width,
                                       int height, std::span<const glm::mat4> world_from_object,
                                       const ShadowOptions& shadows)
{
    if (!gpu::has_current_context()) return error(StatusCode::gpu_error, "render: no current OpenGL context");
    STANDIN_RETURN_IF_ERROR(check_render_target(width, height, "render"));
    // the shadow map first: the same renderer and instances seen from the light
    std::unique_ptr<ShadowMap> shadow_map;
    if (shadows.enabled) {
        Result<std::unique_ptr<ShadowMap>> made = ShadowMap::create(shadows.resolution);
        if (!made) return made.status();
        shadow_map = std::move(*made);
        STANDIN_RETURN_IF_ERROR(shadow_map->render(renderer, light, shadows.scene, world_from_object));
    }

    gpu::Texture color = gpu::make_texture_2d(GL_RGBA8, width, height);
    gpu::Texture depth = gpu::make_texture_2d(GL_DEPTH_COMPONENT32F, width, height);
    gpu::Framebuffer fbo = gpu::make_framebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
    if (glCheckNamedFramebufferStatus(fbo.get(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return error(StatusCode::gpu_error, "render: offscreen framebuffer incomplete");

    glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
    glViewport(0, 0, width, height);
    const float transparent[4] = {0, 0, 0, 0};
    const float far_depth = 1.0f;
    glClearNamedFramebufferfv(fbo.get(), GL_COLOR, 0, transparent);
    glClearNamedFramebufferfv(fbo.get(), GL_DEPTH, 0, &far_depth);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_BLEND);

    DrawParams params;
    params.camera = camera;
    params.light = light;
    params.viewport = {width, height};
    params.world_from_object = world_from_object;
    params.shadow_map = shadow_map.get();
    renderer.draw(params);

    RenderedImage result;
    result.color = ImageRGBA8(width, height);
    result.depth.resize(std::size_t(width) * height);
    std::vector<std::uint8_t> rows(result.color.pixels.size());
    std::vector<float> depth_rows(result.depth.size());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    glReadPixels(0, 0, width, height, GL_DEPTH_COMPONENT, GL_FLOAT, depth_rows.data());
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR) return error(StatusCode::gpu_error, "render: OpenGL error " + std::to_string(gl_error));
    // GL's row 0 is the bottom row; images are stored top row first.
    std::size_t stride = std::size_t(width) * 4;
    for (int y = 0; y < height; ++y) {
        std::memcpy(&result.color.pixels[std::size_t(y) * stride], &rows[std::size_t(height - 1 - y) * stride], stride);
        std::memcpy(&result.depth[std::size_t(y) * width], &depth_rows[std::size_t(height - 1 - y) * width],
                    std::size_t(width) * sizeof(float));
    }
    return result;
}

} // namespace standin
