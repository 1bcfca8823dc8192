// Compressed package images: the KTX2 container round trip and its refusal of hostile files
// (truncated, wrong format, sizes, levels, huge dimensions, damaged zlib data: one line, no crash,
// no huge allocation), BC blocks independent of the thread count, octahedral normals' precision.
#include "reps/common/block_compress.h"
#include "reps/common/package_codec.h"
#include "test_support.h"

#include <standin/files.h>
#include <standin/image.h>

#include <gtest/gtest.h>
#include <squish.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <filesystem>
#include <random>

namespace standin {
namespace {

using manifest_io::BlockFormat;
using manifest_io::BlockImage;

BlockImage sample_image(BlockFormat format, int width, int height, int levels)
{
    BlockImage image{format, width, height, {}};
    std::mt19937 random(7);
    for (int m = 0; m < levels; ++m) {
        std::vector<std::uint8_t> level(manifest_io::level_bytes(format, std::max(width >> m, 1), std::max(height >> m, 1)));
        for (std::size_t k = 0; k < level.size(); ++k) level[k] = std::uint8_t(k % 7 == 0 ? random() : k / 64);
        image.levels.push_back(level);
    }
    return image;
}

void put32(std::string& bytes, std::size_t at, std::uint32_t v)
{
    for (int k = 0; k < 4; ++k) bytes[at + std::size_t(k)] = char((v >> (8 * k)) & 0xff);
}

void expect_refused(const std::string& bytes, BlockFormat format, int width, int height, int levels, const std::string& needle)
{
    Result<BlockImage> read = manifest_io::decode_ktx2(bytes, "x.ktx2", format, width, height, levels);
    ASSERT_FALSE(read) << needle;
    EXPECT_EQ(read.status().code(), StatusCode::bad_data);
    EXPECT_NE(read.status().message().find("x.ktx2"), std::string::npos) << read.status().message();
    EXPECT_NE(read.status().message().find(needle), std::string::npos) << read.status().message();
    EXPECT_EQ(read.status().message().find('\n'), std::string::npos);
}

TEST(Ktx2, RoundTripsEveryFormatWithLevels)
{
    for (BlockFormat format : {BlockFormat::bc3_srgb, BlockFormat::bc4, BlockFormat::bc5, BlockFormat::r16, BlockFormat::r8}) {
        BlockImage image = sample_image(format, 37, 20, 3);
        std::string bytes = manifest_io::encode_ktx2(image);
        EXPECT_EQ(bytes, manifest_io::encode_ktx2(image)); // deterministic
        EXPECT_EQ(bytes.substr(1, 6), "KTX 20");
        Result<BlockImage> read = manifest_io::decode_ktx2(bytes, "x.ktx2", format, 37, 20, 3);
        ASSERT_TRUE(read) << read.status().message();
        EXPECT_EQ(read->levels, image.levels) << manifest_io::block_format_name(format);
    }
    EXPECT_EQ(manifest_io::level_bytes(BlockFormat::bc3_srgb, 5, 4), 32u);
    EXPECT_EQ(manifest_io::level_bytes(BlockFormat::bc4, 4, 4), 8u);
    EXPECT_EQ(manifest_io::level_bytes(BlockFormat::r16, 3, 2), 12u);
}

TEST(Ktx2, HostileFilesAreRefusedOnOneLine)
{
    const std::string good = manifest_io::encode_ktx2(sample_image(BlockFormat::bc5, 64, 32, 2));
    // every truncation, including inside the header and the level index
    for (std::size_t size = 0; size < good.size(); size += (size < 200 ? 1 : 97)) {
        Result<BlockImage> read = manifest_io::decode_ktx2(good.substr(0, size), "x.ktx2", BlockFormat::bc5, 64, 32, 2);
        EXPECT_FALSE(read) << size;
    }
    expect_refused("not a ktx file at all, but long enough to hold a header..........................", BlockFormat::bc5, 64,
                   32, 2, "not a KTX2 file");
    expect_refused(good, BlockFormat::bc3_srgb, 64, 32, 2, "VkFormat 141");
    expect_refused(good, BlockFormat::bc5, 64, 64, 2, "is 64x32, the manifest says 64x64");
    expect_refused(good, BlockFormat::bc5, 64, 32, 3, "has 2 mip levels");
    std::string layered = good;
    put32(layered, 32, 4);
    expect_refused(layered, BlockFormat::bc5, 64, 32, 2, "single 2D image");
    std::string scheme = good;
    put32(scheme, 44, 2); // zstd: not read
    expect_refused(scheme, BlockFormat::bc5, 64, 32, 2, "supercompression scheme 2");
    std::string beyond = good;
    put32(beyond, 80, 0xfffffff0u); // level 0's offset
    expect_refused(beyond, BlockFormat::bc5, 64, 32, 2, "beyond the end");
    std::string wrong_raw = good;
    put32(wrong_raw, 96, 100); // level 0's uncompressed length
    expect_refused(wrong_raw, BlockFormat::bc5, 64, 32, 2, "needs 2048");
    std::string damaged = good;
    damaged[damaged.size() - 5] = char(damaged[damaged.size() - 5] ^ 0x55); // inside level 0's zlib stream
    expect_refused(damaged, BlockFormat::bc5, 64, 32, 2, "does not inflate");
    // a manifest claiming huge dimensions with a header to match: refused before any allocation
    std::string huge = good;
    put32(huge, 20, 1u << 20);
    put32(huge, 24, 1u << 20);
    expect_refused(huge, BlockFormat::bc5, 1 << 20, 1 << 20, 2, "too large");
}

// Exact depth as a grey PNG (format version 5): the same samples back, at 8 and 16 bits; a planar
// depth (what most of a surface is) leaves PNG's prediction a constant residual, so the file is a
// fraction of the raw-zlib KTX2 of the same level; packages of version 4 keep their KTX2 depth,
// which still reads; a PNG of another kind is refused on one line naming it.
TEST(ExactChannel, DepthRoundTripsThroughAGreyPngSmallerThanItsKtx2)
{
    const std::string dir = test::fresh_directory("exact_channel");
    const int width = 96, height = 64;
    for (BlockFormat format : {BlockFormat::r16, BlockFormat::r8}) {
        const bool wide = format == BlockFormat::r16;
        BlockImage depth{format, width, height, {std::vector<std::uint8_t>(manifest_io::level_bytes(format, width, height))}};
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const std::size_t k = std::size_t(y) * width + std::size_t(x);
                const int v = x > 80 ? 0 : (wide ? 9000 + 211 * x + 97 * y : 20 + x + y); // a plane, then uncovered
                if (wide) depth.levels[0][2 * k] = std::uint8_t(v & 0xff), depth.levels[0][2 * k + 1] = std::uint8_t(v >> 8);
                else depth.levels[0][k] = std::uint8_t(v);
            }
        nlohmann::json files = nlohmann::json::object();
        const std::string name = wide ? "d16.png" : "d8.png";
        ASSERT_TRUE(manifest_io::write_exact_channel(depth, dir, name, files));
        ASSERT_TRUE(manifest_io::write_blocks(depth, dir, wide ? "d16.ktx2" : "d8.ktx2", files));
        const manifest_io::Reader in(dir);
        EXPECT_EQ(manifest_io::read_exact_channel(in, files, name, format, width, height).levels, depth.levels);
        EXPECT_EQ(manifest_io::read_exact_channel(in, files, wide ? "d16.ktx2" : "d8.ktx2", format, width, height).levels,
                  depth.levels);
        const auto png_bytes = files[name]["bytes"].get<std::uint64_t>();
        const auto ktx2_bytes = files[wide ? "d16.ktx2" : "d8.ktx2"]["bytes"].get<std::uint64_t>();
        EXPECT_LT(png_bytes * 2, ktx2_bytes) << manifest_io::block_format_name(format);
        Result<PngInfo> info = read_png_info(dir + "/" + name);
        ASSERT_TRUE(info);
        EXPECT_EQ(info->color_type, k_png_color_grey);
        EXPECT_EQ(info->bit_depth, wide ? 16 : 8);
    }
    // the other kinds of PNG where depth is expected: RGBA, and grey of the other bit depth
    nlohmann::json files = nlohmann::json::object();
    ASSERT_TRUE(manifest_io::write_image(ImageRGBA8(width, height), dir, "rgba.png", files));
    const manifest_io::Reader in(dir);
    auto refusal = [&](const std::string& name, BlockFormat format, const nlohmann::json& listed) {
        try {
            (void)manifest_io::read_exact_channel(in, listed, name, format, width, height);
        } catch (const manifest_io::BadField& bad) {
            EXPECT_EQ(bad.message.find('\n'), std::string::npos);
            EXPECT_NE(bad.message.find(name), std::string::npos) << bad.message;
            return bad.message;
        }
        ADD_FAILURE() << name << " was read";
        return std::string();
    };
    EXPECT_NE(refusal("rgba.png", BlockFormat::r8, files).find("colour type 6"), std::string::npos);
    nlohmann::json both = nlohmann::json::object();
    BlockImage eight{BlockFormat::r8, width, height, {std::vector<std::uint8_t>(std::size_t(width) * height, 7)}};
    ASSERT_TRUE(manifest_io::write_exact_channel(eight, dir, "eight.png", both));
    EXPECT_NE(refusal("eight.png", BlockFormat::r16, both).find("8-bit samples"), std::string::npos);
}

TEST(BlockCompress, OutputDoesNotDependOnTheThreadCount)
{
    const int width = 67, height = 45;
    std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4), mask(std::size_t(width) * height);
    std::mt19937 random(3);
    for (std::size_t k = 0; k < rgba.size(); ++k) rgba[k] = std::uint8_t(random());
    for (std::size_t k = 0; k < mask.size(); ++k) mask[k] = std::uint8_t(k % 3 != 0);
    std::vector<std::uint8_t> results[2][2];
    for (int threads : {1, 2})
        tbb::task_arena(threads).execute([&] {
            results[threads - 1][0] = reps::compress_blocks(rgba.data(), width, height, mask.data(), squish::kBc5);
            results[threads - 1][1] = reps::compress_blocks(rgba.data(), width, height, nullptr,
                                                            squish::kDxt5 | squish::kColourIterativeClusterFit);
        });
    EXPECT_EQ(results[0][0], results[1][0]);
    EXPECT_EQ(results[0][1], results[1][1]);
    EXPECT_EQ(results[0][0].size(), manifest_io::level_bytes(BlockFormat::bc5, width, height));
}

TEST(BlockCompress, Bc3KeepsBinaryCoverageExactly)
{
    const int width = 13, height = 9;
    std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4);
    for (std::size_t k = 0; k < rgba.size() / 4; ++k) {
        rgba[k * 4] = std::uint8_t(k * 3), rgba[k * 4 + 1] = 90, rgba[k * 4 + 2] = std::uint8_t(200 - k);
        rgba[k * 4 + 3] = (k * 7) % 5 < 2 ? 0 : 255;
    }
    std::vector<std::uint8_t> blocks = reps::compress_blocks(rgba.data(), width, height, nullptr, squish::kDxt5);
    std::vector<std::uint8_t> back = reps::decompress_blocks(blocks.data(), width, height, squish::kDxt5);
    for (std::size_t k = 0; k < rgba.size() / 4; ++k) EXPECT_EQ(back[k * 4 + 3], rgba[k * 4 + 3]) << k;
}

TEST(BlockCompress, Bc5DecodesToTheEncodedChannels)
{
    const int width = 10, height = 7;
    std::vector<std::uint8_t> rgba(std::size_t(width) * height * 4);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            std::uint8_t* t = &rgba[(std::size_t(y) * width + x) * 4];
            t[0] = std::uint8_t(20 + 9 * x), t[1] = std::uint8_t(240 - 11 * y), t[2] = 7, t[3] = 255;
        }
    std::vector<std::uint8_t> blocks = reps::compress_blocks(rgba.data(), width, height, nullptr, squish::kBc5);
    std::vector<std::uint8_t> back = reps::decompress_blocks(blocks.data(), width, height, squish::kBc5);
    for (std::size_t k = 0; k < rgba.size() / 4; ++k) {
        EXPECT_NEAR(back[k * 4], rgba[k * 4], 3) << k;
        EXPECT_NEAR(back[k * 4 + 1], rgba[k * 4 + 1], 3) << k;
    }
}

TEST(Octahedral, EightBitCodesKeepNormalsWithinADegree)
{
    std::mt19937 random(11);
    std::normal_distribution<float> gauss;
    float worst = 0.0f;
    for (int k = 0; k < 20000; ++k) {
        glm::vec3 n = glm::normalize(glm::vec3(gauss(random), gauss(random), gauss(random)));
        glm::vec2 e = reps::octahedral_encode(n);
        glm::vec2 q = glm::round(e * 255.0f) / 255.0f;
        glm::vec3 back = reps::octahedral_decode(q);
        worst = std::max(worst, std::acos(std::min(glm::dot(n, back), 1.0f)));
        EXPECT_NEAR(glm::length(back), 1.0f, 1e-5f);
    }
    EXPECT_LT(glm::degrees(worst), 1.0f);
    EXPECT_NEAR(glm::dot(reps::octahedral_decode(reps::octahedral_encode({0, 0, -1})), glm::vec3(0, 0, -1)), 1.0f, 1e-6f);
}

} // namespace
} // namespace standin
