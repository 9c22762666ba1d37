// Backlash of both mesh families (contact.backlash_sun_planet_m,
// backlash_planet_ring_m). With zero backlash the mesh is linear: a contact
// pulls as well as it pushes (the coast flank takes over at once). With play,
// teeth that the dynamic load drives apart lose contact: the force is cut at
// zero and the mesh is piecewise linear (derivation §3.3). It shows only where
// the dynamic mesh force exceeds the static one (light load near a mesh
// resonance); elsewhere its Jacobian is zero and it explains nothing.
//
// 'Absent' is the configured backlash (usually 0, the linear mesh): the
// screening secant runs from the model as it is to 20 um of play. Once the
// play exceeds the deepest separation, its size changes nothing (the coast
// flank is never reached; measured: 0.1, 1 and 20 um identical at 19 500 rpm,
// docs/diagnose.md), so the parameters saturate: the report gives the
// smallest value that fits as well, a lower limit.
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {
class Backlash final : public Candidate {
public:
  std::string name() const override { return "backlash"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "the meshes have circumferential play, so teeth that the dynamic load drives apart lose contact "
           "(the mesh force cannot pull) and re-engage with an impact";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  std::optional<FindingClass> finding_class() const override { return tooth_contact_class(); }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    auto spec = [&](const char* key, double b0) {
      const double upper = std::max(0.1 * b.stage.sun.module_m, 2 * b0);  // [m] the configuration allows < 1 module
      // Play of a few tens of um is typical for module-3 gears (ISO 1328 / DIN 3967 fits).
      const double screen = std::min(upper, std::max(2e-5, 2 * b0));
      ParameterSpec p{.name = key, .unit = "m", .lower = b0, .upper = upper,
          .log_scale = false, .initial = screen, .null_value = b0, .screen_value = screen};
      p.saturates = true;
      return p;
    };
    return {spec("contact.backlash_sun_planet_m", b.contact.backlash_sun_planet_m),
            spec("contact.backlash_planet_ring_m", b.contact.backlash_planet_ring_m)};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "contact.backlash_sun_planet_m", x[0], o);
    set_parameter(c, "contact.backlash_planet_ring_m", x[1], o);
  }
};
} // namespace
std::unique_ptr<Candidate> backlash() { return std::make_unique<Backlash>(); }
} // namespace pw::diagnose::candidates
