// Alpha (issue #14) on the CPU: the alpha test of Mesh::covered_at against analytic areas (a disc
// cut out of a quad, its cutoff moving the edge), import of glTF alphaMode / alphaCutoff /
// doubleSided from a file written here by write_gltf, OBJ map_d and d, and the generated tree.
#include <standin/image.h>
#include <standin/mesh.h>

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <unistd.h>

namespace standin {
namespace {

namespace fs = std::filesystem;

std::string alpha_test_dir(const std::string& name)
{
    fs::path dir = fs::path(::testing::TempDir()) / ("standin_alpha_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

// The fraction of a fine grid of points of the quad that pass the alpha test.
double covered_fraction(const Mesh& quad)
{
    const int n = 400;
    std::size_t covered = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            float u = (i + 0.5f) / n, v = (j + 0.5f) / n;
            // triangle 0 is corners 0, 1, 2: (u, v) = (b1 + b2, b2); triangle 1 corners 0, 2, 3:
            // (u, v) = (b1, b1 + b2)
            if (u >= v)
                covered += quad.covered_at(0, u - v, v);
            else
                covered += quad.covered_at(1, u, v - u);
        }
    return double(covered) / double(n * n);
}

TEST(Alpha, MaskCutoffCutsADiscOfTheAnalyticArea)
{
    for (float cutoff : {0.25f, 0.5f, 0.75f}) {
        double expected = std::numbers::pi * (1.0 - cutoff) * (1.0 - cutoff) / 4.0;
        EXPECT_NEAR(covered_fraction(test::alpha_quad(AlphaMode::mask, cutoff, true)), expected, 0.01) << "cutoff " << cutoff;
    }
    EXPECT_DOUBLE_EQ(covered_fraction(test::alpha_quad(AlphaMode::opaque, 0.5f, true)), 1.0);
    // blend is drawn as mask at 0.5, whatever the cutoff field holds
    EXPECT_NEAR(covered_fraction(test::alpha_quad(AlphaMode::blend, 0.9f, true)), std::numbers::pi / 16.0, 0.01);
    EXPECT_FALSE(test::alpha_quad(AlphaMode::opaque, 0.5f, true).has_alpha_test());
    EXPECT_TRUE(test::alpha_quad(AlphaMode::mask, 0.5f, true).has_alpha_test());
    EXPECT_TRUE(test::alpha_quad(AlphaMode::opaque, 0.5f, false).has_alpha_test());
}

TEST(Alpha, GltfRoundTripKeepsAlphaModeCutoffDoubleSidedAndTheTexture)
{
    std::string dir = alpha_test_dir("gltf");
    for (AlphaMode mode : {AlphaMode::opaque, AlphaMode::mask, AlphaMode::blend})
        for (bool double_sided : {false, true}) {
            Mesh quad = test::alpha_quad(mode, 0.3f, double_sided);
            std::string path = dir + "/quad.gltf";
            ASSERT_TRUE(write_gltf(quad, path).is_ok());
            ImportReport report;
            Result<Mesh> imported = import_mesh(path, &report);
            ASSERT_TRUE(imported.is_ok()) << imported.status().message();
            ASSERT_EQ(imported->materials.size(), 1u);
            const Material& m = imported->materials[0];
            EXPECT_EQ(m.alpha_mode, mode);
            EXPECT_EQ(m.double_sided, double_sided);
            if (mode == AlphaMode::mask) {
                EXPECT_NEAR(m.alpha_cutoff, 0.3f, 1e-6f);
            }
            bool warned = std::any_of(report.warnings.begin(), report.warnings.end(),
                                      [](const std::string& w) { return w.find("blends") != std::string::npos; });
            EXPECT_EQ(warned, mode == AlphaMode::blend);
            // the same texture at the same UVs: albedo and coverage agree point by point
            ASSERT_EQ(imported->triangle_count(), 2u);
            EXPECT_EQ(imported->textures.at(0).rgba, quad.textures[0].rgba);
            EXPECT_NEAR(covered_fraction(*imported), covered_fraction(quad), 1e-3);
        }
}

TEST(Alpha, ObjOpacityMapIsAMaskAndOpacityBelowOneBlends)
{
    std::string dir = alpha_test_dir("obj");
    // map_d: a grey PNG without alpha (the red channel is the opacity): a disc of radius 0.5
    ImageRGBA8 opacity(64, 64);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            double dx = (x + 0.5) / 64 - 0.5, dy = (y + 0.5) / 64 - 0.5;
            std::uint8_t g = dx * dx + dy * dy < 0.25 ? 255 : 0;
            std::uint8_t* p = opacity.at(x, y);
            p[0] = p[1] = p[2] = g, p[3] = 255;
        }
    ASSERT_TRUE(write_png(opacity, dir + "/leaf_alpha.png").is_ok());
    std::ofstream(dir + "/leaf.mtl") << "newmtl leaf\nKd 0.2 0.6 0.1\nmap_d leaf_alpha.png\n\nnewmtl glass\nKd 0.5 0.5 0.9\nd 0.4\n";
    std::ofstream(dir + "/leaf.obj") << "mtllib leaf.mtl\n"
                                        "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                        "v -0.5 -0.5 1\nv 0.5 -0.5 1\nv 0.5 0.5 1\n"
                                        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                                        "usemtl leaf\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"
                                        "usemtl glass\nf 5/1 6/2 7/3\n";
    ImportReport report;
    Result<Mesh> mesh = import_mesh(dir + "/leaf.obj", &report);
    ASSERT_TRUE(mesh.is_ok()) << mesh.status().message();
    const Material* leaf = nullptr;
    const Material* glass = nullptr;
    for (const Material& m : mesh->materials) (m.name == "leaf" ? leaf : glass) = &m;
    ASSERT_TRUE(leaf && glass);
    EXPECT_EQ(leaf->alpha_mode, AlphaMode::mask);
    EXPECT_EQ(glass->alpha_mode, AlphaMode::blend);
    EXPECT_TRUE(leaf->double_sided); // OBJ has no notion of it: both sides, as always
    ASSERT_GE(leaf->base_color_texture, 0);
    // the merged texture: white colour (there was no map_Kd), the disc in alpha
    std::size_t covered = 0, leaf_triangles = 0;
    for (std::size_t t = 0; t < mesh->triangle_count(); ++t) {
        if (&mesh->materials[mesh->face_materials[t]] != leaf) continue;
        ++leaf_triangles;
        for (int j = 0; j < 40; ++j)
            for (int i = 0; i + j < 40; ++i) covered += mesh->covered_at(t, (i + 0.33f) / 40.0f, (j + 0.33f) / 40.0f);
    }
    ASSERT_EQ(leaf_triangles, 2u);
    EXPECT_NEAR(double(covered) / (2.0 * 820.0), std::numbers::pi / 4.0, 0.03);
    bool warned = std::any_of(report.warnings.begin(), report.warnings.end(),
                              [](const std::string& w) { return w.find("'glass' blends") != std::string::npos; });
    EXPECT_TRUE(warned);
}

// A model whose every face its opacity cuts out would draw nothing (exporters writing opacity
// inverted): it is drawn opaque, with one warning; one visible face and the file is read as written.
TEST(Alpha, AModelThatWouldDrawNothingIsDrawnOpaque)
{
    std::string dir = alpha_test_dir("invisible");
    std::ofstream(dir + "/inverted.mtl") << "newmtl wall\nKd 0.7 0.2 0.2\nd 0\n\nnewmtl window\nKd 0.5 0.5 0.9\nd 0.3\n";
    const std::string geometry = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\n"
                                 "usemtl wall\nf 1 2 3\nf 1 3 4\nusemtl window\nf 5 6 7\n";
    std::ofstream(dir + "/inverted.obj") << "mtllib inverted.mtl\n" << geometry;
    ImportReport report;
    Result<Mesh> mesh = import_mesh(dir + "/inverted.obj", &report);
    ASSERT_TRUE(mesh.is_ok()) << mesh.status().message();
    for (const Material& m : mesh->materials) EXPECT_EQ(m.alpha_mode, AlphaMode::opaque) << m.name;
    for (std::size_t t = 0; t < mesh->triangle_count(); ++t) EXPECT_TRUE(mesh->covered_at(t, 0.3f, 0.3f));
    EXPECT_EQ(std::count_if(report.warnings.begin(), report.warnings.end(),
                            [](const std::string& w) { return w.find("would draw nothing; drawn opaque") != std::string::npos; }),
              1);
    EXPECT_TRUE(std::none_of(report.warnings.begin(), report.warnings.end(),
                             [](const std::string& w) { return w.find("blends") != std::string::npos; }));

    // the same with one visible material: read as written
    std::ofstream(dir + "/visible.mtl") << "newmtl wall\nKd 0.7 0.2 0.2\n\nnewmtl window\nKd 0.5 0.5 0.9\nd 0.3\n";
    std::ofstream(dir + "/visible.obj") << "mtllib visible.mtl\n" << geometry;
    ImportReport kept;
    Result<Mesh> visible = import_mesh(dir + "/visible.obj", &kept);
    ASSERT_TRUE(visible.is_ok()) << visible.status().message();
    std::size_t covered = 0;
    for (std::size_t t = 0; t < visible->triangle_count(); ++t) covered += visible->covered_at(t, 0.3f, 0.3f);
    EXPECT_EQ(covered, 2u); // the wall's two triangles, not the window
    EXPECT_TRUE(std::none_of(kept.warnings.begin(), kept.warnings.end(),
                             [](const std::string& w) { return w.find("would draw nothing") != std::string::npos; }));
}

TEST(Alpha, GeneratedTreeIsDeterministicWithAMaskedDoubleSidedLeafMaterial)
{
    GenerateOptions options;
    options.shape = GeneratedShape::tree;
    options.target_triangles = 3000;
    options.seed = 7;
    Result<Mesh> a = generate_mesh(options);
    Result<Mesh> b = generate_mesh(options);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    EXPECT_TRUE(validate_mesh(*a, "tree").is_ok());
    EXPECT_EQ(a->positions, b->positions);
    EXPECT_EQ(a->textures.at(0).rgba, b->textures.at(0).rgba);
    EXPECT_NEAR(double(a->triangle_count()), 3000.0, 300.0);
    ASSERT_EQ(a->materials.size(), 2u);
    EXPECT_EQ(a->materials[0].alpha_mode, AlphaMode::opaque);
    EXPECT_EQ(a->materials[1].alpha_mode, AlphaMode::mask);
    EXPECT_TRUE(a->materials[1].double_sided);
    // the leaf texture is a cut-out: a good part of the card, not all of it
    const Texture& leaf = a->textures[0];
    std::size_t opaque = 0;
    for (std::size_t i = 3; i < leaf.rgba.size(); i += 4) opaque += leaf.rgba[i] >= 128;
    double fraction = double(opaque) / double(leaf.width * leaf.height);
    EXPECT_GT(fraction, 0.15);
    EXPECT_LT(fraction, 0.6);
    BoundingSphere sphere = a->bounding_sphere();
    EXPECT_NEAR(sphere.radius, 1.0f, 1e-4f);
    options.seed = 8;
    EXPECT_NE(generate_mesh(options)->positions, a->positions);

    // written as glTF and read back: the same model
    std::string path = alpha_test_dir("tree") + "/tree.gltf";
    ASSERT_TRUE(write_gltf(*a, path).is_ok());
    Result<Mesh> imported = import_mesh(path);
    ASSERT_TRUE(imported.is_ok()) << imported.status().message();
    EXPECT_EQ(imported->triangle_count(), a->triangle_count());
    std::size_t masked = 0;
    for (const Material& m : imported->materials) masked += m.alpha_mode == AlphaMode::mask && m.double_sided;
    EXPECT_EQ(masked, 1u);
    // base colours written as glTF's linear factors and encoded back on import (bark and leaves)
    for (const Material& m : imported->materials) {
        auto same = std::find_if(a->materials.begin(), a->materials.end(), [&](const Material& o) { return o.name == m.name; });
        ASSERT_NE(same, a->materials.end()) << m.name;
        for (int c = 0; c < 4; ++c) EXPECT_NEAR(m.base_color[c], same->base_color[c], 1e-5f) << m.name << " channel " << c;
    }
    EXPECT_LT(glm::length(glm::vec3(imported->colors[imported->indices[0]]) - glm::vec3(a->colors[a->indices[0]])), 1e-4f);
    // vertex colours other than the material's cannot be written without vertex colours
    Mesh shrub = *generate_mesh({GeneratedShape::shrub, 400});
    EXPECT_EQ(write_gltf(shrub, path + "2.gltf").code(), StatusCode::invalid_argument);
}

TEST(Alpha, GeneratedBushHasCrossedCardsOfManyLeaves)
{
    GenerateOptions options;
    options.shape = GeneratedShape::bush;
    options.target_triangles = 2000;
    options.seed = 3;
    Result<Mesh> a = generate_mesh(options);
    Result<Mesh> b = generate_mesh(options);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    EXPECT_TRUE(validate_mesh(*a, "bush").is_ok());
    EXPECT_EQ(a->positions, b->positions);
    EXPECT_NEAR(double(a->triangle_count()), 2000.0, 200.0);
    ASSERT_EQ(a->materials.size(), 2u);
    EXPECT_EQ(a->materials[1].alpha_mode, AlphaMode::mask);
    EXPECT_TRUE(a->materials[1].double_sided);
    EXPECT_NEAR(a->bounding_sphere().radius, 1.0f, 1e-4f);
    // the cards come in crossed pairs: the second card's quad turned a right angle about the
    // shared stem (its first vertex's edge), so the two planes cut each other along it
    std::size_t first_leaf = 0;
    while (a->face_materials[first_leaf] != 1u) ++first_leaf;
    const std::size_t leaf_faces = a->triangle_count() - first_leaf;
    ASSERT_EQ(leaf_faces % 4, 0u);
    for (std::size_t f = first_leaf; f < a->triangle_count(); f += 4) {
        glm::vec3 n0 = a->normals[a->indices[f * 3]], n1 = a->normals[a->indices[(f + 2) * 3]];
        EXPECT_NEAR(glm::dot(n0, n1), 0.0f, 1e-4f);
        // both quads' stems (u = 0.5) run through the same points
        glm::vec3 foot0 = 0.5f * (a->positions[a->indices[f * 3]] + a->positions[a->indices[f * 3 + 1]]);
        glm::vec3 foot1 = 0.5f * (a->positions[a->indices[(f + 2) * 3]] + a->positions[a->indices[(f + 2) * 3 + 1]]);
        EXPECT_LT(glm::length(foot0 - foot1), 1e-4f);
    }
    // the texture is a sprig of many separate leaves: opaque texels a minority, in many runs along
    // a row across the middle (leaf, gap, leaf, ...)
    const Texture& sprig = a->textures.at(0);
    std::size_t opaque = 0;
    for (std::size_t i = 3; i < sprig.rgba.size(); i += 4) opaque += sprig.rgba[i] >= 128;
    double fraction = double(opaque) / double(sprig.width * sprig.height);
    EXPECT_GT(fraction, 0.1);
    EXPECT_LT(fraction, 0.5);
    int runs = 0;
    for (int row = sprig.height / 4; row < 3 * sprig.height / 4; row += sprig.height / 16) {
        bool previous = false;
        for (int x = 0; x < sprig.width; ++x) {
            bool on = sprig.rgba[(std::size_t(row) * sprig.width + std::size_t(x)) * 4 + 3] >= 128;
            runs += on && !previous;
            previous = on;
        }
    }
    EXPECT_GE(runs, 16); // 8 rows, at least two leaves' or a leaf's and the stem's runs each
    options.seed = 4;
    EXPECT_NE(generate_mesh(options)->positions, a->positions);
}

} // namespace
} // namespace standin
