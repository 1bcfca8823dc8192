// View atlases baked on the GPU from small generated meshes and drawn against the ground truth:
// the seed style reproduces a captured view, the corrected style beats it away from the captured
// views, bakes are byte-identical, styles a package cannot serve are refused, and pages split over
// several texture arrays (a forced small budget) draw exactly as one array.
#include "test_support.h"

#include "reps/view_atlas/shaders/atlas_layout.glsl"
#include "reps/view_atlas/view_atlas.h"

#include <standin/eval.h>
#include <standin/files.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

namespace standin::view_atlas {
namespace {

Mesh torus()
{
    GenerateOptions options;
    options.shape = GeneratedShape::torus;
    options.target_triangles = 2000;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

std::unique_ptr<Package> bake_atlas(const Mesh& mesh, const std::vector<std::pair<std::string, std::string>>& values)
{
    test::gpu_context();
    SourceInfo source;
    source.bounds = mesh.bounds();
    BakeParameters parameters;
    for (const auto& [name, value] : values) parameters.set(name, value);
    Progress progress;
    BakeContext context{mesh, source, parameters, progress, 1};
    Result<std::unique_ptr<Package>> package = bake(context);
    EXPECT_TRUE(package.is_ok()) << package.status().message();
    return package.is_ok() ? std::move(*package) : nullptr;
}

ImageMetrics compare(Renderer& truth, Renderer& standin, const Mesh& mesh, const OrbitView& view, int size)
{
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    Light light = default_light(camera);
    Result<RenderedImage> a = render_offscreen(truth, camera, light, size, size);
    Result<RenderedImage> b = render_offscreen(standin, camera, light, size, size);
    EXPECT_TRUE(a.is_ok() && b.is_ok());
    return compare_images(a->color, b->color);
}

TEST(ViewAtlasRenderer, SeedStyleReproducesACapturedView)
{
    Mesh mesh = torus();
    std::unique_ptr<Package> package =
        bake_atlas(mesh, {{"subdivisions", "1"}, {"resolution", "96"}, {"maps", "lit"}, {"page-size", "1024"}});
    ASSERT_TRUE(package);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    RenderOptions options;
    options.style = "seed";
    Result<std::unique_ptr<Renderer>> atlas = make_renderer(*package, options);
    ASSERT_TRUE(truth.is_ok() && atlas.is_ok()) << atlas.status().message();
    // the top view is captured (+Y is a face centre): orthographic, the same framing as the capture
    OrbitView top;
    top.elevation_degrees = 90.0f;
    top.orthographic = true;
    ImageMetrics m = compare(**truth, **atlas, mesh, top, 96);
    EXPECT_GT(m.iou, 0.97);
    EXPECT_LT(m.luv_mean, 3.0);

    // lit-only packages cannot be corrected
    options.style = "corrected";
    EXPECT_FALSE(make_renderer(*package, options).is_ok());
    options.style = "sideways";
    EXPECT_FALSE(make_renderer(*package, options).is_ok());
}

TEST(ViewAtlasRenderer, CorrectedBeatsSeedBetweenViews)
{
    Mesh mesh = torus();
    std::unique_ptr<Package> package = bake_atlas(mesh, {{"subdivisions", "2"}, {"resolution", "96"}, {"page-size", "2048"}});
    ASSERT_TRUE(package);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth.is_ok());
    OrbitView view;
    view.azimuth_degrees = 23.0f;
    view.elevation_degrees = 41.0f;
    view.fov_y_degrees = 60.0f;
    double error[3], iou[3];
    const char* styles[3] = {"seed", "octahedral-baseline", "corrected"};
    for (int k = 0; k < 3; ++k) {
        RenderOptions options;
        options.style = styles[k];
        Result<std::unique_ptr<Renderer>> atlas = make_renderer(*package, options);
        ASSERT_TRUE(atlas.is_ok()) << atlas.status().message();
        ImageMetrics m = compare(**truth, **atlas, mesh, view, 128);
        error[k] = m.rgb_avg;
        iou[k] = m.iou;
        std::printf("%s: rgb_avg %.2f iou %.3f luv %.2f\n", styles[k], m.rgb_avg, m.iou, m.luv_mean);
    }
    EXPECT_GT(iou[0], 0.6);
    EXPECT_GT(iou[2], 0.85);
    EXPECT_LT(error[2], error[0]);
    EXPECT_LT(error[2], error[1]);
}

TEST(ViewAtlasRenderer, BakesAreByteIdentical)
{
    Mesh mesh = torus();
    std::string dir = test::fresh_directory("view_atlas_bake_twice");
    for (const char* name : {"/a.standin", "/b.standin"}) {
        std::unique_ptr<Package> package =
            bake_atlas(mesh, {{"layout", "hemi-octahedral"}, {"frames", "4"}, {"resolution", "64"}, {"page-size", "512"}});
        ASSERT_TRUE(package);
        ASSERT_TRUE(write_package(*package, dir + name).is_ok());
    }
    for (const char* file : {"/manifest.json", "/page_000_color.png", "/page_000_normal_depth.png"})
        EXPECT_EQ(*read_file(dir + "/a.standin" + file), *read_file(dir + "/b.standin" + file)) << file;
}

// STANDIN_ATLAS_TEXTURE_BYTES set for the lifetime of this object
struct TextureBudget {
    explicit TextureBudget(std::uint64_t bytes) { setenv("STANDIN_ATLAS_TEXTURE_BYTES", std::to_string(bytes).c_str(), 1); }
    ~TextureBudget() { unsetenv("STANDIN_ATLAS_TEXTURE_BYTES"); }
};

TEST(ViewAtlasRenderer, PagesSplitOverSeveralArraysDrawAsOne)
{
    Mesh mesh = torus();
    std::unique_ptr<Package> baked =
        bake_atlas(mesh, {{"layout", "hemi-octahedral"}, {"frames", "4"}, {"resolution", "128"}, {"page-size", "256"}});
    ASSERT_TRUE(baked);
    const auto& package = dynamic_cast<const ViewAtlasPackage&>(*baked);
    const int pages = int(package.color_pages.size());
    ASSERT_GE(pages, 3) << "the test needs several pages";
    std::uint64_t page_bytes = 0; // 256² RGBA8 with its k_mip_levels levels
    for (int level = 0; level < k_mip_levels; ++level) page_bytes += std::uint64_t(256 >> level) * (256 >> level) * 4;

    for (const char* style : {"seed", "corrected"}) {
        RenderOptions options;
        options.style = style;
        Result<std::unique_ptr<Renderer>> one = make_renderer(package, options);
        ASSERT_TRUE(one.is_ok()) << one.status().message();
        // one page per array: every page in its own array at layer 0
        TextureBudget budget(page_bytes + page_bytes / 2);
        Result<std::unique_ptr<Renderer>> split = make_renderer(package, options);
        ASSERT_TRUE(split.is_ok()) << split.status().message();
        for (float azimuth : {31.0f, 121.0f, 211.0f, 301.0f}) { // views on every page
            OrbitView view;
            view.azimuth_degrees = azimuth;
            view.elevation_degrees = 37.0f;
            Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
            Light light = default_light(camera);
            Result<RenderedImage> a = render_offscreen(**one, camera, light, 64, 64);
            Result<RenderedImage> b = render_offscreen(**split, camera, light, 64, 64);
            ASSERT_TRUE(a.is_ok() && b.is_ok());
            EXPECT_GT(compare_images(a->color, a->color).intersection_pixels, 100u) << "nothing drawn";
            EXPECT_EQ(a->color.pixels, b->color.pixels) << style << " at azimuth " << azimuth;
        }
    }

    // a budget below one page, or one needing more arrays than the shader binds: refused by name
    {
        TextureBudget budget(page_bytes - 1);
        Result<std::unique_ptr<Renderer>> refused = make_renderer(package, RenderOptions{});
        ASSERT_FALSE(refused.is_ok());
        EXPECT_NE(refused.status().message().find("does not fit"), std::string::npos) << refused.status().message();
        EXPECT_NE(refused.status().message().find(std::to_string(pages) + " pages"), std::string::npos);
    }
    {
        TextureBudget budget(page_bytes); // one page per array
        EXPECT_EQ(make_renderer(package, RenderOptions{}).is_ok(), pages <= ATLAS_MAX_ARRAYS);
    }
}

} // namespace
} // namespace standin::view_atlas
