// The grid atlas of today's impostor shaders (Unreal's Impostor Baker by Ryan Brucks, 2018; Amplify
// Impostors; Godot's octahedral impostors): frames x frames views of a (hemi-)octahedral layout,
// each uncropped into its square cell of one colour + alpha image and one normal + depth image.
// docs/FORMAT.md ("Grid atlas") documents the frame -> direction mapping and the encodings.
#pragma once

#include "reps/common/view_layout.h"

#include <standin/image.h>
#include <standin/status.h>

#include <vector>

namespace standin::reps {

// What the views were captured at and are stored in.
struct GridAtlasInput {
    const std::vector<View>* views = nullptr;              // frames * frames, layout order
    const std::vector<ImageRGBA8>* color_pages = nullptr;  // RGB sRGB albedo, A covered fraction (0..255)
    const std::vector<ImageRGBA8>* normal_depth_pages = nullptr; // may be null: colour only
    int resolution = 0; // capture size, pixels
    int frames = 0;
    // the colour pages' RGB is sRGB-encoded (albedo, emission), averaged in linear light; false:
    // linear data (ORM pages: occlusion, roughness, metallic), averaged as it is
    bool color_srgb = true;
};

struct GridAtlas {
    ImageRGBA8 color;        // RGB sRGB, A coverage fraction
    ImageRGBA8 normal_depth; // empty when the input has no normal + depth
};

// Resamples every view into its cell: atlas texel (x, y) lies in frame (i, j) = floor((x, y) *
// frames / size) and shows capture point (x, y) * frames / size - (i, j) (in [0, 1]^2) times the
// resolution; a box filter over the capture pixels under the texel (colour averaged in linear light
// weighted by coverage, the mean coverage as alpha, at least 1/255 where any pixel has some;
// normals averaged and renormalised, depth averaged, over the pixels with coverage). At size =
// frames x resolution the box is one pixel: the captures' texels, coverage and depth as stored.
// Empty texels take the colour and normal of covered neighbours in their cell (a few texels of
// dilation, so that bilinear filtering and mips do not darken silhouettes); their alpha stays 0 and
// their depth is 1. Deterministic.
Result<GridAtlas> make_grid_atlas(const GridAtlasInput& input, int size);

} // namespace standin::reps
