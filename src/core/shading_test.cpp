// White-furnace tests of the shading model (core/shading.cpp, the CPU twin of lighting.glsl): a
// white surface under a uniform white light must reflect at most what it receives, and lose no
// more than single scattering does; the split-sum environment term must agree with the BRDF it
// approximates. Integrals are deterministic stratified importance sampling (cosine for the diffuse
// lobe, GGX normals for the specular one), so narrow lobes integrate as well as wide ones.
#include "core/shading.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace standin {
namespace {

constexpr float k_furnace_pi = 3.14159265358979f;

// The directional albedo seen from `to_eye` (n = +z): the integral over the hemisphere of
// f(l, v) n.l dl, what a white furnace of radiance 1 reflects towards the eye.
glm::vec3 directional_albedo(const BrdfInputs& inputs, glm::vec3 to_eye)
{
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    const int strata = 256;
    float roughness = std::clamp(inputs.roughness, 0.05f, 1.0f);
    float a2 = roughness * roughness * roughness * roughness;
    glm::dvec3 sum(0.0);
    for (int j = 0; j < strata; ++j)
        for (int i = 0; i < strata; ++i) {
            float u1 = (float(i) + 0.5f) / float(strata), u2 = (float(j) + 0.5f) / float(strata);
            float phi = 2.0f * k_furnace_pi * u2;
            // diffuse lobe: l cosine-distributed (pdf n.l / pi), weight f pi
            float r = std::sqrt(u1);
            glm::vec3 l(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u1)));
            sum += glm::dvec3(evaluate_brdf_lobes(inputs, n, l, to_eye).diffuse * k_furnace_pi);
            // specular lobe: h drawn from D(h) n.h, l = reflect(-v, h) (pdf D n.h / (4 v.h))
            float cos_theta = std::sqrt((1.0f - u1) / (1.0f + (a2 - 1.0f) * u1));
            float sin_theta = std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta));
            glm::vec3 h(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
            float v_dot_h = glm::dot(to_eye, h);
            if (v_dot_h <= 0.0f) continue;
            glm::vec3 reflected = 2.0f * v_dot_h * h - to_eye;
            float n_dot_l = reflected.z;
            if (n_dot_l <= 0.0f) continue;
            float alpha2 = a2;
            float d = cos_theta * cos_theta * (alpha2 - 1.0f) + 1.0f;
            float pdf = alpha2 / (k_furnace_pi * d * d) * cos_theta / (4.0f * v_dot_h);
            sum += glm::dvec3(evaluate_brdf_lobes(inputs, n, reflected, to_eye).specular * (n_dot_l / pdf));
        }
    return glm::vec3(sum / double(strata * strata));
}

glm::vec3 eye_at(float theta_degrees)
{
    float t = glm::radians(theta_degrees);
    return {std::sin(t), 0.0f, std::cos(t)};
}

const float k_roughnesses[] = {0.05f, 0.25f, 0.5f, 0.75f, 1.0f};
const float k_view_angles[] = {0.0f, 30.0f, 60.0f, 80.0f};

TEST(ShadingFurnace, NeverReflectsMoreThanItReceives)
{
    // rough metals lose what single scattering loses (down to about 0.31 at roughness 1); nothing
    // may gain (the 1.5 % margin is the integration's own error on the narrowest lobe)
    for (float metallic : {0.0f, 1.0f})
        for (float roughness : k_roughnesses)
            for (float theta : k_view_angles) {
                glm::vec3 albedo = directional_albedo({glm::vec3(1.0f), roughness, metallic}, eye_at(theta));
                EXPECT_LE(albedo.x, 1.015f) << "metallic " << metallic << " roughness " << roughness << " at " << theta;
                EXPECT_GT(albedo.x, 0.3f) << "metallic " << metallic << " roughness " << roughness << " at " << theta;
            }
}

TEST(ShadingFurnace, WhiteDielectricKeepsEverything)
{
    // the diffuse lobe gets exactly what the specular one leaves, at every roughness and angle
    for (float roughness : k_roughnesses)
        for (float theta : k_view_angles) {
            float albedo = directional_albedo({glm::vec3(1.0f), roughness, 0.0f}, eye_at(theta)).x;
            EXPECT_NEAR(albedo, 1.0f, 0.01f) << "roughness " << roughness << " at " << theta;
        }
}

TEST(ShadingFurnace, SmoothMetalLosesNothing)
{
    // at low roughness single scattering is exact: a white mirror-like metal reflects everything
    for (float theta : {0.0f, 30.0f, 60.0f})
        EXPECT_NEAR(directional_albedo({glm::vec3(1.0f), 0.05f, 1.0f}, eye_at(theta)).x, 1.0f, 0.015f) << "at " << theta;
}

TEST(ShadingFurnace, EnvironmentTermMatchesTheBrdfItApproximates)
{
    // the split-sum ambient (uniform environment of radiance 1) against the integral of the BRDF: a
    // white furnace lit by the environment alone reflects what one lit from every direction does
    for (float metallic : {0.0f, 0.5f, 1.0f})
        for (float roughness : k_roughnesses)
            for (float theta : k_view_angles) {
                BrdfInputs inputs{glm::vec3(1.0f), roughness, metallic};
                glm::vec3 v = eye_at(theta);
                float split_sum = environment_reflectance(inputs, v.z).x;
                EXPECT_LE(split_sum, 1.0f + 1e-4f);
                EXPECT_NEAR(split_sum, directional_albedo(inputs, v).x, 0.01f)
                    << "metallic " << metallic << " roughness " << roughness << " at " << theta;
            }
}

TEST(ShadingFurnace, ColouredMetalReflectsItsColourAtNormalIncidence)
{
    // Schlick: F0 = base for a metal, so a smooth red metal reflects red and almost no green
    glm::vec3 albedo = directional_albedo({glm::vec3(0.9f, 0.1f, 0.1f), 0.1f, 1.0f}, eye_at(0.0f));
    EXPECT_NEAR(albedo.x, 0.9f, 0.02f);
    EXPECT_NEAR(albedo.y, 0.1f, 0.02f);
}

TEST(ShadingFurnace, DefaultMaterialStaysCloseToTheOldLambertLook)
{
    // formats without PBR materials get a fully rough dielectric: under the default light (ambient
    // 0.2, diffuse 0.8) a grey 0.5 surface stays within 4 % of the old Lambert + ambient value
    const glm::vec3 n(0.0f, 0.0f, 1.0f);
    for (float light_theta : {0.0f, 45.0f, 75.0f})
        for (float view_theta : {0.0f, 40.0f}) {
            glm::vec3 l = eye_at(light_theta), v(-std::sin(glm::radians(view_theta)), 0.0f, std::cos(glm::radians(view_theta)));
            float now = shade_linear({glm::vec3(0.5f), 1.0f, 0.0f}, n, l, v, 0.2f, 0.8f).x;
            float before = 0.5f * (0.2f + 0.8f * l.z);
            EXPECT_NEAR(now / before, 1.0f, 0.04f) << "light " << light_theta << " view " << view_theta;
        }
}

} // namespace
} // namespace standin
