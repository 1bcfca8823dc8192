// The error of microfacets against the angle to the nearest captured view, for several voxel sizes
// (Yamazaki et al. 2002 §4.1, eq. 2: two facets l apart along a view's ray show its texel e = l tan
// delta apart when seen delta away from it). The model is rendered orthographically from azimuths
// base + delta around a captured view (a turntable package: --layout circle) at each fixed octree
// level, and compared with the mesh (compare_images: rgb_avg over the object rectangle, Luv, IoU).
// The prediction W tan(delta) in pixels of the screen is printed beside each row. Not a test:
// prints a Markdown table.
//   microfacets_parallax MODEL PACKAGE [--levels 5,6,7] [--deltas 0,1,2,3,4,5] [--azimuth 0]
//                        [--elevation 0] [--size 256] [--variant NAME=VALUE,...]
// --variant sets the renderer's other options (default: the paper's texturing, views=1,clip=seed,
// coverage=any, so that the error is eq. 2's alone; --variant '' measures the defaults).
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

static std::vector<float> numbers(const std::string& list)
{
    std::vector<float> out;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');) out.push_back(std::stof(item));
    return out;
}

int main(int argc, char** argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: microfacets_parallax MODEL PACKAGE [--levels 5,6,7] [--deltas 0,1,2,3,4,5] "
                             "[--azimuth A] [--elevation E] [--size N] [--variant NAME=VALUE,...]\n");
        return 2;
    }
    std::string model = argv[1], package_path = argv[2];
    std::vector<float> levels = {5, 6, 7}, deltas = {0, 1, 2, 3, 4, 5};
    float azimuth = 0.0f, elevation = 0.0f;
    int size = 256;
    std::string variant = "views=1,clip=seed,coverage=any";
    for (int i = 3; i + 1 < argc; i += 2) {
        std::string flag = argv[i], value = argv[i + 1];
        if (flag == "--levels") levels = numbers(value);
        else if (flag == "--deltas") deltas = numbers(value);
        else if (flag == "--azimuth") azimuth = std::stof(value);
        else if (flag == "--elevation") elevation = std::stof(value);
        else if (flag == "--size") size = std::atoi(value.c_str());
        else if (flag == "--variant") variant = value;
        else return std::fprintf(stderr, "microfacets_parallax: unknown option %s\n", flag.c_str()), 2;
    }

    Result<Mesh> mesh = import_mesh(model);
    if (!mesh) return std::fprintf(stderr, "%s\n", mesh.status().message().c_str()), 1;
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return std::fprintf(stderr, "%s\n", context.status().message().c_str()), 1;
    Result<std::unique_ptr<Package>> package = read_package(package_path);
    if (!package) return std::fprintf(stderr, "%s\n", package.status().message().c_str()), 1;
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return std::fprintf(stderr, "%s\n", truth.status().message().c_str()), 1;
    BoundingSphere sphere = mesh->bounding_sphere();
    // the voxel grid's side (microfacets: the largest extent of the box, 1e-4 wider)
    glm::vec3 extent = mesh->bounds().extent();
    float grid = std::max({extent.x, extent.y, extent.z}) * (1.0f + 1e-4f);

    std::printf("device: %s\npackage %s, orthographic %dx%d, azimuth %g + delta, elevation %g, options '%s'\n\n",
                (*context)->device_name().c_str(), package_path.c_str(), size, size, double(azimuth), double(elevation),
                variant.c_str());
    std::printf("| level | W (px) | delta (deg) | W tan(delta) (px) | rgb_avg | Luv | IoU | holes | spill |\n"
                "|---|---|---|---|---|---|---|---|---|\n");
    for (float level : levels) {
        RenderOptions options;
        std::stringstream list(variant);
        for (std::string item; std::getline(list, item, ',');) {
            std::size_t equals = item.find('=');
            if (equals != std::string::npos) options.values.set(item.substr(0, equals), item.substr(equals + 1));
        }
        options.values.set("level", std::to_string(int(level)));
        Result<std::unique_ptr<Renderer>> standin = make_package_renderer(**package, options);
        if (!standin) return std::fprintf(stderr, "%s\n", standin.status().message().c_str()), 1;
        for (float delta : deltas) {
            OrbitView view;
            view.azimuth_degrees = azimuth + delta;
            view.elevation_degrees = elevation;
            view.orthographic = true;
            Camera camera = orbit_camera(sphere, view, 1.0f);
            Result<RenderedImage> t = render_offscreen(**truth, camera, default_light(camera), size, size);
            Result<RenderedImage> s = render_offscreen(**standin, camera, default_light(camera), size, size);
            if (!t || !s) return std::fprintf(stderr, "render failed\n"), 1;
            ImageMetrics m = compare_images(t->color, s->color);
            float w_pixels = grid / float(1 << int(level)) * float(size) / (2.0f * sphere.radius); // ortho: 2r spans the image
            std::printf("| %d | %.2f | %g | %.3f | %.2f | %.2f | %.4f | %.4f | %.4f |\n", int(level), double(w_pixels),
                        double(delta), double(w_pixels * std::tan(glm::radians(delta))), m.rgb_avg, m.luv_mean, m.iou,
                        m.hole_fraction, m.spill_fraction);
        }
    }
    return 0;
}
