// Gear condition indicators against closed forms (docs/indicators.md §5).
// Every tolerance is stated with its reason: exact identities are checked to
// a few hundred ulps of FFT round-off (1e-12 relative), statistical ones to
// four standard errors of the estimator (a false failure with probability
// ~6e-5; the seeds are fixed, so a run is deterministic).
#include "core/constants.hpp"
#include "core/error.hpp"
#include "signal/condition_indicators.hpp"
#include "signal/resample.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace {

namespace sg = pw::signal;
using pw::kPi;
constexpr double kExact = 1e-12;  // relative: FFT round-off O(eps log n) with margin

/// sum_i a_i cos(o_i theta_j + phi_i) on n samples of one revolution.
std::vector<double> tones(std::size_t n, const std::vector<std::array<double, 3>>& parts) {
  std::vector<double> x(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const double th = 2 * kPi * static_cast<double>(j) / static_cast<double>(n);
    for (const auto& [a, order, phase] : parts) x[j] += a * std::cos(order * th + phase);
  }
  return x;
}

std::vector<double> gaussian(std::size_t n, double sigma, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> nd(0.0, sigma);
  std::vector<double> x(n);
  for (double& v : x) v = nd(gen);
  return x;
}

TEST(ConditionIndicators, SinusoidHasCrestFactorSqrt2AndKurtosis1p5) {
  // 1024 samples hold the peak (n divisible by 4 x order): max|x| = A exactly, sum sin^4 = 3n/8.
  const auto x = tones(1024, {{2.5, 8, -kPi / 2}});
  EXPECT_NEAR(sg::crest_factor(x), std::sqrt(2.0), kExact);
  EXPECT_NEAR(sg::kurtosis(x), 1.5, kExact);
  EXPECT_NEAR(sg::rms(x), 2.5 / std::sqrt(2.0), kExact);
  EXPECT_NEAR(sg::peak_to_peak(x), 5.0, kExact);
}

TEST(ConditionIndicators, GaussianNoiseMomentsWithinFourStandardErrors) {
  // N Gaussian samples: kurtosis 3 with standard error sqrt(24/N) = 0.0191 (N = 65536); m6/m2^3 = 15 and
  // m8/m2^4 = 105 with standard errors 0.315 and 5.16 at this N (Monte Carlo, 400 numpy trials of N samples,
  // docs/indicators.md §5). Tolerance: 4 standard errors each.
  const std::size_t n = 1u << 16;
  const auto x = gaussian(n, 0.7, 12345);
  const double se = std::sqrt(24.0 / static_cast<double>(n));
  EXPECT_NEAR(sg::kurtosis(x), 3.0, 4 * se);
  EXPECT_NEAR(sg::fm4(x), 3.0, 4 * se);
  EXPECT_NEAR(sg::m6a(x), 15.0, 4 * 0.315);
  EXPECT_NEAR(sg::m8a(x), 105.0, 4 * 5.16);
  // Crest factor: the largest of 65536 |N(0,1)| over the std is 4.44 +- 0.28 (Monte Carlo as above): 4 x 0.28.
  EXPECT_NEAR(sg::crest_factor(x), 4.44, 4 * 0.28);
}

TEST(ConditionIndicators, FourthMomentOfSinusoidPlusImpulseMatchesClosedForm) {
  // x = A sin(5 theta) + h delta_{j,0}: sin(0) = 0, so the impulse adds to a zero sample.
  // With mu = h/n and sums over whole periods (sum s = sum s^3 = 0, sum s^2 = n A^2/2, sum s^4 = 3 n A^4/8):
  //   S2 = n A^2/2 + n mu^2 - mu^2 + (h - mu)^2
  //   S4 = 3 n A^4/8 + 6 mu^2 n A^2/2 + n mu^4 - mu^4 + (h - mu)^4
  //   FM4 = n S4 / S2^2.
  const std::size_t n = 2048;
  const double A = 1.0, h = 12.0, nn = static_cast<double>(n), mu = h / nn;
  auto x = tones(n, {{A, 5, -kPi / 2}});
  const double healthy = sg::fm4(x);
  x[0] += h;
  const double s2 = nn * A * A / 2 + nn * mu * mu - mu * mu + (h - mu) * (h - mu);
  const double s4 = 3 * nn * std::pow(A, 4) / 8 + 6 * mu * mu * nn * A * A / 2 + nn * std::pow(mu, 4) -
                    std::pow(mu, 4) + std::pow(h - mu, 4);
  const double expected = nn * s4 / (s2 * s2);
  EXPECT_NEAR(healthy, 1.5, kExact);
  EXPECT_NEAR(sg::fm4(x), expected, kExact * expected);
  EXPECT_GT(sg::fm4(x), 3.0 + 10.0);  // 16.9: the impulse dominates the fourth moment
}

TEST(ConditionIndicators, Fm0OfPureMeshHarmonicIsTwoAndOfTwoHarmonicsIsClosedForm) {
  // Z = 20 teeth, n = 1600 samples: both the mesh peak (theta = 0) and trough (theta = pi/Z) are samples.
  const int z = 20;
  const double A = 3.0, C = 0.5;  // C < A/4: the trough stays at cos(Z theta) = -1, x = -A + C
  EXPECT_NEAR(sg::fm0(tones(1600, {{A, z, 0}}), z), 2.0, kExact);
  // x = A cos(Z theta) + C cos(2 Z theta): PP = (A + C) - (-A + C) = 2A, sum of harmonics A + C.
  EXPECT_NEAR(sg::fm0(tones(1600, {{A, z, 0}, {C, 2 * z, 0}}), z), 2 * A / (A + C), kExact);
  // A shaft order (not a mesh harmonic) adds to PP but not to the denominator.
  const auto x = tones(1600, {{A, z, 0}, {0.2, 7, 0}});
  EXPECT_NEAR(sg::fm0(x, z), sg::peak_to_peak(x) / A, kExact);
}

TEST(ConditionIndicators, DecompositionSplitsRegularDifferenceAndResidual) {
  const int z = 20;
  // mean 0.3, mesh harmonics (20, 40), first sidebands (19, 41), shaft order 1, difference content at 7 and 55.
  const auto x = tones(1024, {{0.3, 0, 0}, {2.0, 20, 0.1}, {0.7, 40, 0.4}, {0.2, 19, 1.0}, {0.15, 41, 2.0},
                               {0.4, 1, 0.5}, {0.25, 7, 0.3}, {0.05, 55, 0.9}});
  const auto d = sg::decompose_tsa(x, {z, 2});
  const auto regular = tones(1024, {{2.0, 20, 0.1}, {0.7, 40, 0.4}, {0.2, 19, 1.0}, {0.15, 41, 2.0}, {0.4, 1, 0.5}});
  const auto difference = tones(1024, {{0.25, 7, 0.3}, {0.05, 55, 0.9}});
  const auto residual = tones(1024, {{0.2, 19, 1.0}, {0.15, 41, 2.0}, {0.25, 7, 0.3}, {0.05, 55, 0.9}});
  for (std::size_t j = 0; j < x.size(); ++j) {
    EXPECT_NEAR(d.regular[j], regular[j], 1e-12 * 4) << j;
    EXPECT_NEAR(d.difference[j], difference[j], 1e-12 * 4) << j;
    EXPECT_NEAR(d.residual[j], residual[j], 1e-12 * 4) << j;
  }
}

TEST(ConditionIndicators, EnergyRatioOfKnownDifferenceAndRegularEnergies) {
  // Regular: the mesh tone A1 (rms A1/sqrt 2); difference: order 7, A2 (rms A2/sqrt 2): ER = A2/A1.
  const double a1 = 2.0, a2 = 0.3;
  const auto x = tones(1024, {{a1, 20, 0.2}, {a2, 7, 1.1}});
  const auto ind = sg::condition_indicators(x, {20, 2});
  EXPECT_NEAR(ind.energy_ratio, a2 / a1, kExact);
  // No difference content: ER = 0 and the difference-signal statistics are undefined, not round-off noise.
  // n = 1280 = 64 Z samples hold the tone's peak and trough, so FM0 = 2 exactly.
  const auto pure = sg::condition_indicators(tones(1280, {{a1, 20, 0}}), {20, 2});
  EXPECT_EQ(pure.energy_ratio, 0.0);
  EXPECT_TRUE(std::isnan(pure.fm4));
  EXPECT_TRUE(std::isnan(pure.na4));
  EXPECT_NEAR(pure.fm0, 2.0, kExact);
}

TEST(ConditionIndicators, SidebandLevelFactorIsSidebandsOverStandardDeviation) {
  // Mesh tone A plus sidebands b, c at Z -+ 1: std = sqrt((A^2 + b^2 + c^2)/2).
  const double A = 1.0, b = 0.2, c = 0.1;
  const auto x = tones(512, {{A, 20, 0}, {b, 19, 0.5}, {c, 21, 1.5}});
  EXPECT_NEAR(sg::sideband_level_factor(x, 20), (b + c) / std::sqrt((A * A + b * b + c * c) / 2), kExact);
}

TEST(ConditionIndicators, Na4OfStationaryGaussianResidualIsThree) {
  // Ten records of one stationary process: m4 of the last over the squared mean variance.
  // SE: kurtosis sqrt(24/N) = 0.019 plus the variance-ratio term 3 x 2 sqrt(2/N) = 0.033 (N = 65536):
  // combined 0.038, tolerance 4 x 0.038 = 0.15.
  const std::size_t n = 1u << 16;
  std::vector<double> variances;
  for (unsigned r = 0; r < 9; ++r) variances.push_back(sg::central_variance(gaussian(n, 1.3, 100 + r)));
  const auto last = gaussian(n, 1.3, 200);
  EXPECT_NEAR(sg::na4(last, variances), 3.0, 0.15);
  EXPECT_NEAR(sg::na4(last, {}), sg::kurtosis(last), kExact);
  // A louder last record (damage): NA4 = 3 s_L^4 / ((9 s^2 + s_L^2)/10)^2 = 28.4 for s = 1.3, s_L = 2.6;
  // relative SE about 1.5 % (kurtosis 0.64 %, the squared mean variance under 1.1 %), tolerance 4 x 1.5 %.
  const auto loud = gaussian(n, 2.6, 300);
  const double s2 = 1.3 * 1.3, l2 = 2.6 * 2.6, mean_var = (9 * s2 + l2) / 10;
  EXPECT_NEAR(sg::na4(loud, variances), 3 * l2 * l2 / (mean_var * mean_var), 0.06 * 28.4);
}

TEST(ConditionIndicators, BandEnvelopeOfAmplitudeModulatedMeshToneIsTheModulation) {
  // (1 + m cos(theta)) A cos(Z theta) = mesh + sidebands A m / 2 at Z -+ 1: envelope A (1 + m cos theta).
  const double A = 2.0, m = 0.3;
  const auto x = tones(1024, {{A, 20, 0}, {A * m / 2, 19, 0}, {A * m / 2, 21, 0}, {0.5, 60, 0}});
  const auto env = sg::band_envelope(x, 20, sg::nb4_half_band(20));
  for (std::size_t j = 0; j < x.size(); ++j)
    EXPECT_NEAR(env[j], A * (1 + m * std::cos(2 * kPi * static_cast<double>(j) / 1024.0)), 1e-12 * 4) << j;
}

TEST(ConditionIndicators, WeightedAverageWithUnitWeightsIsTheTsaAndReducesNoiseVariance) {
  // TSA of a periodic signal plus white noise sigma over R = 64 periods: the error variance is sigma^2/R.
  // Estimated from P = 4096 samples: relative SE sqrt(2/P) = 0.022, tolerance 4 SE = 8.8 %.
  const int p = 4096, revs = 64;
  const double sigma = 0.5;
  const auto noise = gaussian(static_cast<std::size_t>(p) * revs, sigma, 7);
  const auto periodic = tones(static_cast<std::size_t>(p), {{1.0, 20, 0}, {0.3, 3, 1}});
  std::vector<double> x(noise.size()), w(noise.size(), 1.0);
  for (std::size_t j = 0; j < x.size(); ++j) x[j] = periodic[j % p] + noise[j];
  const auto a = sg::weighted_synchronous_average(x, w, p);
  const auto tsa = sg::time_synchronous_average(x, p);
  std::vector<double> err(static_cast<std::size_t>(p));
  for (std::size_t j = 0; j < err.size(); ++j) {
    EXPECT_NEAR(a.average[j], tsa[j], 1e-12);
    err[j] = a.average[j] - periodic[j];
  }
  EXPECT_EQ(a.periods, revs);
  EXPECT_NEAR(sg::central_variance(err) / (sigma * sigma / revs), 1.0, 4 * std::sqrt(2.0 / p));
}

TEST(ConditionIndicators, WeightedAverageRecoversEachPlanetFromItsWindow) {
  // Two "planets" alternate in front of a sensor: in even periods the signal is a, in odd ones b.
  // Weights 1 on even periods and 0 on odd ones separate a exactly.
  const int p = 64;
  const auto a = tones(p, {{1.0, 3, 0}}), b = tones(p, {{0.5, 5, 0}});
  std::vector<double> x, w;
  for (int r = 0; r < 6; ++r)
    for (int j = 0; j < p; ++j) {
      x.push_back(r % 2 == 0 ? a[j] : b[j]);
      w.push_back(r % 2 == 0 ? 1.0 : 0.0);
    }
  const auto s = sg::weighted_synchronous_average(x, w, p);
  for (int j = 0; j < p; ++j) EXPECT_NEAR(s.average[j], a[j], 1e-15);
  EXPECT_DOUBLE_EQ(s.weight_sum[0], 3.0);
  EXPECT_DOUBLE_EQ(sg::hann_angle_window(0.0, 1.0), 1.0);
  EXPECT_NEAR(sg::hann_angle_window(0.5, 1.0), 0.5, 1e-15);
  EXPECT_EQ(sg::hann_angle_window(2 * kPi + 1.0, 1.0), 0.0);
}

TEST(ConditionIndicators, CrackedToothRaisesFm4AboveHealthyGear) {
  // Healthy: mesh harmonics plus Gaussian noise (difference ~ Gaussian, FM4 ~ 3 +- 4 x sqrt(24/2048) = 0.43).
  // Damaged: the same plus a short one-tooth dip of 8 noise sigmas: FM4 well above the healthy band.
  const int z = 21;
  const std::size_t n = 2048;
  auto healthy = tones(n, {{1.0, z, 0}, {0.4, 2 * z, 0.3}});
  const auto noise = gaussian(n, 0.02, 11);
  for (std::size_t j = 0; j < n; ++j) healthy[j] += noise[j];
  auto cracked = healthy;
  for (std::size_t j = 500; j < 510; ++j) cracked[j] -= 0.16;
  const auto h = sg::condition_indicators(healthy, {z, 2});
  const auto c = sg::condition_indicators(cracked, {z, 2});
  EXPECT_NEAR(h.fm4, 3.0, 4 * std::sqrt(24.0 / static_cast<double>(n)));
  EXPECT_GT(c.fm4, h.fm4 + 4 * 4 * std::sqrt(24.0 / static_cast<double>(n)));
  EXPECT_GT(c.na4, h.na4);
  EXPECT_GT(c.m6a, h.m6a);
}

TEST(ConditionIndicators, RejectsImpossibleOrdersNamingTheParameter) {
  const auto x = tones(64, {{1.0, 4, 0}});
  auto message = [&](auto f) -> std::string {
    try {
      f();
    } catch (const pw::InputError& e) {
      return e.what();
    }
    return "<none>";
  };
  EXPECT_NE(message([&] { sg::decompose_tsa(x, {40, 2}); }).find("mesh_order"), std::string::npos);
  EXPECT_NE(message([&] { sg::decompose_tsa(x, {4, 3}); }).find("shaft_harmonics"), std::string::npos);
  EXPECT_NE(message([&] { sg::band_envelope(x, 4, -1); }).find("half_width_orders"), std::string::npos);
  EXPECT_NE(message([&] { sg::hann_angle_window(0, 0); }).find("half_width_rad"), std::string::npos);
  std::vector<double> w(10, 1.0);
  EXPECT_NE(message([&] { sg::weighted_synchronous_average(x, w, 8); }).find("weights"), std::string::npos);
}

} // namespace
