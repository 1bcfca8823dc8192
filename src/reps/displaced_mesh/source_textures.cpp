// Control faces that are source triangles, and the textures they read (source_textures.h says why).
// Steps:
//  1. key every textured source triangle that qualifies (alpha-masked, or any with every_face) by
//     its three positions' bits, rotated to start at the smallest corner (winding kept), first
//     triangle first;
//  2. look each control face up by the same key: a hit is that triangle, corner for corner, and
//     the face takes its UVs and colours in its own corner order;
//  3. the textures the hits use become layers, in the order of their index in the mesh.
#include "reps/displaced_mesh/source_textures.h"

#include "reps/displaced_mesh/displaced_mesh.h"

#include <algorithm>
#include <array>
#include <bit>
#include <map>
#include <unordered_map>

namespace standin::displaced_mesh {

namespace {

using Key = std::array<std::uint32_t, 9>;

struct KeyHash {
    std::size_t operator()(const Key& key) const
    {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint32_t v : key) h = (h ^ v) * 1099511628211ull;
        return std::size_t(h);
    }
};

std::array<std::uint32_t, 3> bits_of(glm::vec3 p)
{
    return {std::bit_cast<std::uint32_t>(p.x), std::bit_cast<std::uint32_t>(p.y), std::bit_cast<std::uint32_t>(p.z)};
}

// The triangle's key and the corner it starts at: the rotation whose first corner's bits are least.
Key key_of(const glm::vec3 (&corner)[3], int& rotation)
{
    std::array<std::uint32_t, 3> bits[3] = {bits_of(corner[0]), bits_of(corner[1]), bits_of(corner[2])};
    rotation = 0;
    for (int r = 1; r < 3; ++r)
        if (bits[r] < bits[rotation]) rotation = r;
    Key key{};
    for (int i = 0; i < 3; ++i)
        for (int c = 0; c < 3; ++c) key[std::size_t(3 * i + c)] = bits[(i + rotation) % 3][std::size_t(c)];
    return key;
}

bool finite(glm::vec2 uv) { return std::isfinite(uv.x) && std::isfinite(uv.y); }

} // namespace

std::size_t SourceTextures::matched_faces() const
{
    return std::size_t(std::count_if(faces.begin(), faces.end(), [](const FaceTexture& f) { return f.layer != k_no_texture; }));
}

SourceTextures match_source_textures(const Mesh& mesh, const std::vector<glm::vec3>& positions,
                                     const std::vector<std::uint32_t>& indices, bool every_face)
{
    SourceTextures out;
    if (!mesh.has_texture_coordinates()) return out;
    auto qualifies = [&](std::size_t t) {
        const Material& m = mesh.materials[mesh.face_materials[t]];
        if (m.base_color_texture < 0) return false;
        const Texture& texture = mesh.textures[std::size_t(m.base_color_texture)];
        if (texture.width <= 0 || texture.height <= 0) return false;
        return every_face || alpha_test_cutoff(m) > 0.0f;
    };
    // 1. the source triangles by key
    std::unordered_map<Key, std::pair<std::uint32_t, int>, KeyHash> source;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        if (!qualifies(t)) continue;
        const std::uint32_t* v = &mesh.indices[3 * t];
        if (!finite(mesh.uvs[v[0]]) || !finite(mesh.uvs[v[1]]) || !finite(mesh.uvs[v[2]])) continue;
        const glm::vec3 corner[3] = {mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]};
        int rotation = 0;
        Key key = key_of(corner, rotation);
        source.try_emplace(key, std::uint32_t(t), rotation);
    }
    if (source.empty()) return out;

    // 2. the control faces
    const std::size_t faces = indices.size() / 3;
    std::vector<std::int64_t> matched(faces, -1); // source triangle
    std::vector<int> shift(faces, 0);             // control corner k is source corner (k + shift) % 3
    std::map<int, std::uint32_t> layer_of;        // texture index -> layer, ascending
    for (std::size_t f = 0; f < faces; ++f) {
        const glm::vec3 corner[3] = {positions[indices[3 * f]], positions[indices[3 * f + 1]], positions[indices[3 * f + 2]]};
        int rotation = 0;
        auto hit = source.find(key_of(corner, rotation));
        if (hit == source.end()) continue;
        matched[f] = hit->second.first;
        shift[f] = (hit->second.second - rotation + 3) % 3;
        layer_of.emplace(mesh.materials[mesh.face_materials[hit->second.first]].base_color_texture, 0u);
    }
    if (layer_of.empty()) return out;

    // 3. the layers
    std::uint32_t next = 0;
    for (auto& [texture, layer] : layer_of) {
        layer = next++;
        out.layers.push_back(mesh.textures[std::size_t(texture)]);
    }
    out.faces.resize(faces);
    out.source_corners.resize(faces, {0u, 0u, 0u});
    for (std::size_t f = 0; f < faces; ++f) {
        if (matched[f] < 0) continue;
        const std::size_t t = std::size_t(matched[f]);
        const Material& m = mesh.materials[mesh.face_materials[t]];
        FaceTexture& record = out.faces[f];
        record.layer = layer_of.at(m.base_color_texture);
        record.cutoff = alpha_test_cutoff(m);
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t v = mesh.indices[3 * t + std::size_t((k + shift[f]) % 3)];
            record.uv[k] = mesh.uvs[v];
            record.color[k] = pack_rgba8(mesh.colors[v]);
            out.source_corners[f][std::size_t(k)] = v;
        }
    }
    return out;
}

} // namespace standin::displaced_mesh
