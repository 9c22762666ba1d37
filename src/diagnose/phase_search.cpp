#include "diagnose/phase_search.hpp"

#include "core/statistics.hpp"
#include "diagnose/fit.hpp"
#include "diagnose/forecast.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>

namespace pw::diagnose {

namespace {

/// Local minima of the one-step phase profile followed further, and the Broyden steps each gets.
constexpr std::size_t kRefinedPhases = 4;
constexpr int kRefinementRounds = 2;
/// Passes of the phase screening for phases that trade off against the parameters.
constexpr int kPhasePasses = 3;
/// Saturating profile: s = 10^-6 .. 1 on a log grid of 13 points, then 6 inside the bracket.
constexpr double kProfileLowest = 1e-6;
constexpr int kProfileGrid = 13, kProfileRefine = 6;

/// One pass of the phase search from the winner's current place and parameters.
class PhasePass {
public:
  PhasePass(FitContext& ctx, const Candidate& cand, const CandidateResult& w, std::vector<Variant> phases,
            const Progress& say)
      : ctx_(ctx), cand_(cand), w_(w), phases_(std::move(phases)), say_(say),
        profile_(cand.phase_trades_with_parameters()), pspec_(cand.parameters(ctx.base)) {
    const SplitParameters s = split_parameters(w, ctx.nuisance_x);
    own_ = s.own;
    nx_ = s.nuisance;
    per_ = profile_ ? 1 + own_.size() : 1;
    for (const auto& p : pspec_) box_.push_back({p.lower, p.upper, p.log_scale});
  }

  /// Fit-half chi2 of every phase at the winner's parameters, or (profiled) after one
  /// Gauss-Newton step of the parameters on secants to a point half their distance from
  /// "absent" further out (the screening value if at "absent").
  void screen() {
    std::vector<double> h(own_.size(), 0.0);
    if (profile_)
      for (std::size_t k = 0; k < own_.size(); ++k) {
        double x1 = own_[k] + 0.5 * (own_[k] - pspec_[k].null_value);
        if (x1 == own_[k]) x1 = pspec_[k].screen_value;
        h[k] = std::clamp(x1, pspec_[k].lower, pspec_[k].upper) - own_[k];
      }
    say_("screening " + std::to_string(phases_.size()) + " phase variants of " + w_.name +
         (profile_ ? " with its parameters profiled (" + std::to_string(phases_.size() * per_) + " simulations)" : ""));
    res_.assign(phases_.size() * per_, {});
    parallel_for(static_cast<int>(res_.size()), ctx_.threads, [&](int ti) {
      const std::size_t i = static_cast<std::size_t>(ti) / per_, k = static_cast<std::size_t>(ti) % per_;
      std::vector<double> x = own_;
      if (k > 0) x[k - 1] += h[k - 1];
      res_[static_cast<std::size_t>(ti)] = residual(i, x);
    });
    chi_.assign(phases_.size(), std::numeric_limits<double>::infinity());
    xstart_.assign(phases_.size(), own_);
    prof_.assign(phases_.size(), SecantProfile{});
    for (std::size_t i = 0; i < phases_.size(); ++i) {
      const auto& r0 = res_[i * per_];
      if (r0.empty()) continue;
      const Eigen::Map<const Eigen::VectorXd> e0(r0.data(), static_cast<Eigen::Index>(r0.size()));
      chi_[i] = e0.squaredNorm();
      if (!profile_) continue;
      Eigen::MatrixXd J(e0.size(), static_cast<Eigen::Index>(own_.size()));
      bool ok = true;
      for (std::size_t k = 0; k < own_.size() && ok; ++k) {
        const auto& rk = res_[i * per_ + 1 + k];
        ok = !rk.empty() && rk.size() == r0.size() && h[k] != 0;
        if (ok) J.col(static_cast<Eigen::Index>(k)) = (Eigen::Map<const Eigen::VectorXd>(rk.data(), e0.size()) - e0) / h[k];
      }
      if (!ok) continue;
      prof_[i] = SecantProfile(own_, e0, J);
      const auto step = prof_[i].gauss_newton_step(box_);
      if (std::isfinite(step.predicted_cost) && step.predicted_cost < chi_[i]) chi_[i] = step.predicted_cost, xstart_[i] = step.x;
    }
  }

  /// The one-step profile is a linearization about the winner's severity; a place that needs a
  /// very different one can be ranked too low. Neighbouring places share one basin; distinct
  /// hypotheses (e.g. mirror places either side of a symmetric sensor window) are distinct
  /// local minima along the closed path winner, phases[0], ..., phases[n-1], winner. The best
  /// few minima are followed by Broyden-updated Gauss-Newton steps, each one simulation, and
  /// ranked by the chi2 they reach at a simulated point (docs/diagnose.md §5, step 11).
  void follow_minima() {
    if (!profile_) return;
    std::vector<double> usable_chi = chi_;
    for (std::size_t i = 0; i < phases_.size(); ++i)
      if (!prof_[i].usable()) usable_chi[i] = std::numeric_limits<double>::infinity();
    const std::vector<std::size_t> order = local_minima_on_closed_path(usable_chi, w_.fit.chi2, kRefinedPhases);
    std::string minima = "one-step profile's local minima:";
    for (std::size_t i : order) minima += " " + phases_[i].label + " " + fmt("%.0f", chi_[i]) + ";";
    if (order.empty()) minima += " none below the winner's chi2 " + fmt("%.0f", w_.fit.chi2);
    say_(minima);
    for (int round = 0; round < kRefinementRounds; ++round) {
      std::vector<std::vector<double>> rr(order.size());
      parallel_for(static_cast<int>(order.size()), ctx_.threads, [&](int ti) {
        const std::size_t i = order[static_cast<std::size_t>(ti)];
        rr[static_cast<std::size_t>(ti)] = residual(i, xstart_[i]);
      });
      for (std::size_t o = 0; o < order.size(); ++o) {
        const std::size_t i = order[o];
        if (rr[o].size() != res_[i * per_].size()) continue;
        prof_[i].accept(xstart_[i], Eigen::Map<const Eigen::VectorXd>(rr[o].data(), static_cast<Eigen::Index>(rr[o].size())));
        const auto step = prof_[i].gauss_newton_step(box_);
        xstart_[i] = std::isfinite(step.predicted_cost) && step.predicted_cost < prof_[i].best_cost() ? step.x
                                                                                                      : prof_[i].best_x();
      }
    }
    for (std::size_t i : order) chi_[i] = prof_[i].best_cost(), xstart_[i] = prof_[i].best_x();
    std::vector<std::size_t> ranked(phases_.size());
    std::iota(ranked.begin(), ranked.end(), std::size_t{0});
    std::sort(ranked.begin(), ranked.end(), [&](std::size_t a, std::size_t c) { return chi_[a] < chi_[c]; });
    std::string top = "best places (fit-half chi2, simulated for the followed minima, predicted for the rest; "
                      "winner " + fmt("%.0f", w_.fit.chi2) + "):";
    for (std::size_t r = 0; r < std::min<std::size_t>(ranked.size(), kRefinedPhases); ++r)
      top += " " + phases_[ranked[r]].label + " " + fmt("%.0f", chi_[ranked[r]]) + ";";
    say_(top);
  }

  /// The best place if it looks better than the winner: refitted jointly (nothing if it does not
  /// look better or the solver fails).
  std::optional<CandidateResult> refit_best(int max_iterations) {
    best_ = static_cast<std::size_t>(std::min_element(chi_.begin(), chi_.end()) - chi_.begin());
    if (!(chi_[best_] < w_.fit.chi2)) return std::nullopt;
    std::vector<double> x0 = xstart_[best_];
    x0.insert(x0.end(), nx_.begin(), nx_.end());
    return try_fit_model(ctx_, &cand_, phases_[best_], true, ctx_.threads, std::max(2, max_iterations / 2), x0);
  }

  const Variant& best_phase() const { return phases_[best_]; }
  std::size_t phases() const { return phases_.size(); }
  long simulations() const { return sims_.load(); }
  bool profiled() const { return profile_; }

private:
  /// Whitened fit-half residual of phase i at parameters x; empty if the solver fails there.
  std::vector<double> residual(std::size_t i, const std::vector<double>& x) {
    return ctx_.fit_residual(&cand_, phases_[i], x, nx_, false, &sims_);
  }

  FitContext& ctx_;
  const Candidate& cand_;
  const CandidateResult& w_;
  std::vector<Variant> phases_;
  const Progress& say_;
  bool profile_;
  std::vector<ParameterSpec> pspec_;
  std::vector<double> own_, nx_;
  std::size_t per_ = 1;  ///< simulations per phase (1 + own parameters when profiled)
  std::vector<Bound> box_;
  std::vector<std::vector<double>> res_;
  std::vector<double> chi_;
  std::vector<std::vector<double>> xstart_;
  std::vector<SecantProfile> prof_;
  std::size_t best_ = 0;
  std::atomic<long> sims_{0};  ///< simulations this pass's screening and refinement ran
};

} // namespace

void search_phases(FitContext& ctx, CandidateResult& w, const LocatedEvidence& evidence, const ToothMap& teeth,
                   int max_iterations, const Assessment& assess, const Progress& say) {
  const Candidate* cand = find_candidate(w.name);
  Variant v = w.chosen;
  for (int pass = 0; pass < kPhasePasses; ++pass) {
    auto phases = cand->phase_variants(v, evidence, ctx.base, teeth);
    if (phases.empty()) break;
    PhasePass p(ctx, *cand, w, std::move(phases), say);
    p.screen();
    p.follow_minima();
    std::optional<CandidateResult> r2 = p.refit_best(max_iterations);
    bool replaced = false;
    if (r2 && r2->fit.chi2 < w.fit.chi2) {
      assess(*r2);
      if (r2->counts()) {
        r2->evidence_z = w.evidence_z;
        r2->predicted_improvement = w.predicted_improvement;
        r2->reason = w.reason + "; " + p.best_phase().label + " among " + std::to_string(p.phases() + 1) + " phases";
        r2->simulations += w.simulations + static_cast<int>(p.simulations());
        r2->seconds = w.seconds;
        w = std::move(*r2);
        v = w.chosen;
        replaced = true;
      }
    }
    if (!replaced || !p.profiled()) break;
  }
}

double lower_limit_scale(const std::function<double(double)>& chi2_at, double limit, int threads) {
  // The grid on [lo, hi] and the smallest index from which every larger grid point fits
  // within the limit.
  const auto scan = [&](double lo, double hi, int n) {
    const std::vector<double> sv = geometric_grid(lo, hi, n);
    std::vector<double> chi(sv.size());
    parallel_for(n, threads, [&](int i) { chi[static_cast<std::size_t>(i)] = chi2_at(sv[static_cast<std::size_t>(i)]); });
    int first = n;
    while (first > 0 && chi[static_cast<std::size_t>(first - 1)] <= limit) --first;
    return std::pair<std::vector<double>, int>(sv, first);
  };
  auto [s1, f1] = scan(kProfileLowest, 1.0, kProfileGrid);
  if (f1 == 0) return s1.front();
  if (f1 == static_cast<int>(s1.size())) return 1.0;
  auto [s2, f2] = scan(s1[static_cast<std::size_t>(f1 - 1)], s1[static_cast<std::size_t>(f1)], kProfileRefine);
  return s2[static_cast<std::size_t>(std::min(f2, static_cast<int>(s2.size()) - 1))];
}

void profile_saturating(FitContext& ctx, CandidateResult& w, double alpha, const Progress& say) {
  const Candidate* cand = find_candidate(w.name);
  const std::vector<ParameterSpec> wspec = cand->parameters(ctx.base);
  if (!any_saturates(wspec)) return;
  const SplitParameters s = split_parameters(w, ctx.nuisance_x);
  const std::vector<double>& own = s.own;
  const double limit = w.fit.chi2 + chi2_quantile(1, alpha);
  // Fit-half chi2 at x(s) = null + s (x_fit - null), the nuisance fixed.
  const auto chi2_at = [&](double sc) {
    std::vector<double> x(own.size());
    for (std::size_t i = 0; i < own.size(); ++i) x[i] = wspec[i].null_value + sc * (own[i] - wspec[i].null_value);
    return ctx.fit_chi2(cand, w.chosen, x, s.nuisance);
  };
  say("profiling the saturating parameter(s) of " + w.name + " for their lower limit");
  const double s_low = lower_limit_scale(chi2_at, limit, ctx.threads);
  for (std::size_t i = 0; i < wspec.size() && i < w.parameters.size(); ++i)
    if (wspec[i].saturates) w.parameters[i].lower_limit = wspec[i].null_value + s_low * (own[i] - wspec[i].null_value);
}

} // namespace pw::diagnose

namespace pw::diagnose {

long expected_phase_search_simulations(const FitContext& ctx, const CandidateResult& w, const LocatedEvidence& evidence,
                                       const ToothMap& teeth, int max_iterations) {
  const Candidate* cand = find_candidate(w.name);
  if (!cand) return 0;
  const std::vector<ParameterSpec> spec = cand->parameters(ctx.base);
  const std::size_t own = spec.size(), nuisance = ctx.nuisance_x.size();
  long n = 0;
  // One pass (PhasePass): every phase screened, the followed minima's Broyden rounds and the
  // refit of the best place; a further pass only runs when the place moved.
  const std::size_t phases = cand->phase_variants(w.chosen, evidence, ctx.base, teeth).size();
  if (phases > 0) {
    const bool profiled = cand->phase_trades_with_parameters();
    n += static_cast<long>(phases * (profiled ? 1 + own : 1));
    if (profiled) n += static_cast<long>(kRefinedPhases) * kRefinementRounds;
    n += lm_simulations(own + nuisance, std::max(2, max_iterations / 2));
  }
  if (any_saturates(spec)) n += kProfileGrid + kProfileRefine;  // profile_saturating
  return n;
}

} // namespace pw::diagnose
