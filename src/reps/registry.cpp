// Every representation standin knows: name -> {bake, write, read, make_renderer}. Adding one is a
// folder under src/reps/ and a line here.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/enhanced_billboards/billboards.h"
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
        {"displaced-mesh",
         "coarse control mesh + per-face displacement maps, bisected on the GPU every frame to a "
         "screen-space tolerance (Bauman, Livny & El-Sana)",
         displaced_mesh::bake, displaced_mesh::write, displaced_mesh::read, displaced_mesh::make_renderer},
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
