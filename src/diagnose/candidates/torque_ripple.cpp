// Input torque ripple (imperfections.torque_ripple_fraction at
// torque_ripple_order): a motor or coupling that pulses k times per input
// revolution. The order comes from the strongest input-shaft lines located in
// the residual (a discrete variant); the fraction is fitted.
//
// How the ripple reaches the sensors depends on the machines at both ends, far more than on the
// gears: at k f_s (a few hertz to tens of hertz) the drive line turns as one body, and the ripple
// torque splits between accelerating what lies on the sun's side (the motor; under the seed's
// constant-power input, the law's own damping P / w^2) and what the carrier drives. The speed
// lines carry the first part, the mesh forces -- the housing accelerometer -- the second. A
// gear-set model without the load machine puts the whole ripple into the speeds and almost none
// into the mesh forces: measured on the independent simulator's four-planet rig (a 0.8 kg m^2
// dynamometer; four4p rec_01, ripple 0.08 at order 2, 300 rpm), the fitted fraction read 0.081
// from the speed channels, but the housing line at the ripple's order was 126 times the model's
// and the fit left 17.7 times its bound. The same simulation with the dynamometer's inertia on
// the carrier gives the recording's ratio of the housing line to the sun-speed line within 10 %
// (docs/diagnose-log.md, session 39). Healthy recordings have no line at k f_s, so a calibration
// cannot give that inertia: when the configuration states none (and the carrier is not held by a
// speed-controlled machine behind a shaft), the candidate fits the load machine's inertia with
// the fraction, as a transfer parameter (ParameterSpec::transfer): on load_inertia's box (1e-4 to
// 1e4 times the carrier's own inertia, rig_inertia.cpp), not tested against 'absent', not the
// finding's size. A configured (calibrated) inertia is used as it is.
//
// The fraction's size is read against the input side's dynamics the same way: at k f_s the ripple
// torque r T moves the sun's speed by r T / |P / W^2 + i w J_in| under the seed's constant-power law
// (test_rig.cpp), by r T / (w J_in) under a torque-controlled motor, with J_in everything the input
// turns (the motor's rotor included). The speed lines fix r / |Z_in(w)|, one number for two
// unknowns: a motor inertia the configuration does not state rescales the fraction, and nothing in
// the recording separates the two (both act on the same lines in the same ratio). So the fitted
// fraction is reported as the size for the configured input (ParameterSpec::size_conditional_on)
// whenever the motor's inertia acts and is not configured. Measured on the independent simulator's
// rigs (a 0.12 kg m^2 torque-controlled motor; docs/diagnose-log.md, sessions 39-40): 0.0829 for
// 0.08 where P / W^2 = 10 N m s happened to lie near w J_m = 7.5 N m s (four4p, 300 rpm, 10 kW,
// order 2), 0.0192 for 0.05 where 4.6 stood against 16 (fresh4p, 420 rpm, 9 kW, order 3).
//
// Behind a shaft the motor is the speed-source stand-in the shaft element writes when the
// configuration states none (kSpeedSourceOfOwnInertia times the sun's inertia, rig_shaft.cpp): right
// at the mesh frequencies the calibration analyses, far too heavy at k f_s, where it takes almost
// all of the ripple torque. There the candidate fits the motor's inertia as a second transfer
// parameter, on the same box as the load's, and the fraction is the size for the fitted inertia.
// Why: on indepsim2's rigA3 (a 0.12 kg m^2 motor behind a 2e4 N m/rad shaft, a 3 Hz speed loop;
// rec_04, ripple 0.05 at order 2, 900 rpm) the stand-in of 1.56 kg m^2 put the fraction at its
// bound 0.5, "not a finding"; the same diagnosis with the motor's true inertia stated reads 0.0438
// (docs/diagnose-log.md, session 48). Unlike a motor rigidly on the sun, a motor behind a shaft
// and the carrier's load split the ripple between the speed lines and the mesh forces in a ratio
// the inertias set, so the housing channel constrains them apart from the fraction.
#include "diagnose/candidates/factories.hpp"
#include "diagnose/candidates/rig_body.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace pw::diagnose::candidates {
namespace {

class TorqueRipple final : public Candidate {
public:
  std::string name() const override { return "torque_ripple"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "the input torque pulses at a fixed order of the input shaft (motor cogging, coupling, cardan "
           "shaft), which modulates the speeds and every mesh force at k f_s";
  }
  std::vector<Component> families() const override { return {Component::InputShaft}; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    std::vector<ParameterSpec> out{ParameterSpec{.name = "torque_ripple_fraction", .unit = "1", .lower = 1e-4,
        .upper = 0.5, .log_scale = true, .initial = 0.01, .null_value = 1e-4, .screen_value = 0.02}};
    out[0].size_conditional_on = input_side_unstated(b);
    if (fits_load_inertia(b)) out.push_back(machine_inertia(b, RigEnd::Output));
    if (fits_motor_inertia(b)) {
      // 'Absent' and the start are the stand-in: the screening's secant of the fraction (taken with
      // the other parameters at 'absent') and the choice of the ripple's order then see the model
      // as configured -- at the load's 'absent', a motor 1e-4 times the sun's inertia, a fraction
      // of 1e-4 already makes lines far above the recording's -- and the fit moves the inertia
      // down only as far as the recording asks.
      ParameterSpec j = machine_inertia(b, RigEnd::Input);
      j.initial = j.null_value = std::clamp(b.stage.input_inertia_kgm2, j.lower, j.upper);
      out.push_back(j);
    }
    return out;
  }
  std::vector<Variant> variants(const LocatedEvidence& ev, const model::SimulationConfig&,
                                const ToothMap&) const override {
    std::vector<Variant> out;
    for (double k : ev.input_orders) {
      if (k <= 0) continue;
      Variant v;
      v.order = k;
      v.label = "order " + format_value(k);
      bool dup = false;
      for (const auto& o : out) dup = dup || std::fabs(o.order - k) < 1e-9;
      if (!dup) out.push_back(v);
      if (out.size() >= 2) break;
    }
    if (out.empty()) out.push_back(Variant{"order 1", model::Body::Sun, 0, 0, 1.0});
    return out;
  }
  void apply(model::SimulationConfig& c, const Variant& v, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "imperfections.torque_ripple_fraction", x[0], o);
    set_parameter(c, "imperfections.torque_ripple_order", v.order > 0 ? v.order : 1.0, o);
    // The transfer inertias parameters() offered on the base configuration, load first. Here the
    // configuration carries the nuisance values too, and a shaft among them may have written a
    // stand-in the base lacks (then the base had no machine there): one extra parameter is the
    // motor's only where this configuration fits the motor, not the load, and its load machine
    // is not such a stand-in either (the base stated it), else the load's as before.
    const std::size_t extras = x.size() - 1;
    const bool motor_only = extras == 1 && fits_motor_inertia(c) && !fits_load_inertia(c) &&
                            !machine_is_speed_source_stand_in(c, RigEnd::Output);
    if (extras >= 1 && !motor_only) set_parameter(c, "stage.output_inertia_kgm2", x[1], o);
    if (extras >= 2 || motor_only) set_parameter(c, "stage.input_inertia_kgm2", x[extras], o);
  }

private:
  /// What the fraction's size is conditional on: the input law as configured without the motor's
  /// inertia, when that inertia acts (not behind a shaft whose far end an ideal speed control holds)
  /// and the configuration states none; empty when the input side is stated.
  static std::string input_side_unstated(const model::SimulationConfig& b) {
    if (fits_motor_inertia(b))
      return "the fitted motor inertia (stage.input_inertia_kgm2, a transfer parameter: the configuration's motor is "
             "a speed-source stand-in behind the input shaft)";
    if (b.stage.input_inertia_kgm2 > 0 || !machine_inertia_acts(b, RigEnd::Input)) return {};
    const std::string law = b.rig.input_control == model::InputControl::Power ? "constant power, " : "";
    return "the configured input: " + law + "no motor inertia; a motor's inertia (stage.input_inertia_kgm2) rescales it";
  }
  /// The load machine's inertia is fitted where the configuration states none and the carrier is
  /// not held at its speed by a speed-controlled machine behind a shaft (whose far end turns at the
  /// set speed whatever its inertia).
  static bool fits_load_inertia(const model::SimulationConfig& b) {
    return b.stage.output_inertia_kgm2 <= 0 && machine_inertia_acts(b, RigEnd::Output);
  }
  /// The motor's inertia is fitted where it acts and the configuration holds only the speed-source
  /// stand-in a shaft element wrote for it.
  static bool fits_motor_inertia(const model::SimulationConfig& b) {
    return machine_inertia_acts(b, RigEnd::Input) && machine_is_speed_source_stand_in(b, RigEnd::Input);
  }
  /// A machine's inertia as a transfer parameter: load_inertia's box and screening value
  /// (rig_body.hpp), so the two read the same machine alike; not tested against 'absent'.
  static ParameterSpec machine_inertia(const model::SimulationConfig& b, RigEnd end) {
    const double own = own_inertia_kgm2(b, end);
    ParameterSpec j{.name = end == RigEnd::Input ? "stage.input_inertia_kgm2" : "stage.output_inertia_kgm2",
        .unit = "kg m^2", .lower = kAbsentOfOwnInertia * own, .upper = kSpeedSourceOfOwnInertia * own,
        .log_scale = true, .initial = kScreenOfOwnInertia * own, .null_value = kAbsentOfOwnInertia * own,
        .screen_value = kScreenOfOwnInertia * own};
    j.transfer = true;
    return j;
  }
};

} // namespace
std::unique_ptr<Candidate> torque_ripple() { return std::make_unique<TorqueRipple>(); }
} // namespace pw::diagnose::candidates
