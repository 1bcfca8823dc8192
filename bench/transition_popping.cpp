// Popping of level-of-detail switches along a dolly (issue #14): the camera moves away from the
// model from --near-distance to --far-distance (distance_rel, geometric steps, --frames frames) and
// every consecutive pair of frames is compared with compare_images (rgb_avg: mean |dR|+|dG|+|dB|
// over the object rectangle, as bench/atlas_popping). Each pair FROM:TO (the mesh or a package) is
// measured twice: a hard switch (CrossFade at amount 0 before the middle of --band, 1 from it on)
// and the screen-door cross-fade over the band (transition_amount, 1/64 of the pixels per step of
// coverage; CrossFade in render.h). The mesh alone gives the change the motion itself causes;
// popping is the excess over it: its largest single step (max excess) and its mean.
// Not a test: prints a Markdown table.
//   transition_popping MODEL [--package NAME=DIR]... [--pair FROM:TO]... [--band NEAR:FAR]
//                      [--near-distance 1] [--far-distance 4] [--frames 61] [--size 256]
//                      [--azimuth 30] [--elevation 15]
// FROM and TO are `mesh` or a package NAME; without --pair: mesh:NAME for every package, then
// each package to the next.
#include <standin/camera.h>
#include <standin/eval.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

using namespace standin;

struct Dolly {
    float near_distance = 1.0f, far_distance = 4.0f, azimuth = 30.0f, elevation = 15.0f;
    int frames = 61, size = 256;
    float band_near = 1.8f, band_far = 2.6f;

    float distance(int i) const
    {
        return near_distance * std::pow(far_distance / near_distance, float(i) / float(frames - 1));
    }
};

// Draws a cross-fade whose amount follows the camera's distance (in distance_rel) over a band.
class DistanceFade final : public Renderer {
public:
    DistanceFade(Renderer& from, Renderer& to, float near, float far) : fade_(from, to), near_(near), far_(far) {}
    void set_distance(float d) { fade_.set_amount(transition_amount(d, near_, far_)); }
    DrawStats draw(const DrawParams& params) override { return fade_.draw(params); }

private:
    CrossFade fade_;
    float near_, far_;
};

// the frame-to-frame changes (rgb_avg) of one subject along the dolly; `at` is told each distance
template <typename SetDistance>
static Result<std::vector<double>> dolly_changes(Renderer& renderer, const BoundingSphere& sphere, const Dolly& d,
                                                 SetDistance at)
{
    std::vector<double> changes;
    ImageRGBA8 previous;
    for (int i = 0; i < d.frames; ++i) {
        OrbitView view;
        view.azimuth_degrees = d.azimuth;
        view.elevation_degrees = d.elevation;
        view.distance_rel = d.distance(i);
        at(view.distance_rel);
        Camera camera = orbit_camera(sphere, view, 1.0f);
        Result<RenderedImage> image = render_offscreen(renderer, camera, default_light(camera), d.size, d.size);
        if (!image) return image.status();
        if (i > 0) changes.push_back(compare_images(previous, image->color).rgb_avg);
        previous = std::move(image->color);
    }
    return changes;
}

struct Changes {
    double mean = 0.0, p95 = 0.0, max = 0.0;
    double max_excess = 0.0, mean_excess = 0.0; // change - the mesh's change at the same step
};

static Changes summarise(std::vector<double> changes, const std::vector<double>& truth)
{
    Changes c;
    for (std::size_t i = 0; i < changes.size(); ++i) {
        c.mean += changes[i] / double(changes.size());
        double excess = changes[i] - truth[i];
        c.mean_excess += std::abs(excess) / double(changes.size());
        c.max_excess = std::max(c.max_excess, excess);
    }
    std::sort(changes.begin(), changes.end());
    c.max = changes.back();
    c.p95 = changes[std::min(changes.size() - 1, std::size_t(0.95 * double(changes.size())))];
    return c;
}

static bool parse_pair(const std::string& text, std::string& a, std::string& b, char separator = ':')
{
    std::size_t at = text.find(separator);
    if (at == std::string::npos || at == 0 || at + 1 == text.size()) return false;
    a = text.substr(0, at);
    b = text.substr(at + 1);
    return true;
}

static int fail(const Status& status) { return std::fprintf(stderr, "transition_popping: %s\n", status.message().c_str()), 1; }

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: transition_popping MODEL [--package NAME=DIR]... [--pair FROM:TO]... [--band NEAR:FAR] "
                             "[--near-distance D] [--far-distance D] [--frames N] [--size N] [--azimuth A] [--elevation E]\n");
        return 2;
    }
    Dolly d;
    std::vector<std::pair<std::string, std::string>> packages, pairs;
    for (int i = 2; i + 1 < argc; i += 2) {
        std::string flag = argv[i], value = argv[i + 1], a, b;
        bool ok = true;
        if (flag == "--package") {
            ok = parse_pair(value, a, b, '=');
            packages.push_back({a, b});
        } else if (flag == "--pair") {
            ok = parse_pair(value, a, b);
            pairs.push_back({a, b});
        } else if (flag == "--band") {
            ok = parse_pair(value, a, b);
            if (ok) d.band_near = std::stof(a), d.band_far = std::stof(b);
        } else if (flag == "--near-distance") d.near_distance = std::stof(value);
        else if (flag == "--far-distance") d.far_distance = std::stof(value);
        else if (flag == "--frames") d.frames = std::atoi(value.c_str());
        else if (flag == "--size") d.size = std::atoi(value.c_str());
        else if (flag == "--azimuth") d.azimuth = std::stof(value);
        else if (flag == "--elevation") d.elevation = std::stof(value);
        else ok = false;
        if (!ok) return std::fprintf(stderr, "transition_popping: bad option %s %s\n", flag.c_str(), value.c_str()), 2;
    }
    if (d.frames < 3 || d.size < 16 || !(d.near_distance > 0.0f) || !(d.far_distance > d.near_distance) ||
        !(d.band_far >= d.band_near))
        return std::fprintf(stderr, "transition_popping: need --frames >= 3, --size >= 16, 0 < near < far distance, band near <= far\n"), 2;
    if (pairs.empty()) {
        for (const auto& p : packages) pairs.push_back({"mesh", p.first});
        for (std::size_t k = 0; k + 1 < packages.size(); ++k) pairs.push_back({packages[k].first, packages[k + 1].first});
    }

    Result<Mesh> mesh = import_mesh(argv[1]);
    if (!mesh) return fail(mesh.status());
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());
    BoundingSphere sphere = mesh->bounding_sphere();
    std::map<std::string, std::unique_ptr<Package>> loaded;
    std::map<std::string, std::unique_ptr<Renderer>> renderers;
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return fail(truth.status());
    renderers["mesh"] = std::move(*truth);
    for (const auto& [name, path] : packages) {
        Result<std::unique_ptr<Package>> package = read_package(path);
        if (!package) return fail(package.status());
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(**package, {});
        if (!renderer) return fail(renderer.status());
        loaded[name] = std::move(*package);
        renderers[name] = std::move(*renderer);
    }
    for (const auto& [a, b] : pairs)
        for (const std::string& name : {a, b})
            if (!renderers.count(name)) return std::fprintf(stderr, "transition_popping: --pair names %s, not mesh or a --package\n", name.c_str()), 2;

    auto nothing = [](float) {};
    Result<std::vector<double>> truth_changes = dolly_changes(*renderers["mesh"], sphere, d, nothing);
    if (!truth_changes) return fail(truth_changes.status());
    float middle = 0.5f * (d.band_near + d.band_far);
    int band_steps = 0;
    for (int i = 0; i < d.frames; ++i) band_steps += d.distance(i) > d.band_near && d.distance(i) < d.band_far ? 1 : 0;

    std::printf("device: %s\n", (*context)->device_name().c_str());
    std::printf("dolly: distance %g..%g in %d frames (x%.4f per frame), azimuth %g, elevation %g, %dx%d; band %g..%g "
                "(%d frames inside), hard switch at %g\n\n",
                double(d.near_distance), double(d.far_distance), d.frames,
                double(std::pow(d.far_distance / d.near_distance, 1.0f / float(d.frames - 1))), double(d.azimuth),
                double(d.elevation), d.size, d.size, double(d.band_near), double(d.band_far), band_steps, double(middle));
    std::printf("| transition | switch | mean change | p95 | max | max excess over mesh | mean excess |\n|---|---|---|---|---|---|---|\n");
    Changes t = summarise(*truth_changes, *truth_changes);
    std::printf("| mesh alone | - | %.2f | %.2f | %.2f | - | - |\n", t.mean, t.p95, t.max);
    std::map<std::string, bool> alone_done;
    for (const auto& [a, b] : pairs) {
        for (const std::string& name : {a, b}) {
            if (name == "mesh" || alone_done[name]) continue;
            alone_done[name] = true;
            Result<std::vector<double>> changes = dolly_changes(*renderers[name], sphere, d, nothing);
            if (!changes) return fail(changes.status());
            Changes c = summarise(*changes, *truth_changes);
            std::printf("| %s alone | - | %.2f | %.2f | %.2f | %.2f | %.2f |\n", name.c_str(), c.mean, c.p95, c.max,
                        c.max_excess, c.mean_excess);
        }
        for (bool dithered : {false, true}) {
            DistanceFade fade(*renderers[a], *renderers[b], dithered ? d.band_near : middle, dithered ? d.band_far : middle);
            Result<std::vector<double>> changes = dolly_changes(fade, sphere, d, [&](float distance) { fade.set_distance(distance); });
            if (!changes) return fail(changes.status());
            Changes c = summarise(*changes, *truth_changes);
            char mode[64];
            if (dithered) std::snprintf(mode, sizeof mode, "dithered %g..%g", double(d.band_near), double(d.band_far));
            else std::snprintf(mode, sizeof mode, "hard at %g", double(middle));
            std::printf("| %s -> %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n", a.c_str(), b.c_str(), mode, c.mean, c.p95,
                        c.max, c.max_excess, c.mean_excess);
        }
        std::fflush(stdout);
    }
    return 0;
}
