// The displaced-mesh renderer beyond the Renderer interface: its run-time settings, the counters
// of the paper's Table 4 (processed and rendered triangles, culled faces, the measured
// screen-space error) and §5.3's animation (new control-vertex positions every frame).
#pragma once

#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/refine.h"

#include <standin/render.h>

#include <memory>
#include <span>
#include <string>

namespace standin::displaced_mesh {

struct RendererSettings {
    float tau = 1.0f;                 // screen-space tolerance, pixels (the paper's τ)
    Criterion criterion = Criterion::error;
    bool cull = true;                 // frustum and back-face culling of control faces on their prisms
    bool mip = true;                  // elevations from the level whose spacing projects to about tau
    float outline = 2.0f;             // error criterion: how much more error counts near the silhouette
    std::string subdivision = "leb";  // "leb": compute-shader bisection; "tess": tessellation-shader baseline
    bool cut_out_pre_pass = true;     // packages with cut-outs: depth first, then one shaded fragment per pixel (leb only)
    int max_depth = 0;                // bisection passes; 0: refinement_passes()
    DebugView debug_view = DebugView::none; // none, parts, level, error, depth, normal
    float error_scale = 0.0f;         // full scale of the "error" view, pixels; 0: tau
    // the largest storage buffer a shader may read, bytes; 0: the GL's (GL_MAX_SHADER_STORAGE_BLOCK_SIZE,
    // 128 MiB on llvmpipe). A package whose buffers would exceed it is refused with what to bake instead.
    std::uint64_t max_storage_block_bytes = 0;
};

// What the last draw did, read back from the GPU (one small read per draw).
struct RefineCounters {
    std::uint64_t faces_visible = 0; // control faces x instances that passed culling
    std::uint64_t processed = 0;     // triangles tested over all passes
    std::uint64_t rendered = 0;      // triangles drawn
    std::uint64_t capped = 0;        // triangles that wanted to split after the last pass
    std::uint64_t overflowed = 0;    // made final for lack of list room (the lists grow next draw)
    std::uint64_t dropped = 0;       // final triangles that did not fit (the lists grow next draw)
};

// Counters summed over the draws made while counting (Renderer::set_counting).
struct ErrorCounters {
    std::uint64_t fragments = 0;     // fragments that passed the depth test
    double error_mean_px = 0.0;      // their mean distance to the finest surface, pixels
    double error_max_px = 0.0;
};

class DisplacedRenderer : public Renderer {
public:
    static Result<std::unique_ptr<DisplacedRenderer>> create(const DisplacedMeshPackage& package, const RendererSettings& settings);
    // §5.3: the control mesh's vertices moved (object space, one per package vertex, unit normals).
    virtual Status update_control(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) = 0;
    virtual RefineCounters last_counters() const = 0;
    virtual ErrorCounters read_error_counters() = 0;
    virtual const RendererSettings& settings() const = 0;
};

// The declared run-time options (representation.cpp) typed.
RendererSettings renderer_settings(const RenderSettings& settings);

// What a renderer of `package` holds in GPU buffers whatever it draws: control vertices, per-face
// data, every level's elevations (float) and the shading samples (normal + albedo, 8 bytes; PBR 8
// more); the refinement's lists, which grow with the view, are not counted.
std::uint64_t package_buffer_bytes(const DisplacedMeshPackage& package);

} // namespace standin::displaced_mesh
