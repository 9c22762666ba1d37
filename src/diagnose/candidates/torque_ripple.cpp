// Input torque ripple (imperfections.torque_ripple_fraction at
// torque_ripple_order): a motor or coupling that pulses k times per input
// revolution. The order comes from the strongest input-shaft lines located in
// the residual (a discrete variant); the fraction is fitted.
#include "diagnose/candidates/factories.hpp"

#include <cmath>

namespace pw::diagnose::candidates {
namespace {
class TorqueRipple final : public Candidate {
public:
  std::string name() const override { return "torque_ripple"; }
  std::string physics() const override {
    return "the input torque pulses at a fixed order of the input shaft (motor cogging, coupling, cardan "
           "shaft), which modulates the speeds and every mesh force at k f_s";
  }
  std::vector<Component> families() const override { return {Component::InputShaft}; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig&) const override {
    return {ParameterSpec{.name = "torque_ripple_fraction", .unit = "1", .lower = 1e-4, .upper = 0.5,
        .log_scale = true, .initial = 0.01, .null_value = 1e-4, .screen_value = 0.02}};
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
  }
};
} // namespace
std::unique_ptr<Candidate> torque_ripple() { return std::make_unique<TorqueRipple>(); }
} // namespace pw::diagnose::candidates
