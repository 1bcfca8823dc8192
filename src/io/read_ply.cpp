// A PLY reader (ASCII and binary, both byte orders) for import_mesh; read_ply.h says why assimp's
// is not used. Format: Greg Turk, "The PLY Polygon File Format" (1994). The file is read whole;
// every count is checked against the bytes that remain before anything is allocated for it, so a
// corrupt header fails with a status instead of an enormous allocation.
#include "io/read_ply.h"

#include <standin/files.h>
#include <standin/limits.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <string_view>

namespace standin {

enum class PlyType { int8, uint8, int16, uint16, int32, uint32, float32, float64 };
enum class PlyFormat { ascii, binary_little_endian, binary_big_endian };

struct PlyProperty {
    std::string name;
    PlyType type = PlyType::float32;
    bool is_list = false;
    PlyType count_type = PlyType::uint8; // lists only
};

struct PlyElement {
    std::string name;
    std::size_t count = 0;
    std::vector<PlyProperty> properties;
};

struct PlyHeader {
    PlyFormat format = PlyFormat::ascii;
    std::vector<PlyElement> elements;
    std::size_t body_offset = 0;
    std::vector<std::string> warnings;
};

static std::size_t type_size(PlyType type)
{
    switch (type) {
    case PlyType::int8: case PlyType::uint8: return 1;
    case PlyType::int16: case PlyType::uint16: return 2;
    case PlyType::int32: case PlyType::uint32: case PlyType::float32: return 4;
    case PlyType::float64: return 8;
    }
    return 1;
}

static bool parse_type(std::string_view name, PlyType* type)
{
    static const std::pair<std::string_view, PlyType> k_names[] = {
        {"char", PlyType::int8},     {"int8", PlyType::int8},       {"uchar", PlyType::uint8},    {"uint8", PlyType::uint8},
        {"short", PlyType::int16},   {"int16", PlyType::int16},     {"ushort", PlyType::uint16},  {"uint16", PlyType::uint16},
        {"int", PlyType::int32},     {"int32", PlyType::int32},     {"uint", PlyType::uint32},    {"uint32", PlyType::uint32},
        {"float", PlyType::float32}, {"float32", PlyType::float32}, {"double", PlyType::float64}, {"float64", PlyType::float64},
    };
    for (const auto& [n, t] : k_names)
        if (n == name) {
            *type = t;
            return true;
        }
    return false;
}

static std::vector<std::string_view> split_words(std::string_view line)
{
    std::vector<std::string_view> words;
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
        std::size_t start = i;
        while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
        if (i > start) words.push_back(line.substr(start, i - start));
    }
    return words;
}

// ---------------------------------------------------------------------------------------------
// Header

static std::string joined(const std::vector<std::string_view>& words)
{
    std::string line;
    for (std::string_view w : words) {
        if (!line.empty()) line += ' ';
        line.append(w);
    }
    return one_line(line, 80);
}

static Status parse_header_line(const std::vector<std::string_view>& words, PlyHeader& header, bool* has_format)
{
    std::string_view keyword = words[0];
    if (keyword == "comment" || keyword == "obj_info") return Status::ok();
    if (keyword == "format" && words.size() >= 2) {
        if (words[1] == "ascii") header.format = PlyFormat::ascii;
        else if (words[1] == "binary_little_endian") header.format = PlyFormat::binary_little_endian;
        else if (words[1] == "binary_big_endian") header.format = PlyFormat::binary_big_endian;
        else return error(StatusCode::unsupported, "unknown format '" + one_line(words[1], 40) + "'");
        *has_format = true;
        return Status::ok();
    }
    if (keyword == "element" && words.size() == 3) {
        PlyElement element;
        element.name = words[1];
        auto [end, ec] = std::from_chars(words[2].data(), words[2].data() + words[2].size(), element.count);
        if (ec != std::errc() || end != words[2].data() + words[2].size())
            return error(StatusCode::bad_data, "element '" + one_line(element.name, 40) + "' has a bad count '" + one_line(words[2], 40) + "'");
        header.elements.push_back(std::move(element));
        return Status::ok();
    }
    if (keyword == "property" && !header.elements.empty()) {
        PlyProperty property;
        bool ok = false;
        if (words.size() == 5 && words[1] == "list") {
            property.is_list = true;
            property.name = words[4];
            ok = parse_type(words[2], &property.count_type) && parse_type(words[3], &property.type);
        } else if (words.size() == 3) {
            property.name = words[2];
            ok = parse_type(words[1], &property.type);
        }
        if (ok) {
            header.elements.back().properties.push_back(std::move(property));
            return Status::ok();
        }
    }
    if (keyword == "format" || keyword == "element" || keyword == "property")
        return error(StatusCode::unsupported, "header line '" + joined(words) + "' is not understood");
    // an unknown keyword: a comment without "comment" (Blender 2.4's "Created by Blender3D ...")
    header.warnings.push_back("header line '" + joined(words) + "' taken as a comment");
    return Status::ok();
}

static Result<PlyHeader> parse_header(std::string_view bytes)
{
    PlyHeader header;
    bool has_format = false, first = true;
    std::size_t pos = 0;
    // the file is in memory: a header without end_header ends at the end of the bytes, not in a loop
    while (pos < bytes.size()) {
        std::size_t newline = bytes.find('\n', pos);
        if (newline == std::string_view::npos) break;
        std::string_view line = bytes.substr(pos, newline - pos);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        pos = newline + 1; // binary bodies start right after end_header's '\n', whatever byte that is
        if (first) {
            if (line != "ply") return error(StatusCode::bad_data, "does not start with 'ply'");
            first = false;
            continue;
        }
        std::vector<std::string_view> words = split_words(line);
        if (words.empty()) continue;
        if (words[0] == "end_header") {
            if (!has_format) return error(StatusCode::bad_data, "header has no format line");
            header.body_offset = pos;
            return header;
        }
        STANDIN_RETURN_IF_ERROR(parse_header_line(words, header, &has_format));
    }
    return error(StatusCode::bad_data, first ? "does not start with 'ply'" : "header has no end_header line");
}

// ---------------------------------------------------------------------------------------------
// Body

// Reads values one at a time as doubles (exact for every PLY integer type).
class PlyBody {
public:
    PlyBody(std::string_view bytes, PlyFormat format) : bytes_(bytes), format_(format) {}

    std::size_t remaining() const { return bytes_.size() - pos_; }

    // False at the end of the data or on text that is not a number.
    bool read(PlyType type, double* value)
    {
        if (format_ == PlyFormat::ascii) return read_ascii(value);
        switch (type) {
        case PlyType::int8: return read_binary<std::int8_t>(value);
        case PlyType::uint8: return read_binary<std::uint8_t>(value);
        case PlyType::int16: return read_binary<std::int16_t>(value);
        case PlyType::uint16: return read_binary<std::uint16_t>(value);
        case PlyType::int32: return read_binary<std::int32_t>(value);
        case PlyType::uint32: return read_binary<std::uint32_t>(value);
        case PlyType::float32: return read_binary<float>(value);
        case PlyType::float64: return read_binary<double>(value);
        }
        return false;
    }

private:
    template <typename T>
    bool read_binary(double* value)
    {
        if (remaining() < sizeof(T)) return false;
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, bytes_.data() + pos_, sizeof(T));
        pos_ += sizeof(T);
        // the host is little-endian (static_assert in mesh.cpp's writer)
        if (format_ == PlyFormat::binary_big_endian) std::reverse(raw, raw + sizeof(T));
        T typed;
        std::memcpy(&typed, raw, sizeof(T));
        *value = double(typed);
        return true;
    }

    bool read_ascii(double* value)
    {
        auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
        while (pos_ < bytes_.size() && is_space(bytes_[pos_])) ++pos_;
        std::size_t end = pos_;
        while (end < bytes_.size() && !is_space(bytes_[end])) ++end;
        if (end == pos_) return false;
        const char* first = bytes_.data() + pos_;
        if (*first == '+') ++first; // from_chars does not take a plus sign
        auto [stop, ec] = std::from_chars(first, bytes_.data() + end, *value);
        pos_ = end;
        return ec == std::errc() && stop == bytes_.data() + end;
    }

    std::string_view bytes_;
    PlyFormat format_;
    std::size_t pos_ = 0;
};

// Fewest bytes one instance of the element can take, to check counts against the file size.
static std::size_t min_instance_bytes(const PlyElement& element, PlyFormat format)
{
    std::size_t bytes = 0;
    for (const PlyProperty& p : element.properties)
        bytes += format == PlyFormat::ascii ? 2 : type_size(p.is_list ? p.count_type : p.type);
    return bytes;
}

static constexpr double k_max_list_length = 1 << 16;

// One instance: scalars into values[property], the items of property `wanted_list` into `list`.
static Status read_instance(PlyBody& body, const PlyElement& element, int wanted_list, std::vector<double>& values,
                            std::vector<double>& list)
{
    auto truncated = [&] { return error(StatusCode::bad_data, "element '" + element.name + "' is truncated or malformed"); };
    for (std::size_t p = 0; p < element.properties.size(); ++p) {
        const PlyProperty& property = element.properties[p];
        if (!property.is_list) {
            if (!body.read(property.type, &values[p])) return truncated();
            continue;
        }
        double length = 0;
        if (!body.read(property.count_type, &length)) return truncated();
        if (!(length >= 0 && length <= k_max_list_length) || length != std::floor(length))
            return error(StatusCode::bad_data, "element '" + element.name + "' has a list of length " + std::to_string(length));
        bool keep = int(p) == wanted_list;
        if (keep) list.resize(std::size_t(length));
        for (std::size_t i = 0; i < std::size_t(length); ++i) {
            double item = 0;
            if (!body.read(property.type, &item)) return truncated();
            if (keep) list[i] = item;
        }
    }
    return Status::ok();
}

static int find_property(const PlyElement& element, std::initializer_list<std::string_view> names, bool list = false)
{
    for (std::string_view name : names)
        for (std::size_t p = 0; p < element.properties.size(); ++p)
            if (element.properties[p].name == name && element.properties[p].is_list == list) return int(p);
    return -1;
}

// Integer colour channels are fractions of their type's maximum; float channels are taken as is.
static double color_scale(PlyType type)
{
    switch (type) {
    case PlyType::uint8: return 1.0 / 255.0;
    case PlyType::int8: return 1.0 / 127.0;
    case PlyType::uint16: return 1.0 / 65535.0;
    case PlyType::int16: return 1.0 / 32767.0;
    case PlyType::uint32: return 1.0 / 4294967295.0;
    case PlyType::int32: return 1.0 / 2147483647.0;
    default: return 1.0;
    }
}

static Status read_vertices(PlyBody& body, const PlyElement& element, PlyData& ply)
{
    int x = find_property(element, {"x"}), y = find_property(element, {"y"}), z = find_property(element, {"z"});
    if (x < 0 || y < 0 || z < 0) return error(StatusCode::bad_data, "vertex element has no x, y and z");
    int nx = find_property(element, {"nx"}), ny = find_property(element, {"ny"}), nz = find_property(element, {"nz"});
    int r = find_property(element, {"red", "diffuse_red", "r"}), g = find_property(element, {"green", "diffuse_green", "g"}),
        b = find_property(element, {"blue", "diffuse_blue", "b"}), a = find_property(element, {"alpha", "diffuse_alpha", "a"});
    int u = find_property(element, {"s", "u", "texture_u", "texture_s"}), v = find_property(element, {"t", "v", "texture_v", "texture_t"});
    bool has_normals = nx >= 0 && ny >= 0 && nz >= 0, has_colors = r >= 0 && g >= 0 && b >= 0, has_uvs = u >= 0 && v >= 0;

    ply.positions.resize(element.count);
    if (has_normals) ply.normals.resize(element.count);
    if (has_colors) ply.colors.resize(element.count);
    if (has_uvs) ply.uvs.resize(element.count);
    auto scale = [&](int p) { return p >= 0 ? color_scale(element.properties[std::size_t(p)].type) : 1.0; };
    double sr = scale(r), sg = scale(g), sb = scale(b), sa = scale(a);
    std::vector<double> values(element.properties.size()), unused;
    for (std::size_t i = 0; i < element.count; ++i) {
        STANDIN_RETURN_IF_ERROR(read_instance(body, element, -1, values, unused));
        ply.positions[i] = glm::vec3(values[std::size_t(x)], values[std::size_t(y)], values[std::size_t(z)]);
        if (has_normals) ply.normals[i] = glm::vec3(values[std::size_t(nx)], values[std::size_t(ny)], values[std::size_t(nz)]);
        if (has_colors)
            ply.colors[i] = glm::vec4(values[std::size_t(r)] * sr, values[std::size_t(g)] * sg, values[std::size_t(b)] * sb,
                                      a >= 0 ? values[std::size_t(a)] * sa : 1.0);
        if (has_uvs) ply.uvs[i] = glm::vec2(values[std::size_t(u)], values[std::size_t(v)]);
    }
    return Status::ok();
}

static Status read_faces(PlyBody& body, const PlyElement& element, PlyData& ply)
{
    int corners = find_property(element, {"vertex_indices", "vertex_index"}, true);
    if (corners < 0) return error(StatusCode::bad_data, "face element has no vertex_indices list");
    ply.triangles.reserve(ply.triangles.size() + element.count * 3);
    std::vector<double> values(element.properties.size()), list;
    const std::uint64_t max_triangles = budget().max_triangles;
    for (std::size_t f = 0; f < element.count; ++f) {
        STANDIN_RETURN_IF_ERROR(read_instance(body, element, corners, values, list));
        // polygons of 65,535 corners fan into billions of triangles: the budget counts as they come
        if (list.size() >= 3 && ply.triangles.size() / 3 + (list.size() - 2) > max_triangles)
            return error(StatusCode::bad_data, "has more than " + std::to_string(max_triangles) + " triangles once face " +
                                                   std::to_string(f) + "'s polygons are fanned (STANDIN_MAX_TRIANGLES raises the limit)");
        for (double index : list)
            if (!(index >= 0 && index <= double(std::numeric_limits<std::uint32_t>::max())) || index != std::floor(index))
                return error(StatusCode::bad_data, "face " + std::to_string(f) + " has a bad vertex index");
        if (list.size() < 3) {
            ++ply.skipped_faces;
            continue;
        }
        // PLY polygons are convex in practice: a fan around the first corner
        for (std::size_t k = 1; k + 1 < list.size(); ++k)
            ply.triangles.insert(ply.triangles.end(), {std::uint32_t(list[0]), std::uint32_t(list[k]), std::uint32_t(list[k + 1])});
    }
    return Status::ok();
}

static Status read_body(const PlyHeader& header, std::string_view bytes, PlyData& ply)
{
    PlyBody body(bytes.substr(header.body_offset), header.format);
    bool has_vertices = false;
    for (const PlyElement& element : header.elements) {
        if (element.properties.empty() && element.count > 0)
            return error(StatusCode::bad_data, "element '" + one_line(element.name, 40) + "' declares " + std::to_string(element.count) +
                                                   " instances but no properties");
        if (element.properties.empty()) continue;
        // + 1: the last ASCII number needs no separator after it
        if (element.count > (body.remaining() + 1) / std::max<std::size_t>(1, min_instance_bytes(element, header.format)))
            return error(StatusCode::bad_data, "declares " + std::to_string(element.count) + " " + element.name +
                                                   " elements but only " + std::to_string(body.remaining()) + " bytes follow");
        std::vector<double> values(element.properties.size()), unused;
        if (element.name == "vertex" && !has_vertices) {
            STANDIN_RETURN_IF_ERROR(read_vertices(body, element, ply));
            has_vertices = true;
        } else if (element.name == "face") {
            STANDIN_RETURN_IF_ERROR(read_faces(body, element, ply));
        } else {
            for (std::size_t i = 0; i < element.count; ++i) STANDIN_RETURN_IF_ERROR(read_instance(body, element, -1, values, unused));
        }
    }
    if (!has_vertices) return error(StatusCode::bad_data, "has no vertex element");
    for (std::size_t i = 0; i < ply.triangles.size(); ++i)
        if (ply.triangles[i] >= ply.positions.size())
            return error(StatusCode::bad_data, "face refers to vertex " + std::to_string(ply.triangles[i]) + " of " +
                                                   std::to_string(ply.positions.size()));
    return Status::ok();
}

// Whether the vertex colours are stored as floating point (0..1 by convention, 0..255 by some tools).
static bool float_colors(const PlyHeader& header)
{
    for (const PlyElement& element : header.elements)
        if (element.name == "vertex") {
            int red = find_property(element, {"red", "diffuse_red", "r"});
            if (red < 0) return false;
            PlyType type = element.properties[std::size_t(red)].type;
            return type == PlyType::float32 || type == PlyType::float64;
        }
    return false;
}

// Colours into [0, 1]: float colours above 1 were written as 0..255; values outside are clamped and
// non-finite ones made white, each with a warning rather than a refusal.
static void normalise_colors(PlyData& ply, bool float_channels, const std::string& name)
{
    if (ply.colors.empty()) return;
    bool finite = true;
    float largest = 0.0f;
    for (const glm::vec4& c : ply.colors)
        for (int k = 0; k < 4; ++k) {
            if (!std::isfinite(c[k])) finite = false;
            else largest = std::max(largest, c[k]);
        }
    float scale = float_channels && largest > 1.0f && largest <= 255.0f ? 1.0f / 255.0f : 1.0f;
    if (scale != 1.0f) ply.warnings.push_back(name + ": float colours above 1 taken as 0..255");
    if (!finite) ply.warnings.push_back(name + ": non-finite colours made white");
    if (largest * scale > 1.0f) ply.warnings.push_back(name + ": colours above 1 clamped");
    for (glm::vec4& c : ply.colors)
        for (int k = 0; k < 4; ++k) c[k] = std::isfinite(c[k]) ? std::clamp(c[k] * scale, 0.0f, 1.0f) : 1.0f;
}

Result<PlyData> read_ply(const std::string& path)
{
    Result<std::string> bytes = read_file(path);
    if (!bytes) return bytes.status();
    Result<PlyHeader> header = parse_header(*bytes);
    if (!header) return error(header.status().code(), quoted(path) + ": " + header.status().message());
    PlyData ply;
    for (const std::string& warning : header->warnings) ply.warnings.push_back(quoted(path) + ": " + warning);
    Status body = read_body(*header, *bytes, ply);
    if (!body.is_ok()) return error(body.code(), quoted(path) + ": " + body.message());
    normalise_colors(ply, float_colors(*header), quoted(path));
    return ply;
}

} // namespace standin
