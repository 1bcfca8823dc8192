// The atlas hull (issue #16): the convex polytope a view atlas bounds its model by.
// Sources: the convex hull of a visual hull (Laurentini 1994, "The visual hull concept for
// silhouette-based image understanding": the model lies inside every view's silhouette cone;
// here only each silhouette's bounding rectangle is kept, which is convex), plus each view's
// nearest depth (a supporting plane of the model seen from that side); polytope clipping is
// Sutherland & Hodgman's reentrant polygon clipping (1974) applied to every face, the cut closed by
// a cap polygon, the 2-D convex hull of the points on the plane (Andrew's monotone chain, 1979).
// Steps:
//  1. per view, the covered texels' rectangle and nearest depth become 4 + 1 half-spaces, each
//     moved outwards by the sampling error (atlas_half_spaces);
//  2. start from the source's bounding box, grown by half a texel (never flat);
//  3. clip by each half-space in view order: classify the vertices (inside / on / outside, with a
//     tolerance relative to the box), skip a plane that cuts nothing or less than min_cut, clip
//     every face, cap the cut; an intersection point is computed from the edge's inside end, so
//     the two faces sharing an edge get bit-identical points;
//  4. weld vertices closer than the tolerance, drop repeated and collinear corners and faces left
//     without area.
// Departures: the silhouette cones are reduced to their bounding rectangles (the polytope stays
// convex and small: 5 planes a view, a few hundred faces), and only near depth planes are used:
// a view's far depth is that of the surface it sees, not of the model's back (the opposite view's
// near plane bounds that).
#include "reps/view_atlas/hull.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace standin::view_atlas {

namespace {

// How far, in capture texels, the model may reach beyond the outermost covered texel centre (and
// in front of the nearest depth): a smooth outline reaches less than one, a thin tip further
// between two texel centres (the bunny's ear: 1.6, measured with the hull's own export).
constexpr double k_sampling_margin = 2.0;

struct Face {
    std::vector<glm::dvec3> points; // counter-clockwise from outside
    glm::dvec3 normal;
};

enum class Side { inside, on, outside };

Side side_of(double distance, double eps)
{
    if (distance > eps) return Side::outside;
    if (distance < -eps) return Side::inside;
    return Side::on;
}

// two unit vectors spanning the plane of `normal`, right-handed with it
void plane_basis(glm::dvec3 normal, glm::dvec3& a, glm::dvec3& b)
{
    glm::dvec3 helper = std::abs(normal.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    a = glm::normalize(glm::cross(helper, normal));
    b = glm::cross(normal, a);
}

double cross2(glm::dvec2 o, glm::dvec2 a, glm::dvec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// the cap of a cut: the convex hull of the points on the plane, counter-clockwise seen along
// +normal from outside (monotone chain; points closer than eps are one, collinear ones dropped)
std::vector<glm::dvec3> cap_polygon(const std::vector<glm::dvec3>& points, glm::dvec3 normal, double eps)
{
    glm::dvec3 a, b;
    plane_basis(normal, a, b);
    struct P {
        glm::dvec2 q;
        glm::dvec3 p;
    };
    std::vector<P> ps;
    ps.reserve(points.size());
    for (const glm::dvec3& p : points) ps.push_back({{glm::dot(p, a), glm::dot(p, b)}, p});
    std::sort(ps.begin(), ps.end(), [](const P& l, const P& r) { return l.q.x < r.q.x || (l.q.x == r.q.x && l.q.y < r.q.y); });
    std::vector<P> unique;
    for (const P& p : ps) {
        bool seen = false;
        for (const P& u : unique)
            if (glm::length(u.p - p.p) <= eps) seen = true;
        if (!seen) unique.push_back(p);
    }
    if (unique.size() < 3) return {};
    std::vector<P> hull(2 * unique.size());
    std::size_t k = 0;
    // a turn must exceed eps times the edge length to count (collinear points are dropped)
    auto left = [eps](const P& o, const P& p, const P& q) {
        return cross2(o.q, p.q, q.q) > eps * std::max(glm::length(p.q - o.q), glm::length(q.q - o.q));
    };
    for (const P& p : unique) {
        while (k >= 2 && !left(hull[k - 2], hull[k - 1], p)) --k;
        hull[k++] = p;
    }
    for (std::size_t i = unique.size() - 1, t = k + 1; i-- > 0;) {
        while (k >= t && !left(hull[k - 2], hull[k - 1], unique[i])) --k;
        hull[k++] = unique[i];
    }
    if (k < 4) return {}; // the first point is repeated at the end
    std::vector<glm::dvec3> out;
    for (std::size_t i = 0; i + 1 < k; ++i) out.push_back(hull[i].p);
    return out; // (a, b, normal) is right-handed: counter-clockwise in (a, b) is so from +normal
}

// clips one face by the plane; collects the points it leaves on the plane
Face clip_face(const Face& face, const HalfSpace& h, double eps, std::vector<glm::dvec3>& on_plane)
{
    Face out{{}, face.normal};
    const std::size_t n = face.points.size();
    std::vector<double> d(n);
    for (std::size_t i = 0; i < n; ++i) d[i] = glm::dot(h.normal, face.points[i]) - h.offset;
    for (std::size_t i = 0; i < n; ++i) {
        const glm::dvec3 &a = face.points[i], &b = face.points[(i + 1) % n];
        const double da = d[i], db = d[(i + 1) % n];
        const Side sa = side_of(da, eps), sb = side_of(db, eps);
        if (sa != Side::outside) out.points.push_back(a);
        if (sa == Side::on) on_plane.push_back(a);
        if ((sa == Side::inside && sb == Side::outside) || (sa == Side::outside && sb == Side::inside)) {
            // from the inside end, so that the face across this edge computes the same point
            const glm::dvec3& in = sa == Side::inside ? a : b;
            const glm::dvec3& outside = sa == Side::inside ? b : a;
            const double din = sa == Side::inside ? da : db, dout = sa == Side::inside ? db : da;
            glm::dvec3 p = in + (outside - in) * (din / (din - dout));
            out.points.push_back(p);
            on_plane.push_back(p);
        }
    }
    return out;
}

// the faces as a welded polytope: vertices within eps are one, repeated and collinear corners
// and faces with fewer than 3 corners dropped
ConvexPolytope weld(const std::vector<Face>& faces, double eps)
{
    ConvexPolytope poly;
    for (const Face& f : faces) {
        std::vector<std::uint32_t> ids;
        for (const glm::dvec3& p : f.points) {
            std::uint32_t id = std::uint32_t(poly.vertices.size());
            for (std::uint32_t v = 0; v < poly.vertices.size(); ++v)
                if (glm::length(poly.vertices[v] - p) <= eps) {
                    id = v;
                    break;
                }
            if (id == poly.vertices.size()) poly.vertices.push_back(p);
            if (ids.empty() || ids.back() != id) ids.push_back(id);
        }
        while (ids.size() > 1 && ids.front() == ids.back()) ids.pop_back();
        // collinear corners (a neighbour's vertex on this face's edge): repeat until none is left
        for (bool changed = true; changed && ids.size() >= 3;) {
            changed = false;
            for (std::size_t i = 0; i < ids.size(); ++i) {
                const glm::dvec3& prev = poly.vertices[ids[(i + ids.size() - 1) % ids.size()]];
                const glm::dvec3& cur = poly.vertices[ids[i]];
                const glm::dvec3& next = poly.vertices[ids[(i + 1) % ids.size()]];
                double turn = glm::dot(glm::cross(cur - prev, next - cur), f.normal);
                if (turn <= eps * glm::length(next - prev)) {
                    ids.erase(ids.begin() + std::ptrdiff_t(i));
                    changed = true;
                    break;
                }
            }
        }
        if (ids.size() < 3) continue;
        poly.faces.push_back(std::move(ids));
        poly.face_normals.push_back(f.normal);
    }
    // vertices no face uses any more (collinear ones) stay: harmless, and indices stay stable
    return poly;
}

double polytope_size(const ConvexPolytope& p)
{
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& v : p.vertices) lo = glm::min(lo, v), hi = glm::max(hi, v);
    return p.vertices.empty() ? 1.0 : std::max(glm::length(hi - lo), 1e-30);
}

} // namespace

bool ConvexPolytope::contains(glm::dvec3 p, double tolerance) const
{
    for (std::size_t f = 0; f < faces.size(); ++f)
        if (glm::dot(face_normals[f], p - vertices[faces[f][0]]) > tolerance) return false;
    return !faces.empty();
}

double ConvexPolytope::volume() const
{
    double v = 0.0;
    for (const std::vector<std::uint32_t>& f : faces)
        for (std::size_t i = 1; i + 1 < f.size(); ++i)
            v += glm::dot(vertices[f[0]], glm::cross(vertices[f[i]], vertices[f[i + 1]]));
    return v / 6.0;
}

double ConvexPolytope::surface_area() const
{
    double area = 0.0;
    for (const std::vector<std::uint32_t>& f : faces) {
        glm::dvec3 sum(0.0);
        for (std::size_t i = 1; i + 1 < f.size(); ++i)
            sum += glm::cross(vertices[f[i]] - vertices[f[0]], vertices[f[i + 1]] - vertices[f[0]]);
        area += 0.5 * glm::length(sum);
    }
    return area;
}

std::size_t ConvexPolytope::triangle_count() const
{
    std::size_t n = 0;
    for (const std::vector<std::uint32_t>& f : faces) n += f.size() - 2;
    return n;
}

double ConvexPolytope::projected_area(glm::dvec3 direction) const
{
    double area = 0.0;
    for (std::size_t f = 0; f < faces.size(); ++f) {
        glm::dvec3 sum(0.0);
        for (std::size_t i = 1; i + 1 < faces[f].size(); ++i)
            sum += glm::cross(vertices[faces[f][i]] - vertices[faces[f][0]], vertices[faces[f][i + 1]] - vertices[faces[f][0]]);
        area += 0.5 * std::abs(glm::dot(sum, direction));
    }
    return 0.5 * area;
}

ConvexPolytope box_polytope(glm::dvec3 lo, glm::dvec3 hi)
{
    ConvexPolytope p;
    for (int k = 0; k < 8; ++k) p.vertices.push_back({k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z});
    // counter-clockwise from outside
    p.faces = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    p.face_normals = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    return p;
}

ConvexPolytope clip_polytope(const ConvexPolytope& polytope, const std::vector<HalfSpace>& half_spaces, double min_cut,
                             ClipStats* stats)
{
    ClipStats counts;
    counts.planes = int(half_spaces.size());
    // tolerances relative to the polytope: far below a texel, far above double rounding
    const double size = polytope_size(polytope);
    const double eps = 1e-9 * size, weld_eps = 1e-7 * size;
    std::vector<Face> faces;
    for (std::size_t f = 0; f < polytope.faces.size(); ++f) {
        Face face{{}, polytope.face_normals[f]};
        for (std::uint32_t v : polytope.faces[f]) face.points.push_back(polytope.vertices[v]);
        faces.push_back(std::move(face));
    }
    for (const HalfSpace& h : half_spaces) {
        // how deep it cuts, and whether anything stays
        double deepest = -std::numeric_limits<double>::max(), lowest = std::numeric_limits<double>::max();
        for (const Face& f : faces)
            for (const glm::dvec3& p : f.points) {
                double d = glm::dot(h.normal, p) - h.offset;
                deepest = std::max(deepest, d), lowest = std::min(lowest, d);
            }
        if (faces.empty() || deepest <= std::max(eps, min_cut)) {
            ++counts.skipped;
            continue;
        }
        if (lowest >= -eps) {
            ++counts.refused;
            continue;
        }
        // clip every face, then close the cut
        std::vector<Face> clipped;
        std::vector<glm::dvec3> on_plane;
        for (const Face& f : faces) {
            Face c = clip_face(f, h, eps, on_plane);
            if (c.points.size() >= 3) clipped.push_back(std::move(c));
        }
        std::vector<glm::dvec3> cap = cap_polygon(on_plane, h.normal, weld_eps);
        if (!cap.empty()) clipped.push_back({std::move(cap), h.normal});
        faces = std::move(clipped);
        ++counts.cut;
    }
    if (stats) *stats = counts;
    return weld(faces, weld_eps);
}

double capture_texel(const ViewAtlasPackage& package)
{
    return 2.0 * double(package.half_extent()) / double(package.settings.resolution);
}

std::vector<HalfSpace> atlas_half_spaces(const ViewAtlasPackage& package)
{
    const BakeSettings& s = package.settings;
    const bool perspective = s.projection == "perspective";
    const double h = package.half_extent(), t = capture_texel(package), r = package.radius;
    const double eye = package.capture_distance();
    const glm::dvec3 c = package.center;
    std::vector<HalfSpace> out;
    // a half-space dot(n, p - c) <= offset_from_centre, n normalised
    auto add = [&out, c](glm::dvec3 n, double offset_from_centre) {
        double length = glm::length(n);
        if (!(length > 0.0)) return;
        out.push_back({n / length, (offset_from_centre + glm::dot(n, c)) / length});
    };
    for (const View& v : package.views) {
        if (v.width == 0) continue;
        const ImageRGBA8& color = package.color_pages[std::size_t(v.page)];
        const ImageRGBA8* nd = package.has_surface() ? &package.normal_depth_pages[std::size_t(v.page)] : nullptr;
        int x0 = std::numeric_limits<int>::max(), y0 = x0, x1 = -1, y1 = -1, nearest = 255;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x) {
                if (color.at(v.atlas_x + x, v.atlas_y + y)[3] == 0) continue;
                const int sx = v.crop_x + x, sy = v.crop_y + y;
                x0 = std::min(x0, sx), y0 = std::min(y0, sy), x1 = std::max(x1, sx), y1 = std::max(y1, sy);
                if (nd) nearest = std::min(nearest, int(nd->at(v.atlas_x + x, v.atlas_y + y)[3]));
            }
        if (x1 < 0) continue;
        const glm::dvec3 u = v.axis_u, w = v.axis_v, d = v.direction;
        // k_sampling_margin texels beyond the outermost covered texels' centres, on the plane through
        // the centre: a thin tip crosses the next columns between their centres
        const double m = k_sampling_margin;
        const double u_lo = -h + (x0 + 0.5 - m) * t, u_hi = -h + (x1 + 0.5 + m) * t;
        const double v_lo = -h + (y0 + 0.5 - m) * t, v_hi = -h + (y1 + 0.5 + m) * t;
        if (perspective) {
            // the plane through the capture camera (at eye along d) and the line at u0 on the centre
            // plane: eye u + u0 (d . q) <= u0 eye on the model's side
            add(eye * u + u_hi * d, u_hi * eye);
            add(-(eye * u + u_lo * d), -u_lo * eye);
            add(eye * w + v_hi * d, v_hi * eye);
            add(-(eye * w + v_lo * d), -v_lo * eye);
        } else {
            add(u, u_hi);
            add(-u, -u_lo);
            add(w, v_hi);
            add(-w, -v_lo);
        }
        // depth code k puts the surface at r - 2 r k / 255 along d (rounded to the nearest code)
        if (nd) add(d, r - 2.0 * r * nearest / 255.0 + r / 255.0 + k_sampling_margin * t);
    }
    return out;
}

ConvexPolytope source_box(const ViewAtlasPackage& package)
{
    const double t = capture_texel(package);
    const Bounds& b = package.source.bounds;
    return box_polytope(glm::dvec3(b.min) - 0.5 * t, glm::dvec3(b.max) + 0.5 * t);
}

ConvexPolytope atlas_hull(const ViewAtlasPackage& package, ClipStats* stats)
{
    return clip_polytope(source_box(package), atlas_half_spaces(package), 0.25 * capture_texel(package), stats);
}

std::vector<HalfSpace> fewest_planes(const std::vector<HalfSpace>& candidates, const ConvexPolytope& enclosing,
                                     int max_planes, double min_gain)
{
    std::vector<HalfSpace> chosen;
    std::vector<bool> taken(candidates.size(), false);
    ConvexPolytope current = enclosing;
    double area = current.surface_area();
    for (int step = 0; step < max_planes; ++step) {
        std::size_t best = candidates.size();
        ConvexPolytope best_polytope;
        double best_area = area;
        for (std::size_t c = 0; c < candidates.size(); ++c) {
            if (taken[c]) continue;
            ClipStats stats;
            ConvexPolytope clipped = clip_polytope(current, {candidates[c]}, 0.0, &stats);
            if (stats.cut == 0) {
                taken[c] = true; // cuts nothing now, so nothing later either (the polytope only shrinks)
                continue;
            }
            const double a = clipped.surface_area();
            if (a < best_area) best = c, best_area = a, best_polytope = std::move(clipped);
        }
        if (best == candidates.size() || area - best_area <= min_gain * area) break;
        current = std::move(best_polytope);
        area = best_area;
        taken[best] = true;
        chosen.push_back(candidates[best]);
    }
    return chosen;
}

std::vector<HalfSpace> proxy_planes(const std::vector<glm::vec3>& points, const std::vector<glm::vec3>& directions,
                                    const ConvexPolytope& box, double margin, int max_planes)
{
    std::vector<HalfSpace> candidates;
    for (const glm::vec3& direction : directions)
        for (double sign : {1.0, -1.0}) {
            const glm::dvec3 d = sign * glm::normalize(glm::dvec3(direction));
            double support = -std::numeric_limits<double>::max();
            for (const glm::vec3& p : points) support = std::max(support, glm::dot(d, glm::dvec3(p)));
            if (!points.empty()) candidates.push_back({d, support + margin});
        }
    return fewest_planes(candidates, box, max_planes, 0.002);
}

ConvexPolytope proxy_polytope(const ViewAtlasPackage& package, double margin)
{
    if (package.proxy_planes.empty()) return {};
    std::vector<HalfSpace> planes;
    for (const glm::vec4& p : package.proxy_planes) planes.push_back({glm::dvec3(glm::vec3(p)), double(p.w) + margin});
    return clip_polytope(source_box(package), planes, 0.0);
}

} // namespace standin::view_atlas
