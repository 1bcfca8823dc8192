// Manifest helpers shared by the package codecs: both write and validate manifest.json the same
// way (docs/FORMAT.md). See manifest.h.
#include "reps/common/package_codec.h"

#include <standin/files.h>

#include <tbb/parallel_for.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>
#include <optional>
#include <utility>
#include <filesystem>

namespace standin::manifest_io {

namespace fs = std::filesystem;

nlohmann::json vec3_json(glm::vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json source_json(const SourceInfo& s)
{
    return {{"file_name", s.file_name},
            {"content_hash", s.content_hash},
            {"file_bytes", s.file_bytes},
            {"triangles", s.triangles},
            {"vertices", s.vertices},
            {"bounds", {{"min", vec3_json(s.bounds.min)}, {"max", vec3_json(s.bounds.max)}}},
            {"surface_area", s.surface_area}};
}

std::string numbered_png(const char* prefix, std::size_t index, const char* map)
{
    char name[64];
    std::snprintf(name, sizeof name, "%s_%03zu_%s.png", prefix, index, map);
    return name;
}

Status record_file(const std::string& directory, const std::string& name, nlohmann::json& files)
{
    Result<std::string> bytes = read_file((fs::path(directory) / name).string());
    if (!bytes) return bytes.status();
    files[name] = {{"bytes", bytes->size()}, {"fnv1a64", hex64(hash_bytes(*bytes))}};
    return Status::ok();
}

const nlohmann::json& Reader::member(const nlohmann::json& object, const std::string& key, const std::string& where) const
{
    if (!object.is_object() || !object.contains(key)) fail(where + key, "is missing");
    return object[key];
}

Reader::Reader(const std::string& directory)
    : directory_(directory), path_((fs::path(directory) / "manifest.json").string())
{
}

Result<std::unique_ptr<Package>> read_fields(const std::function<std::unique_ptr<Package>()>& body)
{
    try {
        return body();
    } catch (const BadField& bad) {
        return error(StatusCode::bad_data, bad.message);
    }
}

void read_each(std::size_t count, const std::function<void(std::size_t k)>& read)
{
    std::vector<std::optional<BadField>> refused(count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) {
        try {
            read(k);
        } catch (const BadField& bad) {
            refused[k] = bad;
        }
    });
    for (const std::optional<BadField>& bad : refused)
        if (bad) throw *bad;
}

double Reader::number(const nlohmann::json& object, const std::string& key, const std::string& where, double lo, double hi) const
{
    const nlohmann::json& value = member(object, key, where);
    if (!value.is_number()) fail(where + key, "is not a number");
    double x = value.get<double>();
    if (!std::isfinite(x) || x < lo || x > hi)
        fail(where + key, "= " + value.dump() + " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return x;
}

std::int64_t Reader::integer(const nlohmann::json& object, const std::string& key, const std::string& where, std::int64_t lo,
                             std::int64_t hi) const
{
    const nlohmann::json& value = member(object, key, where);
    if (!value.is_number_integer()) fail(where + key, "is not an integer");
    std::int64_t x = value.get<std::int64_t>();
    if (x < lo || x > hi)
        fail(where + key, "= " + std::to_string(x) + " is out of range " + std::to_string(lo) + ".." + std::to_string(hi));
    return x;
}

std::string Reader::string(const nlohmann::json& object, const std::string& key, const std::string& where) const
{
    const nlohmann::json& value = member(object, key, where);
    if (!value.is_string()) fail(where + key, "is not a string");
    return value.get<std::string>();
}

std::string Reader::choice(const nlohmann::json& object, const std::string& key, const std::string& where,
                           const std::vector<std::string>& choices) const
{
    std::string value = string(object, key, where);
    for (const std::string& c : choices)
        if (c == value) return value;
    fail(where + key, "= \"" + value + "\" is not known");
}

glm::vec3 Reader::vec3(const nlohmann::json& object, const std::string& key, const std::string& where) const
{
    const nlohmann::json& value = member(object, key, where);
    if (!value.is_array() || value.size() != 3) fail(where + key, "is not an array of 3 numbers");
    glm::vec3 v;
    for (int k = 0; k < 3; ++k) {
        if (!value[k].is_number() || !std::isfinite(value[k].get<double>())) fail(where + key, "holds a non-finite value");
        v[k] = value[k].get<float>();
    }
    return v;
}

void Reader::fail(const std::string& field, const std::string& problem) const
{
    throw BadField{quoted(path_) + ": \"" + one_line(field, 200) + "\" " + problem};
}

SourceInfo read_source(const Reader& in, const nlohmann::json& manifest)
{
    const nlohmann::json& source = in.member(manifest, "source", "");
    SourceInfo s;
    s.file_name = in.string(source, "file_name", "source.");
    s.content_hash = in.string(source, "content_hash", "source.");
    s.file_bytes = std::uint64_t(in.integer(source, "file_bytes", "source.", 0, INT64_MAX));
    s.triangles = std::size_t(in.integer(source, "triangles", "source.", 0, INT64_MAX));
    s.vertices = std::size_t(in.integer(source, "vertices", "source.", 0, INT64_MAX));
    const nlohmann::json& bounds = in.member(source, "bounds", "source.");
    s.bounds.min = in.vec3(bounds, "min", "source.bounds.");
    s.bounds.max = in.vec3(bounds, "max", "source.bounds.");
    s.surface_area = in.number(source, "surface_area", "source.", 0.0, 1e300);
    for (int k = 0; k < 3; ++k) {
        if (!(s.bounds.min[k] <= s.bounds.max[k])) in.fail("source.bounds", "has min above max");
        if (std::abs(s.bounds.min[k]) > k_max_coordinate || std::abs(s.bounds.max[k]) > k_max_coordinate)
            in.fail("source.bounds", "lies beyond +-1e15, where float arithmetic overflows");
    }
    if (!(s.bounds.diagonal() > 0.0f) || !std::isfinite(s.bounds.diagonal())) in.fail("source.bounds", "has no extent");
    return s;
}

static std::string manifest_key(const std::string& name)
{
    std::string key = name;
    for (char& c : key)
        if (c == '-') c = '_';
    return key;
}

nlohmann::json settings_json(const Options& parameters)
{
    nlohmann::json bake = nlohmann::json::object();
    for (const auto& [name, value] : parameters.values()) {
        nlohmann::json& entry = bake[manifest_key(name)];
        switch (value.type) {
        case OptionType::integer: entry = value.integer; break;
        case OptionType::number: entry = value.number; break;
        case OptionType::choice: entry = value.choice; break;
        case OptionType::flag: entry = value.flag; break;
        }
    }
    return bake;
}

const nlohmann::json& with_setting_default(const nlohmann::json& manifest, const char* key, const nlohmann::json& value,
                                           nlohmann::json& storage)
{
    if (!manifest.contains("bake") || !manifest["bake"].is_object() || manifest["bake"].contains(key)) return manifest;
    storage = manifest;
    storage["bake"][key] = value;
    return storage;
}

Options read_settings(const Reader& in, const nlohmann::json& manifest, std::span<const OptionSpec> specs)
{
    const nlohmann::json& bake = in.member(manifest, "bake", "");
    OptionValues values;
    for (const OptionSpec& spec : specs) {
        std::string key = manifest_key(spec.name);
        if (spec.default_value.empty() && !bake.contains(key)) continue;
        const nlohmann::json& entry = in.member(bake, key, "bake.");
        std::string text;
        switch (spec.type) {
        case OptionType::integer:
            if (!entry.is_number_integer()) in.fail("bake." + key, "is not an integer");
            text = std::to_string(entry.get<std::int64_t>());
            break;
        case OptionType::number: {
            if (!entry.is_number()) in.fail("bake." + key, "is not a number");
            char buffer[64];
            std::snprintf(buffer, sizeof buffer, "%.9g", entry.get<double>());
            text = buffer;
            break;
        }
        case OptionType::choice: text = in.string(bake, key, "bake."); break;
        case OptionType::flag:
            if (!entry.is_boolean()) in.fail("bake." + key, "is not true or false");
            text = entry.get<bool>() ? "on" : "off";
            break;
        }
        values.set(spec.name, text);
    }
    Result<Options> options = Options::parse(specs, values, "this package");
    if (!options) {
        // "--NAME: ..." becomes "bake.NAME ...", in the manifest's terms
        std::string message = options.status().message();
        std::size_t colon = message.find(':');
        std::string name = message.substr(2, colon == std::string::npos ? 0 : colon - 2);
        in.fail("bake." + manifest_key(name), colon == std::string::npos ? message : message.substr(colon + 2));
    }
    // what the user asked for beyond the defaults, as the bake recorded it (a batch compares it)
    if (manifest.contains("requested")) {
        const nlohmann::json& requested = manifest["requested"];
        if (!requested.is_object()) in.fail("requested", "is not an object");
        std::set<std::string> names;
        for (const auto& [name, text] : requested.items()) {
            if (!options->declared(name)) in.fail("requested." + name, "is not a bake option of this representation");
            names.insert(name);
        }
        options->set_requested(names);
    }
    return std::move(*options);
}

void check_axes(const Reader& in, const std::string& where, glm::vec3 axis_u, glm::vec3 axis_v, glm::vec3 direction)
{
    for (auto [axis, name] : {std::pair{axis_u, "axis_u"}, {axis_v, "axis_v"}, {direction, "direction"}})
        if (std::abs(glm::length(axis) - 1.0f) > 1e-3f) in.fail(where + name, "is not a unit vector");
    if (std::abs(glm::dot(axis_u, axis_v)) > 1e-3f || std::abs(glm::dot(axis_u, direction)) > 1e-3f ||
        std::abs(glm::dot(axis_v, direction)) > 1e-3f)
        in.fail(where + "axis_u", "axis_u, axis_v and direction are not orthogonal");
}

nlohmann::json view_json(const reps::View& v)
{
    return {{"direction", vec3_json(v.direction)}, {"axis_u", vec3_json(v.axis_u)}, {"axis_v", vec3_json(v.axis_v)},
            {"crop_x", v.crop_x}, {"crop_y", v.crop_y}, {"width", v.width}, {"height", v.height}, {"page", v.page},
            {"atlas_x", v.atlas_x}, {"atlas_y", v.atlas_y}};
}

reps::View read_view(const Reader& in, const nlohmann::json& entry, const std::string& where, int resolution,
                     int page_size, int pages)
{
    const int cell = reps::k_cell, n = resolution;
    reps::View v;
    v.direction = in.vec3(entry, "direction", where);
    v.axis_u = in.vec3(entry, "axis_u", where);
    v.axis_v = in.vec3(entry, "axis_v", where);
    check_axes(in, where, v.axis_u, v.axis_v, v.direction);
    v.width = int(in.integer(entry, "width", where, 0, page_size));
    v.height = int(in.integer(entry, "height", where, 0, page_size));
    v.crop_x = int(in.integer(entry, "crop_x", where, -1, n));
    v.crop_y = int(in.integer(entry, "crop_y", where, -1, n));
    v.page = int(in.integer(entry, "page", where, 0, std::max(0, pages - 1)));
    v.atlas_x = int(in.integer(entry, "atlas_x", where, 0, page_size - v.width));
    v.atlas_y = int(in.integer(entry, "atlas_y", where, 0, page_size - v.height));
    if (v.width % cell || v.height % cell || v.atlas_x % cell || v.atlas_y % cell)
        in.fail(where + "width", "rectangles must lie on whole cells of " + std::to_string(cell) + " texels");
    if (v.crop_x + v.width > n + 2 * cell || v.crop_y + v.height > n + 2 * cell)
        in.fail(where + "crop_x", "the crop reaches beyond the capture");
    return v;
}

bool is_plain_file_name(const std::string& name)
{
    if (name.empty() || name == "." || name == ".." || name.size() > 255) return false;
    for (unsigned char c : name)
        if (c == '/' || c == '\\' || c < 0x20 || c == 0x7f) return false;
    return true;
}

void check_file(const Reader& in, const std::string& directory, const nlohmann::json& files, const std::string& name)
{
    if (!is_plain_file_name(name)) in.fail("files", "names " + quoted(name) + ", which is not a plain file name");
    const nlohmann::json& entry = in.member(files, name, "files.");
    std::string path = (fs::path(directory) / name).string();
    Result<std::string> bytes = read_file(path);
    if (!bytes) throw BadField{bytes.status().message() + " (listed in the manifest)"};
    std::int64_t size = in.integer(entry, "bytes", "files." + name + ".", 0, INT64_MAX);
    if (std::uint64_t(size) != bytes->size())
        throw BadField{quoted(path) + ": has " + std::to_string(bytes->size()) + " bytes, the manifest says " + std::to_string(size)};
    if (in.string(entry, "fnv1a64", "files." + name + ".") != hex64(hash_bytes(*bytes)))
        throw BadField{quoted(path) + ": content does not match the manifest's hash (damaged file)"};
}

Status write_each(std::size_t count, const std::function<Status(std::size_t k, nlohmann::json& files)>& write,
                  nlohmann::json& files)
{
    std::vector<nlohmann::json> listed(count, nlohmann::json::object());
    std::vector<Status> written(count);
    tbb::parallel_for(std::size_t(0), count, [&](std::size_t k) { written[k] = write(k, listed[k]); });
    for (std::size_t k = 0; k < count; ++k) {
        STANDIN_RETURN_IF_ERROR(written[k]);
        files.update(listed[k]);
    }
    return Status::ok();
}

Status write_image(const ImageRGBA8& image, const std::string& directory, const std::string& name, nlohmann::json& files)
{
    STANDIN_RETURN_IF_ERROR(write_png(image, (fs::path(directory) / name).string()));
    return record_file(directory, name, files);
}

Status write_image(const ImageRGBA16& image, const std::string& directory, const std::string& name, nlohmann::json& files)
{
    STANDIN_RETURN_IF_ERROR(write_png(image, (fs::path(directory) / name).string()));
    return record_file(directory, name, files);
}

nlohmann::json manifest_header(const Package& package, const Options& parameters, int version)
{
    return {{"format", k_package_format},
            {"version", version},
            {"representation", package.representation()},
            {"source", source_json(package.source)},
            {"bake", settings_json(parameters)},
            {"requested", parameters.requested()}};
}

Status write_manifest(const std::string& directory, const nlohmann::json& manifest, int indent)
{
    return write_file_atomic((fs::path(directory) / "manifest.json").string(), manifest.dump(indent) + "\n");
}

// Size, bit depth and colour type of a listed PNG against the manifest, before it is decoded.
static std::string checked_png(const Reader& in, const nlohmann::json& files, const std::string& name, int width,
                               int height, int bits, int color_type = k_png_color_rgba)
{
    check_file(in, in.directory(), files, name);
    std::string path = (fs::path(in.directory()) / name).string();
    Result<PngInfo> info = read_png_info(path);
    if (!info) throw BadField{info.status().message()};
    if (info->width != width || info->height != height)
        throw BadField{quoted(path) + ": is " + std::to_string(info->width) + "x" + std::to_string(info->height) +
                       ", the manifest says " + std::to_string(width) + "x" + std::to_string(height)};
    if (info->bit_depth != bits)
        throw BadField{quoted(path) + ": has " + std::to_string(info->bit_depth) + "-bit samples, the manifest says " +
                       std::to_string(bits)};
    if (info->color_type != color_type)
        throw BadField{quoted(path) + ": PNG colour type " + std::to_string(info->color_type) + ", this map is " +
                       (color_type == k_png_color_grey ? "grey (colour type 0)" : "RGBA (colour type 6)")};
    return path;
}

ImageRGBA8 read_image8(const Reader& in, const nlohmann::json& files, const std::string& name, int width, int height)
{
    Result<ImageRGBA8> image = read_png_rgba8(checked_png(in, files, name, width, height, 8));
    if (!image) throw BadField{image.status().message()};
    return std::move(*image);
}

ImageRGBA16 read_image16(const Reader& in, const nlohmann::json& files, const std::string& name, int width, int height,
                         int bits)
{
    std::string path = checked_png(in, files, name, width, height, bits);
    if (bits == 16) {
        Result<ImageRGBA16> image = read_png_rgba16(path);
        if (!image) throw BadField{image.status().message()};
        return std::move(*image);
    }
    Result<ImageRGBA8> image = read_png_rgba8(path);
    if (!image) throw BadField{image.status().message()};
    ImageRGBA16 wide(image->width, image->height);
    for (std::size_t k = 0; k < image->pixels.size(); ++k) wide.pixels[k] = std::uint16_t(image->pixels[k] * 257);
    return wide;
}

// ------------------------------------------------------------------------------------------------
// KTX2 (Khronos, "KTX File Format Specification 2.0"): the 80-byte header, the level index (level 0
// first), the data format descriptor (one basic block), no key/value data, no supercompression
// global data, then the levels smallest first, each zlib-compressed (supercompressionScheme 3, so
// no alignment padding). The DFD follows the Khronos Data Format 1.3 tables for BC1A..BC5 and R16.

namespace {

constexpr unsigned char k_ktx2_identifier[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
constexpr std::uint32_t k_ktx2_zlib = 3;
constexpr std::size_t k_ktx2_header = 80, k_ktx2_level_entry = 24;

bool is_block_format(BlockFormat f) { return f == BlockFormat::bc3_srgb || f == BlockFormat::bc4 || f == BlockFormat::bc5; }

void put32(std::string& out, std::uint32_t v)
{
    for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
}
void put64(std::string& out, std::uint64_t v)
{
    for (int k = 0; k < 8; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
}
std::uint64_t get(std::string_view bytes, std::size_t at, int width)
{
    std::uint64_t v = 0;
    for (int k = 0; k < width; ++k) v |= std::uint64_t(static_cast<unsigned char>(bytes[at + std::size_t(k)])) << (8 * k);
    return v;
}

// The data format descriptor: dfdTotalSize, then one basic descriptor block.
std::string ktx2_dfd(BlockFormat format)
{
    struct Sample {
        std::uint32_t bit_offset, bit_length, channel, upper;
    };
    std::uint32_t model = 1, transfer = 1, bytes = 0; // KHR_DF_MODEL_RGBSDA, linear
    std::vector<Sample> samples;
    switch (format) {
    case BlockFormat::bc3_srgb:
        model = 130, transfer = 2, bytes = 16; // KHR_DF_MODEL_BC3, sRGB
        samples = {{0, 63, 15, 0xffffffffu}, {64, 63, 0, 0xffffffffu}}; // alpha block, then colour block
        break;
    case BlockFormat::bc4: model = 131, bytes = 8, samples = {{0, 63, 0, 0xffffffffu}}; break;
    case BlockFormat::bc5: model = 132, bytes = 16, samples = {{0, 63, 0, 0xffffffffu}, {64, 63, 1, 0xffffffffu}}; break;
    case BlockFormat::r16: bytes = 2, samples = {{0, 15, 0, 65535}}; break;
    case BlockFormat::r8: bytes = 1, samples = {{0, 7, 0, 255}}; break;
    }
    const std::uint32_t block = 24 + 16 * std::uint32_t(samples.size());
    std::string out;
    put32(out, 4 + block);
    put32(out, 0);                         // vendorId 0 (Khronos), descriptorType 0 (basic)
    put32(out, 2u | (block << 16));        // versionNumber 2 (Data Format 1.3), descriptorBlockSize
    put32(out, model | (1u << 8) | (transfer << 16)); // colour primaries BT.709, flags 0 (straight alpha)
    put32(out, is_block_format(format) ? 0x00000303u : 0u); // texel block 4x4 (dimensions minus one)
    put32(out, 0);                         // bytesPlane0..3: 0, the levels are supercompressed
    put32(out, 0);                         // bytesPlane4..7
    (void)bytes;                           // (uncompressed block bytes: level_bytes())
    for (const Sample& s : samples) {
        put32(out, s.bit_offset | (s.bit_length << 16) | (s.channel << 24));
        put32(out, 0); // sample position 0
        put32(out, 0); // sampleLower
        put32(out, s.upper);
    }
    return out;
}

} // namespace

const char* block_format_name(BlockFormat format)
{
    switch (format) {
    case BlockFormat::bc3_srgb: return "BC3_SRGB";
    case BlockFormat::bc4: return "BC4";
    case BlockFormat::bc5: return "BC5";
    case BlockFormat::r16: return "R16";
    case BlockFormat::r8: return "R8";
    }
    return "?";
}

std::uint64_t level_bytes(BlockFormat format, int width, int height)
{
    const std::uint64_t w = std::uint64_t(std::max(width, 0)), h = std::uint64_t(std::max(height, 0));
    switch (format) {
    case BlockFormat::bc3_srgb:
    case BlockFormat::bc5: return ((w + 3) / 4) * ((h + 3) / 4) * 16;
    case BlockFormat::bc4: return ((w + 3) / 4) * ((h + 3) / 4) * 8;
    case BlockFormat::r16: return w * h * 2;
    case BlockFormat::r8: return w * h;
    }
    return 0;
}

std::string encode_ktx2(const BlockImage& image)
{
    const std::size_t levels = image.levels.size();
    std::vector<std::string> packed(levels);
    for (std::size_t m = 0; m < levels; ++m) {
        const std::vector<std::uint8_t>& level = image.levels[m];
        uLongf size = compressBound(uLong(level.size()));
        packed[m].resize(size);
        // zlib's default level: 9 made a view atlas bake 1.2-1.4x as long for 0.3% fewer bytes on
        // BC blocks (docs/RESULTS.md, "zlib level 6")
        if (compress2(reinterpret_cast<Bytef*>(packed[m].data()), &size, level.data(), uLong(level.size()), 6) != Z_OK)
            throw std::bad_alloc(); // zlib fails only without memory
        packed[m].resize(size);
    }
    const std::string dfd = ktx2_dfd(image.format);
    const std::size_t dfd_offset = k_ktx2_header + levels * k_ktx2_level_entry;
    std::string out(reinterpret_cast<const char*>(k_ktx2_identifier), sizeof k_ktx2_identifier);
    put32(out, std::uint32_t(image.format));
    put32(out, image.format == BlockFormat::r16 ? 2u : 1u); // typeSize
    put32(out, std::uint32_t(image.width));
    put32(out, std::uint32_t(image.height));
    put32(out, 0); // pixelDepth
    put32(out, 0); // layerCount
    put32(out, 1); // faceCount
    put32(out, std::uint32_t(levels));
    put32(out, k_ktx2_zlib);
    put32(out, std::uint32_t(dfd_offset));
    put32(out, std::uint32_t(dfd.size()));
    put32(out, 0); // no key/value data
    put32(out, 0);
    put64(out, 0); // no supercompression global data
    put64(out, 0);
    // levels are stored smallest first after the DFD
    std::vector<std::uint64_t> offsets(levels);
    std::uint64_t at = dfd_offset + dfd.size();
    for (std::size_t m = levels; m-- > 0;) offsets[m] = at, at += packed[m].size();
    for (std::size_t m = 0; m < levels; ++m) {
        put64(out, offsets[m]);
        put64(out, packed[m].size());
        put64(out, image.levels[m].size());
    }
    out += dfd;
    for (std::size_t m = levels; m-- > 0;) out += packed[m];
    return out;
}

Result<BlockImage> decode_ktx2(std::string_view bytes, const std::string& path, BlockFormat format, int width, int height,
                               int levels)
{
    auto bad = [&](const std::string& problem) { return error(StatusCode::bad_data, quoted(path) + ": " + problem); };
    if (bytes.size() < k_ktx2_header || bytes.compare(0, sizeof k_ktx2_identifier,
                                                      std::string_view(reinterpret_cast<const char*>(k_ktx2_identifier),
                                                                       sizeof k_ktx2_identifier)) != 0)
        return bad("not a KTX2 file (truncated or wrong identifier)");
    auto field = [&](std::size_t at) { return std::uint32_t(get(bytes, at, 4)); };
    if (field(12) != std::uint32_t(format))
        return bad("holds VkFormat " + std::to_string(field(12)) + ", the manifest says " + block_format_name(format) + " (" +
                   std::to_string(std::uint32_t(format)) + ")");
    if (field(20) != std::uint32_t(width) || field(24) != std::uint32_t(height))
        return bad("is " + std::to_string(field(20)) + "x" + std::to_string(field(24)) + ", the manifest says " +
                   std::to_string(width) + "x" + std::to_string(height));
    if (field(28) != 0 || field(32) != 0 || field(36) != 1) return bad("is not a single 2D image (depth, layers or faces)");
    if (field(40) != std::uint32_t(levels))
        return bad("has " + std::to_string(field(40)) + " mip levels, the manifest says " + std::to_string(levels));
    const std::uint32_t scheme = field(44);
    if (scheme != 0 && scheme != k_ktx2_zlib)
        return bad("supercompression scheme " + std::to_string(scheme) + " is not read (only none and zlib)");
    if (bytes.size() < k_ktx2_header + std::size_t(levels) * k_ktx2_level_entry) return bad("truncated level index");
    BlockImage image;
    image.format = format, image.width = width, image.height = height;
    std::uint64_t total = 0;
    for (int m = 0; m < levels; ++m) {
        const int w = std::max(width >> m, 1), h = std::max(height >> m, 1);
        const std::uint64_t expected = level_bytes(format, w, h);
        total += expected;
        if (expected == 0 || total > k_max_level_bytes * 2)
            return bad("level " + std::to_string(m) + " is too large (" + std::to_string(expected) + " bytes)");
        const std::size_t entry = k_ktx2_header + std::size_t(m) * k_ktx2_level_entry;
        const std::uint64_t offset = get(bytes, entry, 8), length = get(bytes, entry + 8, 8), raw = get(bytes, entry + 16, 8);
        if (offset > bytes.size() || length > bytes.size() - offset)
            return bad("level " + std::to_string(m) + " reaches beyond the end of the file (truncated)");
        if (raw != expected)
            return bad("level " + std::to_string(m) + " holds " + std::to_string(raw) + " bytes, " + block_format_name(format) +
                       " of " + std::to_string(w) + "x" + std::to_string(h) + " needs " + std::to_string(expected));
        std::vector<std::uint8_t> level(expected);
        const auto* source = reinterpret_cast<const Bytef*>(bytes.data() + offset);
        if (scheme == 0) {
            if (length != expected) return bad("level " + std::to_string(m) + " has the wrong length");
            std::copy_n(source, expected, level.data());
        } else {
            uLongf size = uLongf(expected);
            if (uncompress(level.data(), &size, source, uLong(length)) != Z_OK || size != expected)
                return bad("level " + std::to_string(m) + " does not inflate to its " + std::to_string(expected) +
                           " bytes (damaged)");
        }
        image.levels.push_back(std::move(level));
    }
    return image;
}

Status write_blocks(const BlockImage& image, const std::string& directory, const std::string& name, nlohmann::json& files)
{
    STANDIN_RETURN_IF_ERROR(write_file_atomic((fs::path(directory) / name).string(), encode_ktx2(image)));
    return record_file(directory, name, files);
}

BlockImage read_blocks(const Reader& in, const nlohmann::json& files, const std::string& name, BlockFormat format,
                       int width, int height, int levels)
{
    check_file(in, in.directory(), files, name);
    std::string path = (fs::path(in.directory()) / name).string();
    Result<std::string> bytes = read_file(path);
    if (!bytes) throw BadField{bytes.status().message()};
    Result<BlockImage> image = decode_ktx2(*bytes, path, format, width, height, levels);
    if (!image) throw BadField{image.status().message()};
    return std::move(*image);
}

// ------------------------------------------------------------------------------------------------
// Exact channels: grey PNGs. Depth is smooth across a surface, so PNG's per-row filters (libpng's
// adaptive choice among none, sub, up, average and Paeth) leave small residuals for zlib: on the
// held-out engine's billboards 47% of the bytes of the same depth zlib'd raw in a KTX2
// (docs/RESULTS.md, "Depth as grey PNG"). KTX2 has no such filter, and the renderer uploads
// depth as R16 either way, so nothing is lost by leaving the GPU container for it.

Status write_exact_channel(const BlockImage& image, const std::string& directory, const std::string& name,
                           nlohmann::json& files)
{
    if ((image.format != BlockFormat::r8 && image.format != BlockFormat::r16) || image.levels.size() != 1)
        return error(StatusCode::invalid_argument, name + ": only one level of R8 or R16 is written as a grey PNG");
    const bool wide = image.format == BlockFormat::r16;
    const std::vector<std::uint8_t>& bytes = image.levels[0];
    std::vector<std::uint16_t> samples(std::size_t(image.width) * std::size_t(image.height));
    if (bytes.size() != samples.size() * (wide ? 2 : 1))
        return error(StatusCode::invalid_argument, name + ": level size does not match the image");
    for (std::size_t k = 0; k < samples.size(); ++k)
        samples[k] = wide ? std::uint16_t(bytes[2 * k] | (bytes[2 * k + 1] << 8)) : bytes[k];
    Result<std::string> png = encode_png_grey_bytes(image.width, image.height, wide ? 16 : 8, samples);
    if (!png) return error(png.status().code(), name + ": " + png.status().message());
    STANDIN_RETURN_IF_ERROR(write_file_atomic((fs::path(directory) / name).string(), *png));
    return record_file(directory, name, files);
}

BlockImage read_exact_channel(const Reader& in, const nlohmann::json& files, const std::string& name, BlockFormat format,
                              int width, int height)
{
    if (!name.ends_with(".png")) return read_blocks(in, files, name, format, width, height, 1);
    const bool wide = format == BlockFormat::r16;
    const std::string path = checked_png(in, files, name, width, height, wide ? 16 : 8, k_png_color_grey);
    int w = 0, h = 0;
    Result<std::vector<std::uint16_t>> samples = read_png_grey(path, wide ? 16 : 8, &w, &h);
    if (!samples) throw BadField{samples.status().message()};
    if (w != width || h != height || samples->size() != std::size_t(width) * std::size_t(height)) // checked_png saw the header
        throw BadField{quoted(path) + ": decodes to " + std::to_string(w) + "x" + std::to_string(h)};
    BlockImage image{format, width, height, {std::vector<std::uint8_t>(samples->size() * (wide ? 2 : 1))}};
    std::vector<std::uint8_t>& level = image.levels[0];
    for (std::size_t k = 0; k < samples->size(); ++k) {
        const std::uint16_t v = (*samples)[k];
        if (wide) {
            level[2 * k] = std::uint8_t(v & 0xff);
            level[2 * k + 1] = std::uint8_t(v >> 8);
        } else {
            level[k] = std::uint8_t(v);
        }
    }
    return image;
}

std::string gzip_bytes(std::string_view bytes)
{
    z_stream z{};
    // windowBits 15 + 16: a gzip wrapper, whose header zlib writes with mtime 0, no name, OS unix
    if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::bad_alloc();
    std::string out(deflateBound(&z, uLong(bytes.size())), '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    std::size_t in_left = bytes.size(), out_left = out.size();
    int result = Z_OK;
    while (result == Z_OK) { // avail_in and avail_out are 32-bit: feed arrays over 4 GiB in chunks
        const uInt in_chunk = uInt(std::min<std::size_t>(in_left, 1u << 30)), out_chunk = uInt(std::min<std::size_t>(out_left, 1u << 30));
        z.avail_in = in_chunk;
        z.avail_out = out_chunk;
        result = deflate(&z, in_chunk == in_left ? Z_FINISH : Z_NO_FLUSH);
        in_left -= in_chunk - z.avail_in;
        out_left -= out_chunk - z.avail_out;
    }
    deflateEnd(&z);
    if (result != Z_STREAM_END) throw std::bad_alloc(); // deflateBound's buffer always suffices
    out.resize(out.size() - out_left);
    return out;
}

Status write_gzip(std::string_view bytes, const std::string& directory, const std::string& name, nlohmann::json& files)
{
    STANDIN_RETURN_IF_ERROR(write_file_atomic((fs::path(directory) / name).string(), gzip_bytes(bytes)));
    return record_file(directory, name, files);
}

std::string read_gzip(const Reader& in, const nlohmann::json& files, const std::string& name, std::size_t expected)
{
    check_file(in, in.directory(), files, name);
    const std::string path = (fs::path(in.directory()) / name).string();
    Result<std::string> packed = read_file(path);
    if (!packed) throw BadField{packed.status().message()};
    auto bad = [&](const std::string& problem) { return BadField{quoted(path) + ": " + problem}; };
    z_stream z{};
    if (inflateInit2(&z, 15 + 16) != Z_OK) throw std::bad_alloc(); // gzip only
    std::string out;
    out.reserve(std::min<std::size_t>(expected, std::size_t(64) << 20));
    z.next_in = reinterpret_cast<Bytef*>(packed->data());
    std::size_t in_left = packed->size();
    char chunk[1 << 16];
    int result = Z_OK;
    while (result == Z_OK) {
        const uInt in_chunk = uInt(std::min<std::size_t>(in_left, 1u << 30));
        z.avail_in = in_chunk;
        z.next_out = reinterpret_cast<Bytef*>(chunk);
        z.avail_out = sizeof chunk;
        result = inflate(&z, Z_NO_FLUSH);
        in_left -= in_chunk - z.avail_in;
        const std::size_t produced = sizeof chunk - z.avail_out;
        if (out.size() + produced > expected) {
            inflateEnd(&z);
            throw bad("inflates to more than the " + std::to_string(expected) + " bytes the manifest implies");
        }
        out.append(chunk, produced); // Z_BUF_ERROR: the input ended inside the stream (output always has room)
    }
    inflateEnd(&z);
    if (result != Z_STREAM_END) throw bad("is not a complete gzip stream (damaged or truncated)");
    if (in_left != 0) throw bad("has bytes after its gzip stream");
    if (out.size() != expected)
        throw bad("inflates to " + std::to_string(out.size()) + " bytes, the manifest implies " + std::to_string(expected));
    return out;
}

} // namespace standin::manifest_io
