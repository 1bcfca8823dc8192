// Procedural meshes for tests and scale benchmarks: a sphere, a torus and a noisy sphere of about
// a requested number of triangles, bit-for-bit deterministic so that tests can compare results.
// The sphere is a cube-sphere with the equal-angle warp (tan of the angle along each cube face,
// as in equi-angular cubemaps): triangles vary in area by less than 1.5x, where a UV sphere
// piles slivers at the poles and an icosphere only comes in powers of four.
#include <standin/mesh.h>

#include <tbb/parallel_for.h>

#include <cmath>
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

Result<Mesh> generate_mesh(const GenerateOptions& options)
{
    STANDIN_RETURN_IF_ERROR(check_options(options));
    Mesh mesh;
    switch (options.shape) {
    case GeneratedShape::sphere: make_sphere(mesh, options); break;
    case GeneratedShape::torus: make_torus(mesh, options); break;
    case GeneratedShape::noisy_sphere: make_noisy_sphere(mesh, options); break;
    }
    // one material whose colour is folded into every vertex colour (see Material in mesh.h)
    Material material;
    material.name = "generated";
    material.base_color = options.color;
    mesh.materials.push_back(material);
    mesh.colors.assign(mesh.positions.size(), options.color);
    mesh.face_materials.assign(mesh.triangle_count(), 0u);
    return mesh;
}

} // namespace standin
