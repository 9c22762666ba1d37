// Tooth friction coefficient (contact.friction_coefficient): the friction
// force reverses at the pitch point, a mesh-periodic excitation of its own.
#include "diagnose/candidates/factories.hpp"

namespace pw::diagnose::candidates {
namespace {
class Friction final : public Candidate {
public:
  std::string name() const override { return "friction"; }
  bool every_planet_alike() const override { return true; }
  std::string physics() const override {
    return "the Coulomb friction coefficient of the tooth contacts differs (lubricant, surface finish); "
           "friction reverses at the pitch point and excites the mesh harmonics";
  }
  std::vector<Component> families() const override { return {Component::Mesh}; }
  std::optional<FindingClass> finding_class() const override { return tooth_contact_class(); }
  std::vector<ParameterSpec> parameters(const model::SimulationConfig& b) const override {
    const double mu = b.contact.friction_coefficient;
    return {ParameterSpec{.name = "contact.friction_coefficient", .unit = "1", .lower = 0.0, .upper = 0.4,
        .log_scale = false, .initial = mu > 0.05 ? 0.5 * mu : 0.1, .null_value = mu, .screen_value = mu + 0.05}};
  }
  void apply(model::SimulationConfig& c, const Variant&, std::span<const double> x,
             std::vector<std::string>* o) const override {
    set_parameter(c, "contact.friction_coefficient", x[0], o);
  }
};
} // namespace
std::unique_ptr<Candidate> friction() { return std::make_unique<Friction>(); }
} // namespace pw::diagnose::candidates
