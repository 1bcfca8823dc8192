// Mip levels of the displacement maps (Bauman, Livny & El-Sana §3.4: "we have constructed a MipMap
// hierarchy for every displacement-map ... so adjacent elevation values are taken into account in
// a view-dependent manner"). The paper names no filter; this is a vertex-centred dyadic pyramid
// (level l + 1 keeps the even vertices of level l).
//
// Steps, per face and level:
//  - corners: copied from the finest level (they are the control vertices, shared by every face
//    around them);
//  - vertices on the face's edges: 1/2 of the centre plus 1/4 of the sum of its two neighbours
//    along the edge, a formula symmetric in the two neighbours, so both faces of the edge, which
//    walk it in opposite directions, compute the same bits from the same (copied) finest samples;
//  - inside: 1/2 of the centre plus 1/12 of each of its six neighbours (the hat's weights).
#include "reps/displaced_mesh/sample.h"

#include <tbb/parallel_for.h>

namespace standin::displaced_mesh {

std::vector<float> build_levels(const PatternLayout& layout, const std::vector<float>& finest)
{
    const std::size_t faces = finest.size() / layout.finest_samples;
    std::vector<float> out(faces * layout.samples_per_face, 0.0f);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, faces), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t f = r.begin(); f != r.end(); ++f) {
            float* face = &out[f * layout.samples_per_face];
            std::copy_n(&finest[f * layout.finest_samples], layout.finest_samples, face);
            for (int level = 0; level < layout.exponent; ++level) {
                const int n = layout.level_segments(level), half = n / 2;
                auto fine = [&](int i, int j) { return face[layout.index(level, i, j)]; };
                for (int i = 0; i <= half; ++i)
                    for (int j = 0; j <= half - i; ++j) {
                        int fi = 2 * i, fj = 2 * j;
                        float c = fine(fi, fj), value;
                        bool corner = (i == 0 && j == 0) || (i == 0 && j == half) || i == half;
                        if (corner) {
                            value = c;
                        } else if (i == 0) {
                            value = 0.5f * c + 0.25f * (fine(0, fj - 1) + fine(0, fj + 1));
                        } else if (j == 0) {
                            value = 0.5f * c + 0.25f * (fine(fi - 1, 0) + fine(fi + 1, 0));
                        } else if (i + j == half) {
                            value = 0.5f * c + 0.25f * (fine(fi - 1, fj + 1) + fine(fi + 1, fj - 1));
                        } else {
                            float ring = fine(fi, fj - 1) + fine(fi, fj + 1) + fine(fi - 1, fj) + fine(fi + 1, fj) +
                                         fine(fi - 1, fj + 1) + fine(fi + 1, fj - 1);
                            value = 0.5f * c + ring / 12.0f;
                        }
                        face[layout.index(level + 1, i, j)] = value;
                    }
            }
        }
    });
    return out;
}

} // namespace standin::displaced_mesh
