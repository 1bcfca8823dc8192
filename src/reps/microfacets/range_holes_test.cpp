// The range-image hole filter (Yamazaki et al. 2002 §5.1) on hand-made 5 x 5 images whose results
// were worked out by hand: the window's median, the threshold, the mask of fillable pixels, and
// iterations that close a hole from its rim inwards.
#include "reps/microfacets/range_holes.h"

#include <gtest/gtest.h>

namespace standin::microfacets {
namespace {

constexpr float H = -1.0f; // a hole

RangeImage image_from(const std::vector<float>& values, int width)
{
    RangeImage image;
    image.width = width;
    image.height = int(values.size()) / width;
    image.depth = values;
    for (float v : values) image.valid.push_back(v == H ? 0 : 1);
    return image;
}

float at(const RangeImage& image, int x, int y)
{
    std::size_t p = std::size_t(y) * image.width + x;
    return image.valid[p] ? image.depth[p] : H;
}

const std::vector<float> k_case = {
    10, 20, 30, 40, 50, //
    11, H,  H,  41, 51, //
    12, H,  32, 42, 52, //
    13, 23, 33, H,  H,  //
    14, 24, 34, H,  H,  //
};

TEST(MicrofacetRangeHoles, MedianOfTheValidNeighboursBelowTheThreshold)
{
    RangeImage image = image_from(k_case, 5);
    EXPECT_EQ(fill_range_holes(image, {}), 4u);
    // (1,1): window 10 20 30 11 12 32 (3 holes) -> lower median of 10 11 12 20 30 32 = 12
    EXPECT_EQ(at(image, 1, 1), 12.0f);
    EXPECT_EQ(at(image, 2, 1), 32.0f); // 20 30 32 40 41 42
    EXPECT_EQ(at(image, 1, 2), 13.0f); // 11 12 13 23 32 33
    EXPECT_EQ(at(image, 3, 3), 34.0f); // 4 holes: 32 33 34 42 52
    // the corner block: 4 holes and 3 pixels outside the image per window, never below 5
    EXPECT_EQ(at(image, 4, 3), H);
    EXPECT_EQ(at(image, 3, 4), H);
    EXPECT_EQ(at(image, 4, 4), H);
    // valid pixels are never changed
    EXPECT_EQ(at(image, 2, 2), 32.0f);
    EXPECT_EQ(at(image, 0, 0), 10.0f);
}

TEST(MicrofacetRangeHoles, ThresholdAndMask)
{
    RangeImage strict = image_from(k_case, 5);
    HoleFilter four;
    four.threshold = 4;
    EXPECT_EQ(fill_range_holes(strict, {}, four), 3u);
    EXPECT_EQ(at(strict, 3, 3), H); // its window holds 4 holes

    RangeImage masked = image_from(k_case, 5);
    std::vector<std::uint8_t> fillable(25, 1);
    fillable[1 * 5 + 2] = 0; // (2, 1) lies outside the colour image's coverage
    EXPECT_EQ(fill_range_holes(masked, fillable), 3u);
    EXPECT_EQ(at(masked, 2, 1), H);
    EXPECT_EQ(at(masked, 1, 1), 12.0f); // fills read the image before the pass, as without the mask
}

TEST(MicrofacetRangeHoles, IterationsCloseAHoleFromItsRim)
{
    // a 3 x 3 hole inside depth 5 (with a 7 at one corner of the rim)
    std::vector<float> values = {
        5, 5, 5, 5, 7, //
        5, H, H, H, 5, //
        5, H, H, H, 5, //
        5, H, H, H, 5, //
        5, 5, 5, 5, 5, //
    };
    RangeImage once = image_from(values, 5);
    HoleFilter one_pass;
    one_pass.max_iterations = 1;
    EXPECT_EQ(fill_range_holes(once, {}, one_pass), 4u); // the block's corners (4 holes each)
    EXPECT_EQ(at(once, 2, 1), H);                         // edge middles: 6 holes
    EXPECT_EQ(at(once, 3, 1), 5.0f);                      // median of 5 5 7 5 5

    RangeImage full = image_from(values, 5);
    EXPECT_EQ(fill_range_holes(full, {}), 9u); // corners, then edge middles, then the centre
    for (int y = 1; y <= 3; ++y)
        for (int x = 1; x <= 3; ++x) EXPECT_EQ(at(full, x, y), 5.0f) << x << "," << y;
}

} // namespace
} // namespace standin::microfacets
