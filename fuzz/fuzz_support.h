// Helpers shared by the libFuzzer harnesses (fuzz/): readers take paths, so each input is written to
// a file in a per-process scratch folder first; the budgets are lowered so that the library refuses
// large inputs itself, within libFuzzer's per-input memory limit.
#pragma once

#include <standin/limits.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace standin::fuzz {

inline std::string scratch_directory()
{
    static const std::string dir = [] {
        std::filesystem::path d = std::filesystem::temp_directory_path() / ("standin_fuzz_" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        return d.string();
    }();
    return dir;
}

inline std::string write_input(const std::string& name, const std::uint8_t* data, std::size_t size)
{
    std::string path = scratch_directory() + "/" + name;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

// The little-endian 32-bit word at `at` of a fuzzer input, 0 past its end: harnesses take the
// counts a manifest would give from the input's own header, so that inputs reach the decoders.
inline std::uint32_t input_u32(const std::uint8_t* data, std::size_t size, std::size_t at)
{
    if (size < at + 4) return 0;
    return std::uint32_t(data[at]) | std::uint32_t(data[at + 1]) << 8 | std::uint32_t(data[at + 2]) << 16 |
           std::uint32_t(data[at + 3]) << 24;
}

// 256 MiB and 2 million triangles: refusals come before libFuzzer's -rss_limit_mb (2048 by default).
inline void lower_budgets()
{
    Budget b;
    b.memory_bytes = 256ull << 20;
    b.max_triangles = 2'000'000;
    set_budget(b);
}

} // namespace standin::fuzz
