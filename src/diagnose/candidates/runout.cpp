// Sun or carrier runout (eccentricity), fitted as the Cartesian components
// (e cos phi, e sin phi) so that the phase has no wrap-around and a small
// runout has no singular phase; e and phi are reported.
#include "diagnose/candidates/factories.hpp"

#include <cmath>

namespace pw::diagnose::candidates {
namespace {
class Runout final : public Candidate {
public:
  explicit Runout(bool sun) : sun_(sun) {}
  std::string name() const override { return sun_ ? "sun_runout" : "carrier_runout"; }
  std::string physics() const override {
    return sun_ ? "the sun runs eccentric: its centre circles once per sun revolution relative to the carrier, "
                  "modulating every sun-mesh deflection at f_s - f_c"
                : "the carrier is eccentric: the planet centres are displaced by a vector fixed in the carrier, "
                  "which unequalises the load sharing like a pattern of pin errors";
  }
  std::vector<Component> families() const override {
    return sun_ ? std::vector<Component>{Component::Sun} : std::vector<Component>{Component::Carrier, Component::Mesh};
  }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double m = 0.02 * b.stage.sun.module_m;
    const std::string p = sun_ ? "sun_eccentricity" : "carrier_eccentricity";
    return {{p + "_x_m", "m", -m, m, false, 0.05 * m}, {p + "_y_m", "m", -m, m, false, 0.0}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    const double e = std::hypot(x[0], x[1]);
    const double phi = e > 0 ? std::atan2(x[1], x[0]) : 0.0;
    const std::string p = sun_ ? "imperfections.sun_eccentricity" : "imperfections.carrier_eccentricity";
    if (sun_) {
      c.imperfections.sun_eccentricity_m = e;
      c.imperfections.sun_eccentricity_phase_rad = phi;
    } else {
      c.imperfections.carrier_eccentricity_m = e;
      c.imperfections.carrier_eccentricity_phase_rad = phi;
    }
    if (o) {
      o->push_back(p + "_m=" + format_value(e));
      o->push_back(p + "_phase_rad=" + format_value(phi));
    }
  }

private:
  bool sun_;
};
} // namespace
std::unique_ptr<Candidate> sun_runout() { return std::make_unique<Runout>(true); }
std::unique_ptr<Candidate> carrier_runout() { return std::make_unique<Runout>(false); }
} // namespace pw::diagnose::candidates
