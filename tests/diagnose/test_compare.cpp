// The recording-side noise model of the comparison (compare.hpp): the
// dispersion phi measured between the recording's two halves. No simulation is
// run: ModelComparison analyses the recording in its constructor.
//
// The recording is synthetic: the seed stage at 1200 rpm (mesh frequency
// 333.5 Hz, carrier revolution 0.243 s), 3.2 carrier revolutions at 10 kHz; a
// sun-speed channel (constant + white noise) and a sun-planet mesh
// acceleration made of 8 mesh harmonics plus white noise.
#include "diagnose/compare.hpp"
#include "diagnose/kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pw::diagnose {
namespace {

constexpr double kPi = std::numbers::pi;

model::SimulationConfig stage_1200rpm() {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 1200;
  c.operating.input_power_W = 20000;
  return c;
}

/// phase_jitter_rad: standard deviation per sample of a random walk in the
/// mesh phase (harmonic k sees k times it) — the skirt that slow speed or load
/// wander spreads around every mesh harmonic. sideband_m_s2: a stationary
/// line at carrier order 2 Zr + 3 (a carrier-family fault signature).
Recording synthetic(double phase_jitter_rad, double sideband_m_s2, unsigned seed) {
  const auto cfg = stage_1200rpm();
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  const double fs = 10000, seconds = 3.2 / k.carrier_Hz;
  const std::size_t n = static_cast<std::size_t>(seconds * fs);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Recording r;
  r.source = "synthetic";
  r.operating = cfg.operating;
  SignalChannel w{"sun_speed", Quantity::SunSpeed, "rad/s", 0, 0.0, {}};
  SignalChannel a{"sp_acc", Quantity::MeshAccelerationSunPlanet, "m/s^2", 0, 0.0, {}};
  const double omega = cfg.operating.input_speed_rpm * 2 * kPi / 60;
  double phase = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / fs;
    r.time_s.push_back(t);
    w.values.push_back(omega + 0.01 * nd(rng));
    phase += phase_jitter_rad * nd(rng);
    double x = 0.5 * nd(rng);
    for (int h = 1; h <= 8; ++h) x += (10.0 / h) * std::cos(2 * kPi * h * k.mesh_Hz * t + h * phase);
    x += sideband_m_s2 * std::cos(2 * kPi * (2 * k.ring_teeth + 3) * k.carrier_Hz * t + 0.4);
    a.values.push_back(x);
  }
  r.channels = {w, a};
  return r;
}

TEST(Compare, DispersionStaysOneWhenTheHalvesAgreeEvenWithAStationaryFaultLine) {
  // A stationary line 10x the noise at a carrier sideband is the same in both halves: it
  // cancels in A_1 - A_2 and must not be read as extra noise.
  const ModelComparison cmp(synthetic(0.0, 5.0, 3), stage_1200rpm());
  ASSERT_EQ(cmp.channels(), 2);
  EXPECT_EQ(cmp.dispersion(0), 1.0);
  EXPECT_EQ(cmp.dispersion(1), 1.0);
}

TEST(Compare, DispersionMeasuresTheSkirtOfAJitteredMeshHarmonic) {
  // Phase wander of 2e-3 rad per sample: over a carrier revolution (2430 samples) the
  // mesh phase walks ~0.1 rad (harmonic 8: ~0.8 rad), a skirt over the sideband cells that
  // changes between the halves while the floor between the sideband groups does not see it.
  // phi is set only when it exceeds 1 beyond its sampling error, and more wander gives a
  // wider skirt, so phi grows with it.
  const ModelComparison cmp(synthetic(2e-3, 0.0, 4), stage_1200rpm());
  EXPECT_EQ(cmp.dispersion(0), 1.0);  // the speed channel has no jitter
  EXPECT_GT(cmp.dispersion(1), 1.0);
  const ModelComparison more(synthetic(4e-3, 0.0, 4), stage_1200rpm());
  EXPECT_GT(more.dispersion(1), cmp.dispersion(1));
}

} // namespace
} // namespace pw::diagnose
