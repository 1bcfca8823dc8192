// Popping of level-of-detail switches along a dolly (issue #14): the camera moves away from the
// model from --near-distance to --far-distance (distance_rel, geometric steps, --frames frames) and
// every consecutive pair of frames is compared with compare_images (rgb_avg: mean |dR|+|dG|+|dB|
// over the object rectangle, as bench/atlas_popping). Each pair FROM:TO (the mesh or a package) is
// measured twice: a hard switch (CrossFade at amount 0 before the middle of --band, 1 from it on)
// and the screen-door cross-fade over the band (transition_amount, 1/64 of the pixels per step of
// coverage; CrossFade in render.h). The mesh alone gives the change the motion itself causes. Along
// a dolly the motion changes every pixel a little each frame, which hides a switch in the plain
// change, so the table also gives the change of the error image: per pixel
// |(S_i - S_i-1) - (M_i - M_i-1)|, S the subject's frame and M the mesh's at the same camera,
// |dR|+|dG|+|dB| averaged over the rectangle holding all four images' coverage. It is 0 for the
// mesh itself, small for a stand-in whose error drifts smoothly, and a switch shows as one large
// step (its max): the pop.
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

// |(s - s0) - (m - m0)| summed over RGB, averaged over the rectangle covered by any of the four
static double error_change(const ImageRGBA8& s0, const ImageRGBA8& s, const ImageRGBA8& m0, const ImageRGBA8& m)
{
    int x0 = s.width, y0 = s.height, x1 = -1, y1 = -1;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x)
            if (s0.at(x, y)[3] || s.at(x, y)[3] || m0.at(x, y)[3] || m.at(x, y)[3]) {
                x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
            }
    if (x1 < 0) return 0.0;
    double sum = 0.0;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x)
            for (int c = 0; c < 3; ++c)
                sum += std::abs((int(s.at(x, y)[c]) - int(s0.at(x, y)[c])) - (int(m.at(x, y)[c]) - int(m0.at(x, y)[c])));
    return sum / (double(x1 - x0 + 1) * double(y1 - y0 + 1));
}

struct Sweep {
    std::vector<double> changes;       // rgb_avg between consecutive frames
    std::vector<double> error_changes; // error_change against the mesh's frames (empty for the mesh)
    std::vector<ImageRGBA8> frames;    // the mesh's only
};

// one subject along the dolly; `at` is told each distance; `mesh` (null for the mesh itself) gives
// the mesh's frames for the error change
template <typename SetDistance>
static Result<Sweep> dolly(Renderer& renderer, const BoundingSphere& sphere, const Dolly& d, SetDistance at,
                           const Sweep* mesh)
{
    Sweep sweep;
    std::vector<double>& changes = sweep.changes;
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
        if (i > 0 && mesh)
            sweep.error_changes.push_back(error_change(previous, image->color, mesh->frames[std::size_t(i - 1)],
                                                       mesh->frames[std::size_t(i)]));
        if (!mesh) sweep.frames.push_back(image->color);
        previous = std::move(image->color);
    }
    return sweep;
}

struct Stats {
    double mean = 0.0, p95 = 0.0, max = 0.0;
};

static Stats summarise(std::vector<double> values)
{
    Stats c;
    if (values.empty()) return c;
    for (double v : values) c.mean += v / double(values.size());
    std::sort(values.begin(), values.end());
    c.max = values.back();
    c.p95 = values[std::min(values.size() - 1, std::size_t(0.95 * double(values.size())))];
    return c;
}

static void print_row(const std::string& subject, const std::string& mode, const Sweep& sweep)
{
    Stats c = summarise(sweep.changes), e = summarise(sweep.error_changes);
    if (sweep.error_changes.empty())
        std::printf("| %s | %s | %.2f | %.2f | - | - | - |\n", subject.c_str(), mode.c_str(), c.mean, c.max);
    else
        std::printf("| %s | %s | %.2f | %.2f | %.3f | %.3f | %.3f |\n", subject.c_str(), mode.c_str(), c.mean, c.max, e.mean,
                    e.p95, e.max);
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
    Result<std::unique_ptr<Renderer>> mesh_renderer = make_mesh_renderer(*mesh);
    if (!mesh_renderer) return fail(mesh_renderer.status());
    renderers["mesh"] = std::move(*mesh_renderer);
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
    Result<Sweep> truth = dolly(*renderers["mesh"], sphere, d, nothing, nullptr);
    if (!truth) return fail(truth.status());
    float middle = 0.5f * (d.band_near + d.band_far);
    int band_steps = 0;
    for (int i = 0; i < d.frames; ++i) band_steps += d.distance(i) > d.band_near && d.distance(i) < d.band_far ? 1 : 0;

    std::printf("device: %s\n", (*context)->device_name().c_str());
    std::printf("dolly: distance %g..%g in %d frames (x%.4f per frame), azimuth %g, elevation %g, %dx%d; band %g..%g "
                "(%d frames inside), hard switch at %g\n\n",
                double(d.near_distance), double(d.far_distance), d.frames,
                double(std::pow(d.far_distance / d.near_distance, 1.0f / float(d.frames - 1))), double(d.azimuth),
                double(d.elevation), d.size, d.size, double(d.band_near), double(d.band_far), band_steps, double(middle));
    std::printf("| transition | switch | mean change | max change | error change: mean | p95 | max (the pop) |\n"
                "|---|---|---|---|---|---|---|\n");
    print_row("mesh alone", "-", *truth);
    std::map<std::string, bool> alone_done;
    for (const auto& [a, b] : pairs) {
        for (const std::string& name : {a, b}) {
            if (name == "mesh" || alone_done[name]) continue;
            alone_done[name] = true;
            Result<Sweep> alone = dolly(*renderers[name], sphere, d, nothing, &*truth);
            if (!alone) return fail(alone.status());
            print_row(name + " alone", "-", *alone);
        }
        for (bool dithered : {false, true}) {
            DistanceFade fade(*renderers[a], *renderers[b], dithered ? d.band_near : middle, dithered ? d.band_far : middle);
            Result<Sweep> sweep = dolly(fade, sphere, d, [&](float distance) { fade.set_distance(distance); }, &*truth);
            if (!sweep) return fail(sweep.status());
            char mode[64];
            if (dithered) std::snprintf(mode, sizeof mode, "dithered %g..%g", double(d.band_near), double(d.band_far));
            else std::snprintf(mode, sizeof mode, "hard at %g", double(middle));
            print_row(a + " -> " + b, mode, *sweep);
        }
        std::fflush(stdout);
    }
    return 0;
}
