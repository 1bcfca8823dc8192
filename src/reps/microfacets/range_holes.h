// Hole filling of range images (Yamazaki et al. 2002 §5.1, Fig. 9). Only matters when the voxels
// and range images come from a worse mesh than the colour (the bake's `geometry-from` experiment):
// a hole in a range image would delete texture through the clipping rule (eq. 1).
#pragma once

#include <cstdint>
#include <vector>

namespace standin::microfacets {

struct HoleFilter {
    int threshold = 5;       // fill a hole only when its 3x3 window holds fewer holes than this
    int max_iterations = 16; // the paper iterates "until" without a count: until nothing changes, capped
};

// A range image: depth per pixel and whether the pixel has one. Pixels outside the image count as
// holes.
struct RangeImage {
    int width = 0, height = 0;
    std::vector<float> depth;         // width * height, row-major
    std::vector<std::uint8_t> valid;  // 1 where depth holds a value
};

// The paper's "morphological filter", a masked median: every hole pixel that may be filled
// (`fillable`, width * height; empty: every pixel) whose 3 x 3 window (centre included) holds fewer
// than `threshold` holes gets the median of the window's valid depths (the lower median of an even
// count). Passes read the previous pass's image (the result does not depend on the pixel order)
// and repeat until one fills nothing or max_iterations passes ran. Returns the pixels filled.
std::size_t fill_range_holes(RangeImage& image, const std::vector<std::uint8_t>& fillable, const HoleFilter& filter = {});

} // namespace standin::microfacets
