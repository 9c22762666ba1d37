// The verdict of a diagnosis (docs/diagnose.md §5, "Verdict"): a pure function
// of the numbers diagnose() computed, so that it can be tested on hand-built
// values.
//
// A candidate that counts (CandidateResult::counts(): significant on the fit
// half, holds on the held-out half, a parameter away from 'absent') is named
// as the missing physics only if also
//   (a) its fitted model explains the held-out half: chi2_h <= B_lead, the
//       1 - alpha/2 quantile of the held-out chi2 under "this fitted model is
//       the truth" (ModelComparison::null_quantile with the model's own
//       amplitudes, the same Monte-Carlo null as the noise test, plus 2 chi2(k)
//       for its k parameters fitted on the other half: see null_quantile).
//       Both chi2_h and B_lead use the model-fidelity directions recomputed at
//       the candidate's own fitted model: the nuisance model's directions hold
//       no discretization or speed change of the lines the candidate adds.
//       B_lead is the smaller of that null with the fidelity weights folded into
//       the lines and with them added to the residual as chi2 profiles them
//       (FidelityDraw): a pass owed to the fold alone is no evidence
//       (diagnose.cpp, OwnModelScore).
//       The budget is max(B_lead, chi2_rep): chi2_rep is the held-out chi2 of
//       the recording's own fit half used as the prediction (model-free, E ~ 2m
//       for a stationary recording). Why: own-simulator findings leave 2-9 %
//       above B_lead (tests/diagnose/test_diagnose.cpp, docs/diagnose.md §5),
//       a model-form remainder no null of ours describes; a fitted model that
//       predicts the held-out half no worse than the data's other half does is
//       as good as any prediction from one half can be asked to be;
//   (b) no parameter that carries the finding sits at a bound: none of its own
//       (saturating ones excepted: only their lower limit is claimed, and
//       "any larger value fits as well" means the fit may stop at the top of
//       the box), and no nuisance parameter of its joint fit that moved
//       (recalibrated: kRecalibration and z_{1-alpha/2} standard errors, as
//       for the nuisance-only fit);
//   (c) the excess replicated: with the nuisance parameters alone the held-out half
//       exceeds its bound as well. A fit-half-only excess is what the noise test
//       admits with probability alpha/2, and a held-out half with nothing to explain
//       confirms nothing (found on a calibrated independent-simulator recording whose
//       stiffness change the recalibration absorbed: a transfer-path window that
//       improved both halves by ~10 was named).
//   (d) the data tell it apart from the other counting candidates: its BIC
//       posterior probability among those of other names (equal prior odds,
//       BIC summed over both halves) is at least 1 - alpha/2 -- the confidence
//       the other steps ask for. Two near-equivalent explanations (a carrier
//       runout is a pin-error pattern plus a small radial part) are a lead, not
//       a finding.
// Class finding: when (a)-(c) hold and (d) and (e) fail only against members of the
// lead's own FindingClass (candidate.hpp: pin errors and a carrier runout, both planet
// centres displaced in the carrier), the class is named -- "planet_position_error" --
// with the lead's fit as its model and its size in the class's canonical member's terms.
// Its BIC posterior, summed over its members (Bayesian model averaging), must reach
// 1 - alpha/2 against every rival of another class. Why: the members differ only by the
// radial part of the displacements, which the budget says the model cannot resolve
// (condition (e)); refusing both names then withholds what the data do establish -- that
// the planets are off their positions -- while naming either member would overstate.
// Measured on the independent corpus, differential, sensors a rig has: 8 runouts and pin
// errors with the pair as lead and rival (docs/diagnose-log.md, session 36). The second class,
// tooth_contact_change (friction, wear, relief, clearance; covering the stiffness and damping
// levels), on the same grounds: its members change the mesh harmonics alone, and (e) holds them
// undecidable from each other under a budget (session 38).
// Otherwise the verdict is "unexplained residual", with the best candidate
// reported as a lead, never as a finding.
//
// Under a correct finding from a model that can reproduce the recording,
// (a) fails with probability <= alpha/2 (the quantile's definition; the
// 2 chi2(k) term bounds the parameter-estimation error from above), and (b)
// fails only when the truth lies on the edge of a box.
#pragma once

#include "diagnose/candidates/candidate.hpp"
#include "diagnose/diagnose.hpp"
#include "diagnose/ranking.hpp"

#include <functional>
#include <map>
#include <string>

namespace pw::diagnose {

/// value moved from initial by > z standard errors and > kRecalibration relative.
bool recalibrated(const FittedParameter& p, double z);

/// The nuisance-fitted values as the summaries state them ("stiffness.scale = 1.02 ± 0.001
/// (recalibrated), ...", and the mesh phase and housing path where they are not the defaults).
std::string nuisance_text(const Diagnosis& d);

/// The nuisance parameters of r's joint fit that condition (b) withholds a name for and a held
/// refit can hold (docs/diagnose.md §5, step 12b): moved (recalibrated at z) and at a bound of
/// their box. Housing gains are profiled, not fitted, and are never listed.
std::vector<std::string> moved_nuisance_at_bound(const CandidateResult& r, double z);

/// What the verdict needs beyond the Diagnosis itself.
struct VerdictInputs {
  /// DiagnoseOptions::line_coverage: for Diagnosis::coverage_gap and the unexplained summary.
  std::vector<LineCoverage> line_coverage;
  /// Nuisance-fitted held-out chi2 within bound_held_out (the fit half is not required: its
  /// excess alone did not replicate).
  bool noise_consistent = false;
  /// The lead's held-out chi2 with the fidelity directions at its own fitted model (NaN: its
  /// ranked held_out.chi2 is used).
  double lead_held_out_chi2 = std::numeric_limits<double>::quiet_NaN();
  /// B_lead: 1 - alpha/2 null quantile of that chi2 (NaN: no lead or not computed).
  double lead_bound_held_out = std::numeric_limits<double>::quiet_NaN();
  /// The same quantile with the fidelity weights folded into the lines (FidelityDraw::Folded;
  /// B_lead is the smaller of the two): for the reason when only the folded one holds it.
  double lead_bound_folded = std::numeric_limits<double>::quiet_NaN();
  /// Why B_lead could not be computed (the solver's message on the lead's model or one of its
  /// fidelity variants); empty when it was.
  std::string lead_score_failure;
  /// chi2 of the recording's fit half as the prediction of its held-out half
  /// (ModelComparison::replicate_chi2; NaN: not used).
  double replicate_chi2 = std::numeric_limits<double>::quiet_NaN();
  /// Condition (e), under a discrepancy budget: a fitted near-alias of the lead
  /// (Candidate::start_from maps one's parameters onto the other's) that counts; empty: none.
  /// Its held-out chi2 and bound at its own model, scored as the lead is, for the text (NaN
  /// bound: it could not be simulated).
  std::string counting_alias;
  /// false: the alias is in the library but no fit of it counted (it did not converge from its
  /// own start); it blocks the name unscored.
  bool alias_counts = true;
  /// The alias is one because both act on the mesh harmonics alone (their difference is the
  /// harmonics' shape), not because one's parameters map onto the other's; it then need only
  /// improve both halves beyond its threshold, not count.
  bool alias_mesh_shape = false;
  /// The family both act on alone when alias_mesh_shape (Mesh: the harmonics' shape; Sun: how the
  /// change is shared among the sun family's orders).
  Component alias_shape_family = Component::Mesh;
  double alias_held_out_chi2 = std::numeric_limits<double>::quiet_NaN();
  double alias_bound_held_out = std::numeric_limits<double>::quiet_NaN();
  double alpha = 0.01;
  /// The calibration's discrepancy budgets in force (CompareOptions::discrepancy; empty: none).
  /// A "no missing physics" under a budget says how large a change of the lines it leaves
  /// undetectable.
  std::vector<DiscrepancyEntry> discrepancy;
  /// Differential diagnosis (a baseline): the discrepancy budgets apply to the model's change
  /// from the baseline's model, so they say nothing about a "no missing physics".
  bool differential = false;
};

/// Condition (e)'s rival of the lead `ranked.front()`, if any: under a discrepancy budget the
/// first candidate in ranked order that
///  * is a displacement near-alias of the lead (Candidate::start_from maps one's own parameters
///    onto the other's: pin errors and a carrier runout) and counts; or
///  * acts on one family alone, the same as the lead's, that family being the mesh harmonics
///    (acts_on_mesh_harmonics_only) or the sun's (a damaged sun tooth and a sun runout), and
///    improves both halves beyond its threshold (significant && holds), counting or not;
/// fitted candidates that failed, and variants of the lead's own name, are never rivals. If no
/// fitted one blocks, a displacement near-alias of the lead in the library that was screened
/// (`screened`) but whose fit did not count blocks unscored (fitted = false): its fit not
/// converging is not evidence against it; so does a screened one-family shape rival of the kind
/// above with no successful fit among `ranked` (the screening left it out), only a fit that fails
/// to improve both halves refuting it. nuisance_x: the fixed nuisance values (split_parameters).
struct NearAlias {
  std::string name;         ///< empty: nothing blocks
  std::size_t index = 0;    ///< into `ranked` when fitted
  bool fitted = false;      ///< a fitted candidate (else a library alias, unscored)
  bool mesh_shape = false;  ///< a one-family shape rival (see shape_family) rather than a displacement alias
  Component shape_family = Component::Mesh;  ///< the family a shape rival and the lead act on alone
};
NearAlias blocking_near_alias(const std::vector<CandidateResult>& ranked, const std::vector<double>& nuisance_x,
                              const model::SimulationConfig& base,
                              const std::function<bool(const Candidate&)>& screened);

/// Where the differential checks of a change since the baseline (a housing sensor's gain, a
/// level) run: with a baseline, after a "no missing physics", and after an "unexplained residual"
/// that no candidate counts for -- never after a finding, and never beside a counting candidate,
/// whose own verdict (a lead or a finding) stands. Why the second: each hypothesis is judged by
/// its own V (fit_sensor_scale; a level by its own model's score), so passing its held-out test
/// means it explains the whole recording, every other channel against the baseline recording
/// within the noise: a complete explanation, not one part of one. Tried and withdrawn in session
/// 28, when the sensor hypothesis was scored under the nuisance fit's V, whose discrepancy budget
/// let a gear change in the speed channels pass (a stiffness x0.8 named the housing gain x1.09);
/// restored in session 38 with the own V (four4p rec_33's housing x1.8 named, x1.8 +- 0.0008;
/// docs/diagnose-log.md).
bool change_since_baseline_testable(bool has_baseline, Verdict verdict, const std::vector<CandidateResult>& candidates);

/// Where the lead of an "unexplained residual" acts on every planet alike
/// (Candidate::every_planet_alike) while the located planet pattern (planet_pattern.hpp) has a
/// significant order k >= 1: the share of the speed channels' mesh-harmonic excess at k >= 1,
/// which no such candidate can make; 0 otherwise (another lead, no pattern, none significant).
double planet_pattern_conflict_share(const Diagnosis& d);

/// A level's ratio rho since the baseline is a change: kRecalibration from 1 and |ln rho| beyond
/// `threshold_ln`, what the noise and the calibration's healthy scatter of that level allow
/// (level_move_test, level_change.hpp).
bool level_moved(double rho, double threshold_ln);

/// After the differential check named nothing (docs/diagnose.md section 6b item 7): the index in
/// `changes` of the level change that still rules out "no missing physics" -- a stiffness or
/// damping level that explains (both halves by more than chi2_{1-alpha}(1)), moved
/// (level_moved) and lies off its box's edge (at the edge its ratio is a bound, not a size) --
/// the lowest chi2 over both halves first; -1 when there is none. Why: the recording is then not
/// the healthy reference's, whatever kept the change unnamed (its own model's shortfall, a rival).
int unnamed_level_change(const std::vector<BaselineChange>& changes);

/// The mesh levels' configuration keys (candidates/candidate.hpp).
inline constexpr const char* kLevelParameters[] = {kStiffnessLevelKey, kDampingLevelKey};

/// After a "no missing physics" (docs/diagnose.md section 6b item 7): the levels the nuisance fit
/// moved (FittedParameter::moved: more than z_{1-alpha/2} standard errors and kRecalibration from
/// where it started; or more than kRecalibration to an edge of its box, where it has no standard
/// error) when `levels_tested` is false, i.e. no healthy reference at the recording's
/// operating point tested them as changes; empty for any other verdict or when they were tested.
/// Why: a fit that moves a level freely absorbs a change of friction, wear, relief, clearance or
/// the level itself (indepsim4's offpoint plan: a friction x1.95 at 750 rpm came out "no missing
/// physics" with stiffness.scale 1.60 against the calibration's 1.02), while the healthy controls
/// of the same plan moved it as far (0.49-1.25 against 0.98-1.02): without a reference the move is
/// no evidence either way, and the verdict must say what it leaves open.
std::vector<UntestedLevel> untested_level_moves(const Diagnosis& d, bool levels_tested);

/// The summary's sentence for untested_level_moves ("" for none): each level from where to where,
/// and what a "no missing physics" then does not rule out. `calibrated`: the start is the
/// calibration's value (else the configuration's).
std::string untested_levels_text(const std::vector<UntestedLevel>& levels, bool calibrated);

/// " Under the calibration's discrepancy budget ... not detectable" for the largest relative
/// budgets (at least kReportedBudget), or "" if none is that large.
std::string budget_sensitivity_text(const std::vector<DiscrepancyEntry>& budgets);

/// What a finding's size is stated against when the reference's nuisance fit left values at an
/// edge of their box (`limits`, bound_ends): "the reference's model with stiffness.scale at the
/// lower edge of its box (a limit, not a fit)"; empty without limits. The model's change from the
/// reference is computed at those values, so a size fitted to it is conditional on them
/// (FittedParameter::size_conditional_on; docs/diagnose.md section 6b, "When it is valid").
std::string limited_reference_text(const std::map<std::string, int>& limits);

/// Sets d.verdict, d.winner (0 = candidates.front() named, else -1), d.lead,
/// d.excess_by_channel and d.summary; appends the verdict rule with its numbers
/// to d.rule. Expects d.candidates ranked (counting ones first) and d.winner = 0
/// iff candidates.front() counts. Marks `moved` on the lead's nuisance parameters.
void decide_verdict(Diagnosis& d, const VerdictInputs& in);

} // namespace pw::diagnose
