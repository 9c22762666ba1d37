// The nuisance fit's start (nuisance_start.hpp) and the saturating parameter's profile scale
// (phase_search.hpp lower_limit_scale) on closed-form chi2 functions: which grid point each picks,
// when the nominal model wins, when a rig element starts absent, and that threads do not matter.
#include "diagnose/fit.hpp"
#include "diagnose/nuisance_start.hpp"
#include "diagnose/phase_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pw::diagnose {
namespace {

ParameterSpec spec(double lower, double upper, double initial, double null_value) {
  ParameterSpec p;
  p.name = "p";
  p.lower = lower;
  p.upper = upper;
  p.log_scale = true;
  p.initial = initial;
  p.null_value = null_value;
  return p;
}

/// The stiffness level [0.5, 2], start 1 = 'absent'; chi2 with one basin at `minimum` (log scale).
std::vector<ParameterSpec> stiffness_only() { return {spec(0.5, 2.0, 1.0, 1.0)}; }
NuisanceChi2 basin_at(double minimum) {
  return [minimum](const std::vector<double>& x) { return 10.0 + 1000.0 * std::pow(std::log(x[0] / minimum), 2); };
}

TEST(GeometricGrid, RunsFromLoToHiWithAConstantRatio) {
  const std::vector<double> g = geometric_grid(0.5 * 1.4, 2.0 / 1.4, kNuisanceScanPoints);
  ASSERT_EQ(g.size(), 7u);
  EXPECT_DOUBLE_EQ(g.front(), 0.7);
  EXPECT_NEAR(g.back(), 2.0 / 1.4, 1e-15);
  for (std::size_t i = 1; i < g.size(); ++i) EXPECT_NEAR(g[i] / g[i - 1], std::pow(2.0 / 1.4 / 0.7, 1.0 / 6), 1e-14);
}

TEST(NuisanceStart, TheScanStartsAtTheGridPointNearestTheBasin) {
  const std::vector<double> grid = geometric_grid(0.5 * kNuisanceScanInset, 2.0 / kNuisanceScanInset, kNuisanceScanPoints);
  for (double minimum : {0.72, 0.95, 1.3}) {
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < grid.size(); ++i)
      if (std::fabs(std::log(grid[i] / minimum)) < std::fabs(std::log(grid[nearest] / minimum))) nearest = i;
    const std::vector<double> x0 = nuisance_start(stiffness_only(), 1e9, basin_at(minimum), 1);
    ASSERT_EQ(x0.size(), 1u);
    EXPECT_DOUBLE_EQ(x0[0], grid[nearest]) << "basin at " << minimum;
  }
}

TEST(NuisanceStart, TheNominalModelStartsEveryParameterAbsentWhenItFitsBetter) {
  std::vector<ParameterSpec> s = stiffness_only();
  s.push_back(spec(0.01, 0.3, 0.05, 0.02));  // a damping ratio: start 0.05, 'absent' 0.02
  const std::vector<double> x0 = nuisance_start(s, 5.0, basin_at(1.3), 1);  // every scan point >= 10
  ASSERT_EQ(x0.size(), 2u);
  EXPECT_EQ(x0[0], 1.0);
  EXPECT_EQ(x0[1], 0.02);
}

TEST(NuisanceStart, ARigElementStartsAbsentWhenTheRecordingIsBetterWithoutIt) {
  std::vector<ParameterSpec> s = stiffness_only();
  s.push_back(spec(1e3, 1e6, 2e4, 0.0));  // e.g. a shaft stiffness: present at 2e4, absent at 0
  const auto chi2 = [](const std::vector<double>& x) {
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + (x[1] == 0.0 ? 0.0 : 50.0);
  };
  const std::vector<double> absent = nuisance_start(s, 1e9, chi2, 1);
  EXPECT_EQ(absent[1], 0.0);
  const auto present_better = [](const std::vector<double>& x) {
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + (x[1] == 0.0 ? 50.0 : 0.0);
  };
  EXPECT_EQ(nuisance_start(s, 1e9, present_better, 1)[1], 2e4);
}

TEST(NuisanceStart, AScannedRigElementStartsAtTheGridPointNearestItsBasinAndOnlyWhenItIsBetter) {
  // A shaft stiffness over [1, 1e8] (absent at the bottom, screened at 1e4): chi2 has its basin at
  // 3e6, which neither 'absent' nor the screening value is near. Scanned (7 log-spaced points over
  // [1.4, 1e8 / 1.4]: ratio 10^(7.7 / 6), points 1.4, 27, ..., 3.7e6, 7.1e7), the start is the grid
  // point nearest the basin; unflagged, it stays at the better of absent and screened; and a scan
  // whose every point is worse than the start so far changes nothing.
  std::vector<ParameterSpec> s = stiffness_only();
  s.push_back(spec(1.0, 1e8, 1e4, 1.0));
  const auto shaft_basin = [](const std::vector<double>& x) {
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + 100.0 * std::pow(std::log(x[1] / 3e6), 2);
  };
  const std::vector<double> unflagged = nuisance_start(s, 1e9, shaft_basin, 1);
  EXPECT_EQ(unflagged[1], 1e4);
  s[1].scan_at_start = true;
  const std::vector<double> scanned = nuisance_start(s, 1e9, shaft_basin, 1);
  const std::vector<double> grid = geometric_grid(1.0 * kNuisanceScanInset, 1e8 / kNuisanceScanInset, kNuisanceScanPoints);
  double nearest = grid.front();
  for (double g : grid)
    if (std::fabs(std::log(g / 3e6)) < std::fabs(std::log(nearest / 3e6))) nearest = g;
  EXPECT_EQ(scanned[1], nearest);
  EXPECT_NEAR(scanned[0], unflagged[0], 0.0);  // the first parameter's scan is not redone
  const auto present_only_at_start = [](const std::vector<double>& x) {
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + (x[1] == 1e4 ? 0.0 : 50.0);
  };
  EXPECT_EQ(nuisance_start(s, 1e9, present_only_at_start, 1)[1], 1e4);
  EXPECT_EQ(nuisance_start(s, 1e9, shaft_basin, 1), nuisance_start(s, 1e9, shaft_basin, 2));
}

TEST(NuisanceStart, AScanWithAStepRatioFindsABasinNarrowerThanTheCoarseGridsSpacing) {
  // A shaft's stiffness over [1, 1e8] with a basin 1.2 wide (a factor ~1.1 either side) at 2e4,
  // between the coarse grid's points (steps of ~10 here): the coarse scan misses it, a scan
  // stepping by 1.21 cannot. The damping, following the stiffness as sqrt, moves with it.
  std::vector<ParameterSpec> s = stiffness_only();
  s.push_back(spec(1.0, 1e8, 1e3, 1.0));
  s.push_back(spec(1e-3, 1e3, 0.5, 1e-3));
  s[1].scan_at_start = true;
  const auto narrow = [](const std::vector<double>& x) {
    const double d = std::log(x[1] / 2e4) / std::log(1.1);
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) - 500.0 * std::exp(-0.5 * d * d) + 0.0 * x[2];
  };
  const std::vector<double> coarse = nuisance_start(s, 1e9, narrow, 1);
  EXPECT_GT(std::fabs(std::log(coarse[1] / 2e4)), std::log(1.5));  // not found
  s[1].scan_step_ratio = 1.21;
  EXPECT_GT(scan_points(s[1].lower * kNuisanceScanInset, s[1].upper / kNuisanceScanInset, 1.21), 80);
  const std::vector<double> fine = nuisance_start(s, 1e9, narrow, 1);
  EXPECT_LT(std::fabs(std::log(fine[1] / 2e4)), std::log(1.21) / 2 + 1e-12);  // within half a step
  EXPECT_EQ(fine[2], 0.5);  // no follower: the damping stays at its start
  s[2].scan_follows_previous_power = 0.5;
  const std::vector<double> followed = nuisance_start(s, 1e9, narrow, 1);
  EXPECT_EQ(followed[1], fine[1]);
  EXPECT_NEAR(followed[2], 0.5 * std::sqrt(followed[1] / 1e3), 1e-12 * followed[2]);
  EXPECT_EQ(nuisance_start(s, 1e9, narrow, 1), nuisance_start(s, 1e9, narrow, 2));
  // The coarse grid when no ratio is asked for, never fewer points than it.
  EXPECT_EQ(scan_points(1.0, 1e8, 0.0), kNuisanceScanPoints);
  EXPECT_EQ(scan_points(1.0, 1.1, 1.21), kNuisanceScanPoints);
}

TEST(NuisanceStart, ALinearParametersScanSpansItsWholeBoxAtItsStepAndFindsTheLobeOfItsMinimum) {
  // An engagement ramp r over [0, 0.5] (linear; 'absent' 0 is a value of the box), whose chi2 has
  // the sinc lobes of a high harmonic: chi2 = 10 + 1000 (sinc(n r) - sinc(n r0))^2 with n = 12,
  // r0 = 0.2 and a slow bowl, lobes 1/12 wide. A local start from the screen value 0.1 lies in
  // another lobe; the scan at step 0.025 has a point within 0.0125 of r0, so the start is there.
  std::vector<ParameterSpec> s = stiffness_only();
  ParameterSpec r;
  r.name = "ramp";
  r.lower = 0.0;
  r.upper = 0.5;
  r.initial = 0.1;
  r.null_value = 0.0;
  r.scan_at_start = true;
  r.scan_step = 0.025;
  s.push_back(r);
  const std::vector<double> g = scan_grid(s[1]);
  ASSERT_EQ(g.size(), 21u);
  EXPECT_EQ(g.front(), 0.0);
  EXPECT_EQ(g.back(), 0.5);
  for (std::size_t i = 1; i < g.size(); ++i) EXPECT_NEAR(g[i] - g[i - 1], 0.025, 1e-15);
  const auto sinc = [](double x) { return x == 0 ? 1.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x); };
  const auto lobes = [&](const std::vector<double>& x) {
    return 10.0 + 1000.0 * std::pow(std::log(x[0]), 2) + 1000.0 * std::pow(sinc(12 * x[1]) - sinc(12 * 0.2), 2) +
           10.0 * std::pow(x[1] - 0.2, 2);
  };
  const std::vector<double> start = nuisance_start(s, 1e9, lobes, 1);
  EXPECT_NEAR(start[1], 0.2, 0.0125);
  // Without a step: the coarse kNuisanceScanPoints points over the box, ends included.
  s[1].scan_step = 0;
  EXPECT_EQ(scan_grid(s[1]).size(), static_cast<std::size_t>(kNuisanceScanPoints));
  EXPECT_EQ(scan_grid(s[1]).front(), 0.0);
}

/// The stiffness level, an encoder-like bandwidth (not scanned: start 2000, 'absent' 1e4) and a
/// shaft stiffness scanned at start, which interact as an encoder's low-pass and a shaft's mode
/// do on the same speed lines.
std::vector<ParameterSpec> level_bandwidth_shaft() {
  std::vector<ParameterSpec> s = stiffness_only();
  s.push_back(spec(100.0, 1e4, 2000.0, 1e4));
  s.push_back(spec(1.0, 1e8, 1e3, 1.0));
  s[2].scan_at_start = true;
  s[2].scan_step_ratio = 1.21;
  return s;
}

TEST(NuisanceStart, FromAnEarlierFitTheShaftsScanFindsTheBasinTheNominalStartCannot) {
  // The bandwidth's basin at 300; the shaft's basin at 2e4 only when the bandwidth is near its
  // own, a ridge there when it is far. From the nominal start the shaft's scan runs with the
  // bandwidth at 2000 and finds nothing better; from an earlier fit without the shaft (level
  // 1.3, bandwidth 300, the shaft 'absent') it finds the basin.
  const std::vector<ParameterSpec> s = level_bandwidth_shaft();
  const auto chi2 = [](const std::vector<double>& x) {
    const double b = std::log(x[1] / 300.0), k = std::log(x[2] / 2e4) / std::log(1.1);
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + 200.0 * b * b -
           150.0 * std::exp(-0.5 * k * k) * (2 * std::exp(-b * b) - 1);
  };
  const std::vector<double> plain = nuisance_start(s, 1e9, chi2, 1);
  EXPECT_EQ(plain[1], 2000.0);
  EXPECT_GT(std::fabs(std::log(plain[2] / 2e4)), std::log(2.0));  // the shaft's basin not found
  const std::vector<double> earlier{1.3, 300.0, 1.0};
  const std::vector<double> nested = nuisance_start_from(s, earlier, chi2, 1);
  EXPECT_EQ(nested[0], 1.3);
  EXPECT_EQ(nested[1], 300.0);
  EXPECT_LT(std::fabs(std::log(nested[2] / 2e4)), std::log(1.21) / 2 + 1e-12);
  EXPECT_LT(chi2(nested), chi2(earlier));
  // A value outside its box is clamped into it; a point of another size gives no start.
  EXPECT_EQ(nuisance_start_from(s, {1.3, 50.0, 1.0}, chi2, 1)[1], 100.0);
  EXPECT_TRUE(nuisance_start_from(s, {1.3, 300.0}, chi2, 1).empty());
  EXPECT_EQ(nuisance_start_from(s, earlier, chi2, 1), nuisance_start_from(s, earlier, chi2, 2));
}

TEST(NuisanceStart, FromAnEarlierFitTheShaftCanStayInAPoorerBasinThanTheNominalStartFinds) {
  // The reverse: the earlier fit's bandwidth (300) leaves the shaft a shallow, misplaced basin
  // (at 2e3, depth 40), while from the nominal start (bandwidth 2000) the scan finds the deep one
  // (at 2e4, depth 5000). The earlier point is the lower one before the scans and the higher one
  // after them -- why the diagnosis fits from both starts and keeps the lower end.
  const std::vector<ParameterSpec> s = level_bandwidth_shaft();
  const auto chi2 = [](const std::vector<double>& x) {
    const double b = std::log(x[1] / 300.0), near = std::exp(-b * b), far = 1 - near;
    const double deep = std::log(x[2] / 2e4) / std::log(1.1), shallow = std::log(x[2] / 2e3) / std::log(1.1);
    return 10.0 + 1000.0 * std::pow(std::log(x[0] / 1.3), 2) + 200.0 * b * b -
           5000.0 * far * std::exp(-0.5 * deep * deep) - 40.0 * near * std::exp(-0.5 * shallow * shallow);
  };
  const std::vector<double> earlier{1.3, 300.0, 1.0};
  const std::vector<double> first{s[0].initial, s[1].initial, s[2].initial};  // the nominal start's point
  const std::vector<double> plain = nuisance_start(s, 1e9, chi2, 1);
  const std::vector<double> nested = nuisance_start_from(s, earlier, chi2, 1);
  EXPECT_LT(chi2(earlier), chi2(first));                            // lower before the scans
  EXPECT_LT(chi2(plain), chi2(nested));                             // higher after them
  EXPECT_LT(std::fabs(std::log(plain[2] / 2e4)), std::log(1.21) / 2 + 1e-12);
  EXPECT_LT(std::fabs(std::log(nested[2] / 2e3)), std::log(1.21) / 2 + 1e-12);
}

TEST(NuisanceStart, TwoThreadsGiveTheSameStartAsOne) {
  EXPECT_EQ(nuisance_start(stiffness_only(), 1e9, basin_at(0.9), 1), nuisance_start(stiffness_only(), 1e9, basin_at(0.9), 2));
}

TEST(NuisanceStart, NoNuisanceParametersNoStart) {
  EXPECT_TRUE(nuisance_start({}, 1.0, basin_at(1.0), 1).empty());
}

/// A saturating parameter's chi2 along x(s): flat (the fit's 100) above s_c, rising below as
/// 100 + A ln(s_c / s)^2; the limit fit + 6.6 is crossed at s* = s_c exp(-sqrt(6.6 / A)).
double saturating_chi2(double s, double s_c, double a) { return s >= s_c ? 100.0 : 100.0 + a * std::pow(std::log(s_c / s), 2); }

TEST(LowerLimitScale, BracketsTheCrossingWithinOneRefinedGridStep) {
  const double limit = 106.6, refined_step = std::pow(10.0, 6.0 / 12 / 5);  // 10^(1/10) = 1.259
  for (const auto& [s_c, a] : {std::pair{0.3, 50.0}, {0.01, 2.0}, {0.9, 1000.0}}) {
    const double crossing = s_c * std::exp(-std::sqrt(6.6 / a));
    const double s = lower_limit_scale([&](double x) { return saturating_chi2(x, s_c, a); }, limit, 1);
    EXPECT_GE(s, crossing * (1 - 1e-12)) << "s_c " << s_c;
    EXPECT_LT(s, crossing * refined_step * (1 + 1e-12)) << "s_c " << s_c;
  }
}

TEST(LowerLimitScale, EveryScaleWithinTheLimitGivesTheLowestGridPoint) {
  EXPECT_DOUBLE_EQ(lower_limit_scale([](double) { return 100.0; }, 106.6, 1), 1e-6);
}

TEST(LowerLimitScale, TheFitItselfOutsideTheLimitGivesOne) {
  EXPECT_EQ(lower_limit_scale([](double s) { return s >= 1.0 ? 200.0 : 100.0; }, 106.6, 1), 1.0);
}

TEST(LowerLimitScale, ABumpAboveTheLimitEndsTheTailEvenWithLowerValuesBelowIt) {
  // Within below 2e-4 and from 2e-2 on, over the limit in between: the limit is above the bump.
  const auto chi2 = [](double s) { return s > 2e-4 && s < 2e-2 ? 200.0 : 100.0; };
  const double s = lower_limit_scale(chi2, 106.6, 2);
  EXPECT_GE(s, 2e-2);
  EXPECT_LT(s, 2e-2 * std::pow(10.0, 0.1));
  EXPECT_EQ(s, lower_limit_scale(chi2, 106.6, 1)) << "threads must not change the result";
}

} // namespace
} // namespace pw::diagnose
