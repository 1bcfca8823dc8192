// The surface image: what every image-based stand-in stores of a piece of surface. A billboard, a
// view of an atlas, a microfacet texture and a displaced patch are all oriented images of colour +
// coverage and normal + depth over a plane, with one depth encoding (16 bits over a depth range).
#pragma once

#include <standin/image.h>

#include "reps/common/shaders/height_field.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace standin::reps {

// Texel (i, j) covers the square origin + [i, i+1) * texel_size * axis_u + [j, j+1) * texel_size *
// axis_v on the front plane; row j of the images (j = 0 first in memory) is texel row j. Depth d in
// [0, 1] of a texel puts the surface at plane point + d * depth_range * direction.
struct SurfaceImage {
    glm::vec3 origin{0.0f};        // world position of the plane corner at texel (0, 0)
    glm::vec3 axis_u{1, 0, 0};     // unit, along image columns
    glm::vec3 axis_v{0, 1, 0};     // unit, along image rows
    glm::vec3 direction{0, 0, -1}; // unit, from the plane into the model (away from the capture)
    float texel_size = 1.0f;       // world units per texel
    float depth_range = 1.0f;      // world units from the plane (depth 0) to depth 1
    int width = 0, height = 0;     // texels
    // RGB: albedo (sRGB-encoded), A: coverage (0 empty, 255 covered)
    ImageRGBA8 color;
    // RGB: shading normal, world space, n * 0.5 + 0.5 (encode_normal); A: depth (encode_depth).
    // Packages that store fewer bits hold the quantised value, expanded to 16 in memory.
    ImageRGBA16 normal_depth;
    // PBR maps (issue #14), both empty unless the model has PBR materials (Mesh::has_pbr_materials):
    // orm: occlusion, perceptual roughness, metallic (linear), coverage; emission: the emitted
    // colour, sRGB-encoded and clamped to [0, 1], coverage. Renderers use Material's defaults
    // (1, 1, 0; black) where they are empty.
    ImageRGBA8 orm, emission;
};

// One texel of the PBR maps from a surface sample (write_pbr_texel) and the default one.
inline void write_pbr_texel(ImageRGBA8& orm, ImageRGBA8& emission, int x, int y, float occlusion, float roughness,
                            float metallic, glm::vec3 emissive_linear)
{
    auto unorm8 = [](float v) { return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    std::uint8_t* o = orm.at(x, y);
    o[0] = unorm8(occlusion), o[1] = unorm8(roughness), o[2] = unorm8(metallic), o[3] = 255;
    std::uint8_t* e = emission.at(x, y);
    for (int c = 0; c < 3; ++c) {
        e[c] = unorm8(linear_to_srgb(std::clamp(emissive_linear[c], 0.0f, 1.0f)));
    }
    e[3] = 255;
}

// The one depth encoding: d in [0, 1] of the depth range, as a 16-bit code.
constexpr float k_depth_codes = 65535.0f;
static_assert(k_depth_codes == float(HF_DEPTH_CODES), "one depth encoding for C++ and GLSL");
inline std::uint16_t encode_depth(float depth) { return std::uint16_t(std::lround(std::clamp(depth, 0.0f, 1.0f) * k_depth_codes)); }
inline float decode_depth(std::uint16_t code) { return float(code) / k_depth_codes; }
// A normal component n in [-1, 1] as n * 0.5 + 0.5 in 16 bits, and back.
inline std::uint16_t encode_normal(float n) { return encode_depth(n * 0.5f + 0.5f); }
inline glm::vec3 decode_normal(const std::uint16_t* rgb) { return glm::vec3(rgb[0], rgb[1], rgb[2]) / k_depth_codes * 2.0f - 1.0f; }

// The shared link rule (height_field.h) in C++: the depth change per texel along `along` that a
// stored normal implies, in texels of depth, capped at HF_MAX_SLOPE (the twin of hf_slope in
// height_field.glsl); and whether two neighbouring covered texels `depth_step` depth codes apart
// continue one surface, a texel being `texel_world` wide, depth `codes_per_world` codes per world
// unit, and `quantum_codes` one step of the stored depth.
inline float hf_normal_slope(glm::vec3 normal, glm::vec3 along, glm::vec3 direction)
{
    const float max_slope = float(HF_MAX_SLOPE);
    float across = std::abs(glm::dot(normal, direction)), along_slope = std::abs(glm::dot(normal, along));
    if (along_slope >= across * max_slope) return max_slope;
    return along_slope / across;
}
inline bool hf_linked(float depth_step, glm::vec3 normal_a, glm::vec3 normal_b, glm::vec3 along, glm::vec3 direction,
                      float texel_world, float codes_per_world, float quantum_codes)
{
    float slope = std::max(hf_normal_slope(normal_a, along, direction), hf_normal_slope(normal_b, along, direction));
    float allowed = (float(HF_SLOPE_TOLERANCE) * slope + float(HF_CURVATURE_TEXELS)) * texel_world * codes_per_world +
                    float(HF_QUANTA) * quantum_codes;
    return std::abs(depth_step) <= allowed;
}

} // namespace standin::reps
