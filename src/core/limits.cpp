// The memory and triangle budgets (limits.h): read once from the environment, else from what the
// machine allows (physical memory, the cgroup's limit, rlimits), so that a refusal comes before an
// allocation the system would answer with std::bad_alloc or the out-of-memory killer.
#include <standin/limits.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <mutex>
#include <sys/resource.h>
#include <unistd.h>

namespace standin {

namespace {

constexpr std::uint64_t k_unlimited = std::numeric_limits<std::uint64_t>::max();

// "123", "64K", "1.5G", "2T" -> bytes; 0 when it does not parse
std::uint64_t parse_bytes(const char* text)
{
    if (!text || !*text) return 0;
    char* end = nullptr;
    double value = std::strtod(text, &end);
    if (end == text || !(value > 0.0)) return 0;
    double scale = 1.0;
    switch (std::toupper(static_cast<unsigned char>(*end))) {
    case 'K': scale = 1024.0; ++end; break;
    case 'M': scale = 1024.0 * 1024.0; ++end; break;
    case 'G': scale = 1024.0 * 1024.0 * 1024.0; ++end; break;
    case 'T': scale = 1024.0 * 1024.0 * 1024.0 * 1024.0; ++end; break;
    default: break;
    }
    if (*end == 'i' || *end == 'B') ++end;
    if (*end == 'B') ++end;
    if (*end != '\0') return 0;
    double bytes = value * scale;
    return bytes >= 1.8e19 ? k_unlimited : std::uint64_t(bytes);
}

std::uint64_t cgroup_limit()
{
    for (const char* file : {"/sys/fs/cgroup/memory.max", "/sys/fs/cgroup/memory/memory.limit_in_bytes"}) {
        std::ifstream in(file);
        std::string text;
        if (in >> text && text != "max") {
            std::uint64_t bytes = std::strtoull(text.c_str(), nullptr, 10);
            if (bytes > 0) return bytes;
        }
    }
    return k_unlimited;
}

std::uint64_t rlimit_of(int resource)
{
    rlimit limit{};
    if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return k_unlimited;
    return std::uint64_t(limit.rlim_cur);
}

Budget budget_from_environment()
{
    Budget b;
    b.memory_bytes = parse_bytes(std::getenv("STANDIN_MEMORY_LIMIT"));
    if (b.memory_bytes == 0) {
        long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
        std::uint64_t physical = pages > 0 && page_size > 0 ? std::uint64_t(pages) * std::uint64_t(page_size) : k_unlimited;
        std::uint64_t smallest = std::min({physical, cgroup_limit(), rlimit_of(RLIMIT_AS), rlimit_of(RLIMIT_DATA)});
        // a quarter is left to the libraries, the driver and what the estimates do not count
        b.memory_bytes = smallest == k_unlimited ? (std::uint64_t(8) << 30) : smallest / 4 * 3;
    }
    const char* triangles = std::getenv("STANDIN_MAX_TRIANGLES");
    b.max_triangles = triangles && *triangles ? std::strtoull(triangles, nullptr, 10) : 0;
    if (b.max_triangles == 0) b.max_triangles = k_default_max_triangles;
    return b;
}

std::mutex g_mutex;
Budget g_budget;
bool g_budget_set = false;

} // namespace

const Budget& budget()
{
    std::lock_guard lock(g_mutex);
    if (!g_budget_set) {
        g_budget = budget_from_environment();
        g_budget_set = true;
    }
    return g_budget;
}

void set_budget(const Budget& b)
{
    std::lock_guard lock(g_mutex);
    g_budget = b;
    g_budget_set = true;
}

std::string bytes_text(std::uint64_t bytes)
{
    char text[64];
    const double gib = 1024.0 * 1024.0 * 1024.0;
    if (bytes >= (std::uint64_t(1) << 30)) std::snprintf(text, sizeof text, "%.1f GiB", double(bytes) / gib);
    else if (bytes >= (std::uint64_t(1) << 20)) std::snprintf(text, sizeof text, "%.0f MiB", double(bytes) / (1024.0 * 1024.0));
    else if (bytes >= 1024) std::snprintf(text, sizeof text, "%.0f KiB", double(bytes) / 1024.0);
    else std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
    return text;
}

Status check_memory(std::uint64_t bytes, const std::string& what)
{
    std::uint64_t limit = budget().memory_bytes;
    if (bytes <= limit) return Status::ok();
    return error(StatusCode::invalid_argument, what + " needs about " + bytes_text(bytes) + ", more than the memory budget of " +
                                                   bytes_text(limit) + " (STANDIN_MEMORY_LIMIT raises it)");
}

Status check_triangles(std::uint64_t triangles, const std::string& what)
{
    std::uint64_t limit = budget().max_triangles;
    if (triangles <= limit) return Status::ok();
    return error(StatusCode::bad_data, what + " has more than " + std::to_string(limit) +
                                           " triangles after triangulation (STANDIN_MAX_TRIANGLES raises the limit)");
}

} // namespace standin
