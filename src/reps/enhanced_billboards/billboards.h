// Enhanced billboards in memory (seed 000 §3.1, 001 §3.1): oriented boxes, each with a colour +
// coverage image and a normal + depth image over its front plane. Shared by the baker, the package
// codec and the renderer of this folder.
#pragma once

#include <standin/image.h>
#include <standin/package.h>

#include <glm/glm.hpp>

#include <map>
#include <string>
#include <vector>

namespace standin::billboards {

// Texel (i, j) covers the square origin + [i, i+1) * texel_size * axis_u + [j, j+1) * texel_size *
// axis_v on the front plane; row j of the images (j = 0 first in memory) is texel row j, and it is
// uploaded as texture row j (t = (j + 0.5) / height). Depth d in [0, 1] of a texel puts the
// surface at plane point + d * depth_range * direction.
struct Billboard {
    glm::vec3 origin{0.0f};        // world position of the plane corner at texel (0, 0)
    glm::vec3 axis_u{1, 0, 0};     // unit, along image columns
    glm::vec3 axis_v{0, 1, 0};     // unit, along image rows
    glm::vec3 direction{0, 0, -1}; // unit projection direction w, from the plane into the model
    float texel_size = 1.0f;       // world units per texel
    float depth_range = 1.0f;      // world units from the plane (depth 0) to depth 1
    int width = 0, height = 0;     // texels
    // RGB: albedo (sRGB-encoded), A: coverage (0 empty, 255 covered)
    ImageRGBA8 color;
    // RGB: shading normal, world space, encoded n * 0.5 + 0.5 in 16 bits; A: depth in [0,1] * 65535
    // (8-bit packages hold depth quantised to 8 bits, expanded to 16 in memory).
    ImageRGBA16 normal_depth;
    std::size_t captured_faces = 0;
    double captured_area = 0.0;    // world units squared of source surface rasterised here
};

// Why surface was left out of every billboard (manifest "left"): fractions of total area.
struct LeftOver {
    std::size_t faces = 0;
    double area = 0.0;
};

constexpr int k_max_grid_texels = 16384;        // texels along the diagonal
constexpr int k_default_direction_count = 256; // --directions sphere

// The bake parameters as the baker uses them (typed), read from the declared options
// (representation.cpp) by settings_from.
struct BakeSettings {
    int resolution = 512;        // texels along the bounding-box diagonal
    float texel_size = 0.0f;     // world units; 0: diagonal / resolution
    std::string directions = "seed"; // "seed" (36 x 18), "sphere" (even Fibonacci set), "axis" (+-X, +-Y, +-Z)
    int direction_count = 0;     // sphere only
    std::string score = "area";  // "area" (captured projected area) or "faces" (seed: facing faces)
    float depth_limit = 0.0f;    // fraction of the diagonal
    float grazing_angle = 0.0f;  // degrees from the plane below which faces are not projected
    int max_billboards = 0;
    float min_coverage = 0.0f;   // billboards capturing less than this fraction of area are dropped
    int depth_bits = 16;
    float coarse_ratio = 0.1f;
};

class EnhancedBillboardsPackage final : public Package {
public:
    std::string representation() const override { return "enhanced-billboards"; }

    Options parameters;    // as baked, derived values resolved (texel-size, direction-count)
    BakeSettings settings; // settings_from(parameters)
    std::vector<Billboard> billboards;
    Mesh coarse_mesh;                       // hole filling (seed §3.4); may be empty
    std::size_t faces_total = 0;
    double area_total = 0.0;
    double area_captured = 0.0;
    std::map<std::string, LeftOver> left;   // reason -> what was left
};

BakeSettings settings_from(const Options& parameters);

// The registry entry (representation.cpp): options, debug views and the functions below.
Representation registration();
Result<std::unique_ptr<Package>> bake(const BakeContext& context);
Status write(const Package& package, const std::string& directory);
Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest);
Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings);

} // namespace standin::billboards
