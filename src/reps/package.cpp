// Representation-independent package handling: bake parameters, source identity, atomic writing
// of package directories and dispatching reads by the manifest's representation.
#include "reps/common/package_codec.h"

#include <standin/files.h>
#include <standin/image.h>
#include <standin/limits.h>
#include <standin/package.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <sys/stat.h>

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
    std::string name = quoted(final_path.string());
    // one rule for every output: the folder must exist (nothing is created on the way)
    STANDIN_RETURN_IF_ERROR(check_output_path(final_path.string()));
    std::error_code ec;
    if (fs::exists(final_path, ec) && !fs::is_directory(final_path, ec))
        return error(StatusCode::invalid_argument, name + ": exists and is not a package directory");
    if (fs::is_directory(final_path, ec) && !fs::exists(final_path / "manifest.json", ec) && !fs::is_empty(final_path, ec))
        return error(StatusCode::invalid_argument, name + ": exists and is not a package (no manifest.json); refusing to replace it");
    // temporaries of earlier bakes of this output that were killed half-way
    remove_stale_temporaries(final_path.string());
    std::string temporary = temporary_path_for(final_path.string());
    fs::create_directory(temporary, ec);
    if (ec) return error(StatusCode::io_error, quoted(temporary) + ": cannot create directory: " + ec.message());
    Status written = representation->write(package, temporary);
    if (!written) {
        fs::remove_all(temporary, ec);
        return written;
    }
    return commit_path(temporary, final_path.string());
}

// Every entry of "files", used or not: a plain file name (no separators, no "..", not absolute), a
// regular file inside the package (not a link out of it) of the size recorded, and a PNG declared
// by its name is an RGBA or grey PNG. The codecs check which each file must be, and hashes and what each file must hold.
static Status check_listed_files(const std::string& directory, const nlohmann::json& manifest, const std::string& manifest_path)
{
    if (!manifest.contains("files")) return Status::ok(); // the codec names the missing field
    const nlohmann::json& files = manifest["files"];
    if (!files.is_object()) return error(StatusCode::bad_data, quoted(manifest_path) + ": \"files\" is not an object");
    for (const auto& [name, entry] : files.items()) {
        std::string field = quoted(manifest_path) + ": \"files\" names " + quoted(name);
        if (!manifest_io::is_plain_file_name(name)) return error(StatusCode::bad_data, field + ", which is not a plain file name");
        std::string path = (fs::path(directory) / name).string();
        struct stat link {};
        if (::lstat(path.c_str(), &link) != 0) return error(StatusCode::bad_data, field + ", which is not in the package");
        if (S_ISLNK(link.st_mode))
            return error(StatusCode::bad_data, field + ", which is a symbolic link (package files are plain files)");
        STANDIN_RETURN_IF_ERROR(check_regular_file(path));
        if (!entry.is_object() || !entry.contains("bytes") || !entry["bytes"].is_number_unsigned())
            return error(StatusCode::bad_data, field + " without a byte count");
        if (entry["bytes"].get<std::uint64_t>() != std::uint64_t(link.st_size))
            return error(StatusCode::bad_data, quoted(path) + ": has " + std::to_string(link.st_size) + " bytes, the manifest says " +
                                                   std::to_string(entry["bytes"].get<std::uint64_t>()));
        if (name.size() > 4 && name.compare(name.size() - 4, 4, ".png") == 0) {
            Result<PngInfo> png = read_png_info(path);
            if (!png) return png.status();
            if (png->color_type != k_png_color_rgba && png->color_type != k_png_color_grey)
                return error(StatusCode::bad_data, quoted(path) + ": PNG colour type " + std::to_string(png->color_type) +
                                                       ", package images are RGBA or grey (colour type 6 or 0)");
        }
    }
    return Status::ok();
}

Result<std::unique_ptr<Package>> read_package(const std::string& directory)
{
    Status is_directory = check_directory(directory);
    if (!is_directory) {
        if (is_directory.code() == StatusCode::not_found) return error(StatusCode::not_found, quoted(directory) + ": no such package");
        return is_directory;
    }
    std::string manifest_path = (fs::path(directory) / "manifest.json").string();
    std::error_code ec;
    if (!fs::exists(manifest_path, ec)) { // a folder of packages (a batch bake's output) is named as one
        std::size_t held = 0;
        for (fs::directory_iterator it(directory, ec), end; !ec && it != end && held < 1000; it.increment(ec))
            held += fs::exists(it->path() / "manifest.json", ec);
        if (held > 0)
            return error(StatusCode::not_found, quoted(directory) + ": not a package but a folder of " + std::to_string(held) +
                                                    " (a batch bake's output): name one of them");
        return error(StatusCode::not_found, quoted(directory) + ": not a package (no manifest.json)");
    }
    Result<std::string> text = read_file(manifest_path, k_max_manifest_bytes);
    if (!text) return text.status();
    if (!json_nesting_within(*text, 64)) return error(StatusCode::bad_data, quoted(manifest_path) + ": nested more than 64 levels deep");
    nlohmann::json manifest = nlohmann::json::parse(*text, nullptr, false);
    if (manifest.is_discarded() || !manifest.is_object())
        return error(StatusCode::bad_data, quoted(manifest_path) + ": not valid JSON");
    if (manifest.value("format", std::string()) != k_package_format)
        return error(StatusCode::bad_data, quoted(manifest_path) + ": \"format\" is not \"" + std::string(k_package_format) + "\"");
    if (!manifest.contains("version") || !manifest["version"].is_number_integer())
        return error(StatusCode::bad_data, quoted(manifest_path) + ": missing integer \"version\"");
    std::int64_t version = manifest["version"].get<std::int64_t>();
    if (version > k_package_format_version)
        return error(StatusCode::unsupported, quoted(manifest_path) + ": format version " + std::to_string(version) +
                                                  " is newer than this standin reads (" +
                                                  std::to_string(k_package_format_version) + ")");
    if (version < 1) return error(StatusCode::bad_data, quoted(manifest_path) + ": bad format version");
    std::string name = manifest["representation"].is_string() ? manifest["representation"].get<std::string>() : std::string();
    const Representation* representation = find_representation(name);
    if (!representation)
        return error(StatusCode::unsupported, quoted(manifest_path) + ": unknown representation " + quoted(name));
    STANDIN_RETURN_IF_ERROR(check_listed_files(directory, manifest, manifest_path));
    Result<std::unique_ptr<Package>> package = error(StatusCode::bad_data, quoted(manifest_path) + ": unreadable");
    try {
        package = representation->read(directory, manifest);
    } catch (const nlohmann::json::exception& e) {
        return error(StatusCode::bad_data, quoted(manifest_path) + ": " + one_line(e.what(), 300));
    } catch (const std::bad_alloc&) {
        return error(StatusCode::bad_data, quoted(directory) + ": the package needs more memory than there is (memory budget " +
                                               bytes_text(budget().memory_bytes) + ", STANDIN_MEMORY_LIMIT)");
    } catch (const std::exception& e) {
        return error(StatusCode::bad_data, quoted(directory) + ": " + one_line(e.what(), 300));
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
    // links are not followed (a loop inside a package must not end the process) and not counted
    std::error_code ec;
    std::uint64_t total = 0;
    fs::recursive_directory_iterator it(directory, fs::directory_options::none, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        std::error_code entry_ec;
        if (it->is_regular_file(entry_ec) && !it->is_symlink(entry_ec)) total += it->file_size(entry_ec);
    }
    if (ec) return error(StatusCode::io_error, quoted(directory) + ": " + ec.message());
    return total;
}

} // namespace standin
