// Image differences between a ground-truth render and a stand-in render of the same camera.
// CIE L*u*v* average intensity difference: Vichitvejpaisal 2005 (Vichitvejpaisal 2005
// §2.1.5, eq. 2.2). Per-pixel RGB error, total and average over the object rectangle: Saraiva et al.
// (Saraiva et al. §3). CIEDE2000 from Little CMS (cmsCIE2000DeltaE).
// Differences from the papers: the seed's "red vs. blue = 580" is not what the CIE formulas give
// (about 250 with D65 and L in 0..100); we keep the standard formulas (docs/EVAL.md).
#include <standin/eval.h>

#include <lcms2.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cassert>
#include <cmath>

namespace standin {

namespace {

// D65 reference white, Y = 1.
constexpr double k_white_x = 0.95047, k_white_y = 1.0, k_white_z = 1.08883;

// sRGB decoding of all 256 8-bit values, computed once.
const std::array<double, 256>& linear_table()
{
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) {
            double c = i / 255.0;
            t[i] = c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

glm::dvec3 xyz_from_srgb8(glm::u8vec3 rgb)
{
    const auto& lin = linear_table();
    double r = lin[rgb.x], g = lin[rgb.y], b = lin[rgb.z];
    // IEC 61966-2-1 primaries, D65
    return {0.4124564 * r + 0.3575761 * g + 0.1804375 * b, 0.2126729 * r + 0.7151522 * g + 0.0721750 * b,
            0.0193339 * r + 0.1191920 * g + 0.9503041 * b};
}

glm::u8vec3 composited(const std::uint8_t* p, glm::u8vec3 background)
{
    if (p[3] == 255) return {p[0], p[1], p[2]};
    if (p[3] == 0) return background;
    // Renderers write opaque colour; partial alpha only comes from foreign images: blend in the
    // encoded space, as PNG viewers do.
    auto mix = [&](int c, int bg) { return std::uint8_t(std::lround((c * p[3] + bg * (255 - p[3])) / 255.0)); };
    return {mix(p[0], background.x), mix(p[1], background.y), mix(p[2], background.z)};
}

// L*u*v* and L*a*b* of one colour, cached per pixel value would be overkill: an image of 800x600
// has at most a few thousand distinct colours but the formulas are cheap enough.
struct ColorPair {
    glm::dvec3 luv, lab;
};
ColorPair colors_of(glm::u8vec3 rgb) { return {luv_from_srgb8(rgb), lab_from_srgb8(rgb)}; }

} // namespace

glm::dvec3 luv_from_srgb8(glm::u8vec3 rgb)
{
    glm::dvec3 xyz = xyz_from_srgb8(rgb);
    double yr = xyz.y / k_white_y;
    constexpr double epsilon = 216.0 / 24389.0, kappa = 24389.0 / 27.0;
    double l = yr > epsilon ? 116.0 * std::cbrt(yr) - 16.0 : kappa * yr;
    double d = xyz.x + 15.0 * xyz.y + 3.0 * xyz.z;
    double dn = k_white_x + 15.0 * k_white_y + 3.0 * k_white_z;
    double un = 4.0 * k_white_x / dn, vn = 9.0 * k_white_y / dn;
    if (d <= 0.0) return {l, 0.0, 0.0}; // black: u' v' undefined, L = 0 makes u = v = 0
    double u = 13.0 * l * (4.0 * xyz.x / d - un);
    double v = 13.0 * l * (9.0 * xyz.y / d - vn);
    return {l, u, v};
}

glm::dvec3 lab_from_srgb8(glm::u8vec3 rgb)
{
    glm::dvec3 xyz = xyz_from_srgb8(rgb);
    const cmsCIEXYZ white{k_white_x, k_white_y, k_white_z};
    cmsCIEXYZ in{xyz.x, xyz.y, xyz.z};
    cmsCIELab lab;
    cmsXYZ2Lab(&white, &lab, &in);
    return {lab.L, lab.a, lab.b};
}

double ciede2000(glm::dvec3 lab1, glm::dvec3 lab2)
{
    cmsCIELab a{lab1.x, lab1.y, lab1.z}, b{lab2.x, lab2.y, lab2.z};
    return cmsCIE2000DeltaE(&a, &b, 1.0, 1.0, 1.0);
}

ImageRGBA8 composite_over_background(const ImageRGBA8& image, const MetricOptions& options)
{
    ImageRGBA8 out(image.width, image.height);
    for (std::size_t i = 0; i < image.pixels.size(); i += 4) {
        glm::u8vec3 c = composited(&image.pixels[i], options.background);
        out.pixels[i] = c.x, out.pixels[i + 1] = c.y, out.pixels[i + 2] = c.z, out.pixels[i + 3] = 255;
    }
    return out;
}

ResolvedImage resolve_supersampled(const ImageRGBA8& image, int factor, const MetricOptions& options)
{
    assert(factor >= 1 && factor <= k_max_supersample && image.width % factor == 0 && image.height % factor == 0);
    const auto& lin = linear_table();
    const int w = image.width / factor, h = image.height / factor;
    const glm::dvec3 background{lin[options.background.x], lin[options.background.y], lin[options.background.z]};
    const double samples = double(factor * factor);
    ResolvedImage out;
    out.color = ImageRGBA8(w, h);
    out.sample_coverage.assign(std::size_t(w) * h, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 sum{0.0};
            std::uint64_t mask = 0;
            for (int sy = 0; sy < factor; ++sy)
                for (int sx = 0; sx < factor; ++sx) {
                    const std::uint8_t* p = image.at(x * factor + sx, y * factor + sy);
                    const double alpha = p[3] / 255.0;
                    // each sample over the background in linear light, as it would be displayed
                    sum += glm::dvec3{lin[p[0]], lin[p[1]], lin[p[2]]} * alpha + background * (1.0 - alpha);
                    if (p[3] > 0) mask |= std::uint64_t(1) << (sy * factor + sx);
                }
            std::uint8_t* o = out.color.at(x, y);
            for (int c = 0; c < 3; ++c)
                o[c] = std::uint8_t(std::lround(255.0 * std::clamp(double(linear_to_srgb(float(sum[c] / samples))), 0.0, 1.0)));
            o[3] = mask ? 255 : 0;
            if (!mask) o[0] = options.background.x, o[1] = options.background.y, o[2] = options.background.z;
            out.sample_coverage[std::size_t(y) * w + x] = mask;
        }
    return out;
}

void count_silhouette_over_samples(ImageMetrics& m, const std::vector<std::uint64_t>& truth_coverage,
                                   const std::vector<std::uint64_t>& standin_coverage, int factor)
{
    assert(truth_coverage.size() == standin_coverage.size());
    std::size_t t = 0, s = 0, both = 0, either = 0;
    for (std::size_t i = 0; i < truth_coverage.size(); ++i) {
        const std::uint64_t a = truth_coverage[i], b = standin_coverage[i];
        t += std::size_t(std::popcount(a));
        s += std::size_t(std::popcount(b));
        both += std::size_t(std::popcount(a & b));
        either += std::size_t(std::popcount(a | b));
    }
    const std::size_t samples = std::size_t(factor) * std::size_t(factor);
    auto pixels = [&](std::size_t n) { return (n + samples / 2) / samples; };
    m.truth_pixels = pixels(t);
    m.standin_pixels = pixels(s);
    m.intersection_pixels = pixels(both);
    m.union_pixels = pixels(either);
    m.hole_pixels = pixels(t - both);
    m.spill_pixels = pixels(s - both);
    m.hole_fraction = t ? double(t - both) / double(t) : 0.0;
    m.spill_fraction = t ? double(s - both) / double(t) : 0.0;
    m.iou = either ? double(both) / double(either) : 1.0;
}

ImageMetrics compare_images(const ImageRGBA8& truth, const ImageRGBA8& standin, const MetricOptions& options)
{
    assert(truth.width == standin.width && truth.height == standin.height);
    ImageMetrics m;
    const int w = truth.width, h = truth.height;
    int x0 = w, y0 = h, x1 = 0, y1 = 0;

    // coverage sets and the object rectangle
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            bool t = truth.at(x, y)[3] > 0, s = standin.at(x, y)[3] > 0;
            m.truth_pixels += t;
            m.standin_pixels += s;
            m.intersection_pixels += t && s;
            m.hole_pixels += t && !s;
            m.spill_pixels += s && !t;
            if (t || s) {
                ++m.union_pixels;
                x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
            }
        }
    if (m.union_pixels == 0) {
        m.psnr = options.psnr_cap_db;
        return m;
    }
    m.rect_x0 = x0, m.rect_y0 = y0, m.rect_x1 = x1, m.rect_y1 = y1;
    m.rect_pixels = std::size_t(x1 - x0) * std::size_t(y1 - y0);

    // colour differences over the rectangle (outside it both images are background)
    std::vector<double> de2000;
    de2000.reserve(m.union_pixels);
    double luv_sum = 0.0, luv_edge_sum = 0.0, squared_sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* pt = truth.at(x, y);
            const std::uint8_t* ps = standin.at(x, y);
            glm::u8vec3 ct = composited(pt, options.background), cs = composited(ps, options.background);
            int dr = int(ct.x) - cs.x, dg = int(ct.y) - cs.y, db = int(ct.z) - cs.z;
            m.rgb_total += std::abs(dr) + std::abs(dg) + std::abs(db);
            squared_sum += double(dr * dr + dg * dg + db * db);
            m.differing_pixels += (dr | dg | db) != 0;
            if (pt[3] == 0 && ps[3] == 0) continue;
            double luv = 0.0, de = 0.0;
            if (ct != cs) {
                ColorPair a = colors_of(ct), b = colors_of(cs);
                luv = glm::length(a.luv - b.luv);
                de = ciede2000(a.lab, b.lab);
            }
            luv_sum += luv;
            if ((pt[3] == 0) != (ps[3] == 0)) luv_edge_sum += luv;
            m.luv_pixel_max = std::max(m.luv_pixel_max, luv);
            de2000.push_back(de);
        }

    // summaries
    double u = double(m.union_pixels);
    m.luv_mean = luv_sum / u;
    m.luv_edge = luv_edge_sum / u;
    if (m.intersection_pixels > 0) m.luv_shared = (luv_sum - luv_edge_sum) / double(m.intersection_pixels);
    m.rgb_avg = m.rgb_total / double(m.rect_pixels);
    double de_sum = 0.0;
    for (double d : de2000) de_sum += d;
    m.de2000_mean = de_sum / u;
    std::size_t rank = std::size_t(std::ceil(0.95 * double(de2000.size()))); // nearest rank, 1-based
    rank = std::clamp<std::size_t>(rank, 1, de2000.size());
    std::nth_element(de2000.begin(), de2000.begin() + (rank - 1), de2000.end());
    m.de2000_p95 = de2000[rank - 1];
    if (m.truth_pixels > 0) {
        m.hole_fraction = double(m.hole_pixels) / double(m.truth_pixels);
        m.spill_fraction = double(m.spill_pixels) / double(m.truth_pixels);
    }
    m.iou = double(m.intersection_pixels) / u;
    double mse = squared_sum / (3.0 * double(m.rect_pixels));
    m.psnr = mse > 0.0 ? std::min(options.psnr_cap_db, 10.0 * std::log10(255.0 * 255.0 / mse)) : options.psnr_cap_db;
    return m;
}

ImageRGBA8 difference_heatmap(const ImageRGBA8& truth, const ImageRGBA8& standin, double full_scale,
                              const MetricOptions& options)
{
    assert(truth.width == standin.width && truth.height == standin.height);
    ImageRGBA8 out(truth.width, truth.height);
    for (std::size_t i = 0; i < truth.pixels.size(); i += 4) {
        std::uint8_t* o = &out.pixels[i];
        o[3] = 255;
        if (truth.pixels[i + 3] == 0 && standin.pixels[i + 3] == 0) {
            o[0] = o[1] = o[2] = 24;
            continue;
        }
        glm::u8vec3 a = composited(&truth.pixels[i], options.background);
        glm::u8vec3 b = composited(&standin.pixels[i], options.background);
        double t = a == b ? 0.0 : std::min(1.0, glm::length(luv_from_srgb8(a) - luv_from_srgb8(b)) / full_scale);
        // black -> red -> yellow -> white
        o[0] = std::uint8_t(std::lround(255.0 * std::min(1.0, 3.0 * t)));
        o[1] = std::uint8_t(std::lround(255.0 * std::clamp(3.0 * t - 1.0, 0.0, 1.0)));
        o[2] = std::uint8_t(std::lround(255.0 * std::clamp(3.0 * t - 2.0, 0.0, 1.0)));
        if (t == 0.0) o[0] = o[1] = o[2] = 48; // covered and identical: lighter than the background
    }
    return out;
}

} // namespace standin
