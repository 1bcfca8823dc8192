// Baking a displaced control mesh: the paper's offline stage.
// Bauman, Livny & El-Sana, §3 (control mesh), §3.1 (sampling), §3.2 (displacement maps and ∆_f),
// §3.4 (mip maps) and §5.1 (0.4% / 0.1% of the faces for degrees 17 / 33).
//
// Steps:
//  1. the settings (declared in representation.cpp); the target control-face count is the
//     input's over (k - 1)^2, so the refined mesh has about as many triangles as the input (the
//     paper's 0.4% and 0.1%) at degree 17; with the degree chosen (--degree 0, the default),
//     inputs under 65,536 faces spend the 65,536 finest triangles of the floor's 256 faces on
//     4,096 control faces at degree 5, or keep every face (default_control_plan: beyond the paper,
//     whose models are large); alpha-masked models default to degree 33, coarser where their cards would
//     hold over 8 million samples (cutout_degree, issue #14); a control mesh that stops over
//     k_max_pattern_growth times its target's samples takes 9 or 5 instead (control_degree);
//  2. the control mesh (control_mesh.cpp), and its edge table (topology.cpp); a model with
//     alpha-masked materials keeps its leaf cards whole in it (issue #14); control faces that are
//     textured source triangles keep the source's texture (source_textures.cpp);
//  3. sample the original along the pattern (sample.cpp), the mip levels (levels.cpp);
//  4. quantise the elevations (16 bits over the package's range) and use the decoded values from
//     here on, so what is measured is what is drawn;
//  5. rebuild Ms and measure ∆_f and d against the original;
//  6. encode shading normals (octahedral) and albedo (RGBA8); for models with alpha-masked
//     materials, the samples' coverage (issue #14: sample.cpp sees through cut-outs). Departure:
//     a textured model's shading is sampled 2 or 4 times finer than the pattern where its texels
//     are finer than the pattern step and it shows (finest_useful_detail, albedo_residual;
//     sample.cpp sample_fine_shading).
// Boundary loops keep k_min_loop_vertices in the control mesh (control_mesh.cpp), so a model of
// many open parts may stop above the target face count.
// Deterministic for any thread count: the decimator is sequential; everything else writes fixed
// slots from TBB loops.
#include "reps/displaced_mesh/control_mesh.h"
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/common/coverage_capture.h"
#include "reps/common/ray_scene.h"
#include "reps/displaced_mesh/sample.h"
#include <standin/log.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <optional>

namespace standin::displaced_mesh {

namespace {

std::size_t target_faces(std::size_t input_faces, const BakeSettings& s)
{
    if (s.control_faces > 0) return std::size_t(s.control_faces);
    std::size_t per_face = std::size_t(s.degree - 1) * std::size_t(s.degree - 1);
    std::size_t target = (input_faces + per_face / 2) / per_face;
    return std::max(target, std::min(k_min_control_faces, input_faces));
}

// The world length of one texel of the model's base-colour and normal textures, area-weighted
// over the faces that read one: sqrt(world area / texel area). 0 for models without them.
double texel_length(const Mesh& mesh)
{
    if (!mesh.has_texture_coordinates()) return 0.0;
    double world = 0.0, texels = 0.0;
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        const Material& material = mesh.materials[mesh.face_materials[f]];
        const int texture = material.base_color_texture >= 0 ? material.base_color_texture : material.normal_texture;
        if (texture < 0) continue;
        world += mesh.triangle_area(f);
        texels += triangle_texel_area(mesh, f, texture);
    }
    return texels > 0.0 && world > 0.0 ? std::sqrt(world / texels) : 0.0;
}

} // namespace

// The finest shading detail (1, 2 or 4) auto may choose: finer while the shading step is over
// k_blurred_pixels reference pixels (the thesis protocol's at 800 x 600, where the model's
// bounding sphere fills the view: a pixel is about diagonal / 564), or the cut-out faces' step
// over k_outline_pixels, and over two of the model's texels; within k_max_shading_samples (models
// with cut-out faces: k_max_outline_shading_samples). 1 for untextured models, and where every
// face draws the source's texture. Faces drawn from the source's texture are left out of the mean
// step, and the cut-out faces' step is left out when as many cut-out faces draw it as the source
// has (leaf cards, matched always): the 2,000-face bush took detail 2 for its cards' outlines,
// which its texture now draws.
int finest_useful_detail(const Mesh& mesh, const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& indices,
                         int degree, const std::vector<std::uint8_t>& drawn_from_source)
{
    const double texel = texel_length(mesh);
    if (!(texel > 0.0) || indices.empty()) return 1;
    const std::size_t faces = indices.size() / 3;
    auto from_source = [&](std::size_t f) { return f < drawn_from_source.size() && drawn_from_source[f] != 0; };
    double edges = 0.0;
    std::size_t sampled_faces = 0, cutout_faces_from_source = 0;
    for (std::size_t f = 0; f < faces; ++f) {
        if (from_source(f)) {
            cutout_faces_from_source += drawn_from_source[f] == k_drawn_from_source_cut_out;
            continue;
        }
        for (std::size_t k = 0; k < 3; ++k)
            edges += glm::length(glm::dvec3(positions[indices[3 * f + k]]) - glm::dvec3(positions[indices[3 * f + (k + 1) % 3]]));
        ++sampled_faces;
    }
    const double step = sampled_faces > 0 ? edges / double(3 * sampled_faces) / double(degree - 1) : 0.0; // the mean pattern step
    // the cut-out faces' own (kept whole in the control mesh, cutout_degree): the mean step over them
    double cutout_edges = 0.0;
    std::size_t cutout_faces = 0;
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        if (!(alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f)) continue;
        const std::uint32_t* v = &mesh.indices[3 * f];
        for (int k = 0; k < 3; ++k)
            cutout_edges += glm::length(glm::dvec3(mesh.positions[v[k]]) - glm::dvec3(mesh.positions[v[(k + 1) % 3]]));
        ++cutout_faces;
    }
    if (cutout_faces > 0 && cutout_faces_from_source >= cutout_faces) cutout_faces = 0;
    const double cutout_step = cutout_faces > 0 ? cutout_edges / double(3 * cutout_faces) / double(degree - 1) : 0.0;
    const double pixel = mesh.bounds().diagonal() / k_reference_pixels;
    auto shows = [&](int d) {
        return (step / d > k_blurred_pixels * pixel && step / d > 2.0 * texel) ||
               (cutout_step / d > k_outline_pixels * pixel && cutout_step / d > 2.0 * texel);
    };
    int detail = 1;
    while (detail < 4 && shows(detail)) detail *= 2;
    const std::size_t budget = cutout_faces > 0 ? k_max_outline_shading_samples : k_max_shading_samples;
    while (detail > 1 && faces * triangle_samples((degree - 1) * detail) > budget) detail /= 2;
    return detail;
}

namespace {

// The values of a shading pattern `fine_detail` times finer than n segments at the vertices of the
// one `detail` times finer, which the finer pattern holds: face-major, per face triangle_samples.
template <typename T>
std::vector<T> coarser(const std::vector<T>& fine, std::size_t faces, int n, int fine_detail, int detail)
{
    const int fine_n = n * fine_detail, coarse_n = n * detail, ratio = fine_detail / detail;
    const std::size_t per_fine = triangle_samples(fine_n), per_coarse = triangle_samples(coarse_n);
    std::vector<T> out(faces * per_coarse);
    for (std::size_t f = 0; f < faces; ++f)
        for (int i = 0; i <= coarse_n; ++i)
            for (int j = 0; j <= coarse_n - i; ++j)
                out[f * per_coarse + triangle_index(coarse_n, i, j)] = fine[f * per_fine + triangle_index(fine_n, i * ratio, j * ratio)];
    return out;
}

// How far the albedo of `fine` (shading samples `fine_detail` times finer than the pattern's n
// segments) lies from what `detail` draws there: the mean over the fine samples of the largest
// channel difference to the barycentric blend of the three `detail` samples around them (the
// renderer's interpolation), in [0, 1]. With `coverage` (alpha-masked models), a fine sample whose
// coverage the blend, cut at 1/2, gets wrong counts 1: a cut-out's outline is what detail draws there.
double albedo_residual(const std::vector<glm::vec4>& albedo, const std::vector<std::uint8_t>& coverage, std::size_t faces, int n,
                       int fine_detail, int detail, const std::vector<std::uint8_t>& drawn_from_source)
{
    const int fine_n = n * fine_detail, coarse_n = n * detail, ratio = fine_detail / detail;
    const std::size_t per_fine = triangle_samples(fine_n), per_coarse = triangle_samples(coarse_n);
    const std::vector<glm::vec4> coarse = coarser(albedo, faces, n, fine_detail, detail);
    const std::vector<std::uint8_t> coarse_coverage = coverage.empty() ? coverage : coarser(coverage, faces, n, fine_detail, detail);
    double sum = 0.0;
    std::size_t counted = 0;
    for (std::size_t f = 0; f < faces; ++f) {
        if (f < drawn_from_source.size() && drawn_from_source[f]) continue; // their samples' colour is not drawn
        ++counted;
        for (int a = 0; a <= fine_n; ++a)
            for (int b = 0; b <= fine_n - a; ++b) {
                const PatternTriangle cell = pattern_triangle(coarse_n, double(b) / ratio, double(a) / ratio);
                glm::vec4 blend(0.0f);
                double blend_coverage = 0.0;
                for (int k = 0; k < 3; ++k) {
                    blend += float(cell.weight[k]) * coarse[f * per_coarse + cell.index[k]];
                    if (!coverage.empty()) blend_coverage += cell.weight[k] * double(coarse_coverage[f * per_coarse + cell.index[k]]);
                }
                const std::size_t at = f * per_fine + triangle_index(fine_n, a, b);
                const glm::vec4 d = glm::abs(blend - albedo[at]);
                const bool outline_moved = !coverage.empty() && (blend_coverage >= 0.5) != (coverage[at] != 0);
                sum += outline_moved ? 1.0 : double(std::max({d.x, d.y, d.z}));
            }
    }
    return counted > 0 ? sum / double(counted * per_fine) : 0.0;
}

// Per control face, whether it draws colour and cut-outs from the source's texture
// (k_drawn_from_source, k_drawn_from_source_cut_out) or its samples (0): empty where the samples
// carry maps of the source besides colour (normal, ORM, emission textures: the renderer reads
// those from the samples, whose detail they then need).
std::vector<std::uint8_t> faces_drawn_from_source(const Mesh& mesh, const SourceTextures& source)
{
    for (const Material& m : mesh.materials)
        if (m.normal_texture >= 0 || m.metallic_roughness_texture >= 0 || m.occlusion_texture >= 0 || m.emissive_texture >= 0) return {};
    std::vector<std::uint8_t> drawn(source.faces.size(), 0);
    for (std::size_t f = 0; f < drawn.size(); ++f)
        if (source.faces[f].layer != k_no_texture)
            drawn[f] = source.faces[f].cutoff > 0.0f ? k_drawn_from_source_cut_out : k_drawn_from_source;
    return drawn;
}

// The shading normals of faces drawn from the source's texture, from the source triangle they are:
// its vertex normals interpolated at each sample, where sampling had found the nearest surface,
// which near the line where crossed cards meet is the other card (the 2,000-face bush's leaves
// shaded in stripes along their sprigs' stems at shading detail 1: Luv 1.08 against 0.07 drawn
// from the source's normals). Only where faces_drawn_from_source marks them (no normal maps).
void exact_source_normals(const Mesh& mesh, const SourceTextures& source, const std::vector<std::uint8_t>& drawn_from_source,
                          int shading_segments, std::vector<glm::vec3>& normals)
{
    const std::size_t per_face = triangle_samples(shading_segments);
    for (std::size_t f = 0; f < drawn_from_source.size() && f < source.source_corners.size(); ++f) {
        if (!drawn_from_source[f] || normals.size() < (f + 1) * per_face) continue;
        const std::array<std::uint32_t, 3>& v = source.source_corners[f];
        const glm::dvec3 n0(mesh.normals[v[0]]), n1(mesh.normals[v[1]]), n2(mesh.normals[v[2]]);
        // sample (i, j) has weights j / n on corner 1 and i / n on corner 2
        for (int i = 0; i <= shading_segments; ++i)
            for (int j = 0; j <= shading_segments - i; ++j) {
                const double w1 = double(j) / shading_segments, w2 = double(i) / shading_segments;
                const glm::dvec3 n = (1.0 - w1 - w2) * n0 + w1 * n1 + w2 * n2;
                const double length = glm::length(n);
                if (length > 1e-12) normals[f * per_face + triangle_index(shading_segments, i, j)] = glm::vec3(n / length);
            }
    }
}

} // namespace

ControlPlan default_control_plan(std::size_t input_faces)
{
    constexpr std::size_t paper_per_face = std::size_t(k_paper_degree - 1) * std::size_t(k_paper_degree - 1);
    const std::size_t paper_target = (input_faces + paper_per_face / 2) / paper_per_face;
    if (paper_target >= k_min_control_faces) return {k_paper_degree, paper_target};
    // the finest triangles the floor's faces held at the paper's degree, spent on control faces
    constexpr std::size_t budget = k_min_control_faces * paper_per_face;
    if (input_faces * 16 > budget) return {5, budget / 16};
    for (const int degree : {33, 17, 9})
        if (input_faces * std::size_t(degree - 1) * std::size_t(degree - 1) <= budget) return {degree, input_faces};
    return {5, input_faces};
}

// The default degree where the control mesh stopped above its target (displaced_mesh.h
// k_max_pattern_growth): the given default, coarser (9, 5) while `faces` would hold over
// k_max_pattern_growth times the finest samples `target` faces would.
int control_degree(std::size_t faces, std::size_t target, int degree)
{
    const std::size_t wanted = target * triangle_samples(degree - 1);
    while (degree > 5 && faces * triangle_samples(degree - 1) > k_max_pattern_growth * wanted) degree = (degree + 1) / 2;
    return degree;
}

// The default degree of a model with alpha-masked materials (displaced_mesh.h k_alpha_degree): its
// cut-out faces stay whole in the control mesh, so each holds a whole pattern; k_alpha_degree,
// coarser (17, 9, 5) while those faces would hold over k_max_cutout_samples finest samples.
int cutout_degree(const Mesh& mesh)
{
    std::size_t faces = 0;
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f)
        faces += alpha_test_cutoff(mesh.materials[mesh.face_materials[f]]) > 0.0f;
    int degree = k_alpha_degree;
    while (degree > 5 && faces * triangle_samples(degree - 1) > k_max_cutout_samples) degree = (degree + 1) / 2;
    return degree;
}

std::uint32_t encode_normal(glm::vec3 n)
{
    float sum = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    glm::vec2 p = sum > 0.0f ? glm::vec2(n.x, n.y) / sum : glm::vec2(0.0f);
    if (n.z < 0.0f) {
        glm::vec2 folded((1.0f - std::abs(p.y)) * (p.x >= 0.0f ? 1.0f : -1.0f), (1.0f - std::abs(p.x)) * (p.y >= 0.0f ? 1.0f : -1.0f));
        p = folded;
    }
    auto snorm = [](float v) { return std::uint32_t(std::uint16_t(std::int16_t(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f)))); };
    return snorm(p.x) | (snorm(p.y) << 16);
}

glm::vec3 decode_normal(std::uint32_t packed)
{
    auto unsnorm = [](std::uint32_t bits) { return std::max(float(std::int16_t(std::uint16_t(bits))) / 32767.0f, -1.0f); };
    glm::vec2 p(unsnorm(packed & 0xffffu), unsnorm(packed >> 16));
    glm::vec3 n(p.x, p.y, 1.0f - std::abs(p.x) - std::abs(p.y));
    if (n.z < 0.0f) {
        float x = n.x;
        n.x = (1.0f - std::abs(n.y)) * (x >= 0.0f ? 1.0f : -1.0f);
        n.y = (1.0f - std::abs(x)) * (n.y >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::normalize(n);
}

std::uint32_t pack_rgba8(glm::vec4 c)
{
    auto unorm = [](float v) { return std::uint32_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    return unorm(c.x) | (unorm(c.y) << 8) | (unorm(c.z) << 16) | (unorm(c.w) << 24);
}

Mesh sampled_mesh(const DisplacedMeshPackage& package)
{
    const PatternLayout layout = package.layout();
    std::vector<float> finest(package.face_count() * layout.finest_samples);
    for (std::size_t f = 0; f < package.face_count(); ++f)
        std::copy_n(&package.elevations[f * layout.samples_per_face], layout.finest_samples, &finest[f * layout.finest_samples]);
    ControlGeometry control{package.positions, package.normals, package.indices, package.topology};
    return reconstruct(control, layout, finest);
}

Result<std::unique_ptr<DisplacedMeshPackage>> bake_displaced(const Mesh& mesh, const SourceInfo& source,
                                                            const Options& parameters, const Progress& progress)
{
    // the settings: the paper's target is the input's faces over (k - 1)^2; alpha-masked models at
    // the default degree take cutout_degree (the leaf texture's detail lives in the samples' colours)
    Options effective = parameters;
    const bool auto_degree = effective.integer("degree") == 0, cutouts = reps::has_cutouts(mesh);
    std::optional<ControlPlan> plan; // small inputs: more control faces at a coarser degree, or all of them
    if (auto_degree) {
        if (cutouts) effective.set_integer("degree", cutout_degree(mesh));
        else if (effective.integer("control-faces") == 0) effective.set_integer("degree", (plan = default_control_plan(mesh.triangle_count()))->degree);
        else effective.set_integer("degree", k_paper_degree);
    }
    // back faces: culled where the truth culls single-sided backs that can be seen from outside
    // (assimp's COLLADA.dae, a single-sided plane under text: drawn from below, IoU 0.62); shown
    // elsewhere, where a closed model's backs face its inside
    if (effective.choice("back-faces") == "auto")
        effective.set_choice("back-faces", reps::visible_single_sided_backs(mesh) > reps::k_visible_backs ? "cull" : "show");
    BakeSettings settings = settings_from(effective);
    STANDIN_RETURN_IF_ERROR(check_settings(settings));
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, "displaced mesh bake"));
    auto package = std::make_unique<DisplacedMeshPackage>();
    package->source = source;

    // the control mesh under the cone constraint
    progress.report("control mesh", 0.0);
    ControlMeshOptions simplify;
    simplify.target_faces = plan ? plan->target_faces : target_faces(mesh.triangle_count(), settings);
    simplify.cone_angle_degrees = settings.cone_angle;
    simplify.keep_cutout_faces = cutouts;
    simplify.min_loop_vertices = k_min_loop_vertices;
    Result<ControlMesh> control = build_control_mesh(mesh, simplify);
    if (!control) return control.status();
    package->positions = std::move(control->positions);
    package->normals = std::move(control->normals);
    package->indices = std::move(control->indices);
    package->control = {control->input_faces, control->target_faces, control->reached_target, control->stopped_by,
                        control->collapses, control->refused_cone, control->refused_flip, control->refused_topology};
    Result<ControlTopology> topology = build_topology(package->positions.size(), package->indices);
    if (!topology) return topology.status();
    package->topology = std::move(*topology);
    // faces that are the source's textured triangles draw its texture (leaf cards always; every
    // face where the control mesh kept them all)
    if (settings.source_textures == "auto")
        package->source_textures = match_source_textures(mesh, package->positions, package->indices, control->collapses == 0);
    progress.report("control mesh", 1.0);
    // a control mesh that stopped far above its target (the boundary loops of many open parts keep
    // their vertices) takes a coarser default degree, so that its finest pattern holds about what
    // the target's would (control_degree)
    if (auto_degree && !cutouts) {
        const int degree = control_degree(package->face_count(), simplify.target_faces, settings.degree);
        if (degree != settings.degree) {
            log_message(LogLevel::info, "displaced mesh: " + std::to_string(package->face_count()) + " control faces (target " +
                                            std::to_string(simplify.target_faces) + "): degree " + std::to_string(degree) +
                                            " instead of " + std::to_string(settings.degree));
            effective.set_integer("degree", degree);
            settings = settings_from(effective);
        }
    }
    package->parameters = effective;
    package->settings = settings;
    const PatternLayout layout(settings.degree);
    // the shading detail: given, or for auto the finest that shows (finest_useful_detail), then the
    // coarsest whose colours stay within k_shading_residual of it (after sampling, below)
    const bool auto_detail = effective.choice("shading-detail") == "auto";
    const std::vector<std::uint8_t> drawn_from_source = faces_drawn_from_source(mesh, package->source_textures);
    const int sampled_detail = auto_detail ? finest_useful_detail(mesh, package->positions, package->indices, settings.degree, drawn_from_source)
                                           : settings.shading_detail;

    // sample the original, then the levels
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh.positions, mesh.indices);
    if (!scene) return scene.status();
    ControlGeometry geometry{package->positions, package->normals, package->indices, package->topology};
    SampleOptions sample_options;
    sample_options.degree = settings.degree;
    sample_options.sampler = settings.sampler;
    sample_options.interpolation_rays = settings.interpolation_rays;
    sample_options.ray_range = settings.ray_range * mesh.bounds().diagonal();
    sample_options.move_hidden_out = control->collapses > 0 || cutouts; // kept whole: every surface its own faces
    Result<SampledSurface> sampled = sample_surface(mesh, **scene, geometry, sample_options, progress);
    if (!sampled) return sampled.status();
    std::vector<float> levels = build_levels(layout, sampled->elevation);

    // quantise, and keep what the renderer will decode
    if (settings.elevation_bits == 16) {
        Quantisation q = choose_quantisation(levels, elevation_step_floor(mesh.bounds().diagonal()));
        package->elevation_codes = quantise(levels, q);
        package->elevation_minimum = q.minimum;
        package->elevation_step = q.step;
        for (std::size_t i = 0; i < levels.size(); ++i) levels[i] = q.decode(package->elevation_codes[i]);
    }
    package->elevations = std::move(levels);

    // Ms against the original: ∆_f and d
    Mesh ms = sampled_mesh(*package);
    Result<SamplingError> measured =
        measure_sampling_error(mesh, **scene, ms, package->face_count(), settings.degree, progress);
    if (!measured) return measured.status();
    package->face_error = std::move(measured->face_error);
    package->sampling = {sampled->rays, sampled->misses, measured->original_to_sampled_mean, measured->original_to_sampled_max,
                         measured->sampled_to_original_mean, measured->sampled_to_original_max};

    // shading attributes, finer than the pattern where the texture's detail asks for it
    int shading_detail = sampled_detail;
    if (sampled_detail > 1) {
        SampledSurface fine = sample_fine_shading(mesh, **scene, geometry, *sampled, settings.degree, sampled_detail,
                                                  sample_options.ray_range, progress);
        if (auto_detail) {
            shading_detail = 1;
            while (shading_detail < sampled_detail &&
                   albedo_residual(fine.albedo, fine.coverage, package->face_count(), layout.segments, sampled_detail, shading_detail,
                                   drawn_from_source) >
                       k_shading_residual)
                shading_detail *= 2;
            if (shading_detail < sampled_detail) {
                const std::size_t faces = package->face_count();
                fine.normal = coarser(fine.normal, faces, layout.segments, sampled_detail, shading_detail);
                fine.albedo = coarser(fine.albedo, faces, layout.segments, sampled_detail, shading_detail);
                if (!fine.pbr.empty()) fine.pbr = coarser(fine.pbr, faces, layout.segments, sampled_detail, shading_detail);
                if (!fine.coverage.empty()) fine.coverage = coarser(fine.coverage, faces, layout.segments, sampled_detail, shading_detail);
            }
        }
        if (shading_detail > 1) {
            sampled->normal = std::move(fine.normal);
            sampled->albedo = std::move(fine.albedo);
            sampled->pbr = std::move(fine.pbr);
            sampled->coverage = std::move(fine.coverage);
        }
    }
    exact_source_normals(mesh, package->source_textures, drawn_from_source, layout.segments * shading_detail, sampled->normal);
    // textures finer than the shading samples chosen: their colours averaged over each sample's cell
    prefilter_texture_colour(mesh, **scene, geometry, layout.segments * shading_detail, sample_options.ray_range, *sampled);
    if (auto_detail) {
        effective.set_choice("shading-detail", std::to_string(shading_detail));
        package->parameters = effective;
        package->settings = settings_from(effective);
    }
    package->shading_normals.resize(sampled->normal.size());
    package->albedo.resize(sampled->albedo.size());
    for (std::size_t i = 0; i < sampled->normal.size(); ++i) {
        package->shading_normals[i] = encode_normal(sampled->normal[i]);
        package->albedo[i] = pack_rgba8(sampled->albedo[i]);
    }
    if (!sampled->coverage.empty()) {
        package->coverage.resize(sampled->coverage.size());
        for (std::size_t i = 0; i < sampled->coverage.size(); ++i) package->coverage[i] = sampled->coverage[i] ? 255 : 0;
    }
    if (!sampled->pbr.empty()) {
        package->orm.resize(sampled->pbr.size());
        package->emission.resize(sampled->pbr.size());
        for (std::size_t i = 0; i < sampled->pbr.size(); ++i) {
            const PbrSample& s = sampled->pbr[i];
            package->orm[i] = pack_rgba8(glm::vec4(s.occlusion, s.roughness, s.metallic, 1.0f));
            glm::vec3 e = glm::clamp(s.emissive, 0.0f, 1.0f);
            glm::vec3 encoded = glm::mix(e * 12.92f, 1.055f * glm::pow(e, glm::vec3(1.0f / 2.4f)) - 0.055f,
                                         glm::vec3(glm::greaterThan(e, glm::vec3(0.0031308f))));
            package->emission[i] = pack_rgba8(glm::vec4(encoded, 1.0f));
        }
    }
    return package;
}

Result<std::unique_ptr<Package>> bake(const BakeContext& context)
{
    std::optional<tbb::global_control> threads;
    if (context.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(context.threads));
    Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(context.mesh, context.source, context.parameters, context.progress);
    if (!package) return package.status();
    return std::unique_ptr<Package>(std::move(*package));
}

} // namespace standin::displaced_mesh
