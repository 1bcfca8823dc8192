// The coarse mesh (coarse_mesh.h). Vichitvejpaisal 2005 §3.4 asks for "usually 10 times fewer
// polygons" than the model; how is not said: we simplify with meshoptimizer (Garland & Heckbert's
// quadric error metric).
#include "reps/common/coarse_mesh.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <vector>

namespace standin::reps {

namespace {

// A texture's mean colour over its texels weighted by alpha (white when it has no alpha at all).
glm::vec4 covered_mean(const Texture& texture)
{
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (std::size_t i = 0; i + 3 < texture.rgba.size(); i += 4) {
        double a = texture.rgba[i + 3] / 255.0;
        sum += a * glm::dvec3(texture.rgba[i], texture.rgba[i + 1], texture.rgba[i + 2]) / 255.0;
        weight += a;
    }
    return weight > 0.0 ? glm::vec4(glm::vec3(sum / weight), 1.0f) : glm::vec4(1.0f);
}

// The albedo of a source corner. An alpha-tested face's corners (a leaf card's) usually lie in its
// texture's cut-out, whose colour is arbitrary (black in most files): such a corner takes the vertex
// colour times the texture's mean over its covered texels instead (issue #14: the coarse mesh fills
// holes inside a crown, and black corners made those fills black).
glm::vec4 corner_albedo(const Mesh& mesh, std::uint32_t face, std::uint32_t slot, const std::vector<glm::vec4>& covered_colors)
{
    float b1 = slot == 1 ? 1.0f : 0.0f, b2 = slot == 2 ? 1.0f : 0.0f;
    const Material& material = mesh.materials[mesh.face_materials[face]];
    if (alpha_test_cutoff(material) <= 0.0f || material.base_color_texture < 0 || !mesh.has_texture_coordinates() ||
        mesh.covered_at(face, b1, b2))
        return mesh.albedo_at(face, b1, b2);
    glm::vec4 color = mesh.colors[mesh.indices[std::size_t(face) * 3 + slot]];
    return glm::vec4(glm::vec3(color) * glm::vec3(covered_colors[std::size_t(material.base_color_texture)]), color.w);
}

} // namespace

Mesh make_coarse_mesh(const Mesh& mesh, float ratio)
{
    Mesh coarse;
    if (ratio <= 0.0f) return coarse;
    std::size_t index_count = mesh.indices.size();
    std::vector<std::uint32_t> welded(index_count), simplified(index_count);
    meshopt_generateShadowIndexBuffer(welded.data(), mesh.indices.data(), index_count, mesh.positions.data(),
                                      mesh.vertex_count(), sizeof(glm::vec3), sizeof(glm::vec3));
    std::size_t triangles = index_count / 3;
    std::size_t target_triangles = std::max(std::size_t(double(triangles) * ratio), std::min(triangles, k_min_coarse_triangles));
    std::size_t target = std::max<std::size_t>(1, target_triangles) * 3;
    const float* positions = &mesh.positions[0].x;
    std::size_t count = meshopt_simplify(simplified.data(), welded.data(), index_count, positions, mesh.vertex_count(),
                                         sizeof(glm::vec3), target, 1.0f, 0, nullptr);
    if (count > target * 2)
        count = meshopt_simplifySloppy(simplified.data(), welded.data(), index_count, positions, mesh.vertex_count(),
                                       sizeof(glm::vec3), target, 1.0f, nullptr);
    simplified.resize(count);

    // compact the vertices, in order of first use; colour = albedo of the source vertex
    std::vector<glm::vec4> covered_colors;
    covered_colors.reserve(mesh.textures.size());
    for (const Texture& texture : mesh.textures) covered_colors.push_back(covered_mean(texture));
    std::vector<std::uint32_t> remap(mesh.vertex_count(), 0xffffffffu);
    std::vector<std::uint32_t> corner_face(mesh.vertex_count(), 0), corner_slot(mesh.vertex_count(), 0);
    for (std::size_t i = 0; i < index_count; ++i) corner_face[welded[i]] = std::uint32_t(i / 3), corner_slot[welded[i]] = std::uint32_t(i % 3);
    for (std::uint32_t& index : simplified) {
        if (remap[index] == 0xffffffffu) {
            remap[index] = std::uint32_t(coarse.positions.size());
            coarse.positions.push_back(mesh.positions[index]);
            // the welded vertex is one of the source corners at this position; take its albedo
            std::uint32_t face = corner_face[index], slot = corner_slot[index];
            coarse.colors.push_back(corner_albedo(mesh, face, slot, covered_colors));
        }
        index = remap[index];
    }
    coarse.indices = std::move(simplified);
    coarse.face_materials.assign(coarse.triangle_count(), 0);
    coarse.materials.push_back(Material{"coarse", glm::vec4(1.0f), -1});
    compute_smooth_normals(coarse);
    return coarse;
}

} // namespace standin::reps
