// Factor distributions (sweep/distribution.hpp): the inverse CDFs against
// closed forms (normal quantiles at tabulated probabilities, the lognormal's
// median, the triangular's explicit quantile), truncation, the finite tails at
// u = 0, and the moments a Latin hypercube of each distribution reproduces.
#include "sweep/design.hpp"

#include "core/error.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

namespace pw::sweep {
namespace {

Distribution normal(double mean, double sd) { return {DistributionKind::Normal, mean, sd, 0}; }
Distribution lognormal(double mean, double sd) { return {DistributionKind::LogNormal, mean, sd, 0}; }

TEST(Distribution, NormalQuantilesMatchTabulatedValues) {
  // Phi(1) = 0.841344746068543, Phi(-1.959963984540054) = 0.025 (Abramowitz & Stegun 26.2).
  const Distribution d = normal(0.06, 0.01);
  EXPECT_NEAR(inverse_cdf(d, 0.5), 0.06, 1e-15);
  EXPECT_NEAR(inverse_cdf(d, 0.841344746068543), 0.07, 1e-12);
  EXPECT_NEAR(inverse_cdf(d, 0.025), 0.06 - 0.01959963984540054, 1e-12);
}

TEST(Distribution, TruncationKeepsValuesInsideAndSpansTheBounds) {
  const Distribution d = normal(0.06, 0.01);
  EXPECT_DOUBLE_EQ(inverse_cdf(d, 0.0, 0.05, 0.08), 0.05);
  EXPECT_NEAR(inverse_cdf(d, std::nextafter(1.0, 0.0), 0.05, 0.08), 0.08, 1e-12);
  // The median of the truncated distribution: F(x) = (F(a) + F(b)) / 2.
  const double x = inverse_cdf(d, 0.5, 0.05, 0.08);
  const double Fa = 0.5 * std::erfc(1.0 / std::sqrt(2.0)), Fb = 0.5 * std::erfc(-2.0 / std::sqrt(2.0));
  EXPECT_NEAR(0.5 * std::erfc(-(x - 0.06) / 0.01 / std::sqrt(2.0)), 0.5 * (Fa + Fb), 1e-12);
  for (double u = 0; u < 1; u += 1.0 / 64) {
    const double v = inverse_cdf(d, u, 0.05, 0.08);
    EXPECT_GE(v, 0.05);
    EXPECT_LE(v, 0.08);
  }
}

TEST(Distribution, UntruncatedTailsStayFiniteAtTheCubesCorners) {
  // u = 0 is row 0 of an unshifted Saltelli design: p = 2^-33 gives z = -6.33796 (scipy.stats.norm.ppf) (not -infinity).
  const double z = inverse_cdf(normal(0, 1), 0.0);
  EXPECT_TRUE(std::isfinite(z));
  EXPECT_NEAR(z, -6.337957754553790, 1e-9);
  EXPECT_NEAR(inverse_cdf(normal(0, 1), std::nextafter(1.0, 0.0)), 6.337957754553790, 1e-9);
}

TEST(Distribution, LognormalHasTheGivenMeanAndItsMedianInClosedForm) {
  const Distribution d = lognormal(1000, 300);
  const double zeta2 = std::log(1 + 0.09);
  EXPECT_NEAR(inverse_cdf(d, 0.5), 1000 * std::exp(-0.5 * zeta2), 1e-9);  // median exp(lambda)
  // Mean of the quantiles at the midpoints of 2^16 strata: the integral of F^-1 over (0, 1) = the mean.
  const int n = 1 << 16;
  double sum = 0;
  for (int k = 0; k < n; ++k) sum += inverse_cdf(d, (k + 0.5) / n);
  EXPECT_NEAR(sum / n, 1000, 0.5);  // the midpoint rule's error in the tails, measured 0.06
}

TEST(Distribution, TriangularQuantileIsTheClosedForm) {
  // F^-1(u) = a + sqrt(u (b - a)(c - a)) for u < (c - a)/(b - a), else b - sqrt((1 - u)(b - a)(b - c)).
  const Distribution d{DistributionKind::Triangular, 0, 0, 200};
  const double a = 100, c = 200, b = 400;
  for (double u : {0.0, 0.1, 0.3, 1.0 / 3.0, 0.5, 0.9, 0.999}) {
    const double expected = u < (c - a) / (b - a) ? a + std::sqrt(u * (b - a) * (c - a))
                                                  : b - std::sqrt((1 - u) * (b - a) * (b - c));
    EXPECT_NEAR(inverse_cdf(d, u, a, b), expected, 1e-9) << "u = " << u;
  }
}

Factor sampled(std::string key, Distribution d) {
  Factor f;
  f.key = std::move(key);
  f.unit = "-";
  f.distribution = d;
  return f;
}

TEST(Distribution, LatinHypercubeReproducesTheMoments) {
  DesignSpec spec;
  spec.type = DesignType::LatinHypercube;
  spec.samples = 4000;
  spec.seed = 3;
  Factor tri = sampled("c", {DistributionKind::Triangular, 0, 0, 200});
  tri.min = 100;
  tri.max = 400;
  const auto cases = make_design({sampled("a", normal(0.06, 0.01)), sampled("b", lognormal(1000, 300)), tri}, spec);
  std::vector<double> mean(3, 0), var(3, 0);
  for (const auto& p : cases)
    for (int j = 0; j < 3; ++j) mean[j] += p.values[j] / 4000;
  for (const auto& p : cases)
    for (int j = 0; j < 3; ++j) var[j] += (p.values[j] - mean[j]) * (p.values[j] - mean[j]) / 3999;
  // One value per stratum: the sample moments are those of the distribution up to the
  // discretization of the tails (a few 1e-3 relative at n = 4000), far inside the 1/sqrt(n)
  // = 1.6 % of independent sampling.
  EXPECT_NEAR(mean[0], 0.06, 0.01 * 0.01);
  EXPECT_NEAR(std::sqrt(var[0]), 0.01, 0.01 * 0.01);
  EXPECT_NEAR(mean[1], 1000, 3);
  EXPECT_NEAR(std::sqrt(var[1]), 300, 3);
  EXPECT_NEAR(mean[2], (100 + 200 + 400) / 3.0, 0.5);
  // Triangular variance (a^2 + b^2 + c^2 - ab - ac - bc) / 18.
  EXPECT_NEAR(var[2], (1e4 + 4e4 + 16e4 - 2e4 - 4e4 - 8e4) / 18.0, 0.01 * 3888.9);
}

TEST(Distribution, ParameterErrorsNameTheFactorsKey) {
  DesignSpec spec;
  spec.type = DesignType::LatinHypercube;
  spec.samples = 10;
  auto param = [&](Factor f) {
    const auto e = pw::test::thrown<InputError>([&] { (void)make_design({f}, spec); });
    return e ? e->parameter() : std::string("accepted");
  };
  EXPECT_EQ(param(sampled("a", normal(0.06, 0))), "factors[0].std_dev");
  EXPECT_EQ(param(sampled("a", normal(0.06, -1))), "factors[0].std_dev");
  EXPECT_EQ(param(sampled("a", lognormal(-1, 1))), "factors[0].mean");
  Factor tri = sampled("a", {DistributionKind::Triangular, 0, 0, 500});
  tri.min = 100;
  tri.max = 400;
  EXPECT_EQ(param(tri), "factors[0].mode");
  tri.min.reset();
  EXPECT_EQ(param(tri), "factors[0].min");
  Factor far = sampled("a", normal(0, 1));  // truncation 100 standard deviations out: no probability
  far.min = 100;
  far.max = 101;
  EXPECT_EQ(param(far), "factors[0].min");
  Factor logscale = sampled("a", normal(1, 0.1));
  logscale.scale = Scale::Log;
  EXPECT_EQ(param(logscale), "factors[0].scale");
  DesignSpec factorial;
  factorial.type = DesignType::FullFactorial;
  Factor lv = sampled("a", normal(1, 0.1));
  lv.levels = {1, 2};
  const auto e = pw::test::thrown<InputError>([&] { (void)make_design({lv}, factorial); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "factors[0].distribution");
}

} // namespace
} // namespace pw::sweep
