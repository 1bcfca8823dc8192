// Model import through assimp into one flat Mesh: the scene graph is flattened with its transforms,
// polygons are triangulated, points and lines skipped, degenerate triangles dropped and counted.
// Normals in the file are kept (split normals are how files encode creases); where a mesh has none
// they are computed here, smooth within the crease angle and split across it. assimp's own
// GenSmoothNormals is not used: it needs unindexed ("verbose") input, which glTF and PLY are not.
// Base colour comes from the base-colour or diffuse texture (decoded with stb_image, embedded or
// next to the model), vertex colours and the material colour; see Material in mesh.h. glTF
// metallic-roughness factors and maps (occlusion, emissive, normal) fill Material's PBR fields.
// PLY is read by our own reader (read_ply.h says why) and handed to the same conversion.
// assimp never prints: no DefaultLogger is created, so it logs to its NullLogger.
#include "io/check_gltf.h"
#include "io/read_ply.h"

#include <standin/files.h>
#include <standin/image.h>
#include <standin/limits.h>
#include <standin/mesh.h>

#include <assimp/DefaultIOSystem.h>
#include <assimp/GltfMaterial.h>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
// via /usr/include: the pkg-config include directory of stb is not public on standin_core
#include <stb/stb_image.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <numeric>
#include <sstream>

namespace fs = std::filesystem;

namespace standin {

static std::string lower_extension(const std::string& path)
{
    std::string ext = fs::path(path).extension().string();
    if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// assimp's messages may span lines and quote whole file names; a Status message is one line.
static std::string assimp_message(std::string text)
{
    std::replace_if(text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r' || c == '\t'; }, ' ');
    text.erase(std::unique(text.begin(), text.end(), [](char a, char b) { return a == ' ' && b == ' '; }), text.end());
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? "unknown error" : one_line(text, 200);
}

bool is_model_file_name(const std::string& path)
{
    std::string extension = fs::path(path).extension().string();
    if (extension.size() < 2) return false;
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    // files that only accompany a model (materials, glTF buffers) are not models of their own
    if (extension == ".mtl" || extension == ".bin") return false;
    Assimp::Importer importer;
    return importer.IsExtensionSupported(extension);
}

static Status check_source_file(const std::string& path, const std::string& extension)
{
    STANDIN_RETURN_IF_ERROR(check_regular_file(path));
    if (extension.empty()) return error(StatusCode::unsupported, quoted(path) + ": no file extension to tell the format by (rename it with its format's extension, e.g. .obj, .glb, .ply)");
    Assimp::Importer importer;
    if (!importer.IsExtensionSupported("." + extension))
        return error(StatusCode::unsupported, quoted(path) + ": unsupported model format " + quoted("." + extension));
    return Status::ok();
}

// assimp opens the model and what it refers to (MTL, glTF buffers, textures) itself: through this,
// only regular files are opened, so a FIFO or a device among them fails the import instead of
// blocking it or reading forever.
class RegularFileIOSystem : public Assimp::DefaultIOSystem {
public:
    bool Exists(const char* file) const override { return file && check_regular_file(file).is_ok(); }
    Assimp::IOStream* Open(const char* file, const char* mode = "rb") override
    {
        if (!file || !mode) return nullptr;
        if (mode[0] == 'r' && !check_regular_file(file).is_ok()) return nullptr;
        return Assimp::DefaultIOSystem::Open(file, mode);
    }
};

// OFF headers declare their counts up front and assimp allocates them before reading: a count the
// file cannot hold (assimp's own invalid/OutOfMemory.off declares 353 billion vertices) is refused here.
static Status check_off_counts(const std::string& path)
{
    Result<std::string> head = read_file_head(path, 4096);
    if (!head) return head.status();
    std::istringstream in(*head);
    std::string word;
    in >> word;
    if (word.find("OFF") == std::string::npos) return Status::ok();
    double vertices = 0, faces = 0;
    if (!(in >> vertices >> faces)) return Status::ok(); // assimp names what is wrong
    std::error_code ec;
    double bytes = double(std::filesystem::file_size(path, ec));
    // the shortest ASCII vertex is "0 0 0\n", the shortest face "3 0 1 2\n"
    if (!ec && (vertices * 6.0 > bytes || faces * 8.0 > bytes || vertices < 0 || faces < 0))
        return error(StatusCode::bad_data, quoted(path) + ": declares " + std::to_string((long long)vertices) + " vertices and " +
                                               std::to_string((long long)faces) + " faces, more than its " +
                                               std::to_string((long long)bytes) + " bytes can hold");
    return Status::ok();
}

static Status check_import_size(std::uint64_t triangles, std::uint64_t vertices, const std::string& path)
{
    STANDIN_RETURN_IF_ERROR(check_triangles(triangles, quoted(path)));
    return check_memory(triangles * 120 + vertices * 100, "importing " + quoted(path) + " (" + std::to_string(triangles) + " triangles)");
}

// Triangles the scene will have after triangulation, against the triangle budget and the memory
// the conversion needs (about 120 bytes per triangle at its peak, assimp's copy included).
static Status check_scene_size(const aiScene& scene, const std::string& path)
{
    std::uint64_t triangles = 0, vertices = 0;
    for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
        const aiMesh* mesh = scene.mMeshes[m];
        if (!mesh || !mesh->mFaces) continue;
        vertices += mesh->mNumVertices;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f)
            if (mesh->mFaces[f].mNumIndices >= 3) triangles += mesh->mFaces[f].mNumIndices - 2;
    }
    return check_import_size(triangles, vertices, path);
}

// Before post-processing: JoinIdenticalVertices merges NaN vertices into their neighbours, hiding them.
static Status check_finite_coordinates(const aiScene& scene, const std::string& path)
{
    for (unsigned m = 0; m < scene.mNumMeshes; ++m) {
        const aiMesh* mesh = scene.mMeshes[m];
        if (!mesh || !mesh->mVertices) continue;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                return error(StatusCode::bad_data, quoted(path) + ": mesh " + quoted(mesh->mName.C_Str()) + " vertex " + std::to_string(v) +
                                                       " has a non-finite coordinate");
        }
    }
    return Status::ok();
}

// What assimp's validation refuses a whole file for though standin draws none of it: lights,
// cameras and animations (a light no node places, a camera's bad aspect), and meshes without faces
// or vertices (an empty solid beside the model in an STL, a point cloud). Dropped before validation
// so that the triangles the file does hold are read; returns how many meshes were dropped. Node
// references are remapped; out-of-range ones are left for the converter to refuse.
static unsigned drop_what_is_not_drawn(aiScene& scene)
{
    for (unsigned i = 0; i < scene.mNumLights; ++i) delete scene.mLights[i];
    delete[] scene.mLights;
    scene.mLights = nullptr;
    scene.mNumLights = 0;
    for (unsigned i = 0; i < scene.mNumCameras; ++i) delete scene.mCameras[i];
    delete[] scene.mCameras;
    scene.mCameras = nullptr;
    scene.mNumCameras = 0;
    for (unsigned i = 0; i < scene.mNumAnimations; ++i) delete scene.mAnimations[i];
    delete[] scene.mAnimations;
    scene.mAnimations = nullptr;
    scene.mNumAnimations = 0;

    auto drawn = [](const aiMesh* m) { return m && m->mNumFaces > 0 && m->mFaces && m->mNumVertices > 0 && m->mVertices; };
    const unsigned old_count = scene.mNumMeshes;
    std::vector<unsigned> new_index(old_count, ~0u);
    unsigned kept = 0;
    for (unsigned m = 0; m < old_count; ++m) {
        if (drawn(scene.mMeshes[m])) {
            new_index[m] = kept;
            scene.mMeshes[kept++] = scene.mMeshes[m];
        } else {
            delete scene.mMeshes[m];
        }
    }
    for (unsigned m = kept; m < old_count; ++m) scene.mMeshes[m] = nullptr;
    scene.mNumMeshes = kept;
    if (kept == old_count) return 0;
    std::vector<aiNode*> stack{scene.mRootNode};
    while (!stack.empty()) {
        aiNode* node = stack.back();
        stack.pop_back();
        if (!node) continue;
        unsigned out = 0;
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            const unsigned m = node->mMeshes[i];
            if (m < old_count && new_index[m] == ~0u) continue; // dropped
            node->mMeshes[out++] = m < old_count ? new_index[m] : m;
        }
        node->mNumMeshes = out;
        for (unsigned c = 0; c < node->mNumChildren; ++c) stack.push_back(node->mChildren[c]);
    }
    return old_count - kept;
}

static Result<const aiScene*> read_scene(Assimp::Importer& importer, const std::string& path, ImportReport& report)
{
    // read first, post-process second: a scene with no meshes at all is "no triangles", not the
    // validation failure assimp would report for it
    const aiScene* scene = nullptr;
    importer.SetIOHandler(new RegularFileIOSystem); // the importer owns it
    STANDIN_RETURN_IF_ERROR(check_off_counts(path));
    STANDIN_RETURN_IF_ERROR(check_gltf_accessors(path, lower_extension(path)));
    try {
        scene = importer.ReadFile(path, 0);
        if (scene) {
            // assimp hands out its scene as const, but post-processing edits it in place the same way
            const unsigned dropped = drop_what_is_not_drawn(*const_cast<aiScene*>(scene));
            if (dropped > 0 && scene->mNumMeshes > 0)
                report.warnings.push_back(quoted(path) + ": skipped " + std::to_string(dropped) +
                                          (dropped == 1 ? " mesh" : " meshes") + " without faces");
        }
        if (scene && scene->mNumMeshes == 0) return error(StatusCode::bad_data, quoted(path) + ": contains no triangles");
        if (scene) STANDIN_RETURN_IF_ERROR(check_finite_coordinates(*scene, path));
        if (scene) STANDIN_RETURN_IF_ERROR(check_scene_size(*scene, path));
        // validation comes first in assimp's pipeline: truncated files carry out-of-range indices
        // that would crash the later steps
        if (scene)
            scene = importer.ApplyPostProcessing(aiProcess_ValidateDataStructure | aiProcess_Triangulate |
                                                 aiProcess_JoinIdenticalVertices | aiProcess_SortByPType);
    } catch (const std::bad_alloc&) {
        return error(StatusCode::bad_data, quoted(path) + ": declares more data than memory holds (assimp's allocation failed; "
                                               "memory budget " + bytes_text(budget().memory_bytes) + ", STANDIN_MEMORY_LIMIT)");
    } catch (const std::exception& e) {
        return error(StatusCode::bad_data, quoted(path) + ": cannot read: " + assimp_message(e.what()));
    }
    if (!scene) return error(StatusCode::bad_data, quoted(path) + ": cannot read: " + assimp_message(importer.GetErrorString()));
    return scene;
}

// Our PLY reader's result as an assimp scene, so that PLY goes through the same conversion as every
// other format. The aiScene destructor frees what is allocated here.
static std::unique_ptr<aiScene> scene_from_ply(const PlyData& ply)
{
    auto scene = std::make_unique<aiScene>();
    auto* mesh = new aiMesh();
    mesh->mName = "ply";
    mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    mesh->mNumVertices = unsigned(ply.positions.size());
    mesh->mVertices = new aiVector3D[mesh->mNumVertices];
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) mesh->mVertices[v] = {ply.positions[v].x, ply.positions[v].y, ply.positions[v].z};
    if (!ply.normals.empty()) {
        mesh->mNormals = new aiVector3D[mesh->mNumVertices];
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) mesh->mNormals[v] = {ply.normals[v].x, ply.normals[v].y, ply.normals[v].z};
    }
    if (!ply.colors.empty()) {
        mesh->mColors[0] = new aiColor4D[mesh->mNumVertices];
        for (unsigned v = 0; v < mesh->mNumVertices; ++v)
            mesh->mColors[0][v] = {ply.colors[v].x, ply.colors[v].y, ply.colors[v].z, ply.colors[v].w};
    }
    if (!ply.uvs.empty()) {
        mesh->mTextureCoords[0] = new aiVector3D[mesh->mNumVertices];
        mesh->mNumUVComponents[0] = 2;
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) mesh->mTextureCoords[0][v] = {ply.uvs[v].x, ply.uvs[v].y, 0.0f};
    }
    mesh->mNumFaces = unsigned(ply.triangles.size() / 3);
    mesh->mFaces = new aiFace[mesh->mNumFaces];
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        mesh->mFaces[f].mNumIndices = 3;
        mesh->mFaces[f].mIndices = new unsigned[3]{ply.triangles[f * 3], ply.triangles[f * 3 + 1], ply.triangles[f * 3 + 2]};
    }
    scene->mNumMeshes = 1;
    scene->mMeshes = new aiMesh*[1]{mesh};
    scene->mNumMaterials = 1;
    scene->mMaterials = new aiMaterial*[1]{new aiMaterial()};
    scene->mRootNode = new aiNode("ply");
    scene->mRootNode->mNumMeshes = 1;
    scene->mRootNode->mMeshes = new unsigned[1]{0};
    return scene;
}

// ---------------------------------------------------------------------------------------------
// Textures

// References in OBJ/MTL files written on Windows use backslashes; glTF URIs are percent-encoded.
static std::string normalise_reference(std::string reference)
{
    std::replace(reference.begin(), reference.end(), '\\', '/');
    std::string decoded;
    for (std::size_t i = 0; i < reference.size(); ++i) {
        if (reference[i] == '%' && i + 2 < reference.size() && std::isxdigit((unsigned char)reference[i + 1]) &&
            std::isxdigit((unsigned char)reference[i + 2])) {
            decoded += char(std::stoi(reference.substr(i + 1, 2), nullptr, 16));
            i += 2;
        } else {
            decoded += reference[i];
        }
    }
    return decoded;
}

// stb_image and image files store the top row first; Texture wants row 0 at v = 0.
static void flip_rows(Texture& texture)
{
    std::size_t row = std::size_t(texture.width) * 4;
    for (int y = 0; y < texture.height / 2; ++y)
        std::swap_ranges(texture.rgba.begin() + std::ptrdiff_t(y * row), texture.rgba.begin() + std::ptrdiff_t((y + 1) * row),
                         texture.rgba.begin() + std::ptrdiff_t((texture.height - 1 - y) * row));
}

static Result<Texture> decode_image(const std::string& name, const unsigned char* bytes, std::size_t size)
{
    if (size == 0 || size > std::size_t(std::numeric_limits<int>::max()))
        return error(StatusCode::bad_data, "texture '" + name + "' is empty or too large");
    int width = 0, height = 0, channels = 0;
    stbi_uc* pixels = stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 4);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        return error(StatusCode::bad_data, "texture '" + name + "' cannot be decoded: " + (reason ? reason : "unknown error"));
    }
    Texture texture;
    texture.name = name;
    texture.width = width;
    texture.height = height;
    texture.rgba.assign(pixels, pixels + std::size_t(width) * height * 4);
    stbi_image_free(pixels);
    flip_rows(texture);
    return texture;
}

static Result<Texture> load_embedded_texture(const std::string& name, const aiTexture& embedded)
{
    // mHeight == 0 marks a compressed file (PNG, JPEG, ...) of mWidth bytes
    if (embedded.mHeight == 0)
        return decode_image(name, reinterpret_cast<const unsigned char*>(embedded.pcData), embedded.mWidth);
    Texture texture;
    texture.name = name;
    texture.width = int(embedded.mWidth);
    texture.height = int(embedded.mHeight);
    texture.rgba.resize(std::size_t(texture.width) * texture.height * 4);
    for (std::size_t i = 0; i < std::size_t(texture.width) * texture.height; ++i) {
        const aiTexel& t = embedded.pcData[i];
        std::uint8_t rgba[4] = {t.r, t.g, t.b, t.a};
        std::copy(rgba, rgba + 4, texture.rgba.begin() + std::ptrdiff_t(i * 4));
    }
    flip_rows(texture);
    return texture;
}

static Result<Texture> load_texture(const aiScene& scene, const std::string& reference, const fs::path& model_directory)
{
    if (const aiTexture* embedded = scene.GetEmbeddedTexture(reference.c_str()))
        return load_embedded_texture(reference, *embedded);

    // as written, then percent-decoded; then, for models moved from another machine with absolute or
    // foreign paths, the bare file name beside the model
    std::string slashes = reference;
    std::replace(slashes.begin(), slashes.end(), '\\', '/');
    const fs::path written[2] = {fs::path(slashes), fs::path(normalise_reference(reference))};
    std::vector<fs::path> candidates;
    for (const fs::path& w : written) candidates.push_back(w.is_relative() ? model_directory / w : w);
    for (const fs::path& w : written) candidates.push_back(model_directory / w.filename());
    std::error_code ec;
    auto found = std::find_if(candidates.begin(), candidates.end(), [&](const fs::path& p) { return fs::is_regular_file(p, ec); });
    if (found == candidates.end()) return error(StatusCode::not_found, "texture '" + reference + "' not found");
    const fs::path& file = *found;
    Result<std::string> bytes = read_file(file.string());
    if (!bytes) return bytes.status();
    return decode_image(reference, reinterpret_cast<const unsigned char*>(bytes->data()), bytes->size());
}

// ---------------------------------------------------------------------------------------------
// Crease normals

// Compressed lists: items of bucket b are items[offsets[b] .. offsets[b + 1]).
struct Buckets {
    std::vector<std::uint32_t> offsets, items;
};

static Buckets bucket_by(const std::vector<std::uint32_t>& bucket_of_item, std::size_t bucket_count)
{
    Buckets buckets;
    buckets.offsets.assign(bucket_count + 1, 0);
    for (std::uint32_t b : bucket_of_item) ++buckets.offsets[b + 1];
    std::partial_sum(buckets.offsets.begin(), buckets.offsets.end(), buckets.offsets.begin());
    buckets.items.resize(bucket_of_item.size());
    std::vector<std::uint32_t> cursor(buckets.offsets.begin(), buckets.offsets.end() - 1);
    // items enter in increasing order, so every bucket is sorted: sums below run in a fixed order
    for (std::uint32_t item = 0; item < bucket_of_item.size(); ++item) buckets.items[cursor[bucket_of_item[item]]++] = item;
    return buckets;
}

// Vertices that share a position (UV seams, split normals) get one id, so smoothing crosses seams.
static std::vector<std::uint32_t> position_groups(const Mesh& mesh, std::size_t first_vertex, std::size_t* group_count)
{
    std::size_t count = mesh.positions.size() - first_vertex;
    std::vector<std::uint32_t> order(count);
    std::iota(order.begin(), order.end(), 0u);
    auto key = [&](std::uint32_t v) {
        const glm::vec3& p = mesh.positions[first_vertex + v];
        return std::make_tuple(p.x, p.y, p.z);
    };
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return key(a) < key(b); });
    std::vector<std::uint32_t> group(count);
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < count; ++i) {
        if (i > 0 && key(order[i]) != key(order[i - 1])) ++next;
        group[order[i]] = next;
    }
    *group_count = count == 0 ? 0 : next + 1;
    return group;
}

// Smoothing compares the faces around one position pairwise: exact for up to k_exact_group corners
// (nearly every vertex of a real mesh); above, the faces are binned by direction first, so that a
// fan of 200k triangles around one apex costs 200k + 256^2, not 200k^2 (import stays linear).
constexpr std::size_t k_exact_group = 64;
constexpr int k_direction_cells = 16; // per side of the octahedral map of directions

static glm::vec3 safe_normalize(glm::vec3 v)
{
    float length = glm::length(v); // only underflow gives 0: the sums include the face itself
    return length > 0.0f && std::isfinite(length) ? v / length : glm::vec3(0.0f, 0.0f, 1.0f);
}

static void smooth_group_exactly(const std::uint32_t* corners, std::size_t count, const std::vector<glm::vec3>& weighted,
                                 const std::vector<glm::vec3>& unit, float cos_crease, std::vector<glm::vec3>& normals)
{
    for (std::size_t i = 0; i < count; ++i) {
        std::size_t t = corners[i] / 3;
        glm::vec3 sum(0.0f);
        for (std::size_t j = 0; j < count; ++j) {
            std::size_t other = corners[j] / 3;
            if (glm::dot(unit[other], unit[t]) >= cos_crease) sum += weighted[other];
        }
        normals[corners[i]] = safe_normalize(sum);
    }
}

// The cell of a unit direction in an octahedral map of k_direction_cells^2 cells.
static int direction_cell(glm::vec3 n)
{
    float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
    if (!(l1 > 0.0f)) return 0;
    glm::vec2 p = glm::vec2(n.x, n.y) / l1;
    if (n.z < 0.0f)
        p = glm::vec2((1.0f - std::abs(p.y)) * (p.x >= 0.0f ? 1.0f : -1.0f), (1.0f - std::abs(p.x)) * (p.y >= 0.0f ? 1.0f : -1.0f));
    auto index = [](float x) { return std::clamp(int((x * 0.5f + 0.5f) * k_direction_cells), 0, k_direction_cells - 1); };
    return index(p.y) * k_direction_cells + index(p.x);
}

// Faces binned by direction: each cell's faces are smoothed with the cells whose mean direction is
// within the crease angle of their own cell's.
static void smooth_group_by_direction_cells(const std::uint32_t* corners, std::size_t count,
                                            const std::vector<glm::vec3>& weighted, const std::vector<glm::vec3>& unit,
                                            float cos_crease, std::vector<glm::vec3>& normals)
{
    constexpr int k_cells = k_direction_cells * k_direction_cells;
    std::vector<glm::vec3> cell_weighted(k_cells, glm::vec3(0.0f)), cell_direction(k_cells, glm::vec3(0.0f));
    std::vector<int> occupied;
    std::vector<char> is_occupied(k_cells, 0);
    for (std::size_t i = 0; i < count; ++i) {
        std::size_t t = corners[i] / 3;
        int cell = direction_cell(unit[t]);
        if (!is_occupied[cell]) occupied.push_back(cell);
        is_occupied[cell] = 1;
        cell_weighted[cell] += weighted[t];
        cell_direction[cell] += unit[t];
    }
    std::sort(occupied.begin(), occupied.end()); // a fixed order of the sums below
    for (int a : occupied) cell_direction[a] = safe_normalize(cell_direction[a]);
    std::vector<glm::vec3> cell_normal(k_cells, glm::vec3(0.0f, 0.0f, 1.0f));
    for (int a : occupied) {
        glm::vec3 sum(0.0f);
        for (int b : occupied)
            if (a == b || glm::dot(cell_direction[a], cell_direction[b]) >= cos_crease) sum += cell_weighted[b];
        cell_normal[a] = safe_normalize(sum);
    }
    for (std::size_t i = 0; i < count; ++i) normals[corners[i]] = cell_normal[direction_cell(unit[corners[i] / 3])];
}

// One normal per corner of triangles [first_triangle, end): the area-weighted average of the faces
// around the corner's position whose normals are within the crease angle of the corner's face.
static std::vector<glm::vec3> corner_normals(const Mesh& mesh, std::size_t first_vertex, std::size_t first_triangle,
                                             float crease_degrees)
{
    std::size_t triangle_count = mesh.triangle_count() - first_triangle;
    auto corner_vertex = [&](std::size_t corner) { return mesh.indices[first_triangle * 3 + corner]; };

    // face normals: unit for the angle test, area-weighted for the sums
    std::vector<glm::vec3> weighted(triangle_count), unit(triangle_count);
    for (std::size_t t = 0; t < triangle_count; ++t) {
        glm::vec3 p0 = mesh.positions[corner_vertex(t * 3)];
        weighted[t] = glm::cross(mesh.positions[corner_vertex(t * 3 + 1)] - p0, mesh.positions[corner_vertex(t * 3 + 2)] - p0);
        float length = glm::length(weighted[t]);
        unit[t] = length > 0.0f ? weighted[t] / length : glm::vec3(0.0f); // underflow: joins no neighbour
    }

    // the faces around each position
    std::size_t group_count = 0;
    std::vector<std::uint32_t> group = position_groups(mesh, first_vertex, &group_count);
    std::vector<std::uint32_t> group_of_corner(triangle_count * 3);
    for (std::size_t c = 0; c < group_of_corner.size(); ++c) group_of_corner[c] = group[corner_vertex(c) - first_vertex];
    Buckets corners_at_group = bucket_by(group_of_corner, group_count);

    float cos_crease = std::cos(glm::radians(std::clamp(crease_degrees, 0.0f, 180.0f))) - 1e-6f;
    std::vector<glm::vec3> normals(triangle_count * 3);
    for (std::size_t g = 0; g < group_count; ++g) {
        const std::uint32_t* first = corners_at_group.items.data() + corners_at_group.offsets[g];
        std::size_t count = corners_at_group.offsets[g + 1] - corners_at_group.offsets[g];
        if (count <= k_exact_group) smooth_group_exactly(first, count, weighted, unit, cos_crease, normals);
        else smooth_group_by_direction_cells(first, count, weighted, unit, cos_crease, normals);
    }
    return normals;
}

// Corners of one vertex with equal normals share it; each further normal gets a copy of the vertex.
static void split_vertices_by_normal(Mesh& mesh, std::size_t first_vertex, std::size_t first_triangle,
                                     const std::vector<glm::vec3>& corner_normal)
{
    std::vector<std::uint32_t> vertex_of_corner(corner_normal.size());
    for (std::size_t c = 0; c < corner_normal.size(); ++c)
        vertex_of_corner[c] = mesh.indices[first_triangle * 3 + c] - std::uint32_t(first_vertex);
    Buckets corners_at_vertex = bucket_by(vertex_of_corner, mesh.positions.size() - first_vertex);

    std::vector<std::pair<glm::vec3, std::uint32_t>> seen; // distinct normals of this vertex so far
    for (std::size_t v = 0; v + 1 < corners_at_vertex.offsets.size(); ++v) {
        seen.clear();
        std::size_t original = first_vertex + v;
        for (std::uint32_t i = corners_at_vertex.offsets[v]; i < corners_at_vertex.offsets[v + 1]; ++i) {
            std::uint32_t c = corners_at_vertex.items[i];
            auto same = std::find_if(seen.begin(), seen.end(), [&](const auto& s) { return s.first == corner_normal[c]; });
            std::uint32_t vertex = std::uint32_t(original);
            if (same != seen.end()) {
                vertex = same->second;
            } else if (seen.empty()) {
                mesh.normals[original] = corner_normal[c];
                seen.emplace_back(corner_normal[c], vertex);
            } else {
                vertex = std::uint32_t(mesh.positions.size());
                glm::vec3 position = mesh.positions[original]; // copies: push_back may reallocate
                glm::vec4 color = mesh.colors[original];
                glm::vec2 uv = mesh.uvs[original];
                mesh.positions.push_back(position);
                mesh.normals.push_back(corner_normal[c]);
                mesh.colors.push_back(color);
                mesh.uvs.push_back(uv);
                seen.emplace_back(corner_normal[c], vertex);
            }
            mesh.indices[first_triangle * 3 + c] = vertex;
        }
    }
}

// Normals for triangles [first_triangle, end) over vertices [first_vertex, end): each corner gets
// the area-weighted average of the faces around its position whose normals are within the crease
// angle of its own face; corners of one vertex that end up different split the vertex.
static void compute_crease_normals(Mesh& mesh, std::size_t first_vertex, std::size_t first_triangle, float crease_degrees)
{
    if (mesh.triangle_count() == first_triangle) return;
    std::vector<glm::vec3> normals = corner_normals(mesh, first_vertex, first_triangle, crease_degrees);
    split_vertices_by_normal(mesh, first_vertex, first_triangle, normals);
}

// ---------------------------------------------------------------------------------------------
// Scene conversion

static glm::mat4 to_glm(const aiMatrix4x4& m)
{
    glm::mat4 result;
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column) result[column][row] = m[row][column];
    return result;
}

static bool is_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// What a placed aiMesh needs from its material.
struct MaterialUse {
    std::uint32_t index = 0;  // into Mesh::materials
    glm::vec4 factor{0.8f};   // multiplied into every vertex colour
    int texture = -1;         // Mesh::textures index, -1 for none
    unsigned uv_channel = 0;
    bool pbr_maps = false;    // a PBR map (metallic-roughness, occlusion, emissive, normal) reads the UVs
    bool vertex_colors = false; // the mesh's first colour set paints it (paints_vertex_colors)
};

class SceneConverter {
public:
    SceneConverter(const aiScene& scene, const std::string& path, const ImportOptions& options, ImportReport& report)
        : scene_(scene), path_(quoted(path)), model_directory_(fs::path(path).parent_path()), options_(options), report_(report),
          linear_colors_(lower_extension(path) == "gltf" || lower_extension(path) == "glb")
    {
    }

    Status convert();
    Mesh take_mesh() { return std::move(mesh_); }

private:
    Status add_mesh(const aiMesh& source, const glm::mat4& world_from_object);
    Status add_triangles(const aiMesh& source, std::size_t first_vertex, std::uint32_t material, bool mirrored);
    bool has_usable_normals(const aiMesh& source) const;
    MaterialUse use_material(const aiMesh& source);
    int use_texture(const aiMaterial& material, unsigned* uv_channel);
    int use_opacity_texture(const aiMaterial& material, int base_texture);
    void convert_alpha(const aiMaterial& material, const aiMesh& source, MaterialUse& use, Material& converted);
    int use_map(const aiMaterial& material, aiTextureType type, unsigned* uv_channel);
    bool read_pbr(const aiMaterial& material, const aiMesh& source, unsigned uv_channel, Material& converted);
    void remove_unused_vertices();
    void keep_a_model_that_would_draw_nothing();
    Status check_extent() const;

    const aiScene& scene_;
    std::string path_; // quoted, as messages show it
    fs::path model_directory_;
    ImportOptions options_;
    ImportReport& report_;
    // glTF's baseColorFactor and COLOR_0 are linear (glTF 2.0 §3.9.2, §3.7.2.1), where Mesh's
    // colours are sRGB-encoded like every other format's: they are encoded on import
    bool linear_colors_ = false;
    Mesh mesh_;
    std::map<std::pair<unsigned, unsigned>, MaterialUse> materials_; // (assimp index, variant) -> use
    std::map<std::string, int> textures_;                            // reference -> index, -1 failed
    std::size_t skipped_primitives_ = 0;
};

static bool is_authored(const aiMaterial& material)
{
    // assimp invents a material for formats without one (OBJ without MTL: "DefaultMaterial" grey 0.6;
    // PLY and OFF: unnamed, white or grey); those must not tint the model
    aiColor4D unused;
    if (material.Get(AI_MATKEY_BASE_COLOR, unused) == AI_SUCCESS) return true;
    if (material.GetTextureCount(aiTextureType_DIFFUSE) + material.GetTextureCount(aiTextureType_BASE_COLOR) > 0) return true;
    std::string name = material.GetName().C_Str();
    return !name.empty() && name != AI_DEFAULT_MATERIAL_NAME;
}

// Whether the mesh's first vertex colour set paints it. A set with no positive component anywhere
// does not: nothing authored paints a model black and transparent, and assimp's Blender loader
// gives BlenderDefault_250.blend, Blender's grey default cube, a set of (-1, -1, -1, -1) that,
// multiplied in, drew the truth black where all three stand-ins drew it grey.
static bool paints_vertex_colors(const aiMesh& source)
{
    if (!source.HasVertexColors(0)) return false;
    for (unsigned v = 0; v < source.mNumVertices; ++v) {
        const aiColor4D& c = source.mColors[0][v];
        if (c.r > 0.0f || c.g > 0.0f || c.b > 0.0f || c.a > 0.0f) return true;
    }
    return false;
}

static glm::vec4 srgb_encode(glm::vec4 linear)
{
    auto encode = [](float c) { return linear_to_srgb(std::clamp(c, 0.0f, 1.0f)); };
    return {encode(linear.x), encode(linear.y), encode(linear.z), linear.w};
}

static glm::vec4 material_color(const aiMaterial& material, bool has_vertex_colors)
{
    if (!is_authored(material)) return has_vertex_colors ? glm::vec4(1.0f) : glm::vec4(0.8f, 0.8f, 0.8f, 1.0f);
    aiColor4D color(1.0f, 1.0f, 1.0f, 1.0f);
    if (material.Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS) return {color.r, color.g, color.b, color.a};
    if (material.Get(AI_MATKEY_COLOR_DIFFUSE, color) != AI_SUCCESS) color = aiColor4D(0.8f, 0.8f, 0.8f, 1.0f);
    float opacity = 1.0f;
    if (material.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS) color.a = opacity;
    return {color.r, color.g, color.b, color.a};
}

// (glTF's factor encoded as Mesh's colours are; the defaults are standin's, sRGB already)
static glm::vec4 material_color(const aiMaterial& material, bool has_vertex_colors, bool linear_colors)
{
    const glm::vec4 color = material_color(material, has_vertex_colors);
    return linear_colors && is_authored(material) ? srgb_encode(color) : color;
}

static bool has_pbr_map(const aiMaterial& material)
{
    for (aiTextureType type : {aiTextureType_UNKNOWN, aiTextureType_METALNESS, aiTextureType_DIFFUSE_ROUGHNESS,
                               aiTextureType_LIGHTMAP, aiTextureType_AMBIENT_OCCLUSION, aiTextureType_EMISSIVE,
                               aiTextureType_EMISSION_COLOR, aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA})
        if (material.GetTextureCount(type) > 0) return true;
    return false;
}

int SceneConverter::use_texture(const aiMaterial& material, unsigned* uv_channel)
{
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE})
        if (material.GetTextureCount(type) > 0) return use_map(material, type, uv_channel);
    return -1;
}

// The first texture of `type`, loaded once per reference; -1 when there is none or it failed to load
// (a warning). *uv_channel is set to its UV set.
int SceneConverter::use_map(const aiMaterial& material, aiTextureType type, unsigned* uv_channel)
{
    if (material.GetTextureCount(type) == 0) return -1;
    aiString reference;
    unsigned channel = 0;
    if (material.GetTexture(type, 0, &reference, nullptr, &channel) != AI_SUCCESS) return -1;
    *uv_channel = channel;
    std::string key = reference.C_Str();
    auto [it, inserted] = textures_.try_emplace(key, -1);
    if (inserted) {
        Result<Texture> texture = load_texture(scene_, key, model_directory_);
        if (texture) {
            it->second = int(mesh_.textures.size());
            mesh_.textures.push_back(std::move(*texture));
        } else {
            report_.warnings.push_back(path_ + ": " + texture.status().message() + "; using the material's factor");
        }
    }
    return it->second;
}

// glTF 2.0 metallic-roughness (issue #14) as assimp 5.2 hands it over: factors as material keys, the
// metallic-roughness map as aiTextureType_UNKNOWN (or METALNESS / DIFFUSE_ROUGHNESS from other
// importers), occlusion as LIGHTMAP (or AMBIENT_OCCLUSION), emissive and normal maps. Materials
// without these keep Material's defaults (a rough dielectric: the old look). Maps must read the UV
// set `uv_channel` of the base colour (Mesh has one UV set); others are dropped with a warning.
// Returns whether a map reads the UVs.
bool SceneConverter::read_pbr(const aiMaterial& material, const aiMesh& source, unsigned uv_channel, Material& converted)
{
    float factor = 0.0f;
    if (material.Get(AI_MATKEY_METALLIC_FACTOR, factor) == AI_SUCCESS && std::isfinite(factor))
        converted.metallic = std::clamp(factor, 0.0f, 1.0f);
    if (material.Get(AI_MATKEY_ROUGHNESS_FACTOR, factor) == AI_SUCCESS && std::isfinite(factor))
        converted.roughness = std::clamp(factor, 0.0f, 1.0f);
    aiColor3D emissive(0.0f, 0.0f, 0.0f);
    if (material.Get(AI_MATKEY_COLOR_EMISSIVE, emissive) == AI_SUCCESS) {
        float strength = 1.0f;
        if (material.Get(AI_MATKEY_EMISSIVE_INTENSITY, strength) != AI_SUCCESS || !std::isfinite(strength)) strength = 1.0f;
        glm::vec3 e = glm::vec3(emissive.r, emissive.g, emissive.b) * strength;
        if (is_finite(e)) converted.emissive = glm::max(e, glm::vec3(0.0f));
    }

    bool has_uvs = source.HasTextureCoords(uv_channel);
    auto map = [&](std::initializer_list<aiTextureType> types, const char* what) {
        for (aiTextureType type : types) {
            unsigned channel = 0;
            int texture = use_map(material, type, &channel);
            if (texture < 0) continue;
            if (channel != uv_channel || !source.HasTextureCoords(channel) || !has_uvs) {
                report_.warnings.push_back(path_ + ": mesh '" + source.mName.C_Str() + "' " + what +
                                           " map reads another UV set than its base colour (or none); ignoring it");
                return -1;
            }
            return texture;
        }
        return -1;
    };
    converted.metallic_roughness_texture =
        map({aiTextureType_UNKNOWN, aiTextureType_METALNESS, aiTextureType_DIFFUSE_ROUGHNESS}, "metallic-roughness");
    converted.occlusion_texture = map({aiTextureType_LIGHTMAP, aiTextureType_AMBIENT_OCCLUSION}, "occlusion");
    converted.emissive_texture = map({aiTextureType_EMISSIVE, aiTextureType_EMISSION_COLOR}, "emissive");
    converted.normal_texture = map({aiTextureType_NORMALS, aiTextureType_NORMAL_CAMERA}, "normal");
    if (converted.occlusion_texture >= 0 &&
        material.Get(AI_MATKEY_GLTF_TEXTURE_STRENGTH(aiTextureType_LIGHTMAP, 0), factor) == AI_SUCCESS && std::isfinite(factor))
        converted.occlusion_strength = std::clamp(factor, 0.0f, 1.0f);
    if (converted.normal_texture >= 0 &&
        material.Get(AI_MATKEY_GLTF_TEXTURE_SCALE(aiTextureType_NORMALS, 0), factor) == AI_SUCCESS && std::isfinite(factor))
        converted.normal_scale = factor;
    // an emissive map multiplies the factor, which glTF defaults to black
    if (converted.emissive_texture >= 0 && converted.emissive == glm::vec3(0.0f)) converted.emissive_texture = -1;
    return converted.metallic_roughness_texture >= 0 || converted.occlusion_texture >= 0 ||
           converted.emissive_texture >= 0 || converted.normal_texture >= 0;
}

MaterialUse SceneConverter::use_material(const aiMesh& source)
{
    // one Mesh material per (assimp material, whether this mesh can show its texture, whether it
    // has vertex colours): the texture needs UVs, and the stand-in default colour depends on both
    const aiMaterial& material = *scene_.mMaterials[source.mMaterialIndex];
    unsigned uv_channel = 0;
    int texture = use_texture(material, &uv_channel);
    bool textured = texture >= 0 && source.HasTextureCoords(uv_channel);
    bool colored = paints_vertex_colors(source);
    // (and whether its PBR maps have UVs to read)
    bool mapped = source.HasTextureCoords(uv_channel) && has_pbr_map(material);
    unsigned variant = (textured ? 1u : 0u) | (colored ? 2u : 0u) | (mapped ? 4u : 0u);
    auto [it, inserted] = materials_.try_emplace({source.mMaterialIndex, variant});
    if (!inserted) return it->second;

    MaterialUse& use = it->second;
    use.factor = material_color(material, colored, linear_colors_);
    use.vertex_colors = colored;
    use.texture = textured ? texture : -1;
    use.uv_channel = uv_channel;
    use.index = std::uint32_t(mesh_.materials.size());
    Material converted;
    converted.name = material.GetName().C_Str();
    converted.base_color = use.factor;
    converted.base_color_texture = use.texture;
    convert_alpha(material, source, use, converted);
    use.pbr_maps = read_pbr(material, source, uv_channel, converted);
    mesh_.materials.push_back(converted);
    if (texture >= 0 && !textured)
        report_.warnings.push_back(path_ + ": mesh '" + source.mName.C_Str() + "' has a texture but no UVs; using the material colour");
    return use;
}

// Alpha (issue #14). glTF says how alpha shows (alphaMode, alphaCutoff) and whether back faces
// show (doubleSided, through AI_MATKEY_TWOSIDED); other formats only carry an opacity (OBJ d, a
// uniform transparency: blend) or an opacity map (OBJ map_d: leaf cut-outs, mask at 0.5). The
// opacity map is merged into the base-colour texture's alpha (a new texture), so everything after
// import finds colour and coverage in one lookup.
void SceneConverter::convert_alpha(const aiMaterial& material, const aiMesh& source, MaterialUse& use, Material& converted)
{
    aiString mode;
    bool gltf = material.Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS;
    if (gltf) {
        std::string name = mode.C_Str();
        converted.alpha_mode = name == "MASK" ? AlphaMode::mask : name == "BLEND" ? AlphaMode::blend : AlphaMode::opaque;
        float cutoff = 0.5f;
        if (material.Get(AI_MATKEY_GLTF_ALPHACUTOFF, cutoff) == AI_SUCCESS && std::isfinite(cutoff))
            converted.alpha_cutoff = std::clamp(cutoff, 0.0f, 1.0f);
    } else {
        float opacity = 1.0f;
        if (material.Get(AI_MATKEY_OPACITY, opacity) == AI_SUCCESS && opacity < 1.0f) converted.alpha_mode = AlphaMode::blend;
        if (material.GetTextureCount(aiTextureType_OPACITY) > 0) {
            int merged = use_opacity_texture(material, use.texture);
            if (merged >= 0 && source.HasTextureCoords(use.uv_channel)) {
                use.texture = converted.base_color_texture = merged;
                converted.alpha_mode = AlphaMode::mask;
            }
        }
    }
    int two_sided = 1;
    if (material.Get(AI_MATKEY_TWOSIDED, two_sided) == AI_SUCCESS) converted.double_sided = two_sided != 0;
    // (blending materials are reported once the whole model is read: keep_a_model_that_would_draw_nothing
    // may turn them opaque)
}

// The base-colour texture (white where there is none) with the opacity map's alpha, or its red
// channel when the map is grey (map_d is a scalar map; PNGs of it are often grey without alpha).
int SceneConverter::use_opacity_texture(const aiMaterial& material, int base_texture)
{
    aiString reference;
    if (material.GetTexture(aiTextureType_OPACITY, 0, &reference) != AI_SUCCESS) return -1;
    std::string key = std::string("\x01opacity:") + std::to_string(base_texture) + ":" + reference.C_Str();
    auto [it, inserted] = textures_.try_emplace(key, -1);
    if (!inserted) return it->second;
    Result<Texture> opacity = load_texture(scene_, reference.C_Str(), model_directory_);
    if (!opacity) {
        report_.warnings.push_back(path_ + ": " + opacity.status().message() + "; the material is opaque");
        return -1;
    }
    Texture merged;
    if (base_texture >= 0) {
        merged = mesh_.textures[std::size_t(base_texture)];
    } else {
        merged.width = opacity->width;
        merged.height = opacity->height;
        merged.rgba.assign(std::size_t(merged.width) * std::size_t(merged.height) * 4, 255);
    }
    merged.name += std::string(merged.name.empty() ? "" : "+") + reference.C_Str();
    std::size_t pixels = std::size_t(opacity->width) * std::size_t(opacity->height);
    bool has_alpha = false;
    for (std::size_t i = 0; i < pixels && !has_alpha; ++i) has_alpha = opacity->rgba[4 * i + 3] != 255;
    for (int y = 0; y < merged.height; ++y)
        for (int x = 0; x < merged.width; ++x) {
            // nearest texel of the opacity map at this texel's centre (the two may differ in size)
            int ox = std::min(opacity->width - 1, int((double(x) + 0.5) * opacity->width / merged.width));
            int oy = std::min(opacity->height - 1, int((double(y) + 0.5) * opacity->height / merged.height));
            const std::uint8_t* o = &opacity->rgba[(std::size_t(oy) * std::size_t(opacity->width) + std::size_t(ox)) * 4];
            std::uint8_t& a = merged.rgba[(std::size_t(y) * std::size_t(merged.width) + std::size_t(x)) * 4 + 3];
            a = std::uint8_t((int(a) * int(has_alpha ? o[3] : o[0]) + 127) / 255);
        }
    it->second = int(mesh_.textures.size());
    mesh_.textures.push_back(std::move(merged));
    return it->second;
}

bool SceneConverter::has_usable_normals(const aiMesh& source) const
{
    if (!source.HasNormals()) return false;
    for (unsigned v = 0; v < source.mNumVertices; ++v) {
        const aiVector3D& n = source.mNormals[v];
        glm::vec3 normal(n.x, n.y, n.z);
        if (!is_finite(normal) || glm::dot(normal, normal) < 1e-12f) return false;
    }
    return true;
}

// A triangle is degenerate when two corners coincide or it has no area up to rounding: its
// normal is undefined and the bakers would divide by its area.
static bool is_degenerate(const Mesh& mesh, std::uint32_t a, std::uint32_t b, std::uint32_t c)
{
    if (a == b || b == c || a == c) return true;
    glm::dvec3 p0 = mesh.positions[a], p1 = mesh.positions[b], p2 = mesh.positions[c];
    glm::dvec3 e1 = p1 - p0, e2 = p2 - p0, e3 = p2 - p1;
    double longest_squared = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
    double twice_area = glm::length(glm::cross(e1, e2));
    // relative to the longest edge, so the test does not depend on the model's units
    return !(twice_area > 1e-12 * longest_squared);
}

Status SceneConverter::add_triangles(const aiMesh& source, std::size_t first_vertex, std::uint32_t material, bool mirrored)
{
    for (unsigned f = 0; f < source.mNumFaces; ++f) {
        const aiFace& face = source.mFaces[f];
        if (face.mNumIndices != 3) {
            ++skipped_primitives_;
            continue;
        }
        std::uint32_t corner[3];
        for (int k = 0; k < 3; ++k) {
            if (face.mIndices[k] >= source.mNumVertices)
                return error(StatusCode::bad_data, path_ + ": mesh '" + source.mName.C_Str() + "' face " + std::to_string(f) +
                                                       " refers to vertex " + std::to_string(face.mIndices[k]) + " of " +
                                                       std::to_string(source.mNumVertices));
            corner[k] = std::uint32_t(first_vertex + face.mIndices[k]);
        }
        // a mirroring transform turns counter-clockwise into clockwise; swap to keep faces outward
        if (mirrored) std::swap(corner[1], corner[2]);
        if (is_degenerate(mesh_, corner[0], corner[1], corner[2])) {
            ++report_.degenerate_dropped;
            continue;
        }
        mesh_.indices.insert(mesh_.indices.end(), corner, corner + 3);
        mesh_.face_materials.push_back(material);
    }
    return Status::ok();
}

Status SceneConverter::add_mesh(const aiMesh& source, const glm::mat4& world_from_object)
{
    if (!(source.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !source.mVertices) {
        skipped_primitives_ += source.mNumFaces;
        return Status::ok();
    }
    if (source.mMaterialIndex >= scene_.mNumMaterials)
        return error(StatusCode::bad_data, path_ + ": mesh '" + source.mName.C_Str() + "' has no valid material");
    ++report_.meshes_in_scene;
    MaterialUse material = use_material(source);
    glm::mat3 normal_from_object = glm::transpose(glm::inverse(glm::mat3(world_from_object)));
    bool mirrored = glm::determinant(glm::mat3(world_from_object)) < 0.0f;
    bool keep_normals = has_usable_normals(source);

    std::size_t first_vertex = mesh_.positions.size(), first_triangle = mesh_.triangle_count();
    for (unsigned v = 0; v < source.mNumVertices; ++v) {
        const aiVector3D& p = source.mVertices[v];
        glm::vec3 position = glm::vec3(world_from_object * glm::vec4(p.x, p.y, p.z, 1.0f));
        if (!is_finite(glm::vec3(p.x, p.y, p.z)) || !is_finite(position))
            return error(StatusCode::bad_data, path_ + ": mesh '" + source.mName.C_Str() + "' vertex " + std::to_string(v) +
                                                   " has a non-finite coordinate");
        mesh_.positions.push_back(position);
        glm::vec3 normal(0.0f, 0.0f, 1.0f);
        if (keep_normals) {
            const aiVector3D& n = source.mNormals[v];
            glm::vec3 transformed = normal_from_object * glm::vec3(n.x, n.y, n.z);
            float length = glm::length(transformed);
            // a singular transform leaves no usable direction: recompute the whole mesh below
            // (unit normals are kept bit for bit: a package's coarse mesh must read back as written)
            if (length > 0.0f && std::isfinite(length)) normal = std::abs(length - 1.0f) <= 1e-6f ? transformed : transformed / length;
            else keep_normals = false;
        }
        mesh_.normals.push_back(normal);
        glm::vec4 color = material.factor;
        if (material.vertex_colors) {
            const aiColor4D& c = source.mColors[0][v];
            const glm::vec4 painted = glm::max(glm::vec4(c.r, c.g, c.b, c.a), glm::vec4(0.0f)); // negative: no light reflected
            color *= linear_colors_ ? srgb_encode(painted) : painted;
        }
        mesh_.colors.push_back(color);
        glm::vec2 uv(0.0f);
        if (material.texture >= 0 || material.pbr_maps) uv = {source.mTextureCoords[material.uv_channel][v].x, source.mTextureCoords[material.uv_channel][v].y};
        mesh_.uvs.push_back(uv);
    }
    STANDIN_RETURN_IF_ERROR(add_triangles(source, first_vertex, material.index, mirrored));
    if (!keep_normals) {
        if (source.HasNormals())
            report_.warnings.push_back(path_ + ": mesh '" + source.mName.C_Str() + "' has invalid normals; recomputed them");
        compute_crease_normals(mesh_, first_vertex, first_triangle, options_.crease_angle_degrees);
    }
    return Status::ok();
}

Status SceneConverter::convert()
{
    if (!scene_.mRootNode) return error(StatusCode::bad_data, path_ + ": contains no triangles (no scene graph)");
    // walk the scene graph with an explicit stack: deep hierarchies must not overflow the call stack
    std::vector<std::pair<const aiNode*, glm::mat4>> stack{{scene_.mRootNode, glm::mat4(1.0f)}};
    while (!stack.empty()) {
        auto [node, parent_from_object] = stack.back();
        stack.pop_back();
        glm::mat4 world_from_node = parent_from_object * to_glm(node->mTransformation);
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            if (node->mMeshes[i] >= scene_.mNumMeshes || !scene_.mMeshes[node->mMeshes[i]])
                return error(StatusCode::bad_data, path_ + ": node '" + node->mName.C_Str() + "' refers to a missing mesh");
            STANDIN_RETURN_IF_ERROR(add_mesh(*scene_.mMeshes[node->mMeshes[i]], world_from_node));
        }
        // children pushed in reverse so that they are visited in file order (stable output)
        for (unsigned c = node->mNumChildren; c-- > 0;)
            if (node->mChildren[c]) stack.emplace_back(node->mChildren[c], world_from_node);
    }

    if (report_.degenerate_dropped > 0)
        report_.warnings.push_back(path_ + ": dropped " + std::to_string(report_.degenerate_dropped) + " degenerate triangles");
    if (skipped_primitives_ > 0)
        report_.warnings.push_back(path_ + ": skipped " + std::to_string(skipped_primitives_) + " points and lines");
    if (mesh_.triangle_count() == 0) {
        std::string detail = report_.degenerate_dropped > 0
                                 ? " (" + std::to_string(report_.degenerate_dropped) + " degenerate triangles dropped)"
                                 : "";
        return error(StatusCode::bad_data, path_ + ": contains no triangles" + detail);
    }
    remove_unused_vertices();
    keep_a_model_that_would_draw_nothing();
    for (const Material& m : mesh_.materials)
        if (m.alpha_mode == AlphaMode::blend)
            report_.warnings.push_back(path_ + ": material '" + m.name +
                                       "' blends (alpha); drawn alpha-tested at 0.5, as every stand-in keeps binary coverage");
    STANDIN_RETURN_IF_ERROR(check_extent());
    bool any_texture = std::any_of(mesh_.materials.begin(), mesh_.materials.end(),
                                   [](const Material& m) {
                                       return m.base_color_texture >= 0 || m.metallic_roughness_texture >= 0 ||
                                              m.occlusion_texture >= 0 || m.emissive_texture >= 0 || m.normal_texture >= 0;
                                   });
    if (!any_texture) mesh_.uvs.clear();
    return validate_mesh(mesh_, path_);
}

// A model none of whose faces can pass its alpha test (every material's opacity below its cutoff,
// its texture's alpha included) would draw nothing, in the truth and in every stand-in, and a
// stand-in of nothing is no package. Such files are almost always exporters writing opacity
// inverted: COLLADA's <transparency> 0 meant as opaque (3ds Max and Blender 2.4x exporters; among
// Debian's assimp-testmodels Collada/teapots.DAE and regr01.dae, whose A_ONE mode makes it 0
// opacity by the specification). Only then are the materials drawn opaque, with a warning: one
// visible face and the file is read as written (glTF's hidden helpers stay hidden).
void SceneConverter::keep_a_model_that_would_draw_nothing()
{
    // the most alpha a texture holds, read only for textures a face needs (-1: not read yet)
    std::vector<float> texture_max_alpha(mesh_.textures.size(), -1.0f);
    auto max_alpha = [&](std::size_t t) {
        if (texture_max_alpha[t] < 0.0f) {
            std::uint8_t most = 0;
            const std::vector<std::uint8_t>& rgba = mesh_.textures[t].rgba;
            for (std::size_t i = 3; i < rgba.size() && most < 255; i += 4) most = std::max(most, rgba[i]);
            texture_max_alpha[t] = float(most) / 255.0f;
        }
        return texture_max_alpha[t];
    };
    for (std::size_t f = 0; f < mesh_.triangle_count(); ++f) {
        const Material& material = mesh_.materials[mesh_.face_materials[f]];
        const float cutoff = alpha_test_cutoff(material);
        if (cutoff <= 0.0f) return;
        float alpha = 0.0f; // the most any point of the face can have: its corners bound the interpolation
        for (int k = 0; k < 3; ++k) alpha = std::max(alpha, mesh_.colors[mesh_.indices[3 * f + std::size_t(k)]].w);
        const int texture = material.base_color_texture;
        if (texture >= 0 && std::size_t(texture) < mesh_.textures.size()) alpha *= max_alpha(std::size_t(texture));
        if (alpha >= cutoff) return;
    }
    for (Material& material : mesh_.materials) {
        material.alpha_mode = AlphaMode::opaque;
        material.base_color.w = 1.0f;
    }
    for (glm::vec4& colour : mesh_.colors) colour.w = 1.0f;
    report_.warnings.push_back(path_ + ": every face is cut out by its material's opacity, so the model would draw "
                                       "nothing; drawn opaque instead (exporters often write opacity inverted, "
                                       "e.g. COLLADA <transparency> 0 for opaque)");
}

// Renderers, cameras and bakers work in float: squares of coordinates must stay finite, and a model
// needs an extent to be framed.
Status SceneConverter::check_extent() const
{
    constexpr float k_max_coordinate = 1e15f;
    Bounds bounds = mesh_.bounds();
    for (int k = 0; k < 3; ++k)
        if (std::abs(bounds.min[k]) > k_max_coordinate || std::abs(bounds.max[k]) > k_max_coordinate)
            return error(StatusCode::bad_data, path_ + ": coordinates reach " +
                                                   std::to_string(std::max(std::abs(bounds.min[k]), std::abs(bounds.max[k]))) +
                                                   ", beyond +-1e15 where float arithmetic overflows");
    if (!(bounds.diagonal() > 0.0f) || !std::isfinite(bounds.diagonal()))
        return error(StatusCode::bad_data, path_ + ": the model has no extent (all its vertices coincide)");
    return Status::ok();
}

// Dropped triangles, points and lines leave vertices no triangle uses; bounds must not see them.
void SceneConverter::remove_unused_vertices()
{
    constexpr std::uint32_t k_unused = ~0u;
    std::vector<std::uint32_t> new_index(mesh_.positions.size(), k_unused);
    for (std::uint32_t i : mesh_.indices) new_index[i] = 0;
    std::uint32_t next = 0;
    for (std::size_t v = 0; v < new_index.size(); ++v) {
        if (new_index[v] == k_unused) continue;
        new_index[v] = next;
        mesh_.positions[next] = mesh_.positions[v];
        mesh_.normals[next] = mesh_.normals[v];
        mesh_.colors[next] = mesh_.colors[v];
        mesh_.uvs[next] = mesh_.uvs[v];
        ++next;
    }
    mesh_.positions.resize(next);
    mesh_.normals.resize(next);
    mesh_.colors.resize(next);
    mesh_.uvs.resize(next);
    for (std::uint32_t& i : mesh_.indices) i = new_index[i];
}

// ---------------------------------------------------------------------------------------------

// PLY through read_ply, everything else through assimp; either way an aiScene owned by `storage`.
// A PLY whose header our reader does not understand goes to assimp: a file assimp reads is never
// refused (bodies are not retried: assimp hangs or misreads where ours refuses, read_ply.h).
static Result<const aiScene*> read_any(const std::string& path, const std::string& format, ImportReport& report,
                                       Assimp::Importer& importer, std::unique_ptr<aiScene>& storage)
{
    if (format != "ply") return read_scene(importer, path, report);
    Result<PlyData> ply = read_ply(path);
    if (!ply && ply.status().code() == StatusCode::unsupported) {
        Result<const aiScene*> scene = read_scene(importer, path, report);
        if (scene) report.warnings.push_back(ply.status().message() + "; read by assimp instead");
        return scene ? scene : Result<const aiScene*>(error(StatusCode::bad_data, ply.status().message()));
    }
    if (!ply) return ply.status();
    report.warnings.insert(report.warnings.end(), ply->warnings.begin(), ply->warnings.end());
    if (ply->skipped_faces > 0)
        report.warnings.push_back(quoted(path) + ": skipped " + std::to_string(ply->skipped_faces) + " faces with fewer than 3 corners");
    if (ply->triangles.empty()) return error(StatusCode::bad_data, quoted(path) + ": contains no triangles");
    STANDIN_RETURN_IF_ERROR(check_import_size(ply->triangles.size() / 3, ply->positions.size(), path));
    storage = scene_from_ply(*ply);
    STANDIN_RETURN_IF_ERROR(check_finite_coordinates(*storage, path));
    return static_cast<const aiScene*>(storage.get());
}

static Result<Mesh> import_checked(const std::string& path, ImportReport& r, const ImportOptions& options)
{
    // check the file before reading so that the error says which of missing / unknown / corrupt
    STANDIN_RETURN_IF_ERROR(check_source_file(path, r.format));
    Assimp::Importer importer;
    std::unique_ptr<aiScene> own_scene;
    Result<const aiScene*> scene = read_any(path, r.format, r, importer, own_scene);
    if (!scene) return scene.status();

    // flatten, then fix what the formats leave open (normals, colours, degenerate faces)
    SceneConverter converter(**scene, path, options, r);
    STANDIN_RETURN_IF_ERROR(converter.convert());
    return converter.take_mesh();
}

Result<Mesh> import_mesh_isolated(const std::string& path, ImportReport& report, const ImportOptions& options);

Result<Mesh> import_mesh(const std::string& path, ImportReport* report, const ImportOptions& options)
{
    ImportReport local_report;
    ImportReport& r = report ? *report : local_report;
    r = ImportReport{};
    r.source_path = path;
    r.format = lower_extension(path);
    if (options.isolate_parser) return import_mesh_isolated(path, r, options); // import_isolated.cpp
    try {
        return import_checked(path, r, options);
    } catch (const std::bad_alloc&) {
        // the checks above estimate; this is the boundary for what they miss
        return error(StatusCode::bad_data, quoted(path) + ": needs more memory than there is (memory budget " +
                                               bytes_text(budget().memory_bytes) + ", STANDIN_MEMORY_LIMIT)");
    } catch (const std::length_error&) {
        return error(StatusCode::bad_data, quoted(path) + ": declares more data than can be held");
    }
}

} // namespace standin
