// The BRDF of src/gpu/shaders/common/lighting.glsl evaluated on the CPU (glTF 2.0 metallic-roughness:
// GGX, height-correlated Smith, Schlick Fresnel, Lambert diffuse weighted by 1 - F), so tests can
// integrate it: the white-furnace check that the shading model neither creates energy nor loses
// more than single scattering does. Keep every formula equal to the GLSL one.
#pragma once

#include <glm/glm.hpp>

namespace standin {

struct BrdfInputs {
    glm::vec3 base{1.0f};  // linear base colour
    float roughness = 1.0f; // perceptual, clamped to [0.05, 1] as the shader does
    float metallic = 0.0f;
};

// The BRDF f(l, v) = diffuse + specular for unit n, l, v (0 where n.l <= 0), linear RGB per
// steradian: diffuse = (1 - F) base (1 - metallic) / pi, specular = F D V.
struct BrdfLobes {
    glm::vec3 diffuse{0.0f}, specular{0.0f};
};
BrdfLobes evaluate_brdf_lobes(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye);
glm::vec3 evaluate_brdf(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye);

// What the shader returns (linear, before sRGB encoding and clamping) for a light of `diffuse`
// strength from `to_light` and a uniform environment of radiance `ambient` (split-sum approximation),
// occlusion 1 and no emission.
glm::vec3 shade_linear(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye, float ambient,
                       float diffuse);

// The split-sum environment term alone: the reflectance of the surface seen from `n_dot_v` under a
// uniform white environment of radiance 1 (split sum with the tabulated specular albedo).
glm::vec3 environment_reflectance(const BrdfInputs& inputs, float n_dot_v);

} // namespace standin
