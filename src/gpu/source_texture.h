// A model's own texture on the GPU as the ground truth draws it (src/reference/mesh_renderer.cpp
// says why its levels are what they are), for every renderer that reads source textures: the
// truth, and the displaced mesh's faces that are source triangles.
#pragma once

#include "gpu/gl.h"

#include <standin/mesh.h>

#include <cstdint>
#include <vector>

namespace standin::gpu {

// The next coverage-weighted mip level of an RGBA8 image (w x h): each texel the 2 x 2 (1 x 2 or
// 2 x 1 along a side of size 1) block under it; colour weighted by alpha, alpha the plain mean. A
// block with no coverage takes its covered neighbours' colour.
std::vector<std::uint8_t> coverage_weighted_level(const std::vector<std::uint8_t>& fine, int w, int h);

// A texture with every mip level: coverage-weighted where any alpha is under 255, the GL's own
// (glGenerateTextureMipmap) otherwise; trilinear, repeating.
Texture upload_source_texture(const standin::Texture& texture);

// Textures as the layers of one 2D array texture of the largest width and height among them
// (a smaller one resampled bilinearly, wrapping, to it: what reads it by UV sees the same image),
// each with the levels upload_source_texture gives it; the same sampling.
Texture upload_source_texture_array(const std::vector<standin::Texture>& layers);

} // namespace standin::gpu
