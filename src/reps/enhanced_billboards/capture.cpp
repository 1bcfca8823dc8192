// Capturing the faces one enhanced billboard can hold, exactly.
// Vichitvejpaisal 2005 (§3.1 conditions 1-3, §3.2 steps 6-9, §4.3).
//
// For a direction w the faces still to capture are split into
//   S   facing the plane (n.w < 0), and S_p those of S not grazing (-n.w >= sin(grazing angle));
//   the plane sits at the front of S_p;
//   S'  faces of S_p that lie entirely within the depth limit;
//   S'' faces of S' that no other face hides, decided with an item buffer: every face of S within
//       the depth slab (grazing ones too: they are surface in front of what they hide) is
//       rasterised at texel centres with a depth test, keeping (depth, face id) per texel; a face
//       is hidden if any of its texels is won by a face in front of it by more than a tolerance.
// Differences from the seed, which used GPU occlusion queries:
// - exact CPU rasterisation: 8-bit sub-texel fixed point, 64-bit edge functions and a top-left fill
//   rule, so neighbouring faces cover each texel centre exactly once and never "occlude" each other
//   at shared edges. The depth test is an atomic min on a packed (depth, face id) key, so the
//   result is the same for any thread count and ties go to the lower face id.
// - tolerance: a face is hidden only where the winner is nearer by more than texel * (1 + slope),
//   slope = tan(angle between the face and the plane): the depth a smooth surface varies across one
//   texel, so coincident or touching surfaces do not hide each other.
// - faces smaller than a texel: the seed dropped faces whose projection covers less than a pixel,
//   which at 512 texels per diagonal is most of a million-face model. Here a face that covers no
//   texel centre is splatted at its centroid's texel and tested there: it is captured when it is
//   not behind the winner of that texel (same tolerance) and that winner is captured, since the
//   winner's texel then stands for it. Only faces foreshortened by this direction (grazing) are
//   refused, and they stay for another direction.
// - intersecting faces (seed §4.3: they hide each other in every direction): a hidden face whose
//   every occluder (up to k_max_occluders of them) is in turn hidden by it, directly or through a
//   cycle of faces hiding each other (a strongly connected component of the "is hidden by"
//   graph), bypasses the test.
// - seams: a one-texel rim of the front-most surface around the captured texels is written and
//   marked covered, where its depth continues that of the captured neighbour, so that billboards
//   meeting at a seam overlap by a texel instead of leaving a crack.
// - sheet edges (issue #17, --sheet-edges overlap): a texel next to a captured face that the face
//   overlaps only across an edge of an open surface is covered too (the edge has no wall beyond
//   it for another billboard to capture).
// - sheet edge lines (issue #17, --sheet-edges clip, the default for sheet models): those texels are
//   covered too, and every covered texel an open edge crosses stores the edge's line within it
//   (the nearest open edge, quantised into the colour map's alpha: billboard_layout.glsl,
//   EDGE_LINE_*); the march clips its hits against it (march.frag), so the rim is neither a
//   staircase of lost texels nor one of spilled ones.
// - alpha (issue #14): a face of a mask or blend material exists only at the texel centres that
//   pass its alpha test (Mesh::covered_at): cut-out texels are neither put in the item buffer nor
//   tested, so leaf cards become their leaves (holes where the texture is cut) and do not hide what
//   their holes show. A sub-texel face's centroid splat is not tested (it stands for a texel).
// - alpha contour lines (issue #14, --sheet-edges clip, the default for alpha-tested models): a
//   leaf's outline is its texture's cut-out contour, not a mesh edge; every texel of an alpha-tested
//   face that the contour crosses stores, in the same code as a sheet edge line, the line that
//   misclassifies the fewest of 8 x 8 points of the texel (best_contour_code), and a texel whose
//   centre is cut out but which a neighbour's leaf partly covers is grown with that leaf and
//   clipped; the colour of every texel of an alpha-tested face is the mean of its covered points.
// - outline lines (issue #17, --sheet-edges clip, the default): on every model, a texel its own
//   surface's outline crosses (a silhouette, the end of a part over what lies behind it) stores the
//   line that best splits its 8 x 8 points, and an empty texel beyond that a covered neighbour's
//   surface reaches into is grown with it and clipped (outline_surface_points).
// - partly hidden faces (--partly-hidden, by default for alpha-tested models): a hidden face at least
//   that fraction of whose texels are in front is captured all the same, at the texels it wins in
//   the item buffer (the only ones written); its hidden texels are lost to later billboards, and
//   counted as left ("hidden_parts", by the fraction of its texels hidden).
// - colour: a textured face's texel averages the texture over the texel (texel_albedo), covered
//   points only, where the seed read one point: the truth's mips filter, a point sample aliases.
#include "reps/enhanced_billboards/capture.h"
#include "reps/common/coverage_capture.h"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <bit>
#include <atomic>
#include <cmath>
#include <limits>

namespace standin::billboards {

namespace {

constexpr int k_subtexel_bits = 8;
constexpr std::int64_t k_subtexel = 1 << k_subtexel_bits;
constexpr std::uint32_t k_none = 0xffffffffu;
constexpr std::uint64_t k_empty = ~0ull;
constexpr int k_max_occluders = 8;
constexpr int k_grid_margin = 2;       // texels of empty border around everything rasterised
constexpr float k_rim_depth_texels = 3.0f; // a rim texel continues its neighbour within this depth
constexpr double k_depth_scale = 4294967040.0; // depth keys use 32 bits

// Everything one capture needs about the direction and its texel grid.
struct Grid {
    glm::dvec3 center{0.0}, u{0.0}, v{0.0}, w{0.0};
    double texel = 1.0;
    int x0 = 0, y0 = 0;        // grid texel (0, 0) is plane texel (x0, y0) around the centre
    int width = 0, height = 0;
    float z_base = 0.0f, z_span = 1.0f; // depth keys cover [z_base, z_base + z_span]
    std::vector<float> a, b, z;          // per vertex: plane coordinates in texels, depth along w
    std::vector<std::int32_t> fx, fy;    // per vertex: fixed-point grid coordinates
    std::vector<std::uint64_t> items;    // per texel: (quantised depth << 32) | face id

    std::uint32_t key_depth(float depth) const
    {
        double t = (double(depth) - z_base) / z_span;
        return std::uint32_t(std::clamp(t, 0.0, 1.0) * k_depth_scale);
    }
    float depth_of_key(std::uint64_t key) const { return float(z_base + double(key >> 32) / k_depth_scale * z_span); }
};

struct Corners {
    std::int64_t x[3], y[3];
    float z[3];
};

Corners corners(const Mesh& mesh, const Grid& grid, std::uint32_t face)
{
    Corners c{};
    for (int k = 0; k < 3; ++k) {
        std::uint32_t vertex = mesh.indices[std::size_t(face) * 3 + k];
        c.x[k] = grid.fx[vertex];
        c.y[k] = grid.fy[vertex];
        c.z[k] = grid.z[vertex];
    }
    return c;
}

std::int64_t edge(const Corners& c, int a, int b, std::int64_t px, std::int64_t py)
{
    return (c.x[b] - c.x[a]) * (py - c.y[a]) - (c.y[b] - c.y[a]) * (px - c.x[a]);
}

// Calls visit(i, j, weights) for every texel centre (i + 0.5, j + 0.5) inside the triangle under
// the top-left rule, weights being the barycentric weights of the face's three corners; returns
// how many texels were visited.
template <typename Visit>
int rasterize(const Corners& c, Visit&& visit)
{
    int order[3] = {0, 1, 2};
    std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
    if (area2 == 0) return 0;
    if (area2 < 0) {
        std::swap(order[1], order[2]);
        area2 = -area2;
    }
    // an edge owns the texel centres on it when it is a "top" or "left" edge; the reversed edge of
    // the neighbouring face then does not, so shared edges cover each centre once
    std::int64_t bias[3];
    for (int k = 0; k < 3; ++k) {
        int from = order[(k + 1) % 3], to = order[(k + 2) % 3];
        std::int64_t dx = c.x[to] - c.x[from], dy = c.y[to] - c.y[from];
        bias[k] = (dy > 0 || (dy == 0 && dx < 0)) ? 0 : 1;
    }
    std::int64_t min_x = std::min({c.x[0], c.x[1], c.x[2]}), max_x = std::max({c.x[0], c.x[1], c.x[2]});
    std::int64_t min_y = std::min({c.y[0], c.y[1], c.y[2]}), max_y = std::max({c.y[0], c.y[1], c.y[2]});
    auto first_centre = [](std::int64_t lo) { // smallest i with i * S + S/2 >= lo (lo >= 0)
        std::int64_t t = lo - k_subtexel / 2;
        return t <= 0 ? std::int64_t(0) : (t + k_subtexel - 1) / k_subtexel;
    };
    std::int64_t i0 = first_centre(min_x), i1 = (max_x - k_subtexel / 2) >> k_subtexel_bits;
    std::int64_t j0 = first_centre(min_y), j1 = (max_y - k_subtexel / 2) >> k_subtexel_bits;
    int count = 0;
    double inverse = 1.0 / double(area2);
    for (std::int64_t j = j0; j <= j1; ++j) {
        std::int64_t py = j * k_subtexel + k_subtexel / 2;
        for (std::int64_t i = i0; i <= i1; ++i) {
            std::int64_t px = i * k_subtexel + k_subtexel / 2;
            std::int64_t e[3];
            bool inside = true;
            for (int k = 0; k < 3 && inside; ++k) {
                e[k] = edge(c, order[(k + 1) % 3], order[(k + 2) % 3], px, py);
                inside = e[k] >= bias[k];
            }
            if (!inside) continue;
            float weights[3];
            for (int k = 0; k < 3; ++k) weights[order[k]] = float(double(e[k]) * inverse);
            visit(int(i), int(j), weights);
            ++count;
        }
    }
    return count;
}

// The texel holding a face's centroid, and the centroid's depth.
void centroid_texel(const Corners& c, int& i, int& j, float& depth)
{
    i = int((c.x[0] + c.x[1] + c.x[2]) / (3 * k_subtexel));
    j = int((c.y[0] + c.y[1] + c.y[2]) / (3 * k_subtexel));
    depth = (c.z[0] + c.z[1] + c.z[2]) / 3.0f;
}

// Barycentric weights of the point of the face nearest (in weights) to texel centre (i, j); used
// to read attributes of a face that won a texel by its centroid splat.
void clamped_weights_at(const Corners& c, std::int64_t px, std::int64_t py, float weights[3])
{
    std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
    if (area2 == 0) {
        weights[0] = weights[1] = weights[2] = 1.0f / 3.0f;
        return;
    }
    double e[3] = {double(edge(c, 1, 2, px, py)), double(edge(c, 2, 0, px, py)), double(edge(c, 0, 1, px, py))};
    double sum = 0.0;
    for (double& x : e) {
        x = std::max(0.0, x / double(area2));
        sum += x;
    }
    for (int k = 0; k < 3; ++k) weights[k] = sum > 0.0 ? float(e[k] / sum) : 1.0f / 3.0f;
}

void clamped_weights(const Corners& c, int i, int j, float weights[3])
{
    clamped_weights_at(c, std::int64_t(i) * k_subtexel + k_subtexel / 2, std::int64_t(j) * k_subtexel + k_subtexel / 2, weights);
}

// Sub-points per side of a texel whose colours a textured face's texel averages.
constexpr int k_colour_subsamples = 3;

// The albedo of texel (i, j) on textured face f: the mean over k x k points spread over the texel
// (barycentrics clamped to the face), counting only points that survive an alpha test (issue #14).
// A point sample at the texel centre aliases once a texel spans several texture texels (a leaf
// texture on a billboard of the whole tree), while the truth reads (coverage-weighted) mips: this
// is the box filter a mip level applies, at the billboard's texel. Untextured faces' colour is
// linear over the face, so their centre sample is kept.
glm::vec4 texel_albedo(const Mesh& mesh, std::uint32_t f, const Corners& c, int i, int j, const float centre[3])
{
    const Material& material = mesh.materials[mesh.face_materials[f]];
    glm::vec4 at_centre = mesh.albedo_at(f, centre[1], centre[2]);
    if (material.base_color_texture < 0 || !mesh.has_texture_coordinates()) return at_centre;
    const float cutoff = alpha_test_cutoff(material);
    glm::vec3 sum(0.0f);
    int count = 0;
    for (int a = 0; a < k_colour_subsamples; ++a)
        for (int b = 0; b < k_colour_subsamples; ++b) {
            std::int64_t px = std::int64_t(i) * k_subtexel + (2 * a + 1) * k_subtexel / (2 * k_colour_subsamples);
            std::int64_t py = std::int64_t(j) * k_subtexel + (2 * b + 1) * k_subtexel / (2 * k_colour_subsamples);
            float w[3];
            clamped_weights_at(c, px, py, w);
            // one texture lookup gives colour and alpha (Mesh::covered_at's test, without a second lookup)
            glm::vec4 colour = mesh.albedo_at(f, w[1], w[2]);
            if (cutoff > 0.0f && colour.w < cutoff) continue;
            sum += glm::vec3(colour);
            ++count;
        }
    return count > 0 ? glm::vec4(sum / float(count), at_centre.w) : at_centre;
}

void atomic_min(std::uint64_t& slot, std::uint64_t value)
{
    std::atomic_ref<std::uint64_t> ref(slot);
    std::uint64_t current = ref.load(std::memory_order_relaxed);
    while (value < current && !ref.compare_exchange_weak(current, value, std::memory_order_relaxed)) {
    }
}

template <typename Body>
void parallel_over(std::size_t count, Body&& body)
{
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t k = r.begin(); k != r.end(); ++k) body(k);
    });
}

// What the classification of the remaining faces found.
struct Sets {
    std::vector<std::uint32_t> occluders;  // S within the depth slab, ascending
    std::vector<std::uint32_t> candidates; // S', ascending
    std::vector<float> tolerance;          // per candidate, world units
    float front = 0.0f;                    // plane depth
};

Sets classify(const Mesh& mesh, const FaceData& faces, const std::vector<std::uint32_t>& remaining, const Grid& grid,
              const CaptureSettings& settings)
{
    // per face: 1 facing, 2 projectable; depth range
    std::vector<std::uint8_t> kind(remaining.size());
    std::vector<float> z_min(remaining.size()), z_max(remaining.size());
    glm::vec3 w(grid.w);
    parallel_over(remaining.size(), [&](std::size_t r) {
        std::uint32_t f = remaining[r];
        float facing = -glm::dot(faces.normal[f], w);
        float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
        for (int k = 0; k < 3; ++k) {
            float z = grid.z[mesh.indices[std::size_t(f) * 3 + k]];
            lo = std::min(lo, z);
            hi = std::max(hi, z);
        }
        z_min[r] = lo;
        z_max[r] = hi;
        bool real = faces.area[f] > 0.0;
        kind[r] = std::uint8_t((real && facing > 0.0f ? 1 : 0) | (real && facing >= settings.min_facing ? 2 : 0));
    });
    Sets sets;
    sets.front = std::numeric_limits<float>::max();
    for (std::size_t r = 0; r < remaining.size(); ++r)
        if (kind[r] & 2) sets.front = std::min(sets.front, z_min[r]);
    if (sets.front == std::numeric_limits<float>::max()) return sets;
    float back = sets.front + settings.depth_limit;
    for (std::size_t r = 0; r < remaining.size(); ++r) {
        if (!(kind[r] & 1) || z_min[r] >= back) continue;
        sets.occluders.push_back(remaining[r]);
        if ((kind[r] & 2) && z_max[r] <= back) {
            sets.candidates.push_back(remaining[r]);
            float c = std::max(-glm::dot(faces.normal[remaining[r]], w), settings.min_facing);
            c = std::max(c, 1e-3f);
            float slope = std::sqrt(std::max(0.0f, 1.0f - c * c)) / c;
            sets.tolerance.push_back(settings.texel_size * (1.0f + slope));
        }
    }
    return sets;
}

// Sizes the grid to the occluders and converts their corners to fixed point.
void place_grid(const Mesh& mesh, const Sets& sets, Grid& grid)
{
    float lo_a = std::numeric_limits<float>::max(), hi_a = std::numeric_limits<float>::lowest();
    float lo_b = lo_a, hi_b = hi_a, lo_z = lo_a, hi_z = hi_a;
    for (std::uint32_t f : sets.occluders)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t vertex = mesh.indices[std::size_t(f) * 3 + k];
            lo_a = std::min(lo_a, grid.a[vertex]);
            hi_a = std::max(hi_a, grid.a[vertex]);
            lo_b = std::min(lo_b, grid.b[vertex]);
            hi_b = std::max(hi_b, grid.b[vertex]);
            lo_z = std::min(lo_z, grid.z[vertex]);
            hi_z = std::max(hi_z, grid.z[vertex]);
        }
    grid.x0 = int(std::floor(lo_a)) - k_grid_margin;
    grid.y0 = int(std::floor(lo_b)) - k_grid_margin;
    grid.width = int(std::ceil(hi_a)) - grid.x0 + k_grid_margin + 1;
    grid.height = int(std::ceil(hi_b)) - grid.y0 + k_grid_margin + 1;
    grid.z_base = lo_z;
    grid.z_span = std::max(hi_z - lo_z, 1e-20f);
    grid.fx.resize(grid.a.size());
    grid.fy.resize(grid.a.size());
    parallel_over(grid.a.size(), [&](std::size_t vertex) {
        grid.fx[vertex] = std::int32_t(std::llround((double(grid.a[vertex]) - grid.x0) * k_subtexel));
        grid.fy[vertex] = std::int32_t(std::llround((double(grid.b[vertex]) - grid.y0) * k_subtexel));
    });
    grid.items.assign(std::size_t(grid.width) * grid.height, k_empty);
}

// Item buffer: the front-most occluder per texel centre; faces covering no centre are splatted at
// their centroid. A slot keeps the least (depth, face) key whatever order the faces come in, so a
// fragment that already loses to its slot skips its alpha test, a texture read: in a crown of cards
// many deep most do (a 2,000-face bush's bake: 44 of 77 million). Sorting the faces front to back
// skips more but scatters the slots each thread writes: tried, not measurably faster.
void fill_items(const Mesh& mesh, const Sets& sets, Grid& grid)
{
    parallel_over(sets.occluders.size(), [&](std::size_t r) {
        std::uint32_t f = sets.occluders[r];
        Corners c = corners(mesh, grid, f);
        auto put = [&](int i, int j, float depth) {
            atomic_min(grid.items[std::size_t(j) * grid.width + i], (std::uint64_t(grid.key_depth(depth)) << 32) | f);
        };
        const bool alpha_tested = alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f;
        int covered = rasterize(c, [&](int i, int j, const float* wt) {
            const float depth = wt[0] * c.z[0] + wt[1] * c.z[1] + wt[2] * c.z[2];
            if (alpha_tested) {
                std::uint64_t& slot = grid.items[std::size_t(j) * grid.width + i];
                const std::uint64_t key = (std::uint64_t(grid.key_depth(depth)) << 32) | f;
                if (std::atomic_ref<std::uint64_t>(slot).load(std::memory_order_relaxed) < key) return;
                if (!mesh.covered_at(f, wt[1], wt[2])) return;
            }
            put(i, j, depth);
        });
        if (covered == 0) {
            int i, j;
            float depth;
            centroid_texel(c, i, j, depth);
            put(i, j, depth);
        }
    });
}

struct Visibility {
    bool hidden = false;
    bool sub_texel = false;
    int occluder_count = 0; // -1: more than k_max_occluders
    std::uint32_t occluders[k_max_occluders]{};
    std::uint32_t centroid_winner = k_none;
    int texels = 0, hidden_texels = 0; // texel centres tested, and those a nearer face wins

    void add_occluder(std::uint32_t g)
    {
        hidden = true;
        if (occluder_count < 0) return;
        for (int k = 0; k < occluder_count; ++k)
            if (occluders[k] == g) return;
        if (occluder_count == k_max_occluders) {
            occluder_count = -1;
            return;
        }
        occluders[occluder_count++] = g;
    }
};

std::vector<Visibility> test_visibility(const Mesh& mesh, const Sets& sets, const Grid& grid)
{
    std::vector<Visibility> result(sets.candidates.size());
    parallel_over(sets.candidates.size(), [&](std::size_t r) {
        std::uint32_t f = sets.candidates[r];
        Corners c = corners(mesh, grid, f);
        Visibility& vis = result[r];
        float tolerance = sets.tolerance[r];
        auto test = [&](int i, int j, float depth) {
            std::uint64_t key = grid.items[std::size_t(j) * grid.width + i];
            std::uint32_t winner = std::uint32_t(key & 0xffffffffu);
            ++vis.texels;
            if (winner == f || key == k_empty) return winner;
            if (grid.depth_of_key(key) < depth - tolerance) {
                vis.add_occluder(winner);
                ++vis.hidden_texels;
            }
            return winner;
        };
        const bool alpha_tested = alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f;
        int covered = rasterize(c, [&](int i, int j, const float* wt) {
            // a texel this face won passed its alpha test in fill_items (a face covering a texel
            // centre is never splatted): only the others read the texture again
            const bool won = std::uint32_t(grid.items[std::size_t(j) * grid.width + i] & 0xffffffffu) == f;
            if (alpha_tested && !won && !mesh.covered_at(f, wt[1], wt[2])) return;
            test(i, j, wt[0] * c.z[0] + wt[1] * c.z[1] + wt[2] * c.z[2]);
        });
        if (covered == 0) {
            int i, j;
            float depth;
            centroid_texel(c, i, j, depth);
            vis.sub_texel = true;
            vis.centroid_winner = test(i, j, depth);
        }
    });
    return result;
}

// Strongly connected components of the "is hidden by" graph over the candidates (iterative
// Tarjan); returns a component id per candidate. Edges to non-candidates are ignored.
std::vector<std::uint32_t> hiding_components(const Sets& sets, const std::vector<Visibility>& vis,
                                             const std::vector<std::uint32_t>& slot)
{
    std::size_t n = sets.candidates.size();
    std::vector<std::uint32_t> index(n, k_none), low(n, 0), component(n, k_none), stack;
    std::vector<std::uint8_t> on_stack(n, 0);
    std::vector<std::pair<std::uint32_t, int>> calls; // (node, next edge)
    std::uint32_t counter = 0, components = 0;
    auto target = [&](std::uint32_t node, int k) { return slot[vis[node].occluders[k]]; };
    for (std::uint32_t root = 0; root < n; ++root) {
        if (index[root] != k_none || !vis[root].hidden) continue;
        calls.push_back({root, 0});
        index[root] = low[root] = counter++;
        stack.push_back(root);
        on_stack[root] = 1;
        while (!calls.empty()) {
            auto& [node, next] = calls.back();
            if (next < std::max(vis[node].occluder_count, 0)) {
                std::uint32_t to = target(node, next++);
                if (to == k_none) continue;
                if (index[to] == k_none) {
                    index[to] = low[to] = counter++;
                    stack.push_back(to);
                    on_stack[to] = 1;
                    calls.push_back({to, 0});
                } else if (on_stack[to]) {
                    low[node] = std::min(low[node], index[to]);
                }
                continue;
            }
            std::uint32_t done = node;
            calls.pop_back();
            if (!calls.empty()) low[calls.back().first] = std::min(low[calls.back().first], low[done]);
            if (low[done] == index[done]) {
                std::uint32_t member;
                do {
                    member = stack.back();
                    stack.pop_back();
                    on_stack[member] = 0;
                    component[member] = components;
                } while (member != done);
                ++components;
            }
        }
    }
    return component;
}

// S'': visible faces; hidden faces whose every occluder is, directly or through others, hidden
// by them (intersecting faces, seed §4.3: they would hide each other in every direction) are let
// through; sub-texel faces only where the texel standing for them is captured. Returns a flag per
// candidate.
std::vector<std::uint8_t> decide_captured(const Sets& sets, const std::vector<Visibility>& vis,
                                          const std::vector<std::uint32_t>& slot, float partly_visible)
{
    std::size_t n = sets.candidates.size();
    std::vector<std::uint32_t> component = hiding_components(sets, vis, slot);
    std::vector<std::uint8_t> visible(n);
    parallel_over(n, [&](std::size_t r) {
        const Visibility& v = vis[r];
        if (!v.hidden) {
            visible[r] = 1;
            return;
        }
        // partly hidden, and enough of it in front: captured where it is (write_maps writes only
        // the texels a captured face wins)
        if (partly_visible > 0.0f && !v.sub_texel && v.texels > 0 &&
            float(v.texels - v.hidden_texels) >= partly_visible * float(v.texels)) {
            visible[r] = 1;
            return;
        }
        if (v.occluder_count <= 0) return;
        for (int k = 0; k < v.occluder_count; ++k) {
            std::uint32_t s = slot[v.occluders[k]];
            if (s == k_none || component[s] != component[r]) return;
        }
        visible[r] = 1;
    });
    std::vector<std::uint8_t> captured(n);
    parallel_over(n, [&](std::size_t r) {
        if (!visible[r]) return;
        const Visibility& v = vis[r];
        if (!v.sub_texel || v.centroid_winner == sets.candidates[r]) {
            captured[r] = 1;
            return;
        }
        std::uint32_t s = v.centroid_winner == k_none ? k_none : slot[v.centroid_winner];
        captured[r] = s != k_none && visible[s];
    });
    return captured;
}

// Writes the maps of the captured texels (and their rim), cropped to the content plus one texel.
// Whether the square of texel (i, j) overlaps face f (corners c) but its centre lies outside it, and
// only across edges of an open surface (bits of `open`): the texels a sheet's edge crosses.
bool across_open_edge(const Corners& c, std::uint8_t open, int i, int j)
{
    std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
    if (area2 == 0) return false;
    std::int64_t sign = area2 > 0 ? 1 : -1;
    std::int64_t px = std::int64_t(i) * k_subtexel + k_subtexel / 2, py = std::int64_t(j) * k_subtexel + k_subtexel / 2;
    bool outside_open = false;
    for (int k = 0; k < 3; ++k) {
        int a = k, b = (k + 1) % 3;
        std::int64_t e = sign * edge(c, a, b, px, py); // edge length x signed distance inside
        if (e >= 0) continue;
        if (!(open & (1 << k))) return false;
        // a unit square meets the edge's line within half its extent along the edge's normal
        std::int64_t reach = (std::abs(c.x[b] - c.x[a]) + std::abs(c.y[b] - c.y[a])) * (k_subtexel / 2);
        if (-e > reach) return false;
        outside_open = true;
    }
    return outside_open;
}

// Alpha contour lines (issue #14): a leaf card's outline is not a mesh edge but the contour where
// its texture's alpha crosses the cutoff, so the texels a leaf's outline crosses were whole or
// empty by their centre, half a texel off on average. The contour is measured at k x k points of
// the texel and the edge-line code (or the whole texel, or nothing) that misclassifies the fewest
// of them is stored, so the march clips leaves inside a texel as it clips sheet rims.
constexpr int k_contour_subsamples = 8; // 64 points: one bit each of a std::uint64_t
constexpr int k_edge_line_codes = EDGE_LINE_ANGLES * EDGE_LINE_OFFSETS;

// Point a of n across a texel (n divides k_contour_subsamples).
std::int64_t contour_point(int texel, int a, int n = k_contour_subsamples)
{
    return std::int64_t(texel) * k_subtexel + (2 * a + 1) * k_subtexel / (2 * n);
}

// Points across a texel at which face f's alpha and colour are read (face_coverage): all
// k_contour_subsamples, or half as many (each standing for 2 x 2 of the mask) where the face's
// texture has at most k_coarse_contour_texels texels across a capture texel, as at the 2048 texels
// foliage is captured at (issue #14): bilinear alpha and colour vary little within a texture texel,
// and the 64 reads a texel were the largest part of that bake's time (generated tree, 4000 faces:
// 98 -> 79 s; foliage Luv at distance 1 2.888 -> 2.902, 3.049 -> 3.035 in the tests' views). `area2` is the face's doubled area in
// fixed-point grid units (corners, edge).
constexpr double k_coarse_contour_texels = 2.0;
int contour_samples(const Mesh& mesh, std::uint32_t f, std::int64_t area2)
{
    const double texture_texels = reps::texture_texel_area(mesh, f);
    const double capture_texels = 0.5 * std::abs(double(area2)) / (double(k_subtexel) * double(k_subtexel));
    if (!(texture_texels > 0.0) || !(capture_texels > 0.0) || !std::isfinite(texture_texels)) return k_contour_subsamples;
    return texture_texels <= k_coarse_contour_texels * k_coarse_contour_texels * capture_texels ? k_contour_subsamples / 2
                                                                                                  : k_contour_subsamples;
}

// Per edge-line code, the contour points (bit b * k + a for point a, b) on the surface's side.
const std::array<std::uint64_t, k_edge_line_codes>& edge_line_masks()
{
    static const std::array<std::uint64_t, k_edge_line_codes> masks = [] {
        std::array<std::uint64_t, k_edge_line_codes> result{};
        for (int code = 0; code < k_edge_line_codes; ++code)
            for (int b = 0; b < k_contour_subsamples; ++b)
                for (int a = 0; a < k_contour_subsamples; ++a) {
                    glm::vec2 p((float(a) + 0.5f) / k_contour_subsamples, (float(b) + 0.5f) / k_contour_subsamples);
                    if (edge_line_contains(std::uint8_t(EDGE_LINE_FIRST_CODE + code), p))
                        result[std::size_t(code)] |= 1ull << (b * k_contour_subsamples + a);
                }
        return result;
    }();
    return masks;
}

bool is_alpha_tested(const Mesh& mesh, std::uint32_t f)
{
    return alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f;
}

// Which contour points of texel (i, j) face f covers (alpha test passed). With `extend`, points
// just outside the face count on the face's plane (its texture coordinates extended), unless they
// lie beyond an open edge: a card is split into triangles (and long edges into pieces), and the
// leaf's contour runs across them. `colour`, when given, receives the mean albedo of the covered points;
// without it only the alpha is read (Mesh::covered_at decides as albedo_at's alpha does).
std::uint64_t face_coverage(const Mesh& mesh, const FaceData& faces, const Grid& grid, std::uint32_t f, int i, int j,
                            bool extend, glm::vec3* colour = nullptr)
{
    Corners c = corners(mesh, grid, f);
    std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
    if (area2 == 0) return 0;
    const std::uint8_t open = faces.open_edges.empty() ? 0 : faces.open_edges[f];
    const float cutoff = alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]);
    std::uint64_t mask = 0;
    glm::vec3 sum(0.0f);
    const int n = contour_samples(mesh, f, area2), step = k_contour_subsamples / n;
    std::uint64_t block = 0; // the mask bits one point stands for
    for (int db = 0; db < step; ++db)
        for (int da = 0; da < step; ++da) block |= 1ull << (db * k_contour_subsamples + da);
    for (int b = 0; b < n; ++b)
        for (int a = 0; a < n; ++a) {
            std::int64_t px = contour_point(i, a, n), py = contour_point(j, b, n);
            float w[3] = {float(double(edge(c, 1, 2, px, py)) / double(area2)), float(double(edge(c, 2, 0, px, py)) / double(area2)),
                          float(double(edge(c, 0, 1, px, py)) / double(area2))};
            bool inside = true, beyond_open = false;
            for (int k = 0; k < 3; ++k)
                if (w[(k + 2) % 3] < 0.0f) {
                    inside = false;
                    beyond_open = beyond_open || (open & (1 << k));
                }
            if (!inside && (!extend || beyond_open)) continue;
            if (!colour) {
                if (mesh.covered_at(f, w[1], w[2])) mask |= block << (b * step * k_contour_subsamples + a * step);
                continue;
            }
            glm::vec4 albedo = mesh.albedo_at(f, w[1], w[2]);
            if (cutoff > 0.0f && albedo.w < cutoff) continue;
            mask |= block << (b * step * k_contour_subsamples + a * step);
            sum += glm::vec3(albedo) * float(step * step);
        }
    if (colour && mask) *colour = sum / float(std::popcount(mask));
    return mask;
}

// The colour alpha code that best matches contour points `target`: 255 (whole texel), an edge
// line, or 0 (nothing) when `may_be_empty`; ties keep the first of that order.
std::uint8_t best_contour_code(std::uint64_t target, bool may_be_empty)
{
    int best_error = std::popcount(~target);
    std::uint8_t best = 255;
    if (may_be_empty && std::popcount(target) < best_error) best_error = std::popcount(target), best = 0;
    const auto& masks = edge_line_masks();
    for (int code = 0; code < k_edge_line_codes; ++code) {
        int error = std::popcount(masks[std::size_t(code)] ^ target);
        if (error < best_error) best_error = error, best = std::uint8_t(EDGE_LINE_FIRST_CODE + code);
    }
    return best;
}

// The open edge nearest a texel's centre among those whose line crosses the texel's square: the
// outward unit normal (away from the face) in texel units, the line's signed distance from the
// centre along it (positive: the centre is on the face's side), and the edge's depth there.
struct EdgeLine {
    double distance = std::numeric_limits<double>::max(); // from the texel centre to the edge segment
    std::uint32_t face = k_none;
    glm::dvec2 normal{0.0};
    double offset = 0.0;
    float depth = 0.0f;
};

// Every texel within reach of an open edge of a captured face, with the nearest such edge; on a
// covered texel only edges of the part its winner belongs to (a casing's rim touching a flange does
// not cut the flange). Serial over the faces in ascending order (ties keep the first), so the result
// is deterministic. Sparse: few texels lie on an open edge, and a line per texel of the grid (48
// bytes, millions of texels on foliage grids) was allocated and cleared for each billboard, serially
// (the 2,000-face tree's bake: 2.5 of its 32 s).
struct EdgeLines {
    std::vector<std::int32_t> slot; // per texel: index into lines, or -1
    std::vector<EdgeLine> lines;
    std::vector<std::size_t> texel; // per line: its texel
};

EdgeLines nearest_open_edges(const Mesh& mesh, const FaceData& faces, const Grid& grid,
                             const std::vector<std::uint32_t>& captured_faces, const std::vector<std::uint8_t>& covered,
                             bool contour_lines)
{
    EdgeLines found;
    found.slot.assign(std::size_t(grid.width) * grid.height, -1);
    for (std::uint32_t f : captured_faces) {
        // an alpha-tested card's edges are not its leaf's outline: its contour lines are
        if (!faces.open_edges[f] || (contour_lines && is_alpha_tested(mesh, f))) continue;
        Corners c = corners(mesh, grid, f);
        for (int k = 0; k < 3; ++k) {
            if (!(faces.open_edges[f] & (1 << k))) continue;
            int a = k, b = (k + 1) % 3, opposite = (k + 2) % 3;
            glm::dvec2 pa(double(c.x[a]) / k_subtexel, double(c.y[a]) / k_subtexel);
            glm::dvec2 pb(double(c.x[b]) / k_subtexel, double(c.y[b]) / k_subtexel);
            glm::dvec2 po(double(c.x[opposite]) / k_subtexel, double(c.y[opposite]) / k_subtexel);
            glm::dvec2 along = pb - pa;
            double length = glm::length(along);
            if (!(length > 0.0)) continue;
            glm::dvec2 normal(along.y / length, -along.x / length);
            if (glm::dot(normal, po - pa) > 0.0) normal = -normal; // away from the face
            double reach = 0.5 * (std::abs(normal.x) + std::abs(normal.y));
            int i0 = std::max(0, int(std::floor(std::min(pa.x, pb.x))) - 1);
            int i1 = std::min(grid.width - 1, int(std::floor(std::max(pa.x, pb.x))) + 1);
            int j0 = std::max(0, int(std::floor(std::min(pa.y, pb.y))) - 1);
            int j1 = std::min(grid.height - 1, int(std::floor(std::max(pa.y, pb.y))) + 1);
            for (int j = j0; j <= j1; ++j)
                for (int i = i0; i <= i1; ++i) {
                    glm::dvec2 centre(i + 0.5, j + 0.5);
                    double offset = glm::dot(normal, pa - centre);
                    if (std::abs(offset) >= reach) continue; // the line misses the square
                    double s = std::clamp(glm::dot(centre - pa, along) / (length * length), 0.0, 1.0);
                    double distance = glm::length(pa + s * along - centre);
                    std::size_t t = std::size_t(j) * grid.width + i;
                    if (covered[t] && faces.part[std::uint32_t(grid.items[t] & 0xffffffffu)] != faces.part[f]) continue;
                    if (distance > 0.75) continue; // about half the diagonal
                    if (found.slot[t] < 0) {
                        found.slot[t] = std::int32_t(found.lines.size());
                        found.lines.emplace_back();
                        found.texel.push_back(t);
                    }
                    EdgeLine& line = found.lines[std::size_t(found.slot[t])];
                    if (distance >= line.distance) continue;
                    line = {distance, f, normal, offset, float((1.0 - s) * c.z[a] + s * c.z[b])};
                }
        }
    }
    return found;
}

// The colour alpha code of an edge line (billboard_layout.glsl): EDGE_LINE_ANGLES directions of
// the outward normal, EDGE_LINE_OFFSETS positions of the line across the square along it, from
// -1 to 1 of the half-extent (|n.x| + |n.y|) / 2 where the line still meets the square.
std::uint8_t edge_line_code(glm::dvec2 normal, double offset)
{
    const double step = 2.0 * 3.14159265358979323846 / EDGE_LINE_ANGLES;
    long angle = std::lround(std::atan2(normal.y, normal.x) / step);
    angle = ((angle % EDGE_LINE_ANGLES) + EDGE_LINE_ANGLES) % EDGE_LINE_ANGLES;
    glm::dvec2 quantised(std::cos(double(angle) * step), std::sin(double(angle) * step));
    // the point of the line nearest the centre stays on the line drawn with the quantised normal
    double along = offset * glm::dot(quantised, normal);
    double half_extent = 0.5 * (std::abs(quantised.x) + std::abs(quantised.y));
    double position = std::clamp((along / half_extent + 1.0) * 0.5, 0.0, 1.0);
    int level = std::clamp(int(position * EDGE_LINE_OFFSETS), 0, EDGE_LINE_OFFSETS - 1);
    return std::uint8_t(EDGE_LINE_FIRST_CODE + angle * EDGE_LINE_OFFSETS + level);
}

// Outline lines (issue #17): a texel is covered or not by its centre, so where a surface ends
// within a texel (the silhouette of a thin leg, a letter's end over the plane it stands on) the
// outline was a staircase of whole texels, up to a texel out (spill, and walls a ray from another
// side hits) or in (holes no other billboard need fill). The 8 x 8 points of the alpha contour are
// rasterised for the texels next to an outline, keeping the front-most facing face per point
// (rasterise_outline_points); then
// - a covered texel keeps the points on its own surface (outline_surface_points: the winner's
//   plane within its tolerance, or nearer, where something in front hides whether the surface goes
//   on, as its centre did) and stores the line that best splits them (best_contour_code);
// - an empty texel that a covered neighbour's surface reaches into is grown with that surface
//   (the neighbour holding most of its points), clipped the same way, at the mean depth of those
//   points. Only points within a quarter texel of the neighbour's plane count, and none a nearer
//   face hides: grown on the face's whole tolerance, the texels of a surface curving away from the
//   billboard stood out of it as shelves (spill 0.07% -> 0.19% on a noisy sphere), and at the
//   face's nearest point instead of the points' own depth, 0.09%.
struct OutlinePoints {
    std::vector<std::int32_t> slot;  // per grid texel: index of its points in keys / 64, or -1
    std::vector<std::uint64_t> keys; // per point: (quantised depth << 32) | face id, as Grid::items
};

constexpr int k_outline_points = k_contour_subsamples * k_contour_subsamples;
constexpr float k_grow_tolerance_texels = 0.25f;

// Barycentric weights of fixed-point point (px, py) in face c (`inverse`: 1 / its doubled area),
// unclamped: negative outside the face, and the depth of the face's plane there.
float plane_depth_at(const Corners& c, double inverse, std::int64_t px, std::int64_t py, double w[3])
{
    w[0] = double(edge(c, 1, 2, px, py)) * inverse;
    w[1] = double(edge(c, 2, 0, px, py)) * inverse;
    w[2] = double(edge(c, 0, 1, px, py)) * inverse;
    return float(w[0] * c.z[0] + w[1] * c.z[1] + w[2] * c.z[2]);
}

OutlinePoints rasterise_outline_points(const Mesh& mesh, const Grid& grid, const std::vector<std::uint32_t>& occluders,
                                       const std::vector<std::size_t>& texels)
{
    OutlinePoints points;
    points.slot.assign(grid.items.size(), -1);
    for (std::size_t k = 0; k < texels.size(); ++k) points.slot[texels[k]] = std::int32_t(k);
    points.keys.assign(texels.size() * k_outline_points, k_empty);
    parallel_over(occluders.size(), [&](std::size_t r) {
        std::uint32_t f = occluders[r];
        Corners c = corners(mesh, grid, f);
        std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
        if (area2 == 0) return;
        const bool alpha_tested = is_alpha_tested(mesh, f);
        int i0 = std::max(0, int(std::min({c.x[0], c.x[1], c.x[2]}) >> k_subtexel_bits));
        int i1 = std::min(grid.width - 1, int(std::max({c.x[0], c.x[1], c.x[2]}) >> k_subtexel_bits));
        int j0 = std::max(0, int(std::min({c.y[0], c.y[1], c.y[2]}) >> k_subtexel_bits));
        int j1 = std::min(grid.height - 1, int(std::max({c.y[0], c.y[1], c.y[2]}) >> k_subtexel_bits));
        const double inverse = 1.0 / double(area2);
        for (int j = j0; j <= j1; ++j)
            for (int i = i0; i <= i1; ++i) {
                std::int32_t s = points.slot[std::size_t(j) * grid.width + i];
                if (s < 0) continue;
                for (int b = 0; b < k_contour_subsamples; ++b)
                    for (int a = 0; a < k_contour_subsamples; ++a) {
                        double w[3];
                        float depth = plane_depth_at(c, inverse, contour_point(i, a), contour_point(j, b), w);
                        if (w[0] < 0.0 || w[1] < 0.0 || w[2] < 0.0) continue;
                        if (alpha_tested && !mesh.covered_at(f, float(w[1]), float(w[2]))) continue;
                        atomic_min(points.keys[std::size_t(s) * k_outline_points + std::size_t(b * k_contour_subsamples + a)],
                                   (std::uint64_t(grid.key_depth(depth)) << 32) | f);
                    }
            }
    });
    return points;
}

// The points of texel t on face f's surface (see above): for a covered texel (`growing` false)
// within f's tolerance of its plane or nearer; for one to grow into, within a quarter texel.
// `mean_depth`, when given, receives the mean depth of the points found.
std::uint64_t outline_surface_points(const Mesh& mesh, const FaceData& faces, const Grid& grid, const OutlinePoints& points,
                                     std::size_t t, std::uint32_t f, bool growing, float* mean_depth = nullptr)
{
    Corners c = corners(mesh, grid, f);
    std::int64_t area2 = edge(c, 0, 1, c.x[2], c.y[2]);
    std::int32_t s = points.slot[t];
    if (area2 == 0 || s < 0) return 0;
    // the depth neighbouring faces of one surface may be off a face's plane across a texel
    // (classify's tolerance)
    float facing = std::max(-glm::dot(faces.normal[f], glm::vec3(grid.w)), 1e-3f);
    float slope = std::min(std::sqrt(std::max(0.0f, 1.0f - facing * facing)) / facing, 8.0f);
    float tolerance = float(grid.texel) * (growing ? k_grow_tolerance_texels : 1.0f + slope);
    const int i = int(t % std::size_t(grid.width)), j = int(t / std::size_t(grid.width));
    const double inverse = 1.0 / double(area2);
    std::uint64_t mask = 0;
    double depth_sum = 0.0;
    for (int b = 0; b < k_contour_subsamples; ++b)
        for (int a = 0; a < k_contour_subsamples; ++a) {
            std::uint64_t key = points.keys[std::size_t(s) * k_outline_points + std::size_t(b * k_contour_subsamples + a)];
            if (key == k_empty) continue;
            double w[3];
            float plane = plane_depth_at(c, inverse, contour_point(i, a), contour_point(j, b), w);
            float depth = grid.depth_of_key(key);
            if (depth > plane + tolerance || (growing && depth < plane - tolerance)) continue;
            mask |= 1ull << (b * k_contour_subsamples + a);
            depth_sum += depth;
        }
    if (mean_depth && mask) *mean_depth = float(depth_sum / double(std::popcount(mask)));
    return mask;
}

Billboard write_maps(const Mesh& mesh, const FaceData& faces, const Grid& grid, const std::vector<std::uint32_t>& slot,
                     const std::vector<std::uint8_t>& captured, const std::vector<std::uint32_t>& captured_faces,
                     const std::vector<std::uint32_t>& occluders, bool edge_lines)
{
    int width = grid.width, height = grid.height;
    std::vector<std::uint8_t> covered(std::size_t(width) * height, 0);
    auto winner_at = [&](std::size_t t) { return std::uint32_t(grid.items[t] & 0xffffffffu); };
    parallel_over(covered.size(), [&](std::size_t t) {
        if (grid.items[t] == k_empty) return;
        std::uint32_t s = slot[winner_at(t)];
        covered[t] = s != k_none && captured[s];
    });
    // rim: front-most surface next to a captured texel, continuing its depth
    std::vector<std::uint8_t> rim(covered.size(), 0);
    float rim_depth = k_rim_depth_texels * float(grid.texel);
    parallel_over(covered.size(), [&](std::size_t t) {
        if (covered[t] || grid.items[t] == k_empty) return;
        int i = int(t % width), j = int(t / width);
        float depth = grid.depth_of_key(grid.items[t]);
        const int di[4] = {1, -1, 0, 0}, dj[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4; ++k) {
            int ni = i + di[k], nj = j + dj[k];
            if (ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
            std::size_t n = std::size_t(nj) * width + ni;
            if (covered[n] && std::abs(grid.depth_of_key(grid.items[n]) - depth) <= rim_depth) {
                rim[t] = 1;
                return;
            }
        }
    });
    // sheet edges (issue #17): texels are covered where their centre is on the surface, and a
    // closed part's edge is a wall that other billboards capture and overlap, but nothing lies
    // beyond the edge of a sheet, so its outline lost about half the texels the edge crosses: holes
    // along every rim seen at an angle. Those texels are covered too, by the captured face next to
    // them that overlaps them across an open edge (its attributes at its nearest point).
    // alpha contour lines need no open edges (an alpha-tested model's sheet edges are its cards')
    const bool contour_lines = edge_lines;
    std::vector<std::uint32_t> grown(faces.open_edges.empty() && !contour_lines ? 0 : covered.size(), k_none);
    // the first captured face of the 8 neighbours (rows, then columns) overlapping texel (i, j) across
    // an open edge, or k_none
    auto neighbour_across_open_edge = [&](int i, int j) {
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                int ni = i + di, nj = j + dj;
                if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
                std::size_t n = std::size_t(nj) * width + ni;
                if (!covered[n]) continue;
                std::uint32_t f = winner_at(n);
                if (faces.open_edges[f] && !(contour_lines && is_alpha_tested(mesh, f)) && across_open_edge(corners(mesh, grid, f), faces.open_edges[f], i, j)) return f;
            }
        return k_none;
    };
    // sheet edge lines: the texels an open edge crosses are covered, and clipped to its line
    // (march.frag); a texel another surface wins keeps that surface whole
    edge_lines = edge_lines && !faces.open_edges.empty();
    std::vector<std::uint8_t> line_code(edge_lines || contour_lines ? covered.size() : 0, 0);
    if (edge_lines) {
        const EdgeLines found = nearest_open_edges(mesh, faces, grid, captured_faces, covered, contour_lines);
        parallel_over(found.lines.size(), [&](std::size_t k) {
            const EdgeLine& line = found.lines[k];
            const std::size_t t = found.texel[k];
            if (line.face == k_none || rim[t]) return;
            int i = int(t % width), j = int(t / width);
            if (covered[t]) {
                std::uint32_t f = winner_at(t);
                if (f != line.face && std::abs(grid.depth_of_key(grid.items[t]) - line.depth) > rim_depth) return;
            } else {
                // the face the edge is on overlaps the texel across it, or else a captured
                // neighbour does across one of its open edges (the rim turns within the texel)
                bool across = across_open_edge(corners(mesh, grid, line.face), faces.open_edges[line.face], i, j);
                std::uint32_t face = across ? line.face : neighbour_across_open_edge(i, j);
                if (face == k_none) return;
                grown[t] = face;
            }
            line_code[t] = edge_line_code(line.normal, line.offset);
        });
    }
    // alpha contour lines (issue #14): a texel the leaf's cut-out contour crosses keeps the line
    // that best splits it (best_contour_code); a texel whose centre is cut out but which a
    // neighbour's leaf partly covers is grown with that leaf and clipped the same way. The colour of
    // every texel of a leaf is the mean over its covered contour points (the truth's coverage-
    // weighted mips, 64 points where texel_albedo reads 9).
    std::vector<glm::vec4> contour_colour(contour_lines ? covered.size() : 0, glm::vec4(0.0f));
    if (contour_lines) {
        parallel_over(covered.size(), [&](std::size_t t) {
            if (line_code[t] != 0 || grown[t] != k_none) return;
            int i = int(t % width), j = int(t / width);
            const bool whole = covered[t] || rim[t];
            std::uint32_t front = k_none;
            std::uint64_t front_mask = 0;
            glm::vec3 colour(0.0f);
            if (whole) {
                front = winner_at(t);
                if (!is_alpha_tested(mesh, front)) return;
                front_mask = face_coverage(mesh, faces, grid, front, i, j, true, &colour);
                if (front_mask == ~0ull) {
                    // a whole leaf texel: no line, and the finer mean (measured: Luv d1 3.94 -> 3.89)
                    contour_colour[t] = glm::vec4(colour, 1.0f);
                    return;
                }
            } else {
                // the alpha-tested face of a covered 3 x 3 neighbour that covers most of the texel
                // (ties: the first, rows then columns). Each distinct face is tested once and by its
                // alpha only; the winner's colour is read after (the same points: the same mean).
                // In a dense crown many texels are gaps between leaves with several leaf neighbours
                // (a 30,000-card tree's bake: 230 -> 210 s, the same bytes).
                std::uint32_t tested[9];
                int tested_count = 0;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        int ni = i + di, nj = j + dj;
                        if (ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
                        std::size_t n = std::size_t(nj) * width + ni;
                        std::uint32_t f = winner_at(n);
                        if ((!covered[n] && !rim[n]) || f == front || !is_alpha_tested(mesh, f)) continue;
                        if (std::find(tested, tested + tested_count, f) != tested + tested_count) continue;
                        tested[tested_count++] = f;
                        std::uint64_t mask = face_coverage(mesh, faces, grid, f, i, j, true);
                        if (std::popcount(mask) > std::popcount(front_mask)) front = f, front_mask = mask;
                    }
                if (front == k_none) return;
                if (front_mask) face_coverage(mesh, faces, grid, front, i, j, true, &colour);
            }
            // the texel shows the front leaf only: where it is cut out the ray goes on (a leaf behind
            // it in this texel is lost either way; counting it as the front leaf's, measured, kept
            // leaf-over-leaf edges on texel borders: Luv d1 4.07 against 3.94)
            std::uint8_t code = best_contour_code(front_mask, !whole);
            if (code == 0) return;
            if (!whole) grown[t] = front;
            if (code != 255) line_code[t] = code;
            if (front_mask) contour_colour[t] = glm::vec4(colour, 1.0f);
        });
    }
    // outline lines (issue #17; above): the texels next to an outline that no sheet edge or leaf
    // contour already holds (those keep theirs)
    std::vector<float> grown_depth; // per texel grown at its outline: the depth of its points, else NaN
    if (contour_lines) {
        auto whole = [&](std::size_t t) { return covered[t] || rim[t]; };
        auto has_line = [&](std::size_t t) { return line_code[t] != 0 || grown[t] != k_none; };
        auto outlined = [&](std::uint32_t f) { return !is_alpha_tested(mesh, f); }; // leaves have contours
        std::vector<std::size_t> texels; // ascending
        for (std::size_t t = 0; t < covered.size(); ++t) {
            if (has_line(t) || (whole(t) && !outlined(winner_at(t)))) continue;
            int i = int(t % width), j = int(t / width);
            bool outline = false; // a neighbour on the other side of the covered texels' edge
            for (int dj = -1; dj <= 1 && !outline; ++dj)
                for (int di = -1; di <= 1 && !outline; ++di) {
                    int ni = i + di, nj = j + dj;
                    if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
                    std::size_t n = std::size_t(nj) * width + ni;
                    outline = whole(n) != whole(t) && (whole(t) || outlined(winner_at(n)));
                }
            if (outline) texels.push_back(t);
        }
        OutlinePoints points = rasterise_outline_points(mesh, grid, occluders, texels);
        std::vector<std::uint8_t> outline_code(covered.size(), 0);
        std::vector<std::uint32_t> outline_face(covered.size(), k_none);
        grown_depth.assign(covered.size(), std::numeric_limits<float>::quiet_NaN());
        parallel_over(texels.size(), [&](std::size_t k) {
            std::size_t t = texels[k];
            if (whole(t)) {
                outline_code[t] = best_contour_code(outline_surface_points(mesh, faces, grid, points, t, winner_at(t), false), false);
                return;
            }
            // grow the surface of the covered 3 x 3 neighbour that holds most of the texel's points
            // (ties: the first, rows then columns)
            int i = int(t % width), j = int(t / width);
            std::uint32_t best = k_none;
            std::uint64_t best_points = 0;
            float best_depth = 0.0f;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    int ni = i + di, nj = j + dj;
                    if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= width || nj >= height) continue;
                    std::size_t n = std::size_t(nj) * width + ni;
                    std::uint32_t f = winner_at(n);
                    if (!whole(n) || f == best || !outlined(f)) continue;
                    float depth = 0.0f;
                    std::uint64_t on = outline_surface_points(mesh, faces, grid, points, t, f, true, &depth);
                    if (std::popcount(on) > std::popcount(best_points)) best = f, best_points = on, best_depth = depth;
                }
            if (best == k_none) return;
            std::uint8_t code = best_contour_code(best_points, true);
            if (code == 0) return;
            outline_face[t] = best;
            outline_code[t] = code;
            grown_depth[t] = best_depth;
        });
        for (std::size_t t : texels) {
            if (outline_face[t] != k_none) grown[t] = outline_face[t];
            if (outline_code[t] != 0 && outline_code[t] != 255) line_code[t] = outline_code[t];
        }
    }
    if (!faces.open_edges.empty() && !edge_lines) {
        parallel_over(covered.size(), [&](std::size_t t) {
            if (covered[t] || rim[t]) return;
            grown[t] = neighbour_across_open_edge(int(t % width), int(t / width));
        });
    }
    for (std::size_t t = 0; t < covered.size(); ++t) covered[t] |= rim[t] | std::uint8_t(!grown.empty() && grown[t] != k_none);
    auto face_at = [&](std::size_t t) { return !grown.empty() && grown[t] != k_none ? grown[t] : winner_at(t); };

    // crop to the covered texels plus one empty texel of margin
    int lo_i = width, hi_i = -1, lo_j = height, hi_j = -1;
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i)
            if (covered[std::size_t(j) * width + i]) {
                lo_i = std::min(lo_i, i), hi_i = std::max(hi_i, i);
                lo_j = std::min(lo_j, j), hi_j = std::max(hi_j, j);
            }
    Billboard board;
    if (hi_i < 0) return board;
    lo_i -= 1, lo_j -= 1, hi_i += 1, hi_j += 1; // inside the grid: it has a margin of k_grid_margin
    board.width = hi_i - lo_i + 1;
    board.height = hi_j - lo_j + 1;

    // surface point per covered texel: the winner's attributes at the texel centre
    std::size_t n = std::size_t(board.width) * board.height;
    std::vector<float> depth(n, 0.0f);
    std::vector<glm::vec3> normal(n, glm::vec3(0.0f));
    std::vector<glm::vec4> albedo(n, glm::vec4(0.0f));
    // PBR inputs (issue #14) only for models that have them: other packages stay as they were
    const bool pbr = mesh.has_pbr_materials();
    std::vector<PbrSample> surface(pbr ? n : 0);
    parallel_over(n, [&](std::size_t k) {
        int i = lo_i + int(k % board.width), j = lo_j + int(k / board.width);
        std::size_t t = std::size_t(j) * width + i;
        if (!covered[t]) return;
        std::uint32_t f = face_at(t);
        Corners c = corners(mesh, grid, f);
        float wt[3];
        clamped_weights(c, i, j, wt);
        depth[k] = wt[0] * c.z[0] + wt[1] * c.z[1] + wt[2] * c.z[2];
        if (!grown_depth.empty() && !std::isnan(grown_depth[t])) depth[k] = grown_depth[t];
        glm::vec3 sum(0.0f);
        for (int v = 0; v < 3; ++v) sum += wt[v] * mesh.normals[mesh.indices[std::size_t(f) * 3 + v]];
        float length = glm::length(sum);
        normal[k] = length > 0.0f ? sum / length : glm::vec3(-grid.w);
        albedo[k] = !contour_colour.empty() && contour_colour[t].w > 0.0f ? contour_colour[t] : texel_albedo(mesh, f, c, i, j, wt);
        if (pbr) {
            surface[k] = mesh.pbr_at(f, wt[1], wt[2]);
            if (mesh.materials[mesh.face_materials[f]].normal_texture >= 0) normal[k] = mesh.shading_normal_at(f, wt[1], wt[2]);
        }
    });
    float front = std::numeric_limits<float>::max(), back = std::numeric_limits<float>::lowest();
    for (std::size_t k = 0; k < n; ++k)
        if (covered[std::size_t(lo_j + int(k / board.width)) * width + lo_i + int(k % board.width)]) {
            front = std::min(front, depth[k]);
            back = std::max(back, depth[k]);
        }

    board.texel_size = float(grid.texel);
    board.depth_range = std::max(back - front, 0.01f * board.texel_size);
    board.axis_u = glm::vec3(grid.u);
    board.axis_v = glm::vec3(grid.v);
    board.direction = glm::vec3(grid.w);
    board.origin = glm::vec3(grid.center + grid.u * (double(grid.x0 + lo_i) * grid.texel) +
                             grid.v * (double(grid.y0 + lo_j) * grid.texel) + grid.w * double(front));
    board.color = ImageRGBA8(board.width, board.height);
    board.normal_depth = ImageRGBA16(board.width, board.height);
    if (pbr) board.orm = ImageRGBA8(board.width, board.height), board.emission = ImageRGBA8(board.width, board.height);
    auto unorm8 = [](float x) { return std::uint8_t(std::lround(std::clamp(x, 0.0f, 1.0f) * 255.0f)); };
    for (int y = 0; y < board.height; ++y)
        for (int x = 0; x < board.width; ++x) {
            std::size_t k = std::size_t(y) * board.width + x;
            if (!covered[std::size_t(lo_j + y) * width + lo_i + x]) continue;
            std::uint8_t* rgba = board.color.at(x, y);
            std::uint8_t code = line_code.empty() ? 0 : line_code[std::size_t(lo_j + y) * width + lo_i + x];
            rgba[0] = unorm8(albedo[k].x), rgba[1] = unorm8(albedo[k].y), rgba[2] = unorm8(albedo[k].z);
            rgba[3] = code != 0 ? code : 255;
            std::uint16_t* nd = board.normal_depth.at(x, y);
            for (int a = 0; a < 3; ++a) nd[a] = reps::encode_normal(normal[k][a]);
            nd[3] = reps::encode_depth((depth[k] - front) / board.depth_range);
            if (pbr) {
                const PbrSample& s = surface[k];
                reps::write_pbr_texel(board.orm, board.emission, x, y, s.occlusion, s.roughness, s.metallic, s.emissive);
            }
        }
    return board;
}

} // namespace

FaceData compute_face_data(const Mesh& mesh)
{
    FaceData data;
    std::size_t n = mesh.triangle_count();
    data.normal.resize(n);
    data.area.resize(n);
    parallel_over(n, [&](std::size_t f) {
        const std::uint32_t* idx = &mesh.indices[f * 3];
        glm::dvec3 p0 = mesh.positions[idx[0]], p1 = mesh.positions[idx[1]], p2 = mesh.positions[idx[2]];
        glm::dvec3 cross = glm::cross(p1 - p0, p2 - p0);
        double length = glm::length(cross);
        data.area[f] = 0.5 * length;
        if (!(length > 0.0) || !std::isfinite(length)) {
            data.area[f] = 0.0;
            data.normal[f] = glm::vec3(0.0f);
            return;
        }
        glm::vec3 normal(cross / length);
        // a face wound against its vertex normals is oriented by them (models with flipped winding)
        glm::vec3 shading = mesh.normals[idx[0]] + mesh.normals[idx[1]] + mesh.normals[idx[2]];
        data.normal[f] = glm::dot(normal, shading) < 0.0f ? -normal : normal;
    });
    return data;
}

bool edge_line_contains(std::uint8_t code, glm::vec2 p)
{
    if (code >= 255 || code < EDGE_LINE_FIRST_CODE) return true;
    int k = code - EDGE_LINE_FIRST_CODE;
    float angle = float(k / EDGE_LINE_OFFSETS) * (6.28318530718f / float(EDGE_LINE_ANGLES));
    glm::vec2 n(std::cos(angle), std::sin(angle));
    float e = ((float(k % EDGE_LINE_OFFSETS) + 0.5f) / float(EDGE_LINE_OFFSETS) * 2.0f - 1.0f) * 0.5f * (std::abs(n.x) + std::abs(n.y));
    return glm::dot(n, p - glm::vec2(0.5f)) <= e;
}

void plane_basis(glm::vec3 w, glm::vec3& u, glm::vec3& v)
{
    glm::vec3 up = std::abs(w.y) < 0.99f ? glm::vec3(0, 1, 0) : glm::vec3(0, 0, 1);
    v = glm::normalize(up - w * glm::dot(up, w));
    u = glm::cross(v, w);
}

Capture capture_direction(const Mesh& mesh, const FaceData& faces, const std::vector<std::uint32_t>& remaining,
                          glm::vec3 w, const CaptureSettings& settings)
{
    assert(std::abs(glm::length(w) - 1.0f) < 1e-4f);
    Capture capture;
    // project every vertex: plane coordinates in texels and depth, relative to the bounds' centre
    Grid grid;
    glm::vec3 u, v;
    plane_basis(w, u, v);
    Bounds bounds = mesh.bounds();
    grid.center = glm::dvec3(bounds.center());
    grid.u = u, grid.v = v, grid.w = w;
    grid.texel = settings.texel_size;
    grid.a.resize(mesh.vertex_count());
    grid.b.resize(mesh.vertex_count());
    grid.z.resize(mesh.vertex_count());
    parallel_over(mesh.vertex_count(), [&](std::size_t i) {
        glm::dvec3 p = glm::dvec3(mesh.positions[i]) - grid.center;
        grid.a[i] = float(glm::dot(p, grid.u) / grid.texel);
        grid.b[i] = float(glm::dot(p, grid.v) / grid.texel);
        grid.z[i] = float(glm::dot(p, grid.w));
    });

    // S, S' and the plane at the front of the projectable faces
    Sets sets = classify(mesh, faces, remaining, grid, settings);
    if (sets.candidates.empty()) return capture;
    place_grid(mesh, sets, grid);

    // S'': item buffer, then per face whether any of its texels is hidden
    fill_items(mesh, sets, grid);
    std::vector<std::uint32_t> slot(mesh.triangle_count(), k_none);
    for (std::size_t r = 0; r < sets.candidates.size(); ++r) slot[sets.candidates[r]] = std::uint32_t(r);
    std::vector<Visibility> visibility = test_visibility(mesh, sets, grid);
    std::vector<std::uint8_t> captured = decide_captured(sets, visibility, slot, settings.partly_visible);
    // faces left for another billboard decide visibility like the rest (they hide, they stand for a
    // sub-texel face's texel, they intersect), but are not captured here
    if (settings.allowed)
        for (std::size_t r = 0; r < sets.candidates.size(); ++r) {
            if (!(*settings.allowed)[sets.candidates[r]]) {
                captured[r] = 0;
            } else if (!captured[r] && visibility[r].hidden) {
                for (int k = 0; k < visibility[r].occluder_count; ++k) capture.hidden_by.push_back({sets.candidates[r], visibility[r].occluders[k]});
            }
        }

    for (std::size_t r = 0; r < sets.candidates.size(); ++r)
        if (captured[r]) {
            const Visibility& v = visibility[r];
            capture.faces.push_back(sets.candidates[r]);
            capture.area += faces.area[sets.candidates[r]];
            if (settings.partly_visible > 0.0f && v.hidden_texels > 0 && v.texels > 0) {
                capture.hidden_area += faces.area[sets.candidates[r]] * double(v.hidden_texels) / double(v.texels);
                capture.partly_hidden.push_back(sets.candidates[r]);
            }
        }
    if (settings.write_maps && !capture.faces.empty()) {
        capture.billboard = write_maps(mesh, faces, grid, slot, captured, capture.faces, sets.occluders, settings.edge_lines);
        capture.billboard.captured_faces = capture.faces.size();
        capture.billboard.captured_area = capture.area - capture.hidden_area;
    }
    return capture;
}

} // namespace standin::billboards
