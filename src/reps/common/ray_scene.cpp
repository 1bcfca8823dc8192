// embree 3 behind RayScene (ray_scene.h). Steps: one device and one static triangle scene over the
// caller's arrays; rays with rtcIntersect1; closest points with rtcPointQuery and a callback that
// tests each candidate triangle exactly and shrinks the query radius.
#include "reps/common/ray_scene.h"

#include <standin/mesh.h>

#include <tbb/parallel_for.h>

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace standin::reps {

struct RayScene::State {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    const std::vector<glm::vec3>* positions = nullptr;
    const std::vector<std::uint32_t>* indices = nullptr;
    ~State()
    {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
};

RayScene::~RayScene() = default;

Result<std::unique_ptr<RayScene>> RayScene::create(const std::vector<glm::vec3>& positions,
                                                   const std::vector<std::uint32_t>& indices)
{
    std::unique_ptr<RayScene> out(new RayScene());
    out->state_ = std::make_unique<State>();
    State& s = *out->state_;
    s.positions = &positions;
    s.indices = &indices;
    s.device = rtcNewDevice(nullptr);
    if (!s.device) return error(StatusCode::unsupported, "displaced mesh: embree device creation failed");
    s.scene = rtcNewScene(s.device);
    rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_MEDIUM);
    RTCGeometry geometry = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, positions.data(), 0,
                               sizeof(glm::vec3), positions.size());
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices.data(), 0,
                               3 * sizeof(std::uint32_t), indices.size() / 3);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(s.scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(s.scene);
    if (rtcGetDeviceError(s.device) != RTC_ERROR_NONE)
        return error(StatusCode::bad_data, "displaced mesh: embree could not build the surface");
    return out;
}

SurfacePoint RayScene::intersect(glm::vec3 origin, glm::vec3 direction, float t_max, float t_min) const
{
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRayHit query{};
    query.ray.org_x = origin.x, query.ray.org_y = origin.y, query.ray.org_z = origin.z;
    query.ray.dir_x = direction.x, query.ray.dir_y = direction.y, query.ray.dir_z = direction.z;
    query.ray.tnear = t_min;
    query.ray.tfar = t_max;
    query.ray.mask = 0xffffffffu;
    query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(state_->scene, &context, &query);
    SurfacePoint out;
    if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return out;
    out.found = true;
    out.triangle = query.hit.primID;
    out.b1 = query.hit.u, out.b2 = query.hit.v;
    out.t = query.ray.tfar;
    out.position = origin + out.t * direction;
    return out;
}

// The closest point of a triangle: the plane projection when it falls inside, else the nearest of
// the three edges' closest points.
glm::vec3 closest_point_in_triangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c, float& b1, float& b2)
{
    // in double: the normal equations' determinant of a long thin triangle cancels in float, and
    // a point on such a triangle's edge came back up to 1.1e-5 off it on the generated tree's trunk
    // (its edge ~0.1 long), past the samplers' on-surface radius: the displaced mesh then cast rays
    // from a point on the surface and took a branch behind it (elevations of +-0.01, faces refined
    // 6-10 bisections, 463,621 triangles a frame)
    const glm::dvec3 da(a), e1 = glm::dvec3(b) - da, e2 = glm::dvec3(c) - da, d = glm::dvec3(p) - da;
    const double d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const double det = d11 * d22 - d12 * d12;
    if (det > 0.0) {
        const double r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
        const double u = (d22 * r1 - d12 * r2) / det, v = (d11 * r2 - d12 * r1) / det;
        if (u >= 0.0 && v >= 0.0 && u + v <= 1.0) {
            b1 = float(u), b2 = float(v);
            return glm::vec3(da + u * e1 + v * e2);
        }
    }
    // on the boundary: the best of the three segments, each clamped
    const glm::dvec3 corners[3] = {da, glm::dvec3(b), glm::dvec3(c)};
    const glm::dvec3 dp(p);
    double best = std::numeric_limits<double>::infinity();
    glm::dvec3 best_point = da;
    b1 = b2 = 0.0f;
    for (int k = 0; k < 3; ++k) {
        const glm::dvec3 s0 = corners[k], s = corners[(k + 1) % 3] - s0;
        const double length2 = glm::dot(s, s);
        const double t = length2 > 0.0 ? std::clamp(glm::dot(dp - s0, s) / length2, 0.0, 1.0) : 0.0;
        const glm::dvec3 q = s0 + t * s;
        const double dist2 = glm::dot(dp - q, dp - q);
        if (dist2 < best) {
            best = dist2, best_point = q;
            float w[3] = {0.0f, 0.0f, 0.0f};
            w[k] = float(1.0 - t), w[(k + 1) % 3] = float(t);
            b1 = w[1], b2 = w[2];
        }
    }
    return glm::vec3(best_point);
}

namespace {

struct ClosestQuery {
    const RayScene::State* state;
    const std::function<bool(std::uint32_t)>* accept;
    float limit; // the query's radius: embree visits triangles whose bounds reach it, nearer or not
    SurfacePoint best;
};

bool closest_callback(RTCPointQueryFunctionArguments* args)
{
    auto* q = static_cast<ClosestQuery*>(args->userPtr);
    if (*q->accept && !(*q->accept)(args->primID)) return false;
    const std::vector<glm::vec3>& positions = *q->state->positions;
    const std::uint32_t* t = &(*q->state->indices)[3 * std::size_t(args->primID)];
    glm::vec3 p(args->query->x, args->query->y, args->query->z);
    const glm::vec3 a = positions[t[0]], b = positions[t[1]], c3 = positions[t[2]];
    // A triangle whose plane lies beyond the query's radius cannot be nearer: most of those whose
    // boxes reach a point among crossed leaf cards (large, tilted cards have large boxes) are
    // left here, before the exact closest point. The margin keeps every triangle the exact test
    // could accept (its rounding, relative to the coordinates' size, is far below 1e-5 of them):
    // the same answers, bit for bit.
    const glm::vec3 normal = glm::cross(b - a, c3 - a);
    const float normal_length = glm::length(normal);
    if (normal_length > 0.0f && std::isfinite(normal_length)) {
        const glm::vec3 offset = p - a;
        const float plane_distance = std::abs(glm::dot(offset, normal)) / normal_length;
        if (plane_distance > args->query->radius * 1.001f + 1e-5f * (glm::length(p) + glm::length(a))) return false;
    }
    float b1 = 0.0f, b2 = 0.0f;
    glm::vec3 c = closest_point_in_triangle(p, a, b, c3, b1, b2);
    float distance = glm::length(p - c);
    if (distance > q->limit) return false;
    // ties (a point closest to an edge two triangles share) go to the lower triangle index, so the
    // answer does not depend on the order embree visits them
    if (q->best.found && (distance > q->best.distance || (distance == q->best.distance && args->primID > q->best.triangle)))
        return false;
    q->best = {true, args->primID, b1, b2, 0.0f, distance, c};
    args->query->radius = distance * (1.0f + 1e-6f) + 1e-30f; // keep visiting exact ties
    return true;
}

} // namespace

SurfacePoint RayScene::closest(glm::vec3 point, float radius, const std::function<bool(std::uint32_t triangle)>& accept) const
{
    RTCPointQuery query;
    query.x = point.x, query.y = point.y, query.z = point.z;
    query.time = 0.0f;
    query.radius = radius;
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    ClosestQuery q{state_.get(), &accept, radius, {}};
    rtcPointQuery(state_->scene, &query, &context, closest_callback, &q);
    return q.best;
}

SurfacePoint RayScene::closest_anywhere(glm::vec3 point, float first_radius) const
{
    for (float radius = first_radius; radius > 0.0f && radius < std::numeric_limits<float>::max() / 16.0f; radius *= 16.0f)
        if (SurfacePoint found = closest(point, radius); found.found) return found;
    return closest(point, std::numeric_limits<float>::infinity());
}

// The share of the model's area on single-sided faces whose back can be seen from outside: a ray
// from the back of the face (its winding's, which the truth culls by), along the back's normal,
// leaves the model without meeting a face. A closed part's backs face its own inside, whose other
// walls stop the rays, however its seams are welded (the held-out engine: every material
// single-sided, 57 of 59 parts open by exact welding); a single-sided sheet's back faces the world.
// At most k_back_probe_faces faces are probed, evenly over the index order, weighted by area.
constexpr std::size_t k_back_probe_faces = 20000;
namespace {

// The share of the model's area on faces (single-sided ones only, or all) whose backs rays leave the
// model from (visible_single_sided_backs, visible_backs).
double backs_seen_from_outside(const Mesh& mesh, bool single_sided_only)
{
    std::vector<std::uint32_t> single_sided;
    double total_area = 0.0;
    for (std::size_t f = 0; f < mesh.triangle_count(); ++f) {
        total_area += mesh.triangle_area(f);
        if (!single_sided_only || !mesh.materials[mesh.face_materials[f]].double_sided) single_sided.push_back(std::uint32_t(f));
    }
    if (single_sided.empty() || !(total_area > 0.0)) return 0.0;
    Result<std::unique_ptr<RayScene>> scene = RayScene::create(mesh.positions, mesh.indices);
    if (!scene) return 0.0;
    const std::size_t stride = std::max<std::size_t>(1, (single_sided.size() + k_back_probe_faces - 1) / k_back_probe_faces);
    const std::size_t probes = (single_sided.size() + stride - 1) / stride;
    const float offset = 1e-4f * std::max(mesh.bounds().diagonal(), 1e-20f);
    std::vector<double> seen(probes, 0.0), probed(probes, 0.0);
    tbb::parallel_for(std::size_t(0), probes, [&](std::size_t k) {
        const std::uint32_t f = single_sided[k * stride];
        const glm::vec3 a = mesh.positions[mesh.indices[3 * f]], b = mesh.positions[mesh.indices[3 * f + 1]],
                        c = mesh.positions[mesh.indices[3 * f + 2]];
        const glm::vec3 cross = glm::cross(b - a, c - a);
        const float length = glm::length(cross);
        if (!(length > 0.0f) || !std::isfinite(length)) return;
        const glm::vec3 back = -cross / length, centre = (a + b + c) / 3.0f;
        probed[k] = mesh.triangle_area(f);
        if (!(*scene)->intersect(centre + back * offset, back, std::numeric_limits<float>::infinity()).found) seen[k] = probed[k];
    });
    double seen_area = 0.0, probed_area = 0.0, single_sided_area = 0.0;
    for (std::size_t k = 0; k < probes; ++k) seen_area += seen[k], probed_area += probed[k];
    for (std::uint32_t f : single_sided) single_sided_area += mesh.triangle_area(f);
    return probed_area > 0.0 ? seen_area / probed_area * single_sided_area / total_area : 0.0;
}

} // namespace

double visible_single_sided_backs(const Mesh& mesh) { return backs_seen_from_outside(mesh, true); }

double visible_backs(const Mesh& mesh) { return backs_seen_from_outside(mesh, false); }

} // namespace standin::reps
