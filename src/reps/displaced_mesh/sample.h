// Sampling the original surface over the control mesh's pattern, the mip levels of the samples,
// and how far the result lies from the original (Bauman, Livny & El-Sana §3.1, §3.2, §3.4, §5.1).
// sample.cpp and levels.cpp hold the algorithms.
#pragma once

#include "reps/displaced_mesh/pattern.h"
#include "reps/common/ray_scene.h"
#include "reps/displaced_mesh/topology.h"

#include <standin/mesh.h>
#include <standin/progress.h>
#include <standin/status.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <cmath>
#include <vector>

namespace standin::displaced_mesh {

using reps::closest_point_in_triangle;
using reps::RayScene;
using reps::SurfacePoint;

// The control mesh as the sampler and the reconstruction read it.
struct ControlGeometry {
    const std::vector<glm::vec3>& positions;
    const std::vector<glm::vec3>& normals;     // unit, one per vertex
    const std::vector<std::uint32_t>& indices; // three per face
    const ControlTopology& topology;
    std::size_t face_count() const { return indices.size() / 3; }
};

struct SampleOptions {
    int degree = 17;
    // "intersection": the elevation where the vertex's ray meets the surface (§3.1);
    // "interpolation": the paper's neighbourhood sampler, here the mean of sub-ray elevations over
    // the vertex's ring of pattern triangles, weighted by the vertex's hat function.
    std::string sampler = "intersection";
    int interpolation_rays = 16; // per pattern triangle, a square number (r x r sub-triangles)
    float ray_range = 1.0f;      // world units, each way along the normal
    // A hit hidden inside a closed part moves out to the surface enclosing it (outermost_visible),
    // and one under a layer a hair over it to the layer (over_layers), so a simplified control
    // face sunk into a part or under a decal draws what the model shows. false where the control
    // mesh is the input's own faces (bake.cpp: a small model kept whole): each surface is drawn by
    // its own faces and a sample stays on the one it lies on; the moves only put spikes in faces
    // (assimp's minigun: 5,069 triangles drawn for 576 faces, 454 without them). The intersection
    // sampler's samples only.
    bool move_hidden_out = true;
};

// The finest level of every face, face-major (PatternLayout::finest_samples per face).
struct SampledSurface {
    std::vector<float> elevation;      // signed, along the unit interpolated normal
    std::vector<glm::vec3> normal;     // unit shading normal of the original where the ray met it
    std::vector<glm::vec4> albedo;     // sRGB-encoded albedo there (Mesh::albedo_at)
    std::vector<PbrSample> pbr;        // its PBR inputs (Mesh::pbr_at); empty unless Mesh::has_pbr_materials()
    // 1 where the sample's ray met a point that survives the alpha test, 0 where it went through
    // cut-outs only or met nothing (issue #14); empty unless has_cutouts(original)
    std::vector<std::uint8_t> coverage;
    std::size_t rays = 0;              // rays cast
    std::size_t misses = 0;            // vertices whose rays met nothing within range (closest point used)
};


// Shared edges and corners are sampled once, from the edge or the vertex, and copied into every
// face that has them: the faces' values there are bit-identical. Deterministic for any thread count.
Result<SampledSurface> sample_surface(const Mesh& original, const RayScene& original_scene, const ControlGeometry& control,
                                      const SampleOptions& options, const Progress& progress);

// The area of `triangle` in texels of `texture` (its texture coordinates' area times the
// texture's size): with Mesh::triangle_area, how fine a texture lies on the surface.
double triangle_texel_area(const Mesh& mesh, std::size_t triangle, int texture);

// Departure: shading finer than the elevations. A textured model keeps its colour detail in the
// shading samples, and at one per pattern vertex a low-poly textured model's texture was read 17
// times along a control face (the bundled 12-face box: thesis Luv 7.1). `detail` (2 or 4) times
// finer, per face (PatternLayout::finest_samples of (k - 1) x detail segments each, face-major):
// the pattern's own vertices keep `coarse`'s shading; every other one takes the original's
// shading at the point closest to the displaced surface there (the finest elevations interpolated
// as the renderer draws them), so shading follows the geometry drawn, hidden surfaces included.
// Points on a face's edges are taken a hair inside it, so each face shades a crease with its own
// side (as take_own_shading does). Elevations are left empty; coverage is not sampled (models
// with alpha-masked materials keep detail 1). Deterministic for any thread count.
SampledSurface sample_fine_shading(const Mesh& original, const RayScene& scene, const ControlGeometry& control,
                                   const SampledSurface& coarse, int degree, int detail, float range, const Progress& progress);

// Departure: the colour of a textured model's shading samples that lie on the original (a small
// model keeps every face: bake.cpp default_control_plan), averaged over each sample's cell where
// the triangle's texels are finer than the sample step (`segments` per control edge): a point
// sample of such a texture aliases, where the truth reads the mip level of its footprint (assimp's
// spider, 1,312 faces kept at degree 5: thesis Luv 2.85 -> 1.98, CIEDE2000 2.10 -> 1.49). Samples
// off the surface and coarser texels keep their point sample; models with cut-outs are filtered
// while sampling. Deterministic for any thread count.
void prefilter_texture_colour(const Mesh& original, const RayScene& scene, const ControlGeometry& control, int segments, float range,
                              SampledSurface& shading);

// Every level of every face from the finest (levels.cpp): level l + 1 keeps the even vertices of
// level l, filtered: corners copied, vertices on the face's edges by 1/4, 1/2, 1/4 along the edge
// (a symmetric formula, so both faces of an edge compute the same bits), inside by 1/2 of the
// centre and 1/12 of each of the six neighbours. Face-major, PatternLayout::samples_per_face each.
std::vector<float> build_levels(const PatternLayout& layout, const std::vector<float>& finest);

// Elevations stored in 16 bits: codes over one range for the whole package (per-face ranges would
// decode the sample two faces share differently on each, and crack).
struct Quantisation {
    float minimum = 0.0f;
    float step = 0.0f; // (maximum - minimum) / 65535, at least the floor below
    float decode(std::uint16_t code) const { return minimum + float(code) * step; }
};
// `min_step`: no finer than this (the bake's: 2^-22 of the model's diagonal, two float ulps of its
// largest coordinates). Samples lying on the original carry elevations of float rounding; where
// nothing else widens the range (a model kept whole: the generated tree's ±7e-8), 65,535 codes over
// that noise made it incompressible (elevations 32 kB -> 2.6 MB).
Quantisation choose_quantisation(const std::vector<float>& values, float min_step = 0.0f);
// The bake's floor for choose_quantisation: two float ulps of a model of this diagonal.
inline float elevation_step_floor(float diagonal) { return std::ldexp(diagonal, -22); }
std::vector<std::uint16_t> quantise(const std::vector<float>& values, const Quantisation& q);

// The sampled mesh Ms at the finest level: every face's pattern displaced, one vertex per face
// sample (shared samples repeated), (k - 1)^2 triangles per face, face-major. Positions use the
// face_point arithmetic of the renderer.
Mesh reconstruct(const ControlGeometry& control, const PatternLayout& layout, const std::vector<float>& finest_elevation);

// Distances between the original and Ms: ∆_f per face (A7 of the design note: the largest
// distance from an original vertex to Ms among the vertices whose closest point lies on f's patch)
// and the paper's d both ways.
struct SamplingError {
    std::vector<float> face_error;  // ∆_f, world units
    double original_to_sampled_mean = 0.0, original_to_sampled_max = 0.0; // the paper's d (Table 2)
    double sampled_to_original_mean = 0.0, sampled_to_original_max = 0.0; // over Ms's vertices
};
Result<SamplingError> measure_sampling_error(const Mesh& original, const RayScene& original_scene, const Mesh& sampled,
                                             std::size_t control_faces, int degree, const Progress& progress);

} // namespace standin::displaced_mesh
