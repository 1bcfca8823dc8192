// Binary glTF 2.0 writer (Khronos glTF 2.0 specification, §4.4 "GLB file format"; materials §3.9,
// KHR_materials_unlit is not used): the JSON is built with nlohmann::json and the binary chunk by
// hand rather than with tinygltf (Debian's libtinygltf-dev 2.7) because
//   1. the output must be byte-identical for the same scene (nlohmann's objects are sorted maps,
//      numbers print the same every time, and we choose the buffer order), and
//   2. our scenes are a handful of flat meshes: a writer is ~200 lines, a new dependency is not.
// Steps: one buffer (the BIN chunk); per mesh a buffer view and accessor per attribute (POSITION
// with its exact min/max as the validator requires) and one for 32-bit indices; per texture a
// buffer view holding the PNG; one material per mesh; a root node with one child node per mesh.
#include <standin/export.h>
#include <standin/image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace standin {

namespace {

constexpr int k_gltf_float = 5126;
constexpr int k_gltf_unsigned_int = 5125;
constexpr int k_gltf_array_buffer = 34962;
constexpr int k_gltf_element_array_buffer = 34963;
constexpr int k_gltf_linear = 9729;
constexpr int k_gltf_linear_mipmap_linear = 9987;
constexpr int k_gltf_clamp_to_edge = 33071;
constexpr int k_gltf_repeat = 10497;

struct GlbBuilder {
    std::string bin;
    nlohmann::json buffer_views = nlohmann::json::array();
    nlohmann::json accessors = nlohmann::json::array();

    int add_view(const void* data, std::size_t bytes, int target)
    {
        while (bin.size() % 4 != 0) bin.push_back('\0');
        nlohmann::json view = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (target != 0) view["target"] = target;
        bin.append(static_cast<const char*>(data), bytes);
        buffer_views.push_back(view);
        return int(buffer_views.size()) - 1;
    }

    int add_accessor(int view, int component_type, std::size_t count, const char* type)
    {
        accessors.push_back({{"bufferView", view}, {"componentType", component_type}, {"count", count}, {"type", type}});
        return int(accessors.size()) - 1;
    }

    template <typename T>
    int add_floats(const std::vector<T>& values, const char* type)
    {
        int view = add_view(values.data(), values.size() * sizeof(T), k_gltf_array_buffer);
        return add_accessor(view, k_gltf_float, values.size(), type);
    }
};

Status glb_check_mesh(const ExportMesh& mesh, std::size_t textures)
{
    auto bad = [&](const std::string& what) { return error(StatusCode::bad_data, "export mesh " + mesh.name + ": " + what); };
    const std::size_t n = mesh.positions.size();
    if (n == 0 || mesh.indices.empty() || mesh.indices.size() % 3 != 0) return bad("no triangles");
    if (!mesh.normals.empty() && mesh.normals.size() != n) return bad("normal count");
    if (!mesh.uvs.empty() && mesh.uvs.size() != n) return bad("uv count");
    if (!mesh.colors.empty() && mesh.colors.size() != n) return bad("colour count");
    for (std::uint32_t i : mesh.indices)
        if (i >= n) return bad("index out of range");
    for (const glm::vec3& p : mesh.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return bad("position not finite");
    for (int texture : {mesh.base_color_texture, mesh.orm_texture, mesh.emissive_texture})
        if (texture >= int(textures)) return bad("texture index out of range");
    return Status::ok();
}

// glTF requires unit normals (the validator checks |n| = 1 within 0.0005): renormalise, and give
// degenerate ones a direction rather than refusing the mesh.
std::vector<glm::vec3> glb_unit_normals(const std::vector<glm::vec3>& normals)
{
    std::vector<glm::vec3> out(normals.size());
    for (std::size_t i = 0; i < normals.size(); ++i) {
        glm::vec3 n = normals[i];
        float length = glm::length(n);
        out[i] = std::isfinite(length) && length > 1e-12f ? n / length : glm::vec3(0.0f, 0.0f, 1.0f);
    }
    return out;
}

nlohmann::json glb_vec(glm::vec3 v) { return {v.x, v.y, v.z}; }

// A material factor to six decimals: a float's 0.3 prints as 0.30000001192092896 through double.
double short_number(float value)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.6f", double(value));
    return std::strtod(text, nullptr);
}

} // namespace

Result<ExportTexture> make_export_texture(const std::string& name, const ImageRGBA8& image)
{
    Result<std::string> png = encode_png_bytes(image);
    if (!png) return png.status();
    return ExportTexture{name, image.width, image.height, 8, std::move(*png)};
}

Result<ExportTexture> make_export_texture(const std::string& name, const ImageRGBA16& image)
{
    Result<std::string> png = encode_png_bytes(image);
    if (!png) return png.status();
    return ExportTexture{name, image.width, image.height, 16, std::move(*png)};
}

ExportMesh export_vertex_colored_mesh(const Mesh& mesh, const std::string& name)
{
    ExportMesh out;
    out.name = name;
    out.positions = mesh.positions;
    out.normals = mesh.normals;
    out.indices = mesh.indices;
    out.colors.resize(mesh.colors.size());
    for (std::size_t i = 0; i < mesh.colors.size(); ++i) {
        const glm::vec4& c = mesh.colors[i];
        out.colors[i] = {srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z), c.w};
    }
    return out;
}

std::uint64_t export_mesh_bytes(const ExportMesh& mesh)
{
    std::uint64_t n = mesh.positions.size();
    return n * 12 + mesh.normals.size() * 12 + mesh.uvs.size() * 8 + mesh.colors.size() * 16 + mesh.indices.size() * 4;
}

std::uint64_t export_texture_bytes(const ExportTexture& texture)
{
    return std::uint64_t(texture.width) * std::uint64_t(texture.height) * 4 * std::uint64_t(texture.bits / 8) * 4 / 3;
}

void use_pbr_maps(ExportMesh& mesh, int orm_texture, int emissive_texture)
{
    if (orm_texture >= 0) mesh.orm_texture = orm_texture, mesh.metallic = mesh.roughness = 1.0f;
    if (emissive_texture >= 0) mesh.emissive_texture = emissive_texture, mesh.emissive = glm::vec3(1.0f);
}

Result<std::string> encode_glb(const ExportScene& scene, const std::string& generator)
{
    GlbBuilder b;
    nlohmann::json gltf;
    gltf["asset"] = {{"version", "2.0"}, {"generator", generator}};

    nlohmann::json images = nlohmann::json::array(), textures = nlohmann::json::array();
    for (const ExportTexture& t : scene.textures) {
        if (t.png.empty() || t.width <= 0 || t.height <= 0)
            return error(StatusCode::bad_data, "export texture " + t.name + ": empty");
        int view = b.add_view(t.png.data(), t.png.size(), 0);
        images.push_back({{"name", t.name}, {"bufferView", view}, {"mimeType", "image/png"}});
        textures.push_back({{"name", t.name}, {"sampler", t.repeat ? 1 : 0}, {"source", int(images.size()) - 1}});
    }

    nlohmann::json meshes = nlohmann::json::array(), materials = nlohmann::json::array(), nodes = nlohmann::json::array();
    nlohmann::json children = nlohmann::json::array();
    nodes.push_back(nlohmann::json::object()); // the root, filled below
    for (const ExportMesh& mesh : scene.meshes) {
        STANDIN_RETURN_IF_ERROR(glb_check_mesh(mesh, scene.textures.size()));
        nlohmann::json attributes;
        int position = b.add_floats(mesh.positions, "VEC3");
        glm::vec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        b.accessors[std::size_t(position)]["min"] = glb_vec(lo);
        b.accessors[std::size_t(position)]["max"] = glb_vec(hi);
        attributes["POSITION"] = position;
        if (!mesh.normals.empty()) attributes["NORMAL"] = b.add_floats(glb_unit_normals(mesh.normals), "VEC3");
        if (!mesh.uvs.empty()) attributes["TEXCOORD_0"] = b.add_floats(mesh.uvs, "VEC2");
        if (!mesh.colors.empty()) {
            std::vector<glm::vec4> colors(mesh.colors.size());
            for (std::size_t i = 0; i < colors.size(); ++i) colors[i] = glm::clamp(mesh.colors[i], 0.0f, 1.0f);
            attributes["COLOR_0"] = b.add_floats(colors, "VEC4");
        }
        int index_view = b.add_view(mesh.indices.data(), mesh.indices.size() * 4, k_gltf_element_array_buffer);
        int indices = b.add_accessor(index_view, k_gltf_unsigned_int, mesh.indices.size(), "SCALAR");

        nlohmann::json pbr = {{"baseColorFactor", {mesh.base_color.x, mesh.base_color.y, mesh.base_color.z, mesh.base_color.w}},
                              {"metallicFactor", short_number(mesh.metallic)},
                              {"roughnessFactor", short_number(mesh.roughness)}};
        if (mesh.base_color_texture >= 0) pbr["baseColorTexture"] = {{"index", mesh.base_color_texture}};
        if (mesh.orm_texture >= 0) pbr["metallicRoughnessTexture"] = {{"index", mesh.orm_texture}};
        nlohmann::json material = {{"name", mesh.name}, {"pbrMetallicRoughness", pbr}, {"alphaMode", mesh.alpha_mode}};
        if (mesh.orm_texture >= 0) material["occlusionTexture"] = {{"index", mesh.orm_texture}};
        if (mesh.emissive_texture >= 0) material["emissiveTexture"] = {{"index", mesh.emissive_texture}};
        if (mesh.emissive != glm::vec3(0.0f)) {
            const glm::vec3 e = glm::clamp(mesh.emissive, 0.0f, 1.0f);
            material["emissiveFactor"] = {short_number(e.x), short_number(e.y), short_number(e.z)};
        }
        if (mesh.alpha_mode == "MASK") material["alphaCutoff"] = short_number(mesh.alpha_cutoff);
        if (mesh.double_sided) material["doubleSided"] = true;
        materials.push_back(material);
        meshes.push_back({{"name", mesh.name},
                          {"primitives", {{{"attributes", attributes}, {"indices", indices}, {"material", int(materials.size()) - 1}, {"mode", 4}}}}});
        nlohmann::json node = {{"name", mesh.name}, {"mesh", int(meshes.size()) - 1}};
        if (!mesh.extras.empty()) node["extras"] = mesh.extras;
        nodes.push_back(node);
        children.push_back(int(nodes.size()) - 1);
    }
    if (scene.meshes.empty()) return error(StatusCode::bad_data, "export: nothing to export");
    nodes[0] = {{"name", "standin"}, {"children", children}};
    if (!scene.extras.empty()) nodes[0]["extras"] = scene.extras;

    gltf["scene"] = 0;
    gltf["scenes"] = {{{"name", "standin"}, {"nodes", {0}}}};
    gltf["nodes"] = nodes;
    gltf["meshes"] = meshes;
    gltf["materials"] = materials;
    gltf["accessors"] = b.accessors;
    gltf["bufferViews"] = b.buffer_views;
    if (!images.empty()) {
        gltf["images"] = images;
        gltf["textures"] = textures;
        // 0 clamped: atlas frames and billboard maps must not wrap into their neighbours; 1 (only
        // when a texture asks for it) repeated, as the source model's own textures are read
        gltf["samplers"] = {{{"magFilter", k_gltf_linear}, {"minFilter", k_gltf_linear_mipmap_linear},
                             {"wrapS", k_gltf_clamp_to_edge}, {"wrapT", k_gltf_clamp_to_edge}}};
        if (std::any_of(scene.textures.begin(), scene.textures.end(), [](const ExportTexture& t) { return t.repeat; }))
            gltf["samplers"].push_back({{"magFilter", k_gltf_linear}, {"minFilter", k_gltf_linear_mipmap_linear},
                                        {"wrapS", k_gltf_repeat}, {"wrapT", k_gltf_repeat}});
    }
    while (b.bin.size() % 4 != 0) b.bin.push_back('\0');
    gltf["buffers"] = {{{"byteLength", b.bin.size()}}};

    std::string json = gltf.dump();
    while (json.size() % 4 != 0) json.push_back(' ');
    const std::uint64_t total = 12 + 8 + json.size() + 8 + b.bin.size();
    if (total > 0xffffffffull) return error(StatusCode::invalid_argument, "export: the scene exceeds the 4 GiB a .glb can hold");
    std::string out;
    out.reserve(std::size_t(total));
    auto u32 = [&](std::uint32_t v) {
        for (int k = 0; k < 4; ++k) out.push_back(char((v >> (8 * k)) & 0xff));
    };
    out += "glTF";
    u32(2);
    u32(std::uint32_t(total));
    u32(std::uint32_t(json.size()));
    out += "JSON";
    out += json;
    u32(std::uint32_t(b.bin.size()));
    out.append("BIN\0", 4);
    out += b.bin;
    return out;
}

} // namespace standin
