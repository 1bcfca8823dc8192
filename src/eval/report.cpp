// The evaluation report: one self-contained directory a person opens in a browser. index.html
// holds the seed-style tables (000 Tables A-1/A-2, 003 Tables 1-3), hand-written SVG charts
// (error vs. relative distance on log axes like Saraiva et al. Figs. 1-6; frame rate vs. resolution),
// and a truth / stand-in / difference triplet per view.
#include <standin/eval.h>
#include <standin/files.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

namespace standin {

namespace fs = std::filesystem;

struct ReportWriter::State {
    std::string directory; // final
    std::string temporary; // being written
    bool finished = false;
};

namespace {

std::string fmt(const char* format, double value)
{
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, format, value);
    return buffer;
}

std::string escape_html(const std::string& text)
{
    std::string out;
    for (char c : text) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string view_stem(std::size_t index)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "images/%03zu", index);
    return buffer;
}

// One line chart as SVG: series of (x, y) points, optional log axes (base 2 for x, 10 for y).
struct Series {
    std::string label;
    std::vector<std::pair<double, double>> points;
};
struct Chart {
    std::string title, x_label, y_label;
    bool log_x = false, log_y = false;
    std::vector<Series> series;
};

std::string svg_chart(const Chart& chart)
{
    const double width = 520, height = 320, left = 70, right = 130, top = 30, bottom = 50;
    const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
    auto tx = [&](double x) { return chart.log_x ? std::log2(x) : x; };
    auto ty = [&](double y) { return chart.log_y ? std::log10(std::max(y, 1e-12)) : y; };

    // data range in transformed space
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const Series& s : chart.series)
        for (auto [x, y] : s.points) {
            if (chart.log_y && y <= 0) continue;
            x0 = std::min(x0, tx(x)), x1 = std::max(x1, tx(x)), y0 = std::min(y0, ty(y)), y1 = std::max(y1, ty(y));
        }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    if (!chart.log_y) y0 = std::min(y0, 0.0);
    if (chart.log_y) y0 = std::floor(y0), y1 = std::ceil(y1);
    if (x1 - x0 < 1e-9) x0 -= 0.5, x1 += 0.5;
    if (y1 - y0 < 1e-9) y1 = y0 + 1.0;
    if (!chart.log_y) y1 += 0.05 * (y1 - y0);
    const double pw = width - left - right, ph = height - top - bottom;
    auto px = [&](double x) { return left + (tx(x) - x0) / (x1 - x0) * pw; };
    auto py = [&](double y) { return top + ph - (ty(y) - y0) / (y1 - y0) * ph; };

    std::ostringstream svg;
    svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << width << "' height='" << height
        << "' font-family='sans-serif' font-size='11'>\n";
    svg << "<rect width='100%' height='100%' fill='white'/>\n";
    svg << "<text x='" << left + pw / 2 << "' y='18' text-anchor='middle' font-size='13'>" << escape_html(chart.title)
        << "</text>\n";
    svg << "<rect x='" << left << "' y='" << top << "' width='" << pw << "' height='" << ph
        << "' fill='none' stroke='#444'/>\n";

    // ticks: integer powers on log axes, 5 steps on linear ones
    auto tick_values = [](double lo, double hi, bool log) {
        std::vector<double> ticks;
        if (log) {
            for (double t = std::ceil(lo - 1e-9); t <= hi + 1e-9; t += 1.0) ticks.push_back(t);
        } else {
            for (int i = 0; i <= 5; ++i) ticks.push_back(lo + (hi - lo) * i / 5.0);
        }
        return ticks;
    };
    for (double t : tick_values(x0, x1, chart.log_x)) {
        double x = left + (t - x0) / (x1 - x0) * pw;
        std::string label = chart.log_x ? fmt("%g", std::exp2(t)) : fmt("%.3g", t);
        svg << "<line x1='" << x << "' y1='" << top + ph << "' x2='" << x << "' y2='" << top + ph + 4
            << "' stroke='#444'/><text x='" << x << "' y='" << top + ph + 16 << "' text-anchor='middle'>" << label
            << "</text>\n";
    }
    for (double t : tick_values(y0, y1, chart.log_y)) {
        double y = top + ph - (t - y0) / (y1 - y0) * ph;
        std::string label = chart.log_y ? "1e" + fmt("%.0f", t) : fmt("%.3g", t);
        svg << "<line x1='" << left - 4 << "' y1='" << y << "' x2='" << left + pw << "' y2='" << y
            << "' stroke='#ddd'/><text x='" << left - 6 << "' y='" << y + 4 << "' text-anchor='end'>" << label
            << "</text>\n";
    }
    svg << "<text x='" << left + pw / 2 << "' y='" << height - 12 << "' text-anchor='middle'>"
        << escape_html(chart.x_label) << "</text>\n";
    svg << "<text transform='translate(14," << top + ph / 2 << ") rotate(-90)' text-anchor='middle'>"
        << escape_html(chart.y_label) << "</text>\n";

    // series with legend
    for (std::size_t i = 0; i < chart.series.size(); ++i) {
        const Series& s = chart.series[i];
        const char* color = colors[i % 6];
        std::ostringstream path;
        for (auto [x, y] : s.points) {
            if (chart.log_y && y <= 0) continue;
            path << (path.tellp() == 0 ? "" : " ") << px(x) << "," << py(y);
        }
        svg << "<polyline fill='none' stroke='" << color << "' stroke-width='2' points='" << path.str() << "'/>\n";
        for (auto [x, y] : s.points)
            if (!(chart.log_y && y <= 0))
                svg << "<circle cx='" << px(x) << "' cy='" << py(y) << "' r='3' fill='" << color << "'/>\n";
        double ly = top + 14 + 16.0 * double(i);
        svg << "<line x1='" << left + pw + 10 << "' y1='" << ly << "' x2='" << left + pw + 28 << "' y2='" << ly
            << "' stroke='" << color << "' stroke-width='2'/><text x='" << left + pw + 32 << "' y='" << ly + 4 << "'>"
            << escape_html(s.label) << "</text>\n";
    }
    svg << "</svg>\n";
    return svg.str();
}

// Views grouped by fov, each series over relative distance (Saraiva et al. Figs. 1-6).
std::vector<Series> series_by_fov(const EvalResult& result, double (*figure)(const ViewResult&))
{
    std::map<float, std::map<float, std::pair<double, int>>> sums; // fov -> distance -> (sum, n)
    for (const ViewResult& v : result.views) {
        auto& cell = sums[v.view.orbit.fov_y_degrees][v.view.orbit.distance_rel];
        cell.first += figure(v);
        cell.second += 1;
    }
    std::vector<Series> series;
    for (const auto& [fov, by_distance] : sums) {
        Series s;
        s.label = "fov " + fmt("%g", fov);
        for (const auto& [distance, cell] : by_distance) s.points.push_back({distance, cell.first / cell.second});
        series.push_back(s);
    }
    return series;
}

// The frame rate of truth and stand-in per resolution (Vichitvejpaisal 2005 Table A-1 / Fig. 4-6).
std::vector<Series> fps_by_pixels(const EvalResult& result, bool wall_time)
{
    std::map<int, std::pair<double, double>> ms; // pixels -> (truth, standin) sums
    std::map<int, int> counts;
    for (const ViewResult& v : result.views) {
        double t = wall_time ? v.truth_wall_ms : v.truth_ms, s = wall_time ? v.standin_wall_ms : v.standin_ms;
        if (t <= 0.0 || s <= 0.0) continue;
        int pixels = v.view.width * v.view.height;
        ms[pixels].first += t;
        ms[pixels].second += s;
        counts[pixels] += 1;
    }
    Series truth{"original mesh", {}}, standin{"stand-in", {}};
    for (const auto& [pixels, sums] : ms) {
        truth.points.push_back({pixels / 1000.0, 1000.0 / (sums.first / counts[pixels])});
        standin.points.push_back({pixels / 1000.0, 1000.0 / (sums.second / counts[pixels])});
    }
    return {truth, standin};
}

std::string html_table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows)
{
    std::ostringstream out;
    out << "<table><tr>";
    for (const std::string& h : header) out << "<th>" << escape_html(h) << "</th>";
    out << "</tr>\n";
    for (const auto& row : rows) {
        out << "<tr>";
        for (const std::string& cell : row) out << "<td>" << escape_html(cell) << "</td>";
        out << "</tr>\n";
    }
    out << "</table>\n";
    return out.str();
}

std::string json_text(const nlohmann::json& value)
{
    if (value.is_string()) return value.get<std::string>();
    if (value.is_null()) return "";
    return value.dump();
}

} // namespace

Result<std::string> report_directory_path(const std::string& directory)
{
    fs::path final_path(directory);
    if (final_path.filename().empty()) final_path = final_path.parent_path();
    std::error_code ec;
    if (fs::exists(final_path, ec) && !fs::is_directory(final_path, ec))
        return error(StatusCode::invalid_argument, final_path.string() + ": exists and is not a directory");
    if (fs::is_directory(final_path, ec) && !fs::is_empty(final_path, ec) && !fs::exists(final_path / "index.html", ec))
        return error(StatusCode::invalid_argument,
                     final_path.string() + ": exists and is not a report (no index.html); refusing to replace it");
    STANDIN_RETURN_IF_ERROR(check_output_path(final_path.string())); // folders are never created
    return final_path.string();
}

Result<ReportWriter> ReportWriter::begin(const std::string& directory)
{
    Result<std::string> final_path = report_directory_path(directory);
    if (!final_path) return final_path.status();
    std::error_code ec;
    ReportWriter writer;
    writer.state_ = std::make_unique<State>();
    writer.state_->directory = *final_path;
    writer.state_->temporary = temporary_path_for(*final_path);
    fs::create_directories(fs::path(writer.state_->temporary) / "images", ec);
    if (ec) return error(StatusCode::io_error, writer.state_->temporary + ": cannot create directory: " + ec.message());
    return writer;
}

ReportWriter::ReportWriter(ReportWriter&&) noexcept = default;
ReportWriter& ReportWriter::operator=(ReportWriter&&) noexcept = default;
ReportWriter::~ReportWriter()
{
    if (state_ && !state_->finished) {
        std::error_code ec;
        fs::remove_all(state_->temporary, ec);
    }
}

const std::string& ReportWriter::directory() const { return state_->directory; }

Status ReportWriter::add_view(std::size_t index, const ViewResult& result, const RenderedImage& truth,
                              const RenderedImage& standin)
{
    std::string stem = (fs::path(state_->temporary) / view_stem(index)).string();
    STANDIN_RETURN_IF_ERROR(write_png(truth.color, stem + "_truth.png"));
    STANDIN_RETURN_IF_ERROR(write_png(standin.color, stem + "_standin.png"));
    return write_png(difference_heatmap(truth.color, standin.color), stem + "_diff.png");
}

Status ReportWriter::finish(const EvalResult& result, const nlohmann::json& json)
{
    fs::path dir(state_->temporary);

    // machine-readable copies: the JSON and one CSV per table
    STANDIN_RETURN_IF_ERROR(write_file_atomic((dir / "eval.json").string(), json.dump(2) + "\n"));
    for (const auto& [name, text] : eval_tables_csv(result))
        STANDIN_RETURN_IF_ERROR(write_file_atomic((dir / name).string(), text));

    // charts
    std::vector<std::pair<std::string, Chart>> charts;
    bool several_distances = false;
    for (const ViewResult& v : result.views)
        several_distances |= v.view.orbit.distance_rel != result.views.front().view.orbit.distance_rel;
    if (several_distances) {
        charts.push_back({"chart_total_error.svg",
                          {"Total colour error by distance", "relative distance (log2)",
                           "total |dR|+|dG|+|dB| (log10)", true, true,
                           series_by_fov(result, [](const ViewResult& v) { return v.metrics.rgb_total; })}});
        charts.push_back({"chart_average_error.svg",
                          {"Average colour error by distance", "relative distance (log2)",
                           "average error per rectangle pixel", true, false,
                           series_by_fov(result, [](const ViewResult& v) { return v.metrics.rgb_avg; })}});
        charts.push_back({"chart_luv.svg",
                          {"Luv difference by distance", "relative distance (log2)", "Luv difference", true,
                           false, series_by_fov(result, [](const ViewResult& v) { return v.metrics.luv_mean; })}});
    }
    const Verdict verdict = eval_verdict(result);
    std::vector<Series> fps = fps_by_pixels(result, verdict.wall_time);
    if (fps.front().points.size() >= 2) // a chart of one point says nothing a table does not
        charts.push_back({"chart_fps.svg",
                          {"Frame rate by image size", "kilopixels", "frames per second (log10)", false, true, fps}});
    for (const auto& [name, chart] : charts)
        STANDIN_RETURN_IF_ERROR(write_file_atomic((dir / name).string(), svg_chart(chart)));

    // the page
    std::ostringstream html;
    html << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><title>standin eval: "
         << escape_html(json_text(json.value("package", nlohmann::json()))) << "</title>\n<style>\n"
         << "body{font-family:sans-serif;margin:2em;max-width:1400px;color:#222}\n"
         << "table{border-collapse:collapse;margin:0.5em 0 1.5em}\n"
         << "th,td{border:1px solid #bbb;padding:3px 8px;text-align:right;font-size:13px}\n"
         << "th{background:#eee}\n.triplet{display:inline-block;margin:0 1em 1.5em 0;vertical-align:top}\n"
         << ".triplet img{border:1px solid #999;margin-right:2px;max-width:320px;image-rendering:pixelated}\n"
         << ".caption{font-size:12px}\n</style></head><body>\n";
    html << "<h1>standin eval</h1>\n";
    std::vector<std::vector<std::string>> identity_rows;
    for (const char* key : {"model", "package", "representation", "protocol", "supersample", "device", "command"})
        if (json.contains(key)) identity_rows.push_back({key, json_text(json[key])});
    html << html_table({"", ""}, identity_rows);
    html << "<h2>Verdict</h2>\n<p><strong>" << escape_html(verdict.line) << "</strong></p>\n";

    // summary
    html << "<h2>Summary over " << result.views.size() << " views</h2>\n";
    std::vector<std::vector<std::string>> rows;
    for (auto it = json["stats"].begin(); it != json["stats"].end(); ++it)
        rows.push_back({it.key(), fmt("%.4g", it.value()["mean"].get<double>()),
                        fmt("%.4g", it.value()["median"].get<double>()), fmt("%.4g", it.value()["max"].get<double>()),
                        fmt("%.4g", it.value()["min"].get<double>())});
    html << html_table({"figure", "mean", "median", "max", "min"}, rows);
    if (result.surface)
        html << "<p>One-sided surface distance stand-in &rarr; original (" << result.surface->samples
             << " samples): mean " << fmt("%.4g", result.surface->mean_rel) << ", max "
             << fmt("%.4g", result.surface->max_rel) << " of the bounding-box diagonal.</p>\n";

    // Vichitvejpaisal 2005 tables A-2 and A-1
    html << "<h2>Colour difference by image size</h2>\n<p>Vichitvejpaisal 2005 Table A-2; Luv is its eq. 2.2.</p>\n";
    rows.clear();
    std::vector<std::vector<std::string>> fps_rows;
    for (const auto& row : json["tables"]["by_resolution"]) {
        std::string size = std::to_string(row["width"].get<int>()) + "x" + std::to_string(row["height"].get<int>());
        rows.push_back({size, std::to_string(row["views"].get<int>()), fmt("%.2f", row["luv_mean"].get<double>()),
                        fmt("%.3f", row["de2000_mean"].get<double>()), fmt("%.2f", row["rgb_avg"].get<double>())});
        const char* clock = verdict.wall_time ? "_wall_ms" : "_ms";
        double tm = row[std::string("truth") + clock].get<double>(), sm = row[std::string("standin") + clock].get<double>();
        if (tm > 0 && sm > 0)
            fps_rows.push_back({size, fmt("%.3f", tm), fmt("%.3f", sm), fmt("%.2f", 1000.0 / tm),
                                fmt("%.2f", 1000.0 / sm), fmt("%.2f", tm / sm)});
    }
    html << html_table({"resolution", "views", "Luv (eq. 2.2)", "CIEDE2000", "RGB avg"}, rows);
    if (!fps_rows.empty()) {
        html << "<h2>Frame time by image size</h2>\n<p>Vichitvejpaisal 2005 Table A-1, on " << escape_html(result.device)
             << ". "
             << (verdict.wall_time ? "Wall time from submission to glFinish: this device's GPU timer queries miss its "
                                     "work (llvmpipe rasterises later). Software rendering: compare ratios only."
                                   : "GPU timer queries.")
             << " Median of a few frames per view, mean over views.</p>\n";
        html << html_table({"resolution", "mesh ms", "stand-in ms", "mesh fps", "stand-in fps", "speed-up"}, fps_rows);
    }

    // Saraiva et al. Tables 1-3
    if (several_distances) {
        html << "<h2>Colour error by distance</h2>\n<p>Saraiva et al. Tables 1-3: total and average |dR|+|dG|+|dB| over "
                "the rectangle holding both objects.</p>\n";
        rows.clear();
        for (const auto& row : json["tables"]["by_fov_distance"])
            rows.push_back({fmt("%g", row["fov"].get<double>()), fmt("%g", row["distance"].get<double>()),
                            fmt("%.3e", row["rgb_total"].get<double>()), fmt("%.3e", row["rgb_avg"].get<double>()),
                            fmt("%.2f", row["luv_mean"].get<double>())});
        html << html_table({"fov", "rel. distance", "total", "average", "Luv"}, rows);
    }
    if (!charts.empty()) {
        html << "<h2>Charts</h2>\n";
        for (const auto& [name, chart] : charts) html << "<img src='" << name << "' alt='" << escape_html(chart.title) << "'>\n";
    }
    html << "<p>Tables as CSV: ";
    for (const auto& [name, text] : eval_tables_csv(result)) html << "<a href='" << name << "'>" << name << "</a> ";
    html << "&middot; <a href='eval.json'>eval.json</a></p>\n";

    // image triplets
    html << "<h2>Views: truth, stand-in, Luv difference (black 0, white &ge; 50)</h2>\n";
    for (std::size_t i = 0; i < result.views.size(); ++i) {
        const ViewResult& v = result.views[i];
        std::string stem = view_stem(i);
        html << "<div class='triplet'><img loading='lazy' src='" << stem << "_truth.png' alt='truth " << i
             << "'><img loading='lazy' src='" << stem << "_standin.png' alt='stand-in " << i
             << "'><img loading='lazy' src='" << stem << "_diff.png' alt='difference " << i << "'>"
             << "<div class='caption'>#" << i << " az " << fmt("%g", v.view.orbit.azimuth_degrees) << " el "
             << fmt("%g", v.view.orbit.elevation_degrees) << " d " << fmt("%g", v.view.orbit.distance_rel) << " fov "
             << fmt("%g", v.view.orbit.fov_y_degrees) << " " << v.view.width << "x" << v.view.height << " &middot; Luv "
             << fmt("%.2f", v.metrics.luv_mean) << " &middot; &Delta;E00 " << fmt("%.2f", v.metrics.de2000_mean)
             << " &middot; IoU " << fmt("%.3f", v.metrics.iou) << " &middot; PSNR " << fmt("%.1f", v.metrics.psnr)
             << "</div></div>\n";
    }
    html << "</body></html>\n";
    STANDIN_RETURN_IF_ERROR(write_file_atomic((dir / "index.html").string(), html.str()));

    STANDIN_RETURN_IF_ERROR(commit_path(state_->temporary, state_->directory));
    state_->finished = true;
    return Status::ok();
}

// ---------------------------------------------------------------------------------------------
// Comparison of several stand-ins (eval.h)

std::optional<std::pair<double, double>> comparison_frame_ms(const nlohmann::json& eval)
{
    const std::string timing = eval.contains("verdict") ? json_text(eval["verdict"].value("timing", nlohmann::json("none"))) : "none";
    if (timing == "none" || !eval.contains("views")) return std::nullopt;
    const char* standin_key = timing == "wall" ? "standin_wall_ms" : "standin_ms";
    const char* mesh_key = timing == "wall" ? "truth_wall_ms" : "truth_ms";
    double standin = 0.0, mesh = 0.0;
    std::size_t timed = 0;
    for (const nlohmann::json& view : eval["views"]) {
        const double s = view.value(standin_key, 0.0), m = view.value(mesh_key, 0.0);
        if (s <= 0.0 || m <= 0.0) continue;
        standin += s, mesh += m, ++timed;
    }
    if (timed == 0) return std::nullopt;
    return std::make_pair(standin / double(timed), mesh / double(timed));
}

ImageRGBA8 comparison_picture(const ImageRGBA8& picture)
{
    constexpr int k_grey = 64; // a dark grey behind the transparent background (most models are lighter)
    const int factor = std::max(1, (picture.width + k_comparison_sheet_width - 1) / k_comparison_sheet_width);
    ImageRGBA8 out(picture.width / factor, picture.height / factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            int sum[3] = {0, 0, 0};
            for (int j = 0; j < factor; ++j)
                for (int i = 0; i < factor; ++i) {
                    const std::uint8_t* p = picture.at(x * factor + i, y * factor + j);
                    for (int c = 0; c < 3; ++c) sum[c] += (p[c] * p[3] + k_grey * (255 - p[3]) + 127) / 255;
                }
            std::uint8_t* q = out.at(x, y);
            for (int c = 0; c < 3; ++c) q[c] = std::uint8_t((sum[c] + factor * factor / 2) / (factor * factor));
            q[3] = 255;
        }
    return out;
}

namespace {

// Column labels of the contact sheet: "T" (the truth) and the stand-ins' numbers, in a 3 x 5 pixel
// font drawn 3 times larger, white on a black box in each first-row picture's top-left corner.
void draw_label(ImageRGBA8& image, int x0, int y0, const std::string& text)
{
    static const char* const glyphs[] = {"111101101101111", "010110010010111", "111001111100111", "111001111001111",
                                         "101101111001001", "111100111001111", "111100111101111", "111001001001001",
                                         "111101111101111", "111101111001111"};
    static const char* const truth_glyph = "111010010010010";
    constexpr int k_scale = 3;
    const int width = int(text.size()) * 4 * k_scale + k_scale, height = 7 * k_scale;
    for (int y = 0; y < height && y0 + y < image.height; ++y)
        for (int x = 0; x < width && x0 + x < image.width; ++x) {
            std::uint8_t* p = image.at(x0 + x, y0 + y);
            p[0] = p[1] = p[2] = 0;
        }
    for (std::size_t k = 0; k < text.size(); ++k) {
        const char* glyph = text[k] == 'T' ? truth_glyph : text[k] >= '0' && text[k] <= '9' ? glyphs[text[k] - '0'] : nullptr;
        if (!glyph) continue;
        for (int gy = 0; gy < 5; ++gy)
            for (int gx = 0; gx < 3; ++gx) {
                if (glyph[gy * 3 + gx] != '1') continue;
                for (int y = 0; y < k_scale; ++y)
                    for (int x = 0; x < k_scale; ++x) {
                        const int px = x0 + k_scale + int(k) * 4 * k_scale + gx * k_scale + x, py = y0 + k_scale + gy * k_scale + y;
                        if (px < image.width && py < image.height) {
                            std::uint8_t* p = image.at(px, py);
                            p[0] = p[1] = p[2] = 255;
                        }
                    }
            }
    }
}

} // namespace

ImageRGBA8 comparison_sheet(const std::vector<ImageRGBA8>& truth, const std::vector<ComparedStandin>& standins)
{
    constexpr int k_gap = 4;
    std::vector<const std::vector<ImageRGBA8>*> columns = {&truth};
    for (const ComparedStandin& s : standins) columns.push_back(&s.pictures);
    std::size_t rows = 0;
    int width = 0, height = 0;
    for (const auto* column : columns) rows = std::max(rows, column->size());
    std::vector<int> column_width(columns.size(), 0), row_height(rows, 0);
    for (std::size_t c = 0; c < columns.size(); ++c)
        for (std::size_t r = 0; r < columns[c]->size(); ++r) {
            column_width[c] = std::max(column_width[c], (*columns[c])[r].width);
            row_height[r] = std::max(row_height[r], (*columns[c])[r].height);
        }
    for (int w : column_width) width += w + k_gap;
    for (int h : row_height) height += h + k_gap;
    ImageRGBA8 sheet(std::max(width - k_gap, 1), std::max(height - k_gap, 1));
    std::fill(sheet.pixels.begin(), sheet.pixels.end(), std::uint8_t(255));
    int y0 = 0;
    for (std::size_t r = 0; r < rows; ++r) {
        int x0 = 0;
        for (std::size_t c = 0; c < columns.size(); ++c) {
            if (r < columns[c]->size()) {
                const ImageRGBA8& picture = (*columns[c])[r];
                for (int y = 0; y < picture.height; ++y)
                    std::copy_n(picture.at(0, y), std::size_t(picture.width) * 4, sheet.at(x0, y0 + y));
                if (r == 0) draw_label(sheet, x0, y0, c == 0 ? std::string("T") : std::to_string(c));
            }
            x0 += column_width[c] + k_gap;
        }
        y0 += row_height[r] + k_gap;
    }
    return sheet;
}

nlohmann::json comparison_to_json(const std::string& model, const std::string& protocol, const std::string& device,
                                  const std::string& command, const std::vector<ComparedStandin>& standins)
{
    nlohmann::json doc = {{"format", "standin-eval-comparison"}, {"version", 1},   {"model", model},
                          {"protocol", protocol},                {"device", device}, {"command", command}};
    nlohmann::json list = nlohmann::json::array();
    for (const ComparedStandin& s : standins)
        list.push_back({{"package", s.package},
                        {"representation", s.representation},
                        {"bytes", s.bytes},
                        {"report", s.report.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.report)},
                        {"eval", s.json}});
    doc["standins"] = list;
    return doc;
}

Status write_comparison_page(const std::string& directory, const nlohmann::json& comparison,
                             const std::vector<ImageRGBA8>& truth, const std::vector<ComparedStandin>& standins)
{
    const fs::path dir(directory);
    STANDIN_RETURN_IF_ERROR(write_file_atomic((dir / "comparison.json").string(), comparison.dump(2) + "\n"));
    STANDIN_RETURN_IF_ERROR(write_png(comparison_sheet(truth, standins), (dir / "sheet.png").string()));

    std::ostringstream html;
    html << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'><title>standin eval: "
         << standins.size() << " stand-ins of " << escape_html(json_text(comparison["model"])) << "</title>\n<style>\n"
         << "body{font-family:sans-serif;margin:2em;max-width:1600px;color:#222}\n"
         << "table{border-collapse:collapse;margin:0.5em 0 1.5em}\n"
         << "th,td{border:1px solid #bbb;padding:3px 8px;text-align:right;font-size:13px}\n"
         << "th{background:#eee}\ntd.text{text-align:left}\n.row{margin:0 0 1em}\n"
         << ".cell{display:inline-block;margin-right:4px;vertical-align:top}\n"
         << ".cell img{border:1px solid #999;max-width:320px;image-rendering:pixelated}\n"
         << ".caption{font-size:12px}\n</style></head><body>\n";
    html << "<h1>standin eval: " << standins.size() << " stand-ins of " << escape_html(json_text(comparison["model"]))
         << "</h1>\n";
    std::vector<std::vector<std::string>> identity_rows;
    for (const char* key : {"model", "protocol", "device", "command"})
        identity_rows.push_back({key, json_text(comparison[key])});
    html << html_table({"", ""}, identity_rows);

    // the figures, one row per stand-in, each linking its own report
    std::uint64_t source_bytes = 0;
    {
        std::error_code ec;
        const std::uintmax_t size = fs::file_size(json_text(comparison["model"]), ec);
        if (!ec) source_bytes = size;
    }
    html << "<h2>Figures</h2>\n<p>Means over the protocol's views; each stand-in's own report holds its tables, "
            "charts and every view with its difference image.</p>\n<table><tr><th>#</th><th>stand-in</th>"
            "<th>representation</th><th>bytes</th>"
         << (source_bytes > 0 ? "<th>of the source</th>" : "")
         << "<th>Luv</th><th>CIEDE2000</th><th>IoU</th><th>holes</th><th>spill</th><th>PSNR dB</th>"
            "<th>frame ms: stand-in / mesh</th><th>verdict</th></tr>\n";
    for (std::size_t k = 0; k < standins.size(); ++k) {
        const ComparedStandin& s = standins[k];
        const nlohmann::json& summary = s.json["summary"];
        const std::string name = escape_html(s.package);
        html << "<tr><td>" << k + 1 << "</td><td class='text'>"
             << (s.report.empty() ? name : "<a href='" + escape_html(s.report) + "/index.html'>" + name + "</a>")
             << "</td><td class='text'>" << escape_html(s.representation) << "</td><td>" << s.bytes << "</td>";
        if (source_bytes > 0) html << "<td>" << fmt("%.1f%%", 100.0 * double(s.bytes) / double(source_bytes)) << "</td>";
        html << "<td>" << fmt("%.3f", summary["luv_mean"].get<double>()) << "</td><td>"
             << fmt("%.3f", summary["de2000_mean"].get<double>()) << "</td><td>" << fmt("%.4f", summary["iou"].get<double>())
             << "</td><td>" << fmt("%.3f%%", 100.0 * summary["hole_fraction"].get<double>()) << "</td><td>"
             << fmt("%.3f%%", 100.0 * summary["spill_fraction"].get<double>()) << "</td><td>"
             << fmt("%.2f", summary["psnr"].get<double>()) << "</td><td>";
        if (const auto ms = comparison_frame_ms(s.json)) html << fmt("%.2f", ms->first) << " / " << fmt("%.2f", ms->second);
        else html << "not timed";
        html << "</td><td class='text'>" << escape_html(json_text(s.json["verdict"]["line"])) << "</td></tr>\n";
    }
    html << "</table>\n";

    // the sheet, then every view side by side (the pictures of the stand-ins' own reports)
    html << "<h2>Side by side</h2>\n<p>Columns: the truth, then the stand-ins in the order above; rows: the protocol's first "
         << std::min(truth.size(), k_comparison_sheet_views) << " views (<a href='sheet.png'>sheet.png</a>).</p>\n"
         << "<img src='sheet.png' alt='truth and stand-ins side by side' style='max-width:100%'>\n";
    const bool reports = !standins.empty() && !standins.front().report.empty();
    if (reports) {
        const nlohmann::json& views = standins.front().json["views"];
        html << "<h2>Every view</h2>\n";
        for (std::size_t i = 0; i < views.size(); ++i) {
            const nlohmann::json& v = views[i];
            html << "<div class='row'><div class='caption'>#" << i << " az " << fmt("%g", v["azimuth"].get<double>())
                 << " el " << fmt("%g", v["elevation"].get<double>()) << " d " << fmt("%g", v["distance"].get<double>())
                 << " " << v["width"].get<int>() << "x" << v["height"].get<int>() << "</div>";
            html << "<div class='cell'><img loading='lazy' src='" << escape_html(standins.front().report) << "/"
                 << view_stem(i) << "_truth.png' alt='truth'><div class='caption'>truth</div></div>";
            for (std::size_t k = 0; k < standins.size(); ++k) {
                const nlohmann::json& views_k = standins[k].json["views"];
                const double luv = i < views_k.size() ? views_k[i]["luv_mean"].get<double>() : 0.0;
                html << "<div class='cell'><img loading='lazy' src='" << escape_html(standins[k].report) << "/"
                     << view_stem(i) << "_standin.png' alt='" << k + 1 << "'><div class='caption'>" << k + 1 << " "
                     << escape_html(standins[k].representation) << " &middot; Luv " << fmt("%.2f", luv) << "</div></div>";
            }
            html << "</div>\n";
        }
    }
    html << "</body></html>\n";
    return write_file_atomic((dir / "index.html").string(), html.str());
}

} // namespace standin
