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

namespace {

/// Duffing oscillator u'' + u + eps u^3 = 0: nonlinear, so an earlier step's iteration matrix
/// is only approximate and Newton's chord iterations contract linearly.
class Duffing final : public SecondOrderSystem {
public:
  explicit Duffing(double eps) : eps_(eps), M_(Eigen::MatrixXd::Identity(1, 1)) {}
  int size() const override { return 1; }
  const Eigen::MatrixXd& mass() const override { return M_; }
  double force_scale() const override { return 1.0; }
  void force(double, const Eigen::VectorXd& q, const Eigen::VectorXd&, Eigen::VectorXd& g, Eigen::MatrixXd* K,
             Eigen::MatrixXd* C) override {
    const double u = q(0);
    g = Eigen::VectorXd::Constant(1, -u - eps_ * u * u * u);
    if (K) *K = Eigen::MatrixXd::Constant(1, 1, 1 + 3 * eps_ * u * u);
    if (C) C->setZero(1, 1);
  }

private:
  double eps_;
  Eigen::MatrixXd M_;
};

struct DuffingRun {
  double u = 0, v = 0;
  long evaluations = 0, steps = 0;
};

/// 10 periods of the linearized oscillator (2 pi each) in `per_period` steps per period.
DuffingRun run_duffing(const NewtonSettings& newton, int per_period = 400) {
  Duffing sys(10.0);
  NewmarkSolver solver(sys, 2 * std::numbers::pi / per_period, {}, newton);
  NewmarkState s;
  s.q = Eigen::VectorXd::Constant(1, 1.0);
  s.v = Eigen::VectorXd::Zero(1);
  solver.initialize(s);
  for (int i = 0; i < 10 * per_period; ++i) solver.step(s);
  return {s.q(0), s.v(0), solver.statistics().force_evaluations, solver.statistics().steps};
}

DuffingRun run_duffing(bool predicted_stop, int per_period = 400) {
  NewtonSettings newton;
  newton.predicted_stop = predicted_stop;
  return run_duffing(newton, per_period);
}

double per_step(const DuffingRun& r) { return static_cast<double>(r.evaluations) / static_cast<double>(r.steps); }

} // namespace

TEST(Newmark, PredictedStopChangesTheSolutionFarLessThanTheStepWithFewerEvaluations) {
  // The predicted stop accepts the chord iterate whose residual is predicted (not measured) to be
  // within Newton's tolerance: the same iterate the measured stop evaluates and accepts, unless
  // the prediction fails. After 10 periods the states agree (bit for bit here; the bound is 1e-4
  // of what halving the step changes, the discretization error), with fewer evaluations.
  const DuffingRun measured = run_duffing(false), predicted = run_duffing(true);
  const DuffingRun halved = run_duffing(false, 800);
  const double discretization = std::fabs(halved.u - measured.u);
  ASSERT_GT(discretization, 1e-6);
  EXPECT_LT(std::fabs(predicted.u - measured.u), 1e-4 * discretization);
  EXPECT_EQ(predicted.steps, measured.steps);
  EXPECT_LT(per_step(predicted), per_step(measured) - 0.5);
  std::printf("u after 10 periods: |predicted - measured stop| = %.3g, |dt/2 - dt| = %.3g; force evaluations "
              "per step %.3f (measured stop) vs %.3f (predicted)\n",
              std::fabs(predicted.u - measured.u), discretization, per_step(measured), per_step(predicted));
}

TEST(Newmark, QuadraticStartChangesTheSolutionFarLessThanTheStepWithFewerEvaluations) {
  // Newton's start extrapolated from three accelerations is O(dt^3) from the root instead of
  // O(dt^2): fewer chord iterations, the same root to Newton's tolerance. Both runs measure every
  // stop (no prediction), so only the start differs. Bound: 1e-4 of the discretization error,
  // as for the predicted stop.
  NewtonSettings linear, quadratic;
  linear.start = NewtonStart::Linear;
  quadratic.start = NewtonStart::Quadratic;
  linear.predicted_stop = quadratic.predicted_stop = false;
  const DuffingRun a = run_duffing(linear), b = run_duffing(quadratic);
  const double discretization = std::fabs(run_duffing(linear, 800).u - a.u);
  ASSERT_GT(discretization, 1e-6);
  EXPECT_LT(std::fabs(b.u - a.u), 1e-4 * discretization);
  EXPECT_LT(std::fabs(b.v - a.v), 1e-4 * discretization);
  EXPECT_LT(per_step(b), per_step(a));
  std::printf("|quadratic - linear start| = %.3g (discretization %.3g); evaluations per step %.3f -> %.3f\n",
              std::fabs(b.u - a.u), discretization, per_step(a), per_step(b));
}
