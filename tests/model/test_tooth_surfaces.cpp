// Flank state (model/tooth_surfaces.hpp) and the time step's skip of untouched flanks.
#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace pw::model;

TEST(FlankSet, IsPristineUntilSomethingHasWriteAccess) {
  FlankSet a(5, 4, 0.0, 1e-3);
  EXPECT_TRUE(a.pristine());
  const FlankSet& ca = a;
  (void)ca.tooth_deviation(2);
  (void)ca.deviations();
  (void)ca.deviation_m(1, 5e-4);
  EXPECT_TRUE(a.pristine()) << "reading does not clear it";
  FlankSet b = a, c = a, d = a, e = a;
  (void)b.tooth_deviation(0);
  (void)c.deviations();
  d.set_stiffness_factor(3, 1.0);
  e.add_uniform(1, 0.0);
  for (const FlankSet* f : {&b, &c, &d, &e}) EXPECT_FALSE(f->pristine()) << "write access clears it, even of 0 or 1";
}

TEST(FlankSet, UnitFactorsHoldsUntilAFactorOtherThanOneIsSetAndWearDoesNotClearIt) {
  // The time step skips the factor multiplications while unit_factors() holds: it must hold
  // exactly while every factor is 1.
  FlankSet a(5, 4, 0.0, 1e-3);
  EXPECT_TRUE(a.unit_factors());
  a.set_stiffness_factor(2, 1.0);
  a.add_uniform(1, 3e-6);
  a.deviations()[0] = 1e-6;
  EXPECT_TRUE(a.unit_factors()) << "a factor of exactly 1 and worn deviations leave the factors at 1";
  EXPECT_FALSE(a.pristine());
  a.set_stiffness_factor(3, 0.6);
  EXPECT_FALSE(a.unit_factors());
  a.set_stiffness_factor(3, 1.0);
  EXPECT_FALSE(a.unit_factors()) << "conservative: once cleared it stays cleared";
  for (int t = 0; t < a.teeth(); ++t) EXPECT_EQ(a.stiffness_factor(t), 1.0);
}

TEST(FlankSet, ElementAtIsTheClampedFloorOfTheGridPositionEverywhereIncludingBoundariesAndNaN) {
  // element_at takes the floor by truncation; it must give clamp(floor((xi - xi_min) / dxi)) for
  // every xi: inside, on every element boundary and its neighbouring doubles, outside on both sides.
  const double x0 = -1.3e-3, x1 = 2.1e-3;
  const int n = 17;
  const FlankSet f(3, n, x0, x1);
  const double dx = f.element_width_m();
  auto reference = [&](double xi) {
    const double u = std::floor((xi - x0) / dx);
    return std::isnan(u) ? 0 : static_cast<int>(std::clamp(u, 0.0, static_cast<double>(n - 1)));
  };
  std::vector<double> xs = {x0 - 1.0, x0 - dx, x0, x1, x1 + dx, 1.0, -0.0, 0.0,
                            std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (int e = 0; e <= n; ++e) {
    const double b = x0 + e * dx;
    xs.push_back(b);
    xs.push_back(std::nextafter(b, -1.0));
    xs.push_back(std::nextafter(b, 1.0));
    xs.push_back(b + 0.5 * dx);
  }
  for (int k = 0; k <= 1000; ++k) xs.push_back(x0 - dx + (x1 - x0 + 2 * dx) * k / 1000.0);
  for (double xi : xs) EXPECT_EQ(f.element_at(xi), reference(xi)) << "xi = " << xi;
  EXPECT_EQ(f.element_at(std::numeric_limits<double>::quiet_NaN()), 0);
}

TEST(FlankSet, UntouchedFlanksGiveTheSameForcesBitForBitAsFlanksWrittenToZero) {
  // The time step skips the deviation and stiffness-factor look-ups of pristine flanks. With
  // every flank then written to (deviation 0, factor 1), the look-ups run: forces, tangents and
  // mesh states must not change in a single bit, over times covering whole mesh cycles.
  SimulationConfig c;
  c.contact.friction_coefficient = 0.1;  // friction terms (sliding speeds) in the force too
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const int n = sys.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n);
  // A deflection of ~2 um on every sun mesh (sun rotation) and a small velocity.
  q(0) = 2e-6 / sys.structure().meshes[0].g(0);
  v(0) = 1e-3 / sys.structure().meshes[0].g(0);
  sys.set_roll_reference(q);
  const double period = 1.0 / p.mesh_frequency_Hz;
  struct Sample {
    Eigen::VectorXd g;
    Eigen::MatrixXd K, C;
    std::vector<MeshState> states;
  };
  auto run = [&] {
    std::vector<Sample> out;
    for (int i = 0; i < 97; ++i) {
      const double t = 3.0 * period * i / 97.0;
      Sample s;
      s.g.resize(n);
      s.K.setZero(n, n);  // the system writes into n x n tangents
      s.C.setZero(n, n);
      sys.force(t, q, v, s.g, &s.K, &s.C);
      s.states = sys.mesh_states();
      out.push_back(std::move(s));
    }
    return out;
  };
  const std::vector<Sample> pristine = run();
  ToothSurfaces& surf = sys.surfaces();
  ASSERT_TRUE(surf.sun.pristine());
  for (FlankSet* f : {&surf.sun, &surf.ring}) (void)f->deviations();
  for (auto* family : {&surf.planet_sun_side, &surf.planet_ring_side})
    for (FlankSet& f : *family) f.set_stiffness_factor(0, 1.0);
  const std::vector<Sample> written = run();
  int pairs = 0;
  for (std::size_t i = 0; i < pristine.size(); ++i) {
    ASSERT_TRUE(pristine[i].g == written[i].g) << i;
    ASSERT_TRUE(pristine[i].K == written[i].K) << i;
    ASSERT_TRUE(pristine[i].C == written[i].C) << i;
    for (std::size_t m = 0; m < pristine[i].states.size(); ++m) {
      const MeshState &a = pristine[i].states[m], &b = written[i].states[m];
      ASSERT_EQ(a.pairs, b.pairs);
      ASSERT_EQ(a.force_N, b.force_N) << i << " mesh " << m;
      ASSERT_EQ(a.stiffness_N_m, b.stiffness_N_m);
      ASSERT_EQ(a.friction_N, b.friction_N);
      pairs += a.pairs;
    }
  }
  EXPECT_GT(pairs, 0);
}
