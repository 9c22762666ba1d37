// Differential diagnosis (baseline.hpp): a healthy baseline's per-cell offsets added to the
// model. No simulation is run: the "model" is the order spectrum of a noise-free synthetic
// recording (what a perfect simulator of the synthetic stage would give), and its model-form
// error is a carrier-family line it lacks (as an unmodelled rig element would add).
//
// The recordings are those of test_compare.cpp's kind: the seed stage at 1200 rpm, 3.2 carrier
// revolutions at 10 kHz, a sun-speed channel and a sun-planet mesh acceleration made of 8 mesh
// harmonics, an optional line at carrier order 2 Zr + 3, and white noise.
#include "diagnose/baseline.hpp"
#include "diagnose/calibration.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/fit.hpp"
#include "diagnose/fitted_parameter.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/stage_1200rpm.hpp"
#include "model/validate.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace pw::diagnose {
namespace {

/// Per-window false-alarm level of the tests below (the diagnosis's alpha / 2 at alpha = 0.01).
constexpr double kAlphaHalf = 0.005;

/// The shared synthetic stage recording without phase jitter or speed bias: a carrier-family
/// line of line_m_s2 (0: none), acceleration and speed noise per sample.
Recording synthetic(double line_m_s2, unsigned seed, double noise_m_s2 = 0.5, double speed_noise_rad_s = 0.01) {
  return test::synthetic(0.0, line_m_s2, seed, 0.0, noise_m_s2, speed_noise_rad_s);
}

/// The fit-half spectrum [channel][bin] of a noise-free recording without the carrier line.
std::vector<std::vector<double>> perfect_model() {
  const Recording clean = synthetic(0.0, 1, 1e-6, 1e-9);
  const ModelComparison c(clean, test::stage_1200rpm());
  return c.spectra().amplitude[0];
}

/// held-out chi2 of `model` on `rec` and its 1 - kAlphaHalf null quantile.
std::pair<double, double> held_out(const Recording& rec, const std::vector<std::vector<double>>& model,
                                   const CompareOptions& co = {}) {
  ModelComparison cmp(rec, test::stage_1200rpm(), co);
  cmp.set_reference(model, {});
  return {cmp.score(model, Half::HeldOut, {}, HousingGains::Given).chi2, cmp.null_quantile(model, {}, Half::HeldOut, kAlphaHalf)};
}

std::vector<BaselineCell> baseline_of(const Recording& base, const std::vector<std::vector<double>>& model) {
  ModelComparison cmp(base, test::stage_1200rpm());
  cmp.set_reference(model, {});
  std::vector<BaselineCell> out;
  for (const CalibrationCell& c : calibration_cells(cmp, model, {1.0, 1.0})) out.push_back(baseline_cell(c));
  return out;
}

TEST(Baseline, CellOffsetIsTheDebiasedMeanOfBothHalvesMinusTheModel) {
  CalibrationCell c;
  c.channel = "sp_acc";
  c.order = 165;
  c.model = 1.0;
  c.recording[0] = 3.0;
  c.recording[1] = 5.0;
  c.noise_variance = 4.0;
  c.variance[0] = 2.0;
  c.variance[1] = 6.0;
  const BaselineCell b = baseline_cell(c);
  EXPECT_EQ(b.channel, "sp_acc");
  EXPECT_EQ(b.order, 165);
  // sqrt(3^2 - 4) = sqrt 5, sqrt(5^2 - 4) = sqrt 21; the mean of two halves has a quarter of their summed variance.
  EXPECT_DOUBLE_EQ(b.offset, 0.5 * (std::sqrt(5.0) + std::sqrt(21.0)) - 1.0);
  EXPECT_DOUBLE_EQ(b.variance, 2.0);
  // A cell below the noise floor has no line: its de-biased amplitude is 0.
  c.recording[0] = c.recording[1] = 1.5;
  EXPECT_DOUBLE_EQ(baseline_cell(c).offset, -1.0);
}

TEST(Baseline, AModelMissingALineExplainsARecordingWithItOnceTheBaselineCarriesIt) {
  const auto model = perfect_model();
  const Recording rec = synthetic(3.0, 11);
  const auto [chi2_absolute, bound_absolute] = held_out(rec, model);
  EXPECT_GT(chi2_absolute, 2 * bound_absolute) << "the unmodelled line must stand out in the absolute comparison";
  CompareOptions co;
  co.baseline = baseline_of(synthetic(3.0, 12), model);
  const auto [chi2, bound] = held_out(rec, model, co);
  EXPECT_LE(chi2, bound);
}

TEST(Baseline, AChangeFromTheBaselineStillStandsOut) {
  // The baseline lacks the line the recording has: the change is not absorbed.
  const auto model = perfect_model();
  CompareOptions co;
  co.baseline = baseline_of(synthetic(0.0, 12), model);
  const auto [chi2, bound] = held_out(synthetic(3.0, 11), model, co);
  EXPECT_GT(chi2, 2 * bound);
}

TEST(Baseline, LineRatioTransferIsTheMeasuredRatioWhereBothLinesStandAboveTheNoiseAndLogLinearBetween) {
  // One channel, noise standard deviation 1 (the detection floor z_0.995 = 2.576): lines at orders
  // 2 (baseline 10, model 20: ratio 1/2) and 5 (40 against 10: ratio 4) are detectable in both; the
  // others are not in one of them. A second channel has no detectable pair: it stays additive.
  auto cell = [](std::string ch, double order, double baseline, double model) {
    CalibrationCell c;
    c.channel = std::move(ch);
    c.order = order;
    c.model = model;
    c.noise_variance = 1.0;
    c.recording[0] = c.recording[1] = std::sqrt(baseline * baseline + 1.0);  // de-biased: `baseline`
    c.variance[0] = c.variance[1] = 1.0;
    return c;
  };
  const std::vector<CalibrationCell> source = {
      cell("a", 6, 1.0, 30.0), cell("a", 1, 1.0, 0.5), cell("a", 2, 10.0, 20.0), cell("a", 3, 0.0, 2.0),
      cell("a", 4, 5.0, 1.0),  cell("a", 5, 40.0, 10.0), cell("b", 1, 30.0, 1.0), cell("b", 2, 1.0, 30.0)};
  std::vector<BaselineCell> cells;
  for (const CalibrationCell& c : source) cells.push_back(baseline_cell(c));
  const std::vector<BaselineCell> additive = cells;
  line_ratio_transfer(cells, source, 0.01);
  const std::vector<double> expected = {4.0, 0.5, 0.5, 1.0, 2.0, 4.0, 1.0, 1.0};  // 0.5 * 8^(1/3) = 1, 0.5 * 8^(2/3) = 2
  for (std::size_t i = 0; i < cells.size(); ++i) {
    EXPECT_NEAR(cells[i].transfer, expected[i], 1e-12) << cells[i].channel << " order " << cells[i].order;
    // The baseline's own amplitude is what the comparison takes at the baseline's model.
    EXPECT_NEAR(cells[i].transfer * cells[i].model + cells[i].offset, additive[i].model + additive[i].offset, 1e-12);
    EXPECT_EQ(cells[i].variance, additive[i].variance);
  }
  EXPECT_EQ(cells[6].offset, additive[6].offset);  // channel b: untouched
}

TEST(Baseline, AModelWhoseTransferIsTwiceTheRigsPredictsAChangeTwiceTooLargeUnlessScaledByTheLineRatio) {
  // The model reads every line twice as strongly as the rig (a transfer it gets wrong by a factor,
  // as a free sun does against a rig's heavy motor behind a shaft). The recording changed from its
  // baseline by a carrier-family line the model predicts at twice its size too. Additive, the
  // change is judged twice too large; scaled by the baseline's measured line ratio (the mesh
  // harmonics around the new line: 1/2), it is explained.
  const Recording clean_line = synthetic(3.0, 1, 1e-6, 1e-9);
  const ModelComparison clean(clean_line, test::stage_1200rpm());
  auto twice = [](std::vector<std::vector<double>> m) {
    for (auto& ch : m)
      for (double& a : ch) a *= 2.0;
    return m;
  };
  const auto model_base = twice(perfect_model());
  const auto model_changed = twice(clean.spectra().amplitude[0]);
  const Recording base = synthetic(0.0, 12);
  ModelComparison bc(base, test::stage_1200rpm());
  bc.set_reference(model_base, {});
  const std::vector<CalibrationCell> source = calibration_cells(bc, model_base, {1.0, 1.0});
  std::vector<BaselineCell> cells;
  for (const CalibrationCell& c : source) cells.push_back(baseline_cell(c));
  CompareOptions additive;
  additive.baseline = cells;
  line_ratio_transfer(cells, source, 0.01);
  CompareOptions ratio;
  ratio.baseline = cells;
  const Recording rec = synthetic(3.0, 11);
  const auto [chi2_additive, bound_additive] = held_out(rec, model_changed, additive);
  const auto [chi2_ratio, bound_ratio] = held_out(rec, model_changed, ratio);
  EXPECT_GT(chi2_additive, 2 * bound_additive);
  EXPECT_LE(chi2_ratio, bound_ratio);
  // Where nothing changed both compare the baseline's own lines: the healthy recording passes both.
  const Recording healthy = synthetic(0.0, 11);
  const auto [chi2_healthy_additive, bound_healthy_additive] = held_out(healthy, model_base, additive);
  const auto [chi2_healthy_ratio, bound_healthy_ratio] = held_out(healthy, model_base, ratio);
  EXPECT_LE(chi2_healthy_additive, bound_healthy_additive);
  EXPECT_LE(chi2_healthy_ratio, bound_healthy_ratio);
}

TEST(Baseline, AHousingGainIsSearchedFromAPositiveStartWhenTheOffsetsExceedTheRecording) {
  // Found on an independent simulator's recording diagnosed against its baseline with rig keys
  // (session 23): the baseline's offsets exceeded the recording's housing lines, the weighted
  // least-squares start of the housing gain came out negative, its logarithm NaN, and every chi2
  // of the diagnosis with it. The mesh-acceleration channel is read as a housing accelerometer
  // here, so that its gain is profiled.
  auto as_housing = [](Recording r) {
    r.channels[1].quantity = Quantity::HousingAcceleration;
    return r;
  };
  const auto model = perfect_model();
  CompareOptions co;
  co.baseline = baseline_of(as_housing(synthetic(0.0, 12)), model);
  for (BaselineCell& b : co.baseline)
    if (b.channel == "sp_acc") b.offset = 50.0;  // [m/s^2]: above every line (10/h) of the recording
  const Recording rec = as_housing(synthetic(0.0, 11));
  ModelComparison cmp(rec, test::stage_1200rpm(), co);
  ASSERT_TRUE(cmp.is_housing(1));
  cmp.set_reference(model, {1.0, 1.0});
  const WindowScore s = cmp.score(model, Half::Fit, {1.0, 1.0}, HousingGains::Profile);
  EXPECT_TRUE(std::isfinite(s.chi2));
  ASSERT_EQ(s.gains.size(), 2u);
  EXPECT_GT(s.gains[1], 0.0);
  EXPECT_LT(s.gains[1], 1.0);         // the search goes down from the given gain: the offsets are too large already
  EXPECT_TRUE(s.gain_at_edge[1]);     // and the optimum lies beyond its bracket: reported, not hidden
}

TEST(Baseline, AHousingGainStopsAtTheConfigurationsLargestWhenTheModelsHousingLinesAreAllButZero) {
  // An in-phase stage on the ring's translation: the model's healthy housing lines cancel to
  // round-off while the recording's are real (session 72). The gain that would match them is
  // ~10^12 times any physical one; the search stops at the configuration's largest gain and says
  // so, instead of handing the configuration a gain it refuses as a unit mistake.
  auto as_housing = [](Recording r) {
    r.channels[1].quantity = Quantity::HousingAcceleration;
    return r;
  };
  auto model = perfect_model();
  for (double& a : model[1]) a *= 1e-12;
  const Recording rec = as_housing(synthetic(0.0, 11));
  ModelComparison cmp(rec, test::stage_1200rpm());
  ASSERT_TRUE(cmp.is_housing(1));
  cmp.set_reference(model, {1.0, 1.0});
  const WindowScore s = cmp.score(model, Half::Fit, {1.0, 1.0}, HousingGains::Profile);
  const double largest = model::largest_housing_gain_m_s2_per_N(test::stage_1200rpm());
  EXPECT_TRUE(std::isfinite(s.chi2));
  ASSERT_EQ(s.gains.size(), 2u);
  EXPECT_NEAR(s.gains[1], largest, 1e-5 * largest);  // at the bound
  EXPECT_LE(s.gains[1], largest);
  EXPECT_TRUE(s.gain_at_edge[1]);
  // The bound is what stopped the search, not where it would have ended anyway: the gain that
  // undoes the 1e-12 fits far better.
  const WindowScore matched = cmp.score(model, Half::Fit, {1.0, 1e12}, HousingGains::Given);
  EXPECT_LT(matched.chi2, 0.01 * s.chi2);
}

TEST(Baseline, TheDiscretizationErrorTheBaselinesModelSharesCancelsInTheNull) {
  // A model whose lines are 30-90 times the rig's (an independent simulator's speed channels behind
  // encoders that remove them, session 23), with a discretization direction of 10 % of its raw
  // lines: 3 times the lines the recordings have. The baseline's model has the same error,
  // which its offset carries with the opposite sign. Drawn as the model's own error, the null
  // folded it at 0 and put the bound far above what a recording like its baseline gives.
  auto model = perfect_model();
  for (auto& channel : model)
    for (std::size_t b = 0; b < channel.size(); ++b) channel[b] *= 30.0 * (1.0 + static_cast<double>(b % 7) / 3.0);
  auto fidelity = [&](const ModelComparison& cmp) {
    std::vector<std::vector<double>> u(2, std::vector<double>(static_cast<std::size_t>(cmp.features()), 0.0));
    for (int c = 0; c < cmp.channels(); ++c)
      for (int i = 0; i < cmp.cells(); ++i) {
        const auto bin = static_cast<std::size_t>(cmp.spectra().layout.cells[static_cast<std::size_t>(i)].bin);
        u[0][static_cast<std::size_t>(c * cmp.cells() + i)] = 0.1 * model[static_cast<std::size_t>(c)][bin];
      }
    return u;
  };
  const std::vector<std::string> names = {"discretization", "speed"};
  const Recording base = synthetic(0.0, 12);
  ModelComparison bc(base, test::stage_1200rpm());
  bc.set_reference(model, {});
  bc.set_fidelity(fidelity(bc), names, 0);
  CompareOptions co;
  for (const CalibrationCell& c : calibration_cells(bc, model, {1.0, 1.0})) co.baseline.push_back(baseline_cell(c));
  const Recording rec = synthetic(0.0, 11);
  ModelComparison rc(rec, test::stage_1200rpm(), co);
  rc.set_reference(model, {});
  rc.set_fidelity(fidelity(rc), names, 0);
  const double m = rc.features();
  const double chi2 = rc.score(model, Half::HeldOut, {}, HousingGains::Given).chi2;
  const double bound = rc.null_quantile(model, {}, Half::HeldOut, kAlphaHalf);
  rc.set_fidelity(fidelity(rc), names, -1);  // the column as the model's own error
  const double bound_unshared = rc.null_quantile(model, {}, Half::HeldOut, kAlphaHalf);
  EXPECT_LE(chi2, bound);
  // m features of mean 1 plus a 1 - 0.005 margin of a few sqrt(2 m): 1.2 m is generous.
  EXPECT_LT(bound, 1.2 * m) << "chi2 " << chi2;
  EXPECT_GT(bound_unshared, 2 * bound) << "bound " << bound << ", m " << m;
}

TEST(Baseline, ARecordingLikeItsBaselineScoresOnePerFeatureAsTheNullAssumes) {
  // The baseline's offset enters inside the Rician mean, so its error moves a cell whose line
  // is below the noise hardly at all. Counted whole in V (session 22 and before), a recording
  // like its baseline scored chi2 = 0.6 m while the null assumed m: a test at a fraction of its
  // stated size. chi2 ~ m +- sqrt(2 m) here; 4 standard deviations either side.
  const auto model = perfect_model();
  CompareOptions co;
  co.baseline = baseline_of(synthetic(0.0, 12), model);
  for (unsigned seed : {11u, 13u}) {
    const Recording rec = synthetic(0.0, seed);
    ModelComparison rc(rec, test::stage_1200rpm(), co);
    rc.set_reference(model, {});
    const double m = rc.features();
    const double chi2 = rc.score(model, Half::HeldOut, {}, HousingGains::Given).chi2;
    EXPECT_NEAR(chi2, m, 4 * std::sqrt(2 * m)) << "seed " << seed;
    const double bound = rc.null_quantile(model, {}, Half::HeldOut, kAlphaHalf);
    EXPECT_NEAR(bound, m + 2.58 * std::sqrt(2 * m), 4 * std::sqrt(2 * m)) << "seed " << seed;
  }
}

TEST(Baseline, ABaselineWithoutTheRecordingsCellsIsRefusedNamingTheOption) {
  const auto model = perfect_model();
  CompareOptions co;
  co.baseline = baseline_of(synthetic(3.0, 12), model);
  co.baseline.back().order += 0.5;  // as a baseline analysed in other windows would be
  const Recording rec = synthetic(3.0, 11);
  try {
    ModelComparison cmp(rec, test::stage_1200rpm(), co);
    FAIL() << "a baseline without the recording's cells was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--baseline"), std::string::npos) << e.what();
  }
}

TEST(CalibratedDiscrepancy, AModelWithStrongerLinesThanTheReferenceIsNotGivenAWiderNull) {
  // V holds the calibrated relative discrepancy at the reference (healthy, calibrated) model's
  // amplitudes. The null of a scored model must draw it the same size: a candidate whose mesh
  // lines are 10x the reference's must not get (0.5 x 10 a)^2 of allowance per cell that its
  // chi2, weighted by V, never charges (an 850-fold bound measured in session 16).
  CompareOptions co;
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.5, 0.0});
  const Recording rec = synthetic(0.0, 5);
  ModelComparison cmp(rec, test::stage_1200rpm(), co);
  const auto model = perfect_model();
  cmp.set_reference(model, {});
  auto strong = model;
  for (double& a : strong[1]) a *= 10;  // the mesh acceleration's lines
  const double q_ref = cmp.null_quantile(model, {}, Half::HeldOut, kAlphaHalf);
  const double q_strong = cmp.null_quantile(strong, {}, Half::HeldOut, kAlphaHalf);
  // Without a discrepancy the stronger lines change the null only through the Rician variance
  // (lines near the noise floor): the calibrated ratio must be that one to Monte-Carlo error
  // (a few % at 1000 draws), where drawing the discrepancy at the scored amplitudes multiplies
  // the mesh cells' share by 100.
  ModelComparison plain(rec, test::stage_1200rpm());
  plain.set_reference(model, {});
  const double p_ref = plain.null_quantile(model, {}, Half::HeldOut, kAlphaHalf);
  const double p_strong = plain.null_quantile(strong, {}, Half::HeldOut, kAlphaHalf);
  EXPECT_NEAR((q_strong / q_ref) / (p_strong / p_ref), 1.0, 0.1)
      << "calibrated " << q_ref << " -> " << q_strong << ", plain " << p_ref << " -> " << p_strong;
  // The discrepancy is in V: lines 30 % off the reference cost far less chi2 with it than
  // without (noise alone makes the strong mesh lines' 30 % many standard deviations).
  auto off = model;
  for (double& a : off[1]) a *= 1.3;
  const double chi_plain = plain.score(off, Half::HeldOut, {}, HousingGains::Given).chi2;
  const double chi_cal = cmp.score(off, Half::HeldOut, {}, HousingGains::Given).chi2;
  EXPECT_LT(chi_cal, q_ref) << "30 % is within a calibrated relative discrepancy of 50 %";
  EXPECT_GT(chi_plain, p_ref) << "30 % is far outside the noise";
}

TEST(Baseline, TheBaselinesDiscrepancyScalesWithTheModelsChangeNotWithItsLines) {
  // Differential with a relative budget of 50 % (what fit_baseline estimates from the baseline):
  // (1) a lead that predicts the recording's new line 30 % too strong is within the budget of its
  //     own change, and fails against the noise alone;
  // (2) a model whose mesh lines are 30 % too strong where nothing changed gets no allowance at
  //     all (a model-form error common to both recordings cancels, so none is budgeted), where
  //     the absolute calibrated comparison lets 50 % of every line pass.
  const auto model = perfect_model();
  const double line = 5.0;  // [m/s^2], against 0.5 m/s^2 of white noise per sample
  const Recording rec = synthetic(line, 6);
  CompareOptions co;
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.5, 0.0});
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Carrier, 0.5, 0.0, true});
  CompareOptions differential = co;
  differential.baseline = baseline_of(synthetic(0.0, 12), model);
  ModelComparison cmp(rec, test::stage_1200rpm(), differential);
  const Recording clean_with_line = synthetic(line, 1, 1e-6, 1e-9);
  const auto with_line = ModelComparison(clean_with_line, test::stage_1200rpm()).spectra().amplitude[0];
  auto lead = model, mesh_off = model;
  int line_bins = 0, mesh_bins = 0;
  double strongest = 0;
  for (double a : model[1]) strongest = std::max(strongest, a);
  for (std::size_t b = 0; b < lead[1].size(); ++b) {
    if (with_line[1][b] > 0.5 * line && with_line[1][b] > 2 * model[1][b]) lead[1][b] = 1.3 * with_line[1][b], ++line_bins;
    if (model[1][b] > 0.1 * strongest) mesh_off[1][b] *= 1.3, ++mesh_bins;
  }
  ASSERT_GT(line_bins, 0);
  ASSERT_GT(mesh_bins, 0);
  cmp.set_reference(model, {});
  EXPECT_GT(cmp.score(lead, Half::HeldOut, {}, HousingGains::Given).chi2,
            cmp.null_quantile(lead, {}, Half::HeldOut, kAlphaHalf, 1))
      << "at the baseline's model no change is budgeted";
  cmp.set_discrepancy_reference(lead, {});
  EXPECT_LT(cmp.score(lead, Half::HeldOut, {}, HousingGains::Given).chi2,
            cmp.null_quantile(lead, {}, Half::HeldOut, kAlphaHalf, 1))
      << "30 % of the predicted change is within the budget of that change";
  // (2) Nothing changed in the mesh lines (the recording's baseline has them as the model does).
  const Recording same = synthetic(0.0, 7);
  ModelComparison diff_same(same, test::stage_1200rpm(), differential);
  diff_same.set_reference(model, {});
  EXPECT_GT(diff_same.score(mesh_off, Half::HeldOut, {}, HousingGains::Given).chi2,
            diff_same.null_quantile(mesh_off, {}, Half::HeldOut, kAlphaHalf))
      << "differential: a model-form error of the mesh lines is not budgeted";
  ModelComparison abs_same(same, test::stage_1200rpm(), co);
  abs_same.set_reference(model, {});
  EXPECT_LT(abs_same.score(mesh_off, Half::HeldOut, {}, HousingGains::Given).chi2,
            abs_same.null_quantile(mesh_off, {}, Half::HeldOut, kAlphaHalf))
      << "absolute: 30 % of a mesh line is within the calibrated 50 %";
}

/// The fit of a one-parameter "lead" whose change from `model` is theta times (with_line - model)
/// (the carrier-family line and nothing else), on the fit half of `cmp`.
LmResult fit_line_scale(const ModelComparison& cmp, const std::vector<std::vector<double>>& model,
                        const std::vector<std::vector<double>>& with_line) {
  auto lead_at = [&](double theta) {
    auto m = model;
    for (std::size_t c = 0; c < m.size(); ++c)
      for (std::size_t b = 0; b < m[c].size(); ++b) m[c][b] += theta * (with_line[c][b] - model[c][b]);
    return m;
  };
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    return cmp.score(lead_at(x[0]), Half::Fit, {}, HousingGains::Given).residual;
  };
  LmOptions o;
  o.max_iterations = 20;
  o.threads = 1;
  return levenberg_marquardt(f, {{0.0, 3.0, false}}, {0.5}, o);
}

TEST(Baseline, AFittedChangesModelFormUncertaintyIsTheBudgetTimesTheChange) {
  // Differential, a relative budget of 50 % on the carrier family: a model that gets the
  // transfer of the fitted change wrong by 50 % gets its size wrong by 50 %. The lead's only
  // change is the carrier line (strong: 5 m/s^2 against 0.5 of noise per sample, Rician slope
  // 1 to ~1e-4; an integer carrier order in whole revolutions, so it does not leak into weaker
  // bins), so the propagated model-form standard deviation of its scale theta is 0.5 theta; 1 %
  // allows for the Rician slope and the fit's finite differences. The noise's own standard error
  // is far smaller: the model-form term is what sizes it.
  const auto model = perfect_model();
  const double line = 5.0;
  const Recording clean_with_line = synthetic(line, 1, 1e-6, 1e-9);
  const auto with_line = ModelComparison(clean_with_line, test::stage_1200rpm()).spectra().amplitude[0];
  CompareOptions differential;
  differential.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.5, 0.0});
  differential.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Carrier, 0.5, 0.0, true});
  differential.baseline = baseline_of(synthetic(0.0, 12), model);
  const Recording rec = synthetic(line, 6);
  ModelComparison cmp(rec, test::stage_1200rpm(), differential);
  cmp.set_reference(model, {});
  const LmResult fit = fit_line_scale(cmp, model, with_line);
  ASSERT_EQ(fit.x.size(), 1u);
  EXPECT_NEAR(fit.x[0], 1.0, 0.1) << "the line is fitted at its size";
  auto fitted = model;
  for (std::size_t c = 0; c < fitted.size(); ++c)
    for (std::size_t b = 0; b < fitted[c].size(); ++b) fitted[c][b] += fit.x[0] * (with_line[c][b] - model[c][b]);
  const std::vector<double> sd = propagated_std(fit, cmp.model_form_shifts(fitted, {}));
  ASSERT_EQ(sd.size(), 1u);
  EXPECT_NEAR(sd[0], 0.5 * fit.x[0], 0.01 * fit.x[0]);
  EXPECT_LT(fit.std_error[0], 0.2 * sd[0]);
  // Without a budget there is no model-form shift, and at the baseline's model (nothing changed)
  // none either: what cancels in the change is not an uncertainty of its size.
  const Recording plain_rec = synthetic(line, 6);
  ModelComparison plain(plain_rec, test::stage_1200rpm());
  plain.set_reference(model, {});
  EXPECT_TRUE(plain.model_form_shifts(fitted, {}).empty());
  EXPECT_TRUE(cmp.model_form_shifts(model, {}).empty());
}

TEST(CalibratedDiscrepancy, ALineTheLeadAddsIsJudgedAgainstTheDiscrepancyAtTheLeadsOwnAmplitude) {
  // A candidate ("lead") adds the carrier-family line the reference (healthy) model lacks, 30 %
  // stronger than the recording's: a model-form error of the size the calibration allows
  // (relative 50 %). With the discrepancy taken at the reference, the cell's V holds the noise
  // only and the lead fails its own null; taken at the lead's amplitudes
  // (set_discrepancy_reference, the verdict's hypothesis "recording = lead + discrepancy") it
  // passes; and restoring the reference gives the reference's chi2 back exactly.
  CompareOptions co;
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.5, 0.0});
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Carrier, 0.5, 0.0, true});
  const double line = 5.0;  // [m/s^2], against 0.5 m/s^2 of white noise per sample
  const Recording rec = synthetic(line, 6);
  ModelComparison cmp(rec, test::stage_1200rpm(), co);
  const auto model = perfect_model();
  const Recording clean_with_line = synthetic(line, 1, 1e-6, 1e-9);
  const auto with_line = ModelComparison(clean_with_line, test::stage_1200rpm()).spectra().amplitude[0];
  auto lead = model;
  int line_bins = 0;
  for (std::size_t b = 0; b < lead[1].size(); ++b)
    if (with_line[1][b] > 0.5 * line && with_line[1][b] > 2 * model[1][b]) lead[1][b] = 1.3 * with_line[1][b], ++line_bins;
  ASSERT_GT(line_bins, 0);
  cmp.set_reference(model, {});
  const double chi_at_ref = cmp.score(lead, Half::HeldOut, {}, HousingGains::Given).chi2;
  const double q_at_ref = cmp.null_quantile(lead, {}, Half::HeldOut, kAlphaHalf, 1);
  EXPECT_GT(chi_at_ref, q_at_ref) << "the added line against the noise alone";
  cmp.set_discrepancy_reference(lead, {});
  const double chi_at_lead = cmp.score(lead, Half::HeldOut, {}, HousingGains::Given).chi2;
  const double q_at_lead = cmp.null_quantile(lead, {}, Half::HeldOut, kAlphaHalf, 1);
  EXPECT_LT(chi_at_lead, q_at_lead) << "30 % is within the discrepancy at the lead's own line";
  cmp.set_discrepancy_reference(model, {});
  EXPECT_EQ(cmp.score(lead, Half::HeldOut, {}, HousingGains::Given).chi2, chi_at_ref);
  EXPECT_EQ(cmp.null_quantile(lead, {}, Half::HeldOut, kAlphaHalf, 1), q_at_ref);
}

TEST(Baseline, NuisanceValuesAtAnEdgeOfTheirBoxAreListedWithThatEdgeAndGainsAreNot) {
  auto param = [](std::string name, double value, double lower, double upper, bool at_bound, bool gain = false) {
    FittedParameter p;
    p.name = std::move(name);
    p.value = value, p.lower = lower, p.upper = upper, p.at_bound = at_bound, p.sensor_gain = gain;
    return p;
  };
  const std::vector<FittedParameter> ps = {param("stiffness.scale", 1.9999, 0.5, 2.0, true),
                                           param("contact.mesh_damping_ratio", 0.0021, 0.002, 0.05, true),
                                           param("friction", 0.06, 0.0, 0.3, false),
                                           param("sensor.gain_m_s2_per_N", 3e-3, 0.0, 1.0, true, true)};
  const std::vector<std::string> t = bound_texts(ps);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0], "stiffness.scale at its upper bound 2");
  EXPECT_EQ(t[1], "contact.mesh_damping_ratio at its lower bound 0.002");
}

} // namespace
} // namespace pw::diagnose

namespace pw::diagnose {
namespace {

/// A nuisance value of the baseline's fit, at an edge of its box or not.
FittedParameter baseline_value(const std::string& name, double value, double lower, double upper, bool at_bound) {
  FittedParameter p = test::parameter(name, value, 0.0, lower, upper, value, true);
  p.at_bound = at_bound;
  return p;
}

TEST(BoundEnds, ListsTheBaselinesParametersAtAnEdgeByKeyWithTheEndAndSkipsGainsAndFits) {
  const FittedParameter k = baseline_value("stiffness.scale", 2.0, 0.5, 2.0, true);
  const FittedParameter z = baseline_value("contact.mesh_damping_ratio", 0.002, 0.002, 0.25, true);
  const FittedParameter inside = baseline_value("sensor.encoder_bandwidth_Hz", 800, 10, 1e6, false);
  FittedParameter gain = baseline_value("sensor.gain_m_s2_per_N", 3, 0, 1e6, true);
  gain.sensor_gain = true;
  const std::map<std::string, int> ends = bound_ends({k, z, inside, gain});
  ASSERT_EQ(ends.size(), 2u);
  EXPECT_EQ(ends.at("stiffness.scale"), +1);
  EXPECT_EQ(ends.at("contact.mesh_damping_ratio"), -1);
  // The same parameters as the report's texts.
  EXPECT_EQ(bound_texts({k, z, inside, gain}).size(), 2u);
}

// "The same operating point" for a healthy reference: speed within the mesh damping ratio,
// power within kRecalibration (5 %), both relative to the recording's; a baseline at another
// operating point is still compared, but its level changes are not tested
// (DiagnoseOptions::baseline_at_operating_point). The boundaries are inclusive.
TEST(OperatingPoint, AReferenceIsTheSameOperatingPointOnlyWithinTheDampingRatioInSpeedAndFivePercentInPower) {
  const double zeta = 0.05;
  const OperatingPointDistance same = operating_point_distance(1200, 20000, 1200, 20000, zeta);
  EXPECT_TRUE(same.same);
  EXPECT_EQ(same.speed, 0.0);
  EXPECT_EQ(same.power, 0.0);
  // 4 % slower, 4 % less power: inside both.
  EXPECT_TRUE(operating_point_distance(1200, 20000, 1152, 19200, zeta).same);
  // Half the speed (a calibration's other operating point, indepsim4's 600 vs 1200 rpm): not the same.
  const OperatingPointDistance half = operating_point_distance(1200, 50000, 600, 40000, zeta);
  EXPECT_FALSE(half.same);
  EXPECT_DOUBLE_EQ(half.speed, 0.5);
  EXPECT_DOUBLE_EQ(half.power, 0.2);
  // The speed alone, or the power alone, outside: not the same.
  EXPECT_FALSE(operating_point_distance(1200, 20000, 1300, 20000, zeta).same);   // 8.3 % in speed
  EXPECT_FALSE(operating_point_distance(1200, 20000, 1200, 22000, zeta).same);   // 10 % in power
  // The speed bound is the damping ratio: 8.3 % is the same for a 10 % damped mesh.
  EXPECT_TRUE(operating_point_distance(1200, 20000, 1300, 20000, 0.10).same);
}

} // namespace
} // namespace pw::diagnose
