// Where the image-based stand-ins look from, and how their crops share pages.
// Icosahedral directions: Saraiva et al. (§3, after Oliveira &
// Buxton's PNORMS): centres of the faces of an icosahedron subdivided k times (k = 4: 5120 views).
// Octahedral / hemi-octahedral frames: the grids of today's impostor bakers (Unreal's Impostor
// Baker, Amplify Impostors), frame centres decoded from the octahedral map.
// Packing: shelf packing of cell-aligned crops (Jylänki, "A Thousand Ways to Pack the Bin", 2010).
#include "reps/common/view_layout.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <numeric>

#include <glm/glm.hpp>

namespace standin::reps {

namespace {

using Triangle = std::array<glm::vec3, 3>;

std::vector<Triangle> icosahedron()
{
    const float p = (1.0f + std::sqrt(5.0f)) * 0.5f;
    const glm::vec3 v[12] = {{-1, p, 0}, {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                             {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    const int f[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                          {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                          {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    std::vector<Triangle> faces;
    for (const auto& face : f)
        faces.push_back({glm::normalize(v[face[0]]), glm::normalize(v[face[1]]), glm::normalize(v[face[2]])});
    return faces;
}

// rotation taking unit a to unit b (Rodrigues; a and b not opposite)
glm::mat3 rotation_between(glm::vec3 a, glm::vec3 b)
{
    glm::vec3 axis = glm::cross(a, b);
    float c = glm::dot(a, b), s = glm::length(axis);
    if (s < 1e-7f) return glm::mat3(1.0f);
    axis /= s;
    glm::mat3 k(0.0f);
    k[1][0] = -axis.z, k[2][0] = axis.y, k[0][1] = axis.z, k[2][1] = -axis.x, k[0][2] = -axis.y, k[1][2] = axis.x;
    return glm::mat3(1.0f) + s * k + (1.0f - c) * k * k;
}

std::vector<glm::vec3> icosahedral(int subdivisions)
{
    // subdivide: four triangles per triangle through the normalised edge midpoints
    std::vector<Triangle> faces = icosahedron();
    for (int level = 0; level < subdivisions; ++level) {
        std::vector<Triangle> finer;
        finer.reserve(faces.size() * 4);
        for (const Triangle& t : faces) {
            glm::vec3 a = glm::normalize(t[0] + t[1]), b = glm::normalize(t[1] + t[2]), c = glm::normalize(t[2] + t[0]);
            finer.push_back({t[0], a, c});
            finer.push_back({a, t[1], b});
            finer.push_back({c, b, t[2]});
            finer.push_back({a, b, c});
        }
        faces = std::move(finer);
    }
    // rotate so that the centre of original face 1 (0, 5, 1), the one at the top, is +Y: the
    // central sub-face of an original face keeps its centre, so +Y and -Y are captured views
    const Triangle top = icosahedron()[1];
    glm::mat3 rotation = rotation_between(glm::normalize(top[0] + top[1] + top[2]), glm::vec3(0, 1, 0));
    std::vector<glm::vec3> directions;
    directions.reserve(faces.size());
    for (const Triangle& t : faces) directions.push_back(glm::normalize(rotation * glm::normalize(t[0] + t[1] + t[2])));
    return directions;
}

glm::vec3 octahedral_direction(glm::vec2 e) // e in [-1, 1]^2, +Y up
{
    glm::vec3 n(e.x, 1.0f - std::abs(e.x) - std::abs(e.y), e.y);
    if (n.y < 0.0f) {
        float x = n.x, z = n.z;
        n.x = (1.0f - std::abs(z)) * (x >= 0.0f ? 1.0f : -1.0f);
        n.z = (1.0f - std::abs(x)) * (z >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::normalize(n);
}

glm::vec3 hemi_octahedral_direction(glm::vec2 e) // the square turned 45 degrees onto the upper diamond
{
    float a = 0.5f * (e.x + e.y), b = 0.5f * (e.y - e.x);
    return glm::normalize(glm::vec3(a, 1.0f - std::abs(a) - std::abs(b), b));
}

} // namespace

std::vector<glm::vec3> layout_directions(const std::string& layout, int subdivisions, int frames)
{
    if (layout == "icosahedral") return icosahedral(subdivisions);
    std::vector<glm::vec3> directions;
    for (int j = 0; j < frames; ++j) {
        for (int i = 0; i < frames; ++i) {
            glm::vec2 e((float(i) + 0.5f) / float(frames) * 2.0f - 1.0f, (float(j) + 0.5f) / float(frames) * 2.0f - 1.0f);
            directions.push_back(layout == "octahedral" ? octahedral_direction(e) : hemi_octahedral_direction(e));
        }
    }
    return directions;
}

glm::vec3 grid_decode(const std::string& layout, float ex, float ey)
{
    return layout == "hemi-octahedral" ? hemi_octahedral_direction({ex, ey}) : octahedral_direction({ex, ey});
}

void grid_encode(const std::string& layout, glm::vec3 d, float& ex, float& ey)
{
    if (layout == "hemi-octahedral") d.y = std::max(d.y, 0.0f);
    float l1 = std::abs(d.x) + std::abs(d.y) + std::abs(d.z);
    glm::vec3 p = l1 > 0.0f ? d / l1 : glm::vec3(0.0f, 1.0f, 0.0f);
    if (layout == "hemi-octahedral") {
        // the inverse of hemi_octahedral_direction: (a, b) = (p.x, p.z) turned back by 45 degrees
        ex = p.x - p.z;
        ey = p.x + p.z;
        return;
    }
    if (p.y >= 0.0f) {
        ex = p.x;
        ey = p.z;
    } else {
        ex = (1.0f - std::abs(p.z)) * (p.x >= 0.0f ? 1.0f : -1.0f);
        ey = (1.0f - std::abs(p.x)) * (p.z >= 0.0f ? 1.0f : -1.0f);
    }
}

void grid_frame(const std::string& layout, int frames, glm::vec3 direction, int& i, int& j)
{
    float ex = 0.0f, ey = 0.0f;
    grid_encode(layout, direction, ex, ey);
    i = std::clamp(int(std::floor((ex * 0.5f + 0.5f) * float(frames))), 0, frames - 1);
    j = std::clamp(int(std::floor((ey * 0.5f + 0.5f) * float(frames))), 0, frames - 1);
}

int pack_views(std::vector<View>& views, int page_size)
{
    assert(page_size % k_cell == 0);
    std::vector<std::size_t> order(views.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return views[a].height > views[b].height; });
    int page = 0, x = 0, y = 0, shelf = 0, pages = 0;
    for (std::size_t index : order) {
        View& v = views[index];
        assert(v.width % k_cell == 0 && v.height % k_cell == 0 && v.width <= page_size && v.height <= page_size);
        if (v.width == 0 || v.height == 0) {
            v.page = v.atlas_x = v.atlas_y = 0;
            continue;
        }
        if (x + v.width > page_size) { // next shelf
            x = 0;
            y += shelf;
            shelf = 0;
        }
        if (y + v.height > page_size) { // next page
            ++page;
            x = y = shelf = 0;
        }
        v.page = page;
        v.atlas_x = x;
        v.atlas_y = y;
        x += v.width;
        shelf = std::max(shelf, v.height);
        pages = page + 1;
    }
    return pages;
}

} // namespace standin::reps
