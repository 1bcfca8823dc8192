// standin bake: a polygon model in, a NAME.standin package directory out (written atomically).
// The options come from the representations' declarations (declared_options.h); bake_package
// checks the given ones against the chosen representation, so each applies its own defaults.
#include "commands.h"
#include "common.h"
#include "batch.h"
#include "declared_options.h"

#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <chrono>
#include <cstdio>
#include <memory>

namespace standin::cli {

struct BakeArgs {
    std::vector<std::string> inputs;
    std::string input; // the one model of a single bake
    std::string list;
    std::string shard;
    bool force = false, no_eval = false;
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
    if (is_batch(args.inputs, args.list, args.output)) {
        BatchArgs batch;
        batch.inputs = args.inputs;
        batch.list = args.list;
        batch.output = args.output;
        batch.representation = representation;
        batch.parameters = args.parameters.given();
        batch.threads = args.threads;
        batch.force = args.force;
        batch.evaluate = !args.no_eval;
        if (Status s = parse_shard(args.shard, batch.shard, batch.shards); !s) return fail(s);
        return run_batch(batch);
    }
    if (!args.shard.empty() || args.force || args.no_eval)
        return fail("--shard, --force and --no-eval apply to batches (several models, a folder, --list, or -o FOLDER)");
    std::string output = args.output;
    while (output.size() > 1 && output.back() == '/') output.pop_back();
    if (output.size() < 9 || output.substr(output.size() - 8) != ".standin")
        return fail(args.output + ": name the package NAME.standin");

    if (Status s = check_output_is_not_input(output, {args.input}); !s) return fail(s);

    auto start = std::chrono::steady_clock::now();
    Result<Mesh> mesh = import_mesh(args.input, nullptr, k_isolated_import);
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
    command->add_option("models", args->inputs,
                        "Model files (any format assimp reads) or folders of them; several, a folder or --list bake a batch");
    command->add_option("-o,--output", args->output,
                        "Output package directory NAME.standin, or for a batch the output folder (NAME.standin per "
                        "model, and standin-batch.json)")
        ->required();
    command->add_option("--list", args->list, "Batch: a file naming one model per line (relative to the file; # comments)");
    command->add_option("--shard", args->shard,
                        "Batch: bake only shard I of N (I/N, 0 <= I < N); default from SLURM_ARRAY_TASK_ID and "
                        "SLURM_ARRAY_TASK_COUNT (scripts/slurm/bake-array.sbatch)");
    command->add_flag("--force", args->force, "Batch: bake even the packages that are up to date");
    command->add_flag("--no-eval", args->no_eval, "Batch: do not measure each stand-in against its model at distance 1");
    std::vector<std::string> choices;
    for (const Representation& r : representations()) choices.push_back(r.name);
    command->add_option("-r,--representation", args->representation, "Representation to bake")
        ->check(CLI::IsMember(choices))
        ->capture_default_str();
    command->add_option("--threads", args->threads, "Worker threads (0: all cores); results do not depend on it")
        ->capture_default_str();
    args->parameters.add_to(*command, OptionKind::bake);
    return [args] {
        if (args->inputs.empty() && args->list.empty()) return fail("bake: give a model, a folder of models or --list FILE");
        if (args->inputs.size() == 1) args->input = args->inputs.front();
        return run_bake(*args);
    };
}

} // namespace standin::cli
