// Control faces drawn with the source's own base-colour texture (issue #14; a departure from
// Bauman, Livny & El-Sana, whose faces carry only sampled maps). Where a control face is one of the
// source's triangles, corner for corner — every leaf card (alpha-masked faces keep their vertices:
// ControlMeshOptions::keep_cutout_faces) and every face of a model kept whole — its displaced
// surface is that triangle, so the renderer can read the texture at the fragment's UV as the truth
// does: colour filtered by the same mip levels, the alpha test at the texture's own texels. The
// samples' colour and coverage (a few samples across a leaf) then serve only the other faces and
// `standin export`. source_textures.cpp has the matching.
#pragma once

#include <standin/mesh.h>

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace standin::displaced_mesh {

// A face's record, as the package stores it and the renderer's storage buffer holds it
// (docs/FORMAT.md "Source textures"): 48 bytes, little-endian.
struct FaceTexture {
    glm::vec2 uv[3]{};                // at the control face's corners, in its corner order
    std::uint32_t layer = 0xffffffffu; // k_no_texture, or the layer of SourceTextures::layers
    float cutoff = 0.0f;              // alpha_test_cutoff of the face's material: 0 tests nothing
    std::uint32_t color[3]{};         // Mesh::colors at the corners, RGBA8 (sRGB as stored)
    std::uint32_t reserved = 0;
};
static_assert(sizeof(FaceTexture) == 48, "the package's and the storage buffer's record");
constexpr std::uint32_t k_no_texture = 0xffffffffu;

struct SourceTextures {
    // the textures the matched faces use, one layer each, at their own sizes (the renderer
    // resamples them to the largest for its one texture array: gpu/source_texture.h)
    std::vector<Texture> layers;
    // one record per control face (layer k_no_texture where the face is not a source triangle or
    // has no texture), or empty when no face is matched
    std::vector<FaceTexture> faces;
    // the bake's, not stored: the source vertices at a matched face's corners, in its corner order
    // (its exact shading normals: bake.cpp exact_source_normals)
    std::vector<std::array<std::uint32_t, 3>> source_corners;

    std::size_t matched_faces() const;
};

// The records of control faces (`positions`, `indices`: positions are the source's welded ones,
// bit for bit) that are source triangles with a base-colour texture: alpha-masked ones always, the
// rest only when `every_face` (the control mesh kept every face). Deterministic: a control face
// that is several source triangles (duplicates) takes the first.
SourceTextures match_source_textures(const Mesh& mesh, const std::vector<glm::vec3>& positions,
                                     const std::vector<std::uint32_t>& indices, bool every_face);

} // namespace standin::displaced_mesh
