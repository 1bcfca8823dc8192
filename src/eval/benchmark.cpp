// Frame-time benchmarks of a stand-in against its original mesh: the seed's three resolutions
// (Vichitvejpaisal 2005 appendix A, Table A-1, with and without the coarse mesh), frame
// time vs. screen coverage, and a crowd of instances on a ground grid (the case stand-ins exist
// for; Saraiva et al. §6 Table 4 compares billboard and triangle frame rates the same way).
// Differences from the papers: GPU timer queries, median of many frames, instead of FRAPS.
#include <standin/eval.h>

#include "gpu/frame_timing.h"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <fstream>
#include <string>

namespace standin {

CrowdScene make_crowd(const BoundingSphere& sphere, const Bounds& bounds, std::size_t instances, float aspect)
{
    // a square grid, rows receding from the camera along -z, centred on x = 0
    CrowdScene scene;
    const std::size_t side = std::max<std::size_t>(1, std::size_t(std::ceil(std::sqrt(double(instances)))));
    const float spacing = 2.5f * sphere.radius;
    const glm::vec3 foot(bounds.center().x, bounds.min.y, bounds.center().z);
    for (std::size_t i = 0; i < instances; ++i) {
        float column = float(i % side) - 0.5f * float(side - 1);
        float row = float(i / side);
        glm::vec3 at(column * spacing, 0.0f, -row * spacing);
        scene.world_from_object.push_back(glm::translate(glm::mat4(1.0f), at - foot));
    }

    // eye at the model's height, one spacing and a half in front of the first row, looking
    // across the grid at a point a third of the way in at half the model's height
    const float height = std::max(bounds.extent().y, 1e-6f);
    const float depth = float(side - 1) * spacing;
    glm::vec3 eye(0.0f, height, 1.5f * spacing + sphere.radius);
    glm::vec3 target(0.0f, 0.5f * height, -depth / 3.0f);
    float far_plane = glm::length(glm::vec2(0.5f * depth, depth)) + eye.z + 4.0f * sphere.radius;
    scene.camera = look_at_camera(eye, target, {0, 1, 0}, 60.0f, aspect, 0.05f * sphere.radius, far_plane);
    scene.light = default_light(scene.camera);
    return scene;
}

static Result<FrameRecord> time_subject(Renderer& renderer, const std::string& subject, const std::string& scene_name,
                                        const DrawParams& params, int warmup, int frames)
{
    Result<gpu::FrameTimes> times = gpu::time_frames(renderer, params, warmup, frames);
    if (!times) return times.status();
    FrameRecord record;
    record.width = params.viewport.x;
    record.height = params.viewport.y;
    record.subject = subject;
    record.scene = scene_name;
    record.instances = params.world_from_object.empty() ? 1 : params.world_from_object.size();
    record.ms_median = times->median_ms;
    record.ms_min = times->min_ms;
    record.ms_max = times->max_ms;
    record.wall_ms_median = times->wall_median_ms;
    record.cpu_ms_median = times->cpu_median_ms;
    record.covered_pixels = times->covered_pixels;
    record.fetches_per_pixel = times->fetches_per_pixel;
    record.fragments_per_pixel = times->fragments_per_pixel;
    record.primitives = times->stats.primitives;
    return record;
}

Result<std::vector<FrameRecord>> benchmark_frames(const BenchSubjects& subjects, const Mesh& mesh,
                                                  const BenchOptions& options, const Progress& progress)
{
    std::vector<std::pair<std::string, Renderer*>> list;
    if (subjects.package) list.push_back({"package", subjects.package});
    for (const auto& variant : subjects.package_variants)
        if (variant.second) list.push_back(variant);
    if (subjects.mesh) list.push_back({"mesh", subjects.mesh});
    const BoundingSphere sphere = mesh.bounding_sphere();
    const std::size_t steps =
        list.size() * (options.resolutions.size() + options.coverage_distances.size() + options.crowd_counts.size());
    std::size_t step = 0;
    std::vector<FrameRecord> records;
    auto orbit_params = [&](glm::ivec2 size, float distance_rel) {
        OrbitView view;
        view.azimuth_degrees = 30.0f;
        view.elevation_degrees = 20.0f;
        view.distance_rel = distance_rel;
        DrawParams params;
        params.camera = orbit_camera(sphere, view, float(size.x) / float(size.y));
        params.light = default_light(params.camera);
        params.viewport = size;
        return params;
    };

    // the seed's resolutions (Table A-1), one model filling the view
    for (glm::ivec2 size : options.resolutions)
        for (auto& [name, renderer] : list) {
            progress.report("bench", double(step++) / double(std::max<std::size_t>(steps, 1)));
            Result<FrameRecord> r = time_subject(*renderer, name, "orbit", orbit_params(size, 1.0f),
                                                 options.warmup_frames, options.frames);
            if (!r) return r.status();
            records.push_back(*r);
        }

    // frame time vs. screen coverage: the same model further away
    for (float distance : options.coverage_distances)
        for (auto& [name, renderer] : list) {
            progress.report("bench", double(step++) / double(std::max<std::size_t>(steps, 1)));
            Result<FrameRecord> r = time_subject(*renderer, name, "coverage", orbit_params(options.crowd_resolution, distance),
                                                 options.warmup_frames, options.frames);
            if (!r) return r.status();
            r->distance_rel = distance;
            records.push_back(*r);
        }

    // the crowd: N instances on a ground grid, same camera for every subject
    for (std::size_t count : options.crowd_counts) {
        CrowdScene crowd = make_crowd(sphere, mesh.bounds(), count,
                                      float(options.crowd_resolution.x) / float(options.crowd_resolution.y));
        for (auto& [name, renderer] : list) {
            progress.report("bench", double(step++) / double(std::max<std::size_t>(steps, 1)));
            DrawParams params;
            params.camera = crowd.camera;
            params.light = crowd.light;
            params.viewport = options.crowd_resolution;
            params.world_from_object = crowd.world_from_object;
            int frames = std::max(1, std::min(options.frames, count >= 1000 ? 3 : options.frames));
            Result<FrameRecord> r = time_subject(*renderer, name, "crowd", params, 1, frames);
            if (!r) return r.status();
            r->distance_rel = 0.0f;
            records.push_back(*r);
        }
    }
    progress.report("bench", 1.0);
    return records;
}

double peak_rss_mb()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0; // kB
    return 0.0;
}

bool reset_peak_rss()
{
    std::ofstream clear("/proc/self/clear_refs");
    if (!clear) return false;
    clear << "5";
    clear.flush();
    return bool(clear);
}

} // namespace standin
