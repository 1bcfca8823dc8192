// standin export: a package to a binary glTF 2.0 file engines and viewers load (export.h,
// docs/FORMAT.md "Export"). The options come from the representations' export declarations.
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/export.h>
#include <standin/files.h>
#include <standin/package.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace standin::cli {

struct ExportArgs {
    std::string package;
    std::string output;
    DeclaredOptions options;
};

static int run_export(const ExportArgs& args)
{
    if (args.output.size() < 5 || args.output.substr(args.output.size() - 4) != ".glb")
        return fail(quoted(args.output) + ": output must be a .glb file");
    if (Status s = check_output_path(args.output); !s) return fail(s);
    if (Status s = check_output_is_not_input(args.output, {args.package}); !s) return fail(s);
    if (Status s = check_directory(args.package); !s) return fail(s);
    auto start = std::chrono::steady_clock::now();
    Result<std::unique_ptr<Package>> package = read_package(args.package);
    if (!package) return fail(package.status());
    ExportScene scene;
    if (Status s = export_package(**package, args.options.given(), args.output, &scene); !s)
        return fail(naming_file(s, args.package));
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    for (const std::string& line : scene.notes) note(line);
    std::error_code ec;
    std::uint64_t bytes = std::filesystem::file_size(args.output, ec);
    char line[300];
    std::snprintf(line, sizeof line, "wrote %s (%zu mesh%s, %zu texture%s, %.2f MiB; %.2f MiB on the GPU) in %.2f s",
                  quoted(args.output).c_str(), scene.meshes.size(), scene.meshes.size() == 1 ? "" : "es",
                  scene.textures.size(), scene.textures.size() == 1 ? "" : "s",
                  double(bytes) / (1 << 20), double(scene.gpu_bytes) / (1 << 20), seconds);
    note(line);
    return k_exit_ok;
}

CommandRun add_export_command(CLI::App& root)
{
    auto args = std::make_shared<ExportArgs>();
    CLI::App* command = root.add_subcommand("export", "Export a NAME.standin package to binary glTF 2.0 (.glb): its proxy "
                                                      "geometry in the model's object space, its textures as PNG, and in "
                                                      "extras what a shader needs (docs/FORMAT.md, \"Export\")");
    command->add_option("package", args->package, "NAME.standin package directory")->required();
    command->add_option("-o,--output", args->output, "Output .glb file (written under a temporary name, then renamed)")->required();
    args->options.add_to(*command, OptionKind::export_);
    return [args] { return run_export(*args); };
}

} // namespace standin::cli
