// Every representation standin knows. Adding one is a folder under src/reps/ (its registration()
// describes it: options, debug views, bake, codec, renderer, summary) and a line here.
#include "reps/displaced_mesh/displaced_mesh.h"
#include "reps/enhanced_billboards/billboards.h"
#include "reps/microfacets/microfacets.h"
#include "reps/view_atlas/view_atlas.h"

#include <standin/package.h>

// this target's shaders, registered at static initialisation (cmake/shaders.cmake)
#include "embedded_shaders.inc"

namespace standin {

const std::vector<Representation>& representations()
{
    static const std::vector<Representation> all = {
        billboards::registration(),
        view_atlas::registration(),
        microfacets::registration(),
        displaced_mesh::registration(),
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
