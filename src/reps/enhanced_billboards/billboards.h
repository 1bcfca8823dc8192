// Enhanced billboards in memory (Vichitvejpaisal 2005 §3.1, Vichitvejpaisal & Kanongchaiyos 2006 §3.1): oriented boxes, each with a colour +
// coverage image and a normal + depth image over its front plane. Shared by the baker, the package
// codec and the renderer of this folder.
#pragma once

#include <standin/image.h>
#include <standin/package.h>

#include "reps/common/surface_image.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace standin::billboards {

struct FaceData; // capture.h

// A billboard is a surface image (reps/common/surface_image.h: its frame, colour + coverage and
// normal + depth, one depth encoding) with what its capture took. Row j of the images is uploaded
// as texture row j (t = (j + 0.5) / height).
struct Billboard : reps::SurfaceImage {
    std::size_t captured_faces = 0;
    double captured_area = 0.0;    // world units squared of source surface rasterised here
    // The BC5 blocks of the normals as read from a compressed package, written back as they are:
    // re-encoding the decoded normals would not give the same blocks (the contract's write, read,
    // write round trip is byte-identical). Empty for baked billboards.
    std::vector<std::uint8_t> normal_bc5;
};

// Why surface was left out of every billboard (manifest "left"): fractions of total area.
struct LeftOver {
    std::size_t faces = 0;
    double area = 0.0;
};

constexpr int k_max_grid_texels = 16384;        // texels along the diagonal
constexpr int k_default_direction_count = 256; // --directions sphere
// Texels along the diagonal for models with alpha-tested materials when neither --resolution nor
// --texel-size is given (issue #14): a leaf's outline and gaps need finer texels than a solid's
// surface. Measured on the generated tree (docs/RESULTS.md "Billboards on foliage: resolution and
// coarse mesh"): silhouette IoU at distance 8 is 0.943 at 512, 0.956 at 768, 0.963 at 1024.
constexpr int k_alpha_resolution = 1024;
// ... and up to k_alpha_max_resolution where the cut-out textures' own texels are finer
// (bake.cpp cutout_resolution: a capture texel as fine as a texel of the leaf texture, whose
// contour the alpha test draws). Measured on the generated tree (128-texel leaf texture, 2325 of
// its texels along the diagonal; docs/RESULTS.md "Billboards on foliage: texels as fine as the
// leaf texture's"): foliage protocol Luv at distance 1 3.40 at 1024, 3.05 at 1536, 2.89 at 2048;
// 4096 does not fit llvmpipe's texture memory.
constexpr int k_alpha_max_resolution = 2048;
// ... as long as the billboards' texels stay within k_alpha_texel_budget (the tree at 2048: 47.8M,
// 1049 MiB of GPU textures); a crown that would take more is baked again at the resolution that
// fits (budget_resolution), at least k_alpha_resolution.
constexpr std::size_t k_alpha_texel_budget = std::size_t(64) << 20;
// The resolution at which billboards of `texels` texels at `resolution` take about `budget`
// (texels grow with the square of the resolution), at least `floor`; `resolution` when they fit.
int budget_resolution(int resolution, std::size_t texels, std::size_t budget, int floor);
// Texels along the diagonal for models with detail finer than the default texels when neither
// --resolution nor --texel-size is given (issue #17: the held-out 110k-face engine, whose cooling
// fins and nested parts are a texel or two apart): after a bake at 512, when more than
// k_detail_edge_fraction of the covered texels end their surface (bake.cpp depth_edge_texels: a
// neighbour empty or across a depth edge), the model is baked again at k_detail_resolution.
// Measured (docs/RESULTS.md "Billboards: finer texels where the model's detail needs them"): the
// engine 0.52 at 512 (thesis Luv 3.49), 0.43 at 768 (2.50), 0.35 at 1024 (1.96); the generated
// assemblies 0.17-0.18 (Luv 1.2-1.3 at 512), the bunny 0.06, a noisy sphere 0.05. Lowered from
// 0.3 to 0.22 in session 14 for assimp's spider (thin legs, 0.265 at 512: IoU 0.971 -> 0.985, Luv
// 2.91 -> 2.61 at 1024, 0.6 -> 1.6 MB); the teapot 0.11 and Wuson 0.14 stay at 512. Lowered to
// 0.21 in session 21 with the 20-degree grazing angle, which ends fewer texels on steep faces:
// assimp's dwarf 0.227 at 10 degrees, 0.217 at 20 (Luv 0.50 at 1024 against 0.92 at 512), BCN 0.201
// and the generated assemblies 0.177-0.178 stay at 512.
constexpr int k_detail_resolution = 1024;
constexpr double k_detail_edge_fraction = 0.21;
// Grazing angle (degrees) for models with alpha-tested materials when --grazing-angle is not
// given: a leaf card captured at a grazing angle is a streak of texels whose walls the march meets
// from other directions, a leaf where the truth shows another card. Measured on the generated tree
// at 1024 texels: Luv at distance 1 5.22 at 10 degrees, 4.64 at 20 (the default of other models),
// 4.41 at 30, 4.39 at 40; holes 1.00% -> 0.50% at 30 (the faces left at the 64-billboard limit lie
// inside the crown: 128 billboards gave 4.37).
constexpr float k_alpha_grazing_angle = 30.0f;
// --partly-hidden for models with alpha-tested materials when it is not given: a dense crown hides
// part of every leaf card from every direction, and the seed's test (a face is captured only where
// no texel of it is hidden) left them all (docs/RESULTS.md "Partly hidden leaves").
constexpr float k_alpha_partly_hidden = 0.5f;
// --face-assignment squarer: a face the first billboard able to hold it would see at more than this
// many degrees from its normal waits for a later billboard of the same bake that sees it more
// squarely (bake.cpp, assign_squarer). 45 adds at most 3 billboards on 14 models (0, every face on
// its squarest billboard, gave 40-55% more billboards on concave models, the faces deferred past
// the ones hiding them) while it moves the steeply captured faces: assimp's COLLADA.dae, whose
// letter fronts the greedy put on a billboard 20.3 degrees from their plane (docs/RESULTS.md "Faces
// on the billboard that sees them squarely").
constexpr float k_squarer_angle = 45.0f;
// Rounds of squarer assignment without maps (each re-captures every billboard) before the one that
// writes them; they stop early once no fewer faces are left hidden.
constexpr int k_squarer_rounds = 5;
// The coarse mesh may stray from the model by at most this many texels (make_coarse_mesh's
// max_error; issue #17): it fills the pixels the billboards' texel-centre outlines lose at
// silhouettes, so it must reach them, and the model's 10% simplification lay inside its convex
// silhouettes by more. Measured on the held-out engine at 1024 texels (docs/RESULTS.md "The held-out
// engine: a coarse mesh within a texel of the surface"): holes with the coarse mesh 0.0118% at the
// ratio alone (9.9k triangles), 0.0029% within 1 texel (56k, package +1.9%), 0.0022% within 1/2
// (63k, +2.3%), 0.0022% with every triangle (+3.3%); spill, Luv and IoU better in each.
constexpr float k_coarse_error_texels = 1.0f;

// The bake parameters as the baker uses them (typed), read from the declared options
// (representation.cpp) by settings_from.
struct BakeSettings {
    int resolution = 512;        // texels along the bounding-box diagonal
    float texel_size = 0.0f;     // world units; 0: diagonal / resolution
    std::string directions = "seed"; // "seed" (36 x 18), "sphere" (even Fibonacci set), "axis" (+-X, +-Y, +-Z)
    int direction_count = 0;     // sphere only
    std::string score = "area";  // "area" (captured projected area) or "faces" (seed: facing faces)
    float depth_limit = 0.0f;    // fraction of the diagonal
    float grazing_angle = 0.0f;  // degrees from the plane below which faces are not projected
    // a partly hidden face is captured where it is in front when at least this fraction of its
    // texels are (capture.h, CaptureSettings::partly_visible); 0: the seed's all-or-nothing test
    float partly_hidden = 0.0f;
    // the most faces, in millions, of the greedy's second round, which splits the alpha-tested faces
    // it left (bake.cpp, bake_pass); 0: none (models without alpha-tested materials)
    float split_budget = 0.0f;
    int max_billboards = 0;
    float min_coverage = 0.0f;   // billboards capturing less than this fraction of the area found so far are dropped
    int depth_bits = 16;
    float coarse_ratio = 0.1f;
    std::string compression = "bc"; // "bc": KTX2 block-compressed maps; "none": PNG (package.cpp)
    // "clip": texels an open edge crosses are covered and clipped to its line, and texels an
    // alpha-tested face's cut-out contour crosses to the contour's line (capture.cpp, march.frag);
    // "overlap": covered whole; "centre": by their centre; "auto" (the bake's default) is resolved
    // by the baker to clip for sheet models and alpha-tested models, else centre
    std::string sheet_edges = "centre";
    // The back of a height field (a ray meeting a texel's top from behind): "show" draws it, marked a
    // near miss (closed surfaces through holes, double-sided sheets where their back was not
    // captured, a part's inside through an unwelded seam); "hide" drops it (a near miss for the
    // coarse mesh, which then culls back faces), for models with open parts of single-sided
    // materials, whose backs the truth culls (assimp's COLLADA.dae: a plane under the text, seen
    // from below). "auto" (the bake's default) is resolved to "show" by the baker (bake.cpp says
    // why); packages from before it read "show".
    std::string back_hits = "show";
    // "first": each face on the first billboard able to hold it (the greedy's, Vichitvejpaisal 2005
    // §3.2); "squarer": the greedy chooses the directions, then a face seen steeper than
    // k_squarer_angle goes to a later one of them that sees it more squarely (bake.cpp)
    std::string face_assignment = "first";
};

class EnhancedBillboardsPackage final : public Package {
public:
    std::string representation() const override { return "enhanced-billboards"; }

    Options parameters;    // as baked, derived values resolved (texel-size, direction-count)
    BakeSettings settings; // settings_from(parameters)
    std::vector<Billboard> billboards;
    Mesh coarse_mesh;                       // hole filling (seed §3.4); may be empty
    // The coarse mesh's open boundaries are sheet rims to fill without the near-miss test
    // (renderer.cpp, rims_first; manifest coarse_mesh.rims): set by the baker for models with open
    // double-sided parts and no alpha-tested material (a leaf card's outline is not its leaf's).
    // Packages without it (older ones, closed models) render as before.
    bool coarse_rims = false;
    // The model is one closed, outward surface (bake.cpp, one_closed_surface; manifest
    // one_closed_surface, absent: false): back hits are never the surface to show, and the renderer
    // leaves out proxies that hold only them (--cull-back-proxies auto).
    bool one_closed_surface = false;
    // Not closed, but one part whose backs face its own inside (bake.cpp, backs_unseen; manifest
    // backs_unseen, absent: false): the renderer leaves out back-hit proxies for it too.
    bool backs_unseen = false;
    // The compact coarse-mesh file as read from a bc package (coarse_mesh.h), written back as it is:
    // quantising and reordering again would not give the same bytes (read, write: byte-identical).
    std::string coarse_file;
    std::size_t faces_total = 0;
    double area_total = 0.0;
    double area_captured = 0.0;
    std::map<std::string, LeftOver> left;   // reason -> what was left
};

BakeSettings settings_from(const Options& parameters);
// Each vertex's representative among the vertices at exactly its position (bake.cpp).
std::vector<std::uint32_t> weld_by_position(const Mesh& mesh);
// `mesh` with its faces bisected until no edge is longer than `max_edge` into `out`, `source_face`
// naming each piece's face of `mesh`; false (and `out` untouched) when no edge was longer (bake.cpp).
bool split_long_edges(const Mesh& mesh, float max_edge, Mesh& out, std::vector<std::uint32_t>& source_face);
// The work mesh of the billboards' second round (bake.cpp, bake_pass): faces `remaining` of `mesh`
// alone, in their order, the alpha-tested ones bisected as split_long_edges does to edges of at most
// `max_edge`, each face's pieces in a row. `faces` and `source_face` become the new mesh's (each
// piece with its face's normal, part and source; an open edge's pieces open, the cuts not),
// `remaining` all of its faces (bake.cpp).
Mesh split_remaining(const Mesh& mesh, FaceData& faces, std::vector<std::uint32_t>& source_face, std::vector<std::uint32_t>& remaining,
                     float max_edge);
// The faces split_remaining would make, counted without making them (bake.cpp).
std::size_t split_remaining_faces(const Mesh& mesh, const std::vector<std::uint32_t>& remaining, float max_edge);
// The edge length of the second round for capture texels of `texel`: 8 texels where that makes at
// most `budget` faces (--split-budget), else 11.3 (bake.cpp); `pieces`, where given: the faces it makes.
float second_round_edge(const Mesh& mesh, const std::vector<std::uint32_t>& remaining, float texel, std::size_t budget,
                        std::size_t* pieces = nullptr);

// The registry entry (representation.cpp): options, debug views and the functions below.
Representation registration();
Result<std::unique_ptr<Package>> bake(const BakeContext& context);

// The share of a package's covered texels that end their surface: a 4-neighbour empty, or across a
// depth step larger than the link rule allows (height_field.h), where rays meet a depth edge the
// capture cannot resolve. Over k_detail_edge_fraction, the model has detail finer than its texels.
double depth_edge_fraction(const EnhancedBillboardsPackage& package);
Status write(const Package& package, const std::string& directory);
Result<std::unique_ptr<Package>> read(const std::string& directory, const nlohmann::json& manifest);
Result<std::unique_ptr<Renderer>> make_renderer(const Package& package, const RenderSettings& settings);
// `standin export` (export.cpp): the boxes with their maps and the coarse mesh.
Result<ExportScene> export_scene(const Package& package, const Options& options);

} // namespace standin::billboards
