// Page preparation the view atlas's package codec and renderer share: pages premultiplied by
// coverage (Saraiva et al. §5: the seed's mip maps bled the background; filtering premultiplied
// texels and dividing by the filtered coverage does not), their box-filtered mip levels, and the
// DXT5 blocks of a colour page with its levels (what `--texture-format bc3` uploads and what a
// `--compression bc-color` package stores, so that loading it compresses nothing).
// Steps of color_page_blocks: premultiply by the page's own alpha (0 or 255, or the covered fraction for alpha-tested models); halve
// k_mip_levels - 1 times with a 2x2 box filter (as glGenerateMipmap does, so bc3 pages filter like
// rgba8 ones); compress every level with libsquish's cluster fit (reps/common/block_compress.h).
#include "reps/view_atlas/view_atlas.h"
#include "reps/common/block_compress.h"

#include <squish.h>

#include <algorithm>

namespace standin::view_atlas {

std::vector<std::uint8_t> premultiplied(const ImageRGBA8& page, const ImageRGBA8& coverage, bool keep_alpha, bool any)
{
    std::vector<std::uint8_t> out(page.pixels.size());
    for (std::size_t p = 0; p < out.size(); p += 4) {
        unsigned a = coverage.pixels[p + 3];
        if (any && a != 0) a = 255;
        for (int c = 0; c < 3; ++c) out[p + c] = std::uint8_t((page.pixels[p + c] * a + 127) / 255);
        out[p + 3] = keep_alpha ? page.pixels[p + 3] : std::uint8_t((page.pixels[p + 3] * a + 127) / 255);
    }
    return out;
}

std::vector<std::uint16_t> premultiplied16(const ImageRGBA8& normal_depth, const std::vector<std::uint16_t>& depth,
                                           const ImageRGBA8& coverage, bool any)
{
    std::vector<std::uint16_t> out(normal_depth.pixels.size());
    for (std::size_t p = 0; p < out.size(); p += 4) {
        unsigned a = coverage.pixels[p + 3];
        if (any && a != 0) a = 255;
        for (int c = 0; c < 3; ++c) out[p + c] = std::uint16_t((normal_depth.pixels[p + c] * 257u * a + 127u) / 255u);
        out[p + 3] = std::uint16_t((unsigned(depth[p / 4]) * a + 127u) / 255u);
    }
    return out;
}

std::vector<std::uint8_t> half_level(const std::vector<std::uint8_t>& level, int size)
{
    const int half = std::max(size / 2, 1);
    std::vector<std::uint8_t> out(std::size_t(half) * half * 4);
    for (int y = 0; y < half; ++y)
        for (int x = 0; x < half; ++x)
            for (int c = 0; c < 4; ++c) {
                auto at = [&](int dx, int dy) {
                    return unsigned(level[(std::size_t(std::min(2 * y + dy, size - 1)) * size + std::min(2 * x + dx, size - 1)) * 4 + c]);
                };
                out[(std::size_t(y) * half + x) * 4 + c] = std::uint8_t((at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1) + 2) / 4);
            }
    return out;
}

std::vector<std::vector<std::uint8_t>> color_page_blocks(const ImageRGBA8& page)
{
    std::vector<std::vector<std::uint8_t>> levels;
    std::vector<std::uint8_t> level = premultiplied(page, page, true);
    int size = page.width;
    for (int m = 0; m < k_mip_levels; ++m) {
        if (m > 0) {
            level = half_level(level, size);
            size = std::max(size / 2, 1);
        }
        levels.push_back(reps::compress_blocks(level.data(), size, size, nullptr, squish::kDxt5 | squish::kColourClusterFit));
    }
    return levels;
}

} // namespace standin::view_atlas
