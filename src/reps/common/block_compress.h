// Block compression of the image-based stand-ins' maps (docs/FORMAT.md, "Compressed images"):
// BC3 / BC4 / BC5 blocks through Debian's libsquish (Brown, "squish" 1.15: cluster fit for colour,
// the DXT5 alpha fit for BC4/BC5 channels), and octahedral normal encoding (Meyer et al. 2010, "On
// floating-point normal vectors"; Cigolle et al. 2014, "A survey of efficient representations for
// independent unit vectors"), so that a normal takes the two channels of a BC5 block.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <functional>
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

// The BC5 blocks of a width x height map of octahedral normals (the packages' normal maps: the
// enhanced billboards' and the view atlas's). `normal_at(k, n)` gives texel k's unit normal and
// returns true, or false where the texel is not covered: those are left out of their block's fit
// and stored as the code of +Z.
std::vector<std::uint8_t> compress_octahedral_normals(int width, int height,
                                                      const std::function<bool(std::size_t, glm::vec3&)>& normal_at);
// Texel k's unit normal from the RGBA8 image decompress_blocks(blocks, ..., squish::kBc5) gives.
inline glm::vec3 octahedral_texel(const std::vector<std::uint8_t>& decoded, std::size_t k)
{
    return octahedral_decode(glm::vec2(decoded[k * 4], decoded[k * 4 + 1]) / 255.0f);
}

} // namespace standin::reps
