// A procedural mechanical assembly (59 parts: a thin-walled casing open at both ends, liners with
// pistons, rods, pins, shafts, flanges with bolts, feet, pulleys) of about a requested number of
// triangles, deterministic: the nested-parts case for tests and `standin generate assembly`. Kept
// out of GeneratedShape so that adding it did not touch mesh.h, which nearly every file includes.
#pragma once

#include <standin/mesh.h>

namespace standin {

// sheets: the casing, liners and flanges as zero-thickness sheets, some parts inside out, as CAD
// exports of sheet-metal parts are (issue #17); otherwise every part has thickness.
Result<Mesh> generate_assembly(std::size_t target_triangles, float radius = 1.0f, bool sheets = false);

} // namespace standin
