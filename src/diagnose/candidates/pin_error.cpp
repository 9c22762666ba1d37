// Planet pin position errors (imperfections.pin_error_m): tangential offsets
// of the planet pins in the carrier, which unequalise the load sharing. A
// common offset of all pins is a rotation of the carrier and has no effect,
// so planet 0's pin is the reference (0) and the other N - 1 are fitted.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class PinError final : public Candidate {
public:
  std::string name() const override { return "pin_error"; }
  std::string physics() const override {
    return "planet pins sit off their nominal positions tangentially, so the planets share the load unequally "
           "(each planet's mesh forces change level, and a housing sensor sees the planets pass with unequal "
           "amplitudes)";
  }
  std::vector<Component> families() const override { return {Component::Carrier, Component::Mesh}; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    std::vector<ParameterSpec> p;
    const double m = b.stage.sun.module_m;
    for (int i = 1; i < b.stage.planet_count; ++i)
      p.push_back({"pin_error_m[" + std::to_string(i) + "]", "m", -0.02 * m, 0.02 * m, false, 0.0, 0.0, 1e-6});
    return p;
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    c.imperfections.pin_error_m.assign(static_cast<std::size_t>(c.stage.planet_count), 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) c.imperfections.pin_error_m[i + 1] = x[i];
    if (o) {
      std::string s = "imperfections.pin_error_m=[";
      for (std::size_t i = 0; i < c.imperfections.pin_error_m.size(); ++i) {
        if (i > 0) s += ",";
        s += format_value(c.imperfections.pin_error_m[i]);
      }
      o->push_back(s + "]");
    }
  }
};
} // namespace
std::unique_ptr<Candidate> pin_error() { return std::make_unique<PinError>(); }
} // namespace pw::diagnose::candidates
