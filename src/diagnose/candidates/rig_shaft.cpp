// Rig elements: a machine behind a flexible shaft at either end of the stage. On a test rig
// the motor drives the sun and the carrier drives a load machine (a dynamometer) through
// shafts and couplings; the machines are far heavier than the gears, and a dynamometer's speed
// loop is far slower than the mesh (a few hertz), so at the analysed frequencies each end is a
// torsional spring to a body that hardly moves. The shaft then makes a mode of the sun (input)
// or the carrier (output) on it: below it the body follows the machine, near it the body's
// speed lines resonate, far above it the body is free, as in the gear-set model alone. A
// rigidly coupled inertia (rig_inertia.cpp) has the first regime only, an encoder's low-pass
// (encoder_bandwidth.cpp) neither.
//
// Measured on the independent simulator's seed-gear rig (docs/diagnose-log.md, session 17),
// before these elements existed: the machines' true inertias rigidly coupled left 4.3e7 of a
// healthy recording's chi2, the same machines behind their true shafts 5.2e6.
//
// Two parameters, the shaft's keys (so a calibration's medians are configuration values):
//   * the torsional stiffness k [N m/rad], log scale, bounded through the frequency of the body
//     on it, f = sqrt(k / J_b) / (2 pi), J_b the body's own inertia (rig_body.hpp): from f_m / 4
//     to 30 f_m (the body locked to the machine up to the 20th mesh harmonic; a higher mode would
//     only shorten the time step: at 400 rpm 30 f_m is 3.3 kHz for the seed stage, below its
//     stiffest mode); screening value: the mode on the mesh frequency;
//   * the viscous damping c [N m s/rad], log scale, from a modal damping ratio of 5 % at the
//     softest shaft to 100 % at the stiffest (c = 2 zeta sqrt(k J_b)); screening value: 5 % at
//     the screening stiffness (contact.mesh_damping_ratio's default).
// Why the softest end is f_m / 4 at 5 %, not a value without effect: a mode far below the mesh
// frequency, lightly damped, behind a speed source decays over tens of seconds, and every
// simulation's warm-up waits for it (a four-planet baseline at 100 rpm with the box reaching
// f_m / 100 at 1 %: one simulation ran > 10 min, another recorded 1 % of a carrier revolution).
// So the box has no 'absent' value (its bottom still moves the body's response at f_m by about
// (1/4)^2 = 6 %), and the element is calibration-only (Candidate::calibration_only): fitted as a
// rig element, never screened as a finding.
// The machine's inertia is the configured one (stage.input_inertia_kgm2 or
// stage.output_inertia_kgm2, e.g. a calibrated one) or, when the configuration states none, a
// speed source: kSpeedSourceOfOwnInertia J_b, written with the shaft's keys. Use it instead
// of motor_inertia / load_inertia, not beside them.
#include "diagnose/candidates/factories.hpp"
#include "diagnose/candidates/rig_body.hpp"

#include "core/constants.hpp"

#include <algorithm>
#include <cmath>

namespace pw::diagnose::candidates {
namespace {

constexpr double kSoftestModeInMeshFrequencies = 0.25;
constexpr double kTopModeInMeshFrequencies = 30.0;
constexpr double kScreenModeInMeshFrequencies = 1.0;
constexpr double kLowestDampingRatio = 0.05;
constexpr double kHighestDampingRatio = 1.0;
constexpr double kScreenDampingRatio = 0.05;

/// Shaft stiffness [N m/rad] that puts a body of inertia J [kg m^2] on it at f [Hz].
double stiffness_for_mode(double f_Hz, double J) {
  const double w = 2 * kPi * f_Hz;
  return J * w * w;
}
/// Viscous damping [N m s/rad] of modal damping ratio zeta for that body on a shaft of stiffness k.
double damping_for_ratio(double zeta, double k, double J) { return 2 * zeta * std::sqrt(k * J); }

class RigShaft final : public Candidate {
public:
  explicit RigShaft(RigEnd end) : end_(end) {}
  std::string name() const override { return end_ == RigEnd::Input ? "input_shaft" : "output_shaft"; }
  std::string physics() const override {
    return end_ == RigEnd::Input
               ? "the motor drives the sun through a flexible shaft: a torsional mode of the sun on that shaft that "
                 "the model lacks, which holds the sun below the mode and resonates near it"
               : "the carrier drives the load machine through a flexible shaft: a torsional mode of the carrier on "
                 "that shaft that the model lacks, which holds the carrier below the mode and resonates near it";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool calibration_only() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double J = own_inertia_kgm2(b, end_);
    const double fm = model::mesh_frequency_Hz(b.stage, b.operating.input_speed_rpm);
    const double k_lo = stiffness_for_mode(kSoftestModeInMeshFrequencies * fm, J);
    const double k_hi = stiffness_for_mode(kTopModeInMeshFrequencies * fm, J);
    const double k_screen = stiffness_for_mode(kScreenModeInMeshFrequencies * fm, J);
    const double c_lo = damping_for_ratio(kLowestDampingRatio, k_lo, J);
    const double c_hi = damping_for_ratio(kHighestDampingRatio, k_hi, J);
    const double c_screen = damping_for_ratio(kScreenDampingRatio, k_screen, J);
    ParameterSpec k = spec(key_stiffness(), "N m/rad", k_lo, k_hi, k_screen, configured(b).first);
    // The mode moves through the lines: chi2 has a basin per line, about as wide as the mode's
    // half-power band f (1 +- zeta), i.e. a ratio (1 + 2 zeta) in f and its square in k ~ f^2 at
    // the screening damping ratio, which the damping keeps during the scan (it follows the
    // stiffness). A scan stepping by that ratio cannot step over a basin; the box's 7 coarse
    // points stepped by 4.4 in k, and on the second independent simulator's rig (a 2e4 N m/rad
    // input shaft) the healthy recordings' chi2 is 1.3-1.6 times higher at half or twice the
    // true stiffness (docs/diagnose-log.md, session 45). A configured shaft (documented, or a
    // calibration's) is the start: its basin is the one the configuration names.
    k.scan_at_start = configured(b).first <= 0;
    k.scan_step_ratio = (1 + 2 * kScreenDampingRatio) * (1 + 2 * kScreenDampingRatio);
    ParameterSpec c = spec(key_damping(), "N m s/rad", c_lo, c_hi, c_screen, configured(b).second);
    c.scan_follows_previous_power = 0.5;  // c = 2 zeta sqrt(k J_b): the scan keeps the screening ratio
    return {k, c};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    double& machine = end_ == RigEnd::Input ? c.stage.input_inertia_kgm2 : c.stage.output_inertia_kgm2;
    if (machine <= 0)
      set_parameter(c, key_inertia(), kSpeedSourceOfOwnInertia * own_inertia_kgm2(c, end_), o);
    set_parameter(c, key_stiffness(), x[0], o);
    set_parameter(c, key_damping(), x[1], o);
  }

private:
  /// A parameter on a log scale; a configured (calibrated) shaft is both its start and 'absent'.
  static ParameterSpec spec(std::string name, std::string unit, double lo, double hi, double screen,
                            double configured) {
    const double absent = configured > 0 ? configured : lo;
    const double lower = std::min(lo, absent), upper = std::max(hi, absent);
    return ParameterSpec{.name = std::move(name), .unit = std::move(unit), .lower = lower, .upper = upper,
        .log_scale = true, .initial = configured > 0 ? configured : std::clamp(screen, lower, upper),
        .null_value = absent, .screen_value = std::clamp(screen, lower, upper)};
  }
  /// The configured shaft (stiffness, damping), or zeros when the configuration states none.
  std::pair<double, double> configured(const model::SimulationConfig& b) const {
    return end_ == RigEnd::Input
               ? std::pair{b.rig.input_shaft_stiffness_N_m_rad, b.rig.input_shaft_damping_N_m_s_rad}
               : std::pair{b.rig.output_shaft_stiffness_N_m_rad, b.rig.output_shaft_damping_N_m_s_rad};
  }
  std::string key_stiffness() const {
    return end_ == RigEnd::Input ? "rig.input_shaft_stiffness_N_m_rad" : "rig.output_shaft_stiffness_N_m_rad";
  }
  std::string key_damping() const {
    return end_ == RigEnd::Input ? "rig.input_shaft_damping_N_m_s_rad" : "rig.output_shaft_damping_N_m_s_rad";
  }
  std::string key_inertia() const {
    return end_ == RigEnd::Input ? "stage.input_inertia_kgm2" : "stage.output_inertia_kgm2";
  }
  RigEnd end_;
};

} // namespace
std::unique_ptr<Candidate> input_shaft() { return std::make_unique<RigShaft>(RigEnd::Input); }
std::unique_ptr<Candidate> output_shaft() { return std::make_unique<RigShaft>(RigEnd::Output); }
} // namespace pw::diagnose::candidates
