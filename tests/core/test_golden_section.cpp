// The one-parameter minimiser and curvature error of core/golden_section.hpp against closed forms.
#include "core/golden_section.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace pw {
namespace {

TEST(GoldenSection, FindsAParabolasVertexToTheFinalBracketsWidth) {
  int calls = 0;
  auto f = [&](double x) {
    ++calls;
    return 3.0 * (x - 0.7) * (x - 0.7) + 2.0;
  };
  const BracketedMinimum m = golden_section_minimum(f, -2.0, 4.0, 40);
  // Each reduction keeps 0.618 of the bracket: 6 * 0.618^40 = 2.7e-8.
  EXPECT_NEAR(m.width, 6.0 * std::pow((std::sqrt(5.0) - 1) / 2, 40), 1e-12);
  EXPECT_NEAR(m.x, 0.7, m.width);
  EXPECT_NEAR(m.value, 2.0, 3.0 * m.width * m.width);
  EXPECT_FALSE(m.at_edge);
  EXPECT_EQ(calls, 42);  // two interior points, then one evaluation per reduction
}

TEST(GoldenSection, AMinimumBeyondTheIntervalIsReportedAtItsEdge) {
  auto f = [](double x) { return (x - 5.0) * (x - 5.0); };
  const BracketedMinimum up = golden_section_minimum(f, -1.0, 1.0, 30);
  EXPECT_TRUE(up.at_edge);
  EXPECT_NEAR(up.x, 1.0, up.width);
  auto g = [](double x) { return (x + 5.0) * (x + 5.0); };
  const BracketedMinimum down = golden_section_minimum(g, -1.0, 1.0, 30);
  EXPECT_TRUE(down.at_edge);
  EXPECT_NEAR(down.x, -1.0, down.width);
}

TEST(ExpandingGoldenSection, FollowsAMinimumFarBeyondTheFirstBracketAndKeepsOneInside) {
  // A housing gain's profile (compare.cpp): ln g0 +- 0.4 first. A vertex 6 beyond the start (a
  // gain 400 times smaller) is reached by the doublings (0.8, 1.6, 3.2, 6.4), to the last
  // bracket's resolution; one inside the first bracket gives golden_section_minimum's answer.
  auto far = [](double x) { return 4.0 * (x + 6.0) * (x + 6.0) + 1.0; };
  const BracketedMinimum m = expanding_golden_section_minimum(far, 0.0, 0.4, 30, 8, 0.01);
  EXPECT_FALSE(m.at_edge);
  EXPECT_NEAR(m.x, -6.0, m.width);
  EXPECT_GT(m.width, 0.0);
  EXPECT_TRUE(golden_section_minimum(far, -0.4, 0.4, 30).at_edge);  // the first bracket alone: at its edge
  auto near = [](double x) { return (x - 0.1) * (x - 0.1); };
  const BracketedMinimum a = expanding_golden_section_minimum(near, 0.0, 0.4, 30, 8, 0.01);
  const BracketedMinimum b = golden_section_minimum(near, -0.4, 0.4, 30);
  EXPECT_EQ(a.x, b.x);
  EXPECT_EQ(a.width, b.width);
  EXPECT_FALSE(a.at_edge);
}

TEST(ExpandingGoldenSection, AFunctionThatFlattensTowardsAnEdgeStaysAtTheEdge) {
  // chi2 falling towards g -> 0 without a minimum: in ln g, c + exp(x) (rounding hides the slope
  // far down). No wider bracket lowers it by the resolution once exp(x) is below it: the
  // doubling stops there, at an edge.
  auto flat = [](double x) { return 100.0 + std::exp(x); };
  const BracketedMinimum m = expanding_golden_section_minimum(flat, 0.0, 0.4, 30, 8, 0.01);
  EXPECT_TRUE(m.at_edge);
  EXPECT_LT(std::exp(m.x), 0.05);  // went down while that still lowered f by more than 0.01
  // A minimum beyond every bracket (8 doublings reach +-102.4 + the path there) is at the edge too.
  auto beyond = [](double x) { return (x - 1000.0) * (x - 1000.0); };
  EXPECT_TRUE(expanding_golden_section_minimum(beyond, 0.0, 0.4, 30, 8, 0.01).at_edge);
}

TEST(Chi2CurvatureStd, IsTheStandardDeviationOfAGaussianLikelihood) {
  // chi2(x) = (x - mu)^2 / sigma^2: its minimiser has standard error sigma (exact for a parabola,
  // up to the round-off of the central difference).
  const double sigma = 0.037;
  auto chi2 = [&](double x) { return (x - 1.3) * (x - 1.3) / (sigma * sigma); };
  EXPECT_NEAR(chi2_curvature_std(chi2, 1.3, 1e-3), sigma, 1e-6 * sigma);
  auto flat = [](double) { return 5.0; };
  EXPECT_TRUE(std::isinf(chi2_curvature_std(flat, 0.0, 1e-3)));
  // A failed evaluation beside the minimum is no information, not an infinite curvature.
  auto failed_right = [&](double x) { return x > 1.3 ? std::numeric_limits<double>::infinity() : chi2(x); };
  EXPECT_TRUE(std::isinf(chi2_curvature_std(failed_right, 1.3, 1e-3)));
}

// The scan that scanned_minimum's callers hand it: f at each point, in order.
template <class F>
auto serial_scan(F& f) {
  return [&f](const std::vector<double>& xs) {
    std::vector<double> v;
    for (const double x : xs) v.push_back(f(x));
    return v;
  };
}

TEST(ScannedMinimum, FindsTheDeeperOfTwoWellsWhereGoldenSectionAloneTakesTheOther) {
  // Two parabolic wells: a shallow one at x = 1.2 (floor 1) and a deeper one at x = -1.5
  // (floor 0). The golden section's first two points (-0.472, 0.472) both lie in the shallow
  // well's basin, so alone it ends there; the scan's first cell centre (-1.714, f = 0.18) sees
  // the deep one.
  auto f = [](double x) { return std::min(1.0 + (x - 1.2) * (x - 1.2), 4.0 * (x + 1.5) * (x + 1.5)); };
  const BracketedMinimum local = golden_section_minimum(f, -2.0, 2.0, 30);
  ASSERT_NEAR(local.x, 1.2, 1e-3);  // the premise: golden section alone is trapped
  const ScannedMinimum m = scanned_minimum(f, serial_scan(f), -2.0, 2.0, 7, 12, 0.02);
  EXPECT_FALSE(m.failed);
  EXPECT_FALSE(m.at_edge);
  // A parabola is fitted exactly by the three-point step: the vertex to round-off, far inside
  // the final bracket (3 cells x 0.618^12 = 5.7e-3 wide).
  EXPECT_NEAR(m.x, -1.5, 1e-9);
  EXPECT_NEAR(m.value, 0.0, 1e-12);
  ASSERT_EQ(m.scan_x.size(), 7u);
  EXPECT_DOUBLE_EQ(m.scan_x.front(), -2.0 + 0.5 * 4.0 / 7);
}

TEST(ScannedMinimum, EvaluatesTheScanTheGoldenSectionAndOneParabolicStep) {
  int calls = 0;
  auto f = [&](double x) {
    ++calls;
    return 5.0 * (x - 0.31) * (x - 0.31);
  };
  const ScannedMinimum m = scanned_minimum(f, serial_scan(f), -1.0, 1.0, 7, 12, 0.02);
  // 7 scan points, 2 + 12 golden-section points, the midpoint and its two neighbours, the vertex.
  EXPECT_EQ(calls, 7 + 14 + 3 + 1);
  EXPECT_NEAR(m.x, 0.31, 1e-9);
}

TEST(ScannedMinimum, AFailedEvaluationIsNeverChosenAndAllFailedIsReported) {
  const double inf = std::numeric_limits<double>::infinity();
  // The solver fails below x = -0.2, where the function would be lowest.
  auto f = [&](double x) { return x < -0.2 ? inf : (x + 0.5) * (x + 0.5); };
  const ScannedMinimum m = scanned_minimum(f, serial_scan(f), -1.0, 1.0, 7, 12, 0.02);
  EXPECT_FALSE(m.failed);
  EXPECT_TRUE(std::isfinite(m.value));
  EXPECT_GE(m.x, -0.2);
  EXPECT_EQ(m.value, f(m.x));
  EXPECT_LE(m.value, 0.25);  // no worse than the scan's best finite point (x = 0)

  int calls = 0;
  auto none = [&](double) {
    ++calls;
    return inf;
  };
  const ScannedMinimum all = scanned_minimum(none, serial_scan(none), -1.0, 1.0, 7, 12, 0.02);
  EXPECT_TRUE(all.failed);
  EXPECT_EQ(calls, 7);  // nothing evaluated beyond the scan
}

TEST(ScannedMinimum, AMinimumBeyondTheIntervalIsAtItsEdgeAndAnInteriorOneIsNot) {
  auto beyond = [](double x) { return (x - 3.0) * (x - 3.0); };
  const ScannedMinimum up = scanned_minimum(beyond, serial_scan(beyond), -1.0, 1.0, 7, 12, 0.02);
  EXPECT_TRUE(up.at_edge);
  EXPECT_NEAR(up.x, 1.0, 0.01);
  // The minimum in the last cell but inside the interval: the bracket's edge at the interval's
  // edge is not reached.
  auto inside = [](double x) { return (x - 0.8) * (x - 0.8); };
  const ScannedMinimum in = scanned_minimum(inside, serial_scan(inside), -1.0, 1.0, 7, 12, 0.02);
  EXPECT_FALSE(in.at_edge);
  EXPECT_NEAR(in.x, 0.8, 1e-9);
}

} // namespace
} // namespace pw
