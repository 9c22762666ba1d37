// Levenberg-Marquardt on an analytic model with a known covariance.
#include "diagnose/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace pw::diagnose {
namespace {

TEST(Fit, RecoversExponentialDecayParametersAndTheirCovariance) {
  // y = a exp(-b t) + noise (unit variance after whitening by sigma).
  const double a = 2.5, b = 1.7, sigma = 0.02;
  const int m = 200;
  std::vector<double> t(m), y(m);
  std::mt19937 rng(7);
  std::normal_distribution<double> nd(0.0, sigma);
  for (int i = 0; i < m; ++i) {
    t[i] = 3.0 * i / m;
    y[i] = a * std::exp(-b * t[i]) + nd(rng);
  }
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) r[i] = (y[i] - x[0] * std::exp(-x[1] * t[i])) / sigma;
    return r;
  };
  LmOptions o;
  o.max_iterations = 50;
  o.relative_tolerance = 1e-10;
  o.step = 1e-6;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {{0.1, 10, true}, {0.01, 10, false}}, {1.0, 0.5}, o);
  // Analytic covariance (J^T J)^{-1} at the truth.
  double s11 = 0, s12 = 0, s22 = 0;
  for (int i = 0; i < m; ++i) {
    const double e = std::exp(-b * t[i]);
    const double j1 = -e / sigma, j2 = a * t[i] * e / sigma;
    s11 += j1 * j1, s12 += j1 * j2, s22 += j2 * j2;
  }
  const double det = s11 * s22 - s12 * s12;
  const double sa = std::sqrt(s22 / det), sb = std::sqrt(s11 / det);
  EXPECT_NEAR(r.x[0], a, 4 * sa);
  EXPECT_NEAR(r.x[1], b, 4 * sb);
  EXPECT_NEAR(r.std_error[0], sa, 0.05 * sa);
  EXPECT_NEAR(r.std_error[1], sb, 0.05 * sb);
  EXPECT_NEAR(r.covariance[0][1], -s12 / det, 0.05 * std::fabs(s12 / det));
  EXPECT_NEAR(r.cost, m, 4 * std::sqrt(2.0 * m));  // chi2(m - 2)
}

TEST(Fit, StaysInsideTheBoxAndFlagsTheBound) {
  // Minimum at x = 3 outside [0, 2]: the estimate sits on the upper bound.
  ResidualFn f = [](const std::vector<double>& x, const std::vector<double>*) {
    return std::vector<double>{x[0] - 3.0, 0.1 * (x[0] - 3.0)};
  };
  LmOptions o;
  o.threads = 1;
  o.max_iterations = 30;
  const LmResult r = levenberg_marquardt(f, {{0.0, 2.0, false}}, {0.5}, o);
  EXPECT_NEAR(r.x[0], 2.0, 1e-9);
  EXPECT_TRUE(r.at_bound[0]);
}

TEST(Fit, WithNoParametersReturnsTheModelAsItIsWithoutIterating) {
  // `diagnose --candidates backlash` leaves no nuisance parameters: the fit is one
  // evaluation (this crashed in the covariance step before).
  int calls = 0;
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    ++calls;
    EXPECT_TRUE(x.empty());
    return std::vector<double>{3.0, 4.0};
  };
  LmOptions o;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {}, {}, o);
  EXPECT_EQ(calls, 1);
  EXPECT_DOUBLE_EQ(r.cost, 25.0);
  EXPECT_TRUE(r.x.empty());
  EXPECT_TRUE(r.std_error.empty());
  EXPECT_TRUE(r.converged);
}

} // namespace
} // namespace pw::diagnose
