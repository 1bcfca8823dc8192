// Evaluation of one stand-in against the ground truth over a protocol's views: both rendered from
// the same camera with the same light (Saraiva et al. §3: "rendered in the same lighting conditions"),
// compared per pixel, summarised over views, and laid out as the seeds' tables (000 appendix A
// Table A-2, 003 Tables 1-3).
#include <standin/eval.h>

#include "gpu/frame_timing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

namespace standin {

namespace {

// The figures every summary, table and JSON view carries, by name.
struct Figure {
    const char* name;
    double (*get)(const ViewResult&);
};
const std::vector<Figure>& figures()
{
    static const std::vector<Figure> all = {
        {"luv_mean", [](const ViewResult& v) { return v.metrics.luv_mean; }},
        {"luv_pixel_max", [](const ViewResult& v) { return v.metrics.luv_pixel_max; }},
        {"de2000_mean", [](const ViewResult& v) { return v.metrics.de2000_mean; }},
        {"de2000_p95", [](const ViewResult& v) { return v.metrics.de2000_p95; }},
        {"rgb_avg", [](const ViewResult& v) { return v.metrics.rgb_avg; }},
        {"rgb_total", [](const ViewResult& v) { return v.metrics.rgb_total; }},
        {"hole_fraction", [](const ViewResult& v) { return v.metrics.hole_fraction; }},
        {"spill_fraction", [](const ViewResult& v) { return v.metrics.spill_fraction; }},
        {"iou", [](const ViewResult& v) { return v.metrics.iou; }},
        {"psnr", [](const ViewResult& v) { return v.metrics.psnr; }},
        {"luv_edge", [](const ViewResult& v) { return v.metrics.luv_edge; }},
        {"luv_shared", [](const ViewResult& v) { return v.metrics.luv_shared; }},
    };
    return all;
}

double median_of(std::vector<double> values)
{
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    std::size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Result<gpu::FrameTimes> time_view(Renderer& renderer, const Camera& camera, const Light& light, const EvalView& view,
                                  int frames)
{
    DrawParams params;
    params.camera = camera;
    params.light = light;
    params.viewport = {view.width, view.height};
    return gpu::time_frames(renderer, params, 1, frames);
}

// One view's picture at `n` x `n` samples a pixel, resolved (resolve_supersampled): its sample
// masks appended to `sample_coverage`. n = 1 is the picture as rendered, nothing appended.
Result<RenderedImage> render_view(Renderer& renderer, const Camera& camera, const Light& light, const EvalView& view,
                                  const ShadowOptions& shadows, int n, const MetricOptions& metrics,
                                  std::vector<std::vector<std::uint64_t>>& sample_coverage)
{
    Result<RenderedImage> image = render_offscreen(renderer, camera, light, view.width * n, view.height * n, {}, shadows);
    if (!image || n == 1) return image;
    ResolvedImage resolved = resolve_supersampled(image->color, n, metrics);
    sample_coverage.push_back(std::move(resolved.sample_coverage));
    return RenderedImage{std::move(resolved.color), {}};
}

// Views grouped by a key, in order of first appearance.
template <typename Key>
std::vector<std::pair<Key, std::vector<const ViewResult*>>> group_views(const EvalResult& result,
                                                                        Key (*key_of)(const ViewResult&))
{
    std::vector<std::pair<Key, std::vector<const ViewResult*>>> groups;
    for (const ViewResult& v : result.views) {
        Key key = key_of(v);
        auto it = std::find_if(groups.begin(), groups.end(), [&](const auto& g) { return g.first == key; });
        if (it == groups.end()) groups.push_back({key, {&v}});
        else it->second.push_back(&v);
    }
    return groups;
}

double mean_over(const std::vector<const ViewResult*>& views, double (*figure)(const ViewResult&))
{
    double sum = 0.0;
    for (const ViewResult* v : views) sum += figure(*v);
    return views.empty() ? 0.0 : sum / double(views.size());
}

std::pair<int, int> size_key(const ViewResult& v) { return {v.view.width, v.view.height}; }
std::pair<float, float> fov_distance_key(const ViewResult& v)
{
    return {v.view.orbit.fov_y_degrees, v.view.orbit.distance_rel};
}

std::string number(double value)
{
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.6g", value);
    return buffer;
}

} // namespace

Result<EvalResult> evaluate(Renderer& truth, Renderer& standin, const BoundingSphere& sphere, const Protocol& protocol,
                            const EvalOptions& options, const Progress& progress, const ViewSink& sink,
                            TruthViews* truth_views)
{
    TruthViews own;
    TruthViews& kept = truth_views ? *truth_views : own;
    if (options.supersample < 1 || options.supersample > k_max_supersample)
        return error(StatusCode::invalid_argument, "supersample: " + std::to_string(options.supersample) +
                                                       " samples a pixel along each axis is outside 1.." +
                                                       std::to_string(k_max_supersample));
    const int n = options.supersample;
    if (kept.supersample == 0) kept.supersample = n;
    if (kept.supersample != n)
        return error(StatusCode::invalid_argument, "evaluate: the kept truth views have " + std::to_string(kept.supersample) +
                                                       " samples a pixel along each axis, not " + std::to_string(n));
    EvalResult result;
    result.protocol = protocol.name;
    result.supersample = n;
    for (std::size_t i = 0; i < protocol.views.size(); ++i) {
        progress.report("eval", double(i) / double(protocol.views.size()));
        const EvalView& view = protocol.views[i];

        // the same camera and light for both
        Camera camera = orbit_camera(sphere, view.orbit, float(view.width) / float(view.height));
        Light light = default_light(camera);
        light.shading = options.shading;
        ShadowOptions shadows;
        shadows.enabled = options.shadows;
        shadows.scene = sphere;
        shadows.resolution = options.shadow_resolution;
        const bool truth_kept = kept.images.size() > i;
        if (!truth_kept) {
            Result<RenderedImage> truth_image = render_view(truth, camera, light, view, shadows, n,
                                                            options.metrics, kept.sample_coverage);
            if (!truth_image) return truth_image.status();
            kept.images.push_back(std::move(*truth_image));
            kept.gpu_ms.push_back(0.0);
            kept.wall_ms.push_back(0.0);
        }
        const RenderedImage& truth_image = kept.images[i];
        std::vector<std::vector<std::uint64_t>> standin_coverage;
        Result<RenderedImage> standin_image =
            render_view(standin, camera, light, view, shadows, n, options.metrics, standin_coverage);
        if (!standin_image) return standin_image.status();

        // compare, time, hand the images on
        ViewResult view_result;
        view_result.view = view;
        view_result.metrics = compare_images(truth_image.color, standin_image->color, options.metrics);
        if (n > 1)
            count_silhouette_over_samples(view_result.metrics, kept.sample_coverage[i], standin_coverage.front(), n);
        if (options.timed_frames > 0) {
            if (!truth_kept) {
                Result<gpu::FrameTimes> truth_ms = time_view(truth, camera, light, view, options.timed_frames);
                if (!truth_ms) return truth_ms.status();
                kept.gpu_ms[i] = truth_ms->median_ms;
                kept.wall_ms[i] = truth_ms->wall_median_ms;
            }
            Result<gpu::FrameTimes> standin_ms = time_view(standin, camera, light, view, options.timed_frames);
            if (!standin_ms) return standin_ms.status();
            view_result.truth_ms = kept.gpu_ms[i];
            view_result.standin_ms = standin_ms->median_ms;
            view_result.truth_wall_ms = kept.wall_ms[i];
            view_result.standin_wall_ms = standin_ms->wall_median_ms;
        }
        if (sink) STANDIN_RETURN_IF_ERROR(sink(i, view_result, truth_image, *standin_image));
        result.views.push_back(view_result);
    }
    progress.report("eval", 1.0);
    return result;
}

MetricStats stats_over_views(const EvalResult& result, double (*figure)(const ViewResult&))
{
    MetricStats stats;
    if (result.views.empty()) return stats;
    std::vector<double> values;
    for (const ViewResult& v : result.views) values.push_back(figure(v));
    double sum = 0.0;
    for (double x : values) sum += x;
    stats.mean = sum / double(values.size());
    stats.max = *std::max_element(values.begin(), values.end());
    stats.min = *std::min_element(values.begin(), values.end());
    stats.median = median_of(values);
    return stats;
}

// Whether the GPU timer queries of a result can be trusted: llvmpipe's miss its deferred
// rasterisation, and a query that read zero measured nothing.
static bool gpu_timers_usable(const EvalResult& result)
{
    if (result.device.find("llvmpipe") != std::string::npos) return false;
    for (const ViewResult& v : result.views)
        if (v.truth_wall_ms > 0.0 && (v.truth_ms <= 0.0 || v.standin_ms <= 0.0)) return false;
    return true;
}

static std::string distance_text(float d)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g", double(d));
    return std::string(text) + "x the base distance";
}

Verdict eval_verdict(const EvalResult& result)
{
    Verdict verdict;
    // per distance: mean CIEDE2000, mean frame times, mean pixels the mesh covers
    struct Group {
        double de2000 = 0.0, truth_ms = 0.0, standin_ms = 0.0, pixels = 0.0;
        int views = 0, timed = 0;
    };
    std::map<float, Group> by_distance;
    verdict.wall_time = !gpu_timers_usable(result);
    for (const ViewResult& v : result.views) {
        Group& g = by_distance[v.view.orbit.distance_rel];
        g.de2000 += v.metrics.de2000_mean;
        g.pixels += double(v.metrics.truth_pixels);
        g.views += 1;
        double t = verdict.wall_time ? v.truth_wall_ms : v.truth_ms, s = verdict.wall_time ? v.standin_wall_ms : v.standin_ms;
        if (t > 0.0 && s > 0.0) {
            g.truth_ms += t;
            g.standin_ms += s;
            g.timed += 1;
        }
    }
    if (by_distance.empty()) return verdict;
    // scanning from the farthest: the nearest distance from which all farther ones pass
    bool all_indistinguishable = true, all_cheaper = true;
    verdict.timed = std::all_of(by_distance.begin(), by_distance.end(), [](const auto& g) { return g.second.timed > 0; });
    for (auto it = by_distance.rbegin(); it != by_distance.rend(); ++it) {
        const Group& g = it->second;
        all_indistinguishable = all_indistinguishable && g.de2000 / g.views <= verdict.de2000_threshold;
        if (all_indistinguishable) verdict.indistinguishable_from = it->first;
        all_cheaper = all_cheaper && verdict.timed && g.standin_ms < g.truth_ms;
        if (all_cheaper) {
            verdict.cheaper_from = it->first;
            verdict.cheaper_below_pixels = g.pixels / g.views;
        }
    }

    // the sentence
    char text[160];
    const Group& first = by_distance.begin()->second;
    bool one_distance = by_distance.size() == 1;
    std::string line;
    if (one_distance) {
        std::snprintf(text, sizeof text, "at %s: %s (mean CIEDE2000 %.2f, threshold %.0f)",
                      distance_text(by_distance.begin()->first).c_str(),
                      verdict.indistinguishable_from ? "indistinguishable from the mesh" : "distinguishable from the mesh",
                      first.de2000 / first.views, verdict.de2000_threshold);
        line = text;
    } else if (verdict.indistinguishable_from) {
        std::snprintf(text, sizeof text, "indistinguishable from the mesh (mean CIEDE2000 <= %.0f) from %s on",
                      verdict.de2000_threshold, distance_text(*verdict.indistinguishable_from).c_str());
        line = text;
    } else {
        std::snprintf(text, sizeof text, "distinguishable from the mesh at every distance (mean CIEDE2000 > %.0f at %s)",
                      verdict.de2000_threshold, distance_text(by_distance.rbegin()->first).c_str());
        line = text;
    }
    std::string clock = verdict.wall_time ? "wall time to glFinish: this device's GPU timers miss its work" : "GPU timer queries";
    if (!verdict.timed) {
        line += "; not timed (--frames 0)";
    } else if (one_distance) {
        std::snprintf(text, sizeof text, "; %s than the mesh there (%.3f vs %.3f ms, %s)",
                      first.standin_ms < first.truth_ms ? "cheaper" : "dearer", first.standin_ms / first.timed,
                      first.truth_ms / first.timed, clock.c_str());
        line += text;
    } else if (verdict.cheaper_from) {
        std::snprintf(text, sizeof text, "; cheaper than the mesh from %s on, where it covers %.0f px or fewer (%s)",
                      distance_text(*verdict.cheaper_from).c_str(), verdict.cheaper_below_pixels, clock.c_str());
        line += text;
    } else {
        line += "; never cheaper than the mesh at these distances (" + clock + ")";
    }
    verdict.line = line;
    return verdict;
}

nlohmann::json eval_to_json(const EvalResult& result, const nlohmann::json& identity)
{
    using nlohmann::json;
    json doc = json::object();
    doc["format"] = "standin-eval";
    doc["version"] = 1;
    if (identity.is_object())
        for (auto it = identity.begin(); it != identity.end(); ++it) doc[it.key()] = it.value();
    doc["protocol"] = result.protocol;
    doc["supersample"] = result.supersample;
    doc["device"] = result.device;

    // summary: means over views, plus the worst view of the Luv difference
    json summary = json::object(), stats = json::object();
    for (const Figure& f : figures()) {
        MetricStats s = stats_over_views(result, f.get);
        summary[f.name] = s.mean;
        stats[f.name] = {{"mean", s.mean}, {"median", s.median}, {"max", s.max}, {"min", s.min}};
    }
    summary["luv_max"] = stats["luv_mean"]["max"];
    summary["luv_median"] = stats["luv_mean"]["median"];
    summary["views"] = result.views.size();
    doc["summary"] = summary;
    doc["stats"] = stats;
    Verdict verdict = eval_verdict(result);
    doc["verdict"] = {{"line", verdict.line},
                      {"de2000_threshold", verdict.de2000_threshold},
                      {"indistinguishable_from_distance", verdict.indistinguishable_from ? json(*verdict.indistinguishable_from) : json(nullptr)},
                      {"cheaper_from_distance", verdict.cheaper_from ? json(*verdict.cheaper_from) : json(nullptr)},
                      {"cheaper_below_pixels", verdict.cheaper_from ? json(verdict.cheaper_below_pixels) : json(nullptr)},
                      {"timing", !verdict.timed ? "none" : verdict.wall_time ? "wall" : "gpu"}};

    // every view
    json views = json::array();
    for (const ViewResult& v : result.views) {
        const ImageMetrics& m = v.metrics;
        json item = {{"azimuth", v.view.orbit.azimuth_degrees},
                     {"elevation", v.view.orbit.elevation_degrees},
                     {"distance", v.view.orbit.distance_rel},
                     {"fov", v.view.orbit.fov_y_degrees},
                     {"width", v.view.width},
                     {"height", v.view.height}};
        for (const Figure& f : figures()) item[f.name] = f.get(v);
        item["truth_pixels"] = m.truth_pixels;
        item["standin_pixels"] = m.standin_pixels;
        item["union_pixels"] = m.union_pixels;
        item["hole_pixels"] = m.hole_pixels;
        item["spill_pixels"] = m.spill_pixels;
        item["differing_pixels"] = m.differing_pixels;
        item["rect"] = {m.rect_x0, m.rect_y0, m.rect_x1, m.rect_y1};
        item["rect_pixels"] = m.rect_pixels;
        item["truth_ms"] = v.truth_ms;
        item["standin_ms"] = v.standin_ms;
        item["truth_wall_ms"] = v.truth_wall_ms;
        item["standin_wall_ms"] = v.standin_wall_ms;
        views.push_back(item);
    }
    doc["views"] = views;

    // the seed-style tables
    json a2 = json::array();
    for (const auto& [size, group] : group_views(result, size_key))
        a2.push_back({{"width", size.first},
                      {"height", size.second},
                      {"views", group.size()},
                      {"luv_mean", mean_over(group, figures()[0].get)},
                      {"de2000_mean", mean_over(group, figures()[2].get)},
                      {"rgb_avg", mean_over(group, figures()[4].get)},
                      {"truth_ms", mean_over(group, [](const ViewResult& v) { return v.truth_ms; })},
                      {"standin_ms", mean_over(group, [](const ViewResult& v) { return v.standin_ms; })},
                      {"truth_wall_ms", mean_over(group, [](const ViewResult& v) { return v.truth_wall_ms; })},
                      {"standin_wall_ms", mean_over(group, [](const ViewResult& v) { return v.standin_wall_ms; })}});
    json saraiva = json::array();
    for (const auto& [key, group] : group_views(result, fov_distance_key))
        saraiva.push_back({{"fov", key.first},
                           {"distance", key.second},
                           {"views", group.size()},
                           {"rgb_total", mean_over(group, figures()[5].get)},
                           {"rgb_avg", mean_over(group, figures()[4].get)},
                           {"luv_mean", mean_over(group, figures()[0].get)}});
    doc["tables"] = {{"by_resolution", a2}, {"by_fov_distance", saraiva}};
    if (result.surface) {
        const SurfaceDistance& s = *result.surface;
        doc["surface"] = {{"samples", s.samples}, {"mean", s.mean}, {"max", s.max}, {"mean_rel", s.mean_rel},
                          {"max_rel", s.max_rel}};
    } else {
        doc["surface"] = nullptr;
    }
    return doc;
}

std::vector<std::pair<std::string, std::string>> eval_tables_csv(const EvalResult& result)
{
    std::vector<std::pair<std::string, std::string>> files;

    // views.csv: every view, every figure
    std::ostringstream views;
    views << "index,azimuth,elevation,distance,fov,width,height";
    for (const Figure& f : figures()) views << "," << f.name;
    views << ",truth_pixels,standin_pixels,hole_pixels,spill_pixels,rect_pixels,truth_ms,standin_ms\n";
    for (std::size_t i = 0; i < result.views.size(); ++i) {
        const ViewResult& v = result.views[i];
        views << i << "," << number(v.view.orbit.azimuth_degrees) << "," << number(v.view.orbit.elevation_degrees) << ","
              << number(v.view.orbit.distance_rel) << "," << number(v.view.orbit.fov_y_degrees) << "," << v.view.width
              << "," << v.view.height;
        for (const Figure& f : figures()) views << "," << number(f.get(v));
        views << "," << v.metrics.truth_pixels << "," << v.metrics.standin_pixels << "," << v.metrics.hole_pixels << ","
              << v.metrics.spill_pixels << "," << v.metrics.rect_pixels << "," << number(v.truth_ms) << ","
              << number(v.standin_ms) << "\n";
    }
    files.push_back({"views.csv", views.str()});

    // table_a2.csv (Vichitvejpaisal 2005 Table A-2: Luv difference per resolution) and frame_times.csv
    std::ostringstream a2, a1;
    a2 << "width,height,views,luv_mean,de2000_mean,rgb_avg\n";
    a1 << "width,height,views,truth_ms,standin_ms,truth_fps,standin_fps,truth_wall_ms,standin_wall_ms\n";
    for (const auto& [size, group] : group_views(result, size_key)) {
        a2 << size.first << "," << size.second << "," << group.size() << "," << number(mean_over(group, figures()[0].get))
           << "," << number(mean_over(group, figures()[2].get)) << "," << number(mean_over(group, figures()[4].get))
           << "\n";
        double tm = mean_over(group, [](const ViewResult& v) { return v.truth_ms; });
        double sm = mean_over(group, [](const ViewResult& v) { return v.standin_ms; });
        a1 << size.first << "," << size.second << "," << group.size() << "," << number(tm) << "," << number(sm) << ","
           << number(tm > 0 ? 1000.0 / tm : 0.0) << "," << number(sm > 0 ? 1000.0 / sm : 0.0) << ","
           << number(mean_over(group, [](const ViewResult& v) { return v.truth_wall_ms; })) << ","
           << number(mean_over(group, [](const ViewResult& v) { return v.standin_wall_ms; })) << "\n";
    }
    files.push_back({"table_a2.csv", a2.str()});
    files.push_back({"frame_times.csv", a1.str()});

    // table_saraiva.csv (Saraiva et al. Tables 1-3: error per relative distance, one block per fov)
    std::ostringstream s;
    s << "fov,distance,views,rgb_total,rgb_avg,luv_mean\n";
    for (const auto& [key, group] : group_views(result, fov_distance_key))
        s << number(key.first) << "," << number(key.second) << "," << group.size() << ","
          << number(mean_over(group, figures()[5].get)) << "," << number(mean_over(group, figures()[4].get)) << ","
          << number(mean_over(group, figures()[0].get)) << "\n";
    files.push_back({"table_saraiva.csv", s.str()});
    return files;
}

} // namespace standin
