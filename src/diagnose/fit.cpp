#include "diagnose/fit.hpp"

#include "core/error.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pw::diagnose {

double to_unit(const Bound& b, double x) {
  if (b.log_scale) return std::log(x / b.lower) / std::log(b.upper / b.lower);
  return (x - b.lower) / (b.upper - b.lower);
}

double from_unit(const Bound& b, double v) {
  v = std::clamp(v, 0.0, 1.0);
  // Clamped into the box as well: l exp(log(u / l)) exceeds u by an ulp for about a fifth of
  // the boxes, and a box's end is often the end of the key's range (the damping ratio's 1),
  // which validate() then refuses (measured: a calibrated diagnosis refused on the independent
  // corpus, docs/diagnose-log.md session 17).
  const double x = b.log_scale ? b.lower * std::exp(v * std::log(b.upper / b.lower)) : b.lower + v * (b.upper - b.lower);
  return std::clamp(x, std::min(b.lower, b.upper), std::max(b.lower, b.upper));
}

namespace {
double dx_dv(const Bound& b, double v) {
  if (b.log_scale) return from_unit(b, v) * std::log(b.upper / b.lower);
  return b.upper - b.lower;
}
double norm2(const std::vector<double>& r) {
  double s = 0;
  for (double v : r) s += v * v;
  return s;
}

/// The estimate's covariance (J^T J)^-1 in v, mapped to x, over the parameters the residual
/// depends on: a zero column (a parameter held for the iteration, or one the model does not see
/// there, such as a saturated bandwidth) has no standard error (NaN) and is left out, as if
/// fixed, so that it does not take the others' with it; a singular rest leaves all NaN. The
/// same inverse gives the estimate's sensitivity to a residual shift, (J^T J)^-1 J^T.
void set_covariance(const Eigen::MatrixXd& J, const std::vector<Bound>& bounds, const std::vector<double>& v,
                    double scale, LmResult& res) {
  std::vector<Eigen::Index> seen;
  for (Eigen::Index i = 0; i < J.cols(); ++i)
    if (J.col(i).squaredNorm() > 0) seen.push_back(i);
  const Eigen::Index q = static_cast<Eigen::Index>(seen.size());
  if (q == 0) return;
  Eigen::MatrixXd A(q, q);
  for (Eigen::Index a = 0; a < q; ++a)
    for (Eigen::Index b = 0; b < q; ++b) A(a, b) = J.col(seen[a]).dot(J.col(seen[b]));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(A);
  if (!(es.eigenvalues().minCoeff() > 1e-12 * std::max(es.eigenvalues().maxCoeff(), 1e-300))) return;
  const Eigen::MatrixXd Ainv = A.inverse();
  for (Eigen::Index a = 0; a < q; ++a)
    for (Eigen::Index b = 0; b < q; ++b) {
      const std::size_t i = static_cast<std::size_t>(seen[a]), j = static_cast<std::size_t>(seen[b]);
      res.covariance[i][j] = Ainv(a, b) * scale * dx_dv(bounds[i], v[i]) * dx_dv(bounds[j], v[j]);
    }
  for (Eigen::Index a = 0; a < q; ++a) {
    const std::size_t i = static_cast<std::size_t>(seen[a]);
    res.std_error[i] = std::sqrt(std::max(0.0, res.covariance[i][i]));
    Eigen::VectorXd row = Eigen::VectorXd::Zero(J.rows());
    for (Eigen::Index b = 0; b < q; ++b) row += Ainv(a, b) * J.col(seen[b]);
    row *= dx_dv(bounds[i], v[i]);
    res.sensitivity[i].assign(row.data(), row.data() + row.size());
  }
}

} // namespace

LmResult levenberg_marquardt(const ResidualFn& f, const std::vector<Bound>& bounds, std::vector<double> x0,
                             const LmOptions& o) {
  const std::size_t p = bounds.size();
  require(x0.size() == p, "x0", "has ", x0.size(), " values for ", p, " parameters");
  for (std::size_t i = 0; i < p; ++i) {
    const Bound& b = bounds[i];
    require(b.upper > b.lower && (!b.log_scale || b.lower > 0), "bounds",
            "parameter ", i, ": need lower < upper (and lower > 0 on a log scale), got [", b.lower, ", ", b.upper, "]");
  }
  std::vector<double> v(p);
  for (std::size_t i = 0; i < p; ++i) v[i] = std::clamp(to_unit(bounds[i], x0[i]), 0.0, 1.0);
  auto xs = [&](const std::vector<double>& vv) {
    std::vector<double> x(p);
    for (std::size_t i = 0; i < p; ++i) x[i] = from_unit(bounds[i], vv[i]);
    return x;
  };
  LmResult res;
  std::vector<double> r = f(xs(v), nullptr);
  res.evaluations = 1;
  double cost = norm2(r);
  res.initial_cost = cost;
  if (p == 0) {  // nothing to fit (e.g. --candidates without the nuisance candidates): the model as it is
    res.residual = std::move(r);
    res.cost = cost;
    res.converged = true;
    res.message = "no parameters";
    return res;
  }
  const std::size_t m = r.size();
  double lambda = o.lambda0;
  Eigen::MatrixXd J(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(p));
  bool have_J = false;
  for (int it = 0; it < o.max_iterations; ++it) {
    res.iterations = it + 1;
    // Jacobian columns in parallel (forward differences, backward at the upper bound).
    std::vector<std::vector<double>> cols(p);
    std::vector<double> h(p);
    for (std::size_t i = 0; i < p; ++i) h[i] = v[i] + o.step <= 1.0 ? o.step : -o.step;
    const std::vector<double> centre = xs(v);
    std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 1) num_threads(o.threads > 0 ? o.threads : omp_get_max_threads()) if (p > 1)
    for (std::size_t i = 0; i < p; ++i) {
      try {
        std::vector<double> vi = v;
        vi[i] += h[i];
        try {
          cols[i] = f(xs(vi), &centre);
        } catch (const SolverError&) {
          // The model failed there (e.g. a jammed mesh): difference the other way.
          h[i] = -h[i];
          vi[i] = v[i] + h[i];
          try {
            cols[i] = f(xs(vi), &centre);
          } catch (const SolverError&) {
            // It fails on both sides: no slope is known, so the parameter is held this iteration
            // (a zero column gives it a zero step) rather than the whole fit abandoned.
            cols[i] = r;
#pragma omp atomic
            ++res.failed_evaluations;
          }
        }
      } catch (...) {
#pragma omp critical(pw_lm_error)
        if (!error) error = std::current_exception();
      }
    }
    if (error) std::rethrow_exception(error);
    res.evaluations += static_cast<int>(p);
    for (std::size_t i = 0; i < p; ++i) {
      require(cols[i].size() == m, "residual", "length changed from ", m, " to ", cols[i].size());
      for (std::size_t k = 0; k < m; ++k)
        J(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(i)) = (cols[i][k] - r[k]) / h[i];
    }
    have_J = true;
    const Eigen::Map<const Eigen::VectorXd> rv(r.data(), static_cast<Eigen::Index>(m));
    const Eigen::MatrixXd A = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * rv;
    bool improved = false;
    double max_step = 0;
    for (int tries = 0; tries < 6; ++tries) {
      Eigen::MatrixXd Ad = A;
      for (Eigen::Index i = 0; i < Ad.rows(); ++i) Ad(i, i) += lambda * std::max(A(i, i), 1e-12);
      const Eigen::VectorXd dv = Ad.ldlt().solve(-g);
      std::vector<double> vt(p);
      max_step = 0;
      for (std::size_t i = 0; i < p; ++i) {
        vt[i] = std::clamp(v[i] + dv(static_cast<Eigen::Index>(i)), 0.0, 1.0);
        max_step = std::max(max_step, std::fabs(vt[i] - v[i]));
      }
      if (max_step < 1e-12) break;
      std::vector<double> rt;
      try {
        rt = f(xs(vt), nullptr);
      } catch (const SolverError&) {
        ++res.failed_evaluations;  // the model cannot be simulated there: a worse step
        lambda *= 8;
        continue;
      }
      ++res.evaluations;
      const double ct = norm2(rt);
      if (ct < cost) {
        const double gain = (cost - ct) / std::max(cost, 1e-300);
        v = vt;
        r = std::move(rt);
        cost = ct;
        lambda = std::max(lambda / 5, 1e-9);
        improved = true;
        if (gain < o.relative_tolerance || max_step < o.step_tolerance) res.converged = true;
        break;
      }
      lambda *= 8;
    }
    if (!improved) {
      res.converged = true;  // no downhill step: a (local) minimum within the FD accuracy
      res.message = "no further decrease";
      break;
    }
    if (res.converged) {
      res.message = "cost change below tolerance";
      break;
    }
  }
  if (res.message.empty()) res.message = "iteration limit";
  res.x = xs(v);
  res.residual = r;
  res.cost = cost;
  res.at_bound.resize(p);
  for (std::size_t i = 0; i < p; ++i) res.at_bound[i] = v[i] <= 1e-9 || v[i] >= 1 - 1e-9;
  // Covariance from the last Jacobian (evaluated at or next to the estimate).
  res.std_error.assign(p, std::numeric_limits<double>::quiet_NaN());
  res.covariance.assign(p, std::vector<double>(p, std::numeric_limits<double>::quiet_NaN()));
  res.sensitivity.assign(p, {});
  if (have_J) set_covariance(J, bounds, v, o.covariance_scale, res);
  return res;
}

std::vector<double> propagated_std(const LmResult& fit, const std::vector<std::vector<double>>& shifts) {
  std::vector<double> out(fit.sensitivity.size(), 0.0);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::vector<double>& row = fit.sensitivity[i];
    if (row.empty()) {
      out[i] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    double var = 0;
    for (const std::vector<double>& w : shifts) {
      require(w.size() == row.size(), "residual shift", "has ", w.size(), " entries, the residual ", row.size());
      double dx = 0;
      for (std::size_t k = 0; k < w.size(); ++k) dx += row[k] * w[k];
      var += dx * dx;
    }
    out[i] = std::sqrt(var);
  }
  return out;
}

std::vector<double> propagated_std_correlated(const LmResult& fit, const std::vector<std::vector<double>>& shifts) {
  if (shifts.empty()) return std::vector<double>(fit.sensitivity.size(), 0.0);
  std::vector<double> sum(shifts.front().size(), 0.0);
  for (const std::vector<double>& w : shifts) {
    require(w.size() == sum.size(), "residual shift", "has ", w.size(), " entries, the first ", sum.size());
    for (std::size_t k = 0; k < w.size(); ++k) sum[k] += w[k];
  }
  return propagated_std(fit, {sum});
}

double level_spread_std(const LmResult& fit, std::size_t i, const std::vector<LevelSpread>& levels) {
  std::vector<LevelSpread> used;
  for (const LevelSpread& l : levels) {
    require(l.index < fit.covariance.size(), "level", "index ", l.index, " of a fit with ", fit.covariance.size(),
            " parameters");
    if (l.index == i) return 0.0;  // the level itself: its own spread is not the fit's
    if (l.std > 0) used.push_back(l);
  }
  if (used.empty()) return 0.0;
  require(i < fit.covariance.size(), "parameter", "index ", i, " of a fit with ", fit.covariance.size(), " parameters");
  const Eigen::Index q = static_cast<Eigen::Index>(used.size());
  Eigen::MatrixXd cll(q, q);
  Eigen::VectorXd cil(q);
  for (Eigen::Index a = 0; a < q; ++a) {
    const std::size_t ia = used[static_cast<std::size_t>(a)].index;
    cil(a) = fit.covariance[i][ia];
    for (Eigen::Index b = 0; b < q; ++b) cll(a, b) = fit.covariance[ia][used[static_cast<std::size_t>(b)].index];
  }
  if (!cll.allFinite() || !cil.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(cll);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd b = ldlt.solve(cil);  // Cov(L, L)^-1 Cov(L, x_i): symmetric, so b^T = Cov(x_i, L) Cov(L, L)^-1
  double var = 0;
  for (Eigen::Index a = 0; a < q; ++a) {
    const double d = b(a) * used[static_cast<std::size_t>(a)].std;
    var += d * d;
  }
  return std::sqrt(var);
}

namespace {
/// Up to this many boxed parameters the exact minimum is found over all 3^p faces of the box
/// (6561 small solves at 8); beyond it by coordinate descent. The library's candidates have at
/// most a handful of parameters (a pin error per planet but the first, two transfer inertias).
constexpr Eigen::Index kBoxMaxEnumerated = 8;
/// Coordinate-descent sweeps at most (each sweep moves every parameter once).
constexpr int kBoxCoordinateSweeps = 10000;

/// The box-constrained minimizer of the convex quadratic |rp + Ap a|^2 over every face of the box:
/// each parameter free, on its lower or on its upper bound (3^p faces). On each face the free
/// parameters take the face's minimum-norm minimizer; the box's minimum lies in the relative
/// interior of some face, where it is that face's minimizer (or, if the face's minimizers form a
/// set, that set meets a smaller face with the same cost), so the least cost over the faces whose
/// minimizer lies in the box is the exact minimum.
Eigen::VectorXd box_minimum_by_faces(const Eigen::MatrixXd& Ap, const Eigen::VectorXd& rp, const Eigen::VectorXd& lower,
                                     const Eigen::VectorXd& upper) {
  const Eigen::Index p = Ap.cols();
  Eigen::VectorXd best = lower;
  double best_cost = std::numeric_limits<double>::infinity();
  std::vector<int> face(static_cast<std::size_t>(p), 0);  // 0 free, 1 lower, 2 upper
  for (;;) {
    Eigen::VectorXd a(p);
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < p; ++i) {
      const int f = face[static_cast<std::size_t>(i)];
      a(i) = f == 1 ? lower(i) : f == 2 ? upper(i) : 0.0;
      if (f == 0) free.push_back(i);
    }
    bool inside = true;
    if (!free.empty()) {
      Eigen::VectorXd r_fixed = rp + Ap * a;  // the free parameters are 0 in a here
      Eigen::MatrixXd J(Ap.rows(), static_cast<Eigen::Index>(free.size()));
      for (std::size_t c = 0; c < free.size(); ++c) J.col(static_cast<Eigen::Index>(c)) = Ap.col(free[c]);
      const Eigen::VectorXd x = -Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(J).solve(r_fixed);
      for (std::size_t c = 0; c < free.size(); ++c) {
        const Eigen::Index i = free[c];
        const double v = x(static_cast<Eigen::Index>(c));
        // A bound a hair away (round-off of the solve) still counts as inside: the face with that
        // parameter on the bound is enumerated too and gives the same cost.
        const double tol = 1e-12 * std::max(1.0, upper(i) - lower(i));
        if (!(v >= lower(i) - tol && v <= upper(i) + tol)) inside = false;
        a(i) = std::clamp(v, lower(i), upper(i));
      }
    }
    if (inside) {
      const double cost = (rp + Ap * a).squaredNorm();
      if (cost < best_cost) best_cost = cost, best = a;
    }
    Eigen::Index i = 0;  // next face: count in base 3
    while (i < p && ++face[static_cast<std::size_t>(i)] == 3) face[static_cast<std::size_t>(i++)] = 0;
    if (i == p) break;
  }
  return best;
}

/// The same minimum by cyclic coordinate descent on the box (each parameter in turn set to its
/// one-dimensional minimizer, clamped): convergent for a convex quadratic, used where 3^p faces
/// are too many.
Eigen::VectorXd box_minimum_by_coordinates(const Eigen::MatrixXd& Ap, const Eigen::VectorXd& rp,
                                           const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  const Eigen::Index p = Ap.cols();
  const Eigen::MatrixXd G = Ap.transpose() * Ap;
  const Eigen::VectorXd g = Ap.transpose() * rp;
  Eigen::VectorXd a = Eigen::VectorXd::Zero(p).cwiseMax(lower).cwiseMin(upper);
  for (int sweep = 0; sweep < kBoxCoordinateSweeps; ++sweep) {
    double moved = 0;
    for (Eigen::Index i = 0; i < p; ++i) {
      if (!(G(i, i) > 0)) continue;
      const double grad = g(i) + G.row(i).dot(a);
      const double v = std::clamp(a(i) - grad / G(i, i), lower(i), upper(i));
      moved = std::max(moved, std::fabs(v - a(i)) / std::max(1.0, upper(i) - lower(i)));
      a(i) = v;
    }
    if (moved < 1e-14) break;
  }
  return a;
}
} // namespace

BoxedLeastSquares boxed_least_squares(const Eigen::MatrixXd& A, const Eigen::VectorXd& lower,
                                      const Eigen::VectorXd& upper, const Eigen::MatrixXd& B, const Eigen::VectorXd& r) {
  const Eigen::Index p = A.cols(), q = B.cols(), m = r.size();
  if (A.rows() != m || B.rows() != m || lower.size() != p || upper.size() != p)
    throw std::invalid_argument("boxed_least_squares: the shapes of A, B, r and the bounds do not match");
  for (Eigen::Index i = 0; i < p; ++i)
    if (!(lower(i) <= upper(i))) throw std::invalid_argument("boxed_least_squares: a box with lower > upper");
  // b is free: profiled out exactly by projecting r and A onto the complement of B's columns
  // (b = -B^+ (r + A a) for any a), which leaves a box-constrained problem in a alone.
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_b;
  if (q > 0) cod_b.compute(B);
  const auto project = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return q > 0 ? Eigen::VectorXd(v - B * cod_b.solve(v)) : v;
  };
  Eigen::MatrixXd Ap(m, p);
  for (Eigen::Index i = 0; i < p; ++i) Ap.col(i) = project(A.col(i));
  const Eigen::VectorXd rp = project(r);

  BoxedLeastSquares out;
  out.a = p <= kBoxMaxEnumerated ? box_minimum_by_faces(Ap, rp, lower, upper)
                                 : box_minimum_by_coordinates(Ap, rp, lower, upper);
  const Eigen::VectorXd ra = r + A * out.a;
  out.b = q > 0 ? Eigen::VectorXd(-cod_b.solve(ra)) : Eigen::VectorXd();
  out.cost = (q > 0 ? Eigen::VectorXd(ra + B * out.b) : ra).squaredNorm();
  out.held.resize(static_cast<std::size_t>(p));
  for (Eigen::Index i = 0; i < p; ++i) out.held[static_cast<std::size_t>(i)] = out.a(i) == lower(i) || out.a(i) == upper(i);
  return out;
}

SecantProfile::SecantProfile(std::vector<double> x0, Eigen::VectorXd r0, Eigen::MatrixXd J0)
    : x_(x0), best_x_(std::move(x0)), r_(std::move(r0)), jacobian_(std::move(J0)), best_cost_(r_.squaredNorm()) {
  if (jacobian_.rows() != r_.size() || jacobian_.cols() != static_cast<Eigen::Index>(x_.size()))
    throw std::invalid_argument("SecantProfile: the Jacobian's shape does not match the residual and parameters");
}

SecantProfile::Step SecantProfile::gauss_newton_step(const std::vector<Bound>& bounds) const {
  // Least-squares solve (rank-revealing): a column that does not move the residual gets no step.
  const Eigen::VectorXd dx = jacobian_.colPivHouseholderQr().solve(-r_);
  Step s{x_, 0.0};
  Eigen::VectorXd taken(dx.size());
  for (std::size_t k = 0; k < x_.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    s.x[k] = std::clamp(x_[k] + (std::isfinite(dx(i)) ? dx(i) : 0.0), bounds[k].lower, bounds[k].upper);
    taken(i) = s.x[k] - x_[k];
  }
  s.predicted_cost = (r_ + jacobian_ * taken).squaredNorm();
  return s;
}

void SecantProfile::accept(const std::vector<double>& x, const Eigen::Ref<const Eigen::VectorXd>& r) {
  if (x.size() != x_.size() || r.size() != r_.size())
    throw std::invalid_argument("SecantProfile::accept: size mismatch");
  Eigen::VectorXd s(static_cast<Eigen::Index>(x.size()));
  for (std::size_t k = 0; k < x.size(); ++k) s(static_cast<Eigen::Index>(k)) = x[k] - x_[k];
  if (s.squaredNorm() > 0) jacobian_ += (r - r_ - jacobian_ * s) * s.transpose() / s.squaredNorm();
  r_ = r;
  x_ = x;
  if (r.squaredNorm() < best_cost_) best_cost_ = r.squaredNorm(), best_x_ = x;
}

std::vector<std::size_t> local_minima_on_closed_path(const std::vector<double>& f, double end, std::size_t max_count) {
  // A neighbour that could not be evaluated (NaN) is no better than any value.
  const auto at = [&](std::size_t i, bool before) {
    const double v = before ? (i == 0 ? end : f[i - 1]) : (i + 1 == f.size() ? end : f[i + 1]);
    return std::isnan(v) ? std::numeric_limits<double>::infinity() : v;
  };
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (std::isfinite(f[i]) && f[i] < end && f[i] <= at(i, true) && f[i] <= at(i, false)) out.push_back(i);
  std::stable_sort(out.begin(), out.end(), [&](std::size_t a, std::size_t b) { return f[a] < f[b]; });
  if (out.size() > max_count) out.resize(max_count);
  return out;
}

std::vector<double> geometric_grid(double lo, double hi, int n) {
  std::vector<double> g(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) g[static_cast<std::size_t>(i)] = lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1));
  return g;
}

} // namespace pw::diagnose
