// The GPU renderer of enhanced billboards: per-pixel ray casting of each billboard's height field
// inside its box (Vichitvejpaisal 2005 §3.3; Vichitvejpaisal & Kanongchaiyos 2006 Fig. 7), with
// the coarse mesh filling holes (000 §3.4).
// Differences from the paper, all in shaders/march.frag:
//  - default march "exact": the depth map is treated as a sheet of texel columns whose neighbours
//    on one surface are joined by walls; the crossing is exact and independent of step size, found
//    through a min/max depth pyramid (Tevs, Ihrke & Seidel, "Maximum Mipmaps", I3D 2008) built at
//    load time (acceleration.cpp). "seed" keeps the paper's linear march and its holes.
//  - every hit writes its true depth (conservative depth layout, so early depth testing stays);
//  - boxes that cross the near plane are drawn from their back faces, rays starting at the eye;
//  - the coarse mesh is depth-tested against the billboards' own hits (per-pixel images), not
//    only the depth buffer, so it never covers a front hit it lies a little in front of; with
//    --coarse-fill near-misses it fills only pixels where rays came near a surface and missed;
//  - colour is the mean of the texels under the pixel that continue the hit's surface without a
//    crease (a mip pyramid of one-surface cells built at load, build_color_pyramid, and bilinear
//    weights over smooth links), as the truth filters its textures; the paper reads the hit texel
//    (--color-filter texel), which is noise on textured models seen from afar.
// Proxies: instead of the paper's one box per billboard (which covers nearly the whole model, so
// every pixel marched ~5 boxes), every occupied 16 x 16-texel tile of a billboard is a box of its
// own, as tight as its covered texels and their depths (build_tiles): empty tiles draw nothing and
// rays inside a tile are short. A tile's box is sheared to follow a plane fitted to its depths
// (TileBox::slope), so on tilted or rough surfaces a ray enters it next to the surface, not at the
// top of a box as deep as the tile's whole depth change (noisy sphere, 800x600: 24.5 -> 17.4
// fetches and 5.97 -> 4.05 fragments per covered pixel; with the march's start at the texel and
// one-level climbs, 11.0 fetches). Where a tile holds texels at depths far apart (the nested parts
// of an assembly), each depth layer gets a box of its own (build_tiles), so the empty depth between
// them is neither drawn nor marched (2CylinderEngine, 800x600: 72.5 -> 16.6 fetches, 108 -> 28
// fragments per covered pixel, the same picture). Each frame the CPU sorts instances and tiles front
// to back and the shader stops every ray at the nearest front hit already found at its pixel, so
// boxes behind the visible surface cost a few instructions, not a march. Instances whose tiles would
// be small on screen draw coarse tiles of 64 x 64 texels (layered the same way), those smaller
// still (and the "seed" march) one box per billboard, and the march stops at pyramid nodes no wider
// than half a pixel (level of detail: far instances in a crowd walk a few nodes, not texels).
// The CPU also leaves out proxies whose texels' normals (a cone per proxy, built at load) all face
// away from the eye (--cull-back-proxies): llvmpipe starts a fragment for every pixel of every box,
// however early its ray stops (ns235k, 800x600: 3.80 -> 2.16 fragments per covered pixel). By
// default only for packages of one closed surface, or of one part whose backs face its own inside
// (bake.cpp one_closed_surface, backs_unseen): elsewhere a back hit can be the surface to show (an
// open sheet's back, a part's inside through a seam), and the coarse mesh or what lies behind
// would show instead (docs/RESULTS.md). And it leaves out proxies hidden from the eye's cell of
// view directions (--cull-hidden-proxies, hidden_proxies.h: nested parts; 2CylinderEngine, 800x600:
// 9.62 -> 6.79 fragments per covered pixel, 406 -> 230 ms).
// All boxes of all instances are one instanced draw driven by a per-frame (instance, tile) list
// (before it, one for the boxes that may cross the near plane); textures are 2D arrays, one layer
// per billboard, read with texelFetch (no filtering, so the empty background never bleeds into the colour).
// Debug view "proxies" draws every billboard's box over the shaded picture as lines (boxes.vert).
#include "reps/enhanced_billboards/acceleration.h"
#include "reps/enhanced_billboards/billboards.h"
#include "reps/enhanced_billboards/hidden_proxies.h"
#include "reps/common/block_compress.h"
#include "reps/common/coarse_mesh.h"
#include "reps/common/depth_batches.h"
#include "reps/common/package_cast.h"
#include <standin/log.h>

#include "gpu/counters.h"
#include "gpu/frame.h"
#include "gpu/gl.h"
#include "gpu/mesh_buffers.h"
#include "gpu/shaders/common/bindings.h"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <numbers>
#include <tuple>
#include <span>

namespace standin::billboards {

namespace {

// std430 mirror of BillboardData in shaders/billboard.glsl
struct BillboardGpu {
    glm::mat4 object_from_box;
    glm::mat4 box_from_object;
    glm::ivec4 info; // layer, the surface map's range unit (pack_surface), width, height
    glm::vec4 box_min, box_max;
    glm::ivec4 offset; // xy: texel offset of the billboard's maps in its layer (pack_layers)
};
static_assert(sizeof(BillboardGpu) == 192, "std430 layout of BillboardData");
static_assert(k_texel_clipped == (1u << TEXEL_LINE_LOW_BIT) && (k_smooth_plus_v >> TEXEL_LINE_HIGH_SHIFT) == 0 &&
                  EDGE_LINE_ANGLES * EDGE_LINE_OFFSETS + 1 <= 127 && k_texel_covered == TEXEL_COVERED && k_smooth_plus_u == SMOOTH_PLUS_U &&
                  k_smooth_minus_v == SMOOTH_MINUS_V && (k_link_plus_v << k_smooth_link_shift) == k_smooth_plus_v,
              "surface flags of march.frag");

// std430 mirror of TileData in shaders/billboard.glsl
struct TileGpu {
    glm::vec4 box_min, box_max; // w: the plane's slope along x (min) and y (max)
    glm::ivec4 info; // billboard, highest pyramid level, 1: start at the ray footprint's level (whole boxes, coarse tiles), unused
};
static_assert(sizeof(TileGpu) == 48, "std430 layout of TileData");

// a margin of a hundredth of a texel in depth keeps flat sheets inside their box
constexpr float k_depth_margin = 1e-4f;

// The box of the covered texels and their depth ranges (their walls and tilted tops), in box space (a billboard's box is often larger
// than what it holds; a tighter box means fewer fragments and shorter rays). Empty: min > max.
void covered_box(const HeightFieldAcceleration& acc, const Billboard& b, BillboardGpu& g)
{
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            const SurfaceTexel& texel = acc.surface[std::size_t(j) * acc.width + i];
            if (!(texel.flags & k_texel_covered)) continue;
            lo = glm::min(lo, glm::vec3(float(i), float(j), reps::decode_depth(texel.min)));
            hi = glm::max(hi, glm::vec3(float(i + 1), float(j + 1), reps::decode_depth(texel.max)));
        }
    }
    g.box_min = glm::vec4(lo - glm::vec3(0.0f, 0.0f, k_depth_margin), 0.0f);
    g.box_max = glm::vec4(hi + glm::vec3(0.0f, 0.0f, k_depth_margin), 0.0f);
}

// tiles of 2^4 texels: a tile proxy per 16 x 16 texels; or more where the package's texels are
// finer than 1/1024 of the model's diagonal (fine_tile_level)
constexpr int k_tile_level = 4;
constexpr double k_tile_diagonal_fraction = 16.0 / 1024.0;
// a tile's depth layers get boxes of their own where they lie this many tile widths apart (build_tiles)
constexpr double k_tile_layer_gap = 0.25;
// coarse tiles of 2^6 texels, for instances whose tiles would be small on screen
constexpr int k_coarse_tile_level = 6;
// instances whose tiles would cover fewer pixels across than this draw coarse tiles, and those
// whose coarse tiles would, one box per billboard
constexpr float k_min_tile_pixels = 6.0f;
// Instances smaller than this on screen (bounding-sphere radius in pixels) get no coarse mesh: a
// hole cannot show on them. Without the coarse mesh the exact march leaves about 0.02% of the
// covered pixels as holes (noisy sphere, thesis protocol), so an instance of radius r px expects
// 0.0002 * pi * r^2 hole pixels: under one pixel below r = 40 px. In crowds the coarse mesh (10% of
// the faces per instance, more where that strays over a texel) costs more than all the billboards
// together (1000 copies of a 235k-face model on llvmpipe: 13.3 s with it at r >= 16 px, 2.8 s
// without; 7.0 s at r >= 32 px).
constexpr float k_min_coarse_radius_pixels = 40.0f;
// Those instances draw the coarsest level of the coarse mesh (reps::coarse_mesh_levels) that lies
// within this many pixels of the coarse mesh: it fills the same holes, with a quarter of the
// triangles a level (1000 copies of a 252k-face head at 800x600 on llvmpipe: 25k triangles on each
// of the near instances took a third of the frame; docs/RESULTS.md).
constexpr float k_coarse_level_pixels = 0.5f;
// march.frag's level of detail ends the walk at pyramid nodes no wider than half a pixel, from 4
// texels per pixel (pixel_level >= 1): an instance that cannot reach that anywhere on screen is
// drawn by the program without it (MARCH_LOD 0), whose loop is shorter (the contact test's code,
// run masked at every closer look on llvmpipe: 8% of ns235k's frame at 800x600).
constexpr float k_lod_texels_per_pixel = 4.0f;
// Depth batches of one instance's boxes (front_batch_ends): worth their resolves where the boxes lie
// deep behind each other. box_overdraw estimates that without a view: the boxes' mean projected
// area over the model's bounding disc. Measured at 800x600 on llvmpipe (CPU, the single stand-in,
// batches of 64, 256, 1024, ... boxes against one draw): a 108k-face assembly of nested parts (1.23)
// 373-390 -> 206-214 ms, a generated 4k-face tree (4.11) 1210 -> 790, a teapot (0.94) 262-271 ->
// 179-208; but a scan (0.33) +5-15% and the bunny (0.24) +10-20%, whose boxes tile one surface.
// Batches of 64, 256, 1024, ... boxes; of 64, 128, 256, ... where box_overdraw is 2 or more: the
// held-out 2CylinderEngine (2.68, 43k boxes) 840-1070 -> 660-720 ms, the tree (4.11) 895-953 ->
// 760-850; the assembly (1.23) 213-240 -> 225-285 and the teapot 183-209 -> 201-250 with growth 2.
constexpr double k_box_batch_overdraw = 0.6, k_deep_box_overdraw = 2.0;
constexpr std::size_t k_first_box_batch = 64;

// What the CPU needs of a proxy box to sort and choose boxes each frame.
struct ProxyInfo {
    glm::vec3 centre_object; // of the box
    int billboard = 0;
    // a sphere around the box (object space), and a cone holding the stored normals of every covered
    // texel the box holds (half_angle over pi/2: they face every way)
    float radius = 0.0f;
    float mean_area = 0.0f; // the box's projected area averaged over view directions (Cauchy: surface / 4), object units
    glm::vec3 normal_axis{0.0f, 0.0f, 1.0f};
    float normal_half_angle = 4.0f;
};

// The cone of the stored normals of the covered texels in [lo, hi) of billboard `b`.
void texel_normal_cone(const Billboard& b, const HeightFieldAcceleration& acc, glm::ivec2 lo, glm::ivec2 hi, ProxyInfo& proxy)
{
    lo = glm::max(lo, glm::ivec2(0)), hi = glm::min(hi, glm::ivec2(b.width, b.height));
    auto normal_at = [&](int i, int j) {
        const std::uint16_t* n = &b.normal_depth.pixels[(std::size_t(j) * std::size_t(b.width) + std::size_t(i)) * 4];
        glm::vec3 v = glm::vec3(n[0], n[1], n[2]) / 32767.5f - 1.0f;
        float length = glm::length(v);
        return length > 0.0f ? v / length : glm::vec3(0.0f);
    };
    auto covered = [&](int i, int j) { return (acc.surface[std::size_t(j) * std::size_t(acc.width) + std::size_t(i)].flags & k_texel_covered) != 0; };
    glm::vec3 sum(0.0f);
    for (int j = lo.y; j < hi.y; ++j)
        for (int i = lo.x; i < hi.x; ++i)
            if (covered(i, j)) sum += normal_at(i, j);
    float length = glm::length(sum);
    if (!(length > 0.0f)) return; // none, or they cancel: no cone
    proxy.normal_axis = sum / length;
    float min_cos = 1.0f;
    for (int j = lo.y; j < hi.y; ++j)
        for (int i = lo.x; i < hi.x; ++i)
            if (covered(i, j)) min_cos = std::min(min_cos, glm::dot(proxy.normal_axis, normal_at(i, j)));
    proxy.normal_half_angle = std::acos(std::clamp(min_cos, -1.0f, 1.0f));
}

// The radius of a sphere around `centre` holding the (sheared, TileGpu) box `t` of billboard box space.
float proxy_radius(const glm::mat4& object_from_box, const TileGpu& t, glm::vec3 centre)
{
    float radius = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        glm::vec3 p((corner & 1) ? t.box_max.x : t.box_min.x, (corner & 2) ? t.box_max.y : t.box_min.y,
                    (corner & 4) ? t.box_max.z : t.box_min.z);
        p.z += t.box_min.w * p.x + t.box_max.w * p.y;
        radius = std::max(radius, glm::length(glm::vec3(object_from_box * glm::vec4(p, 1.0f)) - centre));
    }
    return radius;
}

// The mean over view directions of a tile box's projected area, object units (a convex body's is
// its surface area over 4, Cauchy): the box is a parallelepiped, sheared by the tile's slope.
float proxy_mean_area(const glm::mat4& object_from_box, const TileGpu& t)
{
    const glm::mat3 m(object_from_box);
    const glm::vec3 size = glm::vec3(t.box_max) - glm::vec3(t.box_min);
    const glm::vec3 a = m * glm::vec3(size.x, 0.0f, t.box_min.w * size.x), b = m * glm::vec3(0.0f, size.y, t.box_max.w * size.y),
                    c = m * glm::vec3(0.0f, 0.0f, size.z);
    return 0.5f * (glm::length(glm::cross(a, b)) + glm::length(glm::cross(b, c)) + glm::length(glm::cross(c, a)));
}

// Where the eye is, for culling proxies whose hits face away from it: its position in object space,
// or for an orthographic camera the direction to it.
struct BackCull {
    bool orthographic = false;
    glm::vec3 eye_object{0.0f};
};

// An instance that may cross the near plane: which of its proxies do (build_draw_list).
struct NearSplit {
    const glm::mat4* world_from_object = nullptr;
    float scale = 1.0f; // the largest axis scale of world_from_object
    const Camera* camera = nullptr;
};

// Whether a world-space sphere may reach the camera's near plane (with a margin for rounding): then
// what it holds is drawn from its back faces (the inside pass).
bool reaches_near_plane(glm::vec3 centre_world, float radius_world, const Camera& camera)
{
    return glm::dot(centre_world - camera.eye_world, camera.forward_world) - radius_world <= camera.near_plane * 1.01f;
}

// Whether `m` is a rotation times a uniform scale (mirrors included).
bool similarity(const glm::mat3& m)
{
    const float scale2 = glm::dot(m[0], m[0]), tolerance = 1e-4f * scale2;
    return std::abs(glm::dot(m[1], m[1]) - scale2) <= tolerance && std::abs(glm::dot(m[2], m[2]) - scale2) <= tolerance &&
           std::abs(glm::dot(m[0], m[1])) <= tolerance && std::abs(glm::dot(m[0], m[2])) <= tolerance &&
           std::abs(glm::dot(m[1], m[2])) <= tolerance;
}

// Whether every hit in the proxy is a back hit: each of its texels' normals faces away from every
// eye ray that can reach its sphere. `to_eye` (object space): the eye's position relative to the
// proxy's centre, or for an orthographic camera the direction to the eye (`orthographic`). For the
// normals n in the cone and points x in the sphere, max n.(eye - x) <= |v| cos(phi - half_angle) +
// radius, phi the angle between the cone's axis and v = eye - centre.
bool faces_away(const ProxyInfo& proxy, glm::vec3 to_eye, bool orthographic)
{
    float distance = glm::length(to_eye);
    if (!(distance > 0.0f) || proxy.normal_half_angle >= 0.5f * std::numbers::pi_v<float>) return false;
    float phi = std::acos(std::clamp(glm::dot(proxy.normal_axis, to_eye) / distance, -1.0f, 1.0f));
    float turn = phi - proxy.normal_half_angle;
    if (turn <= 0.5f * std::numbers::pi_v<float>) return false;
    // a margin of a thousandth of the distance for rounding (march.frag decides per hit in floats)
    return distance * std::cos(turn) + (orthographic ? 0.0f : proxy.radius) < -1e-3f * distance;
}

// One draw-list entry (std430 uvec2 in box.vert).
struct DrawEntry {
    std::uint32_t instance, tile;
};

// One vertex of the "boxes" debug view's lines (boxes.vert).
struct BoxLineVertex {
    glm::vec3 position_object;
    std::int32_t billboard = 0, front = 0; // front: on the front plane (depth 0)
};

struct ProgramLocations {
    GLint first_entry = -1, seed_steps = -1, seed_hit_range = -1, counting = -1, depth_batch = -1;
};

// What a march program compiles in (march.frag): settings fixed for the renderer's life are
// constants, not uniforms, since llvmpipe runs the code a uniform switches off too, masked, for
// every fragment (measured: 5-10% of ns235k's frame at 800x600; docs/RESULTS.md).
struct MarchProgramSettings {
    int march_mode = MARCH_EXACT, debug_view = DEBUG_VIEW_NONE;
    bool mark_pixels = false, has_pbr_maps = false, color_footprint = true, hide_back_hits = false;
};

// The march's passes: boxes in front of the near plane, boxes around the eye (back faces), and
// the front boxes of depth batches after the first (reps/common/depth_batches.h).
enum class MarchPass { front = 0, inside = 1, front_batched = 2 };

struct MarchProgram {
    gpu::Program program;
    ProgramLocations at;
    bool failed = false; // compiling it failed once: not tried again
};

class BillboardRenderer final : public Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const EnhancedBillboardsPackage& package,
                                                    const RenderSettings& settings);
    DrawStats draw(const DrawParams& params) override;
    void set_counting(bool on) override { counters_.set_counting(on); }
    std::uint64_t read_counter(Counter counter) override { return counters_.read(int(counter)); }

private:
    Status upload_billboards(const EnhancedBillboardsPackage& package);
    void upload_coarse_mesh(const Mesh& mesh, bool rims);
    void upload_box_lines(const EnhancedBillboardsPackage& package);
    void draw_box_lines(DrawStats& stats);
    Status create_march_programs(const Options& options); // after the uploads, which decide some of their settings
    void set_march_uniforms(const gpu::Program& program, const ProgramLocations& at, GLint first_entry) const;
    void prepare_pixel_images(glm::ivec2 viewport, bool flags);
    // whether the march marks near misses: only the coarse mesh's near-miss fill reads them (sheet
    // rims included, which are drawn without that test)
    bool marks_near_misses() const { return coarse_index_count_ > 0 && fill_near_misses_only_; }
    std::array<GLsizei, 2> build_draw_list(const DrawParams& params);
    void append_proxies(std::uint32_t instance, int proxy_level, glm::vec3 forward_object, const BackCull* cull,
                        const BackCull* hidden, const NearSplit* near, std::vector<DrawEntry>& front,
                        std::vector<DrawEntry>& inside);

    int march_mode_ = MARCH_EXACT, seed_steps_ = 100, debug_view_ = DEBUG_VIEW_NONE;
    float seed_hit_range_ = 0.01f;
    bool tile_layers_ = true;   // build_tiles splits tiles into depth layers (--tile-layers)
    bool cull_back_proxies_ = false; // proxies that can hold only back hits are not drawn (--cull-back-proxies)
    bool cull_hidden_proxies_ = true; // proxies hidden from the eye's cell of directions are not drawn (--cull-hidden-proxies)
    HiddenProxies hidden_;
    // cut boxes (HiddenProxies::cut_box) by cell: for each coarse and whole proxy, the proxies to draw
    // in its place, [first, first + count) (itself where count is 0); computed on a cell's first
    // need, appended to proxies_ and tile_boxes_
    struct CutProxies {
        std::uint32_t first = 0, count = 0;
    };
    std::vector<std::vector<CutProxies>> cut_proxies_;
    CutProxies cut_proxy(std::size_t k, std::size_t cell);
    std::vector<TileGpu> tile_boxes_; // every proxy's box as tiles_ holds it (cut ones appended)
    std::size_t tiles_uploaded_ = 0, tiles_capacity_ = 0;
    void upload_cut_boxes();
    double hidden_area_ = 0.0; // this frame's hidden proxies' mean projected area (ProxyInfo::mean_area)
    bool color_footprint_ = true; // colour filtered over the pixel's footprint (--color-filter)
    bool hide_back_hits_ = false; // the package's back_hits is "hide": back hits are dropped
    bool one_closed_surface_ = false; // the package's model is one closed surface wound outward
    // the coarse mesh fills only near misses (--coarse-fill near-misses), not every empty pixel
    bool fill_near_misses_only_ = false;
    // the march's programs by pass and level of detail (MARCH_LOD): the ones without it compiled at
    // creation, the others when an instance first needs them; front_batched only with depth batches
    // (--depth-batches: reps/common/depth_batches.h, software rasterisers only)
    MarchProgramSettings march_settings_;
    std::array<std::array<MarchProgram, 2>, 3> march_programs_;
    const MarchProgram& march_program(MarchPass pass, bool lod);
    std::vector<std::uint8_t> lod_instances_; // build_draw_list: instances that may need the level of detail
    bool entries_need_lod(std::span<const DrawEntry> entries) const;
    gpu::Program coarse_;
    reps::DepthBatches depth_batches_;
    bool depth_batches_on_ = false;
    std::vector<std::size_t> front_batch_ends(const DrawParams& params);
    double box_overdraw(std::span<const DrawEntry> entries) const; // k_box_batch_overdraw
    std::vector<glm::ivec4> batch_rects_; // front_batch_ends: each batch's instances on screen
    GLint coarse_near_only_at_ = -1, coarse_debug_at_ = -1, coarse_first_at_ = -1, coarse_cull_in_shader_at_ = -1;
    int billboard_count_ = 0, top_level_ = 0;
    gpu::Texture color_maps_, normal_maps_, surface_maps_, minmax_maps_, color_mips_;
    gpu::Texture orm_maps_, emission_maps_; // only for packages with PBR maps (issue #14)
    gpu::Buffer billboards_, tiles_, draw_list_;
    gpu::Counters counters_{COUNTER_COUNT};
    // proxies: tiles [0, fine_count_), coarse tiles [fine_count_, coarse_end_), then one
    // whole-billboard box per billboard
    std::vector<ProxyInfo> proxies_; // (cut boxes appended after whole_end_)
    std::size_t fine_count_ = 0, coarse_end_ = 0, whole_end_ = 0;
    std::vector<glm::vec3> billboard_directions_; // object space
    std::vector<glm::mat4> object_from_box_;      // by billboard
    glm::vec3 bound_centre_{0.0f};                 // object-space sphere around every box
    float bound_radius_ = 0.0f;
    float tile_world_ = 0.0f;                      // object units across a tile
    float smallest_texel_ = 0.0f;                  // the billboards' smallest texel, object units
    float coarse_tile_factor_ = 1.0f;              // coarse tiles' width over fine tiles'
    std::size_t draw_list_capacity_ = 0;
    std::vector<DrawEntry> front_entries_, inside_entries_, draw_entries_; // the passes' proxies; both, as drawn
    std::vector<std::uint32_t> coarse_instances_; // instances that get the coarse mesh this frame
    std::vector<std::uint8_t> coarse_instance_levels_; // and the level of the coarse mesh each gets
    std::vector<reps::CoarseLevel> coarse_levels_;     // the coarse mesh and its coarser levels (--coarse-lod)
    bool coarse_lod_ = true;
    gpu::Buffer coarse_list_;
    std::size_t coarse_list_capacity_ = 0;
    // append_proxies: (key, proxy, the proxy drawn: a cut box's index depends on when its cell was
    // first used, so ties go by the proxy's own and then by the part's place among its parts)
    std::vector<std::tuple<float, std::uint32_t, std::uint32_t, std::uint32_t>> sort_keys_;
    gpu::VertexArray empty_vertex_array_; // with box_indices_ as its element buffer
    gpu::Buffer box_indices_;
    gpu::MeshBuffers coarse_mesh_;
    GLsizei coarse_index_count_ = 0;
    GLsizei coarse_rim_index_count_ = 0; // leading indices: triangles on a sheet's rim (rims_first)
    gpu::Texture pixel_flags_, pixel_depth_;
    glm::ivec2 pixel_images_size_{0};
    gpu::FrameResources frame_;
    // debug view "proxies" only
    bool box_lines_ = false;
    gpu::Program box_lines_program_;
    GLint box_lines_alpha_at_ = -1;
    gpu::VertexArray box_lines_vertex_array_;
    gpu::Buffer box_lines_vertices_;
    GLsizei box_lines_vertex_count_ = 0;
};

gpu::Texture make_texture_array(GLenum internal_format, int width, int height, int layers, int levels)
{
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    glTextureStorage3D(name, levels, internal_format, width, height, layers);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return gpu::Texture(name);
}

// box space (x, y in texels, z in [0, 1] of the depth range) to object space
glm::mat4 object_from_box(const Billboard& b)
{
    glm::mat4 m(1.0f);
    m[0] = glm::vec4(b.axis_u * b.texel_size, 0.0f);
    m[1] = glm::vec4(b.axis_v * b.texel_size, 0.0f);
    m[2] = glm::vec4(b.direction * b.depth_range, 0.0f);
    m[3] = glm::vec4(b.origin, 1.0f);
    return m;
}

Status check_billboard(const Billboard& b, std::size_t index)
{
    std::string name = "enhanced billboards: billboard " + std::to_string(index);
    if (b.width < 1 || b.height < 1) return error(StatusCode::bad_data, name + ": empty");
    if (b.color.width != b.width || b.color.height != b.height || b.normal_depth.width != b.width ||
        b.normal_depth.height != b.height || (!b.orm.empty() && (b.orm.width != b.width || b.orm.height != b.height)) ||
        (!b.emission.empty() && (b.emission.width != b.width || b.emission.height != b.height)))
        return error(StatusCode::bad_data, name + ": image sizes differ from width x height");
    if (!(b.texel_size > 0.0f) || !(b.depth_range > 0.0f))
        return error(StatusCode::bad_data, name + ": texel_size and depth_range must be positive");
    if (std::abs(glm::determinant(glm::mat3(b.axis_u, b.axis_v, b.direction))) < 0.5f)
        return error(StatusCode::bad_data, name + ": axes are not an orthonormal frame");
    return Status::ok();
}

Result<gpu::Program> make_march_program(const MarchProgramSettings& settings, MarchPass pass, bool lod,
                                        ProgramLocations& at)
{
    std::vector<std::pair<std::string, std::string>> defines = {
        {"MARCH_MODE", std::to_string(settings.march_mode)},
        {"MARCH_LOD", lod ? "1" : "0"},
        {"MARCH_DEBUG_VIEW", std::to_string(settings.debug_view)},
        {"MARCH_MARK_PIXELS", settings.mark_pixels ? "1" : "0"},
        {"MARCH_HAS_PBR_MAPS", settings.has_pbr_maps ? "1" : "0"},
        {"MARCH_COLOR_FOOTPRINT", settings.color_footprint ? "1" : "0"},
        {"MARCH_HIDE_BACK_HITS", settings.hide_back_hits ? "1" : "0"}};
    if (pass == MarchPass::inside) defines.push_back({"INSIDE_PASS", "1"});
    if (pass == MarchPass::front_batched) defines.push_back({"DEPTH_BATCHES", "1"});
    Result<gpu::Program> program = gpu::Program::create(
        {"reps/enhanced_billboards/shaders/box.vert", "reps/enhanced_billboards/shaders/march.frag"}, defines);
    if (!program) return program;
    at.first_entry = program->uniform("first_entry");
    at.seed_steps = program->uniform("seed_steps");
    at.seed_hit_range = program->uniform("seed_hit_range");
    at.counting = program->uniform("counting");
    at.depth_batch = program->uniform("depth_batch");
    return program;
}

Result<std::unique_ptr<Renderer>> BillboardRenderer::create(const EnhancedBillboardsPackage& package,
                                                            const RenderSettings& settings)
{
    auto renderer = std::make_unique<BillboardRenderer>();
    const Options& options = settings.options;
    renderer->march_mode_ = options.choice("march") == "seed" ? MARCH_SEED : MARCH_EXACT;
    renderer->seed_steps_ = options.integer("steps");
    renderer->seed_hit_range_ = options.number("hit-range");
    renderer->tile_layers_ = options.flag("tile-layers");
    const std::string cull = options.choice("cull-back-proxies");
    renderer->cull_back_proxies_ = cull == "on" || (cull == "auto" && (package.one_closed_surface || package.backs_unseen));
    renderer->cull_hidden_proxies_ = options.choice("cull-hidden-proxies") == "on";
    renderer->color_footprint_ = options.choice("color-filter") == "footprint";
    renderer->hide_back_hits_ = package.settings.back_hits == "hide";
    renderer->one_closed_surface_ = package.one_closed_surface;
    renderer->fill_near_misses_only_ = options.choice("coarse-fill") == "near-misses";
    // (near misses are filled by the mesh the bake made: its rims first, drawn apart)
    renderer->coarse_lod_ = options.choice("coarse-lod") == "on" && !renderer->fill_near_misses_only_;
    // "proxies" is the shaded picture with the box lines drawn over it
    bool proxies = settings.debug_view == DebugView::proxies;
    renderer->debug_view_ = proxies ? DEBUG_VIEW_NONE : int(settings.debug_view);
    for (std::size_t i = 0; i < package.billboards.size(); ++i)
        STANDIN_RETURN_IF_ERROR(check_billboard(package.billboards[i], i));

    Result<gpu::Program> coarse = gpu::Program::create(
        {"reps/enhanced_billboards/shaders/coarse.vert", "reps/enhanced_billboards/shaders/coarse.frag"});
    if (!coarse) return coarse.status();
    renderer->coarse_ = std::move(*coarse);
    renderer->coarse_near_only_at_ = renderer->coarse_.uniform("fill_near_misses_only");
    renderer->coarse_debug_at_ = renderer->coarse_.uniform("debug_view");
    renderer->coarse_first_at_ = renderer->coarse_.uniform("first_coarse");
    renderer->coarse_cull_in_shader_at_ = renderer->coarse_.uniform("cull_in_shader");
    if (proxies) {
        Result<gpu::Program> lines = gpu::Program::create(
            {"reps/enhanced_billboards/shaders/boxes.vert", "reps/enhanced_billboards/shaders/boxes.frag"});
        if (!lines) return lines.status();
        renderer->box_lines_program_ = std::move(*lines);
        renderer->box_lines_alpha_at_ = renderer->box_lines_program_.uniform("line_alpha");
        renderer->box_lines_ = true;
    }

    // upload maps and accelerations, then the coarse mesh
    STANDIN_RETURN_IF_ERROR(renderer->upload_billboards(package));
    if (options.flag("coarse") && package.coarse_mesh.triangle_count() > 0) renderer->upload_coarse_mesh(package.coarse_mesh, package.coarse_rims);
    if (renderer->box_lines_) renderer->upload_box_lines(package);
    STANDIN_RETURN_IF_ERROR(renderer->create_march_programs(options));
    renderer->empty_vertex_array_ = gpu::make_vertex_array();
    // box.vert's corners, 12 triangles counter-clockwise seen from outside: drawn indexed, so that a
    // box's 8 corners are shaded once each, not once per triangle (36 times)
    const std::vector<std::uint16_t> box_indices = {0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5, 0, 1, 5, 0, 5, 4,
                                                    2, 6, 7, 2, 7, 3, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
    renderer->box_indices_ = gpu::make_buffer(box_indices);
    glVertexArrayElementBuffer(renderer->empty_vertex_array_.get(), renderer->box_indices_.get());
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "enhanced billboards: " + gpu::gl_error_text(e) + " while uploading");
    return std::unique_ptr<Renderer>(std::move(renderer));
}

// The pyramid level of the fine tiles: k_tile_level, or coarser where 2^k_tile_level texels are
// under k_tile_diagonal_fraction of the model's diagonal, so that finer texels (foliage: 2048 along
// the diagonal, issue #14) do not multiply the boxes. Measured on the generated tree at 2048 texels,
// 800x600 on llvmpipe: tiles of 16 texels 1542 ms a frame (63 fragments per covered pixel, 187k
// boxes), of 32 texels 1099 ms (82 fragments): the boxes' vertices cost more than the fragments.
static int fine_tile_level(const EnhancedBillboardsPackage& package)
{
    const double diagonal = double(package.source.bounds.diagonal());
    double texel = 0.0;
    for (const Billboard& b : package.billboards) texel = std::max(texel, double(b.texel_size));
    int level = k_tile_level;
    while (texel > 0.0 && diagonal > 0.0 && double(1 << level) * texel < k_tile_diagonal_fraction * diagonal * 0.99 &&
           level < k_coarse_tile_level)
        ++level;
    return level;
}

Status BillboardRenderer::upload_billboards(const EnhancedBillboardsPackage& package)
{
    billboard_count_ = int(package.billboards.size());
    if (billboard_count_ == 0) return Status::ok();
    GLint max_layers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);

    // the billboards packed into array layers, each padded to whole top-level pyramid cells
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    const GpuLayout layout = gpu_layout(package.billboards, std::min(int(max_size), k_max_layer_side));
    const LayerPacking& packing = layout.packing;
    const int levels = layout.levels, cell = 1 << levels;
    top_level_ = levels;
    const int width = packing.width, height = packing.height, layers = packing.layers;
    if (width > max_size || height > max_size)
        return error(StatusCode::gpu_error, "enhanced billboards: billboard larger than GL_MAX_TEXTURE_SIZE");
    if (layers > max_layers)
        return error(StatusCode::gpu_error, "enhanced billboards: " + std::to_string(layers) +
                                                " texture layers exceed GL_MAX_ARRAY_TEXTURE_LAYERS");
    color_maps_ = make_texture_array(GL_RGBA8, width, height, layers, 1);
    // normals octahedral in RG16 (4 bytes a texel instead of RGBA16's 8; the package's depth, the
    // fourth channel, is the surface maps' already): as exact as 16 bits per axis, where RGB10_A2 cost
    // the engine's thesis Luv 0.007
    normal_maps_ = make_texture_array(GL_RG16, width, height, layers, 1);
    surface_maps_ = make_texture_array(GL_RGBA16UI, width, height, layers, 1);
    minmax_maps_ = make_texture_array(GL_RG16UI, std::max(1, width / 2), std::max(1, height / 2), layers,
                                      std::max(1, levels));
    color_mips_ = make_texture_array(GL_RGBA8, std::max(1, width / 2), std::max(1, height / 2), layers,
                                     std::max(1, levels));
    if (has_pbr_maps(package.billboards) && layers > 0) {
        orm_maps_ = make_texture_array(GL_RGBA8, width, height, layers, 1);
        emission_maps_ = make_texture_array(GL_RGBA8, width, height, layers, 1);
    }

    LinkSettings links;
    links.depth_bits = package.settings.depth_bits;
    links.edge_lines = package.settings.sheet_edges == "clip";
    std::vector<BillboardGpu> gpu_billboards;
    std::vector<TileGpu> fine, coarse, whole;
    std::vector<ProxyInfo> coarse_proxies, whole_proxies;
    const int coarse_level = std::min(k_coarse_tile_level, levels), tile_level = std::min(fine_tile_level(package), coarse_level);
    coarse_tile_factor_ = float(1 << (coarse_level - tile_level));
    glm::vec3 bound_lo(1e30f), bound_hi(-1e30f);
    std::size_t covered_texels = 0;
    float largest_texel = 0.0f;
    for (const Billboard& b : package.billboards) {
        for (std::size_t k = 3; k < b.color.pixels.size(); k += 4) covered_texels += b.color.pixels[k] != 0;
        largest_texel = std::max(largest_texel, b.texel_size);
    }
    if (covered_texels > HiddenProxies::k_texel_budget) cull_hidden_proxies_ = false; // (hidden_proxies.h)
    // What a billboard's upload computes on the CPU (normals encoded, the march's acceleration, tiles
    // and their proxies, the colour pyramid) is independent of the other billboards: prepared on
    // every core a few billboards at a time, then uploaded and appended in order on the context's
    // thread (the same buffers at any thread count). The held-out engine's 34 billboards at 1024
    // texels: docs/RESULTS.md "Packages loaded on every core".
    struct Prepared {
        BillboardGpu g;
        std::vector<std::uint16_t> octahedral, surface;
        HeightFieldAcceleration acc;
        std::vector<TileBox> fine_boxes, coarse_boxes;
        std::vector<TileGpu> fine, coarse;
        std::vector<ProxyInfo> fine_info, coarse_info;
        TileGpu whole;
        ProxyInfo whole_proxy;
        std::vector<std::vector<std::uint8_t>> color_pyramid;
    };
    auto prepare = [&](int layer, Prepared& out) {
        const Billboard& b = package.billboards[std::size_t(layer)];
        const LayerPlacement at = packing.placements[std::size_t(layer)];
        const glm::ivec2 padded = (glm::ivec2(b.width, b.height) + cell - 1) / cell * cell;
        BillboardGpu& g = out.g;
        g.object_from_box = object_from_box(b);
        g.box_from_object = glm::inverse(g.object_from_box);
        g.info = glm::ivec4(at.layer, 0, b.width, b.height);
        g.offset = glm::ivec4(at.offset, 0, 0);
        out.octahedral.resize(std::size_t(b.width) * std::size_t(b.height) * 2);
        for (std::size_t k = 0; k < out.octahedral.size() / 2; ++k) {
            const std::uint16_t* n = &b.normal_depth.pixels[k * 4];
            const glm::vec2 e = reps::octahedral_encode(glm::vec3(n[0], n[1], n[2]) / 32767.5f - 1.0f);
            for (int c = 0; c < 2; ++c) out.octahedral[k * 2 + std::size_t(c)] = std::uint16_t(std::lround(std::clamp(e[c], 0.0f, 1.0f) * 65535.0f));
        }
        out.acc = build_acceleration(b, padded.x, padded.y, levels, links);
        int range_unit = 1;
        out.surface = pack_surface(out.acc, range_unit);
        g.info.y = range_unit;
        covered_box(out.acc, b, g);
        // proxies: the occupied tiles, the coarse tiles, and the whole box of covered texels
        auto add_tiles = [&](int level, int start_at_footprint, std::vector<TileGpu>& tiles, std::vector<ProxyInfo>& info) {
            // a tile's layers split where they lie more than a quarter of the tile's width apart in
            // depth (2CylinderEngine, 800x600: a quarter against the whole width 16.6 against 27.3
            // fetches, 28 against 43 fragments per covered pixel; a twentieth 14.3 / 25 for more boxes)
            const double layer_gap = tile_layers_ ? std::min(65535.0, k_tile_layer_gap * double(1 << level) *
                                                                          double(b.texel_size) / double(b.depth_range) * HF_DEPTH_CODES)
                                                  : 65535.0;
            std::vector<TileBox> boxes = build_tiles(out.acc, 1 << level, int(layer_gap));
            for (const TileBox& t : boxes) {
                TileGpu tile;
                // sheared to follow the surface (TileBox::slope): z holds the offset from the plane
                tile.box_min = glm::vec4(glm::vec2(t.texel_min), t.offset_min - k_depth_margin, t.slope.x);
                tile.box_max = glm::vec4(glm::vec2(t.texel_max), t.offset_max + k_depth_margin, t.slope.y);
                tile.info = glm::ivec4(layer, level, start_at_footprint, 0);
                tiles.push_back(tile);
                glm::vec2 centre = 0.5f * (glm::vec2(tile.box_min) + glm::vec2(tile.box_max));
                float centre_z = 0.5f * (tile.box_min.z + tile.box_max.z) + glm::dot(t.slope, centre);
                ProxyInfo proxy{glm::vec3(g.object_from_box * glm::vec4(centre, centre_z, 1.0f)), layer};
                proxy.radius = proxy_radius(g.object_from_box, tile, proxy.centre_object);
                proxy.mean_area = proxy_mean_area(g.object_from_box, tile);
                texel_normal_cone(b, out.acc, t.texel_min, t.texel_max, proxy);
                info.push_back(proxy);
            }
            return boxes;
        };
        out.fine_boxes = add_tiles(tile_level, 0, out.fine, out.fine_info);
        if (coarse_level > tile_level) out.coarse_boxes = add_tiles(coarse_level, 1, out.coarse, out.coarse_info);
        out.whole = TileGpu{g.box_min, g.box_max, glm::ivec4(layer, levels, 1, 0)}; // z: a whole billboard (march.frag)
        out.whole_proxy = ProxyInfo{glm::vec3(g.object_from_box * (0.5f * (g.box_min + g.box_max) + glm::vec4(0, 0, 0, 1))), layer};
        out.whole_proxy.radius = proxy_radius(g.object_from_box, out.whole, out.whole_proxy.centre_object);
        out.whole_proxy.mean_area = proxy_mean_area(g.object_from_box, out.whole);
        texel_normal_cone(b, out.acc, glm::ivec2(0), glm::ivec2(b.width, b.height), out.whole_proxy);
        out.color_pyramid = build_color_pyramid(b, out.acc);
    };
    auto upload = [&](int layer, Prepared& in) {
        const Billboard& b = package.billboards[std::size_t(layer)];
        const LayerPlacement at = packing.placements[std::size_t(layer)];
        const glm::ivec2 padded = (glm::ivec2(b.width, b.height) + cell - 1) / cell * cell;
        const BillboardGpu& g = in.g;
        glTextureSubImage3D(color_maps_.get(), 0, at.offset.x, at.offset.y, at.layer, b.width, b.height, 1, GL_RGBA,
                            GL_UNSIGNED_BYTE, b.color.pixels.data());
        glTextureSubImage3D(normal_maps_.get(), 0, at.offset.x, at.offset.y, at.layer, b.width, b.height, 1, GL_RG,
                            GL_UNSIGNED_SHORT, in.octahedral.data());
        if (orm_maps_) {
            glTextureSubImage3D(orm_maps_.get(), 0, at.offset.x, at.offset.y, at.layer, b.width, b.height, 1, GL_RGBA,
                                GL_UNSIGNED_BYTE, b.orm.pixels.data());
            glTextureSubImage3D(emission_maps_.get(), 0, at.offset.x, at.offset.y, at.layer, b.width, b.height, 1,
                                GL_RGBA, GL_UNSIGNED_BYTE, b.emission.pixels.data());
        }
        gpu_billboards.push_back(g);
        const std::uint32_t first_fine = std::uint32_t(fine.size()), first_coarse = std::uint32_t(coarse.size());
        fine.insert(fine.end(), in.fine.begin(), in.fine.end());
        proxies_.insert(proxies_.end(), in.fine_info.begin(), in.fine_info.end());
        coarse.insert(coarse.end(), in.coarse.begin(), in.coarse.end());
        coarse_proxies.insert(coarse_proxies.end(), in.coarse_info.begin(), in.coarse_info.end());
        if (cull_hidden_proxies_)
            hidden_.add_billboard(b, in.acc, {in.fine_boxes, first_fine}, {in.coarse_boxes, first_coarse});
        whole.push_back(in.whole);
        whole_proxies.push_back(in.whole_proxy);
        billboard_directions_.push_back(b.direction);
        object_from_box_.push_back(g.object_from_box);
        tile_world_ = std::max(tile_world_, float(1 << tile_level) * b.texel_size);
        smallest_texel_ = smallest_texel_ > 0.0f ? std::min(smallest_texel_, b.texel_size) : b.texel_size;
        if (g.box_min.x <= g.box_max.x) {
            for (int corner = 0; corner < 8; ++corner) {
                glm::vec3 f(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
                glm::vec3 p = glm::vec3(g.object_from_box *
                                        glm::vec4(glm::mix(glm::vec3(g.box_min), glm::vec3(g.box_max), f), 1.0f));
                bound_lo = glm::min(bound_lo, p);
                bound_hi = glm::max(bound_hi, p);
            }
        }
        glTextureSubImage3D(surface_maps_.get(), 0, at.offset.x, at.offset.y, at.layer, padded.x, padded.y, 1,
                            GL_RGBA_INTEGER, GL_UNSIGNED_SHORT, in.surface.data());
        for (int level = 1; level <= levels; ++level)
            glTextureSubImage3D(minmax_maps_.get(), level - 1, at.offset.x >> level, at.offset.y >> level, at.layer,
                                padded.x >> level, padded.y >> level, 1, GL_RG_INTEGER, GL_UNSIGNED_SHORT,
                                in.acc.pyramid[std::size_t(level - 1)].data());
        for (int level = 1; level <= levels; ++level)
            glTextureSubImage3D(color_mips_.get(), level - 1, at.offset.x >> level, at.offset.y >> level, at.layer,
                                padded.x >> level, padded.y >> level, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                                in.color_pyramid[std::size_t(level - 1)].data());
    };
    // a few billboards at a time: as many as there are cores, within about 300 MB of prepared data
    // (about 36 bytes a padded texel)
    const std::size_t cores = std::size_t(std::max(1, tbb::this_task_arena::max_concurrency()));
    constexpr std::size_t k_prepared_texels = std::size_t(8) << 20;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    std::vector<Prepared> prepared;
    for (int first = 0; first < billboard_count_;) {
        int end = first;
        std::size_t texels = 0;
        while (end < billboard_count_ && std::size_t(end - first) < cores && (end == first || texels < k_prepared_texels)) {
            const Billboard& b = package.billboards[std::size_t(end)];
            texels += std::size_t(b.width) * std::size_t(b.height);
            ++end;
        }
        prepared.assign(std::size_t(end - first), Prepared{});
        tbb::parallel_for(first, end, [&](int layer) { prepare(layer, prepared[std::size_t(layer - first)]); });
        for (int layer = first; layer < end; ++layer) upload(layer, prepared[std::size_t(layer - first)]); // (a billboard's index, as tiles name it)
        first = end;
    }
    log_message(LogLevel::info, "enhanced billboards: " + std::to_string(billboard_count_) + " billboards in " +
                                    std::to_string(layers) + " texture layers of " + std::to_string(width) + "x" +
                                    std::to_string(height) + ", " +
                                    std::to_string(std::llround(double(gpu_texture_bytes(layout, bool(orm_maps_))) / double(1 << 20))) + " MiB");
    billboards_ = gpu::make_buffer(gpu_billboards);
    fine_count_ = fine.size();
    coarse_end_ = fine_count_ + coarse.size();
    proxies_.insert(proxies_.end(), coarse_proxies.begin(), coarse_proxies.end());
    proxies_.insert(proxies_.end(), whole_proxies.begin(), whole_proxies.end());
    fine.insert(fine.end(), coarse.begin(), coarse.end());
    fine.insert(fine.end(), whole.begin(), whole.end());
    whole_end_ = proxies_.size();
    tile_boxes_ = std::move(fine);
    tiles_capacity_ = tiles_uploaded_ = tile_boxes_.size();
    tiles_ = gpu::make_buffer(tile_boxes_, GL_DYNAMIC_STORAGE_BIT);
    if (bound_lo.x <= bound_hi.x) {
        bound_centre_ = 0.5f * (bound_lo + bound_hi);
        bound_radius_ = 0.5f * glm::length(bound_hi - bound_lo);
    }
    // back-facing texels hide nothing where their back hits are dropped or their proxies culled
    if (cull_hidden_proxies_) {
        hidden_.finish(bound_centre_, bound_radius_, largest_texel, hide_back_hits_ || cull_back_proxies_);
        cut_proxies_.assign(std::size_t(HiddenProxies::k_cells * HiddenProxies::k_cells), {});
    }
    return Status::ok();
}

// Sheet rims (issue #17): a billboard texel is covered where its centre lies on the surface, and
// nothing lies beyond a sheet's edge for another billboard to overlap, so about half the texels an
// open edge crosses are lost: a staircase of holes along every rim seen at an angle, where the ray
// passes no covered texel and so marks no near miss for the coarse mesh to fill. The coarse mesh
// keeps open boundaries where they are (make_coarse_mesh locks them), so its triangles that touch
// one cover the rim's true outline: they are drawn first, wherever no front hit is at the pixel,
// without the near-miss test. Returns the number of their indices (they lead `mesh.indices`); closed
// coarse meshes have none. Only for packages whose baker asked for it (coarse_rims: open opaque
// parts; leaf cards' outlines are not their leaves'); others are drawn as before.
std::size_t rims_first(Mesh& mesh)
{
    std::size_t n = mesh.triangle_count();
    // weld by position (a coarse mesh is welded already; older or foreign files need not be)
    std::vector<std::uint32_t> weld = weld_by_position(mesh);
    std::vector<std::uint64_t> edges;
    edges.reserve(3 * n);
    for (std::size_t f = 0; f < n; ++f)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = weld[mesh.indices[f * 3 + k]], b = weld[mesh.indices[f * 3 + (k + 1) % 3]];
            if (a != b) edges.push_back(std::uint64_t(std::min(a, b)) << 32 | std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint8_t> on_rim(mesh.vertex_count(), 0);
    bool any = false;
    for (std::size_t k = 0; k < edges.size();) {
        std::size_t end = k;
        while (end < edges.size() && edges[end] == edges[k]) ++end;
        if (end - k == 1) {
            on_rim[std::size_t(edges[k] >> 32)] = on_rim[std::size_t(edges[k] & 0xffffffffu)] = 1;
            any = true;
        }
        k = end;
    }
    if (!any) return 0;
    std::vector<std::uint32_t> rim, rest;
    for (std::size_t f = 0; f < n; ++f) {
        const std::uint32_t* t = &mesh.indices[f * 3];
        bool touches = on_rim[weld[t[0]]] || on_rim[weld[t[1]]] || on_rim[weld[t[2]]];
        (touches ? rim : rest).insert((touches ? rim : rest).end(), t, t + 3);
    }
    std::size_t rim_count = rim.size();
    rim.insert(rim.end(), rest.begin(), rest.end());
    mesh.indices = std::move(rim);
    return rim_count;
}

void BillboardRenderer::upload_coarse_mesh(const Mesh& mesh, bool rims)
{
    Mesh ordered = rims ? mesh : Mesh{};
    coarse_rim_index_count_ = rims ? GLsizei(rims_first(ordered)) : 0;
    const Mesh& drawn = coarse_rim_index_count_ > 0 ? ordered : mesh;
    std::vector<std::uint32_t> indices;
    if (coarse_lod_) {
        coarse_levels_ = reps::coarse_mesh_levels(drawn, indices);
    } else {
        indices = drawn.indices;
        coarse_levels_ = {{0, std::uint32_t(indices.size()), 0.0f}};
    }
    coarse_mesh_ = gpu::MeshBuffers::upload(drawn, indices);
    coarse_index_count_ = GLsizei(coarse_levels_[0].index_count);
}

// The twelve edges of every billboard's whole box, in object space: corner bits (u, v, depth) pick
// origin + {0, width} texels along axis_u, {0, height} along axis_v, {0, depth_range} along the
// direction; an edge changes one bit, and the four edges with depth bit 0 outline the front plane.
void BillboardRenderer::upload_box_lines(const EnhancedBillboardsPackage& package)
{
    std::vector<BoxLineVertex> vertices;
    for (std::size_t k = 0; k < package.billboards.size(); ++k) {
        const Billboard& b = package.billboards[k];
        glm::vec3 extent_u = b.axis_u * (float(b.width) * b.texel_size);
        glm::vec3 extent_v = b.axis_v * (float(b.height) * b.texel_size);
        glm::vec3 extent_w = b.direction * b.depth_range;
        auto corner = [&](int bits) {
            return b.origin + float(bits & 1) * extent_u + float((bits >> 1) & 1) * extent_v +
                   float((bits >> 2) & 1) * extent_w;
        };
        for (int from = 0; from < 8; ++from) {
            for (int bit = 1; bit < 8; bit <<= 1) {
                if (from & bit) continue;
                std::int32_t front = (from & 4) == 0 && bit != 4 ? 1 : 0;
                vertices.push_back({corner(from), std::int32_t(k), front});
                vertices.push_back({corner(from | bit), std::int32_t(k), front});
            }
        }
    }
    box_lines_vertex_count_ = GLsizei(vertices.size());
    if (vertices.empty()) return;
    box_lines_vertices_ = gpu::make_buffer(vertices);
    box_lines_vertex_array_ = gpu::make_vertex_array();
    GLuint vao = box_lines_vertex_array_.get();
    glVertexArrayVertexBuffer(vao, 0, box_lines_vertices_.get(), 0, GLsizei(sizeof(BoxLineVertex)));
    glVertexArrayAttribFormat(vao, ATTRIB_POSITION, 3, GL_FLOAT, GL_FALSE, GLuint(offsetof(BoxLineVertex, position_object)));
    glVertexArrayAttribIFormat(vao, ATTRIB_BOX_EDGE, 2, GL_INT, GLuint(offsetof(BoxLineVertex, billboard)));
    glVertexArrayAttribBinding(vao, ATTRIB_POSITION, 0);
    glVertexArrayAttribBinding(vao, ATTRIB_BOX_EDGE, 0);
    glEnableVertexArrayAttrib(vao, ATTRIB_POSITION);
    glEnableVertexArrayAttrib(vao, ATTRIB_BOX_EDGE);
}

// Debug view "proxies": the box lines of every instance over what was drawn, depth-tested against
// it without writing depth: first the hidden parts, dimmed (blended at a third), then the visible
// parts at full colour. Leaves depth testing at GL_LESS, depth writes on and blending off.
void BillboardRenderer::draw_box_lines(DrawStats& stats)
{
    if (box_lines_vertex_count_ == 0) return;
    GLsizei instances = GLsizei(frame_.instance_count());
    box_lines_program_.use();
    glBindVertexArray(box_lines_vertex_array_.get());
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    const std::pair<GLenum, float> passes[2] = {{GL_GREATER, 0.35f}, {GL_LEQUAL, 1.0f}};
    for (const auto& [depth_func, alpha] : passes) {
        glDepthFunc(depth_func);
        glProgramUniform1f(box_lines_program_.id(), box_lines_alpha_at_, alpha);
        glDrawArraysInstanced(GL_LINES, 0, box_lines_vertex_count_, instances);
        stats.draw_calls += 1;
    }
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
}

Status BillboardRenderer::create_march_programs(const Options& options)
{
    MarchProgramSettings& settings = march_settings_;
    settings.march_mode = march_mode_;
    settings.debug_view = debug_view_;
    settings.mark_pixels = marks_near_misses();
    settings.has_pbr_maps = bool(orm_maps_);
    settings.color_footprint = color_footprint_;
    settings.hide_back_hits = hide_back_hits_;
    depth_batches_on_ = options.choice("depth-batches") == "auto" && gpu::software_rasteriser();
    for (MarchPass pass : {MarchPass::front, MarchPass::inside, MarchPass::front_batched}) {
        if (pass == MarchPass::front_batched && !depth_batches_on_) continue;
        MarchProgram& program = march_programs_[std::size_t(pass)][0];
        Result<gpu::Program> compiled = make_march_program(settings, pass, false, program.at);
        if (!compiled) return compiled.status();
        program.program = std::move(*compiled);
    }
    if (depth_batches_on_) STANDIN_RETURN_IF_ERROR(depth_batches_.create());
    return Status::ok();
}

// The program for a pass, with the level of detail or without: compiled on first use; should that
// fail, the one without (the exact walk to level 0: the same surfaces, more fetches far away).
const MarchProgram& BillboardRenderer::march_program(MarchPass pass, bool lod)
{
    MarchProgram& wanted = march_programs_[std::size_t(pass)][lod ? 1 : 0];
    if (!lod || wanted.program.id() != 0) return wanted;
    if (!wanted.failed) {
        Result<gpu::Program> compiled = make_march_program(march_settings_, pass, true, wanted.at);
        if (compiled) {
            wanted.program = std::move(*compiled);
            return wanted;
        }
        wanted.failed = true;
        log_message(LogLevel::warning, "enhanced billboards: " + compiled.status().message() + "; drawing without the level of detail");
    }
    return march_programs_[std::size_t(pass)][0];
}

bool BillboardRenderer::entries_need_lod(std::span<const DrawEntry> entries) const
{
    for (const DrawEntry& entry : entries)
        if (lod_instances_[entry.instance] != 0) return true;
    return false;
}

void BillboardRenderer::set_march_uniforms(const gpu::Program& program, const ProgramLocations& at,
                                           GLint first_entry) const
{
    GLuint id = program.id();
    glProgramUniform1i(id, at.first_entry, first_entry);
    glProgramUniform1i(id, at.seed_steps, seed_steps_);
    glProgramUniform1f(id, at.seed_hit_range, seed_hit_range_);
    glProgramUniform1i(id, at.counting, counters_.counting() ? 1 : 0);
}

// the per-pixel nearest front hit and the hit / near-miss flags the coarse mesh reads, cleared
// every frame
void BillboardRenderer::prepare_pixel_images(glm::ivec2 viewport, bool flags)
{
    if (!pixel_depth_ || pixel_images_size_ != viewport) {
        pixel_depth_ = gpu::make_texture_2d(GL_R32UI, viewport.x, viewport.y);
        pixel_flags_ = gpu::make_texture_2d(GL_R32UI, viewport.x, viewport.y);
        pixel_images_size_ = viewport;
    }
    const float far_depth = 1.0f;
    std::uint32_t far_bits = 0;
    std::memcpy(&far_bits, &far_depth, sizeof far_bits);
    glClearTexImage(pixel_depth_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &far_bits);
    glBindImageTexture(IMAGE_PIXEL_DEPTH, pixel_depth_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    if (flags) {
        const std::uint32_t zero = 0;
        glClearTexImage(pixel_flags_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
    }
    glBindImageTexture(IMAGE_PIXEL_FLAGS, pixel_flags_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
}

// The proxies of one instance, front to back along forward_object: tiles (proxy_level 0), coarse
// tiles (1) or one box per billboard (2), those of billboards that see surfaces facing the eye first.
// They go to `front`, except, for an instance that may cross the near plane (`near`), those whose
// sphere reaches it, which go to `inside`. Per proxy, not per instance: the instance's sphere
// holds every box's corners, over 1.05 times the model's, so the orbit cameras' near plane
// (camera.cpp: 1.05 radii before the centre) crossed it up to distance 6 and every box went to
// the inside pass, where a box's depth does not bound its hits (no depth_greater early depth test
// on a GPU, no stop before the set-up in march.frag).
void BillboardRenderer::append_proxies(std::uint32_t instance, int proxy_level, glm::vec3 forward_object,
                                       const BackCull* cull, const BackCull* hidden, const NearSplit* near,
                                       std::vector<DrawEntry>& front, std::vector<DrawEntry>& inside)
{
    const std::size_t bounds[4] = {0, fine_count_, coarse_end_, whole_end_};
    std::size_t first = bounds[proxy_level], last = bounds[proxy_level + 1];
    sort_keys_.clear();
    for (std::size_t k = first; k < last; ++k) {
        const ProxyInfo& p = proxies_[k];
        if (cull && faces_away(p, cull->orthographic ? cull->eye_object : cull->eye_object - p.centre_object, cull->orthographic))
            continue;
        CutProxies drawn{std::uint32_t(k), 0};
        if (hidden) {
            const glm::vec3 direction = hidden->orthographic ? -hidden->eye_object : p.centre_object - hidden->eye_object;
            const std::size_t cell = HiddenProxies::cell_index_or_none(direction); // (one octahedral encode)
            if (!hidden_.may_show(k, cell)) {
                hidden_area_ += double(p.mean_area);
                continue;
            }
            // a coarse tile or whole box: cut to what shows from the cell (which may append to
            // proxies_: p is read again below)
            if (k >= fine_count_ && cell != HiddenProxies::k_no_cell) {
                drawn = cut_proxy(k, cell);
                hidden_area_ += double(proxies_[k].mean_area);
                if (drawn.count == 0) drawn = {std::uint32_t(k), 1};
                for (std::uint32_t part = 0; part < drawn.count; ++part) hidden_area_ -= double(proxies_[drawn.first + part].mean_area);
            }
        }
        const ProxyInfo& kept = proxies_[k];
        bool facing = glm::dot(billboard_directions_[std::size_t(kept.billboard)], forward_object) > 0.0f;
        float key = glm::dot(kept.centre_object - bound_centre_, forward_object) + (facing ? 0.0f : 4.0f * bound_radius_);
        if (drawn.count == 0) drawn.count = 1;
        for (std::uint32_t part = 0; part < drawn.count; ++part) sort_keys_.push_back({key, std::uint32_t(k), part, drawn.first + part});
    }
    std::sort(sort_keys_.begin(), sort_keys_.end());
    for (const auto& [key, own, part, tile] : sort_keys_) {
        bool crosses = false;
        if (near) {
            const ProxyInfo& p = proxies_[tile];
            glm::vec3 centre = glm::vec3(*near->world_from_object * glm::vec4(p.centre_object, 1.0f));
            crosses = reaches_near_plane(centre, p.radius * near->scale * 1.001f + 1e-6f, *near->camera);
        }
        (crosses ? inside : front).push_back({instance, tile});
    }
}

// The proxies drawn for coarse tile or whole box k seen from `cell`: its box cut to the fine tiles
// that show from there, or a whole box's parts (HiddenProxies::cut_box), appended on the cell's first
// need; a count of 0 where k itself is drawn.
BillboardRenderer::CutProxies BillboardRenderer::cut_proxy(std::size_t k, std::size_t cell)
{
    std::vector<CutProxies>& drawn = cut_proxies_[cell];
    if (drawn.empty()) {
        drawn.resize(whole_end_ - fine_count_);
        for (std::size_t q = fine_count_; q < whole_end_; ++q) {
            std::array<HiddenProxies::Cut, 4> parts;
            const int count = hidden_.cut_box(q, cell, parts);
            drawn[q - fine_count_] = {std::uint32_t(proxies_.size()), std::uint32_t(count)};
            for (int part = 0; part < count; ++part) {
                const HiddenProxies::Cut& cut = parts[std::size_t(part)];
                const TileGpu own = tile_boxes_[q];
                TileGpu box = own;
                // (the cut lies within the box but for rounding: keep it there, with the margin the box has)
                box.box_min = glm::vec4(glm::max(glm::vec2(own.box_min), glm::vec2(cut.texel_min)),
                                        std::max(own.box_min.z, cut.offset_min - k_depth_margin), own.box_min.w);
                box.box_max = glm::vec4(glm::min(glm::vec2(own.box_max), glm::vec2(cut.texel_max)),
                                        std::min(own.box_max.z, cut.offset_max + k_depth_margin), own.box_max.w);
                ProxyInfo info = proxies_[q]; // (its normal cone: of the whole box, a superset)
                const glm::mat4 object_from_box = object_from_box_[std::size_t(info.billboard)];
                const glm::vec2 centre = 0.5f * (glm::vec2(box.box_min) + glm::vec2(box.box_max));
                const float centre_z = 0.5f * (box.box_min.z + box.box_max.z) + box.box_min.w * centre.x + box.box_max.w * centre.y;
                info.centre_object = glm::vec3(object_from_box * glm::vec4(centre, centre_z, 1.0f));
                info.radius = proxy_radius(object_from_box, box, info.centre_object);
                info.mean_area = proxy_mean_area(object_from_box, box);
                proxies_.push_back(info);
                tile_boxes_.push_back(box);
            }
        }
        upload_cut_boxes();
    }
    return drawn[k - fine_count_];
}

// tiles_ holds tile_boxes_: the new cut boxes written after those uploaded, into a buffer twice as
// large where they do not fit
void BillboardRenderer::upload_cut_boxes()
{
    if (tile_boxes_.size() == tiles_uploaded_) return;
    if (tile_boxes_.size() > tiles_capacity_) {
        tiles_capacity_ = std::max(tile_boxes_.size(), 2 * tiles_capacity_);
        tiles_ = gpu::make_buffer(nullptr, tiles_capacity_ * sizeof(TileGpu), GL_DYNAMIC_STORAGE_BIT);
        tiles_uploaded_ = 0;
    }
    glNamedBufferSubData(tiles_.get(), GLintptr(tiles_uploaded_ * sizeof(TileGpu)),
                         GLsizeiptr((tile_boxes_.size() - tiles_uploaded_) * sizeof(TileGpu)), tile_boxes_.data() + tiles_uploaded_);
    tiles_uploaded_ = tile_boxes_.size();
}

// The (instance, proxy) list of this frame: instances outside the view are left out; the others,
// nearest first, go to the front-face pass, or to the inside pass when they may cross the near
// plane (append_proxies). Returns the entry counts of the two passes (inside first, as they are
// drawn) and uploads the list.
std::array<GLsizei, 2> BillboardRenderer::build_draw_list(const DrawParams& params)
{
    static const glm::mat4 identity(1.0f);
    std::span<const glm::mat4> transforms = params.world_from_object;
    if (transforms.empty()) transforms = std::span<const glm::mat4>(&identity, 1);
    const Camera& camera = params.camera;
    glm::mat4 clip_from_world = camera.clip_from_world();
    glm::mat4 rows = glm::transpose(clip_from_world);
    // frustum planes (Gribb & Hartmann), not normalised: a sphere is outside when its centre is
    // further than its radius times the plane normal's length on the outer side
    std::array<glm::vec4, 6> planes = {rows[3] + rows[0], rows[3] - rows[0], rows[3] + rows[1],
                                       rows[3] - rows[1], rows[3] + rows[2], rows[3] - rows[2]};
    float pixels_per_unit_at_1 = float(params.viewport.y) /
                                 (camera.orthographic ? 2.0f * camera.ortho_half_height
                                                      : 2.0f * std::tan(glm::radians(camera.fov_y_degrees) * 0.5f));
    bool tiles = march_mode_ == MARCH_EXACT;

    struct Visible {
        float depth;
        std::uint32_t instance;
        bool inside;
        int proxy_level; // append_proxies
        float scale;     // the transform's largest axis scale
    };
    std::vector<Visible> visible;
    coarse_instances_.clear();
    coarse_instance_levels_.clear();
    lod_instances_.assign(transforms.size(), 0);
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        const glm::mat4& m = transforms[i];
        glm::vec3 centre = glm::vec3(m * glm::vec4(bound_centre_, 1.0f));
        float scale = std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
        float radius = bound_radius_ * scale * 1.001f + 1e-6f;
        bool outside = false;
        for (const glm::vec4& plane : planes)
            outside = outside || glm::dot(glm::vec3(plane), centre) + plane.w < -radius * glm::length(glm::vec3(plane));
        if (outside) continue;
        float depth = glm::dot(centre - camera.eye_world, camera.forward_world);
        bool inside = reaches_near_plane(centre, radius, camera);
        float tile_pixels = tile_world_ * scale * pixels_per_unit_at_1 /
                            (camera.orthographic ? 1.0f : std::max(depth - radius, camera.near_plane));
        const bool has_coarse = coarse_end_ > fine_count_;
        const int proxy_level = !tiles                                  ? 2
                                : tile_pixels >= k_min_tile_pixels      ? 0
                                : has_coarse && tile_pixels * coarse_tile_factor_ >=
                                                    k_min_tile_pixels ? 1
                                                                      : 2;
        visible.push_back({depth, std::uint32_t(i), inside, proxy_level, scale});
        // the most texels a pixel can span on a billboard of this instance (march.frag's
        // texels_per_pixel): neighbouring rays at distance t lie at most t / pixels_per_unit_at_1
        // apart (orthographic: 1 / pixels_per_unit_at_1), t at most the sphere's far side, and a
        // world length is at most 1 / (texel x the transform's smallest singular value) texels:
        // that value is the axis scale for a similarity, else at least 2 |det| / |m|_F^2
        const glm::mat3 axes(m);
        const float smallest_scale =
            similarity(axes) ? glm::length(axes[0])
                             : 2.0f * std::abs(glm::determinant(axes)) /
                                   std::max(glm::dot(axes[0], axes[0]) + glm::dot(axes[1], axes[1]) + glm::dot(axes[2], axes[2]), 1e-30f);
        const float far_distance = camera.orthographic ? 1.0f : glm::length(centre - camera.eye_world) + radius;
        const float texels_per_pixel = far_distance / (pixels_per_unit_at_1 * smallest_texel_ * std::max(smallest_scale, 1e-30f));
        if (!(texels_per_pixel < k_lod_texels_per_pixel)) lod_instances_[i] = 1;
        float radius_pixels = radius * pixels_per_unit_at_1 / (camera.orthographic ? 1.0f : std::max(depth, camera.near_plane));
        if (inside || radius_pixels >= k_min_coarse_radius_pixels) {
            // the coarsest level that strays under half a pixel from the coarse mesh at the
            // instance's nearest point (--coarse-lod)
            std::size_t level = 0;
            const float pixels_per_unit = pixels_per_unit_at_1 / (camera.orthographic ? 1.0f : std::max(depth - radius, camera.near_plane));
            while (!inside && level + 1 < coarse_levels_.size() &&
                   coarse_levels_[level + 1].error * scale * pixels_per_unit <= k_coarse_level_pixels)
                ++level;
            coarse_instances_.push_back(std::uint32_t(i));
            coarse_instance_levels_.push_back(std::uint8_t(level));
        }
    }
    std::sort(visible.begin(), visible.end(),
              [](const Visible& a, const Visible& b) { return a.depth < b.depth || (a.depth == b.depth && a.instance < b.instance); });

    front_entries_.clear();
    inside_entries_.clear();
    hidden_area_ = 0.0;
    for (const Visible& v : visible) {
        const glm::mat4& m = transforms[v.instance];
        glm::vec3 centre = glm::vec3(m * glm::vec4(bound_centre_, 1.0f));
        glm::vec3 forward_world = camera.orthographic ? camera.forward_world : centre - camera.eye_world;
        glm::vec3 forward_object = glm::transpose(glm::mat3(m)) * forward_world; // ordering only: no scale needed
        // --cull-back-proxies: proxies holding only back hits are left out. Where such a hit was
        // the nearest (on one closed surface: a hole between captures), the coarse mesh (which
        // fills every pixel without a front hit, --coarse-fill empty) or what lies behind shows
        // instead; not with --coarse-fill near-misses, which reads the near misses back hits mark.
        // march.frag turns normals by mat3(world_from_object): the object-space test decides as
        // it does only for rotations and uniform scales.
        BackCull cull;
        const bool culls = cull_back_proxies_ && !marks_near_misses() && similarity(glm::mat3(m));
        // the eye in object space, for both cullers (the exact inverse: any affine transform)
        const glm::mat4 object_from_world = glm::inverse(m);
        const glm::vec3 eye_object = glm::vec3(object_from_world * glm::vec4(camera.eye_world, 1.0f));
        if (culls) {
            cull.orthographic = camera.orthographic;
            cull.eye_object = camera.orthographic ? glm::transpose(glm::mat3(m)) * -camera.forward_world : eye_object;
        }
        // --cull-hidden-proxies: proxies hidden along the eye's direction to them are left out. Along
        // a line, occlusion is the same under any affine transform and for orthographic and
        // perspective rays, as long as no part of the model lies behind the eye or before the near
        // plane: so not for an instance whose texels' sphere holds the eye or reaches the near
        // plane, nor where rays mark near misses behind what hides them (--coarse-fill near-misses).
        BackCull hidden;
        bool hides = cull_hidden_proxies_ && !hidden_.empty() && !marks_near_misses();
        if (hides) {
            const glm::vec3 texel_centre = glm::vec3(m * glm::vec4(hidden_.texel_centre(), 1.0f));
            // (reaches_near_plane's margin grows with the distance: a far instance would never pass)
            hides = glm::dot(texel_centre - camera.eye_world, camera.forward_world) - hidden_.texel_radius() * v.scale * 1.01f >
                    camera.near_plane;
        }
        if (hides) {
            hidden.orthographic = camera.orthographic;
            if (camera.orthographic) {
                hidden.eye_object = glm::mat3(object_from_world) * -camera.forward_world;
            } else {
                hidden.eye_object = eye_object;
                hides = glm::length(hidden.eye_object - hidden_.texel_centre()) > hidden_.texel_radius() * 1.001f + 1e-6f;
            }
        }
        const NearSplit near{&m, v.scale, &camera};
        append_proxies(v.instance, v.proxy_level, forward_object, culls ? &cull : nullptr, hides ? &hidden : nullptr,
                       v.inside ? &near : nullptr, front_entries_, inside_entries_);
    }
    // the inside pass first: its proxies are the nearest, and front to back is what stops rays early
    std::array<GLsizei, 2> counts = {GLsizei(inside_entries_.size()), GLsizei(front_entries_.size())};
    draw_entries_.assign(inside_entries_.begin(), inside_entries_.end());
    draw_entries_.insert(draw_entries_.end(), front_entries_.begin(), front_entries_.end());
    if (draw_entries_.size() > draw_list_capacity_ || !draw_list_) {
        draw_list_capacity_ = std::max<std::size_t>({draw_entries_.size(), 2 * draw_list_capacity_, 64});
        draw_list_ = gpu::make_buffer(nullptr, draw_list_capacity_ * sizeof(DrawEntry), GL_DYNAMIC_STORAGE_BIT);
    }
    if (!draw_entries_.empty())
        glNamedBufferSubData(draw_list_.get(), 0, GLsizeiptr(draw_entries_.size() * sizeof(DrawEntry)),
                             draw_entries_.data());
    return counts;
}

// The boxes' mean projected area (ProxyInfo::mean_area) over the model's bounding disc: about the
// fragments per covered pixel they would draw from an average direction, up to a factor of the
// model's shape (measured 0.1-0.15 of the overdraw, a scan and an assembly).
double BillboardRenderer::box_overdraw(std::span<const DrawEntry> entries) const
{
    double area = 0.0;
    for (const DrawEntry& entry : entries) area += double(proxies_[entry.tile].mean_area);
    const double disc = std::numbers::pi * double(bound_radius_) * double(bound_radius_);
    return disc > 0.0 ? area / disc : 0.0;
}

// Depth batches of the front pass (reps/common/depth_batches.h): batches of whole instances, whose
// boxes lie together in front_entries_ (build_draw_list), ending at DepthBatches::batch_ends of the
// instance count; with each batch's screen rectangle (batch_rects_) for its resolve. One instance
// whose boxes overlap deeply is drawn in batches of its boxes instead (k_box_batch_overdraw).
std::vector<std::size_t> BillboardRenderer::front_batch_ends(const DrawParams& params)
{
    static const glm::mat4 identity(1.0f);
    std::vector<std::size_t> instance_ends; // in front_entries_, where each instance's boxes end
    for (std::size_t k = 1; k <= front_entries_.size(); ++k)
        if (k == front_entries_.size() || front_entries_[k].instance != front_entries_[k - 1].instance) instance_ends.push_back(k);
    std::vector<std::size_t> ends;
    batch_rects_.clear();
    // (the hidden proxies left out count: how deep the model's layers lie is what decides whether
    // batches pay, and the boxes kept still lie behind each other where the model is deep)
    const double disc = std::numbers::pi * double(bound_radius_) * double(bound_radius_);
    const double overdraw = instance_ends.size() == 1 ? box_overdraw(front_entries_) + (disc > 0.0 ? hidden_area_ / disc : 0.0) : 0.0;
    if (overdraw >= k_box_batch_overdraw) {
        // one instance whose boxes lie deep behind each other (nested parts, foliage): batches of its
        // boxes, front to back, each after the first tested early against those before it
        const glm::mat4& m = params.world_from_object.empty() ? identity : params.world_from_object[front_entries_[0].instance];
        const glm::ivec4 rect =
            reps::DepthBatches::sphere_rect(params.camera, params.viewport, m, bound_centre_, bound_radius_ * 1.001f);
        const std::size_t growth = overdraw >= k_deep_box_overdraw ? 2 : 4;
        for (std::size_t end = std::min(front_entries_.size(), k_first_box_batch); end > 0;
             end = std::min(front_entries_.size(), growth * end)) {
            ends.push_back(end);
            batch_rects_.push_back(rect);
            if (end == front_entries_.size()) break;
        }
        return ends;
    }
    std::size_t instance_begin = 0;
    for (const std::size_t instance_end : reps::DepthBatches::batch_ends(instance_ends.size())) {
        glm::ivec4 rect(0);
        for (std::size_t i = instance_begin; i < instance_end; ++i) {
            const std::uint32_t instance = front_entries_[instance_ends[i] - 1].instance;
            const glm::mat4& m = params.world_from_object.empty() ? identity : params.world_from_object[instance];
            rect = reps::DepthBatches::rect_union(
                rect, reps::DepthBatches::sphere_rect(params.camera, params.viewport, m, bound_centre_, bound_radius_ * 1.001f));
        }
        ends.push_back(instance_ends[instance_end - 1]);
        batch_rects_.push_back(rect);
        instance_begin = instance_end;
    }
    return ends;
}

DrawStats BillboardRenderer::draw(const DrawParams& params)
{
    DrawStats stats;
    frame_.bind(params);
    GLsizei instances = GLsizei(frame_.instance_count());
    bool coarse = coarse_index_count_ > 0;
    prepare_pixel_images(params.viewport, marks_near_misses());
    glEnable(GL_DEPTH_TEST);

    // billboards: front faces of boxes beyond the near plane, back faces of boxes crossing it
    if (billboard_count_ > 0) {
        std::array<GLsizei, 2> counts = build_draw_list(params);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_BILLBOARDS_SSBO, billboards_.get());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_TILES_SSBO, tiles_.get());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_DRAW_LIST_SSBO, draw_list_.get());
        counters_.bind();
        glBindTextureUnit(BINDING_COLOR_MAPS, color_maps_.get());
        glBindTextureUnit(BINDING_NORMAL_MAPS, normal_maps_.get());
        glBindTextureUnit(BINDING_SURFACE_MAPS, surface_maps_.get());
        glBindTextureUnit(BINDING_MINMAX_MAPS, minmax_maps_.get());
        glBindTextureUnit(BINDING_COLOR_MIPS, color_mips_.get());
        glBindTextureUnit(BINDING_ORM_MAPS, orm_maps_ ? orm_maps_.get() : 0u);
        glBindTextureUnit(BINDING_EMISSION_MAPS, emission_maps_ ? emission_maps_.get() : 0u);
        glBindVertexArray(empty_vertex_array_.get());
        glEnable(GL_CULL_FACE);
        glFrontFace(GL_CCW);
        // depth batches (reps/common/depth_batches.h): the front pass's first batch drawn as it is,
        // the later ones tested early against the batches resolved before them; not where rays mark
        // near misses behind back hits (--coarse-fill near-misses), which an early test would stop
        const bool batches = depth_batches_on_ && !marks_near_misses() && counts[1] > 0 && depth_batches_.begin_frame();
        for (int pass = 0; pass < 2; ++pass) {
            if (counts[pass] == 0) continue;
            glCullFace(pass == 0 ? GL_FRONT : GL_BACK);
            const GLint first = pass == 0 ? 0 : counts[0];
            std::vector<std::size_t> ends = {std::size_t(counts[pass])};
            if (pass == 1 && batches) ends = front_batch_ends(params);
            const std::vector<DrawEntry>& entries = pass == 0 ? inside_entries_ : front_entries_;
            std::size_t begin = 0;
            for (std::size_t batch = 0; batch < ends.size(); ++batch) {
                const std::size_t end = ends[batch];
                const bool early = begin > 0;
                const bool lod = entries_need_lod(std::span<const DrawEntry>(entries).subspan(begin, end - begin));
                const MarchProgram& march = march_program(early ? MarchPass::front_batched : pass == 0 ? MarchPass::inside : MarchPass::front, lod);
                const gpu::Program& program = march.program;
                const ProgramLocations& at = march.at;
                std::uint32_t stamp = 0;
                if (early) {
                    stamp = depth_batches_.begin_batch();
                    glProgramUniform1ui(program.id(), at.depth_batch, stamp);
                }
                set_march_uniforms(program, at, first + GLint(begin));
                program.use();
                glBindVertexArray(empty_vertex_array_.get());
                glDrawElementsInstanced(GL_TRIANGLES, 36, GL_UNSIGNED_SHORT, nullptr, GLsizei(end - begin));
                stats.draw_calls += 1;
                if (early) {
                    depth_batches_.resolve(stamp, batch_rects_[batch]);
                    stats.draw_calls += 1;
                }
                begin = end;
            }
            stats.primitives += std::uint64_t(counts[pass]) * 12;
        }
        if (batches) depth_batches_.end_frame();
        glDisable(GL_CULL_FACE);
        glCullFace(GL_BACK);
    }

    // the coarse mesh on pixels without a front hit (--coarse-fill near-misses: only where rays
    // came near a surface and missed), on instances large enough to show a hole (build_draw_list
    // chose them; with no billboards at all, every instance)
    if (coarse && billboard_count_ == 0) {
        coarse_instances_.resize(std::size_t(instances));
        for (std::size_t i = 0; i < coarse_instances_.size(); ++i) coarse_instances_[i] = std::uint32_t(i);
        coarse_instance_levels_.assign(coarse_instances_.size(), 0);
    }
    // the instances by level, each level's a run of the list (a stable order: the same at every run)
    std::vector<std::size_t> level_ends;
    if (coarse && !coarse_instances_.empty()) {
        std::vector<std::uint32_t> by_level;
        by_level.reserve(coarse_instances_.size());
        for (std::size_t level = 0; level < coarse_levels_.size(); ++level) {
            for (std::size_t k = 0; k < coarse_instances_.size(); ++k)
                if (coarse_instance_levels_[k] == level) by_level.push_back(coarse_instances_[k]);
            level_ends.push_back(by_level.size());
        }
        coarse_instances_ = std::move(by_level);
    }
    if (coarse && !coarse_instances_.empty()) {
        if (coarse_instances_.size() > coarse_list_capacity_ || !coarse_list_) {
            coarse_list_capacity_ = std::max<std::size_t>({coarse_instances_.size(), 2 * coarse_list_capacity_, 64});
            coarse_list_ = gpu::make_buffer(nullptr, coarse_list_capacity_ * sizeof(std::uint32_t), GL_DYNAMIC_STORAGE_BIT);
        }
        glNamedBufferSubData(coarse_list_.get(), 0, GLsizeiptr(coarse_instances_.size() * sizeof(std::uint32_t)),
                             coarse_instances_.data());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BINDING_COARSE_LIST_SSBO, coarse_list_.get());
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        glProgramUniform1i(coarse_.id(), coarse_near_only_at_, fill_near_misses_only_ ? 1 : 0);
        glProgramUniform1i(coarse_.id(), coarse_debug_at_, debug_view_);
        coarse_.use();
        coarse_mesh_.bind();
        // models with open single-sided parts (back_hits "hide"): the truth culls their backs, and
        // so does the coarse mesh (closed parts show no back face anyway); one closed surface wound
        // outward: its back faces lie behind its front faces, which fill every hole they could
        // (the same picture for half the fragments: docs/RESULTS.md). A mirroring instance turns
        // its faces' winding, and one draw holds every instance: where any mirrors, the culling
        // the picture needs (back_hits "hide") is coarse.frag's, and the other is left out
        const bool mirrors = frame_.any_instance_mirrors();
        glProgramUniform1i(coarse_.id(), coarse_cull_in_shader_at_, hide_back_hits_ && mirrors ? 1 : 0);
        if ((hide_back_hits_ || one_closed_surface_) && !mirrors) {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(GL_CCW);
        }
        GLsizei coarse_count = GLsizei(coarse_instances_.size());
        glProgramUniform1i(coarse_.id(), coarse_first_at_, 0);
        if (coarse_rim_index_count_ > 0 && fill_near_misses_only_) {
            // sheet rims (rims_first): without the near-miss test
            glProgramUniform1i(coarse_.id(), coarse_near_only_at_, 0);
            glDrawElementsInstanced(GL_TRIANGLES, coarse_rim_index_count_, GL_UNSIGNED_INT, nullptr, coarse_count);
            glProgramUniform1i(coarse_.id(), coarse_near_only_at_, 1);
            stats.draw_calls += 1;
        }
        if (fill_near_misses_only_) {
            const GLsizei first = coarse_rim_index_count_;
            glDrawElementsInstanced(GL_TRIANGLES, coarse_index_count_ - first, GL_UNSIGNED_INT,
                                    reinterpret_cast<const void*>(std::uintptr_t(first) * sizeof(std::uint32_t)), coarse_count);
            stats.draw_calls += 1;
            stats.primitives += std::uint64_t(coarse_index_count_ / 3) * std::uint64_t(coarse_count);
        } else {
            for (std::size_t level = 0, begin = 0; level < level_ends.size(); begin = level_ends[level++]) {
                const GLsizei count = GLsizei(level_ends[level] - begin);
                if (count == 0) continue;
                const reps::CoarseLevel& at = coarse_levels_[level];
                glProgramUniform1i(coarse_.id(), coarse_first_at_, GLint(begin));
                glDrawElementsInstanced(GL_TRIANGLES, GLsizei(at.index_count), GL_UNSIGNED_INT,
                                        reinterpret_cast<const void*>(std::uintptr_t(at.first_index) * sizeof(std::uint32_t)), count);
                stats.draw_calls += 1;
                stats.primitives += std::uint64_t(at.index_count / 3) * std::uint64_t(count);
            }
        }
        glDisable(GL_CULL_FACE);
    }

    // debug view "proxies": the boxes over the picture (lines are not counted as primitives)
    if (box_lines_) draw_box_lines(stats);
    glBindVertexArray(0);
    return stats;
}

} // namespace

Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings)
{
    return BillboardRenderer::create(reps::package_cast<EnhancedBillboardsPackage>(package), settings);
}

} // namespace standin::billboards
