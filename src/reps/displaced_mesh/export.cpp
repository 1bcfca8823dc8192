// Export of a displaced control mesh (docs/FORMAT.md, "Export: displaced mesh"): the surface the
// GPU refinement of Bauman, Livny & El-Sana (§3.3, §3.4; refine.h) draws, frozen into one plain
// triangle mesh that any glTF viewer shows. Steps: a view-independent refinement (orthographic,
// the bounding sphere's diameter spanning --pixels pixels, no culling, the paper's weighted split
// rule so that no facing term enters), each refined corner displaced as the vertex stage does,
// corners welded by exact position (the refinement evaluates shared edges bit-identically), and
// shading normal + albedo from the nearest finest-level sample; packages of alpha-masked models
// (issue #14) put each sample's coverage in the vertex alpha of a MASK material (cut-off 1/2,
// double-sided), which is what the renderer does with it (interpolate, discard below 1/2). Departs from the renderer in the
// criterion (the renderer's default "error" weighs edges by how they face the camera; an export
// has no camera) and in having no per-frame view.
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

} // namespace

Result<ExportScene> export_scene(const Package& base, const Options& options)
{
    const auto& p = reps::package_cast<DisplacedMeshPackage>(base);
    const PatternLayout layout = p.layout();
    std::vector<FaceRefineData> faces =
        prepare_faces(p.positions, p.normals, p.indices, p.topology, layout, p.elevations, p.face_error);
    RefineSurface surface;
    surface.positions = &p.positions;
    surface.normals = &p.normals;
    surface.indices = &p.indices;
    surface.topology = &p.topology;
    surface.elevations = &p.elevations;
    surface.faces = &faces;
    surface.degree = p.settings.degree;

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
    RefineStats stats;
    std::vector<RefinedTriangle> triangles = refine(surface, view, refine_options, stats);

    ExportMesh mesh;
    mesh.name = "displaced_mesh";
    const int n = layout.segments;
    std::map<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>, std::uint32_t> welded;
    mesh.indices.reserve(triangles.size() * 3);
    for (const RefinedTriangle& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            glm::vec3 position = displaced_position(surface, t.face, t.q[k][0], t.q[k][1], view, refine_options);
            std::uint32_t bits[3];
            std::memcpy(bits, &position, sizeof bits);
            auto [it, inserted] = welded.try_emplace({bits[0], bits[1], bits[2]}, std::uint32_t(mesh.positions.size()));
            if (inserted) {
                // pattern vertex (i, j) has weights j / n on corner 1 and i / n on corner 2
                int i = int(std::lround(double(t.q[k][1]) * n / double(k_bary_one)));
                int j = int(std::lround(double(t.q[k][0]) * n / double(k_bary_one)));
                i = std::clamp(i, 0, n);
                j = std::clamp(j, 0, n - i);
                const int detail = p.settings.shading_detail;
                std::size_t sample = std::size_t(t.face) * p.shading_samples_per_face() + triangle_index(n * detail, i * detail, j * detail);
                std::uint32_t albedo = p.albedo[sample];
                mesh.positions.push_back(position);
                mesh.normals.push_back(decode_normal(p.shading_normals[sample]));
                const float alpha = p.coverage.empty() ? float(albedo >> 24) / 255.0f : float(p.coverage[sample]) / 255.0f;
                mesh.colors.push_back({export_srgb_to_linear(albedo), export_srgb_to_linear(albedo >> 8),
                                       export_srgb_to_linear(albedo >> 16), alpha});
            }
            mesh.indices.push_back(it->second);
        }
    }
    if (!p.coverage.empty()) {
        mesh.alpha_mode = "MASK";
        mesh.double_sided = true; // cut-out cards are seen from both sides, as the renderer draws them
    }
    mesh.extras["standin"] = {{"role", "mesh"},
                              {"tau", refine_options.tau},
                              {"pixels", pixels},
                              {"criterion", "weighted"},
                              {"control_faces", p.face_count()},
                              {"degree", p.settings.degree}};
    ExportScene scene;
    char line[200];
    std::snprintf(line, sizeof line, "displaced mesh refined to tau %g px at %d px: %zu triangles, %zu vertices (from %zu control faces)",
                  double(refine_options.tau), pixels, mesh.indices.size() / 3, mesh.positions.size(), p.face_count());
    scene.notes.push_back(line);
    scene.meshes.push_back(std::move(mesh));
    return scene;
}

} // namespace standin::displaced_mesh
