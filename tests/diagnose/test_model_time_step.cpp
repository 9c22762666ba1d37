// The model time step of a diagnosis (compare.cpp, diagnosis_steps_per_mode_period):
// 32 steps per period of the recording's Nyquist frequency, at least the 8 steps per
// period of the highest mode that model::prepare accepts, never finer than the
// configuration asks; an explicit solver.time_step_s is left alone.
#include "diagnose/compare.hpp"
#include "diagnose/stage_1200rpm.hpp"
#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pw::diagnose {
namespace {

using test::stage_1200rpm;
using test::synthetic;

double highest_mode_Hz(const model::SimulationConfig& c) { return model::prepare(c).natural_frequencies_Hz.maxCoeff(); }

TEST(ModelTimeStep, ResolvesTheRecordingsBandWithThirtyTwoStepsPerPeriodAndNoFiner) {
  const ModelComparison cmp(synthetic(0.0, 0.0, 1), stage_1200rpm());  // 10 kHz: Nyquist 5 kHz
  const int n = cmp.base().solver.steps_per_mode_period;
  const double f_max = highest_mode_Hz(cmp.base());
  const double f_nyquist = 5000.0;
  ASSERT_GT(f_max, f_nyquist);  // the seed's stiffest mode (about 11 kHz) lies above the band
  // The step 1 / (n f_max) gives >= 32 steps per Nyquist period ...
  EXPECT_LE(1.0 / (n * f_max), 1.0 / (32 * f_nyquist) * (1 + 1e-12));
  // ... and is the coarsest that does (or the floor of 8 steps per highest period).
  EXPECT_TRUE(n == 8 || 1.0 / ((n - 1) * f_max) > 1.0 / (32 * f_nyquist)) << n;
  EXPECT_GE(n, 8);
  EXPECT_LT(n, model::SimulationConfig{}.solver.steps_per_mode_period);  // coarser than simulate's default here
}

TEST(ModelTimeStep, NeverFinerThanConfiguredAndAnExplicitStepIsKept) {
  model::SimulationConfig coarse = stage_1200rpm();
  coarse.solver.steps_per_mode_period = 9;
  EXPECT_EQ(ModelComparison(synthetic(0.0, 0.0, 1), coarse).base().solver.steps_per_mode_period, 9);
  model::SimulationConfig fixed = stage_1200rpm();
  fixed.solver.time_step_s = 2e-6;
  const ModelComparison cmp(synthetic(0.0, 0.0, 1), fixed);
  EXPECT_EQ(cmp.base().solver.time_step_s, 2e-6);
  EXPECT_EQ(cmp.base().solver.steps_per_mode_period, fixed.solver.steps_per_mode_period);
}

} // namespace
} // namespace pw::diagnose
