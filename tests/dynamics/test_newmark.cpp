// Newmark-beta integrator: order of accuracy and energy behaviour on linear
// systems with closed-form solutions.
#include "dynamics/newmark.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pw::dynamics;

namespace {

/// M a + K q = 0 with constant matrices (and optional constant force f).
class LinearSystem final : public SecondOrderSystem {
public:
  LinearSystem(Eigen::MatrixXd M, Eigen::MatrixXd K) : M_(std::move(M)), K_(std::move(K)) {}
  int size() const override { return static_cast<int>(M_.rows()); }
  const Eigen::MatrixXd& mass() const override { return M_; }
  double force_scale() const override { return 1.0; }
  void force(double, const Eigen::VectorXd& q, const Eigen::VectorXd&, Eigen::VectorXd& g, Eigen::MatrixXd* K,
             Eigen::MatrixXd* C) override {
    g = -K_ * q;
    if (K) *K = K_;
    if (C) C->setZero(size(), size());
  }

private:
  Eigen::MatrixXd M_, K_;
};

double oscillator_error(double dt, NewmarkScheme scheme) {
  // u'' + w^2 u = 0, u(0) = 1, u'(0) = 0: u = cos(w t). Error at t = 1.25
  // periods, where u = 0 and the O(dt^2) phase error shows at first order
  // (at a whole period it would show only quadratically, as O(dt^4)).
  const double w = 2 * std::numbers::pi;
  LinearSystem sys(Eigen::MatrixXd::Identity(1, 1), Eigen::MatrixXd::Constant(1, 1, w * w));
  NewmarkSolver solver(sys, dt, scheme);
  NewmarkState s;
  s.q = Eigen::VectorXd::Constant(1, 1.0);
  s.v = Eigen::VectorXd::Zero(1);
  solver.initialize(s);
  const int n = static_cast<int>(std::lround(1.25 / dt));
  for (int i = 0; i < n; ++i) solver.step(s);
  return std::fabs(s.q(0) - std::cos(w * s.t));
}

} // namespace

TEST(Newmark, AverageAccelerationConvergesAtSecondOrder) {
  // Halving dt four times; observed order log2(e(dt)/e(dt/2)) must be 2
  // within 0.05 (the asymptotic range is reached from 32 steps per period).
  double prev = oscillator_error(1.0 / 32, NewmarkScheme::average_acceleration());
  for (int k = 1; k <= 4; ++k) {
    const double e = oscillator_error(1.0 / (32 << k), NewmarkScheme::average_acceleration());
    EXPECT_NEAR(std::log2(prev / e), 2.0, 0.05) << "dt = 1/" << (32 << k);
    prev = e;
  }
}

TEST(Newmark, LinearAccelerationAlsoSecondOrder) {
  const double e1 = oscillator_error(1.0 / 64, NewmarkScheme::linear_acceleration());
  const double e2 = oscillator_error(1.0 / 128, NewmarkScheme::linear_acceleration());
  EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.05);
}

TEST(Newmark, AverageAccelerationConservesEnergyOfUndampedLinearSystem) {
  // The trapezoidal rule conserves (1/2) v'Mv + (1/2) q'Kq exactly for linear
  // undamped systems, whatever dt; only Newton round-off remains (1e-12).
  Eigen::MatrixXd M(3, 3), K(3, 3);
  M << 2, 0, 0, 0, 1, 0, 0, 0, 3;
  K << 400, -200, 0, -200, 500, -300, 0, -300, 300;
  LinearSystem sys(M, K);
  NewmarkSolver solver(sys, 0.05);  // coarse: ~7 steps per shortest period
  NewmarkState s;
  s.q = Eigen::Vector3d(0.01, -0.02, 0.005);
  s.v = Eigen::Vector3d(0.1, 0, -0.1);
  solver.initialize(s);
  auto energy = [&] { return 0.5 * s.v.dot(M * s.v) + 0.5 * s.q.dot(K * s.q); };
  const double e0 = energy();
  for (int i = 0; i < 100000; ++i) solver.step(s);
  EXPECT_NEAR(energy(), e0, 1e-10 * e0);
}
