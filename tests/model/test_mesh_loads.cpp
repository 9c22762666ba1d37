// MeshLoadRecorder: the engineering summary's loads (src/model/mesh_loads.hpp).
#include "model/mesh_loads.hpp"

#include "geometry/mesh.hpp"
#include "simulation_fixture.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pw;
using pw::test::fast_seed;
using pw::test::scalar;

namespace {

double find(const std::vector<model::Scalar>& s, const std::string& name) {
  for (const auto& x : s)
    if (x.name == name) return x.value;
  ADD_FAILURE() << "no scalar " << name;
  return NAN;
}

/// All 2N meshes unloaded except sun-planet mesh `planet`, one pair at roll xi carrying F.
std::vector<model::MeshState> one_loaded_pair(int planets, int planet, double xi_m, double F_N) {
  std::vector<model::MeshState> s(2 * static_cast<std::size_t>(planets));
  model::MeshState& m = s[2 * static_cast<std::size_t>(planet)];
  m.pairs = 1;
  m.pair[0].xi_m = xi_m;
  m.pair_force_N[0] = F_N;
  m.force_N = F_N;
  return s;
}

} // namespace

TEST(MeshLoads, ForcesDynamicFactorAndHertzPressureMatchClosedForms) {
  const model::SimulationConfig c = fast_seed();
  const geometry::StageGeometry g = geometry::make_stage_geometry(c.stage);
  const double T = 100.0;  // input torque [N m]
  model::MeshLoadRecorder rec(g, c.stage, T);
  const double xi_p = g.sun_planet.pitch_point_m;
  // Planet 1's sun mesh carries F, F, 2F at the pitch point: mean 4F/3, peak 2F, K_v = 1.5.
  const double F = 1000.0;
  rec.add(one_loaded_pair(3, 1, xi_p, F));
  rec.add(one_loaded_pair(3, 1, xi_p, F));
  rec.add(one_loaded_pair(3, 1, xi_p, 2 * F));
  const auto s = rec.scalars();
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/static_force"), T / (3 * g.sun_planet.base_radius_a_m), 1e-9);
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/mean_force"), (4 * F / 3) / 3, 1e-9);  // averaged over 3 planets
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/max_force"), 2 * F, 1e-9);
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/dynamic_factor"), 1.5, 1e-12);
  // Hertz at the pitch point (Johnson Eq. 4.45): rho_A = r_bA tan a', rho_B = L - rho_A.
  const double Es = 1.0 / (2 * (1 - 0.09) / 206e9);  // two steel gears of the seed (E = 206 GPa, nu = 0.3)
  const double rho_a = xi_p, rho_b = g.sun_planet.tangent_distance_m - xi_p;
  const double R = rho_a * rho_b / (rho_a + rho_b);
  const double b = std::min(c.stage.sun.face_width_m, c.stage.planet.face_width_m);
  const double p0 = std::sqrt(2 * F / b * Es / (std::numbers::pi * R));
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/max_contact_pressure"), p0, 1e-9 * p0);
  EXPECT_EQ(find(s, "mesh_load/sun_planet/max_contact_pressure_planet"), 1.0);
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/max_contact_pressure_position"), 0.0, 1e-15);
  // The ring meshes carried nothing.
  EXPECT_EQ(find(s, "mesh_load/planet_ring/max_force"), 0.0);
  EXPECT_EQ(find(s, "mesh_load/planet_ring/max_contact_pressure"), 0.0);
}

TEST(MeshLoads, PressureGrowsTowardsTheSunRootWhereItsFlankIsSharper) {
  // Same load, two positions: the smaller equivalent radius (nearer the sun's
  // base circle) gives the larger pressure, and the recorder reports where.
  const model::SimulationConfig c = fast_seed();
  const geometry::StageGeometry g = geometry::make_stage_geometry(c.stage);
  model::MeshLoadRecorder rec(g, c.stage, 100.0);
  const double lo = g.sun_planet.start_active_m, hi = g.sun_planet.end_active_m;
  rec.add(one_loaded_pair(3, 0, hi, 1000.0));
  rec.add(one_loaded_pair(3, 2, lo, 1000.0));
  const auto s = rec.scalars();
  EXPECT_EQ(find(s, "mesh_load/sun_planet/max_contact_pressure_planet"), 2.0);
  EXPECT_NEAR(find(s, "mesh_load/sun_planet/max_contact_pressure_position"), lo - g.sun_planet.pitch_point_m, 1e-15);
}

TEST(MeshLoads, FrictionlessMeanMeshForceIsTheStaticForceInBothMeshes) {
  // Statics of the sun (T_s = N F r_bs) and of each planet (F_sp r_bp = F_pr r_bp):
  // without friction both mean forces equal T_s / (N r_bs) within 0.5 % (as the
  // simulation test of the sun mesh force: the damping force averages out over whole
  // mesh periods), and a dynamic mesh force peaks above its mean (K_v > 1).
  model::SimulationConfig c = fast_seed();
  c.contact.friction_coefficient = 0;
  const model::SimulationResult r = model::simulate(c);
  const double F0 = scalar(r, "mesh_load/sun_planet/static_force");
  const double Ts = 1000.0 / (400 * 2 * std::numbers::pi / 60);
  const geometry::StageGeometry g = geometry::make_stage_geometry(c.stage);
  EXPECT_NEAR(F0, Ts / (3 * g.sun_planet.base_radius_a_m), 1e-9 * F0);
  EXPECT_NEAR(scalar(r, "mesh_load/sun_planet/mean_force"), F0, 5e-3 * F0);
  EXPECT_NEAR(scalar(r, "mesh_load/planet_ring/mean_force"), F0, 5e-3 * F0);
  EXPECT_GT(scalar(r, "mesh_load/sun_planet/dynamic_factor"), 1.0);
  EXPECT_GE(scalar(r, "mesh_load/sun_planet/max_force"), scalar(r, "mesh_load/sun_planet/mean_force"));
}
