// Images in memory and as PNG files. Rows are stored top row first, as PNG stores them.
#pragma once

#include <standin/status.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace standin {

// The sRGB transfer function (IEC 61966-2-1) per channel in [0, 1]: an encoded value's linear
// one, and back. Colours are stored encoded (textures, vertex colours, maps), shaded linear.
inline float srgb_to_linear(float c) { return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f); }
inline float linear_to_srgb(float c) { return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f; }

// 8 bits per channel, RGBA, sRGB-encoded colour and linear alpha.
struct ImageRGBA8 {
    int width = 0, height = 0;
    std::vector<std::uint8_t> pixels; // width * height * 4

    ImageRGBA8() = default;
    ImageRGBA8(int w, int h) : width(w), height(h), pixels(std::size_t(w) * h * 4, 0) {}
    std::uint8_t* at(int x, int y) { return &pixels[(std::size_t(y) * width + x) * 4]; }
    const std::uint8_t* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * 4]; }
    bool empty() const { return width == 0 || height == 0; }
};

// 16 bits per channel, RGBA (normal + depth maps of 16-bit packages).
struct ImageRGBA16 {
    int width = 0, height = 0;
    std::vector<std::uint16_t> pixels; // width * height * 4

    ImageRGBA16() = default;
    ImageRGBA16(int w, int h) : width(w), height(h), pixels(std::size_t(w) * h * 4, 0) {}
    std::uint16_t* at(int x, int y) { return &pixels[(std::size_t(y) * width + x) * 4]; }
    const std::uint16_t* at(int x, int y) const { return &pixels[(std::size_t(y) * width + x) * 4]; }
};

// PNG writers are deterministic (fixed zlib level, no timestamps) and atomic.
Status write_png(const ImageRGBA8& image, const std::string& path);
Status write_png(const ImageRGBA16& image, const std::string& path);
// The same PNG files' bytes, in memory (images embedded in other files: glTF export).
Result<std::string> encode_png_bytes(const ImageRGBA8& image);
Result<std::string> encode_png_bytes(const ImageRGBA16& image);
// One channel of exact samples (depth), 8 or 16 bits, as a grey PNG at zlib level 6: PNG's per-row
// prediction suits smooth depth, which zlib alone does not (docs/RESULTS.md, "Depth as grey PNG");
// level 9 took a view atlas bake 1.7x as long for 1.4% fewer bytes ("zlib level 6").
Result<std::string> encode_png_grey_bytes(int width, int height, int bit_depth, const std::vector<std::uint16_t>& samples);

// Readers: regular files only; the decoded size is checked against the memory budget (limits.h)
// before decoding. Any colour type is converted to RGBA.
Result<ImageRGBA8> read_png_rgba8(const std::string& path);
Result<ImageRGBA16> read_png_rgba16(const std::string& path);
// A grey PNG of exactly `bit_depth` bits (anything else is refused), its samples row by row.
Result<std::vector<std::uint16_t>> read_png_grey(const std::string& path, int bit_depth, int* width = nullptr,
                                                 int* height = nullptr);

// What a PNG file's header (IHDR) declares, read without decoding it, for validating packages.
struct PngInfo {
    int width = 0, height = 0;
    int bit_depth = 0;  // 1, 2, 4, 8 or 16
    int color_type = 0; // PNG colour type: 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
};
constexpr int k_png_color_rgba = 6;
constexpr int k_png_color_grey = 0;
Result<PngInfo> read_png_info(const std::string& path);
// Bit depth of a PNG file (8 or 16) without decoding it, for validating packages.
Result<int> png_bit_depth(const std::string& path, int* width = nullptr, int* height = nullptr);

} // namespace standin
