// A minimal glTF 2.0 writer (Khronos glTF 2.0 specification, 2017): one self-contained .gltf whose
// buffer and textures are data URIs, so `standin generate tree` writes one file, atomically.
// Steps: check that vertex colours are the materials' base colours (glTF vertex colours are linear
// and would multiply the base colour a second time on import), written as glTF's linear factors; pack positions, normals, UVs and one
// index range per material into one buffer; write one primitive per material with its base colour,
// texture, alphaMode, alphaCutoff and doubleSided. Textures are written top row first with v
// flipped (glTF's UV origin is the image's top left; Mesh keeps row 0 at v = 0), which is what
// import_mesh undoes. nlohmann::json orders keys, so the bytes depend on the mesh alone.
#include <standin/files.h>
#include <standin/image.h>
#include <standin/mesh.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>

namespace standin {

namespace {

std::string gltf_base64(const std::string& bytes)
{
    static const char* k_digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        std::uint32_t v = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= std::uint32_t(std::uint8_t(bytes[i + 2]));
        out += k_digits[(v >> 18) & 63];
        out += k_digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? k_digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? k_digits[v & 63] : '=';
    }
    return out;
}

void gltf_append(std::string& buffer, const void* data, std::size_t size)
{
    buffer.append(static_cast<const char*>(data), size);
    while (buffer.size() % 4 != 0) buffer.push_back('\0');
}

} // namespace

Status write_gltf(const Mesh& mesh, const std::string& path)
{
    STANDIN_RETURN_IF_ERROR(validate_mesh(mesh, quoted(path)));
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
        const glm::vec4& base = mesh.materials[mesh.face_materials[t]].base_color;
        for (int k = 0; k < 3; ++k) {
            glm::vec4 d = glm::abs(mesh.colors[mesh.indices[3 * t + std::size_t(k)]] - base);
            if (std::max(std::max(d.x, d.y), std::max(d.z, d.w)) > 1.0f / 512.0f)
                return error(StatusCode::invalid_argument,
                             quoted(path) + ": glTF is written without vertex colours, and triangle " + std::to_string(t) +
                                 " has vertex colours other than its material's base colour");
        }
    }
    nlohmann::json doc;
    doc["asset"] = {{"version", "2.0"}, {"generator", "standin"}};
    std::string buffer;
    nlohmann::json views = nlohmann::json::array(), accessors = nlohmann::json::array();
    auto add_view = [&](const void* data, std::size_t size, int target) {
        std::size_t offset = buffer.size();
        gltf_append(buffer, data, size);
        views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}, {"target", target}});
        return views.size() - 1;
    };
    const std::size_t n = mesh.vertex_count();
    glm::vec3 lo = mesh.positions[0], hi = mesh.positions[0];
    for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    std::size_t view = add_view(mesh.positions.data(), n * sizeof(glm::vec3), 34962);
    accessors.push_back({{"bufferView", view}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"},
                         {"min", {lo.x, lo.y, lo.z}}, {"max", {hi.x, hi.y, hi.z}}});
    nlohmann::json attributes = {{"POSITION", 0}};
    view = add_view(mesh.normals.data(), n * sizeof(glm::vec3), 34962);
    accessors.push_back({{"bufferView", view}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}});
    attributes["NORMAL"] = accessors.size() - 1;
    if (mesh.has_texture_coordinates()) {
        std::vector<glm::vec2> uvs = mesh.uvs;
        for (glm::vec2& uv : uvs) uv.y = 1.0f - uv.y;
        view = add_view(uvs.data(), n * sizeof(glm::vec2), 34962);
        accessors.push_back({{"bufferView", view}, {"componentType", 5126}, {"count", n}, {"type", "VEC2"}});
        attributes["TEXCOORD_0"] = accessors.size() - 1;
    }
    nlohmann::json primitives = nlohmann::json::array();
    for (std::size_t m = 0; m < mesh.materials.size(); ++m) {
        std::vector<std::uint32_t> indices;
        for (std::size_t t = 0; t < mesh.triangle_count(); ++t)
            if (mesh.face_materials[t] == m) indices.insert(indices.end(), &mesh.indices[3 * t], &mesh.indices[3 * t] + 3);
        if (indices.empty()) continue;
        view = add_view(indices.data(), indices.size() * sizeof(std::uint32_t), 34963);
        accessors.push_back({{"bufferView", view}, {"componentType", 5125}, {"count", indices.size()}, {"type", "SCALAR"}});
        primitives.push_back({{"attributes", attributes}, {"indices", accessors.size() - 1}, {"material", m}, {"mode", 4}});
    }
    nlohmann::json materials = nlohmann::json::array();
    for (const Material& m : mesh.materials) {
        // glTF's factor is linear; Mesh's colours are sRGB-encoded (import encodes it back)
        nlohmann::json pbr = {{"baseColorFactor", {srgb_to_linear(m.base_color.x), srgb_to_linear(m.base_color.y), srgb_to_linear(m.base_color.z), m.base_color.w}},
                              {"metallicFactor", 0.0},
                              {"roughnessFactor", 1.0}};
        if (m.base_color_texture >= 0) pbr["baseColorTexture"] = {{"index", m.base_color_texture}};
        nlohmann::json material = {{"name", m.name}, {"pbrMetallicRoughness", pbr}, {"doubleSided", m.double_sided}};
        material["alphaMode"] = m.alpha_mode == AlphaMode::mask ? "MASK" : m.alpha_mode == AlphaMode::blend ? "BLEND" : "OPAQUE";
        if (m.alpha_mode == AlphaMode::mask) material["alphaCutoff"] = m.alpha_cutoff;
        materials.push_back(material);
    }
    nlohmann::json images = nlohmann::json::array(), textures = nlohmann::json::array();
    for (std::size_t t = 0; t < mesh.textures.size(); ++t) {
        const Texture& texture = mesh.textures[t];
        ImageRGBA8 image(texture.width, texture.height);
        std::size_t row = std::size_t(texture.width) * 4;
        for (int y = 0; y < texture.height; ++y)
            std::memcpy(image.at(0, y), &texture.rgba[std::size_t(texture.height - 1 - y) * row], row);
        Result<std::string> png = encode_png_bytes(image);
        if (!png) return error(png.status().code(), quoted(path) + ": " + png.status().message());
        images.push_back({{"name", texture.name}, {"uri", "data:image/png;base64," + gltf_base64(*png)}});
        textures.push_back({{"source", t}, {"sampler", 0}});
    }
    doc["buffers"] = {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + gltf_base64(buffer)}}};
    doc["bufferViews"] = views;
    doc["accessors"] = accessors;
    doc["materials"] = materials;
    doc["meshes"] = {{{"primitives", primitives}}};
    doc["nodes"] = {{{"mesh", 0}}};
    doc["scenes"] = {{{"nodes", {0}}}};
    doc["scene"] = 0;
    if (!textures.empty()) {
        doc["images"] = images;
        doc["textures"] = textures;
        doc["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}, {"wrapS", 10497}, {"wrapT", 10497}}};
    }
    return write_file_atomic(path, doc.dump(1) + "\n");
}

} // namespace standin
