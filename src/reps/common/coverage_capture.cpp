// Supersampled captures of alpha-tested models box-filtered to fractional coverage (issue #14;
// coverage_capture.h). Moved from the view atlas's bake, where it was first measured
// (docs/RESULTS.md "Fractional coverage in the view atlas"), to be shared with microfacets.
// Steps per texel: count the covered samples of its f x f block; alpha = that fraction, rounded, at
// least 1 when any is covered; the other channels = the covered samples' mean; depth = the block's
// nearest covered sample's (a separate geometry capture's depth may be 1 there: the minimum skips it
// where another covered sample has one). With a front tolerance, samples farther than it behind the
// nearest are left out as if empty: the texel is its front surface's, whose coverage, colour and
// normal it then holds unmixed.
#include "reps/common/coverage_capture.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace standin::reps {

bool has_cutouts(const Mesh& mesh)
{
    return std::any_of(mesh.materials.begin(), mesh.materials.end(), [](const Material& m) { return alpha_test_cutoff(m) > 0.0f; });
}

int coverage_samples(const Mesh& mesh, int resolution, int preferred, const char* override_variable)
{
    if (!has_cutouts(mesh)) return 1;
    int samples = preferred;
    if (const char* text = override_variable ? std::getenv(override_variable) : nullptr) {
        int n = std::atoi(text);
        if (n >= 1 && n <= 8) samples = n;
    }
    return std::clamp(8192 / resolution, 1, samples);
}

void downsample_coverage(ImageRGBA8& color, std::initializer_list<ImageRGBA8*> averaged, std::vector<float>* depth, int f,
                         float front_tolerance)
{
    if (f == 1) return;
    const int big = color.width, n = big / f;
    std::vector<ImageRGBA8*> images{&color};
    for (ImageRGBA8* image : averaged)
        if (image) images.push_back(image);
    std::vector<ImageRGBA8> small(images.size(), ImageRGBA8(n, n));
    std::vector<float> small_depth(depth ? std::size_t(n) * n : 0, 1.0f);
    std::vector<unsigned> sums(images.size() * 3);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            unsigned count = 0;
            std::fill(sums.begin(), sums.end(), 0u);
            float nearest = 1.0f;
            const bool front_only = depth && front_tolerance >= 0.0f;
            if (front_only)
                for (int j = 0; j < f; ++j)
                    for (int i = 0; i < f; ++i)
                        if (color.at(x * f + i, y * f + j)[3] != 0)
                            nearest = std::min(nearest, (*depth)[std::size_t(y * f + j) * big + x * f + i]);
            for (int j = 0; j < f; ++j)
                for (int i = 0; i < f; ++i) {
                    int sx = x * f + i, sy = y * f + j;
                    if (color.at(sx, sy)[3] == 0) continue;
                    if (front_only && (*depth)[std::size_t(sy) * big + sx] > nearest + front_tolerance) continue;
                    ++count;
                    if (depth) nearest = std::min(nearest, (*depth)[std::size_t(sy) * big + sx]);
                    for (std::size_t m = 0; m < images.size(); ++m)
                        for (int k = 0; k < 3; ++k) sums[m * 3 + k] += images[m]->at(sx, sy)[k];
                }
            if (count == 0) continue;
            if (depth) small_depth[std::size_t(y) * n + x] = nearest;
            for (std::size_t m = 0; m < images.size(); ++m) {
                std::uint8_t* target = small[m].at(x, y);
                for (int k = 0; k < 3; ++k) target[k] = std::uint8_t((sums[m * 3 + k] + count / 2) / count);
                target[3] = 255;
            }
            const unsigned samples = unsigned(f * f);
            small[0].at(x, y)[3] = std::uint8_t(std::max(1u, (count * 255 + samples / 2) / samples));
        }
    for (std::size_t m = 0; m < images.size(); ++m) *images[m] = std::move(small[m]);
    if (depth) *depth = std::move(small_depth);
}

double texture_texel_area(const Mesh& mesh, std::size_t f)
{
    const Material& material = mesh.materials[mesh.face_materials[f]];
    if (material.base_color_texture < 0 || !mesh.has_texture_coordinates()) return 0.0;
    const Texture& texture = mesh.textures[std::size_t(material.base_color_texture)];
    const glm::vec2 a = mesh.uvs[mesh.indices[3 * f]], b = mesh.uvs[mesh.indices[3 * f + 1]], c = mesh.uvs[mesh.indices[3 * f + 2]];
    const glm::dvec2 ab = glm::dvec2(b - a) * glm::dvec2(texture.width, texture.height),
                     ac = glm::dvec2(c - a) * glm::dvec2(texture.width, texture.height);
    return 0.5 * std::abs(ab.x * ac.y - ab.y * ac.x);
}

double cutout_texel_size(const Mesh& mesh)
{
    struct Sample {
        double texel_world, area;
    };
    std::vector<Sample> samples;
    double total_area = 0.0;
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        if (alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) <= 0.0f) continue;
        const double texels = texture_texel_area(mesh, f), area = mesh.triangle_area(f);
        if (!(texels > 0.0) || !(area > 0.0) || !std::isfinite(texels) || !std::isfinite(area)) continue;
        samples.push_back({std::sqrt(area / texels), area});
        total_area += area;
    }
    if (samples.empty()) return 0.0;
    std::sort(samples.begin(), samples.end(), [](const Sample& x, const Sample& y) { return x.texel_world < y.texel_world; });
    double below = 0.0;
    for (const Sample& s : samples) {
        below += s.area;
        if (below >= 0.5 * total_area) return s.texel_world;
    }
    return samples.back().texel_world;
}

} // namespace standin::reps
