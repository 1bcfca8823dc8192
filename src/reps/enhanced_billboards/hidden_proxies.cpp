// Hidden proxies by view direction (hidden_proxies.h).
#include "reps/enhanced_billboards/hidden_proxies.h"

#include "reps/common/block_compress.h"
#include "reps/common/surface_image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace standin::billboards {

namespace {

// Depth-buffer pixels this many texels wide: about the texels' size on screen at
// distance 1 (a model's diagonal of 512-1024 texels over about 600 pixels of 800x600), so a gap
// the screen shows is mostly one the buffer shows.
constexpr float k_pixel_texels = 2.0f;
constexpr int k_max_resolution = 1024;
// What lies within this many pixels behind its 3 x 3 neighbourhood's farthest nearest depth counts
// as visible: squares are flat at their texel's depth, the march meets tilted tops and walls.
constexpr float k_depth_tolerance_pixels = 2.0f;
// Where back-facing texels see through, a texel hides only if its normal faces the eye by more
// than this (grazing ones may be either).
constexpr float k_front_facing_cos = -0.05f;

constexpr std::uint16_t k_block_hides = 1u << 14;
// Blocks are kept by groups of this many texels square (2 x 2 depth-buffer pixels), each with its
// extent, so that a tile partly in front is tested a group at a time.
constexpr int k_group_texels = 4;

void set_proxy_bit(std::vector<std::uint64_t>& bits, std::size_t k) { bits[k >> 6] |= std::uint64_t(1) << (k & 63); }
bool has_proxy_bit(const std::vector<std::uint64_t>& bits, std::size_t k) { return (bits[k >> 6] >> (k & 63)) & 1u; }

bool in_box_layer(const SurfaceTexel& texel, const TileBox& box)
{
    return (texel.flags & k_texel_covered) && texel.min >= box.depth_min && texel.min <= box.depth_max;
}

// Cut boxes (HiddenProxies::cut_box): a rectangle and a range of z about a plane of slope `slope`
// growing to hold fine box f, whose z about it over f's rectangle is f's own range plus the planes'
// difference at f's corners (both planes are linear); the volume of one, 0 when empty.
HiddenProxies::Cut cut_empty()
{
    return {glm::ivec2(std::numeric_limits<int>::max()), glm::ivec2(std::numeric_limits<int>::min()),
            std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
}

void cut_add(HiddenProxies::Cut& c, const TileBox& f, glm::vec2 slope)
{
    const glm::vec2 ds = f.slope - slope;
    const float x0 = ds.x * float(f.texel_min.x), x1 = ds.x * float(f.texel_max.x);
    const float y0 = ds.y * float(f.texel_min.y), y1 = ds.y * float(f.texel_max.y);
    c.texel_min = glm::min(c.texel_min, f.texel_min), c.texel_max = glm::max(c.texel_max, f.texel_max);
    c.offset_min = std::min(c.offset_min, f.offset_min + std::min(x0, x1) + std::min(y0, y1));
    c.offset_max = std::max(c.offset_max, f.offset_max + std::max(x0, x1) + std::max(y0, y1));
}

double cut_volume(const HiddenProxies::Cut& c)
{
    if (c.texel_min.x >= c.texel_max.x || c.texel_min.y >= c.texel_max.y || !(c.offset_min <= c.offset_max)) return 0.0;
    return double(c.texel_max.x - c.texel_min.x) * double(c.texel_max.y - c.texel_min.y) * std::max(double(c.offset_max - c.offset_min), 1e-4);
}

} // namespace

void HiddenProxies::grow(Extent& e, const Block& b)
{
    e.i0 = std::min(e.i0, b.i), e.j0 = std::min(e.j0, b.j), e.i1 = std::max(e.i1, b.i), e.j1 = std::max(e.j1, b.j);
    e.depth0 = std::min(e.depth0, reps::decode_depth(b.depth)), e.depth1 = std::max(e.depth1, reps::decode_depth(b.depth));
}

void HiddenProxies::grow(Extent& e, const Extent& other)
{
    e.i0 = std::min(e.i0, other.i0), e.j0 = std::min(e.j0, other.j0), e.i1 = std::max(e.i1, other.i1), e.j1 = std::max(e.j1, other.j1);
    e.depth0 = std::min(e.depth0, other.depth0), e.depth1 = std::max(e.depth1, other.depth1);
}

void HiddenProxies::add_billboard(const Billboard& b, const HeightFieldAcceleration& acc, const Level& fine,
                                  const Level& coarse)
{
    Frame frame{b.origin, b.axis_u * b.texel_size, b.axis_v * b.texel_size, b.direction * b.depth_range};
    frame.first_fine = fine.first;
    frame.end_fine = fine.first + std::uint32_t(fine.boxes.size());
    const std::uint32_t billboard = std::uint32_t(frames_.size());
    frames_.push_back(frame);
    const int width = std::min(b.width, acc.width), height = std::min(b.height, acc.height);
    auto texel_at = [&](int i, int j) -> const SurfaceTexel& {
        return acc.surface[std::size_t(j) * std::size_t(acc.width) + std::size_t(i)];
    };
    if (fine_blocks_.empty()) fine_blocks_.push_back(0), fine_groups_.push_back(0);
    for (const TileBox& box : fine.boxes) {
        // the tile's blocks by groups of k_group_texels x k_group_texels texels, each with its extent
        Extent tile = empty_extent();
        const int i_end = std::min(box.texel_max.x, width), j_end = std::min(box.texel_max.y, height);
        for (int group_j = box.texel_min.y; group_j < j_end; group_j += k_group_texels)
            for (int group_i = box.texel_min.x; group_i < i_end; group_i += k_group_texels) {
                Group group{empty_extent(), std::uint32_t(blocks_.size()), 0};
                for (int j = group_j; j < std::min(group_j + k_group_texels, j_end); ++j)
                    for (int i = group_i; i < std::min(group_i + k_group_texels, i_end); ++i) {
                        const SurfaceTexel& t = texel_at(i, j);
                        if (!in_box_layer(t, box)) continue;
                        Block block{std::uint16_t(i), std::uint16_t(j), t.depth, 0};
                        const std::uint16_t* n = &b.normal_depth.pixels[(std::size_t(j) * std::size_t(b.width) + std::size_t(i)) * 4];
                        const glm::vec2 e = glm::clamp(reps::octahedral_encode(glm::vec3(n[0], n[1], n[2]) / 32767.5f - 1.0f), 0.0f, 1.0f);
                        block.bits = std::uint16_t(std::lround(e.x * 127.0f) | (std::lround(e.y * 127.0f) << 7));
                        if (!(t.flags & k_texel_clipped)) block.bits |= k_block_hides;
                        blocks_.push_back(block);
                        grow(group.extent, block);
                    }
                group.end = std::uint32_t(blocks_.size());
                if (group.end == group.first) continue;
                grow(tile, group.extent);
                groups_.push_back(group);
            }
        fine_extents_.push_back(tile);
        fine_blocks_.push_back(std::uint32_t(blocks_.size()));
        fine_groups_.push_back(std::uint32_t(groups_.size()));
        fine_billboard_.push_back(billboard);
    }
    fine_boxes_.insert(fine_boxes_.end(), fine.boxes.begin(), fine.boxes.end());
    coarse_boxes_.insert(coarse_boxes_.end(), coarse.boxes.begin(), coarse.boxes.end());
    // each coarse tile: the fine tiles of this billboard whose texels and depth ranges overlap it
    if (coarse_fines_offset_.empty()) coarse_fines_offset_.push_back(0);
    for (const TileBox& c : coarse.boxes) {
        for (std::size_t k = 0; k < fine.boxes.size(); ++k) {
            const TileBox& f = fine.boxes[k];
            const bool overlap = f.texel_min.x < c.texel_max.x && c.texel_min.x < f.texel_max.x &&
                                 f.texel_min.y < c.texel_max.y && c.texel_min.y < f.texel_max.y &&
                                 f.depth_min <= c.depth_max && c.depth_min <= f.depth_max;
            if (overlap) coarse_fines_.push_back(fine.first + std::uint32_t(k));
        }
        coarse_fines_offset_.push_back(std::uint32_t(coarse_fines_.size()));
    }
    fine_count_ = frame.end_fine;
    coarse_count_ = coarse.first + coarse.boxes.size();
}

void HiddenProxies::finish(glm::vec3 centre, float radius, float texel, bool backs_see_through)
{
    backs_see_through_ = backs_see_through;
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (std::size_t k = 0; k < fine_count_; ++k) {
        const Frame& f = frames_[fine_billboard_[k]];
        for (std::uint32_t s = fine_blocks_[k]; s < fine_blocks_[k + 1]; ++s) {
            const Block& q = blocks_[s];
            const glm::vec3 p = f.origin + f.u * (float(q.i) + 0.5f) + f.v * (float(q.j) + 0.5f) + f.z * reps::decode_depth(q.depth);
            lo = glm::min(lo, p), hi = glm::max(hi, p);
        }
    }
    texel_centre_ = blocks_.empty() ? centre : 0.5f * (lo + hi);
    // (texel centres: half a texel's diagonal beyond them holds the squares)
    texel_radius_ = 0.5f * glm::length(hi - lo) + texel;
    // the depth buffer covers the texels' sphere (the boxes' reach further out)
    centre_ = texel_centre_;
    radius_ = blocks_.empty() ? radius : texel_radius_;
    resolution_ = std::clamp(int(std::ceil(2.0f * radius_ / (k_pixel_texels * texel))), 1, k_max_resolution);
    pixel_ = 2.0f * radius_ / float(resolution_);
    corners_.assign(std::size_t((k_cells + 1) * (k_cells + 1)), {});
    cells_.assign(std::size_t(k_cells * k_cells), {});
}

glm::ivec2 HiddenProxies::cell_of(glm::vec3 direction)
{
    // (the octahedral map the packages' normals use: the lower hemisphere folded over the diagonals)
    const glm::vec2 p = reps::octahedral_encode(direction);
    return glm::clamp(glm::ivec2(glm::floor(p * float(k_cells))), glm::ivec2(0), glm::ivec2(k_cells - 1));
}

std::vector<std::uint64_t> HiddenProxies::visible_along(glm::vec3 direction) const
{
    const std::size_t proxies = proxy_count();
    std::vector<std::uint64_t> bits((proxies + 63) / 64, 0);
    const glm::vec3 d = glm::normalize(direction);
    // the depth buffer's axes across the direction, and its corner
    const glm::vec3 helper = std::abs(d.x) < 0.6f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    const glm::vec3 axis_x = glm::normalize(glm::cross(helper, d)), axis_y = glm::cross(d, axis_x);
    const glm::vec3 corner = centre_ - radius_ * (axis_x + axis_y);
    const int n = resolution_;
    const float infinity = std::numeric_limits<float>::infinity();
    std::vector<float> nearest(std::size_t(n) * std::size_t(n), infinity);

    // A billboard's texel coordinates (x, y, depth in [0, 1]) to pixels and view depth: linear.
    struct Projection {
        glm::vec3 x, y, depth; // per unit of texel x, texel y, depth
        glm::vec3 origin;      // pixel x, pixel y, view depth at x = y = depth = 0
        glm::vec3 operator()(float tx, float ty, float tz) const
        {
            return origin + glm::vec3(x.x, y.x, depth.x) * tx + glm::vec3(x.y, y.y, depth.y) * ty + glm::vec3(x.z, y.z, depth.z) * tz;
        }
    };
    const float inverse_pixel = 1.0f / pixel_;
    std::vector<Projection> projections;
    projections.reserve(frames_.size());
    for (const Frame& f : frames_) {
        Projection p;
        p.x = glm::vec3(glm::dot(f.u, axis_x), glm::dot(f.v, axis_x), glm::dot(f.z, axis_x)) * inverse_pixel;
        p.y = glm::vec3(glm::dot(f.u, axis_y), glm::dot(f.v, axis_y), glm::dot(f.z, axis_y)) * inverse_pixel;
        p.depth = glm::vec3(glm::dot(f.u, d), glm::dot(f.v, d), glm::dot(f.z, d));
        p.origin = glm::vec3(glm::dot(f.origin - corner, axis_x) * inverse_pixel, glm::dot(f.origin - corner, axis_y) * inverse_pixel,
                             glm::dot(f.origin, d));
        projections.push_back(p);
    }
    // Calls visit(pixel index, depth) for the pixel centres inside a texel's square (or its centre's
    // pixel, for a square too small to hold one) until it returns true.
    auto cover = [&](const Projection& p, const Block& b, auto&& visit) {
        const float zc = reps::decode_depth(b.depth);
        // the square's corners c0, c0 + ex, c0 + ey, c0 + ex + ey; a pixel centre is inside where its
        // texel coordinates (the inverse of [ex ey]) fall in [0, 1)
        const glm::vec3 c0 = p(float(b.i), float(b.j), zc);
        const glm::vec2 ex(p.x.x, p.y.x), ey(p.x.y, p.y.y);
        const float det = ex.x * ey.y - ex.y * ey.x;
        if (std::abs(det) > 1e-6f) {
            const glm::vec2 lo = glm::vec2(c0) + glm::min(glm::vec2(0.0f), ex) + glm::min(glm::vec2(0.0f), ey);
            const glm::vec2 hi = glm::vec2(c0) + glm::max(glm::vec2(0.0f), ex) + glm::max(glm::vec2(0.0f), ey);
            const int x0 = std::max(0, int(std::ceil(lo.x - 0.5f))), x1 = std::min(n - 1, int(std::floor(hi.x - 0.5f)));
            const int y0 = std::max(0, int(std::ceil(lo.y - 0.5f))), y1 = std::min(n - 1, int(std::floor(hi.y - 0.5f)));
            const float inverse_det = 1.0f / det;
            bool any = false;
            for (int y = y0; y <= y1; ++y)
                for (int x = x0; x <= x1; ++x) {
                    const glm::vec2 r = glm::vec2(float(x) + 0.5f, float(y) + 0.5f) - glm::vec2(c0);
                    const float tx = (r.x * ey.y - r.y * ey.x) * inverse_det, ty = (ex.x * r.y - ex.y * r.x) * inverse_det;
                    if (tx < 0.0f || tx >= 1.0f || ty < 0.0f || ty >= 1.0f) continue;
                    any = true;
                    if (visit(std::size_t(y) * std::size_t(n) + std::size_t(x), c0.z + p.depth.x * tx + p.depth.y * ty)) return;
                }
            if (any) return;
        }
        const glm::vec3 c = p(float(b.i) + 0.5f, float(b.j) + 0.5f, zc);
        const int x = std::clamp(int(c.x), 0, n - 1), y = std::clamp(int(c.y), 0, n - 1);
        visit(std::size_t(y) * std::size_t(n) + std::size_t(x), c.z);
    };
    auto hides = [&](const Block& b) {
        if (!(b.bits & k_block_hides)) return false;
        if (!backs_see_through_) return true;
        const glm::vec3 normal = reps::octahedral_decode(glm::vec2(b.bits & 127u, (b.bits >> 7) & 127u) / 127.0f);
        return glm::dot(normal, d) < k_front_facing_cos;
    };
    // Whole tiles and groups first: the pixels a fine tile's (or group's) squares, or their centres'
    // pixels, can reach, a pixel wider each way, and the nearest depth any of them has, a little
    // nearer (the projection is linear: the extremes are the extent's corners). One whose squares
    // could change no pixel is skipped whole: in an assembly most tiles lie behind others, and a
    // tile's rectangle (16 x 16 texels: about 8 x 8 pixels) is read in a fraction of the time its
    // squares take. The held-out engine (3.2M blocks, 43,367 tiles): pass 1 rasterises 20-27% of the
    // blocks, pass 2 7-9%, and a corner takes about half the CPU it did (docs/RESULTS.md).
    struct Footprint {
        int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
        float nearest = 0.0f;
    };
    const float depth_slack = 1e-4f * (radius_ + glm::length(centre_));
    auto footprint_of = [&](const Extent& e, const Projection& p) {
        glm::vec3 lo(infinity), hi(-infinity);
        for (int c = 0; c < 8; ++c) {
            const glm::vec3 v = p(float((c & 1) ? e.i1 + 1 : e.i0), float((c & 2) ? e.j1 + 1 : e.j0), (c & 4) ? e.depth1 : e.depth0);
            lo = glm::min(lo, v), hi = glm::max(hi, v);
        }
        const float top = float(n - 1);
        Footprint f;
        f.x0 = int(std::clamp(std::floor(lo.x) - 1.0f, 0.0f, top)), f.x1 = int(std::clamp(std::floor(hi.x) + 1.0f, 0.0f, top));
        f.y0 = int(std::clamp(std::floor(lo.y) - 1.0f, 0.0f, top)), f.y1 = int(std::clamp(std::floor(hi.y) + 1.0f, 0.0f, top));
        f.nearest = lo.z - depth_slack;
        return f;
    };
    std::vector<Footprint> footprints(fine_count_);
    tbb::parallel_for(std::size_t(0), fine_count_, [&](std::size_t k) {
        if (fine_blocks_[k] != fine_blocks_[k + 1]) footprints[k] = footprint_of(fine_extents_[k], projections[fine_billboard_[k]]);
    });
    auto farthest_in = [&](std::vector<float>& buffer, const Footprint& f) {
        float farthest = -infinity;
        for (int y = f.y0; y <= f.y1; ++y)
            for (int x = f.x0; x <= f.x1; ++x)
                farthest = std::max(farthest, std::atomic_ref<float>(buffer[std::size_t(y) * std::size_t(n) + std::size_t(x)]).load(std::memory_order_relaxed));
        return farthest;
    };
    // pass 1: the nearest hiding surface of each pixel; tiles front to back, so that those behind
    // find their pixels already nearer than any of their squares. Tiles run on every core and lower
    // pixels atomically: a minimum is the same in any order, and a tile is skipped only where its
    // pixels' depths (which only fall) were already nearer, so the buffer is the same at any
    // thread count.
    std::vector<std::uint32_t> front_to_back;
    front_to_back.reserve(fine_count_);
    for (std::size_t k = 0; k < fine_count_; ++k)
        if (fine_blocks_[k] != fine_blocks_[k + 1]) front_to_back.push_back(std::uint32_t(k));
    std::sort(front_to_back.begin(), front_to_back.end(), [&](std::uint32_t a, std::uint32_t b) {
        return footprints[a].nearest < footprints[b].nearest || (footprints[a].nearest == footprints[b].nearest && a < b);
    });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, front_to_back.size(), 64), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t r = range.begin(); r < range.end(); ++r) {
            const std::size_t k = front_to_back[r];
            if (farthest_in(nearest, footprints[k]) <= footprints[k].nearest) continue;
            const Projection& p = projections[fine_billboard_[k]];
            const bool one_group = fine_groups_[k + 1] - fine_groups_[k] == 1;
            for (std::uint32_t g = fine_groups_[k]; g < fine_groups_[k + 1]; ++g) {
                const Group& group = groups_[g];
                if (!one_group) {
                    const Footprint f = footprint_of(group.extent, p);
                    if (farthest_in(nearest, f) <= f.nearest) continue;
                }
                for (std::uint32_t s = group.first; s < group.end; ++s)
                    if (hides(blocks_[s]))
                        cover(p, blocks_[s], [&](std::size_t pixel, float z) {
                            std::atomic_ref<float> depth(nearest[pixel]);
                            float was = depth.load(std::memory_order_relaxed);
                            while (z < was && !depth.compare_exchange_weak(was, z, std::memory_order_relaxed)) {
                            }
                            return false;
                        });
            }
        }
    });
    // each pixel's limit: the farthest nearest depth around it (beyond the buffer nothing hides),
    // 3 x 3 as a row and then a column of 3
    std::vector<float> row_farthest(nearest.size()), limit(nearest.size());
    const float tolerance = k_depth_tolerance_pixels * pixel_;
    auto at = [n](int x, int y) { return std::size_t(y) * std::size_t(n) + std::size_t(x); };
    tbb::parallel_for(0, n, [&](int y) {
        for (int x = 0; x < n; ++x)
            row_farthest[at(x, y)] = std::max({x > 0 ? nearest[at(x - 1, y)] : infinity, nearest[at(x, y)],
                                               x + 1 < n ? nearest[at(x + 1, y)] : infinity});
    });
    tbb::parallel_for(0, n, [&](int y) {
        for (int x = 0; x < n; ++x)
            limit[at(x, y)] = std::max({y > 0 ? row_farthest[at(x, y - 1)] : infinity, row_farthest[at(x, y)],
                                        y + 1 < n ? row_farthest[at(x, y + 1)] : infinity}) +
                              tolerance;
    });
    // pass 2: fine tiles with a block within the limit at a pixel it covers; tiles without are kept;
    // a tile whose nearest depth lies beyond every limit of its rectangle is hidden whole
    std::vector<std::uint8_t> fine_visible(fine_count_, 0);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, fine_count_, 64), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t k = range.begin(); k < range.end(); ++k) {
            bool visible = fine_blocks_[k] == fine_blocks_[k + 1];
            if (!visible && !(footprints[k].nearest > farthest_in(limit, footprints[k]))) {
                const Projection& p = projections[fine_billboard_[k]];
                const bool one_group = fine_groups_[k + 1] - fine_groups_[k] == 1;
                for (std::uint32_t g = fine_groups_[k]; g < fine_groups_[k + 1] && !visible; ++g) {
                    const Group& group = groups_[g];
                    if (!one_group) {
                        const Footprint f = footprint_of(group.extent, p);
                        if (f.nearest > farthest_in(limit, f)) continue;
                    }
                    for (std::uint32_t s = group.first; s < group.end && !visible; ++s)
                        cover(p, blocks_[s], [&](std::size_t pixel, float z) { return visible = z <= limit[pixel]; });
                }
            }
            fine_visible[k] = visible ? 1 : 0;
        }
    });
    for (std::size_t k = 0; k < fine_count_; ++k)
        if (fine_visible[k]) set_proxy_bit(bits, k);
    for (std::size_t c = 0; c < coarse_count_; ++c) {
        bool visible = coarse_fines_offset_[c] == coarse_fines_offset_[c + 1];
        for (std::uint32_t o = coarse_fines_offset_[c]; o < coarse_fines_offset_[c + 1] && !visible; ++o)
            visible = has_proxy_bit(bits, coarse_fines_[o]);
        if (visible) set_proxy_bit(bits, fine_count_ + c);
    }
    for (std::size_t f = 0; f < frames_.size(); ++f) {
        bool visible = frames_[f].first_fine == frames_[f].end_fine;
        for (std::uint32_t k = frames_[f].first_fine; k < frames_[f].end_fine && !visible; ++k) visible = has_proxy_bit(bits, k);
        if (visible) set_proxy_bit(bits, fine_count_ + coarse_count_ + f);
    }
    return bits;
}

void HiddenProxies::compute_corners(std::span<const int> corners)
{
    tbb::parallel_for(std::size_t(0), corners.size(), [&](std::size_t k) {
        const int c = corners[k];
        const glm::vec2 p = glm::vec2(c % (k_cells + 1), c / (k_cells + 1)) / float(k_cells);
        corners_[std::size_t(c)] = visible_along(reps::octahedral_decode(p));
    });
}

const std::vector<std::uint64_t>& HiddenProxies::cell(glm::ivec2 c)
{
    std::vector<std::uint64_t>& bits = cells_[std::size_t(c.y * k_cells + c.x)];
    if (!bits.empty()) return bits;
    int corners[4], missing[4], count = 0;
    for (int k = 0; k < 4; ++k) {
        corners[k] = (c.y + (k >> 1)) * (k_cells + 1) + c.x + (k & 1);
        if (corners_[std::size_t(corners[k])].empty()) missing[count++] = corners[k];
    }
    compute_corners(std::span<const int>(missing, std::size_t(count)));
    bits = corners_[std::size_t(corners[0])];
    for (int k = 1; k < 4; ++k) {
        const std::vector<std::uint64_t>& other = corners_[std::size_t(corners[k])];
        for (std::size_t w = 0; w < bits.size(); ++w) bits[w] |= other[w];
    }
    return bits;
}

int HiddenProxies::cut_box(std::size_t k, std::size_t cell_at, std::array<Cut, 4>& parts)
{
    if (k < fine_count_ || k >= proxy_count() || cell_at >= cells_.size()) return 0;
    const std::vector<std::uint64_t>& bits = cell(glm::ivec2(int(cell_at % k_cells), int(cell_at / k_cells)));
    // the proxy's own box: a coarse tile's, or the union of its billboard's fine tiles (a whole box
    // holds every covered texel, and each fine tile every crossing of its texels)
    const bool coarse = k < fine_count_ + coarse_count_;
    const std::size_t billboard = coarse ? 0 : k - fine_count_ - coarse_count_;
    const TileBox* own = coarse ? &coarse_boxes_[k - fine_count_] : nullptr;
    const glm::vec2 slope = own ? own->slope : glm::vec2(0.0f);
    std::vector<std::uint32_t> shown_tiles;
    Cut all = cut_empty(), shown = cut_empty();
    auto visit = [&](std::uint32_t f) {
        cut_add(all, fine_boxes_[f], slope);
        if (!has_proxy_bit(bits, f)) return;
        cut_add(shown, fine_boxes_[f], slope);
        shown_tiles.push_back(f);
    };
    if (coarse) {
        for (std::uint32_t s = coarse_fines_offset_[k - fine_count_]; s < coarse_fines_offset_[k - fine_count_ + 1]; ++s)
            visit(coarse_fines_[s]);
        // within the coarse tile's own box (its layer)
        for (Cut* c : {&all, &shown}) {
            c->texel_min = glm::max(c->texel_min, own->texel_min), c->texel_max = glm::min(c->texel_max, own->texel_max);
            c->offset_min = std::max(c->offset_min, own->offset_min), c->offset_max = std::min(c->offset_max, own->offset_max);
        }
    } else {
        for (std::uint32_t f = frames_[billboard].first_fine; f < frames_[billboard].end_fine; ++f) visit(f);
    }
    if (!(cut_volume(shown) > 0.0)) return 0; // nothing shows: may_show leaves the proxy out
    // a whole box whose shown tiles lie apart (an assembly's parts at its corners, or a surface's
    // near and far sides): one box per quadrant of their rectangle, where those hold 40% less volume
    // than the one box (each box costs its triangles: llvmpipe sets up 12 a box). Measured on the
    // held-out engine's crowd of 1,000 (800x600, llvmpipe): overdraw 67.7 -> 41.9, 1,362-1,558 ->
    // 1,109-1,240 ms; a rule by the boxes' surfaces (mean projected areas) at 0.6 or 0.85 split
    // less (60.4, 48.9) for no less time; Suzanne's crowd within noise either way.
    if (!coarse) {
        const glm::ivec2 middle = (shown.texel_min + shown.texel_max) / 2;
        std::array<Cut, 4> quadrants;
        quadrants.fill(cut_empty());
        for (std::uint32_t f : shown_tiles) {
            const glm::ivec2 centre2 = fine_boxes_[f].texel_min + fine_boxes_[f].texel_max;
            cut_add(quadrants[std::size_t((centre2.x >= 2 * middle.x ? 1 : 0) + (centre2.y >= 2 * middle.y ? 2 : 0))], fine_boxes_[f], slope);
        }
        int count = 0;
        double split = 0.0;
        for (const Cut& q : quadrants)
            if (cut_volume(q) > 0.0) parts[std::size_t(count++)] = q, split += cut_volume(q);
        if (count > 1 && split < 0.6 * cut_volume(shown)) return count;
    }
    // worth a box of its own where it leaves out a tenth of the volume
    if (!(cut_volume(shown) < 0.9 * cut_volume(all))) return 0;
    parts[0] = shown;
    return 1;
}

bool HiddenProxies::may_show(std::size_t k, std::size_t cell_index)
{
    if (k >= proxy_count() || blocks_.empty() || cell_index >= std::size_t(k_cells * k_cells)) return true;
    return has_proxy_bit(cell(glm::ivec2(int(cell_index % k_cells), int(cell_index / k_cells))), k);
}

} // namespace standin::billboards
