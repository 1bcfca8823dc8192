// A glTF 2.0 model with PBR materials written by tests (issue #14): four spheres side by side, one
// material each, so the truth, the importer and every stand-in can be checked on metals, rough and
// smooth dielectrics, maps and emission without a binary fixture in the repository.
//   0 gold metal, roughness 0.3          1 red plastic, roughness 0.2 (a sharp highlight)
//   2 grey metal, roughness 0.8          3 white dielectric with maps: a metallic-roughness map in
//                                          latitude bands (top half smooth metal, bottom half rough
//                                          dielectric), an occlusion map darkening the bottom
//                                          quarter, and a blue emissive factor x an emissive map
//                                          lit only in the top quarter
// Header-only (inline): tests/CMakeLists.txt builds test_support.cpp alone.
#pragma once

#include <standin/image.h>
#include <standin/mesh.h>

#include <glm/glm.hpp>

#include <cmath>
#include <cstring>
#include "test_support.h"

#include <sstream>
#include <string>

namespace standin::test {

// A 4 x 16 map whose rows are `top` in the top half (or quarter) of the image and `bottom` below;
// glTF puts v = 0 at the image's top row.
inline ImageRGBA8 pbr_fixture_bands(glm::u8vec4 top, glm::u8vec4 bottom, int top_rows)
{
    ImageRGBA8 image(4, 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 4; ++x) {
            glm::u8vec4 c = y < top_rows ? top : bottom;
            std::memcpy(image.at(x, y), &c, 4);
        }
    return image;
}

// Writes pbr_spheres.gltf (and its three PNG maps) into `dir`; returns the model's path, or "" when a
// file could not be written. Spheres of radius 1, centres 2.5 apart along x; glTF v = 0 at the
// north pole (v = 0.5 - asin(y) / pi), so bands of the maps are latitudes.
inline std::string write_pbr_spheres_gltf(const std::string& dir, std::size_t triangles_per_sphere = 3000)
{
    GenerateOptions options;
    options.shape = GeneratedShape::sphere;
    options.target_triangles = triangles_per_sphere;
    Result<Mesh> made = generate_mesh(options);
    if (!made) return "";
    const Mesh& sphere = *made;
    // PNG maps beside the model
    if (!write_png(pbr_fixture_bands({0, 40, 255, 255}, {0, 230, 0, 255}, 8), dir + "/pbr_mr.png").is_ok()) return "";
    if (!write_png(pbr_fixture_bands({255, 255, 255, 255}, {90, 90, 90, 255}, 12), dir + "/pbr_occlusion.png").is_ok())
        return "";
    if (!write_png(pbr_fixture_bands({255, 255, 255, 255}, {0, 0, 0, 255}, 4), dir + "/pbr_emissive.png").is_ok()) return "";

    // one buffer: positions, normals, uvs, indices of the sphere, shared by four meshes
    std::size_t n = sphere.vertex_count();
    std::string bytes;
    auto append = [&](const void* p, std::size_t size) { bytes.append(static_cast<const char*>(p), size); };
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (glm::vec3 p : sphere.positions) {
        append(&p, 12);
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    for (glm::vec3 v : sphere.normals) append(&v, 12);
    for (glm::vec3 p : sphere.positions) {
        glm::vec3 d = glm::normalize(p);
        glm::vec2 uv(std::atan2(d.z, d.x) / 6.2831853f + 0.5f, 0.5f - std::asin(glm::clamp(d.y, -1.0f, 1.0f)) / 3.14159265f);
        append(&uv, 8);
    }
    append(sphere.indices.data(), sphere.indices.size() * 4);
    std::size_t uv_offset = n * 24, index_offset = n * 32;

    std::ostringstream gltf;
    gltf << R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],)"
         << R"("nodes": [)";
    for (int k = 0; k < 4; ++k)
        gltf << (k ? ", " : "") << R"({"mesh": )" << k << R"(, "translation": [)" << (2.5f * float(k) - 3.75f) << ", 0, 0]}";
    gltf << R"(], "meshes": [)";
    for (int k = 0; k < 4; ++k)
        gltf << (k ? ", " : "")
             << R"({"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": )"
             << k << "}]}";
    gltf << R"(], "materials": [)"
         << R"({"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.34, 1], "metallicFactor": 1, "roughnessFactor": 0.3}},)"
         << R"({"name": "red plastic", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.05, 0.05, 1], "metallicFactor": 0, "roughnessFactor": 0.2}},)"
         << R"({"name": "rough metal", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 1, "roughnessFactor": 0.8}},)"
         << R"({"name": "mapped", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 1, "roughnessFactor": 1,)"
         << R"( "metallicRoughnessTexture": {"index": 0}}, "occlusionTexture": {"index": 1, "strength": 1},)"
         << R"( "emissiveTexture": {"index": 2}, "emissiveFactor": [0.1, 0.3, 1.0]}],)"
         << R"("images": [{"uri": "pbr_mr.png"}, {"uri": "pbr_occlusion.png"}, {"uri": "pbr_emissive.png"}],)"
         << R"("textures": [{"source": 0}, {"source": 1}, {"source": 2}],)"
         << R"("buffers": [{"byteLength": )" << bytes.size() << R"(, "uri": "data:application/octet-stream;base64,)"
         << base64(bytes) << R"("}],)"
         << R"("bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": )" << n * 12 << "},"
         << R"({"buffer": 0, "byteOffset": )" << n * 12 << R"(, "byteLength": )" << n * 12 << "},"
         << R"({"buffer": 0, "byteOffset": )" << uv_offset << R"(, "byteLength": )" << n * 8 << "},"
         << R"({"buffer": 0, "byteOffset": )" << index_offset << R"(, "byteLength": )" << sphere.indices.size() * 4 << "}],"
         << R"("accessors": [)"
         << R"({"bufferView": 0, "componentType": 5126, "count": )" << n << R"(, "type": "VEC3", "min": [)" << lo.x << ", "
         << lo.y << ", " << lo.z << R"(], "max": [)" << hi.x << ", " << hi.y << ", " << hi.z << "]},"
         << R"({"bufferView": 1, "componentType": 5126, "count": )" << n << R"(, "type": "VEC3"},)"
         << R"({"bufferView": 2, "componentType": 5126, "count": )" << n << R"(, "type": "VEC2"},)"
         << R"({"bufferView": 3, "componentType": 5125, "count": )" << sphere.indices.size() << R"(, "type": "SCALAR"}]})";
    std::string path = dir + "/pbr_spheres.gltf";
    std::FILE* file = std::fopen(path.c_str(), "wb");
    if (!file) return "";
    std::string text = gltf.str();
    bool written = std::fwrite(text.data(), 1, text.size(), file) == text.size();
    written = std::fclose(file) == 0 && written;
    return written ? path : "";
}

} // namespace standin::test
