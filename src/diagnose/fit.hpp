// Bounded nonlinear least squares: Levenberg-Marquardt in a normalized box.
//
// Each parameter x_i in [l_i, u_i] is mapped to v_i in [0, 1], linearly or,
// for parameters whose natural scale is logarithmic, as
// v = ln(x / l) / ln(u / l). LM minimizes |r(x(v))|^2 with
//   (J^T J + lambda diag(J^T J)) dv = -J^T r     (Marquardt 1963 scaling)
// and projects each trial step onto the box. The Jacobian is by forward
// differences (backward at the upper bound) with step h in v; its columns are
// independent model evaluations and run in parallel (OpenMP; each call must
// be thread-safe). The residual is assumed whitened (unit variance): the
// covariance of the estimate is (J^T J)^{-1} in v, mapped to x by the
// derivative of the transform, and multiplied by `covariance_scale`
// (e.g. the whitened residual of compare.hpp).
//
// References: K. Levenberg, Q. Appl. Math. 2:164-168, 1944; D. W. Marquardt,
// J. SIAM 11(2):431-441, 1963; J. J. More, "The Levenberg-Marquardt
// algorithm: implementation and theory", LNM 630, 1978.
#pragma once

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

namespace pw::diagnose {

struct Bound {
  double lower = 0, upper = 1;
  bool log_scale = false;
};

double to_unit(const Bound& b, double x);
double from_unit(const Bound& b, double v);

struct LmOptions {
  int max_iterations = 8;        ///< Jacobian evaluations
  double step = 2e-3;            ///< finite-difference step in v
  double lambda0 = 1e-3;
  double relative_tolerance = 1e-3;  ///< stop when the cost falls by less than this fraction
  double step_tolerance = 1e-4;      ///< or when |dv|_inf is below this
  double covariance_scale = 1.0;
  int threads = 0;               ///< OpenMP threads for the Jacobian (0: the default)
};

/// The model: residual vector at parameters x (physical units). For the
/// Jacobian columns `centre` points to the iteration's centre (already
/// evaluated), so that the evaluations of one Jacobian can share settings
/// such as a time step; it is nullptr for centres and trial steps.
using ResidualFn = std::function<std::vector<double>(const std::vector<double>& x, const std::vector<double>* centre)>;

struct LmResult {
  std::vector<double> x;            ///< estimate
  std::vector<double> std_error;    ///< sqrt(diag(cov)) in x units (NaN if singular)
  std::vector<std::vector<double>> covariance;  ///< in x units
  /// The estimate's first-order response to a shift of the residual vector: a shift dr moves the
  /// minimizer by dx = -sensitivity dr (Gauss-Newton: (J^T J)^-1 J^T, mapped to x units; no
  /// covariance_scale). Exact for a residual linear in x. A row is empty for a parameter without
  /// a standard error (NaN). Used to carry a systematic model error into the parameters.
  std::vector<std::vector<double>> sensitivity;
  std::vector<double> residual;     ///< at x
  double cost = 0;                  ///< |r|^2 at x
  double initial_cost = 0;
  int iterations = 0;
  int evaluations = 0;
  int failed_evaluations = 0;       ///< trial steps and Jacobian columns where the model threw pw::SolverError
  bool converged = false;
  std::vector<bool> at_bound;       ///< parameter ended on its bound
  std::string message;
};

/// Minimizes |r(x)|^2 over the box from x0 (clamped into it). A trial step
/// whose evaluation throws pw::SolverError counts as a worse step; a Jacobian
/// column that throws is differenced the other way, and when that throws too the
/// parameter is held for the iteration (zero column); an exception at the start
/// point propagates.
LmResult levenberg_marquardt(const ResidualFn& residual, const std::vector<Bound>& bounds, std::vector<double> x0,
                             const LmOptions& options = {});

/// Per parameter, the standard deviation of the estimate when the residual carries the shifts
/// w_k, each with an independent N(0, 1) weight: sqrt(sum_k (sensitivity w_k)^2), through
/// LmResult::sensitivity. Empty shifts give 0; a parameter without a sensitivity row gets NaN.
std::vector<double> propagated_std(const LmResult& fit, const std::vector<std::vector<double>>& shifts);
/// Per parameter, the standard deviation of the estimate when the residual carries the shifts
/// w_k all with one common N(0, 1) weight (fully correlated): |sensitivity sum_k w_k|. Empty
/// shifts give 0; a parameter without a sensitivity row gets NaN.
std::vector<double> propagated_std_correlated(const LmResult& fit, const std::vector<std::vector<double>>& shifts);

/// A nuisance level the estimate is conditional on, known only to within a spread: the fit's
/// parameter `index` and the standard deviation of its value [x units] (e.g. how far a
/// calibration's healthy recordings scatter it).
struct LevelSpread {
  std::size_t index = 0;
  double std = 0;
};
/// The standard deviation of estimate `i` that the levels' spreads carry into it: each level held
/// at another value and everything else refitted moves the estimate by the regression of x_i on
/// the levels in the fit's covariance, b = Cov(x_i, L) Cov(L, L)^-1 (for a Gaussian the
/// conditional mean's slope, exact for a residual linear in x); the levels' spreads taken as
/// independent, sqrt(sum_j (b_j std_j)^2). 0 without levels or when i is one of them; NaN where
/// the covariance of i or of a level is missing (a singular fit) or Cov(L, L) is singular.
double level_spread_std(const LmResult& fit, std::size_t i, const std::vector<LevelSpread>& levels);

/// Minimizer of the linear least-squares cost |r + A a + B b|^2 with each a_i in the box
/// [lower_i, upper_i] and b free. b is profiled out exactly (r and A projected onto the complement
/// of B's columns); the box problem in a is then solved exactly over the box's faces (each a_i
/// free or on either bound; up to 8 parameters) or by coordinate descent beyond. The cost is never
/// above the cost at any point of the box, a = 0 included when the box holds it.
///
/// Why not a projected active set (hold each a_i that leaves its box on the bound it crossed and
/// solve the rest again), as before session 64: it can end above the cost of no step at all. On
/// indepsim3's setB5 torque-ripple recording the motor inertia's linear step ran far below its
/// box, was held at the bound, the fraction then wanted a negative value and was held at 0: cost
/// 632 235 against 608 350 without a step, so the ripple screened at S = 0 and was never fitted
/// (docs/diagnose-log.md, session 64).
struct BoxedLeastSquares {
  Eigen::VectorXd a, b;   ///< the step (a on its boxes)
  double cost = 0;        ///< |r + A a + B b|^2 at the step
  std::vector<bool> held; ///< a_i held on a bound
};
BoxedLeastSquares boxed_least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& lower,
                                      const Eigen::VectorXd& upper, const Eigen::MatrixXd& B, const Eigen::VectorXd& r);

/// A parameter vector profiled by bounded Gauss-Newton steps on a secant Jacobian that
/// Broyden's rank-one update (J += (y - J s) s^T / s^T s, Nocedal & Wright, Numerical
/// Optimization, 2nd ed., eq. 11.27) refreshes from each new evaluation: one model
/// evaluation per step and no finite differences, for following many starting points
/// cheaply. It keeps the best evaluated point.
class SecantProfile {
public:
  SecantProfile() = default;
  /// x0 evaluated to residual r0; J0 approximates dr/dx there (e.g. by secants).
  SecantProfile(std::vector<double> x0, Eigen::VectorXd r0, Eigen::MatrixXd J0);

  bool usable() const { return jacobian_.size() > 0; }
  /// Best evaluated parameters and their |r|^2.
  const std::vector<double>& best_x() const { return best_x_; }
  double best_cost() const { return best_cost_; }

  struct Step {
    std::vector<double> x;  ///< the bounded Gauss-Newton point from the last evaluation
    double predicted_cost;  ///< |r + J dx|^2 there
  };
  Step gauss_newton_step(const std::vector<Bound>& bounds) const;
  /// The residual r at a new point x: the Jacobian takes the secant from the last point.
  void accept(const std::vector<double>& x, const Eigen::Ref<const Eigen::VectorXd>& r);

private:
  std::vector<double> x_, best_x_;
  Eigen::VectorXd r_;
  Eigen::MatrixXd jacobian_;
  double best_cost_ = 0;
};

/// Indices i of the local minima of f along the closed path  end, f[0], ..., f[n-1], end
/// (f[i] <= both neighbours and < end; non-finite values are never minima and a NaN
/// neighbour counts as +infinity), best first, at
/// most `max_count`. For screening places round a gear starting and ending next to the
/// current one, whose value is `end`: neighbouring places share a basin, so distinct
/// hypotheses are distinct minima.
std::vector<std::size_t> local_minima_on_closed_path(const std::vector<double>& f, double end, std::size_t max_count);

/// n >= 2 points lo (hi / lo)^(i / (n - 1)), i = 0 .. n-1, from lo to hi (0 < lo): the scans of
/// a parameter whose natural scale is logarithmic.
std::vector<double> geometric_grid(double lo, double hi, int n);

} // namespace pw::diagnose
