// The direction lookup of candidate views (view_lookup.h).
// Yamazaki et al. 2002 §3.3.2 (nearest view by angle, or a blend of the 2/3/4 nearest with weights
// that change continuously) and §6.2 (candidates from a cone of directions).
// Steps of build_view_lookup:
//  1. per cube-map cell: its centre direction and angular radius (farthest corner; cell edges are
//     great-circle arcs, so the farthest point is a corner);
//  2. the angle of the centre's fifth-nearest view;
//  3. the candidates: every view within that angle plus twice the radius, nearest first if a cell
//     would hold more than 255, then stored in ascending index order.
#include "reps/microfacets/view_lookup.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numeric>

namespace standin::microfacets {

namespace {

// the cube face of a direction and its coordinates in [-1, 1]^2 on that face; the face's axes are
// (a1, a2) = the two axes after the major one, in x -> y -> z -> x order
struct FacePoint {
    int face = 0;
    glm::vec2 st{0.0f};
};

FacePoint face_point(glm::vec3 d)
{
    glm::vec3 a = glm::abs(d);
    int major = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    FacePoint p;
    p.face = 2 * major + (d[major] < 0.0f ? 1 : 0);
    p.st = glm::vec2(d[(major + 1) % 3], d[(major + 2) % 3]) / a[major];
    return p;
}

glm::vec3 face_direction(int face, glm::vec2 st)
{
    int major = face / 2;
    glm::vec3 d;
    d[major] = (face & 1) ? -1.0f : 1.0f;
    d[(major + 1) % 3] = st.x;
    d[(major + 2) % 3] = st.y;
    return glm::normalize(d);
}

float angle_between(glm::vec3 a, glm::vec3 b) { return std::acos(std::clamp(glm::dot(a, b), -1.0f, 1.0f)); }

} // namespace

int lookup_cell(glm::vec3 direction)
{
    FacePoint p = face_point(direction);
    glm::ivec2 cell = glm::clamp(glm::ivec2(glm::floor((p.st * 0.5f + 0.5f) * float(k_lookup_side))), glm::ivec2(0),
                                 glm::ivec2(k_lookup_side - 1));
    return (p.face * k_lookup_side + cell.y) * k_lookup_side + cell.x;
}

ViewLookup build_view_lookup(const std::vector<glm::vec3>& directions)
{
    assert(!directions.empty());
    const int n = int(directions.size());
    const int rank = std::min(k_lookup_rank, n);
    ViewLookup lookup;
    lookup.cells.reserve(std::size_t(6 * k_lookup_side * k_lookup_side));
    std::vector<float> angles(std::size_t(n), 0.0f);
    std::vector<int> order(static_cast<std::size_t>(n));
    for (int face = 0; face < 6; ++face)
        for (int y = 0; y < k_lookup_side; ++y)
            for (int x = 0; x < k_lookup_side; ++x) {
                // the cell's centre and angular radius
                auto st = [](int i) { return float(i) / float(k_lookup_side) * 2.0f - 1.0f; };
                glm::vec3 center = face_direction(face, {0.5f * (st(x) + st(x + 1)), 0.5f * (st(y) + st(y + 1))});
                float radius = 0.0f;
                for (int corner = 0; corner < 4; ++corner)
                    radius = std::max(radius, angle_between(center, face_direction(face, {st(x + (corner & 1)), st(y + (corner >> 1))})));
                // the centre's rank-th nearest view, then every view that close plus twice the radius
                for (int k = 0; k < n; ++k) angles[std::size_t(k)] = angle_between(center, directions[std::size_t(k)]);
                std::iota(order.begin(), order.end(), 0);
                std::sort(order.begin(), order.end(), [&](int a, int b) {
                    return angles[std::size_t(a)] != angles[std::size_t(b)] ? angles[std::size_t(a)] < angles[std::size_t(b)] : a < b;
                });
                float reach = angles[std::size_t(order[std::size_t(rank - 1)])] + 2.0f * radius + 1e-5f;
                std::size_t count = 0;
                while (count < order.size() && count < 255 && angles[std::size_t(order[count])] <= reach) ++count;
                std::vector<int> chosen(order.begin(), order.begin() + std::ptrdiff_t(count));
                std::sort(chosen.begin(), chosen.end());
                lookup.cells.push_back(std::uint32_t(lookup.candidates.size()) << 8 | std::uint32_t(count));
                for (int k : chosen) lookup.candidates.push_back(std::uint32_t(k));
            }
    return lookup;
}

ViewBlend select_views(const std::vector<glm::vec3>& directions, const ViewLookup& lookup, glm::vec3 e, int count)
{
    assert(count >= 1 && count <= k_max_blend);
    std::uint32_t cell = lookup.cells[std::size_t(lookup_cell(e))];
    // the count + 1 nearest candidates by cosine, ties to the lower index (candidates ascend)
    int best[k_max_blend + 1];
    float cosines[k_max_blend + 1];
    std::fill(best, best + k_max_blend + 1, -1);
    std::fill(cosines, cosines + k_max_blend + 1, -2.0f);
    for (std::uint32_t i = 0; i < (cell & 255u); ++i) {
        int view = int(lookup.candidates[(cell >> 8) + i]);
        float c = glm::dot(directions[std::size_t(view)], e);
        for (int slot = 0; slot <= count; ++slot) {
            if (c > cosines[slot]) {
                for (int m = count; m > slot; --m) cosines[m] = cosines[m - 1], best[m] = best[m - 1];
                cosines[slot] = c;
                best[slot] = view;
                break;
            }
        }
    }
    ViewBlend blend;
    float floor_cosine = best[count] >= 0 ? cosines[count] : -1.0f;
    float sum = 0.0f;
    for (int k = 0; k < count; ++k) {
        blend.ids[k] = std::max(best[k], 0);
        blend.weights[k] = best[k] >= 0 ? std::max(cosines[k] - floor_cosine, 0.0f) : 0.0f;
        sum += blend.weights[k];
    }
    if (count == 1 || sum <= 0.0f) {
        std::fill(blend.weights, blend.weights + k_max_blend, 0.0f);
        blend.weights[0] = 1.0f;
    } else {
        for (int k = 0; k < count; ++k) blend.weights[k] /= sum;
    }
    return blend;
}

} // namespace standin::microfacets
