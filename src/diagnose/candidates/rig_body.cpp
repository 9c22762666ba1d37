#include "diagnose/candidates/rig_body.hpp"

#include "geometry/mesh.hpp"

namespace pw::diagnose::candidates {

double own_inertia_kgm2(const model::SimulationConfig& b, RigEnd end) {
  model::SimulationConfig bare = b;
  bare.stage.input_inertia_kgm2 = 0;
  bare.stage.output_inertia_kgm2 = 0;
  const geometry::StageGeometry g = geometry::make_stage_geometry(bare.stage);
  const model::MassProperties p = model::mass_properties(bare, g);
  if (end == RigEnd::Input) return p.sun_inertia_kgm2;
  const double rc = g.carrier_radius_m;
  return p.carrier_inertia_kgm2 + b.stage.planet_count * p.planet_mass_kg * rc * rc;
}

bool machine_inertia_acts(const model::SimulationConfig& b, RigEnd end) {
  if (end == RigEnd::Input)
    return !(b.rig.input_control == model::InputControl::Speed && b.rig.input_shaft_stiffness_N_m_rad > 0);
  return !(b.rig.load_control == model::LoadControl::Speed && b.rig.output_shaft_stiffness_N_m_rad > 0);
}

bool machine_is_speed_source_stand_in(const model::SimulationConfig& b, RigEnd end) {
  const double J = end == RigEnd::Input ? b.stage.input_inertia_kgm2 : b.stage.output_inertia_kgm2;
  // The stand-in is written as kSpeedSourceOfOwnInertia * own through a round-trip decimal: equal
  // to the last bit; a relative 1e-9 below it still counts (a value typed from a printed one).
  return J > 0 && J >= kSpeedSourceOfOwnInertia * own_inertia_kgm2(b, end) * (1 - 1e-9);
}

} // namespace pw::diagnose::candidates
