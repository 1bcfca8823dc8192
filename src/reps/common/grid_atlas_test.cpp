// The grid atlas layout: frame directions round-trip (direction -> cell -> direction), the encode
// inverts the decode, the frames are layout_directions' views in order, and resampling puts each
// view's pixels in its own cell with coverage as alpha and depth 1 where nothing was seen.
#include "reps/common/grid_atlas.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <cmath>

namespace standin::reps {
namespace {

TEST(GridAtlas, FrameDirectionsRoundTripThroughTheirCells)
{
    for (const std::string layout : {"octahedral", "hemi-octahedral"}) {
        for (int frames : {2, 3, 8, 16, 31}) {
            std::vector<glm::vec3> views = layout_directions(layout, 0, frames);
            ASSERT_EQ(views.size(), std::size_t(frames * frames));
            for (int j = 0; j < frames; ++j) {
                for (int i = 0; i < frames; ++i) {
                    float ex = (float(i) + 0.5f) / float(frames) * 2.0f - 1.0f, ey = (float(j) + 0.5f) / float(frames) * 2.0f - 1.0f;
                    glm::vec3 d = grid_decode(layout, ex, ey);
                    // frame (i, j) is view j * frames + i
                    EXPECT_LT(glm::length(d - views[std::size_t(j) * frames + i]), 1e-6f) << layout << " " << frames;
                    int fi = -1, fj = -1;
                    grid_frame(layout, frames, d, fi, fj);
                    EXPECT_EQ(fi, i) << layout << " frames " << frames << " j " << j;
                    EXPECT_EQ(fj, j) << layout << " frames " << frames << " i " << i;
                    float rx = 0.0f, ry = 0.0f;
                    grid_encode(layout, d, rx, ry);
                    EXPECT_NEAR(rx, ex, 1e-5f);
                    EXPECT_NEAR(ry, ey, 1e-5f);
                }
            }
        }
    }
}

TEST(GridAtlas, EncodeInvertsDecodeOverTheWholeSquare)
{
    for (int a = 0; a <= 40; ++a) {
        for (int b = 0; b <= 40; ++b) {
            float ex = float(a) / 20.0f - 1.0f, ey = float(b) / 20.0f - 1.0f;
            for (const std::string layout : {"octahedral", "hemi-octahedral"}) {
                glm::vec3 d = grid_decode(layout, ex, ey);
                EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
                if (layout == "hemi-octahedral") {
                    EXPECT_GE(d.y, -1e-6f);
                }
                glm::vec3 again;
                float rx = 0.0f, ry = 0.0f;
                grid_encode(layout, d, rx, ry);
                again = grid_decode(layout, rx, ry);
                // the octahedral square's border folds onto itself: compare directions, not coordinates
                EXPECT_LT(glm::length(again - d), 1e-5f) << layout << " " << ex << " " << ey;
            }
        }
    }
    // the poles and the axes land where the docs say
    float ex = 0.0f, ey = 0.0f;
    grid_encode("octahedral", {0, 1, 0}, ex, ey);
    EXPECT_NEAR(ex, 0.0f, 1e-6f);
    EXPECT_NEAR(ey, 0.0f, 1e-6f);
    grid_encode("octahedral", {0, 0, 1}, ex, ey);
    EXPECT_NEAR(ey, 1.0f, 1e-6f);
    grid_encode("octahedral", {1, 0, 0}, ex, ey);
    EXPECT_NEAR(ex, 1.0f, 1e-6f);
}

TEST(GridAtlas, EachViewLandsInItsCellWithCoverageAndDepth)
{
    const int frames = 2, resolution = 32, size = 64;
    std::vector<View> views(4);
    std::vector<ImageRGBA8> color(1, ImageRGBA8(128, 128)), normal_depth(1, ImageRGBA8(128, 128));
    // view k: its left half covered (crop 16 x 32 at atlas (k * 32, 0)), colour k * 60, depth k * 50
    for (int k = 0; k < 4; ++k) {
        View& v = views[std::size_t(k)];
        v.crop_x = 0, v.crop_y = 0, v.width = 16, v.height = 32, v.page = 0, v.atlas_x = k * 32, v.atlas_y = 0;
        for (int y = 0; y < 32; ++y) {
            for (int x = 0; x < 16; ++x) {
                std::uint8_t* c = color[0].at(k * 32 + x, y);
                c[0] = c[1] = c[2] = std::uint8_t(k * 60), c[3] = 255;
                std::uint8_t* n = normal_depth[0].at(k * 32 + x, y);
                n[0] = 128, n[1] = 128, n[2] = 255, n[3] = std::uint8_t(k * 50);
            }
        }
    }
    GridAtlasInput input{&views, &color, &normal_depth, resolution, frames};
    Result<GridAtlas> atlas = make_grid_atlas(input, size);
    ASSERT_TRUE(atlas) << atlas.status().message();
    for (int k = 0; k < 4; ++k) {
        int cx = (k % 2) * 32, cy = (k / 2) * 32;
        // inside the covered half: the view's colour and depth, full coverage
        const std::uint8_t* c = atlas->color.at(cx + 4, cy + 10);
        EXPECT_NEAR(c[0], k * 60, 1);
        EXPECT_EQ(c[3], 255);
        EXPECT_NEAR(atlas->normal_depth.at(cx + 4, cy + 10)[3], k * 50, 1);
        EXPECT_NEAR(atlas->normal_depth.at(cx + 4, cy + 10)[2], 255, 1);
        // the uncovered half: transparent, depth 1, colour dilated from the view (not black)
        EXPECT_EQ(atlas->color.at(cx + 20, cy + 10)[3], 0);
        EXPECT_EQ(atlas->normal_depth.at(cx + 20, cy + 10)[3], 255);
        EXPECT_NEAR(atlas->color.at(cx + 17, cy + 10)[0], k * 60, 1);
    }
    // deterministic
    Result<GridAtlas> again = make_grid_atlas(input, size);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->color.pixels, atlas->color.pixels);
    EXPECT_EQ(again->normal_depth.pixels, atlas->normal_depth.pixels);
    // too few texels per frame is refused
    EXPECT_FALSE(make_grid_atlas(input, 1));
}

// Alpha-tested models store each capture pixel's covered fraction (issue #14); the atlas keeps it
// (issue #16) instead of thresholding it at 1/2: one texel per pixel copies it, a coarser atlas
// averages it, and a pixel with any coverage keeps its full colour and depth.
TEST(GridAtlas, KeepsFractionalCoverage)
{
    const int frames = 2, resolution = 8;
    std::vector<View> views(4);
    std::vector<ImageRGBA8> color(1, ImageRGBA8(64, 64)), normal_depth(1, ImageRGBA8(64, 64));
    // every view: whole crop, pixel x of row y covered by (x + 1) * 25 / 255, colour 200, depth 80
    for (int k = 0; k < 4; ++k) {
        View& v = views[std::size_t(k)];
        v.crop_x = 0, v.crop_y = 0, v.width = 8, v.height = 8, v.page = 0, v.atlas_x = k * 8, v.atlas_y = 0;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) {
                std::uint8_t* c = color[0].at(k * 8 + x, y);
                c[0] = c[1] = c[2] = 200, c[3] = std::uint8_t((x + 1) * 25);
                std::uint8_t* n = normal_depth[0].at(k * 8 + x, y);
                n[0] = 128, n[1] = 128, n[2] = 255, n[3] = 80;
            }
    }
    GridAtlasInput input{&views, &color, &normal_depth, resolution, frames};
    Result<GridAtlas> exact = make_grid_atlas(input, frames * resolution);
    ASSERT_TRUE(exact) << exact.status().message();
    for (int x = 0; x < 8; ++x) {
        EXPECT_EQ(exact->color.at(x, 3)[3], (x + 1) * 25) << x;
        EXPECT_NEAR(exact->color.at(x, 3)[0], 200, 1) << x;
        EXPECT_EQ(exact->normal_depth.at(x, 3)[3], 80) << x;
    }
    Result<GridAtlas> half = make_grid_atlas(input, frames * resolution / 2);
    ASSERT_TRUE(half) << half.status().message();
    for (int x = 0; x < 4; ++x) EXPECT_NEAR(half->color.at(x, 1)[3], (2 * x + 1.5) * 25, 1) << x;
}

} // namespace
} // namespace standin::reps
