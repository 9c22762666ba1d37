// The library of candidate model extensions (docs/diagnose.md §4). Each
// candidate is real physics the model already knows how to simulate, with a
// few parameters that the diagnosis fits; it declares
//   * its name and one sentence of physics,
//   * the line families (kinematics.hpp) it can explain,
//   * its parameters: name, unit, bounds, natural scale (log or linear), start,
//   * its discrete variants (which tooth, which planet, which ripple order),
//     proposed from the located evidence,
//   * how it writes a parameter vector into a SimulationConfig, with the
//     equivalent `--set key=value` overrides for the report.
// Adding a candidate = one new file in this folder defining a Candidate and
// one line in the table of registry.cpp.
#pragma once

#include "config/stage.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/recording.hpp"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pw::diagnose {

/// The configuration keys of the mesh stiffness and damping levels: the stiffness_level and
/// damping_level candidates' parameters, and what a nuisance fit absorbs a change of the tooth
/// contacts into (verdict.hpp, untested_level_moves).
inline constexpr const char* kStiffnessLevelKey = "stiffness.scale";
inline constexpr const char* kDampingLevelKey = "contact.mesh_damping_ratio";

/// One continuous parameter of a candidate.
struct ParameterSpec {
  std::string name;   ///< e.g. "stiffness_factor"
  std::string unit;   ///< SI unit or "1"
  double lower = 0, upper = 1;  ///< bounds (the LM box)
  bool log_scale = false;       ///< normalize as log(x) (requires lower > 0)
  double initial = 0;           ///< start value (inside the bounds)
  /// Screening (docs/diagnose.md §4): the value at which the candidate has no
  /// effect (the nuisance-fitted model) and a value with a moderate effect;
  /// the secant between them is its direction in the residual space.
  double null_value = 0;
  double screen_value = 0;
  /// The effect stops changing beyond some value (a backlash wider than the teeth ever
  /// separate behaves like an infinite one): above it the value is not identifiable, its
  /// standard error is meaningless and "absent" is tested by likelihood ratio instead of
  /// Wald; the report gives the smallest value that fits as well (docs/diagnose.md §5).
  bool saturates = false;
  /// chi2 is far from quadratic in it (it moves a resonance through the lines, as a rig shaft's
  /// stiffness does): fitted as nuisance, its start is the best of a coarse scan over its box
  /// (nuisance_start.hpp), not a local step from 'absent' or its screening value.
  bool scan_at_start = false;
  /// With scan_at_start: the largest ratio between neighbouring points of that scan (log scale),
  /// so that no basin narrower than the coarse grid's spacing is stepped over (a shaft's mode has
  /// a basin per line about as wide as its half-power band). 0: the coarse grid of
  /// kNuisanceScanPoints points (nuisance_start.hpp).
  double scan_step_ratio = 0;
  /// With scan_at_start on a linear scale (log_scale false): the spacing of that scan's uniform
  /// grid from lower to upper [the parameter's unit]. 0: kNuisanceScanPoints points.
  double scan_step = 0;
  /// Non-zero: while the parameter before it is scanned (scan_at_start), this one moves with it
  /// as x = x_start (p / p_start)^power, p the scanned value. A shaft's damping follows its
  /// stiffness with power 1/2 (c = 2 zeta sqrt(k J)), so the scan sees the mode at the damping
  /// ratio the scan's step assumes, not ever lighter as the stiffness grows.
  double scan_follows_previous_power = 0;
  /// How the candidate's excitation reaches the sensors rather than the excitation itself: a rig
  /// property the healthy recordings cannot calibrate because only this physics excites it (the
  /// load machine's inertia, which splits an input torque ripple between the speeds and the mesh
  /// forces). Fitted with the candidate; never what makes it differ from 'absent' (a candidate
  /// with one is tested against 'absent' by likelihood ratio, with this parameter held at its fitted
  /// value: CandidateResult::null_chi2_fit) and never its size.
  bool transfer = false;
  /// Non-empty: the fitted value is the size only for a rig element the configuration leaves at
  /// the model's idealization, and a real value of that element rescales it (how a ripple reads
  /// in the speeds is set by the input machine's inertia and control law: without the motor's
  /// inertia, the fitted fraction is the one the configured input would need). Names what the size
  /// is conditional on, for the report; the fit, the tests and the verdict are unchanged.
  std::string size_conditional_on = {};
};

/// A class of findings whose members describe one physical state at the level a recording
/// resolves: when the data do not tell the lead from another member within the model's fidelity,
/// the class is named instead of neither (verdict.hpp, "class finding"). Every member maps its
/// parameters onto the canonical member's (Candidate::start_from), which states the class's size.
struct FindingClass {
  std::string name;       ///< what a class finding reports, e.g. "planet_position_error"
  std::string physics;    ///< what the members share, one sentence
  std::string canonical;  ///< the member whose parameters describe the class (e.g. "pin_error"); empty: none
  /// Every physics the class stands for (candidate names, the nuisance levels included): what a
  /// class finding asserts one of is there, so a recording of any of them is rightly named by it.
  std::vector<std::string> covers;
};

/// What locate() found, as far as candidates need it to propose variants.
struct LocatedEvidence {
  /// Per family (indexed by Component): excess chi-square z-score of its cells.
  double family_z[5] = {0, 0, 0, 0, 0};
  /// Input-shaft orders (multiples of f_s) with the largest excess, strongest first.
  std::vector<double> input_orders;
  /// Angles of the recording's housing accelerometers [rad] (ring-tooth variants
  /// are placed relative to them: the transfer path makes a ring tooth near a
  /// sensor louder than one far from it).
  std::vector<double> housing_sensor_angles_rad;
};

/// A discrete choice within a candidate.
struct Variant {
  std::string label;  ///< e.g. "sun tooth 5"
  model::Body body = model::Body::Sun;
  int planet = 0;
  int tooth = 0;
  double order = 0;
  /// false: the amplitudes cannot tell which tooth; the label names none, and the `--set` line
  /// only where the index matters to reproduce the fit (a phase other than tooth 0's).
  bool tooth_identifiable = true;
};

class Candidate {
public:
  virtual ~Candidate() = default;
  virtual std::string name() const = 0;
  virtual std::string physics() const = 0;
  virtual std::vector<Component> families() const = 0;
  /// Nuisance: fitted first, before any candidate, and kept in every fit.
  virtual bool nuisance() const { return false; }
  /// Fitted only as a rig element a calibration asks for (`calibrate --rig-elements`, then
  /// recalibrated by the diagnoses that use it), never screened as a finding: its box does not
  /// reach a value without effect ('absent' is only its softest end), so "it improves on the
  /// model without it" cannot be tested.
  virtual bool calibration_only() const { return false; }
  /// A calibration-only element that a diagnosis keeps at its calibrated value instead of
  /// refitting it: a property of the gears' stiffness law, which no fault changes, and too many
  /// parameters to carry through every fit of every candidate.
  virtual bool held_after_calibration() const { return false; }
  /// A property of the rig's design (an encoder's bandwidth, a machine's inertia, the gears' tip
  /// relief) rather than something that changes in service. Under a calibration it is not
  /// screened as a finding: the healthy recordings the calibration was made on carry the same
  /// design, so it is either one of the calibration's rig elements or part of its discrepancy,
  /// never a change since (docs/diagnose.md §6a item 5).
  virtual bool rig_design() const { return false; }
  virtual std::vector<ParameterSpec> parameters(const model::SimulationConfig& base) const = 0;
  /// Discrete variants to screen, most likely first (default: one).
  virtual std::vector<Variant> variants(const LocatedEvidence& evidence, const model::SimulationConfig& base,
                                        const ToothMap& teeth) const;
  /// Variants that differ from `chosen` only in a phase the amplitudes cannot
  /// see directly but the beats inside a short window (which tooth) or the
  /// housing sensor's transfer path (where a ring tooth is) can; the winner's
  /// are screened at its fitted parameters (default: none). When they trade off
  /// against the parameters (phase_trades_with_parameters), they are listed in order
  /// round the gear, starting next to `chosen` and ending next to it again (a closed
  /// path through `chosen`): the screening follows local minima along it.
  virtual std::vector<Variant> phase_variants(const Variant& chosen, const LocatedEvidence& evidence,
                                              const model::SimulationConfig& base, const ToothMap& teeth) const {
    (void)chosen, (void)evidence, (void)base, (void)teeth;
    return {};
  }
  /// The phase variants trade off against the parameters (a ring tooth far from the sensor
  /// sounds like a milder one near it): screen each with its parameters profiled (Gauss-Newton
  /// steps from the winner's values), not at the winner's values (docs/diagnose.md §5 step 11).
  virtual bool phase_trades_with_parameters() const { return false; }
  /// Writes parameters x (physical units, one per parameters()) into config;
  /// appends the equivalent "key=value" overrides to `overrides` if given.
  virtual void apply(model::SimulationConfig& config, const Variant& variant, std::span<const double> x,
                     std::vector<std::string>* overrides = nullptr) const = 0;
  /// Parameters that change only the housing-sensor channels (no new simulation needed).
  virtual bool sensor_only() const { return false; }
  /// Acts on every planet alike (a contact property, a mesh level, the input torque): by the
  /// planets' mesh phasing it changes the speed channels' mesh harmonics of pattern order k = 0
  /// alone (planet_pattern.hpp), whatever the stiffness law, so it cannot make an excess at k >= 1.
  virtual bool every_planet_alike() const { return false; }
  /// Whether the parameters change the model of configuration `base` at all (default: yes). A
  /// machine's inertia behind a shaft whose far end an ideal speed control holds does not: a fit
  /// of it would be flat, and the screening leaves it out.
  virtual bool acts_on(const model::SimulationConfig& base) const {
    (void)base;
    return true;
  }
  /// Whether `recording` has a channel this candidate's parameters change (default: every
  /// channel does). A calibration leaves out rig elements its recordings cannot see.
  virtual bool observable_in(const Recording& recording) const {
    (void)recording;
    return true;
  }
  /// Start values equivalent to another candidate's fitted parameters `other_x` when the
  /// two are near-aliases of one physics (pin errors and a carrier eccentricity: both
  /// displace the planet centres in the carrier); empty if there is no such mapping.
  virtual std::vector<double> start_from(const std::string& other, std::span<const double> other_x,
                                         const model::SimulationConfig& base) const {
    (void)other, (void)other_x, (void)base;
    return {};
  }
  /// The class of findings this candidate belongs to (none by default).
  virtual std::optional<FindingClass> finding_class() const { return std::nullopt; }
};

/// Planet carrier angles psi_i [rad] of the stage (equal spacing when not given).
std::vector<double> planet_angles_rad(const model::SimulationConfig& base);

/// The library, in a fixed order (registry.cpp).
const std::vector<std::unique_ptr<Candidate>>& candidate_library();
/// nullptr if no candidate has that name.
const Candidate* find_candidate(const std::string& name);

/// The planet centres displaced in the carrier: pin position errors and a carrier runout (a pin
/// pattern plus a radial part). The canonical member is pin_error (tangential offsets relative to
/// planet 0), onto which a runout maps exactly for three planets and as a least-squares pattern
/// for more.
FindingClass planet_position_class();

/// The tooth contacts changed alike on every tooth: friction, profile wear or modification,
/// clearance, the mesh stiffness or damping level. Each changes the mesh harmonics alone; how
/// it shares the change among them is what tells them apart, and that is the shape the model's
/// stiffness law fixes (verdict.hpp, condition (e)). No canonical member: a friction
/// coefficient and a wear depth are not one size.
FindingClass tooth_contact_class();

/// The sun carries a defect that meets each planet once per sun-relative revolution: a damaged
/// tooth or a runout. Both put their lines in the sun family alone, in every channel; what tells
/// them apart is how the change is shared among the family's orders (a pulse spreads over many, an
/// eccentricity's sinusoid stays near the first), and that is the transfer the model's form fixes
/// (verdict.hpp, condition (e)). No canonical member: a stiffness factor and an eccentricity are
/// not one size.
FindingClass sun_defect_class();

/// The class of the candidate called `name`; nullopt if it has none or is not in the library.
std::optional<FindingClass> finding_class_of(const std::string& name);

/// True if the candidate's lines are the mesh harmonics alone (Component::Mesh only): two such
/// candidates differ only in how their change is shared among the harmonics and channels, the
/// shape the stiffness law fixes (verdict condition (e), docs/diagnose.md §5 step 10).
bool acts_on_mesh_harmonics_only(const Candidate& c);

/// The one family a candidate's lines lie in, when they lie in one alone (nullopt: several or none).
std::optional<Component> sole_family(const Candidate& c);

/// A double for override strings: the shortest text that reads back exactly (core/format.hpp).
std::string format_value(double v);

/// Writes `value` to the floating-point configuration key `key` (a key path of
/// the schema, config/schema.hpp: "contact.friction_coefficient") and, if
/// `overrides` is given, appends the `key=value` line (--set) that reproduces it.
/// The field and its --set line come from one name, so they cannot disagree.
/// Throws std::logic_error for a key the schema does not have (a programming error).
void set_parameter(model::SimulationConfig& c, std::string_view key, double value,
                   std::vector<std::string>* overrides);

} // namespace pw::diagnose
