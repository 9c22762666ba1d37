// A test probe shared by the flank-deviation tests (worn profile, tip relief):
// the state of planet 0's sun mesh at time t when the sun alone is turned so
// that every sun mesh is compressed by `deflection_m` along its line of action,
// everything else at rest (no damping, no inertia: the contact law alone).
#pragma once

#include "model/simulation.hpp"

#include <Eigen/Core>

namespace pw::test {

inline model::MeshState sun_mesh_under_deflection(model::PreparedStage& p, double t, double deflection_m) {
  model::PlanetaryDynamics& sys = *p.dynamics;
  const int n = sys.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n), gen(n);
  sys.set_roll_reference(q);
  q(0) = deflection_m / sys.structure().meshes[0].g(0);
  sys.force(t, q, v, gen, nullptr, nullptr);
  return sys.mesh_states()[0];
}

} // namespace pw::test
