// End to end on simulated recordings (in-process, no files). The recordings
// are made with DIFFERENT solver settings from the model the diagnosis uses
// (solver.steps_per_mode_period 40 instead of 32, a short warm-up with
// periodicity_tolerance 1e-3, the file starting 0.1 s later than the warm-up
// ended), decimated through an anti-alias filter to about 10 kHz, with 5 %
// white noise and DC offsets on the accelerometers, so only the planted effect,
// the noise and a realistic model/recording mismatch separate them:
//  * the control (no effect) gives "no missing physics found";
//  * a damaged sun tooth is located, named, and its stiffness factor fitted
//    within 20 %;
//  * at the mesh resonance (19 500 rpm, ~50 kHz, 40 carrier revolutions) the
//    control gives "no missing physics" and 20 um of backlash is named, with a
//    lower limit of its size at or below the truth.
#include "diagnose/calibration.hpp"
#include "diagnose/diagnose.hpp"
#include "signal/decimate.hpp"
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

/// Zero-phase low-pass (signal::decimation_filter with 64 k + 1 taps) at every
/// k-th sample from `first`.
std::vector<double> decimate(const std::vector<double>& x, int k, std::size_t first, std::size_t count) {
  return signal::decimate(x, signal::decimation_filter(k, 32), first, count);
}

/// A recording of `truth` (`revolutions` carrier revolutions, sampled every ~sample_s,
/// starting skip_s after the warm-up) made with other solver settings.
Recording synthesize(model::SimulationConfig truth, double noise, unsigned seed, double revolutions = 3.2,
                     double sample_s = 1e-4, double skip_s = 0.1, double periodicity = 1e-3) {
  const Kinematics k = kinematics(truth.stage, truth.operating.input_speed_rpm);
  truth.solver.steps_per_mode_period = 40;
  truth.solver.periodicity_tolerance = periodicity;
  const double seconds = revolutions / k.carrier_Hz;
  truth.solver.record_mesh_cycles = static_cast<int>(std::ceil((skip_s + seconds) * k.mesh_Hz)) + 8;
  const auto r = model::simulate(truth);
  double t0 = 0;
  for (const auto& s : r.scalars)
    if (s.name == "record_start_time") t0 = s.value;
  const double dt = r.time_step_s;
  const int dec = std::max(1, static_cast<int>(std::lround(sample_s / dt)));
  const std::size_t first = static_cast<std::size_t>(skip_s / dt);
  const std::size_t count = static_cast<std::size_t>(seconds / (dt * dec));
  Recording rec;
  rec.source = "synthetic";
  rec.operating = truth.operating;
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

/// A four-planet stage, sequentially phased (27/21/69: 69/4 is not whole), whose planets' ring
/// forces do not cancel at the mesh harmonics: a housing accelerometer hears its healthy mesh lines.
model::SimulationConfig four_planet_stage() {
  model::SimulationConfig c = fast_stage();
  c.stage.planet_count = 4;
  c.stage.sun.teeth = 27;
  c.stage.planet.teeth = 21;
  c.stage.ring.teeth = 69;
  return c;
}

// A calibration (nuisance-only) of a torsional gear set on a recording of the lateral-torsional
// model's ring body (supports damped at 5 %): the window's nuisance model fails the noise test, and
// the calibration's probe of the ring body (docs/diagnose.md §6a item 12) fits the fit half better
// than its two parameters (the form and the supports' damping) buy by chance -- the F test the
// calibration takes it by -- and better than the ring's quasi-static translation, while the fitted
// nuisance model it reports stays the torsional window's (the calibration, not the probe, changes
// the form). Nothing after the probe simulates in a calibration, so the trial's undoing of the
// level (ModelFormTrial) has no outcome here to check.
TEST(Diagnose, ACalibrationProbesTheRingBodyOfALateralTorsionalRecordingAndKeepsItsModelTorsional) {
  model::SimulationConfig truth = four_planet_stage();
  truth.solver.level = model::ModelLevel::LateralTorsional;
  truth.sensor.housing_path = model::HousingPath::RingBody;
  truth.bearings.damping_ratio = 0.05;
  const Recording rec = synthesize(truth, 0.05, 7);
  DiagnoseOptions opt;
  opt.nuisance_only = true;
  opt.probe_ring_body = true;  // calibrate --ring-body
  const Diagnosis d = diagnose(rec, four_planet_stage(), opt);
  ASSERT_GT(d.nuisance.fit.chi2, d.bound_fit) << "the window's model explained the ring body: nothing to probe";
  ASSERT_TRUE(d.ring_body_probe_chi2.has_value()) << d.summary;
  EXPECT_TRUE(form_probes_pass({ModelFormFits{.fit_chi2 = d.nuisance.fit.chi2,
                                              .probe_fit_chi2 = d.ring_body_probe_chi2,
                                              .fit_features = d.nuisance.fit.features,
                                              .held_out_chi2 = d.nuisance.held_out.chi2,
                                              .refit_held_out_chi2 = std::nullopt,
                                              .held_out_features = d.nuisance.held_out.features,
                                              .extra_parameters = 2}},
                               0.01))
      << "probe " << *d.ring_body_probe_chi2 << " against " << d.nuisance.fit.chi2;
  EXPECT_EQ(d.nuisance.config.solver.level, model::ModelLevel::Torsional);
  EXPECT_EQ(d.nuisance.config.sensor.housing_path, model::HousingPath::PlanetPass);
  EXPECT_FALSE(d.ring_translation_probe_chi2 && *d.ring_translation_probe_chi2 <= *d.ring_body_probe_chi2)
      << "the quasi-static translation fits as well: the recording does not need the ring body";
  // Off unless asked for (calibrate's default): no lateral-torsional simulation is spent on it.
  opt.probe_ring_body = false;
  EXPECT_FALSE(diagnose(rec, four_planet_stage(), opt).ring_body_probe_chi2.has_value());
}

/// 19 500 rpm, 2 kW: the mesh frequency (5.42 kHz) sits on the primary mesh mode, the dynamic
/// mesh force exceeds the static one and, with play, the teeth separate (by < 0.1 um).
model::SimulationConfig resonant_stage() {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 19500;
  c.operating.input_power_W = 2000;
  c.sensor.angle_rad = 0.6;
  return c;
}

// At this speed and load the warm-up's speed loop converges slowly: stopped at a periodicity of
// 1e-3, the recording kept a slow drift of the sun speed, which the diagnosis rightly found
// (fitted as a 0.25 % torque ripple at order 1) even 0.4 s later. As in the corpus
// (docs/recordings.md), these recordings warm up to the default 1e-6 and start 0.3 s later.
constexpr double kResonantSkip_s = 0.3, kResonantPeriodicity = 1e-6;

TEST(Diagnose, ControlAtTheMeshResonanceFindsNoMissingPhysics) {
  // 40 carrier revolutions (0.6 s) at ~50 kHz, 5 % noise.
  const Recording rec = synthesize(resonant_stage(), 0.05, 4, 40, 2e-5, kResonantSkip_s, kResonantPeriodicity);
  const Diagnosis d = diagnose(rec, resonant_stage(), {});
  EXPECT_EQ(d.verdict, Verdict::NoMissingPhysics) << d.summary;
}

TEST(Diagnose, BacklashAtTheMeshResonanceIsNamedWithALowerLimitAtOrBelowTheTruth) {
  // The model has no backlash (a linear mesh whose contacts pull as well as push); the
  // recording's stage has 20 um on both meshes. Beyond the separation depth the size does not
  // matter, so the diagnosis must name backlash and bound its size from below only: the
  // lower limit must not exceed the truth, and no standard error is claimed.
  auto truth = resonant_stage();
  truth.contact.backlash_sun_planet_m = 2e-5;
  truth.contact.backlash_planet_ring_m = 2e-5;
  const Recording rec = synthesize(truth, 0.05, 5, 40, 2e-5, kResonantSkip_s, kResonantPeriodicity);
  const Diagnosis d = diagnose(rec, resonant_stage(), {});
  ASSERT_EQ(d.verdict, Verdict::MissingPhysicsFound) << d.summary;
  const auto& w = d.candidates.front();
  EXPECT_EQ(w.name, "backlash") << d.summary;
  int own = 0;
  for (const auto& p : w.parameters) {
    if (p.nuisance) continue;
    ++own;
    EXPECT_TRUE(p.saturates) << p.name;
    ASSERT_TRUE(std::isfinite(p.lower_limit)) << p.name;
    EXPECT_GT(p.lower_limit, 0.0) << p.name;
    EXPECT_LE(p.lower_limit, 2e-5) << p.name;
  }
  EXPECT_EQ(own, 2);
  // 'Absent' tested by the likelihood ratio: the fit with the play put back to 0 is worse.
  EXPECT_GT(w.null_chi2_fit - w.fit.chi2, w.lr_threshold);
}

} // namespace
} // namespace pw::diagnose
