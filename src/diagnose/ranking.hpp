// The ranking of fitted candidates (docs/diagnose.md §5, steps 8-10), as pure functions over
// their results so that each rule can be tested on hand-built fits:
//   * assess: a candidate "counts" when it improves chi2 over the nuisance-only model by more
//     than chi2_{1-alpha}(k) on the fit half and on the held-out half, and 'absent' is rejected:
//     by the likelihood ratio (its own parameters at 'absent', transfer ones and the nuisance as
//     fitted) beyond chi2_{1-alpha}(k), or, where that was not simulated, some own parameter
//     beyond z_{1-alpha/2k} standard errors (Wald); and, when 'absent' is a non-zero level, a
//     move by more than kRecalibration of it; its AIC and BIC count the nuisance parameters and
//     its own;
//   * rank: counting candidates first, then by BIC summed over both halves (stable);
//   * ranking_reason: why each won or lost, with its numbers;
//   * refit_replaces_lead: whether the lead refitted in another model form (step 9c) replaces it.
// Internal to src/diagnose.
#pragma once

#include "diagnose/candidates/candidate.hpp"
#include "diagnose/diagnose.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace pw::diagnose {

/// A nuisance parameter counts as recalibrated beyond this relative change (and
/// z_{1-alpha/2} standard errors): smaller shifts are within the model's fidelity
/// (a discretization difference moves the fitted stiffness level by a few 0.1 %). The same
/// margin applies to a candidate parameter whose 'absent' value is a configured level
/// (friction, a tooth's stiffness factor 1, backlash): a smaller change is no finding.
constexpr double kRecalibration = 0.05;

/// What every candidate is judged against: the nuisance-only model's fit.
struct RankingBasis {
  double nuisance_fit_chi2 = 0;       ///< chi2 of the nuisance-only model, fit half
  double nuisance_held_out_chi2 = 0;  ///< same, held-out half
  std::size_t nuisance_parameters = 0;
  double alpha = 0.01;  ///< family-wise significance level
  double ln_m = 0;      ///< BIC penalty per parameter: ln(features)
};

/// Sets r's thresholds, significance on both halves, test of 'absent' and information criteria.
/// `own_spec`: the candidate's own parameters (null if the candidate is unknown: no test of
/// 'absent' then, r.non_null stays false).
void assess_candidate(CandidateResult& r, const RankingBasis& basis, const std::vector<ParameterSpec>* own_spec);

/// Counting candidates first, then by BIC summed over both halves; ties keep their order.
void rank_candidates(std::vector<CandidateResult>& candidates);

/// Why a fitted candidate won or lost, with its numbers (`best_bic`: the winner's BIC summed
/// over both halves).
std::string ranking_reason(const CandidateResult& r, bool winner, double best_bic);

/// Step 9c: whether `refit`, the lead `lead` fitted again in another model form (both assessed
/// against the same nuisance-only basis), replaces it. It must fit the fit half better; and a
/// lead that counted must still count: a form that leaves the lead's own physics not counting
/// took the excess itself, so the form is a change of the nuisance model's, which step 4c and a
/// calibration own, not the lead's. Measured: indepsim3 setB5 rec_10 (a 3.27 um sun runout, the
/// calibration on the window), refitted on the ring's translation, fitted the fit half better
/// (5709 -> 3164) with the runout at the bottom of its box, and the named runout was lost
/// (docs/diagnose-log.md, session 68).
bool refit_replaces_lead(const CandidateResult& lead, const CandidateResult& refit);

} // namespace pw::diagnose
