// Representation-independent package handling: bake parameters, source identity, atomic writing
// of package directories and dispatching reads by the manifest's representation.
#include <standin/files.h>
#include <standin/package.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

namespace standin {

namespace fs = std::filesystem;

Result<int> BakeParameters::get_int(const std::string& name, int fallback, int min, int max) const
{
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    used_[name] = true;
    int value = 0;
    const std::string& text = it->second;
    auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        return error(StatusCode::invalid_argument, "--" + name + ": '" + text + "' is not an integer");
    if (value < min || value > max)
        return error(StatusCode::invalid_argument, "--" + name + ": " + text + " is out of range " +
                                                       std::to_string(min) + ".." + std::to_string(max));
    return value;
}

Result<float> BakeParameters::get_float(const std::string& name, float fallback, float min, float max) const
{
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    used_[name] = true;
    const std::string& text = it->second;
    char* end = nullptr;
    float value = std::strtof(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(value))
        return error(StatusCode::invalid_argument, "--" + name + ": '" + text + "' is not a finite number");
    if (value < min || value > max)
        return error(StatusCode::invalid_argument, "--" + name + ": " + text + " is out of range [" +
                                                       std::to_string(min) + ", " + std::to_string(max) + "]");
    return value;
}

Result<std::string> BakeParameters::get_choice(const std::string& name, const std::string& fallback,
                                               const std::vector<std::string>& choices) const
{
    auto it = values_.find(name);
    if (it == values_.end()) return fallback;
    used_[name] = true;
    if (std::find(choices.begin(), choices.end(), it->second) != choices.end()) return it->second;
    std::string list;
    for (const std::string& c : choices) list += (list.empty() ? "" : ", ") + c;
    return error(StatusCode::invalid_argument, "--" + name + ": '" + it->second + "' is not one of " + list);
}

Status BakeParameters::check_all_used(const std::string& representation) const
{
    for (const auto& [name, value] : values_)
        if (!used_.count(name))
            return error(StatusCode::invalid_argument, "--" + name + " does not apply to representation " + representation);
    return Status::ok();
}

Result<SourceInfo> describe_source(const std::string& model_path, const Mesh& mesh)
{
    SourceInfo info;
    info.file_name = fs::path(model_path).filename().string();
    if (!model_path.empty()) {
        Result<std::string> bytes = read_file(model_path);
        if (!bytes) return bytes.status();
        info.content_hash = hex64(hash_bytes(*bytes));
        info.file_bytes = bytes->size();
    }
    info.triangles = mesh.triangle_count();
    info.vertices = mesh.vertex_count();
    info.bounds = mesh.bounds();
    info.surface_area = mesh.surface_area();
    return info;
}

Status write_package(const Package& package, const std::string& directory)
{
    const Representation* representation = find_representation(package.representation());
    assert(representation);
    fs::path final_path = fs::path(directory);
    if (final_path.filename().empty()) final_path = final_path.parent_path();
    std::error_code ec;
    if (fs::exists(final_path, ec) && !fs::is_directory(final_path, ec))
        return error(StatusCode::invalid_argument, final_path.string() + ": exists and is not a package directory");
    if (fs::is_directory(final_path, ec) && !fs::exists(final_path / "manifest.json", ec) && !fs::is_empty(final_path, ec))
        return error(StatusCode::invalid_argument,
                     final_path.string() + ": exists and is not a package (no manifest.json); refusing to replace it");
    std::string temporary = temporary_path_for(final_path.string());
    fs::create_directories(temporary, ec);
    if (ec) return error(StatusCode::io_error, temporary + ": cannot create directory: " + ec.message());
    Status written = representation->write(package, temporary);
    if (!written) {
        fs::remove_all(temporary, ec);
        return written;
    }
    return commit_path(temporary, final_path.string());
}

Result<std::unique_ptr<Package>> read_package(const std::string& directory)
{
    std::error_code ec;
    if (!fs::exists(directory, ec)) return error(StatusCode::not_found, directory + ": no such package");
    if (!fs::is_directory(directory, ec))
        return error(StatusCode::bad_data, directory + ": not a package directory");
    std::string manifest_path = (fs::path(directory) / "manifest.json").string();
    Result<std::string> text = read_file(manifest_path);
    if (!text) return text.status();
    nlohmann::json manifest = nlohmann::json::parse(*text, nullptr, false);
    if (manifest.is_discarded() || !manifest.is_object())
        return error(StatusCode::bad_data, manifest_path + ": not valid JSON");
    if (manifest.value("format", std::string()) != k_package_format)
        return error(StatusCode::bad_data, manifest_path + ": \"format\" is not \"" + std::string(k_package_format) + "\"");
    if (!manifest.contains("version") || !manifest["version"].is_number_integer())
        return error(StatusCode::bad_data, manifest_path + ": missing integer \"version\"");
    int version = manifest["version"].get<int>();
    if (version > k_package_format_version)
        return error(StatusCode::unsupported, manifest_path + ": format version " + std::to_string(version) +
                                                  " is newer than this standin reads (" +
                                                  std::to_string(k_package_format_version) + ")");
    if (version < 1) return error(StatusCode::bad_data, manifest_path + ": bad format version");
    std::string name = manifest.value("representation", std::string());
    const Representation* representation = find_representation(name);
    if (!representation)
        return error(StatusCode::unsupported, manifest_path + ": unknown representation \"" + name + "\"");
    try {
        return representation->read(directory, manifest);
    } catch (const nlohmann::json::exception& e) {
        return error(StatusCode::bad_data, manifest_path + ": " + e.what());
    }
}

Result<std::uint64_t> package_bytes(const std::string& directory)
{
    std::error_code ec;
    std::uint64_t total = 0;
    for (const auto& entry : fs::recursive_directory_iterator(directory, ec))
        if (entry.is_regular_file()) total += entry.file_size();
    if (ec) return error(StatusCode::io_error, directory + ": " + ec.message());
    return total;
}

} // namespace standin
