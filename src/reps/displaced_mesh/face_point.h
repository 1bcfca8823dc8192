// Points of a control face in fixed-point barycentric coordinates, evaluated the same way from
// every face that holds them. Two faces sharing an edge must compute bit-identical positions and
// normals for the points on it, or the displaced surface cracks there (Bauman, Livny & El-Sana §3.3
// promise a "crackless" triangulation). So a point on an edge is evaluated from the edge alone, in
// its canonical direction (from the lower vertex index), and a corner is the vertex itself; only
// points inside a face use all three corners. shaders/displaced.glsl mirrors this file.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>

namespace standin::displaced_mesh {

// Barycentric weights are integers over k_bary_one (2^30): a pattern vertex of any degree and any
// midpoint of an edge segment down to 2^-30 is exact, and exact in float on edges (few bits set).
constexpr std::uint32_t k_bary_bits = 30;
constexpr std::uint32_t k_bary_one = 1u << k_bary_bits;

struct FacePoint {
    glm::vec3 position{0.0f};
    glm::vec3 normal{0.0f}; // interpolated, not normalised (Eq. 1b)
};

// corner: the face's three vertex indices; q1, q2: weights of corners 1 and 2 (q0 = one - q1 - q2).
inline FacePoint face_point(const glm::vec3* positions, const glm::vec3* normals, const std::uint32_t corner[3],
                            std::uint32_t q1, std::uint32_t q2)
{
    const std::uint32_t q[3] = {k_bary_one - q1 - q2, q1, q2};
    for (int k = 0; k < 3; ++k)
        if (q[k] == k_bary_one) return {positions[corner[k]], normals[corner[k]]};
    for (int k = 0; k < 3; ++k) {
        if (q[k] != 0) continue;
        // on the edge opposite corner k: from its lower vertex index, by the other end's weight
        int a = (k + 1) % 3, b = (k + 2) % 3;
        int lo = corner[a] < corner[b] ? a : b, hi = lo == a ? b : a;
        float t = float(q[hi]) / float(k_bary_one);
        glm::vec3 p_lo = positions[corner[lo]], n_lo = normals[corner[lo]];
        return {p_lo + t * (positions[corner[hi]] - p_lo), n_lo + t * (normals[corner[hi]] - n_lo)};
    }
    float w[3] = {float(q[0]) / float(k_bary_one), float(q[1]) / float(k_bary_one), float(q[2]) / float(k_bary_one)};
    FacePoint out;
    out.position = w[0] * positions[corner[0]] + w[1] * positions[corner[1]] + w[2] * positions[corner[2]];
    out.normal = w[0] * normals[corner[0]] + w[1] * normals[corner[1]] + w[2] * normals[corner[2]];
    return out;
}

// The unit direction of an interpolated normal (the displacement direction).
inline glm::vec3 unit_direction(glm::vec3 normal)
{
    float length = glm::length(normal);
    return length > 0.0f ? normal / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

} // namespace standin::displaced_mesh
