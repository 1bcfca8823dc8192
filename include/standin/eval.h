// Evaluation: how faithful (image and geometric error against the ground truth) and how fast
// (GPU frame time) a stand-in is. The protocols are the papers' own: Vichitvejpaisal 2005 ch. 4 and appendix A
// ("thesis"), Saraiva et al. §3 ("saraiva"), a small "quick" one and "foliage" (leaf coverage by distance). docs/EVAL.md documents every
// figure, the JSON and the CSV schema.
#pragma once

#include <standin/camera.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/progress.h>
#include <standin/render.h>
#include <standin/status.h>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <vector>

namespace standin {

// ---------------------------------------------------------------------------------------------
// Views and protocols (src/eval/protocols.cpp)

// One camera of a protocol: an orbit view around the model's bounding sphere and an image size.
// The light is always default_light(camera), identical for truth and stand-in.
struct EvalView {
    OrbitView orbit;
    int width = 320, height = 240;
};

struct Protocol {
    std::string name;        // "thesis", "saraiva", "quick", "foliage"
    std::string description; // one line, names the seed section it follows
    std::vector<EvalView> views;
    // Samples a pixel along each axis that the protocol renders with unless told otherwise
    // (EvalOptions::supersample): 1 for the seeds' protocols, 4 for foliage.
    int supersample = 1;
};

// The 14 view directions of Saraiva et al. §3 as (azimuth, elevation) in degrees: 6 meridians
// (azimuth 0, 60, ..., 300) crossed with the 2 zonal lines that cut the sphere into three equal
// bands of latitude (elevation +30 and -30), then the poles (elevation +90, -90).
std::vector<glm::vec2> fourteen_directions();

// Names accepted by make_protocol, in the order --help lists them.
std::vector<std::string> protocol_names();
// thesis: 14 directions x distance 1 x fov 40 x {800x600, 400x300, 200x150} (42 views).
// saraiva: 14 directions x distance 2^-1..2^6 x fov {40, 60, 90} at 512x512 (336 views).
// quick: 4 directions (azimuth 0/90/180/270 at elevation 30, 0, -30, 90) at 320x240, fov 40, distance 1.
// foliage: the 14 directions at distances 1, 4 and 8, fov 40, 800x600, 4 x 4 samples a pixel (issue
// #14: does alpha-tested foliage keep its area in the distance, and its look once aliasing is not the
// measure).
// invalid_argument naming the unknown protocol and the known ones.
Result<Protocol> make_protocol(const std::string& name);

// ---------------------------------------------------------------------------------------------
// Image metrics (src/eval/image_metrics.cpp)

// A pixel is covered (part of the object) when its alpha is non-zero. Before colours are
// compared, both images are composited over the same opaque `background` (sRGB-encoded), so a
// hole compares as background against the truth's colour.
struct MetricOptions {
    glm::u8vec3 background{0, 0, 0};
    double psnr_cap_db = 100.0; // PSNR of identical rectangles (otherwise infinite)
};

// Every figure of one truth / stand-in image pair. Pixel sets: T = covered in the truth,
// S = covered in the stand-in, union U = T | S; the object rectangle is the tightest axis-aligned
// rectangle holding U (Saraiva et al. §3).
struct ImageMetrics {
    std::size_t truth_pixels = 0, standin_pixels = 0, union_pixels = 0, intersection_pixels = 0;
    int rect_x0 = 0, rect_y0 = 0, rect_x1 = 0, rect_y1 = 0; // [x0, x1) x [y0, y1); empty when U is empty
    std::size_t rect_pixels = 0;
    // Seed 000 eq. 2.2: mean over U of the Euclidean L*u*v* distance (sRGB -> linear -> XYZ D65 ->
    // L*u*v* with reference white D65, L in 0..100). 0 when U is empty.
    double luv_mean = 0.0;
    double luv_pixel_max = 0.0; // largest single-pixel distance over U
    // luv_mean split by where the distance arises (issue #14: on foliage most of it is edge):
    // luv_edge = the sum over pixels covered by only one image / |U| (so luv_mean - luv_edge comes
    // from T & S); luv_shared = the mean over T & S alone (0 when T & S is empty).
    double luv_edge = 0.0;
    double luv_shared = 0.0;
    // Seed 003 §3: |dR|+|dG|+|dB| (8-bit values) summed over the object rectangle (pixels outside
    // it are background in both images and add nothing), and that sum / rect_pixels.
    double rgb_total = 0.0;
    double rgb_avg = 0.0;
    // CIEDE2000 (Little CMS cmsCIE2000DeltaE, kL = kC = kH = 1) on L*a*b* with white D65, over U:
    // mean and 95th percentile (nearest rank).
    double de2000_mean = 0.0;
    double de2000_p95 = 0.0;
    std::size_t hole_pixels = 0;  // T and not S
    std::size_t spill_pixels = 0; // S and not T
    double hole_fraction = 0.0;   // hole_pixels / truth_pixels (0 when the truth is empty)
    double spill_fraction = 0.0;  // spill_pixels / truth_pixels (0 when the truth is empty)
    double iou = 1.0;             // |T & S| / |U|, 1 when both are empty
    // Over the object rectangle, RGB channels, MSE on 8-bit values: 10 log10(255^2 / MSE);
    // options.psnr_cap_db when the rectangle is identical or empty.
    double psnr = 0.0;
    std::size_t differing_pixels = 0; // pixels of the rectangle whose composited RGB differ at all
};

// Both images must have the same size (asserted).
ImageMetrics compare_images(const ImageRGBA8& truth, const ImageRGBA8& standin, const MetricOptions& options = {});

// CIE L*u*v* (D65) of one sRGB-encoded 8-bit colour.
glm::dvec3 luv_from_srgb8(glm::u8vec3 rgb);
// CIE L*a*b* (D65) of one sRGB-encoded 8-bit colour.
glm::dvec3 lab_from_srgb8(glm::u8vec3 rgb);
double ciede2000(glm::dvec3 lab1, glm::dvec3 lab2);

// An opaque heat map of the per-pixel L*u*v* distance after compositing over options.background:
// black (0) through red and yellow to white at `full_scale` and above; pixels outside U stay
// dark grey so the silhouette remains visible.
ImageRGBA8 difference_heatmap(const ImageRGBA8& truth, const ImageRGBA8& standin, double full_scale = 50.0,
                              const MetricOptions& options = {});
// The image composited over options.background, opaque.
ImageRGBA8 composite_over_background(const ImageRGBA8& image, const MetricOptions& options = {});

// A picture rendered with `factor` x `factor` samples a pixel, resolved to its pixels
// (EvalOptions::supersample). colour: each pixel the mean of its samples composited over
// options.background, in linear light (what a display shows of an anti-aliased picture), alpha 255
// where any sample is covered, else 0 and the background. sample_coverage: per pixel, bit
// (sy * factor + sx) set where that sample's alpha is non-zero, for the silhouette figures.
constexpr int k_max_supersample = 8; // 64 samples: one 64-bit mask a pixel
struct ResolvedImage {
    ImageRGBA8 color;
    std::vector<std::uint64_t> sample_coverage; // width * height of `color`
};
// `image`'s size must be a multiple of `factor` (1..k_max_supersample; asserted).
ResolvedImage resolve_supersampled(const ImageRGBA8& image, int factor, const MetricOptions& options = {});
// The silhouette figures of `metrics` (truth_pixels, standin_pixels, union_pixels,
// intersection_pixels, hole_pixels, spill_pixels, hole_fraction, spill_fraction, iou) counted
// over samples instead of pixels: the sets T, S and U of samples, the counts in pixels (samples /
// samples a pixel, rounded). The colour figures stay the pixels'. Masks of the same size.
void count_silhouette_over_samples(ImageMetrics& metrics, const std::vector<std::uint64_t>& truth_coverage,
                                   const std::vector<std::uint64_t>& standin_coverage, int factor);

// ---------------------------------------------------------------------------------------------
// Geometric error (src/eval/geometric_error.cpp)

struct SurfaceDistance {
    std::size_t samples = 0;
    double mean = 0.0, max = 0.0;         // world units
    double mean_rel = 0.0, max_rel = 0.0; // divided by the bounding-box diagonal of `to`
};

// One-sided surface distance from `from` to `to`: `samples` points placed on `from` with
// probability proportional to area (deterministic for a given seed), each measured to the
// closest point of `to` (embree 3 point queries). Both meshes must pass validate_mesh;
// invalid_argument when samples is 0.
constexpr std::size_t k_max_surface_samples = 100'000'000; // 1.6 GB of points and distances
Result<SurfaceDistance> surface_distance(const Mesh& from, const Mesh& to, std::size_t samples = 100000,
                                         std::uint32_t seed = 1);

// ---------------------------------------------------------------------------------------------
// Evaluation of one stand-in (src/eval/evaluate.cpp)

struct EvalOptions {
    MetricOptions metrics;
    // GPU time of this many frames per view and subject after one warm-up frame (median kept,
    // for the frame-rate-vs-resolution chart); 0 skips timing.
    int timed_frames = 3;
    // Shadows of the light (ShadowMap), for truth and stand-in alike: each draws its own shadow
    // map, from the same light, fitted to the model's bounding sphere. Timed frames leave them out.
    bool shadows = false;
    int shadow_resolution = 2048;
    // The shading model of truth and stand-in alike (issue #14): lambert_blinn_phong reproduces
    // figures measured before the GGX model became the default.
    ShadingModel shading = ShadingModel::ggx;
    // Samples a pixel along each axis (1..k_max_supersample): both pictures are rendered at this
    // many times the view's size and resolved (resolve_supersampled); colour figures compare the
    // resolved pixels, silhouette figures the samples (count_silhouette_over_samples). A
    // one-sample picture of alpha-tested foliage is mostly aliasing: the truth turned by 0.1 degree
    // differs from itself by more than the Luv 3 (docs/EVAL.md). Timed frames stay at the
    // view's size.
    int supersample = 1;
};

struct ViewResult {
    EvalView view;
    ImageMetrics metrics;
    double truth_ms = 0.0, standin_ms = 0.0; // median GPU frame time (timer query), 0 when not timed
    double truth_wall_ms = 0.0, standin_wall_ms = 0.0; // median wall time to glFinish
};

struct MetricStats {
    double mean = 0.0, median = 0.0, max = 0.0, min = 0.0;
};

struct EvalResult {
    std::string protocol;
    std::string device;                  // GL_RENDERER
    int supersample = 1;                 // EvalOptions::supersample
    std::vector<ViewResult> views;       // in protocol order
    std::optional<SurfaceDistance> surface; // set by the caller for mesh stand-ins
};

// Called once per view with its images, e.g. to write the report's PNG triplets. A non-ok status
// stops the evaluation and is returned.
using ViewSink = std::function<Status(std::size_t index, const ViewResult& result, const RenderedImage& truth,
                                      const RenderedImage& standin)>;

// The truth's images and frame times of an evaluation, by view: several stand-ins evaluated against
// one truth with one protocol, sphere and options (`standin eval MODEL A B ...`) pass the same
// object to each evaluate(), whose first call fills it and the others reuse it, so the mesh is
// drawn and timed once, and every stand-in is compared with the same pictures and the same times.
struct TruthViews {
    std::vector<RenderedImage> images;             // resolved when supersampled
    std::vector<std::vector<std::uint64_t>> sample_coverage; // per view, empty when not supersampled
    int supersample = 0;                           // the evaluation's that filled it; 0 while empty
    std::vector<double> gpu_ms, wall_ms; // 0 when not timed
};

// Renders every view of `protocol` with both renderers (same camera, same default_light) in the
// current GL context and compares the images. `sphere` is the original model's bounding sphere,
// which places the cameras for both. Progress: stage "eval", one step per view. gpu_error when
// rendering fails; the sink's error when it fails. `truth_views`: the truth's side kept across
// evaluations (TruthViews); null renders it anew.
Result<EvalResult> evaluate(Renderer& truth, Renderer& standin, const BoundingSphere& sphere, const Protocol& protocol,
                            const EvalOptions& options, const Progress& progress, const ViewSink& sink = {},
                            TruthViews* truth_views = nullptr);

// What a user asks of an evaluation: from how far is the stand-in as good as the mesh, and from how
// far is it cheaper, so that an engine's level of detail knows where to switch.
struct Verdict {
    double de2000_threshold = 2.0; // "indistinguishable": mean CIEDE2000 over the views at most this
    // The smallest relative distance of the protocol from which every distance as far or farther is
    // indistinguishable (nullopt: none is). With one distance, that distance or none.
    std::optional<float> indistinguishable_from;
    // The smallest relative distance from which the stand-in draws faster than the mesh at every
    // distance as far or farther, and the mesh's mean screen coverage there in pixels (the stand-in
    // is cheaper at that size and below); nullopt when not timed or never cheaper.
    std::optional<float> cheaper_from;
    double cheaper_below_pixels = 0.0;
    // Frame times compared: wall time to glFinish where GPU timer queries miss the work (llvmpipe
    // defers rasterisation) or read zero, else the GPU timer.
    bool wall_time = false;
    bool timed = false;
    std::string line; // the sentence, for the terminal and the report
};
Verdict eval_verdict(const EvalResult& result);

// Mean, median, max and min over views of one figure.
MetricStats stats_over_views(const EvalResult& result, double (*figure)(const ViewResult&));

// The --json document (docs/EVAL.md): {"format", "version", "protocol", "device", "model",
// "package", "summary": {...}, "verdict": {...}, "stats": {...}, "views": [...], "tables": {...},
// "surface"}.
// `identity` is merged in at the top level (model and package names, command line).
nlohmann::json eval_to_json(const EvalResult& result, const nlohmann::json& identity = {});

// The tables of the protocol as CSV texts, keyed by file name ("views.csv", "table_a2.csv",
// "table_saraiva.csv", "frame_times.csv"); header row first, one row per line.
std::vector<std::pair<std::string, std::string>> eval_tables_csv(const EvalResult& result);

// ---------------------------------------------------------------------------------------------
// HTML report (src/eval/report.cpp)

// Writes a self-contained report directory: index.html, the CSVs, SVG charts and per-view
// images/NNN_{truth,standin,diff}.png. Usage: begin() (creates a temporary directory beside
// `directory`), add_view() from the evaluation's ViewSink, finish() (writes the rest and renames
// the temporary directory into place, replacing an older report). io_error naming the path.
// Where a report directory will be: `directory` without a trailing slash, refused (invalid_argument,
// naming it) when it exists and is a file, or a non-empty folder that is not a report (no
// index.html), or when its parent folder does not exist (check_output_path).
Result<std::string> report_directory_path(const std::string& directory);

class ReportWriter {
public:
    static Result<ReportWriter> begin(const std::string& directory);
    ReportWriter(ReportWriter&&) noexcept;
    ReportWriter& operator=(ReportWriter&&) noexcept;
    ~ReportWriter(); // removes the temporary directory if finish() was not reached
    Status add_view(std::size_t index, const ViewResult& result, const RenderedImage& truth,
                    const RenderedImage& standin);
    // `json` is eval_to_json's document (its identity fields head the page).
    Status finish(const EvalResult& result, const nlohmann::json& json);
    const std::string& directory() const;

private:
    ReportWriter() = default;
    struct State;
    std::unique_ptr<State> state_;
};

// ---------------------------------------------------------------------------------------------
// Several stand-ins of one model side by side (standin eval MODEL PACKAGE PACKAGE ...,
// src/eval/report.cpp): which representation, at what cost, looks how next to the mesh.

// One evaluated stand-in of a comparison.
struct ComparedStandin {
    std::string package;        // as given on the command line
    std::string representation; // "mesh" for a model file
    std::uint64_t bytes = 0;    // on disk
    std::string report;         // its own report's directory, relative to the comparison's ("" without)
    nlohmann::json json;        // eval_to_json's document
    std::vector<ImageRGBA8> pictures; // comparison_picture of its first views (k_comparison_sheet_views)
};

// A compared stand-in's frame time and the mesh's, means over its views, by the clock its verdict
// compared them with (wall time on llvmpipe, else the GPU timer): {stand-in ms, mesh ms}, or
// nullopt when it was not timed (--frames 0).
std::optional<std::pair<double, double>> comparison_frame_ms(const nlohmann::json& eval);

// Views of the contact sheet (the protocol's first ones) and their width there, at most.
constexpr std::size_t k_comparison_sheet_views = 8;
constexpr int k_comparison_sheet_width = 320;

// A rendered picture as the sheet shows it: on dark grey where it is transparent, box-filtered
// by a whole factor to at most k_comparison_sheet_width pixels wide.
ImageRGBA8 comparison_picture(const ImageRGBA8& picture);

// The contact sheet: one row per view, the truth's picture first, then each stand-in's in order,
// 4 white pixels apart; the first row's pictures labelled T, 1, 2, ... in their top-left corner. Pictures of one row share its height (the protocol's view size).
ImageRGBA8 comparison_sheet(const std::vector<ImageRGBA8>& truth, const std::vector<ComparedStandin>& standins);

// The comparison's --json document (docs/EVAL.md): {"format": "standin-eval-comparison", "version",
// "model", "protocol", "device", "command", "standins": [{"package", "representation", "bytes",
// "report", "eval": eval_to_json's document}, ...]}.
nlohmann::json comparison_to_json(const std::string& model, const std::string& protocol, const std::string& device,
                                  const std::string& command, const std::vector<ComparedStandin>& standins);

// Writes index.html (a table of every stand-in's figures and size, linking its own report; the
// sheet; each view's pictures side by side), sheet.png and comparison.json into `directory`, an
// existing folder the caller commits (it holds the stand-ins' own reports). `truth`: the truth's
// pictures of the sheet's views. io_error naming the path.
Status write_comparison_page(const std::string& directory, const nlohmann::json& comparison,
                             const std::vector<ImageRGBA8>& truth, const std::vector<ComparedStandin>& standins);

// ---------------------------------------------------------------------------------------------
// Benchmarks (src/eval/benchmark.cpp)

// N copies of a model on a square ground grid (spacing 2.5 bounding radii, each standing on y = 0
// with the middle of its box over its cell), and a perspective camera (fov 60) at the model's
// height, 1.5 spacings in front of the first row, looking across the grid at a point a third of
// the way in. Deterministic; instances may be 0 (an empty scene).
struct CrowdScene {
    std::vector<glm::mat4> world_from_object;
    Camera camera;
    Light light;
};
CrowdScene make_crowd(const BoundingSphere& sphere, const Bounds& bounds, std::size_t instances, float aspect);

struct BenchOptions {
    int warmup_frames = 3;
    int frames = 15;                             // median over these
    std::vector<glm::ivec2> resolutions = {{800, 600}, {400, 300}, {200, 150}}; // seed Table A-1
    std::vector<std::size_t> crowd_counts;       // empty: no crowd
    glm::ivec2 crowd_resolution{800, 600};
    std::vector<float> coverage_distances = {0.5f, 1.0f, 2.0f, 4.0f, 8.0f}; // distance_rel, 800x600
};

struct FrameRecord {
    int width = 0, height = 0;
    std::string subject;       // "package", "package coarse=off" (a variant), "mesh"
    std::string scene;         // "orbit" (one model, protocol camera), "coverage", "crowd"
    std::size_t instances = 1;
    float distance_rel = 1.0f;
    double ms_median = 0.0, ms_min = 0.0, ms_max = 0.0; // GPU timer queries
    double wall_ms_median = 0.0; // submission to glFinish; the figure to compare on llvmpipe
    double cpu_ms_median = 0.0;  // process CPU time (all threads) over the same span: llvmpipe's work, independent of machine load
    std::size_t covered_pixels = 0;
    double fetches_per_pixel = -1.0; // -1 where the renderer does not count fetches
    double fragments_per_pixel = -1.0; // overdraw: fragment-stage runs per covered pixel; -1 where not counted
    std::uint64_t primitives = 0;
};

// The renderers bench measures; null ones are not measured. Variants are the same package drawn
// with other run-time options (Representation::bench_variants), named "package NAME=VALUE".
struct BenchSubjects {
    Renderer* mesh = nullptr;
    Renderer* package = nullptr;
    std::vector<std::pair<std::string, Renderer*>> package_variants;
};

// Times every subject at every resolution (orbit view: azimuth 30, elevation 20, distance 1,
// fov 40, default light), at each coverage distance, and in the crowd scenes. Needs a current
// context. Progress stage "bench".
Result<std::vector<FrameRecord>> benchmark_frames(const BenchSubjects& subjects, const Mesh& mesh,
                                                  const BenchOptions& options, const Progress& progress);

// Peak resident set size of this process in MiB (VmHWM), 0 when unknown; reset_peak_rss() starts
// a new peak (Linux: writes 5 to /proc/self/clear_refs; false where that is refused).
double peak_rss_mb();
bool reset_peak_rss();

} // namespace standin
