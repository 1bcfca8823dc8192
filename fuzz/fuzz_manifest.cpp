// libFuzzer harness: read_package over a package directory whose manifest.json is the fuzz input,
// with valid images and a coarse mesh beside it (a small enhanced-billboards bake made once, on the
// CPU, at start-up). Reaches the shared manifest checks and each representation's reader.
#include "fuzz_support.h"

#include <standin/package.h>

#include <cstdlib>

static std::string make_package()
{
    using namespace standin;
    GenerateOptions options;
    options.target_triangles = 200;
    Result<Mesh> mesh = generate_mesh(options);
    if (!mesh) std::abort();
    Result<SourceInfo> source = describe_source("", *mesh);
    OptionValues parameters;
    parameters.set("resolution", "32");
    parameters.set("max-billboards", "3");
    Result<std::unique_ptr<Package>> package =
        bake_package(*find_representation("enhanced-billboards"), *mesh, *source, parameters, {}, 1);
    if (!package) std::abort();
    std::string directory = fuzz::scratch_directory() + "/package.standin";
    if (!write_package(**package, directory)) std::abort();
    // scripts/fuzz keeps this package's own manifest as a seed (its sizes and hashes match)
    if (const char* seed = std::getenv("STANDIN_FUZZ_SEED_OUT"))
        std::filesystem::copy_file(directory + "/manifest.json", seed, std::filesystem::copy_options::overwrite_existing);
    return directory;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static const std::string directory = (standin::fuzz::lower_budgets(), make_package());
    std::string path = directory + "/manifest.json";
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    standin::Result<std::unique_ptr<standin::Package>> package = standin::read_package(directory);
    if (!package && package.status().message().find('\n') != std::string::npos) __builtin_trap(); // one line
    return 0;
}
