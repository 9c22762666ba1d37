// Angle-domain resampling and time-synchronous averaging.
#include "core/constants.hpp"
#include "core/error.hpp"
#include "signal/resample.hpp"
#include "signal/spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

namespace {

using pw::signal::Interpolation;
using pw::kPi;

template <class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const pw::InputError& e) {
    return e.what();
  }
  return "<no pw::InputError thrown>";
}

// A shaft spinning up: theta(t) = 2 pi (f0 t + a t^2 / 2), f0 = 20 rev/s, a = 15 rev/s^2.
double shaft_angle(double t) { return 2 * kPi * (20.0 * t + 0.5 * 15.0 * t * t); }

TEST(AngularResample, LinearIsExactForSignalLinearInAngle) {
  std::vector<double> t, x, theta;
  for (int j = 0; j < 200; ++j) {
    const double tj = 1e-3 * j + 2e-4 * std::sin(0.37 * j);  // non-uniform, increasing
    t.push_back(tj);
    theta.push_back(shaft_angle(tj));
    x.push_back(3.0 - 0.5 * theta.back());
  }
  const auto r = pw::signal::angular_resample(t, x, theta, 64, Interpolation::Linear);
  ASSERT_FALSE(r.values.empty());
  for (std::size_t j = 0; j < r.values.size(); ++j)
    EXPECT_NEAR(r.values[j], 3.0 - 0.5 * r.angle_rad[j], 1e-11) << "grid point " << j;
}

TEST(AngularResample, CubicIsExactForCubicInAngleOnNonUniformSamples) {
  std::vector<double> t, x, theta;
  for (int j = 0; j < 50; ++j) {
    t.push_back(0.01 * j);
    theta.push_back(0.3 * j + 0.1 * std::sin(1.3 * j));  // increasing: slope 0.3 > 0.13
    const double a = theta.back();
    x.push_back(1.0 - 2.0 * a + 0.25 * a * a - 0.03 * a * a * a);
  }
  const auto r = pw::signal::angular_resample(t, x, theta, 16, Interpolation::Cubic);
  for (std::size_t j = 0; j < r.values.size(); ++j) {
    const double a = r.angle_rad[j];
    EXPECT_NEAR(r.values[j], 1.0 - 2.0 * a + 0.25 * a * a - 0.03 * a * a * a, 1e-9) << j;
  }
}

TEST(AngularResample, GridCoversWholeRevolutionsAndInterpolatesTime) {
  // Constant speed, exactly 5 revolutions: 5 * 32 + 1 grid points, and time
  // (linear in angle here) is recovered exactly.
  const double omega = 2 * kPi * 12.5;  // rad/s
  std::vector<double> t, x, theta;
  for (int j = 0; j <= 400; ++j) {
    t.push_back(j * 0.4 / 400);
    theta.push_back(omega * t.back());
    x.push_back(0.0);
  }
  const auto r = pw::signal::angular_resample(t, x, theta, 32);
  ASSERT_EQ(r.values.size(), 5u * 32u + 1u);
  EXPECT_EQ(r.samples_per_rev, 32);
  for (std::size_t j = 0; j < r.values.size(); ++j) {
    EXPECT_NEAR(r.angle_rad[j], 2 * kPi * static_cast<double>(j) / 32, 1e-12);
    EXPECT_NEAR(r.time_s[j], r.angle_rad[j] / omega, 1e-14);
  }
}

TEST(AngularResample, AcceleratingShaftToneBecomesOneOrder) {
  // sin(5 theta(t)) sampled uniformly in time is a chirp; in the angle domain
  // it is order 5 exactly. Its order spectrum ("sample interval" 1/spr rev)
  // must show amplitude 1 at order 5.
  const double dt = 1.0 / 20000;  // >= 80 samples per cycle of the tone (250 Hz at the end)
  std::vector<double> t, x, theta;
  for (int j = 0; j * dt <= 2.0; ++j) {
    t.push_back(j * dt);
    theta.push_back(shaft_angle(t.back()));
    x.push_back(std::sin(5 * theta.back()));
  }
  const int spr = 64;
  const auto r = pw::signal::angular_resample(t, x, theta, spr);
  double worst = 0;
  for (std::size_t j = 0; j < r.values.size(); ++j)
    worst = std::max(worst, std::abs(r.values[j] - std::sin(5 * r.angle_rad[j])));
  EXPECT_LT(worst, 2e-6) << "cubic interpolation error in the angle domain";

  const std::size_t revs = r.values.size() / spr;  // 70 revolutions in 2 s
  const std::vector<double> whole(r.values.begin(), r.values.begin() + static_cast<long>(revs * spr));
  const auto s = pw::signal::amplitude_spectrum(whole, 1.0 / spr, pw::signal::Window::Hann);
  const auto peaks = pw::signal::dominant_peaks(s, 1, 0.0);
  ASSERT_EQ(peaks.size(), 1u);
  EXPECT_NEAR(peaks[0].frequency_Hz, 5.0, 1e-6) << "order axis: cycles per revolution";
  EXPECT_NEAR(peaks[0].amplitude, 1.0, 1e-4);
}

// Max |error| of resampling sin(5 theta(t)) sampled every dt over 1 s.
double resampling_error(double dt, Interpolation method) {
  std::vector<double> t, x, theta;
  for (int j = 0; j * dt <= 1.0; ++j) {
    t.push_back(j * dt);
    theta.push_back(shaft_angle(t.back()));
    x.push_back(std::sin(5 * theta.back()));
  }
  const auto r = pw::signal::angular_resample(t, x, theta, 50, method);
  double worst = 0;
  for (std::size_t j = 0; j < r.values.size(); ++j)
    worst = std::max(worst, std::abs(r.values[j] - std::sin(5 * r.angle_rad[j])));
  return worst;
}

TEST(AngularResample, ErrorConvergesAtSecondOrderLinearAndFourthOrderCubic) {
  // Halving the time step must divide the error by ~2^p (p = 2 linear, 4 cubic).
  for (const auto& [method, order] : {std::pair{Interpolation::Linear, 2.0},
                                      std::pair{Interpolation::Cubic, 4.0}}) {
    double previous = resampling_error(1.0 / 2000, method);
    for (double fs : {4000.0, 8000.0}) {
      const double e = resampling_error(1.0 / fs, method);
      const double observed = std::log2(previous / e);
      EXPECT_NEAR(observed, order, 0.3) << "fs = " << fs << " Hz, errors " << previous << " -> " << e;
      previous = e;
    }
  }
}

TEST(AngularResample, RejectsMismatchedOrNonMonotonicInput) {
  const std::vector<double> t{0, 1, 2, 3}, x{0, 0, 0, 0}, a{0, 1, 2, 3};
  using pw::signal::angular_resample;
  EXPECT_NE(thrown_message([&] { (void)angular_resample(t, std::vector<double>{0, 0}, a, 8); })
                .find("signal: has 2 samples but time_s has 4"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)angular_resample(t, x, std::vector<double>{0, 1, 1, 3}, 8); })
                .find("angle_rad: must increase strictly, but sample 2"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)angular_resample(std::vector<double>{0, 2, 1, 3}, x, a, 8); })
                .find("time_s"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)angular_resample(t, x, a, 1); }).find("samples_per_rev"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] {
              (void)angular_resample(std::vector<double>{0, 1, 2}, std::vector<double>{0, 0, 0},
                                     std::vector<double>{0, 1, 2}, 8, Interpolation::Cubic);
            }).find("needs at least 4"),
            std::string::npos);
}

TEST(TimeSynchronousAverage, KeepsSynchronousPartAndShrinksNoiseAsOneOverSqrtRevolutions) {
  const int spr = 256;
  const int revs = 64;
  const double sigma = 0.5;
  std::uint64_t s = 7;
  auto uniform = [&s] {  // splitmix64, (0, 1)
    s += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) * 0x1.0p-53;
  };
  auto synchronous = [](double a) { return std::sin(3 * a) + 0.3 * std::cos(7 * a + 0.2); };
  std::vector<double> x(static_cast<std::size_t>(spr * revs) + 17);  // + a partial revolution
  for (std::size_t j = 0; j < x.size(); ++j) {
    const double a = 2 * kPi * static_cast<double>(j) / spr;
    const double noise = sigma * std::sqrt(-2 * std::log(uniform())) * std::cos(2 * kPi * uniform());
    x[j] = synchronous(a) + noise + 0.4 * std::sin(2.5 * a);  // order 2.5: not synchronous
  }
  const auto avg = pw::signal::time_synchronous_average(x, spr);
  ASSERT_EQ(avg.size(), static_cast<std::size_t>(spr));
  double residual_sq = 0;
  for (int j = 0; j < spr; ++j) {
    const double r = avg[j] - synchronous(2 * kPi * j / spr);
    residual_sq += r * r;
  }
  const double residual_rms = std::sqrt(residual_sq / spr);
  const double expected = sigma / std::sqrt(static_cast<double>(revs));  // 0.0625
  // Order 2.5 cancels exactly over an even number of revolutions; what is left
  // is noise, whose RMS estimate from 256 samples scatters by ~5%.
  EXPECT_NEAR(residual_rms, expected, 0.2 * expected)
      << "residual RMS " << residual_rms << ", sigma/sqrt(R) = " << expected;
}

TEST(TimeSynchronousAverage, RejectsLessThanOneRevolution) {
  const std::vector<double> x(10, 1.0);
  EXPECT_NE(thrown_message([&] { (void)pw::signal::time_synchronous_average(x, 11); })
                .find("fewer than one revolution"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)pw::signal::time_synchronous_average(x, 0); })
                .find("samples_per_rev"),
            std::string::npos);
  const auto avg = pw::signal::time_synchronous_average(x, 10);
  EXPECT_EQ(avg, x);
}

// A planned cubic resampling (weights once per angle record) gives angular_resample's values to the
// last bit for every signal sampled at those angles, on a non-uniform angle (a speed ripple),
// whole or cut to its first points; a non-finite sample is refused as angular_resample refuses it.
TEST(CubicResamplePlan, GivesAngularResamplesValuesBitForBitForEverySignalOfTheAngle) {
  const std::size_t n = 3000;
  std::vector<double> t(n), angle(n), a(n), b(n);
  for (std::size_t j = 0; j < n; ++j) {
    t[j] = 1e-4 * static_cast<double>(j);
    angle[j] = 31.0 * t[j] + 0.02 * std::sin(170.0 * t[j]);  // about 0.5 revolution, rippled
    a[j] = std::sin(23.0 * angle[j]) + 0.1 * std::cos(7.0 * angle[j]);
    b[j] = std::exp(-t[j]) * std::sin(41.0 * angle[j] + 0.3);
  }
  const int per_rev = 4096;
  const pw::signal::CubicResamplePlan plan(angle, per_rev);
  for (const auto* x : {&a, &b}) {
    const auto reference = pw::signal::angular_resample(t, *x, angle, per_rev, pw::signal::Interpolation::Cubic);
    EXPECT_EQ(plan.record_points(), reference.values.size());
    EXPECT_EQ(plan.apply(*x), reference.values);
    const pw::signal::CubicResamplePlan first(angle, per_rev, 100);
    ASSERT_EQ(first.points(), 100u);
    EXPECT_EQ(first.apply(*x), std::vector<double>(reference.values.begin(), reference.values.begin() + 100));
  }
  b[17] = std::nan("");
  EXPECT_THROW((void)plan.apply(b), pw::InputError);
}

} // namespace
