// What an engine does with standin, through the public API only: import a model, bake a stand-in
// of every registered representation (with its declared defaults), and draw each next to the mesh
// in a headless OpenGL context, reporting how alike they look.
//   embed MODEL OUTPUT_DIR
#include <standin/eval.h>
#include <standin/image.h>
#include <standin/mesh.h>
#include <standin/package.h>
#include <standin/render.h>

#include <cstdio>
#include <string>

using namespace standin;

static int fail(const Status& status)
{
    std::fprintf(stderr, "embed: %s\n", status.message().c_str());
    return 2;
}

int main(int argc, char** argv)
{
    if (argc != 3) {
        std::fprintf(stderr, "usage: embed MODEL OUTPUT_DIR\n");
        return 2;
    }
    const std::string model = argv[1], output = argv[2];
    Result<Mesh> mesh = import_mesh(model);
    if (!mesh) return fail(mesh.status());
    Result<SourceInfo> source = describe_source(model, *mesh);
    if (!source) return fail(source.status());
    Result<std::unique_ptr<GpuContext>> context = create_headless_context();
    if (!context) return fail(context.status());

    OrbitView view;
    view.azimuth_degrees = 30.0f;
    Camera camera = orbit_camera(mesh->bounding_sphere(), view, 4.0f / 3.0f);
    Light light = default_light(camera);
    Result<std::unique_ptr<Renderer>> truth = make_mesh_renderer(*mesh);
    if (!truth) return fail(truth.status());
    Result<RenderedImage> truth_image = render_offscreen(**truth, camera, light, 320, 240);
    if (!truth_image) return fail(truth_image.status());

    for (const Representation& representation : representations()) {
        Result<std::unique_ptr<Package>> package = bake_package(representation, *mesh, *source, OptionValues{});
        if (!package) return fail(package.status());
        Result<std::unique_ptr<Renderer>> renderer = make_package_renderer(**package, RenderOptions{});
        if (!renderer) return fail(renderer.status());
        Result<RenderedImage> image = render_offscreen(**renderer, camera, light, 320, 240);
        if (!image) return fail(image.status());
        std::string path = output + "/" + representation.name + ".png";
        if (Status s = write_png(image->color, path); !s) return fail(s);
        ImageMetrics m = compare_images(truth_image->color, image->color);
        std::printf("%s: %s; IoU %.3f, Luv %.2f against the mesh -> %s\n", representation.name.c_str(),
                    summarise_package(**package).headline.c_str(), m.iou, m.luv_mean, path.c_str());
        if (m.iou < 0.9) return fail(error(StatusCode::bad_data, representation.name + ": the stand-in does not match the mesh"));
    }
    return 0;
}
