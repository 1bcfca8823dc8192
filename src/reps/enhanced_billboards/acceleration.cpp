// Height-field acceleration for the enhanced-billboard ray march, built at load time.
// Level 0 links neighbouring texels that continue one surface (the depth map is a sheet, not a
// solid: a jump larger than the local slope allows is an edge, and the ray passes it). Levels
// above hold min/max depth over 2^k x 2^k texels, traversed hierarchically as in Tevs, Ihrke &
// Seidel, "Maximum Mipmaps for Fast, Accurate, and Scalable Dynamic Height Field Rendering",
// I3D 2008, with uncovered texels empty (Baboud & Decoret, GI 2006, for relief boxes of a closed
// object).
#include "reps/enhanced_billboards/acceleration.h"

#include "reps/common/shaders/height_field.h"
#include "reps/enhanced_billboards/shaders/billboard_layout.glsl"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace standin::billboards {

// the stored shading normal of a texel, decoded
static glm::vec3 texel_normal(const Billboard& billboard, int i, int j)
{
    return reps::decode_normal(billboard.normal_depth.at(i, j));
}

// one texel of the billboard's plane in depth codes
static float texel_depth_codes(const Billboard& b)
{
    return b.texel_size * reps::k_depth_codes / std::max(b.depth_range, 1e-30f);
}

// How much of a tilted top's reach past its texel's depth a texel's range holds (build_acceleration),
// where its links do not: the march ends a top at the range, so an outline texel's top stops short
// of where a slope capped at HF_TOP_MAX_SLOPE would stand out of a surface curving away. Measured with
// tops tilted by their normals (thesis protocol, BCN_Epileptic / 2CylinderEngine Luv, BCN holes and
// spill): 0 1.563 / 1.320, 0.011% / 0.97%; 0.25 1.547 / 1.217, 0.009% / 1.08%; 0.5 1.577 / 1.251,
// 0.008% / 1.16%; the whole reach 1.656 / 1.330, 0.007% / 1.30% (by the depths, at 0.25: 1.455 /
// 1.310, 0.007% / 0.95%).
constexpr float k_top_reach_fraction = 0.25f;

bool texels_linked(const Billboard& b, int i, int j, int axis, float quantum_codes)
{
    const int ni = i + (axis == 0 ? 1 : 0), nj = j + (axis == 0 ? 0 : 1);
    const glm::vec3 along = axis == 0 ? b.axis_u : b.axis_v;
    float codes_per_world = reps::k_depth_codes / std::max(b.depth_range, 1e-30f);
    float jump = float(b.normal_depth.at(i, j)[3]) - float(b.normal_depth.at(ni, nj)[3]);
    return reps::hf_linked(jump, texel_normal(b, i, j), texel_normal(b, ni, nj), along, b.direction,
                           b.texel_size, codes_per_world, quantum_codes);
}

// Whether covered texels (i, j) and its +axis neighbour continue one plane: the step between them
// is within HF_MAX_SLOPE texels and repeats, within the curvature allowance, on a covered texel
// just before or just after them. The link rule judges a step by the stored normals, which are
// shading normals: on a low-poly model smoothed across its edges a flat face seen steeply stores
// normals that call it far less steep than its depths are (assimp's minigun.MDL: a ring's face at
// 20 degrees from a billboard's plane, its normals at 35), its texels' steps exceed what they allow
// every other row, and rays from other directions slipped between the unlinked texels (stripes of
// holes, 0.8% of the pictures without the coarse mesh). Depths that change at one rate are one
// surface whatever its normals say.
static bool texels_continue_plane(const Billboard& b, const HeightFieldAcceleration& acc, int i, int j, int axis,
                                  float texel_codes, float quantum_codes)
{
    const int di = axis == 0 ? 1 : 0, dj = axis == 0 ? 0 : 1;
    auto covered = [&](int x, int y) {
        return x >= 0 && y >= 0 && x < b.width && y < b.height &&
               (acc.surface[std::size_t(y) * acc.width + x].flags & k_texel_covered) != 0;
    };
    auto depth = [&](int x, int y) { return float(b.normal_depth.at(x, y)[3]); };
    const float step = depth(i + di, j + dj) - depth(i, j);
    if (std::abs(step) > float(HF_MAX_SLOPE) * texel_codes) return false;
    const float tolerance = float(HF_CURVATURE_TEXELS) * texel_codes + float(HF_QUANTA) * quantum_codes;
    if (covered(i - di, j - dj) && std::abs(depth(i, j) - depth(i - di, j - dj) - step) <= tolerance) return true;
    return covered(i + 2 * di, j + 2 * dj) && std::abs(depth(i + 2 * di, j + 2 * dj) - depth(i + di, j + dj) - step) <= tolerance;
}

// links of every covered texel to its covered neighbours on the same surface
static void link_neighbours(const Billboard& b, const LinkSettings& settings, HeightFieldAcceleration& acc)
{
    float quantum_codes = settings.depth_bits >= 16 ? 1.0f : reps::k_depth_codes / float((1 << settings.depth_bits) - 1);
    const float texel_codes = texel_depth_codes(b);
    auto at = [&](int i, int j) -> SurfaceTexel& { return acc.surface[std::size_t(j) * acc.width + i]; };
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            SurfaceTexel& texel = at(i, j);
            if (!(texel.flags & k_texel_covered)) continue;
            const int di[2] = {1, 0}, dj[2] = {0, 1};
            const std::uint16_t bit_here[2] = {k_link_plus_u, k_link_plus_v};
            const std::uint16_t bit_there[2] = {k_link_minus_u, k_link_minus_v};
            for (int k = 0; k < 2; ++k) {
                int ni = i + di[k], nj = j + dj[k];
                if (ni >= b.width || nj >= b.height) continue;
                SurfaceTexel& other = at(ni, nj);
                if (!(other.flags & k_texel_covered)) continue;
                if (!texels_linked(b, i, j, k, quantum_codes) && !texels_continue_plane(b, acc, i, j, k, texel_codes, quantum_codes))
                    continue;
                texel.flags |= bit_here[k];
                other.flags |= bit_there[k];
                // a crease (two parts meeting, two leaves touching) is where the truth's colour
                // changes without filtering: colour is averaged across smooth links only
                if (glm::dot(texel_normal(b, i, j), texel_normal(b, ni, nj)) >= k_smooth_link_cos) {
                    texel.flags |= std::uint16_t(bit_here[k] << k_smooth_link_shift);
                    other.flags |= std::uint16_t(bit_there[k] << k_smooth_link_shift);
                }
            }
        }
    }
}

HeightFieldAcceleration build_acceleration(const Billboard& b, int padded_width, int padded_height, int levels,
                                           const LinkSettings& settings)
{
    assert(padded_width >= b.width && padded_height >= b.height);
    assert(padded_width % (1 << levels) == 0 && padded_height % (1 << levels) == 0);
    HeightFieldAcceleration acc;
    acc.width = padded_width;
    acc.height = padded_height;
    acc.levels = levels;
    acc.surface.assign(std::size_t(padded_width) * padded_height, SurfaceTexel{});

    // level 0: depth and coverage
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            SurfaceTexel& texel = acc.surface[std::size_t(j) * padded_width + i];
            if (b.color.at(i, j)[3] == 0) continue;
            texel.depth = b.normal_depth.at(i, j)[3];
            texel.flags = k_texel_covered;
            std::uint8_t alpha = b.color.at(i, j)[3];
            if (settings.edge_lines && alpha < 255) {
                texel.flags |= k_texel_clipped;
                texel.edge_line = std::uint8_t(alpha - EDGE_LINE_FIRST_CODE + 1);
            }
        }
    }

    // links between texels of one surface, then each texel's range over itself and its links
    link_neighbours(b, settings, acc);
    const float texel_codes = texel_depth_codes(b);
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            SurfaceTexel& texel = acc.surface[std::size_t(j) * padded_width + i];
            if (!(texel.flags & k_texel_covered)) continue;
            texel.min = texel.max = texel.depth;
            // the top's tilt: the depth differences to its linked neighbours (central where it
            // has both, one-sided at an edge, flat where it has none), capped at HF_TOP_MAX_SLOPE.
            // Not its stored normal, as the view atlas's tops: a normal map's or a low-poly
            // model's smoothed normals are shading, not geometry (a normal-mapped square's tilted
            // tops cost CIEDE2000 0.1 -> 8.0), and from the depths BCN_Epileptic read Luv 1.455
            // against 1.547 by its normals (the engine 1.310 against 1.217; docs/RESULTS.md)
            auto depth_at = [&](int x, int y) { return float(acc.surface[std::size_t(y) * padded_width + x].depth); };
            auto step_along = [&](std::uint16_t minus, std::uint16_t plus, int di, int dj) {
                bool before = texel.flags & minus, after = texel.flags & plus;
                if (before && after) return 0.5f * (depth_at(i + di, j + dj) - depth_at(i - di, j - dj));
                if (after) return depth_at(i + di, j + dj) - float(texel.depth);
                if (before) return float(texel.depth) - depth_at(i - di, j - dj);
                return 0.0f;
            };
            glm::vec2 step(step_along(k_link_minus_u, k_link_plus_u, 1, 0), step_along(k_link_minus_v, k_link_plus_v, 0, 1));
            texel.slope = glm::clamp(step / texel_codes, glm::vec2(-float(HF_TOP_MAX_SLOPE)), glm::vec2(float(HF_TOP_MAX_SLOPE)));
            auto include = [&](std::uint16_t bit, int ni, int nj) {
                if (!(texel.flags & bit)) return;
                std::uint16_t d = acc.surface[std::size_t(nj) * padded_width + ni].depth;
                texel.min = std::min(texel.min, d);
                texel.max = std::max(texel.max, d);
            };
            include(k_link_minus_u, i - 1, j);
            include(k_link_plus_u, i + 1, j);
            include(k_link_minus_v, i, j - 1);
            include(k_link_plus_v, i, j + 1);
            // and a part of the texel's own tilted top, whose corners reach half its tilt above
            // and below its depth: the march ends a top at the range (march.frag), and every proxy
            // box and the pyramid hold the range
            int reach = int(std::ceil(k_top_reach_fraction * 0.5f * (std::abs(texel.slope.x) + std::abs(texel.slope.y)) * texel_codes));
            texel.min = std::uint16_t(std::max(0, int(texel.min) - reach));
            texel.max = std::uint16_t(std::min(65535, int(texel.max) + reach));
        }
    }

    // min/max pyramid over the ranges (uncovered texels are empty: [65535, 0])
    int w = padded_width, h = padded_height;
    std::vector<MinMax> below(acc.surface.size());
    for (std::size_t k = 0; k < below.size(); ++k) below[k] = {acc.surface[k].min, acc.surface[k].max};
    for (int level = 1; level <= levels; ++level) {
        int lw = w / 2, lh = h / 2;
        std::vector<MinMax> here(std::size_t(lw) * lh);
        for (int j = 0; j < lh; ++j) {
            for (int i = 0; i < lw; ++i) {
                MinMax m;
                for (int c = 0; c < 4; ++c) {
                    const MinMax& child = below[std::size_t(2 * j + (c >> 1)) * w + 2 * i + (c & 1)];
                    m.min = std::min(m.min, child.min);
                    m.max = std::max(m.max, child.max);
                }
                here[std::size_t(j) * lw + i] = m;
            }
        }
        acc.pyramid.push_back(here);
        below = std::move(here);
        w = lw;
        h = lh;
    }
    return acc;
}

std::vector<std::uint16_t> pack_surface(const HeightFieldAcceleration& acc, int& range_unit)
{
    int widest = 0;
    for (const SurfaceTexel& t : acc.surface)
        if (t.flags & k_texel_covered) widest = std::max({widest, int(t.depth) - int(t.min), int(t.max) - int(t.depth)});
    range_unit = std::max(1, (widest + 254) / 255);
    auto quantise_slope = [](float slope) {
        return std::uint16_t(std::lround(slope / float(HF_TOP_MAX_SLOPE) * 127.0f) + 128);
    };
    std::vector<std::uint16_t> packed(acc.surface.size() * 4, 0);
    for (std::size_t k = 0; k < acc.surface.size(); ++k) {
        const SurfaceTexel& t = acc.surface[k];
        std::uint16_t* out = &packed[4 * k];
        out[0] = t.depth;
        out[3] = std::uint16_t((t.flags & ~k_texel_clipped) | ((t.edge_line & 1u) << TEXEL_LINE_LOW_BIT) |
                               ((t.edge_line >> 1) << TEXEL_LINE_HIGH_SHIFT));
        if (!(t.flags & k_texel_covered)) continue;
        int below = (int(t.depth) - int(t.min) + range_unit - 1) / range_unit;
        int above = (int(t.max) - int(t.depth) + range_unit - 1) / range_unit;
        out[1] = std::uint16_t(below | (above << 8));
        out[2] = std::uint16_t(quantise_slope(t.slope.x) | (quantise_slope(t.slope.y) << 8));
    }
    return packed;
}

// Built bottom up: a cell is one surface when its non-empty children are (level 0: a covered
// texel is), every two covered texels facing each other across the seams between its children are
// linked smoothly (k_smooth_*), and those links join the non-empty children into one group.
std::vector<std::vector<std::uint8_t>> build_color_pyramid(const Billboard& b, const HeightFieldAcceleration& acc)
{
    struct Cell {
        std::uint64_t sum[3] = {0, 0, 0};
        std::uint64_t count = 0;
        bool one_surface = false;
    };
    const int w0 = acc.width;
    auto surface = [&](int i, int j) -> const SurfaceTexel& { return acc.surface[std::size_t(j) * w0 + i]; };
    std::vector<Cell> below(acc.surface.size());
    for (int j = 0; j < b.height; ++j) {
        for (int i = 0; i < b.width; ++i) {
            if (!(surface(i, j).flags & k_texel_covered)) continue;
            Cell& c = below[std::size_t(j) * w0 + i];
            const std::uint8_t* rgba = b.color.at(i, j);
            for (int k = 0; k < 3; ++k) c.sum[k] = rgba[k];
            c.count = 1;
            c.one_surface = true;
        }
    }
    std::vector<std::vector<std::uint8_t>> levels;
    int w = acc.width, h = acc.height;
    for (int level = 1; level <= acc.levels; ++level) {
        const int lw = w / 2, lh = h / 2, size = 1 << level, half = size / 2;
        std::vector<Cell> here(std::size_t(lw) * lh);
        std::vector<std::uint8_t> rgba(std::size_t(lw) * lh * 4, 0);
        for (int cj = 0; cj < lh; ++cj) {
            for (int ci = 0; ci < lw; ++ci) {
                Cell& cell = here[std::size_t(cj) * lw + ci];
                const Cell* child[4];
                bool one = true;
                int groups[4] = {0, 1, 2, 3}; // children 0 1 / 2 3; union by smallest index
                for (int c = 0; c < 4; ++c) {
                    child[c] = &below[std::size_t(2 * cj + (c >> 1)) * w + 2 * ci + (c & 1)];
                    for (int k = 0; k < 3; ++k) cell.sum[k] += child[c]->sum[k];
                    cell.count += child[c]->count;
                    if (child[c]->count > 0 && !child[c]->one_surface) one = false;
                }
                // the seams: between children a and b (b right of or below a), texel pairs along them
                const int x0 = ci * size, y0 = cj * size;
                auto seam = [&](int a, int bc, bool vertical) {
                    bool joined = false;
                    for (int s = 0; s < half && one; ++s) {
                        int i, j;
                        if (vertical) { // a left of bc: pairs (x0 + half - 1, y) - (x0 + half, y)
                            i = x0 + half - 1;
                            j = y0 + (a >> 1) * half + s;
                        } else { // a above bc
                            i = x0 + (a & 1) * half + s;
                            j = y0 + half - 1;
                        }
                        const SurfaceTexel& t = surface(i, j);
                        const SurfaceTexel& u = vertical ? surface(i + 1, j) : surface(i, j + 1);
                        if (!(t.flags & k_texel_covered) || !(u.flags & k_texel_covered)) continue;
                        if (t.flags & (vertical ? k_smooth_plus_u : k_smooth_plus_v)) joined = true;
                        else one = false; // a step between surfaces inside the cell
                    }
                    if (joined) {
                        int ga = groups[a], gb = groups[bc], g = std::min(ga, gb);
                        for (int& x : groups)
                            if (x == ga || x == gb) x = g;
                    }
                };
                seam(0, 1, true);
                seam(2, 3, true);
                seam(0, 2, false);
                seam(1, 3, false);
                int group = -1;
                for (int c = 0; c < 4 && one; ++c) {
                    if (child[c]->count == 0) continue;
                    if (group < 0) group = groups[c];
                    else if (groups[c] != group) one = false;
                }
                cell.one_surface = one && cell.count > 0;
                std::uint8_t* out = &rgba[(std::size_t(cj) * lw + ci) * 4];
                if (cell.count > 0) {
                    for (int k = 0; k < 3; ++k) out[k] = std::uint8_t((cell.sum[k] + cell.count / 2) / cell.count);
                    out[3] = cell.one_surface ? 255 : 0;
                }
            }
        }
        levels.push_back(std::move(rgba));
        below = std::move(here);
        w = lw;
        h = lh;
    }
    return levels;
}

// The sheared box of a tile (TileBox::slope): a least-squares plane through the texels' depths at
// their centres (doubles, fixed order: deterministic), then the offsets that hold every column from
// its min to its max over its whole square (the plane is linear: its extremes over a square are at
// the corners). A flat tile gets slope 0 and the plain box.
// In a layer of a tile: a covered texel whose range starts within the layer's depths.
static bool in_layer(const SurfaceTexel& texel, const TileBox& box)
{
    return (texel.flags & k_texel_covered) && texel.min >= box.depth_min && texel.min <= box.depth_max;
}

static void fit_tile_plane(const HeightFieldAcceleration& acc, TileBox& box)
{
    double n = 0, sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, syy = 0, sxz = 0, syz = 0;
    for (int j = box.texel_min.y; j < box.texel_max.y; ++j) {
        for (int i = box.texel_min.x; i < box.texel_max.x; ++i) {
            const SurfaceTexel& texel = acc.surface[std::size_t(j) * acc.width + i];
            if (!in_layer(texel, box)) continue;
            // centred on the box so the normal equations stay well conditioned
            double x = i + 0.5 - box.texel_min.x, y = j + 0.5 - box.texel_min.y, z = texel.depth / double(HF_DEPTH_CODES);
            n += 1;
            sx += x;
            sy += y;
            sz += z;
            sxx += x * x;
            sxy += x * y;
            syy += y * y;
            sxz += x * z;
            syz += y * z;
        }
    }
    glm::dvec2 slope(0.0);
    double cxx = sxx - sx * sx / n, cxy = sxy - sx * sy / n, cyy = syy - sy * sy / n;
    double cxz = sxz - sx * sz / n, cyz = syz - sy * sz / n;
    double det = cxx * cyy - cxy * cxy;
    if (n >= 3 && det > 1e-9 * std::max(1.0, cxx * cyy)) slope = glm::dvec2(cyy * cxz - cxy * cyz, cxx * cyz - cxy * cxz) / det;
    box.slope = glm::vec2(slope);
    glm::dvec2 s(box.slope); // the plane the renderer evaluates, in the precision it has
    double lo = 1e30, hi = -1e30;
    double plain_lo = box.depth_min / double(HF_DEPTH_CODES), plain_hi = box.depth_max / double(HF_DEPTH_CODES);
    for (int j = box.texel_min.y; j < box.texel_max.y; ++j) {
        for (int i = box.texel_min.x; i < box.texel_max.x; ++i) {
            const SurfaceTexel& texel = acc.surface[std::size_t(j) * acc.width + i];
            if (!in_layer(texel, box)) continue;
            double z_min = texel.min / double(HF_DEPTH_CODES), z_max = texel.max / double(HF_DEPTH_CODES);
            for (int c = 0; c < 4; ++c) {
                double plane = s.x * double(i + (c & 1)) + s.y * double(j + (c >> 1));
                lo = std::min(lo, z_min - plane);
                hi = std::max(hi, z_max - plane);
            }
        }
    }
    if (hi - lo >= plain_hi - plain_lo) {
        // two surfaces at different depths tilt the fit: the plain box is tighter
        box.slope = glm::vec2(0.0f);
        lo = plain_lo;
        hi = plain_hi;
    }
    box.offset_min = float(lo);
    box.offset_max = float(hi);
}

std::vector<TileBox> build_tiles(const HeightFieldAcceleration& acc, int tile_size, int layer_gap)
{
    assert(tile_size > 0 && (tile_size & (tile_size - 1)) == 0);
    std::vector<TileBox> tiles;
    std::vector<MinMax> ranges;
    for (int tj = 0; tj < acc.height; tj += tile_size) {
        for (int ti = 0; ti < acc.width; ti += tile_size) {
            // the depth ranges of the tile's covered texels, merged where they overlap or lie
            // within layer_gap of each other: each merged range is a layer of the tile
            ranges.clear();
            for (int j = tj; j < std::min(tj + tile_size, acc.height); ++j)
                for (int i = ti; i < std::min(ti + tile_size, acc.width); ++i) {
                    const SurfaceTexel& texel = acc.surface[std::size_t(j) * acc.width + i];
                    if (texel.flags & k_texel_covered) ranges.push_back({texel.min, texel.max});
                }
            if (ranges.empty()) continue;
            std::sort(ranges.begin(), ranges.end(), [](MinMax a, MinMax b) { return a.min != b.min ? a.min < b.min : a.max < b.max; });
            std::vector<MinMax> layers{ranges.front()};
            for (const MinMax& r : ranges) {
                if (int(r.min) <= int(layers.back().max) + layer_gap) layers.back().max = std::max(layers.back().max, r.max);
                else layers.push_back(r);
            }
            // at most k_max_tile_layers: the narrowest gaps close first
            while (layers.size() > std::size_t(k_max_tile_layers)) {
                std::size_t narrowest = 1;
                for (std::size_t k = 2; k < layers.size(); ++k)
                    if (layers[k].min - layers[k - 1].max < layers[narrowest].min - layers[narrowest - 1].max) narrowest = k;
                layers[narrowest - 1].max = std::max(layers[narrowest - 1].max, layers[narrowest].max);
                layers.erase(layers.begin() + std::ptrdiff_t(narrowest));
            }
            for (const MinMax& layer : layers) {
                // the bounds of the layer's texels and of their ranges
                TileBox box;
                box.texel_min = glm::ivec2(ti + tile_size, tj + tile_size);
                box.texel_max = glm::ivec2(ti, tj);
                box.depth_min = layer.min;
                box.depth_max = layer.max;
                for (int j = tj; j < std::min(tj + tile_size, acc.height); ++j)
                    for (int i = ti; i < std::min(ti + tile_size, acc.width); ++i)
                        if (in_layer(acc.surface[std::size_t(j) * acc.width + i], box)) {
                            box.texel_min = glm::min(box.texel_min, glm::ivec2(i, j));
                            box.texel_max = glm::max(box.texel_max, glm::ivec2(i + 1, j + 1));
                        }
                fit_tile_plane(acc, box);
                tiles.push_back(box);
            }
        }
    }
    return tiles;
}

// Shelves (pack_layers): billboards sorted by height, tallest first, each into the first shelf of
// any layer with room, else a new shelf under the last one of the first layer with room, else a
// new layer.
static LayerPacking pack_shelves(const std::vector<glm::ivec2>& sizes, const std::vector<std::size_t>& order,
                                 int width, int height)
{
    struct Shelf {
        int layer, y, height, used;
    };
    LayerPacking packing;
    packing.width = width, packing.height = height;
    packing.placements.resize(sizes.size());
    std::vector<Shelf> shelves;
    std::vector<int> layer_top; // where the next shelf of each layer starts
    for (std::size_t k : order) {
        const glm::ivec2 size = sizes[k];
        bool placed = false;
        for (Shelf& shelf : shelves)
            if (size.y <= shelf.height && shelf.used + size.x <= width) {
                packing.placements[k] = {shelf.layer, {shelf.used, shelf.y}};
                shelf.used += size.x;
                placed = true;
                break;
            }
        for (int layer = 0; !placed && layer < int(layer_top.size()); ++layer)
            if (layer_top[std::size_t(layer)] + size.y <= height) {
                shelves.push_back({layer, layer_top[std::size_t(layer)], size.y, size.x});
                packing.placements[k] = {layer, {0, layer_top[std::size_t(layer)]}};
                layer_top[std::size_t(layer)] += size.y;
                placed = true;
            }
        if (!placed) {
            const int layer = int(layer_top.size());
            layer_top.push_back(size.y);
            shelves.push_back({layer, 0, size.y, size.x});
            packing.placements[k] = {layer, {0, 0}};
        }
    }
    packing.layers = int(layer_top.size());
    return packing;
}

LayerPacking pack_layers(const std::vector<glm::ivec2>& sizes, int cell, int max_side)
{
    auto align = [cell](int v) { return std::max(cell, (v + cell - 1) / cell * cell); };
    std::vector<glm::ivec2> aligned;
    glm::ivec2 largest(cell);
    for (glm::ivec2 s : sizes) {
        aligned.push_back({align(s.x), align(s.y)});
        largest = glm::max(largest, aligned.back());
    }
    std::vector<std::size_t> order(sizes.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return aligned[a].y > aligned[b].y; });
    LayerPacking best = pack_shelves(aligned, order, largest.x, largest.y);
    // layers of 1 to 4 times the largest billboard along each side, within the GPU's limit
    for (int nx = 1; nx <= 4; ++nx)
        for (int ny = 1; ny <= 4; ++ny) {
            const int w = align(largest.x * nx / 2 + largest.x / 2), h = align(largest.y * ny / 2 + largest.y / 2);
            if (w > max_side || h > max_side) continue;
            LayerPacking candidate = pack_shelves(aligned, order, w, h);
            const auto texels = [](const LayerPacking& p) { return std::int64_t(p.width) * p.height * p.layers; };
            if (texels(candidate) < texels(best)) best = std::move(candidate);
        }
    return best;
}

GpuLayout gpu_layout(const std::vector<Billboard>& billboards, int max_side)
{
    int max_width = 1, max_height = 1;
    std::vector<glm::ivec2> sizes;
    for (const Billboard& b : billboards) {
        max_width = std::max(max_width, b.width);
        max_height = std::max(max_height, b.height);
        sizes.push_back({b.width, b.height});
    }
    GpuLayout layout;
    while (layout.levels < k_max_pyramid_levels && (1 << layout.levels) < std::max(max_width, max_height)) ++layout.levels;
    layout.packing = pack_layers(sizes, 1 << layout.levels, max_side);
    return layout;
}

std::uint64_t gpu_texture_bytes(const GpuLayout& layout, bool pbr)
{
    const LayerPacking& p = layout.packing;
    const std::uint64_t texels = std::uint64_t(p.width) * std::uint64_t(p.height) * std::uint64_t(p.layers);
    std::uint64_t bytes = texels * (4 + 4 + 8) + (pbr ? texels * 8 : 0);
    for (int level = 1; level <= layout.levels; ++level)
        bytes += std::uint64_t(p.width >> level) * std::uint64_t(p.height >> level) * std::uint64_t(p.layers) * (4 + 4);
    return bytes;
}

bool has_pbr_maps(const std::vector<Billboard>& billboards)
{
    return !billboards.empty() && std::all_of(billboards.begin(), billboards.end(), [](const Billboard& b) {
        return !b.orm.empty() && !b.emission.empty();
    });
}

} // namespace standin::billboards
