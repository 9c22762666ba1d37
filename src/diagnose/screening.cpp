#include "diagnose/screening.hpp"

#include "core/statistics.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace pw::diagnose {

namespace {

/// Relative secant step of the nuisance parameters.
constexpr double kNuisanceStep = 0.02;
/// A start is kept this fraction of the box's span inside it (LM's unit transform is singular on the edge).
constexpr double kInsideBox = 1e-3;

/// The nuisance secants as a matrix and the normal equations' factorization, for the
/// linearized refit of the nuisance parameters to a changed residual.
struct NuisanceDirections {
  Eigen::MatrixXd J;
  Eigen::LDLT<Eigen::MatrixXd> JtJ;
  bool empty() const { return J.cols() == 0; }
  /// Least-squares cost of r after the nuisance step that minimizes it; *step gets that step.
  double refit(const Eigen::VectorXd& r, Eigen::VectorXd* step) const {
    if (empty()) return r.squaredNorm();
    const Eigen::VectorXd dn = -JtJ.solve(J.transpose() * r);
    if (step) *step = dn;
    return (r + J * dn).squaredNorm();
  }
};

} // namespace

Screening::Screening(FitContext& ctx, double alpha) : ctx_(ctx), alpha_(alpha) {
  res0_ = ctx.cmp.score(ctx.nuisance_sim->amplitude, Half::Fit, ctx.nuisance_gains, HousingGains::Profile).residual;
  // The nuisance parameters' own secants, shared by every candidate: the screening step is
  // joint, so physics the nuisance fit absorbed (a worn profile read as a damping level) is
  // given back to its candidate.
  nspec_ = ctx.nuisance_specs();
  ncols_.resize(nspec_.size());
  nstep_.resize(nspec_.size());
  // A parameter fitted at its upper bound takes its secant downwards (the step must stay
  // within the key's range; e.g. a damping ratio at 1). A value of exactly 0 has no scale of
  // its own (an engagement ramp the calibration drove to its lower bound 0): its step is
  // kNuisanceStep of its box's span. Until session 75 that step was 0, every secant 0/0, and
  // the NaN in the joint step scored every candidate S = 0 (docs/diagnose-log.md).
  for (std::size_t i = 0; i < nspec_.size(); ++i) nstep_[i] = nuisance_secant_step(ctx.nuisance_x[i], nspec_[i]);
}

double nuisance_secant_step(double x, const ParameterSpec& spec) {
  const double scale = x != 0 ? std::fabs(x) : spec.upper - spec.lower;
  if (!(std::isfinite(scale) && scale > 0)) return 0;
  const double h = kNuisanceStep * scale;
  return x + h <= spec.upper ? h : -h;
}

void Screening::add_variants(const std::function<bool(const Candidate&)>& wanted, const LocatedEvidence& evidence,
                             const ToothMap& teeth) {
  for (const auto& c : candidate_library()) {
    if (!wanted(*c)) continue;
    for (const auto& v : c->variants(evidence, ctx_.base, teeth)) {
      Screen sc;
      sc.c = c.get();
      sc.v = v;
      sc.spec = c->parameters(ctx_.base);
      sc.cols.resize(sc.spec.size());
      for (std::size_t i = 0; i < sc.spec.size(); ++i) tasks_.push_back({screens_.size(), i});
      if (any_transfer(sc.spec) && !any_saturates(sc.spec) && !c->sensor_only()) {
        sc.transfer_moved.resize(sc.spec.size());
        tasks_.push_back({screens_.size(), Task::kBase, true});
        for (std::size_t i = 0; i < sc.spec.size(); ++i)
          if (!sc.spec[i].transfer) tasks_.push_back({screens_.size(), i, true});
      }
      screens_.push_back(std::move(sc));
    }
  }
}

void Screening::simulate_secants() {
  // A failed simulation leaves its secant empty: a nuisance direction is then left out, a
  // candidate variant is marked failed (not fitted).
  // A secant that is not finite (no step, a residual with a NaN) is no direction: left empty.
  const auto secant = [&](const std::vector<double>& r, double step) {
    std::vector<double> col(r.size());
    for (std::size_t k = 0; k < r.size(); ++k) col[k] = (r[k] - res0_[k]) / step;
    if (step == 0 || !std::all_of(col.begin(), col.end(), [](double c) { return std::isfinite(c); })) col.clear();
    return col;
  };
  parallel_for(static_cast<int>(tasks_.size() + nspec_.size()), ctx_.threads, [&](int ti) {
    if (static_cast<std::size_t>(ti) >= tasks_.size()) {
      const std::size_t i = static_cast<std::size_t>(ti) - tasks_.size();
      if (nstep_[i] == 0) return;  // no finite scale: the direction is left out
      std::vector<double> x = ctx_.nuisance_x;
      x[i] += nstep_[i];
      const auto r = ctx_.fit_residual(nullptr, Variant{}, {}, x);
      if (!r.empty()) ncols_[i] = secant(r, nstep_[i]);
      return;
    }
    const Task& tk = tasks_[static_cast<std::size_t>(ti)];
    Screen& sc = screens_[tk.screen];
    std::vector<double> x;
    for (const auto& ps : sc.spec) x.push_back(ps.null_value);
    if (tk.at_transfer_values) {
      // A failed simulation leaves its residual empty: the second screening is then skipped.
      for (std::size_t i = 0; i < sc.spec.size(); ++i)
        if (sc.spec[i].transfer) x[i] = sc.spec[i].screen_value;
      if (tk.param != Task::kBase) x[tk.param] = sc.spec[tk.param].screen_value;
      auto r = ctx_.fit_residual(sc.c, sc.v, x, ctx_.nuisance_x, sc.c->sensor_only());
      (tk.param == Task::kBase ? sc.transfer_base : sc.transfer_moved[tk.param]) = std::move(r);
      return;
    }
    const ParameterSpec& ps = sc.spec[tk.param];
    x[tk.param] = ps.screen_value;
    const auto r = ctx_.fit_residual(sc.c, sc.v, x, ctx_.nuisance_x, sc.c->sensor_only());
    if (!r.empty()) sc.cols[tk.param] = secant(r, ps.screen_value - ps.null_value);
    if (sc.cols[tk.param].empty()) sc.failed = true;
  });
}

void Screening::linearize() {
  std::vector<std::size_t> nuse;
  for (std::size_t i = 0; i < ncols_.size(); ++i)
    if (!ncols_[i].empty()) nuse.push_back(i);
  const Eigen::Index m_res = static_cast<Eigen::Index>(res0_.size());
  const Eigen::Map<const Eigen::VectorXd> r_res(res0_.data(), m_res);
  NuisanceDirections nd;
  nd.J.resize(m_res, static_cast<Eigen::Index>(nuse.size()));
  for (std::size_t a = 0; a < nuse.size(); ++a)
    for (Eigen::Index k = 0; k < m_res; ++k) nd.J(k, static_cast<Eigen::Index>(a)) = ncols_[nuse[a]][static_cast<std::size_t>(k)];
  nd.JtJ = (nd.J.transpose() * nd.J).ldlt();
  // Improvement by the nuisance directions alone (about zero at the nuisance fit's optimum).
  double S_nuis = 0;
  if (!nuse.empty()) {
    const Eigen::VectorXd gn = nd.J.transpose() * r_res;
    S_nuis = gn.dot(nd.JtJ.solve(gn));
  }

  for (Screen& sc : screens_) {
    const std::size_t p = sc.spec.size();
    sc.start.resize(p);
    for (std::size_t i = 0; i < p; ++i) sc.start[i] = sc.spec[i].null_value;
    sc.nuisance_start = ctx_.nuisance_x;
    if (sc.failed) continue;
    // A saturating candidate has no useful linearization (its secant spans the onset of the
    // effect): its score is the chi2 change actually simulated, null -> screen value.
    const bool saturating = any_saturates(sc.spec);
    // The nuisance parameters re-fitted (linearized) at both ends: a nuisance fit that absorbed
    // part of the effect (a softened mesh read as a lower stiffness level) gives it back.
    if (saturating) {
      const double c0 = nd.refit(r_res, nullptr);
      for (std::size_t i = 0; i < p; ++i) {
        const auto& ps = sc.spec[i];
        Eigen::VectorXd r1 = r_res;
        for (Eigen::Index k = 0; k < m_res; ++k)
          r1(k) += sc.cols[i][static_cast<std::size_t>(k)] * (ps.screen_value - ps.null_value);
        Eigen::VectorXd dn;
        const double c1 = nd.refit(r1, &dn);
        // Visible: the change itself, with the nuisance refitted to it, exceeds the LR threshold.
        // Its chi2 at fixed nuisance may still be worse (a nuisance fit that absorbed the effect
        // lies far from the nuisance values that go with it), so a visible one is fitted jointly.
        if (nd.refit(r1 - r_res, nullptr) > chi2_quantile(static_cast<int>(p), alpha_)) sc.visible = true;
        if (c0 - c1 > sc.S) {
          sc.S = c0 - c1;
          for (std::size_t a = 0; a < nuse.size(); ++a)
            sc.nuisance_start[nuse[a]] = std::clamp(ctx_.nuisance_x[nuse[a]] + dn(static_cast<Eigen::Index>(a)),
                                                    nspec_[nuse[a]].lower, nspec_[nuse[a]].upper);
        }
        if (c0 > c1) sc.start[i] = ps.screen_value;
      }
    }
    // Joint Gauss-Newton step (candidate + nuisance) on the box: a candidate parameter whose
    // step leaves its box is held on the bound it crossed (a projected active set), and the
    // others and the nuisance are solved again with its contribution in the residual. Holding
    // it at 'absent' instead would score an effect larger than the box as no effect at all
    // (S = 0): measured, a pin error whose linear step left its +-0.02 m box was never fitted
    // and its near-alias, a carrier eccentricity, was named (docs/diagnose-log.md, session 15).
    if (!saturating) joint_step(sc, nuse, r_res, S_nuis);
    if (!saturating && !sc.transfer_base.empty()) transfer_screen_step(sc, nuse, r_res, S_nuis);
    // A start on the no-effect value would give LM nothing to difference: keep it inside.
    for (std::size_t i = 0; i < p; ++i) {
      const auto& ps = sc.spec[i];
      const double span = ps.upper - ps.lower;
      sc.start[i] = std::clamp(sc.start[i], ps.lower + kInsideBox * span, ps.upper - kInsideBox * span);
      if (sc.start[i] == ps.null_value) sc.start[i] = 0.5 * (ps.null_value + ps.screen_value);
    }
  }
}

void Screening::joint_step(Screen& sc, const std::vector<std::size_t>& nuse, const Eigen::Ref<const Eigen::VectorXd>& r_res,
                           double S_nuis) const {
  const std::size_t p = sc.spec.size();
  const Eigen::Index m = r_res.size();
  const auto column = [&](const std::vector<double>& c) { return Eigen::Map<const Eigen::VectorXd>(c.data(), m); };
  // The candidate's parameters as offsets from 'absent', on their boxes; the nuisance free.
  Eigen::MatrixXd A(m, static_cast<Eigen::Index>(p)), B(m, static_cast<Eigen::Index>(nuse.size()));
  Eigen::VectorXd lower(static_cast<Eigen::Index>(p)), upper(static_cast<Eigen::Index>(p));
  for (std::size_t i = 0; i < p; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    A.col(ii) = column(sc.cols[i]);
    lower(ii) = sc.spec[i].lower - sc.spec[i].null_value;
    upper(ii) = sc.spec[i].upper - sc.spec[i].null_value;
  }
  for (std::size_t a = 0; a < nuse.size(); ++a) B.col(static_cast<Eigen::Index>(a)) = column(ncols_[nuse[a]]);
  const BoxedLeastSquares step = boxed_least_squares(A, lower, upper, B, r_res);
  const double S = r_res.squaredNorm() - step.cost - S_nuis;
  // A NaN would read as S = 0 through max(): a screen that cannot be scored failed instead.
  if (!std::isfinite(S)) {
    sc.failed = true;
    return;
  }
  sc.S = std::max(0.0, S);
  for (std::size_t i = 0; i < p; ++i) sc.start[i] = sc.spec[i].null_value + step.a(static_cast<Eigen::Index>(i));
  for (std::size_t a = 0; a < nuse.size(); ++a) {
    const auto& ps = nspec_[nuse[a]];
    sc.nuisance_start[nuse[a]] =
        std::clamp(ctx_.nuisance_x[nuse[a]] + step.b(static_cast<Eigen::Index>(a)), ps.lower, ps.upper);
  }
}

void Screening::transfer_screen_step(Screen& sc, const std::vector<std::size_t>& nuse,
                                     const Eigen::Ref<const Eigen::VectorXd>& r_res, double S_nuis) const {
  const Eigen::Index m = r_res.size();
  if (static_cast<Eigen::Index>(sc.transfer_base.size()) != m) return;
  std::vector<std::size_t> own;  // the non-transfer parameters, stepped; the transfer ones held
  for (std::size_t i = 0; i < sc.spec.size(); ++i) {
    if (sc.spec[i].transfer) continue;
    if (static_cast<Eigen::Index>(sc.transfer_moved[i].size()) != m) return;
    own.push_back(i);
  }
  const Eigen::Map<const Eigen::VectorXd> base(sc.transfer_base.data(), m);
  Eigen::MatrixXd A(m, static_cast<Eigen::Index>(own.size())), B(m, static_cast<Eigen::Index>(nuse.size()));
  Eigen::VectorXd lower(A.cols()), upper(A.cols());
  for (std::size_t a = 0; a < own.size(); ++a) {
    const ParameterSpec& ps = sc.spec[own[a]];
    const auto ai = static_cast<Eigen::Index>(a);
    A.col(ai) = (Eigen::Map<const Eigen::VectorXd>(sc.transfer_moved[own[a]].data(), m) - base) /
                (ps.screen_value - ps.null_value);
    lower(ai) = ps.lower - ps.null_value;
    upper(ai) = ps.upper - ps.null_value;
  }
  // The nuisance secants are those taken at the nuisance-fitted model (a first-order stand-in
  // for the same directions at the transfer values).
  for (std::size_t a = 0; a < nuse.size(); ++a)
    B.col(static_cast<Eigen::Index>(a)) = Eigen::Map<const Eigen::VectorXd>(ncols_[nuse[a]].data(), m);
  const BoxedLeastSquares step = boxed_least_squares(A, lower, upper, B, base);
  // Against the same reference as joint_step's S: what the nuisance-only model reaches linearly.
  const double S = r_res.squaredNorm() - step.cost - S_nuis;
  if (!(S > sc.S)) return;
  sc.S = S;
  sc.screened_at_transfer_values = true;
  for (std::size_t i = 0; i < sc.spec.size(); ++i)
    if (sc.spec[i].transfer) sc.start[i] = sc.spec[i].screen_value;
  for (std::size_t a = 0; a < own.size(); ++a)
    sc.start[own[a]] = sc.spec[own[a]].null_value + step.a(static_cast<Eigen::Index>(a));
  for (std::size_t a = 0; a < nuse.size(); ++a) {
    const auto& ps = nspec_[nuse[a]];
    sc.nuisance_start[nuse[a]] =
        std::clamp(ctx_.nuisance_x[nuse[a]] + step.b(static_cast<Eigen::Index>(a)), ps.lower, ps.upper);
  }
}

std::vector<std::size_t> best_per_candidate(const std::vector<Screen>& screens) {
  std::vector<std::size_t> best_of;
  for (std::size_t i = 0; i < screens.size(); ++i) {
    bool replaced = false;
    for (std::size_t& b : best_of)
      if (screens[b].c == screens[i].c) {
        if (screens[i].S > screens[b].S) b = i;
        replaced = true;
      }
    if (!replaced) best_of.push_back(i);
  }
  std::stable_sort(best_of.begin(), best_of.end(), [&](std::size_t a, std::size_t b) { return screens[a].S > screens[b].S; });
  return best_of;
}

std::vector<std::size_t> shortlist(const std::vector<Screen>& screens, const std::vector<std::size_t>& best,
                                   int max_candidates) {
  std::vector<std::size_t> out;
  int heavy = 0;
  for (std::size_t i : best) {
    if (screens[i].c->sensor_only() || screens[i].visible) {
      out.push_back(i);
      continue;
    }
    if (heavy < max_candidates && screens[i].S > 0) {
      out.push_back(i);
      ++heavy;
    }
  }
  return out;
}

std::vector<std::size_t> screened_rivals(const std::vector<Screen>& screens, const std::vector<std::size_t>& best,
                                         const std::vector<std::size_t>& shortlist, double lead_S, double margin) {
  std::vector<std::size_t> out;
  for (std::size_t i : best) {
    const Screen& sc = screens[i];
    if (sc.failed || sc.S <= 0 || sc.S < lead_S - margin) continue;
    if (std::find(shortlist.begin(), shortlist.end(), i) != shortlist.end()) continue;
    out.push_back(i);
  }
  return out;
}

namespace {
/// A shortlisted variant whose start comes from the grid: one parameter, simulated.
bool gridded(const Screen& sc) { return !sc.failed && sc.spec.size() == 1 && !sc.c->sensor_only(); }

/// Indices of the transfer parameters (ParameterSpec::transfer) of `spec`, in order.
std::vector<std::size_t> transfer_parameters(const std::vector<ParameterSpec>& spec) {
  std::vector<std::size_t> out;
  for (std::size_t k = 0; k < spec.size(); ++k)
    if (spec[k].transfer) out.push_back(k);
  return out;
}

/// A shortlisted variant whose start's transfer parameters come from a grid (Screening::grid_starts):
/// simulated, with a start for every parameter, and one or two transfer parameters.
bool transfer_gridded(const Screen& sc) {
  if (sc.failed || sc.c->sensor_only() || sc.start.size() != sc.spec.size()) return false;
  const std::size_t n = transfer_parameters(sc.spec).size();
  return n >= 1 && n <= Screening::kMaxGriddedTransfers;
}

/// The point a fraction t of the way from `from` to `to`, geometric where the parameter is
/// fitted on a log scale (both ends positive there: the box's lower bound is > 0).
double along(const ParameterSpec& ps, double from, double to, double t) {
  if (ps.log_scale && from > 0 && to > 0) return from * std::pow(to / from, t);
  return from + t * (to - from);
}
} // namespace

BacktrackedStart backtrack_start(const std::vector<ParameterSpec>& spec, const std::vector<double>& start,
                                 const std::vector<double>& absent, double absent_chi2, int max_halvings,
                                 const std::function<double(const std::vector<double>&)>& chi2) {
  BacktrackedStart b;
  b.x = start;
  b.chi2 = b.start_chi2 = chi2(start);
  b.evaluations = 1;
  std::vector<double> x = start;
  double t = 1;
  for (int k = 0; k < max_halvings && !(b.chi2 < absent_chi2); ++k) {
    t *= 0.5;
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = along(spec[i], absent[i], start[i], t);
    const double c = chi2(x);
    ++b.evaluations;
    if (c < b.chi2) b.chi2 = c, b.fraction = t, b.x = x;
  }
  return b;
}

std::vector<std::vector<double>> transfer_grid(const std::vector<ParameterSpec>& spec, const std::vector<double>& start) {
  std::vector<double> base = start;
  for (std::size_t k = 0; k < spec.size() && k < base.size(); ++k)
    if (!spec[k].transfer) base[k] = spec[k].screen_value;
  std::vector<std::vector<double>> points{base};
  for (std::size_t k : transfer_parameters(spec)) {
    std::vector<std::vector<double>> next;
    for (const std::vector<double>& p : points)
      for (double x : Screening::grid_values(spec[k])) {
        next.push_back(p);
        next.back()[k] = x;
      }
    points = std::move(next);
  }
  return points;
}

void Screening::backtrack_starts(const std::vector<std::size_t>& list, double absent_chi2,
                                 const std::function<void(const std::string&)>& say) {
  if (!std::isfinite(absent_chi2)) return;
  std::vector<std::string> moved(list.size());
  parallel_for(static_cast<int>(list.size()), ctx_.threads, [&](int li) {
    Screen& sc = screens_[list[static_cast<std::size_t>(li)]];
    if (sc.failed || sc.c->sensor_only() || any_saturates(sc.spec) || sc.start.size() != sc.spec.size()) return;
    // One vector: the candidate's own parameters, then the nuisance ones where its start moves
    // them (the joint step), each interpolated on its own scale.
    const std::size_t nc = sc.spec.size();
    const bool joint = sc.nuisance_start.size() == ctx_.nuisance_x.size() && sc.nuisance_start.size() == nspec_.size();
    std::vector<ParameterSpec> spec = sc.spec;
    std::vector<double> start = sc.start, absent;
    for (const ParameterSpec& ps : sc.spec) absent.push_back(ps.null_value);
    if (joint) {
      spec.insert(spec.end(), nspec_.begin(), nspec_.end());
      start.insert(start.end(), sc.nuisance_start.begin(), sc.nuisance_start.end());
      absent.insert(absent.end(), ctx_.nuisance_x.begin(), ctx_.nuisance_x.end());
    }
    const auto chi2 = [&](const std::vector<double>& x) {
      const std::span<const double> all(x);
      return ctx_.fit_chi2(sc.c, sc.v, all.first(nc), joint ? all.subspan(nc) : std::span<const double>(sc.nuisance_start));
    };
    const BacktrackedStart b = backtrack_start(spec, start, absent, absent_chi2, kBacktracks, chi2);
    if (b.fraction == 1) return;
    sc.start.assign(b.x.begin(), b.x.begin() + static_cast<long>(nc));
    if (joint) sc.nuisance_start.assign(b.x.begin() + static_cast<long>(nc), b.x.end());
    sc.start_step_fraction = b.fraction;
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s: its start fits the fit half worse than its absence (chi2 %.6g >= %.6g); "
                  "started at %g of that step instead (chi2 %.6g)",
                  sc.c->name().c_str(), b.start_chi2, absent_chi2, b.fraction, b.chi2);
    moved[static_cast<std::size_t>(li)] = line;
  });
  for (const std::string& m : moved)
    if (!m.empty()) say(m);
}

std::size_t Screening::grid_simulations(const std::vector<std::size_t>& shortlist) const {
  std::size_t n = 0;
  for (std::size_t i : shortlist) {
    if (gridded(screens_[i])) n += kGridPoints + 1;
    if (transfer_gridded(screens_[i])) {
      std::size_t points = 1;  // transfer_grid's size: kGridPoints per transfer parameter, crossed
      for (std::size_t t = transfer_parameters(screens_[i].spec).size(); t > 0; --t) points *= kGridPoints;
      n += points + 1;
    }
  }
  return n;
}

std::vector<double> Screening::grid_values(const ParameterSpec& ps) {
  std::vector<double> out;
  for (int g = 0; g < kGridPoints; ++g) {
    const double f = (g + 0.5) / kGridPoints;
    out.push_back(along(ps, ps.lower, ps.upper, f));
  }
  return out;
}

void Screening::grid_starts(const std::vector<std::size_t>& shortlist,
                            const std::function<void(const std::string&)>& say) {
  // Each grid point: a screen and its whole parameter vector there.
  struct GridPoint {
    std::size_t screen;
    std::vector<double> x;
  };
  std::vector<GridPoint> grid;
  for (std::size_t i : shortlist) {
    const Screen& sc = screens_[i];
    if (gridded(sc))
      for (double x : grid_values(sc.spec.front())) grid.push_back({i, {x}});
    if (transfer_gridded(sc))
      for (std::vector<double>& x : transfer_grid(sc.spec, sc.start)) grid.push_back({i, std::move(x)});
  }
  if (grid.empty()) return;
  say("grid starts for the one-parameter candidates and the transfer parameters (" + std::to_string(grid.size()) +
      " simulations)");
  std::vector<double> chi(grid.size(), std::numeric_limits<double>::infinity());
  parallel_for(static_cast<int>(grid.size()), ctx_.threads, [&](int gi) {
    const GridPoint& g = grid[static_cast<std::size_t>(gi)];
    const Screen& sc = screens_[g.screen];
    chi[static_cast<std::size_t>(gi)] = ctx_.fit_chi2(sc.c, sc.v, g.x, sc.nuisance_start);
  });
  for (std::size_t i : shortlist) {
    Screen& sc = screens_[i];
    if (!gridded(sc) && !transfer_gridded(sc)) continue;
    double best = std::numeric_limits<double>::infinity();
    const std::vector<double>* xb = nullptr;
    for (std::size_t gi = 0; gi < grid.size(); ++gi)
      if (grid[gi].screen == i && chi[gi] < best) best = chi[gi], xb = &grid[gi].x;
    // The linearized start, +inf where the solver cannot simulate it (the grid's best then wins).
    if (xb && best < ctx_.fit_chi2(sc.c, sc.v, sc.start, sc.nuisance_start)) sc.start = *xb;
  }
}

} // namespace pw::diagnose
