// Helpers shared by the tests: paths, running the CLI, one GL context per test process.
#pragma once

#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/eval.h>
#include <standin/render.h>

#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace standin::test {

// Whether this build is instrumented with AddressSanitizer (scripts/test's second lane, build-asan/):
// a test may leave to the Release lane what only repeats there the work its own first part already
// put under the sanitizers.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool k_sanitized_build = true;
#else
constexpr bool k_sanitized_build = false;
#endif

std::string source_dir();  // repository root
std::string cli_path();    // the built `standin` executable
// A new empty directory under the system temp dir, unique to this test process and name.
std::string fresh_directory(const std::string& name);

struct CommandResult {
    int exit_code = -1;
    std::string out, err;
};
// Lines in a program's output (newlines counted).
int line_count(const std::string& text);
// A JSON file the test wrote or had written; fails the test (and returns null) when unreadable.
nlohmann::json read_json(const std::string& path);
// Component-wise EXPECT_NEAR of two colours or points.
void expect_near(glm::vec4 a, glm::vec4 b, float tolerance = 1e-5f);

// Runs a shell command line, capturing stdout and stderr.
CommandResult run_command(const std::string& command_line);
// Runs `standin ARGS`.
CommandResult run_cli(const std::string& arguments);

// The process-wide headless GL context, created on first use; fails the test if none exists.
GpuContext& gpu_context();

// Bakes `mesh` as `representation` (registry name) with bake parameters NAME=VALUE on one thread;
// fails the test and returns null when the baker refuses.
std::unique_ptr<Package> bake(const Mesh& mesh, const std::string& representation,
                              const std::vector<std::pair<std::string, std::string>>& values);

// generate_mesh of `shape` with about `triangles` triangles (and `seed`, where given) and the other
// options at their defaults; fails the test (and returns an empty mesh) when the generator refuses.
Mesh generated(GeneratedShape shape, std::size_t triangles, std::optional<std::uint32_t> seed = std::nullopt);

// data/bunny.ply, imported once per process; fails the test (and is empty) when it cannot be read.
const Mesh& bunny();

// Standard base64 (RFC 4648, padded): the data URIs of glTF fixtures tests write.
std::string base64(const std::string& bytes);

// A size x size RGBA8 texture named `name`, each texel's four bytes written by paint(x, y, rgba).
Texture painted_texture(const std::string& name, int size, const std::function<void(int x, int y, std::uint8_t* rgba)>& paint);
// A material reading texture 0 over a white base colour, with `mode`, `cutoff` and sides.
Material alpha_textured_material(const std::string& name, AlphaMode mode, float cutoff, bool double_sided);

// A unit quad in the z = 0 plane facing +z (counter-clockwise seen from +z), UVs over [0, 1]^2, one
// material "leaf" of `mode`, `cutoff` and sides, textured with a green square whose alpha falls
// linearly from 1 at the centre to 0 at radius 0.5 of the side: cutoff c keeps the disc of radius
// 0.5 (1 - c), area pi (1 - c)^2 / 4 of the quad (issue #14's alpha tests, CPU and GPU).
Mesh alpha_quad(AlphaMode mode, float cutoff, bool double_sided);

// The stand-in against the truth from every azimuth x elevation (orbit cameras around the mesh's
// bounding sphere), untimed; fails the test when evaluation fails.
Result<EvalResult> evaluate_views(Renderer& truth, Renderer& standin, const Mesh& mesh, const std::vector<float>& azimuths,
                                  const std::vector<float>& elevations, int width, int height);

// A sphere (radius 0.4, centre y = 0.5) over a single-sided square at y = 0 facing +y, 2 units
// across (assimp's COLLADA.dae: text over a plane): the truth culls the square's back.
Mesh sphere_over_single_sided_plane();
// The largest spill fraction and the smallest IoU of `package` against the truth of `mesh` from
// azimuths 0 and 130 at `elevation`, 320 x 240.
std::pair<double, double> worst_spill_and_iou(const Mesh& mesh, const Package& package, float elevation);
// The share of the pixels covered in either picture where `renderer`'s picture of one instance
// mirrored across the plane x = sphere.center.x differs from its unmirrored picture flipped left to
// right (in coverage, by more than 8 in a colour channel, or in depth by more than a thousandth of
// the picture's depth range): seen from azimuth 0 at `elevation` (the camera in the mirror plane),
// lit from a direction in it. Renderers that cull by winding must turn it for mirroring instances.
double mirrored_picture_difference(Renderer& renderer, const BoundingSphere& sphere, float elevation, int size = 160);

} // namespace standin::test
