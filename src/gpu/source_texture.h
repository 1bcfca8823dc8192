// A model's own texture on the GPU as the ground truth draws it (src/reference/mesh_renderer.cpp
// says why its levels are what they are), for every renderer that reads source textures: the
// truth, and the displaced mesh's faces that are source triangles.
#pragma once

#include "gpu/gl.h"

#include <standin/mesh.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace standin::gpu {

// A texture with every mip level: coverage-weighted where any alpha is under 255 (each level's
// colour the alpha-weighted mean of the finer texels', alpha their plain mean, empty texels the
// colour of their covered neighbours), the GL's own (glGenerateTextureMipmap) otherwise;
// trilinear, repeating.
Texture upload_source_texture(const standin::Texture& texture);

// Textures as the layers of one 2D array texture of the largest width and height among them, each
// with the levels upload_source_texture gives it; the same sampling. A smaller one whose size
// divides the array's is repeated across its layer when `uv_scale` is given (its UVs are then to be
// multiplied by (*uv_scale)[k], the layer's size over the array's: the same texels and mip levels as
// its own texture, which power-of-two textures keep to the last level); any other is resampled
// bilinearly, wrapping, to the array's size (the same image, not the same texels: assimp's spider,
// textures of 249, 250, 768 and 128 texels, drew Luv 0.6 against the truth when all were; in
// arrays by size, below, 0.035).
Texture upload_source_texture_array(const std::vector<standin::Texture>& layers, std::vector<glm::vec2>* uv_scale = nullptr);

// Which of at most `max_arrays` arrays each texture goes to, so that each keeps its own texels where
// it can: sizes from the largest area down, each joining the first array whose first size it
// divides (repeated there), else opening a new array while there are fewer than `max_arrays`, else
// joining array 0 (resampled). A model whose texture sizes divide each other (powers of two) gets
// one array. Deterministic.
std::vector<std::uint32_t> source_texture_array_of(const std::vector<standin::Texture>& textures, int max_arrays);

// The textures uploaded as those arrays (upload_source_texture_array each): texture k is layer
// layer_of[k] of arrays[array_of[k]], its UVs to be multiplied by uv_scale[k].
struct SourceTextureArrays {
    std::vector<Texture> arrays;
    std::vector<std::uint32_t> array_of, layer_of;
    std::vector<glm::vec2> uv_scale;
};
SourceTextureArrays upload_source_texture_arrays(const std::vector<standin::Texture>& textures, int max_arrays);

} // namespace standin::gpu
