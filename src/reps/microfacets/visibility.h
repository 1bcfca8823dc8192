// Which captured views saw surface in which octree node: with the ray clip (renderer.h), a facet's
// fragments can only hit surface its views stored inside its voxel (grown by half a texel), so a
// node none of its selected views saw is dropped before it is drawn. Exact: the pictures do not
// change (renderer_gpu_test), only the fragments that would all have missed. That is the hidden
// side of closed surfaces and the inside of foliage, about half the facets.
#pragma once

#include "reps/microfacets/microfacets.h"

#include <cstdint>
#include <vector>

namespace standin::microfacets {

// One bit per view and node: words_per_node() words per node, nodes in the renderer's order
// (levels min..max concatenated, each in code order). A view marks every node its stored surface
// can reach through a hit: for each covered texel, the box around its surface point grown by 1.5
// texels and by the largest depth step to its covered neighbours along the view (a wall hit lies
// between two neighbours' tops), at the finest level; coarser levels are the OR of their children.
struct SeenViews {
    int words_per_node = 0;
    std::vector<std::uint32_t> words;
};
SeenViews seen_views(const MicrofacetsPackage& package);

} // namespace standin::microfacets
