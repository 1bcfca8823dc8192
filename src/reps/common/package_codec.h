// The package-codec plumbing every representation shares (its src/reps/<name>/package.cpp keeps
// only what is its own): manifest.json's header ("format", "version", "representation", "source",
// "bake"), files listed with size and hash, images written and read back with their size, bit depth
// and hash checked, and typed field readers whose refusals name the manifest and the field
// (docs/FORMAT.md).
#pragma once

#include <standin/image.h>
#include <standin/options.h>
#include <standin/package.h>
#include <standin/status.h>

#include "reps/common/view_layout.h"

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace standin::manifest_io {

nlohmann::json vec3_json(glm::vec3 v);
nlohmann::json source_json(const SourceInfo& s);

// "PREFIX_NNN_MAP.png": the name of a numbered image file in a package.
std::string numbered_png(const char* prefix, std::size_t index, const char* map);

// Records the size and hash of the file `name` (already written in `directory`) in `files`.
Status record_file(const std::string& directory, const std::string& name, nlohmann::json& files);

// Writes an image as PNG (8 or 16 bits per sample, as the image holds them) into `directory` and
// records it in `files`.
Status write_image(const ImageRGBA8& image, const std::string& directory, const std::string& name, nlohmann::json& files);
Status write_image(const ImageRGBA16& image, const std::string& directory, const std::string& name, nlohmann::json& files);

// Runs write(k, files_k) for k < count side by side, each recording the files it writes in a list
// of its own, then merges the lists into `files` in order and returns the first failure in order.
// A package's maps are independent files whose encoding (zlib under PNG, block compression) is
// most of its writing time; the manifest's keys are sorted, so its bytes are a serial write's.
Status write_each(std::size_t count, const std::function<Status(std::size_t k, nlohmann::json& files)>& write,
                  nlohmann::json& files);

// What every manifest starts with: "format", "version", "representation", "source" and the "bake"
// block of the parameters the package was baked with (settings_json). The codec adds its own keys
// and "files", then calls write_manifest.
// `version`: 1 for packages of PNG maps only (older standins read them), k_package_format_version
// when the package holds compressed images (KTX2, below).
nlohmann::json manifest_header(const Package& package, const Options& parameters, int version = 1);
// Writes manifest.json (last: a package directory is complete once it is there), with `indent`.
Status write_manifest(const std::string& directory, const nlohmann::json& manifest, int indent);

// ------------------------------------------------------------------------------------------------
// Reading: every accessor names the manifest and the field it refuses.

struct BadField {
    std::string message;
};

class Reader {
public:
    // `directory`: the package; the reader names its manifest.json in every refusal.
    explicit Reader(const std::string& directory);

    const nlohmann::json& member(const nlohmann::json& object, const std::string& key, const std::string& where) const;
    double number(const nlohmann::json& object, const std::string& key, const std::string& where, double lo, double hi) const;
    std::int64_t integer(const nlohmann::json& object, const std::string& key, const std::string& where, std::int64_t lo,
                         std::int64_t hi) const;
    std::string string(const nlohmann::json& object, const std::string& key, const std::string& where) const;
    std::string choice(const nlohmann::json& object, const std::string& key, const std::string& where,
                       const std::vector<std::string>& choices) const;
    glm::vec3 vec3(const nlohmann::json& object, const std::string& key, const std::string& where) const;
    [[noreturn]] void fail(const std::string& field, const std::string& problem) const;
    const std::string& path() const { return path_; }
    const std::string& directory() const { return directory_; }

private:
    std::string directory_, path_;
};

// Runs a codec's reader body, turning the first refused field (BadField) into a bad_data status.
Result<std::unique_ptr<Package>> read_fields(const std::function<std::unique_ptr<Package>()>& body);

// Runs read(k) for k < count side by side (a package's pages or billboards: PNG decoding is most of
// reading one) and rethrows the refusal (BadField) of the lowest k, so that a damaged package is
// refused with the same line however the threads ran.
void read_each(std::size_t count, const std::function<void(std::size_t k)>& read);

SourceInfo read_source(const Reader& in, const nlohmann::json& manifest);

// The "bake" block: every declared bake parameter as used (names with '_' for '-': "texel_size"),
// integers and numbers as JSON numbers, choices as strings, flags as booleans.
nlohmann::json settings_json(const Options& parameters);
// Reads the "bake" block back, checking every value against the same declaration the baker used.
Options read_settings(const Reader& in, const nlohmann::json& manifest, std::span<const OptionSpec> specs);
// The manifest, or a copy in `storage` whose "bake" block gains `key` = `value` where a package
// written before that option existed lacks it (the value that reproduces what it did then).
const nlohmann::json& with_setting_default(const nlohmann::json& manifest, const char* key, const nlohmann::json& value,
                                           nlohmann::json& storage);

// Refuses axes that are not unit vectors or not orthogonal (fields named under `where`).
void check_axes(const Reader& in, const std::string& where, glm::vec3 axis_u, glm::vec3 axis_v, glm::vec3 direction);

// A captured view's entry (reps/common/view_layout.h View), and read back: axes unit and orthogonal,
// rectangles on whole cells (k_cell), the crop inside the capture of `resolution` (padded by a
// cell) and the atlas rectangle inside its page of `page_size`, `page` below `pages`.
nlohmann::json view_json(const reps::View& view);
reps::View read_view(const Reader& in, const nlohmann::json& entry, const std::string& where, int resolution,
                     int page_size, int pages);

// A name a manifest may give a file: one path component inside the package (not empty, not "." or
// "..", no '/' or '\\', no control characters, at most 255 bytes).
bool is_plain_file_name(const std::string& name);

// Largest coordinate a package's bounds (and an imported model) may hold: squares and cross products
// of coordinates must stay finite in float.
constexpr float k_max_coordinate = 1e15f;

// Checks a listed file against its recorded size and hash.
void check_file(const Reader& in, const std::string& directory, const nlohmann::json& files, const std::string& name);

// A listed PNG of the package, checked (check_file) and decoded, refused unless it is width x height
// with `bits` per sample (8 or 16; 8-bit samples read as 16 are scaled by 257).
ImageRGBA8 read_image8(const Reader& in, const nlohmann::json& files, const std::string& name, int width, int height);
ImageRGBA16 read_image16(const Reader& in, const nlohmann::json& files, const std::string& name, int width, int height,
                         int bits);

// ------------------------------------------------------------------------------------------------
// Compressed images (docs/FORMAT.md, "Compressed images"): one image, its mip levels included, as a
// KTX2 file (Khronos KTX 2.0) whose levels are zlib-supercompressed (supercompressionScheme 3) blocks
// of one GPU format, so a renderer can upload them as they are. Only the formats below are written
// or read; anything else in a package is refused.
enum class BlockFormat : std::uint32_t {
    bc3_srgb = 138, // VK_FORMAT_BC3_SRGB_BLOCK: colour (sRGB) + coverage, 16 bytes per 4x4 block
    bc4 = 139,      // VK_FORMAT_BC4_UNORM_BLOCK: one channel, 8 bytes per block
    bc5 = 141,      // VK_FORMAT_BC5_UNORM_BLOCK: two channels (octahedral normals), 16 bytes per block
    r16 = 70,       // VK_FORMAT_R16_UNORM: one exact 16-bit channel (depth), 2 bytes per texel
    r8 = 9,         // VK_FORMAT_R8_UNORM: one exact 8-bit channel, 1 byte per texel
};
const char* block_format_name(BlockFormat format); // "BC3_SRGB", "BC4", "BC5", "R16", "R8"

struct BlockImage {
    BlockFormat format = BlockFormat::bc3_srgb;
    int width = 0, height = 0;                      // level 0, texels
    std::vector<std::vector<std::uint8_t>> levels;  // level 0 first, each of level_bytes()
};

// Bytes of one level of width x height texels (whole 4x4 blocks for BC formats).
std::uint64_t level_bytes(BlockFormat format, int width, int height);
// Largest uncompressed level a package may hold (1 GiB: a 32768² BC3 level).
constexpr std::uint64_t k_max_level_bytes = 1ull << 30;

// The KTX2 file of an image (deterministic: fixed header, zlib level 6).
std::string encode_ktx2(const BlockImage& image);
// Parses a KTX2 file of `bytes`, refusing (one line naming `path`) anything but an image of `format`,
// width x height and `levels` levels, with every level's offsets inside the file and every level
// inflating to exactly level_bytes(). Never allocates more than the expected levels' size.
Result<BlockImage> decode_ktx2(std::string_view bytes, const std::string& path, BlockFormat format, int width,
                               int height, int levels);

// Writes an image as NAME (a .ktx2) into `directory` and records it in `files`.
Status write_blocks(const BlockImage& image, const std::string& directory, const std::string& name, nlohmann::json& files);
// A listed KTX2 of the package, checked (check_file) and parsed as decode_ktx2 does.
BlockImage read_blocks(const Reader& in, const nlohmann::json& files, const std::string& name, BlockFormat format,
                       int width, int height, int levels);

// Exact one-channel images (R8, R16: depth) as grey PNGs (docs/FORMAT.md, "Exact channels"): zlib
// alone packs smooth depth half as tightly as PNG's per-row prediction does. write_exact_channel
// writes NAME (a .png); read_exact_channel reads a .png, or the .ktx2 of packages written before,
// into the little-endian levels[0] a KTX2 gives.
Status write_exact_channel(const BlockImage& image, const std::string& directory, const std::string& name,
                           nlohmann::json& files);
BlockImage read_exact_channel(const Reader& in, const nlohmann::json& files, const std::string& name, BlockFormat format,
                              int width, int height);

// Arrays as gzip files (docs/FORMAT.md, "Compressed arrays"): one RFC 1952 member, deflate level 6,
// no file name and mtime 0, so the bytes depend on the input alone and any gzip tool unpacks them.
// write_gzip writes NAME (a .gz) into `directory` and records it in `files`; read_gzip reads a
// listed one (check_file) that must inflate to exactly `expected` bytes, refusing (BadField naming
// the file) anything else: not gzip, damaged, shorter, longer or followed by more bytes. What it
// holds grows with what inflates, so a hostile manifest's size cannot make it allocate.
std::string gzip_bytes(std::string_view bytes);
Status write_gzip(std::string_view bytes, const std::string& directory, const std::string& name, nlohmann::json& files);
std::string read_gzip(const Reader& in, const nlohmann::json& files, const std::string& name, std::size_t expected);

} // namespace standin::manifest_io
