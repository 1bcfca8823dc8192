// Export of microfacets (docs/FORMAT.md, "Export: microfacets"). Yamazaki, Sagawa, Kawasaki,
// Ikeuchi & Sakauchi 2002 draw every occupied voxel of an octree level as a view-facing square
// textured from the nearest captured views and clipped against their depth (eq. 1); that needs
// standin's shaders and all the views on the GPU. An engine without standin gets the same voxels
// as a plain mesh instead: the paper's geometry (§3.2.2-3.2.3, the voxels of one level) with the
// colour its views give it, baked once.
// Steps:
//  1. the level: --level, or the coarsest level whose voxel spans at most 4 pixels (1 unsnapped)
//     when the bounding sphere's diameter spans --pixels pixels (the displaced mesh's screen-size
//     rule), or the finest level baked;
//  2. the exposed faces (exposed_faces): a dense occupancy grid of the level, the space reachable
//     from outside the grid flood-filled (6-connected), and each voxel face that borders that space
//     kept. Faces between two voxels and faces towards enclosed cavities are culled, so every edge
//     of the result is used as often in one direction as in the other: a closed surface;
//  3. colour and normal per face, projective texturing from every captured view: each covered texel
//     is the surface point its depth stores; walking from that point towards the view's camera
//     (Amanatides & Woo 1987 voxel traversal) the ray leaves the solid voxels through the face that
//     a rasteriser would show at that texel from that view, which gets the texel's albedo (averaged
//     in linear RGB) and normal, weighted by the cosine between the face and the view. Sums are
//     integers, so the parallel accumulation is the same at any thread count;
//  4. --snap (default): each lattice corner moves to the mean of the mean surface points (step 3)
//     of the seen faces around it, at most a voxel per axis: the voxel surface is pulled onto the
//     captured surface, as surface nets (Gibson 1998) place vertices, but on the primal corners so
//     that the closed face structure stays; unsnapped faces stand up to a voxel proud of the surface
//     (bunny at 480x360, level 7: silhouette IoU 0.959 unsnapped, 0.990 snapped);
//  5. one quad (4 vertices, 2 triangles) per face with the face's albedo as vertex colour and its
//     captured normal, so an engine lights the voxels as the surface they hold;
//  6. cut-outs (--cutout T, default 4; 0: opaque faces): T x T coverage texels per face, voted by the
//     views facing it (is the surface there at the texel, or in the solid run behind it?), in an
//     atlas read by a double-sided MASK material, so a leaf thinner than a voxel is not drawn as
//     whole faces (this is what the renderer's per-pixel depth clip does, frozen for all views).
// Planes (the default; --no-planes gives steps 2-6) replace steps 2-6 after step 3's capture walk: one square per voxel in the
// plane of the surface it holds (mean point, principal direction of the captured normals), cut out
// by the views' coverage at the texel's own depth. Faces at the voxel boundary see a leaf with up to
// a voxel of parallax, which a per-face mask cannot undo for every view (generated tree in the web
// viewer against standin render: IoU 0.83 / 0.78 with cut faces, 0.934 / 0.942 with planes), and
// squares in the surface's plane follow a closed surface's silhouette closer than snapped faces
// (bunny: 0.995 / 0.996 against 0.989 / 0.991); planes are not a closed surface. The tree's planes
// stay under 0.95 against standin render because that render has holes where its nearest views saw
// the surface hidden (it is 0.941 / 0.946 against the model, the planes 0.973 / 0.967:
// docs/RESULTS.md "Microfacets planes against the model").
// Departs from the paper: its facets are view-facing and clipped per pixel by depth, so their
// silhouette follows the surface exactly; the exported faces follow it only as closely as snapping
// a voxel's corners can, and a face has one colour instead of a texture. Faces no view saw (inside concavities) take the mean of
// their voxel's seen faces, or the mean of all faces.
#include "reps/microfacets/export.h"
#include "reps/microfacets/microfacets.h"
#include "reps/common/package_cast.h"
#include "reps/common/surface_image.h"

#include <standin/files.h>
#include <standin/image.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>

namespace standin::microfacets {

namespace {

// --pixels picks the coarsest level whose voxel spans at most this many pixels (docs/RESULTS.md,
// "Export to glTF": snapped corners follow the surface, and 4-pixel voxels kept the bunny's
// silhouette IoU against `standin render` at 0.988; unsnapped faces stand up to a voxel proud of
// the surface, so there one pixel keeps the silhouette within a pixel).
constexpr float k_export_voxel_pixels_snapped = 4.0f;
constexpr float k_export_voxel_pixels_unsnapped = 1.0f;

// Fixed-point scales of the integer sums (step 3): weights in 1/256, linear colour in 1/65535,
// surface points in 1/4096 voxel,
// normal components in 1/32767.
constexpr float k_export_weight_scale = 256.0f;
constexpr float k_export_color_scale = 65535.0f;
constexpr float k_export_normal_scale = 32767.0f;
constexpr float k_export_point_scale = 4096.0f;

// Cut-outs (step 6): views facing a face at a shallower angle than this cosine (about 75 degrees)
// see it too obliquely to say where on it the surface is; a capture texel's surface within this
// many voxels of a face texel in depth is the face's own (the renderer's eq. 1 clip keeps the
// surface within W/2 of a facet).
constexpr float k_export_cutout_min_cosine = 0.25f;
constexpr float k_export_cutout_depth_tolerance = 0.5f;

struct ExportGrid {
    int side = 0;
    std::vector<std::uint64_t> bits;

    explicit ExportGrid(int n) : side(n), bits((std::uint64_t(n) * n * n + 63) / 64, 0u) {}
    std::uint64_t index(glm::ivec3 c) const { return std::uint64_t(c.x) + std::uint64_t(side) * (std::uint64_t(c.y) + std::uint64_t(side) * std::uint64_t(c.z)); }
    bool inside(glm::ivec3 c) const { return c.x >= 0 && c.y >= 0 && c.z >= 0 && c.x < side && c.y < side && c.z < side; }
    bool get(glm::ivec3 c) const
    {
        std::uint64_t i = index(c);
        return (bits[i / 64] >> (i % 64)) & 1u;
    }
    void set(glm::ivec3 c)
    {
        std::uint64_t i = index(c);
        bits[i / 64] |= std::uint64_t(1) << (i % 64);
    }
};

constexpr std::array<glm::ivec3, 6> k_export_side_steps = {glm::ivec3(1, 0, 0), glm::ivec3(-1, 0, 0), glm::ivec3(0, 1, 0),
                                                    glm::ivec3(0, -1, 0), glm::ivec3(0, 0, 1), glm::ivec3(0, 0, -1)};

// The space reachable from outside the grid without crossing an occupied voxel.
ExportGrid export_exterior(const ExportGrid& occupied)
{
    const int n = occupied.side;
    ExportGrid outside(n);
    std::deque<glm::ivec3> queue;
    auto seed = [&](glm::ivec3 c) {
        if (!occupied.get(c) && !outside.get(c)) outside.set(c), queue.push_back(c);
    };
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            seed({0, a, b}), seed({n - 1, a, b});
            seed({a, 0, b}), seed({a, n - 1, b});
            seed({a, b, 0}), seed({a, b, n - 1});
        }
    while (!queue.empty()) {
        glm::ivec3 c = queue.front();
        queue.pop_front();
        for (const glm::ivec3& step : k_export_side_steps) {
            glm::ivec3 next = c + step;
            if (occupied.inside(next)) seed(next);
        }
    }
    return outside;
}

ExportGrid export_occupancy(const std::vector<std::uint32_t>& codes, int level)
{
    ExportGrid occupied(1 << level);
    for (std::uint32_t code : codes) occupied.set(glm::ivec3(morton_decode(code)));
    return occupied;
}

// PBR packages (issue #14): the captured occlusion, roughness and metallic (8-bit codes, linear)
// and the emission (linear, 1/65535), summed like the colour, so that each face or plane exports
// its mean material (step 5: constant tiles of an ORM and an emission atlas).
struct ExportMaterialSums {
    std::int64_t orm[3] = {0, 0, 0};
    std::int64_t emission[3] = {0, 0, 0};
};

void export_add_material(ExportMaterialSums& sums, std::int64_t weight, const ExportMaterialSums& texel)
{
    for (int c = 0; c < 3; ++c) {
        std::atomic_ref<std::int64_t>(sums.orm[c]).fetch_add(weight * texel.orm[c], std::memory_order_relaxed);
        std::atomic_ref<std::int64_t>(sums.emission[c]).fetch_add(weight * texel.emission[c], std::memory_order_relaxed);
    }
}

// The mean material of sums over `weight`, as one ORM texel (R occlusion, G roughness, B metallic:
// glTF's packing) and one sRGB emission texel.
void export_material_texels(const ExportMaterialSums& sums, double weight, std::uint8_t orm[4], std::uint8_t emission[4])
{
    for (int c = 0; c < 3; ++c) {
        orm[c] = std::uint8_t(std::clamp(std::lround(double(sums.orm[c]) / weight), 0l, 255l));
        const double linear = std::clamp(double(sums.emission[c]) / weight / double(k_export_color_scale), 0.0, 1.0);
        emission[c] = std::uint8_t(std::lround(255.0 * double(linear_to_srgb(float(linear)))));
    }
    orm[3] = emission[3] = 255;
}

// The ORM and emission atlases of step 5 (PBR packages): tile k of `texels.size()` (laid out as
// the coverage atlas: `columns` a row, `tile` texels a side) filled with texel k, border included.
struct ExportMaterialTexel {
    std::uint8_t orm[4] = {255, 255, 0, 255}; // the default material: unoccluded, rough, dielectric
    std::uint8_t emission[4] = {0, 0, 0, 255};
};

Status export_material_atlases(const std::vector<ExportMaterialTexel>& texels, int columns, int tile, ExportScene& scene,
                               ExportMesh& mesh)
{
    const int rows = (int(texels.size()) + columns - 1) / columns;
    ImageRGBA8 orm(columns * tile, rows * tile), emission(columns * tile, rows * tile);
    for (std::size_t k = 0; k < texels.size(); ++k) {
        const int ox = int(k) % columns * tile, oy = int(k) / columns * tile;
        for (int y = 0; y < tile; ++y)
            for (int x = 0; x < tile; ++x) {
                std::copy(texels[k].orm, texels[k].orm + 4, orm.at(ox + x, oy + y));
                std::copy(texels[k].emission, texels[k].emission + 4, emission.at(ox + x, oy + y));
            }
    }
    const int first = int(scene.textures.size());
    for (auto [name, image] : {std::pair{"microfacets_orm", &orm}, std::pair{"microfacets_emission", &emission}}) {
        Result<ExportTexture> texture = make_export_texture(name, *image);
        if (!texture) return texture.status();
        scene.textures.push_back(std::move(*texture));
    }
    use_pbr_maps(mesh, first, first + 1);
    return Status::ok();
}

// Per exposed face, the integer sums of step 3.
struct ExportFaceSums {
    std::int64_t weight = 0;
    std::int64_t color[3] = {0, 0, 0};
    std::int64_t normal[3] = {0, 0, 0};
    std::int64_t point[3] = {0, 0, 0}; // surface point in grid units (voxels) * k_export_point_scale
    ExportMaterialSums material;
};

// Per voxel, with planes (the default): the samples whose surface point it holds (count, linear colour and point
// as in ExportFaceSums, unweighted) and the normals' second moments n n^T (xx yy zz xy xz yz, in
// 1/32767): its principal direction is the plane's normal whatever side each view saw a leaf from.
struct ExportCellSums {
    std::int64_t count = 0;
    std::int64_t color[3] = {0, 0, 0};
    std::int64_t point[3] = {0, 0, 0};
    std::int64_t tensor[6] = {0, 0, 0, 0, 0, 0};
    ExportMaterialSums material;
};

void export_add(ExportFaceSums& sums, std::int64_t weight, const std::int64_t color[3], const std::int64_t normal[3],
                const std::int64_t point[3])
{
    std::atomic_ref<std::int64_t>(sums.weight).fetch_add(weight, std::memory_order_relaxed);
    for (int c = 0; c < 3; ++c) {
        std::atomic_ref<std::int64_t>(sums.color[c]).fetch_add(weight * color[c], std::memory_order_relaxed);
        std::atomic_ref<std::int64_t>(sums.normal[c]).fetch_add(weight * normal[c], std::memory_order_relaxed);
        std::atomic_ref<std::int64_t>(sums.point[c]).fetch_add(weight * point[c], std::memory_order_relaxed);
    }
}

// Step 3's walk (Amanatides & Woo 1987): from a captured surface point towards the camera of the
// view that saw it, through solid cells (occupied or enclosed), to the first cell boundary that
// leads out of them: the exposed face a rasteriser shows at that texel from that view.
struct ExportWalk {
    const ExportGrid& outside;
    glm::vec3 origin;
    float voxel = 1.0f;

    glm::ivec3 cell_of(glm::vec3 p) const { return glm::ivec3(glm::floor((p - origin) / voxel)); }
    bool solid(glm::ivec3 c) const { return outside.inside(c) && !outside.get(c); }
    // the solid cell and side (0..5) the walk leaves by, side -1 when `q` lies in no solid cell;
    // `q` moves half a voxel deeper when quantised depth left it just outside its voxel
    std::pair<glm::ivec3, int> exit(glm::vec3& q, glm::vec3 d) const
    {
        glm::ivec3 c = cell_of(q);
        if (!solid(c)) {
            q -= 0.5f * voxel * d;
            c = cell_of(q);
            if (!solid(c)) return {c, -1};
        }
        const glm::ivec3 step(d.x > 0.0f ? 1 : (d.x < 0.0f ? -1 : 0), d.y > 0.0f ? 1 : (d.y < 0.0f ? -1 : 0),
                              d.z > 0.0f ? 1 : (d.z < 0.0f ? -1 : 0));
        glm::vec3 t_max(INFINITY), t_delta(INFINITY);
        for (int a = 0; a < 3; ++a)
            if (step[a] != 0) {
                float boundary = origin[a] + float(c[a] + (step[a] > 0 ? 1 : 0)) * voxel;
                t_max[a] = (boundary - q[a]) / d[a];
                t_delta[a] = voxel / std::abs(d[a]);
            }
        for (int walked = 0; walked < 3 * outside.side + 3; ++walked) {
            int a = t_max.x <= t_max.y && t_max.x <= t_max.z ? 0 : (t_max.y <= t_max.z ? 1 : 2);
            glm::ivec3 next = c;
            next[a] += step[a];
            if (!solid(next)) return {c, 2 * a + (step[a] > 0 ? 0 : 1)};
            c = next;
            t_max[a] += t_delta[a];
        }
        return {c, -1};
    }
};

// What a view captured along its ray through `point` (both cut-out votes, voxel faces and planes,
// read the captures this way): the point's place on the view's plane and height along its
// direction (from the package centre), and the height of the surface stored in the capture texel
// under it, where that texel is covered.
struct CapturedAlongRay {
    bool covered = false;
    float su = 0.0f, sv = 0.0f, point_height = 0.0f, surface_height = 0.0f;
};

CapturedAlongRay captured_along_ray(const MicrofacetsPackage& package, const View& view, glm::vec3 point, float texel)
{
    const float r = package.radius;
    const glm::vec3 rel = point - package.center;
    CapturedAlongRay result;
    result.su = glm::dot(rel, view.axis_u), result.sv = glm::dot(rel, view.axis_v);
    result.point_height = glm::dot(rel, view.direction);
    const int x = int(std::floor((result.su + r) / texel)) - view.crop_x, y = int(std::floor((result.sv + r) / texel)) - view.crop_y;
    if (x < 0 || y < 0 || x >= view.width || y >= view.height) return result;
    if (package.color_pages[std::size_t(view.page)].at(view.atlas_x + x, view.atlas_y + y)[3] == 0) return result;
    const ImageRGBA16& normal_depth = package.normal_depth_pages[std::size_t(view.page)];
    result.covered = true;
    result.surface_height = r - 2.0f * r * reps::decode_depth(normal_depth.at(view.atlas_x + x, view.atlas_y + y)[3]);
    return result;
}

// Texel coverage codes from the views' votes: the cosine-weighted share of the views that voted
// (saw the texel's point, or nothing, there) and saw a surface at it; texels no view voted on stay.
void store_votes(const std::vector<float>& covered, const std::vector<float>& voted, std::uint8_t* codes)
{
    for (std::size_t t = 0; t < voted.size(); ++t)
        if (voted[t] > 0.0f) codes[t] = std::uint8_t(std::lround(255.0f * covered[t] / voted[t]));
}

std::string export_package_name(const Package& package)
{
    return quoted(package.directory.empty() ? std::string("package") : package.directory);
}

} // namespace

std::vector<OptionSpec> export_options()
{
    return {
        integer_option("level", -1, -1, k_max_grid_level,
                       "The octree level exported as voxel faces (-1: chosen by --pixels, else the finest baked)"),
        integer_option("pixels", 0, 0, 65536,
                       "The screen size, pixels, the bounding sphere's diameter spans: the coarsest level whose "
                       "voxels span at most 4 pixels there (1 with --no-snap; 0: not used)"),
        integer_option("cutout", 4, 0, 16,
                       "Coverage texels per plane (or face) side: a double-sided alpha MASK texture keeps what the "
                       "captured views see of each, so surfaces thinner than a voxel (leaves) are not drawn as whole "
                       "voxels (0: with --no-planes opaque faces, vertex colours only; planes keep one texel)"),
        flag_option("planes", true,
                    "One square per voxel in the plane of the surface its views saw, cut out by their coverage (no "
                    "parallax between square and leaf; the default: closer to standin render than the faces on the "
                    "bunny and on foliage); --no-planes: the closed surface of the voxels' exposed faces"),
        flag_option("snap", true,
                    "Move each voxel corner onto the captured surface (the mean surface point its faces' "
                    "texels hit), so the silhouette follows the surface instead of standing up to a voxel proud of it"),
    };
}

namespace {

std::vector<VoxelFace> export_faces_bordering(const std::vector<std::uint32_t>& codes, const ExportGrid& outside)
{
    std::vector<VoxelFace> faces;
    for (std::size_t v = 0; v < codes.size(); ++v) {
        glm::ivec3 c(morton_decode(codes[v]));
        for (int side = 0; side < 6; ++side) {
            glm::ivec3 next = c + k_export_side_steps[std::size_t(side)];
            if (!outside.inside(next) || outside.get(next)) faces.push_back({std::uint32_t(v), side});
        }
    }
    return faces;
}

} // namespace

std::vector<VoxelFace> exposed_faces(const Octree& tree, int level)
{
    const std::vector<std::uint32_t>& codes = tree.at(level);
    return export_faces_bordering(codes, export_exterior(export_occupancy(codes, level)));
}

Result<ExportScene> export_scene(const Package& base, const Options& options)
{
    const auto& package = reps::package_cast<MicrofacetsPackage>(base);
    const BakeSettings& s = package.settings;
    const Octree& tree = package.octree;
    const std::string name = export_package_name(package);

    // step 1
    int level = options.integer("level");
    const int pixels = options.integer("pixels");
    if (level >= 0 && pixels > 0)
        return error(StatusCode::invalid_argument, "--level and --pixels: give one of them, not both");
    if (level >= 0 && (level < s.min_level || level > s.level))
        return error(StatusCode::invalid_argument, "--level " + std::to_string(level) + ": " + name + " holds levels " +
                                                       std::to_string(s.min_level) + ".." + std::to_string(s.level));
    const bool snap = options.flag("snap");
    const float voxel_pixels = snap ? k_export_voxel_pixels_snapped : k_export_voxel_pixels_unsnapped;
    std::string level_reason = level >= 0 ? "--level" : "the finest baked";
    if (pixels > 0) {
        level = s.level;
        level_reason = "the finest baked (none has voxels of at most " + std::to_string(int(voxel_pixels)) + " px at --pixels " +
                       std::to_string(pixels) + ")";
        for (int l = s.min_level; l <= s.level; ++l)
            if (float(pixels) * tree.grid.voxel_size(l) / (2.0f * package.radius) <= voxel_pixels) {
                level = l;
                level_reason = "--pixels " + std::to_string(pixels);
                break;
            }
    }
    if (level < 0) level = s.level;

    // step 2
    const std::vector<std::uint32_t>& codes = tree.at(level);
    if (codes.empty()) return error(StatusCode::bad_data, name + ": octree level " + std::to_string(level) + " holds no voxels");
    const ExportGrid outside = export_exterior(export_occupancy(codes, level));
    const std::vector<VoxelFace> faces = export_faces_bordering(codes, outside);
    // slot voxel * 6 + side -> face index, or -1
    std::vector<std::int32_t> face_of(codes.size() * 6, -1);
    for (std::size_t f = 0; f < faces.size(); ++f) face_of[std::size_t(faces[f].voxel) * 6 + std::size_t(faces[f].side)] = std::int32_t(f);

    // step 3
    const Grid& grid = tree.grid;
    const float voxel = grid.voxel_size(level);
    const int n = 1 << level;
    const float r = package.radius, texel = 2.0f * r / float(s.resolution);
    std::array<std::int64_t, 256> linear_code{};
    for (int c = 0; c < 256; ++c) {
        linear_code[std::size_t(c)] = std::lround(srgb_to_linear(float(c) / 255.0f) * k_export_color_scale);
    }
    std::vector<ExportFaceSums> sums(faces.size());
    const bool planes = options.flag("planes");
    std::vector<ExportCellSums> cell_sums(planes ? codes.size() : 0);
    const ExportWalk walk{outside, grid.origin, voxel};
    const bool pbr = package.has_pbr();
    tbb::parallel_for(std::size_t(0), package.views.size(), [&](std::size_t k) {
        const View& view = package.views[k];
        if (view.width == 0) return;
        const ImageRGBA8& colors = package.color_pages[std::size_t(view.page)];
        const ImageRGBA16& normal_depth = package.normal_depth_pages[std::size_t(view.page)];
        const glm::vec3 d = view.direction;
        for (int y = 0; y < view.height; ++y)
            for (int x = 0; x < view.width; ++x) {
                const std::uint8_t* rgba = colors.at(view.atlas_x + x, view.atlas_y + y);
                if (rgba[3] == 0) continue;
                const std::uint16_t* nd = normal_depth.at(view.atlas_x + x, view.atlas_y + y);
                ExportMaterialSums material;
                if (pbr) {
                    const std::uint8_t* o = package.orm_pages[std::size_t(view.page)].at(view.atlas_x + x, view.atlas_y + y);
                    const std::uint8_t* e = package.emission_pages[std::size_t(view.page)].at(view.atlas_x + x, view.atlas_y + y);
                    for (int c = 0; c < 3; ++c) material.orm[c] = o[c], material.emission[c] = linear_code[e[c]];
                }
                float h = r - 2.0f * r * reps::decode_depth(nd[3]);
                glm::vec2 plane = -r + (glm::vec2(float(view.crop_x + x), float(view.crop_y + y)) + 0.5f) * texel;
                glm::vec3 q = package.center + plane.x * view.axis_u + plane.y * view.axis_v + h * d;
                auto [c, side] = walk.exit(q, d);
                if (side < 0) continue;
                if (planes) {
                    // planes: the sums go to the occupied voxel that holds the surface point
                    const glm::ivec3 start = walk.cell_of(q);
                    if (!walk.solid(start)) continue;
                    auto at = std::lower_bound(codes.begin(), codes.end(), morton_encode(glm::uvec3(start)));
                    if (at == codes.end() || *at != morton_encode(glm::uvec3(start))) continue;
                    glm::vec3 sn = reps::decode_normal(nd);
                    const std::int64_t colour_code[3] = {linear_code[rgba[0]], linear_code[rgba[1]], linear_code[rgba[2]]};
                    glm::vec3 g = (q - grid.origin) / voxel * k_export_point_scale;
                    const std::int64_t where[3] = {std::llround(g.x), std::llround(g.y), std::llround(g.z)};
                    ExportCellSums& into = cell_sums[std::size_t(at - codes.begin())];
                    std::atomic_ref<std::int64_t>(into.count).fetch_add(1, std::memory_order_relaxed);
                    if (pbr) export_add_material(into.material, 1, material);
                    for (int a = 0; a < 3; ++a) {
                        std::atomic_ref<std::int64_t>(into.color[a]).fetch_add(colour_code[a], std::memory_order_relaxed);
                        std::atomic_ref<std::int64_t>(into.point[a]).fetch_add(where[a], std::memory_order_relaxed);
                    }
                    const int pairs[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
                    for (int e = 0; e < 6; ++e)
                        std::atomic_ref<std::int64_t>(into.tensor[e]).fetch_add(
                            std::llround(double(sn[pairs[e][0]]) * double(sn[pairs[e][1]]) * double(k_export_normal_scale)), std::memory_order_relaxed);
                    continue;
                }
                auto it = std::lower_bound(codes.begin(), codes.end(), morton_encode(glm::uvec3(c)));
                if (it == codes.end() || *it != morton_encode(glm::uvec3(c))) continue; // a cavity cell never borders the outside
                std::int32_t f = face_of[std::size_t(it - codes.begin()) * 6 + std::size_t(side)];
                if (f < 0) continue;
                float cosine = std::abs(d[side / 2]);
                auto weight = std::int64_t(std::lround(cosine * k_export_weight_scale));
                if (weight <= 0) continue;
                const std::int64_t color[3] = {linear_code[rgba[0]], linear_code[rgba[1]], linear_code[rgba[2]]};
                glm::vec3 normal = reps::decode_normal(nd);
                const std::int64_t normal_code[3] = {std::lround(normal.x * k_export_normal_scale), std::lround(normal.y * k_export_normal_scale),
                                                     std::lround(normal.z * k_export_normal_scale)};
                glm::vec3 g = (q - grid.origin) / voxel * k_export_point_scale;
                const std::int64_t point_code[3] = {std::llround(g.x), std::llround(g.y), std::llround(g.z)};
                export_add(sums[std::size_t(f)], weight, color, normal_code, point_code);
                if (pbr) export_add_material(sums[std::size_t(f)].material, weight, material);
            }
    });

    // faces no view saw: their voxel's seen faces, else every seen face
    ExportFaceSums all;
    std::vector<ExportFaceSums> per_voxel(codes.size());
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const ExportFaceSums& fs = sums[f];
        for (ExportFaceSums* into : {&all, &per_voxel[faces[f].voxel]}) {
            into->weight += fs.weight;
            for (int c = 0; c < 3; ++c) {
                into->color[c] += fs.color[c], into->normal[c] += fs.normal[c];
                into->material.orm[c] += fs.material.orm[c], into->material.emission[c] += fs.material.emission[c];
            }
        }
    }
    std::size_t unseen = 0;

    // step 4, --snap: each lattice corner moves to the mean of its seen faces' mean surface points, at most
    // one voxel along each axis (a surface nets-like placement on the primal corners); corners are
    // keyed by lattice index, so every copy of a corner moves alike and the mesh stays closed
    auto lattice_key = [&](glm::ivec3 c) { return std::uint64_t(c.x) + std::uint64_t(n + 1) * (std::uint64_t(c.y) + std::uint64_t(n + 1) * std::uint64_t(c.z)); };
    std::map<std::uint64_t, std::pair<glm::dvec3, int>> corner_sums;
    auto face_corners = [&](const VoxelFace& face, glm::ivec3 out[4]) {
        const int axis = face.side / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
        glm::ivec3 corner(morton_decode(codes[face.voxel]));
        if (face.side % 2 == 0) corner[axis] += 1;
        glm::ivec3 du(0), dv(0);
        du[u] = 1, dv[v] = 1;
        out[0] = corner, out[1] = corner + du, out[2] = corner + du + dv, out[3] = corner + dv;
    };
    if (snap)
        for (std::size_t f = 0; f < faces.size(); ++f) {
            if (sums[f].weight == 0) continue;
            glm::dvec3 mean(double(sums[f].point[0]), double(sums[f].point[1]), double(sums[f].point[2]));
            mean /= double(sums[f].weight) * double(k_export_point_scale);
            glm::ivec3 corners[4];
            face_corners(faces[f], corners);
            for (const glm::ivec3& c : corners) {
                auto& entry = corner_sums[lattice_key(c)];
                entry.first += mean;
                entry.second += 1;
            }
        }
    auto corner_position = [&](glm::ivec3 c) {
        glm::vec3 lattice(c);
        if (snap) {
            auto it = corner_sums.find(lattice_key(c));
            if (it != corner_sums.end())
                lattice = glm::clamp(glm::vec3(it->second.first / double(it->second.second)), lattice - 1.0f, lattice + 1.0f);
        }
        return grid.origin + lattice * voxel;
    };

    // planes (the default; --no-planes: the faces): one square per seen voxel in the plane of the surface its views saw (the mean of the
    // surface points it holds, and the principal direction of their captured normals, so that the
    // two sides of a leaf do not cancel), side sqrt(3) W about the voxel centre's projection (so the
    // voxel's whole cross-section), textured with the coverage the views give each texel: covered
    // where a view's texel there is covered at the texel's own depth (within half a voxel: the
    // renderer's eq. 1 clip), empty where it is empty or deeper, silent where the surface is in
    // front; texels more than half a voxel outside the voxel are empty (neighbours' squares overlap
    // by that much, so that squares of differently tilted planes leave no cracks between them; the
    // depth test keeps the overlap on the surface). The facets of the paper, frozen in one orientation
    // per voxel: no parallax on flat surfaces (leaves), but not a closed surface.
    if (planes) {
        const int side = std::max(options.integer("cutout"), 1), tile_side = side + 2;
        const std::size_t texels = std::size_t(side) * std::size_t(side);
        std::vector<std::uint8_t> plane_coverage(codes.size() * texels, 0);
        std::vector<glm::vec3> plane_center(codes.size()), plane_normal(codes.size()), plane_u(codes.size()), plane_v(codes.size());
        std::vector<char> drawn(codes.size(), 0);
        const float tolerance = k_export_cutout_depth_tolerance * voxel, half = 0.5f * std::sqrt(3.0f) * voxel;
        tbb::parallel_for(std::size_t(0), codes.size(), [&](std::size_t v) {
            const ExportCellSums& cs = cell_sums[v];
            if (cs.count == 0) return;
            const double m[6] = {double(cs.tensor[0]), double(cs.tensor[1]), double(cs.tensor[2]),
                                 double(cs.tensor[3]), double(cs.tensor[4]), double(cs.tensor[5])};
            // power iteration from the axis of the largest diagonal entry: the principal direction
            glm::dvec3 e(0.0);
            e[m[0] >= m[1] && m[0] >= m[2] ? 0 : (m[1] >= m[2] ? 1 : 2)] = 1.0;
            for (int iteration = 0; iteration < 32; ++iteration) {
                const glm::dvec3 next(m[0] * e.x + m[3] * e.y + m[4] * e.z, m[3] * e.x + m[1] * e.y + m[5] * e.z,
                                      m[4] * e.x + m[5] * e.y + m[2] * e.z);
                if (glm::length(next) == 0.0) return;
                e = glm::normalize(next);
            }
            const glm::vec3 n(e);
            const glm::vec3 mean = grid.origin + glm::vec3(double(cs.point[0]), double(cs.point[1]), double(cs.point[2])) /
                                                     float(double(cs.count) * double(k_export_point_scale)) * voxel;
            const glm::vec3 cell_center = grid.center(codes[v], level);
            const glm::vec3 c = cell_center - glm::dot(cell_center - mean, n) * n;
            const glm::vec3 helper = std::abs(n.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
            const glm::vec3 u = glm::normalize(glm::cross(n, helper)), w = glm::cross(n, u);
            plane_center[v] = c, plane_normal[v] = n, plane_u[v] = u, plane_v[v] = w;
            drawn[v] = 1;
            const glm::vec3 lo = cell_center - voxel, hi = cell_center + voxel;
            std::vector<float> covered(texels, 0.0f), voted(texels, 0.0f);
            for (const View& view : package.views) {
                const float cosine = std::abs(glm::dot(view.direction, n));
                if (view.width == 0 || cosine < k_export_cutout_min_cosine) continue;
                for (int j = 0; j < side; ++j)
                    for (int i = 0; i < side; ++i) {
                        const glm::vec3 x = c + half * ((2.0f * (float(i) + 0.5f) / float(side) - 1.0f) * u +
                                                        (2.0f * (float(j) + 0.5f) / float(side) - 1.0f) * w);
                        if (glm::any(glm::lessThan(x, lo)) || glm::any(glm::greaterThan(x, hi))) continue;
                        const CapturedAlongRay seen = captured_along_ray(package, view, x, texel);
                        bool hit = false;
                        if (seen.covered) {
                            hit = std::abs(seen.surface_height - seen.point_height) <= tolerance;
                            if (!hit && seen.surface_height > seen.point_height) continue; // hidden from this view
                        }
                        const std::size_t t = std::size_t(j) * std::size_t(side) + std::size_t(i);
                        voted[t] += cosine;
                        if (hit) covered[t] += cosine;
                    }
            }
            store_votes(covered, voted, &plane_coverage[v * texels]);
        });
        // tiles: one per drawn voxel with any covered texel; voxels with none are left out
        std::vector<std::uint32_t> plane_tile(codes.size(), 0);
        std::uint32_t plane_tiles = 0;
        for (std::size_t v = 0; v < codes.size(); ++v) {
            const std::uint8_t* a = &plane_coverage[v * texels];
            if (drawn[v] && std::any_of(a, a + texels, [](std::uint8_t c) { return c >= 128; })) plane_tile[v] = plane_tiles++;
            else drawn[v] = 0;
        }
        if (plane_tiles == 0) return error(StatusCode::bad_data, name + ": no view saw surface in the voxels of level " + std::to_string(level));
        const int columns = int(std::ceil(std::sqrt(double(plane_tiles)))), rows = (int(plane_tiles) + columns - 1) / columns;
        ImageRGBA8 plane_atlas(columns * tile_side, rows * tile_side);
        ExportMesh planes;
        planes.name = "microfacets";
        planes.base_color_texture = 0;
        planes.alpha_mode = "MASK";
        planes.double_sided = true;
        const float aw = float(columns * tile_side), ah = float(rows * tile_side);
        for (std::size_t v = 0; v < codes.size(); ++v) {
            if (!drawn[v]) continue;
            const int ox = int(plane_tile[v]) % columns * tile_side, oy = int(plane_tile[v]) / columns * tile_side;
            for (int y = 0; y < tile_side; ++y)
                for (int x = 0; x < tile_side; ++x) {
                    const int i = std::clamp(x - 1, 0, side - 1), j = std::clamp(y - 1, 0, side - 1);
                    std::uint8_t* out = plane_atlas.at(ox + x, oy + y);
                    out[0] = out[1] = out[2] = 255;
                    out[3] = plane_coverage[v * texels + std::size_t(j) * std::size_t(side) + std::size_t(i)];
                }
            glm::vec4 colour(1.0f);
            for (int c = 0; c < 3; ++c) colour[c] = float(double(cell_sums[v].color[c]) / double(cell_sums[v].count) / double(k_export_color_scale));
            const auto first = std::uint32_t(planes.positions.size());
            for (glm::vec2 corner : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)}) {
                planes.positions.push_back(plane_center[v] + half * ((2.0f * corner.x - 1.0f) * plane_u[v] + (2.0f * corner.y - 1.0f) * plane_v[v]));
                planes.normals.push_back(plane_normal[v]);
                planes.colors.push_back(colour);
                planes.uvs.push_back({(float(ox + 1) + corner.x * float(side)) / aw, (float(oy + 1) + corner.y * float(side)) / ah});
            }
            for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) planes.indices.push_back(first + k);
        }
        Result<ExportTexture> texture = make_export_texture("microfacets_coverage", plane_atlas);
        if (!texture) return texture.status();
        ExportScene plane_scene;
        plane_scene.textures.push_back(std::move(*texture));
        if (pbr) {
            std::vector<ExportMaterialTexel> plane_material(plane_tiles);
            for (std::size_t v = 0; v < codes.size(); ++v)
                if (drawn[v] && cell_sums[v].count > 0)
                    export_material_texels(cell_sums[v].material, double(cell_sums[v].count), plane_material[plane_tile[v]].orm,
                                           plane_material[plane_tile[v]].emission);
            STANDIN_RETURN_IF_ERROR(export_material_atlases(plane_material, columns, tile_side, plane_scene, planes));
        }
        planes.extras["standin"] = {{"role", "mesh"},          {"level", level},         {"voxel_size", voxel},
                                    {"grid_origin", {grid.origin.x, grid.origin.y, grid.origin.z}},
                                    {"grid_size", grid.size},  {"voxels", codes.size()}, {"planes", plane_tiles},
                                    {"cutout", side},          {"baked_levels", {s.min_level, s.level}},
                                    {"views", package.views.size()}};
        char plane_line[320];
        std::snprintf(plane_line, sizeof plane_line,
                      "microfacets level %d (%d^3, %s): %zu voxels as %u surface planes (a %dx%d coverage atlas, %d^2 texels each)", level,
                      n, level_reason.c_str(), codes.size(), plane_tiles, columns * tile_side, rows * tile_side, side);
        plane_scene.notes.push_back(plane_line);
        if (pbr) plane_scene.notes.push_back("PBR materials: each plane's mean occlusion, roughness, metallic and emission");
        plane_scene.meshes.push_back(std::move(planes));
        return plane_scene;
    }

    // step 6, cut-outs (--cutout T > 0): T x T coverage texels per face, each voted by the captured
    // views that face it (cosine at least k_export_cutout_min_cosine, weighted by it). A view says
    // "covered" when the texel's point projects onto a covered capture texel whose surface point
    // lies within half a voxel of it in depth, or whose walk (step 3) leaves by this very face, i.e.
    // the view's ray through the texel meets the surface inside the solid run behind the face; it
    // says "empty" when the capture texel is empty or its surface lies beyond that run, and keeps
    // silent when the surface lies in front of the texel (hidden from that view). Faces per face
    // in parallel, views in order: the same votes at any thread count.
    const int cutout = options.integer("cutout");
    std::vector<std::uint8_t> coverage; // faces * T * T, alpha codes
    if (cutout > 0) {
        const std::size_t texels = std::size_t(cutout) * std::size_t(cutout);
        coverage.assign(faces.size() * texels, 255);
        const float tolerance = k_export_cutout_depth_tolerance * voxel;
        tbb::parallel_for(std::size_t(0), faces.size(), [&](std::size_t f) {
            const VoxelFace& face = faces[f];
            const glm::ivec3 cell(morton_decode(codes[face.voxel]));
            glm::ivec3 quad[4];
            face_corners(face, quad);
            glm::vec3 corner[4];
            for (int i = 0; i < 4; ++i) corner[i] = corner_position(quad[i]);
            glm::vec3 axis_normal(0.0f);
            axis_normal[face.side / 2] = face.side % 2 == 0 ? 1.0f : -1.0f;
            std::vector<float> covered(texels, 0.0f), voted(texels, 0.0f);
            for (const View& view : package.views) {
                const float cosine = glm::dot(view.direction, axis_normal);
                if (view.width == 0 || cosine < k_export_cutout_min_cosine) continue;
                for (int j = 0; j < cutout; ++j)
                    for (int i = 0; i < cutout; ++i) {
                        const float u = (float(i) + 0.5f) / float(cutout), v = (float(j) + 0.5f) / float(cutout);
                        // on the triangle step 5 draws there (diagonal 0-2), so texel and drawn point agree
                        const glm::vec3 point = u >= v ? corner[0] + u * (corner[1] - corner[0]) + v * (corner[2] - corner[1])
                                                       : corner[0] + v * (corner[3] - corner[0]) + u * (corner[2] - corner[3]);
                        const CapturedAlongRay seen = captured_along_ray(package, view, point, texel);
                        const std::size_t t = std::size_t(j) * std::size_t(cutout) + std::size_t(i);
                        bool hit = false;
                        if (seen.covered) {
                            const float h = seen.surface_height;
                            glm::vec3 q = package.center + seen.su * view.axis_u + seen.sv * view.axis_v + h * view.direction;
                            if (std::abs(h - seen.point_height) <= tolerance) {
                                hit = true;
                            } else {
                                auto [c, side] = walk.exit(q, view.direction);
                                hit = side == face.side && c == cell;
                                if (!hit && h > seen.point_height) continue; // hidden from this view
                            }
                        }
                        voted[t] += cosine;
                        if (hit) covered[t] += cosine;
                    }
            }
            store_votes(covered, voted, &coverage[f * texels]);
        });
    }

    // the coverage atlas: tiles of (T + 2)^2 texels, the border repeating the tile's edge so that
    // linear filtering never reaches a neighbour's; faces covered (or empty) at every texel share one
    // opaque (one empty) tile, the others get their own. No texture when every face is opaque.
    std::vector<std::uint32_t> tile_of(faces.size(), 0);
    std::uint32_t tiles = 2;
    std::size_t cut_faces = 0, empty_faces = 0;
    if (cutout > 0) {
        const std::size_t texels = std::size_t(cutout) * std::size_t(cutout);
        for (std::size_t f = 0; f < faces.size(); ++f) {
            const std::uint8_t* a = &coverage[f * texels];
            const bool all_in = std::all_of(a, a + texels, [](std::uint8_t c) { return c >= 128; });
            const bool all_out = std::none_of(a, a + texels, [](std::uint8_t c) { return c >= 128; });
            if (all_out) ++empty_faces;
            // a PBR package's faces each carry their own material, so their own tile
            tile_of[f] = pbr ? tiles++ : (all_in ? 0u : (all_out ? 1u : tiles++));
            cut_faces += !all_in;
        }
    } else if (pbr) {
        for (std::size_t f = 0; f < faces.size(); ++f) tile_of[f] = tiles++;
    }
    const int tile_inner = std::max(cutout, 1), tile = tile_inner + 2;
    const int atlas_columns = int(std::ceil(std::sqrt(double(tiles))));
    const int atlas_rows = (int(tiles) + atlas_columns - 1) / atlas_columns;
    const bool cut = cut_faces > 0;
    const bool textured = cut || pbr; // faces have UVs into the atlases
    ExportScene scene;
    if (cut) {
        const std::size_t texels = std::size_t(cutout) * std::size_t(cutout);
        ImageRGBA8 atlas_image(atlas_columns * tile, atlas_rows * tile);
        std::vector<const std::uint8_t*> source(tiles, nullptr);
        const std::vector<std::uint8_t> opaque(texels, 255), empty(texels, 0);
        source[0] = opaque.data(), source[1] = empty.data();
        for (std::size_t f = 0; f < faces.size(); ++f)
            if (tile_of[f] >= 2) source[tile_of[f]] = &coverage[f * texels];
        for (std::uint32_t k = 0; k < tiles; ++k) {
            const int ox = int(k) % atlas_columns * tile, oy = int(k) / atlas_columns * tile;
            for (int y = 0; y < tile; ++y)
                for (int x = 0; x < tile; ++x) {
                    const int i = std::clamp(x - 1, 0, cutout - 1), j = std::clamp(y - 1, 0, cutout - 1);
                    std::uint8_t* texel_out = atlas_image.at(ox + x, oy + y);
                    texel_out[0] = texel_out[1] = texel_out[2] = 255;
                    texel_out[3] = source[k][std::size_t(j) * std::size_t(cutout) + std::size_t(i)];
                }
        }
        Result<ExportTexture> texture = make_export_texture("microfacets_coverage", atlas_image);
        if (!texture) return texture.status();
        scene.textures.push_back(std::move(*texture));
    }

    // step 5
    ExportMesh mesh;
    mesh.name = "microfacets";
    mesh.positions.reserve(faces.size() * 4);
    mesh.normals.reserve(faces.size() * 4);
    mesh.colors.reserve(faces.size() * 4);
    mesh.indices.reserve(faces.size() * 6);
    if (textured) mesh.uvs.reserve(faces.size() * 4);
    if (cut) {
        mesh.base_color_texture = 0;
        mesh.alpha_mode = "MASK";
        mesh.double_sided = true; // a cut-out leaf's voxel faces are seen from inside through its holes
    }
    std::vector<ExportMaterialTexel> tile_material(pbr ? tiles : 0);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        const VoxelFace& face = faces[f];
        const int axis = face.side / 2;
        const bool positive = face.side % 2 == 0;
        glm::vec3 axis_normal(0.0f);
        axis_normal[axis] = positive ? 1.0f : -1.0f;
        const ExportFaceSums* source = &sums[f];
        if (source->weight == 0) {
            ++unseen;
            source = per_voxel[face.voxel].weight > 0 ? &per_voxel[face.voxel] : &all;
        }
        glm::vec4 color(0.5f, 0.5f, 0.5f, 1.0f);
        glm::vec3 normal = axis_normal;
        if (source->weight > 0) {
            const double w = double(source->weight);
            for (int c = 0; c < 3; ++c) color[c] = float(double(source->color[c]) / w / double(k_export_color_scale));
            glm::vec3 sum(float(source->normal[0]), float(source->normal[1]), float(source->normal[2]));
            if (source == &sums[f] && glm::length(sum) > 0.0f) normal = glm::normalize(sum);
            if (pbr) export_material_texels(source->material, w, tile_material[tile_of[f]].orm, tile_material[tile_of[f]].emission);
        }
        // corners: u, v the other two axes in cyclic order, so that u x v is +axis and the loop
        // (0,0) (1,0) (1,1) (0,1) is counter-clockwise seen from the +axis side; positions from
        // lattice corners, so that faces sharing a corner share its exact bits (engines weld
        // them; the watertightness test does)
        glm::ivec3 quad[4];
        face_corners(face, quad);
        auto first = std::uint32_t(mesh.positions.size());
        for (const glm::ivec3& lattice : quad) {
            mesh.positions.push_back(corner_position(lattice));
            mesh.normals.push_back(normal);
            mesh.colors.push_back(color);
        }
        if (textured) {
            const int ox = int(tile_of[f]) % atlas_columns * tile + 1, oy = int(tile_of[f]) / atlas_columns * tile + 1;
            const float w = float(atlas_columns * tile), h = float(atlas_rows * tile), t = float(tile_inner);
            for (glm::vec2 corner_uv : {glm::vec2(0, 0), glm::vec2(1, 0), glm::vec2(1, 1), glm::vec2(0, 1)})
                mesh.uvs.push_back({(float(ox) + corner_uv.x * t) / w, (float(oy) + corner_uv.y * t) / h});
        }
        const std::uint32_t order[6] = {0, 1, 2, 0, 2, 3};
        const std::uint32_t reversed[6] = {0, 2, 1, 0, 3, 2};
        const std::uint32_t* corners = positive ? order : reversed;
        for (int i = 0; i < 6; ++i) mesh.indices.push_back(first + corners[i]);
    }

    const float sphere_pixels = pixels > 0 ? float(pixels) : 0.0f;
    mesh.extras["standin"] = {{"role", "mesh"},
                              {"level", level},
                              {"voxel_size", voxel},
                              {"grid_origin", {grid.origin.x, grid.origin.y, grid.origin.z}},
                              {"grid_size", grid.size},
                              {"voxels", codes.size()},
                              {"faces", faces.size()},
                              {"unseen_faces", unseen},
                              {"pixels", pixels},
                              {"snap", snap},
                              {"cutout", cutout},
                              {"cut_faces", cut_faces},
                              {"empty_faces", empty_faces},
                              {"baked_levels", {s.min_level, s.level}},
                              {"views", package.views.size()},
                              // what a port of the paper's renderer would draw instead of these faces
                              {"facet_side", std::sqrt(3.0f) * voxel},
                              {"max_view_angle_degrees", glm::degrees(package.max_view_angle)}};
    char line[320];
    std::snprintf(line, sizeof line,
                  "microfacets level %d (%d^3, %s): %zu voxels as %zu exposed faces, %zu triangles, %zu vertices; %zu "
                  "faces no view saw",
                  level, n, level_reason.c_str(), codes.size(), faces.size(), mesh.indices.size() / 3, mesh.positions.size(), unseen);
    scene.notes.push_back(line);
    if (cut) {
        std::snprintf(line, sizeof line,
                      "cut-outs: %zu of %zu faces not fully covered (%zu empty), a %dx%d coverage atlas of %u tiles of %d^2 texels",
                      cut_faces, faces.size(), empty_faces, atlas_columns * tile, atlas_rows * tile, tiles, cutout);
        scene.notes.push_back(line);
    }
    if (sphere_pixels > 0.0f) {
        std::snprintf(line, sizeof line, "a voxel spans %.2f px when the bounding sphere spans %d px", double(sphere_pixels * voxel / (2.0f * r)), pixels);
        scene.notes.push_back(line);
    }
    if (pbr) {
        STANDIN_RETURN_IF_ERROR(export_material_atlases(tile_material, atlas_columns, tile, scene, mesh));
        std::snprintf(line, sizeof line, "PBR materials: each face's mean occlusion, roughness, metallic and emission, a %dx%d tile each",
                      tile_inner, tile_inner);
        scene.notes.push_back(line);
    }
    scene.meshes.push_back(std::move(mesh));
    return scene;
}

} // namespace standin::microfacets
