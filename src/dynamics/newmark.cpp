#include "dynamics/newmark.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace pw::dynamics {
namespace {
/// A chord iteration (an earlier step's factorization) that reduces the residual at least this
/// much per iteration is kept; a weaker one refreshes the tangents (a pair entered contact).
constexpr double kChordContraction = 0.1;

// The vector updates below are plain loops over restrict pointers: Eigen's dynamic-size
// assignment costs a size check and a vectorized loop's set-up on every call, more than the five
// to eighteen doubles of a step's vectors (callgrind, session 41); without `restrict` GCC adds
// run-time overlap checks to each loop instead. The same operations per entry as the Eigen
// expressions they replace.

/// dst = src (same length).
inline void copy_n(const double* __restrict src, double* __restrict dst, int n) {
  for (int i = 0; i < n; ++i) dst[i] = src[i];
}
/// out = x - lambda d, lambda d first as Eigen's `x - lambda * d` (lambda = 1 multiplies exactly).
inline void subtract_scaled(const double* __restrict x, double lambda, const double* __restrict d,
                            double* __restrict out, int n) {
  for (int i = 0; i < n; ++i) out[i] = x[i] - lambda * d[i];
}
/// x -= d in place.
inline void subtract_in_place(double* __restrict x, const double* __restrict d, int n) {
  for (int i = 0; i < n; ++i) x[i] -= d[i];
}

// The residual's per-entry loops for a size known at compile time (N > 0; 0: any, length n). At
// n = 5 the run-time loops cost more in overlap checks, vector set-up and remainder handling
// than in arithmetic (~150 of the residual's ~300 instructions per call, callgrind, session 43);
// unrolled, each entry is its few operations. The same operations per entry in the same order.

/// q = q* + cq a, v = v* + cv a, entry by entry as Eigen's expressions evaluate them.
template <int N>
void iterate_n(int n, double cq, double cv, const double* __restrict a, const double* __restrict qp,
               const double* __restrict vp, double* __restrict q, double* __restrict v) {
  const int len = N > 0 ? N : n;
  for (int i = 0; i < len; ++i) {
    q[i] = qp[i] + cq * a[i];
    v[i] = vp[i] + cv * a[i];
  }
}
/// r = diag(M) a, as cwiseProduct.
template <int N>
void mass_diagonal_n(int n, const double* __restrict md, const double* __restrict a, double* __restrict r) {
  const int len = N > 0 ? N : n;
  for (int i = 0; i < len; ++i) r[i] = md[i] * a[i];
}
/// |r|_inf into ma, |g|_inf into gn, r -= g, and |r|_inf returned, in one pass over the entries;
/// `finite` false if any entry of the new r is not finite.
template <int N>
double norms_n(int n, double* __restrict r, const double* __restrict g, double& ma, double& gn, bool& finite) {
  const int len = N > 0 ? N : n;
  double res = 0, max_r = ma, max_g = gn;  // locals: ma and gn may alias r or g for the compiler
  bool all_finite = finite;
  for (int i = 0; i < len; ++i) {
    max_r = std::max(max_r, std::fabs(r[i]));
    max_g = std::max(max_g, std::fabs(g[i]));
    r[i] -= g[i];
    res = std::max(res, std::fabs(r[i]));
    all_finite = all_finite & std::isfinite(r[i]);  // no short circuit: the same value without a branch
  }
  ma = max_r;
  gn = max_g;
  finite = all_finite;
  return res;
}

/// The sizes attempt() is compiled for (its loops unrolled, its kernels inline): the torsional
/// (3-10 coordinates) and lateral-torsional (18-23) sizes SmallLU unrolls too; any other size
/// runs attempt_n<0>, the run-time loops.
template <int... N>
struct AttemptSizes {
  static NewmarkSolver::AttemptFn attempt(int n) {
    NewmarkSolver::AttemptFn f = &NewmarkSolver::attempt_n<0>;
    ((n == N ? (f = &NewmarkSolver::attempt_n<N>, 0) : 0), ...);
    return f;
  }
};
using FixedAttemptSizes = AttemptSizes<3, 4, 5, 6, 7, 8, 9, 10, 18, 19, 20, 21, 22, 23>;
} // namespace

NewmarkSolver::NewmarkSolver(SecondOrderSystem& system, double dt_s, NewmarkScheme scheme, NewtonSettings newton)
    : sys_(system), dt_(dt_s), scheme_(scheme), newton_(newton) {
  require(dt_s > 0 && std::isfinite(dt_s), "solver.time_step_s", "must be > 0 [s], got ", dt_s);
  require(scheme.beta > 0 && scheme.beta <= 0.5, "solver.newmark_beta", "must be in (0, 0.5], got ", scheme.beta);
  require(scheme.gamma >= 0.5 && scheme.gamma <= 1.0, "solver.newmark_gamma", "must be in [0.5, 1], got ",
          scheme.gamma);
  const int n = sys_.size();
  for (Eigen::VectorXd* w : {&q_pred_, &v_pred_, &q_, &v_, &a_, &a_prev_, &g_, &r_, &da_, &a_last_, &a_last2_, &a_n_})
    w->setZero(n);
  K_.setZero(n, n);
  C_.setZero(n, n);
  J_.setZero(n, n);
  lu_.resize(n);
  attempt_ = FixedAttemptSizes::attempt(n);
  // Torsional models in these coordinates have a diagonal mass matrix (absolute rotations);
  // then M a is n products instead of n^2, and the few off-diagonal entries of a
  // lateral-torsional one are added over its non-zeros.
  const Eigen::MatrixXd& M = sys_.mass();
  mass_diagonal_ = M.diagonal();
  for (Eigen::Index j = 0; j < M.cols(); ++j)
    for (Eigen::Index i = 0; i < M.rows(); ++i)
      if (i != j && M(i, j) != 0) mass_off_diagonal_.push_back({static_cast<int>(i), static_cast<int>(j), M(i, j)});
}

void NewmarkSolver::initialize(NewmarkState& s) {
  sys_.force(s.t, s.q, s.v, g_, nullptr, nullptr);
  if (!lu_.factorize(sys_.mass())) throw SolverError("the mass matrix is singular (a body without inertia?)");
  lu_.solve(g_, s.a);
  have_lu_ = false;  // lu_ now holds M, not the iteration matrix
  history_ = 0;
}

template <int N>
double NewmarkSolver::residual_n(double t1, double& scale, bool tangents) {
  const double b = scheme_.beta, gm = scheme_.gamma, dt = dt_;
  set_iterate_n<N>(b * dt * dt, gm * dt);
  if (tangents)
    sys_.force(t1, q_, v_, g_, &K_, &C_);
  else
    sys_.force(t1, q_, v_, g_, nullptr, nullptr);
  const int n = N > 0 ? N : static_cast<int>(r_.size());
  mass_diagonal_n<N>(n, mass_diagonal_.data(), a_.data(), r_.data());  // the diagonal of M a
  // A lateral-torsional mass matrix has a few dozen off-diagonal non-zeros among 324 entries:
  // the dense product was 9 % of its step (perf, session 23).
  for (const MassEntry& e : mass_off_diagonal_) r_(e.row) += e.m * a_(e.col);
  // |M a|_inf, |g|_inf and |M a - g|_inf in one pass over the n entries (Eigen's three
  // reductions on a length-5 vector cost more in set-up than in arithmetic); max is exact, so
  // the figures are those of lpNorm<Infinity>. A NaN entry is caught by the finiteness test.
  double ma = 0, gn = 0;
  bool finite = true;
  const double res = norms_n<N>(n, r_.data(), g_.data(), ma, gn, finite);
  scale = ma + gn + sys_.force_scale() + 1e-300;
  if (!finite || !std::isfinite(res)) [[unlikely]]
    throw_non_finite(t1);
  return res;
}

void NewmarkSolver::throw_non_finite(double t1) const {
  throw SolverError(detail::concat("Newmark step at t = ", t1,
                                   " s produced a non-finite force; the response diverged (reduce "
                                   "solver.time_step_s or check stiffness/damping inputs)"));
}

template <int N>
void NewmarkSolver::set_iterate_n(double cq, double cv) {
  // q = q* + beta dt^2 a, v = v* + gamma dt a, entry by entry as Eigen's expressions evaluate them.
  const int n = N > 0 ? N : static_cast<int>(a_.size());
  iterate_n<N>(n, cq, cv, a_.data(), q_pred_.data(), v_pred_.data(), q_.data(), v_.data());
}

template <int N>
void NewmarkSolver::apply_inverse_n() {
  if constexpr (N > 0)
    multiply_by_inverse<N>(lu_.inverse_data(), r_.data(), da_.data());
  else
    lu_.apply_inverse(r_, da_);
}

void NewmarkSolver::factor_jacobian() {
  const double dt = dt_;
  J_ = sys_.mass();
  J_.noalias() += (scheme_.gamma * dt) * C_;
  J_.noalias() += (scheme_.beta * dt * dt) * K_;
  if (!lu_.factorize(J_))
    throw SolverError(detail::concat("the Newmark iteration matrix is singular (time step ", dt, " s)"));
  lu_.compute_inverse();  // the iterations multiply by J^-1 (SmallLU::apply_inverse)
  ++stats_.factorizations;
  have_lu_ = true;
}

int NewmarkSolver::step(NewmarkState& s) {
  // The extrapolation needs the previous accelerations at full steps back; a state set from
  // outside (or a halved step) starts from a_n instead.
  const int max_history = newton_.start == NewtonStart::Quadratic ? 2 : newton_.start == NewtonStart::Linear ? 1 : 0;
  const int history = s.t == t_end_ ? std::min(history_, max_history) : 0;
  a_n_.resize(s.a.size());  // kept for the next step's extrapolation (a no-op at the same length)
  copy_n(s.a.data(), a_n_.data(), static_cast<int>(s.a.size()));
  int it = (this->*attempt_)(s, history);
  if (it < 0) it = halved_steps(s, 1);
  ++stats_.steps;
  a_last2_.swap(a_last_);
  a_last_.swap(a_n_);
  history_ = std::min(history + 1, 2);
  t_end_ = s.t;
  return it;
}

int NewmarkSolver::halved_steps(NewmarkState& s, int depth) {
  if (depth > kMaxHalvings)
    throw SolverError(detail::concat("Newton iteration of the Newmark step at t = ", s.t + dt_, " s did not converge in ",
                                     newton_.max_iterations, " iterations, nor in steps ", 1 << kMaxHalvings,
                                     " times shorter (set solver.time_step_s smaller or raise "
                                     "solver.newton_max_iterations)"));
  struct Restore {
    NewmarkSolver& solver;
    double dt;
    ~Restore() {
      solver.dt_ = dt;
      solver.have_lu_ = false;
    }
  } restore{*this, dt_};
  dt_ *= 0.5;
  have_lu_ = false;
  ++stats_.halved_steps;
  int iterations = 0;
  for (int half = 0; half < 2; ++half) {
    const int it = (this->*attempt_)(s, 0);
    iterations += it >= 0 ? it : halved_steps(s, depth + 1);
  }
  return iterations;
}

template <int N>
void NewmarkSolver::predict_n(const NewmarkState& s, int history) {
  // q* = q_n + dt v_n + dt^2 (1/2 - beta) a_n, v* = v_n + dt (1 - gamma) a_n, and the start a_(n+1)
  // extrapolated from the last 1 + history accelerations, in one loop; the same operations per
  // entry as the Eigen expressions they replace (no temporaries, no fused multiply-add).
  const int n = N > 0 ? N : static_cast<int>(s.q.size());
  const double dt = dt_, cq = dt * dt * (0.5 - scheme_.beta), cv = dt * (1.0 - scheme_.gamma);
  const double *q = s.q.data(), *v = s.v.data(), *a = s.a.data(), *al = a_last_.data(), *al2 = a_last2_.data();
  double *qp = q_pred_.data(), *vp = v_pred_.data(), *a1 = a_.data();
  for (int i = 0; i < n; ++i) {
    qp[i] = q[i] + dt * v[i] + cq * a[i];
    vp[i] = v[i] + cv * a[i];
  }
  if (history >= 2)
    for (int i = 0; i < n; ++i) a1[i] = 3.0 * (a[i] - al[i]) + al2[i];
  else if (history == 1)
    for (int i = 0; i < n; ++i) a1[i] = 2.0 * a[i] - al[i];
  else
    for (int i = 0; i < n; ++i) a1[i] = a[i];
}

template <int N>
int NewmarkSolver::attempt_n(NewmarkState& s, int history) {
  const double dt = dt_;
  const double b = scheme_.beta, gm = scheme_.gamma;
  const double t1 = s.t + dt;
  predict_n<N>(s, history);
  double scale = 0;
  int evaluations = 0;
  auto evaluate = [&](bool tangents) {
    ++evaluations;
    return residual_n<N>(t1, scale, tangents);
  };
  const int n = N > 0 ? N : static_cast<int>(a_.size());
  // The accepted iterate is handed over by swapping storage, not copied: q_, v_ and a_ are
  // written whole by the next attempt's predict() and set_iterate() before they are read.
  auto accept = [&] {
    s.t = t1;
    s.q.swap(q_);
    s.v.swap(v_);
    s.a.swap(a_);
    stats_.force_evaluations += evaluations;
    return evaluations;
  };
  // Chord (modified Newton) iterations reuse the factorized iteration matrix
  // of an earlier step while they contract fast (residual / 10 per
  // iteration); the tangents are refreshed, and a damped full Newton step
  // taken, as soon as they do not -- e.g. when a tooth pair enters contact.
  // *Why not fresh tangents every step:* measured, assembling K and C costs
  // more than the 0.4-1.3 evaluations per step it saves (docs/benchmark.md).
  double res = evaluate(!have_lu_);
  if (!have_lu_) factor_jacobian();
  bool fresh = false;  // the factorization belongs to this state
  for (int it = 1; it <= newton_.max_iterations; ++it) {
    if (res <= newton_.relative_tolerance * scale) return accept();
    // a_prev_ = a_ by a swap: every path below writes a_ whole before reading it (the chord
    // update, the line search) or copies a_prev_ back.
    a_prev_.swap(a_);
    if (!fresh) {
      apply_inverse_n<N>();
      subtract_scaled(a_prev_.data(), 1.0, da_.data(), a_.data(), n);
      const double trial = evaluate(false);
      if (trial < kChordContraction * res) {
        const double tolerance = newton_.relative_tolerance * scale;
        if (newton_.predicted_stop && trial > tolerance && trial * (trial / res) <= tolerance) {
          apply_inverse_n<N>();  // r_ is the residual at a_: one more chord update, not evaluated
          subtract_in_place(a_.data(), da_.data(), n);
          set_iterate_n<N>(b * dt * dt, gm * dt);
          return accept();
        }
        res = trial;
        continue;
      }
      copy_n(a_prev_.data(), a_.data(), n);  // a_prev_ stays the line search's base
      res = evaluate(true);
      factor_jacobian();
      fresh = true;
      if (res <= newton_.relative_tolerance * scale) continue;
    }
    apply_inverse_n<N>();
    // Backtracking on the residual norm: the smoothed Coulomb friction
    // (tanh of the sliding speed) makes the full Newton step overshoot near
    // the pitch point, where the sliding speed changes sign.
    double lambda = 1.0;
    for (int ls = 0; ls < 12; ++ls) {
      subtract_scaled(a_prev_.data(), lambda, da_.data(), a_.data(), n);
      const double trial = evaluate(false);
      if (trial < (1.0 - 1e-4 * lambda) * res || ls == 11) {
        res = trial;
        break;
      }
      lambda *= 0.5;
    }
    fresh = false;
  }
  stats_.force_evaluations += evaluations;
  return -1;
}

} // namespace pw::dynamics
