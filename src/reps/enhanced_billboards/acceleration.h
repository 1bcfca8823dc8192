// The height-field acceleration the enhanced-billboard renderer marches: per texel the surface
// depth, which neighbours continue the same surface, and a min/max depth pyramid for skipping empty
// space. Built from a billboard's depth, normal and coverage at load time (deterministic, linear in
// the texel count), so packages need not store it.
#pragma once

#include "reps/enhanced_billboards/billboards.h"

#include <cstdint>
#include <vector>

namespace standin::billboards {

// Bits of SurfaceTexel::flags.
enum : std::uint16_t {
    k_texel_covered = 1u << 0,
    k_link_minus_u = 1u << 1, // continues the surface of texel (i - 1, j)
    k_link_plus_u = 1u << 2,  // ... (i + 1, j)
    k_link_minus_v = 1u << 3, // ... (i, j - 1)
    k_link_plus_v = 1u << 4,  // ... (i, j + 1)
    k_texel_clipped = 1u << 5, // holds an edge line (SurfaceTexel::edge_line; billboard_layout.glsl, EDGE_LINE_*)
    // the link continues the surface without a crease (normals within k_smooth_link_cos): colour is
    // filtered across it (build_color_pyramid, march.frag footprint_color)
    k_smooth_minus_u = 1u << 6,
    k_smooth_plus_u = 1u << 7,
    k_smooth_minus_v = 1u << 8,
    k_smooth_plus_v = 1u << 9,
};
constexpr int k_smooth_link_shift = 5; // k_link_* << 5 = k_smooth_*
// 20 degrees: a smooth surface's normals turn by a fraction of that across a texel; parts and
// leaves that touch mostly meet at a larger angle
constexpr float k_smooth_link_cos = 0.94f;

// Level 0 of the march. Depths are the package's 16-bit depth codes. [min, max] holds the texel's
// depth and the depths of the neighbours it links to, so the range contains the walls between
// linked texels; an uncovered texel holds the empty range [65535, 0]. The top is tilted: the plane
// through `depth` at the texel's centre that changes by `slope` texels of depth per texel along u
// and v (from the depths of its linked neighbours, capped at HF_TOP_MAX_SLOPE; zero on uncovered
// texels and on texels without links).
struct SurfaceTexel {
    std::uint16_t depth = 0, min = 65535, max = 0, flags = 0;
    glm::vec2 slope{0.0f};
    std::uint8_t edge_line = 0; // with k_texel_clipped: 1 + the index of its colour alpha's edge line code
};

struct MinMax {
    std::uint16_t min = 65535, max = 0;
};

struct HeightFieldAcceleration {
    int width = 0, height = 0;                // padded to multiples of 2^levels
    int levels = 0;                           // pyramid levels above level 0
    std::vector<SurfaceTexel> surface;        // width * height, row j = texel row j
    std::vector<std::vector<MinMax>> pyramid; // level k (k = 1..levels) at pyramid[k - 1], cells of 2^k texels
};

// The march's level-0 texture, one RGBA16UI texel per SurfaceTexel (billboard_layout.glsl,
// SURFACE_*): depth; (depth - min) and (max - depth) in whole `range_unit` codes, rounded outwards,
// in the low and high byte; the slope along u and v quantised to 8 bits each; the flags, with the
// edge line (1 + its code's index, 7 bits) in place of k_texel_clipped (its low bit) and in bits
// 10-15 (TEXEL_LINE_*). One texel per read, so neither the tilt nor the line costs a fetch. range_unit (at least 1) is the smallest that holds
// the largest range in 8 bits.
std::vector<std::uint16_t> pack_surface(const HeightFieldAcceleration& acc, int& range_unit);

// Two neighbouring covered texels belong to one surface when their depth difference is within
// what the steeper of their stored normals allows across one texel: the rule every image-based
// stand-in shares (reps/common/shaders/height_field.h), with the package's depth quantisation.
struct LinkSettings {
    int depth_bits = 16; // of the package: 8-bit depths quantise more coarsely
    // packages of --sheet-edges clip: colour alphas below 255 are edge lines (k_texel_clipped)
    bool edge_lines = false;
};

// Whether the covered texels (i, j) and its next one along `axis` (0: +u, 1: +v) continue one
// surface by the shared link rule (height_field.h, hf_link_tolerance); `quantum_codes`: one step of
// the stored depth in 16-bit codes. Both texels must be inside the billboard.
bool texels_linked(const Billboard& billboard, int i, int j, int axis, float quantum_codes);

// Builds the acceleration of one billboard, padded to width x height (multiples of 2^levels, at
// least the billboard's size).
HeightFieldAcceleration build_acceleration(const Billboard& billboard, int padded_width, int padded_height,
                                           int levels, const LinkSettings& settings);

// Colour away from the billboard (issue #14): where a pixel covers many texels, the ground truth
// shows its textures filtered over the pixel (mip maps) while one texel of the capture is a point
// sample of them, noise that grows as the stand-in shrinks. Level k (k = 1..acc.levels, at
// [k - 1], cells of 2^k texels, RGBA8 row by row): rgb the mean of the cell's covered texels'
// colour codes (sRGB, averaged as the truth's mip maps average its textures), alpha 255 where those
// texels are one surface and 0 where they are not or there are none. One surface: every two
// covered neighbours inside the cell are linked without a crease (k_smooth_*) and the links join them all,
// so a cell that holds a leaf's edge over another leaf, or two parts of an assembly, is not one and
// the renderer reads a finer level there: the truth does not filter across geometry.
std::vector<std::vector<std::uint8_t>> build_color_pyramid(const Billboard& billboard,
                                                           const HeightFieldAcceleration& acc);

// The proxy of one occupied tile: the texel rectangle [texel_min, texel_max) of the covered texels
// of one tile_size x tile_size tile, and the depth range (16-bit codes) of those texels and of the
// walls to their linked neighbours (SurfaceTexel::min / max). A ray that meets the height field
// inside the tile meets this box first.
// The box is also sheared to follow the surface: `slope` is a plane z = slope.x * x + slope.y * y
// (box space: x, y in texels, z in [0, 1] of the depth range) fitted to the texels' depths, and
// [offset_min, offset_max] holds z - plane over every point of every covered texel's column from its
// min to its max, so a ray enters a steep or tilted tile next to its surface instead of at the top
// of a box as deep as the tile's whole depth change.
struct TileBox {
    glm::ivec2 texel_min{0}, texel_max{0};
    std::uint16_t depth_min = 65535, depth_max = 0;
    glm::vec2 slope{0.0f};
    float offset_min = 0.0f, offset_max = 0.0f;
};

// The boxes of the tiles of `acc` that hold covered texels, row by row (empty tiles have none), so
// that every covered texel lies in exactly one box. tile_size is a power of two, at most 2^levels
// so that tiles align with pyramid cells.
// A tile whose texels' depth ranges fall apart into layers more than `layer_gap` depth codes apart
// (nested parts of an assembly seen through each other) gets one box per layer, at most
// k_max_tile_layers, each over the texels whose range starts in it. Every crossing of a texel's
// column or walls lies in its layer's box, so the boxes together find every crossing the tile's one
// box would, and the empty depth between layers is no longer drawn and marched through.
constexpr int k_max_tile_layers = 8;
std::vector<TileBox> build_tiles(const HeightFieldAcceleration& acc, int tile_size, int layer_gap = 65535);

// Where each billboard's maps lie on the GPU: rectangles of `cell`-aligned size packed into the
// layers of texture arrays (renderer.cpp). One billboard per layer, each layer as large as the
// largest billboard, left half of the tree's layers empty (billboards of other shapes and sizes:
// 94M texels allocated for 48M at 2048 texels, 2 GiB); shelves of billboards sorted by height fill
// layers of the size, among a few multiples of the largest billboard, that allocates the fewest
// texels. Offsets are multiples of `cell` (the pyramid's top cell), so that every pyramid node of a
// billboard lies inside its own rectangle. Deterministic: ties go to the earlier billboard.
struct LayerPlacement {
    int layer = 0;
    glm::ivec2 offset{0}; // texels, multiples of cell
};
struct LayerPacking {
    int width = 0, height = 0, layers = 0; // of every layer
    std::vector<LayerPlacement> placements; // one per size, in order
};
LayerPacking pack_layers(const std::vector<glm::ivec2>& sizes, int cell, int max_side);

// How a package's billboards lie on the GPU (renderer.cpp uploads them so, `standin bake` reports
// the bytes): pyramid levels above the texels (at most k_max_pyramid_levels: long rays cross a few
// top cells, and layers pad to multiples of 64 texels only) and the layers they are packed into.
constexpr int k_max_pyramid_levels = 6;
// the largest side of a texture layer pack_layers may choose (a few billboards of 2048 texels)
constexpr int k_max_layer_side = 8192;
struct GpuLayout {
    int levels = 0;
    LayerPacking packing;
};
GpuLayout gpu_layout(const std::vector<Billboard>& billboards, int max_side = k_max_layer_side);
// The bytes of the texture arrays of that layout: colour RGBA8, octahedral normals RG16, surface
// RGBA16UI, ORM and emission RGBA8 with PBR maps, and the min/max (RG16UI) and colour (RGBA8)
// pyramids.
std::uint64_t gpu_texture_bytes(const GpuLayout& layout, bool pbr);
// Whether every billboard has ORM and emission maps (the renderer then uploads them).
bool has_pbr_maps(const std::vector<Billboard>& billboards);

} // namespace standin::billboards
