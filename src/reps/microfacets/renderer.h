// The microfacet renderer's run-time settings, typed (the declared options of representation.cpp),
// and its constructor, for the registry's entry point (microfacets.h make_renderer) and for tests.
#pragma once

#include "reps/microfacets/microfacets.h"

#include <string>

namespace standin::microfacets {

struct RenderConfig {
    std::string select = "lookup";   // "lookup" (per-cell candidates), "cone" (the seed's, Table 1 c), "all" (row a)
    int views = 4;                   // 1 (the seed's nearest view) .. 4 blended
    std::string facet = "billboard"; // "billboard" (the seed), "fixed" (axis-aligned, Fig. 8), "box" (the voxel's outline; clip "ray")
    std::string primitive = "auto";  // "auto" (points below point_pixels), "quads", "points" (Table 1 b)
    std::string coverage = "vote";   // "vote": views that pass hold half the weight of those that can tell; "any"
    int level = -1;                  // >= 0: draw this octree level (the seed's fixed levels); -1: LOD cut
    // The LOD bound on eq. 2 in pixels (Yamazaki et al. 2002 §4.1: under a pixel); <= 0: 1 for the
    // clips that project views on the facet, 4 for "ray", whose walk places the surface itself (the
    // bound then only sizes the facets: docs/RESULTS.md "Microfacets")
    float max_error_pixels = 0.0f;
    float point_pixels = 1.0f;       // auto: facets narrower than this are drawn as points
    DebugView debug_view = DebugView::none; // parts (by view), depth, normal, fetches, proxies, level
    bool cull_unseen = true;         // clip "ray": drop nodes none of their views saw (exact; visibility.h)
    std::string clip = "ray";        // "seed" (eq. 1), "voxel" (and the surface inside the facet's voxel),
                                     // "ray" (the pixel's ray in the voxel against the view's depth)
};

// The declared run-time options, typed.
RenderConfig config_from(const RenderSettings& settings);

Result<std::unique_ptr<Renderer>> make_microfacet_renderer(const MicrofacetsPackage& package, const RenderConfig& config);

} // namespace standin::microfacets
