// Sampling: an icosphere control mesh inside a sphere gets the radius difference as elevation;
// shared edges and corners hold bit-identical values on every face and every level, for both
// samplers; levels on an edge depend on the edge alone; quantisation round-trips within a step.
#include "reps/displaced_mesh/control_mesh.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>

namespace standin::displaced_mesh {
namespace {

// An icosahedron subdivided `levels` times, vertices at `radius`, normals radial.
void icosphere(int levels, float radius, std::vector<glm::vec3>& positions, std::vector<glm::vec3>& normals,
               std::vector<std::uint32_t>& indices)
{
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    std::vector<glm::vec3> unit = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                   {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (glm::vec3& v : unit) v = glm::normalize(v);
    indices = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4, 11, 10, 2, 10, 7, 6, 7, 1, 8,
               3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8, 3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
        auto mid = [&](std::uint32_t a, std::uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = middle.find(key);
            if (it != middle.end()) return it->second;
            unit.push_back(glm::normalize(unit[a] + unit[b]));
            return middle[key] = std::uint32_t(unit.size() - 1);
        };
        std::vector<std::uint32_t> next;
        for (std::size_t f = 0; f < indices.size(); f += 3) {
            std::uint32_t a = indices[f], b = indices[f + 1], c = indices[f + 2];
            std::uint32_t ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        indices = next;
    }
    normals = unit;
    positions.clear();
    for (glm::vec3 v : unit) positions.push_back(radius * v);
}

TEST(DisplacedMeshSample, IcosphereOverASphereGivesTheRadiusDifference)
{
    GenerateOptions sphere_options;
    sphere_options.target_triangles = 200000;
    Result<Mesh> sphere = generate_mesh(sphere_options); // every vertex at radius 1
    ASSERT_TRUE(sphere.is_ok());
    std::vector<glm::vec3> positions, normals;
    std::vector<std::uint32_t> indices;
    icosphere(1, 0.9f, positions, normals, indices);
    Result<ControlTopology> topology = build_topology(positions.size(), indices);
    ASSERT_TRUE(topology.is_ok());
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(sphere->positions, sphere->indices);
    ASSERT_TRUE(scene.is_ok());
    ControlGeometry control{positions, normals, indices, *topology};
    SampleOptions options;
    options.degree = 9;
    options.ray_range = 0.5f;
    Result<SampledSurface> sampled = sample_surface(*sphere, **scene, control, options, Progress());
    ASSERT_TRUE(sampled.is_ok());
    EXPECT_EQ(sampled->misses, 0u);

    // T(w) = 0.9 N(w) lies on the ray, so the ray meets radius 1 after 1 - 0.9 |N(w)|, less the
    // tessellated sphere's sag below radius 1 (a triangle's deepest point is its plane's foot)
    double sag = 0.0;
    for (std::size_t t = 0; t < sphere->triangle_count(); ++t) {
        const std::uint32_t* v = &sphere->indices[3 * t];
        glm::dvec3 a(sphere->positions[v[0]]), b(sphere->positions[v[1]]), c(sphere->positions[v[2]]);
        sag = std::max(sag, 1.0 - std::abs(glm::dot(glm::normalize(glm::cross(b - a, c - a)), a)));
    }
    ASSERT_LT(sag, 1e-4);
    const PatternLayout layout(9);
    const int n = layout.segments;
    double worst = 0.0;
    for (std::size_t f = 0; f < indices.size() / 3; ++f)
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                FacePoint p = face_point(positions.data(), normals.data(), &indices[3 * f], std::uint32_t(j) * (k_bary_one / n),
                                         std::uint32_t(i) * (k_bary_one / n));
                float expected = 1.0f - 0.9f * glm::length(p.normal);
                float h = sampled->elevation[f * layout.finest_samples + triangle_index(n, i, j)];
                worst = std::max(worst, double(std::abs(h - expected)));
                glm::vec3 shading = sampled->normal[f * layout.finest_samples + triangle_index(n, i, j)];
                EXPECT_GT(glm::dot(shading, unit_direction(p.normal)), 0.999f);
            }
    EXPECT_LT(worst, sag + 2e-6);

    // the interpolation sampler averages the same field over each vertex's ring of pattern
    // triangles; on this coarse icosphere the field varies by ~0.04 across a ring (0.1 at the
    // corners, 0.14 at face centres), so the averages stay within that of the point samples
    options.sampler = "interpolation";
    options.interpolation_rays = 4;
    Result<SampledSurface> averaged = sample_surface(*sphere, **scene, control, options, Progress());
    ASSERT_TRUE(averaged.is_ok());
    double mean_difference = 0.0;
    for (std::size_t i = 0; i < averaged->elevation.size(); ++i) {
        EXPECT_NEAR(averaged->elevation[i], sampled->elevation[i], 0.015f);
        mean_difference += std::abs(averaged->elevation[i] - sampled->elevation[i]) / double(averaged->elevation.size());
    }
    EXPECT_LT(mean_difference, 0.004);
}

// Every face's values along each edge, in the edge's canonical direction, at every level.
void expect_shared_values_equal(const ControlTopology& topology, const std::vector<std::uint32_t>& indices,
                                const PatternLayout& layout, const std::vector<float>& levels)
{
    std::size_t compared = 0, differing = 0;
    for (std::size_t e = 0; e < topology.edges.size(); ++e) {
        const ControlEdge& edge = topology.edges[e];
        for (int level = 0; level <= layout.exponent; ++level) {
            const int n = layout.level_segments(level);
            std::vector<float> first;
            for (std::uint32_t f : edge.faces) {
                int k = 0;
                while (topology.face_edges[f][std::size_t(k)] != e) ++k;
                std::vector<float> along;
                for (int s = 0; s <= n; ++s) {
                    int i = 0, j = 0;
                    edge_vertex(n, k, topology.reversed(f, k) ? n - s : s, i, j);
                    along.push_back(levels[std::size_t(f) * layout.samples_per_face + layout.index(level, i, j)]);
                }
                if (first.empty()) {
                    first = along;
                    continue;
                }
                ++compared;
                differing += std::memcmp(first.data(), along.data(), first.size() * sizeof(float)) != 0;
            }
        }
    }
    EXPECT_GT(compared, 100u);
    EXPECT_EQ(differing, 0u);
}

TEST(DisplacedMeshSample, SharedEdgesAndCornersAreBitIdenticalAtEveryLevel)
{
    GenerateOptions noisy;
    noisy.shape = GeneratedShape::noisy_sphere;
    noisy.target_triangles = 20000;
    noisy.noise_amplitude = 0.15f;
    Result<Mesh> mesh = generate_mesh(noisy);
    ASSERT_TRUE(mesh.is_ok());
    ControlMeshOptions simplify;
    simplify.target_faces = 300;
    Result<ControlMesh> control = build_control_mesh(*mesh, simplify);
    ASSERT_TRUE(control.is_ok());
    Result<ControlTopology> topology = build_topology(control->positions.size(), control->indices);
    ASSERT_TRUE(topology.is_ok());
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh->positions, mesh->indices);
    ASSERT_TRUE(scene.is_ok());
    ControlGeometry geometry{control->positions, control->normals, control->indices, *topology};
    const PatternLayout layout(9);
    for (const char* sampler : {"intersection", "interpolation"}) {
        SCOPED_TRACE(sampler);
        SampleOptions options;
        options.degree = 9;
        options.sampler = sampler;
        options.interpolation_rays = 4;
        options.ray_range = 0.3f;
        Result<SampledSurface> sampled = sample_surface(*mesh, **scene, geometry, options, Progress());
        ASSERT_TRUE(sampled.is_ok());
        std::vector<float> levels = build_levels(layout, sampled->elevation);
        expect_shared_values_equal(*topology, control->indices, layout, levels);
        // and after quantisation
        Quantisation q = choose_quantisation(levels);
        std::vector<std::uint16_t> codes = quantise(levels, q);
        std::vector<float> decoded(levels.size());
        for (std::size_t i = 0; i < levels.size(); ++i) {
            decoded[i] = q.decode(codes[i]);
            ASSERT_LE(std::abs(decoded[i] - levels[i]), 0.51f * q.step + 1e-7f);
        }
        expect_shared_values_equal(*topology, control->indices, layout, decoded);
    }
}

TEST(DisplacedMeshSample, EdgeLevelsDependOnTheEdgeAlone)
{
    const PatternLayout layout(17);
    std::vector<float> finest(layout.finest_samples);
    for (std::size_t i = 0; i < finest.size(); ++i) finest[i] = std::sin(float(i) * 0.37f);
    std::vector<float> a = build_levels(layout, finest);
    // change every interior value: nothing on the edges may move, at any level
    const int n = layout.segments;
    for (int i = 1; i < n; ++i)
        for (int j = 1; j < n - i; ++j) finest[triangle_index(n, i, j)] += 0.5f;
    std::vector<float> b = build_levels(layout, finest);
    for (int level = 0; level <= layout.exponent; ++level) {
        const int m = layout.level_segments(level);
        for (int k = 0; k < 3; ++k)
            for (int s = 0; s <= m; ++s) {
                int i = 0, j = 0;
                edge_vertex(m, k, s, i, j);
                EXPECT_EQ(a[layout.index(level, i, j)], b[layout.index(level, i, j)]) << level << " " << k << " " << s;
            }
    }
    EXPECT_EQ(layout.samples_per_face, 153u + 45u + 15u + 6u + 3u);
    EXPECT_EQ(PatternLayout(33).samples_per_face, 783u);
}

} // namespace
} // namespace standin::displaced_mesh
