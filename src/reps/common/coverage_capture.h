// Fractional coverage for captures of alpha-tested models (issue #14), shared by the bakers that
// capture views by rendering the ground-truth mesh (view atlas, microfacets). An alpha-tested leaf
// card cut out by a texture has edges that run anywhere inside a capture texel; stored as binary
// coverage, the stand-in can only place them on texel borders. Such models are captured at f x f
// samples per texel and box-filtered down: a texel's alpha becomes the fraction of it covered, and
// the stand-ins' walks filter that fraction bilinearly around a hit and keep the hit where it
// reaches 1/2, the truth's own alpha-test rule (reps/common/shaders/coverage.glsl).
#pragma once

#include <standin/image.h>
#include <standin/mesh.h>

#include <initializer_list>
#include <vector>

namespace standin::reps {

// Whether any material of the model is alpha-tested (MASK, or BLEND drawn as MASK): its leaves are
// cut out of their cards.
bool has_cutouts(const Mesh& mesh);

// Capture samples per texel side: 1 for models without alpha-tested materials (their captures and
// packages stay as they were), else `preferred`, or the value of the environment variable
// `override_variable` (1..8, for measurements and tests) when set, as far as the capture stays
// within 8192^2 pixels.
int coverage_samples(const Mesh& mesh, int resolution, int preferred, const char* override_variable);

// Box-filters captures made at f times the resolution per side to one texel per f x f block. A
// sample is covered where `color`'s alpha is not 0. Per texel: `color`'s alpha = the covered fraction
// (at least 1 where any sample is covered); `color`'s RGB and every image of `averaged` = the mean of
// the covered samples (their alpha 255); `depth` (window depths, smaller nearer, 1 where nothing was
// drawn; may be null) = the nearest covered sample's, so a texel holding an edge keeps its front
// surface. Texels without a covered sample are all 0, depth 1. f = 1 changes nothing.
// `front_tolerance` >= 0 (window-depth units, needs `depth`): only the samples within it of the
// texel's nearest covered one count as covered, so that a texel over an edge between a near and a far
// surface holds the near one's coverage, colour and normal, unmixed with the far one's (a texel
// keeps one depth, so the far surface's samples cannot be stored there anyway).
void downsample_coverage(ImageRGBA8& color, std::initializer_list<ImageRGBA8*> averaged, std::vector<float>* depth, int f,
                         float front_tolerance = -1.0f);

// Face f's area in texels of its material's base-colour texture (0 without one): how finely the
// texture, and the alpha contour it draws, covers the face.
double texture_texel_area(const Mesh& mesh, std::size_t f);

// The world size of one texel of the texture that cuts the model's leaves out: the area-weighted
// median, over the textured alpha-tested faces, of sqrt(face area / its area in texture texels).
// 0 where no alpha-tested face is textured (cut-outs by opacity or vertex alpha: their contours are
// their edges). The bakers capture such models with texels about this fine (issue #14).
double cutout_texel_size(const Mesh& mesh);

} // namespace standin::reps
