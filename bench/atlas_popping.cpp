// Popping of view atlases: how much the image changes between camera views a small angle apart.
// The camera orbits the model in azimuth steps of --step degrees (default 0.5) at a fixed
// elevation; every consecutive pair of frames is compared with compare_images (rgb_avg: mean
// |dR|+|dG|+|dB| over the object rectangle, docs/EVAL.md). The same sweep of the ground-truth mesh
// gives the change the motion itself causes; a stand-in that pops shows larger steps (its p95 and
// max) where its view selection switches. Not a test: prints a Markdown table.
//   atlas_popping MODEL PACKAGE [--styles seed,corrected] [--elevation 20] [--start 0] [--span 30]
//                 [--step 0.5] [--distance 1] [--fov 40] [--size 256]
// Any package: --variant NAME=VALUE[,NAME=VALUE...] (repeatable) measures the package with those
// run-time options instead of the view atlas's --styles (e.g. microfacets: --variant views=1
// --variant views=3).
// "Error change" is the flicker the truth does not explain: per step, the mean over the pixels
// either subject covers in either frame of |(S_i - S_i-1) - (T_i - T_i-1)| summed over RGB, i.e.
// how much the stand-in's error image changes between frames (a steady error adds nothing; texture
// shimmer the mesh does not show, or the mesh's own point-sampled shimmer the stand-in lacks, does).
#include <standin/camera.h>
#include <standin/eval.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace standin;

struct Sweep {
    float elevation = 20.0f, start = 0.0f, span = 30.0f, step = 0.5f, distance = 1.0f, fov = 40.0f;
    int size = 256;
};

struct Changes {
    double mean = 0.0, p95 = 0.0, max = 0.0;
    double excess = 0.0;       // mean over steps of |change - truth's change at the same step|
    double error_change = 0.0; // mean over steps of the error image's change (above)
};

struct SweepFrames {
    std::vector<double> changes; // rgb_avg between consecutive frames
    std::vector<ImageRGBA8> frames;
};

// a covered pixel's colour, an empty one black (the frames are composited over black)
static int channel(const ImageRGBA8& image, std::size_t pixel, int c)
{
    return image.pixels[4 * pixel + 3] != 0 ? int(image.pixels[4 * pixel + std::size_t(c)]) : 0;
}

// mean over steps of |(S_i - S_i-1) - (T_i - T_i-1)| (RGB sum) over the pixels any of the four covers
static double error_change(const std::vector<ImageRGBA8>& standin, const std::vector<ImageRGBA8>& truth)
{
    double total = 0.0;
    for (std::size_t i = 1; i < standin.size(); ++i) {
        const ImageRGBA8 *s0 = &standin[i - 1], *s1 = &standin[i], *t0 = &truth[i - 1], *t1 = &truth[i];
        double sum = 0.0;
        std::size_t covered = 0;
        for (std::size_t p = 0; p < s1->pixels.size() / 4; ++p) {
            if (!(s0->pixels[4 * p + 3] | s1->pixels[4 * p + 3] | t0->pixels[4 * p + 3] | t1->pixels[4 * p + 3])) continue;
            ++covered;
            for (int c = 0; c < 3; ++c)
                sum += std::abs((channel(*s1, p, c) - channel(*s0, p, c)) - (channel(*t1, p, c) - channel(*t0, p, c)));
        }
        total += covered ? sum / double(covered) : 0.0;
    }
    return standin.size() > 1 ? total / double(standin.size() - 1) : 0.0;
}

// the frames of one renderer along the sweep and their frame-to-frame changes (rgb_avg)
static Result<SweepFrames> sweep_changes(Renderer& renderer, const BoundingSphere& sphere, const Sweep& s)
{
    SweepFrames sweep;
    std::vector<double>& changes = sweep.changes;
    ImageRGBA8 previous;
    int steps = int(std::lround(s.span / s.step));
    for (int i = 0; i <= steps; ++i) {
        OrbitView view;
        view.azimuth_degrees = s.start + float(i) * s.step;
        view.elevation_degrees = s.elevation;
        view.distance_rel = s.distance;
        view.fov_y_degrees = s.fov;
        Camera camera = orbit_camera(sphere, view, 1.0f);
        Result<RenderedImage> image = render_offscreen(renderer, camera, default_light(camera), s.size, s.size);
        if (!image) return image.status();
        if (i > 0) changes.push_back(compare_images(previous, image->color).rgb_avg);
        previous = image->color;
        sweep.frames.push_back(std::move(image->color));
    }
    return sweep;
}

static Changes summarise(std::vector<double> changes, const std::vector<double>& truth)
{
    Changes c;
    for (std::size_t i = 0; i < changes.size(); ++i) {
        c.mean += changes[i] / double(changes.size());
        c.excess += std::abs(changes[i] - truth[i]) / double(changes.size());
    }
    std::sort(changes.begin(), changes.end());
    c.max = changes.back();
    c.p95 = changes[std::min(changes.size() - 1, std::size_t(0.95 * double(changes.size())))];
    return c;
}

int main(int argc, char** argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: atlas_popping MODEL PACKAGE [--styles a,b | --variant NAME=VALUE,...] [--elevation E] "
                             "[--start A] [--span S] [--step D] [--distance R] [--fov F] [--size N]\n");
        return 2;
    }
    std::string model = argv[1], package_path = argv[2];
    std::vector<std::string> styles = {"seed", "corrected"};
    std::vector<std::string> variants; // NAME=VALUE[,NAME=VALUE...] each
    Sweep s;
    for (int i = 3; i + 1 < argc; i += 2) {
        std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--styles") {
            styles.clear();
            std::stringstream list(value);
            for (std::string item; std::getline(list, item, ',');) styles.push_back(item);
        } else if (flag == "--variant") variants.push_back(value);
        else if (flag == "--elevation") s.elevation = std::stof(value);
        else if (flag == "--start") s.start = std::stof(value);
        else if (flag == "--span") s.span = std::stof(value);
        else if (flag == "--step") s.step = std::stof(value);
        else if (flag == "--distance") s.distance = std::stof(value);
        else if (flag == "--fov") s.fov = std::stof(value);
        else if (flag == "--size") s.size = std::atoi(value.c_str());
        else {
            std::fprintf(stderr, "atlas_popping: unknown option %s\n", flag.c_str());
            return 2;
        }
    }
    if (!(s.step > 0.0f) || !(s.span >= s.step) || s.size < 16) {
        std::fprintf(stderr, "atlas_popping: need --step > 0, --span >= --step, --size >= 16\n");
        return 2;
    }

    Result<Mesh> mesh = import_mesh(model);
    if (!mesh) return std::fprintf(stderr, "%s\n", mesh.status().message().c_str()), 1;
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return std::fprintf(stderr, "%s\n", context.status().message().c_str()), 1;
    Result<std::unique_ptr<Package>> package = read_package(package_path);
    if (!package) return std::fprintf(stderr, "%s\n", package.status().message().c_str()), 1;
    BoundingSphere sphere = mesh->bounding_sphere();

    // the ground truth's own frame-to-frame change
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return std::fprintf(stderr, "%s\n", truth.status().message().c_str()), 1;
    Result<SweepFrames> truth_sweep = sweep_changes(**truth, sphere, s);
    if (!truth_sweep) return std::fprintf(stderr, "%s\n", truth_sweep.status().message().c_str()), 1;
    const std::vector<double>& truth_changes = truth_sweep->changes;

    std::printf("device: %s\n", (*context)->device_name().c_str());
    std::printf("sweep: azimuth %g..%g in %g deg steps, elevation %g, distance %g, fov %g, %dx%d; package %s\n\n",
                double(s.start), double(s.start + s.span), double(s.step), double(s.elevation), double(s.distance),
                double(s.fov), s.size, s.size, package_path.c_str());
    std::printf("| subject | mean change | p95 | max | mean excess over truth | error change |\n|---|---|---|---|---|---|\n");
    Changes t = summarise(truth_changes, truth_changes);
    std::printf("| ground truth | %.2f | %.2f | %.2f | - | - |\n", t.mean, t.p95, t.max);
    if (variants.empty())
        for (const std::string& style : styles) variants.push_back("style=" + style);
    for (const std::string& variant : variants) {
        RenderOptions options;
        std::stringstream list(variant);
        for (std::string item; std::getline(list, item, ',');) {
            std::size_t equals = item.find('=');
            if (equals == std::string::npos) return std::fprintf(stderr, "atlas_popping: --variant %s: NAME=VALUE\n", item.c_str()), 2;
            options.values.set(item.substr(0, equals), item.substr(equals + 1));
        }
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(**package, options);
        if (!renderer) return std::fprintf(stderr, "%s\n", renderer.status().message().c_str()), 1;
        Result<SweepFrames> sweep = sweep_changes(**renderer, sphere, s);
        if (!sweep) return std::fprintf(stderr, "%s\n", sweep.status().message().c_str()), 1;
        Changes c = summarise(sweep->changes, truth_changes);
        c.error_change = error_change(sweep->frames, truth_sweep->frames);
        std::string name = variant.rfind("style=", 0) == 0 ? variant.substr(6) : variant;
        std::printf("| %s | %.2f | %.2f | %.2f | %.2f | %.2f |\n", name.c_str(), c.mean, c.p95, c.max, c.excess,
                    c.error_change);
    }
    return 0;
}
