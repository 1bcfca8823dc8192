// The GPU renderer of view atlases: one quad per instance, views chosen per instance in the vertex
// stage (shaders/atlas.vert), the atlas read per pixel (shaders/atlas.frag).
// Saraiva et al. (§3): style "seed" shows the view nearest to the
// viewing direction (largest cosine) on a camera-facing quad through the sphere's centre.
// Beyond the paper (its §7): "octahedral-baseline" blends the three views around the direction with
// one parallax step, as impostor bakers do; "corrected" (default) picks the three views around each
// pixel's own ray, intersects each view's height field exactly (texel tops and the walls between
// neighbours of one surface, never across a depth edge), votes on coverage, blends the hits on the
// nearest surface, lights the stored normals and writes true depth. Its proxy is the source box cut
// by the package's proxy planes (hull.h proxy_polytope: a few planes tangent to the model, baked),
// drawn with back faces culled; for instances under --hull-above pixels, where the near plane would
// clip it, for mirroring transforms and for packages without proxy planes, the nearest view's crop
// prism (overdraw measured by the fragment counter, `standin bench`).
// Crowds (beyond the paper): a level-of-detail ladder by the instance's size on screen (atlas.vert:
// corrected, then the baseline's shading on the same hull under --baseline-below pixels, then the
// seed's quad under --seed-below), and instances drawn front to back (draw) so that early depth tests reject
// hidden instances' fragments before they walk; llvmpipe tests depth only after this fragment stage,
// so the stage rejects them itself against a record of the depths drawn (bind_early_reject).
// Differences from the paper: the seed's mip maps bled the background (§5); here pages are
// premultiplied by coverage before mip-mapping and divided by the filtered coverage, and levels stop
// where two crops would mix (view_atlas.h, k_cell). Coverage may be fractional (alpha-tested
// models, issue #14): the corrected walk keeps a crossing where the filtered coverage reaches 1/2
// (atlas.frag, hit_coverage), and the normal-depth pages' level 0 is not premultiplied, so the walk
// reads a partly covered texel's full depth (upload_pages).
// PBR packages (issue #14) add ORM and emission pages, read where the colour is read (premultiplied
// by coverage like the normals) and lit with shade_pbr_at; the program is compiled with ATLAS_PBR
// only for them, so other packages bind and read nothing more.
// Pages are split over up to ATLAS_MAX_ARRAYS texture arrays per map (plan_arrays: layer and byte
// limits), the fragment stage picks a view's array by branching.
// Load-time tables: per-view height ranges and per-cell highest surfaces for the corrected walk; a
// direction lookup cube (the nearest view of each cell's centre) and each view's
// NEIGHBOURS nearest views, so the vertex stage finds the nearest view by a short walk.
#include "reps/view_atlas/view_atlas.h"
#include "reps/common/depth_batches.h"
#include "reps/common/package_cast.h"
#include "reps/view_atlas/hull.h"

#include "gpu/counters.h"
#include "gpu/frame.h"
#include "gpu/gl.h"
#include "reps/view_atlas/shaders/atlas_layout.glsl"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <utility>

namespace standin::view_atlas {

namespace {

// std430 mirror of ViewData in shaders/atlas.glsl
struct ViewGpu {
    glm::vec4 direction, axis_u, axis_v;
    glm::ivec4 crop, atlas;
    glm::vec4 depth_range;
};
static_assert(sizeof(ViewGpu) == 96, "std430 layout of ViewData");
static_assert(ATLAS_CELL == k_cell, "the walk skips the cells crops are placed on");

// The magnitudes of a texel top's slope along a view's axis_u and axis_v (height per plane unit)
// from its stored normal, capped: atlas.frag's texel_gradient.
glm::vec2 top_slope(const glm::vec3& normal, const View& view)
{
    const float across = std::max(glm::dot(normal, view.direction), 1e-6f);
    return glm::min(glm::abs(glm::vec2(glm::dot(normal, view.axis_u), glm::dot(normal, view.axis_v))) / across,
                    glm::vec2(ATLAS_TOP_MAX_SLOPE));
}

// Per ATLAS_CELL x ATLAS_CELL cell of every page, the nearest and farthest depth of its covered
// texels' tops in 1/65535 of the range (rounded outwards: the nearest down, the farthest up; 65535 /
// 0 when empty), from one pass over the views' crops (every covered texel lies in one): the
// corrected walk skips cells a ray passes above (nearest codes, uploaded by upload_cell_tops), and
// each view's height range is the range over its crop's cells (crops sit on whole cells). A top is
// tilted by its normal (atlas.frag, texel_gradient), so it reaches up to half a texel's tilt beyond
// the stored depth at the texel's centre.
struct CellDepths {
    int cells = 0;                         // per page side
    std::vector<std::uint16_t> nearest, farthest; // page-major, then row-major cells
    bool partial_coverage = false;         // some texel's alpha is neither 0 nor 255 (alpha-tested bakes)
};

CellDepths cell_depths(const ViewAtlasPackage& package)
{
    CellDepths depths;
    if (!package.has_surface()) return depths;
    const int size = package.settings.page_size;
    depths.cells = size / ATLAS_CELL;
    const std::size_t per_page = std::size_t(depths.cells) * depths.cells;
    depths.nearest.assign(per_page * package.color_pages.size(), 65535);
    depths.farthest.assign(per_page * package.color_pages.size(), 0);
    // codes over 65535 per unit of depth, and half a texel's tilt in such codes per unit of slope
    const double max_code = package.has_fine_depth() ? double(depth_code_max(package.settings.depth_bits)) : 255.0;
    const double texel = 2.0 * package.half_extent() / package.settings.resolution;
    const double tilt_codes = 0.5 * texel / (2.0 * package.radius) * 65535.0;
    for (const View& view : package.views) {
        if (view.width == 0) continue;
        const ImageRGBA8& color = package.color_pages[std::size_t(view.page)];
        const ImageRGBA8& normal_depth = package.normal_depth_pages[std::size_t(view.page)];
        for (int y = view.atlas_y; y < view.atlas_y + view.height; ++y)
            for (int x = view.atlas_x; x < view.atlas_x + view.width; ++x) {
                const std::uint8_t alpha = color.at(x, y)[3];
                if (alpha == 0) continue; // any coverage: the walk meets every covered texel
                depths.partial_coverage = depths.partial_coverage || alpha != 255;
                const std::uint8_t* nd = normal_depth.at(x, y);
                const double code = (package.has_fine_depth() ? double(package.depth_pages[std::size_t(view.page)][std::size_t(y) * size + x])
                                                              : double(nd[3])) * 65535.0 / max_code;
                const glm::vec3 n = glm::vec3(nd[0], nd[1], nd[2]) / 127.5f - 1.0f;
                const glm::vec2 slope = top_slope(n, view);
                const double tilt = tilt_codes * (double(slope.x) + double(slope.y)) + 1.0; // + 1: float rounding
                const std::size_t cell = std::size_t(view.page) * per_page + std::size_t(y / ATLAS_CELL) * depths.cells +
                                         std::size_t(x / ATLAS_CELL);
                depths.nearest[cell] = std::uint16_t(std::min<double>(depths.nearest[cell], std::max(std::floor(code - tilt), 0.0)));
                depths.farthest[cell] = std::uint16_t(std::max<double>(depths.farthest[cell], std::min(std::ceil(code + tilt), 65535.0)));
            }
    }
    return depths;
}

// The heights above the centre plane of a view's nearest and farthest stored surface (x, y; x < y
// when the view holds nothing), so the corrected style walks only the slab between them.
glm::vec2 depth_range(const ViewAtlasPackage& package, const CellDepths& depths, const View& view)
{
    if (depths.cells == 0 || view.width == 0) return {-1.0f, 1.0f};
    int nearest = 65535, farthest = -1;
    const std::size_t page = std::size_t(view.page) * depths.cells * depths.cells;
    for (int cy = view.atlas_y / ATLAS_CELL; cy < (view.atlas_y + view.height) / ATLAS_CELL; ++cy)
        for (int cx = view.atlas_x / ATLAS_CELL; cx < (view.atlas_x + view.width) / ATLAS_CELL; ++cx) {
            std::size_t cell = page + std::size_t(cy) * depths.cells + std::size_t(cx);
            if (depths.nearest[cell] > depths.farthest[cell]) continue; // empty
            nearest = std::min<int>(nearest, depths.nearest[cell]);
            farthest = std::max<int>(farthest, depths.farthest[cell]);
        }
    if (farthest < 0) return {-1.0f, 1.0f};
    auto height = [&](int code) { return package.radius - 2.0f * package.radius * float(code) / 65535.0f; };
    return {height(nearest), height(farthest)};
}

int style_code(const std::string& name)
{
    if (name == "seed") return STYLE_SEED;
    if (name == "octahedral-baseline") return STYLE_BASELINE;
    if (name == "corrected") return STYLE_CORRECTED;
    return -1;
}

glm::vec3 lookup_cell_center(int face, int x, int y)
{
    glm::vec2 uv((float(x) + 0.5f) / LOOKUP_SIDE * 2.0f - 1.0f, (float(y) + 0.5f) / LOOKUP_SIDE * 2.0f - 1.0f);
    switch (face) { // inverse of lookup_cell in shaders/atlas.glsl
    case 0: return glm::normalize(glm::vec3(1.0f, uv.x, uv.y));
    case 1: return glm::normalize(glm::vec3(-1.0f, uv.x, uv.y));
    case 2: return glm::normalize(glm::vec3(uv.x, 1.0f, uv.y));
    case 3: return glm::normalize(glm::vec3(uv.x, -1.0f, uv.y));
    case 4: return glm::normalize(glm::vec3(uv.x, uv.y, 1.0f));
    default: return glm::normalize(glm::vec3(uv.x, uv.y, -1.0f));
    }
}

// the lookup cube, then NEIGHBOURS nearest views per view (-1 where there are fewer views)
std::vector<std::int32_t> build_index(const std::vector<View>& views)
{
    const int n = int(views.size());
    std::vector<std::int32_t> index;
    index.reserve(std::size_t(6 * LOOKUP_SIDE * LOOKUP_SIDE + n * NEIGHBOURS));
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < LOOKUP_SIDE; ++y)
            for (int x = 0; x < LOOKUP_SIDE; ++x) {
                glm::vec3 d = lookup_cell_center(face, x, y);
                int best = 0;
                for (int k = 1; k < n; ++k)
                    if (glm::dot(views[std::size_t(k)].direction, d) > glm::dot(views[std::size_t(best)].direction, d)) best = k;
                index.push_back(best);
            }
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
        std::iota(order.begin(), order.end(), 0);
        glm::vec3 d = views[std::size_t(k)].direction;
        auto nearer = [&](int a, int b) {
            float ca = glm::dot(views[std::size_t(a)].direction, d), cb = glm::dot(views[std::size_t(b)].direction, d);
            return ca != cb ? ca > cb : a < b;
        };
        int keep = std::min(n, NEIGHBOURS + 1);
        std::partial_sort(order.begin(), order.begin() + keep, order.end(), nearer);
        int written = 0;
        for (int i = 0; i < keep && written < NEIGHBOURS; ++i)
            if (order[std::size_t(i)] != k) index.push_back(order[std::size_t(i)]), ++written;
        for (; written < NEIGHBOURS; ++written) index.push_back(-1);
    }
    return index;
}

// How the pages of one map are split over texture arrays: consecutive pages, at most
// pages_per_array per array (GL_MAX_ARRAY_TEXTURE_LAYERS and the byte budget).
struct ArrayPlan {
    int pages_per_array = 1;
    int arrays = 1;
    std::uint64_t page_bytes = 0; // one page with its mip levels
};

std::uint64_t page_bytes_with_mips(int size, int bytes_per_texel)
{
    std::uint64_t bytes = 0;
    for (int level = 0; level < k_mip_levels; ++level)
        bytes += std::uint64_t(std::max(size >> level, 1)) * std::max(size >> level, 1) * std::uint64_t(bytes_per_texel);
    return bytes;
}

// the per-texture budget: k_texture_budget_bytes, or STANDIN_ATLAS_TEXTURE_BYTES when set
std::uint64_t texture_budget_bytes()
{
    if (const char* value = std::getenv("STANDIN_ATLAS_TEXTURE_BYTES"); value && *value) {
        char* end = nullptr;
        unsigned long long bytes = std::strtoull(value, &end, 10);
        if (end && *end == '\0' && bytes > 0) return bytes;
    }
    return k_texture_budget_bytes;
}

std::string mib(std::uint64_t bytes)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.1f MiB", double(bytes) / double(1 << 20));
    return text;
}

Result<ArrayPlan> plan_arrays(const ViewAtlasPackage& package, int max_layers)
{
    const int pages = std::max(int(package.color_pages.size()), 1), size = package.settings.page_size;
    std::uint64_t budget = texture_budget_bytes();
    ArrayPlan plan;
    // every map's arrays hold the same pages: as many as the largest map's texels allow (RGBA16
    // normal-depth pages with 16-bit depth)
    plan.page_bytes = page_bytes_with_mips(size, package.has_fine_depth() ? 8 : 4);
    std::uint64_t fit = std::min<std::uint64_t>(budget / plan.page_bytes, std::uint64_t(std::max(max_layers, 1)));
    plan.pages_per_array = int(std::min<std::uint64_t>(fit, std::uint64_t(pages)));
    plan.arrays = plan.pages_per_array > 0 ? (pages + plan.pages_per_array - 1) / plan.pages_per_array : 0;
    if (plan.pages_per_array < 1 || plan.arrays > ATLAS_MAX_ARRAYS) {
        std::string name = !package.directory.empty() ? package.directory : "(baked from " + package.source.file_name + ")";
        return error(StatusCode::unsupported,
                     "view atlas: package " + name + " does not fit: " + std::to_string(pages) + " pages of " +
                         std::to_string(size) + "² (" + mib(plan.page_bytes) + " each with mips, " +
                         mib(plan.page_bytes * std::uint64_t(pages)) + " per map) need more than " +
                         std::to_string(ATLAS_MAX_ARRAYS) + " texture arrays of at most " + std::to_string(fit) +
                         " pages (" + mib(budget) + " per texture, GL_MAX_ARRAY_TEXTURE_LAYERS " +
                         std::to_string(max_layers) + "); bake with fewer views or a lower --resolution");
    }
    return plan;
}

// The cells' nearest depth codes as one R16 texture array, one layer per page.
Result<gpu::Texture> upload_cell_tops(const CellDepths& depths, int pages)
{
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    gpu::Texture texture(name);
    glTextureStorage3D(name, 1, GL_R16, depths.cells, depths.cells, std::max(pages, 1));
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    const std::size_t per_page = std::size_t(depths.cells) * depths.cells;
    for (int page = 0; page < pages; ++page)
        glTextureSubImage3D(name, 0, 0, 0, page, depths.cells, depths.cells, 1, GL_RED, GL_UNSIGNED_SHORT,
                            depths.nearest.data() + std::size_t(page) * per_page);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "view atlas: " + gpu::gl_error_text(e) + " uploading cell heights");
    return texture;
}

// An empty texture array of `count` pages of size² with k_mip_levels levels, filtered trilinearly.
Result<gpu::Texture> allocate_page_array(GLenum format, int size, int count)
{
    while (glGetError() != GL_NO_ERROR) {} // errors from before are not this allocation's
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    gpu::Texture texture(name);
    glTextureStorage3D(name, k_mip_levels, format, size, size, GLsizei(std::max(count, 1)));
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, gpu::gl_error_text(e) + " allocating " + std::to_string(count) +
                                                " layers of " + std::to_string(size) + "²");
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

// Colour pages [first, first + count) as DXT5 (RenderOptions::texture_format "bc3"): the blocks a
// package of --compression bc-color stores, uploaded as they are, or else made here as such a
// package's writer makes them (color_page_blocks: premultiplied, mip levels made on the CPU, as
// compressed formats cannot be mip-mapped by the GL). Coverage survives exactly: a block whose
// alpha is only 0 and 255 stores both as its end points.
Result<gpu::Texture> upload_compressed_color_pages(const ViewAtlasPackage& package, int size, int first, int count)
{
    Result<gpu::Texture> allocated = allocate_page_array(GL_COMPRESSED_RGBA_S3TC_DXT5_EXT, size, count);
    if (!allocated) return allocated.status();
    gpu::Texture texture = std::move(*allocated);
    GLuint name = texture.get();
    for (int k = 0; k < count && std::size_t(first + k) < package.color_pages.size(); ++k) {
        const std::size_t page = std::size_t(first + k);
        const bool stored = page < package.color_bc3.size() && package.color_bc3[page].size() == std::size_t(k_mip_levels);
        std::vector<std::vector<std::uint8_t>> made;
        if (!stored) made = color_page_blocks(package.color_pages[page]);
        const std::vector<std::vector<std::uint8_t>>& levels = stored ? package.color_bc3[page] : made;
        for (int m = 0; m < k_mip_levels; ++m) {
            const int level_size = std::max(size >> m, 1);
            glCompressedTextureSubImage3D(name, m, 0, 0, GLint(k), level_size, level_size, 1,
                                          GL_COMPRESSED_RGBA_S3TC_DXT5_EXT, GLsizei(levels[std::size_t(m)].size()),
                                          levels[std::size_t(m)].data());
        }
    }
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, gpu::gl_error_text(e) + " uploading DXT5 pages");
    return texture;
}

// Pages [first, first + count) of one map in one texture array. `whole_level0` (normal-depth
// pages): mip levels are made from the pages premultiplied by coverage like every map's, then level
// 0 is replaced by the pages premultiplied by "any coverage", i.e. the stored normal and depth on
// every covered texel. The corrected walk reads heights there (one fetch per texel, atlas.frag
// height_texel): a partly covered edge texel (fractional coverage, issue #14) must keep its full
// depth, which dividing by its coverage would coarsen; readers that filter level 0 take the
// colour's alpha as its weight (surface_sample). `depth16` (normal-depth pages of a package with
// 16-bit depth): the array is RGBA16, its A the 16-bit depth (premultiplied16).
Result<gpu::Texture> upload_pages(const std::vector<ImageRGBA8>& pages, const std::vector<ImageRGBA8>& coverage,
                                  bool color, int size, int first, int count, bool whole_level0,
                                  const std::vector<std::vector<std::uint16_t>>* depth16)
{
    Result<gpu::Texture> allocated = allocate_page_array(depth16 ? GL_RGBA16 : GL_RGBA8, size, count);
    if (!allocated) return allocated.status();
    gpu::Texture texture = std::move(*allocated);
    GLuint name = texture.get();
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    auto upload = [&](int k, bool any) {
        const std::size_t page = std::size_t(first + k);
        if (depth16) {
            std::vector<std::uint16_t> data = premultiplied16(pages[page], (*depth16)[page], coverage[page], any);
            glTextureSubImage3D(name, 0, 0, 0, GLint(k), size, size, 1, GL_RGBA, GL_UNSIGNED_SHORT, data.data());
        } else {
            std::vector<std::uint8_t> data = premultiplied(pages[page], coverage[page], color, any);
            glTextureSubImage3D(name, 0, 0, 0, GLint(k), size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE, data.data());
        }
    };
    for (int k = 0; k < count && std::size_t(first + k) < pages.size(); ++k) upload(k, false);
    glGenerateTextureMipmap(name);
    for (int k = 0; whole_level0 && k < count && std::size_t(first + k) < pages.size(); ++k) upload(k, true);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, gpu::gl_error_text(e) + " uploading pages");
    return texture;
}

// Every page of one map, split as planned.
Status upload_map(const ViewAtlasPackage& package, const std::vector<ImageRGBA8>& pages, bool color, const char* map_name,
                  const ArrayPlan& plan, bool compressed, std::vector<gpu::Texture>& arrays)
{
    for (int a = 0; a < plan.arrays; ++a) {
        int first = a * plan.pages_per_array;
        int count = std::min(plan.pages_per_array, std::max(int(pages.size()), 1) - first);
        Result<gpu::Texture> texture =
            compressed ? upload_compressed_color_pages(package, package.settings.page_size, first, count)
                       : upload_pages(pages, package.color_pages, color, package.settings.page_size, first, count,
                                      &pages == &package.normal_depth_pages,
                                      &pages == &package.normal_depth_pages && package.has_fine_depth() ? &package.depth_pages : nullptr);
        if (!texture) {
            std::string name = !package.directory.empty() ? package.directory : "(baked from " + package.source.file_name + ")";
            return error(StatusCode::gpu_error, "view atlas: package " + name + ", " + map_name +
                                                    " texture array " + std::to_string(a + 1) + " of " +
                                                    std::to_string(plan.arrays) + " (" + mib(plan.page_bytes * std::uint64_t(count)) +
                                                    "): " + texture.status().message());
        }
        arrays.push_back(std::move(*texture));
    }
    return Status::ok();
}

class AtlasRenderer final : public Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const ViewAtlasPackage& package, const RenderSettings& settings);
    DrawStats draw(const DrawParams& params) override;
    void set_counting(bool on) override { counters_.set_counting(on); }
    std::uint64_t read_counter(Counter counter) override { return counters_.read(int(counter)); }

private:

    // One program per fragment path (atlas.frag ATLAS_PATH), indexed by ATLAS_LOD_*: only those the
    // style and the level-of-detail options draw are made (id 0 for the others).
    struct PathProgram {
        gpu::Program program;
        GLint counting_at = -1, early_reject_at = -1, hull_pass_at = -1, instance_offset_at = -1, draw_lod_at = -1,
              depth_batch_at = -1;
    };
    PathProgram paths_[3];
    // --depth-batches (reps/common/depth_batches.h): the same programs compiled with DEPTH_BATCHES,
    // for the instances after the first batch, on software rasterisers only
    PathProgram batched_paths_[3];
    reps::DepthBatches depth_batches_;
    bool depth_batches_on_ = false;
    int level_of(float pixels) const;
    std::vector<gpu::Texture> color_arrays_, normal_depth_arrays_; // ArrayPlan: consecutive pages
    std::vector<gpu::Texture> orm_arrays_, emission_arrays_;       // PBR packages only
    gpu::Texture cell_tops_; // surface maps only (upload_cell_tops)
    gpu::Texture nearest_;   // early rejection's record (atlas.frag nearest_depth), grown to the viewport
    glm::ivec2 nearest_size_{0, 0};
    bool early_reject_ = true; // the run-time option
    gpu::Buffer views_, index_;
    // the proxy hull (hull.h proxy_polytope): vertices (SSBO), fan triangles (element buffer), face
    // corners for the near-plane test; empty: the prism for every instance
    gpu::Buffer hull_vertices_, hull_indices_;
    gpu::VertexArray hull_vertex_array_;
    GLsizei hull_index_count_ = 0;
    std::vector<glm::vec4> hull_corners_;
    float seed_below_ = 0.0f, baseline_below_ = 0.0f, hull_above_ = 0.0f;
    float sphere_pixels(const glm::mat4& world_from_object, const DrawParams& params) const;
    bool on_hull(const glm::mat4& world_from_object, const DrawParams& params, float pixels) const;
    gpu::Counters counters_;
    int style_ = STYLE_CORRECTED;
    bool bind_early_reject();
    glm::vec3 center_{0.0f};                // the package's bounding sphere centre (object space)
    float radius_ = 0.0f;                   // and radius
    std::vector<glm::mat4> sorted_;         // this frame's instances, front to back (draw)
    std::vector<std::pair<float, std::uint32_t>> order_; // (view depth, index), reused across frames
    std::vector<char> hull_chosen_;                      // per instance: on_hull, this frame
    std::vector<std::uint8_t> level_chosen_;             // per instance: ATLAS_LOD_*, this frame
    gpu::VertexArray empty_vertex_array_;
    gpu::FrameResources frame_;
};

Status check_package(const ViewAtlasPackage& package)
{
    const BakeSettings& s = package.settings;
    if (package.views.empty()) return error(StatusCode::bad_data, "view atlas: no views");
    if (package.has_surface() && package.normal_depth_pages.size() != package.color_pages.size())
        return error(StatusCode::bad_data, "view atlas: normal-depth pages missing");
    if (package.has_fine_depth() && package.depth_pages.size() != package.color_pages.size())
        return error(StatusCode::bad_data, "view atlas: 16-bit depth pages missing");
    for (const std::vector<std::uint16_t>& depth : package.depth_pages)
        if (depth.size() != std::size_t(s.page_size) * std::size_t(s.page_size))
            return error(StatusCode::bad_data, "view atlas: a 16-bit depth page is not page_size square");
    if (package.has_pbr() && (!package.has_surface() || package.orm_pages.size() != package.color_pages.size() ||
                              package.emission_pages.size() != package.color_pages.size()))
        return error(StatusCode::bad_data, "view atlas: ORM or emission pages missing, or without surface maps");
    for (std::size_t k = 0; k < package.orm_pages.size(); ++k)
        if (package.orm_pages[k].width != s.page_size || package.orm_pages[k].height != s.page_size ||
            package.emission_pages[k].width != s.page_size || package.emission_pages[k].height != s.page_size)
            return error(StatusCode::bad_data, "view atlas: PBR page " + std::to_string(k) + " is not page_size square");
    for (std::size_t k = 0; k < package.color_pages.size(); ++k) {
        const ImageRGBA8& page = package.color_pages[k];
        if (page.width != s.page_size || page.height != s.page_size ||
            (package.has_surface() && (package.normal_depth_pages[k].width != s.page_size ||
                                       package.normal_depth_pages[k].height != s.page_size)))
            return error(StatusCode::bad_data, "view atlas: page " + std::to_string(k) + " is not page_size square");
    }
    for (std::size_t k = 0; k < package.views.size(); ++k) {
        const View& v = package.views[k];
        if (v.width > 0 && (v.page < 0 || v.page >= int(package.color_pages.size()) || v.atlas_x < 0 || v.atlas_y < 0 ||
                            v.atlas_x + v.width > s.page_size || v.atlas_y + v.height > s.page_size))
            return error(StatusCode::bad_data, "view atlas: view " + std::to_string(k) + " lies outside its page");
    }
    return Status::ok();
}

Result<std::unique_ptr<Renderer>> AtlasRenderer::create(const ViewAtlasPackage& package, const RenderSettings& settings)
{
    const std::string& style_name = settings.options.choice("style");
    int style = style_code(style_name);
    if (style != STYLE_SEED && !package.has_surface())
        return error(StatusCode::invalid_argument, "view atlas: --style " + style_name +
                                                       " needs depth: bake with --maps surface (this package has lit colour only)");
    if (style == STYLE_CORRECTED && package.settings.projection != "ortho")
        return error(StatusCode::unsupported, "view atlas: --style corrected needs orthographic views (bake with "
                                              "--projection ortho); use --style seed or octahedral-baseline");
    int debug_view = int(settings.debug_view);
    STANDIN_RETURN_IF_ERROR(check_package(package));

    GLint max_layers = 0, max_size = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (package.settings.page_size > max_size)
        return error(StatusCode::unsupported, "view atlas: page_size " + std::to_string(package.settings.page_size) +
                                                  " exceeds GL_MAX_TEXTURE_SIZE " + std::to_string(max_size));
    Result<ArrayPlan> plan = plan_arrays(package, max_layers);
    if (!plan) return plan.status();
    const bool pbr = package.has_pbr();
    if (pbr) { // four maps' arrays, the cell tops and the shadow map in one fragment stage
        GLint units = 0, combined = 0;
        glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
        glGetIntegerv(GL_MAX_COMBINED_TEXTURE_IMAGE_UNITS, &combined);
        if (4 * plan->arrays + 2 > units || ATLAS_EMISSION_TEXTURE + plan->arrays > combined)
            return error(StatusCode::unsupported, "view atlas: a PBR package of " + std::to_string(plan->arrays) +
                                                      " texture arrays per map needs more than this OpenGL's " +
                                                      std::to_string(units) + " texture units; bake with fewer views or a lower --resolution");
    }

    auto renderer = std::make_unique<AtlasRenderer>();
    renderer->seed_below_ = style == STYLE_CORRECTED ? float(settings.options.number("seed-below")) : 0.0f;
    renderer->baseline_below_ = style == STYLE_CORRECTED ? float(settings.options.number("baseline-below")) : 0.0f;
    // depth batches where the rasteriser tests depth after a shader that writes it (llvmpipe)
    renderer->early_reject_ = settings.options.flag("early-reject");
    renderer->depth_batches_on_ =
        renderer->early_reject_ && settings.options.choice("depth-batches") == "auto" && gpu::software_rasteriser();
    // the fragment paths drawn: the style's, and the corrected style's levels that are on
    const int style_path = style == STYLE_SEED ? ATLAS_LOD_SEED : style == STYLE_BASELINE ? ATLAS_LOD_BASELINE : ATLAS_LOD_CORRECTED;
    for (int path = 0; path < 3; ++path) {
        const bool drawn = path == style_path || (path == ATLAS_LOD_SEED && renderer->seed_below_ > 0.0f) ||
                           (path == ATLAS_LOD_BASELINE && renderer->baseline_below_ > 0.0f);
        if (!drawn) continue;
        // --color-level auto is level 0 for every package: nearer the truth at every distance, and its
        // change under a slow orbit, relative to the truth's, no larger than at distance 1
        // (docs/RESULTS.md "Colour from level 0 for every model")
        for (const bool batched : {false, true}) {
            if (batched && (!renderer->depth_batches_on_ || path != ATLAS_LOD_CORRECTED)) continue;
            std::vector<std::pair<std::string, std::string>> defines = {
                {"ATLAS_ARRAYS", std::to_string(plan->arrays)},
                {"ATLAS_PBR", pbr ? "1" : "0"},
                {"ATLAS_PATH", std::to_string(path)},
                {"ATLAS_FINEST_COLOR", settings.options.choice("color-level") != "mips" ? "1" : "0"}};
            if (batched) defines.push_back({"DEPTH_BATCHES", "1"});
            Result<gpu::Program> program =
                gpu::Program::create({"reps/view_atlas/shaders/atlas.vert", "reps/view_atlas/shaders/atlas.frag"}, defines);
            if (!program) return program.status();
            PathProgram& slot = batched ? renderer->batched_paths_[path] : renderer->paths_[path];
            slot.program = std::move(*program);
            slot.counting_at = slot.program.uniform("counting");
            slot.early_reject_at = slot.program.uniform("early_reject");
            slot.hull_pass_at = slot.program.uniform("hull_pass");
            slot.instance_offset_at = slot.program.uniform("instance_offset");
            slot.draw_lod_at = slot.program.uniform("draw_lod");
            slot.depth_batch_at = slot.program.uniform("depth_batch");
        }
    }
    if (renderer->depth_batches_on_) STANDIN_RETURN_IF_ERROR(renderer->depth_batches_.create());

    int size = package.settings.page_size;
    const CellDepths depths = cell_depths(package); // one pass over the pages for the walk's tables
    const bool compressed = settings.options.choice("texture-format") == "bc3";
    if (compressed && !epoxy_has_gl_extension("GL_EXT_texture_compression_s3tc"))
        return error(StatusCode::unsupported, "view atlas: --texture-format bc3 needs GL_EXT_texture_compression_s3tc, "
                                              "which this OpenGL lacks; use rgba8");
    STANDIN_RETURN_IF_ERROR(upload_map(package, package.color_pages, true, "colour", *plan, compressed, renderer->color_arrays_));
    if (pbr) {
        STANDIN_RETURN_IF_ERROR(upload_map(package, package.orm_pages, false, "ORM", *plan, false, renderer->orm_arrays_));
        STANDIN_RETURN_IF_ERROR(
            upload_map(package, package.emission_pages, false, "emission", *plan, false, renderer->emission_arrays_));
    }
    if (package.has_surface()) {
        STANDIN_RETURN_IF_ERROR(
            upload_map(package, package.normal_depth_pages, false, "normal-depth", *plan, false, renderer->normal_depth_arrays_));
        Result<gpu::Texture> cell_tops = upload_cell_tops(depths, int(package.color_pages.size()));
        if (!cell_tops) return cell_tops.status();
        renderer->cell_tops_ = std::move(*cell_tops);
    }

    std::vector<ViewGpu> views;
    for (const View& v : package.views)
        views.push_back({glm::vec4(v.direction, 0.0f), glm::vec4(v.axis_u, 0.0f), glm::vec4(v.axis_v, 0.0f),
                         glm::ivec4(v.crop_x, v.crop_y, v.width, v.height), glm::ivec4(v.page % plan->pages_per_array, v.atlas_x, v.atlas_y,
                                                                       v.page / plan->pages_per_array),
                         glm::vec4(depth_range(package, depths, v), 0.0f, 0.0f)});
    renderer->views_ = gpu::make_buffer(views);
    renderer->index_ = gpu::make_buffer(build_index(package.views));
    renderer->empty_vertex_array_ = gpu::make_vertex_array();
    renderer->style_ = style;
    renderer->center_ = package.center;
    renderer->radius_ = package.radius;

    if (style == STYLE_CORRECTED) {
        const ConvexPolytope proxy = proxy_polytope(package);
        std::vector<glm::vec4> vertices;
        for (const glm::dvec3& v : proxy.vertices) vertices.push_back(glm::vec4(glm::vec3(v), 1.0f));
        std::vector<std::uint32_t> indices;
        std::vector<glm::vec4>& corners = renderer->hull_corners_;
        for (std::size_t f = 0; f < proxy.faces.size(); ++f) {
            const std::vector<std::uint32_t>& face = proxy.faces[f]; // counter-clockwise from outside
            for (std::size_t i = 1; i + 1 < face.size(); ++i) indices.insert(indices.end(), {face[0], face[i], face[i + 1]});
            for (std::uint32_t v : face) // the corners faces use (welding may leave unused ones)
                if (std::find(corners.begin(), corners.end(), vertices[v]) == corners.end()) corners.push_back(vertices[v]);
        }
        if (!indices.empty()) {
            renderer->hull_vertices_ = gpu::make_buffer(vertices);
            renderer->hull_indices_ = gpu::make_buffer(indices);
            renderer->hull_vertex_array_ = gpu::make_vertex_array();
            glVertexArrayElementBuffer(renderer->hull_vertex_array_.get(), renderer->hull_indices_.get());
            renderer->hull_index_count_ = GLsizei(indices.size());
        }
    }
    renderer->hull_above_ = float(settings.options.number("hull-above"));
    for (PathProgram* slot_pointer : {&renderer->paths_[0], &renderer->paths_[1], &renderer->paths_[2], &renderer->batched_paths_[0],
                                      &renderer->batched_paths_[1], &renderer->batched_paths_[2]}) {
        PathProgram& slot = *slot_pointer;
        if (slot.program.id() == 0) continue;
        GLuint id = slot.program.id();
        glProgramUniform3fv(id, slot.program.uniform("atlas_center"), 1, &package.center.x);
        glProgramUniform1f(id, slot.program.uniform("atlas_radius"), package.radius);
        glProgramUniform1f(id, slot.program.uniform("half_extent"), package.half_extent());
        glProgramUniform1f(id, slot.program.uniform("resolution"), float(package.settings.resolution));
        // depth steps, and the factor from the normal-depth pages' A to depth (fine depth: codes over
        // depth_code_max, read as over 65535)
        const int depth_bits = package.has_fine_depth() ? package.settings.depth_bits : 8;
        glProgramUniform1f(id, slot.program.uniform("depth_codes"), float((1 << depth_bits) - 1));
        glProgramUniform1f(id, slot.program.uniform("depth_scale"),
                           package.has_fine_depth() ? float(65535.0 / double(depth_code_max(depth_bits))) : 1.0f);
        glProgramUniform1f(id, slot.program.uniform("capture_distance"), package.capture_distance());
        glProgramUniform1i(id, slot.program.uniform("capture_ortho"), package.settings.projection == "ortho");
        glProgramUniform1i(id, slot.program.uniform("view_count"), int(package.views.size()));
        glProgramUniform1f(id, slot.program.uniform("page_size"), float(size));
        glProgramUniform1i(id, slot.program.uniform("style"), style);
        // the baseline style draws as impostor bakers do (one step); the corrected style's level takes
        // k_level_parallax_steps, which keep it near the walk it replaces (view_atlas.h)
        int parallax_steps = settings.options.integer("parallax-steps");
        if (parallax_steps == 0) parallax_steps = style == STYLE_BASELINE ? 1 : k_level_parallax_steps;
        glProgramUniform1i(id, slot.program.uniform("parallax_steps"), parallax_steps);
        // a solid model's texels are whole or empty: the walk's coverage test need not read their alpha
        glProgramUniform1i(id, slot.program.uniform("binary_coverage"), depths.partial_coverage ? 0 : 1);
        glProgramUniform1i(id, slot.program.uniform("alpha_tested"), package.alpha_tested ? 1 : 0);
        glProgramUniform1i(id, slot.program.uniform("debug_view"), debug_view);
        glProgramUniform1i(id, slot.program.uniform("pages_per_array"), plan->pages_per_array);
        glProgramUniform1i(id, slot.program.uniform("lit_maps"), package.has_surface() ? 0 : 1);
    }
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "view atlas: " + gpu::gl_error_text(e) + " while uploading");
    return std::unique_ptr<Renderer>(std::move(renderer));
}

// Early rejection (atlas.frag behind_drawn): only where a fragment that fails the draw's depth test
// is one behind a depth this draw wrote, i.e. a GL_LESS test that writes into a target of one sample
// per pixel (with several, a pixel's record would mix samples' depths); then the record is cleared
// to "nothing drawn" and bound for this draw.
bool AtlasRenderer::bind_early_reject()
{
    if (!early_reject_) return false;
    GLint func = 0, samples = 0, viewport[4] = {0, 0, 0, 0};
    GLboolean mask = GL_FALSE;
    glGetIntegerv(GL_DEPTH_FUNC, &func);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &mask);
    glGetIntegerv(GL_SAMPLES, &samples);
    glGetIntegerv(GL_VIEWPORT, viewport);
    if (func != GL_LESS || mask != GL_TRUE || samples > 1) return false;
    glm::ivec2 size(viewport[0] + viewport[2], viewport[1] + viewport[3]);
    if (size.x <= 0 || size.y <= 0) return false;
    if (size.x > nearest_size_.x || size.y > nearest_size_.y) {
        nearest_size_ = glm::max(size, nearest_size_);
        nearest_ = gpu::make_texture_2d(GL_R32UI, nearest_size_.x, nearest_size_.y);
    }
    const GLuint nothing = 0xffffffffu;
    glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT); // the previous draw's image writes, before the clear
    glClearTexImage(nearest_.get(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &nothing);
    glBindImageTexture(ATLAS_NEAREST_IMAGE, nearest_.get(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    return true;
}

// Whether an instance is drawn on the proxy hull: only where the hull's front faces bound every
// ray into it, i.e. the near plane clips none of it (so the eye is outside it), where the transform
// keeps the winding (the pass culls back faces), and where the instance is at least --hull-above
// pixels in radius (and not under --seed-below, whose level draws a quad). llvmpipe shades whole
// 4x4 blocks along every triangle's edges, so on a small instance the hull's tens of triangles
// cost more than the prism's few large ones save (docs/RESULTS.md, "View atlas: a proxy hull"). The others take
// the prism, which also handles an eye inside.
bool AtlasRenderer::on_hull(const glm::mat4& world_from_object, const DrawParams& params, float pixels) const
{
    if (hull_index_count_ == 0 || glm::determinant(glm::mat3(world_from_object)) <= 0.0f) return false;
    if (pixels < std::max(seed_below_, hull_above_)) return false;
    // every corner beyond the near plane: then the whole hull is (it is convex), the eye outside it
    const Camera& camera = params.camera;
    const glm::mat4 view_from_object = camera.view_from_world * world_from_object;
    for (const glm::vec4& corner : hull_corners_)
        if (!(-(view_from_object * corner).z > camera.near_plane * 1.001f)) return false;
    return true;
}

// Radius in pixels of an instance's bounding sphere (largest axis scale), measured along the
// camera's up vector so that orthographic and perspective cameras are treated alike; huge where the
// sphere's centre or top is behind the eye (never simplified).
float AtlasRenderer::sphere_pixels(const glm::mat4& world_from_object, const DrawParams& params) const
{
    const Camera& camera = params.camera;
    const float scale = std::max({glm::length(glm::vec3(world_from_object[0])), glm::length(glm::vec3(world_from_object[1])),
                                  glm::length(glm::vec3(world_from_object[2]))});
    const glm::vec3 c(world_from_object * glm::vec4(center_, 1.0f));
    const glm::vec3 up(camera.view_from_world[0][1], camera.view_from_world[1][1], camera.view_from_world[2][1]);
    const glm::mat4 clip_from_world = camera.clip_from_world();
    const glm::vec4 a = clip_from_world * glm::vec4(c, 1.0f), b = clip_from_world * glm::vec4(c + up * (radius_ * scale), 1.0f);
    if (!(a.w > 0.0f && b.w > 0.0f)) return std::numeric_limits<float>::max();
    return glm::length(glm::vec2(b) / b.w - glm::vec2(a) / a.w) * 0.5f * float(params.viewport.y);
}

// The corrected style's level of detail for an instance (ATLAS_LOD_*): the seed's quad under
// --seed-below pixels, the baseline's shading under --baseline-below, else the walk.
int AtlasRenderer::level_of(float pixels) const
{
    return pixels < seed_below_ ? ATLAS_LOD_SEED : pixels < baseline_below_ ? ATLAS_LOD_BASELINE : ATLAS_LOD_CORRECTED;
}

// Instances front to back: each one's bounding-sphere centre by its depth along the camera's view
// axis, ties by index, so the order (and so the picture where two hits share a depth) does not
// depend on the sort. Every style writes a depth at or behind its proxy's (depth_greater in
// atlas.frag), so a GPU's early depth test can reject the fragments of instances hidden behind
// nearer ones before they walk; drawn back to front, each would walk and then be overwritten.
// Corrected style: the instances on the proxy hull (on_hull) first, in that order, as indexed draws
// with back faces culled; then the rest on the prism; each level of detail (level_of) a draw of its
// own with its path's program (llvmpipe runs a fragment program's every path for each fragment).
DrawStats AtlasRenderer::draw(const DrawParams& params)
{
    static const glm::mat4 identity(1.0f);
    std::span<const glm::mat4> transforms = params.world_from_object;
    if (transforms.empty()) transforms = std::span<const glm::mat4>(&identity, 1); // as FrameResources::bind
    const std::size_t count = transforms.size();
    const glm::mat4& view = params.camera.view_from_world;
    order_.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
        glm::vec4 center = view * (transforms[i] * glm::vec4(center_, 1.0f));
        float depth = -center.z; // the camera looks down -z
        order_[i] = {std::isnan(depth) ? std::numeric_limits<float>::max() : depth, std::uint32_t(i)};
    }
    std::sort(order_.begin(), order_.end());
    // the draws, in this order, each a run of sorted_ front to back: corrected style, the hull's
    // instances at the walk's level, then at the baseline's; the prism's likewise; the seed's quads
    struct Run {
        int path;  // ATLAS_LOD_*: the program
        bool hull; // the proxy hull's indexed draw, else the prism (or the styles' quads)
        std::size_t first = 0, count = 0;
    };
    std::vector<Run> runs;
    sorted_.clear();
    if (style_ == STYLE_CORRECTED) {
        hull_chosen_.resize(count);
        level_chosen_.resize(count);
        for (std::size_t i = 0; i < count; ++i) {
            const float pixels = sphere_pixels(transforms[i], params); // measured once for both choices
            level_chosen_[i] = std::uint8_t(level_of(pixels));
            hull_chosen_[i] = level_chosen_[i] != ATLAS_LOD_SEED && on_hull(transforms[i], params, pixels);
        }
        const Run order[5] = {{ATLAS_LOD_CORRECTED, true}, {ATLAS_LOD_BASELINE, true}, {ATLAS_LOD_CORRECTED, false},
                              {ATLAS_LOD_BASELINE, false}, {ATLAS_LOD_SEED, false}};
        for (Run run : order) {
            run.first = sorted_.size();
            for (const auto& [depth, i] : order_)
                if (level_chosen_[i] == run.path && bool(hull_chosen_[i]) == run.hull) sorted_.push_back(transforms[i]);
            run.count = sorted_.size() - run.first;
            if (run.count > 0) runs.push_back(run);
        }
    } else {
        for (const auto& [depth, i] : order_) sorted_.push_back(transforms[i]);
        runs.push_back({style_ == STYLE_SEED ? ATLAS_LOD_SEED : ATLAS_LOD_BASELINE, false, 0, count});
    }
    DrawParams sorted_params = params;
    sorted_params.world_from_object = sorted_;
    frame_.bind(sorted_params);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ATLAS_VIEWS_SSBO, views_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ATLAS_INDEX_SSBO, index_.get());
    if (hull_index_count_ > 0) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ATLAS_HULL_SSBO, hull_vertices_.get());
    counters_.bind();
    for (std::size_t a = 0; a < color_arrays_.size(); ++a) {
        glBindTextureUnit(GLuint(ATLAS_COLOR_TEXTURE + a), color_arrays_[a].get());
        glBindTextureUnit(GLuint(ATLAS_NORMAL_DEPTH_TEXTURE + a),
                          normal_depth_arrays_.empty() ? color_arrays_[a].get() : normal_depth_arrays_[a].get());
        if (!orm_arrays_.empty()) {
            glBindTextureUnit(GLuint(ATLAS_ORM_TEXTURE + a), orm_arrays_[a].get());
            glBindTextureUnit(GLuint(ATLAS_EMISSION_TEXTURE + a), emission_arrays_[a].get());
        }
    }
    if (cell_tops_.get() != 0) glBindTextureUnit(ATLAS_CELL_TEXTURE, cell_tops_.get());
    const bool early_reject = bind_early_reject(); // one record for every run: they are one draw
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    DrawStats stats{0, 0};
    // instances [first, first + n) of sorted_ by the run's program (or its depth-batch variant)
    auto draw_instances = [&](const Run& run, const PathProgram& slot, std::size_t first, std::size_t n) {
        const GLuint id = slot.program.id();
        glProgramUniform1i(id, slot.counting_at, counters_.counting() ? 1 : 0);
        glProgramUniform1i(id, slot.early_reject_at, early_reject ? 1 : 0);
        glProgramUniform1i(id, slot.hull_pass_at, run.hull ? 1 : 0);
        glProgramUniform1i(id, slot.instance_offset_at, GLint(first));
        glProgramUniform1i(id, slot.draw_lod_at, run.path);
        slot.program.use();
        const GLsizei count = GLsizei(n);
        if (run.hull) {
            glBindVertexArray(hull_vertex_array_.get());
            glEnable(GL_CULL_FACE);
            glFrontFace(GL_CCW);
            glCullFace(GL_BACK);
            glDrawElementsInstanced(GL_TRIANGLES, hull_index_count_, GL_UNSIGNED_INT, nullptr, count);
            glDisable(GL_CULL_FACE);
            stats.primitives += std::uint64_t(n) * std::uint64_t(hull_index_count_ / 3);
        } else if (style_ != STYLE_CORRECTED) { // the styles' camera-facing quads
            glBindVertexArray(empty_vertex_array_.get());
            glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, count);
            stats.primitives += std::uint64_t(n) * 2u;
        } else { // the prism: a box, 36 vertices, or the seed's quad, its first 6 (shaders/atlas.vert)
            const bool quad = run.path == ATLAS_LOD_SEED;
            glBindVertexArray(empty_vertex_array_.get());
            glDrawArraysInstanced(GL_TRIANGLES, 0, quad ? 6 : 36, count);
            stats.primitives += std::uint64_t(n) * (quad ? 2u : 12u);
        }
        stats.draw_calls += 1;
    };
    // depth batches (reps/common/depth_batches.h): each walk run's first batch drawn as it is, the
    // later ones tested early against the batches resolved before them; they need early rejection's
    // record. The seed's and baseline's levels keep the late test (depth_batches.h says why).
    const bool batches = depth_batches_on_ && early_reject && depth_batches_.begin_frame();
    for (const Run& run : runs) {
        if (!batches || run.path != ATLAS_LOD_CORRECTED) {
            draw_instances(run, paths_[run.path], run.first, run.count);
            continue;
        }
        std::size_t begin = 0;
        for (const std::size_t end : reps::DepthBatches::batch_ends(run.count)) {
            if (begin == 0) {
                draw_instances(run, paths_[run.path], run.first, end);
            } else {
                const PathProgram& slot = batched_paths_[run.path];
                const std::uint32_t stamp = depth_batches_.begin_batch();
                glProgramUniform1ui(slot.program.id(), slot.depth_batch_at, stamp);
                draw_instances(run, slot, run.first + begin, end - begin);
                glm::ivec4 rect(0);
                for (std::size_t k = run.first + begin; k < run.first + end; ++k)
                    rect = reps::DepthBatches::rect_union(
                        rect, reps::DepthBatches::sphere_rect(params.camera, params.viewport, sorted_[k], center_, radius_));
                depth_batches_.resolve(stamp, rect);
                stats.draw_calls += 1;
            }
            begin = end;
        }
    }
    if (batches) depth_batches_.end_frame();
    glBindVertexArray(0);
    if (counters_.counting()) glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    return stats;
}

} // namespace

Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings)
{
    return AtlasRenderer::create(reps::package_cast<ViewAtlasPackage>(package), settings);
}

} // namespace standin::view_atlas
