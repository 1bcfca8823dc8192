// The coarse mesh (coarse_mesh.h). Vichitvejpaisal 2005 §3.4 asks for "usually 10 times fewer
// polygons" than the model; how is not said: we simplify with meshoptimizer (Garland & Heckbert's
// quadric error metric).
//
// The compact file (encode_coarse_mesh, issue #17: the PLY of float positions and normals and
// 32-bit indices was 10% of the source model, more than all the compressed maps together) follows
// meshoptimizer's own recipe for its codecs (Kapoulkine, meshoptimizer README, "Vertex/index buffer
// compression"): optimise the triangle order for the vertex cache, order the vertices by first use,
// quantise, encode the vertex and index buffers, then compress with a general-purpose compressor
// (zlib here, already used by the KTX2 maps). Departures: normals are not stored at all but
// recomputed on decode (they are make_coarse_mesh's smooth normals, a function of positions and
// triangles; docs/RESULTS.md "Compressed packages" measures the pictures), and the encoder format
// versions are pinned (vertex 0, index 1) so that the bytes do not change with the library.
#include "reps/common/coarse_mesh.h"

#include "reps/common/package_codec.h"

#include <standin/files.h>
#include <standin/limits.h>

#include <meshoptimizer.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <mutex>
#include <new>
#include <vector>

namespace standin::reps {

namespace {

// A texture's mean colour over its texels weighted by alpha (white when it has no alpha at all).
glm::vec4 covered_mean(const Texture& texture)
{
    glm::dvec3 sum(0.0);
    double weight = 0.0;
    for (std::size_t i = 0; i + 3 < texture.rgba.size(); i += 4) {
        double a = texture.rgba[i + 3] / 255.0;
        sum += a * glm::dvec3(texture.rgba[i], texture.rgba[i + 1], texture.rgba[i + 2]) / 255.0;
        weight += a;
    }
    return weight > 0.0 ? glm::vec4(glm::vec3(sum / weight), 1.0f) : glm::vec4(1.0f);
}

// The albedo of a source corner. An alpha-tested face's corners (a leaf card's) usually lie in its
// texture's cut-out, whose colour is arbitrary (black in most files): such a corner takes the vertex
// colour times the texture's mean over its covered texels instead (issue #14: the coarse mesh fills
// holes inside a crown, and black corners made those fills black).
glm::vec4 corner_albedo(const Mesh& mesh, std::uint32_t face, std::uint32_t slot, const std::vector<glm::vec4>& covered_colors)
{
    float b1 = slot == 1 ? 1.0f : 0.0f, b2 = slot == 2 ? 1.0f : 0.0f;
    const Material& material = mesh.materials[mesh.face_materials[face]];
    if (alpha_test_cutoff(material) <= 0.0f || material.base_color_texture < 0 || !mesh.has_texture_coordinates() ||
        mesh.covered_at(face, b1, b2))
        return mesh.albedo_at(face, b1, b2);
    glm::vec4 color = mesh.colors[mesh.indices[std::size_t(face) * 3 + slot]];
    return glm::vec4(glm::vec3(color) * glm::vec3(covered_colors[std::size_t(material.base_color_texture)]), color.w);
}

} // namespace

Mesh make_coarse_mesh(const Mesh& mesh, float ratio, bool lock_borders, float max_error)
{
    Mesh coarse;
    // no triangles: nothing to simplify (an alpha-tested model's opaque faces may be none, and
    // meshopt_simplify asserts on a target above its input)
    if (ratio <= 0.0f || mesh.indices.size() < 3) return coarse;
    std::size_t index_count = mesh.indices.size();
    std::vector<std::uint32_t> welded(index_count), simplified(index_count);
    meshopt_generateShadowIndexBuffer(welded.data(), mesh.indices.data(), index_count, mesh.positions.data(),
                                      mesh.vertex_count(), sizeof(glm::vec3), sizeof(glm::vec3));
    std::size_t triangles = index_count / 3;
    std::size_t target_triangles = std::max(std::size_t(double(triangles) * ratio), std::min(triangles, k_min_coarse_triangles));
    std::size_t target = std::max<std::size_t>(1, target_triangles) * 3;
    const float* positions = &mesh.positions[0].x;
    // lock_borders (issue #17): the enhanced billboards' renderer draws the coarse triangles along a
    // sheet's open boundary to fill the rim's holes (enhanced_billboards/renderer.cpp, rims_first),
    // which needs the true outline; collapsing along a border made it chords, inside a curved rim
    // (measured on the sheet assembly: holes 0.022% unlocked, 0.0087% locked)
    const unsigned options = lock_borders ? meshopt_SimplifyLockBorder : 0;
    float error_rel = 0.0f;
    std::size_t count = meshopt_simplify(simplified.data(), welded.data(), index_count, positions, mesh.vertex_count(),
                                         sizeof(glm::vec3), target, 1.0f, options, &error_rel);
    if (count > target * 2)
        count = meshopt_simplifySloppy(simplified.data(), welded.data(), index_count, positions, mesh.vertex_count(),
                                       sizeof(glm::vec3), target, 1.0f, &error_rel);
    // max_error (issue #17): the ratio's mesh strays further from the surface than the stand-in
    // can miss it by, so simplify only as far as that error allows (more triangles); a mesh within
    // it stays as it was
    if (max_error > 0.0f) {
        float scale = meshopt_simplifyScale(positions, mesh.vertex_count(), sizeof(glm::vec3));
        float max_error_rel = scale > 0.0f ? max_error / scale : 0.0f;
        if (error_rel > max_error_rel)
            count = meshopt_simplify(simplified.data(), welded.data(), index_count, positions, mesh.vertex_count(),
                                     sizeof(glm::vec3), target, max_error_rel, options, nullptr);
    }
    simplified.resize(count);

    // compact the vertices, in order of first use; colour = albedo of the source vertex
    std::vector<glm::vec4> covered_colors;
    covered_colors.reserve(mesh.textures.size());
    for (const Texture& texture : mesh.textures) covered_colors.push_back(covered_mean(texture));
    std::vector<std::uint32_t> remap(mesh.vertex_count(), 0xffffffffu);
    std::vector<std::uint32_t> corner_face(mesh.vertex_count(), 0), corner_slot(mesh.vertex_count(), 0);
    for (std::size_t i = 0; i < index_count; ++i) corner_face[welded[i]] = std::uint32_t(i / 3), corner_slot[welded[i]] = std::uint32_t(i % 3);
    for (std::uint32_t& index : simplified) {
        if (remap[index] == 0xffffffffu) {
            remap[index] = std::uint32_t(coarse.positions.size());
            coarse.positions.push_back(mesh.positions[index]);
            // the welded vertex is one of the source corners at this position; take its albedo
            std::uint32_t face = corner_face[index], slot = corner_slot[index];
            coarse.colors.push_back(corner_albedo(mesh, face, slot, covered_colors));
        }
        index = remap[index];
    }
    coarse.indices = std::move(simplified);
    coarse.face_materials.assign(coarse.triangle_count(), 0);
    coarse.materials.push_back(Material{"coarse", glm::vec4(1.0f), -1});
    compute_smooth_normals(coarse);
    return coarse;
}

std::vector<CoarseLevel> coarse_mesh_levels(const Mesh& coarse, std::vector<std::uint32_t>& indices)
{
    indices = coarse.indices;
    std::vector<CoarseLevel> levels = {{0, std::uint32_t(indices.size()), 0.0f}};
    const std::size_t index_count = coarse.indices.size(), min_indices = 3 * (k_min_coarse_triangles / 4);
    if (index_count < 4 * min_indices || coarse.vertex_count() == 0) return levels;
    const float* positions = &coarse.positions[0].x;
    std::vector<std::uint32_t> source(index_count), simplified(index_count);
    meshopt_generateShadowIndexBuffer(source.data(), coarse.indices.data(), index_count, positions, coarse.vertex_count(),
                                      sizeof(glm::vec3), sizeof(glm::vec3));
    const float scale = meshopt_simplifyScale(positions, coarse.vertex_count(), sizeof(glm::vec3));
    float error = 0.0f;
    for (;;) {
        const std::size_t target = source.size() / 12 * 3;
        if (target < min_indices) break;
        float error_rel = 0.0f;
        const std::size_t count = meshopt_simplify(simplified.data(), source.data(), source.size(), positions,
                                                   coarse.vertex_count(), sizeof(glm::vec3), target, 1.0f,
                                                   meshopt_SimplifyLockBorder, &error_rel);
        // (locked borders stop it early on sheets: a level of barely fewer triangles is not worth one)
        if (count < 3 || double(count) > 0.8 * double(source.size())) break;
        error += error_rel * scale;
        levels.push_back({std::uint32_t(indices.size()), std::uint32_t(count), error});
        indices.insert(indices.end(), simplified.begin(), simplified.begin() + std::ptrdiff_t(count));
        source.assign(simplified.begin(), simplified.begin() + std::ptrdiff_t(count));
    }
    return levels;
}

// ------------------------------------------------------------------------------------------------
// Compact file (docs/FORMAT.md, "Compact coarse mesh"), little-endian:
//   0 "STCOARSE", 8 u32 layout 1, 12 u32 vertices, 16 u32 triangles, 20 f32 lo[3], 32 f32 extent[3],
//   44 u32 vertex-codec bytes, 48 u32 index-codec bytes, 52 u32 zlib bytes, 56 the zlib stream of
//   the vertex codec's bytes followed by the index codec's.
// A vertex is 12 bytes: u16 x, y, z (position = lo + q * extent / 65535), u16 0, u8 r, g, b, a.

namespace {

constexpr char k_coarse_magic[8] = {'S', 'T', 'C', 'O', 'A', 'R', 'S', 'E'};
constexpr std::uint32_t k_coarse_layout = 1;
constexpr std::size_t k_coarse_header = 56, k_coarse_vertex = 12;
constexpr float k_coarse_steps = 65535.0f;

void put_u32(std::string& out, std::uint32_t v)
{
    for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
}
void put_f32(std::string& out, float f)
{
    std::uint32_t v = 0;
    std::memcpy(&v, &f, 4);
    put_u32(out, v);
}
std::uint32_t get_u32(std::string_view bytes, std::size_t at)
{
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= std::uint32_t(static_cast<unsigned char>(bytes[at + std::size_t(k)])) << (8 * k);
    return v;
}
float get_f32(std::string_view bytes, std::size_t at)
{
    std::uint32_t v = get_u32(bytes, at);
    float f = 0.0f;
    std::memcpy(&f, &v, 4);
    return f;
}

std::uint8_t coarse_unorm8(float value)
{
    if (!(value > 0.0f)) return 0; // also NaN
    if (value >= 1.0f) return 255;
    return std::uint8_t(std::lround(value * 255.0f));
}

// The codecs' output formats are global settings of the library: pin them once, for every thread.
void pin_codec_versions()
{
    static std::once_flag once;
    std::call_once(once, [] {
        meshopt_encodeVertexVersion(0);
        meshopt_encodeIndexVersion(1);
    });
}

} // namespace

std::string encode_coarse_mesh(const Mesh& mesh)
{
    pin_codec_versions();
    const std::size_t vertex_count = mesh.vertex_count(), index_count = mesh.indices.size();
    // triangle order for the vertex cache, then vertices in order of first use (unused ones last,
    // in their order: the count stays the manifest's)
    std::vector<std::uint32_t> indices(index_count), remap(vertex_count);
    meshopt_optimizeVertexCache(indices.data(), mesh.indices.data(), index_count, vertex_count);
    std::size_t used = meshopt_optimizeVertexFetchRemap(remap.data(), indices.data(), index_count, vertex_count);
    for (std::uint32_t& r : remap)
        if (r == ~0u) r = std::uint32_t(used++);
    for (std::uint32_t& index : indices) index = remap[index];

    glm::vec3 lo(0.0f), hi(0.0f);
    if (vertex_count > 0) lo = hi = mesh.positions[0];
    for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const glm::vec3 extent = hi - lo;
    std::vector<std::uint8_t> vertices(vertex_count * k_coarse_vertex, 0);
    for (std::size_t v = 0; v < vertex_count; ++v) {
        std::uint8_t* out = &vertices[std::size_t(remap[v]) * k_coarse_vertex];
        for (int a = 0; a < 3; ++a) {
            float t = extent[a] > 0.0f ? (mesh.positions[v][a] - lo[a]) / extent[a] : 0.0f;
            auto q = std::uint16_t(std::lround(std::clamp(t, 0.0f, 1.0f) * k_coarse_steps));
            out[2 * a] = std::uint8_t(q & 0xff), out[2 * a + 1] = std::uint8_t(q >> 8);
        }
        glm::vec4 c = v < mesh.colors.size() ? mesh.colors[v] : glm::vec4(1.0f);
        for (int k = 0; k < 4; ++k) out[8 + k] = coarse_unorm8(c[k]);
    }

    std::vector<std::uint8_t> streams(meshopt_encodeVertexBufferBound(vertex_count, k_coarse_vertex) +
                                      meshopt_encodeIndexBufferBound(index_count, vertex_count));
    std::size_t vertex_bytes =
        meshopt_encodeVertexBuffer(streams.data(), streams.size(), vertices.data(), vertex_count, k_coarse_vertex);
    std::size_t index_bytes = meshopt_encodeIndexBuffer(streams.data() + vertex_bytes, streams.size() - vertex_bytes,
                                                        indices.data(), index_count);
    streams.resize(vertex_bytes + index_bytes);
    uLongf packed_size = compressBound(uLong(streams.size()));
    std::string packed(packed_size, '\0');
    if (compress2(reinterpret_cast<Bytef*>(packed.data()), &packed_size, streams.data(), uLong(streams.size()), 9) != Z_OK)
        throw std::bad_alloc(); // zlib fails only without memory
    packed.resize(packed_size);

    std::string out(k_coarse_magic, sizeof k_coarse_magic);
    put_u32(out, k_coarse_layout);
    put_u32(out, std::uint32_t(vertex_count));
    put_u32(out, std::uint32_t(index_count / 3));
    for (int a = 0; a < 3; ++a) put_f32(out, lo[a]);
    for (int a = 0; a < 3; ++a) put_f32(out, extent[a]);
    put_u32(out, std::uint32_t(vertex_bytes));
    put_u32(out, std::uint32_t(index_bytes));
    put_u32(out, std::uint32_t(packed.size()));
    return out + packed;
}

Result<Mesh> decode_coarse_mesh(std::string_view bytes, const std::string& path, std::uint64_t triangles,
                                std::uint64_t vertices)
{
    auto bad = [&](const std::string& problem) { return error(StatusCode::bad_data, quoted(path) + ": " + problem); };
    if (bytes.size() < k_coarse_header || bytes.compare(0, sizeof k_coarse_magic, std::string_view(k_coarse_magic, 8)) != 0)
        return bad("not a compact coarse mesh (truncated or wrong identifier)");
    if (get_u32(bytes, 8) != k_coarse_layout)
        return bad("layout " + std::to_string(get_u32(bytes, 8)) + " is not read (only " + std::to_string(k_coarse_layout) + ")");
    const std::uint64_t vertex_count = get_u32(bytes, 12), triangle_count = get_u32(bytes, 16);
    if (vertex_count != vertices || triangle_count != triangles)
        return bad("holds " + std::to_string(vertex_count) + " vertices and " + std::to_string(triangle_count) +
                   " triangles, the manifest says " + std::to_string(vertices) + " and " + std::to_string(triangles));
    if (triangle_count == 0 || vertex_count == 0) return bad("is empty");
    STANDIN_RETURN_IF_ERROR(check_triangles(triangle_count, quoted(path)));
    const std::uint64_t index_count = triangle_count * 3;
    STANDIN_RETURN_IF_ERROR(check_memory(vertex_count * (k_coarse_vertex + sizeof(glm::vec3) * 2 + sizeof(glm::vec4)) +
                                             index_count * sizeof(std::uint32_t) * 2,
                                         quoted(path)));
    glm::vec3 lo, extent;
    for (int a = 0; a < 3; ++a) lo[a] = get_f32(bytes, 20 + 4 * std::size_t(a)), extent[a] = get_f32(bytes, 32 + 4 * std::size_t(a));
    for (int a = 0; a < 3; ++a)
        if (!std::isfinite(lo[a]) || !std::isfinite(extent[a]) || extent[a] < 0.0f ||
            std::abs(lo[a]) > manifest_io::k_max_coordinate || std::abs(lo[a] + extent[a]) > manifest_io::k_max_coordinate)
            return bad("has a bounding box that is not finite, negative or beyond +-1e15");
    const std::uint64_t vertex_bytes = get_u32(bytes, 44), index_bytes = get_u32(bytes, 48), packed_bytes = get_u32(bytes, 52);
    if (packed_bytes != bytes.size() - k_coarse_header)
        return bad("has " + std::to_string(bytes.size() - k_coarse_header) + " bytes of data, its header says " +
                   std::to_string(packed_bytes) + " (truncated?)");
    if (vertex_bytes > meshopt_encodeVertexBufferBound(vertex_count, k_coarse_vertex) ||
        index_bytes > meshopt_encodeIndexBufferBound(index_count, vertex_count))
        return bad("declares codec streams longer than " + std::to_string(vertex_count) + " vertices and " +
                   std::to_string(triangle_count) + " triangles can take");
    std::vector<std::uint8_t> streams(vertex_bytes + index_bytes);
    uLongf size = uLongf(streams.size());
    if (uncompress(streams.data(), &size, reinterpret_cast<const Bytef*>(bytes.data() + k_coarse_header), uLong(packed_bytes)) != Z_OK ||
        size != streams.size())
        return bad("does not inflate to its " + std::to_string(streams.size()) + " bytes (damaged)");
    std::vector<std::uint8_t> packed_vertices(vertex_count * k_coarse_vertex);
    if (meshopt_decodeVertexBuffer(packed_vertices.data(), vertex_count, k_coarse_vertex, streams.data(), vertex_bytes) != 0)
        return bad("vertex stream does not decode (damaged)");
    Mesh mesh;
    mesh.indices.resize(index_count);
    if (meshopt_decodeIndexBuffer(mesh.indices.data(), index_count, sizeof(std::uint32_t), streams.data() + vertex_bytes,
                                  index_bytes) != 0)
        return bad("index stream does not decode (damaged)");
    for (std::size_t i = 0; i < index_count; ++i)
        if (mesh.indices[i] >= vertex_count)
            return bad("triangle " + std::to_string(i / 3) + " names vertex " + std::to_string(mesh.indices[i]) + " of " +
                       std::to_string(vertex_count) + " (damaged)");
    mesh.positions.resize(vertex_count);
    mesh.colors.resize(vertex_count);
    const glm::vec3 step = extent / k_coarse_steps;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const std::uint8_t* in = &packed_vertices[v * k_coarse_vertex];
        for (int a = 0; a < 3; ++a) mesh.positions[v][a] = lo[a] + float(in[2 * a] | (in[2 * a + 1] << 8)) * step[a];
        mesh.colors[v] = glm::vec4(in[8], in[9], in[10], in[11]) / 255.0f;
    }
    mesh.face_materials.assign(triangle_count, 0);
    mesh.materials.push_back(Material{"coarse", glm::vec4(1.0f), -1});
    compute_smooth_normals(mesh);
    return mesh;
}

} // namespace standin::reps
