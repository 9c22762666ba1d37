// End to end on simulated recordings (in-process, no files). The recordings
// are made with DIFFERENT solver settings from the model the diagnosis uses
// (solver.steps_per_mode_period 40 instead of 32, a short warm-up with
// periodicity_tolerance 1e-3, the file starting 0.1 s later than the warm-up
// ended), decimated through an anti-alias filter to about 10 kHz, with 5 %
// white noise and DC offsets on the accelerometers, so only the planted effect,
// the noise and a realistic model/recording mismatch separate them:
//  * the control (no effect) gives "no missing physics found";
//  * a damaged sun tooth is located, named, and its stiffness factor fitted
//    within 20 %.
#include "diagnose/diagnose.hpp"
#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pw::diagnose {
namespace {

constexpr double kPi = std::numbers::pi;

model::SimulationConfig fast_stage() {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 1200;  // carrier revolution 0.243 s
  c.operating.input_power_W = 20000;
  c.sensor.angle_rad = 0.6;
  return c;
}

/// Zero-phase low-pass (Blackman-windowed sinc, cutoff 0.4 of the new rate,
/// 64 k + 1 taps: > 100 dB stop band) evaluated at every k-th sample whose
/// kernel lies inside x.
std::vector<double> decimate(const std::vector<double>& x, int k, std::size_t first, std::size_t count) {
  const int half = 32 * k;
  const double fc = 0.4 / k;
  std::vector<double> h(2 * static_cast<std::size_t>(half) + 1);
  double sum = 0;
  for (int m = -half; m <= half; ++m) {
    const double s = m == 0 ? 2 * fc : std::sin(2 * kPi * fc * m) / (kPi * m);
    const double a = kPi * (m + half) / half;
    const double w = 0.42 - 0.5 * std::cos(a) + 0.08 * std::cos(2 * a);
    h[static_cast<std::size_t>(m + half)] = s * w;
    sum += s * w;
  }
  for (double& c : h) c /= sum;
  std::vector<double> y;
  for (std::size_t j = 0; j < count; ++j) {
    const std::size_t i = first + j * static_cast<std::size_t>(k);
    double acc = 0;
    for (std::size_t m = 0; m < h.size(); ++m) acc += h[m] * x[i - static_cast<std::size_t>(half) + m];
    y.push_back(acc);
  }
  return y;
}

/// A recording of `truth` (3.2 carrier revolutions) made with other solver settings.
Recording synthesize(model::SimulationConfig truth, double noise, unsigned seed) {
  const Kinematics k = kinematics(truth.stage, truth.operating.input_speed_rpm);
  truth.solver.steps_per_mode_period = 40;
  truth.solver.periodicity_tolerance = 1e-3;
  const double skip_s = 0.1, seconds = 3.2 / k.carrier_Hz;
  truth.solver.record_mesh_cycles = static_cast<int>(std::ceil((skip_s + seconds) * k.mesh_Hz)) + 8;
  const auto r = model::simulate(truth);
  double t0 = 0;
  for (const auto& s : r.scalars)
    if (s.name == "record_start_time") t0 = s.value;
  const double dt = r.time_step_s;
  const int dec = static_cast<int>(std::lround(1e-4 / dt));  // ~10 kHz
  const std::size_t first = static_cast<std::size_t>(skip_s / dt);
  const std::size_t count = static_cast<std::size_t>(seconds / (dt * dec));
  Recording rec;
  rec.source = "synthetic";
  rec.operating = fast_stage().operating;
  for (std::size_t j = 0; j < count; ++j) rec.time_s.push_back(t0 + r.time_s[first + j * static_cast<std::size_t>(dec)]);
  std::mt19937_64 rng(seed);
  const struct {
    const char* name;
    Quantity q;
  } cols[] = {{"sun/speed", Quantity::SunSpeed},
              {"sun_planet/0/acceleration", Quantity::MeshAccelerationSunPlanet},
              {"planet_ring/0/acceleration", Quantity::MeshAccelerationPlanetRing},
              {"housing/acceleration", Quantity::HousingAcceleration}};
  for (const auto& col : cols) {
    const auto* ch = r.find(col.name);
    SignalChannel sc;
    sc.name = col.name;
    sc.quantity = col.q;
    sc.sensor_angle_rad = col.q == Quantity::HousingAcceleration ? truth.sensor.angle_rad : 0.0;
    sc.values = decimate(ch->values, dec, first, count);
    double mean = 0, var = 0;
    for (double v : sc.values) mean += v / static_cast<double>(sc.values.size());
    for (double v : sc.values) var += (v - mean) * (v - mean) / static_cast<double>(sc.values.size());
    std::normal_distribution<double> nd(0.0, noise * std::sqrt(var));
    const double offset = col.q == Quantity::SunSpeed ? 0.0 : 0.3 * std::sqrt(var);
    for (double& v : sc.values) v += offset + nd(rng);
    rec.channels.push_back(std::move(sc));
  }
  return rec;
}

TEST(Diagnose, ControlWithFivePercentNoiseFindsNoMissingPhysics) {
  const Recording rec = synthesize(fast_stage(), 0.05, 1);
  const Diagnosis d = diagnose(rec, fast_stage(), {});
  EXPECT_EQ(d.verdict, Verdict::NoMissingPhysics) << d.summary;
  EXPECT_LE(d.nuisance.fit.chi2, d.bound_fit);
  EXPECT_LE(d.nuisance.held_out.chi2, d.bound_held_out);
  // The speed comes from the recording, within its standard error of the truth.
  EXPECT_NEAR(d.speed.input_rpm, 1200.0, 1200.0 * 1e-4);
  for (const auto& p : d.nuisance.parameters) EXPECT_FALSE(p.moved) << p.name << " = " << p.value;
}

TEST(Diagnose, DamagedSunToothIsLocatedNamedAndFittedWithin20Percent) {
  auto truth = fast_stage();
  model::ToothModifier t;
  t.body = model::Body::Sun;
  t.tooth = 5;
  t.stiffness_factor = 0.6;
  truth.imperfections.teeth.push_back(t);
  const Recording rec = synthesize(truth, 0.05, 2);
  const Diagnosis d = diagnose(rec, fast_stage(), {});
  ASSERT_TRUE(d.located);
  ASSERT_EQ(d.verdict, Verdict::MissingPhysicsFound) << d.summary;
  const auto& w = d.candidates.front();
  EXPECT_EQ(w.name, "sun_tooth_damage") << d.summary;
  ASSERT_FALSE(w.parameters.empty());
  EXPECT_EQ(w.parameters.front().name, "stiffness_factor");
  EXPECT_NEAR(w.parameters.front().value, 0.6, 0.2 * 0.6) << d.summary;
  // The screening put the sun tooth first: the missing physics was located before it was fitted.
  ASSERT_FALSE(d.screening.empty());
  EXPECT_EQ(d.screening.front().name, "sun_tooth_damage");
}

} // namespace
} // namespace pw::diagnose
