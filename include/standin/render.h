// Drawing with OpenGL 4.5 core: the headless context, the interface every representation's
// renderer implements, and offscreen rendering to images.
#pragma once

#include <standin/camera.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/status.h>

#include <glm/glm.hpp>

#include <memory>
#include <span>
#include <string>
#include <vector>

namespace standin {

// An OpenGL 4.5 core context without a window: EGL surfaceless platform, falling back to the EGL
// device platform. Current on the creating thread. One per process is plenty.
class GpuContext {
public:
    virtual ~GpuContext() = default;
    virtual std::string device_name() const = 0; // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    virtual std::string version() const = 0;     // GL_VERSION
};
Result<std::unique_ptr<GpuContext>> create_headless_context();

// Run-time options of the representations' renderers; each renderer reads the ones it knows.
struct RenderOptions {
    std::string march = "exact";  // enhanced billboards: "exact" (default) or "seed" (linear march)
    int steps = 100;              // seed march: steps along the box diagonal
    float hit_range = 0.01f;      // seed march: hit range e, fraction of the box depth
    bool coarse_mesh = true;      // enhanced billboards: fill holes with the package's coarse mesh
    std::string style = "corrected"; // view atlas: "seed", "octahedral-baseline", "corrected"
    std::string debug_view;       // "", "billboard", "depth", "normal", "fetches", "boxes" (billboard boxes as lines)
};

// What one draw of a frame needs. Instances are object-to-world transforms; one identity
// transform when empty.
struct DrawParams {
    Camera camera;
    Light light;
    glm::ivec2 viewport{800, 600};
    std::span<const glm::mat4> world_from_object;
};

struct DrawStats {
    std::uint64_t draw_calls = 0;
    std::uint64_t primitives = 0; // triangles or billboard faces submitted
};

// A representation (or the original mesh) uploaded to the GPU. draw() renders into the currently
// bound framebuffer with depth testing, writing true depth, so stand-ins composite with each other
// and with ordinary geometry.
class Renderer {
public:
    virtual ~Renderer() = default;
    virtual DrawStats draw(const DrawParams& params) = 0;
    // Counters some renderers keep on the GPU (height-field fetches); zero when not supported.
    virtual void set_counting(bool) {}
    virtual std::uint64_t read_fetch_count() { return 0; }
    // Fragment-stage invocations while counting (overdraw = fragments / covered pixels).
    virtual std::uint64_t read_fragment_count() { return 0; }
};

// The ground-truth renderer for the original mesh: per-pixel shading with the shared lighting
// include, textures sampled per pixel. Needs a current context.
Result<std::unique_ptr<Renderer>> make_mesh_renderer(const Mesh& mesh);

// The result of an offscreen render: colour (transparent background) and window-space depth
// (1 where nothing was drawn), both top row first.
struct RenderedImage {
    ImageRGBA8 color;
    std::vector<float> depth;
};

// Renders one frame offscreen at width x height (MSAA off, so that results are exact and
// repeatable) and reads it back. Needs a current context.
Result<RenderedImage> render_offscreen(Renderer& renderer, const Camera& camera, const Light& light,
                                       int width, int height,
                                       std::span<const glm::mat4> world_from_object = {});

} // namespace standin
