// Which views saw surface in which octree node (visibility.h).
// Steps:
//  1. per view (in parallel), per covered texel: its stored surface point, and the largest depth
//     step to its covered neighbours;
//  2. every finest-level voxel within 1.5 texels of that point, or of the segment along the view
//     between it and the deepest or highest neighbour it may be walled to, gets the view's bit (an
//     atomic OR: views of one word run on different threads);
//  3. coarser levels: a node's bits are the OR of its children's.
// Why 1.5 texels: a hit lies on its texel's top within half a texel (sideways) of the texel's
// centre, in the voxel grown by half a texel; 1.5 covers both with a margin.
#include "reps/microfacets/visibility.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>

namespace standin::microfacets {

namespace {

constexpr float k_reach_texels = 1.5f;
// The link rule's largest step between neighbours of one surface (height_field.h: 1.5 x a slope
// of at most 8, plus half a texel and two depth codes): deeper steps are never walked across.
constexpr float k_max_wall_texels = 13.0f;
// Entries of the per-view cache of marked voxels (a power of two: indexed by a morton code's low
// bits, which neighbouring voxels differ in).
constexpr std::size_t k_mark_cache = 4096;
// The finest level up to which a view keeps a bit per grid cell it has visited (512^3: 16 MiB).
constexpr int k_max_visited_level = 9;
static_assert(3 * k_max_grid_level < 32, "the cache's empty slot is a code no voxel has");

// index of `code` in the sorted `codes`, or -1
std::int64_t find(const std::vector<std::uint32_t>& codes, std::uint32_t code)
{
    auto it = std::lower_bound(codes.begin(), codes.end(), code);
    return it != codes.end() && *it == code ? std::int64_t(it - codes.begin()) : -1;
}

} // namespace

SeenViews seen_views(const MicrofacetsPackage& package)
{
    const BakeSettings& s = package.settings;
    const Octree& tree = package.octree;
    SeenViews out;
    out.words_per_node = int((package.views.size() + 31) / 32);
    const std::size_t words = std::size_t(out.words_per_node);
    // nodes in the renderer's order: levels min..max
    std::vector<std::size_t> first(std::size_t(s.level + 2), 0);
    std::size_t total = 0;
    for (int level = s.min_level; level <= s.level; ++level) first[std::size_t(level)] = total, total += tree.at(level).size();
    out.words.assign(total * words, 0u);

    // steps 1 and 2, at the finest level
    const std::vector<std::uint32_t>& fine = tree.at(s.level);
    const float voxel = tree.grid.voxel_size(s.level), r = package.radius, texel = 2.0f * r / float(s.resolution);
    const int cells = 1 << s.level;
    const std::size_t fine_first = first[std::size_t(s.level)];
    tbb::parallel_for(std::size_t(0), package.views.size(), [&](std::size_t k) {
        const View& view = package.views[k];
        if (view.width == 0) return;
        const ImageRGBA16& page = package.normal_depth_pages[std::size_t(view.page)];
        auto covered = [&](int x, int y) {
            const std::uint16_t* nd = page.at(view.atlas_x + x, view.atlas_y + y);
            return nd[0] != 0 || nd[1] != 0 || nd[2] != 0;
        };
        auto height = [&](int x, int y) { return r - 2.0f * r * float(page.at(view.atlas_x + x, view.atlas_y + y)[3]) / 65535.0f; };
        const std::uint32_t bit = 1u << (k % 32);
        // Neighbouring texels reach mostly the same voxels (a voxel spans several texels): a small
        // direct-mapped cache of the voxels this view has marked skips their search and atomic OR
        // (the renderer built this in 1-2 s per microfacets package, most of it searching again).
        struct Marked {
            std::uint32_t code = ~0u; // no morton code of k_max_grid_level (3 bits a level) is all ones
        };
        // Up to k_max_visited_level, a bit per cell of the grid instead of the cache: a texel's box
        // of 8-27 voxels is mostly its neighbours' again, and the cache left each repeat its morton
        // code and most their search (the bunny's package: 29 million boxes, 780 million voxel
        // visits; the renderer took 4-6 s to start)
        const bool bitmap = s.level <= k_max_visited_level;
        std::vector<std::uint64_t> visited(bitmap ? (std::size_t(1) << (3 * s.level)) / 64 + 1 : 0, 0);
        std::vector<Marked> marked(bitmap ? 0 : k_mark_cache);
        for (int y = 0; y < view.height; ++y)
            for (int x = 0; x < view.width; ++x) {
                if (!covered(x, y)) continue;
                float h = height(x, y), step = 0.0f;
                const int neighbours[4][2] = {{x - 1, y}, {x + 1, y}, {x, y - 1}, {x, y + 1}};
                for (const auto& n : neighbours)
                    if (n[0] >= 0 && n[1] >= 0 && n[0] < view.width && n[1] < view.height && covered(n[0], n[1]))
                        step = std::max(step, std::abs(height(n[0], n[1]) - h));
                step = std::min(step, k_max_wall_texels * texel);
                glm::vec2 plane = -r + (glm::vec2(float(view.crop_x + x), float(view.crop_y + y)) + 0.5f) * texel;
                glm::vec3 q = package.center + plane.x * view.axis_u + plane.y * view.axis_v + h * view.direction;
                glm::vec3 lo = glm::min(q - step * view.direction, q + step * view.direction) - k_reach_texels * texel;
                glm::vec3 hi = glm::max(q - step * view.direction, q + step * view.direction) + k_reach_texels * texel;
                glm::ivec3 a = glm::clamp(glm::ivec3(glm::floor((lo - tree.grid.origin) / voxel)), glm::ivec3(0), glm::ivec3(cells - 1));
                glm::ivec3 b = glm::clamp(glm::ivec3(glm::floor((hi - tree.grid.origin) / voxel)), glm::ivec3(0), glm::ivec3(cells - 1));
                for (int cz = a.z; cz <= b.z; ++cz)
                    for (int cy = a.y; cy <= b.y; ++cy)
                        for (int cx = a.x; cx <= b.x; ++cx) {
                            if (bitmap) {
                                const std::size_t cell = (std::size_t(cz) * std::size_t(cells) + std::size_t(cy)) * std::size_t(cells) + std::size_t(cx);
                                std::uint64_t& bits = visited[cell / 64];
                                const std::uint64_t mask = std::uint64_t(1) << (cell % 64);
                                if (bits & mask) continue;
                                bits |= mask;
                            }
                            const std::uint32_t code = morton_encode(glm::uvec3(cx, cy, cz));
                            if (!bitmap) {
                                Marked& slot = marked[code & (k_mark_cache - 1)];
                                if (slot.code == code) continue;
                                slot.code = code;
                            }
                            std::int64_t index = find(fine, code);
                            if (index < 0) continue;
                            std::atomic_ref<std::uint32_t> word(out.words[(fine_first + std::size_t(index)) * words + k / 32]);
                            word.fetch_or(bit, std::memory_order_relaxed);
                        }
            }
    });

    // step 3
    for (int level = s.level - 1; level >= s.min_level; --level) {
        const std::vector<std::uint32_t>& parents = tree.at(level);
        const std::vector<std::uint32_t>& children = tree.at(level + 1);
        std::size_t parent_first = first[std::size_t(level)], child_first = first[std::size_t(level + 1)];
        for (std::size_t c = 0; c < children.size(); ++c) {
            std::int64_t parent = find(parents, children[c] >> 3);
            for (std::size_t w = 0; w < words; ++w)
                out.words[(parent_first + std::size_t(parent)) * words + w] |= out.words[(child_first + c) * words + w];
        }
    }
    return out;
}

} // namespace standin::microfacets
