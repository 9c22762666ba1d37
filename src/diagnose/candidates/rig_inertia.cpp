// Rig elements: the machines at either end of the stage. On a test rig the sun is driven
// by a motor and the carrier drives a load machine (a dynamometer); the gear set's
// documentation rarely states their inertias, and the seed's model has none (the sun and
// the carrier alone take the input power and the load). A machine rigidly coupled to its
// shaft turns with the sun (stage.input_inertia_kgm2, "motor_inertia") or the carrier
// (stage.output_inertia_kgm2, "load_inertia"): the body's speed then hardly follows the mesh
// forces, and the speed channels' mesh harmonics fall by the ratio of the inertias. Measured
// on the independent simulator's rig (a 0.12 kg m^2 motor and a 0.8 kg m^2 dynamometer on
// shafts): the nuisance-fitted chi2 of a healthy seed-gear recording fell from 5.6e8 to 4.3e7
// with both inertias rigidly coupled (docs/diagnose-log.md, session 17).
//
// One parameter each, the inertia [kg m^2] on a log scale relative to the body's own inertia
// J_ref (the sun's disc; the carrier with its planets at the carrier radius, as the model
// derives them): 'absent' is 1e-4 J_ref (it changes the body's inertia by 1e-4, so every line
// by about as much: below the noise of any recording the reader accepts) or the configured
// value when the configuration states one; the box reaches 1e4 J_ref (a machine ten thousand
// times the sun's inertia is a speed source at every analysed frequency); the screening value
// J_ref doubles the body's inertia. The parameter saturates: above some value the body no
// longer moves at the analysed frequencies and the inertia is not identifiable, so the report
// gives its lower limit (docs/diagnose.md §5, step 12).
//
// A flexible shaft (rig.input_shaft_stiffness_N_m_rad > 0) in the configuration puts the
// machine behind it; the candidate then fits the inertia at the far end of that shaft.
#include "diagnose/candidates/factories.hpp"
#include "diagnose/candidates/rig_body.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {

class RigInertia final : public Candidate {
public:
  explicit RigInertia(RigEnd m) : machine_(m) {}
  std::string name() const override { return machine_ == RigEnd::Input ? "motor_inertia" : "load_inertia"; }
  std::string physics() const override {
    return machine_ == RigEnd::Input
               ? "a motor (rotor, coupling) turns with the sun: an inertia on the input shaft that the gear-set "
                 "model lacks, which damps the sun's speed response to the mesh forces"
               : "a load machine (dynamometer, coupling) turns with the carrier: an inertia on the output shaft that "
                 "the gear-set model lacks, which damps the carrier's speed response to the mesh forces";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool rig_design() const override { return true; }
  /// Not behind a flexible shaft held at the nominal speed (rig.X_control = "speed"): the far
  /// end turns at the set speed whatever the machine's inertia.
  bool acts_on(const model::SimulationConfig& b) const override { return machine_inertia_acts(b, machine_); }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double own = own_inertia_kgm2(b, machine_);
    const double configured = configured_kgm2(b);
    const double absent = configured > 0 ? configured : kAbsentOfOwnInertia * own;
    const double lower = std::min(kAbsentOfOwnInertia * own, absent);
    const double upper = std::max(kSpeedSourceOfOwnInertia * own, absent);
    const double screen = std::clamp(kScreenOfOwnInertia * own, lower, upper);
    ParameterSpec p{.name = key(), .unit = "kg m^2", .lower = lower, .upper = upper, .log_scale = true,
        .initial = configured > 0 ? configured : screen, .null_value = absent, .screen_value = screen};
    p.saturates = true;
    return {p};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, key(), x[0], o);
  }

private:
  std::string key() const { return machine_ == RigEnd::Input ? "stage.input_inertia_kgm2" : "stage.output_inertia_kgm2"; }
  double configured_kgm2(const model::SimulationConfig& b) const {
    return machine_ == RigEnd::Input ? b.stage.input_inertia_kgm2 : b.stage.output_inertia_kgm2;
  }
  RigEnd machine_;
};

} // namespace
std::unique_ptr<Candidate> motor_inertia() { return std::make_unique<RigInertia>(RigEnd::Input); }
std::unique_ptr<Candidate> load_inertia() { return std::make_unique<RigInertia>(RigEnd::Output); }
} // namespace pw::diagnose::candidates
