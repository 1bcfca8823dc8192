// The compact coarse-mesh file: a round trip keeps every triangle (positions within half a 16-bit
// step of the bounding box, colours to 8 bits, winding kept), writes the same bytes twice, is far
// smaller than the PLY, and damaged files (truncated, wrong counts, indices out of range, bad
// boxes) are refused with one line naming the file.
#include "reps/common/coarse_mesh.h"
#include "test_support.h"

#include <standin/files.h>

#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

namespace standin::reps {
namespace {

Mesh coarse_of_noisy_sphere()
{
    return make_coarse_mesh(test::generated(GeneratedShape::noisy_sphere, 20000), 0.1f);
}

// A position's grid cell: for the source the encoder's rounding of (p - lo) / extent * 65535, for a
// decoded position (lo + q * extent / 65535) the nearest q.
std::array<long, 3> grid_cell(glm::vec3 p, const Bounds& box, bool decoded)
{
    std::array<long, 3> cell;
    for (int a = 0; a < 3; ++a) {
        float extent = box.max[a] - box.min[a];
        cell[a] = decoded ? std::lround((p[a] - box.min[a]) / (extent / 65535.0f))
                          : std::lround(std::clamp((p[a] - box.min[a]) / extent, 0.0f, 1.0f) * 65535.0f);
    }
    return cell;
}

// Every triangle as its three corners' cells, rotated to start at the smallest corner (the index
// codec may rotate a triangle, never flip it), sorted.
using CoarseCorners = std::array<std::array<long, 3>, 3>;
std::vector<CoarseCorners> coarse_triangle_keys(const Mesh& mesh, const Bounds& box, bool decoded)
{
    std::vector<CoarseCorners> keys;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        CoarseCorners c;
        for (int k = 0; k < 3; ++k) c[k] = grid_cell(mesh.positions[mesh.indices[t * 3 + k]], box, decoded);
        int first = int(std::min_element(c.begin(), c.end()) - c.begin());
        std::rotate(c.begin(), c.begin() + first, c.end());
        keys.push_back(c);
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

// A zero-thickness sheet (issue #17): a wavy square of n x n quads, open along its four sides.
Mesh wavy_sheet(int n)
{
    Mesh mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            float x = float(i) / float(n), y = float(j) / float(n);
            mesh.positions.push_back(glm::vec3(x, y, 0.05f * std::sin(9.0f * x) * std::cos(7.0f * y)));
            mesh.colors.push_back(glm::vec4(0.8f, 0.8f, 0.8f, 1.0f));
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            std::uint32_t a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1), d = c + 1;
            mesh.indices.insert(mesh.indices.end(), {a, b, d, a, d, c});
        }
    mesh.face_materials.assign(mesh.triangle_count(), 0);
    mesh.materials.push_back(Material{});
    compute_smooth_normals(mesh);
    return mesh;
}

// The renderer fills a sheet rim's staircase of holes with the coarse triangles along its open
// boundary (enhanced_billboards/renderer.cpp, rims_first), so the simplifier must keep the outline:
// every boundary vertex of the source stays, and the coarse mesh's boundary is as long as the source's.
TEST(CoarseMesh, OpenBoundariesKeepTheirOutline)
{
    const int n = 60;
    Mesh sheet = wavy_sheet(n);
    Mesh coarse = make_coarse_mesh(sheet, 0.1f, true);
    ASSERT_GT(coarse.triangle_count(), 0u);
    EXPECT_LT(coarse.triangle_count(), sheet.triangle_count() / 4) << "still simplified";
    auto key = [](glm::vec3 p) { return std::array<float, 3>{p.x, p.y, p.z}; };
    std::map<std::array<float, 3>, int> kept;
    for (glm::vec3 p : coarse.positions) kept[key(p)] = 1;
    int border = 0, missing = 0;
    for (glm::vec3 p : sheet.positions) {
        if (p.x != 0.0f && p.x != 1.0f && p.y != 0.0f && p.y != 1.0f) continue;
        ++border;
        missing += kept.count(key(p)) ? 0 : 1;
    }
    EXPECT_EQ(border, 4 * n);
    EXPECT_EQ(missing, 0);
    // boundary length: edges used by one triangle
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
    for (std::size_t f = 0; f < coarse.triangle_count(); ++f)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = coarse.indices[f * 3 + std::size_t(k)], b = coarse.indices[f * 3 + std::size_t(k + 1) % 3];
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    double length = 0.0;
    for (const auto& [edge, count] : uses)
        if (count == 1) length += double(glm::length(coarse.positions[edge.first] - coarse.positions[edge.second]));
    double expected = 0.0; // the source's four wavy sides
    for (int i = 0; i < n; ++i)
        for (int side = 0; side < 4; ++side) {
            auto at = [&](int k) {
                int i2 = side == 0 ? k : side == 1 ? n : side == 2 ? k : 0;
                int j2 = side == 0 ? 0 : side == 1 ? k : side == 2 ? n : k;
                return sheet.positions[std::size_t(j2 * (n + 1) + i2)];
            };
            expected += double(glm::length(at(i + 1) - at(i)));
        }
    EXPECT_NEAR(length, expected, 1e-4 * expected);
}

// The billboards' renderer culls the coarse mesh's back faces for models of one closed surface wound
// outward (enhanced_billboards/renderer.cpp): the simplification must keep that winding and leave
// the surface closed, or the faces that fill a hole would be the culled ones.
TEST(CoarseMesh, ClosedSurfacesStayClosedAndWoundOutward)
{
    for (GeneratedShape shape : {GeneratedShape::sphere, GeneratedShape::noisy_sphere}) {
        Mesh source = test::generated(shape, 20000);
        Mesh coarse = make_coarse_mesh(source, 0.1f);
        ASSERT_GT(coarse.triangle_count(), 0u);
        auto signed_volume = [](const Mesh& m) {
            double v = 0.0;
            for (std::size_t t = 0; t < m.triangle_count(); ++t) {
                glm::dvec3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
                           c = m.positions[m.indices[3 * t + 2]];
                v += glm::dot(a, glm::cross(b, c)) / 6.0;
            }
            return v;
        };
        const double source_volume = signed_volume(source), coarse_volume = signed_volume(coarse);
        EXPECT_GT(source_volume, 0.0);
        EXPECT_NEAR(coarse_volume, source_volume, 0.05 * source_volume) << int(shape);
        // every directed edge (between welded positions) has its opposite: closed, consistently wound
        std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, int> edges;
        auto key = [](glm::vec3 p) { return std::array<float, 3>{p.x, p.y, p.z}; };
        for (std::size_t t = 0; t < coarse.triangle_count(); ++t)
            for (int k = 0; k < 3; ++k)
                ++edges[{key(coarse.positions[coarse.indices[3 * t + k]]), key(coarse.positions[coarse.indices[3 * t + (k + 1) % 3]])}];
        std::size_t unmatched = 0;
        for (const auto& [edge, count] : edges) {
            auto opposite = edges.find({edge.second, edge.first});
            if (count != 1 || opposite == edges.end() || opposite->second != 1) ++unmatched;
        }
        EXPECT_EQ(unmatched, 0u) << int(shape) << ": " << edges.size() << " directed edges";
    }
}

// The coarse mesh's levels for small instances (issue #17): level 0 is the mesh itself, each later
// one at most 4/5 of the triangles before it, all on the mesh's vertices, closed where the mesh is,
// and with an error that grows down the levels and bounds how far the enclosed volume moves (a
// surface within e of the mesh encloses a volume within area x e of its own).
TEST(CoarseMesh, LevelsHaveFewerTrianglesWithinTheirError)
{
    const Mesh coarse = coarse_of_noisy_sphere();
    std::vector<std::uint32_t> indices;
    const std::vector<CoarseLevel> levels = coarse_mesh_levels(coarse, indices);
    ASSERT_GE(levels.size(), 3u) << coarse.triangle_count() << " triangles";
    EXPECT_EQ(levels[0].first_index, 0u);
    EXPECT_EQ(levels[0].index_count, coarse.indices.size());
    EXPECT_EQ(levels[0].error, 0.0f);
    EXPECT_TRUE(std::equal(coarse.indices.begin(), coarse.indices.end(), indices.begin()));
    for (std::uint32_t i : indices) ASSERT_LT(i, coarse.vertex_count());
    auto volume_and_area = [&](const CoarseLevel& level) {
        double v = 0.0, a = 0.0;
        for (std::uint32_t t = level.first_index; t < level.first_index + level.index_count; t += 3) {
            glm::dvec3 p = coarse.positions[indices[t]], q = coarse.positions[indices[t + 1]], r = coarse.positions[indices[t + 2]];
            v += glm::dot(p, glm::cross(q, r)) / 6.0;
            a += 0.5 * glm::length(glm::cross(q - p, r - p));
        }
        return std::pair<double, double>(v, a);
    };
    const auto [volume, area] = volume_and_area(levels[0]);
    for (std::size_t k = 1; k < levels.size(); ++k) {
        SCOPED_TRACE("level " + std::to_string(k));
        EXPECT_EQ(levels[k].first_index, levels[k - 1].first_index + levels[k - 1].index_count);
        EXPECT_EQ(levels[k].index_count % 3, 0u);
        EXPECT_LE(double(levels[k].index_count), 0.8 * double(levels[k - 1].index_count));
        EXPECT_GE(levels[k].index_count, 3 * (k_min_coarse_triangles / 4) / 4);
        EXPECT_GT(levels[k].error, levels[k - 1].error);
        EXPECT_LE(std::abs(volume_and_area(levels[k]).first - volume), area * double(levels[k].error) + 1e-9);
    }
    EXPECT_EQ(indices.size(), std::size_t(levels.back().first_index + levels.back().index_count));

    // too few triangles for a level: the mesh alone
    const Mesh small = make_coarse_mesh(test::generated(GeneratedShape::sphere, 200), 1.0f);
    std::vector<std::uint32_t> small_indices;
    EXPECT_EQ(coarse_mesh_levels(small, small_indices).size(), 1u) << small.triangle_count() << " triangles";
}

TEST(CoarseMeshFile, RoundTripKeepsEveryTriangle)
{
    Mesh mesh = coarse_of_noisy_sphere();
    ASSERT_GT(mesh.triangle_count(), 1000u);
    std::string bytes = encode_coarse_mesh(mesh);
    EXPECT_EQ(encode_coarse_mesh(mesh), bytes) << "deterministic";
    Result<Mesh> read = decode_coarse_mesh(bytes, "c.meshopt", mesh.triangle_count(), mesh.vertex_count());
    ASSERT_TRUE(read) << read.status().message();
    ASSERT_EQ(read->triangle_count(), mesh.triangle_count());
    ASSERT_EQ(read->vertex_count(), mesh.vertex_count());
    ASSERT_EQ(read->normals.size(), read->vertex_count());

    Bounds b = mesh.bounds();
    EXPECT_EQ(coarse_triangle_keys(*read, b, true), coarse_triangle_keys(mesh, b, false));
    // every decoded vertex sits in its source vertex's cell, with its colour to 8 bits
    std::map<std::array<long, 3>, glm::vec4> colour;
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
        colour[grid_cell(mesh.positions[v], b, false)] = glm::round(mesh.colors[v] * 255.0f) / 255.0f;
    for (std::size_t v = 0; v < read->vertex_count(); ++v) {
        auto cell = grid_cell(read->positions[v], b, true);
        ASSERT_TRUE(colour.count(cell)) << v;
        EXPECT_EQ(read->colors[v], colour[cell]);
    }
    // normals are not stored: the smooth normals of the decoded positions, as make_coarse_mesh's
    Mesh recomputed = *read;
    compute_smooth_normals(recomputed);
    EXPECT_EQ(recomputed.normals, read->normals);

    // the PLY of the same mesh: 6 floats and 4 bytes a vertex, 13 bytes a triangle
    std::size_t ply = mesh.vertex_count() * 28 + mesh.triangle_count() * 13;
    EXPECT_LT(bytes.size() * 4, ply) << bytes.size() << " bytes against " << ply;
}

void put_header_u32(std::string& s, std::size_t at, std::uint32_t v) { std::memcpy(&s[at], &v, 4); }

void expect_coarse_refused(const std::string& bytes, std::uint64_t triangles, std::uint64_t vertices, const std::string& needle)
{
    Result<Mesh> read = decode_coarse_mesh(bytes, "damaged.meshopt", triangles, vertices);
    ASSERT_FALSE(read) << needle;
    EXPECT_EQ(read.status().code(), StatusCode::bad_data);
    const std::string& message = read.status().message();
    EXPECT_NE(message.find("damaged.meshopt"), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

TEST(CoarseMeshFile, DamagedFilesAreRefused)
{
    Mesh mesh = coarse_of_noisy_sphere();
    const std::uint64_t t = mesh.triangle_count(), v = mesh.vertex_count();
    const std::string good = encode_coarse_mesh(mesh);
    ASSERT_TRUE(decode_coarse_mesh(good, "good.meshopt", t, v));

    expect_coarse_refused("", t, v, "not a compact coarse mesh");
    expect_coarse_refused(good.substr(0, 40), t, v, "not a compact coarse mesh");
    expect_coarse_refused(good.substr(0, good.size() - 1), t, v, "truncated");
    expect_coarse_refused(good, t + 1, v, "the manifest says");
    std::string layout = good;
    put_header_u32(layout, 8, 7);
    expect_coarse_refused(layout, t, v, "layout 7");
    std::string counts = good; // file and manifest agree, but the streams were coded for fewer
    put_header_u32(counts, 12, 0x7fffffffu);
    put_header_u32(counts, 16, 0x7fffffffu);
    Result<Mesh> huge = decode_coarse_mesh(counts, "damaged.meshopt", 0x7fffffffu, 0x7fffffffu);
    ASSERT_FALSE(huge);
    EXPECT_NE(huge.status().message().find("damaged.meshopt"), std::string::npos) << huge.status().message();
    std::string box = good;
    float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(&box[32], &nan, 4);
    expect_coarse_refused(box, t, v, "bounding box");
    std::string flipped = good; // zlib's checksum catches a changed byte of the stream
    flipped[good.size() / 2] = char(flipped[good.size() / 2] ^ 0x55);
    expect_coarse_refused(flipped, t, v, "damaged");
    std::string streams = good; // stream lengths that do not add up to what the zlib data inflates to
    put_header_u32(streams, 44, 1);
    expect_coarse_refused(streams, t, v, "does not inflate");

    // well-formed streams whose triangle names a vertex beyond the count
    const std::uint32_t indices[6] = {0, 1, 2, 2, 1, 3};
    std::uint8_t vertices[3 * 12] = {};
    std::vector<std::uint8_t> coded(meshopt_encodeVertexBufferBound(3, 12) + meshopt_encodeIndexBufferBound(6, 4));
    std::size_t vb = meshopt_encodeVertexBuffer(coded.data(), coded.size(), vertices, 3, 12);
    std::size_t ib = meshopt_encodeIndexBuffer(coded.data() + vb, coded.size() - vb, indices, 6);
    coded.resize(vb + ib);
    uLongf packed_size = compressBound(uLong(coded.size()));
    std::string packed(packed_size, '\0');
    ASSERT_EQ(compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, coded.data(), uLong(coded.size()), 9), Z_OK);
    packed.resize(packed_size);
    std::string file = good.substr(0, 56);
    put_header_u32(file, 12, 3);
    put_header_u32(file, 16, 2);
    put_header_u32(file, 44, std::uint32_t(vb));
    put_header_u32(file, 48, std::uint32_t(ib));
    put_header_u32(file, 52, std::uint32_t(packed.size()));
    expect_coarse_refused(file + packed, 2, 3, "names vertex 3 of 3");
}

} // namespace
} // namespace standin::reps
