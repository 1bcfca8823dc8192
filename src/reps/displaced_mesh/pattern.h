// The sampling pattern of a displaced control mesh (Bauman, Livny & El-Sana §3.1, Fig. 5): a
// uniform triangular grid of degree k (k vertices along an edge, k = 2^m + 1) mapped onto every
// control face, and the triangular arrays that hold one value per pattern vertex, level by level
// (a vertex-centred pyramid, §3.4's mip maps; level 0 is the finest, level m holds the corners).
//
// Pattern vertex (i, j), 0 <= i <= n, 0 <= j <= n - i, n = k - 1, has barycentric weights
// (w0, w1, w2) = ((n - i - j) / n, j / n, i / n) on the face's corners (c0, c1, c2): row i runs
// parallel to the edge c0 -> c1. Arrays store rows in order, row i holding n + 1 - i values.
// The face's edges are numbered by their first corner: edge 0 = c0 -> c1 (i = 0), edge 1 =
// c1 -> c2 (i + j = n), edge 2 = c2 -> c0 (j = 0).
#pragma once

#include <cassert>
#include <cstddef>
#include <cstdint>

namespace standin::displaced_mesh {

// Degrees the package accepts: 5, 9, 17, 33 (m = 2..5, the DMM subdivision levels 2..5).
constexpr int k_min_pattern_exponent = 2;
constexpr int k_max_pattern_exponent = 5;

constexpr bool is_pattern_degree(int degree)
{
    for (int m = k_min_pattern_exponent; m <= k_max_pattern_exponent; ++m)
        if (degree == (1 << m) + 1) return true;
    return false;
}

constexpr int pattern_exponent(int degree)
{
    int m = 0;
    while ((1 << m) + 1 < degree) ++m;
    return m;
}

// Values in a triangular array of n segments per edge.
constexpr std::size_t triangle_samples(int n) { return std::size_t(n + 1) * std::size_t(n + 2) / 2; }
// Index of (i, j) in a triangular array of n segments per edge.
constexpr std::size_t triangle_index(int n, int i, int j)
{
    return std::size_t(i) * std::size_t(n + 1) - std::size_t(i) * std::size_t(i - 1) / 2 + std::size_t(j);
}

// The pyramid of one face: levels 0..m, level l has n >> l segments per edge.
struct PatternLayout {
    int degree = 17;
    int exponent = 4;   // m
    int segments = 16;  // n = k - 1
    std::size_t level_offset[k_max_pattern_exponent + 2] = {}; // level l starts here; [m + 1] = total
    std::size_t samples_per_face = 0;                         // every level
    std::size_t finest_samples = 0;                           // level 0

    explicit PatternLayout(int degree_) : degree(degree_), exponent(pattern_exponent(degree_)), segments(degree_ - 1)
    {
        assert(is_pattern_degree(degree_));
        std::size_t offset = 0;
        for (int l = 0; l <= exponent; ++l) {
            level_offset[l] = offset;
            offset += triangle_samples(segments >> l);
        }
        level_offset[exponent + 1] = offset;
        samples_per_face = offset;
        finest_samples = triangle_samples(segments);
    }
    int level_segments(int level) const { return segments >> level; }
    std::size_t index(int level, int i, int j) const { return level_offset[level] + triangle_index(segments >> level, i, j); }
};

// Row and column of the pattern vertex at position s (0..n) along edge e of a face, walking from
// the edge's first corner to its second.
inline void edge_vertex(int n, int edge, int s, int& i, int& j)
{
    switch (edge) {
    case 0: i = 0, j = s; break;         // c0 -> c1
    case 1: i = s, j = n - s; break;     // c1 -> c2
    default: i = n - s, j = 0; break;    // c2 -> c0
    }
}

// The triangle of an n-segment pattern holding the point at pattern coordinates (x, y) (x along j,
// y along i, each 0..n): its vertices' array indices and barycentric weights, split as the
// renderer's draw.frag splits a pattern cell.
struct PatternTriangle {
    std::size_t index[3];
    double weight[3];
};
inline PatternTriangle pattern_triangle(int n, double x, double y)
{
    int i0 = y < 0.0 ? 0 : int(y), j0 = x < 0.0 ? 0 : int(x);
    i0 = i0 > n - 1 ? n - 1 : i0;
    j0 = j0 > n - 1 - i0 ? n - 1 - i0 : j0;
    const double fx = x - j0, fy = y - i0;
    if (fx + fy <= 1.0)
        return {{triangle_index(n, i0, j0), triangle_index(n, i0, j0 + 1), triangle_index(n, i0 + 1, j0)}, {1.0 - fx - fy, fx, fy}};
    return {{triangle_index(n, i0, j0 + 1), triangle_index(n, i0 + 1, j0 + 1), triangle_index(n, i0 + 1, j0)},
            {1.0 - fy, fx + fy - 1.0, 1.0 - fx}};
}

} // namespace standin::displaced_mesh
