#include "diagnose/ranking.hpp"

#include "core/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pw::diagnose {

void assess_candidate(CandidateResult& r, const RankingBasis& b, const std::vector<ParameterSpec>* own_spec) {
  const int k = std::max(1, r.own_parameters);
  r.lr_threshold = chi2_quantile(k, b.alpha);
  r.delta_chi2_fit = b.nuisance_fit_chi2 - r.fit.chi2;
  r.delta_chi2_held_out = b.nuisance_held_out_chi2 - r.held_out.chi2;
  r.significant = r.delta_chi2_fit > r.lr_threshold;
  r.holds = r.delta_chi2_held_out > r.lr_threshold;
  r.non_null = false;
  if (own_spec && r.failed.empty()) {
    // A saturating parameter has no meaningful standard error: 'absent' is tested by the
    // likelihood ratio against the same model with its own parameters at 'absent'.
    if (std::isfinite(r.null_chi2_fit)) {
      // The likelihood ratio of 'absent' (transfer parameters and nuisance as fitted), and a level
      // (a non-zero 'absent') moved beyond kRecalibration of itself, as below: the ratio is
      // invariant to how the parameters are written, where a standard error is not (a runout's
      // Cartesian pair whose phase the amplitudes barely fix; a size on a ridge with a transfer).
      bool moved = false;
      for (std::size_t i = 0; i < own_spec->size() && i < r.parameters.size(); ++i) {
        const ParameterSpec& ps = (*own_spec)[i];
        if (ps.transfer) continue;
        moved = moved || ps.saturates ||
                std::fabs(r.parameters[i].value - ps.null_value) > kRecalibration * std::fabs(ps.null_value);
      }
      r.non_null = moved && r.null_chi2_fit - r.fit.chi2 > r.lr_threshold;
    } else {
      // Beyond z standard errors (Wald) and, for a level (a non-zero 'absent'), beyond
      // kRecalibration of it: at high signal-to-noise a level moves by a few % with a tiny
      // standard error to soak up model-form error. Measured against healthy baselines of an
      // independent simulator: friction fitted 0.0595, 0.0574 and 0.0624 for the documented 0.06
      // (standard errors 2e-5 to 1.3e-4) on a worn profile, another worn profile and a stiffness
      // change, each named friction (docs/diagnose-log.md, session 22).
      const double zw = normal_quantile(b.alpha / (2.0 * k));
      for (std::size_t i = 0; i < own_spec->size() && i < r.parameters.size(); ++i) {
        if ((*own_spec)[i].transfer) continue;  // how it reaches the sensors, not whether it is there
        const FittedParameter& p = r.parameters[i];
        const double absent = (*own_spec)[i].null_value;
        const double shift = std::fabs(p.value - absent);
        if (p.std_error > 0 && shift > zw * p.std_error && shift > kRecalibration * std::fabs(absent)) r.non_null = true;
      }
    }
  }
  const double kt = static_cast<double>(b.nuisance_parameters + static_cast<std::size_t>(r.own_parameters));
  r.aic = r.fit.chi2 + 2.0 * kt;
  r.bic = r.fit.chi2 + kt * b.ln_m;
  r.bic_held_out = r.held_out.chi2 + kt * b.ln_m;
}

void rank_candidates(std::vector<CandidateResult>& candidates) {
  std::stable_sort(candidates.begin(), candidates.end(), [](const CandidateResult& a, const CandidateResult& b) {
    if (a.counts() != b.counts()) return a.counts();
    return a.bic + a.bic_held_out < b.bic + b.bic_held_out;
  });
}

std::string ranking_reason(const CandidateResult& r, bool winner, double best_bic) {
  char buf[400];
  if (winner)
    std::snprintf(buf, sizeof buf,
                  "lowest BIC (both halves) among the candidates that improve significantly on both halves "
                  "(fit: -%.1f, held out: -%.1f; threshold %.1f)",
                  r.delta_chi2_fit, r.delta_chi2_held_out, r.lr_threshold);
  else if (!r.failed.empty())
    std::snprintf(buf, sizeof buf, "%s", r.failed.c_str());
  else if (!r.significant)
    std::snprintf(buf, sizeof buf, "improvement on the fit half %.1f is below the threshold %.1f", r.delta_chi2_fit,
                  r.lr_threshold);
  else if (!r.holds)
    std::snprintf(buf, sizeof buf, "fits the first half (-%.1f) but does not hold on the held-out half (%+.1f; threshold %.1f)",
                  r.delta_chi2_fit, -r.delta_chi2_held_out, r.lr_threshold);
  else if (!r.non_null && std::isfinite(r.null_chi2_fit))
    std::snprintf(buf, sizeof buf,
                  "improves both halves (-%.1f, -%.1f) but with its own parameters at 'absent' (transfer ones and "
                  "the nuisance as fitted) the fit half's chi2 rises by %.1f (likelihood-ratio threshold %.1f), or a "
                  "level moved by no more than %.0f %% of itself: the gain is the other parameters moving, or a "
                  "level soaking up model-form error, not this physics",
                  r.delta_chi2_fit, r.delta_chi2_held_out, r.null_chi2_fit - r.fit.chi2, r.lr_threshold,
                  100 * kRecalibration);
  else if (!r.non_null)
    std::snprintf(buf, sizeof buf,
                  "improves both halves (-%.1f, -%.1f) but its parameters do not differ from 'absent' beyond "
                  "their standard errors (Wald test) and, for a level, by more than %.0f %% of it: the gain is the "
                  "nuisance parameters converging further, or a level soaking up model-form error",
                  r.delta_chi2_fit, r.delta_chi2_held_out, 100 * kRecalibration);
  else
    std::snprintf(buf, sizeof buf, "BIC (both halves) %.1f higher than the winner's", r.bic + r.bic_held_out - best_bic);
  return buf;
}

bool refit_replaces_lead(const CandidateResult& lead, const CandidateResult& refit) {
  if (!(refit.fit.chi2 < lead.fit.chi2)) return false;
  return !(lead.counts() && !refit.counts());
}

} // namespace pw::diagnose
