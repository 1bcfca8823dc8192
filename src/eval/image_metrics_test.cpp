// Image metrics on tiny hand-built images with exact expected values, and cross-checks against
// ImageMagick's `compare` (PSNR, MAE, AE) on the same files.
#include "../../tests/test_support.h"

#include <standin/eval.h>
#include <standin/image.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace standin {
namespace {

ImageRGBA8 filled(int w, int h, glm::u8vec4 color)
{
    ImageRGBA8 image(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = image.at(x, y);
            p[0] = color.x, p[1] = color.y, p[2] = color.z, p[3] = color.w;
        }
    return image;
}

void set(ImageRGBA8& image, int x, int y, glm::u8vec4 c)
{
    std::uint8_t* p = image.at(x, y);
    p[0] = c.x, p[1] = c.y, p[2] = c.z, p[3] = c.w;
}

TEST(ImageMetrics, IdenticalImagesHaveNoError)
{
    ImageRGBA8 a = filled(8, 6, {0, 0, 0, 0});
    for (int x = 2; x < 5; ++x) set(a, x, 3, {200, 100, 50, 255});
    ImageMetrics m = compare_images(a, a);
    EXPECT_EQ(m.truth_pixels, 3u);
    EXPECT_EQ(m.union_pixels, 3u);
    EXPECT_EQ(m.luv_mean, 0.0);
    EXPECT_EQ(m.rgb_total, 0.0);
    EXPECT_EQ(m.de2000_mean, 0.0);
    EXPECT_EQ(m.iou, 1.0);
    EXPECT_EQ(m.psnr, 100.0);
    EXPECT_EQ(m.rect_pixels, 3u);
}

TEST(ImageMetrics, LuvSplitsIntoEdgeAndSharedPixels)
{
    // truth: white at x = 0..2; stand-in: grey at x = 1..3. U = 4 pixels: x = 0 (truth only,
    // white vs black = 100), x = 1, 2 (both, white vs grey), x = 3 (stand-in only, grey vs black).
    ImageRGBA8 truth = filled(4, 1, {0, 0, 0, 0}), standin = filled(4, 1, {0, 0, 0, 0});
    for (int x = 0; x < 3; ++x) set(truth, x, 0, {255, 255, 255, 255});
    for (int x = 1; x < 4; ++x) set(standin, x, 0, {128, 128, 128, 255});
    ImageMetrics m = compare_images(truth, standin);
    // neutral greys have u* = v* = 0: their distances are differences of L*
    double white = luv_from_srgb8({255, 255, 255}).x, grey = luv_from_srgb8({128, 128, 128}).x;
    double white_grey = white - grey;
    EXPECT_NEAR(m.luv_edge, (white + grey) / 4.0, 1e-6);
    EXPECT_NEAR(m.luv_shared, white_grey, 1e-6);
    EXPECT_NEAR(m.luv_mean, m.luv_edge + 2.0 * m.luv_shared / 4.0, 1e-9);
}

TEST(ImageMetrics, LuvOfPrimariesMatchesCieFormulas)
{
    // sRGB red is L*u*v* (53.24, 175.01, 37.76); blue (32.30, -9.40, -130.35) (Bruce Lindbloom's
    // calculator, D65). The seed's "580" for red vs. blue is not reproducible (docs/EVAL.md).
    glm::dvec3 red = luv_from_srgb8({255, 0, 0}), blue = luv_from_srgb8({0, 0, 255});
    EXPECT_NEAR(red.x, 53.24, 0.02);
    EXPECT_NEAR(red.y, 175.01, 0.05);
    EXPECT_NEAR(red.z, 37.76, 0.05);
    EXPECT_NEAR(blue.x, 32.30, 0.02);
    EXPECT_NEAR(blue.y, -9.40, 0.05);
    EXPECT_NEAR(blue.z, -130.35, 0.05);
    glm::dvec3 white = luv_from_srgb8({255, 255, 255});
    EXPECT_NEAR(white.x, 100.0, 1e-3);
    EXPECT_NEAR(white.y, 0.0, 0.01);
    EXPECT_NEAR(white.z, 0.0, 0.01);

    ImageRGBA8 a = filled(2, 2, {255, 0, 0, 255}), b = filled(2, 2, {0, 0, 255, 255});
    EXPECT_NEAR(compare_images(a, b).luv_mean, glm::length(red - blue), 1e-9);
    EXPECT_NEAR(compare_images(a, b).luv_mean, 250.44, 0.05);
}

TEST(ImageMetrics, Ciede2000MatchesSharmaReferencePairs)
{
    // Sharma, Wu, Dalal 2005, test data pairs 1, 7 and 17.
    EXPECT_NEAR(ciede2000({50.0, 2.6772, -79.7751}, {50.0, 0.0, -82.7485}), 2.0425, 1e-4);
    EXPECT_NEAR(ciede2000({50.0, 0.0, 0.0}, {50.0, -1.0, 2.0}), 2.3669, 1e-4);
    EXPECT_NEAR(ciede2000({50.0, 2.5, 0.0}, {73.0, 25.0, -18.0}), 27.1492, 1e-4);
}

TEST(ImageMetrics, RgbErrorHolesSpillAndRectangle)
{
    // truth: 2x2 grey block at (1,1); stand-in: block shifted right by one pixel
    ImageRGBA8 truth = filled(6, 4, {0, 0, 0, 0}), standin = truth;
    for (int y = 1; y < 3; ++y) {
        set(truth, 1, y, {100, 100, 100, 255});
        set(truth, 2, y, {100, 100, 100, 255});
        set(standin, 2, y, {110, 100, 100, 255});
        set(standin, 3, y, {110, 100, 100, 255});
    }
    ImageMetrics m = compare_images(truth, standin);
    EXPECT_EQ(m.truth_pixels, 4u);
    EXPECT_EQ(m.standin_pixels, 4u);
    EXPECT_EQ(m.intersection_pixels, 2u);
    EXPECT_EQ(m.union_pixels, 6u);
    EXPECT_EQ(m.hole_pixels, 2u);
    EXPECT_EQ(m.spill_pixels, 2u);
    EXPECT_DOUBLE_EQ(m.hole_fraction, 0.5);
    EXPECT_DOUBLE_EQ(m.spill_fraction, 0.5);
    EXPECT_DOUBLE_EQ(m.iou, 2.0 / 6.0);
    EXPECT_EQ(m.rect_x0, 1);
    EXPECT_EQ(m.rect_x1, 4);
    EXPECT_EQ(m.rect_y0, 1);
    EXPECT_EQ(m.rect_y1, 3);
    EXPECT_EQ(m.rect_pixels, 6u);
    // holes: 300 each (grey vs black), spill: 310 each, overlap: 10 each
    EXPECT_DOUBLE_EQ(m.rgb_total, 2 * 300 + 2 * 310 + 2 * 10);
    EXPECT_DOUBLE_EQ(m.rgb_avg, (2 * 300 + 2 * 310 + 2 * 10) / 6.0);
    // PSNR over the rectangle, 3 channels: squared errors 2*3*100^2 + 2*(110^2+2*100^2) + 2*100
    double mse = (2 * 3 * 100.0 * 100 + 2 * (110.0 * 110 + 2 * 100 * 100) + 2 * 100.0) / 18.0;
    EXPECT_NEAR(m.psnr, 10 * std::log10(255.0 * 255.0 / mse), 1e-9);
    EXPECT_EQ(m.differing_pixels, 6u);
}

// Supersampled views (EvalOptions::supersample): a pixel's colour is the mean of its samples over the
// background in linear light, its alpha whether any sample is covered; silhouettes count samples.
TEST(ImageMetrics, SupersampledPixelsAverageTheirSamplesInLinearLight)
{
    // 4 x 2 samples at 2 x 2 a pixel: the left pixel half white (its left column), the right empty
    ImageRGBA8 big = filled(4, 2, {0, 0, 0, 0});
    set(big, 0, 0, {255, 255, 255, 255});
    set(big, 0, 1, {255, 255, 255, 255});
    ResolvedImage resolved = resolve_supersampled(big, 2);
    ASSERT_EQ(resolved.color.width, 2);
    ASSERT_EQ(resolved.color.height, 1);
    // half of linear 1 over black is linear 0.5: sRGB 188 (not 128, the encoded mean)
    const std::uint8_t* left = resolved.color.at(0, 0);
    EXPECT_EQ(left[0], 188);
    EXPECT_EQ(left[1], 188);
    EXPECT_EQ(left[3], 255);
    EXPECT_EQ(resolved.color.at(1, 0)[3], 0);
    EXPECT_EQ(resolved.sample_coverage[0], 0b0101u); // samples (0,0) and (0,1): bits 0 and 2
    EXPECT_EQ(resolved.sample_coverage[1], 0u);
    // over a white background the uncovered pixel is white, the left one white too
    MetricOptions white;
    white.background = {255, 255, 255};
    ResolvedImage over_white = resolve_supersampled(big, 2, white);
    EXPECT_EQ(over_white.color.at(0, 0)[0], 255);
    EXPECT_EQ(over_white.color.at(1, 0)[0], 255);
    // a sample with partial alpha blends with the background in linear light too
    ImageRGBA8 one = filled(1, 1, {255, 255, 255, 51}); // alpha 0.2
    EXPECT_EQ(resolve_supersampled(one, 1).color.at(0, 0)[0], 124); // linear 0.2
}

// Why foliage is measured supersampled: stripes finer than a pixel (leaves a fraction of a pixel
// wide) against a stand-in that draws their mean. One sample a pixel sees only stripes or only
// gaps, so the mean colour scores as badly as a wrong one; resolved, it is what the truth shows.
TEST(ImageMetrics, SupersampledTruthRewardsTheMeanOfDetailFinerThanAPixel)
{
    const int w = 8, h = 8, n = 4;
    ImageRGBA8 truth(w * n, h * n), standin(w * n, h * n);
    for (int y = 0; y < h * n; ++y)
        for (int x = 0; x < w * n; ++x) {
            set(truth, x, y, x % 2 ? glm::u8vec4{40, 160, 40, 255} : glm::u8vec4{200, 230, 120, 255});
            set(standin, x, y, {149, 199, 91, 255}); // sRGB of the two greens' linear mean
        }
    ImageMetrics resolved = compare_images(resolve_supersampled(truth, n).color, resolve_supersampled(standin, n).color);
    EXPECT_LT(resolved.luv_mean, 0.5);
    // one sample a pixel (the top-left of each, as a pixel centre would fall on one stripe)
    ImageRGBA8 truth_1(w, h), standin_1(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::memcpy(truth_1.at(x, y), truth.at(x * n, y * n), 4);
            std::memcpy(standin_1.at(x, y), standin.at(x * n, y * n), 4);
        }
    EXPECT_GT(compare_images(truth_1, standin_1).luv_mean, 15.0);
}

TEST(ImageMetrics, SupersampledSilhouettesCountSamples)
{
    // one pixel of 4 x 4 samples: the truth covers its left half (8), the stand-in its left
    // quarter and one sample of the right half (5): 4 shared, 9 in either
    std::vector<std::uint64_t> truth(1, 0), standin(1, 0);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            const std::uint64_t bit = std::uint64_t(1) << (y * 4 + x);
            if (x < 2) truth[0] |= bit;
            if (x < 1 || (x == 3 && y == 0)) standin[0] |= bit;
        }
    ImageMetrics m;
    count_silhouette_over_samples(m, truth, standin, 4);
    EXPECT_DOUBLE_EQ(m.iou, 4.0 / 9.0);
    EXPECT_DOUBLE_EQ(m.hole_fraction, 4.0 / 8.0);
    EXPECT_DOUBLE_EQ(m.spill_fraction, 1.0 / 8.0);
    EXPECT_EQ(m.truth_pixels, 1u);  // 8 samples of 16, rounded
    EXPECT_EQ(m.standin_pixels, 0u); // 5 of 16
    // nothing covered at all: IoU 1, no holes
    std::vector<std::uint64_t> empty(3, 0);
    count_silhouette_over_samples(m, empty, empty, 2);
    EXPECT_EQ(m.iou, 1.0);
    EXPECT_EQ(m.hole_fraction, 0.0);
}

TEST(ImageMetrics, BackgroundIsConfigurable)
{
    ImageRGBA8 truth = filled(2, 1, {0, 0, 0, 0}), standin = truth;
    set(truth, 0, 0, {255, 255, 255, 255});
    MetricOptions white;
    white.background = {255, 255, 255};
    // a hole over a white background compares white against white
    EXPECT_EQ(compare_images(truth, standin, white).rgb_total, 0.0);
    EXPECT_EQ(compare_images(truth, standin).rgb_total, 765.0);
}

TEST(ImageMetrics, Percentile95IsNearestRank)
{
    // 20 covered pixels, one of them different: p95 is the 19th smallest = 0, mean is 1/20 of it
    ImageRGBA8 truth = filled(20, 1, {128, 128, 128, 255}), standin = truth;
    set(standin, 7, 0, {0, 0, 0, 255});
    ImageMetrics m = compare_images(truth, standin);
    EXPECT_EQ(m.de2000_p95, 0.0);
    EXPECT_GT(m.de2000_mean, 0.0);
    set(standin, 8, 0, {0, 0, 0, 255});
    EXPECT_GT(compare_images(truth, standin).de2000_p95, 10.0);
}

// ImageMagick on the composited object rectangles: PSNR (dB), MAE (normalised mean absolute
// error per channel, = rgb_avg / (3 * 255)) and AE (pixels that differ).
std::string crop_composite(const ImageRGBA8& image, const ImageMetrics& m, const std::string& path)
{
    ImageRGBA8 full = composite_over_background(image);
    ImageRGBA8 crop(m.rect_x1 - m.rect_x0, m.rect_y1 - m.rect_y0);
    for (int y = 0; y < crop.height; ++y)
        for (int x = 0; x < crop.width; ++x)
            for (int c = 0; c < 4; ++c) crop.at(x, y)[c] = full.at(x + m.rect_x0, y + m.rect_y0)[c];
    EXPECT_TRUE(write_png(crop, path).is_ok());
    return path;
}

double imagemagick_metric(const std::string& metric, const std::string& a, const std::string& b, bool normalised)
{
    // compare prints "absolute (normalised)" on stderr for most metrics, one number for PSNR/AE
    test::CommandResult r = test::run_command("compare -metric " + metric + " " + a + " " + b + " null:");
    std::string text = r.err;
    if (normalised) {
        std::size_t open = text.find('(');
        if (open != std::string::npos) text = text.substr(open + 1);
    }
    return std::strtod(text.c_str(), nullptr);
}

TEST(ImageMetrics, AgreesWithImageMagickCompare)
{
    if (test::run_command("command -v compare").exit_code != 0) GTEST_SKIP() << "ImageMagick compare not installed";
    // a textured disc against a shifted, recoloured, noisier disc
    ImageRGBA8 truth(64, 48), standin(64, 48);
    std::uint32_t state = 12345;
    auto next = [&] { return (state = state * 1664525u + 1013904223u) >> 24; };
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 64; ++x) {
            if ((x - 30) * (x - 30) + (y - 24) * (y - 24) < 300)
                set(truth, x, y, {std::uint8_t(4 * x), std::uint8_t(5 * y), 90, 255});
            if ((x - 33) * (x - 33) + (y - 22) * (y - 22) < 290)
                set(standin, x, y, {std::uint8_t(4 * x + next() % 7), std::uint8_t(5 * y), std::uint8_t(80 + next() % 20), 255});
        }
    ImageMetrics m = compare_images(truth, standin);
    std::string dir = test::fresh_directory("imagemagick");
    std::string a = crop_composite(truth, m, dir + "/a.png"), b = crop_composite(standin, m, dir + "/b.png");

    double psnr = imagemagick_metric("PSNR", a, b, false);
    EXPECT_NEAR(m.psnr, psnr, 0.01) << "ImageMagick PSNR";
    double mae = imagemagick_metric("MAE", a, b, true);
    EXPECT_NEAR(m.rgb_avg / (3.0 * 255.0), mae, 1e-4) << "ImageMagick MAE (normalised)";
    double ae = imagemagick_metric("AE", a, b, false);
    EXPECT_EQ(double(m.differing_pixels), ae) << "ImageMagick AE";
}

TEST(ImageMetrics, HeatmapIsOpaqueAndMarksDifferences)
{
    ImageRGBA8 truth = filled(3, 1, {0, 0, 0, 0}), standin = truth;
    set(truth, 1, 0, {255, 0, 0, 255});
    set(standin, 1, 0, {0, 0, 255, 255});
    set(truth, 2, 0, {9, 9, 9, 255});
    set(standin, 2, 0, {9, 9, 9, 255});
    ImageRGBA8 heat = difference_heatmap(truth, standin);
    EXPECT_EQ(heat.at(0, 0)[3], 255);
    EXPECT_EQ(heat.at(1, 0)[0], 255); // far above full scale: white
    EXPECT_EQ(heat.at(1, 0)[2], 255);
    EXPECT_EQ(heat.at(2, 0)[0], heat.at(2, 0)[2]); // identical: grey
}

} // namespace
} // namespace standin
