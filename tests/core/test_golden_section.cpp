// The one-parameter minimiser and curvature error of core/golden_section.hpp against closed forms.
#include "core/golden_section.hpp"

#include <gtest/gtest.h>

#include <cmath>

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

TEST(Chi2CurvatureStd, IsTheStandardDeviationOfAGaussianLikelihood) {
  // chi2(x) = (x - mu)^2 / sigma^2: its minimiser has standard error sigma (exact for a parabola,
  // up to the round-off of the central difference).
  const double sigma = 0.037;
  auto chi2 = [&](double x) { return (x - 1.3) * (x - 1.3) / (sigma * sigma); };
  EXPECT_NEAR(chi2_curvature_std(chi2, 1.3, 1e-3), sigma, 1e-6 * sigma);
  auto flat = [](double) { return 5.0; };
  EXPECT_TRUE(std::isinf(chi2_curvature_std(flat, 0.0, 1e-3)));
}

} // namespace
} // namespace pw
