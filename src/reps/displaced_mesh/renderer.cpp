// The displaced-mesh renderer: the paper's runtime stage with compute passes instead of geometry
// shaders and stream-out (Bauman, Livny & El-Sana §3.3, §3.4, §4).
//
// Steps per draw (every camera, the shadow map's too):
//  1. upload the frame and refinement blocks; clear the per-draw state;
//  2. cull: one invocation per control face and instance (shaders/cull.comp), a scan of the
//     survivors and their root records in (instance, face) order (scan_groups, scatter_roots);
//  3. bisect, pass by pass: decide (shaders/decide.comp), scan the (splits, finals) counts, scatter
//     children to the other list and finals to the final list (scatter.comp); dispatch sizes come
//     from the GPU (glDispatchComputeIndirect), lists alternate (the paper's two VBOs);
//  4. read back the counts; if a list overflowed, grow the lists and run 2-3 again (the result
//     never depends on when that happened);
//  5. displace the final list's vertices (shaders/displace.comp);
//  6. draw the final list with glDrawArraysIndirect, those vertices pulled by shaders/draw.vert,
//     shaded by shaders/draw.frag; packages with coverage (alpha-masked models, issue #14) first
//     draw depth alone through the cut-out test, with depth tested after the fragment stage so that
//     discarded cut-outs write no depth, then shade the nearest fragments (GL_EQUAL).
// The "tess" subdivision draws each visible control face as a GL patch instead, tessellated to
// power-of-two levels from edge-only data (a baseline to compare with).
#include "reps/displaced_mesh/renderer.h"

#include "gpu/counters.h"
#include "gpu/frame.h"
#include "gpu/source_texture.h"
#include "gpu/gl.h"
#include "reps/common/package_cast.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/shaders/displaced_layout.glsl"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace standin::displaced_mesh {

static_assert(DM_BARY_BITS == k_bary_bits, "shaders/displaced_layout.glsl and face_point.h disagree");
static_assert(int(Criterion::weighted) == DM_CRITERION_WEIGHTED && int(Criterion::length) == DM_CRITERION_LENGTH &&
                  int(Criterion::seed) == DM_CRITERION_SEED && int(Criterion::error) == DM_CRITERION_ERROR,
              "shaders/displaced_layout.glsl and refine.h number the criteria differently");

namespace {

constexpr std::uint64_t k_initial_records = 1u << 18;
// llvmpipe's largest shader storage block is 128 MiB; a record is 36 bytes
constexpr std::uint64_t k_max_records = (std::uint64_t(128) << 20) / (DM_RECORD_UINTS * 4);

struct RefineBlock {
    glm::mat4 clip_from_view;
    glm::vec4 view_terms;   // tau, pixels per unit, near, orthographic
    glm::uvec4 counts;      // faces, instances, n, m
    glm::uvec4 options;     // criterion, mip, cull, debug view
    glm::uvec4 capacities;  // list, final, samples per face, finest samples
    glm::vec4 error_terms;  // full scale of the error view
};
static_assert(sizeof(RefineBlock) == 64 + 5 * 16, "std140 layout of RefineBlock");

struct FaceData {
    glm::uvec4 corners;
    glm::vec4 weights;
    glm::vec4 range;
    glm::vec4 extra;
    glm::vec4 curvature;
};

struct ControlVertex {
    glm::vec4 position;
    glm::vec4 normal;
    glm::vec4 rest_normal;
    glm::vec4 rest_tangent;
    glm::uvec4 reference;
};

// The most GPU memory the source textures' array may take (layers resampled to the largest).
constexpr std::uint64_t k_max_source_texture_bytes = std::uint64_t(2) << 30;

// The package's storage buffers (init uploads them; the refinement's lists are apart).
struct PackageBuffer {
    const char* what;
    std::uint64_t bytes;
};
std::vector<PackageBuffer> package_buffers(const DisplacedMeshPackage& package)
{
    std::vector<PackageBuffer> buffers = {
        {"control vertices", std::uint64_t(package.positions.size()) * sizeof(ControlVertex)},
        {"per-face data", std::uint64_t(package.face_count()) * sizeof(FaceData)},
        {"elevations", std::uint64_t(package.elevations.size()) * sizeof(float)},
        {"shading samples", std::uint64_t(package.shading_normals.size()) * sizeof(glm::uvec2)},
    };
    if (!package.orm.empty()) buffers.push_back({"PBR samples", std::uint64_t(package.orm.size()) * sizeof(glm::uvec2)});
    if (!package.source_textures.faces.empty())
        buffers.push_back({"source texture records", std::uint64_t(package.source_textures.faces.size()) * sizeof(FaceTexture)});
    return buffers;
}

// Each of the package's buffers must fit one storage block, or the shaders would read past what the
// GL binds (foliage of over a million cards kept whole as control faces; docs/failure_cases.md).
Status check_buffer_sizes(const DisplacedMeshPackage& package, std::uint64_t limit)
{
    if (limit == 0) {
        GLint64 gl_limit = 0;
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &gl_limit);
        limit = gl_limit > 0 ? std::uint64_t(gl_limit) : std::uint64_t(128) << 20;
    }
    auto mib = [](std::uint64_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20); };
    for (const PackageBuffer& b : package_buffers(package))
        if (b.bytes > limit)
            return error(StatusCode::unsupported,
                         "displaced mesh: its " + std::string(b.what) + " (" + std::to_string(package.face_count()) +
                             " control faces) take " + mib(b.bytes) + " MiB, over the " + mib(limit) +
                             " MiB this OpenGL lets a shader read from one buffer; bake it again with --degree 5 "
                             "--shading-detail 1, or as another representation");
    return Status::ok();
}

// Source textures go to at most this many texture arrays, one per size class (textures whose sizes
// divide each other share one, repeated: gpu::source_texture_array_of), so that a texture keeps its
// own texels; any further size is resampled into the first. Each array is a texture read in every
// fragment on llvmpipe (draw.frag reads them all, masked), so few: assimp's spider (249 x 250, 250,
// 768 and 128 texels) takes 3, thesis Luv 0.603 -> 0.035 against its model (docs/RESULTS.md).
constexpr int k_max_source_arrays = 4;

// The source textures' arrays (every layer of one at its largest width and height, with its mip
// levels) must be ones the GL can make and not a memory bomb: a package may name 256 layers of up
// to 16384².
Status check_source_texture_size(const SourceTextures& textures)
{
    const std::vector<std::uint32_t> array_of = gpu::source_texture_array_of(textures.layers, k_max_source_arrays);
    std::vector<glm::ivec2> size(k_max_source_arrays, glm::ivec2(0));
    std::vector<std::uint64_t> layers(k_max_source_arrays, 0);
    for (std::size_t k = 0; k < textures.layers.size(); ++k) {
        glm::ivec2& s = size[array_of[k]];
        s = glm::max(s, glm::ivec2(textures.layers[k].width, textures.layers[k].height));
        ++layers[array_of[k]];
    }
    GLint max_size = 0, max_layers = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    std::uint64_t bytes = 0;
    bool fits = true;
    for (int a = 0; a < k_max_source_arrays; ++a) {
        bytes += std::uint64_t(size[a].x) * std::uint64_t(size[a].y) * layers[a] * 4u * 4u / 3u;
        fits = fits && size[a].x <= max_size && size[a].y <= max_size && layers[a] <= std::uint64_t(max_layers);
    }
    if (!fits || bytes > k_max_source_texture_bytes)
        return error(StatusCode::unsupported, "displaced mesh: its " + std::to_string(textures.layers.size()) + " source textures take up to " +
                                                  std::to_string(size[0].x) + "x" + std::to_string(size[0].y) + " texels each on the GPU (" +
                                                  std::to_string(bytes >> 20) + " MiB), over what this OpenGL or standin allows (" +
                                                  std::to_string(max_size) + " texels a side, " + std::to_string(max_layers) + " layers, " +
                                                  std::to_string(k_max_source_texture_bytes >> 20) +
                                                  " MiB); bake it again with --source-textures off");
    return Status::ok();
}

} // namespace

std::uint64_t package_buffer_bytes(const DisplacedMeshPackage& package)
{
    std::uint64_t bytes = 0;
    for (const PackageBuffer& b : package_buffers(package)) bytes += b.bytes;
    return bytes;
}

namespace {

Result<int> debug_view_code(DebugView view)
{
    switch (view) {
    case DebugView::none: case DebugView::parts: case DebugView::level: case DebugView::error: case DebugView::depth:
    case DebugView::normal:
        return int(view);
    default:
        return error(StatusCode::invalid_argument,
                     std::string("--debug-view: the displaced mesh draws parts, level, error, depth and normal, not ") +
                         debug_view_name(view));
    }
}

class Impl final : public DisplacedRenderer {
public:
    Status init(const DisplacedMeshPackage& package, const RendererSettings& settings);
    DrawStats draw(const DrawParams& params) override;
    void set_counting(bool on) override { counters_->set_counting(on); }
    std::uint64_t read_counter(Counter counter) override { return counters_->read(int(counter)); }
    Status update_control(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals) override;
    RefineCounters last_counters() const override { return refine_counters_; }
    ErrorCounters read_error_counters() override;
    const RendererSettings& settings() const override { return settings_; }

private:
    void ensure_capacity(std::uint64_t list_records, std::uint64_t final_records);
    void run_passes(const DrawParams& params, std::uint32_t instances);
    std::vector<std::uint32_t> read_state();
    void dispatch(const gpu::Program& program, GLuint groups);
    void dispatch_indirect(const gpu::Program& program, std::uint32_t parity);

    RendererSettings settings_;
    int debug_code_ = DEBUG_VIEW_NONE;
    PatternLayout layout_{17};
    std::uint32_t face_count_ = 0, vertex_count_ = 0;
    int passes_ = 0;
    void upload_block(const DrawParams& params, std::uint32_t instances);
    DrawStats draw_patches(std::uint32_t instances);
    void set_face_culling();

    gpu::Program cull_, scatter_roots_, decide_, scan_groups_, scatter_, displace_;
    // The draw programs (draw.frag), indexed [faded][measuring]: faded ones test depth after the
    // fragment stage (cross-faded draws, cut-outs); measuring ones compute each fragment's error in
    // pixels (counted frames, the error debug view). Each is compiled with only what it draws
    // (DM_MEASURE_ERROR, DM_FOLLOW_CONTROL, DM_PBR): llvmpipe runs every branch of a fragment
    // program for every fragment, and the error's lookup of the finest surface, run masked on
    // frames that do not want it, was a third of an 800x600 frame (docs/RESULTS.md "The displaced
    // mesh's draw programs, compiled for what they draw"). patches_: the same for --subdivision tess.
    gpu::Program draw_[2][2], patches_[2][2];
    // packages with coverage: the cut-out pre-pass (draw.frag DM_DEPTH_ONLY, late depth tests)
    gpu::Program depth_only_;
    Status compile_draw_programs(); // for the package and moved_
    // this draw's program of draw_ or patches_: late depth tests (unless after the cut-out
    // pre-pass, whose shading pass writes no depth), measuring
    const gpu::Program& chosen(gpu::Program (&programs)[2][2], bool after_pre_pass = false) const
    {
        bool late_tests = !after_pre_pass && (faded_ || cutouts_ || cull_in_shader_);
        return programs[late_tests][counters_->counting() || debug_code_ == DEBUG_VIEW_ERROR];
    }
    bool tessellated_ = false; // --subdivision tess
    bool faded_ = false; // this draw is part of a cross-fade (DrawParams::fade)
    // the package stores coverage (issue #14): every draw discards cut-outs, so every draw tests
    // depth after the fragment stage (the faded programs, or the pre-pass depth_only_), or the
    // holes would still write depth
    bool cutouts_ = false;
    bool cull_back_faces_ = false; // the package's back_faces is cull
    // this draw's instances include a mirroring transform, which turns its faces' winding: one draw
    // holds every instance, so draw.frag culls back faces instead of GL (late depth tests, as a
    // discard needs)
    bool cull_in_shader_ = false;
    int shading_segments_ = 0;           // the shading pattern's segments per edge
    std::uint32_t shading_per_face_ = 0; // and its samples per face
    gpu::Query primitives_query_;
    gpu::Buffer pbr_; // PBR packages only (issue #14)
    // faces drawn with the source's textures (source_textures.h): their records and the textures
    gpu::Buffer face_textures_;
    std::vector<gpu::Texture> source_textures_; // one array per size class, at most k_max_source_arrays
    gpu::Buffer vertices_, faces_, elevations_, shading_, refine_block_, state_, scan_, groups_, final_;
    gpu::Buffer displaced_; // the final list's vertices, displaced (displace.comp): a vec4 each
    gpu::Buffer lists_[2];
    std::uint64_t list_capacity_ = 0, final_capacity_ = 0, scan_capacity_ = 0;
    gpu::VertexArray empty_vertex_array_;
    gpu::FrameResources frame_;
    RefineCounters refine_counters_;
    std::unique_ptr<gpu::Counters> counters_; // fragments, fetches, then DM_COUNTER_ERROR_SUM and _MAX
    std::vector<ControlVertex> rest_; // the package's control vertices with their rest frames
    bool moved_ = false; // update_control was called: shading normals follow the control mesh
};

Status Impl::init(const DisplacedMeshPackage& package, const RendererSettings& settings)
{
    settings_ = settings;
    Result<int> debug = debug_view_code(settings.debug_view);
    if (!debug) return debug.status();
    debug_code_ = *debug;
    if (!(settings.tau > 0.0f)) return error(StatusCode::invalid_argument, "--tau: must be greater than 0");
    STANDIN_RETURN_IF_ERROR(check_buffer_sizes(package, settings.max_storage_block_bytes));
    layout_ = package.layout();
    face_count_ = std::uint32_t(package.face_count());
    vertex_count_ = std::uint32_t(package.positions.size());
    passes_ = refinement_passes(layout_.degree, settings.max_depth);

    struct Stage {
        gpu::Program* program;
        const char* source;
    };
    for (Stage s : {Stage{&cull_, "cull.comp"}, Stage{&scatter_roots_, "scatter_roots.comp"}, Stage{&decide_, "decide.comp"},
                    Stage{&scan_groups_, "scan_groups.comp"}, Stage{&scatter_, "scatter.comp"},
                    Stage{&displace_, "displace.comp"}}) {
        Result<gpu::Program> program = gpu::Program::create({std::string("reps/displaced_mesh/shaders/") + s.source});
        if (!program) return program.status();
        *s.program = std::move(*program);
    }
    if (settings.subdivision == "tess") {
        tessellated_ = true;
        primitives_query_ = gpu::make_query(GL_PRIMITIVES_GENERATED);
    } else if (settings.subdivision != "leb") {
        return error(StatusCode::invalid_argument, "--subdivision: must be leb or tess, not '" + settings.subdivision + "'");
    }

    // the package on the GPU: control vertices (updatable), per-face data, elevations, shading
    // each vertex's rest frame: its normal and the direction to a neighbour (the next corner of
    // its first face), so that a moved control mesh turns the maps' normals with it
    rest_ = std::vector<ControlVertex>(vertex_count_);
    for (std::size_t v = 0; v < rest_.size(); ++v) {
        std::uint32_t neighbour = std::uint32_t(v);
        if (!package.topology.vertex_faces[v].empty()) {
            std::uint32_t f = package.topology.vertex_faces[v].front();
            int k = 0;
            while (package.indices[3 * f + std::size_t(k)] != v) ++k;
            neighbour = package.indices[3 * f + std::size_t((k + 1) % 3)];
        }
        glm::vec3 n = package.normals[v], t = package.positions[neighbour] - package.positions[v];
        t -= glm::dot(t, n) * n;
        t = glm::length(t) > 0.0f ? glm::normalize(t) : glm::vec3(1.0f, 0.0f, 0.0f);
        rest_[v] = {glm::vec4(package.positions[v], 1.0f), glm::vec4(n, 0.0f), glm::vec4(n, 0.0f), glm::vec4(t, 0.0f),
                    glm::uvec4(neighbour, 0u, 0u, 0u)};
    }
    vertices_ = gpu::make_buffer(rest_, GL_DYNAMIC_STORAGE_BIT);
    // faces with a cut-out sample: their parts are seen into, so they keep their back faces
    std::vector<std::uint8_t> see_through(face_count_, 0);
    if (!package.coverage.empty() && face_count_ > 0) {
        const std::size_t per_face = package.coverage.size() / face_count_;
        for (std::size_t i = 0; i < package.coverage.size(); ++i)
            if (package.coverage[i] == 0) see_through[i / per_face] = 1;
    }
    // and faces alpha-tested with the source's texture, whose samples may all be covered
    const SourceTextures& source_textures = package.source_textures;
    bool textured_cutouts = false;
    for (std::size_t f = 0; f < source_textures.faces.size(); ++f)
        if (source_textures.faces[f].layer != k_no_texture && source_textures.faces[f].cutoff > 0.0f)
            see_through[f] = 1, textured_cutouts = true;
    std::vector<FaceRefineData> prepared = prepare_faces(package.positions, package.normals, package.indices, package.topology,
                                                         layout_, package.elevations, package.face_error, see_through);
    std::vector<FaceData> faces(face_count_);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const FaceRefineData& d = prepared[f];
        faces[f].corners = glm::uvec4(package.indices[3 * f], package.indices[3 * f + 1], package.indices[3 * f + 2],
                                      package.topology.face_edge_reversed[f]);
        faces[f].weights = glm::vec4(d.edge_weight[0], d.edge_weight[1], d.edge_weight[2], d.interior_weight);
        faces[f].range = glm::vec4(d.h_min, d.h_max, d.cone_half_angle, d.normal_shrink);
        faces[f].extra = glm::vec4(d.grid_length, 0.0f, 0.0f, 0.0f);
        faces[f].curvature = glm::vec4(d.edge_curvature[0], d.edge_curvature[1], d.edge_curvature[2], d.interior_curvature);
    }
    faces_ = gpu::make_buffer(faces);
    elevations_ = gpu::make_buffer(package.elevations);
    std::vector<glm::uvec2> shading(package.shading_normals.size());
    // with coverage, it takes the albedo's alpha byte (which the shading never reads): one fetch
    // gives colour and coverage, interpolated alike
    cutouts_ = !package.coverage.empty() || textured_cutouts;
    cull_back_faces_ = package.settings.back_faces == "cull";
    shading_segments_ = package.shading_segments();
    shading_per_face_ = std::uint32_t(package.shading_samples_per_face());
    for (std::size_t i = 0; i < shading.size(); ++i) {
        std::uint32_t albedo = package.albedo[i];
        if (cutouts_) albedo = (albedo & 0x00ffffffu) | (package.coverage.empty() ? 0xff000000u : std::uint32_t(package.coverage[i]) << 24);
        shading[i] = {package.shading_normals[i], albedo};
    }
    shading_ = gpu::make_buffer(shading);
    if (!package.orm.empty()) {
        std::vector<glm::uvec2> pbr(package.orm.size());
        for (std::size_t i = 0; i < pbr.size(); ++i) pbr[i] = {package.orm[i], package.emission[i]};
        pbr_ = gpu::make_buffer(pbr);
    }
    if (!source_textures.faces.empty()) {
        STANDIN_RETURN_IF_ERROR(check_source_texture_size(source_textures));
        // a record names its array in the layer's top bits (draw.frag); layers repeated across an
        // array layer (their size divides the array's) read at their UVs times the layer's scale:
        // the records' UVs are scaled here, derivatives follow
        gpu::SourceTextureArrays arrays = gpu::upload_source_texture_arrays(source_textures.layers, k_max_source_arrays);
        std::vector<FaceTexture> records = source_textures.faces;
        for (FaceTexture& r : records) {
            if (r.layer >= arrays.uv_scale.size()) continue;
            for (glm::vec2& uv : r.uv) uv *= arrays.uv_scale[r.layer];
            r.layer = (arrays.array_of[r.layer] << DM_SOURCE_ARRAY_SHIFT) | arrays.layer_of[r.layer];
        }
        source_textures_ = std::move(arrays.arrays);
        face_textures_ = gpu::make_buffer(records);
    }
    STANDIN_RETURN_IF_ERROR(compile_draw_programs());
    refine_block_ = gpu::make_buffer(nullptr, sizeof(RefineBlock), GL_DYNAMIC_STORAGE_BIT);
    std::vector<std::uint32_t> zero(DM_STATE_UINTS, 0u);
    state_ = gpu::make_buffer(zero, GL_DYNAMIC_STORAGE_BIT);
    counters_ = std::make_unique<gpu::Counters>(DM_COUNTER_COUNT);
    empty_vertex_array_ = gpu::make_vertex_array();
    ensure_capacity(k_initial_records, k_initial_records);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "displaced mesh: " + gpu::gl_error_text(e) + " while uploading");
    return Status::ok();
}

Status Impl::compile_draw_programs()
{
    for (int faded = 0; faded < 2; ++faded) {
        for (int measuring = 0; measuring < 2; ++measuring) {
            std::vector<std::pair<std::string, std::string>> defines = {
                {"DM_MEASURE_ERROR", measuring ? "1" : "0"}, {"DM_FOLLOW_CONTROL", moved_ ? "1" : "0"}, {"DM_PBR", pbr_ ? "1" : "0"},
                {"DM_SOURCE_TEXTURES", face_textures_ ? "1" : "0"},
                {"DM_SOURCE_ARRAYS", std::to_string(std::max<std::size_t>(1, source_textures_.size()))}};
            if (faded) defines.push_back({"DM_FADED", "1"});
            Result<gpu::Program> draw =
                gpu::Program::create({"reps/displaced_mesh/shaders/draw.vert", "reps/displaced_mesh/shaders/draw.frag"}, defines);
            if (!draw) return draw.status();
            draw_[faded][measuring] = std::move(*draw);
            if (faded && !measuring && cutouts_ && settings_.cut_out_pre_pass && !tessellated_) {
                defines.push_back({"DM_DEPTH_ONLY", "1"});
                Result<gpu::Program> depth_only =
                    gpu::Program::create({"reps/displaced_mesh/shaders/draw.vert", "reps/displaced_mesh/shaders/draw.frag"}, defines);
                if (!depth_only) return depth_only.status();
                depth_only_ = std::move(*depth_only);
                defines.pop_back();
            }
            if (!tessellated_) continue;
            Result<gpu::Program> patches = gpu::Program::create(
                {"reps/displaced_mesh/shaders/patch.vert", "reps/displaced_mesh/shaders/patch.tesc",
                 "reps/displaced_mesh/shaders/patch.tese", "reps/displaced_mesh/shaders/draw.frag"},
                defines);
            if (!patches) return patches.status();
            patches_[faded][measuring] = std::move(*patches);
        }
    }
    return Status::ok();
}

void Impl::ensure_capacity(std::uint64_t list_records, std::uint64_t final_records)
{
    list_records = std::min(list_records, k_max_records);
    final_records = std::min(final_records, k_max_records);
    if (list_records > list_capacity_) {
        list_capacity_ = list_records;
        for (gpu::Buffer& list : lists_) list = gpu::make_buffer(nullptr, list_capacity_ * DM_RECORD_UINTS * 4);
    }
    if (final_records > final_capacity_) {
        final_capacity_ = final_records;
        final_ = gpu::make_buffer(nullptr, final_capacity_ * DM_RECORD_UINTS * 4);
        displaced_ = gpu::make_buffer(nullptr, final_capacity_ * 3 * sizeof(glm::vec4));
    }
}

void Impl::dispatch(const gpu::Program& program, GLuint groups)
{
    program.use();
    glDispatchCompute(std::max(groups, 1u), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT | GL_UNIFORM_BARRIER_BIT);
}

void Impl::dispatch_indirect(const gpu::Program& program, std::uint32_t parity)
{
    program.use();
    glDispatchComputeIndirect(GLintptr((DM_STATE_DISPATCH + 3 * parity) * sizeof(std::uint32_t)));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
}

// The refinement block of this draw and the package's buffers, bound.
void Impl::upload_block(const DrawParams& params, std::uint32_t instances)
{
    RefineView view = make_refine_view(params.camera, params.viewport.y, glm::mat4(1.0f));
    RefineBlock block;
    block.clip_from_view = params.camera.clip_from_view;
    block.view_terms = glm::vec4(settings_.tau, view.pixels_per_unit, view.near_plane, view.orthographic ? 1.0f : 0.0f);
    block.counts = glm::uvec4(face_count_, instances, std::uint32_t(layout_.segments), std::uint32_t(layout_.exponent));
    block.options = glm::uvec4(std::uint32_t(settings_.criterion), settings_.mip ? 1u : 0u, settings_.cull ? 1u : 0u,
                               std::uint32_t(debug_code_));
    block.capacities = glm::uvec4(std::uint32_t(list_capacity_), std::uint32_t(final_capacity_),
                                  std::uint32_t(layout_.samples_per_face), std::uint32_t(layout_.finest_samples));
    block.error_terms = glm::vec4(settings_.error_scale > 0.0f ? settings_.error_scale : settings_.tau, moved_ ? 1.0f : 0.0f, settings_.outline, 0.0f);
    glNamedBufferSubData(refine_block_.get(), 0, sizeof block, &block);
    std::uint32_t zero = 0;
    glClearNamedBufferSubData(state_.get(), GL_R32UI, 0, DM_STATE_UINTS * sizeof(std::uint32_t), GL_RED_INTEGER,
                              GL_UNSIGNED_INT, &zero);
    counters_->bind();

    glBindBufferBase(GL_UNIFORM_BUFFER, DM_REFINE_UBO, refine_block_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_VERTICES_SSBO, vertices_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_FACES_SSBO, faces_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_ELEVATIONS_SSBO, elevations_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_STATE_SSBO, state_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_SHADING_SSBO, shading_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_PBR_SSBO, pbr_ ? pbr_.get() : 0u);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_FACE_TEXTURE_SSBO, face_textures_ ? face_textures_.get() : 0u);
    for (int a = 0; a < k_max_source_arrays; ++a)
        glBindTextureUnit(DM_SOURCE_TEXTURE_UNIT + a, std::size_t(a) < source_textures_.size() ? source_textures_[std::size_t(a)].get() : 0u);
}

void Impl::run_passes(const DrawParams& params, std::uint32_t instances)
{
    // scan buffers hold one entry per element of the largest list a pass may see
    std::uint64_t elements = std::max<std::uint64_t>(std::uint64_t(face_count_) * instances, list_capacity_);
    if (elements > scan_capacity_) {
        scan_capacity_ = elements;
        scan_ = gpu::make_buffer(nullptr, scan_capacity_ * 16);
        groups_ = gpu::make_buffer(nullptr, (scan_capacity_ / DM_GROUP_SIZE + 1) * 8);
    }
    upload_block(params, instances);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_SCAN_SSBO, scan_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_GROUPS_SSBO, groups_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_FINAL_SSBO, final_.get());
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, state_.get());
    glMemoryBarrier(GL_ALL_BARRIER_BITS);

    // cull into list 0 (the cull pass has parity 1: it writes the counts of slot 0)
    GLuint root_groups = GLuint((std::uint64_t(face_count_) * instances + DM_GROUP_SIZE - 1) / DM_GROUP_SIZE);
    for (const gpu::Program* p : {&cull_, &scan_groups_, &scatter_roots_}) glProgramUniform1ui(p->id(), p->uniform("parity"), 1u);
    glProgramUniform1ui(scan_groups_.id(), scan_groups_.uniform("after_cull"), 1u);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_LIST_OUT_SSBO, lists_[0].get());
    dispatch(cull_, root_groups);
    dispatch(scan_groups_, 1);
    dispatch(scatter_roots_, root_groups);

    // bisect: pass p reads list p % 2 and writes the other
    glProgramUniform1ui(scan_groups_.id(), scan_groups_.uniform("after_cull"), 0u);
    for (int pass = 0; pass < passes_; ++pass) {
        std::uint32_t parity = std::uint32_t(pass % 2);
        for (const gpu::Program* p : {&decide_, &scan_groups_, &scatter_}) glProgramUniform1ui(p->id(), p->uniform("parity"), parity);
        glProgramUniform1ui(decide_.id(), decide_.uniform("last_pass"), pass == passes_ - 1 ? 1u : 0u);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_LIST_IN_SSBO, lists_[parity].get());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_LIST_OUT_SSBO, lists_[1 - parity].get());
        dispatch_indirect(decide_, parity);
        dispatch(scan_groups_, 1);
        dispatch_indirect(scatter_, parity);
    }
}

std::vector<std::uint32_t> Impl::read_state()
{
    std::vector<std::uint32_t> state(DM_STATE_UINTS);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(state_.get(), 0, GLsizeiptr(state.size() * sizeof(std::uint32_t)), state.data());
    return state;
}

DrawStats Impl::draw(const DrawParams& params)
{
    frame_.bind(params);
    faded_ = params.fade.incoming || params.fade.amount > 0.0f;
    cull_in_shader_ = cull_back_faces_ && frame_.any_instance_mirrors();
    std::uint32_t instances = std::uint32_t(frame_.instance_count());
    if (settings_.subdivision == "tess") {
        upload_block(params, instances);
        return draw_patches(instances);
    }

    // refine; when a list overflowed, grow the lists and refine again
    std::vector<std::uint32_t> state;
    for (;;) {
        run_passes(params, instances);
        state = read_state();
        bool short_of_room = state[DM_STATE_OVERFLOWED] > 0 || state[DM_STATE_DROPPED] > 0;
        if (!short_of_room || (list_capacity_ >= k_max_records && final_capacity_ >= k_max_records)) break;
        ensure_capacity(list_capacity_ * 2, final_capacity_ * 2);
    }
    refine_counters_ = {state[DM_STATE_VISIBLE], state[DM_STATE_PROCESSED], state[DM_STATE_FINAL], state[DM_STATE_CAPPED],
                        state[DM_STATE_OVERFLOWED], state[DM_STATE_DROPPED]};

    // draw the final list; packages with coverage first draw it to depth alone through the cut-out
    // test, then shade only the fragments at that depth (GL_EQUAL, early tests, no depth writes):
    // one shaded fragment per pixel instead of one per overlapping leaf card. Same pictures (the
    // nearest fragment that is not cut out). Draws every triangle twice (displaced once, before:
    // displace.comp): on llvmpipe at 800x600 the bushes' frames -25-30%, the trees' within the
    // noise (cards a pixel or two across, or few behind each other); docs/RESULTS.md.
    // (--no-cut-out-pre-pass draws one pass.)
    const void* draw_record = reinterpret_cast<const void*>(std::uintptr_t(DM_STATE_DRAW * sizeof(std::uint32_t)));
    const std::uint32_t vertex_count = state[DM_STATE_DRAW];
    glProgramUniform1ui(displace_.id(), displace_.uniform("vertex_count"), vertex_count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, DM_DISPLACED_SSBO, displaced_.get());
    dispatch(displace_, GLuint((std::uint64_t(vertex_count) + DM_GROUP_SIZE - 1) / DM_GROUP_SIZE)); // (its barrier covers the draw's reads)
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, state_.get());
    glBindVertexArray(empty_vertex_array_.get());
    glEnable(GL_DEPTH_TEST);
    set_face_culling();
    bool pre_pass = depth_only_.id() != 0;
    GLboolean color_mask[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
    if (pre_pass) {
        glProgramUniform1i(depth_only_.id(), depth_only_.uniform("has_coverage"), 1);
        glProgramUniform1i(depth_only_.id(), depth_only_.uniform("cull_in_shader"), cull_in_shader_ ? 1 : 0);
        glProgramUniform1i(depth_only_.id(), depth_only_.uniform("shading_segments"), shading_segments_);
        glProgramUniform1ui(depth_only_.id(), depth_only_.uniform("shading_per_face"), shading_per_face_);
        glGetBooleanv(GL_COLOR_WRITEMASK, color_mask);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        depth_only_.use();
        glDrawArraysIndirect(GL_TRIANGLES, draw_record);
        glColorMask(color_mask[0], color_mask[1], color_mask[2], color_mask[3]);
        glDepthMask(GL_FALSE);
        glDepthFunc(GL_EQUAL);
    }
    // a depth-only target (a shadow map) has nothing left to shade
    bool shade = !pre_pass || color_mask[0] || color_mask[1] || color_mask[2] || color_mask[3];
    const gpu::Program& draw_program = chosen(draw_, pre_pass);
    glProgramUniform1i(draw_program.id(), draw_program.uniform("counting"), counters_->counting() ? 1 : 0);
    glProgramUniform1i(draw_program.id(), draw_program.uniform("has_coverage"), cutouts_ ? 1 : 0);
    glProgramUniform1i(draw_program.id(), draw_program.uniform("has_pbr_maps"), pbr_ ? 1 : 0);
    glProgramUniform1i(draw_program.id(), draw_program.uniform("shading_segments"), shading_segments_);
    glProgramUniform1ui(draw_program.id(), draw_program.uniform("shading_per_face"), shading_per_face_);
    glProgramUniform1i(draw_program.id(), draw_program.uniform("cull_in_shader"), cull_in_shader_ ? 1 : 0);
    if (shade) {
        draw_program.use();
        glDrawArraysIndirect(GL_TRIANGLES, draw_record);
    }
    if (pre_pass) {
        glDepthFunc(GL_LESS);
        glDepthMask(GL_TRUE);
    }
    glBindVertexArray(0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    if (counters_->counting()) glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    return {std::uint64_t(2 + 3 * passes_ + 1 + (pre_pass && shade ? 2 : 1)), refine_counters_.rendered};
}

// Both sides drawn, or back faces culled for packages of single-sided sheets (back_faces cull):
// by GL, or by draw.frag where an instance mirrors (cull_in_shader_).
void Impl::set_face_culling()
{
    if (cull_back_faces_ && !cull_in_shader_) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    } else {
        glDisable(GL_CULL_FACE);
    }
}

// The tessellation baseline: every control face of every instance as one patch; the triangles the
// tessellator made are counted with a GL_PRIMITIVES_GENERATED query.
DrawStats Impl::draw_patches(std::uint32_t instances)
{
    const gpu::Program& patches = chosen(patches_);
    glProgramUniform1i(patches.id(), patches.uniform("counting"), counters_->counting() ? 1 : 0);
    glProgramUniform1i(patches.id(), patches.uniform("has_coverage"), cutouts_ ? 1 : 0);
    glProgramUniform1i(patches.id(), patches.uniform("has_pbr_maps"), pbr_ ? 1 : 0);
    glProgramUniform1i(patches.id(), patches.uniform("shading_segments"), shading_segments_);
    glProgramUniform1ui(patches.id(), patches.uniform("shading_per_face"), shading_per_face_);
    glProgramUniform1i(patches.id(), patches.uniform("cull_in_shader"), cull_in_shader_ ? 1 : 0);
    glBindVertexArray(empty_vertex_array_.get());
    glEnable(GL_DEPTH_TEST);
    set_face_culling();
    glPatchParameteri(GL_PATCH_VERTICES, 3);
    patches.use();
    glBeginQuery(GL_PRIMITIVES_GENERATED, primitives_query_.get());
    glDrawArraysInstanced(GL_PATCHES, 0, GLsizei(3 * face_count_), GLsizei(instances));
    glEndQuery(GL_PRIMITIVES_GENERATED);
    glBindVertexArray(0);
    GLuint64 generated = 0;
    glGetQueryObjectui64v(primitives_query_.get(), GL_QUERY_RESULT, &generated);
    refine_counters_ = {};
    refine_counters_.rendered = generated;
    refine_counters_.processed = std::uint64_t(face_count_) * instances;
    if (counters_->counting()) glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    return {1, generated};
}

ErrorCounters Impl::read_error_counters()
{
    ErrorCounters out;
    out.fragments = counters_->read(COUNTER_FRAGMENTS);
    double sum = double(counters_->read(DM_COUNTER_ERROR_SUM));
    out.error_mean_px = out.fragments ? sum / DM_ERROR_UNITS / double(out.fragments) : 0.0;
    out.error_max_px = double(counters_->read(DM_COUNTER_ERROR_MAX)) / DM_ERROR_UNITS;
    return out;
}

Status Impl::update_control(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals)
{
    if (positions.size() != vertex_count_ || normals.size() != vertex_count_)
        return error(StatusCode::invalid_argument, "displaced mesh: update_control needs " + std::to_string(vertex_count_) +
                                                       " positions and normals");
    std::vector<ControlVertex> vertices = rest_;
    for (std::size_t v = 0; v < vertices.size(); ++v)
        vertices[v].position = glm::vec4(positions[v], 1.0f), vertices[v].normal = glm::vec4(normals[v], 0.0f);
    glNamedBufferSubData(vertices_.get(), 0, GLsizeiptr(vertices.size() * sizeof(ControlVertex)), vertices.data());
    if (!moved_) { // from now on the shading normals follow the control mesh: programs that turn them
        moved_ = true;
        return compile_draw_programs();
    }
    return Status::ok();
}

} // namespace

Result<std::unique_ptr<DisplacedRenderer>> DisplacedRenderer::create(const DisplacedMeshPackage& package, const RendererSettings& settings)
{
    if (!gpu::has_current_context()) return error(StatusCode::gpu_error, "displaced mesh: no current OpenGL context");
    auto renderer = std::make_unique<Impl>();
    STANDIN_RETURN_IF_ERROR(renderer->init(package, settings));
    return std::unique_ptr<DisplacedRenderer>(std::move(renderer));
}

RendererSettings renderer_settings(const RenderSettings& settings)
{
    RendererSettings out;
    out.tau = settings.options.number("tau");
    parse_criterion(settings.options.choice("criterion"), out.criterion);
    out.cull = settings.options.flag("cull");
    out.mip = settings.options.flag("mip");
    out.subdivision = settings.options.choice("subdivision");
    out.cut_out_pre_pass = settings.options.flag("cut-out-pre-pass");
    out.outline = settings.options.number("outline");
    out.debug_view = settings.debug_view;
    return out;
}

Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings)
{
    Result<std::unique_ptr<DisplacedRenderer>> renderer =
        DisplacedRenderer::create(reps::package_cast<DisplacedMeshPackage>(package), renderer_settings(settings));
    if (!renderer) return renderer.status();
    return std::unique_ptr<Renderer>(std::move(*renderer));
}

} // namespace standin::displaced_mesh
