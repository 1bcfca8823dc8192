// standin bake: a polygon model in, a NAME.standin package directory out (written atomically).
// The representation reads and validates its own parameters; only the options given on the
// command line are passed on, so that each representation applies its own defaults.
#include "commands.h"
#include "common.h"

#include <standin/files.h>
#include <standin/mesh.h>
#include <standin/package.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <utility>
#include <vector>

namespace standin::cli {

struct BakeArgs {
    std::string input;
    std::string output;
    std::string representation = "enhanced-billboards";
    int threads = 0;
    // representation parameters by name, as given (CLI11 leaves untouched strings empty)
    std::vector<std::pair<std::string, std::string>> parameters;
};

static const char* const k_parameter_help[][2] = {
    {"resolution", "Texels along the bounding-box diagonal (default 512, seed)"},
    {"texel-size", "World units per texel, instead of --resolution"},
    {"directions", "Candidate directions: seed (default, 36 x 18), sphere (even Fibonacci set), axis (+-X, +-Y, +-Z)"},
    {"direction-count", "Number of directions of --directions sphere (default 256)"},
    {"score", "Direction score: area (default: area really captured) or faces (seed: facing faces)"},
    {"depth-limit", "Depth of a billboard as a fraction of the bounding-box diagonal (default 1: the whole model)"},
    {"grazing-angle", "Faces within this angle (degrees) of the projection direction are left for another billboard "
                      "(default 10)"},
    {"max-billboards", "Stop after this many billboards (default 64)"},
    {"min-coverage", "Stop when the next billboard would capture less than this fraction of the surface (default 0.001)"},
    {"depth-bits", "Depth precision: 16 (default) or 8 (seed: alpha channel of an 8-bit image)"},
    {"coarse-ratio", "Triangles of the coarse hole-filling mesh relative to the model (default 0.1; 0: none)"},
    // view atlas (seed 003); --resolution is its capture size in pixels (default 256)
    {"layout", "View atlas: icosahedral (default, seed), octahedral or hemi-octahedral view directions"},
    {"subdivisions", "View atlas: icosahedron subdivisions, 20 x 4^k views (default 2 = 320 views, chosen by measurement; seed: 4 = 5120 views)"},
    {"frames", "View atlas: frames per side of the (hemi-)octahedral grid (default 16)"},
    {"projection", "View atlas: ortho (default) or perspective capture at the base distance"},
    {"fov", "View atlas: field of view of perspective captures, degrees (default 40)"},
    {"maps", "View atlas: surface (default: albedo, normal, depth) or lit (seed: shaded colour only)"},
    {"page-size", "View atlas: atlas page size in texels (default 2048)"},
};

static int run_bake(const BakeArgs& args, const std::vector<std::pair<std::string, std::string>>& given)
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
    BakeParameters parameters;
    for (const auto& [name, value] : given) parameters.set(name, value);
    Progress progress = stderr_progress();
    BakeContext context{*mesh, *source, parameters, progress, args.threads};
    Result<std::unique_ptr<Package>> package = representation->bake(context);
    if (!package) return fail(naming_file(package.status(), args.input));
    if (Status s = write_package(**package, output); !s) return fail(s);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    nlohmann::json summary = (*package)->summary();
    Result<std::uint64_t> bytes = package_bytes(output);
    std::string detail;
    if (summary.contains("billboards")) detail += std::to_string(summary["billboards"].get<std::size_t>()) + " billboards, ";
    if (summary.contains("area_captured_fraction"))
        detail += std::to_string(summary["area_captured_fraction"].get<double>() * 100.0).substr(0, 6) + "% of the area captured, ";
    std::fprintf(stderr, "standin: wrote %s (%s%llu bytes, %zu faces, %.2f s)\n", output.c_str(), detail.c_str(),
                 bytes ? static_cast<unsigned long long>(*bytes) : 0ull, mesh->triangle_count(), seconds);
    return k_exit_ok;
}

CommandRun add_bake_command(CLI::App& root)
{
    auto args = std::make_shared<BakeArgs>();
    auto values = std::make_shared<std::vector<std::pair<std::string, CLI::Option*>>>();
    auto strings = std::make_shared<std::vector<std::string>>(std::size(k_parameter_help));
    CLI::App* command = root.add_subcommand(
        "bake", "Bake a polygon model into a NAME.standin package of a representation (default: enhanced "
                "billboards, seed 000 §3.2); written atomically, byte-identical for any thread count");
    command->add_option("model", args->input, "Model file (any format assimp reads)")->required();
    command->add_option("-o,--output", args->output, "Output package directory NAME.standin")->required();
    command->add_option("-r,--representation", args->representation, "Representation to bake")->capture_default_str();
    command->add_option("--threads", args->threads, "Worker threads (0: all cores); results do not depend on it")
        ->capture_default_str();
    for (std::size_t k = 0; k < std::size(k_parameter_help); ++k) {
        std::string name = k_parameter_help[k][0];
        values->push_back({name, command->add_option("--" + name, (*strings)[k], k_parameter_help[k][1])});
    }
    return [args, values, strings] {
        std::vector<std::pair<std::string, std::string>> given;
        for (std::size_t k = 0; k < values->size(); ++k)
            if ((*values)[k].second->count() > 0) given.push_back({(*values)[k].first, (*strings)[k]});
        return run_bake(*args, given);
    };
}

} // namespace standin::cli
