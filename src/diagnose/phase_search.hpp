// After the ranking, the named winner's last two questions (docs/diagnose.md §5, steps 11-12):
//   * where: its phase variants (which tooth, which planet) at its fitted parameters. Phases
//     that trade off against the parameters (a ring tooth far from the sensor sounds like a
//     milder one near it) are screened with the parameters profiled and the best local minima
//     followed; a refit replaces the winner if it fits the fit half better and still counts,
//     and the search repeats from the replacement until the place stays (alternating descent
//     over place and parameters);
//   * how large at least: a saturating parameter (backlash wider than the teeth ever separate)
//     is bounded from below only, by a profile of the fit-half chi2.
// Internal to src/diagnose.
#pragma once

#include "diagnose/fit_context.hpp"

#include <functional>
#include <string>

namespace pw::diagnose {

using Progress = std::function<void(const std::string&)>;
/// Recomputes a result's significance, test of 'absent' and BIC against the nuisance-only model.
using Assessment = std::function<void(CandidateResult&)>;

/// Replaces `winner` by the best of its phase variants where that fits better and still counts.
void search_phases(FitContext& ctx, CandidateResult& winner, const LocatedEvidence& evidence, const ToothMap& teeth,
                   int max_iterations, const Assessment& assess, const Progress& say);

/// Sets lower_limit on the winner's saturating parameters: the smallest value, along the line
/// from 'absent' to the fit (nuisance fixed), whose fit-half chi2 stays within
/// chi2_{1-alpha}(1) of the fit's. No-op for a candidate without a saturating parameter.
void profile_saturating(FitContext& ctx, CandidateResult& winner, double alpha, const Progress& say);

/// The profile's scale: the smallest s in [1e-6, 1] along x(s) = null + s (x_fit - null) from
/// which chi2_at(s) stays within `limit` up to s = 1, on a 13-point geometric grid refined by 6
/// points between the last grid point above the limit and the first within (so to a factor
/// (1e-6)^(1/12 * 1/5) ~ 1.26 of the crossing); 1e-6 if every point is within, 1 if s = 1 is not.
double lower_limit_scale(const std::function<double(double)>& chi2_at, double limit, int threads);

/// Simulations search_phases (its first pass) and profile_saturating are expected to run for
/// `winner` (forecast.hpp: LM to its iteration cap).
long expected_phase_search_simulations(const FitContext& ctx, const CandidateResult& winner,
                                       const LocatedEvidence& evidence, const ToothMap& teeth, int max_iterations);

} // namespace pw::diagnose
