// The diagnosis's progress forecast (src/diagnose/forecast.hpp): counts and arithmetic.
#include "diagnose/forecast.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

namespace pw::diagnose {
namespace {

TEST(Forecast, LevenbergMarquardtCountIsStartPlusJacobianAndOneTrialPerIteration) {
  // fit.cpp: one residual at the start, then p Jacobian columns and one accepted trial per iteration.
  EXPECT_EQ(lm_simulations(3, 4), 1 + 4 * (3 + 1));
  EXPECT_EQ(lm_simulations(0, 5), 1 + 5);
  EXPECT_EQ(lm_simulations(2, 0), 1);
}

TEST(Forecast, RemainingSumsTheCurrentAndLaterStepsLessWhatTheCurrentOneRan) {
  SimulationForecast f;
  f.expect(2, 4);
  f.expect(3, 30);
  f.expect(8, 100);
  f.begin(3);
  EXPECT_EQ(f.remaining(0), 130);   // step 2 is done: it no longer counts
  EXPECT_EQ(f.remaining(10), 120);
  EXPECT_EQ(f.remaining(45), 100);  // step 3 ran more than forecast: none of it is left, never negative
}

TEST(Forecast, StepsNeverGoBackwards) {
  SimulationForecast f;
  f.expect(5, 7);
  f.begin(6);
  f.begin(5);  // a later call for an earlier step keeps the later one
  EXPECT_EQ(f.remaining(0), 0);
}

TEST(Forecast, PercentAndEtaFollowFromTheMeasuredRate) {
  SimulationForecast f;
  f.expect(8, 60);
  f.begin(8);
  // 40 done in 200 s (5 s each), 20 of them in step 8: 40 of step 8's 60 are left.
  const SimulationForecast::Estimate e = f.estimate(40, 20, 200.0);
  ASSERT_TRUE(e.known);
  EXPECT_DOUBLE_EQ(e.percent, 50.0);
  EXPECT_DOUBLE_EQ(e.seconds_left, 200.0);
  EXPECT_EQ(to_string(e), "50 %, ETA 3 min 20 s");
}

TEST(Forecast, NothingIsClaimedBeforeASimulationHasBeenTimed) {
  SimulationForecast f;
  f.expect(3, 10);
  EXPECT_FALSE(f.estimate(0, 0, 5.0).known);
  EXPECT_FALSE(f.estimate(3, 3, 0.0).known);
  EXPECT_EQ(to_string(f.estimate(0, 0, 5.0)), "");
}

TEST(Forecast, AStepOutsideOneToThirteenIsRefusedWithItsName) {
  SimulationForecast f;
  EXPECT_THROW(f.expect(0, 1), InputError);
  EXPECT_THROW(f.begin(SimulationForecast::kSteps + 1), InputError);
}

TEST(Forecast, EtaTextUsesHoursForLongRuns) {
  SimulationForecast::Estimate e{true, 12.7, 2.0 * 3600 + 5 * 60 + 9};
  EXPECT_EQ(to_string(e), "12 %, ETA 2 h 05 min");
  e.seconds_left = 42;
  EXPECT_EQ(to_string(e), "12 %, ETA 42 s");
}

} // namespace
} // namespace pw::diagnose
