// Range checks of a SimulationConfig: the single place where user input is
// validated (the configuration reader and the command-line overrides both end
// here). Every failure throws pw::InputError whose parameter() is the TOML key
// path ("operating.input_speed_rpm", "stage.sun.module_m",
// "imperfections.teeth[2].tooth") and whose message gives the value and the
// allowed range. The ranges are listed in docs/config.md.
//
// Each key's own range is stated in the schema (config/schema.hpp, config/range.hpp) and
// checked here by a visitor over it (RangeChecker); written out below are only the rules
// that involve other keys (or have a message of their own), each schema entry of kind
// Rule naming what is checked here.
//
// Not checked here (they need the mesh geometry): interference, contact ratio,
// the assembly condition and planet tip-circle clearance. Those are checked by
// geometry::make_stage_geometry() when the model is built.
#include "model/validate.hpp"

#include "config/schema.hpp"
#include "core/error.hpp"
#include "geometry/gear.hpp"
#include "model/sensor.hpp"

#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

namespace pw::model {
namespace {

constexpr double kMaxWearMeshCycles = 1e12;   ///< [-]
constexpr double kMaxWearCoefficient = config::kMaxWearCoefficient_m2_N;

using config::Ends;

/// A finite double inside [lo, hi] with the given ends: a range that depends on other keys
/// (the module, the mesh period), so it is built here rather than stated in the schema.
void check(double value, const std::string& key, double lo, double hi, Ends ends, std::string_view unit) {
  const config::Range r = config::interval(lo, hi, ends, unit);
  require(r.contains(value), key, "must be a finite number ", config::describe(r), " [", unit, "], got ", value);
}

void check_int(int value, const std::string& key, int lo, int hi) {
  require(value >= lo && value <= hi, key, "must be an integer in [", lo, ", ", hi, "], got ", value);
}

/// Checks every number against the range the schema states for it (intervals and "finite";
/// rules are checked by the functions below, with the keys they involve).
class RangeChecker {
public:
  void section(std::string_view path) { section_ = std::string(path); }
  template <class T>
  void field(std::string_view key, const T& value, std::string_view /*doc*/, const config::Range& range = {}) {
    if (range.kind != config::RangeKind::Interval && range.kind != config::RangeKind::Finite) return;
    static_assert(std::is_same_v<T, int> || std::is_same_v<T, double> || std::is_same_v<T, std::vector<double>> ||
                      std::is_same_v<T, bool> || std::is_enum_v<T>,
                  "a new value type needs its range check here");
    const std::string path = section_ + "." + std::string(key);
    if constexpr (std::is_same_v<T, int>) {
      require(range.contains(value), path, "must be an integer ", config::describe(range), ", got ", value);
    } else if constexpr (std::is_same_v<T, std::vector<double>>) {
      for (std::size_t i = 0; i < value.size(); ++i) number(detail::concat(path, "[", i, "]"), value[i], range);
    } else if constexpr (std::is_same_v<T, double>) {
      number(path, value, range);
    }
  }
  void angle(std::string_view key_rad, std::string_view /*key_deg*/, const double& value_rad, std::string_view doc,
             const config::Range& range = {}) {
    field(key_rad, value_rad, doc, range);
  }
  void teeth(std::string_view key, const std::vector<ToothModifier>& teeth, std::string_view /*doc*/) {
    const std::string outer = section_;
    for (std::size_t i = 0; i < teeth.size(); ++i) {
      section_ = detail::concat(outer, ".", key, "[", i, "]");
      config::visit_tooth(*this, teeth[i]);
    }
    section_ = outer;
  }

private:
  static void number(const std::string& path, double value, const config::Range& range) {
    if (range.kind == config::RangeKind::Finite)
      require(range.contains(value), path, "must be a finite number [", range.note, "], got ", value);
    else
      require(range.contains(value), path, "must be a finite number ", config::describe(range), " [", range.note,
              "], got ", value);
  }

  std::string section_;
};

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
}

void validate_contact(const ContactSettings& c, double module_m) {
  // Backlash and profile errors are fractions of a tooth; a module or more is
  // a unit mistake (mm typed as m), not a gear.
  check(c.backlash_sun_planet_m, "contact.backlash_sun_planet_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check(c.backlash_planet_ring_m, "contact.backlash_planet_ring_m", 0, module_m, Ends::OpenHigh, "m; below module");
  check(c.mesh_error_sun_planet_m, "contact.mesh_error_sun_planet_m", -module_m, module_m, Ends::Open,
        "m; |e| below module");
  check(c.mesh_error_planet_ring_m, "contact.mesh_error_planet_ring_m", -module_m, module_m, Ends::Open,
        "m; |e| below module");
  check(c.tip_relief_m, "contact.tip_relief_m", 0, module_m, Ends::OpenHigh, "m; below module");
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
  check(im.carrier_eccentricity_m, "imperfections.carrier_eccentricity_m", 0, module_m, Ends::OpenHigh,
        "m; below module");
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

void validate_sensor(const SensorSettings& s, double largest_gain_m_s2_per_N, ModelLevel level) {
  require(s.window == SensorWindow::Gaussian || s.window == SensorWindow::Hann, "sensor.window",
          "must be \"gaussian\" or \"hann\"");
  require(s.housing_path == HousingPath::PlanetPass || s.housing_path == HousingPath::RingTranslation ||
              s.housing_path == HousingPath::RingBody,
          "sensor.housing_path", "must be \"planet_pass\", \"ring_translation\" or \"ring_body\"");
  // The torsional model's ring is fixed: it has no translation to read.
  require(s.housing_path != HousingPath::RingBody || level == ModelLevel::LateralTorsional, "sensor.housing_path",
          "\"ring_body\" reads the ring's translation, which only solver.level = \"lateral_torsional\" has; with "
          "solver.level = \"torsional\" use \"planet_pass\" or \"ring_translation\"");
  require(s.housing_mount_frequency_Hz >= 0 && std::isfinite(s.housing_mount_frequency_Hz),
          "sensor.housing_mount_frequency_Hz", "must be >= 0 Hz (0 = no mount resonance), got ",
          s.housing_mount_frequency_Hz);
  require(s.gain_m_s2_per_N > 0 && std::isfinite(s.gain_m_s2_per_N), "sensor.gain_m_s2_per_N",
          "must be > 0 m/s^2 per N, got ", s.gain_m_s2_per_N);
  // The unit-mistake bound is on what the accelerometer hears: the gain through the mount
  // (largest_housing_gain_m_s2_per_N).
  if (s.housing_mount_frequency_Hz > 0)
    require(s.gain_m_s2_per_N <= largest_gain_m_s2_per_N, "sensor.gain_m_s2_per_N",
            "must be at most ", largest_gain_m_s2_per_N, " m/s^2 per N with sensor.housing_mount_frequency_Hz = ",
            s.housing_mount_frequency_Hz, " Hz (through the mount at the mesh frequency that is ",
            config::kMaxSensorGain_m_s2_per_N,
            " m/s^2 per N, an effective mass of 1 g; above it is a unit mistake), got ", s.gain_m_s2_per_N);
  else
    require(s.gain_m_s2_per_N <= largest_gain_m_s2_per_N, "sensor.gain_m_s2_per_N", "must be in (0, ",
            largest_gain_m_s2_per_N, "] m/s^2 per N (an effective mass of 1 g; above it is a unit mistake), got ",
            s.gain_m_s2_per_N);
}

/// A speed loop's two gains: both > 0 when `loop`, else both 0 (a gain without its loop would be
/// ignored). `control` names the key that selects the loop.
void require_loop_gains(bool loop, const char* control, std::initializer_list<std::pair<const char*, double>> gains) {
  for (const auto& [key, gain] : gains) {
    if (loop)
      require(gain > 0, key, "must be > 0 with ", control, " = \"speed_loop\" (got ", gain, ")");
    else
      require(gain == 0, key, "= ", gain, " acts only with ", control, " = \"speed_loop\": set that, or the gain to 0");
  }
}

void validate_rig(const RigSettings& r, const StageSpec& st) {
  require(r.input_control == InputControl::Power || r.input_control == InputControl::Torque ||
              r.input_control == InputControl::Speed || r.input_control == InputControl::SpeedLoop,
          "rig.input_control", "must be \"power\", \"torque\", \"speed\" or \"speed_loop\"");
  require(r.load_control == LoadControl::Torque || r.load_control == LoadControl::Speed ||
              r.load_control == LoadControl::SpeedLoop,
          "rig.load_control", "must be \"torque\", \"speed\" or \"speed_loop\"");
  // A shaft needs a body at its far end: a massless motor behind a spring would
  // leave the spring's far end undetermined.
  // (Under ideal input speed control the motor's far end of the shaft turns at the set speed
  // whatever its inertia.)
  require(r.input_shaft_stiffness_N_m_rad == 0 || r.input_control == InputControl::Speed || st.input_inertia_kgm2 > 0,
          "rig.input_shaft_stiffness_N_m_rad", "= ", r.input_shaft_stiffness_N_m_rad,
          " N m/rad puts the motor behind a shaft, so the motor needs an inertia: set stage.input_inertia_kgm2 > 0, "
          "or rig.input_control = \"speed\", or the shaft stiffness to 0 (rigid)");
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
  // A loop's gains act only under its control mode; a gain set without it would be silently
  // ignored, so it is an error. Under a loop both are needed: without K_i the mean speed
  // would sag by the friction losses / K_p (no integral action), without K_p the loop is an
  // undamped spring.
  require_loop_gains(r.load_control == LoadControl::SpeedLoop, "rig.load_control",
                     {{"rig.load_speed_loop_proportional_N_m_s_rad", r.load_speed_loop_proportional_N_m_s_rad},
                      {"rig.load_speed_loop_integral_N_m_rad", r.load_speed_loop_integral_N_m_rad}});
  require_loop_gains(r.input_control == InputControl::SpeedLoop, "rig.input_control",
                     {{"rig.input_speed_loop_proportional_N_m_s_rad", r.input_speed_loop_proportional_N_m_s_rad},
                      {"rig.input_speed_loop_integral_N_m_rad", r.input_speed_loop_integral_N_m_rad}});
  // Ideal input speed control holds the sun through its shaft, as the load's holds the carrier.
  if (r.input_control == InputControl::Speed)
    require(r.input_shaft_stiffness_N_m_rad > 0, "rig.input_shaft_stiffness_N_m_rad",
            "must be > 0 with rig.input_control = \"speed\" (an ideally speed-controlled motor rigidly attached "
            "would hold the sun still in the rotating frame)");
  // One machine holds the speed, the other the torque: two speed references at the kinematic
  // ratio over a stiff train would leave the torque between them undetermined by the controls.
  const bool input_holds = r.input_control == InputControl::Speed || r.input_control == InputControl::SpeedLoop;
  const bool load_holds = r.load_control == LoadControl::Speed || r.load_control == LoadControl::SpeedLoop;
  require(!(input_holds && load_holds), "rig.load_control",
          "must be \"torque\" when rig.input_control holds the speed (\"speed\" or \"speed_loop\"): one machine "
          "holds the speed, the other the load");
}

void validate_solver(const SolverSettings& s, const SimulationConfig& c) {
  require(s.level == ModelLevel::Torsional || s.level == ModelLevel::LateralTorsional, "solver.level",
          "must be \"torsional\" or \"lateral_torsional\"");
  const double mesh_period_s = 1.0 / mesh_frequency_Hz(c.stage, c.operating.input_speed_rpm);
  check(s.time_step_s, "solver.time_step_s", 0, mesh_period_s / 8, Ends::Closed,
        detail::concat("s; 0 = automatic, else at most 1/8 of the mesh period ", mesh_period_s, " s"));
}

void validate_wear(const WearSettings& w) {
  // mesh_cycles first: 0 is a meaning (no wear), not a lower bound to report as a range.
  require(std::isfinite(w.mesh_cycles), "wear.mesh_cycles", "must be a finite number of mesh cycles [-], got ",
          w.mesh_cycles);
  require(w.mesh_cycles >= 0, "wear.mesh_cycles", "must be >= 0 (0 = no wear) [-], got ", w.mesh_cycles);
  require(w.mesh_cycles <= kMaxWearMeshCycles, "wear.mesh_cycles", "must be at most ", kMaxWearMeshCycles,
          " [-], got ", w.mesh_cycles);
  require(w.archard_K / w.hardness_Pa < kMaxWearCoefficient, "wear.archard_K",
          "gives kappa = archard_K / hardness_Pa = ", w.archard_K / w.hardness_Pa, " m^2/N, must be below ",
          kMaxWearCoefficient, " m^2/N (the limit of wear.coefficient_m2_N); got archard_K = ", w.archard_K,
          ", hardness_Pa = ", w.hardness_Pa);
  require(w.elements_per_flank >= 2 && w.elements_per_flank <= 10000, "wear.elements_per_flank",
          "must be an integer in [2, 10000], got ", w.elements_per_flank,
          " (element counts < 2 cannot resolve a wear profile)");
  for (std::size_t i = 0; i < w.snapshot_mesh_cycles.size(); ++i)
    check(w.snapshot_mesh_cycles[i], detail::concat("wear.snapshot_mesh_cycles[", i, "]"), 0, w.mesh_cycles,
          Ends::Closed, "-; at most wear.mesh_cycles");
}

} // namespace

double largest_housing_gain_m_s2_per_N(const SimulationConfig& c) {
  return config::kMaxSensorGain_m_s2_per_N /
         housing_transfer_gain(1.0, c.sensor.housing_mount_frequency_Hz,
                               mesh_frequency_Hz(c.stage, c.operating.input_speed_rpm),
                               c.sensor.housing_mount_damping_ratio);
}

void validate(const SimulationConfig& c) {
  // Order matters only for which error a config with several mistakes reports first.
  // Every key's own range (the schema) first: the rules below read other keys (the planet
  // count, the module, the mesh period) and need them in range.
  RangeChecker ranges;
  config::visit_config(ranges, c);
  validate_stage(c.stage);  // the gears, before everything that depends on their teeth and module
  validate_contact(c.contact, c.stage.sun.module_m);
  validate_imperfections(c.imperfections, c.stage);
  validate_solver(c.solver, c);
  validate_wear(c.wear);
  validate_sensor(c.sensor, largest_housing_gain_m_s2_per_N(c), c.solver.level);
  validate_rig(c.rig, c.stage);
}

} // namespace pw::model
