// A worn profile in the contact law (model/planetary_system.cpp).
#include "model/simulation.hpp"

#include <gtest/gtest.h>

using namespace pw::model;

TEST(WornContact, WornToothCarriesLessOfTheLoadInDoubleContact) {
  // Two pairs share the load by k_j (delta - e_j): removing e from one
  // flank lowers that pair's force by k_j e relative to the unworn pair.
  SimulationConfig c;
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const int n = sys.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n), g(n);
  // Find a time with two pairs in the sun mesh of planet 0.
  double t = 0;
  const double dt = 1e-5;
  sys.set_roll_reference(q);
  for (;; t += dt) {
    sys.force(t, q, v, g, nullptr, nullptr);
    if (sys.mesh_states()[0].pairs == 2) break;
  }
  const int worn_tooth = sys.mesh_states()[0].pair[0].tooth_a;
  // Impose a uniform deflection of 2 um through the sun rotation alone.
  q(0) = 2e-6 / sys.structure().meshes[0].g(0);
  sys.force(t, q, v, g, nullptr, nullptr);
  const MeshState before = sys.mesh_states()[0];
  sys.surfaces().sun.add_uniform(worn_tooth, 0.5e-6);
  sys.force(t, q, v, g, nullptr, nullptr);
  const MeshState after = sys.mesh_states()[0];
  ASSERT_EQ(after.pair[0].tooth_a, worn_tooth);
  const double k0 = before.pair_force_N[0] / before.deflection_m;
  EXPECT_NEAR(before.pair_force_N[0] - after.pair_force_N[0], k0 * 0.5e-6, 1e-6 * k0 * 0.5e-6);
  EXPECT_DOUBLE_EQ(before.pair_force_N[1], after.pair_force_N[1]);
  EXPECT_LT(after.force_N, before.force_N);
}

TEST(WornContact, BacklashDelaysCoastFlankContact) {
  SimulationConfig c;
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const int n = sys.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n), g(n);
  sys.set_roll_reference(q);
  q(0) = -1e-6 / sys.structure().meshes[0].g(0);  // delta = -1 um on the sun meshes
  sys.set_backlash_m(0, 0.5e-6);
  sys.force(0.0, q, v, g, nullptr, nullptr);
  EXPECT_LT(sys.mesh_states()[0].force_N, 0.0) << "coast flanks touch once delta < -b";
  sys.set_backlash_m(0, 2e-6);
  sys.force(0.0, q, v, g, nullptr, nullptr);
  EXPECT_EQ(sys.mesh_states()[0].force_N, 0.0) << "inside the backlash no force";
}
