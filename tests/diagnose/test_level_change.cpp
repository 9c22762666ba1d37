// A level changed since the baseline (level_change.hpp) when the baseline's own value of that level
// is an edge of its box: the ratio is then a bound on the change, and the text says which way.
#include "diagnose/level_change.hpp"

#include "core/statistics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace pw::diagnose {
namespace {

TEST(OneSidedRatio, ABaselineLevelInsideItsBoxGivesNoNote) {
  EXPECT_TRUE(one_sided_ratio_note("stiffness.scale", 1.2, 0.8, 0).empty());
}

TEST(OneSidedRatio, AnUpperEdgeMakesTheRatioAnUpperBoundAndALowerEdgeALowerBound) {
  // fresh4p rec_13 (session 56): stiffness.scale 1.742 against a baseline at its upper bound 2.
  const std::string up = one_sided_ratio_note("stiffness.scale", 2.0, 0.871, +1);
  EXPECT_NE(up.find("stiffness.scale = 2 is the upper edge"), std::string::npos) << up;
  EXPECT_NE(up.find("smaller than x0.871"), std::string::npos) << up;
  EXPECT_NE(up.find("a bound on the change, not its size"), std::string::npos) << up;
  const std::string down = one_sided_ratio_note("contact.mesh_damping_ratio", 0.002, 2.5, -1);
  EXPECT_NE(down.find("lower edge"), std::string::npos) << down;
  EXPECT_NE(down.find("larger than x2.5"), std::string::npos) << down;
}

TEST(LevelMoveTest, WithoutACalibrationsScatterIsTheNormalTestOfTheNoiseError) {
  for (const int n : {0, 1, 5}) {
    const LevelMoveTest t = level_move_test(0.013, n >= 2 ? 0.0 : 0.3, n, 0.01);
    EXPECT_DOUBLE_EQ(t.ln_std, 0.013);
    EXPECT_DOUBLE_EQ(t.quantile, normal_quantile(0.005));
    EXPECT_DOUBLE_EQ(t.threshold_ln, normal_quantile(0.005) * 0.013);
    EXPECT_TRUE(std::isinf(t.dof));
  }
}

TEST(LevelMoveTest, TwoHealthyRecordingsRatioCarriesTwiceTheScattersVarianceWithItsDegreesOfFreedom) {
  // Scatter alone (no noise): ln rho ~ s sqrt(2) t(n - 1); nu is then exactly n - 1.
  const LevelMoveTest t = level_move_test(0.0, 0.05, 4, 0.01);
  EXPECT_DOUBLE_EQ(t.scatter_ln, 0.05 * std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(t.dof, 3.0);
  EXPECT_NEAR(t.quantile, 5.841, 5e-4);  // t_{0.995}(3), NIST table
  EXPECT_NEAR(t.threshold_ln, 5.841 * 0.05 * std::sqrt(2.0), 1e-4);
  // Equal parts (a = b): nu = (2b)^2 / (b^2 / (n - 1)) = 4 (n - 1).
  const double s = 0.02, sd = s * std::sqrt(2.0);
  const LevelMoveTest e = level_move_test(sd, s, 3, 0.01);
  EXPECT_NEAR(e.dof, 8.0, 1e-12);
  EXPECT_NEAR(e.ln_std, 2 * s, 1e-15);
  EXPECT_DOUBLE_EQ(e.quantile, student_t_quantile(8.0, 0.005));
}

TEST(LevelMoveTest, ALevelFourNoiseErrorsFromItsBaselineIsNoChangeOnARigThatScattersItMore) {
  // The ratio of indepsim3 setB5 rec_18, a healthy control (session 62): x1.051 +- 0.013 (noise),
  // a change by the noise-only test (|ln rho| = 0.050 > 2.576 x 0.013 = 0.033). Against a rig
  // whose healthy recordings scatter that level by 5 % (ln sd, three recordings) the threshold is
  // t_{0.995}(nu ~ 2.1) x 0.072 ~ 0.6.
  const double ln_rho = std::log(1.051);
  EXPECT_GT(ln_rho, level_move_test(0.013, 0.0, 0, 0.01).threshold_ln);
  EXPECT_LT(ln_rho, level_move_test(0.013, 0.05, 3, 0.01).threshold_ln);
}

TEST(LevelMoveTest, AStiffnessLevelAtTheReferencesOperatingPointIsJudgedWithoutTheSpreadBetweenOperatingPoints) {
  // indepsim4 setD4 rec_12 (every mesh stiffness x0.75, 1200 rpm; session 68's run): x0.7706 +-
  // 0.00058 of the calibration's healthy 1200 rpm recording. The calibration's two recordings (600
  // and 1200 rpm) put stiffness.scale 0.537 and 0.918 apart, s = 0.379 in ln: with one degree of
  // freedom the threshold is t_{0.995}(1) x sqrt(2) x 0.379 = 34 in ln, no change could pass it.
  const double ln_rho = std::log(0.7706), ln_std = 0.00058 / 0.7706, spread = 0.379;
  const LevelMoveTest across = level_move_test(ln_std, spread, 2, 0.01);
  EXPECT_GT(across.threshold_ln, 30.0);
  EXPECT_LT(std::fabs(ln_rho), across.threshold_ln);
  // The stiffness of steel teeth at one operating point carries none of that spread: the noise
  // error alone (kRecalibration, 5 %, is required beside it).
  const LevelMoveTest stiff = level_move_test(ln_std, healthy_level_scatter_ln("stiffness_level", spread), 2, 0.01);
  EXPECT_EQ(stiff.scatter_ln, 0.0);
  EXPECT_DOUBLE_EQ(stiff.threshold_ln, normal_quantile(0.005) * ln_std);
  EXPECT_GT(std::fabs(ln_rho), stiff.threshold_ln);
  // The damping keeps it: a lubricant's viscosity has no such bound between two runs.
  EXPECT_DOUBLE_EQ(healthy_level_scatter_ln("damping_level", spread), spread);
  const LevelMoveTest damp = level_move_test(ln_std, healthy_level_scatter_ln("damping_level", spread), 2, 0.01);
  EXPECT_DOUBLE_EQ(damp.threshold_ln, across.threshold_ln);
}

} // namespace
} // namespace pw::diagnose
