// Candidate library (src/diagnose/candidates): the ring-tooth places screened as
// phase variants, and the near-alias start mapping between planet pin errors and
// a carrier eccentricity. Both displace the planet centres in the carrier; a pin
// error along the carrier tangent
// e_t = (-sin psi, cos psi), the eccentricity by one vector (x, y) whose
// tangential part at planet i is -x sin psi_i + y cos psi_i.
#include "config/schema.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/kinematics.hpp"
#include "geometry/mesh.hpp"
#include "io/config_toml.hpp"
#include "model/simulation.hpp"
#include "model/validate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <regex>
#include <tuple>

namespace pw::diagnose {
namespace {

model::SimulationConfig stage(int planets) {
  model::SimulationConfig c;
  c.stage.planet_count = planets;
  return c;
}

TEST(Candidates, PinErrorStartReproducesTheEccentricitysTangentialPattern) {
  const auto base = stage(3);
  const Candidate* pin = find_candidate("pin_error");
  ASSERT_NE(pin, nullptr);
  const double ecc[2] = {3e-6, -1.5e-6};
  const auto p = pin->start_from("carrier_runout", ecc, base);
  ASSERT_EQ(p.size(), 2u);
  const auto psi = planet_angles_rad(base);
  auto t = [&](int i) { return -ecc[0] * std::sin(psi[i]) + ecc[1] * std::cos(psi[i]); };
  EXPECT_NEAR(p[0], t(1) - t(0), 1e-15);
  EXPECT_NEAR(p[1], t(2) - t(0), 1e-15);
  // No mapping from unrelated physics.
  EXPECT_TRUE(pin->start_from("friction", std::vector<double>{0.1}, base).empty());
}

TEST(Candidates, PinAndEccentricityStartsAreInverseForThreePlanets) {
  // Three planets: any pin pattern is a common rotation plus a first harmonic, so the
  // round trip pin -> eccentricity -> pin is exact.
  const auto base = stage(3);
  const Candidate* pin = find_candidate("pin_error");
  const Candidate* ecc = find_candidate("carrier_runout");
  ASSERT_NE(ecc, nullptr);
  const std::vector<double> p0 = {0.0, 5e-6};
  const auto e = ecc->start_from("pin_error", p0, base);
  ASSERT_EQ(e.size(), 2u);
  const auto p1 = pin->start_from("carrier_runout", e, base);
  ASSERT_EQ(p1.size(), 2u);
  EXPECT_NEAR(p1[0], p0[0], 1e-18);
  EXPECT_NEAR(p1[1], p0[1], 1e-18);
}

TEST(Candidates, FourPlanetPinPatternKeepsOnlyItsFirstHarmonic) {
  // Four planets: the pattern [0, a, 0, a] (second harmonic plus a common offset) has no
  // first harmonic, so its equivalent eccentricity is zero (least squares).
  const auto base = stage(4);
  const Candidate* ecc = find_candidate("carrier_runout");
  const auto e = ecc->start_from("pin_error", std::vector<double>{2e-6, 0.0, 2e-6}, base);
  ASSERT_EQ(e.size(), 2u);
  EXPECT_NEAR(e[0], 0.0, 1e-18);
  EXPECT_NEAR(e[1], 0.0, 1e-18);
}

TEST(Candidates, AToothWhosePositionIsNotIdentifiableIsNamedByNoNumberYetItsSetLineReproducesTheFit) {
  // Issue 19 point 5: amplitudes cannot tell which sun or planet tooth is damaged; the severity
  // is fitted on a stand-in tooth, which neither the label (the report's headline) nor the
  // `--set` line may present as a finding. The line still reproduces the fitted model.
  model::SimulationConfig base;
  const ToothMap map(base);
  const std::regex numbered_tooth("tooth [0-9]|tooth=");
  for (const char* name : {"sun_tooth_damage", "planet_tooth_damage"}) {
    const Candidate* c = find_candidate(name);
    ASSERT_NE(c, nullptr);
    for (const Variant& v : c->variants(LocatedEvidence{}, base, map)) {
      EXPECT_FALSE(v.tooth_identifiable);
      EXPECT_FALSE(std::regex_search(v.label, numbered_tooth)) << v.label;
      EXPECT_NE(v.label.find("position not identifiable"), std::string::npos) << v.label;
      model::SimulationConfig fitted = base;
      std::vector<std::string> overrides;
      const double x[1] = {0.6};
      c->apply(fitted, v, x, &overrides);
      ASSERT_EQ(overrides.size(), 1u);
      EXPECT_FALSE(std::regex_search(overrides[0], numbered_tooth)) << overrides[0];
      model::SimulationConfig reproduced = base;
      io::apply_overrides(reproduced, overrides);
      ASSERT_EQ(reproduced.imperfections.teeth.size(), 1u);
      EXPECT_EQ(reproduced.imperfections.teeth[0].tooth, fitted.imperfections.teeth[0].tooth);
      EXPECT_EQ(reproduced.imperfections.teeth[0].planet, fitted.imperfections.teeth[0].planet);
      EXPECT_EQ(reproduced.imperfections.teeth[0].stiffness_factor, 0.6);
    }
    // A phase variant fits better but does not locate the tooth (docs/diagnose-log.md, session
    // 11): its label names none; its --set line keeps the index that reproduces the fit.
    const Variant chosen = c->variants(LocatedEvidence{}, base, map).front();
    for (const Variant& v : c->phase_variants(chosen, LocatedEvidence{}, base, map)) {
      EXPECT_FALSE(v.tooth_identifiable);
      EXPECT_FALSE(std::regex_search(v.label, numbered_tooth)) << v.label;
      model::SimulationConfig fitted = base;
      std::vector<std::string> overrides;
      const double x[1] = {0.6};
      c->apply(fitted, v, x, &overrides);
      model::SimulationConfig reproduced = base;
      io::apply_overrides(reproduced, overrides);
      EXPECT_EQ(reproduced.imperfections.teeth.at(0).tooth, v.tooth) << overrides[0];
    }
  }
}

TEST(Candidates, RingPlacesCoverOnePlanetSpacingAtAQuarterOfTheSensorWindow) {
  // Seed stage: 3 equally spaced planets, Zr = 81 (a multiple of 3), so the housing sensor sees
  // the same stage after 27 teeth; sigma = 0.5 rad is 6.4 tooth pitches, so every tooth of one
  // spacing is a place (step floor(6.4 / 4) = 1): 26 besides the chosen one.
  model::SimulationConfig base;
  const ToothMap map(base);
  const int z = map.teeth(model::Body::Ring);
  ASSERT_EQ(z % base.stage.planet_count, 0);
  const Candidate* ring = find_candidate("ring_tooth_damage");
  ASSERT_NE(ring, nullptr);
  EXPECT_TRUE(ring->phase_trades_with_parameters());
  EXPECT_FALSE(find_candidate("sun_tooth_damage")->phase_trades_with_parameters());
  LocatedEvidence ev;
  ev.housing_sensor_angles_rad = {1.0};
  const Variant chosen = ring->variants(ev, base, map).front();
  auto places = [&](const model::SimulationConfig& c) {
    std::vector<int> t;
    for (const auto& v : ring->phase_variants(chosen, ev, c, map)) t.push_back(v.tooth);
    return t;
  };
  const auto all = places(base);
  const int span = z / base.stage.planet_count;
  ASSERT_EQ(static_cast<int>(all.size()), span - 1);
  for (std::size_t k = 0; k < all.size(); ++k) EXPECT_EQ(all[k], (chosen.tooth + 1 + static_cast<int>(k)) % z);
  // A wide window: places a quarter of it apart (floor(2 / 4 / (2 pi / 81)) = 6 teeth).
  model::SimulationConfig wide = base;
  wide.sensor.window_width_rad = 2.0;
  const int step = static_cast<int>(std::floor(2.0 / 4 / (2 * std::numbers::pi / z)));
  const auto coarse = places(wide);
  ASSERT_EQ(static_cast<int>(coarse.size()), (span - 1) / step);
  EXPECT_EQ(coarse.front(), (chosen.tooth + step) % z);
  // Unequally spaced planets: no symmetry, the places go all round.
  model::SimulationConfig uneven = base;
  uneven.stage.planet_angles_rad = {0.0, 2.0, 4.3};
  EXPECT_EQ(static_cast<int>(places(uneven).size()), z - 1);
  // Without a housing sensor the ring tooth's place changes no amplitude: none to screen.
  EXPECT_TRUE(ring->phase_variants(chosen, LocatedEvidence{}, base, map).empty());
}

namespace pw::diagnose {
namespace {

TEST(Candidates, EncoderBandwidthIsAbsentAtTheTopOfItsBoxAndEveryValueIsInTheKeysRange) {
  // An ideal encoder (bandwidth 0 in the configuration) is the top of the box, 1e4 mesh
  // frequencies (seed at 100 rpm: f_m = 21 * 81 / 102 * 100 / 60 = 27.79 Hz), where the filter is
  // the identity; the parameter saturates; the screen value is 2 f_m; a configured (calibrated)
  // bandwidth is both the start and 'absent'; applying writes the key and a --set override.
  const Candidate* c = find_candidate("encoder_bandwidth");
  ASSERT_NE(c, nullptr);
  model::SimulationConfig b;
  const double fm = 21.0 * 81.0 / 102.0 * 100.0 / 60.0;
  const auto p = c->parameters(b);
  ASSERT_EQ(p.size(), 1u);
  EXPECT_TRUE(p[0].saturates);
  EXPECT_TRUE(p[0].log_scale);
  EXPECT_NEAR(p[0].null_value, 1e4 * fm, 1e-9 * fm);
  EXPECT_NEAR(p[0].upper, p[0].null_value, 1e-9 * fm);
  EXPECT_NEAR(p[0].lower, 0.25 * fm, 1e-9 * fm);
  EXPECT_NEAR(p[0].screen_value, 2 * fm, 1e-9 * fm);
  b.sensor.encoder_bandwidth_Hz = 300;
  const auto q = c->parameters(b);
  EXPECT_EQ(q[0].null_value, 300);
  EXPECT_EQ(q[0].initial, 300);
  std::vector<std::string> o;
  const double x[] = {123.5};
  c->apply(b, Variant{}, x, &o);
  EXPECT_EQ(b.sensor.encoder_bandwidth_Hz, 123.5);
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0], "sensor.encoder_bandwidth_Hz=123.5");
  EXPECT_NO_THROW(model::validate(b));
}

TEST(Candidates, EncoderBandwidthIsObservableOnlyInSpeedChannels) {
  // A calibration on housing accelerometers alone cannot see the encoders: leaving the rig
  // element out there keeps a parameter the data cannot inform out of the fit.
  const Candidate* c = find_candidate("encoder_bandwidth");
  ASSERT_NE(c, nullptr);
  Recording r;
  r.channels.push_back({"a_h", Quantity::HousingAcceleration, "m/s^2", 0, 0.0, {}});
  r.channels.push_back({"a_sp0", Quantity::MeshAccelerationSunPlanet, "m/s^2", 0, 0.0, {}});
  EXPECT_FALSE(c->observable_in(r));
  EXPECT_TRUE(find_candidate("friction")->observable_in(r));
  r.channels.push_back({"w_carrier", Quantity::CarrierSpeed, "rad/s", 0, 0.0, {}});
  EXPECT_TRUE(c->observable_in(r));
}

TEST(Candidates, AMachineInertiaBehindAnIdealSpeedControlDoesNotActAndIsNoCandidate) {
  // Behind a flexible shaft whose far end an ideal speed control holds, the machine's inertia is
  // not in the model (same mass matrix for any value): Candidate::acts_on says so, and the
  // screening leaves the candidate out. Under torque control behind the same shaft, or with a
  // rigid coupling, it acts.
  for (const bool input : {true, false}) {
    SCOPED_TRACE(input ? "motor_inertia" : "load_inertia");
    const Candidate* c = find_candidate(input ? "motor_inertia" : "load_inertia");
    ASSERT_NE(c, nullptr);
    model::SimulationConfig b;
    double& inertia = input ? b.stage.input_inertia_kgm2 : b.stage.output_inertia_kgm2;
    EXPECT_TRUE(c->acts_on(b));  // rigid coupling
    inertia = 0.1;
    (input ? b.rig.input_shaft_stiffness_N_m_rad : b.rig.output_shaft_stiffness_N_m_rad) = 1e5;
    EXPECT_TRUE(c->acts_on(b));  // torque-controlled machine behind the shaft
    if (input)
      b.rig.input_control = model::InputControl::Speed;
    else
      b.rig.load_control = model::LoadControl::Speed;
    ASSERT_NO_THROW(model::validate(b));
    EXPECT_FALSE(c->acts_on(b));
    const Eigen::MatrixXd M1 = model::prepare(b).dynamics->mass();
    inertia = 10.0;
    EXPECT_EQ(model::prepare(b).dynamics->mass(), M1) << "the held machine's inertia changed the model";
  }
}

TEST(Candidates, RigInertiasAreScaledByTheBodysOwnInertiaAndAbsentAtTheBottomOfTheirBox) {
  // 'Absent' = 1e-4 of the body's own inertia (the sun's disc; the carrier with its planets at
  // the carrier radius, as model::mass_properties derives them), the top 1e4 of it, the screen
  // value the body's own inertia (doubling it); saturating; a configured inertia is both the
  // start and 'absent'; applying writes the key and a --set override the validator accepts.
  model::SimulationConfig b;
  const geometry::StageGeometry g = geometry::make_stage_geometry(b.stage);
  const model::MassProperties m = model::mass_properties(b, g);
  const double sun = m.sun_inertia_kgm2;
  const double carrier = m.carrier_inertia_kgm2 + 3 * m.planet_mass_kg * g.carrier_radius_m * g.carrier_radius_m;
  for (const auto& [name, own, key] : {std::tuple{"motor_inertia", sun, "stage.input_inertia_kgm2"},
                                       std::tuple{"load_inertia", carrier, "stage.output_inertia_kgm2"}}) {
    SCOPED_TRACE(name);
    const Candidate* c = find_candidate(name);
    ASSERT_NE(c, nullptr);
    const auto p = c->parameters(b);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0].name, key);
    EXPECT_TRUE(p[0].saturates && p[0].log_scale);
    EXPECT_NEAR(p[0].null_value, 1e-4 * own, 1e-12 * own);
    EXPECT_NEAR(p[0].lower, p[0].null_value, 1e-12 * own);
    EXPECT_NEAR(p[0].upper, 1e4 * own, 1e-6 * own);
    EXPECT_NEAR(p[0].screen_value, own, 1e-12 * own);
    model::SimulationConfig applied = b;
    std::vector<std::string> o;
    const double x[] = {0.25};
    c->apply(applied, Variant{}, x, &o);
    ASSERT_EQ(o.size(), 1u);
    EXPECT_EQ(o[0], std::string(key) + "=0.25");
    EXPECT_NO_THROW(model::validate(applied));
    const auto q = c->parameters(applied);
    EXPECT_EQ(q[0].null_value, 0.25);
    EXPECT_EQ(q[0].initial, 0.25);
  }
  EXPECT_GT(sun, 1e-4);   // seed sun: 21 teeth, m 3 mm, b 50 mm: ~6e-4 kg m^2
  EXPECT_LT(sun, 1e-3);
  EXPECT_GT(carrier, sun);
}

TEST(Candidates, ATorqueRipplesSizeIsConditionalOnTheInputSideWhereTheMotorsInertiaActsUnstated) {
  // The speed lines fix r / |Z_in(w)|: without the motor's inertia in the configuration the fitted
  // fraction is the size for the configured input only (ParameterSpec::size_conditional_on). A
  // stated inertia, or a motor whose far end an ideal speed control holds, makes it the size.
  const Candidate* c = find_candidate("torque_ripple");
  ASSERT_NE(c, nullptr);
  model::SimulationConfig b;
  const std::string why = c->parameters(b)[0].size_conditional_on;
  EXPECT_NE(why.find("constant power"), std::string::npos) << why;
  EXPECT_NE(why.find("stage.input_inertia_kgm2"), std::string::npos) << why;
  model::SimulationConfig torque = b;
  torque.rig.input_control = model::InputControl::Torque;
  EXPECT_EQ(c->parameters(torque)[0].size_conditional_on.find("constant power"), std::string::npos);
  EXPECT_FALSE(c->parameters(torque)[0].size_conditional_on.empty());
  model::SimulationConfig motor = b;
  motor.stage.input_inertia_kgm2 = 0.12;
  EXPECT_TRUE(c->parameters(motor)[0].size_conditional_on.empty());
  model::SimulationConfig held = b;
  held.rig.input_control = model::InputControl::Speed;
  held.rig.input_shaft_stiffness_N_m_rad = 2e5;
  EXPECT_TRUE(c->parameters(held)[0].size_conditional_on.empty());
  // Only the fraction: the load inertia beside it is a transfer parameter, never the size.
  EXPECT_TRUE(c->parameters(b)[1].size_conditional_on.empty());
}

TEST(Candidates, ATorqueRippleFitsTheLoadMachinesInertiaAsATransferOnlyWhereNoneIsConfiguredOrHeld) {
  // The ripple's split between the speeds and the mesh forces is the load machine's inertia's
  // (test_rig.cpp, Rig.UnderConstantPower...): fitted beside the fraction on load_inertia's box,
  // a transfer parameter (not tested against 'absent', not the size). A configured inertia, or a
  // carrier held by a speed-controlled machine behind a shaft, leaves the fraction alone.
  const Candidate* c = find_candidate("torque_ripple");
  ASSERT_NE(c, nullptr);
  const Candidate* load = find_candidate("load_inertia");
  ASSERT_NE(load, nullptr);
  model::SimulationConfig b;
  const auto p = c->parameters(b);
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].name, "torque_ripple_fraction");
  EXPECT_FALSE(p[0].transfer);
  EXPECT_EQ(p[1].name, "stage.output_inertia_kgm2");
  EXPECT_TRUE(p[1].transfer && p[1].log_scale);
  const auto l = load->parameters(b);
  EXPECT_EQ(p[1].lower, l[0].lower);
  EXPECT_EQ(p[1].upper, l[0].upper);
  EXPECT_EQ(p[1].null_value, l[0].null_value);
  model::SimulationConfig applied = b;
  std::vector<std::string> o;
  const double x[] = {0.05, 0.8};
  Variant v;
  v.order = 2;
  c->apply(applied, v, x, &o);
  EXPECT_EQ(applied.stage.output_inertia_kgm2, 0.8);
  EXPECT_EQ(applied.imperfections.torque_ripple_fraction, 0.05);
  EXPECT_EQ(applied.imperfections.torque_ripple_order, 2.0);
  EXPECT_NO_THROW(model::validate(applied));
  EXPECT_EQ(o.back(), "stage.output_inertia_kgm2=0.8");
  model::SimulationConfig configured = b;
  configured.stage.output_inertia_kgm2 = 0.3;
  EXPECT_EQ(c->parameters(configured).size(), 1u);
  model::SimulationConfig held = b;
  held.stage.output_inertia_kgm2 = 0.0;
  held.rig.load_control = model::LoadControl::Speed;
  held.rig.output_shaft_stiffness_N_m_rad = 1e5;
  EXPECT_EQ(c->parameters(held).size(), 1u);
}

TEST(Candidates, ATorqueRippleBehindAShaftFitsTheMotorWhereTheConfigurationHoldsOnlyTheSpeedSourceStandIn) {
  // A calibration's input shaft writes a speed-source stand-in for the motor (1e4 times the sun's
  // inertia) when the gear set states none: right at the mesh frequencies, far too heavy at the
  // ripple's k f_s. The ripple then fits the motor's inertia as a transfer parameter, on the
  // load's box, its 'absent' and start the stand-in (the model as configured), and the fraction
  // is the size for the fitted inertia. A stated motor, or a motor held by an ideal speed control,
  // is left alone.
  const Candidate* c = find_candidate("torque_ripple");
  const Candidate* shaft = find_candidate("input_shaft");
  ASSERT_NE(c, nullptr);
  ASSERT_NE(shaft, nullptr);
  model::SimulationConfig b;
  b.operating.input_speed_rpm = 400;
  model::SimulationConfig with_shaft = b;
  const auto ks = shaft->parameters(b);
  const double xs[] = {ks[0].screen_value, ks[1].screen_value};
  shaft->apply(with_shaft, Variant{}, xs, nullptr);
  ASSERT_GT(with_shaft.stage.input_inertia_kgm2, 0.0);  // the stand-in the shaft wrote
  const auto p = c->parameters(with_shaft);
  ASSERT_EQ(p.size(), 3u);  // fraction, load, motor
  EXPECT_EQ(p[1].name, "stage.output_inertia_kgm2");
  EXPECT_EQ(p[2].name, "stage.input_inertia_kgm2");
  EXPECT_TRUE(p[2].transfer && p[2].log_scale);
  EXPECT_EQ(p[2].null_value, with_shaft.stage.input_inertia_kgm2);
  EXPECT_EQ(p[2].initial, with_shaft.stage.input_inertia_kgm2);
  EXPECT_EQ(p[2].upper, with_shaft.stage.input_inertia_kgm2);
  EXPECT_NEAR(p[2].lower, 1e-8 * with_shaft.stage.input_inertia_kgm2, 1e-12 * with_shaft.stage.input_inertia_kgm2);
  EXPECT_NE(p[0].size_conditional_on.find("fitted motor inertia"), std::string::npos) << p[0].size_conditional_on;
  model::SimulationConfig applied = with_shaft;
  std::vector<std::string> o;
  const double x[] = {0.05, 0.8, 0.12};
  Variant v;
  v.order = 2;
  c->apply(applied, v, x, &o);
  EXPECT_EQ(applied.stage.output_inertia_kgm2, 0.8);
  EXPECT_EQ(applied.stage.input_inertia_kgm2, 0.12);
  EXPECT_EQ(o.back(), "stage.input_inertia_kgm2=0.12");
  EXPECT_NO_THROW(model::validate(applied));
  // The stand-in read back from its printed value (a calibration file) is still the stand-in.
  model::SimulationConfig read_back = with_shaft;
  read_back.stage.input_inertia_kgm2 = std::stod(format_value(with_shaft.stage.input_inertia_kgm2));
  EXPECT_EQ(c->parameters(read_back).size(), 3u);
  // A motor the configuration states (lighter than the stand-in) is the rig's: not fitted.
  model::SimulationConfig stated = with_shaft;
  stated.stage.input_inertia_kgm2 = 0.12;
  EXPECT_EQ(c->parameters(stated).size(), 2u);
  EXPECT_TRUE(c->parameters(stated)[0].size_conditional_on.empty());
  // The configuration apply() sees carries the nuisance values: an output shaft among them writes
  // the load's stand-in where the base had no load machine, and the one extra parameter of such
  // a base is the load's, not the motor's.
  const Candidate* out_shaft = find_candidate("output_shaft");
  ASSERT_NE(out_shaft, nullptr);
  model::SimulationConfig plain_base = b;  // no machines: fraction and load
  ASSERT_EQ(c->parameters(plain_base).size(), 2u);
  model::SimulationConfig both = plain_base;
  const auto os = out_shaft->parameters(b);
  const double xo[] = {os[0].screen_value, os[1].screen_value};
  out_shaft->apply(both, Variant{}, xo, nullptr);
  shaft->apply(both, Variant{}, xs, nullptr);
  const double stand_in_in = both.stage.input_inertia_kgm2;
  const double x2[] = {0.05, 0.7};
  c->apply(both, v, x2, nullptr);
  EXPECT_EQ(both.stage.output_inertia_kgm2, 0.7);
  EXPECT_EQ(both.stage.input_inertia_kgm2, stand_in_in);
  // Behind a shaft whose far end an ideal speed control holds, the motor's inertia does not act.
  model::SimulationConfig held = with_shaft;
  held.rig.input_control = model::InputControl::Speed;
  EXPECT_EQ(c->parameters(held).size(), 2u);
}

TEST(Candidates, AnEngagementRampsBoxEndsWhereTheSimulationWouldRefuseTheRamp) {
  // Half a base pitch, or what the gears' contact ratio leaves below the model's most pairs in a
  // mesh (model::largest_engagement_ramp): a fit that reached a wider ramp would stop on an
  // InputError, which fits do not catch as they catch a solver failure. Its screening value
  // stays inside the box and apart from 'absent'.
  const Candidate* c = find_candidate("engagement_ramp");
  ASSERT_NE(c, nullptr);
  model::SimulationConfig b;
  EXPECT_EQ(c->parameters(b)[0].upper, model::ContactSettings::kMaxEngagementRamp);
  model::SimulationConfig deep = b;  // contact ratios 2.51 and 2.74 (test_simulation.cpp)
  deep.stage.sun.teeth = 48;
  deep.stage.planet.teeth = 60;
  deep.stage.ring.teeth = 168;
  for (geometry::GearSpec* g : {&deep.stage.sun, &deep.stage.planet, &deep.stage.ring}) {
    g->pressure_angle_rad = 14.5 * std::numbers::pi / 180;
    g->addendum_coef = g == &deep.stage.ring ? 1.0 : 1.2;
    g->dedendum_coef = 1.65;
  }
  const ParameterSpec p = c->parameters(deep)[0];
  EXPECT_EQ(p.upper, model::largest_engagement_ramp(deep));
  EXPECT_LT(p.upper, 0.3);
  EXPECT_GT(p.screen_value, p.null_value);
  EXPECT_LE(p.screen_value, p.upper);
  model::SimulationConfig widest = deep;
  const double x[] = {p.upper};
  c->apply(widest, Variant{}, x, nullptr);
  EXPECT_NO_THROW(model::prepare(widest));
}

TEST(Candidates, RigShaftsAreBoundedByTheBodysModeOnThemAndPutASpeedSourceBehindThem) {
  // Stiffness k over J_b (2 pi f)^2 for f from f_m / 4 (the bottom, its null) to 30 f_m,
  // screened at f_m, scanned at the nuisance start; damping c over 2 zeta sqrt(k J_b) from 5 %
  // at the softest to 100 % at the stiffest, screened at 5 % of the screening stiffness; J_b the
  // body's own inertia (sun disc; carrier with its planets). Without a configured machine,
  // applying writes a speed source (1e4 J_b) with the shaft; with one, only the shaft. The
  // result is a configuration the validator accepts (a flexible shaft needs a machine inertia).
  model::SimulationConfig b;
  b.operating.input_speed_rpm = 400;
  const geometry::StageGeometry g = geometry::make_stage_geometry(b.stage);
  const model::MassProperties m = model::mass_properties(b, g);
  const double sun = m.sun_inertia_kgm2;
  const double carrier = m.carrier_inertia_kgm2 + 3 * m.planet_mass_kg * g.carrier_radius_m * g.carrier_radius_m;
  const double wm = 2 * std::numbers::pi * model::mesh_frequency_Hz(b.stage, 400.0);
  for (const auto& [name, J, prefix, machine] :
       {std::tuple{"input_shaft", sun, "rig.input_shaft_", "stage.input_inertia_kgm2"},
        std::tuple{"output_shaft", carrier, "rig.output_shaft_", "stage.output_inertia_kgm2"}}) {
    SCOPED_TRACE(name);
    const Candidate* c = find_candidate(name);
    ASSERT_NE(c, nullptr);
    const auto p = c->parameters(b);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p[0].name, std::string(prefix) + "stiffness_N_m_rad");
    EXPECT_EQ(p[1].name, std::string(prefix) + "damping_N_m_s_rad");
    EXPECT_TRUE(p[0].log_scale && p[1].log_scale && p[0].scan_at_start && !p[1].scan_at_start);
    // The scan steps by the half-power band of a 5 % mode in k ~ f^2, the damping keeping that ratio.
    EXPECT_DOUBLE_EQ(p[0].scan_step_ratio, 1.1 * 1.1);
    EXPECT_EQ(p[1].scan_follows_previous_power, 0.5);
    EXPECT_TRUE(c->calibration_only());  // its box has no value without effect: never a finding
    EXPECT_NEAR(p[0].lower / (J * std::pow(0.25 * wm, 2)), 1.0, 1e-12);
    EXPECT_NEAR(p[0].upper / (J * std::pow(30 * wm, 2)), 1.0, 1e-12);
    EXPECT_NEAR(p[0].screen_value / (J * wm * wm), 1.0, 1e-12);
    EXPECT_EQ(p[0].null_value, p[0].lower);
    EXPECT_NEAR(p[1].lower / (2 * 0.05 * std::sqrt(p[0].lower * J)), 1.0, 1e-12);
    EXPECT_NEAR(p[1].upper / (2 * 1.0 * std::sqrt(p[0].upper * J)), 1.0, 1e-12);
    EXPECT_NEAR(p[1].screen_value / (2 * 0.05 * std::sqrt(p[0].screen_value * J)), 1.0, 1e-12);
    EXPECT_EQ(p[1].null_value, p[1].lower);
    model::SimulationConfig applied = b;
    std::vector<std::string> o;
    const double x[] = {2.5e5, 12.0};
    c->apply(applied, Variant{}, x, &o);
    ASSERT_EQ(o.size(), 3u);
    EXPECT_EQ(o[0].substr(0, o[0].find('=')), machine);
    EXPECT_NEAR(std::stod(o[0].substr(o[0].find('=') + 1)) / (1e4 * J), 1.0, 1e-12);
    EXPECT_EQ(o[1], std::string(prefix) + "stiffness_N_m_rad=250000");
    EXPECT_EQ(o[2], std::string(prefix) + "damping_N_m_s_rad=12");
    EXPECT_NO_THROW(model::validate(applied));
    // Configured now: the shaft is both the start and 'absent'; the machine is not rewritten.
    const auto q = c->parameters(applied);
    EXPECT_EQ(q[0].null_value, 2.5e5);
    EXPECT_EQ(q[0].initial, 2.5e5);
    EXPECT_FALSE(q[0].scan_at_start);  // a configured shaft's basin is the one it names: no scan
    EXPECT_EQ(q[1].null_value, 12.0);
    std::vector<std::string> again;
    c->apply(applied, Variant{}, x, &again);
    EXPECT_EQ(again.size(), 2u);
  }
}

TEST(Candidates, MeshStiffnessHarmonicsIsACalibrationElementOverBothFamiliesThatDiagnosesHoldFixed) {
  const Candidate* c = find_candidate("mesh_stiffness_harmonics");
  ASSERT_NE(c, nullptr);
  EXPECT_TRUE(c->calibration_only());        // a property of the healthy gears: never a finding
  EXPECT_TRUE(c->held_after_calibration());  // kept at its calibrated value by diagnose
  model::SimulationConfig base = stage(3);
  base.stiffness.planet_ring_harmonics.sin[2] = 0.3;  // a calibrated value beyond the default box
  const auto specs = c->parameters(base);
  ASSERT_EQ(specs.size(), 12u);  // 2 families x 3 harmonics x (cos, sin)
  std::vector<double> x;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const ParameterSpec& p = specs[i];
    SCOPED_TRACE(p.name);
    ASSERT_NE(config::find_number(base, p.name), nullptr);
    EXPECT_EQ(p.null_value, *config::find_number(base, p.name));  // absent = as configured
    EXPECT_LE(p.lower, p.null_value);
    EXPECT_GE(p.upper, p.null_value);
    EXPECT_GE(p.lower, -0.5);  // inside the key's range [-0.5, 0.5]
    EXPECT_LE(p.upper, 0.5);
    x.push_back(0.01 * static_cast<double>(i + 1));
  }
  EXPECT_EQ(specs.back().name, "stiffness.planet_ring_h3_sin");
  EXPECT_EQ(specs.back().upper, 0.3);  // the box reaches the configured value
  model::SimulationConfig applied = base;
  c->apply(applied, Variant{}, x, nullptr);
  EXPECT_EQ(applied.stiffness.sun_planet_harmonics.cos[0], 0.01);
  EXPECT_EQ(applied.stiffness.sun_planet_harmonics.sin[0], 0.02);
  EXPECT_EQ(applied.stiffness.sun_planet_harmonics.sin[2], 0.06);
  EXPECT_EQ(applied.stiffness.planet_ring_harmonics.cos[0], 0.07);
  EXPECT_EQ(applied.stiffness.planet_ring_harmonics.sin[2], 0.12);
}

TEST(Candidates, DampingScreenStepStaysInsideTheKeysRangeAtItsTop) {
  // contact.mesh_damping_ratio <= 1 (model/validate.cpp): at 1 the screening secant points down.
  const Candidate* c = find_candidate("damping_level");
  ASSERT_NE(c, nullptr);
  model::SimulationConfig b;
  b.contact.mesh_damping_ratio = 1.0;
  const auto p = c->parameters(b);
  EXPECT_LE(p[0].screen_value, 1.0);
  EXPECT_LE(p[0].upper, 1.0);
  EXPECT_NE(p[0].screen_value, p[0].null_value);
}

// Every candidate of the library writes its parameters and its `--set` lines from
// one key name (set_parameter over the configuration schema): reading the lines
// back through the configuration reader gives the configuration apply() made,
// key for key: exactly, apart from derived values (a runout's magnitude and phase
// from its x, y), which the lines hold to format_value's 9 significant digits.
TEST(Candidates, EveryCandidatesSetLinesReproduceTheConfigurationItsApplyWrites) {
  model::SimulationConfig base = stage(3);
  const ToothMap map(base);
  for (const auto& cand : candidate_library()) {
    SCOPED_TRACE(cand->name());
    const auto specs = cand->parameters(base);
    ASSERT_FALSE(specs.empty());
    std::vector<double> x;
    for (const auto& p : specs) {
      const double v = p.lower + 0.375 * (p.upper - p.lower);
      x.push_back(std::stod(format_value(v)));  // a value the --set line holds exactly
    }
    const auto variants = cand->variants(LocatedEvidence{}, base, map);
    ASSERT_FALSE(variants.empty());
    model::SimulationConfig applied = base;
    std::vector<std::string> overrides;
    cand->apply(applied, variants.front(), x, &overrides);
    EXPECT_FALSE(overrides.empty());
    model::SimulationConfig reproduced = base;
    for (const auto& o : overrides) {
      const auto eq = o.find('=');
      io::apply_override(reproduced, o.substr(0, eq), o.substr(eq + 1));
    }
    for (const auto& key : io::config_keys()) {
      double* got = config::find_number(reproduced, key.path);
      double* want = config::find_number(applied, key.path);
      if (!got) continue;
      EXPECT_NEAR(*got, *want, 5e-9 * std::abs(*want)) << key.path;  // half a unit of the 9th digit
      *got = *want;
    }
    EXPECT_EQ(io::to_toml(reproduced), io::to_toml(applied));  // every other key exactly
  }
}

} // namespace
} // namespace pw::diagnose

TEST(Candidates, BearingDampingActsOnlyOnTheLateralTorsionalModelAndIsAbsentAtTheConfiguredValue) {
  const Candidate* c = find_candidate("bearing_damping");
  ASSERT_NE(c, nullptr);
  model::SimulationConfig b = stage(3);
  EXPECT_FALSE(c->acts_on(b)) << "the torsional model has no bearings: the default diagnosis must not screen it";
  b.solver.level = model::ModelLevel::LateralTorsional;
  EXPECT_TRUE(c->acts_on(b));
  EXPECT_TRUE(c->rig_design());
  for (double configured : {0.0, 0.08}) {
    b.bearings.damping_ratio = configured;
    const std::vector<ParameterSpec> p = c->parameters(b);
    ASSERT_EQ(p.size(), 1u);
    EXPECT_EQ(p[0].null_value, configured) << "'absent' is the configured damping";
    EXPECT_GE(p[0].lower, 0.0);
    EXPECT_LE(p[0].upper, 1.0) << "inside the key's documented range [0, 1]";
    EXPECT_GT(p[0].screen_value, configured) << "the screening step moves away from 'absent'";
    EXPECT_GE(p[0].initial, p[0].lower);
    EXPECT_LE(p[0].initial, p[0].upper);
  }
  std::vector<std::string> o;
  const double x[] = {0.04};
  c->apply(b, Variant{}, x, &o);
  EXPECT_EQ(b.bearings.damping_ratio, 0.04);
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0], "bearings.damping_ratio=0.04");
}

TEST(Candidates, OnlyTheMeshLevelCandidatesActOnTheMeshHarmonicsAlone) {
  // Verdict condition (e) treats two such candidates as aliases under a budget: the level
  // candidates are, every fault with a rotation family of its own (teeth, runouts, pin errors,
  // ripple) is not, nor the sensor path (a carrier-family effect).
  for (const char* name : {"friction", "worn_profile", "damping_level", "stiffness_level", "backlash"}) {
    const Candidate* c = find_candidate(name);
    ASSERT_NE(c, nullptr) << name;
    EXPECT_TRUE(acts_on_mesh_harmonics_only(*c)) << name;
  }
  for (const char* name : {"sun_tooth_damage", "planet_tooth_damage", "ring_tooth_damage", "sun_runout",
                           "carrier_runout", "pin_error", "torque_ripple", "sensor_transfer_path"}) {
    const Candidate* c = find_candidate(name);
    ASSERT_NE(c, nullptr) << name;
    EXPECT_FALSE(acts_on_mesh_harmonics_only(*c)) << name;
  }
}

} // namespace
} // namespace pw::diagnose
