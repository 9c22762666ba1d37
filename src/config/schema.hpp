// The configuration schema: every key of model::SimulationConfig once, in
// file order, with its section, name, the field it names and its doc string
// (unit in brackets). Everything that enumerates keys is a visitor run over
// it, so a key is added in one place:
//  * io/config_toml.cpp - TOML reading (type checks, unknown keys), writing,
//    one-key overrides (--set) and the key listing (planetwear keys);
//  * config::find_number below - a number by its key path, which the
//    diagnosis's candidates write their parameters through;
//  * diagnose::builtin_config_key - the simulation cache key.
// Each number states its range here (config/range.hpp); model::validate checks them, and
// by hand only the rules that involve other keys.
//
// A visitor V provides
//   void section(std::string_view path);
//   template <class T> void field(std::string_view key, T& value, std::string_view doc, const Range& range);
//   void angle(std::string_view key_rad, std::string_view key_deg, double& value_rad, std::string_view doc,
//              const Range& range);
//   void teeth(std::string_view key, std::vector<model::ToothModifier>& value, std::string_view doc);
// (const references when it only reads), with T one of bool, int, double,
// std::vector<double> and the enumerations of config/stage.hpp.
#pragma once

#include "config/range.hpp"
#include "config/stage.hpp"

#include <array>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace pw::config {

/// kappa = K/H: mild-wear steel is 1e-18..1e-14 m^2/N; 1e-10 and above is a unit mistake
/// (mm^2/N typed as m^2/N is a factor 1e6 too large) [m^2/N], exclusive.
inline constexpr double kMaxWearCoefficient_m2_N = 1e-10;
/// The housing path's largest gain [m/s^2 per N]: an effective mass of 1 g. A free housing's gain
/// is 1/m (1e-3 for 1000 kg); above 1e3 it is a unit mistake. The bound is on the transfer a
/// recording measures, G through the mount's high-pass at the mesh frequency
/// (model::housing_transfer_gain): with a mount (sensor.housing_mount_frequency_Hz) G is the gain
/// above the mount's resonance, which a fit to lines far below it puts orders of magnitude higher
/// (indepsim2's rigA3, session 47: 1.7 for a mount at 4 kHz; rigB5 at 1100 rpm, session 48:
/// 3e3-5e3 for a mount at 20 kHz, lines at 1-3 kHz seeing a hundredth of it).
inline constexpr double kMaxSensorGain_m_s2_per_N = 1e3;
/// sqrt(2 pi) sigma <= pi: the Hann window spans at most the whole ring; above it the window
/// overlaps itself around the ring and a Gaussian no longer localizes [rad].
inline constexpr double kMaxSensorWindowWidth_rad = 1.25;
/// Most lines per revolution a speed encoder may have [-]: 2^24, a 24-bit count per revolution,
/// the finest optical and interpolated encoders sold (the period method needs whole edges; with
/// several edges per time step only the last two are timed, so the cost does not grow with it).
inline constexpr int kMaxEncoderLines = 1 << 24;

/// Largest reference pressure angle [rad], pi/4: beyond it the tooth of a standard gear
/// becomes pointed before its addendum (geometry/gear.cpp checks the tip of each gear).
inline constexpr double kMaxPressureAngle_rad = 0.78539816339744830962;

/// The keys of one mesh family's stiffness harmonic corrections (stage.hpp
/// StiffnessSettings::Harmonics), relative to the mean stiffness: names[2h] the cos part of harmonic
/// h + 1, names[2h + 1] its sin part. Half the mean bounds each part: the potential-energy law's own
/// first harmonic is 0.1-0.35 of the mean for contact ratios 1.2-2 (planetwear stiffness), and a
/// change of half the mean in one part is already a different law, not a correction of this one.
template <class V, class Harmonics>
void visit_harmonics(V& v, const std::array<std::string_view, 2 * model::StiffnessSettings::Harmonics::kCount>& names,
                     Harmonics& h) {
  constexpr Range kHarmonicRange = interval(-0.5, 0.5, Ends::Closed, "-");
  for (int i = 0; i < model::StiffnessSettings::Harmonics::kCount; ++i) {
    v.field(names[2 * i], h.cos[i], "cos part of a mesh-stiffness harmonic, relative to the mean stiffness [-]",
            kHarmonicRange);
    v.field(names[2 * i + 1], h.sin[i], "sin part of a mesh-stiffness harmonic, relative to the mean stiffness [-]",
            kHarmonicRange);
  }
}

/// The keys of one gear, under `section` ("stage.sun", ...). Its single-key ranges are stated
/// here; what depends on the whole gear (a pointed tip, a dedendum below the addendum, the root
/// circle) is checked when geometry::make_gear builds it.
template <class V, class Gear>
void visit_gear(V& v, std::string_view section, Gear& g) {
  v.section(section);
  v.field("teeth", g.teeth, "number of teeth z [-]", at_least(3, "-"));
  v.field("module_m", g.module_m, "module m [m]", above(0, "m"));
  v.angle("pressure_angle_rad", "pressure_angle_deg", g.pressure_angle_rad, "reference pressure angle alpha0 [rad]", interval(0, kMaxPressureAngle_rad, Ends::OpenLow, "rad"));
  v.field("profile_shift", g.profile_shift, "profile shift coefficient x, ISO 21771 [-]", interval(-1.5, 1.5, Ends::Closed, "-"));
  v.field("addendum_coef", g.addendum_coef, "addendum coefficient h_a* [-]", interval(0, 2, Ends::OpenLow, "-"));
  v.field("dedendum_coef", g.dedendum_coef, "dedendum coefficient h_f* [-]", rule("in (addendum_coef, 2.5], checked with the whole gear"));
  v.field("root_fillet_coef", g.root_fillet_coef, "root fillet radius coefficient rho_f* [-]", interval(0, 0.5, Ends::Closed, "-"));
  v.field("face_width_m", g.face_width_m, "face width b [m]", above(0, "m"));
  v.field("youngs_modulus_Pa", g.material.youngs_modulus_Pa, "Young's modulus E [Pa]", above(0, "Pa"));
  v.field("shear_modulus_Pa", g.material.shear_modulus_Pa, "shear modulus G [Pa]", above(0, "Pa"));
  v.field("poisson_ratio", g.material.poisson_ratio, "Poisson's ratio nu [-]", interval(-1, 0.5, Ends::Open, "-"));
  v.field("density_kg_m3", g.material.density_kg_m3, "density rho [kg/m^3]", above(0, "kg/m^3"));
}

/// The keys of one tooth modifier (an element of imperfections.teeth).
template <class V, class Tooth>
void visit_tooth(V& v, Tooth& t) {
  v.field("body", t.body, "gear carrying the tooth: \"sun\", \"planet\" or \"ring\"");
  v.field("planet", t.planet, "planet index, 0-based (body = \"planet\" only; else 0) [-]", rule("in [0, stage.planet_count - 1] for body = \"planet\", else 0"));
  v.field("tooth", t.tooth, "tooth index, 0-based (docs/derivation.md 1.4) [-]", rule("in [0, teeth - 1] of that gear"));
  v.field("stiffness_factor", t.stiffness_factor, "multiplies the tooth's mesh stiffness, (0, 1] [-]", interval(0, 1, Ends::OpenLow, "-"));
  v.field("profile_deviation_m", t.profile_deviation_m, "extra profile deviation of the loaded flank, >= 0 [m]", rule("m; >= 0 and below the module of that gear"));
}

/// The [contact] section's keys (visit_config).
template <class V, class Contact>
void visit_contact(V& v, Contact& c) {
  v.section("contact");
  v.field("friction_coefficient", c.friction_coefficient, "friction coefficient mu [-]", interval(0, 1, Ends::OpenHigh, "-"));
  v.field("friction_smoothing_m_s", c.friction_smoothing_m_s, "sliding speed smoothing sgn(v) [m/s]", interval(0, 1, Ends::OpenLow, "m/s"));
  v.field("mesh_damping_ratio", c.mesh_damping_ratio, "viscous mesh damping ratio zeta [-]", interval(0, 1, Ends::Closed, "-"));
  v.field("backlash_sun_planet_m", c.backlash_sun_planet_m, "sun-planet backlash along the LOA [m]", rule("m; >= 0, below the module"));
  v.field("backlash_planet_ring_m", c.backlash_planet_ring_m, "planet-ring backlash along the LOA [m]", rule("m; >= 0, below the module"));
  v.field("mesh_error_sun_planet_m", c.mesh_error_sun_planet_m, "sun-planet profile error e_sp [m]", rule("m; |e| below the module"));
  v.field("mesh_error_planet_ring_m", c.mesh_error_planet_ring_m, "planet-ring profile error e_pr [m]", rule("m; |e| below the module"));
  v.field("tip_relief_m", c.tip_relief_m,
          "linear tip relief on every gear's tip, amount along the line of action [m]; 0 = none", rule("m; >= 0, below the module"));
  v.field("tip_relief_extent", c.tip_relief_extent,
          "roll length of the tip relief as a fraction of the double-contact zone (eps - 1) p_b [-]; 0.5 = short relief, 1 = long", interval(0, 1, Ends::OpenLow, "-"));
  v.field("engagement_ramp", c.engagement_ramp,
          "width of each tooth pair's linear stiffness ramp at the start and end of its path of contact, centred on them, "
          "as a fraction of the base pitch [-]; 0 = sharp entry",
          interval(0, model::ContactSettings::kMaxEngagementRamp, Ends::Closed, "-"));
}

/// The [sensor] section's keys (visit_config).
template <class V, class Sensor>
void visit_sensor(V& v, Sensor& c) {
  v.section("sensor");
  v.field("angle_rad", c.angle_rad, "housing accelerometer angle phi_s, CCW from planet 0 at t = 0 [rad]", any_finite("rad"));
  v.field("gain_m_s2_per_N", c.gain_m_s2_per_N, "transfer gain mesh force -> housing acceleration [m/s^2/N]",
          rule("m/s^2 per N; > 0, and at most 1000 through the mount (sensor.housing_mount_frequency_Hz) at the mesh frequency"));
  v.field("window_width_rad", c.window_width_rad, "transfer-path window width sigma [rad]", interval(0, kMaxSensorWindowWidth_rad, Ends::OpenLow, "rad"));
  v.field("window", c.window, "window shape: \"gaussian\" or \"hann\"");
  v.field("housing_path", c.housing_path,
          "mesh forces -> sensor: \"planet_pass\" (window), \"ring_translation\" (rigid ring, G = 1/ring mass) or "
          "\"ring_body\" (the lateral-torsional model's ring: G m_r times its acceleration)");
  v.field("encoder_bandwidth_Hz", c.encoder_bandwidth_Hz,
          "-3 dB bandwidth of the speed encoders' Butterworth low-pass (sun/speed, carrier/speed) [Hz]; 0 = ideal", at_least(0, "Hz; 0 = ideal encoder"));
  v.field("encoder_filter_order", c.encoder_filter_order, "order of the encoder low-pass, 1 or 2 [-]", integers(1, 2));
  v.field("sun_encoder_lines", c.sun_encoder_lines,
          "lines per revolution of the sun shaft's speed encoder, read by the period method (sun/speed) [-]; 0 = ideal",
          integers(0, kMaxEncoderLines));
  v.field("sun_encoder_phase_rad", c.sun_encoder_phase_rad,
          "angle of a line of the sun shaft's encoder from the shaft's zero [rad] (the phase of its images)", any_finite("rad"));
  v.field("carrier_encoder_lines", c.carrier_encoder_lines,
          "lines per revolution of the carrier's speed encoder, read by the period method (carrier/speed) [-]; 0 = ideal",
          integers(0, kMaxEncoderLines));
  v.field("carrier_encoder_phase_rad", c.carrier_encoder_phase_rad,
          "angle of a line of the carrier's encoder from the carrier's zero [rad] (the phase of its images)", any_finite("rad"));
  v.field("housing_mount_frequency_Hz", c.housing_mount_frequency_Hz,
          "resonance of the housing on its mount: housing/acceleration passes a second-order high-pass there [Hz]; 0 = none (flat gain)",
          rule("Hz; 0 = none, else > 0 and below the Nyquist frequency of the stored samples"));
  v.field("housing_mount_damping_ratio", c.housing_mount_damping_ratio,
          "modal damping ratio of that mount resonance [-]; its gain at the resonance is 1/(2 zeta); 1/sqrt2 = Butterworth, no peak",
          interval(model::SensorSettings::kMinHousingMountDampingRatio, model::SensorSettings::kMaxHousingMountDampingRatio, Ends::Closed, "-"));
}

/// Every key of a SimulationConfig (const or not), in file order.
template <class V, class Config>
void visit_config(V& v, Config& c) {
  v.section("stage");
  v.field("planet_count", c.stage.planet_count, "number of planets N [-]", integers(1, 32));
  v.field("planet_angles_rad", c.stage.planet_angles_rad, "planet angles psi_i [rad]; [] = equally spaced", rule("rad; [] or one per planet, the first 0, increasing, below 2 pi"));
  v.field("carrier_inertia_kgm2", c.stage.carrier_inertia_kgm2, "carrier inertia without planets [kg m^2]; 0 = derived", at_least(0, "kg m^2; 0 = derived"));
  v.field("carrier_mass_kg", c.stage.carrier_mass_kg, "carrier mass without planets [kg]; 0 = derived", at_least(0, "kg; 0 = derived"));
  v.field("sun_inertia_kgm2", c.stage.sun_inertia_kgm2, "sun inertia with its shaft or hub [kg m^2]; 0 = derived", at_least(0, "kg m^2; 0 = derived"));
  v.field("sun_mass_kg", c.stage.sun_mass_kg, "sun mass with its shaft or hub [kg]; 0 = derived", at_least(0, "kg; 0 = derived"));
  v.field("ring_inertia_kgm2", c.stage.ring_inertia_kgm2, "ring inertia with its housing [kg m^2]; 0 = derived", at_least(0, "kg m^2; 0 = derived"));
  v.field("ring_mass_kg", c.stage.ring_mass_kg, "ring mass with its housing [kg]; 0 = derived", at_least(0, "kg; 0 = derived"));
  v.field("input_inertia_kgm2", c.stage.input_inertia_kgm2,
          "inertia on the input shaft besides the sun (motor, coupling) [kg m^2]", at_least(0, "kg m^2"));
  v.field("output_inertia_kgm2", c.stage.output_inertia_kgm2,
          "inertia on the output shaft besides the carrier (load machine) [kg m^2]", at_least(0, "kg m^2"));
  // The fillet-foundation compliance (Sainsot et al. 2004) is fitted for h_f = 1/bore_ratio in
  // [1.4, 7]; [0.15, 0.7] keeps inside it with round numbers (h_f 1.43 .. 6.67).
  v.field("bore_ratio", c.stage.bore_ratio, "bore radius / root radius of sun and planets [-]",
          interval(0.15, 0.7, Ends::Closed, "-; Sainsot's fillet-foundation fit covers bore / root radius 1/7 .. 1/1.4"));
  visit_gear(v, "stage.sun", c.stage.sun);
  visit_gear(v, "stage.planet", c.stage.planet);
  visit_gear(v, "stage.ring", c.stage.ring);

  v.section("operating");
  v.field("input_speed_rpm", c.operating.input_speed_rpm, "sun speed [rpm]", interval(0, 1e5, Ends::OpenLow, "rpm"));
  v.field("input_power_W", c.operating.input_power_W, "sun input power [W]", interval(0, 1e9, Ends::OpenLow, "W"));

  v.section("stiffness");
  v.field("samples_per_pair", c.stiffness.samples_per_pair, "roll positions per tooth-pair contact [-]", integers(16, 100000));
  v.field("include_fillet_foundation", c.stiffness.include_fillet_foundation, "include the fillet-foundation term");
  v.field("scale", c.stiffness.scale, "multiplies every computed mesh stiffness [-]", interval(0, 1e3, Ends::OpenLow, "-"));
  visit_harmonics(v, {"sun_planet_h1_cos", "sun_planet_h1_sin", "sun_planet_h2_cos", "sun_planet_h2_sin",
                      "sun_planet_h3_cos", "sun_planet_h3_sin"}, c.stiffness.sun_planet_harmonics);
  visit_harmonics(v, {"planet_ring_h1_cos", "planet_ring_h1_sin", "planet_ring_h2_cos", "planet_ring_h2_sin",
                      "planet_ring_h3_cos", "planet_ring_h3_sin"}, c.stiffness.planet_ring_harmonics);
  v.field("mesh_phase", c.stiffness.mesh_phase,
          "what the mesh stiffness variation follows: \"rotation\" (the gears' roll angle, physical) or "
          "\"nominal_time\" (the nominal rotation only, k(t) of parametrically excited lumped models)");

  visit_contact(v, c.contact);

  v.section("imperfections");
  v.field("pin_error_m", c.imperfections.pin_error_m, "tangential pin position error per planet [m]; [] = none", rule("m; [] or one per planet, each |e| below the module"));
  v.field("sun_eccentricity_m", c.imperfections.sun_eccentricity_m, "sun runout [m]", rule("m; >= 0, below the module"));
  v.field("sun_eccentricity_phase_rad", c.imperfections.sun_eccentricity_phase_rad, "sun runout phase [rad]", any_finite("rad"));
  v.field("carrier_eccentricity_m", c.imperfections.carrier_eccentricity_m, "carrier runout [m]", rule("m; >= 0, below the module"));
  v.field("carrier_eccentricity_phase_rad", c.imperfections.carrier_eccentricity_phase_rad,
          "carrier runout phase [rad]", any_finite("rad"));
  v.field("torque_ripple_fraction", c.imperfections.torque_ripple_fraction, "input torque ripple / mean [-]", interval(0, 1, Ends::OpenHigh, "-"));
  v.field("torque_ripple_order", c.imperfections.torque_ripple_order, "ripple frequency / sun speed [-]", interval(0, 1e3, Ends::OpenLow, "-"));
  v.field("worn_profile_depth_m", c.imperfections.worn_profile_depth_m,
          "pre-existing Archard-shaped worn profile on every flank, largest depth [m]; 0 = none", rule("m; >= 0, below the module"));
  // Last in its section: Writer emits [[imperfections.teeth]] tables here.
  v.teeth("teeth", c.imperfections.teeth, "damaged or modified teeth; [] = none");

  v.section("bearings");
  v.field("sun_N_m", c.bearings.sun_N_m, "sun bearing stiffness k_s [N/m]", above(0, "N/m"));
  v.field("carrier_N_m", c.bearings.carrier_N_m, "carrier bearing stiffness k_c [N/m]", above(0, "N/m"));
  v.field("ring_N_m", c.bearings.ring_N_m, "ring support stiffness k_r [N/m]", above(0, "N/m"));
  v.field("planet_N_m", c.bearings.planet_N_m, "planet bearing stiffness k_p [N/m]", above(0, "N/m"));
  v.field("ring_torsional_N_m", c.bearings.ring_torsional_N_m, "ring torsional support k_ru [N/m]", above(0, "N/m"));
  v.field("damping_ratio", c.bearings.damping_ratio,
          "viscous damping ratio of every bearing and support, c = 2 zeta sqrt(k m) [-]; 0 = undamped (lateral_torsional only)",
          interval(0, 1, Ends::Closed, "-"));

  v.section("solver");
  v.field("level", c.solver.level, "model: \"torsional\" or \"lateral_torsional\"");
  v.field("time_step_s", c.solver.time_step_s, "time step [s]; 0 = automatic", rule("s; 0 = automatic, else at most 1/8 of the mesh period"));
  v.field("min_steps_per_mesh", c.solver.min_steps_per_mesh, "automatic step: steps per mesh period [-]", integers(8, 1000000));
  v.field("steps_per_mode_period", c.solver.steps_per_mode_period, "automatic step: steps per shortest mode period [-]", integers(8, 1000000));
  v.field("accuracy_band_Hz", c.solver.accuracy_band_Hz,
          "automatic step: band that gets steps_per_mode_period steps per period; modes above it get max(8, steps_per_mode_period/4) [Hz]; 0 = every mode",
          at_least(0, "Hz; 0 = every mode"));
  v.field("newmark_beta", c.solver.newmark_beta, "Newmark beta [-]", interval(0, 0.5, Ends::OpenLow, "-"));
  v.field("newmark_gamma", c.solver.newmark_gamma, "Newmark gamma [-]", interval(0.5, 1, Ends::Closed, "-"));
  v.field("newton_tolerance", c.solver.newton_tolerance, "Newton relative residual tolerance [-]", interval(0, 1e-2, Ends::OpenLow, "-"));
  v.field("newton_max_iterations", c.solver.newton_max_iterations, "Newton iteration limit [-]", integers(1, 1000));
  v.field("warmup_max_mesh_cycles", c.solver.warmup_max_mesh_cycles, "warm-up limit [mesh periods]", integers(1, 1000000));
  v.field("periodicity_tolerance", c.solver.periodicity_tolerance, "steady-state criterion [-]", interval(0, 1e-1, Ends::OpenLow, "-"));
  v.field("record_mesh_cycles", c.solver.record_mesh_cycles, "recorded mesh periods after warm-up [-]", integers(1, 1000000));
  v.field("engagement_smoothing", c.solver.engagement_smoothing,
          "true: tooth pairs enter and leave contact over one time step (sub-step engagement instant)");

  v.section("wear");
  v.field("mesh_cycles", c.wear.mesh_cycles, "mesh cycles to wear the stage through [-]; 0 = no wear (seed: 2e5)", rule("-; in [0, 1e12], 0 = no wear"));
  v.field("coefficient_m2_N", c.wear.coefficient_m2_N,
          "dimensional wear coefficient kappa = K/H [m^2/N]; ignored when archard_K > 0", interval(0, kMaxWearCoefficient_m2_N, Ends::OpenHigh, "m^2/N"));
  v.field("archard_K", c.wear.archard_K, "dimensionless Archard K [-]; > 0: kappa = archard_K / hardness_Pa", interval(0, 1, Ends::OpenHigh, "-"));
  v.field("hardness_Pa", c.wear.hardness_Pa, "hardness H of the softer flank [Pa] (used with archard_K)", above(0, "Pa"));
  v.field("elements_per_flank", c.wear.elements_per_flank, "microelements over each active flank [-]", rule("in [2, 10000]"));
  v.field("window_mesh_cycles", c.wear.window_mesh_cycles,
          "dynamic window per wear update [mesh cycles]; 0 = automatic", integers(0, 1000000));
  v.field("max_increment_fraction", c.wear.max_increment_fraction,
          "largest wear increment per update / static sun-mesh deflection [-]", interval(0, 1, Ends::OpenLow, "-"));
  v.field("max_wear_fraction_of_thickness", c.wear.max_wear_fraction_of_thickness,
          "stop when a flank's wear exceeds this fraction of the chordal tooth thickness [-]", interval(0, 0.5, Ends::OpenLow, "-"));
  v.field("snapshot_mesh_cycles", c.wear.snapshot_mesh_cycles,
          "mesh cycles at which dynamic snapshots are stored [-]; [] = first and last", rule("-; each in [0, wear.mesh_cycles]"));
  v.field("snapshot_record_mesh_cycles", c.wear.snapshot_record_mesh_cycles,
          "mesh cycles each dynamic snapshot records [-]", integers(1, 100000));

  visit_sensor(v, c.sensor);

  v.section("rig");
  v.field("input_control", c.rig.input_control,
          "input machine: \"power\" (constant power P/w, the seed's), \"torque\" (constant torque), \"speed\" (ideal "
          "speed control through the input shaft) or \"speed_loop\" (a PI speed loop of gains input_speed_loop_*)");
  v.field("input_shaft_stiffness_N_m_rad", c.rig.input_shaft_stiffness_N_m_rad,
          "shaft from the motor (stage.input_inertia_kgm2) to the sun [N m/rad]; 0 = rigid", at_least(0, "N m/rad; 0 = rigid"));
  v.field("input_shaft_damping_N_m_s_rad", c.rig.input_shaft_damping_N_m_s_rad, "input shaft damping [N m s/rad]", at_least(0, "N m s/rad"));
  v.field("input_speed_loop_proportional_N_m_s_rad", c.rig.input_speed_loop_proportional_N_m_s_rad,
          "proportional gain K_p of the motor's speed loop (input_control = \"speed_loop\") [N m s/rad]",
          at_least(0, "N m s/rad; > 0 with input_control = \"speed_loop\""));
  v.field("input_speed_loop_integral_N_m_rad", c.rig.input_speed_loop_integral_N_m_rad,
          "integral gain K_i of the motor's speed loop (input_control = \"speed_loop\") [N m/rad]",
          at_least(0, "N m/rad; > 0 with input_control = \"speed_loop\""));
  v.field("load_control", c.rig.load_control,
          "load machine: \"torque\" (constant torque holding the mean speed), \"speed\" (ideal speed control) or "
          "\"speed_loop\" (a PI speed loop of gains load_speed_loop_*)");
  v.field("output_shaft_stiffness_N_m_rad", c.rig.output_shaft_stiffness_N_m_rad,
          "shaft from the carrier to the load machine [N m/rad]; 0 = rigid; > 0 with load_control = \"speed\"", at_least(0, "N m/rad; 0 = rigid"));
  v.field("output_shaft_damping_N_m_s_rad", c.rig.output_shaft_damping_N_m_s_rad,
          "output shaft damping [N m s/rad]", at_least(0, "N m s/rad"));
  v.field("load_speed_loop_proportional_N_m_s_rad", c.rig.load_speed_loop_proportional_N_m_s_rad,
          "proportional gain K_p of the load machine's speed loop (load_control = \"speed_loop\") [N m s/rad]",
          at_least(0, "N m s/rad; > 0 with load_control = \"speed_loop\""));
  v.field("load_speed_loop_integral_N_m_rad", c.rig.load_speed_loop_integral_N_m_rad,
          "integral gain K_i of the load machine's speed loop (load_control = \"speed_loop\") [N m/rad]",
          at_least(0, "N m/rad; > 0 with load_control = \"speed_loop\""));
}

namespace detail {
/// Finds the double-valued field named by a full key path ("contact.friction_coefficient").
class NumberFinder {
public:
  explicit NumberFinder(std::string_view target) : target_(target) {}
  void section(std::string_view path) { section_ = path; }
  template <class T>
  void field(std::string_view key, T& value, std::string_view /*doc*/, const Range& = {}) {
    if constexpr (std::is_same_v<std::remove_cv_t<T>, double>)
      if (matches(key)) found = &value;
  }
  void angle(std::string_view key_rad, std::string_view /*key_deg*/, double& value_rad, std::string_view doc,
             const Range& range = {}) {
    field(key_rad, value_rad, doc, range);
  }
  template <class Teeth>
  void teeth(std::string_view, Teeth&, std::string_view) {}  // per-tooth values have no fixed path

  double* found = nullptr;

private:
  bool matches(std::string_view key) const {
    return target_.size() == section_.size() + 1 + key.size() && target_.substr(0, section_.size()) == section_ &&
           target_[section_.size()] == '.' && target_.substr(section_.size() + 1) == key;
  }
  std::string_view target_;
  std::string_view section_;
};
} // namespace detail

/// The double-valued field of `c` whose key path is `key` ("stiffness.scale"),
/// or nullptr if the schema has no such floating-point key.
inline double* find_number(model::SimulationConfig& c, std::string_view key) {
  detail::NumberFinder finder(key);
  visit_config(finder, c);
  return finder.found;
}

} // namespace pw::config
