// Popping of view atlases: how much the image changes between camera views a small angle apart.
// The camera orbits the model in azimuth steps of --step degrees (default 0.5) at a fixed
// elevation; every consecutive pair of frames is compared with compare_images (rgb_avg: mean
// |dR|+|dG|+|dB| over the object rectangle, docs/EVAL.md). The same sweep of the ground-truth mesh
// gives the change the motion itself causes; a stand-in that pops shows larger steps (its p95 and
// max) where its view selection switches. Not a test: prints a Markdown table.
//   atlas_popping MODEL PACKAGE [--styles seed,corrected] [--elevation 20] [--start 0] [--span 30]
//                 [--step 0.5] [--distance 1] [--fov 40] [--size 256]
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
    double excess = 0.0; // mean over steps of |change - truth's change at the same step|
};

// the frame-to-frame changes (rgb_avg) of one renderer along the sweep
static Result<std::vector<double>> sweep_changes(Renderer& renderer, const BoundingSphere& sphere, const Sweep& s)
{
    std::vector<double> changes;
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
        previous = std::move(image->color);
    }
    return changes;
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
        std::fprintf(stderr, "usage: atlas_popping MODEL PACKAGE [--styles a,b] [--elevation E] [--start A] [--span S] "
                             "[--step D] [--distance R] [--fov F] [--size N]\n");
        return 2;
    }
    std::string model = argv[1], package_path = argv[2];
    std::vector<std::string> styles = {"seed", "corrected"};
    Sweep s;
    for (int i = 3; i + 1 < argc; i += 2) {
        std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--styles") {
            styles.clear();
            std::stringstream list(value);
            for (std::string item; std::getline(list, item, ',');) styles.push_back(item);
        } else if (flag == "--elevation") s.elevation = std::stof(value);
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
    const Representation* representation = find_representation((*package)->representation());
    BoundingSphere sphere = mesh->bounding_sphere();

    // the ground truth's own frame-to-frame change
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return std::fprintf(stderr, "%s\n", truth.status().message().c_str()), 1;
    Result<std::vector<double>> truth_changes = sweep_changes(**truth, sphere, s);
    if (!truth_changes) return std::fprintf(stderr, "%s\n", truth_changes.status().message().c_str()), 1;

    std::printf("device: %s\n", (*context)->device_name().c_str());
    std::printf("sweep: azimuth %g..%g in %g deg steps, elevation %g, distance %g, fov %g, %dx%d; package %s\n\n",
                double(s.start), double(s.start + s.span), double(s.step), double(s.elevation), double(s.distance),
                double(s.fov), s.size, s.size, package_path.c_str());
    std::printf("| subject | mean change | p95 | max | mean excess over truth |\n|---|---|---|---|---|\n");
    Changes t = summarise(*truth_changes, *truth_changes);
    std::printf("| ground truth | %.2f | %.2f | %.2f | - |\n", t.mean, t.p95, t.max);
    for (const std::string& style : styles) {
        RenderOptions options;
        options.values.set("style", style);
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(**package, options);
        if (!renderer) return std::fprintf(stderr, "%s\n", renderer.status().message().c_str()), 1;
        Result<std::vector<double>> changes = sweep_changes(**renderer, sphere, s);
        if (!changes) return std::fprintf(stderr, "%s\n", changes.status().message().c_str()), 1;
        Changes c = summarise(*changes, *truth_changes);
        std::printf("| %s | %.2f | %.2f | %.2f | %.2f |\n", style.c_str(), c.mean, c.p95, c.max, c.excess);
    }
    return 0;
}
