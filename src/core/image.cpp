// PNG reading (stb_image) and writing (libpng, so that 16-bit maps and byte-identical output are
// possible: fixed compression settings, no time chunk).
#include <standin/files.h>
#include <standin/image.h>
#include <standin/limits.h>

#include <png.h>
#include <stb_image.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace standin {

namespace {

struct PngWriteBuffer {
    std::string bytes;
};

void append_png_bytes(png_structp png, png_bytep data, png_size_t length)
{
    auto* buffer = static_cast<PngWriteBuffer*>(png_get_io_ptr(png));
    buffer->bytes.append(reinterpret_cast<const char*>(data), length);
}

void flush_png(png_structp) {}

// Encodes rows (top first) of `channels` (4: RGBA, 1: grey) x `bit_depth` samples; 16-bit samples
// are big-endian in PNG. `level`: zlib's.
Result<std::string> encode_png(int width, int height, int bit_depth, const void* pixels, int channels = 4, int level = 6)
{
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!png) return error(StatusCode::io_error, "libpng: cannot create writer");
    png_infop info = png_create_info_struct(png);
    PngWriteBuffer buffer;
    std::vector<std::uint8_t> row_bytes;
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return error(StatusCode::io_error, "libpng: encoding failed");
    }
    png_set_write_fn(png, &buffer, append_png_bytes, flush_png);
    png_set_compression_level(png, level);
    png_set_IHDR(png, info, png_uint_32(width), png_uint_32(height), bit_depth,
                 channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGBA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    std::size_t stride = std::size_t(width) * std::size_t(channels) * std::size_t(bit_depth / 8);
    row_bytes.resize(stride);
    for (int y = 0; y < height; ++y) {
        if (bit_depth == 8) {
            std::memcpy(row_bytes.data(), static_cast<const std::uint8_t*>(pixels) + y * stride, stride);
        } else {
            const std::size_t samples = std::size_t(width) * std::size_t(channels);
            const std::uint16_t* row = static_cast<const std::uint16_t*>(pixels) + std::size_t(y) * samples;
            for (std::size_t i = 0; i < samples; ++i) {
                row_bytes[2 * i] = std::uint8_t(row[i] >> 8);
                row_bytes[2 * i + 1] = std::uint8_t(row[i] & 0xff);
            }
        }
        png_write_row(png, row_bytes.data());
    }
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return std::move(buffer.bytes);
}

Status check_size(int width, int height, const std::string& path)
{
    if (width <= 0 || height <= 0 || width > 65535 || height > 65535)
        return error(StatusCode::invalid_argument, path + ": image size " + std::to_string(width) + "x" +
                                                       std::to_string(height) + " cannot be written");
    return Status::ok();
}

} // namespace

Result<std::string> encode_png_bytes(const ImageRGBA8& image)
{
    STANDIN_RETURN_IF_ERROR(check_size(image.width, image.height, "PNG"));
    return encode_png(image.width, image.height, 8, image.pixels.data());
}

Status write_png(const ImageRGBA8& image, const std::string& path)
{
    STANDIN_RETURN_IF_ERROR(check_size(image.width, image.height, path));
    Result<std::string> bytes = encode_png(image.width, image.height, 8, image.pixels.data());
    if (!bytes) return error(bytes.status().code(), path + ": " + bytes.status().message());
    return write_file_atomic(path, *bytes);
}

Result<std::string> encode_png_bytes(const ImageRGBA16& image)
{
    STANDIN_RETURN_IF_ERROR(check_size(image.width, image.height, "PNG"));
    return encode_png(image.width, image.height, 16, image.pixels.data());
}

Status write_png(const ImageRGBA16& image, const std::string& path)
{
    STANDIN_RETURN_IF_ERROR(check_size(image.width, image.height, path));
    Result<std::string> bytes = encode_png(image.width, image.height, 16, image.pixels.data());
    if (!bytes) return error(bytes.status().code(), path + ": " + bytes.status().message());
    return write_file_atomic(path, *bytes);
}

Result<std::string> encode_png_grey_bytes(int width, int height, int bit_depth, const std::vector<std::uint16_t>& samples)
{
    STANDIN_RETURN_IF_ERROR(check_size(width, height, "PNG"));
    if ((bit_depth != 8 && bit_depth != 16) || samples.size() != std::size_t(width) * std::size_t(height))
        return error(StatusCode::invalid_argument, "PNG: grey image of " + std::to_string(samples.size()) +
                                                       " samples at " + std::to_string(bit_depth) + " bits");
    if (bit_depth == 16) return encode_png(width, height, 16, samples.data(), 1);
    std::vector<std::uint8_t> narrow(samples.size());
    for (std::size_t k = 0; k < samples.size(); ++k) narrow[k] = std::uint8_t(std::min<std::uint16_t>(samples[k], 255));
    return encode_png(width, height, 8, narrow.data(), 1);
}

// The decoded image must fit the memory budget: a few bytes of PNG can declare 65535 x 65535.
static Status check_decoded_size(const std::string& path, const std::string& bytes, int bytes_per_texel)
{
    int w = 0, h = 0, channels = 0;
    if (!stbi_info_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), int(bytes.size()), &w, &h, &channels))
        return error(StatusCode::bad_data, quoted(path) + ": not a readable image (" + stbi_failure_reason() + ")");
    return check_memory(std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(bytes_per_texel) * 2,
                        quoted(path) + " (" + std::to_string(w) + "x" + std::to_string(h) + ")");
}

Result<ImageRGBA8> read_png_rgba8(const std::string& path)
{
    Result<std::string> bytes = read_file(path);
    if (!bytes) return bytes.status();
    if (bytes->size() > std::size_t(INT32_MAX)) return error(StatusCode::bad_data, quoted(path) + ": image file too large");
    STANDIN_RETURN_IF_ERROR(check_decoded_size(path, *bytes, 4));
    int w = 0, h = 0, channels = 0;
    stbi_uc* data = stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes->data()), int(bytes->size()),
                                          &w, &h, &channels, 4);
    if (!data) return error(StatusCode::bad_data, quoted(path) + ": not a readable image (" + stbi_failure_reason() + ")");
    ImageRGBA8 image(w, h);
    std::memcpy(image.pixels.data(), data, image.pixels.size());
    stbi_image_free(data);
    return image;
}

Result<ImageRGBA16> read_png_rgba16(const std::string& path)
{
    Result<std::string> bytes = read_file(path);
    if (!bytes) return bytes.status();
    if (bytes->size() > std::size_t(INT32_MAX)) return error(StatusCode::bad_data, quoted(path) + ": image file too large");
    STANDIN_RETURN_IF_ERROR(check_decoded_size(path, *bytes, 8));
    int w = 0, h = 0, channels = 0;
    stbi_us* data = stbi_load_16_from_memory(reinterpret_cast<const stbi_uc*>(bytes->data()), int(bytes->size()),
                                             &w, &h, &channels, 4);
    if (!data) return error(StatusCode::bad_data, quoted(path) + ": not a readable image (" + stbi_failure_reason() + ")");
    ImageRGBA16 image(w, h);
    std::memcpy(image.pixels.data(), data, image.pixels.size() * sizeof(std::uint16_t));
    stbi_image_free(data);
    return image;
}

Result<std::vector<std::uint16_t>> read_png_grey(const std::string& path, int bit_depth, int* width, int* height)
{
    Result<PngInfo> info = read_png_info(path);
    if (!info) return info.status();
    if (info->color_type != 0 || info->bit_depth != bit_depth)
        return error(StatusCode::bad_data, quoted(path) + ": not a " + std::to_string(bit_depth) +
                                               "-bit grey PNG (colour type " + std::to_string(info->color_type) +
                                               ", " + std::to_string(info->bit_depth) + " bits)");
    Result<std::string> bytes = read_file(path);
    if (!bytes) return bytes.status();
    if (bytes->size() > std::size_t(INT32_MAX)) return error(StatusCode::bad_data, quoted(path) + ": image file too large");
    STANDIN_RETURN_IF_ERROR(check_decoded_size(path, *bytes, 2));
    int w = 0, h = 0, channels = 0;
    const auto* data = reinterpret_cast<const stbi_uc*>(bytes->data());
    std::vector<std::uint16_t> samples;
    if (bit_depth == 16) {
        stbi_us* decoded = stbi_load_16_from_memory(data, int(bytes->size()), &w, &h, &channels, 1);
        if (!decoded) return error(StatusCode::bad_data, quoted(path) + ": not a readable image (" + stbi_failure_reason() + ")");
        samples.assign(decoded, decoded + std::size_t(w) * std::size_t(h));
        stbi_image_free(decoded);
    } else {
        stbi_uc* decoded = stbi_load_from_memory(data, int(bytes->size()), &w, &h, &channels, 1);
        if (!decoded) return error(StatusCode::bad_data, quoted(path) + ": not a readable image (" + stbi_failure_reason() + ")");
        samples.assign(decoded, decoded + std::size_t(w) * std::size_t(h));
        stbi_image_free(decoded);
    }
    if (width) *width = w;
    if (height) *height = h;
    return samples;
}

Result<PngInfo> read_png_info(const std::string& path)
{
    // signature (8), IHDR length and type (8), width, height, bit depth, colour type
    Result<std::string> head = read_file_head(path, 33);
    if (!head) return head.status();
    const auto* header = reinterpret_cast<const unsigned char*>(head->data());
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (head->size() < 33 || std::memcmp(header, signature, 8) != 0 || std::memcmp(header + 12, "IHDR", 4) != 0)
        return error(StatusCode::bad_data, quoted(path) + ": not a PNG file");
    auto be32 = [&](int at) {
        return std::uint32_t(header[at]) << 24 | std::uint32_t(header[at + 1]) << 16 | std::uint32_t(header[at + 2]) << 8 |
               std::uint32_t(header[at + 3]);
    };
    PngInfo info;
    std::uint32_t w = be32(16), h = be32(20);
    if (w == 0 || h == 0 || w > 0x7fffffffu || h > 0x7fffffffu)
        return error(StatusCode::bad_data, quoted(path) + ": PNG size " + std::to_string(w) + "x" + std::to_string(h) + " is invalid");
    info.width = int(w);
    info.height = int(h);
    info.bit_depth = header[24];
    info.color_type = header[25];
    return info;
}

Result<int> png_bit_depth(const std::string& path, int* width, int* height)
{
    Result<PngInfo> info = read_png_info(path);
    if (!info) return info.status();
    if (width) *width = info->width;
    if (height) *height = info->height;
    return info->bit_depth;
}

} // namespace standin
