// Grid atlas resampling (grid_atlas.h). The layout is the one of Ryan Brucks's Impostor Baker for
// Unreal (2018) and Amplify Impostors: frame (i, j) of an N x N grid over the octahedral map, the
// whole view in its cell. Steps: per atlas texel, its frame and the capture pixels under it (an
// s x s box, s = ceil(resolution / cell) up to 8); colour averaged in linear light weighted by the
// pixels' coverage, alpha = their mean coverage (the captures' covered fraction, issue #14: 0..1
// per pixel for alpha-tested models, kept rather than thresholded at 1/2, so that a reader filtering
// it finds a cut-out's edge inside texels, issue #16); normals and depth averaged over the pixels
// with any coverage; then a few passes of dilation inside each cell. Departs from the bakers in the source of the images only: ours are the view
// atlas's stored crops (packed, cropped to content), put back uncropped.
#include "reps/common/grid_atlas.h"

#include <glm/glm.hpp>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>

namespace standin::reps {

namespace {

constexpr int k_grid_dilation_passes = 8;
constexpr int k_grid_max_box = 8;

const std::array<float, 256>& grid_srgb_to_linear_table()
{
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int k = 0; k < 256; ++k) {
            t[std::size_t(k)] = srgb_to_linear(float(k) / 255.0f);
        }
        return t;
    }();
    return table;
}

// the identity on unorm8 codes, for linear data (GridAtlasInput::color_srgb false)
const std::array<float, 256>& grid_unorm_table()
{
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int k = 0; k < 256; ++k) t[std::size_t(k)] = float(k) / 255.0f;
        return t;
    }();
    return table;
}

std::uint8_t grid_linear_to_srgb8(float c)
{
    return std::uint8_t(std::lround(linear_to_srgb(std::clamp(c, 0.0f, 1.0f)) * 255.0f));
}

std::uint8_t grid_unorm8(float v) { return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); }

// Fills empty texels (mask 0) from the filled ones around them, pass by pass, never across cells.
void grid_dilate(ImageRGBA8& image, std::vector<std::uint8_t>& filled, int frames, bool keep_alpha_channel)
{
    const int size = image.width;
    auto cell = [&](int x) { return std::min(frames - 1, int((std::int64_t(x) * 2 + 1) * frames / (2 * std::int64_t(size)))); };
    std::vector<int> cell_of(static_cast<std::size_t>(size));
    for (int x = 0; x < size; ++x) cell_of[std::size_t(x)] = cell(x);
    for (int pass = 0; pass < k_grid_dilation_passes; ++pass) {
        ImageRGBA8 before = image;
        std::vector<std::uint8_t> was = filled;
        std::atomic<bool> changed = false;
        // rows are independent within a pass (reads from the previous pass only): deterministic
        tbb::parallel_for(0, size, [&](int y) {
            for (int x = 0; x < size; ++x) {
                if (was[std::size_t(y) * size + x]) continue;
                int sum[3] = {0, 0, 0}, count = 0;
                for (int dy = -1; dy <= 1; ++dy) {
                    for (int dx = -1; dx <= 1; ++dx) {
                        int nx = x + dx, ny = y + dy;
                        if (nx < 0 || ny < 0 || nx >= size || ny >= size) continue;
                        if (cell_of[std::size_t(nx)] != cell_of[std::size_t(x)] || cell_of[std::size_t(ny)] != cell_of[std::size_t(y)]) continue;
                        if (!was[std::size_t(ny) * size + nx]) continue;
                        const std::uint8_t* p = before.at(nx, ny);
                        for (int c = 0; c < 3; ++c) sum[c] += p[c];
                        ++count;
                    }
                }
                if (count == 0) continue;
                std::uint8_t* out = image.at(x, y);
                for (int c = 0; c < 3; ++c) out[c] = std::uint8_t((sum[c] + count / 2) / count);
                if (!keep_alpha_channel) out[3] = 0;
                filled[std::size_t(y) * size + x] = 1;
                changed = true;
            }
        });
        if (!changed) break;
    }
}

} // namespace

Result<GridAtlas> make_grid_atlas(const GridAtlasInput& in, int size)
{
    const int frames = in.frames;
    if (!in.views || !in.color_pages || frames <= 0 || in.views->size() != std::size_t(frames) * std::size_t(frames))
        return error(StatusCode::invalid_argument, "grid atlas: the views are not a frames x frames grid");
    if (size < frames) return error(StatusCode::invalid_argument, "--atlas-size: must hold one texel per frame at least");
    const bool with_normals = in.normal_depth_pages && !in.normal_depth_pages->empty();
    const auto& to_linear = in.color_srgb ? grid_srgb_to_linear_table() : grid_unorm_table();
    GridAtlas atlas;
    atlas.color = ImageRGBA8(size, size);
    if (with_normals) atlas.normal_depth = ImageRGBA8(size, size);
    std::vector<std::uint8_t> filled(std::size_t(size) * size, 0);

    // texel footprint in capture pixels, and the box that samples it
    const double capture_per_texel = double(in.resolution) * frames / size;
    const int box = std::clamp(int(std::ceil(capture_per_texel - 1e-9)), 1, k_grid_max_box);
    const int res = in.resolution;
    // capture coordinate of sub-sample a of texel x: frame index and pixel
    auto locate = [&](int x, int a, int& frame, int& pixel) {
        double centre = (double(x) + 0.5) * frames / size;
        frame = std::min(frames - 1, int(std::floor(centre)));
        double t = (double(x) + (double(a) + 0.5) / box) * frames / size - frame;
        pixel = std::clamp(int(std::floor(t * res)), 0, res - 1);
    };
    // every texel reads the pages and writes only itself: rows in parallel, deterministic
    tbb::parallel_for(0, size, [&](int y) {
        for (int x = 0; x < size; ++x) {
            float rgb[3] = {0, 0, 0}, depth = 0.0f, coverage = 0.0f;
            glm::vec3 normal(0.0f);
            int covered = 0, i = 0, j = 0;
            for (int b = 0; b < box; ++b) {
                int py = 0;
                locate(y, b, j, py);
                for (int a = 0; a < box; ++a) {
                    int px = 0;
                    locate(x, a, i, px);
                    const View& v = (*in.views)[std::size_t(j) * frames + i];
                    if (v.width == 0 || px < v.crop_x || py < v.crop_y || px >= v.crop_x + v.width || py >= v.crop_y + v.height)
                        continue;
                    int tx = v.atlas_x + px - v.crop_x, ty = v.atlas_y + py - v.crop_y;
                    const std::uint8_t* c = (*in.color_pages)[std::size_t(v.page)].at(tx, ty);
                    if (c[3] == 0) continue;
                    const float pixel_coverage = float(c[3]) / 255.0f;
                    for (int k = 0; k < 3; ++k) rgb[k] += pixel_coverage * to_linear[c[k]];
                    coverage += pixel_coverage;
                    if (with_normals) {
                        const std::uint8_t* n = (*in.normal_depth_pages)[std::size_t(v.page)].at(tx, ty);
                        normal += glm::vec3(n[0], n[1], n[2]) / 255.0f * 2.0f - 1.0f;
                        depth += float(n[3]) / 255.0f;
                    }
                    ++covered;
                }
            }
            std::uint8_t* out = atlas.color.at(x, y);
            if (covered == 0) {
                if (with_normals) {
                    std::uint8_t* nd = atlas.normal_depth.at(x, y);
                    nd[0] = nd[1] = nd[2] = 128;
                    nd[3] = 255;
                }
                continue;
            }
            filled[std::size_t(y) * size + x] = 1;
            for (int k = 0; k < 3; ++k) out[k] = in.color_srgb ? grid_linear_to_srgb8(rgb[k] / coverage) : grid_unorm8(rgb[k] / coverage);
            // at least 1: a texel with a surface in it has alpha > 0 (readers walk it as covered)
            out[3] = std::uint8_t(std::clamp(std::lround(coverage * 255.0f / float(box * box)), 1L, 255L));
            if (with_normals) {
                float length = glm::length(normal);
                glm::vec3 n = length > 1e-6f ? normal / length : glm::vec3(0.0f);
                std::uint8_t* nd = atlas.normal_depth.at(x, y);
                for (int k = 0; k < 3; ++k) nd[k] = grid_unorm8(n[k] * 0.5f + 0.5f);
                nd[3] = grid_unorm8(depth / float(covered));
            }
        }
    });
    if (with_normals) {
        std::vector<std::uint8_t> mask = filled;
        grid_dilate(atlas.normal_depth, mask, frames, true);
    }
    grid_dilate(atlas.color, filled, frames, false);
    return atlas;
}

} // namespace standin::reps
