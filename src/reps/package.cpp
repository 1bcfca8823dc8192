// Representation-independent package handling: bake parameters, source identity, atomic writing
// of package directories and dispatching reads by the manifest's representation.
#include <standin/files.h>
#include <standin/package.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>

namespace standin {

namespace fs = std::filesystem;

const Representation& representation_of(const Package& package)
{
    const Representation* representation = find_representation(package.representation());
    assert(representation && "every package's representation is registered");
    return *representation;
}

Result<std::unique_ptr<Package>> bake_package(const Representation& representation, const Mesh& mesh,
                                              const SourceInfo& source, const OptionValues& parameters,
                                              const Progress& progress, int threads)
{
    Result<Options> options = Options::parse(representation.bake_options, parameters, representation.name);
    if (!options) return options.status();
    if (threads < 0) return error(StatusCode::invalid_argument, "--threads: must be 0 (all cores) or more");
    BakeContext context{mesh, source, *options, progress, threads};
    return representation.bake(context);
}

Result<std::unique_ptr<Renderer>> make_package_renderer(const Package& package, const RenderOptions& options)
{
    const Representation& representation = representation_of(package);
    std::string owner = representation.name + " packages";
    Result<Options> parsed = Options::parse(representation.render_options, options.values, owner);
    if (!parsed) return parsed.status();
    const auto& views = representation.debug_views;
    if (options.debug_view != DebugView::none && std::find(views.begin(), views.end(), options.debug_view) == views.end())
        return error(StatusCode::invalid_argument,
                     std::string("--debug-view ") + debug_view_name(options.debug_view) + ": not drawn for " + owner);
    return representation.make_renderer(package, RenderSettings{std::move(*parsed), options.debug_view});
}

PackageSummary summarise_package(const Package& package)
{
    PackageSummary summary = representation_of(package).summarise(package);
    summary.details["representation"] = package.representation();
    summary.details["package_bytes"] = package.package_bytes;
    return summary;
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
    Result<std::unique_ptr<Package>> package = error(StatusCode::bad_data, manifest_path + ": unreadable");
    try {
        package = representation->read(directory, manifest);
    } catch (const nlohmann::json::exception& e) {
        return error(StatusCode::bad_data, manifest_path + ": " + e.what());
    }
    if (!package) return package.status();
    Result<std::uint64_t> bytes = package_bytes(directory);
    if (!bytes) return bytes.status();
    (*package)->directory = directory;
    (*package)->package_bytes = *bytes;
    return package;
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
