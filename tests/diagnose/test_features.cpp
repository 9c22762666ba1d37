// Feature extraction on synthetic signals with known lines.
#include "diagnose/features.hpp"
#include "diagnose/order_analysis.hpp"
#include "diagnose/stage_1200rpm.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <numbers>
#include <random>

namespace pw::diagnose {
namespace {

constexpr double kPi = std::numbers::pi;

/// A line of a synthetic mesh acceleration: amplitude [m/s^2], order of the angle reference, phase [rad].
struct OrderLine {
  double amplitude, order, phase;
};

/// A model record at 1200 rpm over `carrier_revolutions` whose sun speed swings by 10 % at twice
/// the shaft frequency (what a 10 % torque ripple of order 2 does to the seed stage): sun speed,
/// carrier angle, and a sun-planet acceleration of `lines` at orders of the angle reference (the
/// integral of the mesh-period-averaged sun speed, as the recording's) plus `offset`.
model::SimulationResult rippled_sun_record(const model::StageSpec& st, double carrier_revolutions,
                                          std::initializer_list<OrderLine> lines, double offset) {
  const double ratio = st.sun.teeth / static_cast<double>(st.sun.teeth + st.ring.teeth);
  const double Omega = 1200 * 2 * kPi / 60, dt = 2.5e-6, carrier_rev_s = 2 * kPi / (Omega * ratio);
  const std::size_t n = static_cast<std::size_t>(carrier_revolutions * carrier_rev_s / dt);
  model::SimulationResult r;
  r.time_step_s = dt;
  model::Channel speed{"sun/speed", "rad/s", "", {}}, angle{"carrier/angle", "rad", "", {}},
      acc{"sun_planet/0/acceleration", "m/s^2", "", {}};
  for (std::size_t j = 0; j < n; ++j) {
    const double t = static_cast<double>(j) * dt;
    const double th_s = Omega * t + 0.05 * std::sin(2 * Omega * t);  // speed Omega (1 + 0.1 cos 2 Omega t)
    speed.values.push_back(Omega * (1 + 0.1 * std::cos(2 * Omega * t)));
    angle.values.push_back(ratio * th_s);
  }
  const double mesh_samples = 2 * kPi / (Omega * ratio * st.ring.teeth) / dt;
  const auto w = mesh_period_average(speed.values, mesh_samples);
  double ref = 0;
  for (std::size_t j = 0; j < n; ++j) {
    if (j > 0) ref += 0.5 * (w[j] + w[j - 1]) * dt * ratio;
    double y = 0;
    for (const OrderLine& l : lines) y += l.amplitude * std::cos(l.order * ref + l.phase);
    acc.values.push_back(y + offset);
  }
  r.channels = {speed, angle, acc};
  return r;
}

/// The two recording channels that rippled_sun_record's channels predict.
Recording sun_speed_and_mesh_recording() {
  Recording rec;
  rec.channels = {SignalChannel{"w", Quantity::SunSpeed, "rad/s", 0, 0.0, {}},
                  SignalChannel{"a", Quantity::MeshAccelerationSunPlanet, "m/s^2", 0, 0.0, {}}};
  return rec;
}

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

TEST(OrderAnalysis, ALineAtNoGearOrderIsFoundAndItsLeakIsTheWindowsSincWhereTheBaselineHoldsItToo) {
  // A rig's tone at a carrier order no gear family makes (as a line-counting encoder's image or
  // mains hum would be), 1 m/s^2 beside 8 mesh harmonics of 10/h m/s^2 and 0.5 m/s^2 noise per
  // sample in a 6.4-revolution recording: find_alien_lines must report it (order to a tenth of
  // the recording's resolution, amplitude to 3 %: three standard deviations of the noise's share
  // of a Hann DTFT there, 2 x 0.5 sqrt(3n/8) / (n/2) = 1 % for n = 15 600 samples), and no gear line; without the tone it reports nothing (its family-wise false
  // alarm rate is 1 %: this seed is one draw of it). Each cell's leak is the window's
  // rectangular kernel: (A/2)^2 sinc^2(W (o - x)).
  const auto cfg = test::stage_1200rpm();
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  const double revs = 6.4;
  Recording clean = test::synthetic_of(cfg, revs / k.carrier_Hz, 0.0, 0.0, 21);
  const RecordingSpectra s0 = analyse_recording(clean, cfg.stage);
  const std::size_t acc = s0.channels[0] == 1 ? 0 : 1;  // the mesh-acceleration channel
  EXPECT_TRUE(s0.alien_lines[acc].empty()) << s0.alien_lines[acc].size() << " found, the first at order "
                                           << (s0.alien_lines[acc].empty() ? 0.0 : s0.alien_lines[acc][0].order);
  // An order at least three resolutions from every labelled line.
  const double resolution = 1.0 / revs, A = 1.0;
  double o = 0;
  for (double trial = 2.5 * k.ring_teeth + 0.37; trial < 4 * k.ring_teeth; trial += 0.05) {
    double near = 1e9, near_cell = 1e9;
    for (const auto& l : s0.layout.lines) near = std::min(near, std::fabs(l.order - trial));
    for (const auto& c : s0.layout.cells) near_cell = std::min(near_cell, std::fabs(c.order - trial));
    // ... and within a few orders of some cell, so that its leak there is not negligible.
    if (near > 3 * resolution && near_cell < 2.0) {
      o = trial;
      break;
    }
  }
  ASSERT_GT(o, 0) << "no clear order found";
  Recording toned = clean;
  for (std::size_t j = 0; j < toned.time_s.size(); ++j)
    toned.channels[1].values[j] += A * std::cos(2 * kPi * o * k.carrier_Hz * toned.time_s[j] + 0.7);
  const RecordingSpectra s = analyse_recording(toned, cfg.stage);
  ASSERT_EQ(s.alien_lines[acc].size(), 1u);
  EXPECT_NEAR(s.alien_lines[acc][0].order, o, 0.1 * resolution);
  EXPECT_NEAR(s.alien_lines[acc][0].amplitude, A, 0.03 * A);
  // Without a baseline no line is known to be the rig's: reported, no leak carried.
  EXPECT_FALSE(s.alien_lines[acc][0].in_baseline);
  for (std::size_t i = 0; i < s.layout.cells.size(); ++i) ASSERT_EQ(s.alien_leak[acc][i][0], 0.0) << "cell " << i;
  // A baseline that holds it (within the tolerance) makes it the rig's: its leak is carried.
  RecordingSpectra with = s;
  BaselineAlienLines baseline;
  baseline.orders[s.channel_names[acc]] = {o + 0.5 * resolution};
  carry_baseline_alien_lines(with, baseline, with.alien_tolerance);
  EXPECT_TRUE(with.alien_lines[acc][0].in_baseline);
  const double W = s.layout.window_revolutions, a = s.alien_lines[acc][0].amplitude;
  double largest = 0;
  for (std::size_t i = 0; i < s.layout.cells.size(); ++i) {
    const double d = W * (s.alien_lines[acc][0].order - s.layout.cells[i].order);
    const double sinc = d == 0 ? 1.0 : std::sin(kPi * d) / (kPi * d);
    const double expected = std::fabs(d) > 64 ? 0.0 : 0.25 * a * a * sinc * sinc;
    largest = std::max(largest, expected);
    ASSERT_NEAR(with.alien_leak[acc][i][0], expected, 1e-12 * a * a) << "cell " << i;
    ASSERT_EQ(with.alien_leak[acc][i][1], with.alien_leak[acc][i][0]) << "one line: the largest is the sum";
  }
  EXPECT_GT(largest, 1e-5 * a * a) << "the tone leaks into no cell: the check above tested nothing";
  // A baseline line elsewhere (farther than both tolerances) does not.
  baseline.orders[s.channel_names[acc]] = {o + 10 * resolution};
  carry_baseline_alien_lines(with, baseline, with.alien_tolerance);
  EXPECT_FALSE(with.alien_lines[acc][0].in_baseline);
  for (std::size_t i = 0; i < s.layout.cells.size(); ++i) ASSERT_EQ(with.alien_leak[acc][i][0], 0.0) << "cell " << i;
  EXPECT_TRUE(s.alien_lines[1 - acc].empty()) << "the speed channel holds no tone";
}

TEST(OrderAnalysis, AngleFourierIsExactForIntegerOrdersAtAVaryingSpeed) {
  // x = 2 cos(81 theta + 0.3) + 0.5 cos(7 theta) sampled uniformly in time while the
  // speed varies slowly; a window of one revolution that starts between samples.
  const double dt = 1e-4, Omega = 8.6;
  std::vector<double> th, x;
  for (int j = 0; j < 9000; ++j) {
    const double t = j * dt;
    const double a = Omega * t + 0.01 * std::sin(1.3 * t);
    th.push_back(a);
    x.push_back(2 * std::cos(81 * a + 0.3) + 0.5 * std::cos(7 * a) + 3.0);
  }
  const auto c = angle_fourier(x, th, 0.0123, 1, 200);
  EXPECT_NEAR(std::abs(c[81]), 1.0, 2e-4);
  EXPECT_NEAR(std::abs(c[7]), 0.25, 2e-4);
  EXPECT_LT(std::abs(c[80]), 2e-4);
  EXPECT_LT(std::abs(c[82]), 2e-4);
  EXPECT_LT(std::abs(c[150]), 2e-4);
}

TEST(OrderAnalysis, AngleFourierDriftDerivativeMatchesAFiniteDifferenceOfTheCorrectedAngle) {
  // Lines at integer and fractional orders plus deterministic "noise"; a window of R = 2
  // revolutions that starts between samples. The analytic dc_k/d delta against the central
  // difference of the coefficients over the corrected angle a0 + (theta - a0)(1 - delta / 4 pi)
  // with delta = +-1e-5 rad (truncation O(delta^2) ~ 1e-10 relative; rounding ~1e-16 / 1e-5).
  const double dt = 1e-4, Omega = 7.3, a0 = 0.0123;
  const int R = 2;
  std::vector<double> th, x;
  for (int j = 0; j < 30000; ++j) {
    const double a = Omega * j * dt;
    th.push_back(a);
    x.push_back(2 * std::cos(81 * a + 0.3) + 0.7 * std::cos(96.5 * a) + 0.05 * std::sin(1e3 * std::sin(0.37 * j)) + 1.0);
  }
  std::vector<std::complex<double>> d;
  angle_fourier(x, th, a0, R, 300, &d);
  auto corrected = [&](double delta) {
    std::vector<double> t(th.size());
    for (std::size_t j = 0; j < th.size(); ++j) t[j] = a0 + (th[j] - a0) * (1 - delta / (2 * kPi * R));
    return angle_fourier(x, t, a0, R, 300);
  };
  const double h = 1e-5;
  const auto cp = corrected(h), cm = corrected(-h);
  double worst = 0, scale = 0;
  for (int k = 1; k <= 300; ++k) {
    const auto fd = (cp[static_cast<std::size_t>(k)] - cm[static_cast<std::size_t>(k)]) / (2 * h);
    worst = std::max(worst, std::abs(fd - d[static_cast<std::size_t>(k)]));
    scale = std::max(scale, std::abs(fd));
  }
  EXPECT_GT(scale, 10.0);  // the order-162 line's derivative is ~ A k / 2 ~ 80 per rad
  EXPECT_LT(worst, 1e-4 * scale);
}

TEST(OrderAnalysis, FirstOrderDriftCorrectionRemovesTheLeakOfADriftedAngleReference) {
  // A line at carrier order 81 recorded against an angle reference that reads delta = 2e-4 rad
  // too much at the end of a one-revolution window: the line leaks ~A 81 delta / (2 pi d) into
  // the bins d away. c_k + delta dc_k/d delta restores the clean coefficients to O(delta^2).
  const double dt = 1e-4, Omega = 8.6, delta = 2e-4;
  std::vector<double> th, x;
  for (int j = 0; j < 9000; ++j) {
    const double a = Omega * j * dt;
    th.push_back(a * (1 + delta / (2 * kPi)));
    x.push_back(2 * std::cos(81 * a + 0.3));
  }
  std::vector<std::complex<double>> d;
  const auto c = angle_fourier(x, th, 0.0, 1, 200, &d);
  const double leak = std::abs(c[82]);
  EXPECT_GT(leak, 0.5 * 81 * delta / (2 * kPi));  // the leak is there
  for (int k : {80, 82, 83, 120}) EXPECT_LT(std::abs(c[static_cast<std::size_t>(k)] + delta * d[static_cast<std::size_t>(k)]), 0.02 * leak) << k;
  EXPECT_NEAR(std::abs(c[81] + delta * d[81]), 1.0, 1e-4);
}

TEST(OrderAnalysis, RiceMeanAndVarianceMatchMonteCarlo) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> nd(0.0, 1.0);
  for (double nu : {0.0, 0.5, 1.0, 3.0, 40.0}) {
    const double s2 = 1.0;  // E|n|^2
    const int n = 200000;
    double m = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
      const double a = std::hypot(nu + std::sqrt(0.5) * nd(rng), std::sqrt(0.5) * nd(rng));
      m += a / n;
      m2 += a * a / n;
    }
    EXPECT_NEAR(rice_mean(nu, s2), m, 4e-3) << "nu = " << nu;
    EXPECT_NEAR(rice_variance(nu, s2), m2 - m * m, 6e-3) << "nu = " << nu;
  }
}

TEST(OrderAnalysis, RiceMeanSlopeIsTheDerivativeOfTheRiceMean) {
  // Central differences of rice_mean (step 1e-6 of the noise: truncation ~1e-12, round-off
  // ~1e-10), across the Bessel form, the asymptotic form (ratio > 25) and nu = 0 (even in nu).
  const double s2 = 2.0;  // E|n|^2: per-component sd 1
  EXPECT_DOUBLE_EQ(rice_mean_slope(0.0, s2), 0.0);
  for (double nu : {0.01, 0.3, 1.0, 2.5, 7.0, 24.0, 26.0, 300.0}) {
    const double h = 1e-6;
    const double fd = (rice_mean(nu + h, s2) - rice_mean(nu - h, s2)) / (2 * h);
    EXPECT_NEAR(rice_mean_slope(nu, s2), fd, 1e-7) << "nu = " << nu;
  }
  EXPECT_NEAR(rice_mean_slope(1e6, s2), 1.0, 1e-12);
}

TEST(OrderAnalysis, ExponentialMeanIsRobustToAFewLines) {
  std::mt19937_64 rng(9);
  std::exponential_distribution<double> ex(1.0 / 2.5);
  std::vector<double> p;
  for (int i = 0; i < 4000; ++i) p.push_back(i % 20 == 0 ? 1e3 : ex(rng));  // 5 % strong lines
  double se = 0;
  const double m = exponential_mean(p, &se);
  EXPECT_NEAR(m, 2.5, 4 * se * 2.5);
  EXPECT_LT(se, 0.03);
}

TEST(OrderAnalysis, MeshPeriodAverageKeepsTheDriftAndRemovesMeshHarmonics) {
  const double fs = 10000, fm = 111.176;
  std::vector<double> w;
  for (int j = 0; j < 20000; ++j) {
    const double t = j / fs;
    w.push_back(42 + 0.01 * t + 0.3 * std::sin(2 * kPi * fm * t) + 0.1 * std::cos(2 * kPi * 7 * fm * t));
  }
  const auto y = mesh_period_average(w, fs / fm);
  for (int j = 200; j < 19800; j += 997) EXPECT_NEAR(y[static_cast<std::size_t>(j)], 42 + 0.01 * j / fs, 2e-4) << j;
}

// Up to the record's first and last samples: a window clipped to half a period there passed
// 2/pi of the 0.3 rad/s mesh ripple (0.19 at j = 0), which the angle reference integrated into a
// phase wiggle at the record's ends. The shifted full period nulls it; what is left is the
// drift's slope times at most half a period (0.01 rad/s^2 x 4.5 ms = 4.5e-5).
TEST(OrderAnalysis, MeshPeriodAverageRemovesMeshHarmonicsUpToTheRecordsEnds) {
  const double fs = 10000, fm = 111.176;
  const int n = 20000;
  std::vector<double> w;
  for (int j = 0; j < n; ++j) {
    const double t = j / fs;
    w.push_back(42 + 0.01 * t + 0.3 * std::sin(2 * kPi * fm * t) + 0.1 * std::cos(2 * kPi * 7 * fm * t));
  }
  const auto y = mesh_period_average(w, fs / fm);
  for (int j : {0, 1, 7, 20, 44, 60, n - 61, n - 45, n - 21, n - 8, n - 2, n - 1})
    EXPECT_NEAR(y[static_cast<std::size_t>(j)], 42 + 0.01 * j / fs, 6e-5) << j;
  // A record shorter than the period: its whole mean, as before.
  const std::vector<double> short_record(w.begin(), w.begin() + 50);
  const auto ys = mesh_period_average(short_record, fs / fm);
  double mean = 0;
  for (std::size_t j = 1; j < short_record.size(); ++j) mean += 0.5 * (short_record[j] + short_record[j - 1]);
  mean /= static_cast<double>(short_record.size() - 1);
  EXPECT_NEAR(ys[0], mean, 1e-12);
  EXPECT_NEAR(ys[49], mean, 1e-12);
}

TEST(OrderAnalysis, ModelSpectrumIsExactForIntegerOrdersUnderA10PercentSpeedRipple) {
  // A model record whose sun speed swings by 10 % at twice the shaft frequency (a 10 % torque
  // ripple of order 2 does that to the seed stage): the carrier angle then departs from
  // uniform by ~0.01 rad, i.e. by ~10 rad of phase at carrier order 1000. Lines at integer
  // orders of the angle reference (the integral of the mesh-period-averaged sun speed, as the
  // recording's) must still land on one bin with their amplitude. A truncated expansion in the
  // angle deviation gets these orders wrong by more than their size.
  const model::SimulationConfig cfg;
  const model::SimulationResult r =
      rippled_sun_record(cfg.stage, 1.05, {{2, 567, 0.3}, {0.8, 1234, 1.1}}, 5.0);
  const Recording rec = sun_speed_and_mesh_recording();
  RecordingSpectra s;
  s.layout.revolutions = 1;
  s.layout.max_bin = 1500;
  s.angle_reference = AngleReference::SunSpeed;
  s.channels = {0, 1};
  const ModelSpectra m = model_spectra(r, rec, s, cfg, false);
  const auto& a = m.amplitude[1];
  EXPECT_NEAR(a[567], 1.0, 1e-3);
  EXPECT_NEAR(a[1234], 0.4, 1e-3);
  EXPECT_LT(a[566] + a[568] + a[1233] + a[1235] + a[900], 2e-3);
}

TEST(OrderAnalysis, RingBodyHousingChannelsComeAgainFromTheKeptRingAccelerations) {
  // sensor.housing_path = ring_body (model/sensor.hpp Eq. S3): the comparison asks the simulation
  // for the ring's accelerations, computes the housing channel at the recording's sensor angle
  // from them, and keeps them, so that the channel at another sensor setting needs no new
  // simulation (housing_spectrum). The kept inputs give the compared spectrum again bit for bit,
  // and the ring_translation path of the same kept forces is another spectrum.
  model::SimulationConfig cfg;
  cfg.solver.level = model::ModelLevel::LateralTorsional;
  cfg.sensor.housing_path = model::HousingPath::RingBody;
  cfg.operating.input_speed_rpm = 1200;
  cfg.imperfections.pin_error_m = {20e-6, 0, 0};  // unequal planets: the ring moves
  cfg.solver.record_mesh_cycles = 2 * cfg.stage.ring.teeth;
  Recording rec;
  const double angle = 0.9;
  rec.channels = {SignalChannel{"h", Quantity::HousingAcceleration, "m/s^2", 0, angle, {}}};
  RecordingSpectra s;
  s.layout.revolutions = 1;
  s.layout.max_bin = 400;
  s.channels = {0};
  const model::SimulationResult r = model::simulate(cfg, {}, model_channels(rec, s, cfg));
  ASSERT_TRUE(r.find("ring/acceleration_x") && r.find("ring/acceleration_y"));
  const ModelSpectra m = model_spectra(r, rec, s, cfg, true);
  EXPECT_GT(m.ring_mass_kg, 0.0);
  ASSERT_EQ(m.amplitude.size(), 1u);
  EXPECT_EQ(housing_spectrum(m, cfg.sensor, angle, s.layout.window_revolutions, s.layout.max_bin), m.amplitude[0]);
  model::SensorSettings translation = cfg.sensor;
  translation.housing_path = model::HousingPath::RingTranslation;
  const auto other = housing_spectrum(m, translation, angle, s.layout.window_revolutions, s.layout.max_bin);
  double peak = 0, diff = 0;
  for (std::size_t k = 0; k < other.size(); ++k) {
    peak = std::max(peak, m.amplitude[0][k]);
    diff = std::max(diff, std::fabs(other[k] - m.amplitude[0][k]));
  }
  EXPECT_GT(peak, 0.0);
  EXPECT_GT(diff, 0.01 * peak);
}

TEST(OrderAnalysis, ShortRecordingsGetHalvesOfWholeSunPeriodsAndResolveOnlyThoseFamilies) {
  // Seed gears (Zs 21, Zp 30, Zr 81): 2 s hold 55.6 / 111.2 / 222.4 mesh cycles at
  // 100 / 200 / 400 rpm; halves of the largest multiple of Zs that fits twice.
  model::SimulationConfig cfg;
  const Kinematics k = kinematics(cfg.stage, 200);
  EXPECT_EQ(min_recording_mesh_cycles(21), 42);
  EXPECT_EQ(short_window_mesh_cycles(k, 55.6), 21);
  EXPECT_EQ(short_window_mesh_cycles(k, 111.2), 42);
  EXPECT_EQ(short_window_mesh_cycles(k, 222.4), 105);
  EXPECT_EQ(short_window_mesh_cycles(k, 41.9), 0);
  // lcm(Zs, Zp) = 210 fits twice in 430 mesh cycles: sun and planet families both resolved.
  EXPECT_EQ(short_window_mesh_cycles(k, 430), 210);
  EXPECT_TRUE(k.completes_periods(Component::Sun, 42));
  EXPECT_FALSE(k.completes_periods(Component::Planet, 42));
  EXPECT_TRUE(k.completes_periods(Component::Planet, 210));
  EXPECT_FALSE(k.completes_periods(Component::Carrier, 42));
  EXPECT_TRUE(k.completes_periods(Component::InputShaft, 567));  // f_m / f_s = 1701 / 102 = 567 / 34
  EXPECT_FALSE(k.completes_periods(Component::InputShaft, 210));

  const FeatureLayout L = make_layout_mesh_cycles(k, 3, 42, 2000.0);
  EXPECT_EQ(L.revolutions, 0);
  EXPECT_EQ(L.mesh_cycles, 42);
  EXPECT_DOUBLE_EQ(L.window_revolutions, 42.0 / 81.0);
  ASSERT_EQ(L.unresolved.size(), 3u);
  EXPECT_EQ(L.unresolved[0], Component::Planet);
  EXPECT_EQ(L.unresolved[1], Component::Carrier);
  EXPECT_EQ(L.unresolved[2], Component::InputShaft);
  EXPECT_TRUE(L.family_cells[static_cast<int>(Component::Carrier)].empty());
  EXPECT_FALSE(L.family_cells[static_cast<int>(Component::Sun)].empty());
  for (const auto& line : L.lines) {
    const double bin = line.order * L.window_revolutions;  // mesh harmonics on n Q, sun lines on n Q + 2 b
    EXPECT_NEAR(bin, std::round(bin), 1e-9) << line.label;
  }
  EXPECT_EQ(L.cells.front().bin, 2);  // f_sr: carrier order 81/21 = 3.857, bin 2
}

TEST(OrderAnalysis, AngleFourierOverWholeMeshCyclesPutsMeshAndSunLinesOnOneBinEach) {
  // Q = 42 mesh cycles of the seed gears = 42/81 carrier revolutions: the mesh line (order 81)
  // on bin 42, a sun sideband (order 81 - 81/21) on bin 40, a window that starts between samples.
  const double W = 42.0 / 81.0, dt = 1e-4, Omega = 8.6;
  std::vector<double> th, x;
  for (int j = 0; j < 6000; ++j) {
    const double a = Omega * j * dt + 0.01 * std::sin(1.3 * j * dt);
    th.push_back(a);
    x.push_back(2 * std::cos(81 * a + 0.3) + 0.5 * std::cos((81 - 81.0 / 21) * a + 1.0) + 3.0);
  }
  const auto c = angle_fourier(x, th, 0.0123, W, 100);
  EXPECT_NEAR(std::abs(c[42]), 1.0, 2e-4);
  EXPECT_NEAR(std::abs(c[40]), 0.25, 2e-4);
  EXPECT_LT(std::abs(c[41]) + std::abs(c[43]) + std::abs(c[39]) + std::abs(c[70]), 4e-4);
}

TEST(OrderAnalysis, ModelSpectrumOverWholeMeshCyclesPutsMeshAndSunLinesOnOneBinEach) {
  // As the speed-ripple test above, over a window of Q = 42 mesh cycles (42/81 carrier
  // revolutions): mesh harmonic 7 (order 567) on bin 294, its sun sideband -2 f_sr (order
  // 567 - 2 * 81/21) on bin 290.
  const model::SimulationConfig cfg;
  const auto& st = cfg.stage;
  const model::SimulationResult r =
      rippled_sun_record(st, 0.6, {{2, 567, 0.3}, {0.8, 567 - 2 * 81.0 / 21, 1.1}}, 5.0);
  const Recording rec = sun_speed_and_mesh_recording();
  RecordingSpectra s;
  s.layout = make_layout_mesh_cycles(kinematics(st, 1200), st.planet_count, 42, 600.0);
  s.angle_reference = AngleReference::SunSpeed;
  s.channels = {0, 1};
  const auto& a = model_spectra(r, rec, s, cfg, false).amplitude[1];
  EXPECT_NEAR(a[294], 1.0, 1e-3);
  EXPECT_NEAR(a[290], 0.4, 1e-3);
  EXPECT_LT(a[293] + a[295] + a[289] + a[291] + a[200], 2e-3);
}

TEST(OrderAnalysis, InMeshCycleWindowsOnlyALineWithoutWholePeriodsMakesTheWindowsStartAVariance) {
  // Q = 42 mesh cycles: mesh harmonic 7 (order 567, bin 294) and its sun sideband (bin 290)
  // complete whole periods, so their bins do not depend on where the window starts. A planet-
  // family line (order 567 + 81/30, bin 295.4: no whole period in 42 mesh cycles) leaks into
  // bin 294 with a phase that does: there the amplitude beats with the window's start.
  const model::SimulationConfig cfg;
  const auto& st = cfg.stage;
  const Recording rec = sun_speed_and_mesh_recording();
  RecordingSpectra s;
  s.layout = make_layout_mesh_cycles(kinematics(st, 1200), st.planet_count, 42, 600.0);
  s.angle_reference = AngleReference::SunSpeed;
  s.channels = {0, 1};
  const ModelSpectra whole =
      model_spectra(rippled_sun_record(st, 1.0, {{2, 567, 0.3}, {0.8, 567 - 2 * 81.0 / 21, 1.1}}, 5.0), rec, s, cfg, false);
  ASSERT_EQ(whole.leak_variance.size(), 2u);
  double largest = 0;
  for (const double v : whole.leak_variance[1]) largest = std::max(largest, v);
  EXPECT_LT(largest, 1e-8);  // resampling round-off only (the lines' amplitudes are 1 and 0.4)
  const ModelSpectra leaky = model_spectra(
      rippled_sun_record(st, 1.0, {{2, 567, 0.3}, {0.8, 567 - 2 * 81.0 / 21, 1.1}, {1.0, 567 + 81.0 / 30, 0.7}}, 5.0),
      rec, s, cfg, false);
  // The leak into bin 294 is 0.5 |sin(1.4 pi) / (1.4 pi)| = 0.11 of the line there: its phase
  // against the line moves by 2 pi 2.7 (Q/4) / 81 per shift, so the mean square change is of
  // order 0.11^2.
  EXPECT_GT(leaky.leak_variance[1][294], 1e-3);
  EXPECT_LT(leaky.leak_variance[1][294], 4 * 0.11 * 0.11);
  EXPECT_LT(leaky.leak_variance[1][290], leaky.leak_variance[1][294]);
  std::printf("window-start variance at bin 294: %.3g (whole-period lines only: largest %.3g)\n",
              leaky.leak_variance[1][294], largest);
  // Whole carrier revolutions: no such variance.
  RecordingSpectra w = s;
  w.layout = RecordingSpectra{}.layout;
  w.layout.revolutions = 1;
  w.layout.max_bin = 700;
  EXPECT_TRUE(model_spectra(rippled_sun_record(st, 1.05, {{2, 567, 0.3}}, 5.0), rec, w, cfg, false).leak_variance.empty());
}

TEST(OrderAnalysis, ManyPlanetsOnASmallRingStillLeaveBinsForTheNoiseBetweenTheirSidebandGroups) {
  // Eight planets, Zs 38 / Zp 18 / Zr 74 (profile shifts 0.3 and 0.6: a valid stage): keeping
  // 4 (N + 2) = 40 carrier orders clear of every mesh harmonic (74 orders apart) leaves no bin, and
  // such a recording was refused as "record too short?" (docs/diagnose-log.md session 60). The
  // clearance steps down to 3 (N + 2) = 30, and the white noise of the mesh channel (0.5 m/s^2
  // per sample, beside 8 mesh harmonics of 10/h m/s^2) is estimated within 4 standard errors of
  // its exponential mean over the bins used (the truncated mean's relative se is ~1/sqrt(bins)).
  model::SimulationConfig cfg = test::stage_1200rpm();
  cfg.stage.planet_count = 8;
  cfg.stage.sun.teeth = 38;
  cfg.stage.planet.teeth = 18;
  cfg.stage.planet.profile_shift = 0.3;
  cfg.stage.ring.teeth = 74;
  cfg.stage.ring.profile_shift = 0.6;
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  const Recording rec = test::synthetic_of(cfg, 3.2 / k.carrier_Hz, 0.0, 0.0, 7);
  const RecordingSpectra s = analyse_recording(rec, cfg.stage);
  EXPECT_DOUBLE_EQ(s.noise_clearance_orders, 30.0);
  ASSERT_EQ(s.noise_sample_variance.size(), 2u);
  const std::size_t acc = s.channels[0] == 1 ? 0 : 1;  // the mesh-acceleration channel
  ASSERT_GE(s.noise_bins_used[acc], 32);
  const double se = 1.0 / std::sqrt(static_cast<double>(s.noise_bins_used[acc]) / 1.944);
  EXPECT_NEAR(s.noise_sample_variance[acc] / 0.25, 1.0, 4 * se) << s.noise_bins_used[acc] << " bins";
  // The seed stage keeps the full clearance.
  const RecordingSpectra seed = analyse_recording(test::synthetic(0.0, 0.0, 3), test::stage_1200rpm().stage);
  EXPECT_DOUBLE_EQ(seed.noise_clearance_orders, 4 * (3 + 2.0));
}

TEST(OrderAnalysis, ALongReferenceInAShortRecordingsMeshCycleWindowsHasItsCellsAndWindowLength) {
  // A reference longer than two carrier revolutions, analysed with OrderAnalysisOptions::mesh_cycles
  // set to a short recording's Q, gets the short recording's layout: the same cells at the same
  // orders and windows of Q mesh cycles (a differential comparison matches them cell by cell).
  const model::SimulationConfig cfg = test::stage_1200rpm();
  const Recording full = test::synthetic(0.0, 0.0, 3);  // 3.2 carrier revolutions
  Recording part = full;                                 // its first 1.5 revolutions
  const std::size_t n = static_cast<std::size_t>(static_cast<double>(full.time_s.size()) * 1.5 / 3.2);
  part.time_s.resize(n);
  for (auto& c : part.channels) c.values.resize(n);
  const RecordingSpectra shrt = analyse_recording(part, cfg.stage);
  ASSERT_GT(shrt.layout.mesh_cycles, 0);  // under two revolutions: halves of mesh cycles
  OrderAnalysisOptions o;
  o.mesh_cycles = shrt.layout.mesh_cycles;
  const RecordingSpectra ref = analyse_recording(full, cfg.stage, o);
  EXPECT_EQ(ref.layout.revolutions, 0);
  EXPECT_EQ(ref.layout.mesh_cycles, shrt.layout.mesh_cycles);
  ASSERT_EQ(ref.layout.cells.size(), shrt.layout.cells.size());
  for (std::size_t i = 0; i < ref.layout.cells.size(); ++i) EXPECT_EQ(ref.layout.cells[i].order, shrt.layout.cells[i].order);
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  for (const OrderWindow& w : ref.windows)  // Q mesh cycles each, to one sample
    EXPECT_NEAR((w.t_end_s - w.t_begin_s) * k.mesh_Hz, o.mesh_cycles, 2e-4 * k.mesh_Hz + 1e-9);
  // Asked for more than fits twice: an input error naming the recording.
  o.mesh_cycles = 4 * shrt.layout.mesh_cycles;
  EXPECT_THROW(analyse_recording(part, cfg.stage, o), InputError);
}

TEST(OrderAnalysis, ALineAQuarterBinOffGetsTheSameCellsWhateverTheRoundOffOfTheMeasuredSpeed) {
  // Five planets, Zs 25, Zp 20, Zr 65 (the independent corpus's fresh gear set): over R = 3 carrier
  // revolutions the planet lines lie Zr R / Zp = 9.75 bins apart, so every fourth one is exactly a
  // quarter bin off its bin. Measured speeds a few ulp apart put it at 0.25 +- 1e-15; both
  // recordings of the operating point must get the same cells (before session 37 one of them had
  // neighbour cells the other lacked: 1194 against 1199 cells, and --baseline refused the pair).
  model::StageSpec st = model::SimulationConfig{}.stage;
  st.planet_count = 5;
  st.sun.teeth = 25;
  st.planet.teeth = 20;
  st.ring.teeth = 65;
  const double rpm = 350;
  const FeatureLayout ref = make_layout(kinematics(st, rpm), 5, 3, 925.0);
  for (double rel : {-3e-12, -1e-15, 1e-15, 2e-14, 5e-12}) {
    const FeatureLayout L = make_layout(kinematics(st, rpm * (1 + rel)), 5, 3, 925.0);
    ASSERT_EQ(L.cells.size(), ref.cells.size()) << "speed x (1 + " << rel << ")";
    for (std::size_t i = 0; i < L.cells.size(); ++i) ASSERT_EQ(L.cells[i].bin, ref.cells[i].bin);
  }
  // The quarter itself gets no neighbour: the planet line f_pr (3.25 carrier orders, 9.75 bins)
  // counts in bin 10 and not in bin 9.
  const auto line = std::find_if(ref.lines.begin(), ref.lines.end(), [](const auto& l) {
    return l.family == Component::Planet && l.mesh_harmonic == 0 && l.sideband == 1;
  });
  ASSERT_NE(line, ref.lines.end());
  EXPECT_NEAR(line->order * 3, 9.75, 1e-12);
  const int index = static_cast<int>(line - ref.lines.begin());
  std::vector<int> bins_of_line;
  for (const FeatureCell& c : ref.cells)
    if (std::find(c.lines.begin(), c.lines.end(), index) != c.lines.end()) bins_of_line.push_back(c.bin);
  EXPECT_EQ(bins_of_line, std::vector<int>{10});
}

TEST(OrderAnalysis, ARecordingAndItsReferenceWithBandEdgesEitherSideOfACellAreComparedUpToTheLowerEdge) {
  // The band ends at 0.3 fs over each recording's own measured carrier speed: 728.6 carrier
  // orders for the 1200 rpm stage at 10 kHz. A recording whose speed channel reads 0.1 % low has
  // its edge at 729.3 and holds the cell of mesh harmonic 9 (order 729) that its reference lacks.
  const model::SimulationConfig cfg = test::stage_1200rpm();
  const Recording reference = test::synthetic(0.0, 0.0, 3);
  const Recording recording = test::synthetic(0.0, 0.0, 4, -1e-3);
  const RecordingSpectra a = analyse_recording(recording, cfg.stage);
  const RecordingSpectra b = analyse_recording(reference, cfg.stage);
  ASSERT_EQ(a.layout.max_bin, 729);
  ASSERT_EQ(b.layout.max_bin, 728);
  EXPECT_FALSE(reference_covers(b, a));
  const auto o = common_analysis_options(recording, cfg.stage, a, reference, cfg.stage);
  ASSERT_TRUE(o.has_value());
  const RecordingSpectra a2 = analyse_recording(recording, cfg.stage, *o);
  const RecordingSpectra b2 = analyse_recording(reference, cfg.stage, *o);
  EXPECT_EQ(a2.layout.max_bin, 728);
  EXPECT_TRUE(reference_covers(b2, a2));
  EXPECT_EQ(a2.layout.cells.size(), b2.layout.cells.size());
  // Recordings of the same edge keep the default analysis (no cap).
  const auto same = common_analysis_options(reference, cfg.stage, b, test::synthetic(0.0, 0.0, 5), cfg.stage);
  ASSERT_TRUE(same.has_value());
  EXPECT_EQ(same->max_order, 0.0);
}

} // namespace
} // namespace pw::diagnose
