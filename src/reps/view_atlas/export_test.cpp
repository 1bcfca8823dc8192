// The view atlas's grid-atlas export with a hand-built octahedral package (no GPU): by default one
// atlas texel per capture pixel (issue #16: resampled to fewer texels, leaves came out rounded off
// and the gaps between them filled in the web viewer), an explicit --atlas-size as given, and
// refusal of a size smaller than the frames; the hull node is the baked proxy moved out by a texel.
#include "reps/common/view_layout.h"
#include "reps/view_atlas/hull.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/export.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace standin::view_atlas {
namespace {

// frames x frames octahedral views of `resolution` pixels, each a covered square in the middle
ViewAtlasPackage octahedral_package(int frames, int resolution)
{
    ViewAtlasPackage p;
    p.source.file_name = "tiny.ply";
    p.source.bounds = {glm::vec3(-1.0f), glm::vec3(1.0f)};
    OptionValues values;
    values.set("layout", "octahedral");
    values.set("frames", std::to_string(frames));
    values.set("resolution", std::to_string(resolution));
    values.set("page-size", "256");
    values.set("compression", "none");
    values.set("depth-bits", "8"); // the 8-bit depth codes below
    p.parameters = *Options::parse(registration().bake_options, values, "test");
    p.settings = settings_from(p.parameters);
    p.center = glm::vec3(0.0f);
    p.radius = std::sqrt(3.0f);
    const std::vector<glm::vec3> directions = reps::layout_directions("octahedral", 0, frames);
    const int side = resolution / 2, per_row = 256 / side;
    p.color_pages.assign(1, ImageRGBA8(256, 256));
    p.normal_depth_pages.assign(1, ImageRGBA8(256, 256));
    for (std::size_t k = 0; k < directions.size(); ++k) {
        View v;
        v.direction = directions[k];
        const glm::vec3 up = std::abs(v.direction.y) > 0.999f ? glm::vec3(0, 0, v.direction.y > 0 ? -1 : 1) : glm::vec3(0, 1, 0);
        v.axis_u = glm::normalize(glm::cross(-v.direction, up));
        v.axis_v = glm::cross(v.axis_u, v.direction);
        v.crop_x = v.crop_y = resolution / 4;
        v.width = v.height = side;
        v.page = 0;
        v.atlas_x = int(k) % per_row * side;
        v.atlas_y = int(k) / per_row * side;
        for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
                std::uint8_t* c = p.color_pages[0].at(v.atlas_x + x, v.atlas_y + y);
                c[0] = c[1] = c[2] = 200, c[3] = 255;
                std::uint8_t* n = p.normal_depth_pages[0].at(v.atlas_x + x, v.atlas_y + y);
                n[0] = 128, n[1] = 128, n[2] = 255, n[3] = 100;
            }
        p.views.push_back(v);
    }
    return p;
}

Result<ExportScene> export_with(const ViewAtlasPackage& package, const OptionValues& values)
{
    Result<Options> options = Options::parse(export_options(), values, "test");
    if (!options) return options.status();
    return export_scene(package, *options);
}

TEST(ViewAtlasExport, DefaultAtlasHasOneTexelPerCapturePixel)
{
    ViewAtlasPackage package = octahedral_package(2, 32);
    Result<ExportScene> scene = export_with(package, {});
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_FALSE(scene->meshes.empty());
    EXPECT_EQ(scene->meshes[0].extras["standin"]["atlas_size"], 64);
    EXPECT_EQ(scene->meshes[0].extras["standin"]["capture_resolution"], 32);
    ASSERT_FALSE(scene->textures.empty());
    EXPECT_EQ(scene->textures[0].width, 64);
    EXPECT_EQ(scene->textures[0].height, 64);

    OptionValues given;
    given.set("atlas-size", "48");
    Result<ExportScene> smaller = export_with(package, given);
    ASSERT_TRUE(smaller) << smaller.status().message();
    EXPECT_EQ(smaller->meshes[0].extras["standin"]["atlas_size"], 48);
    EXPECT_EQ(smaller->textures[0].width, 48);

    OptionValues tiny;
    tiny.set("atlas-size", "1");
    EXPECT_FALSE(export_with(package, tiny));
}

// The hull an engine draws the impostor on is the baked proxy (issue #17), each plane moved out by a
// texel of the exported atlas, not the captured views' atlas hull (issue #16), which cuts what no
// texel centre of some view saw (a sheet seen edge on). Packages without proxy planes keep the
// atlas hull. Here every view saw only a centred square, yet the proxy says the model reaches 0.8
// along every axis: the hull must reach there (and one texel further), not stop at the squares.
TEST(ViewAtlasExport, HullIsTheBakedProxyMovedOutByATexel)
{
    ViewAtlasPackage package = octahedral_package(4, 32);
    auto reach = [](const ExportMesh& mesh) {
        float r = 0.0f;
        for (const glm::vec3& p : mesh.positions) r = std::max({r, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
        return r;
    };
    Result<ExportScene> before = export_with(package, {});
    ASSERT_TRUE(before) << before.status().message();
    ASSERT_EQ(before->meshes.size(), 2u);
    const float atlas_hull_reach = reach(before->meshes[1]);

    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {1.0f, -1.0f}) {
            glm::vec4 plane(0.0f, 0.0f, 0.0f, 0.8f);
            plane[axis] = sign;
            package.proxy_planes.push_back(plane);
        }
    const float texel = float(capture_texel(package));
    Result<ExportScene> scene = export_with(package, {});
    ASSERT_TRUE(scene) << scene.status().message();
    ASSERT_EQ(scene->meshes.size(), 2u);
    EXPECT_EQ(scene->meshes[1].extras["standin"]["role"], "grid-impostor-hull");
    EXPECT_NEAR(reach(scene->meshes[1]), 0.8f + texel, 1e-4f);
    EXPECT_LT(atlas_hull_reach, 0.8f); // the squares the views saw: the old hull would cut the model

    // an atlas coarser than the captures: a texel of the atlas (twice the capture's)
    OptionValues coarser;
    coarser.set("atlas-size", "64");
    Result<ExportScene> coarse = export_with(package, coarser);
    ASSERT_TRUE(coarse) << coarse.status().message();
    EXPECT_NEAR(reach(coarse->meshes[1]), 0.8f + 2.0f * texel, 1e-4f);
}

} // namespace
} // namespace standin::view_atlas
