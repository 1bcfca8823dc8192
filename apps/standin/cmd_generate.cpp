// standin generate: procedural test meshes (sphere, torus, noisy sphere, shrub, fur ball, assembly) up to
// millions of faces.
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
    std::string output;
};

static int run_generate(const GenerateArgs& args)
{
    static const std::map<std::string, GeneratedShape> shapes = {
        {"sphere", GeneratedShape::sphere}, {"torus", GeneratedShape::torus}, {"noisy-sphere", GeneratedShape::noisy_sphere},
        {"shrub", GeneratedShape::shrub}, {"fur-ball", GeneratedShape::fur_ball}};
    Result<Mesh> mesh = Mesh{};
    if (args.shape == "assembly") {
        mesh = generate_assembly(args.triangles, args.radius);
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
    if (args.output.size() < 4 || args.output.substr(args.output.size() - 4) != ".ply")
        return fail(args.output + ": generate writes PLY, name the output *.ply");
    Status written = write_ply(*mesh, args.output);
    if (!written) return fail(written);
    std::fprintf(stderr, "standin: wrote %s (%zu triangles, %zu vertices)\n", args.output.c_str(),
                 mesh->triangle_count(), mesh->vertex_count());
    return k_exit_ok;
}

CommandRun add_generate_command(CLI::App& root)
{
    auto args = std::make_shared<GenerateArgs>();
    CLI::App* command = root.add_subcommand(
        "generate", "Write a procedural test mesh as PLY: a sphere, a torus, a sphere with a noisy radius, a shrub "
                    "(branches and leaf cards), a fur ball (hair ribbons) or a mechanical assembly (59 nested parts) of a chosen triangle count (for tests and scale "
                    "benchmarks up to millions of faces)");
    command->add_option("shape", args->shape, "sphere | torus | noisy-sphere | shrub | fur-ball | assembly")
        ->check(CLI::IsMember({"sphere", "torus", "noisy-sphere", "shrub", "fur-ball", "assembly"}))
        ->required();
    command->add_option("-o,--output", args->output, "Output file (.ply)")->required();
    command->add_option("-t,--triangles", args->triangles, "Approximate triangle count")->capture_default_str();
    command->add_option("--radius", args->radius, "Radius")->capture_default_str();
    command->add_option("--noise", args->noise, "noisy-sphere: displacement amplitude relative to the radius")
        ->capture_default_str();
    command->add_option("--seed", args->seed, "noisy-sphere, shrub, fur-ball: random seed")->capture_default_str();
    return [args] { return run_generate(*args); };
}

} // namespace standin::cli
