// A model's own texture on the GPU as the ground truth draws it (src/reference/mesh_renderer.cpp
// says why its levels are what they are), for every renderer that reads source textures: the
// truth, and the displaced mesh's faces that are source triangles.
#pragma once

#include "gpu/gl.h"

#include <standin/mesh.h>

#include <vector>

namespace standin::gpu {

// A texture with every mip level: coverage-weighted where any alpha is under 255 (each level's
// colour the alpha-weighted mean of the finer texels', alpha their plain mean, empty texels the
// colour of their covered neighbours), the GL's own (glGenerateTextureMipmap) otherwise;
// trilinear, repeating.
Texture upload_source_texture(const standin::Texture& texture);

// Textures as the layers of one 2D array texture of the largest width and height among them
// (a smaller one resampled bilinearly, wrapping, to it: what reads it by UV sees the same image),
// each with the levels upload_source_texture gives it; the same sampling.
Texture upload_source_texture_array(const std::vector<standin::Texture>& layers);

} // namespace standin::gpu
