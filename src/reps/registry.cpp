// Every representation standin knows: name -> {bake, write, read, make_renderer}. Adding one is a
// folder under src/reps/ and a line here.
#include "reps/enhanced_billboards/billboards.h"
#include "reps/microfacets/microfacets.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/package.h>

namespace standin {

const std::vector<Representation>& representations()
{
    static const std::vector<Representation> all = {
        {"enhanced-billboards",
         "greedy orthographic billboards with colour, coverage, normal and depth, ray-cast per pixel "
         "(Vichitvejpaisal 2005/2006)",
         billboards::bake, billboards::write, billboards::read, billboards::make_renderer},
        {"view-atlas",
         "one camera-facing quad showing the nearest (or three blended, depth-corrected) of many "
         "pre-rendered views (Saraiva et al.)",
         view_atlas::bake, view_atlas::write, view_atlas::read, view_atlas::make_renderer},
        {"microfacets",
         "view-facing textured squares at the occupied voxels of an octree, textured from the nearest captured views "
         "and clipped by their depth (Yamazaki et al. 2002)",
         microfacets::bake, microfacets::write, microfacets::read, microfacets::make_renderer},
    };
    return all;
}

const Representation* find_representation(const std::string& name)
{
    for (const Representation& r : representations())
        if (r.name == name) return &r;
    return nullptr;
}

} // namespace standin
