// Drawing with OpenGL 4.5 core: the headless context, the interface every representation's
// renderer implements, and offscreen rendering to images.
#pragma once

#include <standin/camera.h>
#include <standin/debug_view.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/options.h>
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

// Run-time options of a package's renderer: its representation's declared options by name
// (checked against the declaration when the renderer is made; options.h), and a debug view.
struct RenderOptions {
    OptionValues values;
    DebugView debug_view = DebugView::none;
};

class ShadowMap;

// What one draw of a frame needs. Instances are object-to-world transforms; one identity
// transform when empty.
struct DrawParams {
    Camera camera;
    Light light;
    glm::ivec2 viewport{800, 600};
    std::span<const glm::mat4> world_from_object;
    // Shadows of `light`: a map drawn beforehand for the same light (ShadowMap::render); shading
    // multiplies the light's direct term by the fraction of the map's taps that see the light.
    // Null: no shadows, and shading is exactly what it is without this field.
    const ShadowMap* shadow_map = nullptr;
    // A screen-door cross-fade (issue #14): every pixel has a fixed threshold t in (0, 1) from an
    // 8x8 ordered-dither matrix (gpu/shaders/common/fade.glsl); an outgoing draw keeps the pixels
    // with t >= amount, an incoming one those with t < amount. Two renderers drawn into one frame
    // at the same amount, one outgoing and one incoming, cover each pixel exactly once (coverage in
    // steps of 1/64); dropped fragments write neither colour nor depth, so depth stays true and
    // shadow maps drawn the same way fade too. The default (amount 0, outgoing) draws exactly what
    // a draw without a fade draws. CrossFade below draws such a pair.
    struct Fade {
        float amount = 0.0f; // [0, 1]; outside clamped, NaN taken as 0
        bool incoming = false;
    } fade;
};

struct DrawStats {
    std::uint64_t draw_calls = 0;
    std::uint64_t primitives = 0; // triangles (or proxy faces) submitted
};

// A representation (or the original mesh) uploaded to the GPU. draw() renders into the currently
// bound framebuffer with depth testing, writing true depth, so stand-ins composite with each other
// and with ordinary geometry.
class Renderer {
public:
    virtual ~Renderer() = default;
    virtual DrawStats draw(const DrawParams& params) = 0;
    // Counters some renderers keep on the GPU; zero when not supported.
    virtual void set_counting(bool) {}
    virtual std::uint64_t read_counter(Counter) { return 0; }
};

// A level-of-detail transition (issue #14): `from` and `to` drawn into the same frame with
// complementary screen-door masks (DrawParams::fade), so switching representation over a band of
// distances changes 1/64 of the pixels at a time instead of all at once. At amount 0 it is exactly
// `from`, at 1 exactly `to` (the other is not drawn). The fade of the params it is given is
// replaced, not composed. Drawn into a shadow map (ShadowMap::render), the shadow fades too.
// Counters are the sum of both. Both renderers must outlive it.
class CrossFade : public Renderer {
public:
    CrossFade(Renderer& from, Renderer& to) : from_(&from), to_(&to) {}
    void set_amount(float amount); // clamped to [0, 1]; NaN taken as 0
    float amount() const { return amount_; }
    DrawStats draw(const DrawParams& params) override;
    void set_counting(bool on) override;
    std::uint64_t read_counter(Counter counter) override;

private:
    Renderer* from_;
    Renderer* to_;
    float amount_ = 0.0f;
};

// The fade amount over a distance band: 0 at or below `near`, 1 at or above `far`, linear between
// (coverage changes evenly with distance). near == far is a hard switch at that distance (1 from
// `far` on). Distances in any unit, as long as the band uses the same.
float transition_amount(float distance, float near, float far);

// Dynamic shadows of the one directional light (issue #6, Saraiva et al. §7): a depth map of the scene
// seen from the light, drawn by the same renderers with their true depth (the mesh, the billboards'
// ray hits, the view atlas' 'corrected' intersections; the atlas' 'seed' and 'octahedral-baseline'
// styles cast and receive at their camera-facing quad's depth). Shading looks the map up at each
// shaded point's world position: 5 x 5 percentage-closer taps, each a bilinear depth compare, with a
// depth bias (a constant one, bias_world(), plus a slope-scaled one) and a one-texel offset along
// the normal (lighting.glsl).
// The light's camera is orthographic, along the light direction, and fits a world-space sphere
// around everything that casts or receives shadows.
class ShadowMap {
public:
    // A square DEPTH_COMPONENT32F map of resolution^2 texels (1..GL_MAX_TEXTURE_SIZE). Needs a
    // current context; fails with a status naming the size when it is out of range.
    static Result<std::unique_ptr<ShadowMap>> create(int resolution = 2048);
    ~ShadowMap();

    // Clears the map and draws `casters` (with their instances, identity when empty) from `light`
    // into it. `scene` is a world-space sphere holding every caster and receiver: parts outside it
    // neither cast nor receive. Restores the framebuffer binding and viewport it found.
    Status render(Renderer& casters, const Light& light, const BoundingSphere& scene,
                  std::span<const glm::mat4> world_from_object = {});

    const Camera& camera() const;   // the light's camera of the last render()
    glm::mat4 shadow_from_world() const; // world -> [0, 1]^3: map u, v and window depth
    float texel_world() const;     // world units across one texel
    float depth_per_world() const; // window-depth units per world unit along the light
    // The constant depth bias, world units: 0.6% of the scene's radius (at least 1.5 texels).
    // Stand-ins rebuild depth to about a texel of their own maps (an atlas view of 256 texels
    // across the sphere: 0.8% of the radius), and a smaller bias speckles them with acne.
    float bias_world() const;
    int resolution() const;
    unsigned texture() const;      // the GL texture name (compare mode on, for sampler2DShadow)

private:
    ShadowMap();
    struct State;
    std::unique_ptr<State> state_;
};

// Shadows of a render_offscreen call: off by default.
struct ShadowOptions {
    bool enabled = false;
    BoundingSphere scene;  // world space, around every caster and receiver (see ShadowMap::render)
    int resolution = 2048; // of the shadow map
};

// The ground-truth renderer for the original mesh: per-pixel shading with the shared lighting
// include, textures sampled per pixel. Needs a current context.
Result<std::unique_ptr<Renderer>> make_mesh_renderer(const Mesh& mesh);

// Whether a width x height colour + depth target and its read-back fit GL_MAX_RENDERBUFFER_SIZE,
// GL_MAX_TEXTURE_SIZE and the memory budget (limits.h): ok, or invalid_argument naming `what`, the
// size and the limit. Needs a current context. RenderTarget::create checks it; the viewer too.
Status check_render_target(int width, int height, const std::string& what);

// An offscreen target: RGBA8 colour and 32-bit float depth, no multisampling (exact, repeatable
// pixels). What render_offscreen and the benchmarks draw into; an application that composes several
// renderers' pictures (the viewer) keeps a few. Needs a current context.
class RenderTarget {
public:
    // Refuses what check_render_target refuses, and reports gpu_error when the driver cannot
    // allocate the target.
    // `what` names the target in errors ("render", "viewer").
    static Result<RenderTarget> create(int width, int height, const std::string& what = "render target");
    RenderTarget(RenderTarget&&) noexcept;
    RenderTarget& operator=(RenderTarget&&) noexcept;
    ~RenderTarget();

    // Binds it as the framebuffer, sets the viewport to its size, depth testing (GL_LESS, writes
    // on), no blending, no culling.
    void bind() const;
    // Clears colour to `rgba` and depth to 1.
    void clear(const float rgba[4]) const;
    int width() const;
    int height() const;
    unsigned framebuffer() const;   // the GL framebuffer name
    unsigned color_texture() const; // the GL texture name of the colour attachment
    // Read back, top row first.
    ImageRGBA8 read_color() const;
    std::vector<float> read_depth() const;

private:
    RenderTarget();
    struct State;
    std::unique_ptr<State> state_;
};

// GPU time of the commands between begin() and end() (a GL_TIME_ELAPSED query). On llvmpipe the
// query misses deferred rasterisation: compare wall time to glFinish there. Needs a current context.
class GpuTimer {
public:
    GpuTimer();
    ~GpuTimer();
    GpuTimer(const GpuTimer&) = delete;
    GpuTimer& operator=(const GpuTimer&) = delete;
    void begin();
    void end();
    double milliseconds(); // waits for the result

private:
    unsigned query_ = 0;
};

// Where shaders are read from instead of the copies embedded at build time: the src/ folder of a
// source tree (an interactive viewer reloads them after edits). Empty: embedded only.
void set_shader_source_directory(const std::string& src_root);

// The result of an offscreen render: colour (transparent background) and window-space depth
// (1 where nothing was drawn), both top row first.
struct RenderedImage {
    ImageRGBA8 color;
    std::vector<float> depth;
};

// Renders one frame offscreen at width x height (MSAA off, so that results are exact and
// repeatable) and reads it back. With shadows enabled, the same renderer and instances first draw
// a shadow map from `light` (ShadowMap). Needs a current context.
Result<RenderedImage> render_offscreen(Renderer& renderer, const Camera& camera, const Light& light,
                                       int width, int height,
                                       std::span<const glm::mat4> world_from_object = {},
                                       const ShadowOptions& shadows = {});

} // namespace standin
