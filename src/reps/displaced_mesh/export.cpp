// Export of a displaced control mesh (docs/FORMAT.md, "Export: displaced mesh"): the surface the
// GPU refinement of Bauman, Livny & El-Sana (§3.3, §3.4; refine.h) draws, frozen into one plain
// triangle mesh that any glTF viewer shows. Steps: a view-independent refinement (orthographic,
// the bounding sphere's diameter spanning --pixels pixels, no culling, the paper's weighted split
// rule so that no facing term enters), each refined corner displaced as the vertex stage does,
// corners welded by exact position (the refinement evaluates shared edges bit-identically), and
// shading normal + albedo from the nearest finest-level sample. Departs from the renderer in the
// criterion (the renderer's default "error" weighs edges by how they face the camera; an export
// has no camera) and in having no per-frame view.
// Packages of alpha-masked models (issue #14) export their shading samples as a texture instead:
// each control face's shading pattern in a cell of one RGBA atlas (albedo, coverage in alpha), a
// MASK material (cut-off 1/2, double-sided), and faces that lie flat (leaf cards kept whole) as
// their control triangle, left out of the weighted rule's mean (prepare_faces `kept_whole`). Their
// outlines then come from the texture, as the renderer's from its interpolated coverage, where
// vertex alphas needed a vertex per sample (the 4,000-face tree's export: 3.2 million triangles
// and 101 MiB before, 0.49 million and 14 MiB with the atlas).
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/refine.h"
#include "reps/common/package_cast.h"

#include <standin/export.h>

#include <algorithm>
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
    float c = float(code & 0xffu) / 255.0f;
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Widest atlas an export writes: glTF loaders and engines take 8192 texels everywhere.
constexpr int k_max_atlas_side = 8192;

// The shading samples of every face as cells of one texture: face f's cell is (m + 3) texels
// square at column f % columns, row f / columns; its texel (1 + j, 1 + i) holds sample (i, j) of a
// pattern of m = n_s / stride segments (every stride-th shading sample: 1 unless the atlas would be
// wider than k_max_atlas_side), so texel centres lie on the samples and texture coordinates are
// affine over the face. The cell's other texels (beyond the face's diagonal, and a 1-texel rim)
// repeat the samples mirrored across that diagonal or clamped to the rim, so bilinear filtering
// inside the face never reads another face's cell.
struct SampleAtlas {
    int stride = 1, segments = 1, cell = 4, columns = 1, rows = 1;

    SampleAtlas(std::size_t faces, int shading_segments)
    {
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
        const double x = double(int(face % std::uint32_t(columns)) * cell) + 1.5 + w1 * segments;
        const double y = double(int(face / std::uint32_t(columns)) * cell) + 1.5 + w2 * segments;
        return glm::vec2(float(x / width()), float(y / height()));
    }

    ImageRGBA8 image(const DisplacedMeshPackage& p) const
    {
        ImageRGBA8 out(width(), height());
        const int n_s = p.shading_segments();
        for (std::size_t f = 0; f < p.face_count(); ++f) {
            const int x0 = int(f % std::size_t(columns)) * cell, y0 = int(f / std::size_t(columns)) * cell;
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

} // namespace

Result<ExportScene> export_scene(const Package& base, const Options& options)
{
    const auto& p = reps::package_cast<DisplacedMeshPackage>(base);
    const PatternLayout layout = p.layout();
    const bool textured = !p.coverage.empty();
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
    // with the atlas, flat faces' colours and outlines need no vertices: within tau / 8 of their
    // control triangle they stay whole
    const std::vector<std::uint8_t> kept_whole =
        textured ? flat_faces(p, 0.125f * float(refine_options.tau) / view.pixels_per_unit) : std::vector<std::uint8_t>{};
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

    ExportMesh mesh;
    mesh.name = "displaced_mesh";
    const int n = layout.segments;
    const int detail = p.settings.shading_detail;
    const SampleAtlas atlas(textured ? p.face_count() : 0, p.shading_segments());
    // corners welded by exact position; with the atlas within their face only (their texture
    // coordinates are the face's cell)
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> welded;
    mesh.indices.reserve(triangles.size() * 3);
    for (const RefinedTriangle& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            glm::vec3 position = displaced_position(surface, t.face, t.q[k][0], t.q[k][1], view, refine_options);
            std::uint32_t bits[3];
            std::memcpy(bits, &position, sizeof bits);
            auto [it, inserted] =
                welded.try_emplace({textured ? t.face : 0u, bits[0], bits[1], bits[2]}, std::uint32_t(mesh.positions.size()));
            if (inserted) {
                // pattern vertex (i, j) has weights j / n on corner 1 and i / n on corner 2
                int i = int(std::lround(double(t.q[k][1]) * n / double(k_bary_one)));
                int j = int(std::lround(double(t.q[k][0]) * n / double(k_bary_one)));
                i = std::clamp(i, 0, n);
                j = std::clamp(j, 0, n - i);
                std::size_t sample = std::size_t(t.face) * p.shading_samples_per_face() + triangle_index(n * detail, i * detail, j * detail);
                mesh.positions.push_back(position);
                mesh.normals.push_back(decode_normal(p.shading_normals[sample]));
                if (textured) {
                    mesh.uvs.push_back(atlas.uv(t.face, double(t.q[k][0]) / double(k_bary_one), double(t.q[k][1]) / double(k_bary_one)));
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
    if (textured) {
        Result<ExportTexture> texture = make_export_texture("displaced_mesh_samples", atlas.image(p));
        if (!texture) return texture.status();
        scene.textures.push_back(std::move(*texture));
        mesh.base_color_texture = 0;
        mesh.alpha_mode = "MASK";
        mesh.double_sided = true; // cut-out cards are seen from both sides, as the renderer draws them
    }
    mesh.extras["standin"] = {{"role", "mesh"},
                              {"tau", refine_options.tau},
                              {"pixels", pixels},
                              {"criterion", "weighted"},
                              {"control_faces", p.face_count()},
                              {"degree", p.settings.degree}};
    char line[240];
    std::snprintf(line, sizeof line, "displaced mesh refined to tau %g px at %d px: %zu triangles, %zu vertices (from %zu control faces)",
                  double(refine_options.tau), pixels, mesh.indices.size() / 3, mesh.positions.size(), p.face_count());
    scene.notes.push_back(line);
    if (textured) {
        std::snprintf(line, sizeof line, "shading samples and coverage as a %dx%d texture (%d samples per face edge%s)", atlas.width(),
                      atlas.height(), atlas.segments + 1, atlas.stride > 1 ? ", every other one or fewer: the atlas is capped at 8192" : "");
        scene.notes.push_back(line);
    }
    scene.meshes.push_back(std::move(mesh));
    return scene;
}

} // namespace standin::displaced_mesh
