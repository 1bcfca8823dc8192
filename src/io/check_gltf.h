// Internal to src/io: what assimp does not check in glTF files before import_mesh trusts them.
#pragma once

#include <standin/status.h>

#include <string>

namespace standin {

// For .gltf and .glb files: every accessor a mesh primitive uses exists, and the vertex attributes of
// one primitive (POSITION, NORMAL, TEXCOORD_n, COLOR_n, ...) have one count. assimp 5.2 drops or
// misreads mismatched arrays without an error. bad_data naming the file, mesh and attribute.
Status check_gltf_accessors(const std::string& path, const std::string& extension);

} // namespace standin
