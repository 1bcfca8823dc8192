// The verdict of an evaluation on hand-made results: the distance from which the stand-in is as
// good as the mesh, and from which it is cheaper, with the clock the device can be trusted with.
#include <standin/eval.h>

#include <gtest/gtest.h>

namespace standin {
namespace {

ViewResult view(float distance, double de2000, double truth_ms, double standin_ms, std::size_t truth_pixels)
{
    ViewResult v;
    v.view.orbit.distance_rel = distance;
    v.metrics.de2000_mean = de2000;
    v.metrics.truth_pixels = truth_pixels;
    v.truth_ms = v.truth_wall_ms = truth_ms;
    v.standin_ms = v.standin_wall_ms = standin_ms;
    return v;
}

TEST(Verdict, FindsTheDistancesFromWhichTheStandInIsAsGoodAndCheaper)
{
    EvalResult result;
    result.device = "some GPU";
    // error falls with distance, and the stand-in's cost with its pixels
    result.views = {view(0.5f, 6.0, 1.0, 4.0, 200000), view(1.0f, 2.5, 1.0, 2.0, 90000), view(2.0f, 1.9, 1.0, 0.9, 20000),
                    view(4.0f, 1.2, 1.0, 0.3, 5000),   view(8.0f, 0.8, 1.0, 0.1, 1200)};
    Verdict v = eval_verdict(result);
    ASSERT_TRUE(v.indistinguishable_from);
    EXPECT_EQ(*v.indistinguishable_from, 2.0f);
    ASSERT_TRUE(v.cheaper_from);
    EXPECT_EQ(*v.cheaper_from, 2.0f);
    EXPECT_EQ(v.cheaper_below_pixels, 20000.0);
    EXPECT_FALSE(v.wall_time);
    EXPECT_NE(v.line.find("from 2x the base distance"), std::string::npos) << v.line;

    // a near distance that is good again does not count: every distance beyond must pass too
    result.views.push_back(view(16.0f, 3.0, 1.0, 0.05, 300));
    v = eval_verdict(result);
    EXPECT_FALSE(v.indistinguishable_from);
    EXPECT_NE(v.line.find("distinguishable from the mesh at every distance"), std::string::npos) << v.line;
}

TEST(Verdict, UsesWallTimeWhereGpuTimersMissTheWork)
{
    EvalResult result;
    result.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
    ViewResult v = view(1.0f, 0.5, 0.0, 0.0, 1000);
    v.truth_wall_ms = 3.0;
    v.standin_wall_ms = 1.0;
    result.views = {v};
    Verdict verdict = eval_verdict(result);
    EXPECT_TRUE(verdict.wall_time);
    EXPECT_TRUE(verdict.timed);
    EXPECT_TRUE(verdict.indistinguishable_from);
    EXPECT_NE(verdict.line.find("cheaper than the mesh there (1.000 vs 3.000 ms, wall time"), std::string::npos) << verdict.line;

    // untimed evaluations say so instead of comparing zeros
    result.views[0].truth_wall_ms = result.views[0].standin_wall_ms = 0.0;
    verdict = eval_verdict(result);
    EXPECT_FALSE(verdict.timed);
    EXPECT_FALSE(verdict.cheaper_from);
    EXPECT_NE(verdict.line.find("not timed"), std::string::npos) << verdict.line;
}

} // namespace
} // namespace standin
