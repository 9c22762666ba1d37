// Levenberg-Marquardt on an analytic model with a known covariance.
#include "diagnose/fit.hpp"

#include "core/error.hpp"

#include <Eigen/Dense>
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace pw::diagnose {
namespace {

TEST(Fit, RecoversExponentialDecayParametersAndTheirCovariance) {
  // y = a exp(-b t) + noise (unit variance after whitening by sigma).
  const double a = 2.5, b = 1.7, sigma = 0.02;
  const int m = 200;
  std::vector<double> t(m), y(m);
  std::mt19937 rng(7);
  std::normal_distribution<double> nd(0.0, sigma);
  for (int i = 0; i < m; ++i) {
    t[i] = 3.0 * i / m;
    y[i] = a * std::exp(-b * t[i]) + nd(rng);
  }
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) r[i] = (y[i] - x[0] * std::exp(-x[1] * t[i])) / sigma;
    return r;
  };
  LmOptions o;
  o.max_iterations = 50;
  o.relative_tolerance = 1e-10;
  o.step = 1e-6;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {{0.1, 10, true}, {0.01, 10, false}}, {1.0, 0.5}, o);
  // Analytic covariance (J^T J)^{-1} at the truth.
  double s11 = 0, s12 = 0, s22 = 0;
  for (int i = 0; i < m; ++i) {
    const double e = std::exp(-b * t[i]);
    const double j1 = -e / sigma, j2 = a * t[i] * e / sigma;
    s11 += j1 * j1, s12 += j1 * j2, s22 += j2 * j2;
  }
  const double det = s11 * s22 - s12 * s12;
  const double sa = std::sqrt(s22 / det), sb = std::sqrt(s11 / det);
  EXPECT_NEAR(r.x[0], a, 4 * sa);
  EXPECT_NEAR(r.x[1], b, 4 * sb);
  EXPECT_NEAR(r.std_error[0], sa, 0.05 * sa);
  EXPECT_NEAR(r.std_error[1], sb, 0.05 * sb);
  EXPECT_NEAR(r.covariance[0][1], -s12 / det, 0.05 * std::fabs(s12 / det));
  EXPECT_NEAR(r.cost, m, 4 * std::sqrt(2.0 * m));  // chi2(m - 2)
}

TEST(Fit, TheEstimateIsTheSameBitForBitWhateverOpenMPsThreadCount) {
  // A diagnosis's fits have thousands of residuals and several parameters: products large enough
  // for Eigen to split them over OpenMP's threads with a blocking that depends on their number,
  // which would round the sums differently for another OMP_NUM_THREADS (session 71: a
  // calibration apart from the eighth digit on). The build keeps Eigen single-threaded
  // (EIGEN_DONT_PARALLELIZE); here the same fit with 1 and 2 OpenMP threads must agree exactly.
  const int m = 4000, p = 8;
  std::vector<double> t(m), y(m);
  std::mt19937 rng(71);
  std::normal_distribution<double> nd(0.0, 0.01);
  for (int i = 0; i < m; ++i) {
    t[i] = 4.0 * i / m;
    y[i] = nd(rng);
    for (int k = 0; k < p; ++k) y[i] += (1.0 + 0.1 * k) * std::cos((k + 1) * t[i] + 0.3 * k);
  }
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) {
      double model = 0;
      for (int k = 0; k < p; ++k) model += x[k] * std::cos((k + 1) * t[i] + 0.3 * k);
      r[i] = (y[i] - model) / 0.01;
    }
    return r;
  };
  LmOptions o;
  o.max_iterations = 20;
  o.relative_tolerance = 1e-12;
  o.step = 1e-6;
  o.threads = 1;
  const std::vector<Bound> box(p, Bound{-10, 10, false});
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  const LmResult one = levenberg_marquardt(f, box, std::vector<double>(p, 0.5), o);
  omp_set_num_threads(2);
  const LmResult two = levenberg_marquardt(f, box, std::vector<double>(p, 0.5), o);
  omp_set_num_threads(before);
  for (int k = 0; k < p; ++k) {
    EXPECT_EQ(one.x[k], two.x[k]) << k;
    EXPECT_EQ(one.std_error[k], two.std_error[k]) << k;
  }
  EXPECT_EQ(one.cost, two.cost);
}

TEST(Fit, AParameterTheModelCannotMoveOnEitherSideIsHeldWhileTheOthersConverge) {
  // r = (x0 - 3, x1 - 5), but the model fails (pw::SolverError) whenever x1 leaves its start
  // value 1: x1's Jacobian column fails both ways. The fit must finish, keep x1 = 1, fit x0.
  ResidualFn f = [](const std::vector<double>& x, const std::vector<double>*) {
    if (x[1] != 1.0) throw SolverError("jammed");
    return std::vector<double>{x[0] - 3.0, x[1] - 5.0};
  };
  LmOptions o;
  o.max_iterations = 20;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {{0, 10, false}, {0, 10, false}}, {1.0, 1.0}, o);
  EXPECT_NEAR(r.x[0], 3.0, 1e-6);
  EXPECT_EQ(r.x[1], 1.0);
  EXPECT_GE(r.failed_evaluations, 2);  // both sides of x1, at least once
}

TEST(Fit, AParameterTheResidualDoesNotSeeHasNoStandardErrorAndLeavesTheOthersTheirs) {
  // r_i = (x0 t_i + x1 - y_i) / sigma; x2 does not enter (a saturated bandwidth, a held
  // parameter): its Jacobian column is zero. x0 and x1 keep the straight line's closed-form
  // covariance sigma^2 (T^T T)^-1; x2 gets NaN.
  const int m = 50;
  const double sigma = 0.1;
  std::vector<double> t(m), y(m);
  for (int i = 0; i < m; ++i) t[i] = i / 10.0, y[i] = 2.0 * t[i] + 1.0 + (i % 2 ? sigma : -sigma);
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) r[i] = (x[0] * t[i] + x[1] - y[i]) / sigma;
    return r;
  };
  LmOptions o;
  o.max_iterations = 20;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {{-10, 10, false}, {-10, 10, false}, {1, 100, true}}, {0.0, 0.0, 10.0}, o);
  double st = 0, stt = 0;
  for (double ti : t) st += ti, stt += ti * ti;
  const double det = m * stt - st * st;  // T^T T = [[stt, st], [st, m]]; J = T / sigma
  const double s0 = sigma * std::sqrt(m / det), s1 = sigma * std::sqrt(stt / det);
  EXPECT_NEAR(r.std_error[0], s0, 1e-6 * s0);  // linear model: exact up to the differences' round-off
  EXPECT_NEAR(r.std_error[1], s1, 1e-6 * s1);
  EXPECT_TRUE(std::isnan(r.std_error[2]));
  EXPECT_TRUE(std::isnan(r.covariance[0][2]));
}

TEST(Fit, TheSensitivityMovesTheEstimateAsRefittingShiftedDataDoesForALinearModel) {
  // r_i = (x0 t_i + x1 - y_i) / sigma. Data shifted by d (a systematic error, not noise) move
  // the least-squares line by (T^T T)^-1 T^T d; the residual shifts by dr = -d / sigma, and
  // LmResult::sensitivity must give dx = -S dr. Checked against a second fit of the shifted
  // data and against the closed form, for a shift no multiple of the line (so both move).
  const int m = 40;
  const double sigma = 0.05;
  std::vector<double> t(m), y(m), d(m);
  for (int i = 0; i < m; ++i) {
    t[i] = i / 8.0;
    y[i] = -1.5 * t[i] + 0.5 + (i % 3 ? sigma : -2 * sigma);
    d[i] = 0.02 * std::sin(0.7 * i) + 0.01 * t[i];
  }
  auto residual_of = [&](const std::vector<double>& data) {
    return ResidualFn([&, data](const std::vector<double>& x, const std::vector<double>*) {
      std::vector<double> r(m);
      for (int i = 0; i < m; ++i) r[i] = (x[0] * t[i] + x[1] - data[i]) / sigma;
      return r;
    });
  };
  LmOptions o;
  o.max_iterations = 30;
  o.relative_tolerance = 1e-14;
  o.step_tolerance = 1e-14;
  o.threads = 1;
  const std::vector<Bound> box{{-10, 10, false}, {-10, 10, false}};
  const LmResult a = levenberg_marquardt(residual_of(y), box, {0.0, 0.0}, o);
  std::vector<double> ys(m);
  for (int i = 0; i < m; ++i) ys[i] = y[i] + d[i];
  const LmResult b = levenberg_marquardt(residual_of(ys), box, a.x, o);
  // Closed form: [x0; x1] moves by (X^T X)^-1 X^T d with X = [t 1].
  double st = 0, stt = 0, sd = 0, std_ = 0;
  for (int i = 0; i < m; ++i) st += t[i], stt += t[i] * t[i], sd += d[i], std_ += t[i] * d[i];
  const double det = m * stt - st * st;
  const double dx0 = (m * std_ - st * sd) / det, dx1 = (stt * sd - st * std_) / det;
  ASSERT_EQ(a.sensitivity.size(), 2u);
  for (int k = 0; k < 2; ++k) {
    ASSERT_EQ(a.sensitivity[static_cast<std::size_t>(k)].size(), static_cast<std::size_t>(m));
    double dx = 0;
    for (int i = 0; i < m; ++i) dx -= a.sensitivity[static_cast<std::size_t>(k)][static_cast<std::size_t>(i)] * (-d[i] / sigma);
    const double closed = k == 0 ? dx0 : dx1;
    // Forward differences of a linear residual are exact up to round-off (1e-6 relative, as above).
    EXPECT_NEAR(dx, closed, 1e-6 * std::fabs(closed)) << "parameter " << k;
    EXPECT_NEAR(b.x[static_cast<std::size_t>(k)] - a.x[static_cast<std::size_t>(k)], closed, 1e-6 * std::fabs(closed))
        << "parameter " << k;
  }
  EXPECT_GT(std::fabs(dx0), 1e-4);  // the shift does move both
  EXPECT_GT(std::fabs(dx1), 1e-4);
}

TEST(Fit, ShiftsMovingTogetherAddTheirEffectsWhereIndependentOnesAddInQuadrature) {
  // A scale theta fitted to r_i = (theta - 1) a_i / sigma: a residual shift w moves it by
  // -sigma sum a_i w_i / sum a^2 (LmResult::sensitivity). Two entries each shift
  // half the cells by -0.4 a_i / sigma (a 40 % relative error of each line): each moves the
  // estimate by 0.4 times its share of sum a^2, so independent they give 0.4 sqrt(f^2 + (1-f)^2)
  // and together 0.4 (f + (1-f)) = 0.4 -- the one relative error the whole change carries.
  // With the second shift's sign reversed the correlated sum cancels to 0.4 |2f - 1| and the
  // independent reading is the larger.
  const int m = 10;
  const double sigma = 0.1;
  std::vector<double> a(m);
  for (int i = 0; i < m; ++i) a[static_cast<std::size_t>(i)] = 1.0 + 0.1 * i;
  LmOptions o;
  o.threads = 1;
  const ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i) r[static_cast<std::size_t>(i)] = (x[0] - 1.0) * a[static_cast<std::size_t>(i)] / sigma;
    return r;
  };
  const LmResult fit = levenberg_marquardt(f, {{0.0, 3.0, false}}, {1.0}, o);
  std::vector<double> w1(m, 0.0), w2(m, 0.0), w2_reversed(m, 0.0);
  double s1 = 0, s2 = 0;
  for (int i = 0; i < m; ++i) {
    const std::size_t k = static_cast<std::size_t>(i);
    (i < m / 2 ? w1 : w2)[k] = -0.4 * a[k] / sigma;
    w2_reversed[k] = -w2[k];
    (i < m / 2 ? s1 : s2) += a[k] * a[k];
  }
  const double share = s1 / (s1 + s2);
  // Forward differences of a linear residual: the sensitivity is exact to round-off.
  const double tol = 1e-6;
  EXPECT_NEAR(propagated_std(fit, {w1, w2})[0], 0.4 * std::hypot(share, 1 - share), tol);
  EXPECT_NEAR(propagated_std_correlated(fit, {w1, w2})[0], 0.4, tol);
  EXPECT_NEAR(propagated_std_correlated(fit, {w1, w2_reversed})[0], 0.4 * std::fabs(2 * share - 1), tol);
  EXPECT_LT(propagated_std_correlated(fit, {w1, w2_reversed})[0], propagated_std(fit, {w1, w2_reversed})[0]);
  EXPECT_EQ(propagated_std_correlated(fit, {})[0], 0.0);
}

TEST(Fit, ALevelsSpreadMovesAnEstimateByWhatRefittingWithTheLevelHeldElsewhereMovesIt) {
  // A linear model r = (A x - y) / sigma in three parameters: a size x0 that trades against a
  // level x1 (columns nearly parallel) and a second level x2. Holding the levels at x1 + d1,
  // x2 + d2 and refitting x0 alone (closed form) moves x0 by b . d, b the regression slope of x0
  // on the levels in the joint fit's covariance; level_spread_std with spreads s1, s2 must equal
  // sqrt((b1 s1)^2 + (b2 s2)^2), each b_j read off such a refit. An independent computation: the
  // refits never touch the covariance.
  const int m = 12;
  const double sigma = 0.05;
  Eigen::MatrixXd A(m, 3);
  Eigen::VectorXd y(m);
  for (int i = 0; i < m; ++i) {
    const double t = 0.1 * i;
    A(i, 0) = 1.0 + t;
    A(i, 1) = 1.0 + 0.8 * t + 0.05 * t * t;
    A(i, 2) = std::cos(3 * t);
    y(i) = 2.0 * A(i, 0) + 0.5 * A(i, 1) - 0.3 * A(i, 2) + 0.01 * std::sin(7.0 * i);
  }
  LmOptions o;
  o.threads = 1;
  const ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> r(m);
    for (int i = 0; i < m; ++i)
      r[static_cast<std::size_t>(i)] = (A(i, 0) * x[0] + A(i, 1) * x[1] + A(i, 2) * x[2] - y(i)) / sigma;
    return r;
  };
  const LmResult fit = levenberg_marquardt(f, {{-10, 10, false}, {-10, 10, false}, {-10, 10, false}}, {0, 0, 0}, o);
  ASSERT_TRUE(std::isfinite(fit.std_error[0]));
  // x0 refitted with x1, x2 held at the joint fit plus (d1, d2): x0 = a0 . (y - a1 x1 - a2 x2) / |a0|^2.
  const auto refit_x0 = [&](double d1, double d2) {
    const Eigen::VectorXd rest = y - A.col(1) * (fit.x[1] + d1) - A.col(2) * (fit.x[2] + d2);
    return A.col(0).dot(rest) / A.col(0).squaredNorm();
  };
  const double x0 = refit_x0(0, 0);
  // Holding a level and refitting only x0 is the conditional mean when the other level is refitted
  // too: so for b1, refit x0 and x2 with x1 held (a two-column least squares).
  const auto refit_x0_x2 = [&](double d1) {
    Eigen::MatrixXd B(m, 2);
    B << A.col(0), A.col(2);
    const Eigen::VectorXd sol = B.colPivHouseholderQr().solve(y - A.col(1) * (fit.x[1] + d1));
    return sol(0);
  };
  const auto refit_x0_x1 = [&](double d2) {
    Eigen::MatrixXd B(m, 2);
    B << A.col(0), A.col(1);
    const Eigen::VectorXd sol = B.colPivHouseholderQr().solve(y - A.col(2) * (fit.x[2] + d2));
    return sol(0);
  };
  const double s1 = 0.2, s2 = 0.1;
  const double b1 = (refit_x0_x2(s1) - refit_x0_x2(0)) / s1;
  const double b2 = (refit_x0_x1(s2) - refit_x0_x1(0)) / s2;
  // Forward-difference Jacobian of a linear residual: the covariance is exact to round-off, but the
  // levels enter together (Cov(L, L)^-1), so the tolerance is relative to the slopes.
  const double tol = 1e-6 * (std::fabs(b1) * s1 + std::fabs(b2) * s2);
  EXPECT_NEAR(level_spread_std(fit, 0, {{1, s1}}), std::fabs(b1) * s1, tol);
  EXPECT_NEAR(level_spread_std(fit, 0, {{2, s2}}), std::fabs(b2) * s2, tol);
  // Both levels: the regression on both. Holding both and refitting x0 alone is that slope pair.
  const double c1 = (refit_x0(s1, 0) - x0) / s1, c2 = (refit_x0(0, s2) - x0) / s2;
  EXPECT_NEAR(level_spread_std(fit, 0, {{1, s1}, {2, s2}}), std::hypot(c1 * s1, c2 * s2), tol);
  EXPECT_GT(std::fabs(c1), 0.5);  // the size does trade against the level
  EXPECT_EQ(level_spread_std(fit, 1, {{1, s1}}), 0.0);  // a level's own spread is not its fit's
  EXPECT_EQ(level_spread_std(fit, 0, {}), 0.0);
}

TEST(Fit, StaysInsideTheBoxAndFlagsTheBound) {
  // Minimum at x = 3 outside [0, 2]: the estimate sits on the upper bound.
  ResidualFn f = [](const std::vector<double>& x, const std::vector<double>*) {
    return std::vector<double>{x[0] - 3.0, 0.1 * (x[0] - 3.0)};
  };
  LmOptions o;
  o.threads = 1;
  o.max_iterations = 30;
  const LmResult r = levenberg_marquardt(f, {{0.0, 2.0, false}}, {0.5}, o);
  EXPECT_NEAR(r.x[0], 2.0, 1e-9);
  EXPECT_TRUE(r.at_bound[0]);
}

TEST(Fit, WithNoParametersReturnsTheModelAsItIsWithoutIterating) {
  // `diagnose --candidates backlash` leaves no nuisance parameters: the fit is one
  // evaluation (this crashed in the covariance step before).
  int calls = 0;
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    ++calls;
    EXPECT_TRUE(x.empty());
    return std::vector<double>{3.0, 4.0};
  };
  LmOptions o;
  o.threads = 1;
  const LmResult r = levenberg_marquardt(f, {}, {}, o);
  EXPECT_EQ(calls, 1);
  EXPECT_DOUBLE_EQ(r.cost, 25.0);
  EXPECT_TRUE(r.x.empty());
  EXPECT_TRUE(r.std_error.empty());
  EXPECT_TRUE(r.converged);
}

// SecantProfile: Gauss-Newton on a Broyden-updated secant Jacobian.

TEST(SecantProfile, OneStepReachesTheLeastSquaresSolutionOfALinearResidualAndPredictsItsCost) {
  // r(x) = A x - b with the exact Jacobian: one Gauss-Newton step is the normal-equation
  // solution, and the predicted cost is the true one (to round-off, 1e-10 relative).
  Eigen::MatrixXd A(3, 2);
  A << 1, 2, 0, 1, 3, -1;
  const Eigen::Vector3d b(1, -2, 0.5);
  const std::vector<double> x0{0.3, -0.1};
  const Eigen::VectorXd r0 = A * Eigen::Vector2d(x0[0], x0[1]) - b;
  const SecantProfile p(x0, r0, A);
  const auto s = p.gauss_newton_step({{-10, 10}, {-10, 10}});
  const Eigen::Vector2d xs = (A.transpose() * A).ldlt().solve(A.transpose() * b);
  EXPECT_NEAR(s.x[0], xs(0), 1e-12);
  EXPECT_NEAR(s.x[1], xs(1), 1e-12);
  const double cost = (A * xs - b).squaredNorm();
  EXPECT_NEAR(s.predicted_cost, cost, 1e-10 * cost);
}

TEST(SecantProfile, BroydenStepsFromAPoorSecantConvergeOnANonlinearResidual) {
  // r(x) = (x^2 - 2, 0.5 (x^2 - 2)): the minimum is sqrt(2). Starting at x = 1 with a
  // Jacobian from a far secant (x = 1 to 3: slope 4 instead of 2), the secant iteration
  // converges superlinearly: 8 steps reach 1e-9.
  auto r = [](double x) { return Eigen::Vector2d(x * x - 2, 0.5 * (x * x - 2)); };
  Eigen::MatrixXd J(2, 1);
  J.col(0) = (r(3.0) - r(1.0)) / 2.0;
  SecantProfile p({1.0}, r(1.0), J);
  for (int it = 0; it < 8; ++it) {
    const auto s = p.gauss_newton_step({{0.5, 5.0}});
    p.accept(s.x, r(s.x[0]));
  }
  EXPECT_NEAR(p.best_x()[0], std::sqrt(2.0), 1e-9);
  EXPECT_LT(p.best_cost(), 1e-16);
}

TEST(SecantProfile, StepStaysInsideTheBoxAndKeepsTheBestEvaluatedPoint) {
  // The unconstrained minimum x = 4 lies outside [0, 1]: the step stops at the bound.
  auto r = [](double x) { return Eigen::Matrix<double, 1, 1>(x - 4); };
  SecantProfile p({0.0}, r(0.0), Eigen::MatrixXd::Ones(1, 1));
  const auto s = p.gauss_newton_step({{0.0, 1.0}});
  EXPECT_EQ(s.x[0], 1.0);
  EXPECT_DOUBLE_EQ(s.predicted_cost, 9.0);
  p.accept(s.x, r(s.x[0]));
  p.accept({0.5}, r(0.5));  // a worse point does not replace the best
  EXPECT_EQ(p.best_x()[0], 1.0);
  EXPECT_DOUBLE_EQ(p.best_cost(), 9.0);
}

TEST(LocalMinimaOnClosedPath, FindsEachBasinOnceBestFirstWithTheEndsNextToTheCurrentValue) {
  // Two basins (indices 1 and 5) and a shoulder; index 0 and the last index neighbour the
  // current value 10 at both ends. A NaN is never a minimum, nor a better neighbour.
  const double nan = std::nan("");
  const std::vector<double> f{9, 4, 6, 7, nan, 3, 5, 8};
  const auto m = local_minima_on_closed_path(f, 10.0, 4);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0], 5u);
  EXPECT_EQ(m[1], 1u);
  // The path's ends count: a value below `end` at the first index is a minimum there.
  EXPECT_EQ(local_minima_on_closed_path({2, 5, 6}, 10.0, 4), (std::vector<std::size_t>{0}));
  // Nothing below the current value: no minima; the count is capped.
  EXPECT_TRUE(local_minima_on_closed_path({12, 11, 13}, 10.0, 4).empty());
  EXPECT_EQ(local_minima_on_closed_path({1, 2, 1, 2, 1}, 10.0, 2).size(), 2u);
}

// --- the screening's box-constrained linear step (boxed_least_squares) ------------------

/// Minimum over b of |r + A a + B b|^2 for a given a (closed form), for brute-force checks.
double cost_at(const Eigen::MatrixXd& A, const Eigen::VectorXd& a, const Eigen::MatrixXd& B, const Eigen::VectorXd& r) {
  const Eigen::VectorXd re = r + A * a;
  if (B.cols() == 0) return re.squaredNorm();
  const Eigen::VectorXd b = -(B.transpose() * B).ldlt().solve(B.transpose() * re);
  return (re + B * b).squaredNorm();
}

TEST(BoxedLeastSquares, InsideTheBoxItIsTheUnconstrainedSolution) {
  std::mt19937 rng(11);
  std::normal_distribution<double> nd;
  const Eigen::Index m = 40;
  Eigen::MatrixXd A(m, 3), B(m, 2);
  Eigen::VectorXd r(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    for (Eigen::Index j = 0; j < 3; ++j) A(k, j) = nd(rng);
    for (Eigen::Index j = 0; j < 2; ++j) B(k, j) = nd(rng);
    r(k) = nd(rng);
  }
  Eigen::MatrixXd J(m, 5);
  J << A, B;
  const Eigen::VectorXd x = J.colPivHouseholderQr().solve(-r);
  const Eigen::VectorXd big = Eigen::VectorXd::Constant(3, 1e6);
  const BoxedLeastSquares s = boxed_least_squares(A, -big, big, B, r);
  for (Eigen::Index j = 0; j < 3; ++j) EXPECT_NEAR(s.a(j), x(j), 1e-10);
  for (Eigen::Index j = 0; j < 2; ++j) EXPECT_NEAR(s.b(j), x(3 + j), 1e-10);
  EXPECT_NEAR(s.cost, (r + J * x).squaredNorm(), 1e-10);
  for (bool h : s.held) EXPECT_FALSE(h);
}

TEST(BoxedLeastSquares, AStepBeyondTheBoxIsHeldOnTheBoundItCrossedNotAtZero) {
  // Orthogonal columns separate the problem: the exact answer is each unconstrained value clipped.
  // a_0 wants 10 on [-1, 2] -> 2; a_1 wants -0.5 on [-1, 1] -> -0.5; b wants 3.
  const Eigen::Index m = 3;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(m, 2), B = Eigen::MatrixXd::Zero(m, 1);
  A(0, 0) = 1, A(1, 1) = 1, B(2, 0) = 1;
  const Eigen::Vector3d r(-10, 0.5, -3);
  const BoxedLeastSquares s = boxed_least_squares(A, Eigen::Vector2d(-1, -1), Eigen::Vector2d(2, 1), B, r);
  EXPECT_DOUBLE_EQ(s.a(0), 2.0);
  EXPECT_TRUE(s.held[0]);
  EXPECT_DOUBLE_EQ(s.a(1), -0.5);
  EXPECT_FALSE(s.held[1]);
  EXPECT_DOUBLE_EQ(s.b(0), 3.0);
  EXPECT_DOUBLE_EQ(s.cost, 64.0);  // (-10 + 2)^2: the improvement 100 - 64 is what the box allows, not 0
}

TEST(BoxedLeastSquares, CorrelatedColumnsMatchABruteForceSearchOfTheBox) {
  // Two correlated candidate columns (cos 0.6) and a nuisance column; the unconstrained step
  // leaves the box on one side: the projected active set's cost equals the grid minimum over
  // the box (b profiled in closed form) to the grid's resolution, and no grid point is lower.
  const Eigen::Index m = 4;
  Eigen::MatrixXd A(m, 2), B(m, 1);
  A << 1, 0.6, 0, 0.8, 0, 0, 0, 0;
  B << 0, 0, 1, 0.3;
  const Eigen::Vector4d r(-5, -1, 0.4, 2);
  const Eigen::Vector2d lower(-1, -1), upper(1.5, 1.5);
  const BoxedLeastSquares s = boxed_least_squares(A, lower, upper, B, r);
  double best = std::numeric_limits<double>::infinity();
  const int n = 401;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d a(lower(0) + (upper(0) - lower(0)) * i / (n - 1), lower(1) + (upper(1) - lower(1)) * j / (n - 1));
      best = std::min(best, cost_at(A, a, B, r));
    }
  EXPECT_LE(s.cost, best + 1e-9);
  EXPECT_NEAR(s.cost, cost_at(A, s.a, B, r), 1e-10);  // the reported cost is the cost at the step
  EXPECT_GE(s.a(0), lower(0));
  EXPECT_LE(s.a(0), upper(0));
  EXPECT_GE(s.a(1), lower(1));
  EXPECT_LE(s.a(1), upper(1));
}

TEST(BoxedLeastSquares, NeverEndsAboveTheCostOfNoStepWhereHoldingEachCrossedBoundDid) {
  // The unconstrained step (-1.13, -1.98) leaves both boxes. Holding each parameter on the bound it
  // crossed (the projected active set used before session 64) gives a = (0, -1) and cost 18, above
  // the 17 of no step at all; the box's minimum is a = (0, -0.4): with a_0 on its bound the
  // one-dimensional minimum in a_1 is -(r . A_1) / |A_1|^2 = -2 / 5, cost 17 - 2^2 / 5 = 16.2. A
  // fourth row carries a free nuisance column, which the minimum sets to -5 whatever a is.
  Eigen::MatrixXd A(4, 2), B = Eigen::MatrixXd::Zero(4, 1);
  A << 3, 0, -2, 2, 3, -1, 0, 0;
  B(3, 0) = 1;
  const Eigen::Vector4d r(3, 2, 2, 5);
  const BoxedLeastSquares s = boxed_least_squares(A, Eigen::Vector2d(0, -1), Eigen::Vector2d(1, 0), B, r);
  EXPECT_NEAR(s.a(0), 0.0, 1e-12);
  EXPECT_NEAR(s.a(1), -0.4, 1e-12);
  EXPECT_NEAR(s.b(0), -5.0, 1e-12);
  EXPECT_NEAR(s.cost, 16.2, 1e-12);
  EXPECT_TRUE(s.held[0]);
  EXPECT_FALSE(s.held[1]);
}

// The Karush-Kuhn-Tucker conditions of the convex box problem, necessary and sufficient for its
// minimum: with b profiled, the gradient 2 A^T (r + A a + B b) is zero in every parameter strictly
// inside its box, >= 0 on a lower bound, <= 0 on an upper one. Tolerance: 1e-7 of the gradient's
// scale |A_i| |residual|, far above round-off (1e-15 relative) and far below a missed minimum.
void expect_box_minimum(const Eigen::MatrixXd& A, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper,
                        const Eigen::MatrixXd& B, const Eigen::VectorXd& r) {
  const BoxedLeastSquares s = boxed_least_squares(A, lower, upper, B, r);
  const Eigen::VectorXd res = r + A * s.a + B * s.b;
  EXPECT_NEAR(s.cost, res.squaredNorm(), 1e-9 * res.squaredNorm());
  const Eigen::VectorXd gb = B.transpose() * res;
  for (Eigen::Index j = 0; j < B.cols(); ++j) EXPECT_NEAR(gb(j), 0.0, 1e-7 * B.col(j).norm() * res.norm());
  const Eigen::VectorXd ga = A.transpose() * res;
  for (Eigen::Index i = 0; i < A.cols(); ++i) {
    const double tol = 1e-7 * A.col(i).norm() * res.norm();
    ASSERT_GE(s.a(i), lower(i));
    ASSERT_LE(s.a(i), upper(i));
    if (s.a(i) > lower(i) && s.a(i) < upper(i))
      EXPECT_NEAR(ga(i), 0.0, tol) << "parameter " << i << " inside its box";
    else if (s.a(i) == lower(i))
      EXPECT_GE(ga(i), -tol) << "parameter " << i << " on its lower bound";
    else
      EXPECT_LE(ga(i), tol) << "parameter " << i << " on its upper bound";
  }
}

void random_box_problems(Eigen::Index p, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> nd;
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Index m = 3 * p + 4, q = 2;
    Eigen::MatrixXd A(m, p), B(m, q);
    Eigen::VectorXd r(m), lower(p), upper(p);
    for (Eigen::Index k = 0; k < m; ++k) {
      // Correlated columns (a common part) make the bounds interact, as the secants of one
      // candidate's parameters do.
      const double common = nd(rng);
      for (Eigen::Index j = 0; j < p; ++j) A(k, j) = common + 0.5 * nd(rng);
      for (Eigen::Index j = 0; j < q; ++j) B(k, j) = nd(rng);
      r(k) = 3 * nd(rng);
    }
    for (Eigen::Index j = 0; j < p; ++j) {
      lower(j) = -std::fabs(nd(rng));
      upper(j) = std::fabs(nd(rng));
    }
    expect_box_minimum(A, lower, upper, B, r);
  }
}

TEST(BoxedLeastSquares, ThreeParametersMeetTheOptimalityConditionsOfTheBoxOverTheFaces) { random_box_problems(3, 5); }

TEST(BoxedLeastSquares, TenParametersMeetTheOptimalityConditionsOfTheBoxByCoordinateDescent) {
  random_box_problems(10, 6);
}

TEST(BoxedLeastSquares, MismatchedShapesAreRefused) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 2), B = Eigen::MatrixXd::Zero(4, 1);
  EXPECT_THROW(boxed_least_squares(A, Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 1), B, Eigen::Vector3d::Zero()),
               std::invalid_argument);
}

// The damping ratio's box [z/5, min(1, 5 z)] on a log scale: l exp(log(u/l)) rounds above u = 1
// for about a fifth of the z in (0.2, 1), which validate() refused (contact.mesh_damping_ratio
// <= 1). Every value from_unit gives lies in the box.
TEST(Fit, UnitToPhysicalMappingNeverLeavesTheBoxByRoundOff) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> z_of(0.2, 1.0);
  int above_before_clamp = 0;
  for (int i = 0; i < 20000; ++i) {
    const double z = z_of(rng);
    const Bound b{z / 5, std::min(1.0, 5 * z), true};
    if (b.lower * std::exp(std::log(b.upper / b.lower)) > b.upper) ++above_before_clamp;
    EXPECT_LE(from_unit(b, 1.0), b.upper);
    EXPECT_GE(from_unit(b, 0.0), b.lower);
    EXPECT_LE(from_unit(b, 1.0 - 1e-17), b.upper);
    const Bound lin{0.1 * z, 0.3 + z, false};
    EXPECT_LE(from_unit(lin, 1.0), lin.upper);
    EXPECT_GE(from_unit(lin, 0.0), lin.lower);
  }
  EXPECT_GT(above_before_clamp, 1000) << "the round-off this guards against no longer occurs here";
}

} // namespace
} // namespace pw::diagnose
