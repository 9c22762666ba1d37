// Feature extraction on synthetic signals with known lines.
#include "diagnose/features.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pw::diagnose {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Features, FitLinesRecoversAmplitudesAndPhasesWithin1Percent) {
  // Mesh line, two sidebands 5.29 Hz apart, an offset and 5 % white noise.
  const double dt = 1.0 / 5000, t0 = 0.3237;
  const std::size_t n = 10000;  // 2 s
  const double f[] = {111.176, 111.176 - 5.294, 111.176 + 5.294, 222.35};
  const double A[] = {3.0, 0.4, 0.25, 1.1};
  const double ph[] = {0.3, -1.2, 2.0, 0.0};
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.05 * 2.2);
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double t = t0 + static_cast<double>(j) * dt;
    x[j] = 0.7 + noise(rng);
    for (int l = 0; l < 4; ++l) x[j] += A[l] * std::cos(2 * kPi * f[l] * t + ph[l]);
  }
  const auto lines = fit_lines(x, t0, dt, f);
  for (int l = 0; l < 4; ++l) {
    EXPECT_NEAR(std::abs(lines[l].amplitude), A[l], 0.01 * A[l]) << "line " << l;
    EXPECT_NEAR(std::arg(lines[l].amplitude), ph[l], 0.02) << "line " << l;
  }
}

TEST(Features, WhiteNoiseEstimateIsUnbiasedBesideStrongLines) {
  const double dt = 1e-4;
  const std::size_t n = 40000;
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double t = static_cast<double>(j) * dt;
    x[j] = noise(rng) + 20 * std::sin(2 * kPi * 111.2 * t) + 5 * std::sin(2 * kPi * 1234.5 * t);
  }
  const NoiseEstimate e = estimate_white_noise(x);
  EXPECT_NEAR(e.variance, 0.09, 4 * e.relative_uncertainty * 0.09);
  EXPECT_LT(e.relative_uncertainty, 0.03);
}

TEST(Features, SynchronousAverageKeepsTheSynchronousPulseAndItsPosition) {
  // A pulse once every 21 mesh cycles at u = 7.25 (mod 21), plus noise and a non-synchronous tone.
  const double fm = 111.176, dt = 1.0 / 8000;
  const std::size_t n = 8000 * 3;
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j) {
    const double t = static_cast<double>(j) * dt, u = fm * t;
    const double d = std::remainder(u - 7.25, 21.0);
    x[j] = std::exp(-d * d / (2 * 0.2 * 0.2)) + noise(rng) + 0.5 * std::sin(2 * kPi * 3.7 * t);
  }
  const auto tsa = synchronous_average(x, 0.0, dt, fm, 21, 16);
  ASSERT_GE(tsa.averages, 7);
  const auto pk = tsa_energy_peak(tsa);
  EXPECT_NEAR(pk.mesh_cycle, 7.25, 0.5);
  EXPECT_GT(pk.peak_to_mean, 5.0);
}

TEST(Features, InterpolationIsExactForCubics) {
  std::vector<double> x(20);
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double t = 0.5 + 0.1 * static_cast<double>(j);
    x[j] = 2 - t + 0.5 * t * t * t;
  }
  for (double t : {0.5, 0.537, 1.234, 2.39}) EXPECT_NEAR(interpolate_uniform(x, 0.5, 0.1, t), 2 - t + 0.5 * t * t * t, 1e-12);
}

} // namespace
} // namespace pw::diagnose
