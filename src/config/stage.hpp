// Everything that defines one planetary-stage simulation, as plain value
// types. This is the contract between the configuration reader (io/), the
// physics (src/) and the output writers: every field has a unit in its name or
// doc comment and a default equal to the seed paper's case (Bai & Ning 2023,
// Table 1) or, where the seed is silent, a documented assumption
// (docs/derivation.md, "Assumptions").
//
// Validation of ranges happens once, in model::validate() (model/validate.hpp;
// above the geometry, since it builds each gear to check it), which throws
// pw::InputError naming the TOML key (section.key) that is wrong. The types
// keep their namespace pw::model. Every field is also one line of the key
// schema, config/schema.hpp (name, doc string, unit).
#pragma once

#include "config/gear_spec.hpp"

#include <array>
#include <numbers>
#include <string>
#include <vector>

namespace pw::model {

/// Sun (external), planets (external, identical) and a fixed ring (internal).
struct StageSpec {
  geometry::GearSpec sun{.teeth = 21};
  geometry::GearSpec planet{.teeth = 30};
  geometry::GearSpec ring{.teeth = 81, .kind = geometry::GearKind::Internal};
  int planet_count = 3;  ///< N [-]
  /// Planet carrier angles psi_i [rad], counter-clockwise from planet 0.
  /// Empty: equally spaced, psi_i = 2 pi i / N.
  std::vector<double> planet_angles_rad{};
  /// Carrier torsional inertia without the planets [kg m^2]. 0: derived
  /// (docs/derivation.md: two steel side plates of radius 1.2 a, 10 mm thick).
  double carrier_inertia_kgm2 = 0.0;
  double carrier_mass_kg = 0.0;  ///< without planets [kg]; 0: derived as above
  /// Sun torsional inertia with what turns rigidly with it (its shaft, a hub) [kg m^2]. 0:
  /// derived (docs/derivation.md: a steel disc from the bore to the reference circle).
  double sun_inertia_kgm2 = 0.0;
  double sun_mass_kg = 0.0;  ///< sun mass with its shaft or hub [kg] (lateral_torsional); 0: derived as above
  /// Ring torsional inertia with what is fixed to it (housing) [kg m^2]; 0: derived (a steel
  /// rim three modules thick beyond the root circle). Lateral_torsional only (the ring is fixed
  /// in the torsional model).
  double ring_inertia_kgm2 = 0.0;
  double ring_mass_kg = 0.0;  ///< ring mass with its housing [kg] (lateral_torsional); 0: derived as above
  /// Inertia on the input shaft besides the sun (motor rotor, coupling)
  /// [kg m^2]; 0 (the seed's model: the sun alone takes the input power).
  double input_inertia_kgm2 = 0.0;
  /// Inertia on the output shaft besides the carrier (load machine) [kg m^2]; 0 as in the seed.
  double output_inertia_kgm2 = 0.0;
  /// Gear body bore radius as a fraction of the root radius [-], used only for
  /// the derived (solid-disc-with-bore) inertias and masses of sun and planets.
  double bore_ratio = 0.3;
};

/// Where and how fast the stage runs. Constant input power on the sun; the
/// carrier carries the matching constant load torque (seed section 5).
struct OperatingPoint {
  double input_speed_rpm = 100.0;  ///< sun speed [rpm] (seed: 100, 200, 400)
  double input_power_W = 1000.0;   ///< sun power [W] (seed: 1 kW)
};

/// What the mesh stiffness's variation over a mesh cycle follows.
enum class MeshPhase {
  /// The gears' actual roll angle (nominal rotation plus the computed perturbation): a real
  /// gear's tooth pairs change as it turns, so a speed fluctuation modulates the mesh frequency.
  Rotation,
  /// The nominal rotation only, k(t) at the constant mean speed: the time-varying stiffness of
  /// lumped-parameter models that excite the mesh parametrically in time (e.g. Kahraman 1994;
  /// Lin & Parker 2002). No real gear does this; a recording from such a simulator has mesh lines
  /// locked to time, not to the shafts' angle (docs/derivation.md §1).
  NominalTime,
};

/// The configuration's name of a mesh form (stiffness.mesh_phase), also the calibration file's and
/// report.json's.
constexpr const char* mesh_phase_name(MeshPhase p) { return p == MeshPhase::NominalTime ? "nominal_time" : "rotation"; }

/// Mesh stiffness model (potential energy method, docs/derivation.md §2).
struct StiffnessSettings {
  int samples_per_pair = 200;      ///< roll positions sampled over one pair's contact [-]
  bool include_fillet_foundation = true;  ///< Sainsot et al. 2004 body term
  /// Multiplies every computed mesh stiffness [-]. 1 = as computed; the seed's
  /// Table 2 level corresponds to about 0.01 (docs/validation.md).
  double scale = 1.0;
  /// A correction of the first kStiffnessHarmonics harmonics of each mesh family's combined
  /// stiffness over one mesh cycle, relative to its time-mean stiffness [-]:
  ///   K(s) -> K(s) + Kbar sum_h (cos_h cos(2 pi h u / p_b) + sin_h sin(2 pi h u / p_b)),
  /// u the mesh's contact coordinate (pairs at xi_j = u - j p_b), applied to the pairs in contact
  /// in proportion to their stiffness. Zero: the potential-energy law as computed. What a rig's
  /// calibration fits when its gears' stiffness law differs in shape from the model's
  /// (docs/diagnose.md §4, mesh_stiffness_harmonics); the mean stays Kbar.
  struct Harmonics {
    static constexpr int kCount = 3;
    std::array<double, kCount> cos{}, sin{};
    bool any() const {
      for (int h = 0; h < kCount; ++h)
        if (cos[h] != 0 || sin[h] != 0) return true;
      return false;
    }
  };
  Harmonics sun_planet_harmonics;
  Harmonics planet_ring_harmonics;
  /// What the pairs in contact and their stiffness follow (MeshPhase); rotation = physical.
  MeshPhase mesh_phase = MeshPhase::Rotation;
};

/// Mesh contact physics.
struct ContactSettings {
  double friction_coefficient = 0.1;     ///< mu [-] (seed Table 1)
  /// Sliding speed [m/s] over which sgn(v) is smoothed as tanh(v / v_eps).
  double friction_smoothing_m_s = 1e-3;
  /// Viscous mesh damping ratio zeta [-]: c = 2 zeta sqrt(k_mean m_eq) per
  /// mesh (seed silent; 0.05 is mid-range of published 0.03-0.1).
  double mesh_damping_ratio = 0.05;
  double backlash_sun_planet_m = 0.0;    ///< initial circumferential backlash along the LOA [m] (seed assumption 4: zero)
  double backlash_planet_ring_m = 0.0;   ///< [m]
  double mesh_error_sun_planet_m = 0.0;  ///< seed's e_sp: constant profile error along the LOA [m]
  double mesh_error_planet_ring_m = 0.0; ///< seed's e_pr [m]
  /// Linear tip relief on every gear's tip (sun, planets, ring), the amount C_a of material
  /// removed at the tip along the line of action [m] (ISO 21771 "tip relief"); 0 = unmodified
  /// involutes, the seed's. Real gears carry it to soften the engagement impact; a gear set's
  /// documentation often does not give it.
  double tip_relief_m = 0.0;
  /// Roll length of that relief as a fraction of the double-contact zone at the tip,
  /// (epsilon_alpha - 1) p_b [-]: 1 = "long" relief (from the point of single contact to the
  /// tip), 0.5 = "short" relief, the default: the longest for which one pair of every
  /// double-contact position is unrelieved, so that at a load whose deflection is below the
  /// relief the mesh still carries it as the unmodified gears would (a long relief unloads both
  /// pairs there, by C_a / 2 each, and the mesh separates). Gears that run over a range of loads,
  /// and a relief the documentation does not give, call for that.
  double tip_relief_extent = 0.5;
  /// Width of the ramp over which a tooth pair's stiffness rises from zero at the start of the
  /// path of contact and falls to zero at its end, as a fraction of the base pitch p_b [-],
  /// centred on the theoretical start and end points (so a pair's stiffness integrated over its
  /// path, and with it the mean mesh stiffness, is unchanged). 0 = the involute's sharp entry,
  /// today's model. Real pairs never engage at a point: the tip's edge is rounded or chamfered,
  /// and under load a pair touches before the theoretical start because the pairs already in
  /// contact deflect (extended contact). A ramp of width r p_b is a moving average of the pair
  /// stiffness over r p_b: it leaves the first mesh harmonics and attenuates the n-th by about
  /// sinc(n r), which is what a calibration on a rig's healthy recordings can measure when its
  /// gears' documentation does not give their tips. At most 0.5, so that the ramps of a pair's
  /// two ends never overlap for contact ratios above 1.5 and no mesh holds more than
  /// MeshState::kMaxPairs pairs. Below the roll of one time step the step's own smoothing
  /// (solver.engagement_smoothing) is the wider and is used.
  double engagement_ramp = 0.0;
  static constexpr double kMaxEngagementRamp = 0.5;  ///< engagement_ramp's upper end [-], see above
};

/// One gear body a tooth modification applies to.
enum class Body { Sun, Planet, Ring };

/// The body as the configuration spells it: "sun", "planet", "ring".
constexpr const char* body_name(Body b) {
  switch (b) {
  case Body::Sun: return "sun";
  case Body::Planet: return "planet";
  case Body::Ring: return "ring";
  }
  return "?";
}

/// A damaged or modified tooth (crack, chip, local pitting): its mesh stiffness
/// is multiplied by stiffness_factor and its flank carries an extra profile
/// deviation (positive = material removed) on its loaded flank.
struct ToothModifier {
  Body body = Body::Sun;
  int planet = 0;                  ///< which planet (Body::Planet only), 0-based
  int tooth = 0;                   ///< tooth index, 0-based, counted as in docs/derivation.md §1.4
  double stiffness_factor = 1.0;   ///< (0, 1] [-]
  double profile_deviation_m = 0;  ///< [m], >= 0 removes material
};

/// Manufacturing and assembly errors; all zero by default.
struct Imperfections {
  /// Tangential position error of each planet pin [m] (positive = advanced in
  /// the carrier's direction of rotation). Empty = all zero.
  std::vector<double> pin_error_m{};
  double sun_eccentricity_m = 0.0;       ///< sun runout [m]
  double sun_eccentricity_phase_rad = 0.0;
  double carrier_eccentricity_m = 0.0;   ///< carrier runout [m]
  double carrier_eccentricity_phase_rad = 0.0;
  double torque_ripple_fraction = 0.0;   ///< input torque ripple amplitude / mean torque [-]
  double torque_ripple_order = 1.0;      ///< ripple frequency in orders of the sun speed [-]
  std::vector<ToothModifier> teeth{};
  /// Pre-existing worn profile on every flank of every tooth [m]: the largest
  /// depth of an Archard-shaped deviation, depth(xi) proportional to the
  /// flank's slide-to-roll ratio |v_A - v_B| / v_flank (docs/derivation.md
  /// §5, W1 at uniform load), which is zero at the pitch point. Each flank
  /// family's maximum over its active flank equals this value. 0 = none.
  double worn_profile_depth_m = 0.0;
};

enum class ModelLevel { Torsional, LateralTorsional };
/// The name solver.level takes in the configuration.
constexpr const char* model_level_name(ModelLevel l) {
  return l == ModelLevel::LateralTorsional ? "lateral_torsional" : "torsional";
}

/// Bearing supports of the lateral-torsional model (Lin & Parker 1999).
struct BearingSettings {
  double sun_N_m = 1e8;       ///< k_s [N/m]
  double carrier_N_m = 1e8;   ///< k_c [N/m]
  double ring_N_m = 1e8;      ///< k_r [N/m]
  double planet_N_m = 1e8;    ///< k_p [N/m]
  double ring_torsional_N_m = 1e9;  ///< k_ru [N/m] on u_r = r_br theta_r (Lin & Parker 1999 form); ring held torsionally
  /// Viscous damping ratio zeta of every bearing and support [-]: a damper c = 2 zeta sqrt(k m)
  /// in parallel with each spring, m the mass (inertia, for a torsional support) of the body it
  /// holds, or the two bodies' reduced mass for a planet bearing. 0 (default): undamped supports,
  /// Lin & Parker's model; damping then acts on the meshes alone.
  double damping_ratio = 0.0;
};

/// Time integration and output.
struct SolverSettings {
  ModelLevel level = ModelLevel::Torsional;
  /// Time step [s]. 0: automatic, the smaller of (mesh period /
  /// min_steps_per_mesh) and (shortest natural period / steps_per_mode_period).
  double time_step_s = 0.0;
  int min_steps_per_mesh = 64;
  int steps_per_mode_period = 32;  ///< average-acceleration period error ~ (2pi/n)^2/12 = 0.3 % at 32
  /// Automatic step: the band [Hz] whose response must be accurate. 0: every mode gets
  /// steps_per_mode_period steps per period (today's rule). > 0: the forced response and the
  /// modes below it do; a mode above it gets max(8, steps_per_mode_period / 4) steps per period,
  /// 8 being the validity check's floor (the average-acceleration rule is unconditionally
  /// stable, and a mode far above a line acts on it quasi-statically; model::automatic_time_step).
  /// `diagnose` sets it to the analysed band (0.3 f_s).
  double accuracy_band_Hz = 0.0;
  double newmark_beta = 0.25;      ///< average acceleration, unconditionally stable
  double newmark_gamma = 0.5;
  double newton_tolerance = 1e-10; ///< relative residual [-]
  int newton_max_iterations = 30;
  int warmup_max_mesh_cycles = 400; ///< limit on reaching the periodic steady state
  double periodicity_tolerance = 1e-6; ///< relative change of the state over one mesh period [-]
  int record_mesh_cycles = 24;     ///< mesh periods stored after the warm-up [-]
  /// Tooth pairs enter and leave contact over one time step, weighted by the share
  /// of the step they spend in contact (derivation §3.4): the response then varies
  /// smoothly with the step instead of erratically. false = switch at the first step.
  bool engagement_smoothing = true;
};

/// Archard wear on every tooth flank, coupled to the dynamics (seed §4-5;
/// docs/derivation.md §5). Off while mesh_cycles == 0.
struct WearSettings {
  /// Mesh cycles to wear the stage through [-] (seed: 2e5). 0: no wear.
  double mesh_cycles = 0.0;
  /// Dimensional wear coefficient kappa = K/H [m^2/N] (dh = kappa p ds).
  /// The seed's "K = 5e-11" reproduces its wear depths read as
  /// 5e-11 mm^2/N = 5e-17 m^2/N. Ignored when archard_K > 0.
  double coefficient_m2_N = 5e-17;
  /// Alternative input: dimensionless Archard K [-] with hardness_Pa; used
  /// when > 0, then kappa = archard_K / hardness_Pa.
  double archard_K = 0.0;
  double hardness_Pa = 6e9;  ///< H of the softer flank [Pa] (~ 600 HV case-hardened steel)
  int elements_per_flank = 64;  ///< microelements over each active flank [-], >= 2
  /// Dynamic window per wear update [mesh cycles]; 0: automatic, the number
  /// that lets every planet tooth mesh on both flanks (Zp) and every ring
  /// tooth at least once.
  int window_mesh_cycles = 0;
  /// Bound on the wear increment of any element per update, as a fraction of
  /// the static sun-mesh deflection (a proxy for the change in contact
  /// pressure: dp/p ~ dh/delta) [-].
  double max_increment_fraction = 0.1;
  /// Stop (keeping what was computed) when any flank's wear exceeds this
  /// fraction of the tooth's reference-circle chordal thickness [-].
  double max_wear_fraction_of_thickness = 0.1;
  /// Mesh-cycle counts at which dynamic snapshots (time histories and
  /// spectra) are stored; the nearest update is used. Empty: first and last.
  std::vector<double> snapshot_mesh_cycles{};
  /// Mesh cycles each snapshot records [-] (8: enough for spectra of the mesh
  /// harmonics; condition indicators need whole gear revolutions,
  /// docs/indicators.md).
  int snapshot_record_mesh_cycles = 8;
};

/// How the machine on the input shaft drives the sun.
enum class InputControl {
  Power,   ///< constant power P at the actual speed, T = P / w (today's model, the seed's constant input power)
  Torque,  ///< constant torque P / Omega_s (a torque-controlled motor; no speed feedback)
  Speed,   ///< ideal speed control: the input shaft's far end turns at exactly the nominal sun speed
  SpeedLoop,  ///< a PI speed controller on the motor's speed (a drive of finite loop bandwidth)
};

/// How the machine on the output shaft loads the carrier.
enum class LoadControl {
  Torque,  ///< constant load torque, adjusted in the warm-up so that the stage holds its nominal mean speed
  Speed,   ///< ideal speed control: the shaft's far end turns at exactly the nominal carrier speed (a dynamometer)
  SpeedLoop,  ///< a PI speed controller on the load machine's speed: a dynamometer of finite loop bandwidth
};

/// The test rig around the stage: the shafts to the input motor and to the
/// load machine, and how each machine is controlled (docs/derivation.md §3.6).
/// A shaft stiffness of 0 couples its machine's inertia rigidly to the sun or
/// carrier (stage.input_inertia_kgm2 / output_inertia_kgm2), today's model; a
/// positive stiffness puts the machine on its own torsional coordinate behind
/// a shaft spring k and damper c. The defaults reproduce the seed's model.
struct RigSettings {
  InputControl input_control = InputControl::Power;
  /// Input shaft between the motor (inertia stage.input_inertia_kgm2) and the sun [N m/rad]; 0 = rigid.
  double input_shaft_stiffness_N_m_rad = 0.0;
  double input_shaft_damping_N_m_s_rad = 0.0;  ///< [N m s/rad]
  /// Gains of the motor's PI speed loop (input_control = speed_loop): motor torque
  /// T = P / Omega_s - K_p (w - Omega_s) - K_i \int (w - Omega_s) dt, w the motor's speed.
  double input_speed_loop_proportional_N_m_s_rad = 0.0;  ///< K_p [N m s/rad]
  double input_speed_loop_integral_N_m_rad = 0.0;        ///< K_i [N m/rad]
  LoadControl load_control = LoadControl::Torque;
  /// Output shaft between the carrier and the load machine [N m/rad]; 0 = rigid. Required > 0
  /// with load_control = speed (an ideal speed control rigidly attached would lock the carrier).
  /// Under ideal speed control the load machine's own inertia (stage.output_inertia_kgm2) has
  /// no effect: its far end of the shaft turns at the set speed whatever its inertia.
  double output_shaft_stiffness_N_m_rad = 0.0;
  double output_shaft_damping_N_m_s_rad = 0.0;  ///< [N m s/rad]
  /// Gains of the load machine's PI speed loop (load_control = speed_loop): load torque
  /// T = T_ff - K_p (w - Omega_c) - K_i \int (w - Omega_c) dt, w the machine's speed.
  double load_speed_loop_proportional_N_m_s_rad = 0.0;  ///< K_p [N m s/rad]
  double load_speed_loop_integral_N_m_rad = 0.0;        ///< K_i [N m/rad] = [N m s/rad] per s
};

/// Shape of the transfer-path window of a housing accelerometer.
enum class SensorWindow {
  Gaussian,  ///< wrapped Gaussian, w(d) = sum_k exp(-(d + 2 pi k)^2 / (2 sigma^2)), sigma = window_width_rad
  Hann,      ///< w(d) = cos^2(pi d / (2 h)) for |d| < h, else 0; half-width h = sqrt(2 pi) sigma (same area)
};

/// What a housing accelerometer reads of the planet-ring mesh forces (model/sensor.hpp).
enum class HousingPath {
  /// Each planet's ring-mesh force fluctuation through a window of its angular distance from the
  /// sensor (McFadden & Smith 1985): a flexible ring that carries a planet's force to the sensor
  /// only while the planet passes, Eq. (S1).
  PlanetPass,
  /// The ring's rigid-body translation along the sensor's radial direction: every planet's full
  /// ring-mesh force projected on it, a = G sum_i F_pr,i sin(psi_i + theta_c - phi_s + alpha'_pr),
  /// Eq. (S2) (a stiff ring on a compliant housing, the lumped models of Lin & Parker 1999).
  RingTranslation,
  /// The ring body's own translational acceleration in the lateral-torsional model (solver.level =
  /// "lateral_torsional" only): a = G m_r (a_x cos phi_s + a_y sin phi_s), (a_x, a_y) the ring's
  /// acceleration in the fixed frame and m_r its mass, Eq. (S3): (S2)'s net force after the ring's
  /// dynamics on its support (bearings.ring_N_m), through the stage's translational modes.
  RingBody,
};

/// The configuration's name of a housing path (sensor.housing_path), also the calibration
/// file's and report.json's.
constexpr const char* housing_path_name(HousingPath p) {
  return p == HousingPath::RingTranslation ? "ring_translation" : p == HousingPath::RingBody ? "ring_body" : "planet_pass";
}

/// Accelerometer fixed on the ring/housing (McFadden & Smith 1985; Inalpolat
/// & Kahraman 2009): it sees each planet's planet-ring mesh force through a
/// window of the planet's angular distance from the sensor,
///   a_s(t) = G sum_i w(wrap(psi_i + theta_c(t) - phi_s)) (F_pr,i(t) - mean_t F_pr,i)
/// (model/sensor.hpp; docs/recordings.md). Output channel housing/acceleration.
struct SensorSettings {
  /// Sensor angle phi_s [rad], counter-clockwise in the fixed (housing) frame
  /// from the position of planet 0 at simulation time 0 (carrier angle 0).
  double angle_rad = 0.0;
  /// Transfer gain G [m/s^2 per N] from mesh force to housing acceleration.
  /// Assumption (the seed has no housing): 1e-3, i.e. an effective housing
  /// mass of 1000 kg; only the shape of the signal is meaningful.
  double gain_m_s2_per_N = 1e-3;
  /// Window width sigma [rad]: the Gaussian's standard deviation (the Hann
  /// window has the same area, half-width sqrt(2 pi) sigma).
  double window_width_rad = 0.5;
  SensorWindow window = SensorWindow::Gaussian;
  /// The path from the ring-mesh forces to the sensor (HousingPath): the planet-pass window
  /// (today's, the default), the ring's rigid-body translation, where G is 1 / (ring mass) and
  /// the window (window, window_width_rad) plays no part, or the lateral-torsional model's ring
  /// body (its acceleration times its mass, the same G; solver.level = "lateral_torsional" only).
  HousingPath housing_path = HousingPath::PlanetPass;
  /// Speed encoders (channels sun/speed and carrier/speed): -3 dB bandwidth of a Butterworth
  /// low-pass [Hz] that the measured speed has passed through (a finite encoder line count,
  /// the differentiation and smoothing filter of its counter); 0 = ideal (no filter). Applied to
  /// the simulated speeds at every time step, before any decimation (model/sensor.hpp).
  double encoder_bandwidth_Hz = 0.0;
  int encoder_filter_order = 2;  ///< order of that Butterworth low-pass, 1 or 2 [-]
  /// Lines per revolution of the sun shaft's / the carrier's speed encoder, read by the period
  /// method (the speed is the line pitch over the time between the last two edges, held until
  /// the next; model/sensor.hpp LineEncoder); 0 = ideal (the true speed). Applied before the
  /// bandwidth low-pass, at every time step. A rig's documentation gives the count; a recording's
  /// sidecar may state it per speed column (columns.<name>.encoder_lines, docs/recordings.md).
  int sun_encoder_lines = 0;
  int carrier_encoder_lines = 0;
  /// Where those encoders' lines sit on their shafts: the angle of a line from the shaft's zero
  /// (the model's angle at t = 0, tooth 0 of the sun or planet 0's arm at its reference) [rad].
  /// It sets only the phase of the encoder's images against the gear lines; a rig does not know
  /// it, so the diagnosis budgets the images' phase as unknown (docs/diagnose.md §2).
  double sun_encoder_phase_rad = 0.0;
  double carrier_encoder_phase_rad = 0.0;
  /// Resonance of the housing on its mount [Hz]; 0 = none, today's flat transfer G. A housing
  /// (or the ring the accelerometer sits on) is a mass on its mount's stiffness: from the mesh
  /// force to its acceleration the transfer is -w^2 / (k - m w^2 + i c w), flat (1/m, the gain G)
  /// above the mount's resonance f_0 and rising as (f/f_0)^2 below it, where the housing follows
  /// the mount's quasi-static deflection. Modelled as a second-order Butterworth high-pass at
  /// f_0 on housing/acceleration, applied to the record in its periodic steady state
  /// (model/sensor.hpp). Must lie below the Nyquist frequency of the stored samples.
  double housing_mount_frequency_Hz = 0.0;
  /// The mount's modal damping ratio zeta [-]: the high-pass is s^2 / (s^2 + 2 zeta w_0 s + w_0^2),
  /// the transfer of a mass on a spring and damper from the force on it to its acceleration, whose
  /// gain at f_0 is 1 / (2 zeta). The default 1/sqrt2 is the Butterworth high-pass (no peak, the
  /// model before this key existed, bit for bit); a housing on bolted mounts rings with a few per
  /// cent (kMinHousingMountDampingRatio..kMaxHousingMountDampingRatio).
  double housing_mount_damping_ratio = kButterworthDampingRatio;
  /// 1/sqrt2: the damping ratio of a second-order Butterworth filter (maximally flat, no peak) [-].
  static constexpr double kButterworthDampingRatio = std::numbers::sqrt2 / 2;
  /// The range sensor.housing_mount_damping_ratio accepts [-]: 0.1 % (a resonance 500 times the
  /// flat gain, lighter than any assembled steel structure's modal damping) to 2 (overdamped).
  static constexpr double kMinHousingMountDampingRatio = 1e-3;
  static constexpr double kMaxHousingMountDampingRatio = 2.0;
};

/// One complete simulation case.
struct SimulationConfig {
  StageSpec stage{};
  OperatingPoint operating{};
  StiffnessSettings stiffness{};
  ContactSettings contact{};
  Imperfections imperfections{};
  BearingSettings bearings{};
  SolverSettings solver{};
  WearSettings wear{};
  SensorSettings sensor{};
  RigSettings rig{};
};

/// Stage kinematics with the ring fixed (Willis: (w_s - w_c) Z_s = -(0 - w_c) Z_r), the one
/// place the speed ratio and the mesh frequency are written. Speeds in any one unit.
/// Carrier speed from the sun's: w_c = w_s Z_s / (Z_s + Z_r).
inline double carrier_speed(const StageSpec& s, double sun_speed) {
  return sun_speed * s.sun.teeth / static_cast<double>(s.sun.teeth + s.ring.teeth);
}
/// Sun speed from the carrier's: w_s = w_c (Z_s + Z_r) / Z_s.
inline double sun_speed(const StageSpec& s, double carrier_speed) {
  return carrier_speed * static_cast<double>(s.sun.teeth + s.ring.teeth) / s.sun.teeth;
}
/// Carrier-to-sun speed ratio Z_s / (Z_s + Z_r) [-].
inline double carrier_to_sun_ratio(const StageSpec& s) { return carrier_speed(s, 1.0); }
/// Mesh frequency f_m = Z_r f_c = Z_s Z_r / (Z_s + Z_r) n_s / 60 [Hz] at sun speed n_s [rpm].
inline double mesh_frequency_Hz(const StageSpec& s, double sun_speed_rpm) {
  const double zs = s.sun.teeth, zr = s.ring.teeth;
  return zs * zr / (zs + zr) * sun_speed_rpm / 60.0;
}

} // namespace pw::model
