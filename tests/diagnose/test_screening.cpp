// The screening's choice of what to fit (screening.hpp best_per_candidate, shortlist) on
// hand-built screens: one variant per candidate, the largest predicted improvement first, the
// sensor-only and visible saturating ones always, the rest with S > 0 up to the cap.
#include "diagnose/screening.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pw::diagnose {
namespace {

Screen screen(const char* candidate, double S, bool visible = false) {
  Screen s;
  s.c = find_candidate(candidate);
  s.S = S;
  s.visible = visible;
  return s;
}

TEST(Screening, EachCandidateIsRepresentedByItsBestVariantLargestSFirst) {
  const std::vector<Screen> screens{screen("sun_tooth_damage", 40), screen("friction", 10), screen("sun_tooth_damage", 90),
                                    screen("pin_error", 90), screen("friction", 12)};
  ASSERT_NE(screens[0].c, nullptr);
  const std::vector<std::size_t> best = best_per_candidate(screens);
  // sun_tooth_damage best is index 2 (90), pin_error 3 (90, after it: stable), friction 4 (12).
  EXPECT_EQ(best, (std::vector<std::size_t>{2, 3, 4}));
}

TEST(Screening, TheShortlistCapsTheCandidatesWithAPositivePredictedImprovement) {
  const std::vector<Screen> screens{screen("sun_tooth_damage", 90), screen("pin_error", 50), screen("friction", 20),
                                    screen("torque_ripple", 0)};
  const std::vector<std::size_t> best = best_per_candidate(screens);
  EXPECT_EQ(shortlist(screens, best, 2), (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(shortlist(screens, best, 10), (std::vector<std::size_t>{0, 1, 2})) << "S = 0 is never fitted";
}

TEST(Screening, SensorOnlyAndVisibleSaturatingCandidatesAreAlwaysFittedBeyondTheCap) {
  const std::vector<Screen> screens{screen("sun_tooth_damage", 90), screen("sensor_transfer_path", 0),
                                    screen("backlash", 0, true), screen("friction", 20)};
  ASSERT_NE(screens[1].c, nullptr);
  ASSERT_TRUE(screens[1].c->sensor_only());
  const std::vector<std::size_t> best = best_per_candidate(screens);
  const std::vector<std::size_t> fitted = shortlist(screens, best, 1);
  EXPECT_EQ(fitted.size(), 3u);
  EXPECT_NE(std::find(fitted.begin(), fitted.end(), 0u), fitted.end());
  EXPECT_NE(std::find(fitted.begin(), fitted.end(), 1u), fitted.end());
  EXPECT_NE(std::find(fitted.begin(), fitted.end(), 2u), fitted.end());
  EXPECT_EQ(std::find(fitted.begin(), fitted.end(), 3u), fitted.end()) << "friction is beyond the cap of 1";
}

TEST(Screening, UnfittedCandidatesWithinTheMarginOfTheLeadsPredictedImprovementAreItsRivals) {
  // seed3p rec_41 (docs/diagnose-log.md, session 27): the cap of 4 kept carrier runout, pin
  // error, torque ripple and ring tooth (18.5); sun tooth (17.2) and planet tooth (17.0, the
  // truth) were not fitted. With margin chi2_{0.99}(1) = 6.63 both are rivals of a ring-tooth
  // lead; friction at 5 is not (18.5 - 6.63 = 11.9), and neither is S = 0.
  const std::vector<Screen> screens{screen("carrier_runout", 60),   screen("pin_error", 40),
                                    screen("torque_ripple", 25),    screen("ring_tooth_damage", 18.5),
                                    screen("sun_tooth_damage", 17.2), screen("planet_tooth_damage", 17.0),
                                    screen("friction", 5),          screen("backlash", 0)};
  for (const Screen& s : screens) ASSERT_NE(s.c, nullptr);
  const std::vector<std::size_t> best = best_per_candidate(screens);
  const std::vector<std::size_t> fitted = shortlist(screens, best, 4);
  ASSERT_EQ(fitted, (std::vector<std::size_t>{0, 1, 2, 3}));
  const double margin = 6.63;
  EXPECT_EQ(screened_rivals(screens, best, fitted, 18.5, margin), (std::vector<std::size_t>{4, 5}));
  // A lead far ahead of every unfitted candidate has none.
  EXPECT_TRUE(screened_rivals(screens, best, fitted, 60, margin).empty());
  // A lead that is not the top of the screening reaches down from its own S, not from the top's.
  EXPECT_EQ(screened_rivals(screens, best, fitted, 11, margin), (std::vector<std::size_t>{4, 5, 6}));
}

TEST(Screening, AFailedScreenIsNeverARival) {
  std::vector<Screen> screens{screen("ring_tooth_damage", 18.5), screen("planet_tooth_damage", 18.0)};
  screens[1].failed = true;
  const std::vector<std::size_t> best = best_per_candidate(screens);
  EXPECT_TRUE(screened_rivals(screens, best, shortlist(screens, best, 1), 18.5, 6.63).empty());
}

} // namespace

// backtrack_start: an overshooting linearized step is shortened towards 'absent' until it fits
// better than 'absent' (damped Gauss-Newton's backtracking line search, screening.hpp).
ParameterSpec linear_spec(double null_value) {
  ParameterSpec p;
  p.lower = -100, p.upper = 100, p.null_value = null_value;
  return p;
}

TEST(Screening, AStartThatFitsBetterThanAbsentIsKeptWithOneEvaluation) {
  // chi2(x) = (x - 1)^2 + 10: absent (x = 0) scores 11, the start x = 1.5 scores 10.25.
  const auto chi2 = [](const std::vector<double>& x) { return (x[0] - 1) * (x[0] - 1) + 10; };
  const BacktrackedStart b = backtrack_start({linear_spec(0)}, {1.5}, {0}, 11, 6, chi2);
  EXPECT_EQ(b.x, std::vector<double>{1.5});
  EXPECT_EQ(b.fraction, 1);
  EXPECT_EQ(b.evaluations, 1);
}

TEST(Screening, AnOvershootingStartIsHalvedTowardsAbsentUntilItFitsBetterThanAbsent) {
  // The step to x = 6 overshoots the minimum at 1 (chi2 35 >= absent's 11); halving gives 3
  // (chi2 14, still worse), then 1.5 (10.25 < 11): the first point better than absent is taken.
  const auto chi2 = [](const std::vector<double>& x) { return (x[0] - 1) * (x[0] - 1) + 10; };
  const BacktrackedStart b = backtrack_start({linear_spec(0)}, {6}, {0}, 11, 6, chi2);
  EXPECT_DOUBLE_EQ(b.x[0], 1.5);
  EXPECT_DOUBLE_EQ(b.fraction, 0.25);
  EXPECT_DOUBLE_EQ(b.chi2, 10.25);
  EXPECT_DOUBLE_EQ(b.start_chi2, 35);
  EXPECT_EQ(b.evaluations, 3);
}

TEST(Screening, BacktrackingMovesEveryParameterAlongTheStepAndLogScaleOnesGeometrically) {
  // Two parameters, the second fitted on a log scale from 'absent' 1e-8: halving the step
  // from (8, 1e-4) gives (4, 1e-6), the geometric mean of 1e-8 and 1e-4.
  ParameterSpec logp;
  logp.lower = 1e-8, logp.upper = 1e-3, logp.log_scale = true, logp.null_value = 1e-8;
  std::vector<std::vector<double>> tried;
  const auto chi2 = [&](const std::vector<double>& x) {
    tried.push_back(x);
    return x[0] > 5 ? 100.0 : 1.0;  // only the first halving fits better than absent (chi2 50)
  };
  const BacktrackedStart b = backtrack_start({linear_spec(0), logp}, {8, 1e-4}, {0, 1e-8}, 50, 6, chi2);
  ASSERT_EQ(tried.size(), 2u);
  EXPECT_DOUBLE_EQ(b.x[0], 4);
  EXPECT_NEAR(b.x[1], 1e-6, 1e-18);
  EXPECT_DOUBLE_EQ(b.fraction, 0.5);
}

TEST(Screening, WhereNoHalvingFitsBetterThanAbsentTheBestPointTriedIsTheStart) {
  // chi2 falls towards absent but never below it: every halving is tried, the last is best.
  const auto chi2 = [](const std::vector<double>& x) { return 20 + x[0]; };
  const BacktrackedStart b = backtrack_start({linear_spec(0)}, {64}, {0}, 20, 6, chi2);
  EXPECT_EQ(b.evaluations, 7);
  EXPECT_DOUBLE_EQ(b.x[0], 1);  // 64 / 2^6
  EXPECT_DOUBLE_EQ(b.fraction, 1.0 / 64);
  // A start whose step leads only to worse points is kept.
  const auto worse = [](const std::vector<double>& x) { return x[0] < 64 ? 1e9 : 30.0; };
  const BacktrackedStart k = backtrack_start({linear_spec(0)}, {64}, {0}, 20, 6, worse);
  EXPECT_EQ(k.x, std::vector<double>{64});
  EXPECT_EQ(k.fraction, 1);
}

TEST(Screening, TheTransferGridCrossesEveryTransferParameterWithTheSizeAtItsScreeningValue) {
  // A size (screening value 0.02) and two transfer inertias on log boxes of 8 decades: the grid
  // is their 6 x 6 combinations, each at the centres of equal cells of ln J (grid_values), the
  // first varying slowest, the size at 0.02 whatever its start; a spec without transfer
  // parameters gives the start with its size at the screening value alone.
  ParameterSpec size = linear_spec(0);
  size.screen_value = 0.02;
  ParameterSpec j_out, j_in;
  j_out.lower = 1e-6, j_out.upper = 1e2, j_out.log_scale = true, j_out.transfer = true;
  j_in.lower = 1e-7, j_in.upper = 10, j_in.log_scale = true, j_in.transfer = true;
  const std::vector<ParameterSpec> spec{size, j_out, j_in};
  const auto grid = transfer_grid(spec, {0.005, 3e-3, 10});
  const int n = Screening::kGridPoints;
  ASSERT_EQ(grid.size(), static_cast<std::size_t>(n * n));
  const std::vector<double> out = Screening::grid_values(j_out), in = Screening::grid_values(j_in);
  EXPECT_NEAR(out.front(), 1e-6 * std::pow(1e8, 0.5 / n), 1e-18);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const std::vector<double>& x = grid[static_cast<std::size_t>(a * n + b)];
      ASSERT_EQ(x.size(), 3u);
      EXPECT_DOUBLE_EQ(x[0], 0.02);
      EXPECT_DOUBLE_EQ(x[1], out[static_cast<std::size_t>(a)]);
      EXPECT_DOUBLE_EQ(x[2], in[static_cast<std::size_t>(b)]);
    }
  const auto plain = transfer_grid({size}, {0.005});
  ASSERT_EQ(plain.size(), 1u);
  EXPECT_DOUBLE_EQ(plain[0][0], 0.02);
}

} // namespace pw::diagnose

namespace pw::diagnose {

TEST(Screening, ANuisanceParameterAtZeroTakesItsSecantStepFromItsBoxsSpan) {
  // setD4's calibration put contact.engagement_ramp at its lower bound 0: a step of 2 % of the
  // value was 0, the secant 0/0, and the NaN scored every candidate S = 0 (session 75).
  const ParameterSpec ramp{.name = "contact.engagement_ramp", .unit = "1", .lower = 0.0, .upper = 0.25};
  EXPECT_DOUBLE_EQ(nuisance_secant_step(0.0, ramp), 0.02 * 0.25);
  // Elsewhere 2 % of the value, as before, bit for bit; downwards where upwards leaves the box.
  const ParameterSpec scale{.name = "stiffness.scale", .unit = "1", .lower = 0.5, .upper = 2.0};
  EXPECT_EQ(nuisance_secant_step(1.0225, scale), 0.02 * 1.0225);
  EXPECT_EQ(nuisance_secant_step(2.0, scale), -0.02 * 2.0);
  // At 0 with the upper end at 0 the step goes down into the box.
  const ParameterSpec below{.name = "x", .unit = "1", .lower = -1.0, .upper = 0.0};
  EXPECT_DOUBLE_EQ(nuisance_secant_step(0.0, below), -0.02);
  // No finite scale: no step (the direction is left out rather than made NaN).
  const ParameterSpec open{.name = "y", .unit = "1", .lower = 0.0, .upper = std::numeric_limits<double>::infinity()};
  EXPECT_EQ(nuisance_secant_step(0.0, open), 0.0);
  EXPECT_TRUE(std::isfinite(nuisance_secant_step(3.0, open)));
}

} // namespace pw::diagnose
