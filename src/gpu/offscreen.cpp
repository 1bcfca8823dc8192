// Offscreen rendering for tests, eval and the CLI: one frame into an RGBA8 + 32-bit float depth
// framebuffer without multisampling (exact, repeatable pixels), read back top row first; with
// shadows, after a shadow map drawn by the same renderer (shadow_map.cpp).
#include "gpu/gl.h"

#include <standin/render.h>

#include <algorithm>
#include <cstring>

namespace standin {

Result<RenderedImage> render_offscreen(Renderer& renderer, const Camera& camera, const Light& light, int width,
                                       int height, std::span<const glm::mat4> world_from_object,
                                       const ShadowOptions& shadows)
{
    if (!gpu::has_current_context()) return error(StatusCode::gpu_error, "render: no current OpenGL context");
    // the target first: its size is checked before anything is drawn
    Result<RenderTarget> target = RenderTarget::create(width, height);
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
    if (gl_error != GL_NO_ERROR) return error(StatusCode::gpu_error, "render: OpenGL error " + std::to_string(gl_error));
    return result;
}

} // namespace standin
