// One-sided surface distance from one mesh to another, the geometric error of mesh stand-ins
// (Bauman, Livny & El-Sana §5.1 reports it against the original; Metro, Cignoni et al.
// 1998, and MeshLab's Hausdorff filter measure it the same way): sample points on the surface of
// `from` by area, find the closest point of `to` with embree 3 point queries.
#include <standin/eval.h>

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace standin {

namespace {

struct ClosestHit {
    const Mesh* mesh = nullptr;
    float distance_squared = std::numeric_limits<float>::infinity();
};

// Closest point of triangle abc to p (Ericson, Real-Time Collision Detection §5.1.5).
glm::vec3 closest_point_on_triangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c)
{
    glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return a;
    glm::vec3 bp = p - b;
    float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return b;
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + ab * (d1 / (d1 - d3));
    glm::vec3 cp = p - c;
    float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return c;
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + ac * (d2 / (d2 - d6));
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    float denom = 1.0f / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

bool closest_point_callback(RTCPointQueryFunctionArguments* args)
{
    auto* hit = static_cast<ClosestHit*>(args->userPtr);
    const Mesh& mesh = *hit->mesh;
    const std::uint32_t* tri = &mesh.indices[std::size_t(args->primID) * 3];
    glm::vec3 p(args->query->x, args->query->y, args->query->z);
    glm::vec3 q = closest_point_on_triangle(p, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]);
    float d2 = glm::dot(p - q, p - q);
    if (d2 < hit->distance_squared) {
        hit->distance_squared = d2;
        args->query->radius = std::sqrt(d2); // shrink the search
        return true;
    }
    return false;
}

struct EmbreeScene {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    ~EmbreeScene()
    {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

Status build_scene(const Mesh& mesh, EmbreeScene& out)
{
    out.device = rtcNewDevice(nullptr);
    if (!out.device) return error(StatusCode::unsupported, "surface distance: embree device creation failed");
    out.scene = rtcNewScene(out.device);
    RTCGeometry geometry = rtcNewGeometry(out.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(), 0,
                               sizeof(glm::vec3), mesh.positions.size());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                               3 * sizeof(std::uint32_t), mesh.triangle_count());
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(out.scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(out.scene);
    if (rtcGetDeviceError(out.device) != RTC_ERROR_NONE)
        return error(StatusCode::bad_data, "surface distance: embree could not build the target mesh");
    return Status::ok();
}

// Points on the surface with probability proportional to area: stratified over the cumulative
// area so that even small sample counts cover the whole mesh.
std::vector<glm::vec3> sample_surface(const Mesh& mesh, std::size_t samples, std::uint32_t seed)
{
    std::vector<double> cumulative(mesh.triangle_count());
    double total = 0.0;
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) cumulative[t] = total += mesh.triangle_area(t);
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<glm::vec3> points(samples);
    for (std::size_t i = 0; i < samples; ++i) {
        double target = (double(i) + uniform(rng)) / double(samples) * total;
        std::size_t t = std::min<std::size_t>(
            std::lower_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin(), cumulative.size() - 1);
        float r1 = float(uniform(rng)), r2 = float(uniform(rng));
        float s = std::sqrt(r1);
        const std::uint32_t* tri = &mesh.indices[t * 3];
        points[i] = (1.0f - s) * mesh.positions[tri[0]] + s * (1.0f - r2) * mesh.positions[tri[1]] +
                    s * r2 * mesh.positions[tri[2]];
    }
    return points;
}

} // namespace

Result<SurfaceDistance> surface_distance(const Mesh& from, const Mesh& to, std::size_t samples, std::uint32_t seed)
{
    if (samples == 0 || samples > k_max_surface_samples)
        return error(StatusCode::invalid_argument, "surface distance: samples must be within 1.." + std::to_string(k_max_surface_samples));
    STANDIN_RETURN_IF_ERROR(validate_mesh(from, "surface distance: source mesh"));
    STANDIN_RETURN_IF_ERROR(validate_mesh(to, "surface distance: target mesh"));

    // build the point-query structure over the target
    EmbreeScene scene;
    STANDIN_RETURN_IF_ERROR(build_scene(to, scene));

    // sample the source and measure every sample
    std::vector<glm::vec3> points = sample_surface(from, samples, seed);
    std::vector<float> distances(samples);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, samples), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            RTCPointQuery query;
            query.x = points[i].x, query.y = points[i].y, query.z = points[i].z;
            query.time = 0.0f;
            query.radius = std::numeric_limits<float>::infinity();
            RTCPointQueryContext context;
            rtcInitPointQueryContext(&context);
            ClosestHit hit;
            hit.mesh = &to;
            rtcPointQuery(scene.scene, &query, &context, closest_point_callback, &hit);
            distances[i] = std::sqrt(hit.distance_squared);
        }
    });

    // summarise, relative to the target's bounding-box diagonal
    SurfaceDistance result;
    result.samples = samples;
    double sum = 0.0;
    for (float d : distances) {
        sum += d;
        result.max = std::max(result.max, double(d));
    }
    result.mean = sum / double(samples);
    double diagonal = std::max(double(to.bounds().diagonal()), 1e-30);
    result.mean_rel = result.mean / diagonal;
    result.max_rel = result.max / diagonal;
    return result;
}

} // namespace standin
