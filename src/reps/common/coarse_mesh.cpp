// The coarse mesh (coarse_mesh.h). Vichitvejpaisal 2005 §3.4 asks for "usually 10 times fewer
// polygons" than the model; how is not said: we simplify with meshoptimizer (Garland & Heckbert's
// quadric error metric).
#include "reps/common/coarse_mesh.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <vector>

namespace standin::reps {

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
    std::vector<std::uint32_t> remap(mesh.vertex_count(), 0xffffffffu);
    std::vector<std::uint32_t> corner_face(mesh.vertex_count(), 0), corner_slot(mesh.vertex_count(), 0);
    for (std::size_t i = 0; i < index_count; ++i) corner_face[welded[i]] = std::uint32_t(i / 3), corner_slot[welded[i]] = std::uint32_t(i % 3);
    for (std::uint32_t& index : simplified) {
        if (remap[index] == 0xffffffffu) {
            remap[index] = std::uint32_t(coarse.positions.size());
            coarse.positions.push_back(mesh.positions[index]);
            // the welded vertex is one of the source corners at this position; take its albedo
            std::uint32_t face = corner_face[index], slot = corner_slot[index];
            coarse.colors.push_back(mesh.albedo_at(face, slot == 1 ? 1.0f : 0.0f, slot == 2 ? 1.0f : 0.0f));
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
