// Export of enhanced billboards (docs/FORMAT.md, "Export: enhanced billboards"): each billboard's
// box (Vichitvejpaisal 2005 §3.1: the front plane swept over its depth range) as a mesh whose UVs
// project every corner onto the front plane, with its colour + coverage map as base colour and its
// 16-bit normal + depth map referenced from the node's extras for a height-field shader; plus the
// coarse hole-filling mesh (§3.4) as a vertex-coloured mesh. A plain viewer then shows each
// billboard's image on its front face, alpha-masked; a shader ray-marches the box with the maps.
// Departure: both maps are padded to multiples of 4 texels (uncovered texels, zero normal and
// depth, after the last column and row; the UVs reach only the billboard's own texels), because
// KHR_texture_basisu needs block-aligned sizes (examples/web/tools/ktx2.mjs): texel (i, j) stays
// texel (i, j), and `width`, `height` in the extras stay the billboard's.
#include "reps/enhanced_billboards/billboards.h"
#include "reps/common/package_cast.h"

#include <standin/export.h>

#include <algorithm>
#include <cstdio>

namespace standin::billboards {

namespace {

nlohmann::json billboard_vec3(glm::vec3 v) { return {v.x, v.y, v.z}; }

// Maps are padded to this many texels (a Basis / KTX2 block).
constexpr int k_billboard_map_alignment = 4;

int billboard_map_extent(int texels) { return (texels + k_billboard_map_alignment - 1) / k_billboard_map_alignment * k_billboard_map_alignment; }

// `image` grown to billboard_map_extent of its sides, the new texels zero (uncovered)
template <class Image> Image billboard_padded_map(const Image& image)
{
    Image out(billboard_map_extent(image.width), billboard_map_extent(image.height));
    for (int y = 0; y < image.height; ++y)
        std::copy(image.at(0, y), image.at(0, y) + std::size_t(image.width) * 4, out.at(0, y));
    return out;
}

// The six faces of the box as quads of corner indices (bit 0: +u, bit 1: +v, bit 2: +depth).
constexpr int k_box_faces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};

ExportMesh billboard_box(const Billboard& b, const std::string& name)
{
    const float w = float(b.width) * b.texel_size, h = float(b.height) * b.texel_size, d = b.depth_range;
    glm::vec3 corner[8];
    for (int k = 0; k < 8; ++k)
        corner[k] = b.origin + float(k & 1) * w * b.axis_u + float((k >> 1) & 1) * h * b.axis_v + float((k >> 2) & 1) * d * b.direction;
    const glm::vec3 centre = b.origin + 0.5f * (w * b.axis_u + h * b.axis_v + d * b.direction);
    // the billboard's texels are the top-left width x height of the padded maps
    const glm::vec2 uv_extent{float(b.width) / float(billboard_map_extent(b.width)), float(b.height) / float(billboard_map_extent(b.height))};
    ExportMesh mesh;
    mesh.name = name;
    for (const auto& face : k_box_faces) {
        glm::vec3 p[4];
        for (int k = 0; k < 4; ++k) p[k] = corner[face[k]];
        glm::vec3 outward = 0.25f * (p[0] + p[1] + p[2] + p[3]) - centre;
        glm::vec3 normal = glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
        bool flip = glm::dot(normal, outward) < 0.0f;
        if (flip) normal = -normal;
        auto base = std::uint32_t(mesh.positions.size());
        for (int k = 0; k < 4; ++k) {
            mesh.positions.push_back(p[k]);
            mesh.normals.push_back(normal);
            mesh.uvs.push_back(uv_extent * glm::vec2(float(face[k] & 1), float((face[k] >> 1) & 1)));
        }
        if (flip) mesh.indices.insert(mesh.indices.end(), {base, base + 2, base + 1, base, base + 3, base + 2});
        else mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
    }
    mesh.alpha_mode = "MASK";
    return mesh;
}

// A PBR package's maps (issue #14) as the box's glTF material reads them: the ORM map (occlusion,
// roughness, metallic; its alpha, the coverage, unread) and the sRGB emission, padded as the colour.
// Packages without them keep the default material, a rough dielectric without emission.
Status add_pbr_maps(ExportScene& scene, ExportMesh& box, const Billboard& b, const std::string& name)
{
    int orm_texture = -1, emissive_texture = -1;
    if (!b.orm.empty()) {
        Result<ExportTexture> orm = make_export_texture(name + "_orm", billboard_padded_map(b.orm));
        if (!orm) return orm.status();
        orm_texture = int(scene.textures.size());
        scene.textures.push_back(std::move(*orm));
    }
    if (!b.emission.empty()) {
        Result<ExportTexture> emission = make_export_texture(name + "_emission", billboard_padded_map(b.emission));
        if (!emission) return emission.status();
        emissive_texture = int(scene.textures.size());
        scene.textures.push_back(std::move(*emission));
    }
    use_pbr_maps(box, orm_texture, emissive_texture);
    return Status::ok();
}

} // namespace

Result<ExportScene> export_scene(const Package& base, const Options&)
{
    const auto& package = reps::package_cast<EnhancedBillboardsPackage>(base);
    ExportScene scene;
    for (std::size_t k = 0; k < package.billboards.size(); ++k) {
        const Billboard& b = package.billboards[k];
        if (b.width <= 0 || b.height <= 0) continue;
        std::string name = "billboard_" + std::to_string(k);
        Result<ExportTexture> color = make_export_texture(name + "_color", billboard_padded_map(b.color));
        if (!color) return color.status();
        Result<ExportTexture> normal_depth = make_export_texture(name + "_normal_depth", billboard_padded_map(b.normal_depth));
        if (!normal_depth) return normal_depth.status();
        const int color_index = int(scene.textures.size());
        scene.textures.push_back(std::move(*color));
        scene.textures.push_back(std::move(*normal_depth));
        ExportMesh box = billboard_box(b, name);
        box.base_color_texture = color_index;
        STANDIN_RETURN_IF_ERROR(add_pbr_maps(scene, box, b, name));
        box.extras["standin"] = {{"role", "billboard"},
                                 {"color_texture", color_index},
                                 {"normal_depth_texture", color_index + 1},
                                 {"origin", billboard_vec3(b.origin)},
                                 {"axis_u", billboard_vec3(b.axis_u)},
                                 {"axis_v", billboard_vec3(b.axis_v)},
                                 {"direction", billboard_vec3(b.direction)},
                                 {"texel_size", b.texel_size},
                                 {"depth_range", b.depth_range},
                                 {"width", b.width},
                                 {"height", b.height}};
        scene.meshes.push_back(std::move(box));
    }
    if (!package.coarse_mesh.indices.empty()) {
        ExportMesh coarse = export_vertex_colored_mesh(package.coarse_mesh, "coarse_mesh");
        coarse.extras["standin"] = {{"role", "coarse-mesh"}};
        scene.meshes.push_back(std::move(coarse));
    }
    std::uint64_t texture_bytes = 0;
    for (const ExportTexture& t : scene.textures) texture_bytes += export_texture_bytes(t);
    char line[200];
    const bool pbr = !package.billboards.empty() && !package.billboards[0].orm.empty();
    std::snprintf(line, sizeof line, "%zu billboard boxes with colour + coverage (8-bit)%s and normal + depth (16-bit) maps%s: %.1f MiB of textures on the GPU",
                  package.billboards.size(), pbr ? ", ORM, emission" : "", package.coarse_mesh.indices.empty() ? "" : ", coarse mesh",
                  double(texture_bytes) / (1 << 20));
    scene.notes.push_back(line);
    return scene;
}

} // namespace standin::billboards
