// The recording-side noise model of the comparison (compare.hpp): the
// dispersion phi measured between the recording's two halves. No simulation is
// run: ModelComparison analyses the recording in its constructor.
//
// The recording is synthetic: the seed stage at 1200 rpm (mesh frequency
// 333.5 Hz, carrier revolution 0.243 s), 3.2 carrier revolutions at 10 kHz; a
// sun-speed channel (constant + white noise) and a sun-planet mesh
// acceleration made of 8 mesh harmonics plus white noise.
#include "core/error.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/stage_1200rpm.hpp"
#include "io/config_toml.hpp"
#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace pw::diagnose {
namespace {


using test::stage_1200rpm;

using test::synthetic;

// The model a diagnosis simulates resolves the analysed band (0.3 f_s), not every mode; a
// configuration that states a step or a band keeps its own.
/// Monte-Carlo variance of |G + sum_l L_l e^{i phi_l}| - |G + sum_l L_l e^{i psi_l}|, phases uniform.
double mc_difference_variance(double g, const std::vector<double>& leaks, int draws) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 2 * std::numbers::pi);
  auto amp = [&] {
    std::complex<double> z(g, 0);
    for (const double l : leaks) z += std::polar(l, u(rng));
    return std::abs(z);
  };
  double s = 0, s2 = 0;
  for (int k = 0; k < draws; ++k) {
    const double d = amp() - amp();
    s += d, s2 += d * d;
  }
  return s2 / draws - (s / draws) * (s / draws);
}

TEST(UnknownPhaseVariance, SmallLeaksBesideALargeLineGiveTheirSummedPower) {
  // G = 1, leaks 0.05 and 0.03: to first order each amplitude is G + sum L_l cos(phi_l), variance
  // sum L_l^2 / 2, their difference sum L_l^2 = 0.0034. 4e5 draws: Monte-Carlo error of a variance
  // ~ sqrt(2 / n) = 0.2 %; the first-order approximation's error is O(L^2 / G^2) ~ 0.3 %. 2 %.
  const double want = unknown_phase_difference_variance(1.0, 0.05 * 0.05 + 0.03 * 0.03, 0.05 * 0.05);
  EXPECT_NEAR(want, 0.0034, 1e-15);
  const double got = mc_difference_variance(1.0, {0.05, 0.03}, 400000);
  EXPECT_NEAR(got / want, 1.0, 0.02) << got;
}

TEST(UnknownPhaseVariance, ALeakLargerThanTheGearLineIsCountedAsTheLargeTerm) {
  // A line's leak of 1 beside gear content 0.1: the roles swap, P - D = G^2 = 0.01.
  const double want = unknown_phase_difference_variance(0.1, 1.0, 1.0);
  EXPECT_NEAR(want, 0.01, 1e-15);
  EXPECT_NEAR(mc_difference_variance(0.1, {1.0}, 400000) / want, 1.0, 0.02);
}

TEST(UnknownPhaseVariance, TwoEqualTermsAreOverstatedNotUnderstated) {
  // |1 + e^{i phi}| = 2 |cos(phi / 2)|: mean 4/pi, second moment 2, variance 2 - 16/pi^2; the
  // difference of two: 4 - 32/pi^2 = 0.758. P - D = 1: conservative by a third, never below.
  const double exact = 4 - 32 / (std::numbers::pi * std::numbers::pi);
  const double mc = mc_difference_variance(1.0, {1.0}, 400000);
  EXPECT_NEAR(mc / exact, 1.0, 0.02);
  EXPECT_GT(unknown_phase_difference_variance(1.0, 1.0, 1.0), exact);
  EXPECT_LT(unknown_phase_difference_variance(1.0, 1.0, 1.0), 1.5 * exact);
}

TEST(Compare, TheModelsAutomaticStepResolvesTheAnalysedBandUnlessTheConfigurationStatesOne) {
  const Recording rec = synthetic(0.0, 0.0, 3);
  const double band = 0.3 / rec.sample_interval_s();  // LayoutOptions::band_fraction of f_s
  EXPECT_DOUBLE_EQ(ModelComparison(rec, stage_1200rpm()).base().solver.accuracy_band_Hz, band);
  model::SimulationConfig stated = stage_1200rpm();
  stated.solver.accuracy_band_Hz = 1234.5;
  EXPECT_EQ(ModelComparison(rec, stated).base().solver.accuracy_band_Hz, 1234.5);
  model::SimulationConfig fixed = stage_1200rpm();
  fixed.solver.time_step_s = 2e-6;
  EXPECT_EQ(ModelComparison(rec, fixed).base().solver.accuracy_band_Hz, 0.0);
}

TEST(Compare, DispersionStaysOneWhenTheHalvesAgreeEvenWithAStationaryFaultLine) {
  // A stationary line 10x the noise at a carrier sideband is the same in both halves: it
  // cancels in A_1 - A_2 and must not be read as extra noise.
  const Recording rec = synthetic(0.0, 5.0, 3);
  const ModelComparison cmp(rec, stage_1200rpm());
  ASSERT_EQ(cmp.channels(), 2);
  EXPECT_EQ(cmp.dispersion(0), 1.0);
  EXPECT_EQ(cmp.dispersion(1), 1.0);
}

TEST(Compare, DispersionMeasuresTheSkirtOfAJitteredMeshHarmonic) {
  // Phase wander of 2e-3 rad per sample: over a carrier revolution (2430 samples) the
  // mesh phase walks ~0.1 rad (harmonic 8: ~0.8 rad), a skirt over the sideband cells that
  // changes between the halves while the floor between the sideband groups does not see it.
  // phi is set only when it exceeds 1 beyond its sampling error, and more wander gives a
  // wider skirt, so phi grows with it.
  const Recording rec = synthetic(2e-3, 0.0, 4);
  const ModelComparison cmp(rec, stage_1200rpm());
  EXPECT_EQ(cmp.dispersion(0), 1.0);  // the speed channel has no jitter
  EXPECT_GT(cmp.dispersion(1), 1.0);
  const Recording more_rec = synthetic(4e-3, 0.0, 4);
  const ModelComparison more(more_rec, stage_1200rpm());
  EXPECT_GT(more.dispersion(1), cmp.dispersion(1));
}

TEST(Compare, DriftColumnTakesALinearAngleReferenceErrorWithItsSignAndSizeAndRemovesItsLeak) {
  // Copies of one recording (the same noise draws): "exact" with a noiseless speed channel (its
  // amplitudes serve as the model); "clean" with speed-channel noise, whose integral, the angle
  // reference, wanders by a random drift delta_0 over each window; and "biased" copies of the
  // clean one whose speed channel reads eps too high (a calibration error): the angle reads
  // delta = 2 pi R eps more at the end of each window, and every strong line leaks
  // ~A o delta / (2 pi d) into the bins d away. Scored against the exact amplitudes, the drift
  // column (compare.hpp: sd times the amplitudes' derivative under the *correction* of the
  // angle, weight z ~ N(0, 1)) must
  // (a) carry the injected drift with a minus sign and its size: dz = z_biased - z_clean (both
  //     carry the same -delta_0 / sd) lies in [-delta/sd, -delta/(2 sd)]. The fit is ridge-like,
  //     dz = -(delta/sd) S/(1 + S) with S = u'D^-1u; S >= 1 when the column resolves a drift of
  //     one standard deviation. S is not a constant: the derivative is taken at the recording,
  //     whose leak bins also hold noise (|n + delta g| turns linear in delta only well above
  //     the floor), so dz is not exactly proportional to delta (measured: 53–63 % of delta/sd at
  //     4 sd in the two windows, 74 % at 8 sd); a larger drift must still get a larger weight;
  // (b) remove most of the leak's chi2: the biased copy's chi2 exceeds the clean one's by
  //     less than half of what the leak adds without a column (summed squared amplitude
  //     differences over the noise variance).
  // A column of the wrong sign, a wrong scale (a lost 2 pi or R) or no column fails (a).
  // Low acceleration noise puts the leaks of a few-sd drift well above the floor; at 0.05 m/s^2
  // they sit at it and the amplitude-domain linearization takes only ~40 % of a 4 sd drift.
  const double noise = 0.005;  // m/s^2 per sample: lines of 10/h m/s^2 stand 2000:1 above it
  const Recording exact_rec = synthetic(0.0, 0.0, 7, 0.0, noise, 1e-9);
  const ModelComparison exact(exact_rec, stage_1200rpm());
  const Recording clean_rec = synthetic(0.0, 0.0, 7, 0.0, noise);
  const ModelComparison clean(clean_rec, stage_1200rpm());
  const double sd = clean.angle_drift_std_rad();
  ASSERT_GT(sd, 0.0);
  const int R = clean.spectra().layout.revolutions, nc = clean.channels(), ncell = clean.cells();
  double dz_first = 0;
  for (double drift_in_sd : {4.0, 8.0}) {
    const double delta = drift_in_sd * sd, eps = delta / (2 * kPi * R);
    const Recording biased_rec = synthetic(0.0, 0.0, 7, eps, noise);
    const ModelComparison biased(biased_rec, stage_1200rpm());
    ASSERT_NEAR(biased.angle_drift_std_rad(), sd, 0.05 * sd);  // the bias does not change the noise
    for (int w = 0; w < 2; ++w) {
      const auto& model = exact.spectra().amplitude[static_cast<std::size_t>(w)];
      const WindowScore c = clean.score(model, half_of_window(w), {}, HousingGains::Given);
      const WindowScore b = biased.score(model, half_of_window(w), {}, HousingGains::Given);
      ASSERT_FALSE(b.fidelity_z.empty());
      const double dz = b.fidelity_z.back() - c.fidelity_z.back();
      EXPECT_LT(dz, -0.5 * drift_in_sd) << drift_in_sd << " sd, window " << w;
      EXPECT_GT(dz, -drift_in_sd) << drift_in_sd << " sd, window " << w;
      if (drift_in_sd == 4.0 && w == 0) dz_first = dz;
      if (drift_in_sd == 8.0 && w == 0) {
        EXPECT_GT(dz / dz_first, 1.5);
      }
      double leak = 0;
      for (int ch = 0; ch < nc; ++ch)
        for (int i = 0; i < ncell; ++i) {
          const auto k = static_cast<std::size_t>(clean.spectra().layout.cells[static_cast<std::size_t>(i)].bin);
          const double d = biased.spectra().amplitude[static_cast<std::size_t>(w)][static_cast<std::size_t>(ch)][k] -
                           clean.spectra().amplitude[static_cast<std::size_t>(w)][static_cast<std::size_t>(ch)][k];
          leak += d * d / clean.spectra().noise_variance[static_cast<std::size_t>(ch)][static_cast<std::size_t>(i)];
        }
      EXPECT_GT(leak, 50.0) << drift_in_sd << " sd, window " << w;  // the leak is far above the noise
      EXPECT_LT(b.chi2 - c.chi2, 0.5 * leak) << drift_in_sd << " sd, window " << w;
    }
  }
}

// The angle reference integrates the speed channel's noise: a random walk whose Brownian bridge
// over a window leaks every strong line into its neighbouring bins (order_analysis.hpp). The
// bridge is one realization per window: its Fourier coefficient c_d is shared by every cell d
// bins from a line, in every channel, so the leaks rise and fall together. In a cell whose
// variance is leak-dominated the chi2 term follows g_d = |c_d|^2 / E|c_d|^2 ~ Exp(1) (variance
// 1), so the null's chi2 must gain at least about sum_d L_d^2 of variance, L_d = sum over cells
// of leak_d / s2 (the chi2 that distance's leak carries); drawn independently per cell, as
// the comparison did before, it gains only ~sum_f (leak_f / s2_f)^2, a few per cent of that here.
// Lines 1000:1 above the acceleration noise, a speed channel noisy enough that the 16 cells at
// each distance are leak-dominated (L_d ~ 15). The quiet twin has the same acceleration noise and
// a noise-free speed channel: no bridge. The bound 0.5 allows the Rician cells' response below
// linear and the ~10 % sampling error of two 68 % half-widths from 2000 draws; 3 is far above
// what the skew of Exp(1) (its upper tail) adds to a 68 % half-width.
TEST(Compare, NullDrawsTheAngleBridgeLeakOncePerWindowForEveryCell) {
  const Recording exact_rec = synthetic(0.0, 0.0, 1, 0.0, 1e-6, 1e-9);
  const auto model = ModelComparison(exact_rec, stage_1200rpm()).spectra().amplitude[1];
  constexpr double kAccNoise = 0.01, kSpeedNoise = 0.05;  // per sample: m/s^2, rad/s
  const Recording rec = synthetic(0.0, 0.0, 100, 0.0, kAccNoise, kSpeedNoise);
  const Recording quiet_rec = synthetic(0.0, 0.0, 100, 0.0, kAccNoise, 1e-9);
  const ModelComparison cmp(rec, stage_1200rpm()), quiet(quiet_rec, stage_1200rpm());
  ASSERT_EQ(cmp.features(), quiet.features());
  ASSERT_FALSE(cmp.spectra().bridge_leak.empty());
  EXPECT_TRUE(quiet.spectra().bridge_leak.empty() || quiet.angle_drift_std_rad() < 1e-6 * cmp.angle_drift_std_rad());
  std::array<double, RecordingSpectra::kBridgeBins> L{};
  double independent = 0;
  for (int c = 0; c < cmp.channels(); ++c)
    for (int i = 0; i < cmp.cells(); ++i) {
      const int f = c * cmp.cells() + i;
      const auto& by_d = cmp.spectra().bridge_leak[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
      double x = 0;
      for (std::size_t d = 0; d < L.size(); ++d) {
        L[d] += by_d[d] / cmp.noise_variance(f);
        x += by_d[d] / cmp.noise_variance(f);
      }
      independent += x * x;
    }
  double shared = 0;
  for (double l : L) shared += l * l;
  ASSERT_GT(L[0], 10.0);  // leak-dominated cells exist at one bin
  EXPECT_LT(independent, 0.1 * shared);
  auto half_width = [&](const ModelComparison& m) {
    return 0.5 * (m.null_quantile(model, {}, Half::HeldOut, 0.1587) - m.null_quantile(model, {}, Half::HeldOut, 0.8413));
  };
  const double w = half_width(cmp), w0 = half_width(quiet);
  const double gained = w * w - w0 * w0;
  EXPECT_GT(gained, 0.5 * shared) << "half-widths " << w << " (bridge) and " << w0 << " (quiet)";
  EXPECT_LT(gained, 3.0 * shared) << "half-widths " << w << " (bridge) and " << w0 << " (quiet)";
}

// The simulation cache key is derived from the configuration schema: any one
// key changed gives another key (a stale key would reuse the simulation of a
// different configuration). Every key of io::config_keys() is changed in turn
// through the reader's own --set path, so a key the cache key missed fails here.
TEST(Compare, BuiltinCacheKeyChangesWhenAnyOneKeyOfTheSchemaChanges) {
  model::SimulationConfig base{};
  io::apply_override(base, "imperfections.teeth[0].tooth", "1");  // one tooth modifier to vary
  const std::string base_key = builtin_config_key(base);
  const std::string base_toml = io::to_toml(base);
  const std::vector<std::string> enum_names{"torsional", "lateral_torsional", "gaussian", "hann", "power",
                                            "torque",    "speed",             "sun",      "planet", "ring",
                                            "nominal_time", "ring_translation"};
  int changed = 0;
  for (const auto& key : io::config_keys()) {
    std::string path = key.path;
    const auto element = path.find("[]");
    if (element != std::string::npos) path.replace(element, 2, "[0]");
    std::vector<std::string> values;
    if (key.type == "float") values = {"0.987654321", "1.5"};
    else if (key.type == "integer") values = {"7", "2"};
    else if (key.type == "boolean") values = {"true", "false"};
    else if (key.type == "array of floats") values = {"[0.5]"};
    else if (key.type == "string") values = enum_names;
    else if (key.type == "array of tables") values = {"[{body=\"ring\",tooth=3,stiffness_factor=0.5}]"};
    bool varied = false;
    for (const auto& v : values) {
      model::SimulationConfig c = base;
      try {
        io::apply_override(c, path, v);
      } catch (const InputError&) {
        continue;  // not a value of this key (an enumeration's other names)
      }
      if (io::to_toml(c) == base_toml) continue;  // the value it already had
      EXPECT_NE(builtin_config_key(c), base_key) << path << " = " << v;
      varied = true;
      break;
    }
    EXPECT_TRUE(varied) << "no value changed " << path;
    changed += varied;
  }
  EXPECT_EQ(changed, static_cast<int>(io::config_keys().size()));
}


// The band step is ModelComparison's choice (0.3 of the sample rate): where a simulation runs
// away at it (model::Integration::step's solver error) evaluate() runs it at the model's own
// step instead of failing or, as before 2026-11-28, comparing the run-away record. Case: the
// seed stage at 100 rpm / 10 kW, a 2 s recording at 10 kHz (band 3 kHz: a 10.4 us step), and a
// 5 % torque ripple: measured to run away at the band step after 0.62 s, and to reach its steady
// state at the model's own 2.8 us (until session 64 a sun runout of 1 pm did, through the
// warm-up of tooth-level features from the static start; test_simulation.cpp).
TEST(Compare, ASimulationThatRunsAwayAtTheBandStepIsRunAgainAtTheModelsOwnStep) {
  model::SimulationConfig cfg;
  cfg.operating.input_speed_rpm = 100;
  cfg.operating.input_power_W = 10000;
  const double fs = 10000;  // test::synthetic_of's sample rate [Hz]
  const Recording r = test::synthetic_of(cfg, 2.0, 0.0, 0.0, 3);
  const ModelComparison cmp(r, cfg);
  ASSERT_DOUBLE_EQ(cmp.base().solver.accuracy_band_Hz, 0.3 * fs);
  model::SimulationConfig c = cmp.base();
  c.imperfections.torque_ripple_fraction = 0.05;
  EXPECT_THROW((void)model::simulate(c), SolverError);  // at the band step
  const ModelSpectra s = cmp.evaluate(c, false);
  c.solver.accuracy_band_Hz = 0;
  EXPECT_DOUBLE_EQ(s.time_step_s, model::prepare(c).time_step_s);  // the model's own step
  EXPECT_NEAR(s.mean_input_rpm, 100.0, 1.0);
  for (const auto& channel : s.amplitude)
    for (double v : channel) ASSERT_TRUE(std::isfinite(v));
}

// The own null of a fitted model (verdict.hpp, condition (a)) is drawn with its model-fidelity
// weights z folded into its lines, |a + z u|, or added to the residual as chi2_of profiles them.
// Where |u| is small beside the lines the two agree; where u is of the lines' size the fold
// leaves residuals the linear profile cannot take out and the folded quantile grows with |u|,
// so that a model wrong by far more than the noise passes it (seed3p rec_36, session 34). The
// linear one stays near the noise quantile: under r = noise + z u, chi2 = r'(D + u u')^-1 r is
// chi2(m) whatever |u|.
TEST(Compare, AFoldedOwnNullGrowsWithFidelityOfTheLinesSizeWhileTheLinearOneStaysWithTheNoise) {
  const Recording rec = synthetic(0.0, 0.0, 11);
  const Recording clean = synthetic(0.0, 0.0, 1, 0.0, 1e-6, 1e-9);
  const auto model = ModelComparison(clean, stage_1200rpm()).spectra().amplitude[0];
  ModelComparison cmp(rec, stage_1200rpm());
  cmp.set_reference(model, {});
  auto set_u = [&](double scale) {
    std::vector<std::vector<double>> u(1, std::vector<double>(static_cast<std::size_t>(cmp.features()), 0.0));
    for (int c = 0; c < cmp.channels(); ++c)
      for (int i = 0; i < cmp.cells(); ++i) {
        const auto bin = static_cast<std::size_t>(cmp.spectra().layout.cells[static_cast<std::size_t>(i)].bin);
        // Of either sign from cell to cell, as a discretization change of many lines is: a
        // column proportional to the lines would only rescale them, which the fold keeps linear.
        u[0][static_cast<std::size_t>(c * cmp.cells() + i)] = (i % 2 ? -scale : scale) * model[static_cast<std::size_t>(c)][bin];
      }
    cmp.set_fidelity(u, {"discretization"}, 0);
  };
  constexpr double alpha_half = 0.005;
  auto bound = [&](FidelityDraw draw) { return cmp.null_quantile(model, {}, Half::HeldOut, alpha_half, 1, draw); };
  const double m = cmp.features();
  set_u(0.01);
  const double folded_small = bound(FidelityDraw::Folded), linear_small = bound(FidelityDraw::Linear);
  // The same random numbers: only the fold and the second order of the hypot differ.
  EXPECT_NEAR(folded_small, linear_small, 0.02 * linear_small);
  // m features of mean 1, a 1 - 0.005 quantile a few sqrt(2 m) above, + 2 chi2(1).
  EXPECT_NEAR(linear_small, m + 2.58 * std::sqrt(2 * m), 4 * std::sqrt(2 * m));
  set_u(3.0);
  const double folded_large = bound(FidelityDraw::Folded), linear_large = bound(FidelityDraw::Linear);
  EXPECT_NEAR(linear_large, linear_small, 4 * std::sqrt(2 * m));
  EXPECT_GT(folded_large, 3 * linear_large) << "m " << m;
  // A model with its lines at half the recording's, scored against it with u three times its
  // lines: its chi2 is many times the linear null, and still under the folded one.
  auto half = model;
  for (auto& channel : half)
    for (double& v : channel) v *= 0.5;
  cmp.set_reference(half, {});
  const double chi2 = cmp.score(half, Half::HeldOut, {}, HousingGains::Given).chi2;
  EXPECT_GT(chi2, 10 * cmp.null_quantile(half, {}, Half::HeldOut, alpha_half, 1, FidelityDraw::Linear));
  EXPECT_LT(chi2, cmp.null_quantile(half, {}, Half::HeldOut, alpha_half, 1, FidelityDraw::Folded));
}

// null_quantiles draws the folded and the linear null in one pass over one sequence of random
// numbers; each must be the quantile a pass for that form alone gives, to the last bit, with
// every optional draw present (fidelity column, calibrated relative and absolute discrepancy,
// parameters fitted on the other half), so that the diagnosis's bounds did not move when the
// two passes were merged.
TEST(Compare, BothNullFormsFromOnePassEqualTheirSeparatePassesBitForBit) {
  CompareOptions co;
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.3, 1e-4});
  const Recording rec = synthetic(0.0, 0.0, 11);
  const Recording clean = synthetic(0.0, 0.0, 1, 0.0, 1e-6, 1e-9);
  const auto model = ModelComparison(clean, stage_1200rpm()).spectra().amplitude[0];
  ModelComparison cmp(rec, stage_1200rpm(), co);
  cmp.set_reference(model, {});
  std::vector<std::vector<double>> u(1, std::vector<double>(static_cast<std::size_t>(cmp.features()), 0.0));
  for (int c = 0; c < cmp.channels(); ++c)
    for (int i = 0; i < cmp.cells(); ++i) {
      const auto bin = static_cast<std::size_t>(cmp.spectra().layout.cells[static_cast<std::size_t>(i)].bin);
      u[0][static_cast<std::size_t>(c * cmp.cells() + i)] = (i % 2 ? -0.5 : 0.5) * model[static_cast<std::size_t>(c)][bin];
    }
  cmp.set_fidelity(u, {"discretization"}, 0);
  constexpr double alpha_half = 0.005;
  for (const Half half : {Half::Fit, Half::HeldOut})
    for (int k : {0, 2}) {
      const ModelComparison::NullPair both = cmp.null_quantiles(model, {}, half, alpha_half, k);
      EXPECT_EQ(both.folded, cmp.null_quantile(model, {}, half, alpha_half, k, FidelityDraw::Folded)) << k;
      EXPECT_EQ(both.linear, cmp.null_quantile(model, {}, half, alpha_half, k, FidelityDraw::Linear)) << k;
      // The fidelity column is half the lines' size: the fold widens the folded null, so the two
      // forms are different numbers and the equalities above compare each with its own pass.
      EXPECT_NE(both.folded, both.linear);
      const ModelComparison::OwnNull own = cmp.own_null(model, {}, half, alpha_half, k);
      EXPECT_EQ(own.folded, both.folded);
      EXPECT_EQ(own.bound, std::min(both.folded, both.linear));
    }
}

// A calibration estimates the discrepancy against what the noise alone explains; when V already
// carries a budget (a model-form weighted refit, HealthyFit::ModelForm) that yardstick must be the
// noise's, or the refit would measure only the excess beyond its own weights.
TEST(Compare, NoiseDiagonalVarianceIsWhatVHoldsWithoutTheCalibratedDiscrepancy) {
  const Recording rec = synthetic(0.0, 0.0, 11);
  const Recording clean = synthetic(0.0, 0.0, 1, 0.0, 1e-6, 1e-9);
  const auto model = ModelComparison(clean, stage_1200rpm()).spectra().amplitude[0];
  CompareOptions co;
  co.discrepancy.push_back({Quantity::MeshAccelerationSunPlanet, Component::Mesh, 0.3, 1e-4});
  ModelComparison plain(rec, stage_1200rpm());
  ModelComparison budgeted(rec, stage_1200rpm(), co);
  plain.set_reference(model, {});
  budgeted.set_reference(model, {});
  ASSERT_EQ(plain.features(), budgeted.features());
  int inflated = 0;
  for (int w = 0; w < 2; ++w)
    for (int f = 0; f < plain.features(); ++f) {
      EXPECT_EQ(plain.noise_diagonal_variance(w, f), plain.diagonal_variance(w, f)) << f;
      // One subtraction of what was added: round-off of the sum only.
      EXPECT_NEAR(budgeted.noise_diagonal_variance(w, f), plain.diagonal_variance(w, f),
                  1e-12 * budgeted.diagonal_variance(w, f)) << f;
      if (budgeted.diagonal_variance(w, f) > 1.01 * budgeted.noise_diagonal_variance(w, f)) ++inflated;
    }
  EXPECT_GT(inflated, 0);  // the budget is in V: the test compares two different numbers
}

} // namespace
} // namespace pw::diagnose
