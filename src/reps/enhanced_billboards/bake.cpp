// Greedy construction of enhanced billboards.
// Vichitvejpaisal 2005 (§3.2, §3.4, §4.3), Vichitvejpaisal & Kanongchaiyos 2006 (§3.1, Fig. 3).
//
// Steps: one texel size for the whole model (seed: bounding-box diagonal -> 512 texels); then,
// while faces are left, choose a direction, capture what a billboard along it can hold
// (capture.cpp: S, S', S''), remove it, repeat; finally a coarse mesh for hole filling (§3.4).
// Differences from the seed, each chosen by measurement (docs/RESULTS.md, "Bake"):
// - candidate directions: the seed's 36 x 18 array by default; an even Fibonacci set of any size
//   (--directions sphere, --direction-count, default k_default_direction_count) measured no fewer
//   billboards and no better coverage on our models, so it is an option; --directions axis is the
//   seed's ±X/±Y/±Z comparison (Fig. 4-4, 4-5).
// - depth limit: none within the model by default (1 diagonal): 0.5 and 0.25 gave more billboards
//   and left more surface occluded on models with nested parts.
// - faces longer than k_split_texels texels (k_alpha_split_texels for alpha-tested models) are split
//   before baking, since the occlusion test is all or nothing per face (see split_long_edges); the
//   alpha-tested faces the greedy leaves are split again to k_split_texels and the greedy goes on
//   (the second round, in bake_pass).
// - score: the seed counts facing faces (--score faces). The default (--score area) ranks the
//   candidates by the projected area of the remaining non-grazing faces facing them (a histogram of
//   normals makes this cheap for every candidate), then captures the best k_exact_candidates,
//   angularly apart, exactly at half resolution and takes the one that really captures the most
//   area.
// - grazing angle 20 degrees instead of the seed's 10 (§4.3; 30 for alpha-tested models, below): a
//   face is projected only onto a billboard it faces by at least that much. A face captured steeply
//   is a streak of texels joined by walls, whose tiles are as deep as the face is long: rays from
//   other directions cross more texels there (fetches), meet the walls a texel off (colour, spill),
//   and pass between texels the links do not join (holes). Measured on 13 models (docs/RESULTS.md
//   "A grazing angle of 20 degrees"): thesis Luv lower on 11 (the noisy sphere 0.261 -> 0.202, the
//   held-out engine 1.214 -> 1.107), holes without the coarse mesh lower on most, fetches per
//   covered pixel 11.8 -> 9.4. 30 degrees gained more (0.183, 0.992; 7.2 fetches) but drew 39% more
//   proxy triangles in a crowd of tiny instances, whose frame it slowed by half on llvmpipe (20
//   degrees: +18%).
// - face assignment (--face-assignment squarer, not the default): the greedy captures every face a
//   direction can hold, however steeply; squarer keeps the greedy's directions and moves a face seen
//   over k_squarer_angle off its normal to a later billboard that sees it more squarely
//   (assign_squarer). Measured on 14 models (docs/RESULTS.md "Faces on the billboard that sees them
//   squarely"): thesis Luv lower on 11 (up to 29%) and lower than the same bytes spent on texels,
//   up to 3 more billboards, 9-41% more package bytes and 1.7-3.1x the bake time, so an option.
// - stopping: when nothing is left, when what is left cannot be captured (grazing in every
//   candidate direction, degenerate, or hidden in a way the intersection bypass does not resolve),
//   at --max-billboards, or when the best billboard would capture less than --min-coverage of the
//   surface: the seed drops such billboards (§4.3), and every later one would be as small. Of the
//   surface found so far (below_min_coverage), not the seed's whole: a dense crown's inside, hidden from every
//   direction, was most of the whole and stopped the greedy halfway round its outside. What was
//   left is recorded with its reason; the coarse mesh covers it.
// - sheets (issue #17): the seed's models are closed; open surfaces (zero-thickness CAD sheets)
//   show both sides in the ground truth, so their faces also get reversed copies baked from the
//   other side, and closed parts wound inside out are reversed (see add_back_sides).
// - resolution per billboard: instead of the seed's 512² or 256², every billboard keeps the model's
//   texel size and is cropped to its content plus one texel (fewer bytes at equal fidelity).
// - models with detail finer than the default texels (issue #17: fins, grilles, nested thin parts)
//   are baked again at k_detail_resolution when more than k_detail_edge_fraction of the covered
//   texels end their surface (depth_edge_fraction): such texels are where rays meet depth edges the
//   capture could not resolve, and where the held-out engine's pictures lost (billboards.h).
// - alpha-tested models (leaf cards, issue #14) default to k_alpha_resolution texels along the
//   diagonal instead of 512, or finer where their cut-out textures are, up to
//   k_alpha_max_resolution (cutout_resolution): at 512 a leaf's outline and the gaps between leaves
//   are coarser than a pixel at distance 1, and the crown's silhouette IoU at distance 8 falls
//   under 0.95; at 1024 the leaves' edges inside the crown still sit half a texel off, where half a
//   pixel of the truth itself costs over 1 Luv.
//   Their faces are projected only onto billboards they face by at least k_alpha_grazing_angle
//   (30 degrees instead of 20): a card captured edge-on is a streak of texels with walls, which
//   rays from other directions hit where the truth shows another card.
//   Their coarse mesh is made of the opaque faces only (trunk, branches): it cannot cut out a
//   leaf card, and whole cards filled the near-miss ring around every leaf (see opaque_faces).
//   And a leaf that others hide at some of its texels is captured where it is in front when at
//   least k_alpha_partly_hidden of its texels are (--partly-hidden; capture.cpp): in a dense crown
//   every card is partly hidden from every direction, and the seed's test stopped the greedy with
//   most of the crown left (a 30,000-card tree: 41% of its area after 42 billboards; docs/RESULTS.md
//   "Partly hidden leaves").
#include "reps/enhanced_billboards/acceleration.h"
#include "reps/enhanced_billboards/billboards.h"
#include "reps/enhanced_billboards/capture.h"
#include "reps/common/coarse_mesh.h"
#include "reps/common/coverage_capture.h"
#include "reps/common/ray_scene.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <limits>
#include <optional>

namespace standin::billboards {

namespace {

constexpr int k_exact_candidates = 4;
constexpr float k_candidate_separation_degrees = 15.0f;
constexpr float k_scoring_texel_scale = 2.0f;    // exact scoring at half the resolution,
constexpr float k_scoring_resolution = 512.0f;    // or 512 texels along the diagonal where finer (2048: foliage)
constexpr int k_histogram_side = 32;             // octahedral bins of face normals
constexpr float k_split_texels = 8.0f;           // faces are split to edges of at most this many texels,
constexpr float k_alpha_split_texels = 16.0f;    // alpha-tested models' to this many (see split_long_edges),
constexpr float k_split_budget = 16.0f;         // and what the greedy leaves to k_split_texels within this many
constexpr float k_second_round_step = 1.41421356f; // million faces (--split-budget), else to this factor times it (bake_pass)
constexpr std::uint32_t k_no_vertex = 0xffffffffu;

// Whether a capture is too small to be a billboard: under --min-coverage of the surface found so far
// (`area_found`, the billboards' before it), itself included. The seed (§4.3) measures it against the
// whole surface, which counts what no billboard can show: in a dense crown most of the area is inside,
// hidden from every direction, and the billboards still finding leaves on its outside each held
// under 1/1000 of it. A 200,000-card tree stopped at 31 billboards, its outside half captured
// (foliage Luv 7.73, IoU 0.989; docs/RESULTS.md "Billboards of foliage: the surface found so far").
bool below_min_coverage(const Capture& capture, double area_found, const BakeSettings& settings)
{
    return capture.faces.empty() || capture.area < double(settings.min_coverage) * (area_found + capture.area);
}

// The checks between parameters that their declarations cannot express; resolves the direction
// count of the fixed sets.
Status resolve_parameters(Options& parameters)
{
    if (parameters.given("texel-size") && parameters.given("resolution"))
        return error(StatusCode::invalid_argument, "--texel-size and --resolution: give one or the other");
    const std::string& directions = parameters.choice("directions");
    // (its default is accepted with any set, as every declared default is)
    if (parameters.integer("direction-count") != k_default_direction_count && directions != "sphere")
        return error(StatusCode::invalid_argument, "--direction-count: applies to --directions sphere only");
    if (directions != "sphere") parameters.set_integer("direction-count", directions == "seed" ? 36 * 18 : 6);
    int depth_bits = parameters.integer("depth-bits");
    if (depth_bits != 8 && depth_bits != 16) return error(StatusCode::invalid_argument, "--depth-bits: must be 8 or 16");
    return Status::ok();
}

// Unit projection directions w (from the plane into the model).
std::vector<glm::vec3> make_directions(const BakeSettings& settings)
{
    std::vector<glm::vec3> out;
    if (settings.directions == "axis") {
        for (int axis = 0; axis < 3; ++axis)
            for (float sign : {-1.0f, 1.0f}) {
                glm::vec3 w(0.0f);
                w[axis] = sign;
                out.push_back(w);
            }
    } else if (settings.directions == "seed") {
        // 36 x 18 view planes around the model looking at its centre (seed §4.1), 10° apart
        for (int j = 0; j < 18; ++j)
            for (int i = 0; i < 36; ++i) {
                double elevation = glm::radians(-85.0 + 10.0 * j), azimuth = glm::radians(5.0 + 10.0 * i);
                glm::dvec3 eye(std::cos(elevation) * std::cos(azimuth), std::sin(elevation), std::cos(elevation) * std::sin(azimuth));
                out.push_back(glm::vec3(-eye));
            }
    } else {
        // Fibonacci sphere: even spacing for any count
        double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
        int n = settings.direction_count;
        for (int k = 0; k < n; ++k) {
            double y = 1.0 - (2.0 * k + 1.0) / n, r = std::sqrt(std::max(0.0, 1.0 - y * y));
            out.push_back(glm::vec3(glm::dvec3(r * std::cos(golden * k), y, r * std::sin(golden * k))));
        }
    }
    return out;
}

// Octahedral bin of a unit vector.
int histogram_bin(glm::vec3 n)
{
    float s = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    glm::vec2 p(n.x / s, n.y / s);
    if (n.z < 0.0f) p = (1.0f - glm::abs(glm::vec2(p.y, p.x))) * glm::vec2(p.x >= 0 ? 1 : -1, p.y >= 0 ? 1 : -1);
    int i = std::clamp(int((p.x * 0.5f + 0.5f) * k_histogram_side), 0, k_histogram_side - 1);
    int j = std::clamp(int((p.y * 0.5f + 0.5f) * k_histogram_side), 0, k_histogram_side - 1);
    return j * k_histogram_side + i;
}

struct NormalBin {
    glm::dvec3 weighted{0.0}; // sum of area * normal
    double faces = 0.0;
};

// Cheap score of every candidate from a histogram of the remaining faces' normals: projected area
// of the non-grazing faces facing it, or (seed) the number of faces facing it.
std::vector<double> cheap_scores(const FaceData& faces, const std::vector<std::uint32_t>& remaining,
                                 const std::vector<glm::vec3>& directions, const BakeSettings& settings, float min_facing)
{
    std::vector<NormalBin> bins(k_histogram_side * k_histogram_side);
    for (std::uint32_t f : remaining) {
        if (!(faces.area[f] > 0.0)) continue;
        NormalBin& bin = bins[histogram_bin(faces.normal[f])];
        bin.weighted += faces.area[f] * glm::dvec3(faces.normal[f]);
        bin.faces += 1.0;
    }
    std::vector<double> scores(directions.size(), 0.0);
    tbb::parallel_for(std::size_t(0), directions.size(), [&](std::size_t d) {
        glm::dvec3 w = directions[d];
        double score = 0.0;
        for (const NormalBin& bin : bins) {
            double length = glm::length(bin.weighted);
            if (bin.faces == 0.0 || length == 0.0) continue;
            double facing = -glm::dot(bin.weighted, w) / length;
            if (settings.score == "faces")
                score += facing > 0.0 ? bin.faces : 0.0;
            else if (facing >= min_facing)
                score += -glm::dot(bin.weighted, w);
        }
        scores[d] = score;
    });
    return scores;
}

// The direction of the next billboard, or none when no candidate sees any projectable face.
std::optional<glm::vec3> choose_direction(const Mesh& mesh, const FaceData& faces, const std::vector<std::uint32_t>& remaining,
                                          const std::vector<glm::vec3>& directions, const BakeSettings& settings,
                                          const CaptureSettings& capture_settings)
{
    std::vector<double> scores = cheap_scores(faces, remaining, directions, settings, capture_settings.min_facing);
    std::vector<std::size_t> order(directions.size());
    for (std::size_t d = 0; d < order.size(); ++d) order[d] = d;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return scores[a] > scores[b]; });
    if (order.empty() || !(scores[order[0]] > 0.0)) return std::nullopt;
    if (settings.score == "faces") return directions[order[0]];

    // the best few, angularly apart, captured exactly at a reduced resolution
    std::vector<std::size_t> picked;
    float separation = std::cos(glm::radians(k_candidate_separation_degrees));
    for (std::size_t d : order) {
        if (!(scores[d] > 0.0) || int(picked.size()) == k_exact_candidates) break;
        bool apart = std::all_of(picked.begin(), picked.end(), [&](std::size_t p) { return glm::dot(directions[p], directions[d]) < separation; });
        if (apart) picked.push_back(d);
    }
    CaptureSettings coarse = capture_settings;
    coarse.texel_size = std::max(coarse.texel_size * k_scoring_texel_scale, mesh.bounds().diagonal() / k_scoring_resolution);
    coarse.write_maps = false;
    // side by side: each capture is small (a coarse grid) and partly serial, so one at a time left
    // a core idle for a third of a foliage bake's scoring; the order of the comparison is fixed
    std::vector<double> shown(picked.size(), 0.0); // what each shows: partly hidden faces' hidden texels not
    tbb::parallel_for(std::size_t(0), picked.size(), [&](std::size_t k) {
        const Capture capture = capture_direction(mesh, faces, remaining, directions[picked[k]], coarse);
        shown[k] = capture.area - capture.hidden_area;
    });
    std::size_t best = picked[0];
    double best_area = -1.0;
    for (std::size_t k = 0; k < picked.size(); ++k)
        if (shown[k] > best_area) best = picked[k], best_area = shown[k];
    return directions[best];
}

// The longest of a triangle's three edges, by their squared lengths e (edge k joins corners k and
// k + 1); ties to the first, so that every bisection of the bake cuts a face the same way.
int longest_edge(const float e[3])
{
    return e[0] >= e[1] && e[0] >= e[2] ? 0 : (e[1] >= e[2] ? 1 : 2);
}

// Appends the midpoint of edge (a, b) to `mesh`'s vertices, its attributes interpolated; the same
// values whichever way round the edge is given, so the faces on both sides of it place it alike.
std::uint32_t append_midpoint(Mesh& mesh, std::uint32_t a, std::uint32_t b)
{
    if (a > b) std::swap(a, b);
    mesh.positions.push_back(0.5f * (mesh.positions[a] + mesh.positions[b]));
    glm::vec3 n = mesh.normals[a] + mesh.normals[b];
    mesh.normals.push_back(glm::length(n) > 0.0f ? glm::normalize(n) : mesh.normals[a]);
    mesh.colors.push_back(0.5f * (mesh.colors[a] + mesh.colors[b]));
    if (!mesh.uvs.empty()) mesh.uvs.push_back(0.5f * (mesh.uvs[a] + mesh.uvs[b]));
    return std::uint32_t(mesh.positions.size() - 1);
}

} // namespace

// Faces are split so that no edge is longer than `max_edge` (longest-edge bisection, midpoints
// computed the same way from both sides of an edge, so no T-junctions): the occlusion test is all
// or nothing per face, and a long CAD sliver partly covered by a bolt from every side would
// otherwise never be captured. Attributes are interpolated linearly, so albedo (vertex colours,
// textures through UVs) and normals are those of the source. Returns false when nothing needed
// splitting.
// Alpha-tested models are split to k_alpha_split_texels instead: their partly hidden faces are
// captured at the texels they win (--partly-hidden), so a card need not wait for a direction that sees
// all of it, and at 8 texels their foliage-resolution bakes (1024-2048 texels along the diagonal) cut
// each card into hundreds of pieces whose per-face passes were most of the bake (a 20,000-card bush:
// 17.9 million faces with the back sides, 8-10 minutes, 3.4 GB). At 16 texels six foliage models
// bake 1.3-6x faster in 24-62% of the memory; on the four up to 30,000 cards foliage-protocol Luv and
// IoU are better (more of a card stays on one billboard), on crowns of 100,000 and 200,000 cards
// worse (Luv at distance 1 +0.6-0.7, IoU 0.994 -> 0.989 and 0.975 -> 0.965: in such a crown a bigger
// piece more often has under half its texels in front from every direction and is left), which 17
// minutes and 4.4 GB, or 10 GB, of bake at 8 texels did not seem worth; 32 was worse on the
// 30,000-card tree too (docs/RESULTS.md "Billboards of foliage: leaf cards split less"). What the
// greedy leaves is split again, to 8 texels, in a second round (bake_pass, split_remaining).
bool split_long_edges(const Mesh& mesh, float max_edge, Mesh& out, std::vector<std::uint32_t>& source_face)
{
    float limit2 = max_edge * max_edge;
    auto long_edge = [&](std::uint32_t a, std::uint32_t b) {
        glm::vec3 d = mesh.positions[a] - mesh.positions[b];
        return glm::dot(d, d) > limit2;
    };
    bool any = false;
    for (std::size_t t = 0; t < mesh.triangle_count() && !any; ++t)
        any = long_edge(mesh.indices[t * 3], mesh.indices[t * 3 + 1]) || long_edge(mesh.indices[t * 3 + 1], mesh.indices[t * 3 + 2]) ||
              long_edge(mesh.indices[t * 3 + 2], mesh.indices[t * 3]);
    if (!any) return false;
    out = mesh;
    out.indices.clear();
    out.face_materials.clear();
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) { return append_midpoint(out, a, b); };
    auto edge2 = [&](std::uint32_t a, std::uint32_t b) {
        glm::vec3 d = out.positions[a] - out.positions[b];
        return glm::dot(d, d);
    };
    std::vector<std::array<std::uint32_t, 3>> stack;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        stack.push_back({mesh.indices[t * 3], mesh.indices[t * 3 + 1], mesh.indices[t * 3 + 2]});
        while (!stack.empty()) {
            std::array<std::uint32_t, 3> tri = stack.back();
            stack.pop_back();
            float e[3] = {edge2(tri[0], tri[1]), edge2(tri[1], tri[2]), edge2(tri[2], tri[0])};
            int k = longest_edge(e);
            if (e[k] <= limit2 || out.positions.size() >= 0xfffffff0u) {
                out.indices.insert(out.indices.end(), tri.begin(), tri.end());
                out.face_materials.push_back(mesh.face_materials[t]);
                source_face.push_back(std::uint32_t(t));
                continue;
            }
            std::uint32_t a = tri[k], b = tri[(k + 1) % 3], c = tri[(k + 2) % 3], m = midpoint(a, b);
            stack.push_back({m, c, a});
            stack.push_back({m, b, c});
        }
    }
    return true;
}

// Each vertex's representative among the vertices at exactly its position (the lowest index), so
// that parts split at creases and part boundaries (CAD exports) are joined again. Also the
// renderer's, for the coarse mesh's open edges.
std::vector<std::uint32_t> weld_by_position(const Mesh& mesh)
{
    std::vector<std::uint32_t> order(mesh.vertex_count()), weld(mesh.vertex_count());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = std::uint32_t(k);
    auto less = [&](std::uint32_t a, std::uint32_t b) {
        const glm::vec3 &p = mesh.positions[a], &q = mesh.positions[b];
        return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z != q.z ? p.z < q.z : a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (std::size_t k = 0; k < order.size(); ++k)
        weld[order[k]] = k > 0 && mesh.positions[order[k]] == mesh.positions[order[k - 1]] ? weld[order[k - 1]] : order[k];
    return weld;
}

namespace {

// The sides of the model's faces that have area, corners welded by position: one (from, to) per
// side, whether they form one connected part, and the volume they enclose (signed by winding).
struct WeldedSides {
    std::vector<std::uint64_t> directed;
    bool one_part = false;
    double volume = 0.0;
};

WeldedSides welded_sides(const Mesh& mesh)
{
    WeldedSides sides;
    const std::size_t n = mesh.triangle_count();
    if (n == 0) return sides;
    const std::vector<std::uint32_t> weld = weld_by_position(mesh);
    std::vector<std::uint32_t> parent(mesh.vertex_count());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = std::uint32_t(k);
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    sides.directed.reserve(3 * n);
    for (std::size_t f = 0; f < n; ++f) {
        const std::uint32_t* idx = &mesh.indices[3 * f];
        const std::uint32_t w0 = weld[idx[0]], w1 = weld[idx[1]], w2 = weld[idx[2]];
        if (w0 == w1 || w1 == w2 || w0 == w2) continue; // collapsed to an edge (a pole's sliver): no area, no sides
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = weld[idx[k]], b = weld[idx[(k + 1) % 3]];
            sides.directed.push_back(std::uint64_t(a) << 32 | b);
            std::uint32_t ra = root(a), rb = root(b);
            if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
        }
        const glm::dvec3 p0(mesh.positions[idx[0]]), p1(mesh.positions[idx[1]]), p2(mesh.positions[idx[2]]);
        sides.volume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
    }
    if (sides.directed.empty()) return sides;
    const std::uint32_t part = root(std::uint32_t(sides.directed[0] >> 32));
    sides.one_part = std::all_of(sides.directed.begin(), sides.directed.end(),
                                 [&](std::uint64_t side) { return root(std::uint32_t(side >> 32)) == part; });
    return sides;
}

// Whether the model is one closed, outward surface: its faces (corners welded by position) form one
// connected part in which every edge joins exactly two faces wound against each other, enclosing a
// positive volume. Its back can then be the nearest surface only through a hole between the
// billboards' captures, which the coarse mesh fills, so the renderer may leave out proxies that
// hold only back hits (--cull-back-proxies auto). Several closed parts are not: where they meet,
// a gap between their captures shows one part's inside through the other, and back hits drew it
// (the generated assembly: Luv 0.74 -> 0.85 without them, docs/RESULTS.md). Sorts the sides in
// place (3 per face: no copy of them on a model of millions of faces).
bool one_closed_surface(WeldedSides& sides)
{
    if (!sides.one_part) return false;
    std::vector<std::uint64_t>& directed = sides.directed;
    std::sort(directed.begin(), directed.end());
    for (std::size_t k = 0; k < directed.size(); ++k) {
        if (k > 0 && directed[k] == directed[k - 1]) return false; // an edge used twice the same way
        const std::uint64_t reverse = (directed[k] & 0xffffffffu) << 32 | directed[k] >> 32;
        if (!std::binary_search(directed.begin(), directed.end(), reverse)) return false; // an open edge
    }
    return sides.volume > 0.0;
}

// Whether the model, not closed, is one connected part whose faces' backs face its own inside: at
// most reps::k_visible_backs of its area has a back a ray leaves the model from (a scan or a
// subdivided head with a few small openings: Suzanne 0.09%, sample_subdiv.ac 0.05%; the teapot
// 0.17%, BCN_Epileptic 0.86%, a bowl half). Its back hits then show only through openings a few
// faces wide and through holes between captures, which the coarse mesh fills: the renderer leaves out
// proxies of back hits as for a closed surface (Suzanne: thesis Luv 0.617 -> 0.621, 14% less a frame
// at 800x600 on llvmpipe). One part only, as for one_closed_surface: parts meeting show each other's
// insides.
bool backs_unseen(const Mesh& mesh, const WeldedSides& sides)
{
    return sides.one_part && reps::visible_backs(mesh) <= reps::k_visible_backs;
}

// Sheets (issue #17): the ground truth draws both sides of a double-sided face, but a capture takes
// a face from its front only, and a face facing away from a direction neither is captured nor hides
// anything there. A closed surface never shows its back, but an open one (a CAD sheet-metal part,
// a shell, a liner: zero thickness) shows it wherever its inside or underside is in view, and it
// had no billboard there: the back of the front's height field was drawn in its place, marked a
// near miss, and the coarse mesh z-fought it. So the faces of every open surface (a connected part,
// vertices welded by position, with an edge used by one face) of a double-sided material get a
// reversed copy (winding and normals flipped), captured like any face: the back is baked from its
// own side and hides what is behind it from that side. A closed part wound inside out (negative
// volume by its oriented face normals) shows only its back: its faces are replaced by reversed ones.
// Returns false (nothing added, `out` untouched) for models of closed, outward surfaces, so their
// packages are unchanged; `piece_of` maps out's faces to mesh's.
bool add_back_sides(const Mesh& mesh, const FaceData& faces, Mesh& out, std::vector<std::uint32_t>& piece_of,
                    std::vector<std::uint8_t>& open_edges, std::vector<std::uint32_t>& part_of)
{
    std::size_t n = mesh.triangle_count();
    if (n == 0) return false;
    // weld by position: CAD exports split vertices at creases and part boundaries of one surface
    std::vector<std::uint32_t> weld = weld_by_position(mesh);
    // connected parts (union-find over welded vertices)
    std::vector<std::uint32_t> parent(mesh.vertex_count());
    for (std::size_t k = 0; k < parent.size(); ++k) parent[k] = std::uint32_t(k);
    auto root = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<std::uint64_t> edges; // (lower, higher welded vertex): one entry per face side
    edges.reserve(3 * n);
    for (std::size_t f = 0; f < n; ++f)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = weld[mesh.indices[f * 3 + k]], b = weld[mesh.indices[f * 3 + (k + 1) % 3]];
            std::uint32_t ra = root(a), rb = root(b);
            if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
            if (a != b) edges.push_back(std::uint64_t(std::min(a, b)) << 32 | std::max(a, b));
        }
    std::sort(edges.begin(), edges.end());
    std::vector<std::uint8_t> open_part(mesh.vertex_count(), 0);
    std::vector<std::uint64_t> boundary; // edges used by one face, ascending
    for (std::size_t k = 0; k < edges.size();) {
        std::size_t end = k;
        while (end < edges.size() && edges[end] == edges[k]) ++end;
        if (end - k == 1) {
            open_part[root(std::uint32_t(edges[k] >> 32))] = 1;
            boundary.push_back(edges[k]);
        }
        k = end;
    }
    auto open_edge = [&](std::size_t f, int k) {
        std::uint32_t a = weld[mesh.indices[f * 3 + k]], b = weld[mesh.indices[f * 3 + (k + 1) % 3]];
        return std::binary_search(boundary.begin(), boundary.end(), std::uint64_t(std::min(a, b)) << 32 | std::max(a, b));
    };
    // signed volume of every part by its oriented normals (divergence theorem)
    glm::dvec3 centre(mesh.bounds().center());
    std::vector<double> volume(mesh.vertex_count(), 0.0);
    for (std::size_t f = 0; f < n; ++f) {
        glm::dvec3 c = (glm::dvec3(mesh.positions[mesh.indices[f * 3]]) + glm::dvec3(mesh.positions[mesh.indices[f * 3 + 1]]) +
                        glm::dvec3(mesh.positions[mesh.indices[f * 3 + 2]])) / 3.0 - centre;
        volume[root(weld[mesh.indices[f * 3]])] += faces.area[f] * glm::dot(c, glm::dvec3(faces.normal[f])) / 3.0;
    }
    enum Side : std::uint8_t { front, both, back };
    std::vector<std::uint8_t> side(n, front);
    bool any = false;
    for (std::size_t f = 0; f < n; ++f) {
        if (!mesh.materials[mesh.face_materials[f]].double_sided) continue;
        std::uint32_t part = root(weld[mesh.indices[f * 3]]);
        side[f] = open_part[part] ? both : volume[part] < 0.0 ? back : front;
        any = any || side[f] != front;
    }
    if (!any) return false;
    out = mesh;
    out.indices.clear();
    out.face_materials.clear();
    piece_of.clear();
    open_edges.clear();
    part_of.clear();
    bool has_uv = mesh.has_texture_coordinates();
    std::vector<std::uint32_t> reversed(mesh.vertex_count(), k_no_vertex);
    auto reversed_vertex = [&](std::uint32_t v) {
        if (reversed[v] == k_no_vertex) {
            reversed[v] = std::uint32_t(out.positions.size());
            out.positions.push_back(mesh.positions[v]);
            out.normals.push_back(-mesh.normals[v]);
            out.colors.push_back(mesh.colors[v]);
            if (has_uv) out.uvs.push_back(mesh.uvs[v]);
        }
        return reversed[v];
    };
    // the reversed copies come after all front faces, in face order (deterministic)
    for (int pass = 0; pass < 2; ++pass)
        for (std::size_t f = 0; f < n; ++f) {
            bool take = pass == 0 ? side[f] != back : side[f] != front;
            if (!take) continue;
            const std::uint32_t* idx = &mesh.indices[f * 3];
            bool e01 = open_edge(f, 0), e12 = open_edge(f, 1), e20 = open_edge(f, 2);
            if (pass == 0) {
                out.indices.insert(out.indices.end(), idx, idx + 3);
                open_edges.push_back(std::uint8_t((e01 ? 1 : 0) | (e12 ? 2 : 0) | (e20 ? 4 : 0)));
            } else {
                // corners 0, 2, 1: edges (0, 2), (2, 1), (1, 0)
                for (int k : {0, 2, 1}) out.indices.push_back(reversed_vertex(idx[k]));
                open_edges.push_back(std::uint8_t((e20 ? 1 : 0) | (e12 ? 2 : 0) | (e01 ? 4 : 0)));
            }
            out.face_materials.push_back(mesh.face_materials[f]);
            piece_of.push_back(std::uint32_t(f));
            part_of.push_back(root(weld[idx[0]]));
        }
    return true;
}

// Faces of `from` (ascending) not in `taken` (ascending).
std::vector<std::uint32_t> without(const std::vector<std::uint32_t>& from, const std::vector<std::uint32_t>& taken)
{
    std::vector<std::uint32_t> out;
    out.reserve(from.size() - std::min(from.size(), taken.size()));
    std::set_difference(from.begin(), from.end(), taken.begin(), taken.end(), std::back_inserter(out));
    return out;
}

// --face-assignment squarer. The greedy captures every face a direction can hold, so a face goes to
// the first billboard that sees it within the grazing angle, however steeply (assimp's COLLADA.dae:
// letter fronts 20.3 degrees off the billboard's plane, streaks of texels whose outlines the march
// meets a texel off). Here the greedy only chooses the directions (as the first pass would); then a
// face the billboard at hand sees more than k_squarer_angle off its normal is left for the later
// direction that sees it most squarely, among those that can capture it with every face present.
// Deferring a face also defers what it hides: a surface the greedy reached only once the faces in
// front of it were taken can be left hidden at every billboard. Rounds without maps find such
// faces and pin them and the faces that hid them to the first billboard able to hold them (the
// greedy's rule), until no fewer are left; what is still left goes on to further greedy billboards.
struct SquarerAssignment {
    std::vector<glm::vec3> directions;              // the greedy's, in its order
    std::vector<std::vector<std::uint8_t>> visible; // per direction, per face: capturable with every face present
    std::vector<std::uint8_t> pinned;               // per face: to the first billboard able to hold it

    // Per face of `left`, whether billboard i may hold it.
    void allow(std::size_t i, const FaceData& faces, const std::vector<std::uint32_t>& left, std::vector<std::uint8_t>& allowed) const
    {
        const float squarer = glm::radians(k_squarer_angle);
        tbb::parallel_for(std::size_t(0), left.size(), [&](std::size_t r) {
            std::uint32_t f = left[r];
            if (pinned[f]) {
                allowed[f] = 1;
                return;
            }
            float best = -1.0f; // the squarest of the later billboards that can hold it
            for (std::size_t j = i + 1; j < directions.size(); ++j)
                if (visible[j][f]) best = std::max(best, -glm::dot(faces.normal[f], directions[j]));
            float here = std::acos(std::clamp(-glm::dot(faces.normal[f], directions[i]), -1.0f, 1.0f));
            allowed[f] = here <= std::max(squarer, std::acos(std::clamp(best, -1.0f, 1.0f)));
        });
    }
};

SquarerAssignment assign_squarer(const Mesh& mesh, const FaceData& faces, const std::vector<std::uint32_t>& all,
                                 const std::vector<glm::vec3>& candidates, const BakeSettings& settings,
                                 const CaptureSettings& capture_settings, const Progress& progress)
{
    SquarerAssignment result;
    // the greedy's directions, captured without maps
    std::vector<std::uint32_t> left = all;
    double area_found = 0.0;
    while (!left.empty() && int(result.directions.size()) < settings.max_billboards) {
        std::optional<glm::vec3> w = choose_direction(mesh, faces, left, candidates, settings, capture_settings);
        if (!w) break;
        Capture capture = capture_direction(mesh, faces, left, *w, capture_settings);
        if (below_min_coverage(capture, area_found, settings)) break;
        area_found += capture.area - capture.hidden_area;
        result.directions.push_back(*w);
        left = without(left, capture.faces);
    }
    // with fewer faces left to hide them, these stay capturable
    result.visible.assign(result.directions.size(), std::vector<std::uint8_t>(mesh.triangle_count(), 0));
    for (std::size_t j = 0; j < result.directions.size(); ++j)
        for (std::uint32_t f : capture_direction(mesh, faces, all, result.directions[j], capture_settings).faces) result.visible[j][f] = 1;
    result.pinned.assign(mesh.triangle_count(), 0);
    std::size_t previous = all.size() + 1;
    std::vector<std::uint8_t> allowed(mesh.triangle_count(), 0), is_left(mesh.triangle_count(), 0);
    for (int round = 0; round < k_squarer_rounds; ++round) {
        left = all;
        std::vector<std::pair<std::uint32_t, std::uint32_t>> hidden_by;
        CaptureSettings round_settings = capture_settings;
        round_settings.allowed = &allowed;
        for (std::size_t i = 0; i < result.directions.size(); ++i) {
            progress.report("enhanced billboards: assigning faces",
                            (double(round) + double(i) / double(result.directions.size())) / double(k_squarer_rounds));
            result.allow(i, faces, left, allowed);
            Capture capture = capture_direction(mesh, faces, left, result.directions[i], round_settings);
            hidden_by.insert(hidden_by.end(), capture.hidden_by.begin(), capture.hidden_by.end());
            left = without(left, capture.faces);
        }
        if (left.empty() || left.size() >= previous) break;
        previous = left.size();
        for (std::uint32_t f : left) is_left[f] = result.pinned[f] = 1;
        for (auto [f, by] : hidden_by)
            if (is_left[f]) result.pinned[by] = 1;
        for (std::uint32_t f : left) is_left[f] = 0;
    }
    return result;
}

// 8-bit packages hold depth and normal in 8 bits; the in-memory maps match what reading gives.
void quantise_to_8_bits(Billboard& board)
{
    for (std::uint16_t& value : board.normal_depth.pixels) value = std::uint16_t(((value + 128) / 257) * 257);
}

// Sorts what was left into reasons: degenerate; grazing in every candidate direction; captured by
// a billboard too small to keep ("small_billboards", seed §4.3); "max_billboards" when the limit
// stopped the loop; else "occluded" (hidden by other faces in every direction tried). Faces are
// counted as source faces: a face counts once per reason any of its pieces, or of its reversed
// copy's (add_back_sides), was left for.
// The model's face a baked face (a piece of a split face, or a reversed copy) comes from;
// `source_face` is empty when the baked faces are the model's.
std::uint32_t source_of(const std::vector<std::uint32_t>& source_face, std::uint32_t face)
{
    return source_face.empty() ? face : source_face[face];
}

void record_left(const FaceData& faces, const std::vector<std::uint32_t>& remaining, const std::vector<std::uint32_t>& too_small,
                 const std::vector<glm::vec3>& directions, float min_facing, bool hit_limit,
                 const std::vector<std::uint32_t>& source_face, std::size_t source_faces, std::map<std::string, LeftOver>& left)
{
    enum Reason : std::uint8_t { degenerate, grazing, small, limit, occluded, count };
    const char* names[count] = {"degenerate", "grazing", "small_billboards", "max_billboards", "occluded"};
    std::vector<std::uint8_t> reason(remaining.size(), degenerate);
    tbb::parallel_for(std::size_t(0), remaining.size(), [&](std::size_t r) {
        std::uint32_t f = remaining[r];
        if (!(faces.area[f] > 0.0)) return;
        bool projectable = std::any_of(directions.begin(), directions.end(),
                                       [&](glm::vec3 w) { return -glm::dot(faces.normal[f], w) >= min_facing; });
        if (!projectable) reason[r] = grazing;
        else if (std::binary_search(too_small.begin(), too_small.end(), f)) reason[r] = small;
        else reason[r] = hit_limit ? limit : occluded;
    });
    // a face's pieces need not be consecutive among the remaining faces: its reversed copies come
    // after every front face, and its pieces may alternate between reasons
    std::vector<std::uint8_t> counted(source_faces, 0); // per source face, a bit per reason
    for (std::size_t r = 0; r < remaining.size(); ++r) {
        LeftOver& entry = left[names[reason[r]]];
        const std::uint32_t source = source_of(source_face, remaining[r]);
        const std::uint8_t bit = std::uint8_t(1u << reason[r]);
        if (!(counted[source] & bit)) entry.faces += 1;
        counted[source] |= bit;
        entry.area += faces.area[remaining[r]];
    }
}

// Source faces among captured pieces (ascending, so the pieces of one face are consecutive).
std::size_t count_source_faces(const std::vector<std::uint32_t>& pieces, const std::vector<std::uint32_t>& source_face)
{
    if (source_face.empty()) return pieces.size();
    std::size_t n = 0;
    for (std::size_t k = 0; k < pieces.size(); ++k) n += k == 0 || source_face[pieces[k]] != source_face[pieces[k - 1]];
    return n;
}

// The pieces longest-edge bisection to edges of at most sqrt(limit2) cuts a triangle into (1 when it
// is short enough): split_remaining's budget, counted before anything is allocated.
std::size_t bisection_pieces(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c, float limit2)
{
    const glm::vec3 ab = a - b, bc = b - c, ca = c - a;
    const float e[3] = {glm::dot(ab, ab), glm::dot(bc, bc), glm::dot(ca, ca)};
    const int k = longest_edge(e);
    if (!(e[k] > limit2)) return 1;
    const glm::vec3 p[3] = {a, b, c};
    const glm::vec3 &x = p[k], &y = p[(k + 1) % 3], &z = p[(k + 2) % 3], m = 0.5f * (x + y);
    return bisection_pieces(m, z, x, limit2) + bisection_pieces(m, y, z, limit2);
}

} // namespace

// What split_remaining would make: the alpha-tested faces' pieces, the others one each.
std::size_t split_remaining_faces(const Mesh& mesh, const std::vector<std::uint32_t>& remaining, float max_edge)
{
    std::size_t n = 0;
    for (std::uint32_t f : remaining) {
        const std::uint32_t* corner = &mesh.indices[std::size_t(f) * 3];
        n += alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f
                 ? bisection_pieces(mesh.positions[corner[0]], mesh.positions[corner[1]], mesh.positions[corner[2]], max_edge * max_edge)
                 : 1;
    }
    return n;
}

// The second round's edge length (billboards.h): k_split_texels where that makes at most `budget`
// faces, else k_second_round_step times it, whatever that makes.
float second_round_edge(const Mesh& mesh, const std::vector<std::uint32_t>& remaining, float texel, std::size_t budget,
                        std::size_t* pieces)
{
    const float finest = k_split_texels * texel;
    const std::size_t at_finest = split_remaining_faces(mesh, remaining, finest);
    const float edge = at_finest <= budget ? finest : finest * k_second_round_step;
    if (pieces) *pieces = edge == finest ? at_finest : split_remaining_faces(mesh, remaining, edge);
    return edge;
}

// The second round's work mesh (billboards.h): vertices copied as the faces left first use them,
// midpoints appended as the bisection makes them; a face's pieces depth first, in a row.
Mesh split_remaining(const Mesh& mesh, FaceData& faces, std::vector<std::uint32_t>& source_face, std::vector<std::uint32_t>& remaining,
                     float max_edge)
{
    const float limit2 = max_edge * max_edge;
    Mesh out;
    out.materials = mesh.materials;
    out.textures = mesh.textures;
    FaceData next;
    std::vector<std::uint32_t> next_source;
    std::vector<std::uint32_t> vertex(mesh.vertex_count(), k_no_vertex); // mesh's vertex -> out's
    auto keep_vertex = [&](std::uint32_t v) {
        if (vertex[v] == k_no_vertex) {
            vertex[v] = std::uint32_t(out.positions.size());
            out.positions.push_back(mesh.positions[v]);
            out.normals.push_back(mesh.normals[v]);
            out.colors.push_back(mesh.colors[v]);
            if (!mesh.uvs.empty()) out.uvs.push_back(mesh.uvs[v]);
        }
        return vertex[v];
    };
    auto edge2 = [&](std::uint32_t a, std::uint32_t b) {
        glm::vec3 d = out.positions[a] - out.positions[b];
        return glm::dot(d, d);
    };
    struct Piece {
        std::array<std::uint32_t, 3> corner;
        std::uint8_t open; // bit k: edge (k, k + 1) lies on an open edge of the face
        bool whole;        // the face itself
    };
    std::vector<Piece> stack;
    for (std::uint32_t f : remaining) {
        const bool cut_out = alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f;
        stack.push_back({{keep_vertex(mesh.indices[std::size_t(f) * 3]), keep_vertex(mesh.indices[std::size_t(f) * 3 + 1]),
                          keep_vertex(mesh.indices[std::size_t(f) * 3 + 2])},
                         faces.open_edges.empty() ? std::uint8_t(0) : faces.open_edges[f], true});
        while (!stack.empty()) {
            const Piece piece = stack.back();
            stack.pop_back();
            const std::array<std::uint32_t, 3>& t = piece.corner;
            float e[3] = {edge2(t[0], t[1]), edge2(t[1], t[2]), edge2(t[2], t[0])};
            int k = longest_edge(e);
            if (cut_out && e[k] > limit2 && out.positions.size() < 0xfffffff0u) {
                // (a, b) the longest edge, c the corner opposite; edges' open bits named by them
                const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3], m = append_midpoint(out, a, b);
                const std::uint8_t ab = (piece.open >> k) & 1, bc = (piece.open >> ((k + 1) % 3)) & 1,
                                   ca = (piece.open >> ((k + 2) % 3)) & 1;
                stack.push_back({{m, c, a}, std::uint8_t((ca << 1) | (ab << 2)), false}); // (m, c) a cut, (c, a), (a, m)
                stack.push_back({{m, b, c}, std::uint8_t(ab | (bc << 1)), false});        // (m, b), (b, c), (c, m) a cut
                continue;
            }
            out.indices.insert(out.indices.end(), t.begin(), t.end());
            out.face_materials.push_back(mesh.face_materials[f]);
            double area = faces.area[f];
            if (!piece.whole) {
                const glm::dvec3 p0 = out.positions[t[0]], p1 = out.positions[t[1]], p2 = out.positions[t[2]];
                area = 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
                if (!(area > 0.0) || !std::isfinite(area)) area = 0.0;
            }
            next.area.push_back(area);
            next.normal.push_back(area > 0.0 ? faces.normal[f] : glm::vec3(0.0f));
            if (!faces.open_edges.empty()) next.open_edges.push_back(piece.open);
            if (!faces.part.empty()) next.part.push_back(faces.part[f]);
            next_source.push_back(source_face.empty() ? f : source_face[f]);
        }
    }
    faces = std::move(next);
    source_face = std::move(next_source);
    remaining.resize(out.triangle_count());
    for (std::size_t f = 0; f < remaining.size(); ++f) remaining[f] = std::uint32_t(f);
    return out;
}

namespace {

// The faces of `mesh` whose material is not alpha-tested (issue #14), for the coarse mesh: it has
// no texture to cut a leaf card's cut-outs with, so a card's coarse triangles are the whole card,
// and the renderer fills with them the ring of near-miss pixels around every leaf. Measured on the
// generated tree at 1024 texels (docs/RESULTS.md "Billboards on foliage: resolution and coarse
// mesh"): Luv at distance 1 5.46 -> 5.22, IoU 0.978 -> 0.980, spill 1.37% -> 1.01%, holes 0.82% ->
// 1.00%, nearly all of them leaf-edge pixels, where the whole cards had filled as many
// background pixels as leaf ones.
Mesh opaque_faces(const Mesh& mesh)
{
    Mesh opaque = mesh;
    opaque.indices.clear();
    opaque.face_materials.clear();
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        if (alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f) continue;
        opaque.indices.insert(opaque.indices.end(), mesh.indices.begin() + 3 * std::ptrdiff_t(f),
                              mesh.indices.begin() + 3 * std::ptrdiff_t(f + 1));
        opaque.face_materials.push_back(mesh.face_materials[f]);
    }
    return opaque;
}

// The texels along the diagonal for an alpha-tested model (issue #14): k_alpha_resolution, or
// finer up to k_alpha_max_resolution where its cut-out textures are finer, so that a capture texel
// is as fine as a texel of the texture whose alpha draws the leaf's contour
// (reps::cutout_texel_size). A model whose cut-outs come without a texture (opacity, vertex alpha)
// keeps k_alpha_resolution: its contours are its edges.
int cutout_resolution(const Mesh& mesh)
{
    const double texel = reps::cutout_texel_size(mesh);
    if (!(texel > 0.0)) return k_alpha_resolution;
    const double texels = double(mesh.bounds().diagonal()) / texel;
    return int(std::clamp(std::ceil(texels), double(k_alpha_resolution), double(k_alpha_max_resolution)));
}

} // namespace

// The covered texels of a billboard that end its surface on some side (issue #17, the held-out
// assembly): a 4-neighbour empty, or across a depth step larger than the link rule allows
// (height_field.h), so that rays there meet a depth edge the capture cannot resolve. Returns
// (edge texels, covered texels).
static std::pair<std::size_t, std::size_t> depth_edge_texels(const Billboard& image)
{
    std::size_t edges = 0, covered = 0;
    auto is_covered = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < image.width && y < image.height && image.color.at(x, y)[3] != 0;
    };
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            if (!is_covered(x, y)) continue;
            ++covered;
            // each neighbour covered and linked (from the lower texel of the pair, as the renderer links them)
            const bool inner = is_covered(x + 1, y) && texels_linked(image, x, y, 0, 1.0f) && is_covered(x - 1, y) &&
                               texels_linked(image, x - 1, y, 0, 1.0f) && is_covered(x, y + 1) &&
                               texels_linked(image, x, y, 1, 1.0f) && is_covered(x, y - 1) && texels_linked(image, x, y - 1, 1, 1.0f);
            edges += inner ? 0 : 1;
        }
    return {edges, covered};
}

int budget_resolution(int resolution, std::size_t texels, std::size_t budget, int floor)
{
    if (texels <= budget || texels == 0) return resolution;
    const double scaled = double(resolution) * std::sqrt(double(budget) / double(texels));
    return std::min(resolution, std::max(floor, int(std::floor(scaled))));
}

double depth_edge_fraction(const EnhancedBillboardsPackage& package)
{
    std::size_t edges = 0, covered = 0;
    for (const Billboard& b : package.billboards) {
        auto [e, c] = depth_edge_texels(b);
        edges += e, covered += c;
    }
    return covered > 0 ? double(edges) / double(covered) : 0.0;
}

namespace {

// One greedy bake with the resolved parameters (the steps in the comment at the top).
Result<std::unique_ptr<EnhancedBillboardsPackage>> bake_pass(const BakeContext& context, Options parameters, bool alpha_tested)
{
    const Mesh& mesh = context.mesh;
    const BakeSettings settings = settings_from(parameters);

    // one texel size for the whole model (seed: bounding-box diagonal -> 512 texels)
    float diagonal = mesh.bounds().diagonal();
    if (!(diagonal > 0.0f) || !std::isfinite(diagonal))
        return error(StatusCode::bad_data, context.source.file_name + ": the model has no extent");
    float texel = settings.texel_size > 0.0f ? settings.texel_size : diagonal / float(settings.resolution);
    if (diagonal / texel > float(k_max_grid_texels))
        return error(StatusCode::invalid_argument, "--texel-size: " + std::to_string(texel) + " puts " +
                                                       std::to_string(diagonal / texel) + " texels along the diagonal (at most " +
                                                       std::to_string(k_max_grid_texels) + ")");

    auto package = std::make_unique<EnhancedBillboardsPackage>();
    package->source = context.source;
    parameters.set_number("texel-size", texel);
    package->parameters = parameters;
    package->settings = settings_from(parameters);
    package->faces_total = mesh.triangle_count();

    // split faces longer than a few texels, so that partial occlusion costs only a piece
    Mesh split;
    std::vector<std::uint32_t> source_face; // piece -> source face; empty when nothing was split
    const float split_texels = alpha_tested ? k_alpha_split_texels : k_split_texels;
    const Mesh& split_or_source = split_long_edges(mesh, split_texels * texel, split, source_face) ? split : mesh;
    FaceData faces = compute_face_data(split_or_source);
    // both sides of open surfaces (sheets), the outside of inverted closed parts
    Mesh sided;
    std::vector<std::uint32_t> piece_of;
    std::vector<std::uint8_t> open_edges;
    std::vector<std::uint32_t> part_of;
    bool two_sided = add_back_sides(split_or_source, faces, sided, piece_of, open_edges, part_of);
    // sheet edges and outlines (issues #17, #14): auto clips every texel an outline crosses to the
    // outline's line (capture.cpp): open double-sided parts' edges, leaves' cut-out contours (a
    // card's own edges are not its leaf's outline and are not clipped to), and every surface's
    // outline as the billboard sees it (outline lines: measured on 14 models, thesis Luv lower on
    // 10 and within 0.01 on the rest, holes without the coarse mesh lower on all 8 measured;
    // docs/RESULTS.md "Outline lines"); centre is the seed's texel by its centre
    std::string sheet_edges = settings.sheet_edges;
    if (sheet_edges == "auto") sheet_edges = "clip";
    parameters.set_choice("sheet-edges", sheet_edges);
    // the backs of open single-sided parts: the truth culls them. auto hides back hits only where
    // such backs can be seen from outside (reps::visible_single_sided_backs over reps::k_visible_backs of
    // the area): assimp's COLLADA.dae, a single-sided plane under text seen from below, 0.50 (hidden:
    // IoU 0.62 -> 0.991). Elsewhere the back hits stand in for what unwelded seams let through: the
    // held-out engine (57 of its 59 parts open by exact welding, every material single-sided) reads
    // 0, and hidden its holes rose 0.003% -> 0.011%, Luv 1.60 -> 2.13 (docs/RESULTS.md "Backs of
    // single-sided sheets").
    if (settings.back_hits == "auto")
        parameters.set_choice("back-hits", reps::visible_single_sided_backs(mesh) > reps::k_visible_backs ? "hide" : "show");
    package->parameters = parameters;
    package->settings = settings_from(parameters);
    if (two_sided) {
        faces = compute_face_data(sided);
        // --sheet-edges overlap (capture.cpp, write_maps): measured on the sheet assembly, holes
        // 0.10% -> 0.016% but spill 0.65% -> 0.96% and Luv 1.62 -> 1.96 (docs/RESULTS.md), so not
        // the default; since the coarse mesh fills rims (coarse_rims below) it helps only where
        // the coarse mesh is not drawn (--no-coarse: 0.25% -> 0.065%)
        if (sheet_edges == "overlap" || sheet_edges == "clip") {
            faces.open_edges = std::move(open_edges);
            faces.part = std::move(part_of);
        }
        for (std::uint32_t& piece : piece_of) piece = source_of(source_face, piece);
        source_face = std::move(piece_of);
    }
    const Mesh* work = two_sided ? &sided : &split_or_source;
    for (double a : faces.area) package->area_total += a;
    std::vector<glm::vec3> directions = make_directions(settings);
    CaptureSettings capture_settings;
    capture_settings.texel_size = texel;
    capture_settings.depth_limit = settings.depth_limit * diagonal;
    capture_settings.min_facing = std::sin(glm::radians(settings.grazing_angle));
    capture_settings.edge_lines = sheet_edges == "clip";
    capture_settings.partly_visible = settings.partly_hidden;
    std::vector<std::uint32_t> remaining(work->triangle_count());
    for (std::size_t f = 0; f < remaining.size(); ++f) remaining[f] = std::uint32_t(f);

    bool hit_limit = false;
    std::vector<std::uint32_t> too_small;
    std::vector<std::uint8_t> partly_hidden_source; // per source face: captured with a part hidden
    // a capture with its maps becomes a billboard (or, cut out entirely by alpha, nothing)
    auto keep = [&](Capture& capture) {
        if (capture.billboard.width == 0) {
            // every texel of what it holds is cut out by its alpha (assimp's earthCylindrical.DAE,
            // opacity 0: the truth draws nothing): captured, as nothing, with no billboard to store
            package->area_captured += capture.area;
            remaining = without(remaining, capture.faces);
            return;
        }
        if (settings.depth_bits == 8) quantise_to_8_bits(capture.billboard);
        capture.billboard.captured_faces = count_source_faces(capture.faces, source_face);
        package->area_captured += capture.area - capture.hidden_area;
        if (capture.hidden_area > 0.0) {
            LeftOver& hidden = package->left["hidden_parts"];
            hidden.area += capture.hidden_area;
            partly_hidden_source.resize(mesh.triangle_count(), 0);
            for (std::uint32_t piece : capture.partly_hidden) {
                std::uint8_t& flag = partly_hidden_source[source_of(source_face, piece)];
                hidden.faces += flag == 0; // source faces, once however many pieces and billboards
                flag = 1;
            }
        }
        package->billboards.push_back(std::move(capture.billboard));
        remaining = without(remaining, capture.faces);
    };

    if (settings.face_assignment == "squarer") {
        context.progress.report("enhanced billboards: assigning faces", 0.0);
        const SquarerAssignment squarer = assign_squarer(*work, faces, remaining, directions, settings, capture_settings, context.progress);
        context.progress.report("enhanced billboards: assigning faces", 1.0);
        std::vector<std::uint8_t> allowed(work->triangle_count(), 0);
        for (std::size_t i = 0; i < squarer.directions.size(); ++i) {
            context.progress.report("enhanced billboards: capturing", package->area_captured / std::max(package->area_total, 1e-300));
            squarer.allow(i, faces, remaining, allowed);
            CaptureSettings final_settings = capture_settings;
            final_settings.write_maps = true;
            final_settings.allowed = &allowed;
            Capture capture = capture_direction(*work, faces, remaining, squarer.directions[i], final_settings);
            if (!capture.faces.empty()) keep(capture);
        }
        // what it left hidden everywhere goes on to the greedy below
    }

    // Alpha-tested models' second round (issue #14): when the greedy stalls, the alpha-tested faces
    // left (in a dense crown a 16-texel piece more often has under --partly-hidden of its texels in
    // front in every direction) are split to k_split_texels and the greedy goes on with what is left,
    // in a work mesh of its own (captured faces take no part in later captures: the first round's
    // mesh is freed); to k_split_texels x k_second_round_step where k_split_texels would make over
    // k_split_budget million faces (--split-budget: a machine with the memory splits denser crowns to 8).
    // A 100,000-card tree: Luv 7.29 -> 6.15, IoU 0.989 -> 0.995, where splitting every card to 8
    // texels from the start gave 6.61 in 17 minutes and 4.4 GB (docs/RESULTS.md "Billboards of
    // foliage: what is left split again").
    Mesh second_round;
    bool split_again = !alpha_tested || !(settings.split_budget > 0.0f);
    const std::size_t budget = std::size_t(double(settings.split_budget) * 1e6);
    auto split_left_faces = [&]() {
        if (split_again) return false;
        split_again = true;
        std::size_t pieces = 0;
        const float length = second_round_edge(*work, remaining, texel, budget, &pieces);
        if (pieces == remaining.size()) return false; // nothing to split
        second_round = split_remaining(*work, faces, source_face, remaining, length);
        work = &second_round;
        sided = Mesh{};
        split = Mesh{};
        return true;
    };

    // greedy loop over the faces not yet captured
    while (!remaining.empty()) {
        context.progress.report("enhanced billboards: capturing", package->area_captured / std::max(package->area_total, 1e-300));
        if (int(package->billboards.size()) >= settings.max_billboards) {
            hit_limit = true;
            break;
        }
        // choose the direction that captures the most, and capture it at full resolution
        std::optional<glm::vec3> w = choose_direction(*work, faces, remaining, directions, settings, capture_settings);
        if (!w) {
            if (split_left_faces()) continue;
            break;
        }
        CaptureSettings final_settings = capture_settings;
        final_settings.write_maps = true;
        Capture capture = capture_direction(*work, faces, remaining, *w, final_settings);
        if (below_min_coverage(capture, package->area_captured, settings)) {
            if (split_left_faces()) continue;
            if (!capture.faces.empty()) too_small = std::move(capture.faces);
            break;
        }
        keep(capture);
    }
    context.progress.report("enhanced billboards: capturing", 1.0);

    // what was left and why; the coarse mesh covers it
    record_left(faces, remaining, too_small, directions, capture_settings.min_facing, hit_limit, source_face,
                mesh.triangle_count(), package->left);
    context.progress.report("enhanced billboards: coarse mesh", 0.0);
    // sheet rims (issue #17): the coarse mesh keeps open boundaries, and the renderer fills the rim
    // staircase with the triangles along them (renderer.cpp, rims_first); not where a material is
    // alpha-tested: a leaf card's outline is not its leaf's (measured: the generated tree's IoU
    // fell from 0.954 to 0.896, the coarse cards drawn whole)
    package->coarse_rims = two_sided && !alpha_tested;
    // alpha-tested models: the coarse mesh of the opaque faces only (see opaque_faces)
    const Mesh opaque = alpha_tested ? opaque_faces(mesh) : Mesh{};
    // and no further from the surface than a texel (k_coarse_error_texels, issue #17), so that it
    // reaches the silhouette pixels the billboards lose
    package->coarse_mesh = reps::make_coarse_mesh(alpha_tested ? opaque : mesh, settings.coarse_ratio, package->coarse_rims,
                                                  k_coarse_error_texels * texel);
    context.progress.report("enhanced billboards: coarse mesh", 1.0);
    return package;
}

} // namespace

Result<std::unique_ptr<Package>> bake(const BakeContext& context)
{
    const Mesh& mesh = context.mesh;
    Options parameters = context.parameters;
    STANDIN_RETURN_IF_ERROR(resolve_parameters(parameters));
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, context.source.file_name.empty() ? "mesh" : context.source.file_name));
    std::optional<tbb::global_control> threads;
    if (context.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(context.threads));
    const bool default_resolution = !parameters.given("resolution") && !parameters.given("texel-size");
    // alpha-tested models (leaf cards) at the default resolution: finer texels (k_alpha_resolution)
    const bool alpha_tested = std::any_of(mesh.materials.begin(), mesh.materials.end(),
                                          [](const Material& m) { return alpha_test_cutoff(m) > 0.0f; });
    if (alpha_tested && default_resolution) parameters.set_integer("resolution", cutout_resolution(mesh));
    // and faces more squarely facing their billboard (k_alpha_grazing_angle)
    if (alpha_tested && !parameters.given("grazing-angle")) parameters.set_number("grazing-angle", k_alpha_grazing_angle);
    // and captured where they are in front when partly hidden (k_alpha_partly_hidden)
    if (alpha_tested && !parameters.given("partly-hidden")) parameters.set_number("partly-hidden", k_alpha_partly_hidden);
    // and what the greedy leaves of their faces split again within k_split_budget million faces
    if (alpha_tested && !parameters.given("split-budget")) parameters.set_number("split-budget", k_split_budget);
    Result<std::unique_ptr<EnhancedBillboardsPackage>> package = bake_pass(context, parameters, alpha_tested);
    if (!package) return package.status();
    // alpha-tested models above k_alpha_resolution: again, coarser, where the maps exceed the budget
    if (alpha_tested && default_resolution) {
        std::size_t texels = 0;
        for (const Billboard& b : (*package)->billboards) texels += std::size_t(b.width) * std::size_t(b.height);
        const int resolution = int(parameters.integer("resolution"));
        const int fitting = budget_resolution(resolution, texels, k_alpha_texel_budget, k_alpha_resolution);
        if (fitting < resolution) {
            parameters.set_integer("resolution", fitting);
            package = bake_pass(context, parameters, alpha_tested);
            if (!package) return package.status();
        }
    }
    // models with detail finer than the default texels (fins, grilles, nested thin parts): baked
    // again at k_detail_resolution when over k_detail_edge_fraction of the texels end a surface
    if (default_resolution && !alpha_tested && depth_edge_fraction(**package) > k_detail_edge_fraction) {
        parameters.set_integer("resolution", k_detail_resolution);
        package = bake_pass(context, parameters, alpha_tested);
        if (!package) return package.status();
    }
    // once, whichever pass was kept (a cut-out shows a closed surface's inside)
    if (!alpha_tested) {
        WeldedSides sides = welded_sides(mesh);
        (*package)->one_closed_surface = one_closed_surface(sides);
        (*package)->backs_unseen = !(*package)->one_closed_surface && backs_unseen(mesh, sides);
    }
    return std::unique_ptr<Package>(std::move(*package));
}

} // namespace standin::billboards
