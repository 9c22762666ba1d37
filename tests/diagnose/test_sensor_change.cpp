// A housing sensor whose path changed since the baseline (sensor_change.hpp): the recording is
// the baseline's kind of synthetic recording with its housing channel scaled by a known factor.
// No simulation is run: the "model" is the order spectrum of a noise-free synthetic recording
// (test_baseline.cpp's construction), the mesh-acceleration channel read as a housing sensor.
#include "diagnose/sensor_change.hpp"

#include "diagnose/baseline.hpp"
#include "diagnose/calibration.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/stage_1200rpm.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pw::diagnose {
namespace {

constexpr double kAlpha = 0.01;  // the diagnosis's default false-alarm level

Recording housing_recording(unsigned seed, double gain, double noise_m_s2 = 0.5) {
  Recording r = test::synthetic(0.0, 0.0, seed, 0.0, noise_m_s2, 0.01);
  r.channels[1].quantity = Quantity::HousingAcceleration;
  for (double& x : r.channels[1].values) x *= gain;
  return r;
}

std::vector<std::vector<double>> perfect_model() {
  const Recording clean = housing_recording(1, 1.0, 1e-6);
  const ModelComparison c(clean, test::stage_1200rpm());
  return c.spectra().amplitude[0];
}

/// rho fitted for a recording whose housing channel reads `gain` times the baseline's.
SensorScale fitted(double gain) {
  const auto model = perfect_model();
  const Recording baseline = housing_recording(12, 1.0);
  ModelComparison base(baseline, test::stage_1200rpm());
  base.set_reference(model, {1.0, 1.0});
  CompareOptions co;
  for (const CalibrationCell& c : calibration_cells(base, model, {1.0, 1.0})) co.baseline.push_back(baseline_cell(c));
  const Recording rec = housing_recording(11, gain);
  ModelComparison cmp(rec, test::stage_1200rpm(), co);
  cmp.set_reference(model, {1.0, 1.0});
  return fit_sensor_scale(cmp, model, {1.0, 1.0}, 1, kAlpha);
}

TEST(SensorScale, AChannelReadingTheBaselineScaledIsFittedToThatScale) {
  const SensorScale s = fitted(0.6);
  EXPECT_NEAR(s.rho, 0.6, 0.03);  // 5 %: the lines stand far above the noise
  EXPECT_FALSE(s.at_bracket_edge);
  EXPECT_GT(std::fabs(std::log(s.rho)), 10 * s.ln_rho_std);
  EXPECT_LT(s.chi2_held, s.chi2_held_1);
  EXPECT_LE(s.chi2_held, s.bound_held);
}

TEST(SensorScale, AnUnchangedChannelReadsOneWithinItsError) {
  const SensorScale s = fitted(1.0);
  EXPECT_LT(std::fabs(std::log(s.rho)), 3 * s.ln_rho_std + 0.01);
  EXPECT_FALSE(s.at_bracket_edge);
}

TEST(SensorScale, AChannelBeyondTheRangeIsAtTheBracketEdgeNotASize) {
  // x20: beyond kMaxSensorScale; the fit stops at the edge and says so, so that the diagnosis
  // does not state 12 as the change (diagnose.cpp check_sensor_gain_change).
  const SensorScale s = fitted(20.0);
  EXPECT_TRUE(s.at_bracket_edge);
  EXPECT_NEAR(s.rho, kMaxSensorScale, 1e-3 * kMaxSensorScale);
  const SensorScale low = fitted(1.0 / 20);
  EXPECT_TRUE(low.at_bracket_edge);
  EXPECT_NEAR(low.rho, kMinSensorScale, 1e-3 * kMinSensorScale);
}

} // namespace
} // namespace pw::diagnose
