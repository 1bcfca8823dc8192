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
    // the target first: its size and memory are checked before anything is drawn
    Result<RenderTarget> target = RenderTarget::create(width, height, "render");
    if (!target) return target.status();
    // the shadow map first: the same renderer and instances seen from the light
    std::unique_ptr<ShadowMap> shadow_map;
    if (shadows.enabled) {
        Result<std::unique_ptr<ShadowMap>> made = ShadowMap::create(shadows.resolution);
        if (!made) return made.status();
        shadow_map = std::move(*made);
        STANDIN_RETURN_IF_ERROR(shadow_map->render(renderer, light, shadows.scene, world_from_object));
    }

    target->bind();
    const float transparent[4] = {0, 0, 0, 0};
    target->clear(transparent);

    DrawParams params;
    params.camera = camera;
    params.light = light;
    params.viewport = {width, height};
    params.world_from_object = world_from_object;
    params.shadow_map = shadow_map.get();
    renderer.draw(params);

    RenderedImage result;
    result.color = target->read_color();
    result.depth = target->read_depth();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    GLenum gl_error = glGetError();
    if (gl_error != GL_NO_ERROR) return error(StatusCode::gpu_error, "render: " + gpu::gl_error_text(gl_error));
    return result;
}

} // namespace standin
