// Range checks of a SimulationConfig: the single place where user input is
// validated (the configuration reader and the command-line overrides both end
// here). Every failure throws pw::InputError whose parameter() is the TOML key
// path ("operating.input_speed_rpm", "stage.sun.module_m",
// "imperfections.teeth[2].tooth") and whose message gives the value and the
// allowed range. The ranges are listed in docs/config.md.
//
// Not checked here (they need the mesh geometry): interference, contact ratio,
// the assembly condition and planet tip-circle clearance. Those are checked by
// geometry::make_stage_geometry() when the model is built.
#include "model/validate.hpp"

#include "core/error.hpp"
#include "geometry/gear.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>

namespace pw::model {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kMaxWearMeshCycles = 1e12;   ///< [-]
constexpr double kMaxWearCoefficient = 1e-10;  ///< kappa [m^2/N], exclusive
/// sqrt(2 pi) sigma <= pi: the Hann window spans at most the whole ring [rad].
constexpr double kMaxSensorWindowWidth = 1.25;

/// Which ends of [lo, hi] belong to the allowed interval.
enum class Ends { Closed, Open, OpenLow, OpenHigh };

/// "> 0", ">= 0", "(0, 0.5]", "[0.5, 1]" ... for a message.
std::string describe(double lo, double hi, Ends ends) {
  const bool lo_open = ends == Ends::Open || ends == Ends::OpenLow;
  const bool hi_open = ends == Ends::Open || ends == Ends::OpenHigh;
  if (hi == kInf) return detail::concat(lo_open ? "> " : ">= ", lo);
  return detail::concat("in ", lo_open ? "(" : "[", lo, ", ", hi, hi_open ? ")" : "]");
}

/// A finite double inside the interval; NaN and +-inf always fail.
void check(double value, const std::string& key, double lo, double hi, Ends ends, std::string_view unit) {
  const bool lo_open = ends == Ends::Open || ends == Ends::OpenLow;
  const bool hi_open = ends == Ends::Open || ends == Ends::OpenHigh;
  const bool ok = std::isfinite(value) && (lo_open ? value > lo : value >= lo) &&
                  (hi == kInf || (hi_open ? value < hi : value <= hi));
  require(ok, key, "must be a finite number ", describe(lo, hi, ends), " [", unit, "], got ", value);
}

/// Any finite double (angles, signed errors).
void check_finite(double value, const std::string& key, std::string_view unit) {
  require(std::isfinite(value), key, "must be a finite number [", unit, "], got ", value);
}

void check_int(int value, const std::string& key, int lo, int hi) {
  require(value >= lo && value <= hi, key, "must be an integer in [", lo, ", ", hi, "], got ", value);
}

/// Message of an InputError without its "parameter: " prefix.
std::string bare_message(const InputError& e) {
  const std::string what = e.what();
  const std::string prefix = e.parameter() + ": ";
  if (!e.parameter().empty() && what.rfind(prefix, 0) == 0) return what.substr(prefix.size());
  return what;
}

void validate_gear(const geometry::GearSpec& gear, const std::string& section, geometry::GearKind kind) {
  require(gear.kind == kind, section, "must be ",
          kind == geometry::GearKind::External ? "an external" : "an internal", " gear");
  try {
    (void)geometry::make_geometry(gear);
  } catch (const InputError& e) {
    // make_geometry names the GearSpec field; the user wrote it under [stage.<gear>].
    throw InputError(section + "." + e.parameter(), bare_message(e));
  }
}

void validate_stage(const StageSpec& s) {
  validate_gear(s.sun, "stage.sun", geometry::GearKind::External);
  validate_gear(s.planet, "stage.planet", geometry::GearKind::External);
  validate_gear(s.ring, "stage.ring", geometry::GearKind::Internal);

  check_int(s.planet_count, "stage.planet_count", 1, 32);
  const auto n = static_cast<std::size_t>(s.planet_count);
  require(s.planet_angles_rad.empty() || s.planet_angles_rad.size() == n, "stage.planet_angles_rad",
          "must be empty (equal spacing) or list one angle per planet (stage.planet_count = ", s.planet_count,
          "), got ", s.planet_angles_rad.size(), " angles");
  for (std::size_t i = 0; i < s.planet_angles_rad.size(); ++i) {
    const double psi = s.planet_angles_rad[i];
    const std::string key = detail::concat("stage.planet_angles_rad[", i, "]");
    if (i == 0) {
      require(psi == 0.0, key, "planet angles are measured from planet 0, so the first must be 0 [rad], got ", psi);
    } else {
      check(psi, key, s.planet_angles_rad[i - 1], 2 * std::numbers::pi, Ends::Open,
            "rad; increasing, below 2 pi");
    }
  }
  check(s.carrier_inertia_kgm2, "stage.carrier_inertia_kgm2", 0, kInf, Ends::Closed, "kg m^2; 0 = derived");
  check(s.carrier_mass_kg, "stage.carrier_mass_kg", 0, kInf, Ends::Closed, "kg; 0 = derived");
  check(s.input_inertia_kgm2, "stage.input_inertia_kgm2", 0, kInf, Ends::Closed, "kg m^2");
  check(s.output_inertia_kgm2, "stage.output_inertia_kgm2", 0, kInf, Ends::Closed, "kg m^2");
  // The fillet-foundation compliance (Sainsot et al. 2004) is fitted for h_f = 1/bore_ratio in
  // [1.4, 7]; [0.15, 0.7] keeps inside it with round numbers (h_f 1.43 .. 6.67).
  check(s.bore_ratio, "stage.bore_ratio", 0.15, 0.7, Ends::Closed,
        "-; Sainsot's fillet-foundation fit covers bore / root radius 1/7 .. 1/1.4");
}

void validate_operating(const OperatingPoint& op) {
  check(op.input_speed_rpm, "operating.input_speed_rpm", 0, 1e5, Ends::OpenLow, "rpm");
  check(op.input_power_W, "operating.input_power_W", 0, 1e9, Ends::OpenLow, "W");
}

void validate_stiffness(const StiffnessSettings& st) {
  check_int(st.samples_per_pair, "stiffness.samples_per_pair", 16, 100000);
  check(st.scale, "stiffness.scale", 0, 1e3, Ends::OpenLow, "-");
}

void validate_contact(const ContactSettings& c, double module_m) {
  check(c.friction_coefficient, "contact.friction_coefficient", 0, 1, Ends::OpenHigh, "-");
  check(c.friction_smoothing_m_s, "contact.friction_smoothing_m_s", 0, 1, Ends::OpenLow, "m/s");
  check(c.mesh_damping_ratio, "contact.mesh_damping_ratio", 0, 1, Ends::Closed, "-");
  // Backlash and profile errors are fractions of a tooth; a module or more is
  // a unit mistake (mm typed as m), not a gear.
  check(c.backlash_sun_planet_m, "contact.backlash_sun_planet_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check(c.backlash_planet_ring_m, "contact.backlash_planet_ring_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check(c.mesh_error_sun_planet_m, "contact.mesh_error_sun_planet_m", -module_m, module_m, Ends::Open,
        "m; |e| below module");
  check(c.mesh_error_planet_ring_m, "contact.mesh_error_planet_ring_m", -module_m, module_m, Ends::Open,
        "m; |e| below module");
  check(c.tip_relief_m, "contact.tip_relief_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check(c.tip_relief_extent, "contact.tip_relief_extent", 0, 1, Ends::OpenLow, "-");
}

void validate_imperfections(const Imperfections& im, const StageSpec& stage) {
  const double module_m = stage.sun.module_m;
  require(im.pin_error_m.empty() || im.pin_error_m.size() == static_cast<std::size_t>(stage.planet_count),
          "imperfections.pin_error_m", "must be empty (no pin errors) or list one error per planet (",
          "stage.planet_count = ", stage.planet_count, "), got ", im.pin_error_m.size(), " values");
  for (std::size_t i = 0; i < im.pin_error_m.size(); ++i)
    check(im.pin_error_m[i], detail::concat("imperfections.pin_error_m[", i, "]"), -module_m, module_m, Ends::Open,
          "m; |e| below module");
  check(im.sun_eccentricity_m, "imperfections.sun_eccentricity_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check_finite(im.sun_eccentricity_phase_rad, "imperfections.sun_eccentricity_phase_rad", "rad");
  check(im.carrier_eccentricity_m, "imperfections.carrier_eccentricity_m", 0, module_m, Ends::OpenHigh,
        "m; below module");
  check_finite(im.carrier_eccentricity_phase_rad, "imperfections.carrier_eccentricity_phase_rad", "rad");
  check(im.torque_ripple_fraction, "imperfections.torque_ripple_fraction", 0, 1, Ends::OpenHigh, "-");
  check(im.torque_ripple_order, "imperfections.torque_ripple_order", 0, 1e3, Ends::OpenLow, "-");
  check(im.worn_profile_depth_m, "imperfections.worn_profile_depth_m", 0, module_m, Ends::OpenHigh,
        "m; below module");

  for (std::size_t i = 0; i < im.teeth.size(); ++i) {
    const ToothModifier& t = im.teeth[i];
    const std::string key = detail::concat("imperfections.teeth[", i, "]");
    const geometry::GearSpec* gear = nullptr;
    switch (t.body) {
    case Body::Sun: gear = &stage.sun; break;
    case Body::Planet: gear = &stage.planet; break;
    case Body::Ring: gear = &stage.ring; break;
    }
    require(gear != nullptr, key + ".body", "must be \"sun\", \"planet\" or \"ring\"");
    if (t.body == Body::Planet) {
      check_int(t.planet, key + ".planet", 0, stage.planet_count - 1);
    } else {
      require(t.planet == 0, key + ".planet", "only applies to body = \"planet\"; must be 0 for body = \"",
              body_name(t.body), "\", got ", t.planet);
    }
    check_int(t.tooth, key + ".tooth", 0, gear->teeth - 1);
    check(t.stiffness_factor, key + ".stiffness_factor", 0, 1, Ends::OpenLow, "-");
    check(t.profile_deviation_m, key + ".profile_deviation_m", 0, gear->module_m, Ends::OpenHigh,
          "m; below the module of that gear");
    for (std::size_t j = 0; j < i; ++j) {
      const ToothModifier& u = im.teeth[j];
      require(!(u.body == t.body && u.planet == t.planet && u.tooth == t.tooth), key,
              "modifies the same tooth as imperfections.teeth[", j, "] (body = \"", body_name(t.body),
              "\", planet = ", t.planet, ", tooth = ", t.tooth, "); merge them into one entry");
    }
  }
}

void validate_sensor(const SensorSettings& s) {
  check_finite(s.angle_rad, "sensor.angle_rad", "rad");
  // A gain of 1 m/s^2 per N or more would be a housing lighter than 1 kg.
  check(s.gain_m_s2_per_N, "sensor.gain_m_s2_per_N", 0, 1, Ends::OpenLow, "m/s^2 per N");
  require(s.window == SensorWindow::Gaussian || s.window == SensorWindow::Hann, "sensor.window",
          "must be \"gaussian\" or \"hann\"");
  // Above ~1.25 rad the Hann window (half-width sqrt(2 pi) sigma) would
  // overlap itself around the ring, and a Gaussian no longer localizes.
  check(s.window_width_rad, "sensor.window_width_rad", 0, kMaxSensorWindowWidth, Ends::OpenLow, "rad");
  check(s.encoder_bandwidth_Hz, "sensor.encoder_bandwidth_Hz", 0, kInf, Ends::OpenHigh, "Hz; 0 = ideal encoder");
  check_int(s.encoder_filter_order, "sensor.encoder_filter_order", 1, 2);
}

void validate_rig(const RigSettings& r, const StageSpec& st) {
  require(r.input_control == InputControl::Power || r.input_control == InputControl::Torque, "rig.input_control",
          "must be \"power\" or \"torque\"");
  require(r.load_control == LoadControl::Torque || r.load_control == LoadControl::Speed, "rig.load_control",
          "must be \"torque\" or \"speed\"");
  check(r.input_shaft_stiffness_N_m_rad, "rig.input_shaft_stiffness_N_m_rad", 0, kInf, Ends::OpenHigh,
        "N m/rad; 0 = rigid");
  check(r.input_shaft_damping_N_m_s_rad, "rig.input_shaft_damping_N_m_s_rad", 0, kInf, Ends::OpenHigh, "N m s/rad");
  check(r.output_shaft_stiffness_N_m_rad, "rig.output_shaft_stiffness_N_m_rad", 0, kInf, Ends::OpenHigh,
        "N m/rad; 0 = rigid");
  check(r.output_shaft_damping_N_m_s_rad, "rig.output_shaft_damping_N_m_s_rad", 0, kInf, Ends::OpenHigh,
        "N m s/rad");
  // A shaft needs a body at its far end: a massless motor behind a spring would
  // leave the spring's far end undetermined.
  require(r.input_shaft_stiffness_N_m_rad == 0 || st.input_inertia_kgm2 > 0, "rig.input_shaft_stiffness_N_m_rad",
          "= ", r.input_shaft_stiffness_N_m_rad, " N m/rad puts the motor behind a shaft, so the motor needs an "
          "inertia: set stage.input_inertia_kgm2 > 0, or the shaft stiffness to 0 (rigid)");
  require(r.input_shaft_damping_N_m_s_rad == 0 || r.input_shaft_stiffness_N_m_rad > 0,
          "rig.input_shaft_damping_N_m_s_rad", "needs a flexible input shaft (rig.input_shaft_stiffness_N_m_rad > 0)");
  require(r.output_shaft_damping_N_m_s_rad == 0 || r.output_shaft_stiffness_N_m_rad > 0,
          "rig.output_shaft_damping_N_m_s_rad",
          "needs a flexible output shaft (rig.output_shaft_stiffness_N_m_rad > 0)");
  if (r.load_control == LoadControl::Speed) {
    require(r.output_shaft_stiffness_N_m_rad > 0, "rig.output_shaft_stiffness_N_m_rad",
            "must be > 0 with rig.load_control = \"speed\" (an ideally speed-controlled machine rigidly attached "
            "would hold the carrier still in the rotating frame)");
  } else {
    require(r.output_shaft_stiffness_N_m_rad == 0 || st.output_inertia_kgm2 > 0,
            "rig.output_shaft_stiffness_N_m_rad", "= ", r.output_shaft_stiffness_N_m_rad,
            " N m/rad puts the load machine behind a shaft, so it needs an inertia: set stage.output_inertia_kgm2 "
            "> 0, or rig.load_control = \"speed\", or the shaft stiffness to 0 (rigid)");
  }
}

void validate_bearings(const BearingSettings& b) {
  check(b.sun_N_m, "bearings.sun_N_m", 0, kInf, Ends::OpenLow, "N/m");
  check(b.carrier_N_m, "bearings.carrier_N_m", 0, kInf, Ends::OpenLow, "N/m");
  check(b.ring_N_m, "bearings.ring_N_m", 0, kInf, Ends::OpenLow, "N/m");
  check(b.planet_N_m, "bearings.planet_N_m", 0, kInf, Ends::OpenLow, "N/m");
  check(b.ring_torsional_N_m, "bearings.ring_torsional_N_m", 0, kInf, Ends::OpenLow, "N/m");
}

void validate_solver(const SolverSettings& s, const SimulationConfig& c) {
  require(s.level == ModelLevel::Torsional || s.level == ModelLevel::LateralTorsional, "solver.level",
          "must be \"torsional\" or \"lateral_torsional\"");
  // Mesh frequency with the ring fixed: f_m = Zs Zr / (Zs + Zr) * n_s / 60.
  const double zs = c.stage.sun.teeth;
  const double zr = c.stage.ring.teeth;
  const double mesh_period_s = 60.0 / (zs * zr / (zs + zr) * c.operating.input_speed_rpm);
  check(s.time_step_s, "solver.time_step_s", 0, mesh_period_s / 8, Ends::Closed,
        detail::concat("s; 0 = automatic, else at most 1/8 of the mesh period ", mesh_period_s, " s"));
  check_int(s.min_steps_per_mesh, "solver.min_steps_per_mesh", 8, 1000000);
  check_int(s.steps_per_mode_period, "solver.steps_per_mode_period", 8, 1000000);
  check(s.newmark_beta, "solver.newmark_beta", 0, 0.5, Ends::OpenLow, "-");
  check(s.newmark_gamma, "solver.newmark_gamma", 0.5, 1, Ends::Closed, "-");
  check(s.newton_tolerance, "solver.newton_tolerance", 0, 1e-2, Ends::OpenLow, "-");
  check_int(s.newton_max_iterations, "solver.newton_max_iterations", 1, 1000);
  check_int(s.warmup_max_mesh_cycles, "solver.warmup_max_mesh_cycles", 1, 1000000);
  check(s.periodicity_tolerance, "solver.periodicity_tolerance", 0, 1e-1, Ends::OpenLow, "-");
  check_int(s.record_mesh_cycles, "solver.record_mesh_cycles", 1, 1000000);
}

void validate_wear(const WearSettings& w) {
  // mesh_cycles first: 0 is a meaning (no wear), not a lower bound to report as a range.
  require(std::isfinite(w.mesh_cycles), "wear.mesh_cycles", "must be a finite number of mesh cycles [-], got ",
          w.mesh_cycles);
  require(w.mesh_cycles >= 0, "wear.mesh_cycles", "must be >= 0 (0 = no wear) [-], got ", w.mesh_cycles);
  require(w.mesh_cycles <= kMaxWearMeshCycles, "wear.mesh_cycles", "must be at most ", kMaxWearMeshCycles,
          " [-], got ", w.mesh_cycles);
  // kappa = K/H: mild-wear steel is 1e-18..1e-14 m^2/N; 1e-10 and above is a
  // unit mistake (mm^2/N typed as m^2/N is a factor 1e6 too large).
  check(w.coefficient_m2_N, "wear.coefficient_m2_N", 0, kMaxWearCoefficient, Ends::OpenHigh, "m^2/N");
  check(w.archard_K, "wear.archard_K", 0, 1, Ends::OpenHigh, "-");
  check(w.hardness_Pa, "wear.hardness_Pa", 0, kInf, Ends::OpenLow, "Pa");
  require(w.archard_K / w.hardness_Pa < kMaxWearCoefficient, "wear.archard_K",
          "gives kappa = archard_K / hardness_Pa = ", w.archard_K / w.hardness_Pa, " m^2/N, must be below ",
          kMaxWearCoefficient, " m^2/N (the limit of wear.coefficient_m2_N); got archard_K = ", w.archard_K,
          ", hardness_Pa = ", w.hardness_Pa);
  require(w.elements_per_flank >= 2 && w.elements_per_flank <= 10000, "wear.elements_per_flank",
          "must be an integer in [2, 10000], got ", w.elements_per_flank,
          " (element counts < 2 cannot resolve a wear profile)");
  check_int(w.window_mesh_cycles, "wear.window_mesh_cycles", 0, 1000000);
  check(w.max_increment_fraction, "wear.max_increment_fraction", 0, 1, Ends::OpenLow, "-");
  check(w.max_wear_fraction_of_thickness, "wear.max_wear_fraction_of_thickness", 0, 0.5, Ends::OpenLow, "-");
  check_int(w.snapshot_record_mesh_cycles, "wear.snapshot_record_mesh_cycles", 1, 100000);
  for (std::size_t i = 0; i < w.snapshot_mesh_cycles.size(); ++i)
    check(w.snapshot_mesh_cycles[i], detail::concat("wear.snapshot_mesh_cycles[", i, "]"), 0, w.mesh_cycles,
          Ends::Closed, "-; at most wear.mesh_cycles");
}

} // namespace

void validate(const SimulationConfig& c) {
  // Order matters only for which error a config with several mistakes reports
  // first: gears before everything that depends on their teeth and module.
  validate_stage(c.stage);
  validate_operating(c.operating);
  validate_stiffness(c.stiffness);
  validate_contact(c.contact, c.stage.sun.module_m);
  validate_imperfections(c.imperfections, c.stage);
  validate_bearings(c.bearings);
  validate_solver(c.solver, c);
  validate_wear(c.wear);
  validate_sensor(c.sensor);
  validate_rig(c.rig, c.stage);
}

} // namespace pw::model
