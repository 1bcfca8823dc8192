// Rays and closest points against a triangle mesh with embree 3: the displaced mesh samples the
// original with it (Bauman, Livny & El-Sana §3.1: "a ray is shot through each refined-vertex along
// its interpolated normal") and measures how far a reconstruction lies from it (§3.2, §5.1); the
// billboards' bake asks which backs of single-sided faces can be seen from outside.
// Built once, then safe to query from many threads.
#pragma once

#include <standin/status.h>

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

namespace standin {
struct Mesh;
}

namespace standin::reps {

// A point on the mesh: triangle and barycentric weights (b1, b2) of its 2nd and 3rd corner.
struct SurfacePoint {
    bool found = false;
    std::uint32_t triangle = 0;
    float b1 = 0.0f, b2 = 0.0f;
    float t = 0.0f;          // along the ray (ray queries)
    float distance = 0.0f;   // from the query point (closest-point queries)
    glm::vec3 position{0.0f};
};

class RayScene {
public:
    // Keeps references to both arrays: they must outlive the scene. unsupported when embree fails.
    static Result<std::unique_ptr<RayScene>> create(const std::vector<glm::vec3>& positions,
                                                    const std::vector<std::uint32_t>& indices);
    ~RayScene();

    // The first hit along origin + t * direction, t in [t_min, t_max] (t_min: to walk on past a
    // hit that an alpha test cuts out).
    SurfacePoint intersect(glm::vec3 origin, glm::vec3 direction, float t_max, float t_min = 0.0f) const;
    // The closest point of the mesh to `point` within `radius` (infinite: anywhere), among the
    // triangles `accept` takes (all where it is empty).
    SurfacePoint closest(glm::vec3 point, float radius, const std::function<bool(std::uint32_t triangle)>& accept = {}) const;
    // The closest point anywhere, searched within `first_radius` and then 16 times wider until one
    // is found: the same answer as an infinite radius, for a fraction of the visits where the answer
    // is usually near (embree's point query does not visit nodes nearest first, so an unbounded
    // query in dense foliage tests many triangles before its radius shrinks).
    SurfacePoint closest_anywhere(glm::vec3 point, float first_radius) const;

    struct State; // embree's device and scene (ray_scene.cpp)

private:
    RayScene() = default;
    std::unique_ptr<State> state_;
};

// The closest point of triangle abc to p, with its barycentric weights (b1 on b, b2 on c).
glm::vec3 closest_point_in_triangle(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c, float& b1, float& b2);

// The share of the model's area on single-sided faces (Material::double_sided false) whose backs
// can be seen from outside: rays from the backs leave the model (ray_scene.cpp). The truth culls
// such backs; stand-ins that draw both sides hide them above k_visible_backs (the billboards'
// --back-hits auto, the displaced mesh's --back-faces auto). 0 where the mesh is empty or embree fails.
constexpr double k_visible_backs = 0.001;
double visible_single_sided_backs(const Mesh& mesh);
// The same over every face, double-sided ones included: the share of the model's area whose backs
// face the world rather than the model's own inside (an open sheet's, a bowl's; a closed part's none,
// a scan with a small hole a few faces' around it).
double visible_backs(const Mesh& mesh);

} // namespace standin::reps
