// The CPU reference of the refinement: no T-junction on a closed model at several tolerances (the
// displaced vertices of both sides of every edge are bit-identical), the paper's literal rule
// leaves some, at the finest level a face draws 1.5 times its pattern, rendered triangles fall
// as tau grows, culling keeps what the camera sees and culls
// back faces only of closed parts wound outward.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/displaced_mesh/refine.h"

#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <numbers>
#include <memory>
#include <tuple>

namespace standin::displaced_mesh {
namespace {

struct Baked {
    std::unique_ptr<DisplacedMeshPackage> package;
    std::vector<FaceRefineData> faces;
    RefineSurface surface;
};

Baked bake_noisy_sphere(int degree, std::size_t triangles)
{
    GenerateOptions noisy;
    noisy.shape = GeneratedShape::noisy_sphere;
    noisy.target_triangles = triangles;
    noisy.noise_amplitude = 0.12f;
    Result<Mesh> mesh = generate_mesh(noisy);
    EXPECT_TRUE(mesh.is_ok());
    Result<Options> parameters = bake_parameters({{"degree", std::to_string(degree)}});
    EXPECT_TRUE(parameters.is_ok());
    SourceInfo source;
    Result<std::unique_ptr<DisplacedMeshPackage>> package = bake_displaced(*mesh, source, *parameters, Progress());
    EXPECT_TRUE(package.is_ok()) << package.status().message();
    Baked out;
    out.package = std::move(*package);
    const DisplacedMeshPackage& p = *out.package;
    out.faces = prepare_faces(p.positions, p.normals, p.indices, p.topology, p.layout(), p.elevations, p.face_error);
    out.surface = {&p.positions, &p.normals, &p.indices, &p.topology, &p.elevations, &out.faces, degree};
    return out;
}

RefineView view_at(float distance, float azimuth = 30.0f)
{
    OrbitView orbit;
    orbit.azimuth_degrees = azimuth;
    orbit.elevation_degrees = 20.0f;
    orbit.distance_rel = distance;
    Camera camera = orbit_camera({glm::vec3(0.0f), std::sqrt(3.0f)}, orbit, 800.0f / 600.0f);
    return make_refine_view(camera, 600, glm::mat4(1.0f));
}

// Directed edges of the displaced triangles without their reverse: T-junctions and cracks on a
// closed surface (vertices compared bit for bit).
std::size_t unmatched_edges(const Baked& baked, const std::vector<RefinedTriangle>& triangles, const RefineView& view,
                            const RefineOptions& options)
{
    using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>;
    auto key = [](glm::vec3 p) {
        Key k;
        std::memcpy(&std::get<0>(k), &p.x, 4), std::memcpy(&std::get<1>(k), &p.y, 4), std::memcpy(&std::get<2>(k), &p.z, 4);
        return k;
    };
    std::map<std::pair<Key, Key>, int> edges;
    for (const RefinedTriangle& t : triangles) {
        Key v[3];
        for (int k = 0; k < 3; ++k) v[k] = key(displaced_position(baked.surface, t.face, t.q[k][0], t.q[k][1], view, options));
        for (int k = 0; k < 3; ++k) ++edges[{v[k], v[(k + 1) % 3]}];
    }
    std::size_t unmatched = 0;
    for (const auto& [edge, count] : edges) {
        auto reverse = edges.find({edge.second, edge.first});
        if (reverse == edges.end() || reverse->second != count) ++unmatched;
    }
    return unmatched;
}

TEST(DisplacedMeshRefine, NoTJunctionsOnAClosedModelAtSeveralTolerances)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    RefineView view = view_at(1.5f);
    for (Criterion criterion : {Criterion::error, Criterion::weighted, Criterion::length})
        for (float tau : {0.5f, 1.0f, 2.0f, 4.0f, 16.0f}) {
            SCOPED_TRACE(testing::Message() << "criterion " << int(criterion) << " tau " << tau);
            RefineOptions options;
            options.tau = tau;
            options.criterion = criterion;
            options.cull = false;
            RefineStats stats;
            std::vector<RefinedTriangle> triangles = refine(baked.surface, view, options, stats);
            EXPECT_GT(stats.rendered, baked.package->face_count());
            EXPECT_EQ(stats.capped, 0u);
            EXPECT_EQ(unmatched_edges(baked, triangles, view, options), 0u);
        }
}

// Faces kept whole (the textured export's flat cards) on a closed surface: every other face of
// the sphere is marked, so the weighted rule leaves marked faces whose edges touch only marked
// faces as one triangle, splits the rest, and the mesh stays crack-free (an edge touching an
// unmarked face keeps its weight: the segment test is still a function of the segment).
TEST(DisplacedMeshRefine, FacesKeptWholeStayOneTriangleWithoutCracks)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    const DisplacedMeshPackage& p = *baked.package;
    std::vector<std::uint8_t> kept(p.face_count(), 0);
    for (std::size_t f = 0; f < kept.size(); f += 2) kept[f] = 1;
    for (std::size_t f = 0; f < 40 && f < kept.size(); ++f) kept[f] = 1; // a patch of marked faces too
    baked.faces = prepare_faces(p.positions, p.normals, p.indices, p.topology, p.layout(), p.elevations, p.face_error, {}, kept);
    RefineView view = view_at(1.5f);
    RefineOptions options;
    options.tau = 1.0f;
    options.criterion = Criterion::weighted;
    options.cull = false;
    RefineStats stats;
    std::vector<RefinedTriangle> triangles = refine(baked.surface, view, options, stats);
    EXPECT_EQ(unmatched_edges(baked, triangles, view, options), 0u);
    std::vector<int> per_face(p.face_count(), 0);
    for (const RefinedTriangle& t : triangles) ++per_face[t.face];
    std::size_t enclosed = 0, others_split = 0, others = 0;
    for (std::size_t f = 0; f < kept.size(); ++f) {
        bool all_marked = kept[f] != 0;
        for (std::uint32_t e : p.topology.face_edges[f])
            for (std::uint32_t g : p.topology.edges[e].faces) all_marked = all_marked && kept[g];
        if (all_marked) {
            ++enclosed;
            EXPECT_EQ(per_face[f], 1) << "face " << f;
        } else if (!kept[f]) {
            ++others;
            others_split += per_face[f] > 1;
        }
    }
    EXPECT_GT(enclosed, 0u);
    EXPECT_GT(others_split, others / 2) << "unmarked faces refine as before";
}

TEST(DisplacedMeshRefine, ThePapersLiteralRuleLeavesTJunctions)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    RefineView view = view_at(1.5f);
    RefineOptions options;
    options.criterion = Criterion::seed;
    options.cull = false;
    std::size_t unmatched = 0;
    for (float tau : {1.0f, 2.0f, 4.0f}) {
        options.tau = tau;
        RefineStats stats;
        unmatched += unmatched_edges(baked, refine(baked.surface, view, options, stats), view, options);
    }
    EXPECT_GT(unmatched, 0u);
}

// Refined to the finest level (tau far below what any segment shows), the error criterion's
// bisection of the longest edge in pattern units ends on triangles of at least half a pattern
// triangle (measured: 1.5 times the pattern's (k - 1)^2 triangles a face, half of them halves), and
// no fewer than it, crack-free. The longest edge on screen (the paper's rule) cut triangles thinner
// where a face is oblique: 2.11 times here, 3-5 times on hard-surface models.
TEST(DisplacedMeshRefine, AtTheFinestLevelAFaceDrawsAtMostOneAndAHalfTimesItsPattern)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    const std::uint64_t faces = baked.package->face_count(), pattern = 8 * 8;
    for (float azimuth : {30.0f, 75.0f}) {
        RefineView view = view_at(0.8f, azimuth);
        RefineOptions options;
        options.tau = 1e-4f;
        options.cull = false;
        RefineStats stats;
        std::vector<RefinedTriangle> triangles = refine(baked.surface, view, options, stats);
        EXPECT_EQ(stats.capped, 0u);
        EXPECT_GE(stats.rendered, faces * pattern);
        EXPECT_LE(10 * stats.rendered, 16 * faces * pattern) << double(stats.rendered) / double(faces * pattern) << " times the pattern";
        EXPECT_EQ(unmatched_edges(baked, triangles, view, options), 0u);
    }
}

TEST(DisplacedMeshRefine, RenderedTrianglesFallAsTauGrows)
{
    Baked baked = bake_noisy_sphere(17, 20000);
    ASSERT_TRUE(baked.package);
    RefineView view = view_at(3.0f);
    std::uint64_t previous = UINT64_MAX;
    for (float tau : {0.5f, 1.0f, 2.0f, 4.0f, 8.0f}) {
        RefineOptions options;
        options.tau = tau;
        RefineStats stats;
        refine(baked.surface, view, options, stats);
        EXPECT_LT(stats.rendered, previous) << "tau " << tau;
        EXPECT_GT(stats.processed, stats.rendered);
        previous = stats.rendered;
    }
}

TEST(DisplacedMeshRefine, CullingDropsFacesBehindTheModel)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    RefineView view = view_at(1.0f);
    RefineOptions options;
    RefineStats culled, all;
    refine(baked.surface, view, options, culled);
    options.cull = false;
    refine(baked.surface, view, options, all);
    EXPECT_LT(culled.faces_visible, baked.package->face_count() * 3 / 4);
    EXPECT_GT(culled.faces_visible, baked.package->face_count() / 4);
    EXPECT_LT(culled.rendered, all.rendered);
}

// A closed part wound inside out (winding and normals inward, as some exporters write a capsule)
// shows the faces its winding calls backs: they must not be culled; its outward twin's may be.
TEST(DisplacedMeshRefine, OnlyClosedPartsWoundOutwardCullTheirBackFaces)
{
    Baked baked = bake_noisy_sphere(9, 20000);
    ASSERT_TRUE(baked.package);
    const DisplacedMeshPackage& p = *baked.package;
    // part 1: the package's control mesh; part 2: a copy moved aside, every face and normal turned
    std::vector<glm::vec3> positions = p.positions, normals = p.normals;
    std::vector<std::uint32_t> indices = p.indices;
    const std::uint32_t offset = std::uint32_t(positions.size());
    for (std::size_t v = 0; v < p.positions.size(); ++v) {
        positions.push_back(p.positions[v] + glm::vec3(4.0f, 0.0f, 0.0f));
        normals.push_back(-p.normals[v]);
    }
    for (std::size_t f = 0; f < p.face_count(); ++f) {
        const std::uint32_t* c = &p.indices[3 * f];
        for (std::uint32_t corner : {c[0], c[2], c[1]}) indices.push_back(corner + offset);
    }
    std::vector<float> elevations = p.elevations, face_error = p.face_error;
    elevations.insert(elevations.end(), p.elevations.begin(), p.elevations.end());
    face_error.insert(face_error.end(), p.face_error.begin(), p.face_error.end());
    Result<ControlTopology> topology = build_topology(positions.size(), indices);
    ASSERT_TRUE(topology.is_ok());
    std::vector<FaceRefineData> faces = prepare_faces(positions, normals, indices, *topology, p.layout(), elevations, face_error);
    const float all_around = std::numbers::pi_v<float>;
    std::size_t outward_cullable = 0, inward_cullable = 0;
    for (std::size_t f = 0; f < faces.size(); ++f) (f < p.face_count() ? outward_cullable : inward_cullable) += faces[f].cone_half_angle < all_around;
    EXPECT_GT(outward_cullable, p.face_count() / 2);
    EXPECT_EQ(inward_cullable, 0u);
    // an open part (the outward copy less one face) culls nothing either
    std::vector<std::uint32_t> open(p.indices.begin() + 3, p.indices.end());
    Result<ControlTopology> open_topology = build_topology(p.positions.size(), open);
    ASSERT_TRUE(open_topology.is_ok());
    std::vector<float> open_elevations(p.elevations.begin() + std::ptrdiff_t(p.layout().samples_per_face), p.elevations.end());
    std::vector<float> open_error(p.face_error.begin() + 1, p.face_error.end());
    std::vector<FaceRefineData> open_faces = prepare_faces(p.positions, p.normals, open, *open_topology, p.layout(), open_elevations, open_error);
    for (const FaceRefineData& d : open_faces) EXPECT_EQ(d.cone_half_angle, all_around);
}

} // namespace
} // namespace standin::displaced_mesh
