// Manifest helpers shared by the package codecs: both write and validate manifest.json the same
// way (docs/FORMAT.md). See manifest.h.
#include "reps/common/package_codec.h"

#include <standin/files.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

nlohmann::json manifest_header(const Package& package, const Options& parameters)
{
    return {{"format", k_package_format},
            {"version", k_package_format_version},
            {"representation", package.representation()},
            {"source", source_json(package.source)},
            {"bake", settings_json(parameters)},
            {"requested", parameters.requested()}};
}

Status write_manifest(const std::string& directory, const nlohmann::json& manifest, int indent)
{
    return write_file_atomic((fs::path(directory) / "manifest.json").string(), manifest.dump(indent) + "\n");
}

// Size and bit depth of a listed PNG against the manifest, before it is decoded.
static std::string checked_png(const Reader& in, const nlohmann::json& files, const std::string& name, int width,
                               int height, int bits)
{
    check_file(in, in.directory(), files, name);
    std::string path = (fs::path(in.directory()) / name).string();
    int w = 0, h = 0;
    Result<int> depth = png_bit_depth(path, &w, &h);
    if (!depth) throw BadField{depth.status().message()};
    if (w != width || h != height)
        throw BadField{quoted(path) + ": is " + std::to_string(w) + "x" + std::to_string(h) + ", the manifest says " +
                       std::to_string(width) + "x" + std::to_string(height)};
    if (*depth != bits)
        throw BadField{quoted(path) + ": has " + std::to_string(*depth) + "-bit samples, the manifest says " + std::to_string(bits)};
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

} // namespace standin::manifest_io
