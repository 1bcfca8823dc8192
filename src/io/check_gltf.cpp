// glTF checks assimp leaves out (check_gltf.h): the JSON part of a .gltf or .glb is read with the
// same limits as every file from outside, and each mesh primitive's attribute accessors are checked
// to exist and to agree on their vertex count before assimp imports the file.
#include "io/check_gltf.h"

#include <standin/files.h>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>

namespace standin {

// The JSON chunk of a binary glTF (magic, version, length; then chunks of length, type, data).
static Result<std::string> glb_json(const std::string& bytes, const std::string& name)
{
    auto u32 = [&](std::size_t at) {
        std::uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0 || bytes.compare(16, 4, "JSON") != 0)
        return error(StatusCode::bad_data, name + ": not a binary glTF (no glTF header and JSON chunk)");
    std::uint32_t length = u32(12);
    if (length > bytes.size() - 20) return error(StatusCode::bad_data, name + ": JSON chunk runs past the end of the file");
    return bytes.substr(20, length);
}

Status check_gltf_accessors(const std::string& path, const std::string& extension)
{
    if (extension != "gltf" && extension != "glb") return Status::ok();
    std::string name = quoted(path);
    Result<std::string> bytes = read_file(path);
    if (!bytes) return bytes.status();
    std::string text = *bytes;
    if (extension == "glb") {
        Result<std::string> json = glb_json(*bytes, name);
        if (!json) return json.status();
        text = std::move(*json);
    }
    if (!json_nesting_within(text, 64)) return error(StatusCode::bad_data, name + ": JSON nested more than 64 levels deep");
    nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return Status::ok(); // assimp says what is wrong
    const nlohmann::json& accessors = doc.contains("accessors") ? doc["accessors"] : nlohmann::json::array();
    const nlohmann::json& meshes = doc.contains("meshes") ? doc["meshes"] : nlohmann::json::array();
    if (!accessors.is_array() || !meshes.is_array()) return Status::ok();
    auto count_of = [&](const nlohmann::json& index, std::int64_t* count) {
        if (!index.is_number_unsigned() || index.get<std::uint64_t>() >= accessors.size()) return false;
        const nlohmann::json& accessor = accessors[index.get<std::size_t>()];
        if (!accessor.is_object() || !accessor.contains("count") || !accessor["count"].is_number_unsigned()) return false;
        *count = accessor["count"].get<std::int64_t>();
        return true;
    };
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        if (!meshes[m].is_object() || !meshes[m].contains("primitives") || !meshes[m]["primitives"].is_array()) continue;
        const nlohmann::json& primitives = meshes[m]["primitives"];
        for (std::size_t p = 0; p < primitives.size(); ++p) {
            std::string where = name + ": meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
            if (!primitives[p].is_object() || !primitives[p].contains("attributes")) continue;
            const nlohmann::json& attributes = primitives[p]["attributes"];
            if (!attributes.is_object()) return error(StatusCode::bad_data, where + ".attributes is not an object");
            std::int64_t vertices = -1;
            std::string first;
            for (const auto& [attribute, index] : attributes.items()) {
                std::int64_t count = 0;
                if (!count_of(index, &count))
                    return error(StatusCode::bad_data, where + ": attribute " + quoted(attribute) + " refers to no valid accessor");
                if (vertices < 0) {
                    vertices = count;
                    first = attribute;
                } else if (count != vertices) {
                    return error(StatusCode::bad_data, where + ": attribute " + quoted(attribute) + " has " + std::to_string(count) +
                                                           " entries, " + quoted(first) + " has " + std::to_string(vertices));
                }
            }
            std::int64_t indices = 0;
            if (primitives[p].contains("indices") && !count_of(primitives[p]["indices"], &indices))
                return error(StatusCode::bad_data, where + ": indices refer to no valid accessor");
        }
    }
    return Status::ok();
}

} // namespace standin
