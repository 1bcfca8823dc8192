// Block compression of the image-based stand-ins' maps (docs/FORMAT.md, "Compressed images"):
// BC3 / BC4 / BC5 blocks through Debian's libsquish (Brown, "squish" 1.15: cluster fit for colour,
// the DXT5 alpha fit for BC4/BC5 channels), and octahedral normal encoding (Meyer et al. 2010, "On
// floating-point normal vectors"; Cigolle et al. 2014, "A survey of efficient representations for
// independent unit vectors"), so that a normal takes the two channels of a BC5 block.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

namespace standin::reps {

// The blocks of a width x height RGBA8 image (row-major, 4 bytes per texel) for a squish format
// (squish::kDxt5, kBc4, kBc5, with fit flags). Texels where `mask` (width x height, or null for
// all) is 0 do not count in their block's fit; a block with none counts them all. Blocks are
// compressed independently (rows of blocks in parallel): the output does not depend on the thread
// count.
std::vector<std::uint8_t> compress_blocks(const std::uint8_t* rgba, int width, int height, const std::uint8_t* mask,
                                          int squish_flags);
// The RGBA8 image of width x height texels the blocks decode to.
std::vector<std::uint8_t> decompress_blocks(const std::uint8_t* blocks, int width, int height, int squish_flags);

// A unit normal as a point of [0, 1]² (the octahedron folded onto a square), and back (unit).
glm::vec2 octahedral_encode(glm::vec3 n);
glm::vec3 octahedral_decode(glm::vec2 e);

} // namespace standin::reps
