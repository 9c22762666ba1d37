// Calibration's discrepancy estimate (diagnose/calibration.hpp) on cells drawn from its own
// model with known sigma_rel and sigma_abs: the estimates recover them within their standard
// errors, the budget is the upper confidence limit, a model without discrepancy gets a budget
// of about zero, and the calibrated model is the median of the fits.
#include "core/error.hpp"
#include "core/statistics.hpp"
#include "diagnose/calibration.hpp"
#include "diagnose/fitted_parameter.hpp"
#include "diagnose/order_analysis.hpp"
#include "model/simulation.hpp"
#include "model/validate.hpp"

#include <gtest/gtest.h>

#include <map>

#include <cmath>
#include <random>

using namespace pw::diagnose;

namespace {

/// Cells of one channel kind: n_line cells with model lines a in [1, 5] and n_low cells the
/// model predicts at 0; noise variance s2 per bin (complex, both halves independent), the
/// discrepancy (relative on the lines, absolute on every cell) the same in both halves.
std::vector<CalibrationCell> draw_cells(double sigma_rel, double sigma_abs, int n_line, int n_low, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::uniform_real_distribution<double> ud(1.0, 5.0);
  const double s2 = 0.01;
  std::vector<CalibrationCell> cells;
  for (int i = 0; i < n_line + n_low; ++i) {
    CalibrationCell c;
    c.quantity = Quantity::SunSpeed;
    c.families = {Component::Mesh};
    c.noise_variance = s2;
    c.model = i < n_line ? ud(rng) : 0.0;
    const double delta = sigma_rel * nd(rng), b = sigma_abs * nd(rng);
    for (int w = 0; w < 2; ++w) {
      const double s = std::sqrt(0.5 * s2);
      c.recording[w] = std::hypot(c.model * (1 + delta) + s * nd(rng), s * nd(rng)) + b;
      c.variance[w] = rice_variance(c.model, s2);
    }
    cells.push_back(c);
  }
  return cells;
}

} // namespace

TEST(Calibration, RigElementsAreKeptOnlyForAnImprovementBeyondWhatTheirParametersBuyByChance) {
  // m = 2000 held-out features, p = 2 extra parameters, alpha = 0.01: F_{0.99}(2, 2000) = 4.61.
  const double f = pw::f_quantile(2, 2000, 0.01);
  // A right model (chi2 per feature 1): the likelihood-ratio test's threshold, 2 F = 9.2.
  EXPECT_TRUE(rig_elements_improve({.chi2_without = 2000 + 2 * f * 1.01 + 1e-9, .chi2_with = 2000, .features = 2000,
                                    .extra_parameters = 2}, 0.01));
  EXPECT_FALSE(rig_elements_improve({.chi2_without = 2000 + 2 * f * 0.99, .chi2_with = 2000, .features = 2000,
                                     .extra_parameters = 2}, 0.01));
  // Another simulator's rig: 1000 times the noise per feature. An improvement of 100, which a right
  // model would call decisive, is what two parameters buy there by chance; 10 % of chi2 is not.
  EXPECT_FALSE(rig_elements_improve({.chi2_without = 2e6 + 100, .chi2_with = 2e6, .features = 2000,
                                     .extra_parameters = 2}, 0.01));
  EXPECT_TRUE(rig_elements_improve({.chi2_without = 2.2e6, .chi2_with = 2e6, .features = 2000,
                                    .extra_parameters = 2}, 0.01));
  // Worse, equal, or nothing added: never kept.
  EXPECT_FALSE(rig_elements_improve({.chi2_without = 2e6, .chi2_with = 2.1e6, .features = 2000, .extra_parameters = 2}, 0.01));
  EXPECT_FALSE(rig_elements_improve({.chi2_without = 2e6, .chi2_with = 2e6, .features = 2000, .extra_parameters = 2}, 0.01));
  EXPECT_FALSE(rig_elements_improve({.chi2_without = 3e6, .chi2_with = 2e6, .features = 2000, .extra_parameters = 0}, 0.01));
}

TEST(Calibration, TheSharedRigStructureMaximizesTheJointProfileLikelihoodWithOneResidualVariancePerRecording) {
  // Recording 0 (2000 features) loses 1 % with recording 1's structure; recording 1 (1000
  // features) loses 10 % with recording 0's. loss(0) = 500 ln 1.1 = 47.7, loss(1) = 1000 ln 1.01 =
  // 9.95 nats: recording 1's structure is shared, though its raw chi2 cost (1e4) is larger than
  // recording 0's would be (2e3) -- the raw sum would let the worse-fitted recording decide.
  const std::vector<std::vector<double>> chi2{{1e6, 1.01e6}, {2.2e4, 2e4}};
  SharedStructure s = choose_shared_structure(chi2, {2000, 1000}, 2, 0.01);
  EXPECT_EQ(s.from, 1u);
  ASSERT_EQ(s.loss.size(), 2u);
  EXPECT_NEAR(s.loss[0], 500 * std::log(1.1), 1e-9);
  EXPECT_NEAR(s.loss[1], 1000 * std::log(1.01), 1e-9);
  // Scale-free per recording: recording 0's chi2 row times 1000 chooses the same.
  EXPECT_EQ(choose_shared_structure({{1e9, 1.01e9}, {2.2e4, 2e4}}, {2000, 1000}, 2, 0.01).from, 1u);
  // The F test per recording: recording 0's 1 % (Δχ² 1e4 for p = 2 against 2 F χ²/m = 2 * 4.6 * 500)
  // is beyond chance, recording 1's own fit is the shared one.
  ASSERT_EQ(s.rejects_shared.size(), 2u);
  EXPECT_TRUE(s.rejects_shared[0]);
  EXPECT_FALSE(s.rejects_shared[1]);
  // A recording whose refit failed (no chi2) rules that structure out.
  EXPECT_EQ(choose_shared_structure({{1e6, std::nan("")}, {2.2e4, 2e4}}, {2000, 1000}, 2, 0.01).from, 0u);
  // One recording: its own structure, no loss.
  s = choose_shared_structure({{5.0}}, {10}, 1, 0.01);
  EXPECT_EQ(s.from, 0u);
  EXPECT_EQ(s.loss[0], 0.0);
  // A further candidate (the pooled structure) is a column beyond the recordings' own.
  s = choose_shared_structure({{1e6, 1.01e6, 1.0001e6}, {2.2e4, 2e4, 2.0001e4}}, {2000, 1000}, 2, 0.01);
  EXPECT_EQ(s.from, 2u);
  ASSERT_EQ(s.loss.size(), 3u);
  EXPECT_FALSE(s.rejects_shared[0]);
  EXPECT_FALSE(s.rejects_shared[1]);
  EXPECT_THROW(choose_shared_structure({{1, 2}, {3}}, {1, 1}, 1, 0.01), pw::InputError);
  EXPECT_THROW(choose_shared_structure({{1}, {3}}, {1, 1}, 1, 0.01), pw::InputError);
}

namespace {
/// A recording's fitted nuisance value (its box is not read).
FittedParameter estimate(const std::string& name, double value, double std_error, bool at_bound = false) {
  FittedParameter p = test::parameter(name, value, std_error, 0.0, 0.0, 0.0, true);
  p.at_bound = at_bound;
  return p;
}
} // namespace

TEST(Calibration, ThePooledStructureIsTheInverseVarianceMeanOfTheRecordingsEstimatesInLnValue) {
  // Two estimates of a shaft, 1e6 with a relative standard error of 1 %, 2e6 with 2 %: weights
  // 1e4 and 2.5e3 in ln value, so ln k = (1e4 ln 1e6 + 2.5e3 ln 2e6) / 1.25e4 and its standard
  // error 1 / sqrt(1.25e4) = 0.894 %.
  const std::vector<std::vector<FittedParameter>> fits{
      {estimate("stiffness.scale", 1.1, 0.01), estimate("rig.k", 1e6, 1e4), estimate("rig.c", -1.0, 0.5)},
      {estimate("stiffness.scale", 0.9, 0.01), estimate("rig.k", 2e6, 4e4), estimate("rig.c", 2.0, 1.0)}};
  const auto pooled = pooled_structure(fits, {"rig.k", "rig.c"});
  ASSERT_TRUE(pooled.has_value());
  ASSERT_EQ(pooled->size(), 2u);
  const double ln_k = (1e4 * std::log(1e6) + 2.5e3 * std::log(2e6)) / 1.25e4;
  EXPECT_EQ((*pooled)[0].name, "rig.k");
  EXPECT_NEAR((*pooled)[0].value, std::exp(ln_k), 1e-9 * std::exp(ln_k));
  EXPECT_NEAR((*pooled)[0].std_error / (*pooled)[0].value, 1 / std::sqrt(1.25e4), 1e-12);
  // A parameter of either sign is pooled linearly: (4 * -1 + 1 * 2) / 5.
  EXPECT_NEAR((*pooled)[1].value, -0.4, 1e-12);
  EXPECT_NEAR((*pooled)[1].std_error, 1 / std::sqrt(5.0), 1e-12);
  // A value at a bound carries no weight: the other recording's estimate is the pooled one.
  auto bounded = fits;
  bounded[1][1] = estimate("rig.k", 2e6, 4e4, true);
  EXPECT_NEAR(pooled_structure(bounded, {"rig.k"})->front().value, 1e6, 1e-3);
  // Nothing to pool: one recording, a parameter a recording lacks, or no weight at all.
  EXPECT_FALSE(pooled_structure({fits[0]}, {"rig.k"}).has_value());
  EXPECT_FALSE(pooled_structure(fits, {"rig.m"}).has_value());
  bounded[0][1] = estimate("rig.k", 1e6, std::nan(""));
  EXPECT_FALSE(pooled_structure(bounded, {"rig.k"}).has_value());
}

TEST(Calibration, DiscrepancyEstimatesRecoverTheDrawnRelativeAndAbsoluteVariances) {
  // 2000 line cells with sigma_rel = 0.2 and 2000 empty cells with sigma_abs = 0.3, split over
  // two recordings: each estimate within 4 standard errors of the truth (a 4-sigma band: the
  // test fails by chance with probability 6e-5).
  const auto r1 = draw_cells(0.2, 0.3, 1000, 1000, 1), r2 = draw_cells(0.2, 0.3, 1000, 1000, 2);
  const auto est = estimate_discrepancy({r1, r2});
  ASSERT_EQ(est.size(), 1u);
  const DiscrepancyEstimate& d = est[0];
  EXPECT_EQ(d.relative_cells, 2000);
  EXPECT_EQ(d.absolute_cells, 2000);
  EXPECT_GT(d.relative_variance_se, 0);
  EXPECT_NEAR(d.relative_variance, 0.04, 4 * d.relative_variance_se);
  EXPECT_NEAR(d.absolute_variance, 0.09, 4 * d.absolute_variance_se);
  ASSERT_EQ(d.relative_variance_per_recording.size(), 2u);
  for (double v : d.relative_variance_per_recording) EXPECT_NEAR(v, 0.04, 0.015);
  // The budget is the upper limit: above the estimate by z standard errors.
  const DiscrepancyEntry b = d.budget(2.326);
  EXPECT_NEAR(b.relative_std * b.relative_std, d.relative_variance + 2.326 * d.relative_variance_se, 1e-12);
  EXPECT_GT(b.absolute_variance, d.absolute_variance);
}

TEST(Calibration, AModelWithoutDiscrepancyGetsABudgetOfTheOrderOfItsStandardError) {
  // Noise only: the estimates scatter around 0 (|estimate| < 4 s.e.) and the budget stays
  // within a few standard errors, far below the 0.04 of the test above.
  const auto est = estimate_discrepancy({draw_cells(0.0, 0.0, 2000, 2000, 3)});
  ASSERT_EQ(est.size(), 1u);
  const DiscrepancyEstimate& d = est[0];
  EXPECT_LT(std::fabs(d.relative_variance), 4 * d.relative_variance_se);
  EXPECT_LT(std::fabs(d.absolute_variance), 4 * d.absolute_variance_se);
  const DiscrepancyEntry b = d.budget(2.326);
  EXPECT_LT(b.relative_std * b.relative_std, 7 * d.relative_variance_se);
  EXPECT_LT(b.relative_std * b.relative_std, 0.004);
}

TEST(Calibration, CalibratedModelIsTheMedianOfTheFitsWithoutTheSensorGains) {
  auto p = [](const std::string& n, double v) {
    FittedParameter f;
    f.name = n;
    f.value = v;
    f.sensor_gain = n == "sensor.gain_m_s2_per_N";  // as fit_context.cpp makes the housing gains
    return f;
  };
  const auto o = median_overrides({{p("stiffness.scale", 1.0), p("sensor.gain_m_s2_per_N", 3.0)},
                                   {p("stiffness.scale", 1.4), p("sensor.gain_m_s2_per_N", 1.0)},
                                   {p("stiffness.scale", 1.1)}});
  ASSERT_EQ(o.size(), 1u);
  EXPECT_EQ(o[0], "stiffness.scale=1.1");
}

// A calibrated value at the edge of its box is a limit, not a fit: the calibration says
// which parameter, which end and on how many recordings; parameters inside their boxes
// and the sensor gains are not listed.
TEST(Calibration, ARigElementsDerivedSettingsFollowItsCalibratedValuesAndOnlyForKeysTheMediansLack) {
  // A shaft element writes its machine's inertia besides its two parameters when the gear set
  // states none (rig_shaft.cpp): the calibrated model must carry that line, or the shaft would
  // hang on a massless machine (an input error). An element whose parameters the medians lack
  // (not visible in the recordings) adds nothing; a key already among the medians is not repeated.
  pw::model::SimulationConfig base;
  const std::vector<std::string> medians = {"stiffness.scale=1.2", "rig.output_shaft_stiffness_N_m_rad=1000000",
                                            "rig.output_shaft_damping_N_m_s_rad=60"};
  const std::vector<std::string> lines =
      rig_element_settings({"encoder_bandwidth", "input_shaft", "output_shaft"}, base, medians);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].substr(0, lines[0].find('=')), "stage.output_inertia_kgm2");
  EXPECT_GT(std::stod(lines[0].substr(lines[0].find('=') + 1)), 1.0);  // a speed source, 1e4 x the carrier
  base.stage.output_inertia_kgm2 = 0.8;  // stated by the gear set: nothing to add
  EXPECT_TRUE(rig_element_settings({"output_shaft"}, base, medians).empty());
}

TEST(Calibration, ASettingThatIsNotANumberAmongTheCalibrationsSettingsIsNoRigElementsValue) {
  // A calibration file may carry a model form among its settings (solver.level=lateral_torsional
  // for a ring_body housing path); reading the rig elements' values from those lines threw
  // std::invalid_argument from std::stod and a diagnosis ended in an internal error (session 72).
  pw::model::SimulationConfig base;
  const std::vector<std::string> medians = {"solver.level=lateral_torsional", "stiffness.scale=1.2",
                                            "rig.output_shaft_stiffness_N_m_rad=1000000",
                                            "rig.output_shaft_damping_N_m_s_rad=60", "sensor.housing_path=ring_body"};
  std::vector<std::string> lines;
  ASSERT_NO_THROW(lines = rig_element_settings({"output_shaft"}, base, medians));
  ASSERT_EQ(lines.size(), 1u);  // the shaft's values were read past the two words
  EXPECT_EQ(lines[0].substr(0, lines[0].find('=')), "stage.output_inertia_kgm2");
}

TEST(Calibration, TheStructureAReferenceHoldsIsTheKeptShaftsWithTheirMachineAndNothingElse) {
  pw::model::SimulationConfig base{};
  Calibration cal;
  cal.rig_elements = {"encoder_bandwidth", "input_shaft"};
  cal.overrides = {"stiffness.scale=1.2", "sensor.encoder_bandwidth_Hz=900", "rig.input_shaft_stiffness_N_m_rad=20000",
                   "rig.input_shaft_damping_N_m_s_rad=4", "stage.input_inertia_kgm2=2.5"};
  const std::vector<std::string> lines = structural_rig_settings(cal, base);
  // The shaft's two keys at their calibrated values and the speed-source machine it assumes; not
  // the encoder (a sensor's low-pass, refitted nowhere at a reference) nor the nuisance levels.
  ASSERT_EQ(lines.size(), 3u);
  std::map<std::string, double> v;
  for (const std::string& l : lines) v[l.substr(0, l.find('='))] = std::stod(l.substr(l.find('=') + 1));
  EXPECT_DOUBLE_EQ(v.at("rig.input_shaft_stiffness_N_m_rad"), 20000);
  EXPECT_DOUBLE_EQ(v.at("rig.input_shaft_damping_N_m_s_rad"), 4);
  EXPECT_GT(v.at("stage.input_inertia_kgm2"), 0.0);
  // A calibration that left its calibration-only elements out holds nothing at the reference.
  cal.rig_elements = {"encoder_bandwidth"};
  EXPECT_TRUE(structural_rig_settings(cal, base).empty());
  // Nor one whose shaft the recordings could not see (its values are missing).
  cal.rig_elements = {"output_shaft"};
  EXPECT_TRUE(structural_rig_settings(cal, base).empty());
}

TEST(Calibration, AReferenceHoldsTheStructureItsOwnFitMeasuredNotTheMedianOverOperatingPoints) {
  // Two healthy recordings whose fits put the input shaft at 1.1e4 and 364 N m/rad (indepsim2's
  // rigA3 at 300 and 900 rpm): their median holds neither. A reference is one of them, so it
  // holds its own fit's values; without an index (or for a file without per-recording fits) the
  // medians, as before.
  pw::model::SimulationConfig base{};
  Calibration cal;
  cal.rig_elements = {"encoder_bandwidth", "input_shaft"};
  cal.overrides = {"stiffness.scale=1.0", "rig.input_shaft_stiffness_N_m_rad=5781", "rig.input_shaft_damping_N_m_s_rad=6.5",
                   "stage.input_inertia_kgm2=2.5"};
  CalibrationFit a, b;
  a.values = {"stiffness.scale=1.4", "rig.input_shaft_stiffness_N_m_rad=11198", "rig.input_shaft_damping_N_m_s_rad=3.6"};
  b.values = {"stiffness.scale=0.57", "rig.input_shaft_stiffness_N_m_rad=364", "rig.input_shaft_damping_N_m_s_rad=9.5"};
  cal.fits = {a, b};
  auto values = [&](std::optional<std::size_t> at) {
    std::map<std::string, double> v;
    for (const std::string& l : structural_rig_settings(cal, base, at)) v[l.substr(0, l.find('='))] = std::stod(l.substr(l.find('=') + 1));
    return v;
  };
  EXPECT_DOUBLE_EQ(values(0).at("rig.input_shaft_stiffness_N_m_rad"), 11198);
  EXPECT_DOUBLE_EQ(values(1).at("rig.input_shaft_stiffness_N_m_rad"), 364);
  EXPECT_DOUBLE_EQ(values(1).at("rig.input_shaft_damping_N_m_s_rad"), 9.5);
  EXPECT_GT(values(1).at("stage.input_inertia_kgm2"), 0.0);  // the speed-source machine the shaft assumes, still
  EXPECT_EQ(values(1).count("stiffness.scale"), 0u);         // nuisance levels are refitted at the reference
  EXPECT_DOUBLE_EQ(values(std::nullopt).at("rig.input_shaft_stiffness_N_m_rad"), 5781);
  cal.fits.clear();  // a file written before the per-recording fits were kept
  EXPECT_DOUBLE_EQ(values(1).at("rig.input_shaft_stiffness_N_m_rad"), 5781);
}

TEST(Calibration, AReferenceHoldsItsOwnFitsRigDesignElementsOnlyWhereThatFitEndedInsideTheirBox) {
  // The calibration's fit of the reference recording measured an encoder low-pass of 572 Hz
  // within its box: the reference holds it (a sensor's design does not change between the
  // calibration and the diagnosis). Not the median over operating points (900 Hz), not the
  // calibration-only shaft (structural_rig_settings holds that), not a nuisance level.
  pw::model::SimulationConfig base{};
  Calibration cal;
  cal.rig_elements = {"encoder_bandwidth", "input_shaft"};
  cal.overrides = {"stiffness.scale=1.0", "sensor.encoder_bandwidth_Hz=900", "rig.input_shaft_stiffness_N_m_rad=5781",
                   "rig.input_shaft_damping_N_m_s_rad=6.5"};
  CalibrationFit inside, at_edge;
  inside.values = {"stiffness.scale=0.725", "sensor.encoder_bandwidth_Hz=572", "rig.input_shaft_stiffness_N_m_rad=11198",
                   "rig.input_shaft_damping_N_m_s_rad=3.6"};
  at_edge.values = {"stiffness.scale=0.9", "sensor.encoder_bandwidth_Hz=20000", "rig.input_shaft_stiffness_N_m_rad=364",
                    "rig.input_shaft_damping_N_m_s_rad=9.5"};
  at_edge.at_bound = {"sensor.encoder_bandwidth_Hz"};  // a limit, not a measurement
  cal.fits = {inside, at_edge};
  const std::vector<std::string> held = reference_design_settings(cal, base, 0);
  ASSERT_EQ(held.size(), 1u);
  EXPECT_EQ(held[0].substr(0, held[0].find('=')), "sensor.encoder_bandwidth_Hz");
  EXPECT_DOUBLE_EQ(std::stod(held[0].substr(held[0].find('=') + 1)), 572.0);
  EXPECT_TRUE(reference_design_settings(cal, base, 1).empty());  // the fit ended at the box's edge
  EXPECT_TRUE(reference_design_settings(cal, base, 2).empty());  // no fit of that recording
  cal.rig_elements = {"input_shaft"};                            // no design element calibrated
  EXPECT_TRUE(reference_design_settings(cal, base, 0).empty());
}

TEST(Calibration, TheReferenceFitsSecondStartIsTheCalibrationsOwnFitOfThatRecording) {
  Calibration cal;
  CalibrationFit a;
  a.values = {"stiffness.scale=0.725", "contact.mesh_damping_ratio=0.051"};
  cal.fits = {a};
  const std::map<std::string, double> start = fitted_values(cal, 0);
  ASSERT_EQ(start.size(), 2u);
  EXPECT_DOUBLE_EQ(start.at("stiffness.scale"), 0.725);
  EXPECT_DOUBLE_EQ(start.at("contact.mesh_damping_ratio"), 0.051);
  EXPECT_TRUE(fitted_values(cal, 1).empty());  // a file without a fit of that recording: one start
}

TEST(Calibration, ALevelsSpreadIsTheSampleStdOfItsLnValueOverRecordingsThatAllFittedIt) {
  // The three-planet rig's stiffness levels (docs/diagnose-log.md session 60): ln 1.30, ln 0.527,
  // ln 0.706 have sample std (n - 1) 0.4617.
  Calibration cal;
  CalibrationFit a, b, c;
  a.values = {"stiffness.scale=1.3022689190544783", "contact.mesh_damping_ratio=0.25", "stage.shift_m=0.0"};
  b.values = {"stiffness.scale=0.5269181964655391", "contact.mesh_damping_ratio=0.01", "stage.shift_m=1e-6",
              "sensor.encoder_bandwidth_Hz=235"};
  c.values = {"stiffness.scale=0.7063165169715657", "contact.mesh_damping_ratio=0.25", "stage.shift_m=2e-6"};
  cal.fits = {a, b, c};
  const std::map<std::string, double> spread = nuisance_level_spread_ln(cal);
  std::vector<double> ln{std::log(1.3022689190544783), std::log(0.5269181964655391), std::log(0.7063165169715657)};
  const double mean = (ln[0] + ln[1] + ln[2]) / 3;
  double ss = 0;
  for (double x : ln) ss += (x - mean) * (x - mean);
  ASSERT_EQ(spread.count("stiffness.scale"), 1u);
  EXPECT_NEAR(spread.at("stiffness.scale"), std::sqrt(ss / 2), 1e-12);
  EXPECT_NEAR(spread.at("stiffness.scale"), 0.4617, 1e-4);
  // 0.25, 0.01, 0.25: std of (ln 25 * (2/3, -4/3, 2/3)) = ln 25 / sqrt(3).
  EXPECT_NEAR(spread.at("contact.mesh_damping_ratio"), std::log(25.0) / std::sqrt(3.0), 1e-12);
  EXPECT_EQ(spread.count("stage.shift_m"), 0u);               // a value of 0: no ln, no spread
  EXPECT_EQ(spread.count("sensor.encoder_bandwidth_Hz"), 0u);  // fitted on one recording only
  cal.fits = {a};
  EXPECT_TRUE(nuisance_level_spread_ln(cal).empty());  // one recording: nothing to scatter
}

TEST(Calibration, ParametersFittedAtABoundAreListedWithTheEndAndTheirCount) {
  auto p = [](const std::string& n, double v, double lo, double hi, bool at_bound) {
    FittedParameter f;
    f.name = n;
    f.value = v;
    f.lower = lo;
    f.upper = hi;
    f.at_bound = at_bound;
    f.sensor_gain = n == "sensor.gain_m_s2_per_N";
    return f;
  };
  const auto notes = parameters_at_bound({{p("stiffness.scale", 2.0, 0.5, 2.0, true),
                                           p("contact.mesh_damping_ratio", 0.05, 0.005, 0.25, false),
                                           p("sensor.gain_m_s2_per_N", 1.0, 0.0, 1.0, true)},
                                          {p("stiffness.scale", 2.0, 0.5, 2.0, true),
                                           p("contact.mesh_damping_ratio", 0.005, 0.005, 0.25, true)},
                                          {p("stiffness.scale", 1.7, 0.5, 2.0, false),
                                           p("contact.mesh_damping_ratio", 0.04, 0.005, 0.25, false)}});
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_EQ(notes[0], "stiffness.scale at its upper bound 2 on 2 of 3 recordings");
  EXPECT_EQ(notes[1], "contact.mesh_damping_ratio at its lower bound 0.005 on 1 of 3 recordings");
  EXPECT_TRUE(parameters_at_bound({{p("stiffness.scale", 1.2, 0.5, 2.0, false)}}).empty());
}

// A family the healthy model never had a line in (no relative cells) takes the largest
// relative budget measured on the same kind of channel, flagged as inherited; a family of
// another kind of channel, and every absolute budget, keep their own.
TEST(Calibration, AFamilyWithoutMeasuredLinesInheritsTheLargestRelativeBudgetOfItsChannelKind) {
  auto est = [](Quantity q, Component f, double rel, double rel_se, int rel_cells, double abs_v) {
    DiscrepancyEstimate d;
    d.quantity = q, d.family = f;
    d.relative_variance = rel, d.relative_variance_se = rel_se, d.relative_cells = rel_cells;
    d.absolute_variance = abs_v, d.absolute_variance_se = 0, d.absolute_cells = 10;
    return d;
  };
  Calibration cal;
  cal.alpha = 0.01;
  cal.discrepancy = {est(Quantity::SunSpeed, Component::Mesh, 0.09, 0.01, 50, 1e-6),
                     est(Quantity::SunSpeed, Component::Carrier, 0.04, 0.01, 20, 2e-6),
                     est(Quantity::SunSpeed, Component::Sun, 0.0, 0.0, 0, 3e-6),
                     est(Quantity::HousingAcceleration, Component::Sun, 0.0, 0.0, 0, 4e-6)};
  const auto b = cal.budgets();
  ASSERT_EQ(b.size(), 4u);
  const double z = 2.3263478740408408;  // z_{0.99}
  EXPECT_NEAR(b[0].relative_std, std::sqrt(0.09 + z * 0.01), 1e-9);
  EXPECT_FALSE(b[0].relative_inherited);
  EXPECT_FALSE(b[1].relative_inherited);
  EXPECT_DOUBLE_EQ(b[2].relative_std, b[0].relative_std);  // the larger of mesh and carrier
  EXPECT_TRUE(b[2].relative_inherited);
  EXPECT_DOUBLE_EQ(b[2].absolute_variance, 3e-6);           // its own absolute budget
  EXPECT_EQ(b[3].relative_std, 0.0);                        // nothing measured on its kind
  EXPECT_FALSE(b[3].relative_inherited);
}

// Each recording's fit is kept as "key=value" with the keys at a bound, sensor gains left out
// (they are profiled on every recording, not calibrated).
TEST(Calibration, EachRecordingsFitKeepsItsNuisanceValuesAndTheirBoundsWithoutTheSensorGains) {
  auto p = [](const std::string& n, double v, bool at_bound, bool gain) {
    FittedParameter f;
    f.name = n, f.value = v, f.at_bound = at_bound, f.sensor_gain = gain;
    return f;
  };
  const CalibrationFit f = calibration_fit(
      {p("stiffness.scale", 2.0, true, false), p("contact.mesh_damping_ratio", 0.125, false, false),
       p("sensor.gain_m_s2_per_N", 3e-3, false, true)},
      5000.0, 3400.0);
  EXPECT_EQ(f.values, (std::vector<std::string>{"stiffness.scale=2", "contact.mesh_damping_ratio=0.125"}));
  EXPECT_EQ(f.at_bound, (std::vector<std::string>{"stiffness.scale"}));
  EXPECT_EQ(f.nuisance_chi2_held_out, 5000.0);
  EXPECT_EQ(f.noise_bound_held_out, 3400.0);
}

TEST(Calibration, AnotherModelFormIsTakenOnlyWhereEveryRecordingFitsBetterThanOneParameterBuysByChance) {
  // m = 2000 features, alpha = 0.01: F_{0.99}(1, 2000) = 6.65; the improvement must exceed it times
  // the time-locked fit's chi2 per feature.
  const double f = pw::f_quantile(1, 2000, 0.01);
  const auto fits = [](double roll, std::optional<double> locked) {
    return ModelFormFits{.fit_chi2 = roll, .probe_fit_chi2 = locked, .fit_features = 2000, .held_out_chi2 = roll,
                        .refit_held_out_chi2 = locked, .held_out_features = 2000};
  };
  // A model at the noise (chi2 per feature 1): just above and just below the threshold.
  EXPECT_TRUE(form_probes_pass({fits(2000 + f * 1.01, 2000)}, 0.01));
  EXPECT_TRUE(form_refits_improve({fits(2000 + f * 1.01, 2000)}, 0.01));
  EXPECT_FALSE(form_probes_pass({fits(2000 + f * 0.99, 2000)}, 0.01));
  EXPECT_FALSE(form_refits_improve({fits(2000 + f * 0.99, 2000)}, 0.01));
  // Another simulator's rig, 1000 times the noise per feature: an improvement of 100 is chance there.
  EXPECT_FALSE(form_probes_pass({fits(2e6 + 100, 2e6)}, 0.01));
  EXPECT_TRUE(form_probes_pass({fits(2e6 + 2e4, 2e6)}, 0.01));
  // Every recording must agree; a recording that was not probed (its roll-locked model passed the
  // noise test) keeps the roll-locked form for all; no recording, no choice.
  EXPECT_FALSE(form_probes_pass({fits(9e4, 5e3), fits(4e3, 5e3)}, 0.01));
  EXPECT_FALSE(form_probes_pass({fits(9e4, 5e3), fits(4e3, std::nullopt)}, 0.01));
  EXPECT_TRUE(form_probes_pass({fits(9e4, 5e3), fits(4e4, 4e3)}, 0.01));
  EXPECT_FALSE(form_refits_improve({fits(9e4, 5e3), fits(4e4, std::nullopt)}, 0.01));
  EXPECT_FALSE(form_probes_pass({}, 0.01));
  EXPECT_FALSE(form_refits_improve({}, 0.01));
}

TEST(Calibration, ACalibratedModelsFormIsOneSetLinePerPartThatDiffersFromTheDefault) {
  using pw::model::HousingPath;
  using pw::model::MeshPhase;
  EXPECT_TRUE(model_form_settings(ModelForm{}).empty());
  EXPECT_EQ(model_form_settings({.mesh_phase = MeshPhase::NominalTime}),
            std::vector<std::string>{"stiffness.mesh_phase=nominal_time"});
  EXPECT_EQ(model_form_settings({.housing_path = HousingPath::RingTranslation}),
            std::vector<std::string>{"sensor.housing_path=ring_translation"});
  const ModelForm both{.mesh_phase = MeshPhase::NominalTime, .housing_path = HousingPath::RingTranslation};
  EXPECT_EQ(model_form_settings(both).size(), 2u);
  // apply_model_form and model_form_of are inverse, and the default configuration has the default form.
  pw::model::SimulationConfig c;
  EXPECT_EQ(model_form_of(c), ModelForm{});
  apply_model_form(c, both);
  EXPECT_EQ(model_form_of(c), both);
}

// The ring body's housing path is valid only in the lateral-torsional model (model/validate.cpp):
// its form writes the level before the path, so that a calibration file's form lines, applied in
// their order, never name the path on the torsional model; applied to a default (torsional)
// configuration it gives a valid one, and model_form_of reads the form back.
TEST(Calibration, TheRingBodysFormBringsTheLateralTorsionalModelBeforeItsPath) {
  using pw::model::HousingPath;
  using pw::model::ModelLevel;
  EXPECT_EQ(model_form_settings(kRingBodyHousing.changed(ModelForm{})),
            (std::vector<std::string>{"solver.level=lateral_torsional", "sensor.housing_path=ring_body"}));
  pw::model::SimulationConfig c;
  ASSERT_EQ(c.solver.level, ModelLevel::Torsional);
  c.sensor.housing_path = HousingPath::RingBody;
  EXPECT_THROW(pw::model::validate(c), pw::Error);  // the path alone is refused on the torsional model
  c = pw::model::SimulationConfig{};
  apply_model_form(c, kRingBodyHousing.changed(ModelForm{}));
  EXPECT_EQ(c.solver.level, ModelLevel::LateralTorsional);
  EXPECT_EQ(model_form_of(c).housing_path, HousingPath::RingBody);
  EXPECT_NO_THROW(pw::model::validate(c));
  // It brings the supports' damping as a rig element; the other two parts bring none.
  ASSERT_NE(kRingBodyHousing.rig_element, nullptr);
  EXPECT_EQ(std::string(kRingBodyHousing.rig_element), "bearing_damping");
  EXPECT_EQ(kRingTranslationHousing.rig_element, nullptr);
  EXPECT_EQ(kTimeLockedMesh.rig_element, nullptr);
}

// A calibration that took the ring's translation and then the ring body: the body's lines come
// first (the level before the path) and the translation's line goes -- coming after, it would win,
// and the "ring body" refits would run the ring's translation in the lateral-torsional model (as
// they did before this was fixed, session 73). The user's lines stay, after the form's.
TEST(Calibration, ALaterHousingPathReplacesTheEarlierOnesLineAndKeepsTheUsersAfterIt) {
  using pw::model::HousingPath;
  using pw::model::MeshPhase;
  const ModelForm chosen{.mesh_phase = MeshPhase::NominalTime, .housing_path = HousingPath::RingTranslation};
  const std::vector<std::string> before = {"sensor.housing_path=ring_translation", "stiffness.mesh_phase=nominal_time",
                                           "contact.friction_coefficient=0.08"};
  EXPECT_EQ(assignments_in_form(before, chosen, kRingBodyHousing),
            (std::vector<std::string>{"solver.level=lateral_torsional", "sensor.housing_path=ring_body",
                                      "stiffness.mesh_phase=nominal_time", "contact.friction_coefficient=0.08"}));
  // From the default form nothing goes; the part's line leads.
  EXPECT_EQ(assignments_in_form({"contact.friction_coefficient=0.08"}, ModelForm{}, kRingTranslationHousing),
            (std::vector<std::string>{"sensor.housing_path=ring_translation", "contact.friction_coefficient=0.08"}));
}

// A form that brings a rig element is judged by the F test with one more parameter per parameter
// of that element: an improvement just above the one-parameter threshold (F_{0.99}(1, 2000) = 6.65
// per feature of chi2) is not enough for two (F_{0.99}(2, 2000) = 4.62 each, 9.24 in all).
TEST(Calibration, AFormThatBringsARigElementPaysForItsParametersInTheFTests) {
  const double f1 = pw::f_quantile(1, 2000, 0.01), f2 = pw::f_quantile(2, 2000, 0.01);
  ASSERT_GT(2 * f2, 1.2 * f1);
  const auto fits = [](double own, double other, int extra) {
    return ModelFormFits{.fit_chi2 = own, .probe_fit_chi2 = other, .fit_features = 2000, .held_out_chi2 = own,
                         .refit_held_out_chi2 = other, .held_out_features = 2000, .extra_parameters = extra};
  };
  const double just_one = 2000 + f1 * 1.01;
  EXPECT_TRUE(form_probes_pass({fits(just_one, 2000, 1)}, 0.01));
  EXPECT_FALSE(form_probes_pass({fits(just_one, 2000, 2)}, 0.01));
  EXPECT_FALSE(form_refits_improve({fits(just_one, 2000, 2)}, 0.01));
  EXPECT_TRUE(form_probes_pass({fits(2000 + 2 * f2 * 1.01, 2000, 2)}, 0.01));
  EXPECT_TRUE(form_refits_improve({fits(2000 + 2 * f2 * 1.01, 2000, 2)}, 0.01));
}

// A housing channel of pure noise (A^2 exponential with mean s^2 per bin) holds no line: over
// 200 recordings of 500 cells each, none is called heard at alpha = 0.01 (the test's own false
// alarm rate, alpha per recording set, makes a failure here a 1 % event per set: the seed is
// fixed, so the outcome is deterministic). One line of 3 s in amplitude (A^2 = 9 s^2 against
// ln(500 / 0.01) = 10.8 s^2) in both halves is not enough; one of 5 s (25 s^2) is. Speed
// channels do not count; no housing cell at all is "not heard".
TEST(Calibration, AHousingChannelIsHeardOnlyWhereALineExceedsTheNoiseInBothHalvesBeyondTheBonferroniLevel) {
  std::mt19937_64 rng(71);
  std::exponential_distribution<double> power(1.0);
  const double s2 = 4e-6;
  auto noise_cells = [&](Quantity q, int n) {
    std::vector<CalibrationCell> cells(static_cast<std::size_t>(n));
    for (CalibrationCell& c : cells) {
      c.quantity = q;
      c.noise_variance = s2;
      for (double& a : c.recording) a = std::sqrt(s2 * power(rng));
    }
    return cells;
  };
  int heard = 0;
  for (int set = 0; set < 200; ++set) heard += housing_lines_heard({noise_cells(Quantity::HousingAcceleration, 500)}, 0.01);
  EXPECT_EQ(heard, 0);
  auto with_line = [&](double amplitude_in_s, bool both_halves) {
    auto cells = noise_cells(Quantity::HousingAcceleration, 500);
    cells[17].recording[0] = amplitude_in_s * std::sqrt(s2);
    cells[17].recording[1] = both_halves ? amplitude_in_s * std::sqrt(s2) : 0.0;
    return std::vector<std::vector<CalibrationCell>>{cells};
  };
  EXPECT_FALSE(housing_lines_heard(with_line(3.0, true), 0.01));
  EXPECT_TRUE(housing_lines_heard(with_line(5.0, true), 0.01));
  EXPECT_FALSE(housing_lines_heard(with_line(50.0, false), 0.01));
  auto speed = noise_cells(Quantity::SunSpeed, 50);
  speed[3].recording[0] = speed[3].recording[1] = 100 * std::sqrt(s2);
  EXPECT_FALSE(housing_lines_heard({speed}, 0.01));
  EXPECT_FALSE(housing_lines_heard({}, 0.01));
}

TEST(Calibration, AParameterHeldAtNullTakesItsNullValueInEveryRecordingAndIsNoLongerAtABound) {
  FittedParameter f, z, k;
  f.name = "sensor.housing_mount_frequency_Hz";
  f.value = 2.2;
  z.name = "sensor.housing_mount_damping_ratio";
  z.value = 0.01;
  z.at_bound = true;
  k.name = "stiffness.scale";
  k.value = 0.95;
  std::vector<std::vector<FittedParameter>> per_recording{{f, z, k}, {f, z, k}};
  hold_at_null(per_recording, {{f.name, 1.0}, {z.name, std::sqrt(0.5)}});
  for (const auto& params : per_recording) {
    EXPECT_EQ(params[0].value, 1.0);
    EXPECT_EQ(params[1].value, std::sqrt(0.5));
    EXPECT_FALSE(params[1].at_bound);
    EXPECT_EQ(params[2].value, 0.95);
  }
  EXPECT_TRUE(parameters_at_bound(per_recording).empty());
}
