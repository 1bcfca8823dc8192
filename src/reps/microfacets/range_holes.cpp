// Range-image hole filling, Yamazaki et al. 2002 §5.1: "the value of the pixel is replaced by the
// median of the values of the nonhole pixels within the window if the modified pixel is detected as
// a hole ... we also count the number of holes in a window, and fill the hole if the number is less
// than a certain threshold. In our experiments, we use a 3 x 3 pixel window and the threshold is set
// to 5 pixels."
// Choices the paper leaves open (docs/ARCHITECTURE.md, "Microfacets"): the centre counts as one of
// the window's holes; the lower median of an even count (a value that exists, no new depths between
// two surfaces); Jacobi passes until nothing changes, at most max_iterations; in standin a pixel may
// be filled only where the colour image saw the surface (the photograph's matte), so the filter
// never grows the object into the background.
// Steps per pass: for each fillable hole, gather the valid depths of its window and count its
// holes; below the threshold, take the median; then apply every fill of the pass at once.
#include "reps/microfacets/range_holes.h"

#include <algorithm>
#include <cassert>

namespace standin::microfacets {

std::size_t fill_range_holes(RangeImage& image, const std::vector<std::uint8_t>& fillable, const HoleFilter& filter)
{
    const int w = image.width, h = image.height;
    assert(image.depth.size() == std::size_t(w) * h && image.valid.size() == image.depth.size());
    assert(fillable.empty() || fillable.size() == image.depth.size());
    std::size_t filled_total = 0;
    struct Fill {
        std::size_t pixel;
        float depth;
    };
    std::vector<Fill> fills;
    for (int pass = 0; pass < filter.max_iterations; ++pass) {
        fills.clear();
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                std::size_t p = std::size_t(y) * w + x;
                if (image.valid[p] || (!fillable.empty() && !fillable[p])) continue;
                float values[9];
                int count = 0, holes = 0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= w || ny >= h) {
                            ++holes;
                            continue;
                        }
                        std::size_t q = std::size_t(ny) * w + nx;
                        if (image.valid[q]) values[count++] = image.depth[q];
                        else ++holes;
                    }
                if (holes >= filter.threshold || count == 0) continue;
                std::nth_element(values, values + (count - 1) / 2, values + count);
                fills.push_back({p, values[(count - 1) / 2]});
            }
        if (fills.empty()) break;
        for (const Fill& f : fills) {
            image.depth[f.pixel] = f.depth;
            image.valid[f.pixel] = 1;
        }
        filled_total += fills.size();
    }
    return filled_total;
}

} // namespace standin::microfacets
