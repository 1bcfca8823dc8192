// A procedural mechanical assembly (59 parts: a thin-walled casing open at both ends, liners with
// pistons, rods, pins, shafts, flanges with bolts, feet, pulleys) of about a requested number of
// triangles, deterministic: the nested-parts case for tests and `standin generate assembly`. Kept
// out of GeneratedShape so that adding it did not touch mesh.h, which nearly every file includes.
#pragma once

#include <standin/mesh.h>

namespace standin {

Result<Mesh> generate_assembly(std::size_t target_triangles, float radius = 1.0f);

} // namespace standin
