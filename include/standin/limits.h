// Budgets that turn huge or hostile input into a refusal with a reason instead of a crash, a hang or
// the out-of-memory killer: a memory budget for large allocations and a triangle budget for meshes
// after triangulation. Both come from the environment (read once) and default to what the machine
// allows; refusals name the budget and the variable that raises it.
#pragma once

#include <standin/status.h>

#include <cstdint>
#include <string>

namespace standin {

struct Budget {
    // Bytes one command may allocate for its large buffers: STANDIN_MEMORY_LIMIT (bytes, or with a
    // K, M, G or T suffix), else 3/4 of the smallest of physical memory, the cgroup's memory.max
    // and the address-space and data rlimits.
    std::uint64_t memory_bytes = 0;
    // Triangles of a model after triangulation: STANDIN_MAX_TRIANGLES, else 100 million.
    std::uint64_t max_triangles = 0;
};

constexpr std::uint64_t k_default_max_triangles = 100'000'000;

// The process's budget (from the environment at first use; set_budget replaces it, for tests).
const Budget& budget();
void set_budget(const Budget& budget);

// ok when `bytes` fit the memory budget, else invalid_argument: "WHAT needs about 6.0 GiB, more than
// the memory budget of 4.0 GiB (STANDIN_MEMORY_LIMIT raises it)".
Status check_memory(std::uint64_t bytes, const std::string& what);
// ok when `triangles` fit the triangle budget, else bad_data: "WHAT has more than N triangles
// (STANDIN_MAX_TRIANGLES raises the limit)".
Status check_triangles(std::uint64_t triangles, const std::string& what);

// "1.5 GiB", "12 MiB", "512 bytes".
std::string bytes_text(std::uint64_t bytes);

} // namespace standin
