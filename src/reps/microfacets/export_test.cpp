// The exported voxel surface (export.h exposed_faces) on hand-made octrees with known face counts:
// a lone voxel, a solid block, a hollow shell whose cavity faces are culled, a shell with a hole
// (the cavity is then outside and its faces kept), and two voxels touching along an edge only.
// A hand-made package of a leaf thinner than a voxel, seen by captures from six sides: the export
// cuts the voxel's faces to what the captures saw (half the top and bottom faces, none of the
// sides). The export of a baked package (closed mesh, bounds, colours) is tests/export_gpu_test.cpp.
#include "reps/microfacets/export.h"
#include "reps/microfacets/microfacets.h"
#include "reps/common/surface_image.h"
#include "test_support.h"

#include <standin/files.h>

#include <gtest/gtest.h>

#include <algorithm>

namespace standin::microfacets {
namespace {

Octree export_octree_of(std::vector<glm::uvec3> cells, int level)
{
    Octree tree;
    tree.grid.origin = glm::vec3(0.0f);
    tree.grid.size = 1.0f;
    tree.min_level = tree.max_level = level;
    std::vector<std::uint32_t> codes;
    for (glm::uvec3 c : cells) codes.push_back(morton_encode(c));
    std::sort(codes.begin(), codes.end());
    tree.levels = {codes};
    return tree;
}

std::vector<glm::uvec3> export_block(glm::uvec3 lo, glm::uvec3 hi, bool hollow)
{
    std::vector<glm::uvec3> cells;
    for (unsigned z = lo.z; z <= hi.z; ++z)
        for (unsigned y = lo.y; y <= hi.y; ++y)
            for (unsigned x = lo.x; x <= hi.x; ++x) {
                bool surface = x == lo.x || x == hi.x || y == lo.y || y == hi.y || z == lo.z || z == hi.z;
                if (!hollow || surface) cells.push_back({x, y, z});
            }
    return cells;
}

TEST(MicrofacetsExport, LoneVoxelShowsSixFaces)
{
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 2, 3}}, 3), 3).size(), 6u);
    // at the grid's border too: outside the grid is outside
    EXPECT_EQ(exposed_faces(export_octree_of({{0, 0, 0}}, 2), 2).size(), 6u);
}

TEST(MicrofacetsExport, SolidBlockShowsOnlyItsOuterFaces)
{
    // a 3 x 4 x 5 block: 2 (3*4 + 4*5 + 3*5) faces, none between two voxels
    EXPECT_EQ(exposed_faces(export_octree_of(export_block({1, 1, 1}, {3, 4, 5}, false), 3), 3).size(), 2u * (12 + 20 + 15));
    // filling the grid: the faces on the grid's border
    EXPECT_EQ(exposed_faces(export_octree_of(export_block({0, 0, 0}, {3, 3, 3}, false), 2), 2).size(), 6u * 16);
}

TEST(MicrofacetsExport, EnclosedCavitiesAreCulled)
{
    // a hollow 5^3 shell (a voxelised closed surface): only its outside, as if solid
    auto shell = export_block({1, 1, 1}, {5, 5, 5}, true);
    EXPECT_EQ(exposed_faces(export_octree_of(shell, 3), 3).size(), 6u * 25);
    // a hole through one wall lets the outside in: the hole's 4 walls and the 3^3 cavity's
    // faces show (54 less the removed voxel's), the removed voxel's outer face is gone
    shell.erase(std::find(shell.begin(), shell.end(), glm::uvec3(3, 3, 1)));
    EXPECT_EQ(exposed_faces(export_octree_of(shell, 3), 3).size(), 6u * 25 - 1 + 4 + 53);
}

TEST(MicrofacetsExport, VoxelsTouchingAlongAnEdgeKeepAllFaces)
{
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 1, 1}, {2, 2, 1}}, 2), 2).size(), 12u);
    EXPECT_EQ(exposed_faces(export_octree_of({{1, 1, 1}, {2, 1, 1}}, 2), 2).size(), 10u);
}

// One voxel (2, 2, 4) of an 8^3 grid over the unit cube holding a horizontal leaf at z = 9/16 (the
// voxel's middle) over x in [1/4, 5/16) (the voxel's lower half in x), y in [1/4, 3/8) (all of
// it). Captured orthographically from +-z (seen flat) and +-x, +-y (edge-on: nothing covered) at
// 8 capture texels per voxel, one view per page.
MicrofacetsPackage export_leaf_package()
{
    MicrofacetsPackage package;
    package.settings.level = package.settings.min_level = 3;
    package.settings.resolution = 64;
    package.octree.grid.origin = glm::vec3(0.0f);
    package.octree.grid.size = 1.0f;
    package.octree.min_level = package.octree.max_level = 3;
    package.octree.levels = {{morton_encode({2, 2, 4})}};
    package.center = glm::vec3(0.5f);
    package.radius = 0.5f;
    const int res = package.settings.resolution;
    const float r = package.radius, texel = 2.0f * r / float(res), leaf_z = 9.0f / 16.0f;
    const glm::vec3 directions[6] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (int k = 0; k < 6; ++k) {
        View view;
        view.direction = directions[k];
        view.axis_u = std::abs(view.direction.x) > 0.5f ? glm::vec3(0, 0, 1) : glm::vec3(1, 0, 0);
        view.axis_v = glm::cross(view.direction, view.axis_u);
        view.width = view.height = res;
        view.page = k;
        ImageRGBA8 color(res, res);
        ImageRGBA16 normal_depth(res, res);
        if (std::abs(view.direction.z) > 0.5f)
            for (int y = 0; y < res; ++y)
                for (int x = 0; x < res; ++x) {
                    glm::vec3 p = package.center + (-r + (float(x) + 0.5f) * texel) * view.axis_u + (-r + (float(y) + 0.5f) * texel) * view.axis_v;
                    if (p.x < 0.25f || p.x >= 0.3125f || p.y < 0.25f || p.y >= 0.375f) continue;
                    std::uint8_t* c = color.at(x, y);
                    c[0] = 200, c[1] = 150, c[2] = 100, c[3] = 255;
                    std::uint16_t* nd = normal_depth.at(x, y);
                    nd[0] = nd[1] = reps::encode_normal(0.0f);
                    nd[2] = reps::encode_normal(view.direction.z);
                    const float height = (leaf_z - package.center.z) * view.direction.z;
                    nd[3] = reps::encode_depth((r - height) / (2.0f * r));
                }
        package.views.push_back(view);
        package.color_pages.push_back(std::move(color));
        package.normal_depth_pages.push_back(std::move(normal_depth));
    }
    return package;
}

TEST(MicrofacetsExport, FacesKeepTheCutOutsTheCapturesSaw)
{
    const MicrofacetsPackage package = export_leaf_package();
    OptionValues given;
    given.set("planes", "false");
    given.set("snap", "false");
    const std::vector<OptionSpec> specs = export_options();
    Result<Options> options = Options::parse(specs, given, "microfacets export");
    ASSERT_TRUE(options) << options.status().message();
    Result<ExportScene> scene = export_scene(package, *options);
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(scene->meshes.size(), 1u);
    const ExportMesh& mesh = scene->meshes[0];
    // the old export drew the voxel's six faces opaque: a whole voxel where the leaf fills a half
    ASSERT_EQ(mesh.positions.size(), 24u);
    EXPECT_EQ(mesh.alpha_mode, "MASK");
    EXPECT_TRUE(mesh.double_sided);
    ASSERT_EQ(mesh.base_color_texture, 0);
    ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
    const std::string png = test::fresh_directory("microfacets_export_leaf") + "/coverage.png";
    ASSERT_TRUE(write_file_atomic(png, scene->textures[0].png));
    Result<ImageRGBA8> atlas = read_png_rgba8(png);
    ASSERT_TRUE(atlas);
    // each face's coverage where the texel at (s, t) of the face's quad lies, as a viewer samples it
    auto covered = [&](std::size_t face, float s, float t) {
        const glm::vec2* uv = &mesh.uvs[face * 4];
        glm::vec2 at = uv[0] + s * (uv[1] - uv[0]) + t * (uv[3] - uv[0]);
        return atlas->at(int(at.x * float(atlas->width)), int(at.y * float(atlas->height)))[3] >= 128;
    };
    for (std::size_t face = 0; face < 6; ++face) {
        // corners in the exported order: which lattice axis is x, so where the leaf's half lies
        const glm::vec3* p = &mesh.positions[face * 4];
        const glm::vec3 normal = glm::normalize(glm::cross(p[1] - p[0], p[3] - p[0]));
        const bool horizontal = std::abs(normal.z) > 0.5f;
        for (float s : {0.125f, 0.375f, 0.625f, 0.875f})
            for (float t : {0.125f, 0.375f, 0.625f, 0.875f}) {
                const float x = (p[0] + s * (p[1] - p[0]) + t * (p[3] - p[0])).x;
                EXPECT_EQ(covered(face, s, t), horizontal && x < 0.3125f) << "face " << face << " at " << s << ", " << t;
            }
    }
}

TEST(MicrofacetsExport, PlanesLieOnTheLeafAndKeepItsHalf)
{
    const MicrofacetsPackage package = export_leaf_package();
    OptionValues given;
    given.set("cutout", "4"); // planes are the default
    const std::vector<OptionSpec> specs = export_options();
    Result<Options> options = Options::parse(specs, given, "microfacets export");
    ASSERT_TRUE(options) << options.status().message();
    Result<ExportScene> scene = export_scene(package, *options);
    ASSERT_TRUE(scene) << scene.status().message();
    const ExportMesh& mesh = scene->meshes[0];
    // one square, in the leaf's plane
    ASSERT_EQ(mesh.positions.size(), 4u);
    EXPECT_EQ(mesh.alpha_mode, "MASK");
    for (const glm::vec3& p : mesh.positions) EXPECT_NEAR(p.z, 9.0f / 16.0f, 1e-3f);
    const std::string png = test::fresh_directory("microfacets_export_plane") + "/coverage.png";
    ASSERT_TRUE(write_file_atomic(png, scene->textures[0].png));
    Result<ImageRGBA8> atlas = read_png_rgba8(png);
    ASSERT_TRUE(atlas);
    // covered over the leaf (x in [1/4, 5/16), y in the voxel), empty beside it: at the texel
    // centres more than a capture texel (1/64) from the leaf's edges
    int inside = 0, outside = 0;
    const float margin = 1.0f / 64.0f;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const float s = (float(i) + 0.5f) / 4.0f, t = (float(j) + 0.5f) / 4.0f;
            const glm::vec3 p = mesh.positions[0] + s * (mesh.positions[1] - mesh.positions[0]) + t * (mesh.positions[3] - mesh.positions[0]);
            const glm::vec2 uv = mesh.uvs[0] + s * (mesh.uvs[1] - mesh.uvs[0]) + t * (mesh.uvs[3] - mesh.uvs[0]);
            const bool covered = atlas->at(int(uv.x * float(atlas->width)), int(uv.y * float(atlas->height)))[3] >= 128;
            if (p.x > 0.25f + margin && p.x < 0.3125f - margin && p.y > 0.25f + margin && p.y < 0.375f - margin) {
                EXPECT_TRUE(covered) << p.x << ", " << p.y;
                ++inside;
            } else if (p.x > 0.3125f + margin || p.x < 0.25f - margin || p.y > 0.375f + margin || p.y < 0.25f - margin) {
                EXPECT_FALSE(covered) << p.x << ", " << p.y;
                ++outside;
            }
        }
    EXPECT_GT(inside, 0);
    EXPECT_GT(outside, 0);
}

// The leaf captured with a PBR material: an ORM and an emission page per view, the material's values
// wherever the colour is covered (as the bake writes them: zero elsewhere).
constexpr std::uint8_t k_leaf_orm[3] = {200, 60, 230}, k_leaf_emission[3] = {128, 0, 64};

MicrofacetsPackage export_pbr_leaf_package()
{
    MicrofacetsPackage package = export_leaf_package();
    for (const ImageRGBA8& color : package.color_pages) {
        ImageRGBA8 orm(color.width, color.height), emission(color.width, color.height);
        for (int y = 0; y < color.height; ++y)
            for (int x = 0; x < color.width; ++x) {
                if (color.at(x, y)[3] == 0) continue;
                std::uint8_t *o = orm.at(x, y), *e = emission.at(x, y);
                for (int c = 0; c < 3; ++c) o[c] = k_leaf_orm[c], e[c] = k_leaf_emission[c];
                o[3] = e[3] = 255;
            }
        package.orm_pages.push_back(std::move(orm));
        package.emission_pages.push_back(std::move(emission));
    }
    return package;
}

// A texture of the scene decoded, and its texel under a face's UV quad at (s, t).
ImageRGBA8 decoded(const ExportScene& scene, int texture, const std::string& name)
{
    const std::string png = test::fresh_directory("microfacets_export_pbr") + "/" + name + ".png";
    EXPECT_TRUE(write_file_atomic(png, scene.textures[std::size_t(texture)].png));
    Result<ImageRGBA8> image = read_png_rgba8(png);
    EXPECT_TRUE(image);
    return image ? *image : ImageRGBA8();
}

const std::uint8_t* texel_under(const ImageRGBA8& image, const ExportMesh& mesh, std::size_t quad, float s, float t)
{
    const glm::vec2* uv = &mesh.uvs[quad * 4];
    const glm::vec2 at = uv[0] + s * (uv[1] - uv[0]) + t * (uv[3] - uv[0]);
    return image.at(int(at.x * float(image.width)), int(at.y * float(image.height)));
}

// Issue #14: a PBR package's export carries its material (glTF metallicRoughnessTexture,
// occlusionTexture, emissiveTexture), for the planes and for the voxel faces, cut out or opaque.
TEST(MicrofacetsExport, PbrPackagesExportTheirMaterialPerPlaneAndFace)
{
    const MicrofacetsPackage package = export_pbr_leaf_package();
    const std::vector<OptionSpec> specs = export_options();
    struct Case {
        const char* planes;
        const char* cutout;
        bool cut;
    };
    for (const Case& c : {Case{"true", "4", true}, Case{"false", "4", true}, Case{"false", "0", false}}) {
        SCOPED_TRACE(std::string("planes ") + c.planes + ", cutout " + c.cutout);
        OptionValues given;
        given.set("planes", c.planes);
        given.set("cutout", c.cutout);
        given.set("snap", "false");
        Result<Options> options = Options::parse(specs, given, "microfacets export");
        ASSERT_TRUE(options) << options.status().message();
        Result<ExportScene> scene = export_scene(package, *options);
        ASSERT_TRUE(scene) << scene.status().message();
        const ExportMesh& mesh = scene->meshes[0];
        EXPECT_EQ(mesh.alpha_mode, c.cut ? "MASK" : "OPAQUE");
        EXPECT_EQ(mesh.base_color_texture, c.cut ? 0 : -1);
        ASSERT_GE(mesh.orm_texture, 0);
        ASSERT_EQ(mesh.emissive_texture, mesh.orm_texture + 1);
        ASSERT_EQ(int(scene->textures.size()), mesh.emissive_texture + 1);
        EXPECT_EQ(mesh.metallic, 1.0f); // the maps are read as they are
        EXPECT_EQ(mesh.roughness, 1.0f);
        EXPECT_EQ(mesh.emissive, glm::vec3(1.0f));
        ASSERT_EQ(mesh.uvs.size(), mesh.positions.size());
        const ImageRGBA8 orm = decoded(*scene, mesh.orm_texture, "orm");
        const ImageRGBA8 emission = decoded(*scene, mesh.emissive_texture, "emission");
        // every quad (the plane; the six faces, the edge-on ones taking their voxel's seen faces')
        for (std::size_t quad = 0; quad < mesh.positions.size() / 4; ++quad)
            for (float s : {0.1f, 0.5f, 0.9f})
                for (float t : {0.1f, 0.5f, 0.9f})
                    for (int k = 0; k < 3; ++k) {
                        EXPECT_EQ(texel_under(orm, mesh, quad, s, t)[k], k_leaf_orm[k]) << "quad " << quad << " channel " << k;
                        EXPECT_NEAR(texel_under(emission, mesh, quad, s, t)[k], k_leaf_emission[k], 1) << "quad " << quad;
                    }
    }

    // without PBR pages: no maps, the default material
    OptionValues given;
    Result<Options> options = Options::parse(specs, given, "microfacets export");
    ASSERT_TRUE(options);
    Result<ExportScene> plain = export_scene(export_leaf_package(), *options);
    ASSERT_TRUE(plain) << plain.status().message();
    EXPECT_EQ(plain->meshes[0].orm_texture, -1);
    EXPECT_EQ(plain->meshes[0].emissive_texture, -1);
    EXPECT_EQ(plain->textures.size(), 1u);
}

} // namespace
} // namespace standin::microfacets
