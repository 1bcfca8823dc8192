// The contract every registered representation keeps, checked over representations() the way
// pbrt-v4 tests every Filter (filters_test.cpp): a representation is "done" in the plumbing sense
// when it passes. The tests share the bundled bunny baked with the representation's defaults
// (shared_package).
// - bake -> write -> read -> write gives the same bytes, and so do bakes on 1 and 2 threads;
// - every declared option is accepted at its declared default (all given at once bake the same
//   bytes on 2 threads as none given on 1, and draw the same picture) and refused just outside its
//   range;
// - a renderer made and drawn on one thread draws what one on every core draws;
// - the silhouette matches the mesh from the 14 directions of Saraiva et al. (IoU >= 0.98);
// - an instance that mirrors draws the mirror image, in colour and depth;
// - it writes true depth: composited with a plane through the model, each pixel shows what the
//   mesh composited with the same plane shows;
// - it casts the mesh's shadow onto a ground plate;
// - a damaged package is refused with one line naming it.
#include "test_support.h"

#include <standin/eval.h>
#include <standin/files.h>
#include <standin/package.h>
#include <standin/render.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <filesystem>
#include <map>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace standin {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<Package> bake(const Representation& representation, const OptionValues& parameters, int threads = 1)
{
    Result<SourceInfo> source = describe_source(test::source_dir() + "/data/bunny.ply", test::bunny());
    EXPECT_TRUE(source.is_ok());
    Result<std::unique_ptr<Package>> package = bake_package(representation, test::bunny(), *source, parameters, {}, threads);
    EXPECT_TRUE(package.is_ok()) << package.status().message();
    return package ? std::move(*package) : nullptr;
}

// The names of the files that differ between two package directories (or exist in one only).
std::vector<std::string> differing_files(const std::string& a, const std::string& b)
{
    std::map<std::string, std::string> files_a, files_b;
    for (const auto& entry : fs::directory_iterator(a)) files_a[entry.path().filename().string()] = *read_file(entry.path().string());
    for (const auto& entry : fs::directory_iterator(b)) files_b[entry.path().filename().string()] = *read_file(entry.path().string());
    std::vector<std::string> differ;
    for (const auto& [name, bytes] : files_a)
        if (!files_b.count(name) || files_b[name] != bytes) differ.push_back(name);
    for (const auto& [name, bytes] : files_b)
        if (!files_a.count(name)) differ.push_back(name);
    return differ;
}

// Draws several renderers into one picture, in order (a scene of a stand-in and other geometry).
class Scene final : public Renderer {
public:
    explicit Scene(std::vector<Renderer*> parts) : parts_(std::move(parts)) {}
    DrawStats draw(const DrawParams& params) override
    {
        DrawStats total;
        for (Renderer* part : parts_) {
            DrawStats s = part->draw(params);
            total.draw_calls += s.draw_calls;
            total.primitives += s.primitives;
        }
        return total;
    }

private:
    std::vector<Renderer*> parts_;
};

// A flat square of side 2 * half at height y, facing +y, of one colour.
Mesh plate(glm::vec3 centre, float half, glm::vec4 color, glm::vec3 normal = {0, 1, 0})
{
    glm::vec3 u = glm::normalize(glm::cross(normal, std::abs(normal.y) > 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
    glm::vec3 v = glm::cross(normal, u);
    Mesh m;
    const int n = 8;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float a = -half + 2.0f * half * float(i) / n, b = -half + 2.0f * half * float(j) / n;
            m.positions.push_back(centre + a * u + b * v);
            m.normals.push_back(normal);
            m.colors.push_back(color);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
            for (std::uint32_t x : {a, b, c, b, d, c}) m.indices.push_back(x);
            m.face_materials.push_back(0);
            m.face_materials.push_back(0);
        }
    m.materials.push_back(Material{"plate", glm::vec4(1.0f), -1});
    return m;
}

Mesh merged(const Mesh& a, const Mesh& b)
{
    Mesh m = a;
    std::uint32_t offset = std::uint32_t(m.positions.size());
    std::uint32_t material = std::uint32_t(m.materials.size());
    m.positions.insert(m.positions.end(), b.positions.begin(), b.positions.end());
    m.normals.insert(m.normals.end(), b.normals.begin(), b.normals.end());
    m.colors.insert(m.colors.end(), b.colors.begin(), b.colors.end());
    if (m.has_texture_coordinates()) m.uvs.resize(m.positions.size(), glm::vec2(0.0f));
    for (std::uint32_t i : b.indices) m.indices.push_back(i + offset);
    for (std::uint32_t f : b.face_materials) m.face_materials.push_back(f + material);
    m.materials.insert(m.materials.end(), b.materials.begin(), b.materials.end());
    return m;
}

std::vector<std::string> names()
{
    std::vector<std::string> out;
    for (const Representation& r : representations()) out.push_back(r.name);
    return out;
}

// The package of `representation` baked with the defaults, written, and read back as a renderer gets
// it, shared by the contract's tests of one representation. ctest runs every test in a process of
// its own, and the view atlas's and microfacets' bakes of the bunny (6-10 s each, 15-20 s under the
// sanitizers) were most of their six tests' time. The first process to need it bakes and writes it
// under a lock, next to this test executable and stamped with the executable's size and time (a
// rebuild bakes again); the others wait for the lock and read it. Where that folder cannot be
// written, each process bakes its own.
struct SharedPackage {
    std::unique_ptr<Package> package;
    std::string directory; // the package as baked and written
};

SharedPackage shared_package(const Representation& representation)
{
    SharedPackage shared;
    std::error_code ec;
    const fs::path executable = fs::read_symlink("/proc/self/exe", ec);
    const fs::path cache = executable.parent_path() / "contract_packages";
    fs::create_directories(cache, ec);
    const int lock = ec ? -1 : ::open((cache / (representation.name + ".lock")).c_str(), O_CREAT | O_RDWR | O_CLOEXEC, 0644);
    if (lock < 0 || ::flock(lock, LOCK_EX) != 0) {
        if (lock >= 0) ::close(lock);
        shared.directory = test::fresh_directory("contract_" + representation.name) + "/p.standin";
        shared.package = bake(representation, {});
        EXPECT_TRUE(shared.package && write_package(*shared.package, shared.directory).is_ok());
        return shared;
    }
    const std::string stamp = std::to_string(fs::file_size(executable, ec)) + " " +
                              std::to_string(fs::last_write_time(executable, ec).time_since_epoch().count());
    shared.directory = (cache / (representation.name + ".standin")).string();
    const std::string stamp_path = (cache / (representation.name + ".stamp")).string();
    Result<std::string> cached_stamp = read_file(stamp_path);
    Result<std::unique_ptr<Package>> read = error(StatusCode::not_found, "not baked yet");
    if (cached_stamp && *cached_stamp == stamp) read = read_package(shared.directory);
    if (!read) { // not there, from another build, or damaged by hand: baked again
        std::unique_ptr<Package> baked = bake(representation, {});
        EXPECT_TRUE(baked && write_package(*baked, shared.directory).is_ok() && write_file_atomic(stamp_path, stamp).is_ok());
        read = read_package(shared.directory);
    }
    EXPECT_TRUE(read.is_ok()) << read.status().message();
    if (read) shared.package = std::move(*read);
    ::close(lock);
    return shared;
}

class RepresentationContract : public ::testing::TestWithParam<std::string> {
protected:
    const Representation& representation() const { return *find_representation(GetParam()); }
    const SharedPackage& shared()
    {
        static std::map<std::string, SharedPackage> packages;
        SharedPackage& p = packages[GetParam()];
        if (!p.package) p = shared_package(representation());
        return p;
    }
    const Package& package() { return *shared().package; }
    // every bake option that declares a default, given at it
    OptionValues explicit_defaults() const
    {
        OptionValues defaults;
        for (const OptionSpec& spec : representation().bake_options)
            if (!spec.default_value.empty()) defaults.set(spec.name, spec.default_value);
        return defaults;
    }
};

TEST_P(RepresentationContract, RoundTripAndBakesAreByteIdentical)
{
    std::string dir = test::fresh_directory("contract_roundtrip_" + GetParam());
    // the shared package as baked and written, and as read back (package())
    const std::string baked = shared().directory;
    EXPECT_EQ(package().representation(), GetParam());
    ASSERT_TRUE(write_package(package(), dir + "/b.standin").is_ok());
    EXPECT_EQ(differing_files(baked, dir + "/b.standin"), std::vector<std::string>{}) << "written, read and written again";

    // One more bake proves two things at once: on 2 threads, with every bake option given at its
    // declared default, it gives the bytes of the bake on 1 thread with none given. (A bake of its
    // own for each took the view atlas and microfacets 10-25 s more of CI per lane.) Left to the
    // Release lane: under the sanitizers it runs the code of the first bake again (the view atlas and
    // microfacets: 15-20 s each of the sanitizer lane, which ends at CI's budget).
    if (test::k_sanitized_build) return;
    std::unique_ptr<Package> two_threads = bake(representation(), explicit_defaults(), 2);
    ASSERT_TRUE(two_threads);
    ASSERT_TRUE(write_package(*two_threads, dir + "/c.standin").is_ok());
    EXPECT_EQ(differing_files(baked, dir + "/c.standin"), std::vector<std::string>{})
        << "baked on 2 threads with every bake option given at its default";
}

TEST_P(RepresentationContract, EveryOptionIsAcceptedAtItsDefaultAndRefusedOutsideItsRange)
{
    test::gpu_context();
    // (that the bake options given at their defaults bake what none given bakes is proven by
    // RoundTripAndBakesAreByteIdentical's second bake)
    // the run-time options given at their defaults draw the picture none given draws
    RenderOptions given;
    for (const OptionSpec& spec : representation().render_options)
        if (!spec.default_value.empty()) given.values.set(spec.name, spec.default_value); // empty: derived
    Camera camera = orbit_camera(test::bunny().bounding_sphere(), OrbitView{}, 1.0f);
    auto picture = [&](const RenderOptions& options) {
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(package(), options);
        EXPECT_TRUE(renderer.is_ok()) << renderer.status().message();
        Result<RenderedImage> image = render_offscreen(**renderer, camera, default_light(camera), 96, 96);
        EXPECT_TRUE(image.is_ok());
        return image->color.pixels;
    };
    EXPECT_EQ(picture(given), picture(RenderOptions{}));

    // one step outside each declaration is refused, naming the option
    auto outside = [](const OptionSpec& spec) -> std::string {
        switch (spec.type) {
        case OptionType::integer: return std::to_string(std::int64_t(spec.max) + 1);
        case OptionType::number: return std::to_string(spec.max * 2.0 + 1.0);
        case OptionType::choice: return "no-such-choice";
        case OptionType::flag: return "maybe";
        }
        return "";
    };
    for (const OptionSpec& spec : representation().bake_options) {
        OptionValues bad;
        bad.set(spec.name, outside(spec));
        Result<SourceInfo> source = describe_source("", test::bunny());
        Result<std::unique_ptr<Package>> refused = bake_package(representation(), test::bunny(), *source, bad);
        ASSERT_FALSE(refused.is_ok()) << spec.name;
        EXPECT_EQ(refused.status().code(), StatusCode::invalid_argument) << spec.name;
        EXPECT_NE(refused.status().message().find("--" + spec.name), std::string::npos) << refused.status().message();
    }
    for (const OptionSpec& spec : representation().render_options) {
        RenderOptions bad;
        bad.values.set(spec.name, outside(spec));
        Result<std::unique_ptr<Renderer>> refused = make_package_renderer(package(), bad);
        ASSERT_FALSE(refused.is_ok()) << spec.name;
        EXPECT_NE(refused.status().message().find("--" + spec.name), std::string::npos) << refused.status().message();
    }
    // an option no representation declares, and a debug view it does not draw
    RenderOptions unknown;
    unknown.values.set("no-such-option", "1");
    EXPECT_FALSE(make_package_renderer(package(), unknown).is_ok());
    for (int v = 1; v < k_debug_view_count; ++v) {
        RenderOptions view;
        view.debug_view = DebugView(v);
        const auto& drawn = representation().debug_views;
        bool declared = std::find(drawn.begin(), drawn.end(), view.debug_view) != drawn.end();
        EXPECT_EQ(make_package_renderer(package(), view).is_ok(), declared) << debug_view_name(view.debug_view);
    }
}

// Renderers prepare what they upload on every core (the billboards a few at a time, the hidden
// proxies' depth buffers): one made and drawn on one thread draws the same picture, byte for byte.
TEST_P(RepresentationContract, DrawsTheSamePictureOnOneThreadAsOnEveryCore)
{
    test::gpu_context();
    Camera camera = orbit_camera(test::bunny().bounding_sphere(), OrbitView{}, 1.0f);
    auto picture = [&] {
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(package(), {});
        EXPECT_TRUE(renderer.is_ok()) << renderer.status().message();
        Result<RenderedImage> image = render_offscreen(**renderer, camera, default_light(camera), 128, 128);
        EXPECT_TRUE(image.is_ok());
        return image->color.pixels;
    };
    std::vector<std::uint8_t> one_thread;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        one_thread = picture();
    }
    EXPECT_EQ(one_thread, picture());
}

TEST_P(RepresentationContract, SilhouetteMatchesTheMeshFromFourteenDirections)
{
    test::gpu_context();
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(test::bunny());
    Result<std::unique_ptr<Renderer>> standin = make_package_renderer(package(), {});
    ASSERT_TRUE(truth.is_ok() && standin.is_ok()) << standin.status().message();
    for (glm::vec2 direction : fourteen_directions()) {
        OrbitView view;
        view.azimuth_degrees = direction.x;
        view.elevation_degrees = direction.y;
        Camera camera = orbit_camera(test::bunny().bounding_sphere(), view, 1.0f);
        Result<RenderedImage> t = render_offscreen(**truth, camera, default_light(camera), 256, 256);
        Result<RenderedImage> s = render_offscreen(**standin, camera, default_light(camera), 256, 256);
        ASSERT_TRUE(t.is_ok() && s.is_ok());
        ImageMetrics m = compare_images(t->color, s->color);
        EXPECT_GE(m.iou, 0.98) << "azimuth " << direction.x << ", elevation " << direction.y;
    }
}

// An instance under a mirroring transform (scale -1 along x, about the model's centre) draws the
// mirror image of the unmirrored instance: seen along the mirror plane, with a light in it, the
// picture flipped left to right. Renderers that pick faces by winding (boxes' front faces, hulls)
// must turn it for such transforms, or draw what lies behind.
TEST_P(RepresentationContract, MirroredInstanceDrawsTheMirrorImage)
{
    test::gpu_context();
    Result<std::unique_ptr<Renderer>> standin = make_package_renderer(package(), {});
    ASSERT_TRUE(standin.is_ok()) << standin.status().message();
    const double differing = test::mirrored_picture_difference(**standin, test::bunny().bounding_sphere(), 0.0f, 192);
    std::printf("[ mirror ] %s: %.3f%% of the pixels differ\n", GetParam().c_str(), 100.0 * differing);
    EXPECT_LT(differing, 0.01);
}

TEST_P(RepresentationContract, WritesTrueDepth)
{
    test::gpu_context();
    // a plane through the bounding sphere's centre, facing the camera at an angle: half the model
    // is in front of it, half behind
    BoundingSphere sphere = test::bunny().bounding_sphere();
    OrbitView view;
    view.azimuth_degrees = 40.0f;
    view.elevation_degrees = 15.0f;
    Camera camera = orbit_camera(sphere, view, 1.0f);
    glm::vec3 normal = glm::normalize(-camera.forward_world + glm::vec3(0.3f, 0.0f, 0.0f));
    const glm::vec4 blue(0.0f, 0.0f, 1.0f, 1.0f);
    Mesh wall = plate(sphere.center, sphere.radius * 1.5f, blue, normal);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(merged(test::bunny(), wall));
    Result<std::unique_ptr<Renderer>> wall_renderer = make_mesh_renderer(wall);
    Result<std::unique_ptr<Renderer>> standin = make_package_renderer(package(), {});
    ASSERT_TRUE(truth.is_ok() && wall_renderer.is_ok() && standin.is_ok());
    Scene scene({wall_renderer->get(), standin->get()});
    Result<RenderedImage> t = render_offscreen(**truth, camera, default_light(camera), 256, 256);
    Result<RenderedImage> s = render_offscreen(scene, camera, default_light(camera), 256, 256);
    Result<RenderedImage> model = render_offscreen(**standin, camera, default_light(camera), 256, 256);
    ASSERT_TRUE(t.is_ok() && s.is_ok() && model.is_ok());
    // per pixel the model covers: is the wall in front (its blue) or the model?
    auto wall_shows = [](const ImageRGBA8& image, std::size_t p) {
        const std::uint8_t* c = &image.pixels[p * 4];
        return c[2] > 2 * std::max(c[0], c[1]) + 20;
    };
    std::size_t covered = 0, agree = 0, wall_in_front = 0;
    for (std::size_t p = 0; p < model->color.pixels.size() / 4; ++p) {
        if (model->color.pixels[p * 4 + 3] == 0) continue;
        ++covered;
        bool truth_wall = wall_shows(t->color, p);
        wall_in_front += truth_wall;
        agree += truth_wall == wall_shows(s->color, p);
    }
    ASSERT_GT(covered, 1000u);
    EXPECT_GT(wall_in_front, covered / 10) << "the wall hides part of the model";
    EXPECT_LT(wall_in_front, covered * 9 / 10) << "and the model part of the wall";
    EXPECT_GE(double(agree) / double(covered), 0.97);
}

TEST_P(RepresentationContract, CastsTheMeshShadow)
{
    test::gpu_context();
    BoundingSphere sphere = test::bunny().bounding_sphere();
    Bounds box = test::bunny().bounds();
    const glm::vec4 grey(0.8f, 0.8f, 0.8f, 1.0f);
    Mesh ground = plate({sphere.center.x, box.min.y - 0.02f * sphere.radius, sphere.center.z}, sphere.radius * 2.0f, grey);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(merged(test::bunny(), ground));
    Result<std::unique_ptr<Renderer>> ground_renderer = make_mesh_renderer(ground);
    Result<std::unique_ptr<Renderer>> standin = make_package_renderer(package(), {});
    ASSERT_TRUE(truth.is_ok() && ground_renderer.is_ok() && standin.is_ok());
    Scene scene({ground_renderer->get(), standin->get()});
    OrbitView view;
    view.elevation_degrees = 60.0f;
    view.distance_rel = 1.6f;
    Camera camera = orbit_camera(sphere, view, 1.0f);
    Light light = light_from_angles(-35.0f, 55.0f);
    ShadowOptions shadows;
    shadows.enabled = true;
    shadows.scene = BoundingSphere{sphere.center, sphere.radius * 3.0f};
    shadows.resolution = 1024;
    Result<RenderedImage> lit = render_offscreen(*ground_renderer->get(), camera, light, 256, 256);
    Result<RenderedImage> t = render_offscreen(**truth, camera, light, 256, 256, {}, shadows);
    Result<RenderedImage> s = render_offscreen(scene, camera, light, 256, 256, {}, shadows);
    ASSERT_TRUE(lit.is_ok() && t.is_ok() && s.is_ok());
    // shadowed ground: ground pixels (the same depth as the unshadowed ground alone) darker than lit
    std::size_t both = 0, either = 0;
    for (std::size_t p = 0; p < lit->depth.size(); ++p) {
        if (lit->depth[p] >= 1.0f) continue;
        auto on_ground = [&](const RenderedImage& image) { return std::abs(image.depth[p] - lit->depth[p]) < 1e-6f; };
        auto dark = [&](const RenderedImage& image) { return on_ground(image) && image.color.pixels[p * 4] + 25 < lit->color.pixels[p * 4]; };
        bool a = dark(*t), b = dark(*s);
        both += a && b;
        either += a || b;
    }
    ASSERT_GT(either, 500u) << "the model casts a shadow on the ground";
    EXPECT_GE(double(both) / double(either), 0.85);
}

TEST_P(RepresentationContract, DamagedPackageIsRefusedInOneLine)
{
    std::string dir = test::fresh_directory("contract_damage_" + GetParam()) + "/p.standin";
    ASSERT_TRUE(write_package(package(), dir).is_ok());
    // the largest file, one byte changed in its middle
    std::string largest;
    std::uintmax_t largest_bytes = 0;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().filename() != "manifest.json" && entry.file_size() > largest_bytes)
            largest = entry.path().string(), largest_bytes = entry.file_size();
    ASSERT_FALSE(largest.empty());
    std::string bytes = *read_file(largest);
    bytes[bytes.size() / 2] ^= 0x5a;
    ASSERT_TRUE(write_file_atomic(largest, bytes).is_ok());
    Result<std::unique_ptr<Package>> damaged = read_package(dir);
    ASSERT_FALSE(damaged.is_ok());
    EXPECT_EQ(damaged.status().message().find('\n'), std::string::npos);
    EXPECT_NE(damaged.status().message().find(dir), std::string::npos) << damaged.status().message();

    // and a manifest cut short
    ASSERT_TRUE(write_package(package(), dir).is_ok());
    std::string manifest = *read_file(dir + "/manifest.json");
    ASSERT_TRUE(write_file_atomic(dir + "/manifest.json", manifest.substr(0, manifest.size() / 2)).is_ok());
    Result<std::unique_ptr<Package>> cut = read_package(dir);
    ASSERT_FALSE(cut.is_ok());
    EXPECT_EQ(cut.status().message().find('\n'), std::string::npos);
    EXPECT_NE(cut.status().message().find("manifest.json"), std::string::npos) << cut.status().message();
}

INSTANTIATE_TEST_SUITE_P(Registered, RepresentationContract, ::testing::ValuesIn(names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                             std::string name = info.param;
                             std::replace(name.begin(), name.end(), '-', '_');
                             return name;
                         });

} // namespace
} // namespace standin
