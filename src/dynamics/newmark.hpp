// Newmark-beta time integration of M a + f_int(t, q, v) = f_ext(t, q, v) with
// Newton iterations on the new acceleration.
//
// The integrator knows nothing of gears (cf. mfem::NewmarkSolver): a model
// implements SecondOrderSystem and supplies the net force g = f_ext - f_int
// and, for Newton, its tangents K = -dg/dq and C = -dg/dv.
//
// Scheme (Newmark 1959): with predictors
//   q* = q_n + dt v_n + dt^2 (1/2 - beta) a_n,   v* = v_n + dt (1 - gamma) a_n
// the step solves R(a) = M a - g(t_{n+1}, q* + beta dt^2 a, v* + gamma dt a) = 0
// by Newton: J = M + gamma dt C + beta dt^2 K. beta = 1/4, gamma = 1/2
// (average acceleration) is unconditionally stable for linear systems,
// conserves the energy of undamped linear systems exactly and is 2nd order.
#pragma once

#include "dynamics/small_lu.hpp"

#include <Eigen/Dense>

namespace pw::dynamics {

struct NewmarkScheme {
  double beta = 0.25;
  double gamma = 0.5;
  static constexpr NewmarkScheme average_acceleration() { return {0.25, 0.5}; }
  static constexpr NewmarkScheme linear_acceleration() { return {1.0 / 6.0, 0.5}; }
};

/// Where Newton starts the step's acceleration a_(n+1) from.
enum class NewtonStart {
  Previous,   ///< a_n: O(dt) from the root
  Linear,     ///< 2 a_n - a_(n-1): O(dt^2)
  Quadratic,  ///< 3 a_n - 3 a_(n-1) + a_(n-2): O(dt^3)
};

struct NewtonSettings {
  double relative_tolerance = 1e-10;  ///< on the residual, relative to the force scale
  int max_iterations = 30;
  /// Start Newton from the acceleration extrapolated from the last steps instead of a_n: the
  /// closer start saves force evaluations; the root is the same to the Newton tolerance. The
  /// extrapolation falls back to a lower order while fewer full steps precede (the first steps,
  /// after a state set from outside, after halved steps). Measured on the seed stage, the
  /// quadratic start's first residual is ~10x smaller than the linear one's (docs/benchmark.md).
  NewtonStart start = NewtonStart::Quadratic;
  /// Stop one chord iteration early when convergence is predicted: chord iterations contract
  /// linearly, so after a contraction q = r_k / r_(k-1) < 0.1 the next iterate's residual is
  /// about q r_k. When that is within the tolerance (and r_k is not), the next iterate is taken
  /// without evaluating its residual (the stopping rule of Hairer & Wanner, Solving ODEs II,
  /// IV.8, on the residual instead of the increment). The accepted iterate is the one the
  /// measured stop would evaluate and accept, unless the prediction fails; 0.4-1 fewer force
  /// evaluations per step (docs/benchmark.md). The system's per-force state (mesh forces) then
  /// belongs to the last evaluated iterate, one chord update before the accepted one (a
  /// relative difference of the order of the tolerance).
  bool predicted_stop = true;
};

/// A second-order ODE system M a = g(t, q, v) with constant mass matrix.
class SecondOrderSystem {
public:
  virtual ~SecondOrderSystem() = default;
  virtual int size() const = 0;
  virtual const Eigen::MatrixXd& mass() const = 0;
  /// Typical magnitude of the generalized forces that balance each other
  /// (e.g. the applied torques). Newton's tolerance is relative to it: near
  /// equilibrium the net force and M a are both tiny, and a tolerance
  /// relative to them alone would ask for accuracy below round-off.
  virtual double force_scale() const { return 0.0; }
  /// Net generalized force g = f_ext - f_int at (t, q, v). When K and C are
  /// non-null, also writes K = -dg/dq and C = -dg/dv (may be approximate:
  /// only Newton's convergence rate depends on them).
  virtual void force(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& g,
                     Eigen::MatrixXd* K, Eigen::MatrixXd* C) = 0;
};

/// What the solver did so far (it owns its statistics).
struct NewmarkStatistics {
  long steps = 0;              ///< accepted steps of the full length (step() calls)
  long force_evaluations = 0;  ///< residual evaluations, incl. those of failed attempts
  long factorizations = 0;     ///< LU factorizations of the iteration matrix
  long halved_steps = 0;       ///< steps retried as two half steps
};

struct NewmarkState {
  double t = 0;
  Eigen::VectorXd q, v, a;
};

/// Fixed-step Newmark integrator. All work arrays are allocated once in the
/// constructor: step() does not allocate.
class NewmarkSolver {
public:
  NewmarkSolver(SecondOrderSystem& system, double dt_s, NewmarkScheme scheme = {}, NewtonSettings newton = {});

  /// Sets state.a from M a = g(t, q, v).
  void initialize(NewmarkState& state);
  /// Advances one step; returns the force evaluations (Newton residuals) used. If Newton does not
  /// converge, the step is taken as two half steps (recursively, down to
  /// dt / 2^kMaxHalvings). *Why:* with backlash the mesh force jumps when teeth
  /// separate (the viscous term c v drops to zero), and a step that straddles
  /// the jump may have no consistent root; a shorter step ends before or after
  /// it. Steps that converge are untouched, so results without such events do
  /// not change. Throws pw::SolverError if even the shortest steps fail or the
  /// state is not finite.
  int step(NewmarkState& state);
  static constexpr int kMaxHalvings = 6;

  double time_step() const { return dt_; }
  const NewmarkStatistics& statistics() const { return stats_; }

  /// One Newmark step of the current dt_ for n = N coordinates (0: any n): force evaluations
  /// used, or -1 (state untouched) if Newton did not converge. Public for the size dispatch
  /// (newmark.cpp), called through attempt_.
  template <int N>
  int attempt_n(NewmarkState& state, int history);
  using AttemptFn = int (NewmarkSolver::*)(NewmarkState&, int);

private:
  /// Two steps of dt_ / 2 (each halved again if it fails); depth counts the halvings.
  int halved_steps(NewmarkState& state, int depth);
  // The step's parts, compiled for the system's size N (0: the run-time size): at n = 5 the
  // loops' trip counts and the calls between the parts cost as much as their arithmetic
  // (callgrind, session 46). The same operations in the same order for every N.
  /// Evaluates R(a_) into r_ (and K_, C_ when `tangents`); returns |R|_inf,
  /// sets the force scale.
  template <int N>
  double residual_n(double t1, double& scale, bool tangents);
  [[noreturn]] void throw_non_finite(double t1) const;
  /// Predictors q*, v* and Newton's start a_ for a step from s, extrapolated from `history`
  /// earlier full steps' accelerations (0: a_n).
  template <int N>
  void predict_n(const NewmarkState& s, int history);
  /// q_ = q* + cq a_, v_ = v* + cv a_ (cq = beta dt^2, cv = gamma dt).
  template <int N>
  void set_iterate_n(double cq, double cv);
  /// da_ = J^-1 r_ with the inverse of the last factorization.
  template <int N>
  void apply_inverse_n();
  /// Factorizes J = M + gamma dt C + beta dt^2 K from the current K_, C_.
  void factor_jacobian();

  SecondOrderSystem& sys_;
  double dt_;
  NewmarkScheme scheme_;
  NewtonSettings newton_;
  Eigen::VectorXd q_pred_, v_pred_, q_, v_, a_, a_prev_, g_, r_, da_;
  // Accelerations one and two full steps before the state's, and the state's.
  Eigen::VectorXd a_last_, a_last2_, a_n_;
  double t_end_ = 0;  // time of the state the last step() returned: a_last_ (a_last2_) are valid for it
  int history_ = 0;   // how many of a_last_, a_last2_ are valid for the state at t_end_
  Eigen::MatrixXd K_, C_, J_;
  Eigen::VectorXd mass_diagonal_;
  /// Off-diagonal non-zeros of a non-diagonal mass matrix (lateral-torsional: the carrier's
  /// rotation couples to the planets' translations), column by column: M a over them and the
  /// diagonal instead of a dense n x n product.
  struct MassEntry {
    int row, col;
    double m;
  };
  std::vector<MassEntry> mass_off_diagonal_;
  SmallLU lu_;
  AttemptFn attempt_ = nullptr;  // attempt_n<n> for the system's size n (newmark.cpp)
  bool have_lu_ = false;  // lu_ holds an iteration matrix (of an earlier step: modified Newton)
  NewmarkStatistics stats_;
};

} // namespace pw::dynamics
