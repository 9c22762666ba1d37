// The table of candidate model extensions (candidate.hpp). Nuisance
// candidates first: they are fitted before any other.
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/candidates/factories.hpp"

#include "config/schema.hpp"
#include "core/format.hpp"

#include <algorithm>
#include <numbers>

#include <stdexcept>

namespace pw::diagnose {

std::vector<Variant> Candidate::variants(const LocatedEvidence&, const model::SimulationConfig&,
                                         const ToothMap&) const {
  return {Variant{}};
}

std::string format_value(double v) { return round_trip(v); }

void set_parameter(model::SimulationConfig& c, std::string_view key, double value,
                   std::vector<std::string>* overrides) {
  double* field = config::find_number(c, key);
  if (!field) throw std::logic_error("set_parameter: '" + std::string(key) + "' is not a floating-point key");
  *field = value;
  if (overrides) overrides->push_back(std::string(key) + "=" + format_value(value));
}

const std::vector<std::unique_ptr<Candidate>>& candidate_library() {
  static const std::vector<std::unique_ptr<Candidate>> table = [] {
    std::vector<std::unique_ptr<Candidate>> t;
    t.push_back(candidates::stiffness_level());     // nuisance
    t.push_back(candidates::damping_level());       // nuisance
    t.push_back(candidates::sun_tooth_damage());
    t.push_back(candidates::planet_tooth_damage());
    t.push_back(candidates::ring_tooth_damage());
    t.push_back(candidates::pin_error());
    t.push_back(candidates::sun_runout());
    t.push_back(candidates::carrier_runout());
    t.push_back(candidates::torque_ripple());
    t.push_back(candidates::worn_profile());
    t.push_back(candidates::friction());
    t.push_back(candidates::backlash());
    t.push_back(candidates::sensor_transfer_path());
    t.push_back(candidates::encoder_bandwidth());
    t.push_back(candidates::tip_relief());
    t.push_back(candidates::engagement_ramp());
    t.push_back(candidates::housing_mount());
    t.push_back(candidates::motor_inertia());
    t.push_back(candidates::load_inertia());
    t.push_back(candidates::input_shaft());
    t.push_back(candidates::output_shaft());
    t.push_back(candidates::mesh_stiffness_harmonics());
    t.push_back(candidates::bearing_damping());
    return t;
  }();
  return table;
}

std::vector<double> planet_angles_rad(const model::SimulationConfig& base) {
  if (!base.stage.planet_angles_rad.empty()) return base.stage.planet_angles_rad;
  std::vector<double> psi;
  for (int i = 0; i < base.stage.planet_count; ++i) psi.push_back(2 * std::numbers::pi * i / base.stage.planet_count);
  return psi;
}

const Candidate* find_candidate(const std::string& name) {
  for (const auto& c : candidate_library())
    if (c->name() == name) return c.get();
  return nullptr;
}

FindingClass planet_position_class() {
  return {.name = "planet_position_error",
          .physics = "the planet centres sit off their nominal positions in the carrier -- pin position errors or "
                     "a carrier runout, which displace the planets alike and unequalise their load sharing",
          .canonical = "pin_error",
          .covers = {"pin_error", "carrier_runout"}};
}

FindingClass tooth_contact_class() {
  return {.name = "tooth_contact_change",
          .physics = "the tooth contacts differ alike on every tooth -- friction, profile wear or modification, "
                     "clearance, or the mesh stiffness or damping level: each changes the mesh harmonics alone, and "
                     "what tells them apart, how the change is shared among the harmonics, is the shape the model's "
                     "stiffness law fixes",
          .canonical = "",
          .covers = {"friction", "worn_profile", "tip_relief", "backlash", "stiffness_level", "damping_level"}};
}

FindingClass sun_defect_class() {
  return {.name = "sun_defect",
          .physics = "the sun carries a defect that meets each planet once per sun-relative revolution -- a damaged "
                     "tooth or a runout: both put their lines in the sun family alone, and what tells them apart, how "
                     "the change is shared among the family's orders, is the transfer the model's form fixes",
          .canonical = "",
          .covers = {"sun_tooth_damage", "sun_runout"}};
}

std::optional<FindingClass> finding_class_of(const std::string& name) {
  const Candidate* c = find_candidate(name);
  return c ? c->finding_class() : std::nullopt;
}

std::optional<Component> sole_family(const Candidate& c) {
  const std::vector<Component> f = c.families();
  if (f.empty() || !std::all_of(f.begin(), f.end(), [&](Component x) { return x == f.front(); })) return std::nullopt;
  return f.front();
}

bool acts_on_mesh_harmonics_only(const Candidate& c) {
  return sole_family(c) == Component::Mesh;
}

} // namespace pw::diagnose
