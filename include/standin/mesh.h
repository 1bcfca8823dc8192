// The one in-memory mesh every stage of standin works on: an indexed triangle mesh with the scene
// graph already flattened, per-vertex normals and base colour, and the textures kept so that bakers
// can look up albedo per texel.
#pragma once

#include <standin/status.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace standin {

// An 8-bit RGBA image as stored in the source file (sRGB-encoded colour, linear alpha).
struct Texture {
    std::string name;
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgba; // width * height * 4, row 0 at v = 0 (OpenGL convention)

    // Bilinear lookup with wrap-around addressing, returns sRGB-encoded colour in [0,1].
    glm::vec4 sample(glm::vec2 uv) const;
    // sample(uv).w, reading only the alpha bytes (the alpha test of every texel of a leaf card).
    float sample_alpha(glm::vec2 uv) const;
};

// Colour convention: Mesh::colors already holds vertex colour x material base colour (import folds
// base_color in), so the albedo of a point is the interpolated Mesh::colors, times the material's
// texture at the interpolated UV when it has one. base_color is kept for reference and export; do
// not multiply it in again. Products are taken on the stored (sRGB-encoded) values.
// How a material's alpha (the albedo's w: vertex colour alpha x material opacity x texture alpha)
// shows (glTF 2.0 alphaMode; issue #14). opaque ignores alpha; mask keeps a point where alpha >=
// alpha_cutoff and cuts it out elsewhere (leaf cards); blend is drawn as mask at cutoff 0.5, with
// an import warning (docs/ARCHITECTURE.md "Alpha"): every stand-in keeps binary coverage, so an
// alpha-tested truth is the one they can be measured against.
enum class AlphaMode : std::uint8_t { opaque, mask, blend };

struct Material {
    std::string name;
    glm::vec4 base_color{0.8f, 0.8f, 0.8f, 1.0f}; // sRGB-encoded; already folded into Mesh::colors
    int base_color_texture = -1;                   // index into Mesh::textures, -1 for none
    // Alpha (issue #14). A separate opacity map (OBJ map_d) is merged into the base-colour
    // texture's alpha at import, so one texture lookup gives colour and coverage.
    AlphaMode alpha_mode = AlphaMode::opaque;
    float alpha_cutoff = 0.5f; // mask only: alpha below it is cut out
    // Whether back faces show. True unless the file says otherwise (glTF doubleSided: false):
    // formats without the notion keep what standin always drew, both sides.
    bool double_sided = true;

    // glTF 2.0 metallic-roughness (issue #14), shaded by the GGX/Smith + Lambert model of
    // src/gpu/shaders/common/lighting.glsl. The defaults, a fully rough dielectric without emission,
    // are what formats without PBR materials get: the closest GGX comes to standin's old Lambert look.
    float metallic = 0.0f;            // [0,1]
    float roughness = 1.0f;           // perceptual roughness in [0,1] (GGX alpha = roughness^2)
    glm::vec3 emissive{0.0f};         // linear RGB, emissive factor x strength (may exceed 1)
    float occlusion_strength = 1.0f;  // [0,1]: how much of the occlusion map applies
    float normal_scale = 1.0f;        // scales the normal map's tangent-space x and y
    // Mesh::textures indices, -1 for none; all read at Mesh::uvs (the same UV set as base colour)
    int metallic_roughness_texture = -1; // linear: G roughness, B metallic (multiply the factors)
    int occlusion_texture = -1;          // linear: R occlusion
    int emissive_texture = -1;           // sRGB-encoded: multiplies emissive
    int normal_texture = -1;             // tangent-space normal map (glTF: +y up in UV space, v down)

    // Whether anything here differs from the defaults (what a stand-in must bake to relight it).
    bool has_pbr() const
    {
        return metallic != 0.0f || roughness != 1.0f || emissive != glm::vec3(0.0f) || metallic_roughness_texture >= 0 ||
               occlusion_texture >= 0 || emissive_texture >= 0 || normal_texture >= 0;
    }
};

// The PBR inputs of a surface point besides albedo (Mesh::pbr_at): what stand-ins bake as their
// ORM (occlusion, roughness, metallic) and emission maps.
struct PbrSample {
    float occlusion = 1.0f;   // 1 = unoccluded
    float roughness = 1.0f;   // perceptual
    float metallic = 0.0f;
    glm::vec3 emissive{0.0f}; // linear RGB
};

// The alpha below which a point of `material` is cut out: 0 (nothing cut) for opaque, the cutoff
// for mask, 0.5 for blend (drawn as mask), each less k_alpha_cutoff_tolerance. Every consumer
// (truth renderer, bakers) uses this one rule. The tolerance keeps an alpha equal to the cutoff
// drawn, as glTF says ("greater than or equal"), whatever the interpolation rounds it to: assimp's
// LWO2/transparency.lwo is a sphere of uniform alpha 0.5, blended, which the truth and every
// stand-in speckled with holes where the interpolated 0.5 came out a hair below.
constexpr float k_alpha_cutoff_tolerance = 1e-4f;
inline float alpha_test_cutoff(const Material& material)
{
    switch (material.alpha_mode) {
    case AlphaMode::opaque: return 0.0f;
    case AlphaMode::mask:
        return material.alpha_cutoff > k_alpha_cutoff_tolerance ? material.alpha_cutoff - k_alpha_cutoff_tolerance : material.alpha_cutoff;
    case AlphaMode::blend: return 0.5f - k_alpha_cutoff_tolerance;
    }
    return 0.0f;
}

struct Bounds {
    glm::vec3 min{0.0f}, max{0.0f};
    glm::vec3 center() const { return 0.5f * (min + max); }
    glm::vec3 extent() const { return max - min; }
    float diagonal() const { return glm::length(max - min); }
};

struct BoundingSphere {
    glm::vec3 center{0.0f};
    float radius = 1.0f;
};

// The sphere around a box (its centre, half its diagonal). The one rule that frames a model and
// its packages identically: packages store their source's bounds and use this too.
inline BoundingSphere bounding_sphere_of(const Bounds& box) { return {box.center(), 0.5f * box.diagonal()}; }

struct Mesh {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // unit length, one per vertex
    std::vector<glm::vec4> colors;   // vertex colour x material base colour (sRGB-encoded), always present
    std::vector<glm::vec2> uvs;      // empty when no material has a texture; v = 0 at the texture's row 0
    std::vector<std::uint32_t> indices;         // three per triangle
    std::vector<std::uint32_t> face_materials;  // one per triangle, index into materials
    std::vector<Material> materials;            // at least one
    std::vector<Texture> textures;

    std::size_t vertex_count() const { return positions.size(); }
    std::size_t triangle_count() const { return indices.size() / 3; }
    bool has_texture_coordinates() const { return !uvs.empty(); }

    Bounds bounds() const;
    // The sphere around the bounding box (centre of the box, half its diagonal): cheap, stable,
    // and the sphere the orbit cameras of Saraiva et al. fit the view to.
    BoundingSphere bounding_sphere() const;
    double surface_area() const;
    double triangle_area(std::size_t triangle) const;
    // Albedo at a point of a triangle given barycentric weights (b1, b2) for its 2nd and 3rd vertex:
    // the interpolated Mesh::colors (which include the material colour), times the texture at the
    // interpolated UV when the triangle's material has one.
    glm::vec4 albedo_at(std::size_t triangle, float b1, float b2) const;
    // Whether the point survives its material's alpha test (always for opaque materials): what
    // bakers that sample the surface themselves use, so cut-out texels are holes, not cards.
    bool covered_at(std::size_t triangle, float b1, float b2) const;
    // Whether any material cuts anything out (mask or blend) or hides back faces.
    bool has_alpha_test() const;
    // Occlusion, roughness, metallic and emission at a point of a triangle: the material's factors
    // times its maps at the interpolated UV (occlusion: 1 + strength x (map - 1), as glTF has it).
    PbrSample pbr_at(std::size_t triangle, float b1, float b2) const;
    // The shading normal at a point of a triangle: the interpolated vertex normal, bent by the
    // material's normal map in the triangle's tangent frame (from its UVs) when it has one. Unit.
    glm::vec3 shading_normal_at(std::size_t triangle, float b1, float b2) const;
    // Whether any material has PBR inputs beyond the defaults (Material::has_pbr): the bakers store
    // ORM and emission maps only then, so packages of other models are unchanged.
    bool has_pbr_materials() const;
};

// What import found worth telling the user. Nothing in here is fatal.
struct ImportReport {
    std::string source_path;
    std::string format;              // file extension, lower case, without the dot
    std::size_t degenerate_dropped = 0; // triangles with repeated corners or zero area
    std::size_t meshes_in_scene = 0;    // triangle-mesh instances placed by the scene graph
    std::vector<std::string> warnings;
};

struct ImportOptions {
    // Crease angle used when the file has no normals: smooth within it, split across it.
    float crease_angle_degrees = 80.0f;
    // Parse in a child process (POSIX fork) so that a crash inside the third-party parser (assimp)
    // comes back as a bad_data error naming the file instead of ending the program. The command
    // line and the viewer set it; a batch of thousands of assets must not stop at one bad file.
    bool isolate_parser = false;
};

// Reads any format assimp reads (OBJ, STL, OFF, glTF/GLB, COLLADA, FBX, ...; PLY with a reader of
// our own), flattens the scene graph with its transforms, triangulates, drops degenerate triangles
// (counted in the report) and unused vertices, and fills normals and colours. Points and lines are
// skipped. Normals in the file are kept; where a mesh has none they are computed, smooth within
// options.crease_angle_degrees and split across it. Colour (see Material): Mesh::colors = vertex
// colours (white when absent) x material base or diffuse colour; a base-colour (else diffuse)
// texture is decoded, embedded or beside the model, and kept in Mesh::textures with the UVs; a file
// with neither materials nor vertex colours is grey 0.8. `report` may be null. Errors, each naming
// the file: not_found (no such file), unsupported (an extension assimp does not read), bad_data
// (corrupt file, no triangles, non-finite coordinates). A texture that cannot be loaded is a
// warning, not an error.
Result<Mesh> import_mesh(const std::string& path, ImportReport* report = nullptr,
                         const ImportOptions& options = {});

// Whether import_mesh reads files with the extension of `path` (".ply", ".glb", ... any format
// assimp reads), by name alone: what a folder of models given to a batch bake keeps.
bool is_model_file_name(const std::string& path);

// Checks invariants that every later stage relies on (at least one triangle, index ranges, finite
// values, per-vertex arrays of one size, material and texture indices). bad_data naming `what`.
Status validate_mesh(const Mesh& mesh, const std::string& what);

// The albedo at each vertex, for consumers that cannot sample textures: Mesh::colors, times the
// texture at the vertex's UV where the material of the first triangle using the vertex has one.
std::vector<glm::vec4> vertex_albedo(const Mesh& mesh);

// Recomputes smooth per-vertex normals, area-weighted over the triangles that use each vertex (no
// crease handling: vertices are not split). Unreferenced vertices get +z.
void compute_smooth_normals(Mesh& mesh);

// Writes a binary little-endian PLY with positions, normals and 8-bit RGBA colours (used for coarse
// meshes in packages and for round-trip tests). The colour written is vertex_albedo(); textures and
// UVs themselves are not written. Deterministic bytes; atomic: written to a temporary name and renamed.
Status write_ply(const Mesh& mesh, const std::string& path);

// Procedural meshes for tests and scale benchmarks, deterministic for given options. sphere: a
// cube-sphere (equal-angle warp), every vertex at `radius`; torus: ring of `radius` with tube
// `minor_radius` (< radius), around +y; noisy_sphere: the sphere displaced along its normal by
// smooth value noise seeded by `seed`, at most noise_amplitude * radius. One material of `color`.
// shrub: branches (six-sided tubes) ending in leaf cards (two triangles each, greens varied per
// leaf), and fur_ball: a sphere with hair ribbons (3 segments, dark roots, light tips) — intricate
// objects for the microfacets' claim (Yamazaki et al. 2002); both drawn from `seed`, fitted into a
// sphere of `radius`, their own colours (`color` unused).
// invalid_argument for target_triangles outside [8, 50'000'000], non-finite or non-positive sizes,
// minor_radius >= radius (torus) or noise_amplitude outside [0, 1) (noisy_sphere).
// tree (issue #14): a trunk and branches (tubes, a bark material) carrying leaf cards (quads with
// UVs) of one alpha-masked, double-sided material whose texture is made procedurally (an RGBA
// leaf shape: alpha 0 outside it, veins in the colour); a glTF-shaped model for the alpha tests
// and the demo, written by `standin generate tree -o tree.gltf`.
// bush: branches carrying sprigs of two crossed, intersecting cards, each a texture of many leaves
// (game foliage's leaf-cluster cards), materials as the tree's.
enum class GeneratedShape { sphere, torus, noisy_sphere, shrub, fur_ball, tree, bush };
struct GenerateOptions {
    GeneratedShape shape = GeneratedShape::sphere;
    std::size_t target_triangles = 20000; // the result has about this many
    float radius = 1.0f;
    float minor_radius = 0.35f;   // torus only
    float noise_amplitude = 0.08f; // noisy_sphere only, relative to radius
    std::uint32_t seed = 1;
    glm::vec4 color{0.8f, 0.8f, 0.8f, 1.0f};
};
Result<Mesh> generate_mesh(const GenerateOptions& options);

// Writes a glTF 2.0 model (`path` *.gltf, with the buffer and every texture embedded as data URIs)
// with positions, normals, UVs, and per material its base colour, texture, alphaMode, alphaCutoff
// and doubleSided; one primitive per material. Vertex colours are not written: every vertex of a
// material must carry that material's base colour (what generate_mesh's tree holds), else
// invalid_argument. Deterministic bytes; atomic.
Status write_gltf(const Mesh& mesh, const std::string& path);

} // namespace standin
