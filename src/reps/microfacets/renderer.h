// The microfacet renderer's run-time settings and its constructor, for the registry's entry point
// (microfacets.h make_renderer) and for tests and benchmarks that set what RenderOptions cannot
// express yet.
#pragma once

#include "reps/microfacets/microfacets.h"

#include <string>

namespace standin::microfacets {

struct RenderConfig {
    std::string select = "lookup";   // "lookup" (per-cell candidates), "cone" (the seed's, Table 1 c), "all" (row a)
    int views = 3;                   // 1 (the seed's nearest view) .. 4 blended
    std::string facet = "billboard"; // "billboard" (the seed), "fixed" (axis-aligned, Fig. 8)
    std::string primitive = "auto";  // "auto" (points below point_pixels), "quads", "points" (Table 1 b)
    std::string coverage = "any";    // "any" view passes eq. 1, or "vote" (half the weight passes)
    int level = -1;                  // >= 0: draw this octree level (the seed's fixed levels); -1: LOD cut
    float max_error_pixels = 1.0f;   // the LOD bound on eq. 2 (Yamazaki et al. 2002 §4.1: under a pixel)
    float point_pixels = 1.0f;       // auto: facets narrower than this are drawn as points
    std::string debug_view;          // "", "billboard" (by view), "depth", "normal", "fetches", "level", "facets"
};

Result<std::unique_ptr<Renderer>> make_microfacet_renderer(const MicrofacetsPackage& package, const RenderConfig& config);

} // namespace standin::microfacets
