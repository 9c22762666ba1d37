// Planet pin position errors (imperfections.pin_error_m): tangential offsets
// of the planet pins in the carrier, which unequalise the load sharing. A
// common offset of all pins is a rotation of the carrier and has no effect,
// so planet 0's pin is the reference (0) and the other N - 1 are fitted.
#include "diagnose/candidates/factories.hpp"

#include <cmath>

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
      p.push_back(ParameterSpec{.name = "pin_error_m[" + std::to_string(i) + "]", .unit = "m", .lower = -0.02 * m,
          .upper = 0.02 * m,
          .log_scale = false, .initial = 0.0, .null_value = 0.0, .screen_value = 1e-6});
    return p;
  }
  /// From a carrier eccentricity (x, y): its tangential part at planet i, -x sin psi_i + y cos psi_i
  /// (the displacement along e_t = (-sin psi, cos psi), as planetary_system.cpp applies pin errors),
  /// relative to planet 0's; the radial part has no pin counterpart.
  std::vector<double> start_from(const std::string& other, std::span<const double> ox,
                                 const model::SimulationConfig& b) const override {
    if (other != "carrier_runout" || ox.size() != 2) return {};
    const auto psi = planet_angles_rad(b);
    auto t = [&](std::size_t i) { return -ox[0] * std::sin(psi[i]) + ox[1] * std::cos(psi[i]); };
    std::vector<double> x;
    for (std::size_t i = 1; i < psi.size(); ++i) x.push_back(t(i) - t(0));
    return x;
  }
  std::optional<FindingClass> finding_class() const override { return planet_position_class(); }
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
