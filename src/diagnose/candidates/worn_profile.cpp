// A pre-existing worn profile on every flank (imperfections.worn_profile_depth_m):
// Archard-shaped material loss, zero at the pitch point, deepest at the
// flank's root end, which changes the shape of the mesh excitation.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class WornProfile final : public Candidate {
public:
  std::string name() const override { return "worn_profile"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "all flanks carry an Archard-shaped worn profile (material lost in proportion to the slide-to-roll "
           "ratio), which acts like uneven tip and root relief and changes every mesh harmonic";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  std::optional<FindingClass> finding_class() const override { return tooth_contact_class(); }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    return {ParameterSpec{.name = "worn_profile_depth_m", .unit = "m", .lower = 1e-7,
        .upper = 0.02 * b.stage.sun.module_m,
        .log_scale = true, .initial = 2e-6, .null_value = 1e-7, .screen_value = 5e-7}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "imperfections.worn_profile_depth_m", x[0], o);
  }
};
} // namespace
std::unique_ptr<Candidate> worn_profile() { return std::make_unique<WornProfile>(); }
} // namespace pw::diagnose::candidates
