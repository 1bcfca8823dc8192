// The displaced-mesh renderer on the GPU: no crack inside the silhouette of a closed model at
// several tolerances, renders byte-identical across renderers and runs, the GPU refinement matches
// the CPU reference's counts, rendered triangles fall as tau grows, culling and the debug views,
// moving the control mesh moves the picture, shadows are cast, and a textured low-poly model is
// shaded finer than its pattern.
#include "test_support.h"

#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/renderer.h"
#include "gpu/source_texture.h"

#include <standin/assembly.h>
#include <standin/eval.h>
#include <standin/render.h>

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <deque>
#include <string>

namespace standin::displaced_mesh {
namespace {

struct Subject {
    Mesh mesh;
    std::unique_ptr<DisplacedMeshPackage> package;
};

const Subject& noisy_sphere()
{
    test::gpu_context();
    static Subject subject = [] {
        Subject s;
        GenerateOptions options;
        options.shape = GeneratedShape::noisy_sphere;
        options.target_triangles = 20000;
        options.noise_amplitude = 0.12f;
        s.mesh = std::move(*generate_mesh(options));
        Result<Options> parameters = bake_parameters({{"degree", "9"}});
        EXPECT_TRUE(parameters.is_ok());
        Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(s.mesh, SourceInfo{}, *parameters, Progress());
        EXPECT_TRUE(package.is_ok());
        s.package = std::move(*package);
        return s;
    }();
    return subject;
}

// Appends a card of test::alpha_quad's kind (one material, its one texture) to `cards`: with its
// own material and texture, or drawn with the material of the card before it.
void append_card(Mesh& cards, const Mesh& card, bool own_material)
{
    if (own_material || cards.materials.empty()) {
        cards.materials.push_back(card.materials[0]);
        cards.materials.back().base_color_texture = int(cards.textures.size());
        cards.textures.push_back(card.textures[0]);
    }
    const std::uint32_t first = std::uint32_t(cards.positions.size());
    cards.positions.insert(cards.positions.end(), card.positions.begin(), card.positions.end());
    cards.normals.insert(cards.normals.end(), card.normals.begin(), card.normals.end());
    cards.colors.insert(cards.colors.end(), card.colors.begin(), card.colors.end());
    cards.uvs.insert(cards.uvs.end(), card.uvs.begin(), card.uvs.end());
    for (std::uint32_t i : card.indices) cards.indices.push_back(first + i);
    cards.face_materials.insert(cards.face_materials.end(), card.triangle_count(), std::uint32_t(cards.materials.size() - 1));
}

std::unique_ptr<DisplacedRenderer> make(const DisplacedMeshPackage& package, const RendererSettings& settings)
{
    test::gpu_context();
    Result<std::unique_ptr<DisplacedRenderer>> renderer = DisplacedRenderer::create(package, settings);
    EXPECT_TRUE(renderer.is_ok()) << renderer.status().message();
    return renderer.is_ok() ? std::move(*renderer) : nullptr;
}

Camera camera_for(const Mesh& mesh, float azimuth, float distance, int width, int height)
{
    OrbitView view;
    view.azimuth_degrees = azimuth;
    view.elevation_degrees = 25.0f;
    view.distance_rel = distance;
    return orbit_camera(mesh.bounding_sphere(), view, float(width) / float(height));
}

RenderedImage render(Renderer& renderer, const Camera& camera, int width, int height)
{
    Result<RenderedImage> image = render_offscreen(renderer, camera, default_light(camera), width, height);
    EXPECT_TRUE(image.is_ok()) << image.status().message();
    return image.is_ok() ? std::move(*image) : RenderedImage{};
}

// Uncovered pixels that the background cannot reach from the image border: cracks and holes
// inside the silhouette.
std::size_t enclosed_holes(const ImageRGBA8& image)
{
    const int w = image.width, h = image.height;
    std::vector<std::uint8_t> outside(std::size_t(w) * std::size_t(h), 0);
    std::deque<std::pair<int, int>> queue;
    auto covered = [&](int x, int y) { return image.pixels[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4 + 3] != 0; };
    auto push = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
        if (outside[i] || covered(x, y)) return;
        outside[i] = 1;
        queue.push_back({x, y});
    };
    for (int x = 0; x < w; ++x) push(x, 0), push(x, h - 1);
    for (int y = 0; y < h; ++y) push(0, y), push(w - 1, y);
    while (!queue.empty()) {
        auto [x, y] = queue.front();
        queue.pop_front();
        push(x + 1, y), push(x - 1, y), push(x, y + 1), push(x, y - 1);
    }
    std::size_t holes = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) holes += !covered(x, y) && !outside[std::size_t(y) * std::size_t(w) + std::size_t(x)];
    return holes;
}

TEST(DisplacedMeshRenderer, NoCracksAtSeveralTolerancesAndCloseToTheTruth)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(s.mesh);
    ASSERT_TRUE(truth.is_ok());
    for (float tau : {0.5f, 1.0f, 2.0f, 8.0f}) {
        SCOPED_TRACE(tau);
        RendererSettings settings;
        settings.tau = tau;
        std::unique_ptr<DisplacedRenderer> renderer = make(*s.package, settings);
        ASSERT_TRUE(renderer);
        for (float azimuth : {0.0f, 130.0f}) {
            Camera camera = camera_for(s.mesh, azimuth, 1.0f, 320, 240);
            RenderedImage image = render(*renderer, camera, 320, 240);
            EXPECT_EQ(enclosed_holes(image.color), 0u);
            EXPECT_EQ(renderer->last_counters().capped, 0u);
            if (tau <= 1.0f) {
                ImageMetrics m = compare_images(render(**truth, camera, 320, 240).color, image.color);
                EXPECT_GT(m.iou, 0.99);
                EXPECT_LT(m.hole_fraction, 0.005);
                EXPECT_LT(m.luv_mean, 1.5);
            }
        }
    }
}

TEST(DisplacedMeshRenderer, ByteIdenticalAndMatchesTheCpuReference)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    RendererSettings settings;
    std::unique_ptr<DisplacedRenderer> a = make(*s.package, settings), b = make(*s.package, settings);
    ASSERT_TRUE(a && b);
    Camera camera = camera_for(s.mesh, 40.0f, 1.2f, 400, 300);
    RenderedImage first = render(*a, camera, 400, 300);
    RenderedImage second = render(*b, camera, 400, 300);
    RenderedImage again = render(*a, camera, 400, 300);
    EXPECT_EQ(first.color.pixels, second.color.pixels);
    EXPECT_EQ(first.color.pixels, again.color.pixels);
    EXPECT_EQ(first.depth, second.depth);

    // the CPU reference refines the same way (floating-point details of sqrt and log2 aside)
    const DisplacedMeshPackage& p = *s.package;
    std::vector<FaceRefineData> faces = prepare_faces(p.positions, p.normals, p.indices, p.topology, p.layout(), p.elevations, p.face_error);
    RefineSurface surface{&p.positions, &p.normals, &p.indices, &p.topology, &p.elevations, &faces, p.settings.degree};
    RefineStats stats;
    refine(surface, make_refine_view(camera, 300, glm::mat4(1.0f)), RefineOptions{}, stats);
    RefineCounters gpu = a->last_counters();
    EXPECT_EQ(gpu.faces_visible, stats.faces_visible);
    EXPECT_NEAR(double(gpu.rendered), double(stats.rendered), 0.002 * double(stats.rendered));
    EXPECT_NEAR(double(gpu.processed), double(stats.processed), 0.002 * double(stats.processed));
}

// A package whose buffers would not fit one storage block is refused in one line that names the
// buffer and what to bake instead (foliage of over a million cards on llvmpipe's 128 MiB); at the
// GL's own limit the same package draws.
TEST(DisplacedMeshRenderer, BuffersOverTheStorageBlockLimitAreRefused)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    test::gpu_context();
    const std::uint64_t shading = s.package->shading_normals.size() * 8;
    RendererSettings settings;
    settings.max_storage_block_bytes = shading - 1; // every other buffer of this package is smaller
    Result<std::unique_ptr<DisplacedRenderer>> refused = DisplacedRenderer::create(*s.package, settings);
    ASSERT_FALSE(refused.is_ok());
    EXPECT_EQ(refused.status().code(), StatusCode::unsupported);
    const std::string message = refused.status().message();
    EXPECT_NE(message.find("shading samples"), std::string::npos) << message;
    EXPECT_NE(message.find("--degree 5"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    settings.max_storage_block_bytes = shading;
    EXPECT_TRUE(DisplacedRenderer::create(*s.package, settings).is_ok());
    settings.max_storage_block_bytes = 0;
    EXPECT_TRUE(DisplacedRenderer::create(*s.package, settings).is_ok());
}

// A package whose source textures would make a texture array the GL cannot hold, or a memory bomb
// (a hostile package may list 256 layers of 16384²; every layer takes the largest size), is refused
// in one line before anything is uploaded.
TEST(DisplacedMeshRenderer, SourceTexturesOverTheArrayLimitsAreRefused)
{
    test::gpu_context();
    Result<Options> parameters = bake_parameters({{"degree", "5"}});
    ASSERT_TRUE(parameters.is_ok());
    Result<std::unique_ptr<DisplacedMeshPackage>> package =
        bake_displaced(test::alpha_quad(AlphaMode::mask, 0.5f, true), SourceInfo{}, *parameters, Progress());
    ASSERT_TRUE(package.is_ok()) << package.status().message();
    ASSERT_EQ((*package)->source_textures.layers.size(), 1u);
    EXPECT_TRUE(DisplacedRenderer::create(**package, RendererSettings{}).is_ok());
    Texture huge; // its size alone is read before the refusal
    huge.width = huge.height = 16384;
    (*package)->source_textures.layers.push_back(huge);
    Result<std::unique_ptr<DisplacedRenderer>> refused = DisplacedRenderer::create(**package, RendererSettings{});
    ASSERT_FALSE(refused.is_ok());
    EXPECT_EQ(refused.status().code(), StatusCode::unsupported);
    const std::string message = refused.status().message();
    EXPECT_NE(message.find("--source-textures off"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// Source textures of different sizes keep their own texels: one whose size divides the largest's
// is repeated across a layer of its array and read at scaled UVs (its own texels and mip levels, as
// the truth reads them; resampled to the largest, a 32-texel checker of one-texel squares blurred
// at its edges), and one whose size does not goes to an array of its own size
// (gpu::source_texture_array_of). Three opaque cards side by side: a 32-, a 128- and a 48-texel
// checker; measured Luv 0.007 against the truth for the first two, 1.356 with the 32 resampled;
// with the 48 too, 0.001 in its own array, 3.662 resampled to 128 (one array).
TEST(DisplacedMeshRenderer, SmallerSourceTexturesKeepTheirOwnTexels)
{
    test::gpu_context();
    Mesh cards;
    const int sizes[3] = {32, 128, 48};
    for (int k = 0; k < 3; ++k) {
        Mesh card = test::alpha_quad(AlphaMode::opaque, 0.5f, true);
        card.textures[0] = test::painted_texture("checker_" + std::to_string(sizes[k]), sizes[k], [k](int x, int y, std::uint8_t* t) {
            const bool dark = (x + y) % 2 == 0;
            t[0] = dark ? 30 : 230, t[1] = dark ? 60 : std::uint8_t(120 + 45 * k), t[2] = dark ? 90 : 40, t[3] = 255;
        });
        for (glm::vec3& p : card.positions) p.x += 1.1f * float(k - 1);
        append_card(cards, card, true);
    }
    Result<Options> parameters = bake_parameters({{"degree", "5"}});
    ASSERT_TRUE(parameters.is_ok());
    Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(cards, SourceInfo{}, *parameters, Progress());
    ASSERT_TRUE(package.is_ok()) << package.status().message();
    ASSERT_EQ((*package)->source_textures.layers.size(), 3u);
    ASSERT_EQ((*package)->source_textures.matched_faces(), 6u);
    EXPECT_EQ(gpu::source_texture_array_of((*package)->source_textures.layers, 4), (std::vector<std::uint32_t>{0u, 0u, 1u}));
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(cards);
    ASSERT_TRUE(truth.is_ok());
    std::unique_ptr<DisplacedRenderer> renderer = make(**package, RendererSettings{});
    ASSERT_TRUE(renderer);
    double luv = 0.0;
    for (float azimuth : {0.0f, 25.0f}) {
        Camera camera = camera_for(cards, azimuth, 1.0f, 480, 240);
        luv += 0.5 * compare_images(render(**truth, camera, 480, 240).color, render(*renderer, camera, 480, 240).color).luv_mean;
    }
    std::printf("[displaced source texture sizes] Luv %.3f\n", luv);
    EXPECT_LT(luv, 0.05);
}

TEST(DisplacedMeshRenderer, FewerTrianglesAsTauGrowsAndCullingHelps)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    Camera camera = camera_for(s.mesh, 10.0f, 2.0f, 400, 300);
    std::uint64_t previous = UINT64_MAX;
    for (float tau : {0.5f, 1.0f, 2.0f, 4.0f}) {
        RendererSettings settings;
        settings.tau = tau;
        std::unique_ptr<DisplacedRenderer> renderer = make(*s.package, settings);
        render(*renderer, camera, 400, 300);
        RefineCounters c = renderer->last_counters();
        EXPECT_LT(c.rendered, previous) << tau;
        EXPECT_GT(c.processed, c.rendered);
        previous = c.rendered;
    }
    RendererSettings no_cull;
    no_cull.cull = false;
    std::unique_ptr<DisplacedRenderer> all = make(*s.package, no_cull);
    RendererSettings cull;
    std::unique_ptr<DisplacedRenderer> culled = make(*s.package, cull);
    RenderedImage with = render(*culled, camera, 400, 300), without = render(*all, camera, 400, 300);
    EXPECT_LT(culled->last_counters().faces_visible, all->last_counters().faces_visible * 3 / 4);
    EXPECT_EQ(with.color.pixels, without.color.pixels);
}

TEST(DisplacedMeshRenderer, DebugViewsAndMovingTheControlMesh)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    Camera camera = camera_for(s.mesh, 0.0f, 1.0f, 160, 120);
    for (DebugView view : {DebugView::parts, DebugView::level, DebugView::error, DebugView::depth, DebugView::normal}) {
        RendererSettings settings;
        settings.debug_view = view;
        std::unique_ptr<DisplacedRenderer> renderer = make(*s.package, settings);
        ASSERT_TRUE(renderer) << debug_view_name(view);
        EXPECT_GT(compare_images(ImageRGBA8(160, 120), render(*renderer, camera, 160, 120).color).spill_pixels, 1000u);
    }
    RendererSettings bad;
    bad.debug_view = DebugView::fetches;
    EXPECT_FALSE(DisplacedRenderer::create(*s.package, bad).is_ok());

    // §5.3: shift the control mesh to the right: the picture follows
    std::unique_ptr<DisplacedRenderer> renderer = make(*s.package, RendererSettings{});
    RenderedImage before = render(*renderer, camera, 160, 120);
    std::vector<glm::vec3> moved = s.package->positions;
    glm::vec3 right = glm::vec3(glm::inverse(camera.view_from_world)[0]);
    for (glm::vec3& p : moved) p += 0.3f * right;
    ASSERT_TRUE(renderer->update_control(moved, s.package->normals).is_ok());
    RenderedImage after = render(*renderer, camera, 160, 120);
    auto centre_x = [](const ImageRGBA8& image) {
        double sum = 0.0, count = 0.0;
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                if (image.pixels[(std::size_t(y) * image.width + x) * 4 + 3]) sum += x, count += 1;
        return sum / count;
    };
    EXPECT_GT(centre_x(after.color), centre_x(before.color) + 5.0);
    EXPECT_FALSE(renderer->update_control(std::vector<glm::vec3>(3), std::vector<glm::vec3>(3)).is_ok());
}

TEST(DisplacedMeshRenderer, TurningTheControlMeshTurnsItsShadingToo)
{
    // §5.3 with a rigid motion: the control mesh turned by 90 degrees on the CPU must look like the
    // package drawn with that turn as its instance transform (geometry and shading normals alike)
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    glm::mat4 turn = glm::rotate(glm::mat4(1.0f), glm::radians(90.0f), glm::vec3(0.0f, 1.0f, 0.0f));
    std::vector<glm::vec3> positions = s.package->positions, normals = s.package->normals;
    for (glm::vec3& p : positions) p = glm::vec3(turn * glm::vec4(p, 1.0f));
    for (glm::vec3& n : normals) n = glm::normalize(glm::mat3(turn) * n);
    std::unique_ptr<DisplacedRenderer> moved = make(*s.package, RendererSettings{}), instanced = make(*s.package, RendererSettings{});
    ASSERT_TRUE(moved && instanced);
    ASSERT_TRUE(moved->update_control(positions, normals).is_ok());
    Camera camera = camera_for(s.mesh, 20.0f, 1.0f, 320, 240);
    Light light = default_light(camera);
    std::vector<glm::mat4> instance = {turn};
    Result<RenderedImage> a = render_offscreen(*moved, camera, light, 320, 240);
    Result<RenderedImage> b = render_offscreen(*instanced, camera, light, 320, 240, instance);
    ASSERT_TRUE(a.is_ok() && b.is_ok());
    ImageMetrics m = compare_images(b->color, a->color);
    EXPECT_GT(m.iou, 0.995);
    EXPECT_LT(m.luv_mean, 0.3); // turning normals by the vertex normals alone (no twist) gave 1.28
}

TEST(DisplacedMeshRenderer, TessellationBaselineIsCrackFreeAndAgreesWithBisection)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    RendererSettings tess;
    tess.subdivision = "tess";
    std::unique_ptr<DisplacedRenderer> patches = make(*s.package, tess), bisection = make(*s.package, RendererSettings{});
    ASSERT_TRUE(patches && bisection);
    for (float azimuth : {0.0f, 200.0f}) {
        Camera camera = camera_for(s.mesh, azimuth, 1.0f, 320, 240);
        RenderedImage a = render(*patches, camera, 320, 240), b = render(*bisection, camera, 320, 240);
        EXPECT_EQ(enclosed_holes(a.color), 0u);
        EXPECT_GT(patches->last_counters().rendered, 1000u);
        ImageMetrics m = compare_images(b.color, a.color);
        EXPECT_GT(m.iou, 0.995);
        EXPECT_LT(m.luv_mean, 1.0);
    }
    tess.subdivision = "geometry";
    EXPECT_FALSE(DisplacedRenderer::create(*s.package, tess).is_ok());
}

TEST(DisplacedMeshRenderer, ErrorCountersMeasureTheTolerance)
{
    const Subject& s = noisy_sphere();
    ASSERT_TRUE(s.package);
    Camera camera = camera_for(s.mesh, 0.0f, 1.5f, 400, 300);
    double previous = 0.0;
    for (float tau : {1.0f, 4.0f}) {
        RendererSettings settings;
        settings.tau = tau;
        settings.mip = false;
        std::unique_ptr<DisplacedRenderer> renderer = make(*s.package, settings);
        renderer->set_counting(true);
        render(*renderer, camera, 400, 300);
        ErrorCounters e = renderer->read_error_counters();
        EXPECT_GT(e.fragments, 10000u);
        EXPECT_GT(e.error_mean_px, previous);
        EXPECT_LT(e.error_mean_px, tau);
        previous = e.error_mean_px;
    }
}

// A sphere over a single-sided plane (assimp's COLLADA.dae: text over a plane): the truth culls the
// plane's back, so from below it shows the sphere alone. --back-faces auto sees the plane's back
// from outside and culls back faces; drawn both sides (show), the plane's underside spills.
// A textured low-poly model (the bundled 12-face box, a 211-pixel texture): its texture's detail
// lives in the shading samples, which auto takes 4 times finer than the pattern there (thesis
// protocol: Luv 5.27 at 1, 1.08 at 4, docs/RESULTS.md "Shading finer than the pattern"), with the
// source's texture left out (--source-textures off); with it, every face of the box kept whole
// reads the texture itself (source_textures.h), closer still, at shading detail 1.
TEST(DisplacedMeshRenderer, ATexturedLowPolyModelIsShadedFinerThanItsPattern)
{
    test::gpu_context();
    Result<Mesh> box = import_mesh(test::source_dir() + "/data/box_textured.glb");
    ASSERT_TRUE(box.is_ok()) << box.status().message();
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*box);
    ASSERT_TRUE(truth.is_ok());
    double luv[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k) {
        // (degree 17 given: chosen, the 12 faces would take 33, default_control_plan)
        Result<Options> parameters = bake_parameters(
            {{"degree", "17"}, {"shading-detail", k == 0 ? "1" : "auto"}, {"source-textures", k < 2 ? "off" : "auto"}});
        ASSERT_TRUE(parameters.is_ok());
        Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(*box, SourceInfo{}, *parameters, Progress());
        ASSERT_TRUE(package.is_ok()) << package.status().message();
        // (drawn from the source's texture, the faces ask for no finer shading: detail 1)
        EXPECT_EQ((*package)->settings.shading_detail, k == 1 ? 4 : 1);
        EXPECT_EQ((*package)->source_textures.matched_faces(), k < 2 ? 0u : (*package)->face_count());
        EXPECT_EQ((*package)->albedo.size(), (*package)->face_count() * (*package)->shading_samples_per_face());
        std::unique_ptr<DisplacedRenderer> renderer = make(**package, RendererSettings{});
        ASSERT_TRUE(renderer);
        for (float azimuth : {30.0f, 200.0f}) {
            Camera camera = camera_for(*box, azimuth, 1.0f, 400, 300);
            luv[k] += 0.5 * compare_images(render(**truth, camera, 400, 300).color, render(*renderer, camera, 400, 300).color).luv_mean;
        }
    }
    std::printf("[displaced textured box] Luv: shading detail 1 %.3f, auto (4) %.3f, the source's texture %.3f\n", luv[0], luv[1],
                luv[2]);
    EXPECT_LT(luv[1], 2.0);
    EXPECT_LT(luv[1], luv[0] - 2.0);
    EXPECT_LT(luv[2], 0.1); // measured 0.003: the truth's own texture on the truth's own faces
}

// A closed cube, wound outward, whose six faces share an alpha-masked texture: stripes of colour
// and a 4 x 4 grid of round holes (assimp's FBX box with a cut-out paper texture, in miniature).
Mesh perforated_cube()
{
    Texture texture = test::painted_texture("perforated", 128, [](int x, int y, std::uint8_t* t) {
        const double cx = std::fmod(x + 0.5, 32.0) - 16.0, cy = std::fmod(y + 0.5, 32.0) - 16.0;
        t[0] = (x / 8) % 2 ? 220 : 60, t[1] = (y / 8) % 2 ? 200 : 80, t[2] = 90;
        t[3] = cx * cx + cy * cy < 10.0 * 10.0 ? 0 : 255;
    });
    Mesh mesh;
    const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const glm::vec3& n : normals) {
        // s x t = n: the corners below run counter-clockwise seen from outside
        const glm::vec3 up = std::abs(n.y) > 0.5f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
        const glm::vec3 s = glm::normalize(glm::cross(up, n)), t = glm::cross(n, s);
        const auto base = std::uint32_t(mesh.positions.size());
        const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (const glm::vec2& c : corners) {
            mesh.positions.push_back(0.5f * n + (c.x - 0.5f) * s + (c.y - 0.5f) * t);
            mesh.normals.push_back(n);
            mesh.colors.push_back(glm::vec4(1.0f));
            mesh.uvs.push_back(c);
        }
        for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) mesh.indices.push_back(base + i);
        mesh.face_materials.insert(mesh.face_materials.end(), {0u, 0u});
    }
    mesh.textures.push_back(std::move(texture));
    mesh.materials.push_back(test::alpha_textured_material("perforated", AlphaMode::mask, 0.5f, true));
    return mesh;
}

// A low-poly model with cut-outs: its coverage is sampled as finely as its shading (auto detail 4
// on a cube of 12 faces, drawn from its samples), so the holes are round where the pattern drew
// polygons a pattern step wide; drawn from the source's texture, at detail 1, rounder still; and through them the eye sees the far walls' insides, which the closed part's back-face
// cull used to remove (the holes showed the background).
TEST(DisplacedMeshRenderer, CutOutsOfALowPolyModelAreOutlinedFinerAndSeenInto)
{
    test::gpu_context();
    const Mesh cube = perforated_cube();
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(cube);
    ASSERT_TRUE(truth.is_ok());
    double luv[3] = {0.0, 0.0, 0.0}, iou[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k) {
        Result<Options> parameters =
            bake_parameters({{"shading-detail", k == 0 ? "1" : "auto"}, {"source-textures", k < 2 ? "off" : "auto"}});
        ASSERT_TRUE(parameters.is_ok());
        Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(cube, SourceInfo{}, *parameters, Progress());
        ASSERT_TRUE(package.is_ok()) << package.status().message();
        ASSERT_EQ((*package)->coverage.size(), (*package)->albedo.size());
        if (k >= 1) {
            // with the source's texture (k = 2) the faces draw it and ask for no finer samples
            EXPECT_EQ((*package)->settings.shading_detail, k == 1 ? 4 : 1);
        }
        std::unique_ptr<DisplacedRenderer> renderer = make(**package, RendererSettings{});
        ASSERT_TRUE(renderer);
        for (float azimuth : {30.0f, 200.0f}) {
            Camera camera = camera_for(cube, azimuth, 1.0f, 400, 300);
            ImageMetrics m = compare_images(render(**truth, camera, 400, 300).color, render(*renderer, camera, 400, 300).color);
            luv[k] += 0.5 * m.luv_mean, iou[k] += 0.5 * m.iou;
        }
    }
    std::printf("[displaced perforated cube] detail 1: Luv %.3f IoU %.4f; auto (4): Luv %.3f IoU %.4f; the source's texture: Luv "
                "%.3f IoU %.4f\n",
                luv[0], iou[0], luv[1], iou[1], luv[2], iou[2]);
    // measured (the samples alone, --source-textures off): detail 1 Luv 22.6, IoU 0.978; auto 5.8,
    // 0.985; with the far walls' insides culled 33.2, 0.748 and 19.5, 0.778
    EXPECT_GT(iou[0], 0.97) << "the far walls' insides, seen through the holes, are drawn";
    EXPECT_GT(iou[1], 0.98);
    EXPECT_LT(luv[1], 8.0);
    EXPECT_LT(luv[1], luv[0] - 8.0) << "finer coverage and colour outline the holes";
    // the faces read the texture's own cut-outs (source_textures.h): measured Luv 0.003, IoU 1.0000
    EXPECT_GT(iou[2], 0.999);
    EXPECT_LT(luv[2], 0.1);
}

// Leaf cards one behind another: disc-shaped cut-outs (alpha-masked quads) in a stack, each a
// little higher and further right, so from the front every pixel sees several cards' fragments.
Mesh stacked_cards(int count)
{
    Mesh cards;
    for (int k = 0; k < count; ++k) {
        Mesh card = test::alpha_quad(AlphaMode::mask, 0.5f, true);
        for (glm::vec3& p : card.positions) p += glm::vec3(0.08f * float(k), 0.05f * float(k), -0.1f * float(k));
        append_card(cards, card, k == 0);
    }
    return cards;
}

// Packages with cut-outs draw depth through the cut-out test first and then shade only the nearest
// fragments (--cut-out-pre-pass, renderer.cpp draw): the same picture as one pass with late depth
// tests, for cut-outs read from the source's texture and from the coverage samples alike, with
// one shaded fragment per covered pixel where one pass shades every card's. A package whose
// coverage array is missing (damaged) draws its textured cut-outs without reading past it.
TEST(DisplacedMeshRenderer, CutOutPrePassShadesEachPixelOnceWithTheSamePicture)
{
    test::gpu_context();
    const Mesh cards = stacked_cards(6);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(cards);
    ASSERT_TRUE(truth.is_ok());
    OrbitView face_on; // from +z, down the stack
    face_on.elevation_degrees = 0.0f;
    const Camera camera = orbit_camera(cards.bounding_sphere(), face_on, 320.0f / 240.0f);
    const RenderedImage truth_image = render(**truth, camera, 320, 240);
    for (const char* source_textures : {"auto", "off"}) {
        SCOPED_TRACE(source_textures);
        Result<Options> parameters = bake_parameters({{"degree", "5"}, {"source-textures", source_textures}});
        ASSERT_TRUE(parameters.is_ok());
        Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(cards, SourceInfo{}, *parameters, Progress());
        ASSERT_TRUE(package.is_ok()) << package.status().message();
        ASSERT_FALSE((*package)->coverage.empty());
        RenderedImage image[2];
        std::uint64_t fragments[2] = {0, 0};
        for (int pre_pass = 0; pre_pass < 2; ++pre_pass) {
            RendererSettings settings;
            settings.cut_out_pre_pass = pre_pass == 1;
            std::unique_ptr<DisplacedRenderer> renderer = make(**package, settings);
            ASSERT_TRUE(renderer);
            renderer->set_counting(true);
            image[pre_pass] = render(*renderer, camera, 320, 240);
            fragments[pre_pass] = renderer->read_counter(Counter::fragments);
        }
        std::size_t covered = 0, differing = 0;
        const std::vector<std::uint8_t>& a = image[0].color.pixels;
        const std::vector<std::uint8_t>& b = image[1].color.pixels;
        ASSERT_EQ(a.size(), b.size());
        for (std::size_t i = 0; i < a.size(); i += 4) {
            covered += b[i + 3] != 0;
            differing += a[i] != b[i] || a[i + 1] != b[i + 1] || a[i + 2] != b[i + 2] || a[i + 3] != b[i + 3];
        }
        const ImageMetrics m = compare_images(truth_image.color, image[1].color);
        std::printf("[displaced cut-out pre-pass, source textures %s] fragments %llu in one pass, %llu after the pre-pass, "
                    "%zu covered pixels, %zu differing; Luv %.3f IoU %.4f\n",
                    source_textures, (unsigned long long)fragments[0], (unsigned long long)fragments[1], covered, differing,
                    m.luv_mean, m.iou);
        ASSERT_GT(covered, 4000u);
        EXPECT_LE(differing, covered / 1000) << "the same nearest fragments";
        EXPECT_GT(double(fragments[0]), 2.0 * double(covered)) << "one pass shades the cards behind";
        EXPECT_LE(double(fragments[1]), 1.01 * double(covered)) << "once per pixel after the pre-pass";
        // measured: the texture's own discs 1.0000; the samples' coverage, interpolated over
        // degree 5's pattern, 0.945
        EXPECT_GT(m.iou, std::string(source_textures) == "auto" ? 0.999 : 0.9);
    }
    Result<Options> parameters = bake_parameters({{"degree", "5"}});
    ASSERT_TRUE(parameters.is_ok());
    Result<std::unique_ptr<DisplacedMeshPackage>> damaged = bake_displaced(cards, SourceInfo{}, *parameters, Progress());
    ASSERT_TRUE(damaged.is_ok());
    (*damaged)->coverage.clear();
    std::unique_ptr<DisplacedRenderer> renderer = make(**damaged, RendererSettings{});
    ASSERT_TRUE(renderer);
    EXPECT_GT(compare_images(truth_image.color, render(*renderer, camera, 320, 240).color).iou, 0.99);
}

// The pre-pass keeps what depth-writing draws promise: faded out at 1/2 (a screen-door
// cross-fade to nothing), the package draws its plain picture at its own pixels and leaves the
// others empty, depth included (the pre-pass writes no depth where the fade drops a fragment);
// and the cards' shadows on each other (the shadow map drawn through the pre-pass alone) are
// those of one pass.
TEST(DisplacedMeshRenderer, CutOutPrePassCrossFadesAndCastsShadowsAsOnePass)
{
    test::gpu_context();
    const Mesh cards = stacked_cards(6);
    Result<Options> parameters = bake_parameters({{"degree", "5"}});
    ASSERT_TRUE(parameters.is_ok());
    Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(cards, SourceInfo{}, *parameters, Progress());
    ASSERT_TRUE(package.is_ok()) << package.status().message();
    OrbitView view;
    view.azimuth_degrees = 20.0f;
    view.elevation_degrees = 10.0f;
    const Camera camera = orbit_camera(cards.bounding_sphere(), view, 1.0f);
    ShadowOptions shadows;
    shadows.enabled = true;
    shadows.scene = cards.bounding_sphere();
    shadows.resolution = 1024;
    RenderedImage shadowed[2], plain, faded;
    for (int pre_pass = 0; pre_pass < 2; ++pre_pass) {
        RendererSettings settings;
        settings.cut_out_pre_pass = pre_pass == 1;
        std::unique_ptr<DisplacedRenderer> renderer = make(**package, settings);
        ASSERT_TRUE(renderer);
        Result<RenderedImage> image = render_offscreen(*renderer, camera, default_light(camera), 200, 200, {}, shadows);
        ASSERT_TRUE(image.is_ok()) << image.status().message();
        shadowed[pre_pass] = std::move(*image);
        if (!settings.cut_out_pre_pass) continue;
        plain = render(*renderer, camera, 200, 200);
        struct Nothing final : Renderer {
            DrawStats draw(const DrawParams&) override { return {}; }
        } nothing;
        CrossFade to_nothing(*renderer, nothing);
        to_nothing.set_amount(0.5f);
        faded = render(to_nothing, camera, 200, 200);
    }
    std::size_t covered = 0, kept = 0, wrong = 0;
    for (std::size_t i = 0; i < plain.depth.size(); ++i) {
        covered += plain.depth[i] < 1.0f;
        const bool same = faded.depth[i] == plain.depth[i] && std::memcmp(&faded.color.pixels[4 * i], &plain.color.pixels[4 * i], 4) == 0;
        const bool empty = faded.depth[i] == 1.0f && faded.color.pixels[4 * i + 3] == 0;
        kept += plain.depth[i] < 1.0f && same;
        wrong += !same && !empty;
    }
    ASSERT_GT(covered, 2000u);
    EXPECT_EQ(wrong, 0u) << "each pixel the plain picture's or empty";
    EXPECT_NEAR(double(kept) / double(covered), 0.5, 0.05) << "half the picture kept";
    std::size_t differing = 0, darker = 0;
    for (std::size_t i = 0; i < shadowed[0].color.pixels.size(); i += 4) {
        differing += std::memcmp(&shadowed[0].color.pixels[i], &shadowed[1].color.pixels[i], 4) != 0;
        darker += shadowed[1].color.pixels[i + 1] + 8 < plain.color.pixels[i + 1];
    }
    EXPECT_LE(differing, covered / 1000) << "the same shadows";
    EXPECT_GT(darker, covered / 20) << "the cards shade each other";
}

TEST(DisplacedMeshRenderer, SingleSidedSheetsShowNothingFromBehind)
{
    test::gpu_context();
    const Mesh mesh = test::sphere_over_single_sided_plane();
    std::unique_ptr<Package> culled = test::bake(mesh, "displaced-mesh", {});
    std::unique_ptr<Package> shown = test::bake(mesh, "displaced-mesh", {{"back-faces", "show"}});
    ASSERT_TRUE(culled && shown);
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(*culled).settings.back_faces, "cull"); // auto
    auto [below_spill, below_iou] = test::worst_spill_and_iou(mesh, *culled, -35.0f);
    auto [above_spill, above_iou] = test::worst_spill_and_iou(mesh, *culled, 35.0f);
    auto [shown_spill, shown_iou] = test::worst_spill_and_iou(mesh, *shown, -35.0f);
    std::printf("[ behind ] from below: spill %.2f%% IoU %.4f (both sides: %.2f%%, %.4f); from above %.2f%%, %.4f\n",
                100.0 * below_spill, below_iou, 100.0 * shown_spill, shown_iou, 100.0 * above_spill, above_iou);
    EXPECT_LT(below_spill, 0.02);
    EXPECT_GT(below_iou, 0.95);
    EXPECT_GT(above_iou, 0.97) << "the plane's front is drawn";
    EXPECT_GT(shown_spill, 0.5) << "the plane's underside, which the truth culls";
    // an instance that mirrors, whose faces' winding the mirror turns: the mirror image from below,
    // the plane's back culled (by GL it showed the back and hid the front), in the truth too
    {
        auto truth = make_mesh_renderer(mesh);
        auto standin = make_package_renderer(*culled, RenderOptions{});
        RenderOptions tessellated; // the hardware-tessellation baseline culls through the same shader
        tessellated.values.set("subdivision", "tess");
        auto patches = make_package_renderer(*culled, tessellated);
        ASSERT_TRUE(truth.is_ok() && standin.is_ok() && patches.is_ok());
        EXPECT_LT(test::mirrored_picture_difference(**truth, mesh.bounding_sphere(), -35.0f), 0.01);
        EXPECT_LT(test::mirrored_picture_difference(**standin, mesh.bounding_sphere(), -35.0f), 0.01);
        EXPECT_LT(test::mirrored_picture_difference(**patches, mesh.bounding_sphere(), -35.0f), 0.01);
    }
    // a closed single-sided model keeps both sides (its backs face its inside)
    Mesh closed = test::generated(GeneratedShape::sphere, 800);
    for (Material& m : closed.materials) m.double_sided = false;
    std::unique_ptr<Package> sphere = test::bake(closed, "displaced-mesh", {});
    ASSERT_TRUE(sphere);
    EXPECT_EQ(dynamic_cast<const DisplacedMeshPackage&>(*sphere).settings.back_faces, "show");
}

} // namespace
} // namespace standin::displaced_mesh
