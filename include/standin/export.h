// Exporting a package to a format engines and viewers load: binary glTF 2.0 (docs/FORMAT.md,
// "Export"). A representation describes what it exports as an ExportScene (its proxy geometry in
// the source model's object space, its textures, and in extras what a shader needs to draw it);
// encode_glb turns any scene into the bytes of a .glb file, without knowing the representation.
#pragma once

#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/options.h>
#include <standin/status.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin {

class Package;

// A texture of the scene: an RGBA PNG, 8 or 16 bits per channel. Colour textures hold sRGB-encoded
// values (glTF's baseColorTexture); data textures (normal + depth) hold linear codes.
struct ExportTexture {
    std::string name;
    int width = 0, height = 0;
    int bits = 8;
    std::string png; // the encoded file
    // repeated beyond [0, 1] (a source model's own texture, whose UVs may tile it); otherwise
    // clamped to the edge (atlas frames and maps must not wrap into their neighbours)
    bool repeat = false;
};
Result<ExportTexture> make_export_texture(const std::string& name, const ImageRGBA8& image);
Result<ExportTexture> make_export_texture(const std::string& name, const ImageRGBA16& image);

// A triangle mesh, one node of the scene with one material.
struct ExportMesh {
    std::string name;
    std::vector<glm::vec3> positions;   // object space of the source model
    std::vector<glm::vec3> normals;     // empty, or one unit normal per vertex
    std::vector<glm::vec2> uvs;         // empty, or one per vertex: (0, 0) the image's top-left corner
    std::vector<glm::vec4> colors;      // empty, or one linear RGBA per vertex (glTF COLOR_0)
    std::vector<std::uint32_t> indices; // three per triangle, counter-clockwise from outside
    glm::vec4 base_color{1.0f};         // linear
    // glTF's metallicFactor, roughnessFactor and emissiveFactor (linear, at most 1): one value for
    // the mesh (an engine's material), the defaults a rough dielectric without emission
    float metallic = 0.0f, roughness = 1.0f;
    glm::vec3 emissive{0.0f};
    int base_color_texture = -1;        // index into ExportScene::textures, or -1
    // glTF's ORM maps (issue #14's PBR channels), indices into ExportScene::textures or -1: one
    // texture of R occlusion, G roughness, B metallic (linear) as metallicRoughnessTexture and
    // occlusionTexture (the factors above multiply it: 1 to take it as it is), and an sRGB
    // emissive texture (emissive then multiplies it: (1, 1, 1) to take it as it is)
    int orm_texture = -1;
    int emissive_texture = -1;
    std::string alpha_mode = "OPAQUE";  // OPAQUE, MASK (cut-off alpha_cutoff) or BLEND
    float alpha_cutoff = 0.5f;          // MASK only: glTF's alphaCutoff
    bool double_sided = false;
    // the node's extras: {"standin": {...}} with what a shader needs (docs/FORMAT.md)
    nlohmann::json extras = nlohmann::json::object();
};

struct ExportScene {
    std::vector<ExportTexture> textures;
    std::vector<ExportMesh> meshes; // each one node, the children of one root node
    // the root node's extras: {"standin": {...}} naming the representation and the source
    nlohmann::json extras = nlohmann::json::object();
    // what the scene takes in GPU memory as an engine would upload it: textures as stored with a
    // full mip chain, vertex and index buffers
    std::uint64_t gpu_bytes = 0;
    std::vector<std::string> notes; // lines `standin export` prints (sizes, what was left out)
};

// extras.standin.format_version of the root node: raised when a field changes meaning.
constexpr int k_export_format_version = 1;

// A mesh with vertex colours (sRGB-encoded in Mesh, linear in glTF) and normals; textures and
// UVs are left out (coarse meshes carry their albedo in vertex colours).
ExportMesh export_vertex_colored_mesh(const Mesh& mesh, const std::string& name);

// Gives `mesh` a PBR package's maps as its material (ExportMesh::orm_texture, emissive_texture):
// either index may be -1 (left out); a map given takes its factors to 1, so it is read as it is.
void use_pbr_maps(ExportMesh& mesh, int orm_texture, int emissive_texture);

// The .glb bytes of a scene: one JSON chunk, one binary chunk holding every buffer view (vertex
// attributes, indices, PNG images). Deterministic: the same scene gives the same bytes.
Result<std::string> encode_glb(const ExportScene& scene, const std::string& generator);

// What one vertex/index buffer of a scene takes on a GPU (positions, normals, uvs, colours at
// their glTF sizes, 32-bit indices), and one texture with its mip chain.
std::uint64_t export_mesh_bytes(const ExportMesh& mesh);
std::uint64_t export_texture_bytes(const ExportTexture& texture);

// Exports a package: checks `given` against its representation's export_options (an option it does
// not declare: invalid_argument "--NAME does not apply to REP packages"), asks the representation
// for its scene (unsupported when it has no export), and writes OUTPUT atomically (a temporary
// name, renamed when complete). `scene_out`, when given, receives the scene written.
Status export_package(const Package& package, const OptionValues& given, const std::string& output,
                      ExportScene* scene_out = nullptr);

} // namespace standin
