// Sampling: an icosphere control mesh inside a sphere gets the radius difference as elevation;
// surfaces hidden inside closed parts give way to the one enclosing them, other parts do not; a
// layer a hair over a surface, facing its way, is taken over the surface under it;
// shared edges and corners hold bit-identical values on every face and every level, for both
// samplers; levels on an edge depend on the edge alone; quantisation round-trips within a step.
#include "reps/displaced_mesh/control_mesh.h"
#include "reps/displaced_mesh/face_point.h"
#include "reps/displaced_mesh/sample.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
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

// One mesh of closed spheres (each wound outward, or inward where `inward`), each of one colour,
// each turned a different way so that no ray through one's vertices passes through another's
// (concentric icospheres share vertex directions, where a ray tracer that is not watertight
// may miss the second).
struct Ball {
    glm::vec3 centre;
    float radius;
    glm::vec4 colour;
    bool inward = false;
};
Mesh balls(const std::vector<Ball>& parts)
{
    Mesh mesh;
    mesh.materials.emplace_back();
    for (const Ball& ball : parts) {
        std::vector<glm::vec3> positions, normals;
        std::vector<std::uint32_t> indices;
        icosphere(4, ball.radius, positions, normals, indices);
        const auto base = std::uint32_t(mesh.positions.size());
        const float angle = 0.37f * float(&ball - parts.data() + 1);
        const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, 0.8f, 0.5f));
        auto turn = [&](glm::vec3 v) { // Rodrigues' rotation by `angle` about `axis`
            return v * std::cos(angle) + glm::cross(axis, v) * std::sin(angle) + axis * glm::dot(axis, v) * (1.0f - std::cos(angle));
        };
        for (std::size_t v = 0; v < positions.size(); ++v) {
            mesh.positions.push_back(ball.centre + turn(positions[v]));
            mesh.normals.push_back(turn(ball.inward ? -normals[v] : normals[v]));
            mesh.colors.push_back(ball.colour);
        }
        for (std::size_t i = 0; i < indices.size(); i += 3) {
            const std::uint32_t a = indices[i], b = ball.inward ? indices[i + 2] : indices[i + 1],
                                c = ball.inward ? indices[i + 1] : indices[i + 2];
            mesh.indices.insert(mesh.indices.end(), {base + a, base + b, base + c});
            mesh.face_materials.push_back(0);
        }
    }
    return mesh;
}

// Samples of an icosphere control mesh of radius `control_radius` over `mesh`: the sampled
// surface, and per sample the point it displaces to and its displacement direction.
struct SampledOver {
    SampledSurface surface;
    std::vector<glm::vec3> points, directions;
};
SampledOver sample_over(const Mesh& mesh, float control_radius, float range)
{
    std::vector<glm::vec3> positions, normals;
    std::vector<std::uint32_t> indices;
    icosphere(1, control_radius, positions, normals, indices);
    Result<ControlTopology> topology = build_topology(positions.size(), indices);
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh.positions, mesh.indices);
    EXPECT_TRUE(topology.is_ok() && scene.is_ok());
    ControlGeometry control{positions, normals, indices, *topology};
    SampleOptions options;
    options.degree = 9;
    options.ray_range = range;
    Result<SampledSurface> sampled = sample_surface(mesh, **scene, control, options, Progress());
    EXPECT_TRUE(sampled.is_ok());
    SampledOver out{std::move(*sampled), {}, {}};
    const PatternLayout layout(9);
    const int n = layout.segments;
    out.points.resize(out.surface.elevation.size());
    out.directions.resize(out.surface.elevation.size());
    for (std::size_t f = 0; f < indices.size() / 3; ++f)
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                FacePoint p = face_point(positions.data(), normals.data(), &indices[3 * f], std::uint32_t(j) * (k_bary_one / n),
                                         std::uint32_t(i) * (k_bary_one / n));
                const std::size_t at = f * layout.finest_samples + triangle_index(n, i, j);
                out.directions[at] = unit_direction(p.normal);
                out.points[at] = p.position + out.surface.elevation[at] * out.directions[at];
            }
    return out;
}

TEST(DisplacedMeshSample, SurfacesInsideClosedPartsGiveWayToTheOneEnclosingThem)
{
    const glm::vec4 white(1.0f), black(0.0f, 0.0f, 0.0f, 1.0f);
    // nested shells (assimp's UglyVertexColors.lwo): a control mesh at 0.85 is nearest to the
    // black shell at 0.9, which no eye sees; every sample takes the white one at 1 instead
    SampledOver nested = sample_over(balls({{{0, 0, 0}, 1.0f, white}, {{0, 0, 0}, 0.9f, black}}), 0.85f, 0.5f);
    ASSERT_FALSE(nested.points.empty());
    for (std::size_t i = 0; i < nested.points.size(); ++i) {
        ASSERT_NEAR(glm::length(nested.points[i]), 1.0f, 0.01f) << i;
        ASSERT_GT(nested.surface.albedo[i].x, 0.99f) << i;
    }
    // interpenetrating parts: a black ball pokes out of the white one. Around the axis they share
    // both surfaces run nearly parallel, and every sample there lies on the black ball's outer
    // surface, never on the white one inside it; further round they cross at an angle, and a
    // sample keeps the paper's hit (its neighbours would otherwise jump between the two)
    const glm::vec3 poke(0.6f, 0.0f, 0.0f);
    SampledOver joined = sample_over(balls({{{0, 0, 0}, 1.0f, white}, {poke, 0.5f, black}}), 0.85f, 0.5f);
    std::size_t near_axis = 0;
    for (std::size_t i = 0; i < joined.points.size(); ++i) {
        if (joined.directions[i].x < std::cos(glm::radians(20.0f))) continue;
        ASSERT_NEAR(glm::length(joined.points[i] - poke), 0.5f, 0.01f) << i; // on the black ball
        ASSERT_GT(glm::length(joined.points[i]), 1.0f) << i;                 // outside the white one
        ASSERT_LT(joined.surface.albedo[i].x, 0.01f) << i;
        ++near_axis;
    }
    EXPECT_GT(near_axis, 20u);
    // a hollow ball: the cavity's wall (wound inward, at 0.9) faces the control mesh across open
    // air, so it is not hidden from it: the paper's nearer hit stays (the same rule keeps a gap
    // between a bundle's barrels a gap instead of spanning it with the barrels' far sides)
    SampledOver hollow = sample_over(balls({{{0, 0, 0}, 1.0f, white}, {{0, 0, 0}, 0.9f, black, true}}), 0.85f, 0.5f);
    for (std::size_t i = 0; i < hollow.points.size(); ++i) {
        ASSERT_NEAR(glm::length(hollow.points[i]), 0.9f, 0.01f) << i;
        ASSERT_LT(hollow.surface.albedo[i].x, 0.01f) << i;
    }
    // the paper's rule is kept where nothing hides: a separate part within the ray range above
    // the sphere (entered, not left, by the ray) does not pull samples onto it, so every sample
    // still takes the black sphere it lies nearest
    SampledOver apart = sample_over(balls({{{0, 0, 0}, 0.9f, black}, {{0, 1.05f, 0}, 0.1f, white}}), 0.85f, 0.5f);
    for (std::size_t i = 0; i < apart.points.size(); ++i) {
        ASSERT_NEAR(glm::length(apart.points[i]), 0.9f, 0.01f) << i;
        ASSERT_LT(apart.surface.albedo[i].x, 0.01f) << i;
    }
}

// The part of an icosphere of `radius` above height y_min x radius: an open patch of one colour,
// wound outward, or inward where `inward`; turned about y, so that no ray along the control
// icosphere's vertex and edge directions runs through its vertices and edges.
void add_cap(Mesh& mesh, float radius, float y_min, glm::vec4 colour, bool inward)
{
    std::vector<glm::vec3> positions, normals;
    std::vector<std::uint32_t> indices;
    icosphere(4, radius, positions, normals, indices);
    const float c = std::cos(0.29f), s = std::sin(0.29f);
    auto turn = [&](glm::vec3 v) { return glm::vec3(c * v.x + s * v.z, v.y, -s * v.x + c * v.z); };
    const auto base = std::uint32_t(mesh.positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) {
        mesh.positions.push_back(turn(positions[v]));
        mesh.normals.push_back(turn(inward ? -normals[v] : normals[v]));
        mesh.colors.push_back(colour);
    }
    for (std::size_t i = 0; i < indices.size(); i += 3) {
        const glm::vec3 centroid = (positions[indices[i]] + positions[indices[i + 1]] + positions[indices[i + 2]]) / 3.0f;
        if (centroid.y < y_min * radius) continue;
        const std::uint32_t b = inward ? indices[i + 2] : indices[i + 1], c = inward ? indices[i + 1] : indices[i + 2];
        mesh.indices.insert(mesh.indices.end(), {base + indices[i], base + b, base + c});
        mesh.face_materials.push_back(0);
    }
}

// A layer a hair over a surface and facing the same way (a decal, continents modelled over an
// ocean sphere: assimp's Q3D/earth.q3o) is what an eye sees there: samples whose nearest hit is
// the surface under it take the layer. A layer facing the other way is a thin wall's far side and
// does not pull samples onto it.
TEST(DisplacedMeshSample, ALayerAHairOverTheSurfaceIsWhatSamplesTake)
{
    const glm::vec4 white(1.0f), black(0.0f, 0.0f, 0.0f, 1.0f);
    for (bool inward : {false, true}) {
        Mesh mesh = balls({{{0, 0, 0}, 0.9f, black}});
        add_cap(mesh, 0.905f, 0.3f, white, inward);
        SampledOver over = sample_over(mesh, 0.85f, 0.5f); // the layer 1% of the ray range above
        std::size_t on_layer = 0, off_layer = 0;
        for (std::size_t i = 0; i < over.points.size(); ++i) {
            const float y = over.directions[i].y;
            if (y > 0.45f && !inward) {
                ASSERT_NEAR(glm::length(over.points[i]), 0.905f, 0.002f) << i;
                ASSERT_GT(over.surface.albedo[i].x, 0.99f) << i;
                ++on_layer;
            } else if (y < 0.15f || inward) {
                ASSERT_NEAR(glm::length(over.points[i]), 0.9f, 0.002f) << i << (inward ? " inward" : "");
                ASSERT_LT(over.surface.albedo[i].x, 0.01f) << i << (inward ? " inward" : "");
                ++off_layer;
            }
        }
        EXPECT_GT(off_layer, 100u);
        if (!inward) {
            EXPECT_GT(on_layer, 100u);
        }
    }
}

// A ball half sunk into a larger one, each part with control faces of its own (the simplifier's
// control mesh): the small ball's samples inside the large one stay on the small ball, whose
// surface the depth test cuts there, instead of moving onto the large ball's surface, which the
// large ball's own faces draw; moved, they bridged the crease between the balls with a fillet.
TEST(DisplacedMeshSample, PartsSunkIntoOthersKeepTheirOwnSurfaceWhereTheOthersDrawTheirs)
{
    const glm::vec3 small_centre(0.85f, 0.0f, 0.0f);
    const float small_radius = 0.4f;
    const Mesh mesh = balls({{{0, 0, 0}, 1.0f, glm::vec4(1.0f)}, {small_centre, small_radius, glm::vec4(0, 0, 0, 1)}});
    ControlMeshOptions simplify;
    simplify.target_faces = 400;
    Result<ControlMesh> built = build_control_mesh(mesh, simplify);
    ASSERT_TRUE(built.is_ok());
    Result<ControlTopology> topology = build_topology(built->positions.size(), built->indices);
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh.positions, mesh.indices);
    ASSERT_TRUE(topology.is_ok() && scene.is_ok());
    ControlGeometry control{built->positions, built->normals, built->indices, *topology};
    SampleOptions options;
    options.degree = 9;
    options.ray_range = 0.3f;
    Result<SampledSurface> sampled = sample_surface(mesh, **scene, control, options, Progress());
    ASSERT_TRUE(sampled.is_ok());
    const PatternLayout layout(9);
    const int n = layout.segments;
    auto on_small = [&](glm::vec3 p) { return std::abs(glm::length(p - small_centre) - small_radius) < 0.01f; };
    std::size_t small_faces = 0, small_samples = 0, inside_large = 0, moved_off = 0;
    float worst_off = 0.0f;
    for (std::size_t f = 0; f < control.face_count(); ++f) {
        const std::uint32_t* corner = &built->indices[3 * f];
        const bool small = on_small(built->positions[corner[0]]);
        small_faces += small;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; j <= n - i; ++j) {
                FacePoint p = face_point(built->positions.data(), built->normals.data(), corner, std::uint32_t(j) * (k_bary_one / n),
                                         std::uint32_t(i) * (k_bary_one / n));
                const glm::vec3 point = p.position + sampled->elevation[f * layout.finest_samples + triangle_index(n, i, j)] * unit_direction(p.normal);
                if (small) {
                    const float off = std::abs(glm::length(point - small_centre) - small_radius);
                    moved_off += off > 0.01f;
                    worst_off = std::max(worst_off, off);
                    inside_large += glm::length(point) < 0.99f;
                    ++small_samples;
                } else { // the large ball's faces: on either surface (near the crease the small one is nearer)
                    ASSERT_TRUE(std::abs(glm::length(point) - 1.0f) < 0.01f || on_small(point)) << "face " << f << " (" << i << ", " << j << ")";
                }
            }
    }
    std::printf("[ sunk ] %zu of %zu samples of the small ball's faces off it (worst %.4f), %zu inside the large ball\n", moved_off,
                small_samples, worst_off, inside_large);
    EXPECT_GT(small_faces, 20u);
    EXPECT_GT(inside_large, 1000u); // the sunk half was sampled, and stayed
    // only along the crease, within about a pattern step of it, do samples still move (1108 of
    // 6930, up to 0.29 off, before the moves onto surfaces other faces draw were undone)
    EXPECT_LT(moved_off, small_samples / 50);
    EXPECT_LT(worst_off, 0.08f);
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

namespace standin::displaced_mesh {
namespace {

// Elevations of float rounding (samples lying on the original, nothing else to widen the range)
// take the floor's step, not 65,535 codes over the noise: a few codes, which compress.
TEST(DisplacedMeshSample, ElevationsOfRoundingNoiseQuantiseToTheFloor)
{
    std::vector<float> noise;
    for (int i = 0; i < 1000; ++i) noise.push_back(7e-8f * std::sin(float(i) * 1.7f));
    const float floor = elevation_step_floor(1.5f);
    EXPECT_NEAR(floor, 1.5f / 4194304.0f, 1e-12f);
    const Quantisation q = choose_quantisation(noise, floor);
    EXPECT_EQ(q.step, floor);
    std::vector<std::uint16_t> codes = quantise(noise, q);
    EXPECT_LE(*std::max_element(codes.begin(), codes.end()), 1);
    // a range wider than 65,535 floors keeps its own step
    noise.push_back(1.0f);
    EXPECT_FLOAT_EQ(choose_quantisation(noise, floor).step, (1.0f - *std::min_element(noise.begin(), noise.end())) / 65535.0f);
}

} // namespace
} // namespace standin::displaced_mesh
