// Microfacets baked on the GPU from small generated meshes and drawn against the ground truth: a
// sphere seen from a captured direction, the clipping rule (eq. 1) on a hand-made one-facet package,
// the GPU's LOD cut against the CPU's, byte-identical bakes and renders, instances, and the
// styles the options select.
#include "test_support.h"

#include "gpu/gl.h"
#include "reps/microfacets/lod.h"
#include "reps/microfacets/renderer.h"

#include <standin/eval.h>
#include <standin/files.h>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <tbb/task_arena.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace standin::microfacets {
namespace {

Mesh generated(GeneratedShape shape, std::size_t triangles)
{
    GenerateOptions options;
    options.shape = shape;
    options.target_triangles = triangles;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok());
    return std::move(*mesh);
}

const MicrofacetsPackage& as_microfacets(const std::unique_ptr<Package>& package)
{
    return dynamic_cast<const MicrofacetsPackage&>(*package);
}

std::unique_ptr<Package> bake_small(const Mesh& mesh, std::vector<std::pair<std::string, std::string>> extra = {})
{
    test::gpu_context();
    std::vector<std::pair<std::string, std::string>> values = {
        {"level", "6"}, {"subdivisions", "1"}, {"resolution", "128"}, {"page-size", "1024"}};
    for (auto& value : extra) {
        bool replaced = false;
        for (auto& v : values)
            if (v.first == value.first) v.second = value.second, replaced = true;
        if (!replaced) values.push_back(value);
    }
    return test::bake(mesh, "microfacets", values);
}

std::unique_ptr<Renderer> renderer_for(const Package& package, const RenderConfig& config = {})
{
    Result<std::unique_ptr<Renderer>> made = make_microfacet_renderer(dynamic_cast<const MicrofacetsPackage&>(package), config);
    EXPECT_TRUE(made.is_ok()) << made.status().message();
    return made.is_ok() ? std::move(*made) : nullptr;
}

RenderedImage render(Renderer& renderer, const Camera& camera, int size, std::span<const glm::mat4> instances = {})
{
    Result<RenderedImage> image = render_offscreen(renderer, camera, default_light(camera), size, size, instances);
    EXPECT_TRUE(image.is_ok()) << image.status().message();
    return image.is_ok() ? std::move(*image) : RenderedImage{};
}

// One draw into an offscreen target of the viewport's size, for its stats.
DrawStats draw_offscreen(Renderer& renderer, const DrawParams& params)
{
    gpu::Texture color = gpu::make_texture_2d(GL_RGBA8, params.viewport.x, params.viewport.y);
    gpu::Texture depth = gpu::make_texture_2d(GL_DEPTH_COMPONENT32F, params.viewport.x, params.viewport.y);
    gpu::Framebuffer fbo = gpu::make_framebuffer();
    glNamedFramebufferTexture(fbo.get(), GL_COLOR_ATTACHMENT0, color.get(), 0);
    glNamedFramebufferTexture(fbo.get(), GL_DEPTH_ATTACHMENT, depth.get(), 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo.get());
    glViewport(0, 0, params.viewport.x, params.viewport.y);
    DrawStats stats = renderer.draw(params);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
    return stats;
}

TEST(MicrofacetRenderer, SphereFromACapturedDirection)
{
    Mesh mesh = generated(GeneratedShape::sphere, 3000);
    std::unique_ptr<Package> package = bake_small(mesh);
    ASSERT_TRUE(package);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth.is_ok());
    std::unique_ptr<Renderer> facets = renderer_for(*package);
    ASSERT_TRUE(facets);
    // the top view (+Y) is a face centre of the icosahedral layout: orthographic, its framing
    OrbitView top;
    top.elevation_degrees = 90.0f;
    top.orthographic = true;
    Camera camera = orbit_camera(mesh.bounding_sphere(), top, 1.0f);
    ImageMetrics m = compare_images(render(**truth, camera, 128).color, render(*facets, camera, 128).color);
    EXPECT_GE(m.iou, 0.98);
    EXPECT_LT(m.luv_mean, 3.0);
    // under perspective at the base distance, from the same direction: the rim's facets are seen
    // from up to 20 degrees away and take other views
    top.orthographic = false;
    camera = orbit_camera(mesh.bounding_sphere(), top, 1.0f);
    m = compare_images(render(**truth, camera, 128).color, render(*facets, camera, 128).color);
    EXPECT_GE(m.iou, 0.95);
}

// A package of one voxel and one view looking down -Z at a flat covered square whose stored depth
// is `surface_height` above the capture plane through the centre.
MicrofacetsPackage one_facet(float surface_height)
{
    MicrofacetsPackage p;
    p.settings.level = 1;
    p.settings.min_level = 1;
    p.settings.resolution = 32;
    p.settings.page_size = 256;
    p.center = glm::vec3(0.0f);
    p.radius = 1.0f;
    p.max_view_angle = 0.1f;
    // a 2^3 grid over [-1, 1]^3: voxel (1, 1, 1) spans [0, 1]^3, centre (0.5, 0.5, 0.5), W = 1
    p.octree.grid.origin = glm::vec3(-1.0f);
    p.octree.grid.size = 2.0f;
    p.octree.min_level = p.octree.max_level = 1;
    p.octree.levels = {{morton_encode({1, 1, 1})}};
    View v;
    v.direction = {0, 0, 1};
    v.axis_u = {1, 0, 0};
    v.axis_v = {0, -1, 0};
    v.crop_x = v.crop_y = 0;
    v.width = v.height = 32;
    p.views = {v};
    p.color_pages = {ImageRGBA8(256, 256)};
    p.normal_depth_pages = {ImageRGBA16(256, 256)};
    std::uint16_t code = std::uint16_t(std::lround((1.0f - surface_height) / 2.0f * 65535.0f));
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 32; ++x) {
            std::uint8_t* c = p.color_pages[0].at(x, y);
            c[0] = 200, c[1] = 100, c[2] = 50, c[3] = 255;
            std::uint16_t* nd = p.normal_depth_pages[0].at(x, y);
            nd[0] = nd[1] = 32768, nd[2] = 65535, nd[3] = code; // normal +Z
        }
    return p;
}

std::size_t covered(const ImageRGBA8& image)
{
    std::size_t n = 0;
    for (std::size_t p = 3; p < image.pixels.size(); p += 4) n += image.pixels[p] != 0;
    return n;
}

TEST(MicrofacetRenderer, EquationOneClipsAFacetFartherThanHalfAVoxel)
{
    test::gpu_context();
    OrbitView front; // from +Z: the captured direction
    front.orthographic = true;
    Camera camera = orbit_camera(BoundingSphere{{0, 0, 0}, 1.0f}, front, 1.0f);
    RenderConfig config;
    config.views = 1;
    config.level = 1;
    config.primitive = "quads";
    config.clip = "seed";
    // the stored surface through the voxel centre (z = 0.5), 0.4 W above it and 0.6 W below
    std::size_t pixels[3];
    float heights[3] = {0.5f, 0.9f, -0.1f};
    for (int k = 0; k < 3; ++k) {
        MicrofacetsPackage package = one_facet(heights[k]);
        Result<std::unique_ptr<Renderer>> r = make_microfacet_renderer(package, config);
        ASSERT_TRUE(r.is_ok()) << r.status().message();
        pixels[k] = covered(render(**r, camera, 64).color);
    }
    // the facet is a square of side sqrt(3) W seen face on, centred at (0.5, 0.5) of the [-1, 1]^2
    // view: [0.5 - sqrt(3)/2, 1]^2 of it is on screen
    const double side = (1.0 - (0.5 - 0.8660254)) / 2.0;
    EXPECT_NEAR(double(pixels[0]), 64.0 * 64.0 * side * side, 64.0 * 3.0);
    EXPECT_EQ(pixels[1], pixels[0]);
    EXPECT_EQ(pixels[2], 0u);
    // the ray clip: the surface inside the voxel is found (also where the square reaches beyond it,
    // seen face on), the one outside it is not
    config.clip = "ray";
    for (int k = 0; k < 3; ++k) {
        MicrofacetsPackage package = one_facet(heights[k]);
        Result<std::unique_ptr<Renderer>> r = make_microfacet_renderer(package, config);
        ASSERT_TRUE(r.is_ok()) << r.status().message();
        std::size_t n = covered(render(**r, camera, 64).color);
        if (k < 2) EXPECT_GT(n, pixels[0] / 2) << k;
        else EXPECT_EQ(n, 0u);
    }
    config.clip = "seed";
    // the depth written is the stored surface's, not the facet's
    MicrofacetsPackage package = one_facet(0.9f);
    Result<std::unique_ptr<Renderer>> r = make_microfacet_renderer(package, config);
    ASSERT_TRUE(r.is_ok());
    RenderedImage image = render(**r, camera, 64);
    glm::vec4 clip = camera.clip_from_world() * glm::vec4(0.5f, 0.5f, 0.9f, 1.0f);
    EXPECT_NEAR(image.depth[32 * 64 + 40], 0.5f * clip.z / clip.w + 0.5f, 1e-4f);
}

TEST(MicrofacetRenderer, GpuCutMatchesTheCpuCut)
{
    Mesh mesh = generated(GeneratedShape::torus, 3000);
    std::unique_ptr<Package> package = bake_small(mesh, {{"min-level", "2"}});
    ASSERT_TRUE(package);
    const MicrofacetsPackage& p = as_microfacets(package);
    RenderConfig config;
    config.primitive = "quads";
    config.max_error_pixels = 1.0f;
    config.cull_unseen = false; // the CPU's cut does not know which views saw what
    std::unique_ptr<Renderer> facets = renderer_for(*package, config);
    ASSERT_TRUE(facets);
    for (float distance : {1.3f, 2.5f, 6.0f}) {
        OrbitView view;
        view.distance_rel = distance;
        view.azimuth_degrees = 30.0f;
        view.elevation_degrees = 25.0f;
        view.fov_y_degrees = 120.0f; // everything in view: no node is culled
        Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
        DrawParams params;
        params.camera = camera;
        params.light = default_light(camera);
        params.viewport = {200, 200};
        DrawStats stats = draw_offscreen(*facets, params);
        LodRule rule;
        rule.tan_delta = std::tan(p.max_view_angle);
        rule.min_level = p.settings.min_level;
        rule.max_level = p.settings.level;
        ScreenScale scale = screen_scale(camera, 200);
        BoundingSphere sphere{p.center, p.radius};
        int finest = finest_level(rule, scale, p.octree.grid.size, glm::length(camera.eye_world - sphere.center), sphere.radius);
        std::size_t expected = select_cut(p.octree, rule, scale, camera.eye_world, 1.0f, finest).size();
        // the shader's floats may flip a node lying exactly on the bound: allow a few in a thousand
        EXPECT_NEAR(double(stats.primitives / 2), double(expected), 2.0 + 0.003 * double(expected)) << distance;
    }
}

TEST(MicrofacetRenderer, BakesAndRendersAreByteIdentical)
{
    Mesh mesh = generated(GeneratedShape::noisy_sphere, 3000);
    std::unique_ptr<Package> one, two;
    tbb::task_arena(1).execute([&] { one = bake_small(mesh); });
    tbb::task_arena(2).execute([&] { two = bake_small(mesh); });
    ASSERT_TRUE(one && two);
    std::string a = test::fresh_directory("microfacets_a") + "/p.standin", b = test::fresh_directory("microfacets_b") + "/p.standin";
    ASSERT_TRUE(write_package(*one, a).is_ok());
    ASSERT_TRUE(write_package(*two, b).is_ok());
    for (const auto& entry : std::filesystem::directory_iterator(a)) {
        std::string name = entry.path().filename().string();
        EXPECT_EQ(*read_file(a + "/" + name), *read_file(b + "/" + name)) << name;
    }
    // read back, drawn twice by two renderers: the same bytes
    Result<std::unique_ptr<Package>> read = read_package(a);
    ASSERT_TRUE(read.is_ok()) << read.status().message();
    OrbitView view;
    view.azimuth_degrees = 17.0f;
    view.elevation_degrees = 11.0f;
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    std::unique_ptr<Renderer> r1 = renderer_for(**read), r2 = renderer_for(*one);
    RenderedImage i1 = render(*r1, camera, 160), i2 = render(*r2, camera, 160), i3 = render(*r1, camera, 160);
    EXPECT_EQ(i1.color.pixels, i2.color.pixels);
    EXPECT_EQ(i1.color.pixels, i3.color.pixels);
    EXPECT_EQ(i1.depth, i2.depth);
}

TEST(MicrofacetRenderer, DroppingUnseenNodesChangesNoPixel)
{
    Mesh mesh = generated(GeneratedShape::noisy_sphere, 3000);
    std::unique_ptr<Package> package = bake_small(mesh);
    ASSERT_TRUE(package);
    RenderConfig all, culled;
    all.cull_unseen = false;
    // the seen bits also steer the view selection towards views that saw each node, which changes
    // pixels on purpose (select.comp step 4); dropping the nodes is what is exact, so the selection
    // is the nearest views' here, as without the bits; so do the fallback views walked where every
    // blended view abstains (facets.frag), which are off here
    setenv("STANDIN_MICROFACETS_PREFER_SEEN", "0", 1);
    setenv("STANDIN_MICROFACETS_FALLBACK", "0", 1);
    struct Unset {
        ~Unset()
        {
            unsetenv("STANDIN_MICROFACETS_PREFER_SEEN");
            unsetenv("STANDIN_MICROFACETS_FALLBACK");
        }
    } unset;
    std::unique_ptr<Renderer> a = renderer_for(*package, all), b = renderer_for(*package, culled);
    ASSERT_TRUE(a && b);
    for (float azimuth : {0.0f, 37.0f, 150.0f}) {
        OrbitView view;
        view.azimuth_degrees = azimuth;
        view.elevation_degrees = 25.0f;
        view.distance_rel = azimuth == 150.0f ? 0.6f : 1.0f;
        Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
        RenderedImage ia = render(*a, camera, 128), ib = render(*b, camera, 128);
        EXPECT_EQ(ia.color.pixels, ib.color.pixels) << azimuth;
        EXPECT_EQ(ia.depth, ib.depth) << azimuth;
    }
    // and at the finest level a third of the facets (most of the far side of the sphere) are not drawn
    all.level = culled.level = 6;
    a = renderer_for(*package, all);
    b = renderer_for(*package, culled);
    DrawParams params;
    params.camera = orbit_camera(mesh.bounding_sphere(), OrbitView{}, 1.0f);
    params.light = default_light(params.camera);
    params.viewport = {128, 128};
    EXPECT_LT(double(draw_offscreen(*b, params).primitives), 0.75 * double(draw_offscreen(*a, params).primitives));
}

// Where every blended view of a facet abstains at a pixel (the ray passes under surface each of
// them saw nearer its camera: a leaf inside a crown), the nearest other views that saw surface in
// the node are walked (facets.frag). On a small generated tree the holes against the truth (pixels
// the mesh covers and the stand-in does not) fall, and the silhouette IoU rises.
TEST(MicrofacetRenderer, FallbackViewsCloseTheCrownsHoles)
{
    const Mesh tree = test::generated(GeneratedShape::tree, 2000, 3);
    ASSERT_GT(tree.triangle_count(), 0u);
    std::unique_ptr<Package> package = bake_small(tree);
    ASSERT_TRUE(package);
    auto truth = make_mesh_renderer(tree);
    ASSERT_TRUE(truth.is_ok());
    std::array<std::size_t, 2> holes{}, spill{}, both{};
    for (int k = 0; k < 2; ++k) {
        setenv("STANDIN_MICROFACETS_FALLBACK", k == 0 ? "0" : "8", 1);
        std::unique_ptr<Renderer> standin = renderer_for(*package);
        unsetenv("STANDIN_MICROFACETS_FALLBACK");
        ASSERT_TRUE(standin);
        for (float azimuth : {30.0f, 200.0f}) {
            OrbitView view;
            view.azimuth_degrees = azimuth;
            view.elevation_degrees = 20.0f;
            Camera camera = orbit_camera(tree.bounding_sphere(), view, 1.0f);
            RenderedImage t = render(**truth, camera, 256), s = render(*standin, camera, 256);
            for (std::size_t i = 3; i < t.color.pixels.size(); i += 4) {
                bool a = t.color.pixels[i] > 0, b = s.color.pixels[i] > 0;
                holes[std::size_t(k)] += a && !b;
                spill[std::size_t(k)] += b && !a;
                both[std::size_t(k)] += a && b;
            }
        }
    }
    auto iou = [&](int k) { return double(both[std::size_t(k)]) / double(both[std::size_t(k)] + holes[std::size_t(k)] + spill[std::size_t(k)]); };
    std::printf("[microfacets fallback] holes %zu -> %zu, spill %zu -> %zu, IoU %.4f -> %.4f\n", holes[0], holes[1], spill[0],
                spill[1], iou(0), iou(1));
    EXPECT_LT(double(holes[1]), 0.8 * double(holes[0]));
    EXPECT_GT(iou(1), iou(0));
}

// A coarse voxel over fine captures: at level 2 a voxel spans a quarter of a 1024^2 capture, and the
// pixel's ray inside it crosses hundreds of texels of a view 20-30 degrees off, more than the walk's
// steps; it walks blocks of texels then, and still ends inside the voxel (a walk that ran out of
// steps left the pixel empty: foliage at distance 8, 1536^2 captures, holes 0.7% -> 5.4%).
TEST(MicrofacetRenderer, CoarseVoxelsOverFineCapturesLeaveNoHoles)
{
    Mesh mesh = generated(GeneratedShape::sphere, 3000);
    std::unique_ptr<Package> package = bake_small(mesh, {{"resolution", "1024"}, {"subdivisions", "0"}, {"page-size", "2048"}});
    ASSERT_TRUE(package);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth.is_ok());
    RenderConfig coarse;
    coarse.level = 2;
    std::unique_ptr<Renderer> facets = renderer_for(*package, coarse);
    ASSERT_TRUE(facets);
    OrbitView view;
    view.azimuth_degrees = 17.0f; // between captured directions
    view.elevation_degrees = 23.0f;
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    ImageMetrics m = compare_images(render(**truth, camera, 128).color, render(*facets, camera, 128).color);
    std::printf("[microfacets coarse voxels] IoU %.4f, holes %.4f, Luv %.3f\n", m.iou, m.hole_fraction, m.luv_mean);
    EXPECT_GE(m.iou, 0.97);
    EXPECT_LT(m.hole_fraction, 0.02);
}

// A unit quad facing +z textured with stripes two texture texels wide (64 pairs across 256 texels),
// red and green: resolved by 512^2 captures, finer than the pixels at 96^2.
Mesh striped_quad()
{
    Mesh mesh = test::alpha_quad(AlphaMode::opaque, 0.0f, true);
    Texture& texture = mesh.textures[0];
    for (int y = 0; y < texture.height; ++y)
        for (int x = 0; x < texture.width; ++x) {
            std::uint8_t* t = &texture.rgba[(std::size_t(y) * texture.width + x) * 4];
            const bool red = (x / 2) % 2 == 0;
            t[0] = red ? 230 : 20, t[1] = red ? 30 : 200, t[2] = 40, t[3] = 255;
        }
    mesh.materials[0].alpha_mode = AlphaMode::opaque;
    return mesh;
}

// Texture detail finer than a pixel: the truth filters it (its texture's mips), so the ray clip
// filters the captured colour over the pixel's footprint too, where the footprint holds one surface;
// reading the texel hit (STANDIN_MICROFACETS_FILTER_COLOR=0, as before) shows aliased stripes.
TEST(MicrofacetRenderer, ColourFilteredOverThePixelLikeTheTruthsTexture)
{
    const Mesh quad = striped_quad();
    std::unique_ptr<Package> package = bake_small(quad, {{"resolution", "512"}});
    ASSERT_TRUE(package);
    auto truth = make_mesh_renderer(quad);
    ASSERT_TRUE(truth.is_ok());
    OrbitView view;
    view.azimuth_degrees = 10.0f;
    view.elevation_degrees = 10.0f;
    Camera camera = orbit_camera(quad.bounding_sphere(), view, 1.0f);
    const RenderedImage t = render(**truth, camera, 96);
    std::array<double, 2> luv{};
    for (int k = 0; k < 2; ++k) {
        if (k == 0) setenv("STANDIN_MICROFACETS_FILTER_COLOR", "0", 1);
        std::unique_ptr<Renderer> standin = renderer_for(*package);
        unsetenv("STANDIN_MICROFACETS_FILTER_COLOR");
        ASSERT_TRUE(standin);
        ImageMetrics m = compare_images(t.color, render(*standin, camera, 96).color);
        EXPECT_GE(m.iou, 0.97);
        luv[std::size_t(k)] = m.luv_mean;
    }
    std::printf("[microfacets colour filter] Luv %.3f texel hit, %.3f filtered\n", luv[0], luv[1]);
    EXPECT_LT(luv[1], 0.6 * luv[0]);
}

TEST(MicrofacetRenderer, InstancesDrawAsTheSingleModel)
{
    Mesh mesh = generated(GeneratedShape::torus, 2000);
    std::unique_ptr<Package> package = bake_small(mesh);
    ASSERT_TRUE(package);
    std::unique_ptr<Renderer> facets = renderer_for(*package);
    OrbitView view;
    view.azimuth_degrees = 40.0f;
    view.elevation_degrees = 30.0f;
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    RenderedImage single = render(*facets, camera, 128);
    // the same instance among others far outside the view: culled, the picture unchanged
    std::vector<glm::mat4> crowd = {glm::translate(glm::mat4(1.0f), glm::vec3(50.0f, 0.0f, 0.0f)), glm::mat4(1.0f),
                                    glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -60.0f, 0.0f))};
    RenderedImage many = render(*facets, camera, 128, crowd);
    EXPECT_EQ(single.color.pixels, many.color.pixels);
    // turned and scaled: close to the mesh turned and scaled
    glm::mat4 turned = glm::scale(glm::rotate(glm::mat4(1.0f), 0.7f, glm::vec3(0, 1, 0)), glm::vec3(0.8f));
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth.is_ok());
    std::vector<glm::mat4> one = {turned};
    ImageMetrics m = compare_images(render(**truth, camera, 128, one).color, render(*facets, camera, 128, one).color);
    EXPECT_GT(m.iou, 0.93);
}

// The bake's estimate of the crops (bake.cpp estimated_crops, which decides how far a raised
// resolution comes down) holds every crop the captures really took, so its page count is at least
// theirs: a torus, whose views it covers partly and differently.
TEST(MicrofacetRenderer, EstimatedCropsHoldTheCapturedOnes)
{
    Mesh mesh = generated(GeneratedShape::torus, 2000);
    std::unique_ptr<Package> package = bake_small(mesh);
    ASSERT_TRUE(package);
    const MicrofacetsPackage& p = as_microfacets(package);
    std::vector<View> estimated =
        estimated_crops(mesh, mesh.bounding_sphere(), capture_directions(p.settings), p.settings.resolution, p.settings.page_size);
    ASSERT_EQ(estimated.size(), p.views.size());
    int tight = 0;
    for (std::size_t k = 0; k < estimated.size(); ++k) {
        EXPECT_GE(estimated[k].width, p.views[k].width) << "view " << k;
        EXPECT_GE(estimated[k].height, p.views[k].height) << "view " << k;
        tight += estimated[k].width == p.views[k].width && estimated[k].height == p.views[k].height;
    }
    EXPECT_GT(tight, int(estimated.size()) / 2) << "the estimate should be the crop itself on most views";
    std::vector<View> copy = estimated;
    EXPECT_GE(reps::pack_views(copy, p.settings.page_size), int(p.color_pages.size()));
}

TEST(MicrofacetRenderer, OptionsAndRefusals)
{
    Mesh mesh = generated(GeneratedShape::torus, 2000);
    std::unique_ptr<Package> package = bake_small(mesh, {{"layout", "circle"}, {"frames", "12"}});
    ASSERT_TRUE(package);
    EXPECT_EQ(as_microfacets(package).views.size(), 12u);
    OrbitView view;
    view.azimuth_degrees = 15.0f; // halfway between two of the 12 cameras
    Camera camera = orbit_camera(mesh.bounding_sphere(), view, 1.0f);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(mesh);
    ASSERT_TRUE(truth.is_ok());
    ImageRGBA8 reference = render(**truth, camera, 128).color;
    // every variant draws the torus
    for (RenderConfig config : {RenderConfig{}, RenderConfig{"cone", 2}, RenderConfig{"all", 1}, RenderConfig{"lookup", 4, "fixed"},
                                RenderConfig{"lookup", 3, "billboard", "points"}, RenderConfig{"lookup", 3, "billboard", "quads", "vote", 4}}) {
        std::unique_ptr<Renderer> r = renderer_for(*package, config);
        ASSERT_TRUE(r);
        ImageMetrics m = compare_images(reference, render(*r, camera, 128).color);
        EXPECT_GT(m.iou, config.primitive == "points" || config.facet == "fixed" ? 0.6 : 0.9)
            << config.select << " " << config.views << " " << config.facet << " " << config.primitive;
    }
    // the seed's selection (all views) and the lookup pick the same views: the same picture
    RenderConfig all, lookup;
    all.select = "all";
    EXPECT_EQ(render(*renderer_for(*package, all), camera, 96).color.pixels, render(*renderer_for(*package, lookup), camera, 96).color.pixels);
    // refusals name the option
    for (RenderConfig bad : {RenderConfig{"nearest"}, RenderConfig{"lookup", 5}, RenderConfig{"lookup", 3, "round"}}) {
        Result<std::unique_ptr<Renderer>> r = make_microfacet_renderer(as_microfacets(package), bad);
        ASSERT_FALSE(r.is_ok());
        EXPECT_NE(r.status().message().find("microfacets: --"), std::string::npos) << r.status().message();
    }
    RenderConfig deep;
    deep.level = 9;
    EXPECT_FALSE(make_microfacet_renderer(as_microfacets(package), deep).is_ok());
}

} // namespace
} // namespace standin::microfacets
