// standin generate: procedural test meshes (sphere, torus, noisy sphere, shrub, fur ball, tree,
// bush, assembly) up to millions of faces; PLY, or glTF (what the tree's textured, alpha-masked leaves need).
#include "commands.h"
#include "common.h"

#include <standin/assembly.h>
#include <standin/mesh.h>

#include <cstdio>
#include <map>
#include <memory>

namespace standin::cli {

struct GenerateArgs {
    std::string shape = "sphere";
    std::size_t triangles = 20000;
    float radius = 1.0f;
    float noise = 0.08f;
    std::uint32_t seed = 1;
    bool sheets = false;
    std::string output;
};

static int run_generate(const GenerateArgs& args)
{
    static const std::map<std::string, GeneratedShape> shapes = {
        {"sphere", GeneratedShape::sphere}, {"torus", GeneratedShape::torus}, {"noisy-sphere", GeneratedShape::noisy_sphere},
        {"shrub", GeneratedShape::shrub}, {"fur-ball", GeneratedShape::fur_ball},
        {"tree", GeneratedShape::tree}, {"bush", GeneratedShape::bush}};
    Result<Mesh> mesh = Mesh{};
    if (args.sheets && args.shape != "assembly") return fail("--sheets: applies to the assembly only");
    if (args.shape == "assembly") {
        mesh = generate_assembly(args.triangles, args.radius, args.sheets);
    } else {
        GenerateOptions options;
        options.shape = shapes.at(args.shape);
        options.target_triangles = args.triangles;
        options.radius = args.radius;
        options.noise_amplitude = args.noise;
        options.seed = args.seed;
        mesh = generate_mesh(options);
    }
    if (!mesh) return fail(mesh.status());
    auto ends_with = [&](const std::string& tail) {
        return args.output.size() > tail.size() && args.output.compare(args.output.size() - tail.size(), tail.size(), tail) == 0;
    };
    bool gltf = ends_with(".gltf");
    if (!gltf && !ends_with(".ply")) return fail(args.output + ": generate writes PLY or glTF, name the output *.ply or *.gltf");
    if (!gltf && !mesh->textures.empty())
        return fail(args.output + ": PLY keeps no textures (the " + args.shape + "'s leaves are a texture), name the output *.gltf");
    Status written = gltf ? write_gltf(*mesh, args.output) : write_ply(*mesh, args.output);
    if (!written) return fail(written);
    std::fprintf(stderr, "standin: wrote %s (%zu triangles, %zu vertices)\n", args.output.c_str(),
                 mesh->triangle_count(), mesh->vertex_count());
    return k_exit_ok;
}

CommandRun add_generate_command(CLI::App& root)
{
    auto args = std::make_shared<GenerateArgs>();
    CLI::App* command = root.add_subcommand(
        "generate", "Write a procedural test mesh as PLY or glTF: a sphere, a torus, a sphere with a noisy radius, a shrub "
                    "(branches and leaf cards), a fur ball (hair ribbons), a tree (alpha-masked leaf cards; write .gltf), a bush (crossed cards each carrying a cluster of alpha-masked leaves, as game foliage is made; .gltf) or a mechanical assembly (59 nested parts) of a chosen triangle count (for tests and scale "
                    "benchmarks up to millions of faces)");
    command->add_option("shape", args->shape, "sphere | torus | noisy-sphere | shrub | fur-ball | tree | bush | assembly")
        ->check(CLI::IsMember({"sphere", "torus", "noisy-sphere", "shrub", "fur-ball", "tree", "bush", "assembly"}))
        ->required();
    command->add_option("-o,--output", args->output, "Output file (.ply, or .gltf: the textures embedded)")->required();
    command->add_option("-t,--triangles", args->triangles, "Approximate triangle count")->capture_default_str();
    command->add_option("--radius", args->radius, "Radius")->capture_default_str();
    command->add_option("--noise", args->noise, "noisy-sphere: displacement amplitude relative to the radius")
        ->capture_default_str();
    command->add_option("--seed", args->seed, "noisy-sphere, shrub, fur-ball, tree, bush: random seed")->capture_default_str();
    command->add_flag("--sheets", args->sheets,
                      "assembly: casing, liners and flanges as zero-thickness sheets, some parts inside out (CAD "
                      "sheet-metal exports)");
    return [args] { return run_generate(*args); };
}

} // namespace standin::cli
