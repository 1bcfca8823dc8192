// Export of a displaced control mesh (docs/FORMAT.md, "Export: displaced mesh"): the surface the
// GPU refinement of Bauman, Livny & El-Sana (§3.3, §3.4; refine.h) draws, frozen into one plain
// triangle mesh that any glTF viewer shows. Steps: a view-independent refinement (orthographic,
// the bounding sphere's diameter spanning --pixels pixels, no culling, the paper's weighted split
// rule so that no facing term enters), each refined corner displaced as the vertex stage does,
// corners welded by exact position and stored normal (the refinement evaluates shared edges
// bit-identically; hard edges keep a vertex per side), shading normal + albedo from the nearest
// finest-level sample, flat faces of uniform samples left whole, and PBR factors per mesh the
// mean of its samples'. Departs from the renderer in the
// criterion (the renderer's default "error" weighs edges by how they face the camera; an export
// has no camera) and in having no per-frame view.
// Packages of alpha-masked models (issue #14) export their shading samples as a texture instead:
// each control face's shading pattern in a cell of one RGBA atlas (albedo, coverage in alpha), a
// MASK material (cut-off 1/2, double-sided), and faces that lie flat (leaf cards kept whole) as
// their control triangle, left out of the weighted rule's mean (prepare_faces `kept_whole`). Their
// outlines then come from the texture, as the renderer's from its interpolated coverage, where
// vertex alphas needed a vertex per sample (the 4,000-face tree's export: 3.2 million triangles
// and 101 MiB before, 0.49 million and 14 MiB with the atlas).
// Faces drawn with the source's own texture (source_textures.h, session 46) export as the source
// triangles they are: one mesh per (texture, alpha cutoff), TEXCOORD_0 the records' corner UVs
// interpolated at the refined corners, COLOR_0 their corner colours, the texture as the package
// holds it (repeated, as the truth reads it), MASK at the material's own cutoff. They take no cell
// of the samples' atlas and, being source triangles, are not split.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/refine.h"
#include "reps/common/package_cast.h"

#include <standin/export.h>
#include <standin/image.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <tuple>

namespace standin::displaced_mesh {

std::vector<OptionSpec> export_options()
{
    return {
        number_option("tau", "1", 0.0, 1000.0,
                      "displaced-mesh: tolerance of the exported refinement, pixels at --pixels (the paper's tau)", true),
        integer_option("pixels", 1024, 16, 65536,
                       "displaced-mesh: the screen size, pixels, that the bounding sphere's diameter spans for --tau"),
    };
}

namespace {

float export_srgb_to_linear(std::uint32_t code)
{
    return srgb_to_linear(float(code & 0xffu) / 255.0f);
}

// Widest atlas an export writes: glTF loaders and engines take 8192 texels everywhere.
constexpr int k_max_atlas_side = 8192;

// The shading samples of the faces that draw them as cells of one texture: the c-th such face's cell
// is (m + 3) texels square at column c % columns, row c / columns; its texel (1 + j, 1 + i) holds sample (i, j) of a
// pattern of m = n_s / stride segments (every stride-th shading sample: 1 unless the atlas would be
// wider than k_max_atlas_side), so texel centres lie on the samples and texture coordinates are
// affine over the face. The cell's other texels (beyond the face's diagonal, and a 1-texel rim)
// repeat the samples mirrored across that diagonal or clamped to the rim, so bilinear filtering
// inside the face never reads another face's cell.
struct SampleAtlas {
    int stride = 1, segments = 1, cell = 4, columns = 1, rows = 1;
    std::vector<std::uint32_t> cell_faces; // the face of each cell
    std::vector<std::uint32_t> cell_of;    // the cell of each face (faces without one: unused)

    SampleAtlas(const std::vector<std::uint8_t>& has_cell, int shading_segments) : cell_of(has_cell.size(), 0)
    {
        for (std::size_t f = 0; f < has_cell.size(); ++f)
            if (has_cell[f]) cell_of[f] = std::uint32_t(cell_faces.size()), cell_faces.push_back(std::uint32_t(f));
        const std::size_t faces = cell_faces.size();
        for (;;) {
            segments = shading_segments / stride;
            cell = segments + 3;
            columns = std::max(1, int(std::ceil(std::sqrt(double(faces)))));
            rows = int((faces + std::size_t(columns) - 1) / std::size_t(columns));
            if ((std::max(columns, rows) * cell <= k_max_atlas_side) || segments <= 1) break;
            stride *= 2;
        }
    }
    int width() const { return columns * cell; }
    int height() const { return rows * cell; }

    // The texture coordinate of the point with weights w1 (corner 1) and w2 (corner 2) of `face`.
    glm::vec2 uv(std::uint32_t face, double w1, double w2) const
    {
        const std::uint32_t c = cell_of[face];
        const double x = double(int(c % std::uint32_t(columns)) * cell) + 1.5 + w1 * segments;
        const double y = double(int(c / std::uint32_t(columns)) * cell) + 1.5 + w2 * segments;
        return glm::vec2(float(x / width()), float(y / height()));
    }

    ImageRGBA8 image(const DisplacedMeshPackage& p) const
    {
        ImageRGBA8 out(width(), height());
        const int n_s = p.shading_segments();
        for (std::size_t c = 0; c < cell_faces.size(); ++c) {
            const std::size_t f = cell_faces[c];
            const int x0 = int(c % std::size_t(columns)) * cell, y0 = int(c / std::size_t(columns)) * cell;
            for (int y = 0; y < cell; ++y)
                for (int x = 0; x < cell; ++x) {
                    int i = std::clamp(y - 1, 0, segments), j = std::clamp(x - 1, 0, segments);
                    if (i + j > segments) std::tie(i, j) = std::pair(segments - j, segments - i); // across the diagonal
                    const std::size_t sample = f * p.shading_samples_per_face() + triangle_index(n_s, i * stride, j * stride);
                    const std::uint32_t albedo = p.albedo[sample];
                    std::uint8_t* texel = out.at(x0 + x, y0 + y);
                    texel[0] = std::uint8_t(albedo), texel[1] = std::uint8_t(albedo >> 8), texel[2] = std::uint8_t(albedo >> 16);
                    texel[3] = p.coverage.empty() ? 255 : p.coverage[sample];
                }
        }
        return out;
    }
};

// Faces whose displaced surface stays within `flat_below` of their control triangle (leaf cards kept
// whole: elevation 0 but for its 16-bit rounding), which the textured export draws unsplit.
std::vector<std::uint8_t> flat_faces(const DisplacedMeshPackage& p, float flat_below)
{
    const std::size_t per_face = p.layout().samples_per_face;
    std::vector<std::uint8_t> flat(p.face_count(), 0);
    for (std::size_t f = 0; f < flat.size(); ++f) {
        bool within = p.face_error[f] <= flat_below;
        for (std::size_t k = 0; within && k < per_face; ++k) within = std::abs(p.elevations[f * per_face + k]) <= flat_below;
        flat[f] = within;
    }
    return flat;
}

// Whether every shading sample of face f holds the same normal, albedo and PBR inputs.
bool uniform_samples(const DisplacedMeshPackage& p, std::size_t f)
{
    const std::size_t per_face = p.shading_samples_per_face(), first = f * per_face;
    for (std::size_t k = first + 1; k < first + per_face; ++k) {
        if (p.shading_normals[k] != p.shading_normals[first] || p.albedo[k] != p.albedo[first]) return false;
        if (!p.orm.empty() && (p.orm[k] != p.orm[first] || p.emission[k] != p.emission[first])) return false;
    }
    return true;
}

} // namespace

Result<ExportScene> export_scene(const Package& base, const Options& options)
{
    const auto& p = reps::package_cast<DisplacedMeshPackage>(base);
    const PatternLayout layout = p.layout();
    const bool textured = !p.coverage.empty();
    const SourceTextures& source = p.source_textures;
    const Bounds& b = p.source.bounds;
    const float radius = std::max(0.5f * glm::length(b.max - b.min), 1e-12f);
    const int pixels = options.integer("pixels");
    RefineView view;
    view.orthographic = true;
    view.pixels_per_unit = float(pixels) / (2.0f * radius);
    RefineOptions refine_options;
    refine_options.tau = options.number("tau");
    refine_options.criterion = Criterion::weighted;
    refine_options.cull = false;
    refine_options.mip = true;
    // faces drawn with the source's texture (source triangles: never split) and, with the atlas,
    // flat faces, whose colours and outlines need no vertices: within tau / 8 of their control
    std::vector<std::uint8_t> drawn_from_source(p.face_count(), 0);
    for (std::size_t f = 0; f < source.faces.size() && f < p.face_count(); ++f) drawn_from_source[f] = source.faces[f].layer != k_no_texture;
    // triangle they stay whole; without the atlas, also flat faces whose samples are all alike
    // (a box's sides: its vertex colours need no vertex per sample either)
    std::vector<std::uint8_t> kept_whole = flat_faces(p, 0.125f * float(refine_options.tau) / view.pixels_per_unit);
    for (std::size_t f = 0; f < kept_whole.size(); ++f)
        kept_whole[f] = (kept_whole[f] && (textured || uniform_samples(p, f))) || drawn_from_source[f];
    std::vector<FaceRefineData> faces =
        prepare_faces(p.positions, p.normals, p.indices, p.topology, layout, p.elevations, p.face_error, {}, kept_whole);
    RefineSurface surface;
    surface.positions = &p.positions;
    surface.normals = &p.normals;
    surface.indices = &p.indices;
    surface.topology = &p.topology;
    surface.elevations = &p.elevations;
    surface.faces = &faces;
    surface.degree = p.settings.degree;
    RefineStats stats;
    std::vector<RefinedTriangle> triangles = refine(surface, view, refine_options, stats);

    const int n = layout.segments;
    const int detail = p.settings.shading_detail;
    std::vector<std::uint8_t> has_cell(textured ? p.face_count() : 0, 0);
    for (std::size_t f = 0; f < has_cell.size(); ++f) has_cell[f] = !drawn_from_source[f];
    const SampleAtlas atlas(has_cell, p.shading_segments());

    // mesh 0 draws the samples; the others the source's textures, one per (layer, cutoff)
    std::vector<ExportMesh> meshes(1);
    meshes[0].name = "displaced_mesh";
    std::map<std::pair<std::uint32_t, float>, std::size_t> source_mesh_of;
    // corners welded where position and stored shading normal agree (hard edges stay hard): with
    // the atlas within their face only (their texture coordinates are the face's cell), on source
    // faces where their UV and colour agree too
    using WeldKey = std::array<std::uint32_t, 8>;
    std::vector<std::map<WeldKey, std::uint32_t>> welded(1);
    std::vector<std::uint8_t> any_color(1, 0); // a source mesh's corners are not all white
    // PBR packages: each mesh's factors, the mean of its vertices' samples (glTF's factors are one
    // per material; the samples' variation over a mesh is not exported)
    struct PbrSum {
        double roughness = 0.0, metallic = 0.0;
        glm::dvec3 emission{0.0};
        std::size_t count = 0;
    };
    std::vector<PbrSum> pbr_sums(1);
    for (const RefinedTriangle& t : triangles) {
        const bool from_source = drawn_from_source[t.face] != 0;
        std::size_t m = 0;
        if (from_source) {
            const FaceTexture& record = source.faces[t.face];
            auto [it, inserted] = source_mesh_of.try_emplace({record.layer, record.cutoff}, meshes.size());
            if (inserted) {
                meshes.emplace_back();
                char name[64];
                std::snprintf(name, sizeof name, "displaced_mesh_source_texture_%03u", record.layer);
                meshes.back().name = name;
                welded.emplace_back();
                any_color.push_back(0);
                pbr_sums.emplace_back();
            }
            m = it->second;
        }
        ExportMesh& mesh = meshes[m];
        for (int k = 0; k < 3; ++k) {
            glm::vec3 position = displaced_position(surface, t.face, t.q[k][0], t.q[k][1], view, refine_options);
            const double w1 = double(t.q[k][0]) / double(k_bary_one), w2 = double(t.q[k][1]) / double(k_bary_one);
            WeldKey key{};
            std::memcpy(key.data(), &position, sizeof position);
            glm::vec2 uv(0.0f);
            std::uint32_t color = 0xffffffffu;
            if (from_source) {
                const FaceTexture& record = source.faces[t.face];
                const double w0 = 1.0 - w1 - w2;
                uv = glm::vec2(w0 * glm::dvec2(record.uv[0]) + w1 * glm::dvec2(record.uv[1]) + w2 * glm::dvec2(record.uv[2]));
                // corner colours as the renderer interpolates them (sRGB-encoded bytes)
                for (int c = 0; c < 4; ++c) {
                    auto channel = [&](int corner) { return double((record.color[corner] >> (8 * c)) & 0xffu); };
                    const double value = w0 * channel(0) + w1 * channel(1) + w2 * channel(2);
                    color = (color & ~(0xffu << (8 * c))) | (std::uint32_t(std::lround(std::clamp(value, 0.0, 255.0))) << (8 * c));
                }
                std::memcpy(&key[3], &uv, sizeof uv);
                key[5] = color;
            } else if (textured) {
                key[6] = t.face;
            }
            // pattern vertex (i, j) has weights j / n on corner 1 and i / n on corner 2
            int i = int(std::lround(double(t.q[k][1]) * n / double(k_bary_one)));
            int j = int(std::lround(double(t.q[k][0]) * n / double(k_bary_one)));
            i = std::clamp(i, 0, n);
            j = std::clamp(j, 0, n - i);
            const std::size_t sample = std::size_t(t.face) * p.shading_samples_per_face() + triangle_index(n * detail, i * detail, j * detail);
            key[7] = p.shading_normals[sample];
            auto [it, inserted] = welded[m].try_emplace(key, std::uint32_t(mesh.positions.size()));
            if (inserted) {
                if (!p.orm.empty()) {
                    PbrSum& sum = pbr_sums[m];
                    sum.roughness += double((p.orm[sample] >> 8) & 0xffu) / 255.0;
                    sum.metallic += double((p.orm[sample] >> 16) & 0xffu) / 255.0;
                    sum.emission += glm::dvec3(export_srgb_to_linear(p.emission[sample]), export_srgb_to_linear(p.emission[sample] >> 8),
                                               export_srgb_to_linear(p.emission[sample] >> 16));
                    ++sum.count;
                }
                mesh.positions.push_back(position);
                mesh.normals.push_back(decode_normal(p.shading_normals[sample]));
                if (from_source) {
                    mesh.uvs.push_back(uv);
                    mesh.colors.push_back({export_srgb_to_linear(color), export_srgb_to_linear(color >> 8), export_srgb_to_linear(color >> 16),
                                           float(color >> 24) / 255.0f});
                    any_color[m] |= color != 0xffffffffu;
                } else if (textured) {
                    mesh.uvs.push_back(atlas.uv(t.face, w1, w2));
                } else {
                    std::uint32_t albedo = p.albedo[sample];
                    mesh.colors.push_back({export_srgb_to_linear(albedo), export_srgb_to_linear(albedo >> 8),
                                           export_srgb_to_linear(albedo >> 16), float(albedo >> 24) / 255.0f});
                }
            }
            mesh.indices.push_back(it->second);
        }
    }
    ExportScene scene;
    // as the renderer draws them: both sides unless the package culls back faces (single-sided
    // sheets), and cut-out cards always (seen from both sides)
    const bool draws_both_sides = textured || p.settings.back_faces != "cull";
    const nlohmann::json extras = {{"role", "mesh"},
                                   {"tau", refine_options.tau},
                                   {"pixels", pixels},
                                   {"criterion", "weighted"},
                                   {"control_faces", p.face_count()},
                                   {"degree", p.settings.degree}};
    char line[240];
    if (!meshes[0].indices.empty()) {
        ExportMesh& mesh = meshes[0];
        if (textured) {
            Result<ExportTexture> texture = make_export_texture("displaced_mesh_samples", atlas.image(p));
            if (!texture) return texture.status();
            scene.textures.push_back(std::move(*texture));
            mesh.base_color_texture = 0;
            mesh.alpha_mode = "MASK";
        }
        mesh.double_sided = draws_both_sides;
        mesh.extras["standin"] = extras;
    }
    std::map<std::uint32_t, int> texture_of_layer;
    std::size_t source_triangles = 0;
    for (const auto& [group, m] : source_mesh_of) {
        ExportMesh& mesh = meshes[m];
        auto [it, inserted] = texture_of_layer.try_emplace(group.first, int(scene.textures.size()));
        if (inserted) {
            const Texture& layer = source.layers.at(group.first);
            ImageRGBA8 image(layer.width, layer.height);
            image.pixels = layer.rgba; // row 0 at v = 0: the top row of the PNG, as glTF's UVs read it
            Result<ExportTexture> texture = make_export_texture(layer.name, image);
            if (!texture) return texture.status();
            texture->repeat = true;
            scene.textures.push_back(std::move(*texture));
        }
        mesh.base_color_texture = it->second;
        if (group.second > 0.0f) {
            mesh.alpha_mode = "MASK";
            // the material's cutoff (the records hold alpha_test_cutoff's, a tolerance below it)
            mesh.alpha_cutoff = std::min(group.second + k_alpha_cutoff_tolerance, 1.0f);
        }
        mesh.double_sided = draws_both_sides;
        if (!any_color[m]) mesh.colors.clear();
        mesh.extras["standin"] = extras;
        mesh.extras["standin"]["source_texture"] = group.first;
        source_triangles += mesh.indices.size() / 3;
    }
    std::size_t triangles_out = 0, vertices_out = 0;
    for (const ExportMesh& mesh : meshes) triangles_out += mesh.indices.size() / 3, vertices_out += mesh.positions.size();
    std::snprintf(line, sizeof line, "displaced mesh refined to tau %g px at %d px: %zu triangles, %zu vertices (from %zu control faces)",
                  double(refine_options.tau), pixels, triangles_out, vertices_out, p.face_count());
    scene.notes.push_back(line);
    if (textured && !meshes[0].indices.empty()) {
        std::snprintf(line, sizeof line, "shading samples and coverage as a %dx%d texture (%d samples per face edge%s)", atlas.width(),
                      atlas.height(), atlas.segments + 1, atlas.stride > 1 ? ", every other one or fewer: the atlas is capped at 8192" : "");
        scene.notes.push_back(line);
    }
    if (!source_mesh_of.empty()) {
        std::snprintf(line, sizeof line, "%zu triangles drawn with the source's own %zu texture%s (source triangles, as baked)",
                      source_triangles, texture_of_layer.size(), texture_of_layer.size() == 1 ? "" : "s");
        scene.notes.push_back(line);
    }
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        if (meshes[m].indices.empty()) continue;
        if (const PbrSum& sum = pbr_sums[m]; sum.count > 0) {
            meshes[m].roughness = float(sum.roughness / double(sum.count));
            meshes[m].metallic = float(sum.metallic / double(sum.count));
            meshes[m].emissive = glm::vec3(sum.emission / double(sum.count));
        }
        scene.meshes.push_back(std::move(meshes[m]));
    }
    return scene;
}

} // namespace standin::displaced_mesh
