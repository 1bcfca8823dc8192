// The GPU renderer of microfacets (Yamazaki et al. 2002 §3.3 RenderingProcess, §5.3, §5.4, §6.2).
// Per draw, for every instance at once:
//  1. on the CPU, per instance: the eye and axes in object space, viewport culling of its bounding
//     sphere, the finest level it can need (lod.h finest_level), and its range of work items: the
//     nodes of the levels it may draw;
//  2. select.comp, one invocation per work item: viewport culling, the per-node LOD cut (eq. 2 under
//     a pixel), per-facet view selection (lookup cells, the seed's cone, or every view) and blend
//     weights, quad or point; scan.comp and scatter.comp compact the kept facets in work order into
//     a quad list and a point list and write the two indirect draws' counts;
//  3. one indirect draw of the quads (two triangles each, not instances: llvmpipe draws instances one
//     at a time; facets.vert/.frag: view-facing squares of side sqrt(3) W,
//     textured from their views, clipped by eq. 1, lit from stored normals, true depth) and one of
//     the points (points.vert/.frag).
// So a crowd is three dispatches and two draws whatever its size, and nothing depends on thread
// timing (the lists keep work order): renders are byte-identical.
// Beyond the paper: selection on the GPU (the paper's CPU loop was its bottleneck, §6.2), the LOD cut
// per node (its §7 future work), blending weights that change continuously (its Fig. 13 popping),
// lighting from stored normals (its lighting was fixed), 16-bit depth (its 8 bits cap it at 256^3),
// and for PBR models (issue #14) ORM and emission pages read with the colour and lit by
// shade_pbr_at; the programs are compiled with MF_PBR only for those packages.
// Where every blended view of a facet abstains at a pixel (the ray passes under surface each saw,
// deep in a crown), up to k_fallback_views more views that saw surface in the node are walked,
// nearest first, the first that can tell deciding (facets.frag; issues #14 and #16). Packages of
// alpha-tested models store fractional coverage (issue #14): their colour pages are premultiplied
// here, and the walk keeps a surface where its filtered coverage reaches 1/2
// (microfacets_sample.glsl hit_coverage); other packages render as before.
#include "reps/microfacets/lod.h"
#include "reps/microfacets/renderer.h"
#include "reps/microfacets/view_lookup.h"
#include "reps/microfacets/visibility.h"

#include "gpu/counters.h"
#include "reps/common/package_cast.h"
#include "gpu/frame.h"
#include "gpu/gl.h"
#include "reps/microfacets/shaders/microfacets_layout.glsl"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace standin::microfacets {

namespace {

static_assert(MF_LOOKUP_SIDE == k_lookup_side, "the lookup's side, C++ and GLSL");
static_assert(MF_MAX_BLEND == k_max_blend, "views per facet, C++ and GLSL");
static_assert(MF_MAX_LEVELS == k_max_grid_level + 1, "octree levels, C++ and GLSL");

// std430 mirrors of shaders/microfacets.glsl
struct ViewGpu {
    glm::vec4 direction, axis_u, axis_v;
    glm::ivec4 crop, atlas;
};
static_assert(sizeof(ViewGpu) == 80, "std430 layout of ViewData");

struct InstanceLodGpu {
    glm::vec4 eye_object;     // w: world units per object unit
    glm::vec4 forward_object; // w: 1 orthographic
    glm::vec4 up_object;
    glm::uvec4 work;          // first work item, work items, first level, finest level
};
static_assert(sizeof(InstanceLodGpu) == 64, "std430 layout of InstanceLod");

constexpr std::size_t k_facet_bytes = 32;          // Facet: two uvec4
constexpr std::uint64_t k_max_work = 8u << 20;     // work items per draw: 256 MiB of selected facets
constexpr GLuint k_max_groups_x = 65535;
constexpr int k_fallback_views = 8; // facets.frag: views walked where every blended one abstained

struct Codes {
    int select = MF_SELECT_LOOKUP, facet = MF_FACET_BILLBOARD, primitive = MF_PRIMITIVE_AUTO;
    int coverage = MF_COVERAGE_ANY, clip = MF_CLIP_SEED;
};

Result<Codes> codes_of(const RenderConfig& c)
{
    auto pick = [](const std::string& value, std::initializer_list<std::pair<const char*, int>> table, const char* option,
                   int& out) -> Status {
        std::string known;
        for (const auto& [name, code] : table) {
            if (value == name) {
                out = code;
                return Status::ok();
            }
            known += std::string(known.empty() ? "" : ", ") + "'" + name + "'";
        }
        return error(StatusCode::invalid_argument, std::string("microfacets: --") + option + " must be one of " + known +
                                                       ", not '" + value + "'");
    };
    Codes codes;
    STANDIN_RETURN_IF_ERROR(pick(c.select, {{"lookup", MF_SELECT_LOOKUP}, {"cone", MF_SELECT_CONE}, {"all", MF_SELECT_ALL}}, "select", codes.select));
    STANDIN_RETURN_IF_ERROR(pick(c.facet, {{"billboard", MF_FACET_BILLBOARD}, {"fixed", MF_FACET_FIXED}, {"box", MF_FACET_BOX}}, "facet", codes.facet));
    STANDIN_RETURN_IF_ERROR(pick(c.primitive, {{"auto", MF_PRIMITIVE_AUTO}, {"quads", MF_PRIMITIVE_QUADS}, {"points", MF_PRIMITIVE_POINTS}},
                                 "primitive", codes.primitive));
    STANDIN_RETURN_IF_ERROR(pick(c.coverage, {{"any", MF_COVERAGE_ANY}, {"vote", MF_COVERAGE_VOTE}}, "coverage", codes.coverage));
    STANDIN_RETURN_IF_ERROR(pick(c.clip, {{"seed", MF_CLIP_SEED}, {"voxel", MF_CLIP_VOXEL}, {"ray", MF_CLIP_RAY}}, "clip", codes.clip));
    if (codes.facet == MF_FACET_BOX && codes.clip != MF_CLIP_RAY)
        return error(StatusCode::invalid_argument, "microfacets: --facet box needs --clip ray (a box has no plane to project a view on)");
    if (c.views < 1 || c.views > k_max_blend)
        return error(StatusCode::invalid_argument, "microfacets: --views must be 1.." + std::to_string(k_max_blend));
    if (!std::isfinite(c.max_error_pixels) || !(c.point_pixels >= 0.0f))
        return error(StatusCode::invalid_argument, "microfacets: --pixel-error must be finite and --point-pixels not negative");
    return codes;
}

// Frustum planes of a clip_from_world transform (Gribb & Hartmann): inside where dot(xyz, p) + w >= 0.
std::array<glm::vec4, 6> frustum_planes(const glm::mat4& m)
{
    glm::vec4 row[4];
    for (int r = 0; r < 4; ++r) row[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
    std::array<glm::vec4, 6> planes = {row[3] + row[0], row[3] - row[0], row[3] + row[1],
                                       row[3] - row[1], row[3] + row[2], row[3] - row[2]};
    for (glm::vec4& p : planes) p /= std::max(glm::length(glm::vec3(p)), 1e-30f);
    return planes;
}

// What step 1 works out for a draw.
struct DrawPlan {
    std::vector<InstanceLodGpu> instances;
    std::uint64_t work = 0;      // work items
    std::uint64_t capacity = 0;  // facets the lists may need (each instance: its finest level's count)
};

// Whether a page's coverage is fractional somewhere (alpha-tested models, issue #14: capture.h).
bool has_fractional_coverage(const ImageRGBA8& page)
{
    for (std::size_t p = 3; p < page.pixels.size(); p += 4)
        if (page.pixels[p] != 0 && page.pixels[p] != 255) return true;
    return false;
}

// Colour pages, and the ORM and emission pages of PBR packages (same layout and coverage).
Result<gpu::Texture> upload_color_pages(const MicrofacetsPackage& package, const std::vector<ImageRGBA8>& pages, const char* what)
{
    const int size = package.settings.page_size, layers = std::max(int(pages.size()), 1);
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    gpu::Texture texture(name);
    glTextureStorage3D(name, k_mip_levels, GL_RGBA8, size, size, layers);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    // the pages are uploaded premultiplied by their coverage, so that mip levels average covered
    // texels only once divided by their alpha (microfacets_sample.glsl view_page). Where coverage is
    // 0 or 255 and empty texels are 0 the stored pages already are; fractional coverage (alpha-tested
    // models, issue #14) is multiplied in here, the package keeping straight colour.
    std::vector<std::uint8_t> premultiplied;
    for (std::size_t k = 0; k < pages.size(); ++k) {
        const std::vector<std::uint8_t>& pixels = pages[k].pixels;
        const std::uint8_t* data = pixels.data();
        if (has_fractional_coverage(pages[k])) {
            premultiplied.resize(pixels.size());
            for (std::size_t p = 0; p < pixels.size(); p += 4) {
                unsigned a = pixels[p + 3];
                for (int c = 0; c < 3; ++c) premultiplied[p + c] = std::uint8_t((pixels[p + c] * a + 127) / 255);
                premultiplied[p + 3] = std::uint8_t(a);
            }
            data = premultiplied.data();
        }
        glTextureSubImage3D(name, 0, 0, 0, GLint(k), size, size, 1, GL_RGBA, GL_UNSIGNED_BYTE, data);
    }
    glGenerateTextureMipmap(name);
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_NEAREST); // magnified: the exact texel eq. 1 tested
    glTextureParameteri(name, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(name, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "microfacets: " + gpu::gl_error_text(e) + " uploading " + what + " pages");
    return texture;
}

Result<gpu::Texture> upload_normal_depth_pages(const MicrofacetsPackage& package)
{
    const int size = package.settings.page_size, layers = std::max(int(package.normal_depth_pages.size()), 1);
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    gpu::Texture texture(name);
    glTextureStorage3D(name, 1, GL_RGBA16, size, size, layers);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 2);
    for (std::size_t k = 0; k < package.normal_depth_pages.size(); ++k)
        glTextureSubImage3D(name, 0, 0, 0, GLint(k), size, size, 1, GL_RGBA, GL_UNSIGNED_SHORT,
                            package.normal_depth_pages[k].pixels.data());
    glTextureParameteri(name, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(name, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "microfacets: " + gpu::gl_error_text(e) + " uploading normal-depth pages");
    return texture;
}

class MicrofacetRenderer final : public Renderer {
public:
    static Result<std::unique_ptr<Renderer>> create(const MicrofacetsPackage& package, const RenderConfig& config);
    DrawStats draw(const DrawParams& params) override;
    void set_counting(bool on) override { counters_.set_counting(on); }
    std::uint64_t read_counter(Counter counter) override { return counters_.read(int(counter)); }

private:
    DrawPlan make_plan(const DrawParams& params) const;
    void reserve(GLuint work_groups, std::uint64_t work, std::uint64_t capacity);

    // what the per-draw plan needs of the package (which may go before the renderer)
    struct PackageFacts {
        glm::vec3 center{0.0f};
        float radius = 1.0f, grid_size = 1.0f, max_view_angle = 0.1f;
        int min_level = 0, max_level = 0;
        std::uint64_t facets[MF_MAX_LEVELS] = {}; // per level
    } package_;
    RenderConfig config_;
    Codes codes_;
    std::vector<glm::vec3> directions_;
    float cone_slack_ = 0.0f;
    std::uint32_t level_first_[MF_MAX_LEVELS + 1] = {};
    GLuint lookup_list_ = 0;

    gpu::Program select_, scan_, scatter_, quads_program_, points_program_;
    gpu::Texture color_pages_, normal_depth_pages_;
    gpu::Texture orm_pages_, emission_pages_; // PBR packages only
    gpu::Buffer views_, lookup_, nodes_, seen_, lods_, selected_, groups_, quads_, points_, commands_;
    std::uint64_t lods_capacity_ = 0, selected_capacity_ = 0, list_capacity_ = 0, groups_capacity_ = 0;
    gpu::Counters counters_;
    gpu::VertexArray empty_vertex_array_;
    gpu::FrameResources frame_;
};

Status check_package(const MicrofacetsPackage& package)
{
    const BakeSettings& s = package.settings;
    if (package.views.empty()) return error(StatusCode::bad_data, "microfacets: no views");
    if (package.views.size() > 65535) return error(StatusCode::bad_data, "microfacets: more than 65535 views");
    if (package.octree.levels.size() != std::size_t(s.level - s.min_level + 1))
        return error(StatusCode::bad_data, "microfacets: the octree does not hold levels min_level..level");
    if (package.normal_depth_pages.size() != package.color_pages.size())
        return error(StatusCode::bad_data, "microfacets: normal-depth pages missing");
    if (package.has_pbr() && (package.orm_pages.size() != package.color_pages.size() ||
                              package.emission_pages.size() != package.color_pages.size()))
        return error(StatusCode::bad_data, "microfacets: ORM or emission pages missing");
    for (std::size_t k = 0; k < package.orm_pages.size(); ++k)
        if (package.orm_pages[k].width != s.page_size || package.orm_pages[k].height != s.page_size ||
            package.emission_pages[k].width != s.page_size || package.emission_pages[k].height != s.page_size)
            return error(StatusCode::bad_data, "microfacets: PBR page " + std::to_string(k) + " is not page_size square");
    for (std::size_t k = 0; k < package.views.size(); ++k) {
        const View& v = package.views[k];
        if (v.width > 0 && (v.page < 0 || v.page >= int(package.color_pages.size()) || v.atlas_x + v.width > s.page_size ||
                            v.atlas_y + v.height > s.page_size))
            return error(StatusCode::bad_data, "microfacets: view " + std::to_string(k) + " lies outside its page");
    }
    std::uint64_t texels = std::uint64_t(s.page_size) * s.page_size * std::max<std::size_t>(package.color_pages.size(), 1);
    GLint max_layers = 0, max_size = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (s.page_size > max_size || int(package.color_pages.size()) > max_layers || texels * k_page_texel_bytes > k_texture_budget_bytes) {
        std::string name = !package.directory.empty() ? package.directory : "(baked from " + package.source.file_name + ")";
        return error(StatusCode::unsupported, "microfacets: package " + name + " does not fit one texture array: " +
                                                  std::to_string(package.color_pages.size()) + " pages of " +
                                                  std::to_string(s.page_size) + "^2; bake with fewer views or a lower --resolution");
    }
    return Status::ok();
}

Result<std::unique_ptr<Renderer>> MicrofacetRenderer::create(const MicrofacetsPackage& package, const RenderConfig& config)
{
    Result<Codes> codes = codes_of(config);
    if (!codes) return codes.status();
    if (config.level >= 0 && (config.level < package.settings.min_level || config.level > package.settings.level))
        return error(StatusCode::invalid_argument, "microfacets: --level " + std::to_string(config.level) + " is not in the package (levels " +
                                                       std::to_string(package.settings.min_level) + ".." +
                                                       std::to_string(package.settings.level) + ")");
    STANDIN_RETURN_IF_ERROR(check_package(package));

    auto r = std::make_unique<MicrofacetRenderer>();
    r->config_ = config;
    if (r->config_.max_error_pixels <= 0.0f) r->config_.max_error_pixels = codes->clip == MF_CLIP_RAY ? 4.0f : 1.0f;
    r->package_.center = package.center;
    r->package_.radius = package.radius;
    r->package_.grid_size = package.octree.grid.size;
    r->package_.max_view_angle = package.max_view_angle;
    r->package_.min_level = package.settings.min_level;
    r->package_.max_level = package.settings.level;
    for (int level = package.settings.min_level; level <= package.settings.level; ++level)
        r->package_.facets[level] = package.octree.at(level).size();
    r->codes_ = *codes;
    for (auto [program, stages] : {std::pair{&r->select_, std::vector<std::string>{"reps/microfacets/shaders/select.comp"}},
                                   {&r->scan_, {"reps/microfacets/shaders/scan.comp"}},
                                   {&r->scatter_, {"reps/microfacets/shaders/scatter.comp"}},
                                   {&r->quads_program_, {"reps/microfacets/shaders/facets.vert", "reps/microfacets/shaders/facets.frag"}},
                                   {&r->points_program_, {"reps/microfacets/shaders/points.vert", "reps/microfacets/shaders/points.frag"}}}) {
        std::vector<std::pair<std::string, std::string>> defines = {{"MF_PBR", package.has_pbr() ? "1" : "0"}};
        if (program == &r->quads_program_) // facets.frag's microfacets_sample.glsl
            defines.push_back({"MF_CLIP_RULE", std::to_string(r->codes_.clip)});
        Result<gpu::Program> made = gpu::Program::create(stages, defines);
        if (!made) return made.status();
        *program = std::move(*made);
    }

    // textures and tables
    Result<gpu::Texture> color = upload_color_pages(package, package.color_pages, "colour");
    if (!color) return color.status();
    r->color_pages_ = std::move(*color);
    if (package.has_pbr()) {
        Result<gpu::Texture> orm = upload_color_pages(package, package.orm_pages, "ORM");
        if (!orm) return orm.status();
        r->orm_pages_ = std::move(*orm);
        Result<gpu::Texture> emission = upload_color_pages(package, package.emission_pages, "emission");
        if (!emission) return emission.status();
        r->emission_pages_ = std::move(*emission);
    }
    Result<gpu::Texture> normal_depth = upload_normal_depth_pages(package);
    if (!normal_depth) return normal_depth.status();
    r->normal_depth_pages_ = std::move(*normal_depth);
    std::vector<ViewGpu> views;
    for (const View& v : package.views) {
        views.push_back({glm::vec4(v.direction, 0.0f), glm::vec4(v.axis_u, 0.0f), glm::vec4(v.axis_v, 0.0f),
                         glm::ivec4(v.crop_x, v.crop_y, v.width, v.height), glm::ivec4(v.page, v.atlas_x, v.atlas_y, 0)});
        r->directions_.push_back(v.direction);
    }
    r->views_ = gpu::make_buffer(views);
    // the lookup (cells, candidates), then room for a per-draw list of every view
    ViewLookup lookup = build_view_lookup(r->directions_);
    std::vector<std::uint32_t> entries = lookup.cells;
    for (std::uint32_t& cell : entries) cell += std::uint32_t(lookup.cells.size()) << 8; // candidates follow the cells
    entries.insert(entries.end(), lookup.candidates.begin(), lookup.candidates.end());
    r->lookup_list_ = GLuint(entries.size());
    entries.push_back(std::uint32_t(r->directions_.size()));
    for (std::uint32_t k = 0; k < r->directions_.size(); ++k) entries.push_back(k); // "all": every view, ascending
    r->lookup_ = gpu::make_buffer(entries, GL_DYNAMIC_STORAGE_BIT);
    // the cone's slack: the farthest a facet's blended views (and the weights' floor) can be
    const bool circle = package.settings.layout == "circle";
    r->cone_slack_ = max_view_angle(r->directions_, circle, std::min(config.views + 1, int(r->directions_.size())));
    // the octree's codes, coarsest level first
    std::vector<std::uint32_t> nodes;
    for (int level = 0; level <= MF_MAX_LEVELS; ++level) {
        r->level_first_[level] = std::uint32_t(nodes.size());
        if (level >= package.settings.min_level && level <= package.settings.level)
            nodes.insert(nodes.end(), package.octree.at(level).begin(), package.octree.at(level).end());
    }
    if (nodes.empty()) nodes.push_back(0u);
    r->nodes_ = gpu::make_buffer(nodes);
    // which views saw surface in which node: with the ray clip, nodes none of their views saw are
    // dropped before they are drawn (exact)
    GLuint seen_words = 0;
    if (r->codes_.clip == MF_CLIP_RAY && config.cull_unseen) {
        SeenViews seen = seen_views(package);
        seen_words = GLuint(seen.words_per_node);
        r->seen_ = gpu::make_buffer(seen.words);
    } else {
        r->seen_ = gpu::make_buffer(std::vector<std::uint32_t>{0u});
    }
    r->commands_ = gpu::make_buffer(nullptr, 8 * sizeof(std::uint32_t), GL_DYNAMIC_STORAGE_BIT);
    r->empty_vertex_array_ = gpu::make_vertex_array();

    // uniforms that do not change
    const Grid& grid = package.octree.grid;
    for (const gpu::Program* program : {&r->select_, &r->scatter_, &r->quads_program_, &r->points_program_}) {
        GLuint id = program->id();
        glProgramUniform3fv(id, program->uniform("grid_origin"), 1, &grid.origin.x);
        glProgramUniform1f(id, program->uniform("grid_size"), grid.size);
        glProgramUniform3fv(id, program->uniform("mf_center"), 1, &package.center.x);
        glProgramUniform1f(id, program->uniform("mf_radius"), package.radius);
        glProgramUniform1f(id, program->uniform("capture_resolution"), float(package.settings.resolution));
    }
    // every package's coverage is filtered at the hit, binary coverage too: a cut-out's or a
    // silhouette's edge then runs half-way between covered and empty texel centres with the corners
    // cut, instead of along texel borders (measured better on the tree and on the bunny,
    // docs/RESULTS.md "Holes and colour in microfacets' foliage");
    // STANDIN_MICROFACETS_FILTER_BINARY=0 (measurements only) reads binary pages' texels as before
    const char* filter_binary = std::getenv("STANDIN_MICROFACETS_FILTER_BINARY");
    const bool fractional = !(filter_binary && filter_binary[0] == '0') ||
                            std::any_of(package.color_pages.begin(), package.color_pages.end(), has_fractional_coverage);
    for (const gpu::Program* program : {&r->quads_program_, &r->points_program_}) {
        GLuint id = program->id();
        glProgramUniform1i(id, program->uniform("fractional_coverage"), fractional ? 1 : 0);
        glProgramUniform1f(id, program->uniform("page_size"), float(package.settings.page_size));
        glProgramUniform1i(id, program->uniform("max_color_lod"), k_mip_levels - 1);
        glProgramUniform1i(id, program->uniform("debug_view"), int(config.debug_view));
        glProgramUniform1i(id, program->uniform("coverage_rule"), r->codes_.coverage);
        glProgramUniform1i(id, program->uniform("min_level"), package.settings.min_level);
        glProgramUniform1i(id, program->uniform("max_level"), package.settings.level);
    }
    const int vertices_per_facet = r->codes_.facet == MF_FACET_BOX ? MF_VERTICES_PER_FACET : 6;
    glProgramUniform1i(r->quads_program_.id(), r->quads_program_.uniform("facet_shape"), r->codes_.facet);
    glProgramUniform1i(r->quads_program_.id(), r->quads_program_.uniform("vertices_per_facet"), vertices_per_facet);
    glProgramUniform1ui(r->scan_.id(), r->scan_.uniform("vertices_per_facet"), GLuint(vertices_per_facet));
    GLuint select = r->select_.id();
    glProgramUniform1uiv(select, r->select_.uniform("level_first"), MF_MAX_LEVELS + 1, r->level_first_);
    glProgramUniform1i(select, r->select_.uniform("forced_level"), config.level);
    glProgramUniform1i(select, r->select_.uniform("select_mode"), r->codes_.select);
    glProgramUniform1i(select, r->select_.uniform("blend_count"), config.views);
    glProgramUniform1i(select, r->select_.uniform("primitive"), r->codes_.primitive);
    glProgramUniform1f(select, r->select_.uniform("point_pixels"), config.point_pixels);
    glProgramUniform1f(select, r->select_.uniform("max_error_pixels"), r->config_.max_error_pixels);
    glProgramUniform1f(select, r->select_.uniform("tan_delta"), std::tan(package.max_view_angle));
    glProgramUniform1ui(select, r->select_.uniform("lookup_list"), r->lookup_list_);
    glProgramUniform1ui(select, r->select_.uniform("seen_words"), seen_words);
    // STANDIN_MICROFACETS_PREFER_SEEN=0 (measurements only): the nearest views whether or not they
    // saw the node, as before
    const char* prefer_seen = std::getenv("STANDIN_MICROFACETS_PREFER_SEEN");
    glProgramUniform1i(select, r->select_.uniform("prefer_seen"), prefer_seen && prefer_seen[0] == '0' ? 0 : 1);
    // facets under this eq. 2 error walk one view (select.comp): the paper's bound (§4.1), a pixel;
    // STANDIN_MICROFACETS_FAR_ERROR=E (measurements only) sets E
    const char* far_error = std::getenv("STANDIN_MICROFACETS_FAR_ERROR");
    glProgramUniform1f(select, r->select_.uniform("far_error_pixels"), far_error ? std::strtof(far_error, nullptr) : 1.0f);
    glProgramUniform1i(select, r->select_.uniform("clip_rule"), r->codes_.clip);
    // where every blended view of a facet abstains at a pixel, up to this many more views that saw
    // surface in its node are walked (facets.frag); STANDIN_MICROFACETS_FALLBACK=N (measurements
    // only) sets N, 0 turning the fallback off
    const char* fallback = std::getenv("STANDIN_MICROFACETS_FALLBACK");
    GLuint quads = r->quads_program_.id();
    // the ray clip filters colour over the pixel's footprint where it holds one surface (facets.frag);
    // STANDIN_MICROFACETS_FILTER_COLOR=0 (measurements only) reads the texel hit, as before
    const char* filter_color = std::getenv("STANDIN_MICROFACETS_FILTER_COLOR");
    glProgramUniform1i(quads, r->quads_program_.uniform("filter_color"), filter_color && filter_color[0] == '0' ? 0 : 1);
    glProgramUniform1ui(quads, r->quads_program_.uniform("seen_words"), seen_words);
    glProgramUniform1i(quads, r->quads_program_.uniform("fallback_views"), fallback ? std::atoi(fallback) : k_fallback_views);
    if (GLenum e = glGetError(); e != GL_NO_ERROR)
        return error(StatusCode::gpu_error, "microfacets: " + gpu::gl_error_text(e) + " while uploading");
    return std::unique_ptr<Renderer>(std::move(r));
}

DrawPlan MicrofacetRenderer::make_plan(const DrawParams& params) const
{
    const PackageFacts& package = package_;
    const Camera& camera = params.camera;
    static const glm::mat4 identity(1.0f);
    std::span<const glm::mat4> transforms = params.world_from_object;
    if (transforms.empty()) transforms = std::span<const glm::mat4>(&identity, 1);

    LodRule rule;
    rule.max_error_pixels = config_.max_error_pixels;
    rule.tan_delta = std::tan(package.max_view_angle);
    rule.min_level = package.min_level;
    rule.max_level = package.max_level;
    rule.forced_level = config_.level;
    const ScreenScale scale = screen_scale(camera, params.viewport.y);
    const std::array<glm::vec4, 6> planes = frustum_planes(camera.clip_from_world());
    const glm::mat4& v = camera.view_from_world;
    const glm::vec3 up_world(v[0][1], v[1][1], v[2][1]);
    const int first = rule.forced_level >= 0 ? rule.forced_level : rule.min_level;

    DrawPlan plan;
    std::vector<int> finest(transforms.size(), -1);
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        const glm::mat4& m = transforms[i];
        glm::mat4 object_from_world = glm::inverse(m);
        float world_per_object = std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])), glm::length(glm::vec3(m[2]))});
        InstanceLodGpu lod;
        lod.eye_object = glm::vec4(glm::vec3(object_from_world * glm::vec4(camera.eye_world, 1.0f)), world_per_object);
        lod.forward_object = glm::vec4(glm::normalize(glm::mat3(object_from_world) * camera.forward_world), camera.orthographic ? 1.0f : 0.0f);
        lod.up_object = glm::vec4(glm::normalize(glm::mat3(object_from_world) * up_world), 0.0f);
        lod.work = glm::uvec4(0u, 0u, std::uint32_t(first), std::uint32_t(first));
        // the instance's bounding sphere against the viewport, then the finest level it can need
        glm::vec3 center = glm::vec3(m * glm::vec4(package.center, 1.0f));
        float radius = package.radius * world_per_object;
        bool visible = true;
        for (const glm::vec4& p : planes) visible = visible && glm::dot(glm::vec3(p), center) + p.w >= -radius;
        if (visible)
            finest[i] = finest_level(rule, scale, package.grid_size * world_per_object,
                                     glm::length(camera.eye_world - center), radius);
        plan.instances.push_back(lod);
    }
    // the work: each visible instance's nodes of levels first..finest; coarser where a crowd would
    // need more than k_max_work (every instance one level coarser at a time, so the result does not
    // depend on instance order)
    auto total_work = [&] {
        std::uint64_t work = 0;
        for (int f : finest)
            if (f >= 0) work += level_first_[f + 1] - level_first_[first];
        return work;
    };
    while (total_work() > k_max_work) {
        bool coarser = false;
        for (int& f : finest)
            if (f > first) --f, coarser = true;
        if (!coarser) break;
    }
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        InstanceLodGpu& lod = plan.instances[i];
        lod.work.x = std::uint32_t(plan.work);
        if (finest[i] < 0) continue;
        lod.work.y = level_first_[finest[i] + 1] - level_first_[first];
        lod.work.w = std::uint32_t(finest[i]);
        plan.work += lod.work.y;
        plan.capacity += package.facets[finest[i]];
    }
    return plan;
}

void MicrofacetRenderer::reserve(GLuint work_groups, std::uint64_t work, std::uint64_t capacity)
{
    auto grow = [](gpu::Buffer& buffer, std::uint64_t& have, std::uint64_t bytes) {
        if (bytes <= have && buffer) return;
        have = std::max<std::uint64_t>(bytes, 2 * have);
        buffer = gpu::make_buffer(nullptr, std::size_t(have), GL_DYNAMIC_STORAGE_BIT);
    };
    grow(selected_, selected_capacity_, std::max<std::uint64_t>(work, 1) * k_facet_bytes);
    grow(groups_, groups_capacity_, std::uint64_t(std::max<GLuint>(work_groups, 1)) * 2 * sizeof(glm::uvec2));
    std::uint64_t list_bytes = std::max<std::uint64_t>(capacity, 1) * k_facet_bytes;
    if (list_bytes > list_capacity_ || !quads_) {
        list_capacity_ = std::max<std::uint64_t>(list_bytes, 2 * list_capacity_);
        quads_ = gpu::make_buffer(nullptr, std::size_t(list_capacity_), 0);
        points_ = gpu::make_buffer(nullptr, std::size_t(list_capacity_), 0);
    }
}

DrawStats MicrofacetRenderer::draw(const DrawParams& params)
{
    frame_.bind(params);
    DrawPlan plan = make_plan(params);
    if (plan.work == 0) return {};
    const GLuint groups = GLuint((plan.work + MF_GROUP_SIZE - 1) / MF_GROUP_SIZE);
    const GLuint groups_x = std::min(groups, k_max_groups_x), groups_y = (groups + groups_x - 1) / groups_x;
    reserve(groups_x * groups_y, plan.work, plan.capacity);

    // per-draw inputs: the instances' LOD data, the draws' counts reset, the cone's views
    std::uint64_t lod_bytes = plan.instances.size() * sizeof(InstanceLodGpu);
    if (lod_bytes > lods_capacity_ || !lods_) {
        lods_capacity_ = std::max<std::uint64_t>(lod_bytes, 2 * lods_capacity_);
        lods_ = gpu::make_buffer(nullptr, std::size_t(lods_capacity_), GL_DYNAMIC_STORAGE_BIT);
    }
    glNamedBufferSubData(lods_.get(), 0, GLsizeiptr(lod_bytes), plan.instances.data());
    const std::uint32_t commands[8] = {0, 1, 0, 0, 0, 1, 0, 0};
    glNamedBufferSubData(commands_.get(), 0, sizeof commands, commands);
    if (codes_.select == MF_SELECT_CONE) {
        // the seed's cone around each instance's bounding sphere, their union for a crowd
        std::vector<std::uint8_t> candidate(directions_.size(), 0);
        for (std::size_t i = 0; i < plan.instances.size(); ++i) {
            const InstanceLodGpu& lod = plan.instances[i];
            glm::vec3 eye = lod.forward_object.w > 0.5f ? package_.center - glm::vec3(lod.forward_object) * (1e6f * package_.radius)
                                                         : glm::vec3(lod.eye_object);
            for (std::uint32_t k : cone_candidates(directions_, eye, package_.center, package_.radius, cone_slack_)) candidate[k] = 1;
        }
        std::vector<std::uint32_t> list{0u};
        for (std::uint32_t k = 0; k < candidate.size(); ++k)
            if (candidate[k]) list.push_back(k);
        list[0] = std::uint32_t(list.size() - 1);
        glNamedBufferSubData(lookup_.get(), GLintptr(lookup_list_ * sizeof(std::uint32_t)), GLsizeiptr(list.size() * sizeof(std::uint32_t)),
                             list.data());
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_VIEWS_SSBO, views_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_LOOKUP_SSBO, lookup_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_NODES_SSBO, nodes_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_SEEN_SSBO, seen_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_INSTANCES_SSBO, lods_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_SELECTED_SSBO, selected_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_GROUPS_SSBO, groups_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_QUADS_SSBO, quads_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_POINTS_SSBO, points_.get());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, MF_COMMANDS_SSBO, commands_.get());
    counters_.bind();

    // step 2: select, scan, scatter
    const ScreenScale scale = screen_scale(params.camera, params.viewport.y);
    const std::array<glm::vec4, 6> planes = frustum_planes(params.camera.clip_from_world());
    GLuint id = select_.id();
    glProgramUniform1ui(id, select_.uniform("work_total"), GLuint(plan.work));
    glProgramUniform1ui(id, select_.uniform("instance_count"), GLuint(plan.instances.size()));
    glProgramUniform1ui(id, select_.uniform("groups_x"), groups_x);
    glProgramUniform1f(id, select_.uniform("screen_pixels"), scale.pixels);
    glProgramUniform4fv(id, select_.uniform("frustum"), 6, &planes[0].x);
    select_.use();
    glDispatchCompute(groups_x, groups_y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glProgramUniform1ui(scan_.id(), scan_.uniform("group_count"), groups_x * groups_y);
    scan_.use();
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    id = scatter_.id();
    glProgramUniform1ui(id, scatter_.uniform("work_total"), GLuint(plan.work));
    glProgramUniform1ui(id, scatter_.uniform("groups_x"), groups_x);
    glProgramUniform1ui(id, scatter_.uniform("group_count"), groups_x * groups_y);
    glProgramUniform1ui(id, scatter_.uniform("capacity"), GLuint(list_capacity_ / k_facet_bytes));
    scatter_.use();
    glDispatchCompute(groups_x, groups_y, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);

    // step 3: the two indirect draws
    glBindTextureUnit(MF_COLOR_TEXTURE, color_pages_.get());
    glBindTextureUnit(MF_NORMAL_DEPTH_TEXTURE, normal_depth_pages_.get());
    if (orm_pages_.get() != 0) {
        glBindTextureUnit(MF_ORM_TEXTURE, orm_pages_.get());
        glBindTextureUnit(MF_EMISSION_TEXTURE, emission_pages_.get());
    }
    glBindVertexArray(empty_vertex_array_.get());
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, commands_.get());
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glProgramUniform1i(quads_program_.id(), quads_program_.uniform("counting"), counters_.counting() ? 1 : 0);
    quads_program_.use();
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
    glEnable(GL_PROGRAM_POINT_SIZE);
    GLuint points = points_program_.id();
    glProgramUniform1i(points, points_program_.uniform("counting"), counters_.counting() ? 1 : 0);
    glProgramUniform1f(points, points_program_.uniform("screen_pixels"), scale.pixels);
    points_program_.use();
    glDrawArraysIndirect(GL_POINTS, reinterpret_cast<const void*>(4 * sizeof(std::uint32_t)));
    glDisable(GL_PROGRAM_POINT_SIZE);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindVertexArray(0);
    if (counters_.counting()) glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);

    // what was drawn (a read-back: the counts live on the GPU)
    std::uint32_t drawn[8] = {};
    glGetNamedBufferSubData(commands_.get(), 0, sizeof drawn, drawn);
    return {2, std::uint64_t(drawn[0]) / 3 + drawn[4]};
}

} // namespace

Result<std::unique_ptr<Renderer>> make_microfacet_renderer(const MicrofacetsPackage& package, const RenderConfig& config)
{
    return MicrofacetRenderer::create(package, config);
}

RenderConfig config_from(const RenderSettings& settings)
{
    const Options& o = settings.options;
    RenderConfig c;
    c.select = o.choice("select");
    c.views = o.integer("views");
    c.facet = o.choice("facet");
    c.primitive = o.choice("primitive");
    c.coverage = o.choice("coverage");
    c.level = o.integer("level");
    c.max_error_pixels = o.number("pixel-error");
    c.point_pixels = o.number("point-pixels");
    c.debug_view = settings.debug_view;
    c.clip = o.choice("clip");
    return c;
}

Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings)
{
    return MicrofacetRenderer::create(reps::package_cast<MicrofacetsPackage>(package), config_from(settings));
}

} // namespace standin::microfacets
