// Hidden proxies by view direction (issue #17): which of a package's proxy boxes can hold the
// nearest hit of rays along a direction, so that the renderer leaves the others out.
//
// An assembly's billboards lie many layers deep: from any one direction most tiles are behind
// others (2CylinderEngine at 800x600: 3,243 of 43,367 tiles hold a pixel's nearest hit), yet each
// box is drawn, and on llvmpipe, which tests depth after a shader that writes it, each of its
// fragments runs the march's set-up. Precomputed visibility (Airey, Rohlf & Brooks 1990; Teller &
// Séquin 1991) culls what no viewpoint of a region can see; here the region is a cell of view
// directions: an instance is seen from outside its bounding sphere, and along one line occlusion
// is the same for an orthographic and a perspective ray, and under any affine transform.
// Steps:
//  1. At load time (add_billboard): each covered texel of each fine tile as a square at its depth,
//     noting whether it may hide what lies behind it (not a texel an outline crosses, which is
//     covered only in part) and its normal. Packages of over k_texel_budget covered texels (foliage
//     at 2048 texels along the diagonal, whose leaves' texels are mostly clipped and hide little)
//     are drawn without it.
//  2. A direction, on first need (visible_along): the squares are rasterised (pixel centres inside
//     them) into an orthographic depth buffer over the texels' sphere; squares too small to reach a
//     pixel centre mark their centre's pixel; back-facing ones hide nothing where back hits
//     are dropped or back-facing proxies culled. Tiles go front to back on every core, and a tile,
//     or a group of 4 x 4 of its texels, whose pixels are all nearer already is skipped whole
//     (the same buffer, at any thread count). A pixel's limit is the farthest of its 3 x 3
//     neighbours' nearest depths (so a surface beside an outline or a gap, which may cover part of
//     the pixel, is not hidden), plus a tolerance; a fine tile is visible where one of its squares
//     lies within the limit at a pixel it covers; a coarse tile where a fine tile whose
//     texels and depths overlap it is; a whole billboard where any of its tiles is. Squares are
//     flat and not joined by walls, so a steep surface seen from its side lets what lies behind it
//     through: what is kept is a superset of what shows.
//  3. Directions: an octahedral grid of cells; a cell's proxies are those visible from any of its
//     four corners, each corner computed once (in parallel with the others a cell needs).
//  4. Cut boxes (cut_box): a coarse tile's or a whole billboard's box, which small instances draw,
//     spans every texel it holds, though from one cell only some of its fine tiles show (of a
//     closed surface, those facing the eye; of an assembly, the outer parts); cut to the fine tiles
//     visible from the cell, it holds every nearest hit the whole box held, with fewer fragments;
//     a whole box whose visible tiles lie apart becomes a box per quadrant of them.
#pragma once

#include "reps/enhanced_billboards/acceleration.h"
#include "reps/enhanced_billboards/billboards.h"

#include <glm/glm.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace standin::billboards {

class HiddenProxies {
public:
    // Octahedral cells per side (cells about 11 degrees wide, 289 corners at most): docs/RESULTS.md
    // "Hidden proxies by view direction".
    static constexpr int k_cells = 16;
    // Covered texels kept at most (8 bytes each: 32 MB; and 24 bytes for each group of up to 16).
    static constexpr std::size_t k_texel_budget = std::size_t(4) << 20;

    // The proxies of one billboard at one level: `boxes` as build_tiles returned them, the first of
    // them proxy `first` of its level.
    struct Level {
        std::span<const TileBox> boxes;
        std::uint32_t first = 0;
    };
    // Step 1 for the next billboard (billboards in order; its fine and coarse proxies numbered within
    // their levels, in order).
    void add_billboard(const Billboard& b, const HeightFieldAcceleration& acc, const Level& fine, const Level& coarse);
    // After every billboard: the sphere around the boxes (object space), the largest texel, and
    // whether back-facing texels hide nothing (back hits dropped, or back-facing proxies culled).
    void finish(glm::vec3 centre, float radius, float texel, bool backs_see_through);

    // Whether proxy `k` (fine tiles, then coarse tiles, then one whole box per billboard) may hold
    // the nearest hit of a ray along `direction` (object space, from the eye towards it; need not be
    // unit). The cell it falls in is computed on first need.
    bool may_show(std::size_t k, glm::vec3 direction) { return may_show(k, cell_index_or_none(direction)); }
    // The same for a direction's cell (cell_index_or_none), for callers that need the cell too.
    bool may_show(std::size_t k, std::size_t cell);

    // Step 4: the box of coarse tile or whole billboard k cut to its fine tiles visible from cell
    // `cell` (cell_index): texel rectangles and ranges of z about the proxy's own plane (the
    // coarse tile's slope; 0 for a whole billboard, whose z is depth in [0, 1]), within the proxy's
    // own box. Returns how many boxes `parts` holds: 1 for one cut box; 2 to 4 for a whole box
    // whose visible tiles lie apart, one per quadrant of their rectangle that holds some; 0 where
    // the cut would keep nearly all of the box, or k is a fine tile.
    struct Cut {
        glm::ivec2 texel_min{0}, texel_max{0};
        float offset_min = 0.0f, offset_max = 0.0f;
    };
    int cut_box(std::size_t k, std::size_t cell, std::array<Cut, 4>& parts);
    static std::size_t cell_index(glm::vec3 direction)
    {
        const glm::ivec2 c = cell_of(direction);
        return std::size_t(c.y * k_cells + c.x);
    }
    // cell_index, or k_no_cell for a direction of no length or not finite (every proxy may show)
    static constexpr std::size_t k_no_cell = std::size_t(-1);
    static std::size_t cell_index_or_none(glm::vec3 direction)
    {
        const float length = glm::length(direction);
        return length > 0.0f && std::isfinite(length) ? cell_index(direction) : k_no_cell;
    }

    // A sphere around every texel (object space): an instance is culled only where the eye is outside
    // it and the near plane clips none of it (what the near plane clips hides nothing).
    glm::vec3 texel_centre() const { return texel_centre_; }
    float texel_radius() const { return texel_radius_; }
    bool empty() const { return blocks_.empty(); }

    // Exposed for tests: the octahedral cell of a direction, and the proxies visible along exactly
    // `direction` (one depth buffer, no cell) as bits.
    static glm::ivec2 cell_of(glm::vec3 direction);
    std::vector<std::uint64_t> visible_along(glm::vec3 direction) const;
    std::size_t proxy_count() const { return fine_count_ + coarse_count_ + frames_.size(); }
    std::size_t block_count() const { return blocks_.size(); }

private:
    struct Block { // a covered texel, 8 bytes: a package of 3M covered texels takes 25 MB
        std::uint16_t i, j, depth; // the texel and its depth code
        // bits 0-6 and 7-13: the stored normal, octahedral; 14: hides (no outline crosses it)
        std::uint16_t bits;
    };
    struct Frame { // a billboard's box space: object = origin + u x + v y + z depth (x, y texels, depth in [0, 1])
        glm::vec3 origin, u, v, z;
        std::uint32_t first_fine = 0, end_fine = 0;
    };
    struct Extent { // the texels and depths a fine tile's blocks span (inclusive), for whole-tile tests
        std::uint16_t i0, j0, i1, j1;
        float depth0, depth1;
    };
    std::vector<Block> blocks_;               // by fine tile
    std::vector<std::uint32_t> fine_blocks_;  // fine tile k's blocks: [fine_blocks_[k], fine_blocks_[k + 1])
    struct Group { // a fine tile's blocks within a square of texels: blocks_[first, end)
        Extent extent;
        std::uint32_t first = 0, end = 0;
    };
    std::vector<Extent> fine_extents_;        // fine tile k's
    std::vector<Group> groups_;               // by fine tile
    std::vector<std::uint32_t> fine_groups_;  // fine tile k's groups: [fine_groups_[k], fine_groups_[k + 1])
    static Extent empty_extent()
    {
        return {0xffff, 0xffff, 0, 0, std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
    }
    static void grow(Extent& e, const Block& b);
    static void grow(Extent& e, const Extent& other);
    std::vector<std::uint32_t> fine_billboard_;
    std::vector<std::uint32_t> coarse_fines_offset_, coarse_fines_; // coarse tile k: the fine tiles overlapping it
    std::vector<TileBox> fine_boxes_, coarse_boxes_;                 // for cut_box
    std::vector<Frame> frames_;
    std::size_t fine_count_ = 0, coarse_count_ = 0;
    glm::vec3 centre_{0.0f}, texel_centre_{0.0f};
    float radius_ = 0.0f, pixel_ = 1.0f, texel_radius_ = 0.0f;
    int resolution_ = 1;
    bool backs_see_through_ = false;
    std::vector<std::vector<std::uint64_t>> corners_; // (k_cells + 1)^2, empty until computed
    std::vector<std::vector<std::uint64_t>> cells_;   // k_cells^2, empty until computed
    const std::vector<std::uint64_t>& cell(glm::ivec2 c);
    void compute_corners(std::span<const int> corners);
};

} // namespace standin::billboards
