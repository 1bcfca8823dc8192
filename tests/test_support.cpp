#include "test_support.h"

#include <gtest/gtest.h>

#include <standin/files.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace standin::test {

namespace fs = std::filesystem;

std::string source_dir()
{
    const char* dir = std::getenv("STANDIN_SOURCE_DIR");
    return dir ? dir : STANDIN_TEST_SOURCE_DIR;
}

std::string cli_path()
{
    const char* path = std::getenv("STANDIN_CLI");
    return path ? path : STANDIN_TEST_CLI;
}

int line_count(const std::string& text) { return int(std::count(text.begin(), text.end(), '\n')); }

nlohmann::json read_json(const std::string& path)
{
    Result<std::string> text = read_file(path);
    EXPECT_TRUE(text.is_ok()) << path;
    return text ? nlohmann::json::parse(*text) : nlohmann::json();
}

void expect_near(glm::vec4 a, glm::vec4 b, float tolerance)
{
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], tolerance) << "component " << i;
}

std::string fresh_directory(const std::string& name)
{
    fs::path dir = fs::temp_directory_path() / ("standin_test_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
}

static std::string slurp(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

CommandResult run_command(const std::string& command_line)
{
    static int counter = 0;
    fs::path base = fs::temp_directory_path() / ("standin_cmd_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    std::string out = base.string() + ".out", err = base.string() + ".err";
    std::string full = command_line + " >" + out + " 2>" + err + " </dev/null";
    int status = std::system(full.c_str());
    CommandResult result;
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = slurp(out);
    result.err = slurp(err);
    fs::remove(out);
    fs::remove(err);
    return result;
}

CommandResult run_cli(const std::string& arguments) { return run_command(cli_path() + " " + arguments); }

GpuContext& gpu_context()
{
    static Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) {
        ADD_FAILURE() << context.status().message();
        std::abort();
    }
    return **context;
}

std::unique_ptr<Package> bake(const Mesh& mesh, const std::string& representation,
                              const std::vector<std::pair<std::string, std::string>>& values)
{
    SourceInfo source;
    source.bounds = mesh.bounds();
    OptionValues parameters;
    for (const auto& [name, value] : values) parameters.set(name, value);
    const Representation* r = find_representation(representation);
    EXPECT_TRUE(r) << representation;
    if (!r) return nullptr;
    Result<std::unique_ptr<Package>> package = bake_package(*r, mesh, source, parameters, {}, 1);
    EXPECT_TRUE(package.is_ok()) << package.status().message();
    return package.is_ok() ? std::move(*package) : nullptr;
}

Mesh generated(GeneratedShape shape, std::size_t triangles, std::optional<std::uint32_t> seed)
{
    GenerateOptions options;
    options.shape = shape;
    options.target_triangles = triangles;
    if (seed) options.seed = *seed;
    Result<Mesh> mesh = generate_mesh(options);
    EXPECT_TRUE(mesh.is_ok()) << (mesh.is_ok() ? "" : mesh.status().message());
    return mesh.is_ok() ? std::move(*mesh) : Mesh{};
}

const Mesh& bunny()
{
    static const Mesh mesh = [] {
        Result<Mesh> m = import_mesh(source_dir() + "/data/bunny.ply");
        EXPECT_TRUE(m.is_ok()) << (m.is_ok() ? "" : m.status().message());
        return m.is_ok() ? std::move(*m) : Mesh{};
    }();
    return mesh;
}

std::string base64(const std::string& bytes)
{
    static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t chunk = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) chunk |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) chunk |= std::uint8_t(bytes[i + 2]);
        out += alphabet[(chunk >> 18) & 63];
        out += alphabet[(chunk >> 12) & 63];
        out += i + 1 < bytes.size() ? alphabet[(chunk >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? alphabet[chunk & 63] : '=';
    }
    return out;
}

Texture painted_texture(const std::string& name, int size, const std::function<void(int x, int y, std::uint8_t* rgba)>& paint)
{
    Texture texture;
    texture.name = name;
    texture.width = texture.height = size;
    texture.rgba.resize(std::size_t(size) * std::size_t(size) * 4);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) paint(x, y, &texture.rgba[(std::size_t(y) * std::size_t(size) + std::size_t(x)) * 4]);
    return texture;
}

Material alpha_textured_material(const std::string& name, AlphaMode mode, float cutoff, bool double_sided)
{
    Material material;
    material.name = name;
    material.base_color = glm::vec4(1.0f);
    material.base_color_texture = 0;
    material.alpha_mode = mode;
    material.alpha_cutoff = cutoff;
    material.double_sided = double_sided;
    return material;
}

Mesh alpha_quad(AlphaMode mode, float cutoff, bool double_sided)
{
    const int size = 256;
    Mesh mesh;
    mesh.positions = {{-0.5f, -0.5f, 0.0f}, {0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 0.0f}, {-0.5f, 0.5f, 0.0f}};
    mesh.normals.assign(4, glm::vec3(0.0f, 0.0f, 1.0f));
    mesh.colors.assign(4, glm::vec4(1.0f));
    mesh.uvs = {{0.0f, 0.0f}, {1.0f, 0.0f}, {1.0f, 1.0f}, {0.0f, 1.0f}};
    mesh.indices = {0, 1, 2, 0, 2, 3};
    mesh.face_materials = {0, 0};
    mesh.textures.push_back(painted_texture("disc", size, [&](int x, int y, std::uint8_t* t) {
        double dx = (x + 0.5) / size - 0.5, dy = (y + 0.5) / size - 0.5;
        double alpha = std::clamp(1.0 - std::sqrt(dx * dx + dy * dy) / 0.5, 0.0, 1.0);
        t[0] = 40, t[1] = 200, t[2] = 60, t[3] = std::uint8_t(std::lround(alpha * 255.0));
    }));
    mesh.materials.push_back(alpha_textured_material("leaf", mode, cutoff, double_sided));
    return mesh;
}

Result<EvalResult> evaluate_views(Renderer& truth, Renderer& standin, const Mesh& mesh, const std::vector<float>& azimuths,
                                  const std::vector<float>& elevations, int width, int height)
{
    Protocol protocol;
    protocol.name = "sheets";
    for (float azimuth : azimuths)
        for (float elevation : elevations) {
            EvalView view;
            view.orbit.azimuth_degrees = azimuth;
            view.orbit.elevation_degrees = elevation;
            view.width = width;
            view.height = height;
            protocol.views.push_back(view);
        }
    EvalOptions options;
    options.timed_frames = 0;
    Result<EvalResult> result = evaluate(truth, standin, mesh.bounding_sphere(), protocol, options, {});
    EXPECT_TRUE(result.is_ok()) << result.status().message();
    return result;
}

Mesh sphere_over_single_sided_plane()
{
    Mesh mesh = generated(GeneratedShape::sphere, 800);
    for (glm::vec3& p : mesh.positions) p = 0.4f * p + glm::vec3(0.0f, 0.5f, 0.0f);
    Material plane_material;
    plane_material.double_sided = false;
    mesh.materials.push_back(plane_material);
    const std::uint32_t first = std::uint32_t(mesh.positions.size()), material = std::uint32_t(mesh.materials.size() - 1);
    for (glm::vec2 corner : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
        mesh.positions.push_back(glm::vec3(corner.x, 0.0f, corner.y));
        mesh.normals.push_back(glm::vec3(0, 1, 0));
        mesh.colors.push_back(glm::vec4(0.3f, 0.4f, 0.6f, 1.0f));
    }
    for (std::uint32_t i : {0u, 2u, 1u, 0u, 3u, 2u}) mesh.indices.push_back(first + i); // facing +y
    mesh.face_materials.push_back(material);
    mesh.face_materials.push_back(material);
    return mesh;
}

std::pair<double, double> worst_spill_and_iou(const Mesh& mesh, const Package& package, float elevation)
{
    auto truth = make_mesh_renderer(mesh);
    auto standin = make_package_renderer(package, RenderOptions{});
    EXPECT_TRUE(truth.is_ok() && standin.is_ok());
    if (!truth.is_ok() || !standin.is_ok()) return {1.0, 0.0};
    Result<EvalResult> result = evaluate_views(**truth, **standin, mesh, {0.0f, 130.0f}, {elevation}, 320, 240);
    double spill = 0.0, iou = 1.0;
    if (!result.is_ok()) return {1.0, 0.0};
    for (const ViewResult& v : result->views) {
        spill = std::max(spill, v.metrics.spill_fraction);
        iou = std::min(iou, v.metrics.iou);
    }
    return {spill, iou};
}

double mirrored_picture_difference(Renderer& renderer, const BoundingSphere& sphere, float elevation, int size)
{
    OrbitView view;
    view.elevation_degrees = elevation;
    const Camera camera = orbit_camera(sphere, view, 1.0f);
    Light light = default_light(camera);
    light.direction_to_light_world = glm::normalize(glm::vec3(0.0f, 0.6f, 0.8f));
    glm::mat4 mirror(1.0f);
    mirror[0][0] = -1.0f;
    mirror[3][0] = 2.0f * sphere.center.x; // x -> 2 c.x - x
    Result<RenderedImage> plain = render_offscreen(renderer, camera, light, size, size);
    Result<RenderedImage> mirrored = render_offscreen(renderer, camera, light, size, size, std::span<const glm::mat4>(&mirror, 1));
    EXPECT_TRUE(plain.is_ok() && mirrored.is_ok());
    if (!plain.is_ok() || !mirrored.is_ok()) return 1.0;
    float nearest = 1.0f, farthest = 0.0f;
    for (float d : plain->depth)
        if (d < 1.0f) nearest = std::min(nearest, d), farthest = std::max(farthest, d);
    std::size_t covered = 0, differing = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const std::size_t a = std::size_t(y) * std::size_t(size) + std::size_t(size - 1 - x), b = std::size_t(y) * std::size_t(size) + std::size_t(x);
            const std::uint8_t* ca = &plain->color.pixels[a * 4];
            const std::uint8_t* cb = &mirrored->color.pixels[b * 4];
            const bool in_a = ca[3] > 0, in_b = cb[3] > 0;
            if (!in_a && !in_b) continue;
            ++covered;
            bool differs = in_a != in_b || std::abs(plain->depth[a] - mirrored->depth[b]) > 1e-3f * (farthest - nearest);
            for (int c = 0; c < 3; ++c) differs = differs || std::abs(int(ca[c]) - int(cb[c])) > 8;
            differing += differs;
        }
    return covered > 0 ? double(differing) / double(covered) : 0.0;
}

} // namespace standin::test
