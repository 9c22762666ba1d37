// Nuisance: the viscous mesh damping ratio (contact.mesh_damping_ratio), an
// assumption of the model (docs/derivation.md, "Assumptions").
#include "diagnose/candidates/factories.hpp"

#include <algorithm>

namespace pw::diagnose::candidates {
namespace {
class DampingLevel final : public Candidate {
public:
  std::string name() const override { return "damping_level"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "the viscous mesh damping ratio differs from the assumed one (lubricant film, bearing and housing "
           "losses lumped into the meshes)";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  bool nuisance() const override { return true; }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double z = std::max(b.contact.mesh_damping_ratio, 1e-3);
    // contact.mesh_damping_ratio is at most 1 (model/validate.cpp): near that end the screening secant
    // points down instead of beyond the key's range.
    const double upper = std::min(1.0, 5 * z);
    const double screen = 1.2 * z <= upper ? 1.2 * z : z / 1.2;
    return {ParameterSpec{.name = kDampingLevelKey, .unit = "1", .lower = std::max(1e-3, z / 5),
        .upper = upper,
        .log_scale = true, .initial = z, .null_value = z, .screen_value = screen}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, kDampingLevelKey, x[0], o);
  }
};
} // namespace
std::unique_ptr<Candidate> damping_level() { return std::make_unique<DampingLevel>(); }
} // namespace pw::diagnose::candidates
