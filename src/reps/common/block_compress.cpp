// Block compression for packages: libsquish per 4x4 block, octahedral normals. See block_compress.h
// (sources cited there). Departure: masked texels (outside the coverage) are left out of a block's
// fit, as the renderers weight texels by coverage; libsquish's own CompressImage cannot mask.
#include "reps/common/block_compress.h"

#include <squish.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace standin::reps {

namespace {

int block_bytes(int flags) { return (flags & (squish::kDxt1 | squish::kBc4)) != 0 ? 8 : 16; }

// One BC4 block (the DXT5 alpha block layout) into channel `channel` of 16 RGBA texels. Debian's
// libsquish 1.15 compresses BC4/BC5 but does not decode them.
void decode_bc4(const std::uint8_t* block, std::uint8_t* rgba, int channel)
{
    const int a0 = block[0], a1 = block[1];
    int values[8] = {a0, a1};
    if (a0 > a1) {
        for (int k = 1; k < 7; ++k) values[k + 1] = ((7 - k) * a0 + k * a1 + 3) / 7;
    } else {
        for (int k = 1; k < 5; ++k) values[k + 1] = ((5 - k) * a0 + k * a1 + 2) / 5;
        values[6] = 0, values[7] = 255;
    }
    std::uint64_t bits = 0;
    for (int k = 0; k < 6; ++k) bits |= std::uint64_t(block[2 + k]) << (8 * k);
    for (int t = 0; t < 16; ++t) rgba[t * 4 + channel] = std::uint8_t(values[(bits >> (3 * t)) & 7]);
}

} // namespace

std::vector<std::uint8_t> compress_blocks(const std::uint8_t* rgba, int width, int height, const std::uint8_t* mask,
                                          int squish_flags)
{
    const int bw = (width + 3) / 4, bh = (height + 3) / 4, bytes = block_bytes(squish_flags);
    std::vector<std::uint8_t> out(std::size_t(bw) * std::size_t(bh) * std::size_t(bytes));
    tbb::parallel_for(0, bh, [&](int by) {
        for (int bx = 0; bx < bw; ++bx) {
            std::uint8_t texels[16 * 4] = {};
            int inside = 0, counted = 0;
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) {
                    const int x = bx * 4 + i, y = by * 4 + j, k = j * 4 + i;
                    if (x >= width || y >= height) continue;
                    const std::size_t at = std::size_t(y) * std::size_t(width) + std::size_t(x);
                    std::copy_n(rgba + at * 4, 4, texels + k * 4);
                    inside |= 1 << k;
                    if (!mask || mask[at]) counted |= 1 << k;
                }
            squish::CompressMasked(texels, counted ? counted : inside,
                                   out.data() + (std::size_t(by) * std::size_t(bw) + std::size_t(bx)) * std::size_t(bytes),
                                   squish_flags);
        }
    });
    return out;
}

std::vector<std::uint8_t> decompress_blocks(const std::uint8_t* blocks, int width, int height, int squish_flags)
{
    std::vector<std::uint8_t> rgba(std::size_t(width) * std::size_t(height) * 4);
    if ((squish_flags & (squish::kBc4 | squish::kBc5)) == 0) {
        squish::DecompressImage(rgba.data(), width, height, blocks, squish_flags);
        return rgba;
    }
    const int bw = (width + 3) / 4, bh = (height + 3) / 4, bytes = block_bytes(squish_flags);
    for (int by = 0; by < bh; ++by)
        for (int bx = 0; bx < bw; ++bx) {
            const std::uint8_t* block = blocks + (std::size_t(by) * std::size_t(bw) + std::size_t(bx)) * std::size_t(bytes);
            std::uint8_t texels[16 * 4] = {};
            for (int t = 0; t < 16; ++t) texels[t * 4 + 3] = 255;
            decode_bc4(block, texels, 0);
            if (bytes == 16) decode_bc4(block + 8, texels, 1);
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) {
                    const int x = bx * 4 + i, y = by * 4 + j;
                    if (x < width && y < height)
                        std::copy_n(texels + (j * 4 + i) * 4, 4, &rgba[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4]);
                }
        }
    return rgba;
}

glm::vec2 octahedral_encode(glm::vec3 n)
{
    const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(l1 > 0.0f)) return glm::vec2(0.5f, 0.5f);
    n /= l1;
    glm::vec2 e(n.x, n.y);
    if (n.z < 0.0f)
        e = glm::vec2((1.0f - std::abs(n.y)) * (n.x >= 0.0f ? 1.0f : -1.0f), (1.0f - std::abs(n.x)) * (n.y >= 0.0f ? 1.0f : -1.0f));
    return e * 0.5f + 0.5f;
}

glm::vec3 octahedral_decode(glm::vec2 e)
{
    const glm::vec2 f = e * 2.0f - 1.0f;
    glm::vec3 n(f.x, f.y, 1.0f - std::abs(f.x) - std::abs(f.y));
    const float t = std::max(-n.z, 0.0f);
    n.x += n.x >= 0.0f ? -t : t;
    n.y += n.y >= 0.0f ? -t : t;
    return glm::normalize(n);
}

std::vector<std::uint8_t> compress_octahedral_normals(int width, int height,
                                                      const std::function<bool(std::size_t, glm::vec3&)>& normal_at)
{
    const std::size_t texels = std::size_t(width) * std::size_t(height);
    std::vector<std::uint8_t> octahedral(texels * 4, 0), covered(texels, 0);
    for (std::size_t k = 0; k < texels; ++k) {
        glm::vec3 n(0.0f, 0.0f, 1.0f);
        covered[k] = normal_at(k, n) ? 1 : 0;
        glm::vec2 e = covered[k] ? octahedral_encode(n) : glm::vec2(0.5f);
        octahedral[k * 4 + 0] = std::uint8_t(std::lround(std::clamp(e.x, 0.0f, 1.0f) * 255.0f));
        octahedral[k * 4 + 1] = std::uint8_t(std::lround(std::clamp(e.y, 0.0f, 1.0f) * 255.0f));
    }
    return compress_blocks(octahedral.data(), width, height, covered.data(), squish::kBc5);
}

} // namespace standin::reps
