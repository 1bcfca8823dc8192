// The atlas hull (hull.cpp) on the CPU: polytope clipping against analytic volumes, and hulls of
// view atlases "captured" here by casting each texel's ray at an analytic cube or sphere (the
// capture rule of bake.cpp: ortho or perspective from the base distance, covered texels, depth
// codes), so that the expectations are exact: a cube's hull is its box within a texel, a sphere's
// lies between the sphere and its box, and every vertex of a sphere mesh lies inside.
#include "reps/view_atlas/hull.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace standin::view_atlas {
namespace {

constexpr double k_pi = 3.14159265358979323846;

TEST(AtlasHull, ClipsABoxExactly)
{
    const ConvexPolytope box = box_polytope(glm::dvec3(-1.0), glm::dvec3(1.0));
    EXPECT_NEAR(box.volume(), 8.0, 1e-12);
    EXPECT_EQ(box.triangle_count(), 12u);
    EXPECT_NEAR(box.projected_area({0, 0, 1}), 4.0, 1e-12);
    EXPECT_NEAR(box.projected_area(glm::normalize(glm::dvec3(1.0))), 12.0 / std::sqrt(3.0), 1e-12);

    // a slab: x <= 0.5 keeps 3/4
    ClipStats stats;
    ConvexPolytope slab = clip_polytope(box, {{{1, 0, 0}, 0.5}}, 0.0, &stats);
    EXPECT_NEAR(slab.volume(), 6.0, 1e-12);
    EXPECT_EQ(slab.faces.size(), 6u);
    EXPECT_EQ(stats.cut, 1);

    // a corner: x + y + z <= 2 cuts the tetrahedron of legs 1 off (1, 1, 1), one new triangle face
    const glm::dvec3 n = glm::normalize(glm::dvec3(1.0));
    ConvexPolytope corner = clip_polytope(box, {{n, 2.0 / std::sqrt(3.0)}}, 0.0);
    EXPECT_NEAR(corner.volume(), 8.0 - 1.0 / 6.0, 1e-12);
    EXPECT_EQ(corner.faces.size(), 7u);
    EXPECT_EQ(corner.vertices.size(), 10u);
    EXPECT_FALSE(corner.contains(glm::dvec3(0.99), 0.0));
    EXPECT_TRUE(corner.contains(glm::dvec3(0.6), 0.0));

    // a plane through a vertex and an edge at once: no duplicate vertices, no sliver faces
    ConvexPolytope half = clip_polytope(box, {{glm::normalize(glm::dvec3(1, 1, 0)), 0.0}}, 0.0);
    EXPECT_NEAR(half.volume(), 4.0, 1e-12);
    EXPECT_EQ(half.faces.size(), 5u);
    EXPECT_EQ(half.vertices.size(), 6u);
    // the same plane again, and one a hair away, cut nothing more
    ConvexPolytope again = clip_polytope(half, {{glm::normalize(glm::dvec3(1, 1, 0)), 1e-13}}, 0.0, &stats);
    EXPECT_EQ(stats.skipped, 1);
    EXPECT_EQ(again.faces.size(), 5u);

    // a plane that cuts nothing is skipped, one that would leave nothing is refused, a shallow cut
    // under min_cut is skipped
    ConvexPolytope same = clip_polytope(box, {{{1, 0, 0}, 2.0}, {{1, 0, 0}, -1.5}, {{0, 1, 0}, 0.95}}, 0.1, &stats);
    EXPECT_EQ(stats.planes, 3);
    EXPECT_EQ(stats.skipped, 2);
    EXPECT_EQ(stats.refused, 1);
    EXPECT_NEAR(same.volume(), 8.0, 1e-12);

    // many planes: the box clipped by the tangent planes of its inscribed sphere approaches the sphere
    std::vector<HalfSpace> tangents;
    for (int i = 0; i < 24; ++i)
        for (int j = 1; j < 12; ++j) {
            double theta = k_pi * j / 12.0, phi = 2.0 * k_pi * i / 24.0;
            tangents.push_back({{std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)}, 1.0});
        }
    ConvexPolytope round = clip_polytope(box, tangents, 0.0, &stats);
    EXPECT_GT(round.volume(), 4.0 / 3.0 * k_pi);
    EXPECT_LT(round.volume(), 4.0 / 3.0 * k_pi * 1.06);
    for (const glm::dvec3& v : round.vertices) EXPECT_GE(glm::length(v), 1.0 - 1e-9);
    for (std::size_t f = 0; f < round.faces.size(); ++f) {
        // every face convex, counter-clockwise from outside, its corners on its plane
        const std::vector<std::uint32_t>& face = round.faces[f];
        ASSERT_GE(face.size(), 3u);
        for (std::size_t k = 0; k < face.size(); ++k) {
            const glm::dvec3 a = round.vertices[face[k]], b = round.vertices[face[(k + 1) % face.size()]],
                             c = round.vertices[face[(k + 2) % face.size()]];
            EXPECT_GT(glm::dot(glm::cross(b - a, c - b), round.face_normals[f]), 0.0);
            EXPECT_NEAR(glm::dot(a - round.vertices[face[0]], round.face_normals[f]), 0.0, 1e-9);
        }
    }
}

// An analytic solid the test "captures": the first hit of a ray, if any.
struct Solid {
    bool sphere = true;
    glm::dvec3 center{0.0};
    double size = 0.5; // radius, or half side of the cube

    std::optional<double> hit(glm::dvec3 origin, glm::dvec3 ray) const
    {
        if (sphere) {
            glm::dvec3 oc = origin - center;
            double b = glm::dot(oc, ray), c = glm::dot(oc, oc) - size * size, disc = b * b - c;
            if (disc < 0.0) return std::nullopt;
            return -b - std::sqrt(disc);
        }
        double t0 = -1e30, t1 = 1e30;
        for (int a = 0; a < 3; ++a) {
            double lo = (center[a] - size - origin[a]) / ray[a], hi = (center[a] + size - origin[a]) / ray[a];
            t0 = std::max(t0, std::min(lo, hi)), t1 = std::min(t1, std::max(lo, hi));
        }
        if (t0 > t1) return std::nullopt;
        return t0;
    }
};

// A "surface" octahedral view atlas of the solid, captured texel by texel as bake.cpp does.
ViewAtlasPackage capture(const Solid& solid, int frames, int resolution, bool perspective)
{
    ViewAtlasPackage p;
    p.settings.layout = "octahedral";
    p.settings.frames = frames;
    p.settings.resolution = resolution;
    p.settings.projection = perspective ? "perspective" : "ortho";
    p.settings.page_size = 2048;
    p.settings.depth_bits = 8; // the 8-bit codes below
    p.source.bounds = {glm::vec3(solid.center - solid.size), glm::vec3(solid.center + solid.size)};
    p.center = glm::vec3(solid.center);
    p.radius = float(std::sqrt(3.0) * solid.size);
    const double h = p.half_extent(), eye = p.capture_distance(), r = p.radius;
    struct Texel {
        int x, y, depth;
    };
    std::vector<std::vector<Texel>> covered;
    for (glm::vec3 d : layout_directions("octahedral", 0, frames)) {
        View v;
        v.direction = d;
        glm::vec3 up = d.y > 0.999f ? glm::vec3(0, 0, -1) : d.y < -0.999f ? glm::vec3(0, 0, 1) : glm::vec3(0, 1, 0);
        v.axis_u = glm::normalize(glm::cross(-d, up));
        v.axis_v = glm::cross(v.axis_u, d);
        std::vector<Texel> texels;
        int x0 = resolution, y0 = resolution, x1 = -1, y1 = -1;
        for (int y = 0; y < resolution; ++y)
            for (int x = 0; x < resolution; ++x) {
                const double u = -h + (x + 0.5) * 2.0 * h / resolution, w = -h + (y + 0.5) * 2.0 * h / resolution;
                const glm::dvec3 on_plane = solid.center + u * glm::dvec3(v.axis_u) + w * glm::dvec3(v.axis_v);
                const glm::dvec3 origin = perspective ? solid.center + eye * glm::dvec3(d) : on_plane + 2.0 * r * glm::dvec3(d);
                const glm::dvec3 ray = glm::normalize(on_plane - origin);
                std::optional<double> t = solid.hit(origin, ray);
                if (!t) continue;
                const double along = glm::dot(origin + *t * ray - solid.center, glm::dvec3(d));
                const int code = int(std::lround(std::clamp((r - along) / (2.0 * r), 0.0, 1.0) * 255.0));
                texels.push_back({x, y, code});
                x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
            }
        if (x1 >= 0) {
            v.crop_x = x0 - 1, v.crop_y = y0 - 1;
            v.width = (x1 - x0 + 3 + k_cell - 1) / k_cell * k_cell;
            v.height = (y1 - y0 + 3 + k_cell - 1) / k_cell * k_cell;
        }
        p.views.push_back(v);
        covered.push_back(std::move(texels));
    }
    const int pages = pack_views(p.views, p.settings.page_size);
    p.color_pages.assign(std::size_t(pages), ImageRGBA8(p.settings.page_size, p.settings.page_size));
    p.normal_depth_pages.assign(std::size_t(pages), ImageRGBA8(p.settings.page_size, p.settings.page_size));
    for (std::size_t k = 0; k < p.views.size(); ++k) {
        const View& v = p.views[k];
        for (const Texel& t : covered[k]) {
            const int ax = v.atlas_x + t.x - v.crop_x, ay = v.atlas_y + t.y - v.crop_y;
            p.color_pages[std::size_t(v.page)].at(ax, ay)[3] = 255;
            p.normal_depth_pages[std::size_t(v.page)].at(ax, ay)[3] = std::uint8_t(t.depth);
        }
    }
    return p;
}

// points on the solid's surface (its corners and a latitude-longitude net)
std::vector<glm::dvec3> surface_points(const Solid& solid)
{
    std::vector<glm::dvec3> points;
    for (int i = 0; i < 48; ++i)
        for (int j = 0; j <= 24; ++j) {
            double theta = k_pi * j / 24.0, phi = 2.0 * k_pi * i / 48.0;
            glm::dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
            if (!solid.sphere) d /= std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
            points.push_back(solid.center + solid.size * d);
        }
    return points;
}

TEST(AtlasHull, CubeHullIsItsBoxWithinATexel)
{
    const Solid cube{false, {0.3, -0.2, 1.0}, 0.5};
    for (bool perspective : {false, true}) {
        SCOPED_TRACE(perspective ? "perspective" : "ortho");
        ViewAtlasPackage p = capture(cube, 8, 192, perspective);
        const double texel = capture_texel(p);
        ClipStats stats;
        ConvexPolytope hull = atlas_hull(p, &stats);
        ASSERT_FALSE(hull.empty());
        EXPECT_EQ(stats.refused, 0);
        for (const glm::dvec3& v : hull.vertices)
            for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(v[a] - cube.center[a]), cube.size + texel);
        for (const glm::dvec3& q : surface_points(cube)) EXPECT_TRUE(hull.contains(q, 1e-9));
        EXPECT_LT(hull.volume(), std::pow(2.0 * (cube.size + texel), 3.0));
    }
}

TEST(AtlasHull, SphereHullLiesBetweenTheSphereAndItsBox)
{
    const Solid sphere{true, {-1.0, 2.0, 0.5}, 0.5};
    for (bool perspective : {false, true}) {
        SCOPED_TRACE(perspective ? "perspective" : "ortho");
        ViewAtlasPackage p = capture(sphere, 8, 192, perspective);
        const double texel = capture_texel(p);
        ConvexPolytope hull = atlas_hull(p);
        ASSERT_FALSE(hull.empty());
        // inside the box (grown by half a texel), outside the sphere
        for (const glm::dvec3& v : hull.vertices) {
            for (int a = 0; a < 3; ++a) EXPECT_LE(std::abs(v[a] - sphere.center[a]), sphere.size + 0.5 * texel + 1e-9);
            EXPECT_GE(glm::length(v - sphere.center), sphere.size);
        }
        // every vertex of a sphere mesh inside
        for (const glm::dvec3& q : surface_points(sphere)) EXPECT_TRUE(hull.contains(q, 1e-9));
        // and much tighter than the box: 64 views of 5 planes leave ~1.2x the sphere's volume
        const double ball = 4.0 / 3.0 * k_pi * std::pow(sphere.size, 3.0), box = std::pow(2.0 * sphere.size, 3.0);
        EXPECT_GT(hull.volume(), ball);
        EXPECT_LT(hull.volume(), 0.5 * (ball + box));
    }
}

// The renderer's proxy: a few supporting planes of the model's points, chosen by surface area. A
// box's surface area is exact; the proxy holds every point (never cuts the model), keeps to its
// budget, and takes most of the way from the box to the points' convex hull with 24 planes.
TEST(AtlasHull, ProxyPlanesHoldEveryPointWithinTheirBudget)
{
    EXPECT_NEAR(box_polytope(glm::dvec3(0.0), glm::dvec3(1.0, 2.0, 3.0)).surface_area(), 22.0, 1e-12);
    const Solid sphere{true, {0.4, -0.3, 0.2}, 0.8};
    ViewAtlasPackage p = capture(sphere, 8, 128, false); // for its box and its 128 view directions
    std::vector<glm::vec3> points, directions;
    for (const glm::dvec3& q : surface_points(sphere)) points.push_back(glm::vec3(q));
    for (const View& v : p.views) directions.push_back(v.direction);
    const ConvexPolytope box = source_box(p);
    const double ball = 4.0 * k_pi * sphere.size * sphere.size;
    double previous = box.surface_area();
    for (int budget : {0, 6, 24}) {
        SCOPED_TRACE(budget);
        std::vector<HalfSpace> planes = proxy_planes(points, directions, box, 0.0, budget);
        EXPECT_LE(planes.size(), std::size_t(budget));
        ConvexPolytope proxy = clip_polytope(box, planes, 0.0);
        ASSERT_FALSE(proxy.empty());
        for (const glm::vec3& q : points) EXPECT_TRUE(proxy.contains(glm::dvec3(q), 1e-9));
        EXPECT_LE(proxy.surface_area(), previous * (1.0 + 1e-12));
        previous = proxy.surface_area();
        std::printf("%d planes: area / sphere %.3f (%zu faces)\n", budget, proxy.surface_area() / ball, proxy.faces.size());
    }
    // the box has 6 / pi = 1.91 times the sphere's area; 24 planes come within 15% of the sphere
    EXPECT_LT(previous, 1.15 * ball);
    // deterministic, and the order taken is the greedy one (each plane cuts the most area left)
    EXPECT_EQ(proxy_planes(points, directions, box, 0.0).size(), proxy_planes(points, directions, box, 0.0).size());
    std::vector<HalfSpace> a = proxy_planes(points, directions, box, 0.0), b = proxy_planes(points, directions, box, 0.0);
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].normal, b[k].normal);
        EXPECT_EQ(a[k].offset, b[k].offset);
    }
    // a flat sheet seen edge on stays whole (the captured views' hull would cut it: it covers no
    // texel there), as every proxy plane is tangent to the points themselves
    std::vector<glm::vec3> sheet = {{-1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, -1.0f}, {1.0f, 0.0f, 1.0f}, {-1.0f, 0.0f, 1.0f}};
    const ConvexPolytope sheet_box = box_polytope(glm::dvec3(-1.01, -0.01, -1.01), glm::dvec3(1.01, 0.01, 1.01));
    const ConvexPolytope sheet_proxy = clip_polytope(sheet_box, proxy_planes(sheet, directions, sheet_box, 0.0), 0.0);
    for (const glm::vec3& q : sheet) EXPECT_TRUE(sheet_proxy.contains(glm::dvec3(q), 1e-9));
}

TEST(AtlasHull, Deterministic)
{
    const Solid sphere{true, {0.0, 0.0, 0.0}, 1.0};
    ViewAtlasPackage p = capture(sphere, 6, 64, false);
    ConvexPolytope a = atlas_hull(p), b = atlas_hull(p);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    for (std::size_t k = 0; k < a.vertices.size(); ++k) EXPECT_EQ(a.vertices[k], b.vertices[k]);
    EXPECT_EQ(a.faces, b.faces);
}

} // namespace
} // namespace standin::view_atlas
