// Manifest helpers shared by the package codecs (src/reps/*/package.cpp): both write and validate
// manifest.json the same way (docs/FORMAT.md): the "source" block, files listed with size and
// hash, and typed field readers whose refusals name the manifest and the field.
#pragma once

#include <standin/options.h>
#include <standin/package.h>
#include <standin/status.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace standin::manifest_io {

nlohmann::json vec3_json(glm::vec3 v);
nlohmann::json source_json(const SourceInfo& s);

// "PREFIX_NNN_MAP.png": the name of a numbered image file in a package.
std::string numbered_png(const char* prefix, std::size_t index, const char* map);

// Records the size and hash of the file `name` (already written in `directory`) in `files`.
Status record_file(const std::string& directory, const std::string& name, nlohmann::json& files);

// ------------------------------------------------------------------------------------------------
// Reading: every accessor names the manifest and the field it refuses.

struct BadField {
    std::string message;
};

class Reader {
public:
    // `bounds_in_range_errors`: whether number()'s out-of-range refusal also names [lo, hi].
    Reader(std::string path, bool bounds_in_range_errors)
        : path_(std::move(path)), bounds_in_range_errors_(bounds_in_range_errors)
    {
    }

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

private:
    std::string path_;
    bool bounds_in_range_errors_;
};

SourceInfo read_source(const Reader& in, const nlohmann::json& manifest);

// The "bake" block: every declared bake parameter as used (names with '_' for '-': "texel_size"),
// integers and numbers as JSON numbers, choices as strings, flags as booleans.
nlohmann::json settings_json(const Options& parameters);
// Reads the "bake" block back, checking every value against the same declaration the baker used.
Options read_settings(const Reader& in, const nlohmann::json& manifest, std::span<const OptionSpec> specs);

// Refuses axes that are not unit vectors or not orthogonal (fields named under `where`).
void check_axes(const Reader& in, const std::string& where, glm::vec3 axis_u, glm::vec3 axis_v, glm::vec3 direction);

// Checks a listed file against its recorded size and hash.
void check_file(const Reader& in, const std::string& directory, const nlohmann::json& files, const std::string& name);

} // namespace standin::manifest_io
