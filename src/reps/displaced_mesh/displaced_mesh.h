// Displaced control mesh in memory (Bauman, Livny & El-Sana, "GPU-Based Adaptive-Subdivision for
// View-Dependent Rendering"): a control mesh simplified from the original under a normal-cone
// constraint, and per control face a triangular displacement map of degree k (k = 2^m + 1) with
// its mip levels, plus shading normals and albedo sampled with it. At run time the control faces
// are culled on their prisms, bisected on the GPU to a screen-space tolerance and displaced
// (renderer.cpp). Shared by the baker, the package codec and the renderer of this folder.
#pragma once

#include "reps/displaced_mesh/pattern.h"
#include "reps/displaced_mesh/source_textures.h"
#include "reps/displaced_mesh/topology.h"

#include <standin/package.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin::displaced_mesh {

// Bake parameters typed (docs/FORMAT.md, "Displaced control mesh"; declared in representation.cpp,
// defaults measured in docs/RESULTS.md).
struct BakeSettings {
    int degree = 17;                   // pattern degree k: 5, 9, 17 or 33 (the option's 0, chosen, is resolved by the bake)
    int control_faces = 0;             // target; 0: input faces / (k - 1)^2, at least k_min_control_faces (or all)
    float cone_angle = 90.0f;          // degrees: no vertex's normal cone may reach it (90: a half-sphere)
    std::string sampler = "intersection"; // "intersection" or "interpolation" (§3.1)
    int interpolation_rays = 16;       // sub-rays per pattern triangle of the interpolation sampler
    float ray_range = 0.05f;           // fraction of the bounding-box diagonal, each way along the normal
    int elevation_bits = 16;           // 16: unorm over the package's range; 32: float
    // "show" draws both sides of every face; "cull" culls back faces, as the truth does for
    // single-sided materials (the bake's auto resolves to cull where such backs can be seen from
    // outside: reps::visible_single_sided_backs)
    std::string back_faces = "show";
    // shading samples per pattern step along an edge: 1, 2 or 4 (the bake's auto resolves it from
    // the model's texel size; the package records which)
    int shading_detail = 1;
    bool compressed = true; // arrays as .bin.gz (docs/FORMAT.md "Compressed arrays"), else raw .bin
    // "auto": control faces that are textured source triangles read the source's texture at render
    // time (source_textures.h); "off": every face draws its samples, as the paper's maps
    std::string source_textures = "auto";
};

// Control faces wanted at least (all the input's when it has fewer): small models would otherwise
// get a handful of faces whose patches cannot follow the surface.
constexpr std::size_t k_min_control_faces = 256;
// The pattern degree the paper measured best (Bauman et al. §5.1: 17 and 33, 17 faster at equal
// error): the default where the control faces are asked for (--control-faces) and the model is
// large enough for the paper's target (default_control_plan).
constexpr int k_paper_degree = 17;
// The default plan (--degree and --control-faces not given, no cut-outs): the paper's target, the
// input's faces over (k - 1)^2 at degree 17, holds at least k_min_control_faces from 65,536 input
// faces on. Below that the floor made the refined mesh far larger than the input (256 faces x 256
// = 65,536 finest triangles) and its simplification lost parts (assimp's 2,032-face jeep: 504
// control faces, fenders gone, Luv 3.60, IoU 0.964; a 576-face minigun 70 ms a frame against the
// mesh's 6). The same 65,536 finest triangles are now spent on control faces: 4,096 of them at
// degree 5, and inputs of 4,096 faces or fewer keep every face, at the finest degree (5 to 33)
// whose pattern stays within them; a flat face then refines no further than itself, and the
// displaced surface is the input's own (the jeep: Luv 0.73, IoU 1.0, the same bytes; the minigun
// 5 ms; a 5,126-face model at 4,096 faces: Luv 2.21 -> 0.03; docs/RESULTS.md "Small models:
// every face a control face"). Returns the degree and the control-face target.
struct ControlPlan {
    int degree = 17;
    std::size_t target_faces = 0;
};
ControlPlan default_control_plan(std::size_t input_faces);
// The default pattern degree of models with alpha-masked materials (issue #14). A leaf card stays
// whole in the control mesh and its texture's detail lives in the samples' colours: degree 17 left
// 2 or more pixels per sample on the generated tree's cards at distance 1 (foliage Luv 3.40 there,
// 2.74 at 33; docs/RESULTS.md "Displaced mesh on foliage: colour"), at 3.6x the package bytes.
// Coarser (17, 9, 5) only where the cut-out faces would hold over k_max_cutout_samples finest
// samples: a 100,000-card tree at 33 would hold 55 million (some 700 MB; the bake ran past 20
// minutes), cards a few pixels wide whose detail no view shows (bake.cpp cutout_degree). A rule by
// the cards' size on screen (17 where its step is under a reference pixel) was tried and cost
// assimp's human.zae 0.2 Luv (docs/RESULTS.md "The four stand-ins on ... a 100,000-card tree").
constexpr int k_alpha_degree = 33;
constexpr std::size_t k_max_cutout_samples = 8'000'000;
int cutout_degree(const Mesh& mesh);
// The auto shading detail (BakeSettings::shading_detail, bake.cpp): finer than 1 only for
// textured models (alpha-masked ones too: coverage is sampled with the shading) whose mean pattern step is over
// k_blurred_pixels reference pixels (a pixel of an 800 x 600 view the model's bounding sphere
// fills: diagonal / k_reference_pixels) and over two of their texels; there the shading is sampled
// at the finest such detail (up to 4, within k_max_shading_samples) and the coarsest detail whose
// albedo, interpolated, stays within k_shading_residual of it (the mean of the largest channel
// difference) is kept. Measured on textured models in docs/RESULTS.md "Shading finer than the
// pattern". The cut-out faces of alpha-masked models ask for it from k_outline_pixels on: there the
// coverage outlines leaves, and a leaf's edge a pixel off shows where a blur of 4 does not (game
// foliage's cards of many small leaves; docs/RESULTS.md "Cards of many leaves").
constexpr double k_reference_pixels = 564.0;
constexpr double k_blurred_pixels = 4.0;
constexpr double k_outline_pixels = 1.0;
constexpr double k_shading_residual = 0.01;
constexpr std::size_t k_max_shading_samples = 8'000'000;
// Models with cut-out faces: there the samples' coverage is the leaves' outline, and a denser crown
// of cards than 8 million samples hold at detail 2 lost leaves (the 20,000-face bush: 11.2 million
// at degree 17, IoU 0.946 at detail 1, 0.969 at 2; docs/RESULTS.md "Displaced mesh: arrays
// compressed, finer outlines on dense foliage"). The renderer's buffers take 8 bytes a shading
// sample (that bush's buffers: 107 MiB in all, 45 at detail 1; a shading buffer of 16 million
// samples: 122 MiB, under the 128 MiB that llvmpipe allows a storage buffer); the package's gzip arrays a fraction (3.2 MB).
constexpr std::size_t k_max_outline_shading_samples = 16'000'000;
// The finest shading detail auto samples for `mesh` over a control mesh (positions, indices).
// Control faces `drawn_from_source` marks draw colour and cut-outs from the source's own texture
// (source_textures.h): their samples' colour is not shown, so they ask for no detail (empty: none).
constexpr std::uint8_t k_drawn_from_source = 1, k_drawn_from_source_cut_out = 2;
int finest_useful_detail(const Mesh& mesh, const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                         int degree, const std::vector<std::uint8_t>& drawn_from_source = {});
// Vertices a boundary loop of the control mesh keeps (ControlMeshOptions::min_loop_vertices): a
// round rim or hole as a 12-gon is within 3.5% of its radius, where a triangle (what the quadrics
// alone reach on a model of many small open parts) is 50% off.
constexpr std::size_t k_min_loop_vertices = 12;
// A control mesh that stops above its target (boundary loops kept, above) would refine to far more
// triangles than the input has: the held-out 2CylinderEngine (110,000 faces, 59 open parts) keeps
// 17,197 control faces for a target of 431, whose degree-17 patterns drew 3.7 million triangles a
// frame (7 s at 800 x 600 on llvmpipe, against 34 ms for the mesh). Without a given --degree such a
// mesh takes the finest of 17, 9 and 5 that keeps its finest samples within this factor of what
// the target's faces would hold, or 5 (bake.cpp control_degree; docs/RESULTS.md "Displaced mesh on
// assemblies: a coarser degree where the control mesh stops early").
constexpr std::size_t k_max_pattern_growth = 4;
int control_degree(std::size_t faces, std::size_t target, int degree);

struct ControlStats {
    std::size_t input_faces = 0, target_faces = 0;
    bool reached_target = false;
    std::string stopped_by;
    std::size_t collapses = 0, refused_cone = 0, refused_flip = 0, refused_topology = 0;
};

struct SamplingStats {
    std::size_t rays = 0, misses = 0;
    // the paper's d (Table 2/3): mean and max distance from the original's vertices to Ms; and from
    // Ms's vertices to the original. World units.
    double original_to_sampled_mean = 0.0, original_to_sampled_max = 0.0;
    double sampled_to_original_mean = 0.0, sampled_to_original_max = 0.0;
};

class DisplacedMeshPackage final : public Package {
public:
    std::string representation() const override { return "displaced-mesh"; }

    std::size_t face_count() const { return indices.size() / 3; }
    PatternLayout layout() const { return PatternLayout(settings.degree); }
    // the shading arrays' pattern: (k - 1) x shading_detail segments per edge
    int shading_segments() const { return layout().segments * settings.shading_detail; }
    std::size_t shading_samples_per_face() const { return triangle_samples(shading_segments()); }

    Options parameters;    // as baked
    BakeSettings settings; // settings_from(parameters)
    // the control mesh (object space); normals unit, one per vertex (the displacement directions)
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;
    std::vector<std::uint32_t> indices;
    ControlTopology topology; // derived from indices
    ControlStats control;

    // every level of every face's elevations, face-major (PatternLayout::samples_per_face each),
    // decoded to world units; with 16-bit storage also the codes and their range
    std::vector<float> elevations;
    std::vector<std::uint16_t> elevation_codes;
    float elevation_minimum = 0.0f, elevation_step = 0.0f;
    // the shading pattern (shading_samples_per_face per face, face-major; the finest elevation
    // pattern where shading_detail is 1): octahedral unit normal (two snorm16) and RGBA8 albedo (sRGB)
    std::vector<std::uint32_t> shading_normals;
    std::vector<std::uint32_t> albedo;
    // PBR packages only (issue #14), else empty: RGBA8 occlusion, roughness, metallic (linear), 255;
    // RGBA8 emission (sRGB, clamped to 1), 255
    std::vector<std::uint32_t> orm, emission;
    // Packages of models with alpha-masked materials only (issue #14), else empty: per shading
    // sample, 255 where its ray met a point that survives the alpha test, 0 where it saw only
    // cut-outs or nothing. The renderer interpolates it like the albedo and discards below 1/2.
    std::vector<std::uint8_t> coverage;
    std::vector<float> face_error; // ∆_f per face, world units
    SamplingStats sampling;
    // control faces that are source triangles, drawn with the source's base-colour texture
    // (source_textures.h; bake option source-textures), or empty
    SourceTextures source_textures;
};

// Octahedral encoding of unit normals into two snorm16 (x in the low half).
std::uint32_t encode_normal(glm::vec3 n);
glm::vec3 decode_normal(std::uint32_t packed);
std::uint32_t pack_rgba8(glm::vec4 c);

// The sampled mesh Ms of a package at its finest level (sample.h: reconstruct), in object space.
Mesh sampled_mesh(const DisplacedMeshPackage& package);

// The bake parameters typed (representation.cpp), and the checks between them.
BakeSettings settings_from(const Options& parameters);
Status check_settings(const BakeSettings& settings);

// The registry entry (representation.cpp): options, debug views and the functions below.
Representation registration();
Result<std::unique_ptr<Package>> bake(const BakeContext& context);
Status write(const Package& package, const std::string& directory);
Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest);
Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings);
// `standin export` (export.cpp): the surface refined to a tolerance, as one plain mesh.
std::vector<OptionSpec> export_options();
Result<ExportScene> export_scene(const Package& package, const Options& options);

// The bake itself, for tests and benchmarks that want the in-memory package: `parameters` are
// the representation's declared bake options (defaults for those not given).
Result<std::unique_ptr<DisplacedMeshPackage>> bake_displaced(const Mesh& mesh, const SourceInfo& source,
                                                            const Options& parameters, const Progress& progress);
// The declared bake options with the given ones set (NAME, VALUE; invalid_argument as the CLI's).
Result<Options> bake_parameters(const std::vector<std::pair<std::string, std::string>>& values);

} // namespace standin::displaced_mesh
