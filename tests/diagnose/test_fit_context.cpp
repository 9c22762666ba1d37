// fit_context.hpp: the size range a model-form budget allows (model_form_range) and the variance
// a line-counting encoder's unknown phase leaves (with_encoder_phase_variance).
#include "diagnose/fit_context.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace pw::diagnose {
namespace {

constexpr double kZ = 2.5758293035489;  // z_{1 - 0.01/2}

TEST(ModelFormRange, AScaledChangeGivesTheSizeOverOnePlusOrMinusZTimesTheRelativeError) {
  // A tooth stiffness factor 0.75 (absent: 1, size s = -0.25) with a model-form standard
  // deviation 0.05 (r = z 0.05 / 0.25 = 0.515): the true size is s / (1 + r) to s / (1 - r),
  // factors 1 - 0.25/1.515 = 0.8350 and 1 - 0.25/0.485 = 0.4845, and the noise widens each end
  // by z standard errors.
  const SizeRange r = model_form_range(0.75, 1.0, 0.0, 0.05, kZ, 0.05, 1.0);
  const double rr = kZ * 0.05 / 0.25;
  EXPECT_NEAR(r.upper, 1 - 0.25 / (1 + rr), 1e-12);
  EXPECT_NEAR(r.lower, 1 - 0.25 / (1 - rr), 1e-12);
  EXPECT_GT(0.75 - r.lower, r.upper - 0.75) << "lopsided: a smaller model change stands for a larger size";
  const SizeRange n = model_form_range(0.75, 1.0, 0.01, 0.05, kZ, 0.05, 1.0);
  EXPECT_NEAR(n.upper - r.upper, kZ * 0.01, 1e-12);
  EXPECT_NEAR(r.lower - n.lower, kZ * 0.01, 1e-12);
}

TEST(ModelFormRange, ABudgetAsLargeAsTheSizeLeavesItUnboundedTowardsTheBoxEdge) {
  // A runout of 0.5 um with a model-form standard deviation of 0.3 um: z r > 1, so any larger
  // runout up to the box is allowed; the smallest is 0.5 / (1 + r).
  const SizeRange r = model_form_range(0.5e-6, 0.0, 0.0, 0.3e-6, kZ, 1e-8, 5e-5);
  EXPECT_DOUBLE_EQ(r.upper, 5e-5);
  EXPECT_NEAR(r.lower, 0.5e-6 / (1 + kZ * 0.3 / 0.5), 1e-18);
  // Growing from the absent value downwards (a friction below its documented level) alike.
  const SizeRange f = model_form_range(0.04, 0.06, 0.0, 0.02, kZ, 0.0, 0.4);
  EXPECT_DOUBLE_EQ(f.lower, 0.0);
  EXPECT_NEAR(f.upper, 0.06 - 0.02 / (1 + kZ), 1e-15);
}

TEST(ModelFormRange, WithoutABudgetItIsTheNoisesIntervalKeptInTheBox) {
  const SizeRange r = model_form_range(0.6, 1.0, 0.01, 0.0, kZ, 0.05, 1.0);
  EXPECT_NEAR(r.lower, 0.6 - kZ * 0.01, 1e-12);
  EXPECT_NEAR(r.upper, 0.6 + kZ * 0.01, 1e-12);
  const SizeRange edge = model_form_range(0.99, 1.0, 0.01, 0.0, kZ, 0.05, 1.0);
  EXPECT_DOUBLE_EQ(edge.upper, 1.0);
  const SizeRange nan = model_form_range(0.6, 1.0, 0.01, std::nan(""), kZ, 0.05, 1.0);
  EXPECT_NEAR(nan.upper, 0.6 + kZ * 0.01, 1e-12);
}

TEST(HoldNuisance, AHeldCandidateLeavesTheVectorsWithAllItsParametersAtTheirSpecsStarts) {
  auto spec = [](const std::string& name, double initial) {
    ParameterSpec p;
    p.name = name;
    p.initial = initial;
    return p;
  };
  // Three nuisance candidates of 1, 2 and 1 parameters; the two-parameter one is held.
  const std::vector<std::vector<ParameterSpec>> specs = {
      {spec("stiffness.scale", 1.0)},
      {spec("rig.input_shaft_stiffness_N_m_rad", 2e4), spec("rig.input_shaft_damping_N_m_s_rad", 4.0)},
      {spec("contact.mesh_damping_ratio", 0.05)}};
  const std::vector<double> fitted = {1.1, 3e4, 5.0, 0.07}, start = {1.2, 3.5e4, 6.0, 0.25};
  const HeldNuisance h = hold_nuisance(specs, {false, true, false}, fitted, start);
  EXPECT_EQ(h.free, (std::vector<std::size_t>{0, 2}));
  EXPECT_EQ(h.fitted, (std::vector<double>{1.1, 0.07}));
  EXPECT_EQ(h.start, (std::vector<double>{1.2, 0.25}));
  ASSERT_EQ(h.held.size(), 2u);
  EXPECT_EQ(h.held[0].rfind("rig.input_shaft_stiffness_N_m_rad=", 0), 0u);
  EXPECT_DOUBLE_EQ(std::stod(h.held[0].substr(h.held[0].find('=') + 1)), 2e4);
  EXPECT_DOUBLE_EQ(std::stod(h.held[1].substr(h.held[1].find('=') + 1)), 4.0);
  // Nothing held: the vectors as they were.
  const HeldNuisance none = hold_nuisance(specs, {false, false, false}, fitted, start);
  EXPECT_EQ(none.fitted, fitted);
  EXPECT_EQ(none.start, start);
  EXPECT_TRUE(none.held.empty());
  // Vectors shorter than the specs are refused, not read past their end.
  EXPECT_THROW(hold_nuisance(specs, {true, false, false}, std::vector<double>{1.0}, std::vector<double>{1.0}),
               SolverError);
}


TEST(EncoderPhaseVariance, IsTheVarianceOfTheDifferenceOfTwoAmplitudesAtIndependentUniformPhases) {
  // A bin holding gear content G and an encoder image I whose phase phi the rig does not know:
  // its amplitude is |G + I e^{i phi}|. The recording and the model (or the baseline) each have a
  // phase of their own, so the comparison sees |G + I e^{i phi1}| - |G + I e^{i phi2}|; its
  // variance over independent uniform phases (numerical quadrature on 720 x 720 phases) must be
  // what the four-phase estimate gives (tolerance 2 %: its error is of order (|I| / |G|)^2, 1 %
  // at |I| / |G| = 0.1).
  // A bin without an image gets nothing; leak variance already there is kept.
  const double kTwoPi = 2 * std::numbers::pi;
  for (const double ratio : {0.01, 0.1}) {
    const double G = 1.0, I = ratio * G;
    auto amplitude = [&](double phi) { return std::abs(std::complex<double>(G) + I * std::polar(1.0, phi)); };
    std::vector<ModelSpectra> phases(4);
    std::vector<const ModelSpectra*> ptr;
    for (int k = 0; k < 4; ++k) {
      phases[static_cast<std::size_t>(k)].amplitude = {{amplitude(kTwoPi * k / 4), 5.0}};  // bin 1: no image
      phases[static_cast<std::size_t>(k)].leak_variance = {{0.0, 0.25}};
      ptr.push_back(&phases[static_cast<std::size_t>(k)]);
    }
    const auto m = with_encoder_phase_variance(phases[0], ptr);
    const int n = 720;
    double sum = 0, sum2 = 0;
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) {
        const double d = amplitude(kTwoPi * a / n) - amplitude(kTwoPi * b / n);
        sum += d;
        sum2 += d * d;
      }
    const double var = sum2 / (n * n) - (sum / (n * n)) * (sum / (n * n));
    EXPECT_NEAR(m->leak_variance[0][0], var, 0.02 * var) << "|I|/|G| = " << ratio;
    EXPECT_NEAR(var, I * I, 0.02 * I * I) << "to first order the difference's variance is |I|^2";
    EXPECT_EQ(m->leak_variance[0][1], 0.25) << "a bin the encoder's phase does not move keeps its leak variance";
    EXPECT_EQ(m->amplitude, phases[0].amplitude) << "the centre's amplitudes are the reference's";
  }
}

} // namespace
} // namespace pw::diagnose
