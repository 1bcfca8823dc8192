// Billboards packed into texture layers (acceleration.h pack_layers): every billboard's cell-aligned
// rectangle inside its layer, none overlapping, offsets on the pyramid's top cells, and fewer
// texels allocated than one layer per billboard would take. Links (build_acceleration): a plane
// seen steeply is one surface whatever its stored shading normals say, and a depth edge is not.
#include "reps/enhanced_billboards/acceleration.h"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"
#include "reps/common/surface_image.h"
#include "reps/common/shaders/height_field.h"

#include <cmath>

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace standin::billboards {
namespace {

std::int64_t allocated(const LayerPacking& p) { return std::int64_t(p.width) * p.height * p.layers; }

void expect_valid(const std::vector<glm::ivec2>& sizes, int cell, int max_side, const LayerPacking& p)
{
    ASSERT_EQ(p.placements.size(), sizes.size());
    EXPECT_LE(p.width, max_side);
    EXPECT_LE(p.height, max_side);
    EXPECT_EQ(p.width % cell, 0);
    EXPECT_EQ(p.height % cell, 0);
    auto padded = [cell](glm::ivec2 s) { return glm::max(glm::ivec2(cell), (s + cell - 1) / cell * cell); };
    for (std::size_t a = 0; a < sizes.size(); ++a) {
        const LayerPlacement& pa = p.placements[a];
        const glm::ivec2 sa = padded(sizes[a]);
        EXPECT_GE(pa.layer, 0);
        EXPECT_LT(pa.layer, p.layers);
        EXPECT_EQ(pa.offset.x % cell, 0) << a;
        EXPECT_EQ(pa.offset.y % cell, 0) << a;
        EXPECT_GE(pa.offset.x, 0);
        EXPECT_GE(pa.offset.y, 0);
        EXPECT_LE(pa.offset.x + sa.x, p.width) << a;
        EXPECT_LE(pa.offset.y + sa.y, p.height) << a;
        for (std::size_t b = a + 1; b < sizes.size(); ++b) {
            const LayerPlacement& pb = p.placements[b];
            const glm::ivec2 sb = padded(sizes[b]);
            const bool apart = pa.layer != pb.layer || pa.offset.x + sa.x <= pb.offset.x || pb.offset.x + sb.x <= pa.offset.x ||
                               pa.offset.y + sa.y <= pb.offset.y || pb.offset.y + sb.y <= pa.offset.y;
            EXPECT_TRUE(apart) << "billboards " << a << " and " << b << " overlap";
        }
    }
}

TEST(PackLayers, BillboardsOfManySizesShareLayersWithoutOverlap)
{
    std::mt19937 random(5);
    std::uniform_int_distribution<int> side(1, 700);
    std::vector<glm::ivec2> sizes;
    for (int k = 0; k < 60; ++k) sizes.push_back({side(random), side(random)});
    sizes.push_back({700, 700}); // the largest of both sides
    const int cell = 64;
    const LayerPacking p = pack_layers(sizes, cell, 8192);
    expect_valid(sizes, cell, 8192, p);
    // one 704 x 704 layer per billboard is what the renderer allocated before
    const std::int64_t one_each = std::int64_t(704) * 704 * std::int64_t(sizes.size());
    EXPECT_LT(allocated(p), one_each * 7 / 10) << p.width << "x" << p.height << " x " << p.layers;
    // deterministic
    const LayerPacking again = pack_layers(sizes, cell, 8192);
    EXPECT_EQ(again.width, p.width);
    EXPECT_EQ(again.layers, p.layers);
    for (std::size_t k = 0; k < sizes.size(); ++k) {
        EXPECT_EQ(again.placements[k].layer, p.placements[k].layer);
        EXPECT_EQ(again.placements[k].offset, p.placements[k].offset);
    }
}

TEST(PackLayers, LimitsAndSmallCases)
{
    // one billboard: one layer of its own aligned size, at the origin
    LayerPacking one = pack_layers({{100, 30}}, 64, 8192);
    expect_valid({{100, 30}}, 64, 8192, one);
    EXPECT_EQ(one.layers, 1);
    EXPECT_EQ(one.width, 128);
    EXPECT_EQ(one.height, 64);
    EXPECT_EQ(one.placements[0].offset, glm::ivec2(0));
    // four equal billboards fit one layer of twice the side when the limit allows it, else four
    const std::vector<glm::ivec2> four(4, glm::ivec2(256, 256));
    LayerPacking roomy = pack_layers(four, 64, 8192);
    expect_valid(four, 64, 8192, roomy);
    EXPECT_EQ(allocated(roomy), 4 * 256 * 256);
    LayerPacking tight = pack_layers(four, 64, 256);
    expect_valid(four, 64, 256, tight);
    EXPECT_EQ(tight.layers, 4);
    // a small pyramid (cell 8) and no billboards
    const std::vector<glm::ivec2> small{{3, 5}, {8, 8}, {1, 1}};
    expect_valid(small, 8, 8192, pack_layers(small, 8, 8192));
    LayerPacking none = pack_layers({}, 64, 8192);
    EXPECT_TRUE(none.placements.empty());
    EXPECT_EQ(none.layers, 0);
}

// The bytes `standin bake` reports are those of the layout the renderer allocates: 5 billboards of
// 100 x 60 texels (levels: 7 texels -> 2^7 > 100, capped at 6; cells of 64) in layers of 128 x 64.
TEST(PackLayers, GpuBytesCountEveryArrayAndPyramid)
{
    std::vector<Billboard> billboards(5);
    for (Billboard& b : billboards) b.width = 100, b.height = 60;
    const GpuLayout layout = gpu_layout(billboards);
    EXPECT_EQ(layout.levels, 6);
    const LayerPacking& p = layout.packing;
    for (const LayerPlacement& at : p.placements) EXPECT_EQ(at.offset.x % 64 + at.offset.y % 64, 0);
    const std::uint64_t texels = std::uint64_t(p.width) * p.height * p.layers;
    EXPECT_GE(texels, 5u * 128u * 64u);
    std::uint64_t pyramid = 0;
    for (int level = 1; level <= 6; ++level) pyramid += std::uint64_t(p.width >> level) * (p.height >> level) * p.layers * 8;
    EXPECT_EQ(gpu_texture_bytes(layout, false), texels * 16 + pyramid);
    EXPECT_EQ(gpu_texture_bytes(layout, true), texels * 24 + pyramid);
}

// A flat face 20 degrees from the billboard's plane (2.75 texels of depth per texel along u) whose
// shading normals, smoothed across the model's edges, lean to 35 degrees (1.43 per texel: the link
// rule allows 2.64): assimp's minigun.MDL, whose rings showed stripes of holes. Depths that change
// at one rate are linked; a step that does not repeat on either side (a depth edge) is not.
TEST(Links, ASteepPlaneIsOneSurfaceWhateverItsShadingNormals)
{
    Billboard b;
    b.width = 16;
    b.height = 4;
    b.texel_size = 1.0f;
    b.depth_range = 200.0f;
    b.direction = {0, 0, 1};
    b.axis_u = {1, 0, 0};
    b.axis_v = {0, 1, 0};
    b.color = ImageRGBA8(b.width, b.height);
    b.normal_depth = ImageRGBA16(b.width, b.height);
    const float steep = std::tan(glm::radians(70.0f)), leaning = std::tan(glm::radians(55.0f));
    const glm::vec3 shading = glm::normalize(glm::vec3(-leaning, 0.0f, -1.0f)); // a shallower slope than the depths
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            float depth = 10.0f + steep * float(i) + (i >= 12 ? 30.0f : 0.0f); // a depth edge between 11 and 12
            std::uint8_t* c = b.color.at(i, j);
            c[0] = c[1] = c[2] = 200;
            c[3] = 255;
            std::uint16_t* nd = b.normal_depth.at(i, j);
            for (int k = 0; k < 3; ++k) nd[k] = reps::encode_normal(shading[k]);
            nd[3] = reps::encode_depth(depth / b.depth_range);
        }
    }
    ASSERT_FALSE(texels_linked(b, 3, 1, 0, 1.0f)) << "the shading normals alone refuse the plane's steps";
    const HeightFieldAcceleration acc = build_acceleration(b, 16, 4, 2, LinkSettings{});
    auto flags = [&](int i, int j) { return acc.surface[std::size_t(j) * acc.width + i].flags; };
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i + 1 < b.width; ++i) {
            bool linked = (flags(i, j) & k_link_plus_u) != 0;
            EXPECT_EQ(linked, i != 11) << "texel " << i << ", " << j;
            EXPECT_EQ((flags(i + 1, j) & k_link_minus_u) != 0, linked);
        }
    }
}

// The march's packed level 0 (pack_surface): every covered texel's range decodes to one that holds
// [min, max] and is at most a range unit wider on each side, and its tilt decodes to within half a
// quantisation step of the slope (tilted tops, issue #17).
TEST(Links, PackedSurfaceHoldsEachRangeAndTilt)
{
    HeightFieldAcceleration acc;
    acc.width = 4;
    acc.height = 1;
    const std::uint16_t depths[4][3] = {{1000, 900, 1200}, {30000, 29000, 31500}, {65000, 64000, 65535}, {10, 0, 700}};
    const glm::vec2 slopes[4] = {{0.0f, 0.0f}, {2.9f, -3.0f}, {-1.37f, 0.5f}, {3.0f, 0.01f}};
    for (int k = 0; k < 4; ++k) {
        SurfaceTexel t;
        t.depth = depths[k][0];
        t.min = depths[k][1];
        t.max = depths[k][2];
        t.flags = k_texel_covered;
        t.slope = slopes[k];
        acc.surface.push_back(t);
    }
    acc.surface.push_back(SurfaceTexel{}); // uncovered: only depth and flags
    int unit = 0;
    const std::vector<std::uint16_t> packed = pack_surface(acc, unit);
    ASSERT_EQ(packed.size(), acc.surface.size() * 4);
    EXPECT_EQ(unit, 6); // the widest range, 1,500 codes, in 8 bits (255 x 6 = 1,530)
    const float step = float(HF_TOP_MAX_SLOPE) / 127.0f;
    for (int k = 0; k < 4; ++k) {
        const std::uint16_t* p = &packed[std::size_t(k) * 4];
        EXPECT_EQ(p[0], depths[k][0]);
        EXPECT_EQ(p[3], k_texel_covered);
        int lo = int(p[0]) - int(p[1] & 255u) * unit, hi = int(p[0]) + int(p[1] >> 8) * unit;
        EXPECT_LE(lo, depths[k][1]) << k;
        EXPECT_GT(lo, int(depths[k][1]) - unit) << k;
        EXPECT_GE(hi, depths[k][2]) << k;
        EXPECT_LT(hi, int(depths[k][2]) + unit) << k;
        glm::vec2 tilt = (glm::vec2(float(p[2] & 255u), float(p[2] >> 8)) - 128.0f) * step;
        EXPECT_NEAR(tilt.x, slopes[k].x, 0.5f * step) << k;
        EXPECT_NEAR(tilt.y, slopes[k].y, 0.5f * step) << k;
    }
    EXPECT_EQ(packed[16 + 3], 0u);
}

// Edge lines (issue #17) ride in the packed flags, so the march reads them without a colour fetch:
// every code's index + 1 (7 bits) comes back as march.frag decodes it, next to every other flag
TEST(Links, PackedSurfaceHoldsEveryEdgeLine)
{
    HeightFieldAcceleration acc;
    acc.width = EDGE_LINE_ANGLES * EDGE_LINE_OFFSETS + 1;
    acc.height = 1;
    const std::uint16_t others = k_texel_covered | k_link_minus_u | k_link_plus_v | k_smooth_plus_u | k_smooth_plus_v;
    for (int code = -1; code < EDGE_LINE_ANGLES * EDGE_LINE_OFFSETS; ++code) {
        SurfaceTexel t;
        t.depth = 100;
        t.min = 90;
        t.max = 110;
        t.flags = std::uint16_t(others | (code >= 0 ? k_texel_clipped : 0));
        t.edge_line = std::uint8_t(code + 1);
        acc.surface.push_back(t);
    }
    int unit = 0;
    const std::vector<std::uint16_t> packed = pack_surface(acc, unit);
    for (int code = -1; code < EDGE_LINE_ANGLES * EDGE_LINE_OFFSETS; ++code) {
        std::uint16_t flags = packed[std::size_t(code + 1) * 4 + 3];
        unsigned line = ((flags >> TEXEL_LINE_LOW_BIT) & 1u) | ((unsigned(flags) >> TEXEL_LINE_HIGH_SHIFT) << 1u);
        EXPECT_EQ(int(line), code + 1);
        EXPECT_EQ(flags & ~((1u << TEXEL_LINE_LOW_BIT) | (0xffffu << TEXEL_LINE_HIGH_SHIFT)), others) << code;
    }
}

} // namespace
} // namespace standin::billboards
