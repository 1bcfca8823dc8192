// Internal to src/io: a PLY reader of our own, used by import_mesh instead of assimp's. assimp
// 5.2.5 (Debian 12) hangs on a header without end_header and misreads binary bodies whose first
// byte is '\n' (assimp issue #5341) -- one file in a few hundred that write_ply produces.
#pragma once

#include <standin/status.h>

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace standin {

// What a PLY file holds that a Mesh can use. Optional per-vertex arrays are empty when absent.
struct PlyData {
    std::vector<glm::vec3> positions;
    std::vector<glm::vec3> normals;  // nx ny nz
    std::vector<glm::vec4> colors;   // red green blue [alpha], integer types scaled to [0, 1]
    std::vector<glm::vec2> uvs;      // s t, u v or texture_u texture_v
    std::vector<std::uint32_t> triangles; // polygons fanned into triangles, three indices each
    std::size_t skipped_faces = 0;        // faces with fewer than three corners
    std::vector<std::string> warnings;    // header lines taken as comments, colours normalised, ...
};

// Reads ASCII and binary (little and big endian) PLY. Elements other than "vertex" and "face" are
// skipped; header lines with an unknown keyword are taken as comments (Blender 2.4 wrote a bare
// "Created by ..." line), with a warning. Colours of any type are scaled to [0, 1] (float colours
// written as 0..255 are recognised). Errors name the file: unsupported for a header this reader does
// not understand (a property type, a format; import_mesh then tries assimp), bad_data for a file
// that is not PLY, a truncated body, an out-of-range index, an element with instances but no
// properties, or more triangles after fanning polygons than the triangle budget (limits.h).
Result<PlyData> read_ply(const std::string& path);

} // namespace standin
