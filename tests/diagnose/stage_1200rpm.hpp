// The operating point of the diagnose unit tests that build their recordings by
// hand (test_compare, test_locate, test_baseline): the seed stage (Zs 21, Zp 30,
// Zr 81) at 1200 rpm, mesh frequency 333.5 Hz, carrier revolution 0.243 s, 20 kW;
// and a synthetic recording of it: 3.2 carrier revolutions at 10 kHz, a sun-speed
// channel (constant + white noise) and a sun-planet mesh acceleration made of 8
// mesh harmonics plus white noise.
#pragma once

#include "config/stage.hpp"
#include "core/constants.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/recording.hpp"

#include <cmath>
#include <cstddef>
#include <random>

namespace pw::diagnose::test {

inline model::SimulationConfig stage_1200rpm() {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 1200;  // [rpm]
  c.operating.input_power_W = 20000;   // [W]
  return c;
}

/// A synthetic recording of `cfg`'s stage at its operating point: `seconds` at 10 kHz, a
/// sun-speed channel (constant + white noise) and a sun-planet mesh acceleration made of 8 mesh
/// harmonics plus white noise.
/// phase_jitter_rad: standard deviation per sample of a random walk in the
/// mesh phase (harmonic k sees k times it) — the skirt that slow speed or load
/// wander spreads around every mesh harmonic. sideband_m_s2: a stationary
/// line at carrier order 2 Zr + 3 (a carrier-family fault signature).
/// speed_bias: relative error of the speed channel (the integrated angle reference then
/// drifts linearly against the true shaft angle). noise_m_s2: acceleration noise per sample;
/// speed_noise_rad_s: speed-channel noise per sample (its integral is the angle reference's random walk).
inline Recording synthetic_of(const model::SimulationConfig& cfg, double seconds, double phase_jitter_rad,
                              double sideband_m_s2, unsigned seed, double speed_bias = 0.0, double noise_m_s2 = 0.5,
                              double speed_noise_rad_s = 0.01) {
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  const double fs = 10000;
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
    w.values.push_back(omega * (1 + speed_bias) + speed_noise_rad_s * nd(rng));
    phase += phase_jitter_rad * nd(rng);
    double x = noise_m_s2 * nd(rng);
    for (int h = 1; h <= 8; ++h) x += (10.0 / h) * std::cos(2 * kPi * h * k.mesh_Hz * t + h * phase);
    x += sideband_m_s2 * std::cos(2 * kPi * (2 * k.ring_teeth + 3) * k.carrier_Hz * t + 0.4);
    a.values.push_back(x);
  }
  r.channels = {w, a};
  return r;
}

/// synthetic_of the 1200 rpm stage over 3.2 carrier revolutions.
inline Recording synthetic(double phase_jitter_rad, double sideband_m_s2, unsigned seed, double speed_bias = 0.0,
                    double noise_m_s2 = 0.5, double speed_noise_rad_s = 0.01) {
  const auto cfg = stage_1200rpm();
  const Kinematics k = kinematics(cfg.stage, cfg.operating.input_speed_rpm);
  return synthetic_of(cfg, 3.2 / k.carrier_Hz, phase_jitter_rad, sideband_m_s2, seed, speed_bias, noise_m_s2,
                      speed_noise_rad_s);
}

} // namespace pw::diagnose::test
