// End-to-end physics of model::simulate on the seed stage: statics, torque
// balance, and each imperfection on its own. 400 rpm keeps the runs short.
#include "core/error.hpp"
#include "model/simulation.hpp"
#include "simulation_fixture.hpp"
#include "signal/spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>

using namespace pw::model;

namespace {

using pw::test::channel;
using pw::test::fast_seed;
using pw::test::mean;
using pw::test::scalar;

double stddev(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / static_cast<double>(v.size()));
}

constexpr double kRbs = 0.5 * 3e-3 * 21 * 0.9396926207859084;  // sun base radius [m]

} // namespace

TEST(Simulation, EqualPlanetsShareLoadEquallyAndMeshForceIsTsOverNrbs) {
  // Without friction the mean sun-planet force is T_s / (N r_bs) (statics of
  // the sun) within 0.5 % (the tolerance; the damping force averages
  // out over whole mesh periods), and the planets share equally.
  SimulationConfig c = fast_seed();
  c.contact.friction_coefficient = 0;
  const SimulationResult r = simulate(c);
  const double Ts = 1000.0 / (400 * 2 * std::numbers::pi / 60);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(mean(channel(r, "sun_planet/" + std::to_string(i) + "/force")), Ts / (3 * kRbs), 5e-3 * Ts / (3 * kRbs));
    EXPECT_NEAR(scalar(r, "load_sharing_factor/" + std::to_string(i)), 1.0, 1e-6);
  }
  // Torque balance of the whole stage: carrier torque = T_s (Zs + Zr)/Zs.
  EXPECT_NEAR(scalar(r, "load_torque"), Ts * 102.0 / 21.0, 1e-3 * Ts * 102.0 / 21.0);
  EXPECT_NEAR(scalar(r, "efficiency"), 1.0, 1e-3);
}

TEST(Simulation, ToothFrictionCostsEfficiencyOfOrderMuTimesSliding) {
  // With mu = 0.1 a planetary stage of this ratio loses ~1-3 % (Anderson &
  // Loewenthal's mesh-loss estimate mu (1/z1 +- 1/z2) pi eps-ish per mesh).
  const SimulationResult r = simulate(fast_seed());
  const double eta = scalar(r, "efficiency");
  EXPECT_LT(eta, 0.995);
  EXPECT_GT(eta, 0.95);
}

TEST(Simulation, ConstantMeshErrorShiftsMeanDeflectionByTheError) {
  SimulationConfig c = fast_seed();
  c.contact.friction_coefficient = 0;
  const SimulationResult r0 = simulate(c);
  c.contact.mesh_error_sun_planet_m = 2e-6;
  const SimulationResult r1 = simulate(c);
  const double d0 = mean(channel(r0, "sun_planet/0/deflection"));
  const double d1 = mean(channel(r1, "sun_planet/0/deflection"));
  EXPECT_NEAR(d1 - d0, 2e-6, 2e-8);  // load unchanged, so the elastic part is too
}

TEST(Simulation, AdvancedPlanetPinUnloadsThatPlanet) {
  // A pin advanced by e along the carrier's rotation shortens both meshes of
  // that planet by e cos(alpha'); with k ~ 1e9 N/m, 0.3 um moves ~300 N.
  SimulationConfig c = fast_seed();
  c.imperfections.pin_error_m = {0.3e-6, 0.0, 0.0};
  const SimulationResult r = simulate(c);
  const double l0 = scalar(r, "load_sharing_factor/0"), l1 = scalar(r, "load_sharing_factor/1"),
               l2 = scalar(r, "load_sharing_factor/2");
  EXPECT_LT(l0, 0.9);
  EXPECT_GT(l1, 1.03);
  EXPECT_NEAR(l1, l2, 1e-6);
  EXPECT_NEAR(l0 + l1 + l2, 3.0, 1e-9);
}

TEST(Simulation, CrackedSunToothLowersMeshStiffnessOnlyWhileItMeshes) {
  SimulationConfig c = fast_seed(30);  // > one sun revolution relative to the carrier (21 mesh periods)
  const SimulationResult healthy = simulate(c);
  c.imperfections.teeth.push_back({Body::Sun, 0, 0, 0.5, 0.0});
  const SimulationResult cracked = simulate(c);
  const auto& kh = channel(healthy, "sun_planet/0/stiffness");
  const auto& kc = channel(cracked, "sun_planet/0/stiffness");
  const double kh_min = *std::min_element(kh.begin(), kh.end());
  const double kc_min = *std::min_element(kc.begin(), kc.end());
  EXPECT_LT(kc_min, 0.75 * kh_min);
  // Stiffness below the healthy minimum occurs only while tooth 0 is in
  // mesh: at most epsilon_alpha = 1.61 of every 21 mesh periods.
  std::size_t low = 0;
  for (double k : kc) low += k < 0.999 * kh_min;
  const double fraction = static_cast<double>(low) / static_cast<double>(kc.size());
  EXPECT_GT(fraction, 0.2 / 21.0);
  EXPECT_LT(fraction, 1.62 / 21.0);
}

TEST(Simulation, TheWarmUpHoldsTheSpeedAtTheTopOfTheSpeedRangeWhereTheVibrationDwarfsTheTorque) {
  // 1 kW at 50 000 and 100 000 rpm (operating.input_speed_rpm allows up to 1e5): 0.19 and
  // 0.095 N m of input torque against the mesh vibration's inertia torques. The loop on the
  // sun's speed feeds the elastic modes back there (each load update a torque step exciting
  // them): it ended at a load torque of 2.6e11 N m (50 000 rpm) or diverged (100 000 rpm, roll
  // 1e14 m). The warm-up then restarts on the rigid mode's own speed (docs/derivation.md §3.4).
  // Steady state: periodic to the tolerance, mean sun speed nominal to 1e-6, and the load torque
  // the input torque times the ratio and an efficiency between 0.9 and 1. At 400 rpm the sun's
  // speed serves (the results of every earlier session, bit for bit).
  for (const double rpm : {400.0, 50000.0, 100000.0}) {
    SimulationConfig c;
    c.operating.input_speed_rpm = rpm;
    c.solver.record_mesh_cycles = 2;
    const SimulationResult r = simulate(c);
    EXPECT_EQ(scalar(r, "warmup_speed_loop"), rpm < 1000 ? 0.0 : 1.0) << rpm << " rpm";
    EXPECT_LT(scalar(r, "periodicity_residual"), c.solver.periodicity_tolerance) << rpm << " rpm";
    EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6) << rpm << " rpm";
    const double ratio = (c.stage.sun.teeth + c.stage.ring.teeth) / static_cast<double>(c.stage.sun.teeth);
    const double eta = scalar(r, "load_torque") / (scalar(r, "input_torque") * ratio);
    EXPECT_GT(eta, 0.9) << rpm << " rpm";
    EXPECT_LT(eta, 1.0) << rpm << " rpm";
  }
}

TEST(Simulation, InputTorqueRippleShowsInSunSpeedAtItsOrder) {
  SimulationConfig c = fast_seed(60);
  const SimulationResult smooth = simulate(c);
  c.imperfections.torque_ripple_fraction = 0.05;
  c.imperfections.torque_ripple_order = 2;
  const SimulationResult rip = simulate(c);
  const auto& w = channel(rip, "sun/speed");
  EXPECT_GT(stddev(w), 10 * stddev(channel(smooth, "sun/speed")));
  const auto s = pw::signal::amplitude_spectrum(w, rip.time_step_s, pw::signal::Window::Hann);
  const auto peaks = pw::signal::dominant_peaks(s, 1, 1.0);
  const double f_ripple = 2 * 400.0 / 60;  // 2nd order of the sun speed [Hz]
  EXPECT_NEAR(peaks.at(0).frequency_Hz, f_ripple, 0.5 * s.frequency_Hz[1]);
}

namespace {
/// Largest |k(t + T_mesh) - k(t)| over the record, relative to the largest k: 0 for a mesh
/// stiffness that repeats every nominal mesh period.
double mesh_period_mismatch(const SimulationResult& r, const std::string& name) {
  const auto& k = channel(r, name);
  const auto spm = static_cast<std::size_t>(scalar(r, "steps_per_mesh_period"));
  double d = 0;
  for (std::size_t i = 0; i + spm < k.size(); ++i) d = std::max(d, std::fabs(k[i + spm] - k[i]));
  return d / *std::max_element(k.begin(), k.end());
}
} // namespace

TEST(Simulation, UnderNominalTimeMeshPhaseTheStiffnessRepeatsEveryMeshPeriodDespiteATorqueRipple) {
  // stiffness.mesh_phase = nominal_time: the pairs in contact follow the nominal rotation, so
  // the stiffness of a healthy mesh is a function of t with the mesh period (k(t) of
  // parametrically excited lumped models); the dynamics still see the ripple. Under rotation
  // (the default) the same ripple moves the pairs with the sun's angle: the order-2 speed
  // ripple of 5 % modulates the mesh phase. Bounds: the nominal roll's round-off (~1e-12 of a
  // roll of ~1 m after the warm-up's ~1e5 steps) through the engagement ramp, one step wide
  // (~1e-5 m), is ~1e-7 of k (measured 1.6e-7); 1e-5 leaves that a margin of 60. The
  // rotation's modulation (measured 0.40-0.42 of max k) is far above 1e-2.
  SimulationConfig c = fast_seed(60);
  c.imperfections.torque_ripple_fraction = 0.05;
  c.imperfections.torque_ripple_order = 2;
  const SimulationResult by_roll = simulate(c);
  c.stiffness.mesh_phase = MeshPhase::NominalTime;
  const SimulationResult by_time = simulate(c);
  for (const std::string mesh : {"sun_planet/0/stiffness", "planet_ring/1/stiffness"}) {
    EXPECT_LT(mesh_period_mismatch(by_time, mesh), 1e-5) << mesh;
    EXPECT_GT(mesh_period_mismatch(by_roll, mesh), 1e-2) << mesh;
  }
  EXPECT_GT(stddev(channel(by_time, "sun/speed")), 0.5 * stddev(channel(by_roll, "sun/speed")));
}

TEST(Simulation, SunRunoutModulatesSunMeshForceOncePerSunTurnRelativeToCarrier) {
  // Runout e rotates with the sun; against each planet it changes the mesh
  // deflection by e cos(.) at f_s - f_c. The three planets' errors sum to
  // zero, so the torsional sun cannot relieve them: force ~ k_mean e.
  SimulationConfig c = fast_seed(63);  // 3 sun turns relative to the carrier
  c.imperfections.sun_eccentricity_m = 1e-6;
  const SimulationResult r = simulate(c);
  const auto s = pw::signal::amplitude_spectrum(channel(r, "sun_planet/0/force"), r.time_step_s,
                                                pw::signal::Window::Hann);
  const double f_rel = 400.0 / 60 * (1 - 21.0 / 102.0);
  // amplitude at the bin closest to f_rel
  std::size_t k = static_cast<std::size_t>(std::lround(f_rel / s.frequency_Hz[1]));
  const double k_mean = scalar(r, "sun_planet/mean_stiffness");
  EXPECT_GT(s.amplitude[k], 0.3 * k_mean * 1e-6);
  EXPECT_LT(s.amplitude[k], 1.5 * k_mean * 1e-6);
}

TEST(Simulation, CrackedPlanetToothWeakensBothItsMeshesAndNoOtherPlanet) {
  // A planet tooth meets the sun on one flank and the ring on the other.
  SimulationConfig c = fast_seed(31);  // > one planet revolution relative to the carrier (30 mesh periods)
  const SimulationResult healthy = simulate(c);
  c.imperfections.teeth.push_back({Body::Planet, 0, 5, 0.5, 0.0});
  const SimulationResult cracked = simulate(c);
  auto min_of = [&](const SimulationResult& r, const std::string& ch) {
    const auto& v = channel(r, ch);
    return *std::min_element(v.begin(), v.end());
  };
  for (const char* mesh : {"sun_planet/0/stiffness", "planet_ring/0/stiffness"})
    EXPECT_LT(min_of(cracked, mesh), 0.8 * min_of(healthy, mesh)) << mesh;
  // Other planets: unchanged up to where the samples fall on the stiffness
  // waveform (the two runs record from different warm-up lengths): 1e-3.
  for (const char* mesh : {"sun_planet/1/stiffness", "planet_ring/2/stiffness"})
    EXPECT_NEAR(min_of(cracked, mesh), min_of(healthy, mesh), 1e-3 * min_of(healthy, mesh)) << mesh;
}

TEST(Simulation, CarrierRunoutUnequalizesLoadSharingLikePinErrors) {
  // Runout moves every pin by the same vector in the carrier frame: each
  // planet's meshes change by n . d, which sums to zero over 3 equally
  // spaced planets, so the shares change but still add up to N.
  SimulationConfig c = fast_seed();
  c.imperfections.carrier_eccentricity_m = 0.3e-6;
  const SimulationResult r = simulate(c);
  double sum = 0, spread = 0;
  for (int i = 0; i < 3; ++i) {
    const double l = scalar(r, "load_sharing_factor/" + std::to_string(i));
    sum += l;
    spread = std::max(spread, std::fabs(l - 1));
  }
  EXPECT_NEAR(sum, 3.0, 1e-9);
  EXPECT_GT(spread, 0.05);
}

/// Amplitudes of mesh harmonics 1..H of a channel recorded over whole mesh periods (the
/// simulator fits a whole number of steps in a mesh period, so these are exact DFT bins).
std::vector<double> mesh_harmonics(const SimulationResult& r, const std::string& name, int H) {
  const auto& x = channel(r, name);
  const double n = static_cast<double>(x.size());
  const double cycles = std::round((r.time_s.back() - r.time_s.front() + r.time_step_s) * scalar(r, "mesh_frequency"));
  std::vector<double> out;
  for (int h = 1; h <= H; ++h) {
    double re = 0, im = 0;
    for (std::size_t j = 0; j < x.size(); ++j) {
      const double ph = 2 * std::numbers::pi * h * cycles * static_cast<double>(j) / n;
      re += x[j] * std::cos(ph);
      im -= x[j] * std::sin(ph);
    }
    out.push_back(2 * std::hypot(re, im) / n);
  }
  return out;
}

TEST(Simulation, EngagementSmoothingMakesMeshHarmonicsNearResonanceConvergeWithTheTimeStep) {
  // Near the mesh resonance (19 500 rpm, 2 kW) the response amplifies any error in the
  // instant a tooth pair engages. Switching a pair on at the first step past its engagement
  // point delays the stiffness jump by up to one step, by an amount that depends on where
  // the grid falls: an O(dt) error, erratic in dt. Measured 2026-11-24 (`planetwear simulate
  // --speed-rpm 19500 --power-w 2000 --set solver.time_step_s=...`, harmonics 1-6 of the
  // sun-planet acceleration vs dt = 3.125e-7 s): largest error 4.4 % at dt = 2.5e-6 s and
  // 6.3 % at 2.8e-6 s (the automatic step) with sharp switching; 1.8 % and 2.6 % with the
  // pairs weighted by their share of the step in contact. Checked: smoothing at least
  // halves the error at the automatic step, and keeps it below 4 % at both steps (the
  // Newmark period error (omega dt)^2/12 alone is ~0.1 % at 5.4 kHz; the rest is the roll
  // lag and the c v jump, both O(dt)).
  SimulationConfig c;
  c.operating.input_speed_rpm = 19500;
  c.operating.input_power_W = 2000;
  c.solver.record_mesh_cycles = 12;
  const int H = 6;
  const std::string ch = "sun_planet/0/acceleration";
  auto worst = [&](const std::vector<double>& a, const std::vector<double>& ref) {
    double e = 0;
    for (int h = 0; h < H; ++h) e = std::max(e, std::fabs(a[h] / ref[h] - 1));
    return e;
  };
  c.solver.time_step_s = 3.125e-7;
  const auto ref = mesh_harmonics(simulate(c), ch, H);
  double smooth_auto = 0, sharp_auto = 0;
  for (double dt : {2.5e-6, 0.0}) {  // 0 = the automatic step (2.8e-6 s here)
    c.solver.time_step_s = dt;
    c.solver.engagement_smoothing = true;
    const double e_smooth = worst(mesh_harmonics(simulate(c), ch, H), ref);
    c.solver.engagement_smoothing = false;
    const double e_sharp = worst(mesh_harmonics(simulate(c), ch, H), ref);
    EXPECT_LT(e_smooth, 0.04) << "dt " << dt << ": smoothed " << e_smooth << ", sharp " << e_sharp;
    if (dt == 0) smooth_auto = e_smooth, sharp_auto = e_sharp;
  }
  EXPECT_LT(smooth_auto, 0.5 * sharp_auto) << smooth_auto << " vs " << sharp_auto;
}

TEST(Simulation, TheStepsMeshStiffnessCarriesTheEngagementRampThatTheStiffnessCurveDescribes) {
  // Two independent computations of the ramped combined stiffness: the dynamics weights each
  // pair per step (PlanetaryDynamics::update_mesh_geometry, the window widened by the ramp),
  // the stiffness layer sums the pairs of one mesh period (stiffness::combined_stiffness, the
  // 'sun_planet/combined' curve). Their mesh harmonics 1-12 must agree. Tolerance 1e-4 of the
  // first harmonic (measured 2026-12-02: at most 6e-6 of it): the simulated roll carries the
  // elastic deflection (micrometres against the seed's 5.9 mm base pitch: a phase jitter of
  // ~1e-4 of a period at most) and the curve is sampled at 400 points.
  SimulationConfig c = fast_seed(8);
  c.contact.friction_coefficient = 0;
  c.contact.engagement_ramp = 0.3;  // 0.3 p_b: far wider than the step's roll (~1/100 p_b)
  const SimulationResult r = simulate(c);
  const PreparedStage p = prepare(c);
  const auto curves = stiffness_curves(p);
  const auto it = std::find_if(curves.begin(), curves.end(), [](const Curve& k) { return k.name == "sun_planet/combined"; });
  ASSERT_NE(it, curves.end());
  const int n = static_cast<int>(it->y.size()) - 1;  // the last sample repeats the first
  const int H = 12;
  std::vector<double> from_curve;
  for (int h = 1; h <= H; ++h) {
    double re = 0, im = 0;
    for (int j = 0; j < n; ++j) {
      re += it->y[j] * std::cos(2 * std::numbers::pi * h * j / n);
      im -= it->y[j] * std::sin(2 * std::numbers::pi * h * j / n);
    }
    from_curve.push_back(2 * std::hypot(re, im) / n);
  }
  const auto from_step = mesh_harmonics(r, "sun_planet/0/stiffness", H);
  for (int h = 0; h < H; ++h)
    EXPECT_NEAR(from_step[h], from_curve[h], 1e-4 * from_curve[0]) << "harmonic " << h + 1;
  // The ramp did act: harmonic 10 of the sharp model is larger than the ramped one (sinc(3) = 0).
  SimulationConfig sharp = c;
  sharp.contact.engagement_ramp = 0;
  EXPECT_GT(mesh_harmonics(simulate(sharp), "sun_planet/0/stiffness", 10)[9], 3 * from_step[9]);
}

TEST(Simulation, AHousingMountAboveTheStepsNyquistFrequencyIsABadInputBeforeAnythingRuns) {
  // prepare() knows the time step: a mount at or above 1/(2 dt) names its key as an InputError,
  // so a wear run cannot fail half-way as a solver failure; below it the stage prepares.
  SimulationConfig c = fast_seed(2);
  const double nyquist = 0.5 / prepare(c).time_step_s;
  c.sensor.housing_mount_frequency_Hz = nyquist;
  EXPECT_THROW(prepare(c), pw::InputError);
  c.sensor.housing_mount_frequency_Hz = 0.5 * nyquist;
  EXPECT_NO_THROW(prepare(c));
}

TEST(Simulation, TheWidestEngagementRampIsTheOnePrepareAcceptsForTheGearsContactRatio) {
  // largest_engagement_ramp bounds the fits' box (engagement_ramp candidate): it must be a value
  // prepare() accepts, and no more than the room a mesh leaves below MeshState::kMaxPairs pairs.
  // The seed's contact ratios (1.6-1.9) leave more than the key's own limit of half a base pitch;
  // long-addendum 14.5-degree gears (48/60/168 teeth, h_a* 1.2 on sun and planet: contact ratios
  // 2.51 and 2.74, `planetwear stiffness`) leave less.
  SimulationConfig c = fast_seed(2);
  EXPECT_EQ(largest_engagement_ramp(c), ContactSettings::kMaxEngagementRamp);
  SimulationConfig deep = c;
  deep.stage.sun.teeth = 48;
  deep.stage.planet.teeth = 60;
  deep.stage.ring.teeth = 168;
  for (pw::geometry::GearSpec* g : {&deep.stage.sun, &deep.stage.planet, &deep.stage.ring}) {
    g->pressure_angle_rad = 14.5 * std::numbers::pi / 180;
    g->addendum_coef = g == &deep.stage.ring ? 1.0 : 1.2;
    g->dedendum_coef = 1.65;
  }
  const pw::geometry::StageGeometry geo = pw::geometry::make_stage_geometry(deep.stage);
  const double eps = std::max(geo.sun_planet.contact_ratio, geo.planet_ring.contact_ratio);
  ASSERT_GT(eps, MeshState::kMaxPairs - 1 - ContactSettings::kMaxEngagementRamp) << "not a deep enough mesh: " << eps;
  const double r = largest_engagement_ramp(deep);
  EXPECT_LT(r, ContactSettings::kMaxEngagementRamp);
  EXPECT_NEAR(r, MeshState::kMaxPairs - 1 - eps, 1e-8);
  deep.contact.engagement_ramp = r;
  EXPECT_NO_THROW(prepare(deep));
  deep.contact.engagement_ramp = r + 1e-6;
  EXPECT_THROW(prepare(deep), pw::InputError);
}

TEST(Simulation, SeparatingTeethWithBacklashNearResonanceIntegrateAndAgreeWithShorterSteps) {
  // At 19 000 rpm the mesh frequency (5.28 kHz) sits just below the 5.49 kHz mode: the
  // dynamic mesh force exceeds the static one and the teeth separate. With 20 um backlash the
  // flanks then lose contact and the viscous term c v drops to zero, a jump that a full
  // Newmark step of the automatic length cannot straddle (Newton found no root at
  // t = 2.87 ms and the run failed); the solver now halves that step.
  //  * The fallback must leave the step length alone afterwards: the samples stay dt apart.
  //  * The response must be the physics, not an artefact of the fallback. In this separating
  //    regime it is sensitive to the step: the mesh-acceleration RMS at dt/2, dt/4, dt/8 was
  //    365.7, 362.5, 364.4 m/s^2 and 380.7 at the automatic dt (measured 2026-11-24 with
  //    `planetwear simulate --speed-rpm 19000 --power-w 20000 --set solver.time_step_s=...`),
  //    so the automatic step must agree with a quarter step within 8 %.
  SimulationConfig c;
  c.operating.input_speed_rpm = 19000;
  c.operating.input_power_W = 20000;
  c.contact.backlash_sun_planet_m = 2e-5;
  c.contact.backlash_planet_ring_m = 2e-5;
  c.solver.record_mesh_cycles = 300;
  const SimulationResult full = simulate(c);
  c.solver.time_step_s = 0.25 * full.time_step_s;
  const SimulationResult fine = simulate(c);
  const auto& t = full.time_s;
  EXPECT_NEAR((t.back() - t.front()) / static_cast<double>(t.size() - 1), full.time_step_s, 1e-9 * full.time_step_s);
  for (const SimulationResult* r : {&full, &fine}) {
    const auto& f = channel(*r, "sun_planet/0/force");
    EXPECT_LE(*std::min_element(f.begin(), f.end()), 0.0) << "the sun-planet teeth must separate";
  }
  const double a_full = stddev(channel(full, "sun_planet/0/acceleration"));
  const double a_fine = stddev(channel(fine, "sun_planet/0/acceleration"));
  EXPECT_NEAR(a_full / a_fine, 1.0, 0.08) << a_full << " vs " << a_fine << " m/s^2";
}

// OutputSelection stores a subset of the very samples the full run stores:
// the dynamics does not depend on what is recorded, so the selected channels
// must equal the full run's every k-th sample exactly (same arithmetic).
TEST(SimulationOutput, SelectedDecimatedChannelsAreExactlyTheFullRunsEveryKthSample) {
  const SimulationConfig c = fast_seed(2);
  const SimulationResult full = simulate(c);
  constexpr int k = 7;
  const SimulationResult part = simulate(c, {}, OutputSelection{{"sun/speed", "planet_ring/1/", "housing/acceleration"}, k});
  EXPECT_DOUBLE_EQ(part.time_step_s, k * full.time_step_s);
  ASSERT_EQ(part.time_s.size(), (full.time_s.size() + k - 1) / k);
  for (const std::string name : {"sun/speed", "planet_ring/1/force", "planet_ring/1/acceleration"}) {
    const auto& a = channel(full, name);
    const auto& b = channel(part, name);
    for (std::size_t j = 0; j < b.size(); ++j) ASSERT_EQ(b[j], a[j * k]) << name << " sample " << j;
  }
  EXPECT_EQ(part.find("sun_planet/0/force"), nullptr);
  EXPECT_EQ(part.find("carrier/angle"), nullptr);  // needed for the housing sensor, then dropped
  ASSERT_NE(part.find("housing/acceleration"), nullptr);
  // The summary scalars use every step whatever is stored.
  EXPECT_EQ(scalar(part, "load_sharing_factor/0"), scalar(full, "load_sharing_factor/0"));
  EXPECT_EQ(scalar(part, "efficiency"), scalar(full, "efficiency"));
}

TEST(SimulationOutput, HousingChannelAloneEqualsTheFullRunsWithoutDecimation) {
  const SimulationConfig c = fast_seed(2);
  const SimulationResult full = simulate(c);
  const SimulationResult part = simulate(c, {}, OutputSelection{{"housing/acceleration"}, 1});
  ASSERT_EQ(part.channels.size(), 1u);
  EXPECT_EQ(channel(part, "housing/acceleration"), channel(full, "housing/acceleration"));
}

TEST(SimulationOutput, WithoutTheMeshLoadSummaryTheTimeHistoriesAreBitIdenticalAndItsScalarsAbsent) {
  const SimulationConfig c = fast_seed(2);
  const SimulationResult full = simulate(c);
  OutputSelection sel;
  sel.mesh_load_summary = false;
  const SimulationResult part = simulate(c, {}, sel);
  ASSERT_EQ(part.channels.size(), full.channels.size());
  for (std::size_t k = 0; k < full.channels.size(); ++k)
    EXPECT_EQ(part.channels[k].values, full.channels[k].values) << full.channels[k].name;
  for (const Scalar& s : part.scalars) {
    EXPECT_NE(s.name.rfind("mesh_load/", 0), 0u) << s.name;
    EXPECT_NE(s.name.rfind("load_sharing_factor/", 0), 0u) << s.name;
  }
  EXPECT_EQ(scalar(part, "efficiency"), scalar(full, "efficiency"));
  EXPECT_EQ(scalar(part, "time_steps"), scalar(full, "time_steps"));
}

TEST(SimulationOutput, UnknownChannelOrDecimationBelowOneIsAnInputErrorNamingTheKey) {
  const SimulationConfig c = fast_seed(1);
  try {
    (void)simulate(c, {}, OutputSelection{{"sun/sped"}, 1});
    FAIL() << "no error";
  } catch (const pw::InputError& e) {
    EXPECT_EQ(e.parameter(), "output.channels");
    EXPECT_NE(std::string(e.what()).find("sun/sped"), std::string::npos);
  }
  try {
    (void)simulate(c, {}, OutputSelection{{}, 0});
    FAIL() << "no error";
  } catch (const pw::InputError& e) {
    EXPECT_EQ(e.parameter(), "output.time_history_decimation");
  }
}

TEST(Simulation, WearWithoutTheWearLayerIsRefused) {
  // The wear loop lives in src/wear (above model): model::simulate runs it only as the phase
  // wear::simulate hands it, and refuses a wearing configuration without one rather than skip it.
  SimulationConfig c = fast_seed(1);
  c.wear.mesh_cycles = 100;
  EXPECT_THROW((void)simulate(c), std::logic_error);
}

// The automatic step with an accuracy band (solver.accuracy_band_Hz): 0 is today's rule
// bit for bit; a band above the highest mode changes nothing; below it, the band gets
// steps_per_mode_period steps per period and the highest mode max(8, spmp/4); the mesh
// period's limit still holds.
TEST(TimeStep, AnAccuracyBandBelowTheHighestModeResolvesTheBandAndGivesTheModeAQuarter) {
  SolverSettings sv;  // min_steps_per_mesh 64, steps_per_mode_period 32
  const double T_mesh = 1.0 / 111.0, f_max = 11000.0;
  const double today = std::min(T_mesh / 64, 1.0 / (f_max * 32));
  EXPECT_EQ(automatic_time_step(T_mesh, f_max, sv), today);
  sv.accuracy_band_Hz = 2 * f_max;
  EXPECT_EQ(automatic_time_step(T_mesh, f_max, sv), today);
  sv.accuracy_band_Hz = 1500.0;  // band term 1/(32 * 1500) = 20.8 us > 1/(8 * 11000) = 11.4 us
  EXPECT_DOUBLE_EQ(automatic_time_step(T_mesh, f_max, sv), 1.0 / (8 * f_max));
  sv.accuracy_band_Hz = 3000.0;  // 10.4 us < 11.4 us: the band binds
  EXPECT_DOUBLE_EQ(automatic_time_step(T_mesh, f_max, sv), 1.0 / (32 * 3000.0));
  sv.steps_per_mode_period = 48;  // the diagnosis's second discretization: every term 1.5x finer
  EXPECT_DOUBLE_EQ(automatic_time_step(T_mesh, f_max, sv), 1.0 / (48 * 3000.0));
  sv.accuracy_band_Hz = 100.0;
  EXPECT_DOUBLE_EQ(automatic_time_step(T_mesh, f_max, sv), 1.0 / (12 * f_max));
  EXPECT_DOUBLE_EQ(automatic_time_step(1.0 / 3000.0, f_max, sv), 1.0 / (3000.0 * 64));  // mesh period binds
}

namespace {
/// Harmonic h of the mesh frequency in the first sun-planet mesh force's Hann spectrum: the
/// largest amplitude within half a mesh frequency of h f_mesh [N].
double mesh_harmonic_of_force(const SimulationResult& r, int h) {
  const auto s = pw::signal::amplitude_spectrum(channel(r, "sun_planet/0/force"), r.time_step_s, pw::signal::Window::Hann);
  const double f_mesh = scalar(r, "mesh_frequency");
  double best = 0;
  for (std::size_t k = 0; k < s.frequency_Hz.size(); ++k)
    if (std::fabs(s.frequency_Hz[k] - h * f_mesh) < 0.5 * f_mesh) best = std::max(best, s.amplitude[k]);
  return best;
}
} // namespace

// With the band the simulation keeps its physics: seed stage at 400 rpm, band 0.3 x 10 kHz
// (what diagnose sets for a 10 kHz recording), the mesh-force spectrum's first three harmonics
// within 0.1 % of the default step's: the step is 3.7x longer (10.4 us against 2.8 us); measured
// 1e-4; the tolerance is a third of the default step's own period error for its stiffest mode
// (0.3 %), so a change of physics would fail it and the discretization does not.
TEST(TimeStep, TheBandStepKeepsTheMeshHarmonicsOfTheDefaultStep) {
  SimulationConfig c = fast_seed();
  c.solver.record_mesh_cycles = 32;
  const SimulationResult full = simulate(c);
  c.solver.accuracy_band_Hz = 3000.0;
  const SimulationResult band = simulate(c);
  EXPECT_GT(band.time_step_s, 1.5 * full.time_step_s);
  for (int h = 1; h <= 3; ++h)
    EXPECT_NEAR(mesh_harmonic_of_force(band, h) / mesh_harmonic_of_force(full, h), 1.0, 1e-3) << "harmonic " << h;
}

// A response that diverges is an error, never a result. Measured (2026-11-28): the seed stage at
// 100 rpm and 10 kW with a tooth-level feature at the band step of a 10 kHz recording (10.4 us)
// ran away after 0.62 s: the sun turned backwards at up to 7.4e5 rad/s, and simulate() returned
// that record (diagnose compared it as a candidate's model). At the model's own step (2.8 us) the
// same stage reaches its steady state. The error names the keys that shorten the step. The
// feature was a sun runout of 1 pm until session 64; since the stage settles without its
// features first (warm_up_from_static) that one no longer runs away, and a 5 % torque ripple
// does (measured: at t = 0.62 s).
TEST(Simulation, AResponseThatTurnsTheSunBackwardsIsASolverErrorNotARecord) {
  SimulationConfig c;
  c.operating.input_speed_rpm = 100;
  c.operating.input_power_W = 10000;
  c.imperfections.torque_ripple_fraction = 0.05;
  c.solver.record_mesh_cycles = 2;
  c.solver.accuracy_band_Hz = 3000.0;
  try {
    (void)simulate(c);
    ADD_FAILURE() << "the 10.4 us step no longer diverges here: choose a case that does";
  } catch (const pw::SolverError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stopped turning forward"), std::string::npos) << what;
    EXPECT_NE(what.find("solver.steps_per_mode_period"), std::string::npos) << what;
  }
  c.solver.accuracy_band_Hz = 0;
  const SimulationResult r = simulate(c);
  const std::vector<double>& ws = channel(r, "sun/speed");
  EXPECT_GT(*std::min_element(ws.begin(), ws.end()), 0.0);
  // The speed's mean over two mesh periods of a tooth-level steady state (warm-up tolerance 1e-6
  // on the window mean, the mesh vibration's own beat between periods on top): within 1 %.
  EXPECT_NEAR(mean(ws) / scalar(r, "sun_speed"), 1.0, 1e-2);
}

namespace {
/// indepsim3's four-planet rig setA4 (23/31/85, m 2.5 mm, 30 mm wide) at 500 rpm and 15 kW as the
/// diagnosis's calibration left it: a 2.5 kg m^2 motor behind an input shaft of 8268 N m/rad
/// damped by 0.011 N m s/rad, the band step of a 5 kHz recording (docs/diagnose-log.md, session 64).
SimulationConfig lightly_damped_input_shaft_rig() {
  SimulationConfig c;
  c.stage.planet_count = 4;
  for (auto* g : {&c.stage.sun, &c.stage.planet, &c.stage.ring}) {
    g->module_m = 0.0025;
    g->face_width_m = 0.03;
  }
  c.stage.sun.teeth = 23;
  c.stage.planet.teeth = 31;
  c.stage.ring.teeth = 85;
  c.contact.friction_coefficient = 0.06;
  c.contact.backlash_sun_planet_m = c.contact.backlash_planet_ring_m = 2e-5;
  c.contact.mesh_damping_ratio = 0.0789;
  c.stage.input_inertia_kgm2 = 2.514;
  c.rig.input_shaft_stiffness_N_m_rad = 8268;
  c.rig.input_shaft_damping_N_m_s_rad = 0.0106;
  c.operating.input_speed_rpm = 500;
  c.operating.input_power_W = 15000;
  c.solver.accuracy_band_Hz = 1500;
  c.solver.record_mesh_cycles = 60;
  return c;
}

/// Largest line of the sun speed's Hann spectrum more than 3 Hz from every mesh harmonic [rad/s].
double largest_line_off_the_mesh_harmonics(const SimulationResult& r) {
  const auto s = pw::signal::amplitude_spectrum(channel(r, "sun/speed"), r.time_step_s, pw::signal::Window::Hann);
  const double f_mesh = scalar(r, "mesh_frequency");
  double best = 0;
  for (std::size_t k = 1; k < s.frequency_Hz.size(); ++k) {
    const double h = std::round(s.frequency_Hz[k] / f_mesh);
    if (std::fabs(s.frequency_Hz[k] - h * f_mesh) > 3.0) best = std::max(best, s.amplitude[k]);
  }
  return best;
}
} // namespace

// A tooth-level feature of size zero (a tooth of stiffness factor 1) is the stage without it. On
// a rig with a lightly damped input shaft the warm-up of tooth-level features, corrected once per
// window of z mesh periods from the static start, stopped with a 318.6 Hz mode ringing at 0.107
// rad/s in the sun speed (2.7 times the mesh line; measured in the diagnosis's model of setA4,
// session 64), which made every tooth candidate's "absent" fit 280 times worse than the nuisance
// model. Settled without the features first, the largest line off the mesh harmonics is the
// healthy model's residual ring (4.8e-4 rad/s in this shorter record): tolerance a factor 3 of
// it, for the phase at which the two records catch that residual ring; the old warm-up left
// 9.9e-3, 20 times it (measured with session 63's simulation.cpp). The mesh force's harmonics
// agree to 1e-3.
TEST(Simulation, AToothModifierOfFactorOneIsTheStageWithoutItOnALightlyDampedShaft) {
  SimulationConfig c = lightly_damped_input_shaft_rig();
  const SimulationResult healthy = simulate(c);
  ToothModifier t;
  t.body = Body::Planet;
  t.planet = 1;
  t.stiffness_factor = 1.0;
  c.imperfections.teeth.push_back(t);
  const SimulationResult zero = simulate(c);
  const double ring_healthy = largest_line_off_the_mesh_harmonics(healthy);
  EXPECT_LE(largest_line_off_the_mesh_harmonics(zero), 3 * ring_healthy);
  // The mesh force's harmonics (the sun speed carries only multiples of N for this Zs).
  for (int h = 1; h <= 3; ++h)
    EXPECT_NEAR(mesh_harmonic_of_force(zero, h) / mesh_harmonic_of_force(healthy, h), 1.0, 1e-3) << "harmonic " << h;
}
