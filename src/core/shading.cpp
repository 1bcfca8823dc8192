// The shading model of src/gpu/shaders/common/lighting.glsl on the CPU (Khronos glTF 2.0
// specification, Appendix B; Walter et al. 2007 GGX; Heitz 2014 height-correlated Smith; Karis 2014
// split sum, with the specular albedo tabulated in gpu/shaders/common/specular_albedo_table.h). Steps and departures are those of lighting.glsl, which this mirrors
// formula by formula so that tests of this file test the shader's model.
#include "core/shading.h"

#include "gpu/shaders/common/specular_albedo_table.h"

#include <algorithm>
#include <cmath>

namespace standin {

namespace {

constexpr float k_pi = 3.14159265358979f;
constexpr float k_min_roughness = 0.05f;
constexpr float k_dielectric_f0 = 0.04f;

float ggx_distribution(float n_dot_h, float alpha)
{
    float a2 = alpha * alpha;
    float d = n_dot_h * n_dot_h * (a2 - 1.0f) + 1.0f;
    return a2 / (k_pi * d * d);
}

float smith_visibility(float n_dot_l, float n_dot_v, float alpha)
{
    float a2 = alpha * alpha;
    float gv = n_dot_l * std::sqrt(n_dot_v * n_dot_v * (1.0f - a2) + a2);
    float gl = n_dot_v * std::sqrt(n_dot_l * n_dot_l * (1.0f - a2) + a2);
    float g = gv + gl;
    return g > 0.0f ? 0.5f / g : 0.0f;
}

glm::vec3 fresnel_schlick(glm::vec3 f0, float v_dot_h)
{
    float m = 1.0f - std::clamp(v_dot_h, 0.0f, 1.0f);
    float m2 = m * m;
    return f0 + (1.0f - f0) * (m2 * m2 * m);
}

const float k_specular_albedo[SHADING_TABLE_SIZE * SHADING_TABLE_SIZE * 2] = {SHADING_SPECULAR_ALBEDO_TABLE};

glm::vec2 specular_albedo_terms(float n_dot_v, float roughness)
{
    const float last = float(SHADING_TABLE_SIZE - 1);
    glm::vec2 p = glm::clamp(glm::vec2(n_dot_v, roughness), 0.0f, 1.0f) * last;
    glm::ivec2 i0 = glm::min(glm::ivec2(p), glm::ivec2(SHADING_TABLE_SIZE - 2));
    glm::vec2 t = p - glm::vec2(i0);
    int k00 = 2 * (i0.y * SHADING_TABLE_SIZE + i0.x), k01 = k00 + 2 * SHADING_TABLE_SIZE;
    auto at = [](int k) { return glm::vec2(k_specular_albedo[k], k_specular_albedo[k + 1]); };
    glm::vec2 a = glm::mix(at(k00), at(k00 + 2), t.x);
    glm::vec2 b = glm::mix(at(k01), at(k01 + 2), t.x);
    return glm::mix(a, b, t.y);
}

float clamped_roughness(const BrdfInputs& inputs) { return std::clamp(inputs.roughness, k_min_roughness, 1.0f); }

glm::vec3 specular_f0(const BrdfInputs& inputs)
{
    return glm::mix(glm::vec3(k_dielectric_f0), inputs.base, std::clamp(inputs.metallic, 0.0f, 1.0f));
}

glm::vec3 specular_albedo(const BrdfInputs& inputs, float n_dot_v)
{
    glm::vec2 ab = specular_albedo_terms(n_dot_v, clamped_roughness(inputs));
    return specular_f0(inputs) * ab.x + ab.y;
}

// What the specular lobe leaves to the diffuse one, seen from n.v (lighting.glsl's diffuse_weight).
glm::vec3 diffuse_weight(const BrdfInputs& inputs, float n_dot_v) { return 1.0f - specular_albedo(inputs, n_dot_v); }

} // namespace

BrdfLobes evaluate_brdf_lobes(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye)
{
    float n_dot_l = glm::dot(n, to_light);
    float n_dot_v = std::clamp(glm::dot(n, to_eye), 1e-4f, 1.0f);
    if (n_dot_l <= 0.0f) return {};
    float roughness = clamped_roughness(inputs);
    float alpha = roughness * roughness;
    glm::vec3 diffuse = inputs.base * (1.0f - std::clamp(inputs.metallic, 0.0f, 1.0f));
    glm::vec3 h = glm::normalize(to_light + to_eye);
    glm::vec3 f = fresnel_schlick(specular_f0(inputs), glm::dot(to_eye, h));
    float specular = ggx_distribution(std::max(glm::dot(n, h), 0.0f), alpha) * smith_visibility(n_dot_l, n_dot_v, alpha);
    return {diffuse_weight(inputs, n_dot_v) * diffuse / k_pi, f * specular};
}

glm::vec3 evaluate_brdf(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye)
{
    BrdfLobes lobes = evaluate_brdf_lobes(inputs, n, to_light, to_eye);
    return lobes.diffuse + lobes.specular;
}

glm::vec3 environment_reflectance(const BrdfInputs& inputs, float n_dot_v)
{
    n_dot_v = std::clamp(n_dot_v, 1e-4f, 1.0f);
    glm::vec3 diffuse = inputs.base * (1.0f - std::clamp(inputs.metallic, 0.0f, 1.0f));
    return diffuse * diffuse_weight(inputs, n_dot_v) + specular_albedo(inputs, n_dot_v);
}

glm::vec3 shade_linear(const BrdfInputs& inputs, glm::vec3 n, glm::vec3 to_light, glm::vec3 to_eye, float ambient,
                       float diffuse)
{
    glm::vec3 color(0.0f);
    float n_dot_l = glm::dot(n, to_light);
    if (n_dot_l > 0.0f) color += evaluate_brdf(inputs, n, to_light, to_eye) * (k_pi * diffuse * n_dot_l);
    color += ambient * environment_reflectance(inputs, glm::dot(n, to_eye));
    return color;
}

} // namespace standin
