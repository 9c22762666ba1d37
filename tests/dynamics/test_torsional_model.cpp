// The torsional planetary model as assembled from kinematics, against
// hand-derived equations (docs/derivation.md §3) and closed-form behaviour.
#include "dynamics/lumped_model.hpp"
#include "core/constants.hpp"
#include "dynamics/modal.hpp"
#include "dynamics/newmark.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace pw::dynamics;

namespace {

using pw::kPi;

/// The seed stage (m = 3 mm, 21/30/81, 20 deg), three planets.
StageLayout seed_layout() {
  StageLayout l;
  const double a = 20 * kPi / 180, m = 3e-3;
  l.sun_base_radius_m = 0.5 * m * 21 * std::cos(a);
  l.planet_base_radius_m = 0.5 * m * 30 * std::cos(a);
  l.ring_base_radius_m = 0.5 * m * 81 * std::cos(a);
  l.carrier_radius_m = 0.5 * m * (21 + 30);
  l.sun_planet_pressure_angle_rad = a;
  l.planet_ring_pressure_angle_rad = a;
  l.planet_angles_rad = {0, 2 * kPi / 3, 4 * kPi / 3};
  l.sun_mass_kg = 1.2;
  l.sun_inertia_kgm2 = 6e-4;
  l.planet_mass_kg = 2.5;
  l.planet_inertia_kgm2 = 2.5e-3;
  l.carrier_mass_kg = 4;
  l.carrier_inertia_kgm2 = 0.0175;
  return l;
}

/// Applies constant torques and integrates a linear system from rest.
class TorqueDriven final : public SecondOrderSystem {
public:
  TorqueDriven(Eigen::MatrixXd M, Eigen::MatrixXd K, Eigen::VectorXd f)
      : M_(std::move(M)), K_(std::move(K)), f_(std::move(f)) {}
  int size() const override { return static_cast<int>(M_.rows()); }
  const Eigen::MatrixXd& mass() const override { return M_; }
  double force_scale() const override { return f_.lpNorm<Eigen::Infinity>(); }
  void force(double, const Eigen::VectorXd& q, const Eigen::VectorXd&, Eigen::VectorXd& g, Eigen::MatrixXd* K,
             Eigen::MatrixXd* C) override {
    g = f_ - K_ * q;
    if (K) *K = K_;
    if (C) C->setZero(size(), size());
  }

private:
  Eigen::MatrixXd M_, K_;
  Eigen::VectorXd f_;
};

} // namespace

TEST(TorsionalModel, AssembledMatricesEqualHandDerivedEquations) {
  // Hand derivation (q = theta_s, theta_c, theta_p1..3, all CCW):
  //   delta_sp = r_bs th_s - (r_bs + r_bp) th_c + r_bp th_p
  //   delta_pr = -(r_br - r_bp) th_c - r_bp th_p
  //   M = diag(I_s, I_c + N m_p a^2, I_p, I_p, I_p).
  const StageLayout l = seed_layout();
  const LumpedStructure s = build_torsional(l);
  const double rs = l.sun_base_radius_m, rp = l.planet_base_radius_m, rr = l.ring_base_radius_m;
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(5, 5), K = Eigen::MatrixXd::Zero(5, 5);
  M.diagonal() << l.sun_inertia_kgm2,
      l.carrier_inertia_kgm2 + 3 * l.planet_mass_kg * l.carrier_radius_m * l.carrier_radius_m, l.planet_inertia_kgm2,
      l.planet_inertia_kgm2, l.planet_inertia_kgm2;
  const double ksp = 7e8, kpr = 9e8;
  for (int i = 0; i < 3; ++i) {
    Eigen::VectorXd gsp = Eigen::VectorXd::Zero(5), gpr = Eigen::VectorXd::Zero(5);
    gsp(0) = rs;
    gsp(1) = -(rs + rp);
    gsp(2 + i) = rp;
    gpr(1) = -(rr - rp);
    gpr(2 + i) = -rp;
    K += ksp * gsp * gsp.transpose() + kpr * gpr * gpr.transpose();
  }
  EXPECT_LT((s.mass - M).norm(), 1e-12 * M.norm());
  const Eigen::MatrixXd Ka = mesh_stiffness_matrix(s, {ksp, kpr, ksp, kpr, ksp, kpr});
  EXPECT_LT((Ka - K).norm(), 1e-9 * K.norm());
  // Independent eigen-solve (non-symmetric M^-1 K by Eigen::EigenSolver).
  Eigen::EigenSolver<Eigen::MatrixXd> es(M.inverse() * K);
  std::vector<double> f_ref;
  for (int i = 0; i < 5; ++i) f_ref.push_back(std::sqrt(std::max(0.0, es.eigenvalues()(i).real())) / (2 * kPi));
  std::sort(f_ref.begin(), f_ref.end());
  const Eigen::VectorXd f = natural_frequencies(s.mass, Ka).frequencies_Hz;
  for (int i = 1; i < 5; ++i) EXPECT_NEAR(f(i), f_ref[i], 1e-8 * f_ref[i]);
}

TEST(TorsionalModel, RigidModeHasCarrierToSunRatioZsOverZsPlusZr) {
  // The only motion that deflects no mesh is the kinematic one.
  const LumpedStructure s = build_torsional(seed_layout());
  Eigen::MatrixXd G(s.meshes.size(), s.dofs);
  for (std::size_t m = 0; m < s.meshes.size(); ++m) G.row(m) = s.meshes[m].g.transpose();
  Eigen::FullPivLU<Eigen::MatrixXd> lu(G);
  const Eigen::MatrixXd null = lu.kernel();
  ASSERT_EQ(null.cols(), 1);
  EXPECT_NEAR(null(1, 0) / null(0, 0), 21.0 / (21.0 + 81.0), 1e-12);
}

TEST(TorsionalModel, StiffMeshesDriveCarrierAtKinematicRatioFromRest) {
  // Time domain: sun torque T on a stage at rest with very stiff meshes and a
  // free carrier; after the start-up the angles satisfy th_c/th_s = Zs/(Zs+Zr)
  // to O(T/k), here < 1e-6 relative.
  const StageLayout l = seed_layout();
  const LumpedStructure s = build_torsional(l);
  const Eigen::MatrixXd K = mesh_stiffness_matrix(s, std::vector<double>(6, 1e12));
  Eigen::VectorXd f = Eigen::VectorXd::Zero(s.dofs);
  f(0) = 10.0;
  TorqueDriven sys(s.mass, K, f);
  const double fmax = natural_frequencies(s.mass, K).frequencies_Hz.maxCoeff();
  NewmarkSolver solver(sys, 1.0 / (32 * fmax));
  NewmarkState st;
  st.q = Eigen::VectorXd::Zero(s.dofs);
  st.v = Eigen::VectorXd::Zero(s.dofs);
  solver.initialize(st);
  for (int i = 0; i < 20000; ++i) solver.step(st);
  EXPECT_NEAR(st.q(1) / st.q(0), 21.0 / 102.0, 1e-6 * 21.0 / 102.0);
  // Speeds carry the undamped start-up vibration (relative amplitude ~1e-3).
  EXPECT_NEAR(st.v(1) / st.v(0), 21.0 / 102.0, 2e-3 * 21.0 / 102.0);
}

TEST(TorsionalModel, EnergyConservedOver1000MeshPeriodsWithConstantStiffness) {
  // No damping, no friction, constant mesh stiffness: the assembled torsional
  // model keeps (1/2)v'Mv + (1/2)q'Kq to 1e-9 relative over 1000 mesh
  // periods of the seed case at 400 rpm (111.2 Hz), 32 steps per highest
  // period. (Average acceleration conserves it exactly up to round-off.)
  const LumpedStructure s = build_torsional(seed_layout());
  const Eigen::MatrixXd K = mesh_stiffness_matrix(s, {9e8, 1.28e9, 9e8, 1.28e9, 9e8, 1.28e9});
  TorqueDriven sys(s.mass, K, Eigen::VectorXd::Zero(s.dofs));
  const double fmax = natural_frequencies(s.mass, K).frequencies_Hz.maxCoeff();
  const double dt = 1.0 / (32 * fmax);
  NewmarkSolver solver(sys, dt);
  NewmarkState st;
  st.q = Eigen::VectorXd::Zero(s.dofs);
  st.q(2) = 1e-5;  // a planet twisted by 10 urad
  st.v = Eigen::VectorXd::Zero(s.dofs);
  st.v(0) = 1e-3;
  solver.initialize(st);
  auto energy = [&] { return 0.5 * st.v.dot(s.mass * st.v) + 0.5 * st.q.dot(K * st.q); };
  const double e0 = energy();
  const int steps = static_cast<int>(1000 / 111.18 / dt);
  double worst = 0;
  for (int i = 0; i < steps; ++i) {
    solver.step(st);
    if (i % 1000 == 0) worst = std::max(worst, std::fabs(energy() - e0) / e0);
  }
  worst = std::max(worst, std::fabs(energy() - e0) / e0);
  EXPECT_LT(worst, 1e-9);
}
