// The report on a synthetic result with the shape of the saraiva protocol: Saraiva et al.-style table,
// log-axis charts, CSVs, image triplets, and an atomic directory.
#include "../../tests/test_support.h"

#include <standin/eval.h>
#include <standin/files.h>

#include <gtest/gtest.h>

#include <filesystem>

namespace standin {
namespace {

TEST(Report, WritesTablesChartsAndTriplets)
{
    EvalResult result;
    result.protocol = "saraiva";
    result.device = "test";
    RenderedImage image;
    image.color = ImageRGBA8(4, 4);
    image.color.at(1, 1)[3] = 255;
    for (float fov : {40.0f, 60.0f})
        for (float distance : {0.5f, 1.0f, 2.0f}) {
            ViewResult v;
            v.view.orbit.fov_y_degrees = fov;
            v.view.orbit.distance_rel = distance;
            v.view.width = v.view.height = 4;
            v.metrics.rgb_total = 1000.0 / distance;
            v.metrics.rgb_avg = 10.0 + distance;
            v.truth_ms = 2.0, v.standin_ms = 1.0;
            result.views.push_back(v);
        }
    std::string dir = test::fresh_directory("report") + "/out";
    Result<ReportWriter> writer = ReportWriter::begin(dir);
    ASSERT_TRUE(writer.is_ok()) << writer.status().message();
    for (std::size_t i = 0; i < result.views.size(); ++i)
        ASSERT_TRUE(writer->add_view(i, result.views[i], image, image).is_ok());
    EXPECT_FALSE(std::filesystem::exists(dir)); // nothing in place until finished
    ASSERT_TRUE(writer->finish(result, eval_to_json(result, {{"package", "p"}})).is_ok());

    for (const char* file : {"index.html", "eval.json", "chart_total_error.svg", "chart_average_error.svg",
                             "table_saraiva.csv", "images/005_diff.png"})
        EXPECT_TRUE(std::filesystem::exists(dir + "/" + file)) << file;
    // every view has one image size: a frame-rate chart would be one point, so there is none
    EXPECT_FALSE(std::filesystem::exists(dir + "/chart_fps.svg"));
    Result<std::string> html = read_file(dir + "/index.html");
    ASSERT_TRUE(html.is_ok());
    EXPECT_NE(html->find("<h2>Verdict</h2>"), std::string::npos);
    EXPECT_NE(html->find("cheaper than the mesh from 0.5x the base distance on"), std::string::npos);
    Result<std::string> csv = read_file(dir + "/table_saraiva.csv");
    ASSERT_TRUE(csv.is_ok());
    EXPECT_NE(csv->find("40,0.5,1,2000,10.5"), std::string::npos) << *csv;
    Result<std::string> svg = read_file(dir + "/chart_total_error.svg");
    ASSERT_TRUE(svg.is_ok());
    EXPECT_NE(svg->find("fov 60"), std::string::npos);
    EXPECT_NE(svg->find("1e3"), std::string::npos); // log10 axis tick
    // a second report replaces the first
    Result<ReportWriter> again = ReportWriter::begin(dir);
    ASSERT_TRUE(again.is_ok());
    ASSERT_TRUE(again->finish(result, eval_to_json(result)).is_ok());
    EXPECT_TRUE(std::filesystem::exists(dir + "/index.html"));
}

// A comparison's frame times: means over the timed views by the verdict's clock; none untimed.
TEST(Report, ComparisonFrameTimesFollowTheVerdictsClock)
{
    nlohmann::json eval = {{"verdict", {{"timing", "wall"}}},
                           {"views",
                            {{{"standin_wall_ms", 4.0}, {"truth_wall_ms", 2.0}, {"standin_ms", 1.0}, {"truth_ms", 1.0}},
                             {{"standin_wall_ms", 8.0}, {"truth_wall_ms", 4.0}, {"standin_ms", 1.0}, {"truth_ms", 1.0}},
                             {{"standin_wall_ms", 0.0}, {"truth_wall_ms", 0.0}}}}};
    auto ms = comparison_frame_ms(eval);
    ASSERT_TRUE(ms.has_value());
    EXPECT_DOUBLE_EQ(ms->first, 6.0);
    EXPECT_DOUBLE_EQ(ms->second, 3.0);
    eval["verdict"]["timing"] = "gpu";
    ms = comparison_frame_ms(eval);
    ASSERT_TRUE(ms.has_value());
    EXPECT_DOUBLE_EQ(ms->first, 1.0);
    eval["verdict"]["timing"] = "none";
    EXPECT_FALSE(comparison_frame_ms(eval).has_value());
}

} // namespace
} // namespace standin
