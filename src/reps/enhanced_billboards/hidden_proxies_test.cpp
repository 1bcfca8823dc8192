// Hidden proxies by view direction (hidden_proxies.h): a plate in front of a smaller one hides it
// from the front and not from the side or the back; outlines and back-facing texels hide nothing
// where they should not; coarse and whole boxes are cut to what shows, whole boxes of parts
// apart split; directions fall in octahedral cells that cover the sphere; the answer is the same
// at any thread count.
#include "reps/enhanced_billboards/hidden_proxies.h"
#include "reps/common/surface_image.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <array>
#include <cmath>
#include <random>

namespace standin::billboards {
namespace {

constexpr int k_side = 64;

// A billboard looking along +z whose texels in [lo, hi)^2 are covered at world depth z (the
// billboard's plane at z = 0, depth range 100), normals facing the billboard (-z).
Billboard plate(int lo, int hi, float z, bool clipped = false)
{
    Billboard b;
    b.width = b.height = k_side;
    b.texel_size = 1.0f;
    b.depth_range = 100.0f;
    b.origin = {0.0f, 0.0f, 0.0f};
    b.direction = {0, 0, 1};
    b.axis_u = {1, 0, 0};
    b.axis_v = {0, 1, 0};
    b.color = ImageRGBA8(b.width, b.height);
    b.normal_depth = ImageRGBA16(b.width, b.height);
    for (int j = lo; j < hi; ++j)
        for (int i = lo; i < hi; ++i) {
            std::uint8_t* c = b.color.at(i, j);
            c[0] = c[1] = c[2] = 200;
            // an edge line code in the alpha (--sheet-edges clip) marks a texel clipped
            c[3] = clipped ? 3 : 255;
            std::uint16_t* nd = b.normal_depth.at(i, j);
            nd[0] = reps::encode_normal(0.0f), nd[1] = reps::encode_normal(0.0f), nd[2] = reps::encode_normal(-1.0f);
            nd[3] = reps::encode_depth(z / b.depth_range);
        }
    return b;
}

struct Built {
    HiddenProxies hidden;
    std::vector<std::size_t> fine_first; // each billboard's first fine proxy
    std::size_t fine_count = 0;
};

void build(Built& out, std::vector<Billboard>& billboards, bool backs_see_through, bool edge_lines = false)
{
    LinkSettings links;
    links.edge_lines = edge_lines;
    std::uint32_t fine = 0, coarse = 0;
    for (const Billboard& b : billboards) {
        const HeightFieldAcceleration acc = build_acceleration(b, k_side, k_side, 6, links);
        const std::vector<TileBox> fine_boxes = build_tiles(acc, 16), coarse_boxes = build_tiles(acc, 64);
        out.fine_first.push_back(fine);
        out.hidden.add_billboard(b, acc, {fine_boxes, fine}, {coarse_boxes, coarse});
        fine += std::uint32_t(fine_boxes.size());
        coarse += std::uint32_t(coarse_boxes.size());
    }
    out.fine_count = fine;
    out.hidden.finish(glm::vec3(32.0f, 32.0f, 50.0f), 60.0f, 1.0f, backs_see_through);
}

std::size_t visible_fine(const Built& built, std::size_t billboard, const std::vector<std::uint64_t>& bits)
{
    const std::size_t first = built.fine_first[billboard];
    const std::size_t end = billboard + 1 < built.fine_first.size() ? built.fine_first[billboard + 1] : built.fine_count;
    std::size_t n = 0;
    for (std::size_t k = first; k < end; ++k) n += (bits[k >> 6] >> (k & 63)) & 1u;
    return n;
}

// A 64 x 64 plate at z = 20 in front of a 48 x 48 one at z = 60: seen along +z (from the front)
// the small plate's 16 tiles are all hidden, the front plate's 16 all seen; from -z (the back) the
// small plate hides the front plate's middle 4 tiles (whose texels lie 8 or more from its outline),
// unless back-facing texels see through; from the side (along x) every tile shows.
TEST(HiddenProxies, APlateHidesWhatLiesBehindItAlongTheDirection)
{
    for (bool backs_see_through : {false, true}) {
        SCOPED_TRACE(backs_see_through ? "backs see through" : "backs hide");
        std::vector<Billboard> billboards = {plate(0, 64, 20.0f), plate(8, 56, 60.0f)};
        Built built;
        build(built, billboards, backs_see_through);
        ASSERT_EQ(built.fine_count, 32u);
        ASSERT_EQ(built.hidden.proxy_count(), 32u + 2u + 2u); // one coarse tile and one whole box each

        const std::vector<std::uint64_t> front = built.hidden.visible_along({0, 0, 1});
        EXPECT_EQ(visible_fine(built, 0, front), 16u);
        EXPECT_EQ(visible_fine(built, 1, front), 0u);
        EXPECT_EQ((front[0] >> 32) & 1u, 1u) << "the front plate's coarse tile";
        EXPECT_EQ((front[0] >> 33) & 1u, 0u) << "the small plate's coarse tile";
        EXPECT_EQ((front[0] >> 35) & 1u, 0u) << "the small plate's whole box";

        // from behind, the plates' normals (-z) face away from the eye
        const std::vector<std::uint64_t> back = built.hidden.visible_along({0, 0, -1});
        EXPECT_EQ(visible_fine(built, 1, back), 16u);
        EXPECT_EQ(visible_fine(built, 0, back), backs_see_through ? 16u : 12u);

        const std::vector<std::uint64_t> side = built.hidden.visible_along({1, 0, 0.02f});
        EXPECT_EQ(visible_fine(built, 0, side) + visible_fine(built, 1, side), 32u);
    }
}

// Texels an outline crosses are covered in part: a plate of them hides nothing, the same plate
// unclipped hides everything behind it.
TEST(HiddenProxies, ClippedTexelsHideNothing)
{
    for (bool clipped : {false, true}) {
        std::vector<Billboard> billboards = {plate(0, 64, 20.0f, clipped), plate(8, 56, 60.0f)};
        Built built;
        build(built, billboards, false, true);
        EXPECT_EQ(visible_fine(built, 1, built.hidden.visible_along({0, 0, 1})), clipped ? 16u : 0u)
            << (clipped ? "clipped" : "plain");
    }
}

// A tile wholly behind a plate is kept while its texels lie beside the plate's outline (a pixel's
// limit is the farthest of its neighbours': the plate may cover only part of the pixels along its
// rim), and hidden once the outline is a few pixels away.
TEST(HiddenProxies, WhatLiesBesideAnOutlineIsKept)
{
    for (int front_end : {48, 56}) {
        std::vector<Billboard> billboards = {plate(0, front_end, 20.0f), plate(32, 64, 60.0f)};
        Built built;
        build(built, billboards, false);
        // the back plate's 4 tiles: the one at texels 32-47 lies behind the front plate
        EXPECT_EQ(visible_fine(built, 1, built.hidden.visible_along({0, 0, 1})), front_end == 48 ? 4u : 3u)
            << "front plate to texel " << front_end;
    }
}

// A billboard holding two surfaces over texels 8-55, those at x < 32 at z = 20 and the others at
// z = 60, and a second billboard's plate at z = 50 over x >= 16 (reaching past the first's outline,
// which would show what lies behind it): from the cell around +z only the near half of the first
// shows, so its coarse tile and its whole box are cut to that half (rectangle and depth); from the
// side every tile shows and the whole box's parts span all of it.
TEST(HiddenProxies, BoxesAreCutToTheFineTilesThatShow)
{
    Billboard two = plate(8, 56, 20.0f);
    for (int j = 8; j < 56; ++j)
        for (int i = 32; i < 56; ++i) two.normal_depth.at(i, j)[3] = reps::encode_depth(60.0f / two.depth_range);
    Billboard front = plate(0, 64, 50.0f);
    for (int j = 0; j < k_side; ++j)
        for (int i = 0; i < 16; ++i) front.color.at(i, j)[3] = 0;
    std::vector<Billboard> billboards = {two, front};
    Built built;
    build(built, billboards, false);
    ASSERT_EQ(built.fine_count, 16u + 12u); // (tiles of 16 texels: texels 8-55 reach four a side)
    const std::size_t coarse_two = built.fine_count, whole_two = built.fine_count + 2, whole_front = whole_two + 1;
    ASSERT_EQ(built.hidden.proxy_count(), whole_front + 1);

    const std::size_t from_front = HiddenProxies::cell_index({0, 0, 1});
    std::array<HiddenProxies::Cut, 4> parts;
    for (std::size_t k : {coarse_two, whole_two}) {
        SCOPED_TRACE(k == coarse_two ? "coarse tile" : "whole box");
        ASSERT_EQ(built.hidden.cut_box(k, from_front, parts), 1);
        EXPECT_EQ(parts[0].texel_min, glm::ivec2(8, 8));
        EXPECT_EQ(parts[0].texel_max, glm::ivec2(32, 56));
        // (the coarse tile's plane may be tilted: its z about the plane is not the depth)
        if (k == whole_two) {
            EXPECT_NEAR(parts[0].offset_min, 0.2f, 0.02f);
            EXPECT_NEAR(parts[0].offset_max, 0.2f, 0.02f);
        }
    }
    // the plate in front shows wholly: nothing to cut
    EXPECT_EQ(built.hidden.cut_box(whole_front, from_front, parts), 0);
    // from the side every tile shows: the whole box's parts (its near and far halves lie apart in
    // depth) span its whole rectangle
    const int side = built.hidden.cut_box(whole_two, HiddenProxies::cell_index({1, 0, 0.02f}), parts);
    glm::ivec2 lo(1 << 20), hi(-(1 << 20));
    for (int p = 0; p < side; ++p) lo = glm::min(lo, parts[std::size_t(p)].texel_min), hi = glm::max(hi, parts[std::size_t(p)].texel_max);
    EXPECT_GE(side, 2);
    EXPECT_EQ(lo, glm::ivec2(8, 8));
    EXPECT_EQ(hi, glm::ivec2(56, 56));
    EXPECT_EQ(built.hidden.cut_box(0, from_front, parts), 0) << "fine tiles are not cut";
}

// A billboard whose texels are two patches at opposite corners (texels 0-15 and 48-63 along both
// axes): nothing hides them, so one cut box would be the whole box; two boxes, one a patch, hold
// them in an eighth of its volume.
TEST(HiddenProxies, AWholeBoxOfPartsApartIsDrawnAsOneBoxAPart)
{
    Billboard patches = plate(0, 64, 20.0f);
    for (int j = 0; j < k_side; ++j)
        for (int i = 0; i < k_side; ++i)
            if (!((i < 16 && j < 16) || (i >= 48 && j >= 48))) patches.color.at(i, j)[3] = 0;
    std::vector<Billboard> billboards = {patches};
    Built built;
    build(built, billboards, false);
    ASSERT_EQ(built.fine_count, 2u);
    std::array<HiddenProxies::Cut, 4> parts;
    ASSERT_EQ(built.hidden.cut_box(built.fine_count + 1, HiddenProxies::cell_index({0, 0, 1}), parts), 2);
    EXPECT_EQ(parts[0].texel_min, glm::ivec2(0, 0));
    EXPECT_EQ(parts[0].texel_max, glm::ivec2(16, 16));
    EXPECT_EQ(parts[1].texel_min, glm::ivec2(48, 48));
    EXPECT_EQ(parts[1].texel_max, glm::ivec2(64, 64));
    EXPECT_EQ(built.hidden.cut_box(built.fine_count, HiddenProxies::cell_index({0, 0, 1}), parts), 0)
        << "a coarse tile is cut, never split";
}

TEST(HiddenProxies, DirectionsFallInCellsCoveringTheSphere)
{
    std::mt19937 random(3);
    std::normal_distribution<float> normal;
    std::vector<int> hits(std::size_t(HiddenProxies::k_cells * HiddenProxies::k_cells), 0);
    for (int k = 0; k < 200000; ++k) {
        const glm::vec3 d(normal(random), normal(random), normal(random));
        if (glm::length(d) < 1e-3f) continue;
        const glm::ivec2 c = HiddenProxies::cell_of(d);
        ASSERT_GE(c.x, 0);
        ASSERT_LT(c.x, HiddenProxies::k_cells);
        ASSERT_GE(c.y, 0);
        ASSERT_LT(c.y, HiddenProxies::k_cells);
        EXPECT_EQ(HiddenProxies::cell_of(d * 7.5f), c) << "a direction's length does not matter";
        ++hits[std::size_t(c.y * HiddenProxies::k_cells + c.x)];
    }
    // every cell is reached, none holds more than 3x its share (the octahedral map's area distortion)
    const double share = 200000.0 / double(hits.size());
    for (int h : hits) {
        EXPECT_GT(h, 0);
        EXPECT_LT(double(h), 3.0 * share);
    }
    EXPECT_NE(HiddenProxies::cell_of({0, 0, 1}), HiddenProxies::cell_of({0, 0, -1}));
}

// A stack of plates behind a full one: seen from the front only the front plate's tiles show (the
// ones behind are skipped whole, tile or group at a time), and along any direction the answer is
// the same on one thread as on every core (tiles lower the depth buffer concurrently).
TEST(HiddenProxies, AStackOfPlatesGivesTheSameAnswerOnOneThreadAsOnEveryCore)
{
    std::vector<Billboard> billboards = {plate(0, 64, 10.0f)};
    std::mt19937 random(7);
    for (int k = 0; k < 7; ++k) {
        const int lo = 4 + int(random() % 12), hi = 48 + int(random() % 12);
        billboards.push_back(plate(lo, hi, 20.0f + 9.0f * float(k) + float(random() % 5)));
    }
    Built built;
    build(built, billboards, false);
    const std::vector<std::uint64_t> front = built.hidden.visible_along({0, 0, 1});
    EXPECT_EQ(visible_fine(built, 0, front), 16u);
    for (std::size_t b = 1; b < billboards.size(); ++b) EXPECT_EQ(visible_fine(built, b, front), 0u) << "plate " << b;

    std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
    std::size_t differ = 0, shown = 0;
    for (int k = 0; k < 24; ++k) {
        const glm::vec3 direction(unit(random), unit(random), unit(random));
        const std::vector<std::uint64_t> every_core = built.hidden.visible_along(direction);
        std::vector<std::uint64_t> one_thread;
        {
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            one_thread = built.hidden.visible_along(direction);
        }
        differ += one_thread != every_core ? 1 : 0;
        for (std::size_t b = 0; b < billboards.size(); ++b) shown += visible_fine(built, b, every_core);
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(shown, 24u * 16u) << "some directions see past the front plate";
    EXPECT_LT(shown, 24u * built.fine_count) << "some directions see tiles hidden";
}

} // namespace
} // namespace standin::billboards
