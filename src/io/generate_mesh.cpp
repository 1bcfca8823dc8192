// Procedural meshes for tests and scale benchmarks: a sphere, a torus, a noisy sphere, a shrub, a
// fur ball and a mechanical assembly (59 nested parts and thin shells) of about a requested number of triangles, bit-for-bit deterministic so that tests can
// compare results.
// The sphere is a cube-sphere with the equal-angle warp (tan of the angle along each cube face,
// as in equi-angular cubemaps): triangles vary in area by less than 1.5x, where a UV sphere
// piles slivers at the poles and an icosphere only comes in powers of four.
#include <standin/assembly.h>
#include <standin/mesh.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

namespace standin {

static constexpr std::size_t k_min_triangles = 8;
static constexpr std::size_t k_max_triangles = 50'000'000;

static Status check_options(const GenerateOptions& options)
{
    auto bad = [](const std::string& message) { return error(StatusCode::invalid_argument, "generate: " + message); };
    if (options.target_triangles < k_min_triangles || options.target_triangles > k_max_triangles)
        return bad("target_triangles = " + std::to_string(options.target_triangles) + " is outside [" +
                   std::to_string(k_min_triangles) + ", " + std::to_string(k_max_triangles) + "]");
    if (!std::isfinite(options.radius) || options.radius <= 0.0f)
        return bad("radius = " + std::to_string(options.radius) + " must be finite and positive");
    if (options.shape == GeneratedShape::torus &&
        (!std::isfinite(options.minor_radius) || options.minor_radius <= 0.0f || options.minor_radius >= options.radius))
        return bad("minor_radius = " + std::to_string(options.minor_radius) + " must be positive and below radius");
    if (options.shape == GeneratedShape::noisy_sphere &&
        (!std::isfinite(options.noise_amplitude) || options.noise_amplitude < 0.0f || options.noise_amplitude >= 1.0f))
        return bad("noise_amplitude = " + std::to_string(options.noise_amplitude) + " must be in [0, 1)");
    for (int c = 0; c < 4; ++c)
        if (!std::isfinite(options.color[c])) return bad("color is not finite");
    return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// Cube-sphere

// Position on the unit cube of lattice coordinate i in [0, n], warped so that equal steps of i
// are equal angles seen from the centre. The ends are exact so that faces meet bit for bit.
static float warped_cube_coordinate(std::uint32_t i, std::uint32_t n)
{
    if (i == 0) return -1.0f;
    if (i == n) return 1.0f;
    double s = 2.0 * double(i) / double(n) - 1.0;
    return float(std::tan(0.25 * std::numbers::pi * s));
}

struct SphereBuilder {
    std::uint32_t n = 1; // quads along each cube edge
    Mesh* mesh = nullptr;
    // lattice points on cube edges belong to two or three faces; they are looked up here so that
    // the sphere is one closed surface (only O(n) entries; face interiors are numbered directly)
    std::unordered_map<std::uint64_t, std::uint32_t> edge_vertices;

    std::uint32_t add_vertex(glm::uvec3 lattice)
    {
        glm::vec3 cube(warped_cube_coordinate(lattice.x, n), warped_cube_coordinate(lattice.y, n),
                       warped_cube_coordinate(lattice.z, n));
        mesh->positions.push_back(glm::normalize(cube));
        return std::uint32_t(mesh->positions.size() - 1);
    }

    std::uint32_t vertex_at(glm::uvec3 lattice)
    {
        int on_boundary = 0;
        for (int a = 0; a < 3; ++a) on_boundary += lattice[a] == 0 || lattice[a] == n;
        if (on_boundary < 2) return add_vertex(lattice); // interior of one face: visited once
        std::uint64_t key = (std::uint64_t(lattice.x) << 42) | (std::uint64_t(lattice.y) << 21) | lattice.z;
        auto [it, inserted] = edge_vertices.try_emplace(key, 0u);
        if (inserted) it->second = add_vertex(lattice);
        return it->second;
    }

    void add_quad(std::uint32_t c00, std::uint32_t c10, std::uint32_t c11, std::uint32_t c01)
    {
        // split along the shorter diagonal: better-shaped triangles near the cube's corners
        const std::vector<glm::vec3>& p = mesh->positions;
        bool main_diagonal = glm::length(p[c11] - p[c00]) <= glm::length(p[c01] - p[c10]);
        std::uint32_t quad[2][3] = {{c00, c10, c11}, {c00, c11, c01}};
        if (!main_diagonal) {
            std::uint32_t other[2][3] = {{c00, c10, c01}, {c10, c11, c01}};
            std::copy(&other[0][0], &other[0][0] + 6, &quad[0][0]);
        }
        mesh->indices.insert(mesh->indices.end(), &quad[0][0], &quad[0][0] + 6);
    }

    void add_face(int axis, bool positive)
    {
        int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3; // e_u x e_v = e_axis
        std::vector<std::uint32_t> grid(std::size_t(n + 1) * (n + 1));
        for (std::uint32_t v = 0; v <= n; ++v)
            for (std::uint32_t u = 0; u <= n; ++u) {
                glm::uvec3 lattice;
                lattice[axis] = positive ? n : 0;
                lattice[u_axis] = u;
                lattice[v_axis] = v;
                grid[std::size_t(v) * (n + 1) + u] = vertex_at(lattice);
            }
        for (std::uint32_t v = 0; v < n; ++v)
            for (std::uint32_t u = 0; u < n; ++u) {
                std::uint32_t c00 = grid[std::size_t(v) * (n + 1) + u], c10 = grid[std::size_t(v) * (n + 1) + u + 1];
                std::uint32_t c01 = grid[std::size_t(v + 1) * (n + 1) + u], c11 = grid[std::size_t(v + 1) * (n + 1) + u + 1];
                // counter-clockwise seen from outside: on a negative face the (u, v) frame is mirrored
                if (positive) add_quad(c00, c10, c11, c01);
                else add_quad(c00, c01, c11, c10);
            }
    }
};

// Unit sphere directions as positions; 12 n^2 triangles.
static void build_unit_cube_sphere(Mesh& mesh, std::size_t target_triangles)
{
    SphereBuilder builder;
    builder.n = std::max<std::uint32_t>(1, std::uint32_t(std::lround(std::sqrt(double(target_triangles) / 12.0))));
    builder.mesh = &mesh;
    std::size_t n = builder.n;
    mesh.positions.reserve(6 * n * n + 2);
    mesh.indices.reserve(36 * n * n);
    for (int axis = 0; axis < 3; ++axis) {
        builder.add_face(axis, true);
        builder.add_face(axis, false);
    }
}

// ---------------------------------------------------------------------------------------------
// Noise: value noise on the integer lattice, quintic-interpolated (C2, so shading normals are
// smooth), summed over octaves. Hash-based rather than a permutation table so that any seed works.

static std::uint32_t hash_lattice(glm::ivec3 cell, std::uint32_t seed)
{
    // murmur3's finaliser over a mix of the coordinates: cheap, and no visible axis-aligned patterns
    std::uint32_t h = seed * 0x9E3779B9u;
    h ^= std::uint32_t(cell.x) * 0x85EBCA6Bu;
    h = (h << 13) | (h >> 19);
    h ^= std::uint32_t(cell.y) * 0xC2B2AE35u;
    h = (h << 13) | (h >> 19);
    h ^= std::uint32_t(cell.z) * 0x27D4EB2Fu;
    h ^= h >> 16;
    h *= 0x85EBCA6Bu;
    h ^= h >> 13;
    h *= 0xC2B2AE35u;
    h ^= h >> 16;
    return h;
}

static float lattice_value(glm::ivec3 cell, std::uint32_t seed)
{
    return float(hash_lattice(cell, seed) >> 8) * (2.0f / 16777215.0f) - 1.0f; // [-1, 1]
}

static float value_noise(glm::vec3 p, std::uint32_t seed)
{
    glm::vec3 cell_f = glm::floor(p);
    glm::ivec3 cell(cell_f);
    glm::vec3 f = p - cell_f;
    glm::vec3 w = f * f * f * (f * (f * 6.0f - 15.0f) + 10.0f);
    float corners[2][2][2];
    for (int dz = 0; dz < 2; ++dz)
        for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx) corners[dz][dy][dx] = lattice_value(cell + glm::ivec3(dx, dy, dz), seed);
    float y0 = glm::mix(glm::mix(corners[0][0][0], corners[0][0][1], w.x), glm::mix(corners[0][1][0], corners[0][1][1], w.x), w.y);
    float y1 = glm::mix(glm::mix(corners[1][0][0], corners[1][0][1], w.x), glm::mix(corners[1][1][0], corners[1][1][1], w.x), w.y);
    return glm::mix(y0, y1, w.z);
}

// In [-1, 1]: octave weights are normalised to sum to one.
static float fractal_noise(glm::vec3 p, std::uint32_t seed)
{
    constexpr int k_octaves = 4;
    float sum = 0.0f, weight = 1.0f, total = 0.0f, frequency = 1.5f;
    for (int octave = 0; octave < k_octaves; ++octave) {
        sum += weight * value_noise(p * frequency, seed + std::uint32_t(octave) * 0x632BE5ABu);
        total += weight;
        weight *= 0.5f;
        frequency *= 2.0f;
    }
    return sum / total;
}

// ---------------------------------------------------------------------------------------------
// Shapes

static void make_sphere(Mesh& mesh, const GenerateOptions& options)
{
    build_unit_cube_sphere(mesh, options.target_triangles);
    mesh.normals = mesh.positions; // unit directions are the exact normals
    for (glm::vec3& p : mesh.positions) p *= options.radius;
}

static void make_noisy_sphere(Mesh& mesh, const GenerateOptions& options)
{
    build_unit_cube_sphere(mesh, options.target_triangles);
    float amplitude = options.noise_amplitude * options.radius;
    // each vertex depends only on its own direction, so the parallel loop stays deterministic
    tbb::parallel_for(std::size_t(0), mesh.positions.size(), [&](std::size_t v) {
        glm::vec3 direction = mesh.positions[v];
        mesh.positions[v] = direction * (options.radius + amplitude * fractal_noise(direction, options.seed));
    });
    compute_smooth_normals(mesh);
}

static void make_torus(Mesh& mesh, const GenerateOptions& options)
{
    // about square quads: segment counts in the ratio of the two circumferences
    double t = double(options.target_triangles);
    double ratio = double(options.radius) / double(options.minor_radius);
    std::uint32_t major = std::max<std::uint32_t>(3, std::uint32_t(std::lround(std::sqrt(0.5 * t * ratio))));
    std::uint32_t minor = std::max<std::uint32_t>(3, std::uint32_t(std::lround(0.5 * t / major)));

    mesh.positions.reserve(std::size_t(major) * minor);
    mesh.normals.reserve(std::size_t(major) * minor);
    for (std::uint32_t i = 0; i < major; ++i) {
        double phi = 2.0 * std::numbers::pi * i / major;
        for (std::uint32_t j = 0; j < minor; ++j) {
            double theta = 2.0 * std::numbers::pi * j / minor;
            glm::dvec3 normal(std::cos(theta) * std::cos(phi), std::sin(theta), std::cos(theta) * std::sin(phi));
            glm::dvec3 ring(options.radius * std::cos(phi), 0.0, options.radius * std::sin(phi));
            mesh.positions.push_back(glm::vec3(ring + double(options.minor_radius) * normal));
            mesh.normals.push_back(glm::vec3(normal));
        }
    }
    mesh.indices.reserve(std::size_t(major) * minor * 6);
    for (std::uint32_t i = 0; i < major; ++i)
        for (std::uint32_t j = 0; j < minor; ++j) {
            std::uint32_t i1 = (i + 1) % major, j1 = (j + 1) % minor;
            std::uint32_t c00 = i * minor + j, c10 = i1 * minor + j, c11 = i1 * minor + j1, c01 = i * minor + j1;
            // counter-clockwise seen from outside: d(phi) x d(theta) points along -normal
            mesh.indices.insert(mesh.indices.end(), {c00, c01, c11, c00, c11, c10});
        }
}

// ---------------------------------------------------------------------------------------------
// Intricate shapes: what Yamazaki et al. 2002 (microfacet billboarding) target and what a scanner,
// a mesh simplifier or a few billboards handle worst. Random choices come from one stream seeded by
// `seed`, taken in a fixed order, so a shape is bit-for-bit repeatable.

struct RandomStream {
    std::uint64_t state;
    std::uint64_t next() // splitmix64
    {
        std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }
    float uniform() { return float(next() >> 40) * (1.0f / 16777216.0f); } // [0, 1)
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
    glm::vec3 direction() // uniform over the sphere
    {
        float z = range(-1.0f, 1.0f), phi = range(0.0f, 2.0f * std::numbers::pi_v<float>), r = std::sqrt(1.0f - z * z);
        return {r * std::cos(phi), z, r * std::sin(phi)};
    }
};

static glm::vec3 perpendicular_to(glm::vec3 d)
{
    return glm::normalize(glm::cross(d, std::abs(d.y) < 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0)));
}

static void add_vertex(Mesh& mesh, glm::vec3 position, glm::vec3 normal, glm::vec4 color)
{
    mesh.positions.push_back(position);
    mesh.normals.push_back(glm::normalize(normal));
    mesh.colors.push_back(color);
}

// an open six-sided tube from a (radius ra) to b (radius rb): 12 triangles
static void add_tube(Mesh& mesh, glm::vec3 a, glm::vec3 b, float ra, float rb, glm::vec4 color)
{
    constexpr int k_sides = 6;
    glm::vec3 axis = glm::normalize(b - a), u = perpendicular_to(axis), v = glm::cross(axis, u);
    auto first = std::uint32_t(mesh.positions.size());
    for (int k = 0; k < k_sides; ++k) {
        float angle = 2.0f * std::numbers::pi_v<float> * float(k) / k_sides;
        glm::vec3 out = std::cos(angle) * u + std::sin(angle) * v;
        add_vertex(mesh, a + ra * out, out, color);
        add_vertex(mesh, b + rb * out, out, color);
    }
    for (std::uint32_t k = 0; k < k_sides; ++k) {
        std::uint32_t a0 = first + 2 * k, b0 = a0 + 1, a1 = first + 2 * ((k + 1) % k_sides), b1 = a1 + 1;
        mesh.indices.insert(mesh.indices.end(), {a0, a1, b1, a0, b1, b0});
    }
}

// Scales and moves a shape so that its bounding sphere (box centre, half diagonal) has `radius`
// about the origin.
static void fit_into_sphere(Mesh& mesh, float radius)
{
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    glm::vec3 center = 0.5f * (lo + hi);
    float scale = radius / (0.5f * glm::length(hi - lo));
    for (glm::vec3& p : mesh.positions) p = (p - center) * scale;
}

struct Twig {
    glm::vec3 base, tip;
};

// a branch and, below max_depth, its children: 3 (4 from the trunk) spread around it and upwards
static void grow_branch(Mesh& mesh, RandomStream& random, std::vector<Twig>& twigs, glm::vec3 base, glm::vec3 direction,
                        float length, float radius, int depth, int max_depth)
{
    const glm::vec4 bark(0.36f, 0.25f, 0.15f, 1.0f);
    glm::vec3 tip = base + direction * length;
    add_tube(mesh, base, tip, radius, radius * 0.7f, bark);
    if (depth == max_depth) {
        twigs.push_back({base, tip});
        return;
    }
    const int children = depth == 0 ? 4 : 3;
    glm::vec3 u = perpendicular_to(direction), v = glm::cross(direction, u);
    float turn = random.range(0.0f, 2.0f * std::numbers::pi_v<float>);
    for (int c = 0; c < children; ++c) {
        float around = turn + 2.0f * std::numbers::pi_v<float> * float(c) / float(children) + random.range(-0.3f, 0.3f);
        float tilt = glm::radians(random.range(28.0f, 52.0f));
        glm::vec3 side = std::cos(around) * u + std::sin(around) * v;
        glm::vec3 child = glm::normalize(std::cos(tilt) * direction + std::sin(tilt) * side + glm::vec3(0.0f, 0.25f, 0.0f));
        glm::vec3 at = base + direction * length * random.range(0.55f, 1.0f);
        grow_branch(mesh, random, twigs, at, child, length * random.range(0.62f, 0.78f), radius * 0.6f, depth + 1, max_depth);
    }
}

static void make_shrub(Mesh& mesh, const GenerateOptions& options)
{
    RandomStream random{options.seed};
    // the branches: deeper for larger shrubs, so leaves have twigs to sit on (12 triangles each)
    const std::size_t target = options.target_triangles;
    const int max_depth = target >= 8000 ? 4 : (target >= 1500 ? 3 : (target >= 300 ? 2 : 0));
    std::vector<Twig> twigs;
    grow_branch(mesh, random, twigs, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, 0.05f, 0, max_depth);
    // the leaves: diamond cards of two triangles around the twigs, turned every way, greens varied
    std::size_t branch_triangles = mesh.indices.size() / 3;
    std::size_t leaves = std::max<std::size_t>(1, (target > branch_triangles ? target - branch_triangles : 2) / 2);
    const float leaf_length = 0.11f;
    for (std::size_t k = 0; k < leaves; ++k) {
        const Twig& twig = twigs[k % twigs.size()];
        glm::vec3 base = glm::mix(twig.base, twig.tip, random.range(0.15f, 1.0f)) + random.direction() * random.range(0.0f, 0.08f);
        glm::vec3 along = glm::normalize(twig.tip - twig.base);
        glm::vec3 direction = glm::normalize(0.6f * along + random.direction());
        glm::vec3 across = perpendicular_to(direction);
        float roll = random.range(0.0f, 2.0f * std::numbers::pi_v<float>);
        across = std::cos(roll) * across + std::sin(roll) * glm::cross(direction, across);
        glm::vec3 normal = glm::cross(direction, across);
        float length = leaf_length * random.range(0.7f, 1.3f), width = length * random.range(0.35f, 0.5f);
        glm::vec4 green(random.range(0.12f, 0.3f), random.range(0.35f, 0.6f), random.range(0.08f, 0.2f), 1.0f);
        auto first = std::uint32_t(mesh.positions.size());
        add_vertex(mesh, base, normal, green);
        add_vertex(mesh, base + 0.45f * length * direction + 0.5f * width * across, normal, green);
        add_vertex(mesh, base + length * direction, normal, green);
        add_vertex(mesh, base + 0.45f * length * direction - 0.5f * width * across, normal, green);
        mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    }
    fit_into_sphere(mesh, options.radius);
}

// A cut-out's colour bleeds one texel outwards, so bilinear lookups at its edge do not darken
// towards the (black) outside.
static void bleed_cut_out_colour(Texture& texture)
{
    const int w = texture.width, h = texture.height;
    std::vector<std::uint8_t> grown = texture.rgba;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            std::uint8_t* texel = &grown[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4];
            if (texel[3] != 0) continue;
            for (int d = 0; d < 4; ++d) {
                int nx = x + (d == 0) - (d == 1), ny = y + (d == 2) - (d == 3);
                if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const std::uint8_t* n = &texture.rgba[(std::size_t(ny) * std::size_t(w) + std::size_t(nx)) * 4];
                if (n[3] == 0) continue;
                std::copy(n, n + 3, texel);
                break;
            }
        }
    texture.rgba = std::move(grown);
}

// A square leaf card of side `size`, its bottom edge's middle at `base`, spanning `across` and `up`
// (unit, perpendicular), UVs 0..1 with v = 0 at the bottom, white (the texture gives the colour).
static void add_leaf_card(Mesh& mesh, glm::vec3 base, glm::vec3 across, glm::vec3 up, float size)
{
    const glm::vec3 normal = glm::cross(across, up);
    auto first = std::uint32_t(mesh.positions.size());
    const glm::vec2 corners[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const glm::vec2& c : corners) {
        add_vertex(mesh, base + size * ((c.x - 0.5f) * across + c.y * up), normal, glm::vec4(1.0f));
        mesh.uvs.push_back(c);
    }
    mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
}

// The end of a leaf-card model: the bark's vertices (the first `bark_vertices`) get UVs, the model is
// fitted into the sphere, and it gets its two materials: 0 the bark (opaque), 1 the leaves (mask at
// 0.5, double-sided, white, `leaf_texture`) for every face after the first `bark_triangles`.
static void finish_leaf_model(Mesh& mesh, const GenerateOptions& options, Texture leaf_texture, std::size_t bark_vertices,
                              std::size_t bark_triangles)
{
    mesh.uvs.insert(mesh.uvs.begin(), bark_vertices, glm::vec2(0.0f));
    fit_into_sphere(mesh, options.radius);
    mesh.textures.push_back(std::move(leaf_texture));
    Material bark, leaves;
    bark.name = "bark";
    bark.base_color = glm::vec4(0.36f, 0.25f, 0.15f, 1.0f);
    leaves.name = "leaves";
    leaves.base_color = glm::vec4(1.0f);
    leaves.base_color_texture = 0;
    leaves.alpha_mode = AlphaMode::mask;
    leaves.alpha_cutoff = 0.5f;
    leaves.double_sided = true;
    mesh.materials = {bark, leaves};
    mesh.face_materials.assign(mesh.triangle_count(), 1u);
    std::fill(mesh.face_materials.begin(), mesh.face_materials.begin() + std::ptrdiff_t(bark_triangles), 0u);
}

// The tree's leaf texture: a spray of three pointed leaves fanning out from the bottom centre of a
// square, with darker mid-ribs; alpha 255 inside a leaf, 0 outside (binary, so the cut-out does not
// depend on the cutoff between 0 and 1). Row 0 at v = 0 (Texture), the spray's stem at v = 0.
static Texture make_leaf_texture()
{
    constexpr int k_size = 128;
    Texture texture;
    texture.name = "leaf";
    texture.width = texture.height = k_size;
    texture.rgba.assign(std::size_t(k_size) * k_size * 4, 0);
    const float angles[3] = {-0.55f, 0.0f, 0.55f}, lengths[3] = {0.78f, 0.95f, 0.78f};
    const glm::vec3 greens[3] = {{0.20f, 0.47f, 0.12f}, {0.27f, 0.56f, 0.15f}, {0.22f, 0.50f, 0.10f}};
    for (int y = 0; y < k_size; ++y)
        for (int x = 0; x < k_size; ++x) {
            glm::vec2 p((float(x) + 0.5f) / k_size - 0.5f, (float(y) + 0.5f) / k_size - 0.02f);
            for (int l = 0; l < 3; ++l) {
                // the leaf's own frame: t along its rib from the stem (0) to the tip (1), s across
                glm::vec2 along(std::sin(angles[l]), std::cos(angles[l])), across(along.y, -along.x);
                float t = glm::dot(p, along) / lengths[l], s = glm::dot(p, across) / lengths[l];
                if (t <= 0.04f || t >= 1.0f) continue;
                float half_width = 0.2f * std::pow(std::sin(std::numbers::pi_v<float> * std::pow(t, 0.8f)), 0.9f);
                if (std::abs(s) >= half_width) continue;
                float rib = std::abs(s) < 0.012f ? 0.7f : 1.0f;
                glm::vec3 c = greens[l] * rib * (0.85f + 0.3f * std::abs(s) / 0.2f);
                std::uint8_t* texel = &texture.rgba[(std::size_t(y) * k_size + std::size_t(x)) * 4];
                for (int k = 0; k < 3; ++k) texel[k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
                texel[3] = 255;
                break;
            }
        }
    bleed_cut_out_colour(texture);
    return texture;
}

// A tree of leaf cards: a trunk and branches (grow_branch's tubes, bark), then square cards carrying
// the leaf texture around the twigs, stem end at the twig, turned every way. Material 0 is the bark
// (opaque), material 1 the leaves (mask at 0.5, double-sided, white: the colour is the texture's).
static void make_tree(Mesh& mesh, const GenerateOptions& options)
{
    RandomStream random{options.seed};
    const std::size_t target = options.target_triangles;
    const int max_depth = target >= 6000 ? 4 : (target >= 1200 ? 3 : (target >= 200 ? 2 : 1));
    std::vector<Twig> twigs;
    grow_branch(mesh, random, twigs, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 1.0f, 0.07f, 0, max_depth);
    const std::size_t bark_vertices = mesh.positions.size(), bark_triangles = mesh.indices.size() / 3;
    std::size_t cards = std::max<std::size_t>(1, (target > bark_triangles ? target - bark_triangles : 2) / 2);
    const float card_size = 0.36f * std::pow(0.72f, float(max_depth - 2)) * std::max(0.6f, std::sqrt(600.0f / float(cards)));
    for (std::size_t k = 0; k < cards; ++k) {
        const Twig& twig = twigs[k % twigs.size()];
        glm::vec3 base = glm::mix(twig.base, twig.tip, random.range(0.3f, 1.0f)) + random.direction() * random.range(0.0f, 0.05f);
        glm::vec3 along = glm::normalize(twig.tip - twig.base);
        glm::vec3 up = glm::normalize(0.5f * along + random.direction() + glm::vec3(0.0f, 0.3f, 0.0f));
        glm::vec3 across = perpendicular_to(up);
        float roll = random.range(0.0f, 2.0f * std::numbers::pi_v<float>);
        across = std::cos(roll) * across + std::sin(roll) * glm::cross(up, across);
        add_leaf_card(mesh, base, across, up, card_size * random.range(0.8f, 1.2f));
    }
    finish_leaf_model(mesh, options, make_leaf_texture(), bark_vertices, bark_triangles);
}

// A leaf-cluster texture as game foliage uses it: a sprig of many small leaves on one card (a stem
// up the middle, leaves in alternate pairs along it and a few at its tip, tilted outwards, each
// its own green), alpha 255 on leaf and stem, 0 elsewhere. Row 0 at v = 0, the stem's foot there.
static Texture make_leaf_cluster_texture()
{
    constexpr int k_size = 512;
    Texture texture;
    texture.name = "leaf_cluster";
    texture.width = texture.height = k_size;
    texture.rgba.assign(std::size_t(k_size) * k_size * 4, 0);
    struct Leaf {
        glm::vec2 base, along;
        float length, width;
        glm::vec3 green;
    };
    std::vector<Leaf> leaves;
    RandomStream random{0x1eafu}; // the texture is the same for every seed, as a model's would be
    const int pairs = 9;
    for (int k = 0; k < pairs; ++k) {
        float t = 0.1f + 0.78f * float(k) / float(pairs - 1);
        for (int side = -1; side <= 1; side += 2) {
            float angle = float(side) * random.range(0.55f, 1.05f) * (1.0f - 0.35f * t);
            float length = random.range(0.16f, 0.24f) * (1.0f - 0.3f * t);
            glm::vec3 green(random.range(0.14f, 0.30f), random.range(0.38f, 0.60f), random.range(0.07f, 0.18f));
            leaves.push_back({{0.5f, t}, {std::sin(angle), std::cos(angle)}, length, length * random.range(0.3f, 0.42f), green});
        }
    }
    leaves.push_back({{0.5f, 0.9f}, {0.0f, 1.0f}, 0.1f, 0.04f, {0.25f, 0.55f, 0.14f}});
    const glm::vec3 stem(0.30f, 0.24f, 0.12f);
    for (int y = 0; y < k_size; ++y)
        for (int x = 0; x < k_size; ++x) {
            glm::vec2 p((float(x) + 0.5f) / k_size, (float(y) + 0.5f) / k_size);
            std::uint8_t* texel = &texture.rgba[(std::size_t(y) * k_size + std::size_t(x)) * 4];
            glm::vec3 c;
            bool inside = false;
            for (const Leaf& leaf : leaves) {
                glm::vec2 d = p - leaf.base, across(leaf.along.y, -leaf.along.x);
                float t = glm::dot(d, leaf.along) / leaf.length, s = glm::dot(d, across) / leaf.length;
                if (t <= 0.0f || t >= 1.0f) continue;
                float half_width = 0.5f * leaf.width / leaf.length * std::pow(std::sin(std::numbers::pi_v<float> * std::pow(t, 0.7f)), 0.8f);
                if (std::abs(s) >= half_width) continue;
                c = leaf.green * (std::abs(s) < 0.02f ? 0.72f : 0.88f + 0.25f * std::abs(s) / half_width);
                inside = true;
                break;
            }
            if (!inside && std::abs(p.x - 0.5f) < 0.006f && p.y > 0.0f && p.y < 0.95f) c = stem, inside = true;
            if (!inside) continue;
            for (int k = 0; k < 3; ++k) texel[k] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
            texel[3] = 255;
        }
    bleed_cut_out_colour(texture);
    return texture;
}

// A bush of leaf-cluster cards, the way game foliage is modelled (unlike the tree's one leaf per
// card): branches (grow_branch, bark), and at their twigs sprigs of two cards crossed at right
// angles through their stem (the cards intersect), each carrying make_leaf_cluster_texture. The
// cards are large against the bush, and a texel of the model spans many leaves' edges. Materials as
// the tree's: 0 bark (opaque), 1 leaves (mask at 0.5, double-sided, white).
static void make_bush(Mesh& mesh, const GenerateOptions& options)
{
    RandomStream random{options.seed};
    const std::size_t target = options.target_triangles;
    const int max_depth = target >= 3000 ? 3 : (target >= 400 ? 2 : 1);
    std::vector<Twig> twigs;
    grow_branch(mesh, random, twigs, glm::vec3(0.0f), glm::vec3(0.0f, 1.0f, 0.0f), 0.8f, 0.06f, 0, max_depth);
    const std::size_t bark_vertices = mesh.positions.size(), bark_triangles = mesh.indices.size() / 3;
    std::size_t sprigs = std::max<std::size_t>(1, (target > bark_triangles ? target - bark_triangles : 4) / 4);
    const float card_size = 0.55f * std::pow(0.75f, float(max_depth - 1)) * std::max(0.5f, std::sqrt(120.0f / float(sprigs)));
    for (std::size_t k = 0; k < sprigs; ++k) {
        const Twig& twig = twigs[k % twigs.size()];
        glm::vec3 base = glm::mix(twig.base, twig.tip, random.range(0.2f, 1.0f)) + random.direction() * random.range(0.0f, 0.04f);
        glm::vec3 along = glm::normalize(twig.tip - twig.base);
        glm::vec3 up = glm::normalize(along + 0.6f * random.direction() + glm::vec3(0.0f, 0.2f, 0.0f));
        glm::vec3 across = perpendicular_to(up);
        float roll = random.range(0.0f, 2.0f * std::numbers::pi_v<float>);
        across = std::cos(roll) * across + std::sin(roll) * glm::cross(up, across);
        float size = card_size * random.range(0.8f, 1.2f);
        add_leaf_card(mesh, base, across, up, size);
        add_leaf_card(mesh, base, glm::cross(up, across), up, size);
    }
    finish_leaf_model(mesh, options, make_leaf_cluster_texture(), bark_vertices, bark_triangles);
}

static void make_fur_ball(Mesh& mesh, const GenerateOptions& options)
{
    RandomStream random{options.seed};
    const glm::vec4 root(0.28f, 0.17f, 0.09f, 1.0f), tip(0.86f, 0.72f, 0.52f, 1.0f);
    // the body: a cube-sphere of radius 0.7 with a fifth of the triangles, the colour of the roots
    build_unit_cube_sphere(mesh, std::max<std::size_t>(48, options.target_triangles / 5));
    mesh.normals = mesh.positions;
    for (glm::vec3& p : mesh.positions) p *= 0.7f;
    mesh.colors.assign(mesh.positions.size(), root);
    // the hair: ribbons of 3 segments (6 triangles) from the body outwards, bending down, tapering
    constexpr int k_segments = 3;
    std::size_t body = mesh.indices.size() / 3;
    std::size_t hairs = std::max<std::size_t>(1, (options.target_triangles > body ? options.target_triangles - body : 6) / (2 * k_segments));
    for (std::size_t h = 0; h < hairs; ++h) {
        glm::vec3 radial = random.direction();
        glm::vec3 direction = glm::normalize(radial + 0.55f * random.direction());
        if (glm::dot(direction, radial) < 0.3f) direction = glm::normalize(direction + radial);
        float length = 0.3f * random.range(0.6f, 1.2f), shade = random.range(0.85f, 1.15f);
        glm::vec3 across = glm::normalize(glm::cross(direction, radial) + 1e-3f * perpendicular_to(direction));
        glm::vec3 p = radial * 0.69f;
        auto first = std::uint32_t(mesh.positions.size());
        for (int s = 0; s <= k_segments; ++s) {
            float t = float(s) / k_segments, half_width = 0.5f * length * 0.05f * (1.0f - 0.7f * t);
            glm::vec3 normal = glm::cross(across, direction);
            if (glm::dot(normal, radial) < 0.0f) normal = -normal;
            glm::vec4 color = glm::clamp(glm::mix(root, tip, t) * shade, 0.0f, 1.0f);
            color.w = 1.0f;
            add_vertex(mesh, p - half_width * across, normal, color);
            add_vertex(mesh, p + half_width * across, normal, color);
            p += direction * (length / k_segments);
            direction = glm::normalize(direction + glm::vec3(0.0f, -0.3f, 0.0f) / float(k_segments));
        }
        for (std::uint32_t s = 0; s < k_segments; ++s) {
            std::uint32_t a = first + 2 * s;
            mesh.indices.insert(mesh.indices.end(), {a, a + 1, a + 3, a, a + 3, a + 2});
        }
    }
    fit_into_sphere(mesh, options.radius);
}

// A zero-thickness tube (one sheet, open at both ends), normals pointing away from the axis.
static void add_sheet_tube(Mesh& mesh, glm::vec3 a, glm::vec3 b, float radius, int sides, int rings, glm::vec4 color)
{
    glm::vec3 axis = glm::normalize(b - a), u = perpendicular_to(axis), v = glm::cross(axis, u);
    auto first = std::uint32_t(mesh.positions.size());
    for (int r = 0; r <= rings; ++r) {
        glm::vec3 centre = glm::mix(a, b, float(r) / float(rings));
        for (int k = 0; k < sides; ++k) {
            float angle = 2.0f * std::numbers::pi_v<float> * float(k) / float(sides);
            glm::vec3 out = std::cos(angle) * u + std::sin(angle) * v;
            add_vertex(mesh, centre + radius * out, out, color);
        }
    }
    for (int r = 0; r < rings; ++r) {
        for (int k = 0; k < sides; ++k) {
            std::uint32_t a0 = first + std::uint32_t(r * sides + k), a1 = first + std::uint32_t(r * sides + (k + 1) % sides);
            std::uint32_t b0 = a0 + std::uint32_t(sides), b1 = a1 + std::uint32_t(sides);
            mesh.indices.insert(mesh.indices.end(), {a0, a1, b1, a0, b1, b0});
        }
    }
}

// A closed cylinder from a to b: `sides` around, `rings` along, flat caps (fans), outward normals.
static void add_cylinder(Mesh& mesh, glm::vec3 a, glm::vec3 b, float radius, int sides, int rings, glm::vec4 color)
{
    add_sheet_tube(mesh, a, b, radius, sides, rings, color);
    glm::vec3 axis = glm::normalize(b - a), u = perpendicular_to(axis), v = glm::cross(axis, u);
    for (int end = 0; end < 2; ++end) {
        glm::vec3 centre = end == 0 ? a : b, normal = end == 0 ? -axis : axis;
        auto hub = std::uint32_t(mesh.positions.size());
        add_vertex(mesh, centre, normal, color);
        for (int k = 0; k < sides; ++k) {
            float angle = 2.0f * std::numbers::pi_v<float> * float(k) / float(sides);
            add_vertex(mesh, centre + radius * (std::cos(angle) * u + std::sin(angle) * v), normal, color);
        }
        for (int k = 0; k < sides; ++k) {
            std::uint32_t p0 = hub + 1 + std::uint32_t(k), p1 = hub + 1 + std::uint32_t((k + 1) % sides);
            if (end == 0) mesh.indices.insert(mesh.indices.end(), {hub, p1, p0});
            else mesh.indices.insert(mesh.indices.end(), {hub, p0, p1});
        }
    }
}

// A flat ring of `sides` quads between radii inner and outer in the plane of u and v, every vertex
// with `normal`; quads wind counter-clockwise from u towards v, or the other way when `reversed`.
static void add_ring(Mesh& mesh, glm::vec3 centre, glm::vec3 u, glm::vec3 v, glm::vec3 normal, float inner, float outer,
                     int sides, glm::vec4 color, bool reversed)
{
    auto first = std::uint32_t(mesh.positions.size());
    for (int k = 0; k < sides; ++k) {
        float angle = 2.0f * std::numbers::pi_v<float> * float(k) / float(sides);
        glm::vec3 out = std::cos(angle) * u + std::sin(angle) * v;
        add_vertex(mesh, centre + outer * out, normal, color);
        add_vertex(mesh, centre + inner * out, normal, color);
    }
    for (int k = 0; k < sides; ++k) {
        std::uint32_t o0 = first + 2 * std::uint32_t(k), i0 = o0 + 1;
        std::uint32_t o1 = first + 2 * std::uint32_t((k + 1) % sides), i1 = o1 + 1;
        if (reversed) mesh.indices.insert(mesh.indices.end(), {o0, i1, o1, o0, i0, i1});
        else mesh.indices.insert(mesh.indices.end(), {o0, o1, i1, o0, i1, i0});
    }
}

// A thin-walled tube from a to b (a hollow part: outer wall, inner wall facing the axis, annular
// ends), open at both ends so that what it holds shows only through them.
static void add_shell(Mesh& mesh, glm::vec3 a, glm::vec3 b, float outer, float inner, int sides, int rings, glm::vec4 color)
{
    glm::vec3 axis = glm::normalize(b - a), u = perpendicular_to(axis), v = glm::cross(axis, u);
    for (int wall = 0; wall < 2; ++wall) {
        float radius = wall == 0 ? outer : inner, sign = wall == 0 ? 1.0f : -1.0f;
        auto first = std::uint32_t(mesh.positions.size());
        for (int r = 0; r <= rings; ++r) {
            glm::vec3 centre = glm::mix(a, b, float(r) / float(rings));
            for (int k = 0; k < sides; ++k) {
                float angle = 2.0f * std::numbers::pi_v<float> * float(k) / float(sides);
                glm::vec3 out = std::cos(angle) * u + std::sin(angle) * v;
                add_vertex(mesh, centre + radius * out, sign * out, color);
            }
        }
        for (int r = 0; r < rings; ++r) {
            for (int k = 0; k < sides; ++k) {
                std::uint32_t a0 = first + std::uint32_t(r * sides + k), a1 = first + std::uint32_t(r * sides + (k + 1) % sides);
                std::uint32_t b0 = a0 + std::uint32_t(sides), b1 = a1 + std::uint32_t(sides);
                if (wall == 0) mesh.indices.insert(mesh.indices.end(), {a0, a1, b1, a0, b1, b0});
                else mesh.indices.insert(mesh.indices.end(), {a0, b1, a1, a0, b0, b1});
            }
        }
    }
    for (int end = 0; end < 2; ++end)
        add_ring(mesh, end == 0 ? a : b, u, v, end == 0 ? -axis : axis, inner, outer, sides, color, end == 0);
}

// An axis-aligned box, four vertices per face (flat normals).
static void add_box(Mesh& mesh, glm::vec3 lo, glm::vec3 hi, glm::vec4 color)
{
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            glm::vec3 normal(0.0f);
            normal[axis] = side == 0 ? -1.0f : 1.0f;
            int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            auto first = std::uint32_t(mesh.positions.size());
            for (int c = 0; c < 4; ++c) {
                glm::vec3 p;
                p[axis] = side == 0 ? lo[axis] : hi[axis];
                p[a1] = (c & 1) ? hi[a1] : lo[a1];
                p[a2] = (c & 2) ? hi[a2] : lo[a2];
                add_vertex(mesh, p, normal, color);
            }
            // corners 0 (lo, lo), 1 (hi, lo), 3 (hi, hi), 2 (lo, hi) are counter-clockwise about +axis
            if (side == 1) mesh.indices.insert(mesh.indices.end(), {first, first + 1, first + 3, first, first + 3, first + 2});
            else mesh.indices.insert(mesh.indices.end(), {first, first + 3, first + 1, first, first + 2, first + 3});
        }
    }
}

// A mechanical assembly of 59 parts: a thin-walled casing open at both ends holding six liners
// (thin shells) with a piston each, rods, wrist pins, a crankshaft and a camshaft; two annular
// flanges with twelve bolts each, four feet and two pulleys. Nested parts, thin shells and many
// small parts, the case where image-based stand-ins lose surface. `detail` sets the tessellation.
static void build_assembly(Mesh& mesh, int detail)
{
    const glm::vec4 steel(0.62f, 0.64f, 0.68f, 1.0f), dark(0.25f, 0.26f, 0.3f, 1.0f), brass(0.78f, 0.6f, 0.25f, 1.0f),
        red(0.7f, 0.18f, 0.15f, 1.0f), blue(0.2f, 0.35f, 0.7f, 1.0f), green(0.25f, 0.55f, 0.3f, 1.0f);
    int big = std::max(8, 4 * detail), small = std::max(6, detail), rings = std::max(1, detail);
    add_shell(mesh, {-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.6f, 0.57f, big, 2 * rings, blue); // casing
    add_cylinder(mesh, {-1.25f, 0.0f, 0.0f}, {1.25f, 0.0f, 0.0f}, 0.06f, small, 2 * rings, steel); // crankshaft
    add_cylinder(mesh, {-1.1f, 0.42f, 0.0f}, {1.1f, 0.42f, 0.0f}, 0.03f, small, 2 * rings, steel); // camshaft
    for (int c = 0; c < 6; ++c) {
        float x = -0.75f + 0.3f * float(c), phase = float(c % 3) * 0.05f;
        add_shell(mesh, {x, -0.15f, 0.0f}, {x, 0.5f, 0.0f}, 0.11f, 0.1f, 2 * small, rings, green); // liner
        add_cylinder(mesh, {x, 0.12f + phase, 0.0f}, {x, 0.3f + phase, 0.0f}, 0.095f, 2 * small, rings, dark); // piston
        add_box(mesh, {x - 0.02f, 0.0f, -0.025f}, {x + 0.02f, 0.18f + phase, 0.025f}, steel); // rod
        add_cylinder(mesh, {x - 0.08f, 0.18f + phase, 0.0f}, {x + 0.08f, 0.18f + phase, 0.0f}, 0.015f, small, 1, brass); // pin
    }
    for (int side = 0; side < 2; ++side) {
        float x = side == 0 ? -1.0f : 1.0f, out = side == 0 ? -0.03f : 0.03f;
        add_shell(mesh, {x, 0.0f, 0.0f}, {x + out, 0.0f, 0.0f}, 0.72f, 0.45f, big, 1, red); // flange
        for (int k = 0; k < 12; ++k) {
            float angle = 2.0f * std::numbers::pi_v<float> * (float(k) + 0.5f) / 12.0f;
            glm::vec3 p(x + out, 0.66f * std::cos(angle), 0.66f * std::sin(angle));
            add_cylinder(mesh, p, p + glm::vec3(2.0f * out, 0.0f, 0.0f), 0.025f, small, 1, brass); // bolt
        }
        add_cylinder(mesh, {x + 4.0f * out, 0.0f, 0.0f}, {x + 6.0f * out, 0.0f, 0.0f}, 0.25f, big, rings, dark); // pulley
    }
    for (int foot = 0; foot < 4; ++foot) {
        float x = foot < 2 ? -0.7f : 0.5f, z = foot % 2 == 0 ? -0.45f : 0.25f;
        add_box(mesh, {x, -0.75f, z}, {x + 0.2f, -0.55f, z + 0.2f}, steel);
    }
}

// A flat zero-thickness ring about `axis` through `centre`, facing +axis.
static void add_annulus(Mesh& mesh, glm::vec3 centre, glm::vec3 axis, float inner, float outer, int sides, glm::vec4 color)
{
    glm::vec3 u = perpendicular_to(axis), v = glm::cross(axis, u);
    // keep the winding counter-clockwise about the normal whatever perpendicular_to chose
    float angle = 2.0f * std::numbers::pi_v<float> / float(sides);
    glm::vec3 o0 = outer * u, o1 = outer * (std::cos(angle) * u + std::sin(angle) * v), i1 = inner / outer * o1;
    add_ring(mesh, centre, u, v, axis, inner, outer, sides, color, glm::dot(glm::cross(o1 - o0, i1 - o0), axis) < 0.0f);
}

// Turns the part built since (first vertex, first index) inside out, as CAD exports sometimes
// wind a part: reversed winding, normals negated.
static void invert_part(Mesh& mesh, std::size_t first_vertex, std::size_t first_index)
{
    for (std::size_t k = first_vertex; k < mesh.normals.size(); ++k) mesh.normals[k] = -mesh.normals[k];
    for (std::size_t k = first_index; k + 2 < mesh.indices.size(); k += 3) std::swap(mesh.indices[k + 1], mesh.indices[k + 2]);
}

// The assembly as a CAD export of sheet parts gives it (issue #17): the casing, liners and flanges
// are single zero-thickness sheets, the camshaft, every other liner and one flange inside out; the
// rest as in build_assembly. The truth shows both sides of a sheet (double-sided material), the
// inside of the casing through its open ends.
static void build_sheet_assembly(Mesh& mesh, int detail)
{
    const glm::vec4 steel(0.62f, 0.64f, 0.68f, 1.0f), dark(0.25f, 0.26f, 0.3f, 1.0f), brass(0.78f, 0.6f, 0.25f, 1.0f),
        red(0.7f, 0.18f, 0.15f, 1.0f), blue(0.2f, 0.35f, 0.7f, 1.0f), green(0.25f, 0.55f, 0.3f, 1.0f);
    int big = std::max(8, 4 * detail), small = std::max(6, detail), rings = std::max(1, detail);
    auto inverted = [&](auto&& build) {
        std::size_t v = mesh.positions.size(), i = mesh.indices.size();
        build();
        invert_part(mesh, v, i);
    };
    add_sheet_tube(mesh, {-1.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, 0.6f, 2 * big, 4 * rings, blue); // casing
    add_cylinder(mesh, {-1.25f, 0.0f, 0.0f}, {1.25f, 0.0f, 0.0f}, 0.06f, 2 * small, 2 * rings, steel); // crankshaft
    inverted([&] { add_cylinder(mesh, {-1.1f, 0.42f, 0.0f}, {1.1f, 0.42f, 0.0f}, 0.03f, 2 * small, 2 * rings, steel); }); // camshaft
    for (int c = 0; c < 6; ++c) {
        float x = -0.75f + 0.3f * float(c), phase = float(c % 3) * 0.05f;
        auto liner = [&] { add_sheet_tube(mesh, {x, -0.15f, 0.0f}, {x, 0.5f, 0.0f}, 0.1f, 4 * small, rings, green); };
        if (c % 2 == 1) inverted(liner);
        else liner();
        add_cylinder(mesh, {x, 0.12f + phase, 0.0f}, {x, 0.3f + phase, 0.0f}, 0.095f, 4 * small, rings, dark); // piston
        add_box(mesh, {x - 0.02f, 0.0f, -0.025f}, {x + 0.02f, 0.18f + phase, 0.025f}, steel); // rod
        add_cylinder(mesh, {x - 0.08f, 0.18f + phase, 0.0f}, {x + 0.08f, 0.18f + phase, 0.0f}, 0.015f, small, 1, brass); // pin
    }
    for (int side = 0; side < 2; ++side) {
        float x = side == 0 ? -1.0f : 1.0f, out = side == 0 ? -0.03f : 0.03f;
        auto flange = [&] { add_annulus(mesh, {x, 0.0f, 0.0f}, {out > 0.0f ? 1.0f : -1.0f, 0.0f, 0.0f}, 0.45f, 0.72f, 2 * big, red); };
        if (side == 0) inverted(flange);
        else flange();
        for (int k = 0; k < 12; ++k) {
            float angle = 2.0f * std::numbers::pi_v<float> * (float(k) + 0.5f) / 12.0f;
            glm::vec3 p(x + out, 0.66f * std::cos(angle), 0.66f * std::sin(angle));
            add_cylinder(mesh, p, p + glm::vec3(2.0f * out, 0.0f, 0.0f), 0.025f, small, 1, brass); // bolt
        }
        add_cylinder(mesh, {x + 4.0f * out, 0.0f, 0.0f}, {x + 6.0f * out, 0.0f, 0.0f}, 0.25f, 2 * big, rings, dark); // pulley
    }
    for (int foot = 0; foot < 4; ++foot) {
        float x = foot < 2 ? -0.7f : 0.5f, z = foot % 2 == 0 ? -0.45f : 0.25f;
        add_box(mesh, {x, -0.75f, z}, {x + 0.2f, -0.55f, z + 0.2f}, steel);
    }
}

Result<Mesh> generate_assembly(std::size_t target_triangles, float radius, bool sheets)
{
    GenerateOptions options;
    options.target_triangles = target_triangles;
    options.radius = radius;
    STANDIN_RETURN_IF_ERROR(check_options(options));
    // the triangle count grows with detail squared: measure once, then scale
    auto build = sheets ? build_sheet_assembly : build_assembly;
    Mesh probe;
    build(probe, 8);
    double per_detail2 = double(probe.triangle_count()) / 64.0;
    int detail = std::max(1, int(std::lround(std::sqrt(double(target_triangles) / per_detail2))));
    Mesh mesh;
    build(mesh, detail);
    fit_into_sphere(mesh, radius);
    Material material;
    material.name = "generated";
    material.base_color = options.color;
    mesh.materials.push_back(material);
    mesh.face_materials.assign(mesh.triangle_count(), 0u);
    return mesh;
}

Result<Mesh> generate_mesh(const GenerateOptions& options)
{
    STANDIN_RETURN_IF_ERROR(check_options(options));
    Mesh mesh;
    switch (options.shape) {
    case GeneratedShape::sphere: make_sphere(mesh, options); break;
    case GeneratedShape::torus: make_torus(mesh, options); break;
    case GeneratedShape::noisy_sphere: make_noisy_sphere(mesh, options); break;
    case GeneratedShape::shrub: make_shrub(mesh, options); break;
    case GeneratedShape::fur_ball: make_fur_ball(mesh, options); break;
    case GeneratedShape::tree: make_tree(mesh, options); return mesh; // its own materials
    case GeneratedShape::bush: make_bush(mesh, options); return mesh; // its own materials
    }
    // one material whose colour is folded into every vertex colour (see Material in mesh.h)
    Material material;
    material.name = "generated";
    material.base_color = options.color;
    mesh.materials.push_back(material);
    if (mesh.colors.empty()) mesh.colors.assign(mesh.positions.size(), options.color); // shrub, fur ball: their own
    mesh.face_materials.assign(mesh.triangle_count(), 0u);
    return mesh;
}

} // namespace standin
