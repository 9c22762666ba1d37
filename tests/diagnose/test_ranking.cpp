// The ranking rules of ranking.hpp on hand-built fits: when a candidate counts (both halves
// beyond chi2_{1-alpha}(k), 'absent' rejected by Wald at z_{1-alpha/2k} or, for a saturating
// parameter, by the likelihood ratio), its BIC, the order of the ranking and the reasons.
#include "diagnose/ranking.hpp"

#include "core/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pw::diagnose {
namespace {

constexpr double kAlpha = 0.01;

/// The nuisance-only model: chi2 1000 on each half, 2 nuisance parameters, m = e^5 features.
RankingBasis basis() { return RankingBasis{1000.0, 1000.0, 2, kAlpha, 5.0}; }

ParameterSpec own_spec(double null_value = 0.0) {
  ParameterSpec p;
  p.name = "x";
  p.lower = -1;
  p.upper = 1;
  p.null_value = null_value;
  return p;
}

/// A one-parameter candidate fitted to `value` +- `se`, chi2 `fit` / `held_out`.
CandidateResult fitted(double fit, double held_out, double value = 0.5, double se = 0.01) {
  CandidateResult r;
  r.name = "x_candidate";
  r.own_parameters = 1;
  FittedParameter p;
  p.name = "x";
  p.value = value;
  p.std_error = se;
  r.parameters = {p};
  r.fit.chi2 = fit;
  r.held_out.chi2 = held_out;
  return r;
}

TEST(Ranking, ThresholdIsTheChi2QuantileOfTheOwnParameterCount) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult r = fitted(900, 900);
  assess_candidate(r, basis(), &spec);
  EXPECT_DOUBLE_EQ(r.lr_threshold, chi2_quantile(1, kAlpha));
  // chi2_{0.99}(1) = 6.635 (tables); Wilson-Hilferty's cube is 0.8 % low at nu = 1 (statistics.hpp).
  EXPECT_NEAR(r.lr_threshold, 6.635, 0.009 * 6.635);
  r.own_parameters = 2;
  assess_candidate(r, basis(), &spec);
  EXPECT_NEAR(r.lr_threshold, 9.210, 0.009 * 9.210);  // chi2_{0.99}(2)
}

TEST(Ranking, ACandidateCountsOnlyWhenBothHalvesImproveBeyondTheThreshold) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult both = fitted(990, 990), fit_only = fitted(990, 995), held_only = fitted(995, 990);
  for (CandidateResult* r : {&both, &fit_only, &held_only}) assess_candidate(*r, basis(), &spec);
  EXPECT_TRUE(both.significant && both.holds && both.counts());
  EXPECT_TRUE(fit_only.significant);
  EXPECT_FALSE(fit_only.holds);
  EXPECT_FALSE(fit_only.counts());
  EXPECT_FALSE(held_only.significant);
  EXPECT_FALSE(held_only.counts());
  EXPECT_DOUBLE_EQ(both.delta_chi2_fit, 10.0);
  EXPECT_DOUBLE_EQ(fit_only.delta_chi2_held_out, 5.0);
}

// Wald: |x - null| > z_{1-alpha/2k} se; z_{0.995} = 2.576 for k = 1, z_{0.9975} = 2.807 for k = 2.
TEST(Ranking, WaldTestOfAbsentUsesTheBonferroniZOfTheOwnParameters) {
  const std::vector<ParameterSpec> spec{own_spec(0.1)};
  CandidateResult r3 = fitted(900, 900, 0.1 + 2.7, 1.0), r2 = fitted(900, 900, 0.1 - 2.5, 1.0);
  assess_candidate(r3, basis(), &spec);
  assess_candidate(r2, basis(), &spec);
  EXPECT_TRUE(r3.non_null);   // 2.7 > 2.576
  EXPECT_FALSE(r2.non_null);  // 2.5 < 2.576
  CandidateResult k2 = fitted(900, 900, 0.1 + 2.7, 1.0);
  k2.own_parameters = 2;
  assess_candidate(k2, basis(), &spec);
  EXPECT_FALSE(k2.non_null);  // 2.7 < 2.807
  CandidateResult no_error = fitted(900, 900, 0.9, 0.0);
  assess_candidate(no_error, basis(), &spec);
  EXPECT_FALSE(no_error.non_null) << "a zero standard error is no evidence";
}

TEST(Ranking, ATransferParameterMovingAloneIsNoEvidenceThatThePhysicsIsThere) {
  // A torque ripple at 'absent' whose load inertia (how a ripple would reach the sensors) moved
  // far: the gain is the inertia's, a rig property, not a ripple (ParameterSpec::transfer).
  std::vector<ParameterSpec> spec{own_spec(0.0), own_spec(0.0)};
  spec[1].transfer = true;
  CandidateResult r = fitted(900, 900, 0.0, 1.0);
  r.own_parameters = 2;
  FittedParameter inertia;
  inertia.name = "stage.output_inertia_kgm2";
  inertia.value = 0.8;
  inertia.std_error = 0.001;
  r.parameters.push_back(inertia);
  assess_candidate(r, basis(), &spec);
  EXPECT_TRUE(r.significant && r.holds);
  EXPECT_FALSE(r.non_null);
  EXPECT_FALSE(r.counts());
  r.parameters[0].value = 5.0;  // the fraction itself away from 'absent' by 5 standard errors
  assess_candidate(r, basis(), &spec);
  EXPECT_TRUE(r.non_null);
}

TEST(Ranking, ALevelMustMoveByMoreThanFivePercentOfItselfBesidesItsStandardErrors) {
  // A friction coefficient documented 0.06 fitted to 0.0574 +- 0.00013 (20 standard errors, 4.4 %)
  // against a healthy baseline of an independent simulator's worn profile (session 22): no finding.
  const std::vector<ParameterSpec> level{own_spec(0.06)};
  CandidateResult small = fitted(900, 900, 0.0574, 0.00013), large = fitted(900, 900, 0.0566, 0.00013);
  assess_candidate(small, basis(), &level);
  assess_candidate(large, basis(), &level);
  EXPECT_FALSE(small.non_null);  // 0.0026 < 0.05 x 0.06 = 0.003
  EXPECT_FALSE(small.counts());
  EXPECT_TRUE(large.non_null);   // 0.0034 > 0.003 and > 2.576 x 0.00013
  // An absolute 'absent' (0: no runout, no pin error) has no level to be relative to.
  const std::vector<ParameterSpec> absolute{own_spec(0.0)};
  CandidateResult tiny = fitted(900, 900, 1e-9, 1e-10);
  assess_candidate(tiny, basis(), &absolute);
  EXPECT_TRUE(tiny.non_null);
}

TEST(Ranking, ASaturatingParameterIsTestedByTheLikelihoodRatioNotItsStandardError) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult lr = fitted(900, 900, 0.5, 10.0);  // Wald would say 'absent'
  lr.null_chi2_fit = 900 + 7.0;                     // 7 > chi2_{0.99}(1)
  assess_candidate(lr, basis(), &spec);
  EXPECT_TRUE(lr.non_null);
  CandidateResult flat = fitted(900, 900, 0.5, 1e-6);  // Wald would say 'present'
  flat.null_chi2_fit = 900 + 6.0;                      // 6 < chi2_{0.99}(1)
  assess_candidate(flat, basis(), &spec);
  EXPECT_FALSE(flat.non_null);
}

TEST(Ranking, TheLikelihoodRatioDecidesWhereItWasSimulatedAndALevelMustStillMoveByFivePercent) {
  // A carrier runout's Cartesian pair whose phase the amplitudes barely fix (indepsim4 setD4
  // rec_10): each coordinate within its standard error of 0, chi2 2e4 above the fit at 'absent'.
  const std::vector<ParameterSpec> pair{own_spec(0.0), own_spec(0.0)};
  CandidateResult runout = fitted(900, 900, -1.5e-6, 2.6e-6);
  runout.own_parameters = 2;
  FittedParameter y = runout.parameters[0];
  y.value = 7e-8;
  y.std_error = 3.5e-5;
  runout.parameters.insert(runout.parameters.begin() + 1, y);
  assess_candidate(runout, basis(), &pair);
  EXPECT_FALSE(runout.non_null) << "Wald: both within 2.807 standard errors";
  runout.null_chi2_fit = 900 + 2.1e4;
  assess_candidate(runout, basis(), &pair);
  EXPECT_TRUE(runout.non_null);
  runout.null_chi2_fit = 900 + 9.0;  // below chi2_{0.99}(2) = 9.21
  assess_candidate(runout, basis(), &pair);
  EXPECT_FALSE(runout.non_null);
  // A level 4.4 % off its documented value: no finding however large the ratio (session 22).
  const std::vector<ParameterSpec> level{own_spec(0.06)};
  CandidateResult friction = fitted(900, 900, 0.0574, 0.00013);
  friction.null_chi2_fit = 900 + 400.0;
  assess_candidate(friction, basis(), &level);
  EXPECT_FALSE(friction.non_null);
  friction.parameters[0].value = 0.0566;  // 5.7 %
  assess_candidate(friction, basis(), &level);
  EXPECT_TRUE(friction.non_null);
  EXPECT_NE(ranking_reason(runout, false, 0).find("likelihood-ratio threshold"), std::string::npos);
}

TEST(Ranking, ALeadRefittedInAnotherFormReplacesItOnlyIfItFitsBetterAndStillCountsWhereItCounted) {
  // indepsim3 setB5 rec_10 (session 68): a sun runout that counted, refitted with the housing on
  // the ring's translation, fitted the fit half better (5709 -> 3164) with the runout at the
  // bottom of its box -- the form took the excess, and the refit no longer counted.
  const std::vector<ParameterSpec> spec{own_spec()};
  const RankingBasis b{8000.0, 8000.0, 2, kAlpha, 5.0};
  CandidateResult lead = fitted(5709, 5900, 0.5, 0.01);
  assess_candidate(lead, b, &spec);
  ASSERT_TRUE(lead.counts());
  CandidateResult took_the_excess = fitted(3164, 3300, 1e-4, 0.01);  // within its error of 'absent'
  assess_candidate(took_the_excess, b, &spec);
  ASSERT_FALSE(took_the_excess.counts());
  EXPECT_FALSE(refit_replaces_lead(lead, took_the_excess));
  // The same refit still counting (its size off 'absent'): the better fit replaces the lead.
  CandidateResult still_counts = fitted(3164, 3300, 0.4, 0.01);
  assess_candidate(still_counts, b, &spec);
  ASSERT_TRUE(still_counts.counts());
  EXPECT_TRUE(refit_replaces_lead(lead, still_counts));
  // A refit that fits the fit half no better never replaces it, counting or not.
  CandidateResult worse = fitted(5710, 3300, 0.4, 0.01);
  assess_candidate(worse, b, &spec);
  EXPECT_FALSE(refit_replaces_lead(lead, worse));
  // A lead that did not count (only a lead) may take the form where the refit fits better,
  // whether or not the refit counts: nothing that counted is lost.
  CandidateResult weak = fitted(5709, 7999, 0.5, 0.01);  // the held-out half does not improve
  assess_candidate(weak, b, &spec);
  ASSERT_FALSE(weak.counts());
  EXPECT_TRUE(refit_replaces_lead(weak, took_the_excess));
  EXPECT_TRUE(refit_replaces_lead(weak, still_counts));
}

TEST(Ranking, AFailedOrUnknownCandidateNeverRejectsAbsent) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult failed = fitted(900, 900, 0.9, 0.001);
  failed.failed = "the model could not be simulated";
  assess_candidate(failed, basis(), &spec);
  EXPECT_FALSE(failed.non_null);
  CandidateResult unknown = fitted(900, 900, 0.9, 0.001);
  assess_candidate(unknown, basis(), nullptr);
  EXPECT_FALSE(unknown.non_null);
  EXPECT_FALSE(unknown.counts());
}

TEST(Ranking, InformationCriteriaCountTheNuisanceAndTheOwnParameters) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult r = fitted(900, 950);
  assess_candidate(r, basis(), &spec);
  EXPECT_DOUBLE_EQ(r.bic, 900 + 3 * 5.0);
  EXPECT_DOUBLE_EQ(r.bic_held_out, 950 + 3 * 5.0);
  EXPECT_DOUBLE_EQ(r.aic, 900 + 2 * 3.0);
}

TEST(Ranking, CountingCandidatesComeFirstThenTheLowerBicOfBothHalves) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult best_not_counting = fitted(100, 2000), a = fitted(900, 900), b = fitted(800, 980), c = fitted(900, 900);
  best_not_counting.name = "not_counting";
  a.name = "a";
  b.name = "b";
  c.name = "c";  // ties with a: keeps its place after a
  std::vector<CandidateResult> v{best_not_counting, a, c, b};
  for (CandidateResult& r : v) assess_candidate(r, basis(), &spec);
  rank_candidates(v);
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[0].name, "b");  // BIC 815 + 995 = 1810 < 1830
  EXPECT_EQ(v[1].name, "a");
  EXPECT_EQ(v[2].name, "c");
  EXPECT_EQ(v[3].name, "not_counting");
}

TEST(Ranking, EachReasonNamesTheRuleThatDecided) {
  const std::vector<ParameterSpec> spec{own_spec()};
  CandidateResult fit_only = fitted(990, 995), weak = fitted(999, 999), wald = fitted(900, 900, 0.001, 0.01),
                  loser = fitted(950, 950);
  for (CandidateResult* r : {&fit_only, &weak, &wald, &loser}) assess_candidate(*r, basis(), &spec);
  EXPECT_NE(ranking_reason(fit_only, false, 0).find("does not hold on the held-out half"), std::string::npos);
  EXPECT_NE(ranking_reason(weak, false, 0).find("below the threshold"), std::string::npos);
  EXPECT_NE(ranking_reason(wald, false, 0).find("Wald"), std::string::npos);
  EXPECT_NE(ranking_reason(loser, false, 1800).find("BIC (both halves) 130.0 higher"), std::string::npos);
  EXPECT_NE(ranking_reason(loser, true, 0).find("lowest BIC"), std::string::npos);
}

} // namespace
} // namespace pw::diagnose
