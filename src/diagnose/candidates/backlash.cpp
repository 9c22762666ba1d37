// Backlash of both mesh families (contact.backlash_sun_planet_m,
// backlash_planet_ring_m). It acts only when the teeth separate (light load,
// strong dynamics); otherwise its Jacobian is zero and it explains nothing.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class Backlash final : public Candidate {
public:
  std::string name() const override { return "backlash"; }
  std::string physics() const override {
    return "the meshes have circumferential play, so teeth that separate under the dynamic load re-engage "
           "with an impact (coast-flank contact)";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double m = 0.1 * b.stage.sun.module_m;
    return {{"contact.backlash_sun_planet_m", "m", 1e-6, m, true, 2e-5, 1e-6, 2e-5},
            {"contact.backlash_planet_ring_m", "m", 1e-6, m, true, 2e-5, 1e-6, 2e-5}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    c.contact.backlash_sun_planet_m = x[0];
    c.contact.backlash_planet_ring_m = x[1];
    if (o) {
      o->push_back("contact.backlash_sun_planet_m=" + format_value(x[0]));
      o->push_back("contact.backlash_planet_ring_m=" + format_value(x[1]));
    }
  }
};
} // namespace
std::unique_ptr<Candidate> backlash() { return std::make_unique<Backlash>(); }
} // namespace pw::diagnose::candidates
