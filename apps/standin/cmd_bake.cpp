// standin bake: a polygon model in, a NAME.standin package directory out (written atomically).
// The options come from the representations' declarations (declared_options.h); bake_package
// checks the given ones against the chosen representation, so each applies its own defaults.
#include "commands.h"
#include "common.h"
#include "declared_options.h"

#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <chrono>
#include <cstdio>
#include <memory>

namespace standin::cli {

struct BakeArgs {
    std::string input;
    std::string output;
    std::string representation = representations().front().name; // the registry's first is the default
    int threads = 0;
    DeclaredOptions parameters;
};

static int run_bake(const BakeArgs& args)
{
    const Representation* representation = find_representation(args.representation);
    if (!representation) return fail("-r: unknown representation '" + args.representation + "'");
    if (args.threads < 0) return fail("--threads: must be 0 (all cores) or more");
    std::string output = args.output;
    while (output.size() > 1 && output.back() == '/') output.pop_back();
    if (output.size() < 9 || output.substr(output.size() - 8) != ".standin")
        return fail(args.output + ": name the package NAME.standin");

    if (Status s = check_output_is_not_input(output, {args.input}); !s) return fail(s);

    auto start = std::chrono::steady_clock::now();
    Result<Mesh> mesh = import_mesh(args.input);
    if (!mesh) return fail(mesh.status());
    Result<SourceInfo> source = describe_source(args.input, *mesh);
    if (!source) return fail(source.status());
    Result<std::unique_ptr<Package>> package =
        bake_package(*representation, *mesh, *source, args.parameters.given(), stderr_progress(), args.threads);
    if (!package) return fail(naming_file(package.status(), args.input));
    if (Status s = write_package(**package, output); !s) return fail(s);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    Result<std::uint64_t> bytes = package_bytes(output);
    char line[160];
    std::snprintf(line, sizeof line, " (%llu bytes, %zu faces, %.2f s)", bytes ? static_cast<unsigned long long>(*bytes) : 0ull,
                  mesh->triangle_count(), seconds);
    note("wrote " + output + ": " + summarise_package(**package).headline + line);
    return k_exit_ok;
}

CommandRun add_bake_command(CLI::App& root)
{
    auto args = std::make_shared<BakeArgs>();
    std::string names;
    for (const Representation& r : representations())
        names += "\n  " + r.name + ": " + r.description + " (" + r.reference + ")";
    CLI::App* command = root.add_subcommand(
        "bake", "Bake a polygon model into a NAME.standin package of a representation; written atomically, "
                "byte-identical for any thread count. Representations:" + names);
    command->add_option("model", args->input, "Model file (any format assimp reads)")->required();
    command->add_option("-o,--output", args->output, "Output package directory NAME.standin")->required();
    std::vector<std::string> choices;
    for (const Representation& r : representations()) choices.push_back(r.name);
    command->add_option("-r,--representation", args->representation, "Representation to bake")
        ->check(CLI::IsMember(choices))
        ->capture_default_str();
    command->add_option("--threads", args->threads, "Worker threads (0: all cores); results do not depend on it")
        ->capture_default_str();
    args->parameters.add_to(*command, OptionKind::bake);
    return [args] { return run_bake(*args); };
}

} // namespace standin::cli
