// standin info: what a model or a NAME.standin package holds, as text or JSON.
#include "commands.h"
#include "common.h"

#include <standin/mesh.h>
#include <standin/package.h>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>

namespace standin::cli {

struct InfoArgs {
    std::string path;
    bool json = false;
};

static nlohmann::json model_info_json(const Mesh& mesh, const ImportReport& report)
{
    Bounds b = mesh.bounds();
    nlohmann::json info;
    info["path"] = report.source_path;
    info["format"] = report.format;
    info["triangles"] = mesh.triangle_count();
    info["vertices"] = mesh.vertex_count();
    info["bounds"] = {{"min", {b.min.x, b.min.y, b.min.z}}, {"max", {b.max.x, b.max.y, b.max.z}}};
    info["surface_area"] = mesh.surface_area();
    info["materials"] = mesh.materials.size();
    info["textures"] = mesh.textures.size();
    info["texture_coordinates"] = mesh.has_texture_coordinates();
    info["meshes_in_scene"] = report.meshes_in_scene;
    info["degenerate_dropped"] = report.degenerate_dropped;
    info["warnings"] = report.warnings;
    return info;
}

// A package: its representation's summary, plus the bytes it takes on disk.
static int run_package_info(const InfoArgs& args)
{
    Result<std::unique_ptr<Package>> package = read_package(args.path);
    if (!package) return fail(package.status());
    PackageSummary summary = summarise_package(**package);
    nlohmann::json info = summary.details;
    info["path"] = args.path;
    if (args.json) {
        std::printf("%s\n", info.dump(2).c_str());
        return k_exit_ok;
    }
    std::printf("%s\n  %s\n", args.path.c_str(), summary.headline.c_str());
    for (const auto& [key, value] : info.items())
        if (key != "path") std::printf("  %-24s %s\n", key.c_str(), value.dump().c_str());
    return k_exit_ok;
}

static int run_info(const InfoArgs& args)
{
    std::error_code ec;
    if (std::filesystem::is_directory(args.path, ec)) return run_package_info(args);
    ImportReport report;
    Result<Mesh> mesh = import_mesh(args.path, &report, k_isolated_import);
    if (!mesh) return fail(mesh.status());
    nlohmann::json info = model_info_json(*mesh, report);
    if (args.json) {
        std::printf("%s\n", info.dump(2).c_str());
        return k_exit_ok;
    }
    Bounds b = mesh->bounds();
    std::printf("%s\n  format      %s\n  triangles   %zu\n  vertices    %zu\n", args.path.c_str(),
                report.format.c_str(), mesh->triangle_count(), mesh->vertex_count());
    std::printf("  bounds      (%g, %g, %g) .. (%g, %g, %g)\n", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z);
    std::printf("  materials   %zu\n  textures    %zu%s\n", mesh->materials.size(), mesh->textures.size(),
                mesh->has_texture_coordinates() ? " (with UVs)" : "");
    for (const std::string& w : report.warnings) std::printf("  warning     %s\n", w.c_str());
    return k_exit_ok;
}

CommandRun add_info_command(CLI::App& root)
{
    auto args = std::make_shared<InfoArgs>();
    CLI::App* command = root.add_subcommand("info", "Summarise a model (triangles, vertices, bounds, materials, "
                                                    "textures, import warnings) or a NAME.standin package");
    command->add_option("path", args->path, "Model file (any format assimp reads) or NAME.standin package directory")->required();
    command->add_flag("--json", args->json, "Print JSON on stdout (keys: triangles, vertices, bounds{min,max}, "
                                            "materials, textures, warnings, ...; for packages: representation, package_bytes and "
                                            "what the representation reports)");
    return [args] { return run_info(*args); };
}

} // namespace standin::cli
