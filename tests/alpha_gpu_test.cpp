// Alpha (issue #14) on the GPU: the ground truth cuts out what the alpha test cuts (a disc of
// analytic area out of a quad, moved by the cutoff; blend drawn as mask at 0.5), hides the back of
// single-sided materials, and every stand-in baked from the generated leaf-card tree keeps the
// leaves' cut-outs: silhouette IoU and colour at distance 1, leaf coverage at distances 4 and 8
// against the truth's (thresholds measured, with margin: docs/RESULTS.md "Alpha-masked foliage").
#include "test_support.h"

#include <standin/camera.h>
#include <standin/eval.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/progress.h>
#include <standin/render.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <numbers>

namespace standin {
namespace {

std::size_t covered_pixels_of(const ImageRGBA8& image)
{
    std::size_t n = 0;
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) n += image.pixels[i] > 0;
    return n;
}

// Pixels the truth covers, the quad seen square-on from +z (azimuth 0) or from behind (180).
std::size_t alpha_truth_pixels(const Mesh& mesh, float azimuth, int size = 400)
{
    test::gpu_context();
    auto renderer = make_mesh_renderer(mesh);
    EXPECT_TRUE(renderer.is_ok()) << renderer.status().message();
    if (!renderer.is_ok()) return 0;
    OrbitView view;
    view.azimuth_degrees = azimuth;
    view.orthographic = true;
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    auto image = render_offscreen(**renderer, camera, default_light(camera), size, size);
    EXPECT_TRUE(image.is_ok()) << image.status().message();
    return image.is_ok() ? covered_pixels_of(image->color) : 0;
}

TEST(AlphaTruth, MaskCutsADiscOfTheAnalyticAreaAndTheCutoffMovesIt)
{
    double quad = double(alpha_truth_pixels(test::alpha_quad(AlphaMode::opaque, 0.5f, true), 0.0f));
    ASSERT_GT(quad, 10000.0);
    for (float cutoff : {0.25f, 0.5f, 0.75f}) {
        double expected = std::numbers::pi * (1.0 - cutoff) * (1.0 - cutoff) / 4.0;
        double measured = double(alpha_truth_pixels(test::alpha_quad(AlphaMode::mask, cutoff, true), 0.0f)) / quad;
        EXPECT_NEAR(measured, expected, 0.01) << "cutoff " << cutoff;
    }
    // blend: drawn as mask at 0.5 (the documented method), whatever the cutoff field says
    EXPECT_EQ(alpha_truth_pixels(test::alpha_quad(AlphaMode::blend, 0.9f, true), 0.0f),
              alpha_truth_pixels(test::alpha_quad(AlphaMode::mask, 0.5f, true), 0.0f));
}

TEST(AlphaTruth, SingleSidedMaterialsHideTheirBackFaces)
{
    Mesh single = test::alpha_quad(AlphaMode::opaque, 0.5f, false), both = test::alpha_quad(AlphaMode::opaque, 0.5f, true);
    std::size_t front = alpha_truth_pixels(single, 0.0f);
    EXPECT_GT(front, 10000u);
    EXPECT_EQ(alpha_truth_pixels(single, 180.0f), 0u);
    EXPECT_EQ(alpha_truth_pixels(both, 180.0f), front);
    EXPECT_EQ(alpha_truth_pixels(both, 0.0f), front);
}

TEST(AlphaTruth, MinifiedCutOutKeepsItsColour)
{
    // the disc cut-out with black in its empty texels (as most files have), drawn about 9 pixels wide (the
    // 256-texel texture about 4 levels down): coverage-weighted mips keep every covered pixel the
    // disc's one colour; plain means (glGenerateMipmap) darkened its rim towards black
    Mesh quad = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    for (std::size_t i = 0; i < quad.textures[0].rgba.size(); i += 4) {
        std::uint8_t* t = &quad.textures[0].rgba[i];
        if (t[3] < 128) t[0] = t[1] = t[2] = t[3] = 0;
        else t[3] = 255;
    }
    test::gpu_context();
    auto renderer = make_mesh_renderer(quad);
    ASSERT_TRUE(renderer.is_ok()) << renderer.status().message();
    OrbitView view;
    view.orthographic = true;
    Camera camera = orbit_camera(quad.bounding_sphere(), view, 1.0f);
    const Light albedo{default_light(camera).direction_to_light_world, 1.0f, 0.0f, 0.0f, 1.0f,
                       ShadingModel::lambert_blinn_phong}; // pure ambient: the colour is the albedo
    auto image = render_offscreen(**renderer, camera, albedo, 16, 16);
    ASSERT_TRUE(image.is_ok()) << image.status().message();
    // every covered pixel the colour of the disc's interior (the brightest: shading scales all alike)
    glm::ivec3 interior(0);
    for (std::size_t i = 0; i < image->color.pixels.size(); i += 4)
        if (image->color.pixels[i + 3] != 0 && image->color.pixels[i + 1] > interior.y)
            interior = {image->color.pixels[i], image->color.pixels[i + 1], image->color.pixels[i + 2]};
    EXPECT_GT(interior.y, 100);
    int covered = 0;
    for (std::size_t i = 0; i < image->color.pixels.size(); i += 4) {
        const std::uint8_t* p = &image->color.pixels[i];
        if (p[3] == 0) continue;
        ++covered;
        EXPECT_NEAR(p[0], interior.x, 3);
        EXPECT_NEAR(p[1], interior.y, 3);
        EXPECT_NEAR(p[2], interior.z, 3);
    }
    EXPECT_GT(covered, 10); // about 24 pixels
}

// Each stand-in on the generated tree, against the truth: IoU and Luv at distance 1 (4 views of
// the thesis' directions), Luv at distances 4 and 8 (their 8 views), coverage ratio at 4 and 8.
struct FoliageFigures {
    double iou = 0.0, luv = 0.0, luv_far = 0.0, coverage4 = 0.0, coverage8 = 0.0;
};

FoliageFigures foliage_figures(const Mesh& tree, const Package& package, const RenderOptions& options = {})
{
    test::gpu_context();
    auto truth = make_mesh_renderer(tree);
    auto standin = make_package_renderer(package, options);
    EXPECT_TRUE(truth.is_ok() && standin.is_ok());
    FoliageFigures f;
    if (!truth.is_ok() || !standin.is_ok()) return f;
    Protocol protocol;
    protocol.name = "foliage-test";
    const glm::vec2 directions[] = {{0, 30}, {120, -30}, {240, 30}, {0, 90}};
    for (float distance : {1.0f, 4.0f, 8.0f})
        for (glm::vec2 d : directions) {
            EvalView view;
            view.orbit.azimuth_degrees = d.x;
            view.orbit.elevation_degrees = d.y;
            view.orbit.distance_rel = distance;
            view.width = 400, view.height = 300;
            protocol.views.push_back(view);
        }
    EvalOptions eval_options;
    eval_options.timed_frames = 0;
    auto result = evaluate(**truth, **standin, tree.bounding_sphere(), protocol, eval_options, {});
    EXPECT_TRUE(result.is_ok()) << result.status().message();
    if (!result.is_ok()) return f;
    std::map<float, std::pair<double, double>> pixels; // distance -> (stand-in, truth)
    for (const ViewResult& v : result->views) {
        if (v.view.orbit.distance_rel == 1.0f) {
            f.iou += v.metrics.iou / 4.0;
            f.luv += v.metrics.luv_mean / 4.0;
        } else {
            f.luv_far += v.metrics.luv_mean / 8.0;
        }
        pixels[v.view.orbit.distance_rel].first += double(v.metrics.standin_pixels);
        pixels[v.view.orbit.distance_rel].second += double(v.metrics.truth_pixels);
    }
    f.coverage4 = pixels[4.0f].first / pixels[4.0f].second;
    f.coverage8 = pixels[8.0f].first / pixels[8.0f].second;
    return f;
}

// The alpha quad (a green disc kept of its card) with an opaque red card of the same size 0.3
// behind it: seen from the front, the truth shows the disc green and the red card through the
// cut-out corners.
Mesh card_before_card()
{
    Mesh mesh = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    const glm::vec4 red(0.8f, 0.15f, 0.1f, 1.0f);
    const std::uint32_t base = std::uint32_t(mesh.positions.size());
    for (std::uint32_t k = 0; k < 4; ++k) {
        mesh.positions.push_back(mesh.positions[k] + glm::vec3(0.0f, 0.0f, -0.3f));
        mesh.normals.push_back(glm::vec3(0.0f, 0.0f, 1.0f));
        mesh.colors.push_back(red);
        mesh.uvs.push_back(mesh.uvs[k]);
    }
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + k);
    mesh.face_materials.insert(mesh.face_materials.end(), 2, 1u);
    Material back;
    back.name = "back";
    back.base_color = red;
    mesh.materials.push_back(back);
    return mesh;
}

struct FrontView {
    std::size_t green = 0, red = 0; // pixels of the leaf, of the card behind
};

FrontView front_view(Renderer& renderer, const Mesh& mesh)
{
    OrbitView view;
    view.orthographic = true;
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    auto image = render_offscreen(renderer, camera, default_light(camera), 300, 300);
    EXPECT_TRUE(image.is_ok()) << image.status().message();
    FrontView out;
    if (!image.is_ok()) return out;
    const std::vector<std::uint8_t>& p = image->color.pixels;
    for (std::size_t i = 0; i < p.size(); i += 4) {
        if (p[i + 3] == 0) continue;
        if (p[i + 1] > p[i]) ++out.green;
        else ++out.red;
    }
    return out;
}

// The displaced mesh keeps cut-outs (issue #14): its rays see through them at bake, its samples
// store coverage, and its renderer discards the cut-out with depth tested late, so the card behind
// shows through the hole (not the background, not the front card's depth); the leaf keeps its area
// at every distance. The samples' coverage alone (--source-textures off): with the source's texture
// the cards below draw their cut-outs from it (LeafCardsDrawTheSourceTextureAsTheTruthDoes).
TEST(AlphaDisplacedMesh, CutOutsShowWhatIsBehindAndKeepTheirArea)
{
    test::gpu_context();
    const Mesh scene = card_before_card();
    std::unique_ptr<Package> package = test::bake(scene, "displaced-mesh", {{"source-textures", "off"}});
    ASSERT_TRUE(package);
    auto truth = make_mesh_renderer(scene);
    auto standin = make_package_renderer(*package, {});
    ASSERT_TRUE(truth.is_ok() && standin.is_ok());
    FrontView t = front_view(**truth, scene), s = front_view(**standin, scene);
    std::printf("[alpha displaced] front: truth green %zu red %zu, stand-in green %zu red %zu\n", t.green, t.red, s.green, s.red);
    ASSERT_GT(t.green, 5000u);
    ASSERT_GT(t.red, 3u * t.green);
    // measured on llvmpipe: green 0.958 of the truth's (the disc's contour runs through a pattern of
    // 16 steps per card side), red 1.010; without cut-outs green would be 5x and red none
    EXPECT_NEAR(double(s.green) / double(t.green), 1.0, 0.08);
    EXPECT_NEAR(double(s.red) / double(t.red), 1.0, 0.03);

    // the leaf alone, as the foliage protocol measures it: IoU near, coverage far
    const Mesh leaf = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    std::unique_ptr<Package> leaf_package = test::bake(leaf, "displaced-mesh", {{"source-textures", "off"}});
    ASSERT_TRUE(leaf_package);
    FoliageFigures f = foliage_figures(leaf, *leaf_package);
    std::printf("[alpha displaced] leaf: IoU %.4f, Luv %.3f, coverage d4 %.3f, d8 %.3f\n", f.iou, f.luv, f.coverage4, f.coverage8);
    // measured: IoU 0.921 (the contour again, on a card that fills the view), coverage 0.993 / 0.976
    EXPECT_GE(f.iou, 0.88);
    EXPECT_NEAR(f.coverage4, 1.0, 0.06);
    EXPECT_NEAR(f.coverage8, 1.0, 0.06);
}

// Issue #14: a leaf card kept whole is a source triangle, so the displaced mesh draws the source's
// texture on it, filtered and alpha-tested as the truth reads it (source_textures.h): the disc's
// outline and colour come from its texels, not from the samples' coverage interpolated across a
// pattern step; the card behind shows through the cut-out as in the truth.
TEST(AlphaDisplacedMesh, LeafCardsDrawTheSourceTextureAsTheTruthDoes)
{
    test::gpu_context();
    const Mesh leaf = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    std::unique_ptr<Package> textured = test::bake(leaf, "displaced-mesh", {});
    std::unique_ptr<Package> sampled = test::bake(leaf, "displaced-mesh", {{"source-textures", "off"}});
    ASSERT_TRUE(textured && sampled);
    FoliageFigures with = foliage_figures(leaf, *textured), without = foliage_figures(leaf, *sampled);
    std::printf("[alpha displaced] leaf, source texture: IoU %.4f, Luv %.3f, far %.3f, coverage %.3f / %.3f; samples: IoU "
                "%.4f, Luv %.3f, far %.3f\n",
                with.iou, with.luv, with.luv_far, with.coverage4, with.coverage8, without.iou, without.luv, without.luv_far);
    EXPECT_GE(with.iou, 0.995);
    EXPECT_LE(with.luv, 0.5);
    EXPECT_LE(with.luv_far, 0.5);
    EXPECT_NEAR(with.coverage4, 1.0, 0.01);
    EXPECT_NEAR(with.coverage8, 1.0, 0.01);
    // the path is taken: measured, the samples alone IoU 0.9785, Luv 1.90; the texture 1.0000, 0.000
    EXPECT_LT(without.iou, with.iou - 0.01);
    EXPECT_GT(without.luv, with.luv + 1.0);

    const Mesh scene = card_before_card();
    std::unique_ptr<Package> package = test::bake(scene, "displaced-mesh", {});
    ASSERT_TRUE(package);
    auto truth = make_mesh_renderer(scene);
    auto standin = make_package_renderer(*package, {});
    ASSERT_TRUE(truth.is_ok() && standin.is_ok());
    FrontView t = front_view(**truth, scene), s = front_view(**standin, scene);
    std::printf("[alpha displaced] front, source texture: truth green %zu red %zu, stand-in green %zu red %zu\n", t.green, t.red,
                s.green, s.red);
    EXPECT_NEAR(double(s.green) / double(t.green), 1.0, 0.01);
    EXPECT_NEAR(double(s.red) / double(t.red), 1.0, 0.01);
}

// Silhouette IoU of a stand-in against the truth over a front and two oblique views (perspective,
// distance 1, 400 x 400).
double silhouette_iou(Renderer& truth, Renderer& standin, const Mesh& mesh)
{
    double sum = 0.0;
    const glm::vec2 directions[] = {{0.0f, 0.0f}, {35.0f, 20.0f}, {-50.0f, -25.0f}};
    for (glm::vec2 d : directions) {
        OrbitView view;
        view.azimuth_degrees = d.x;
        view.elevation_degrees = d.y;
        Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
        auto t = render_offscreen(truth, camera, default_light(camera), 400, 400);
        auto s = render_offscreen(standin, camera, default_light(camera), 400, 400);
        EXPECT_TRUE(t.is_ok() && s.is_ok());
        if (!t.is_ok() || !s.is_ok()) return 0.0;
        std::size_t both = 0, either = 0;
        for (std::size_t i = 3; i < t->color.pixels.size(); i += 4) {
            bool a = t->color.pixels[i] > 0, b = s->color.pixels[i] > 0;
            both += a && b;
            either += a || b;
        }
        sum += either > 0 ? double(both) / double(either) : 0.0;
    }
    return sum / 3.0;
}

// The disc card's silhouette IoU baked at one capture sample per texel (binary coverage) and at
// `fractional` samples (nullptr: the representation's default), set through the representation's
// measurement switch `samples_variable`.
std::array<double, 2> disc_iou_binary_and_fractional(const char* representation, const char* samples_variable,
                                                     const char* fractional,
                                                     const std::vector<std::pair<std::string, std::string>>& values)
{
    test::gpu_context();
    const Mesh leaf = test::alpha_quad(AlphaMode::mask, 0.5f, true);
    auto truth = make_mesh_renderer(leaf);
    EXPECT_TRUE(truth.is_ok());
    std::array<double, 2> iou = {0.0, 0.0};
    if (!truth.is_ok()) return iou;
    for (int k = 0; k < 2; ++k) {
        if (k == 0 || fractional) setenv(samples_variable, k == 0 ? "1" : fractional, 1);
        std::unique_ptr<Package> package = test::bake(leaf, representation, values);
        unsetenv(samples_variable);
        EXPECT_TRUE(package);
        if (!package) return iou;
        auto standin = make_package_renderer(*package, {});
        EXPECT_TRUE(standin.is_ok()) << standin.status().message();
        if (!standin.is_ok()) return iou;
        iou[std::size_t(k)] = silhouette_iou(**truth, **standin, leaf);
    }
    return iou;
}

// The view atlas places a cut-out's edge inside its capture texels (issue #14): alpha-tested models
// are captured with 2 x 2 samples per texel, the texel's alpha is the covered fraction, and the
// corrected walk filters it bilinearly at the hit and keeps the hit where it reaches 1/2. With one
// sample per texel (STANDIN_ATLAS_COVERAGE_SAMPLES=1: binary coverage, as before) the disc's
// contour is quantised to texels. Coarse 64^2 captures make the texel ~5 pixels on screen.
TEST(AlphaViewAtlas, FractionalCoverageMovesTheCutOutEdgeInsideTexels)
{
    const std::array<double, 2> iou = disc_iou_binary_and_fractional(
        "view-atlas", "STANDIN_ATLAS_COVERAGE_SAMPLES", nullptr, {{"resolution", "64"}, {"subdivisions", "1"}, {"page-size", "512"}});
    std::printf("[alpha view atlas] disc IoU: binary coverage %.4f, fractional %.4f\n", iou[0], iou[1]);
    // measured on llvmpipe: binary 0.9654, fractional 0.9824 (docs/RESULTS.md "Fractional coverage
    // in the view atlas"); main's binary walk read every texel as covered or not, like iou[0]
    EXPECT_GE(iou[1], 0.97);
    EXPECT_GE(iou[1], iou[0] + 0.01);
}

// Microfacets place a cut-out's edge inside their capture texels the same way (issue #14) when
// baked with 2 x 2 capture samples per texel (STANDIN_MICROFACETS_COVERAGE_SAMPLES=2; the default
// stays 1, microfacets.h says why): the covered fraction as the texel's alpha, and a walk that keeps
// a crossing where the bilinearly filtered coverage of the hit's surface reaches 1/2. With one sample
// (binary coverage, the walk of before) the disc's contour runs along texel borders. 64^2 captures
// make the texel ~5 pixels on screen; 32^3 voxels.
TEST(AlphaMicrofacets, FractionalCoverageMovesTheCutOutEdgeInsideTexels)
{
    const std::array<double, 2> iou =
        disc_iou_binary_and_fractional("microfacets", "STANDIN_MICROFACETS_COVERAGE_SAMPLES", "2",
                                       {{"resolution", "64"}, {"subdivisions", "1"}, {"level", "5"}, {"page-size", "512"}});
    std::printf("[alpha microfacets] disc IoU: binary coverage %.4f, fractional %.4f\n", iou[0], iou[1]);
    // measured on llvmpipe: see docs/RESULTS.md "Fractional coverage in microfacets"
    EXPECT_GE(iou[1], 0.97);
    EXPECT_GE(iou[1], iou[0] + 0.01);
}

const Mesh& foliage_tree()
{
    static const Mesh tree = [] {
        GenerateOptions options;
        options.shape = GeneratedShape::tree;
        options.target_triangles = 2000;
        options.seed = 3;
        return *generate_mesh(options);
    }();
    return tree;
}

struct FoliageCase {
    const char* representation;
    double min_iou, max_luv, coverage_tolerance; // measured, with margin (RESULTS)
    double max_luv_far = 0.0;                    // Luv at distances 4 and 8; 0: not checked
};

class AlphaFoliage : public ::testing::TestWithParam<FoliageCase> {};

TEST_P(AlphaFoliage, StandInKeepsTheLeavesCutOutsAtEveryDistance)
{
    const FoliageCase& c = GetParam();
    test::gpu_context();
    std::unique_ptr<Package> package = test::bake(foliage_tree(), c.representation, {});
    ASSERT_TRUE(package);
    FoliageFigures f = foliage_figures(foliage_tree(), *package);
    std::printf("[foliage] %s: IoU %.4f, Luv %.3f, Luv d4 and d8 %.3f, coverage d4 %.3f, d8 %.3f\n", c.representation,
                f.iou, f.luv, f.luv_far, f.coverage4, f.coverage8);
    EXPECT_GE(f.iou, c.min_iou);
    EXPECT_LE(f.luv, c.max_luv);
    if (c.max_luv_far > 0.0) {
        EXPECT_LE(f.luv_far, c.max_luv_far);
    }
    EXPECT_NEAR(f.coverage4, 1.0, c.coverage_tolerance);
    EXPECT_NEAR(f.coverage8, 1.0, c.coverage_tolerance);
    if (std::string(c.representation) == "view-atlas") {
        // an alpha-tested package reads its colour from level 0 at every distance (--color-level
        // auto); the footprint's filtered level, the paper's way, stays far from the truth's leaves
        RenderOptions mips;
        mips.values.set("color-level", "mips");
        FoliageFigures filtered = foliage_figures(foliage_tree(), *package, mips);
        std::printf("[foliage] view-atlas --color-level mips: Luv %.3f, Luv d4 and d8 %.3f\n", filtered.luv, filtered.luv_far);
        EXPECT_LT(f.luv_far, filtered.luv_far - 2.0);
        EXPECT_LT(f.luv, filtered.luv - 0.5); // at 400 x 300 distance 1 is minified too
    }
}

// Measured on llvmpipe (this tree, these 12 views): billboards IoU 0.9974, Luv 2.893, coverage
// 1.002 / 1.003 since session 34 (cards split to 16 texels, not 8: the test 65 -> 43 s in CI's
// Release lane; docs/RESULTS.md "Billboards of foliage: leaf cards split less"); IoU 0.9974, Luv
// 2.899, coverage 1.001 / 1.001 since session 30 (partly hidden leaves captured where they are in front,
// --partly-hidden 0.5: docs/RESULTS.md "Partly hidden leaves"); IoU 0.9965, Luv 3.035, coverage
// 1.002 / 1.000 with their alpha-tested defaults since session 15 (1773 texels along the diagonal here,
// as fine as the leaf texture's, docs/RESULTS.md "Billboards on foliage: texels as fine as the leaf
// texture's"; 84 s here, most of it the bake); IoU 0.9935, Luv 3.63, coverage 1.004 / 1.007 with
// those of session 12 (1024 texels along the diagonal, grazing angle 30, a
// coarse mesh of the opaque faces only, alpha contour lines, and the march's level of detail hitting
// only where the ray crosses the contact texel's top; docs/RESULTS.md "Billboards on foliage: leaf
// outlines inside a texel"); IoU 0.991, Luv 3.88, coverage 1.019 / 1.024 before those two (its
// coverage fails the tolerance below); IoU 0.987, Luv 4.50 at grazing angle 10; IoU 0.962, Luv
// 8.31, coverage 0.990 / 1.013 at 512 with whole coarse cards, as before issue #14's session 11:
// both fail these thresholds (docs/RESULTS.md "Billboards on foliage: resolution and coarse mesh"); view atlas 0.972, 5.31, 0.996 / 0.993 with its alpha-tested default of 512² captures at
// one sample per texel (0.967, 6.55, 1.009 / 1.003 at 256² with 2 x 2 samples; 0.960, 6.40, 1.017 /
// 1.008 with binary coverage; Luv 13.1 and 8.09 before the truth's coverage-weighted mips and the
// coarse mesh's cut-out colours; its Luv threshold fails the 256² package). Luv is far over the 3:
// leaf edges a pixel off compare leaf against background (docs/RESULTS.md "Alpha-masked foliage").
// Microfacets (IoU 0.959, Luv 7.37, coverage 0.991 / 0.986) take 250 s here with their default
// 80 captures of 512^2, over ctest's limit on a loaded machine: measured by
// bench/foliage_results.sh instead. Displaced mesh (its leaf cards kept whole, with coverage, at
// its alpha-masked default of degree 33, cut-out samples coloured by their covered neighbours and
// colours averaged over each sample's cell): IoU 0.988, Luv 3.19, coverage 1.000 / 0.996 (38 s on
// the loaded 2-core machine; IoU 0.980, Luv 8.19 at degree 17 with point-sampled colours); since its
// leaf cards read the source's texture (source_textures.h): IoU 1.0000, Luv 0.459, Luv d4 and d8
// 1.426, coverage 1.000 / 1.000, and since closest points are exact (the branches' samples no
// longer take what lies behind them, reps/common/ray_scene.cpp): Luv 0.029, far 0.032.
INSTANTIATE_TEST_SUITE_P(Tree, AlphaFoliage,
                         ::testing::Values(FoliageCase{"enhanced-billboards", 0.99, 3.35, 0.015},
                                           FoliageCase{"view-atlas", 0.96, 4.8, 0.03, 7.5},
                                           FoliageCase{"displaced-mesh", 0.998, 0.3, 0.01, 0.3}),
                         [](const ::testing::TestParamInfo<FoliageCase>& info) {
                             std::string name = info.param.representation;
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

} // namespace
} // namespace standin
