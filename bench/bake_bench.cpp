// Bake time and peak memory of enhanced billboards on generated noisy spheres (10k, 100k, 1M faces
// by default), so that scaling with face count and cores can be checked (issue #3 targets: 40k
// faces well under a second, 1M faces under 30 s, on 2 cores). Not a test: prints a table.
//   bake_bench [--threads N] [--faces 10000,100000,1000000] [--write DIR]
// Peak RSS is the process high-water mark (VmHWM) read after each bake, so rows are cumulative:
// run one size per process for an exact per-size figure.
#include <standin/mesh.h>
#include <standin/package.h>

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace standin;

static long peak_rss_kib()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::atol(line.c_str() + 6);
    return -1;
}

static std::string cpu_name()
{
    std::ifstream info("/proc/cpuinfo");
    std::string line;
    while (std::getline(info, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown CPU";
}

int main(int argc, char** argv)
{
    int threads = 0;
    std::vector<std::size_t> sizes = {10000, 100000, 1000000};
    std::string write_dir;
    for (int i = 1; i + 1 < argc; i += 2) {
        std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--threads") threads = std::atoi(value.c_str());
        else if (flag == "--write") write_dir = value;
        else if (flag == "--faces") {
            sizes.clear();
            std::stringstream list(value);
            for (std::string item; std::getline(list, item, ',');) sizes.push_back(std::stoul(item));
        } else {
            std::fprintf(stderr, "usage: bake_bench [--threads N] [--faces A,B,C] [--write DIR]\n");
            return 2;
        }
    }
    int cores = threads > 0 ? threads : tbb::info::default_concurrency();
    std::printf("enhanced-billboards bake, %s, %d threads\n", cpu_name().c_str(), cores);
    std::printf("%10s %10s %10s %11s %10s %12s %12s\n", "faces", "bake_s", "write_s", "billboards", "captured", "bytes",
                "peak_rss_MiB");
    for (std::size_t size : sizes) {
        GenerateOptions options;
        options.shape = GeneratedShape::noisy_sphere;
        options.target_triangles = size;
        Result<Mesh> mesh = generate_mesh(options);
        if (!mesh) {
            std::fprintf(stderr, "bake_bench: %s\n", mesh.status().message().c_str());
            return 2;
        }
        Result<SourceInfo> source = describe_source("", *mesh);
        auto start = std::chrono::steady_clock::now();
        Result<std::unique_ptr<Package>> package =
            bake_package(*find_representation("enhanced-billboards"), *mesh, *source, {}, {}, threads);
        double bake_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!package) {
            std::fprintf(stderr, "bake_bench: %s\n", package.status().message().c_str());
            return 2;
        }
        double write_s = 0.0;
        std::uint64_t bytes = 0;
        if (!write_dir.empty()) {
            std::string path = write_dir + "/noisy_sphere_" + std::to_string(size) + ".standin";
            start = std::chrono::steady_clock::now();
            Status written = write_package(**package, path);
            write_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (!written) {
                std::fprintf(stderr, "bake_bench: %s\n", written.message().c_str());
                return 2;
            }
            bytes = package_bytes(path).is_ok() ? *package_bytes(path) : 0;
        }
        nlohmann::json summary = summarise_package(**package).details;
        std::printf("%10zu %10.3f %10.3f %11zu %10.5f %12llu %12.1f\n", mesh->triangle_count(), bake_s, write_s,
                    summary["billboards"].get<std::size_t>(), summary["area_captured_fraction"].get<double>(),
                    static_cast<unsigned long long>(bytes), peak_rss_kib() / 1024.0);
        std::fflush(stdout);
    }
    return 0;
}
