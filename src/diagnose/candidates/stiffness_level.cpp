// Nuisance: the level of every mesh stiffness (stiffness.scale). The potential
// energy method and ISO 6336-1 differ by tens of percent; a recording from a
// real gear set will rarely sit on the computed level.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class StiffnessLevel final : public Candidate {
public:
  std::string name() const override { return "stiffness_level"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "every mesh stiffness differs from the computed one by a common factor (material, face load "
           "distribution, rim and body compliance the potential-energy model leaves out)";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool nuisance() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    return {ParameterSpec{.name = kStiffnessLevelKey, .unit = "1", .lower = 0.5 * b.stiffness.scale,
        .upper = 2.0 * b.stiffness.scale,
        .log_scale = true, .initial = b.stiffness.scale, .null_value = b.stiffness.scale,
        .screen_value = 1.05 * b.stiffness.scale}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, kStiffnessLevelKey, x[0], o);
  }
};
} // namespace
std::unique_ptr<Candidate> stiffness_level() { return std::make_unique<StiffnessLevel>(); }
} // namespace pw::diagnose::candidates
