// Amplitude spectrum, Welch PSD and peak picking against signals whose
// spectra are known in closed form (docs/spectra.md).
#include "core/constants.hpp"
#include "core/error.hpp"
#include "signal/spectrum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <vector>

namespace {

using pw::signal::Window;
using pw::kPi;

std::vector<double> sine(std::size_t n, double dt, double amplitude, double f_Hz, double phase = 0) {
  std::vector<double> x(n);
  for (std::size_t j = 0; j < n; ++j)
    x[j] = amplitude * std::sin(2 * kPi * f_Hz * static_cast<double>(j) * dt + phase);
  return x;
}

// Gaussian white noise, bit-reproducible: splitmix64 + Box-Muller.
std::vector<double> white_noise(std::size_t n, double sigma, std::uint64_t seed) {
  std::uint64_t s = seed;
  auto uniform = [&s] {
    s += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
  };
  std::vector<double> x(n);
  for (auto& v : x) v = sigma * std::sqrt(-2 * std::log(uniform())) * std::cos(2 * kPi * uniform());
  return x;
}

template <class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const pw::InputError& e) {
    return e.what();
  }
  return "<no pw::InputError thrown>";
}

constexpr std::size_t kN = 1024;
constexpr double kDt = 1e-4;  // 10 kHz sampling, bins of 10000/1024 = 9.765625 Hz
const double kDf = 1.0 / (static_cast<double>(kN) * kDt);

TEST(AmplitudeSpectrum, OnBinSineRectangularGivesExactAmplitudeAndNoLeakage) {
  const double A = 2.5;
  const auto s = pw::signal::amplitude_spectrum(sine(kN, kDt, A, 50 * kDf, 0.3), kDt,
                                                Window::Rectangular);
  ASSERT_EQ(s.amplitude.size(), kN / 2 + 1);
  EXPECT_NEAR(s.frequency_Hz[50], 50 * kDf, 1e-9);
  EXPECT_NEAR(s.amplitude[50], A, 1e-10);
  for (std::size_t k = 0; k < s.amplitude.size(); ++k)
    if (k != 50) {
      EXPECT_LT(s.amplitude[k], 1e-10) << "leakage into bin " << k;
    }
  EXPECT_EQ(s.window, "rectangular");
  EXPECT_EQ(s.scaling, "peak amplitude, single-sided, coherent-gain corrected");
}

TEST(AmplitudeSpectrum, OnBinSineHannGivesExactAmplitudeAndHalfInNeighbours) {
  const double A = 0.8;
  const auto s = pw::signal::amplitude_spectrum(sine(kN, kDt, A, 123 * kDf, 1.1), kDt, Window::Hann);
  EXPECT_NEAR(s.amplitude[123], A, 1e-10);
  // Periodic Hann = 1/2 - (e^{i.} + e^{-i.})/4: the tone appears at +-1 bin with half its level.
  EXPECT_NEAR(s.amplitude[122], A / 2, 1e-10);
  EXPECT_NEAR(s.amplitude[124], A / 2, 1e-10);
  for (std::size_t k = 0; k < s.amplitude.size(); ++k)
    if (k < 122 || k > 124) {
      EXPECT_LT(s.amplitude[k], 1e-10) << "leakage into bin " << k;
    }
  EXPECT_EQ(s.window, "hann");
}

TEST(AmplitudeSpectrum, OnBinSineIsExactNearDcAndNyquistWhereNoImageOverlaps) {
  // Hann: exact down to bin 1 and up to n/2 - 1 (main lobe +-1 bin).
  for (std::size_t k : {std::size_t{1}, kN / 2 - 1}) {
    const double f = static_cast<double>(k) * kDf;
    const auto s = pw::signal::amplitude_spectrum(sine(kN, kDt, 1.0, f, 0.7), kDt, Window::Hann);
    EXPECT_NEAR(s.amplitude[k], 1.0, 1e-10) << "bin " << k;
  }
  // Nyquist bin (even n): A cos(pi j) has no mirror image, factor 1 not 2.
  std::vector<double> x(kN);
  for (std::size_t j = 0; j < kN; ++j) x[j] = 1.7 * (j % 2 == 0 ? 1.0 : -1.0);
  const auto s = pw::signal::amplitude_spectrum(x, kDt, Window::Rectangular);
  EXPECT_NEAR(s.amplitude[kN / 2], 1.7, 1e-12);
  EXPECT_NEAR(s.frequency_Hz[kN / 2], 0.5 / kDt, 1e-9);
}

TEST(AmplitudeSpectrum, OffBinSineFlatTopWithinPointOnePercentAnywhereBetweenBins) {
  const std::size_t n = 4096;
  const double df = 1.0 / (static_cast<double>(n) * kDt);
  const double A = 3.0;
  double worst = 0;
  for (int i = 0; i <= 10; ++i) {
    const double offset = 0.05 * i;  // fraction of a bin, 0 .. 0.5
    const auto s = pw::signal::amplitude_spectrum(sine(n, kDt, A, (300 + offset) * df, 0.4), kDt,
                                                  Window::FlatTop);
    const double peak = *std::max_element(s.amplitude.begin(), s.amplitude.end());
    worst = std::max(worst, std::abs(peak - A) / A);
    EXPECT_NEAR(peak, A, 1e-3 * A) << "offset " << offset << " bin";
  }
  RecordProperty("flattop_worst_relative_error", std::to_string(worst));
}

TEST(AmplitudeSpectra, EachIsBitIdenticalToTheSingleSpectrumForOneAndTwoThreads) {
  const double dt = 1e-3;
  std::vector<std::vector<double>> x;
  // Three of the first signal's length (they share one window) and three of other lengths.
  for (int c = 0; c < 6; ++c)
    x.push_back(sine(1000 + (c < 3 ? 0 : 37 * static_cast<std::size_t>(c)), dt, 1.0 + c, 50.0 + 7 * c, 0.3 * c));
  const std::vector<std::span<const double>> signals(x.begin(), x.end());
  for (const int threads : {1, 2}) {
    const auto all = pw::signal::amplitude_spectra(signals, dt, Window::Hann, threads);
    ASSERT_EQ(all.size(), x.size());
    for (std::size_t c = 0; c < x.size(); ++c) {
      const auto one = pw::signal::amplitude_spectrum(x[c], dt, Window::Hann);
      EXPECT_EQ(all[c].amplitude, one.amplitude) << "signal " << c << ", " << threads << " threads";
      EXPECT_EQ(all[c].frequency_Hz, one.frequency_Hz);
    }
  }
}

TEST(AmplitudeSpectra, TheFirstBadSignalsErrorIsRethrownOutsideTheThreads) {
  const std::vector<double> good = sine(64, 1e-3, 1.0, 100.0), one_sample = {1.0};
  const std::vector<std::span<const double>> signals{good, one_sample, good};
  EXPECT_THROW(pw::signal::amplitude_spectra(signals, 1e-3, Window::Hann, 2), pw::InputError);
}

TEST(AmplitudeSpectrum, TwoTonesAreResolvedWithTheirAmplitudes) {
  auto x = sine(kN, kDt, 1.0, 40 * kDf);
  const auto y = sine(kN, kDt, 0.25, 130 * kDf, 2.0);
  for (std::size_t j = 0; j < kN; ++j) x[j] += y[j];
  for (Window w : {Window::Rectangular, Window::Hann, Window::FlatTop}) {
    const auto s = pw::signal::amplitude_spectrum(x, kDt, w);
    EXPECT_NEAR(s.amplitude[40], 1.0, 1e-10) << s.window;
    EXPECT_NEAR(s.amplitude[130], 0.25, 1e-10) << s.window;
  }
}

TEST(AmplitudeSpectrum, MeanRemovalClearsDcAndLeavesTone) {
  auto x = sine(kN, kDt, 1.2, 64 * kDf);
  for (auto& v : x) v += 3.0;
  for (Window w : {Window::Rectangular, Window::Hann, Window::FlatTop}) {
    const auto kept = pw::signal::amplitude_spectrum(x, kDt, w, /*remove_mean=*/false);
    EXPECT_NEAR(kept.amplitude[0], 3.0, 1e-10) << kept.window;  // DC bin is not doubled
    const auto removed = pw::signal::amplitude_spectrum(x, kDt, w, /*remove_mean=*/true);
    EXPECT_LT(removed.amplitude[0], 1e-10) << removed.window;
    EXPECT_NEAR(removed.amplitude[64], 1.2, 1e-10) << removed.window;
  }
}

TEST(AmplitudeSpectrum, EveryBinIsWrittenForEvenAndOddLengths) {
  // The library fills the amplitude vector with NaN before writing it.
  for (std::size_t n : {2u, 3u, 101u, 256u}) {
    const auto s = pw::signal::amplitude_spectrum(white_noise(n, 1.0, n), kDt, Window::Hann);
    ASSERT_EQ(s.amplitude.size(), n / 2 + 1);
    ASSERT_EQ(s.frequency_Hz.size(), n / 2 + 1);
    for (std::size_t k = 0; k < s.amplitude.size(); ++k)
      EXPECT_TRUE(std::isfinite(s.amplitude[k])) << "n = " << n << ", bin " << k;
  }
}

TEST(AmplitudeSpectrum, RejectsEmptyShortNonFiniteInputAndBadInterval) {
  using pw::signal::amplitude_spectrum;
  EXPECT_EQ(thrown_message([] { (void)amplitude_spectrum(std::vector<double>{}, kDt); }),
            "signal: is empty");
  EXPECT_NE(thrown_message([] { (void)amplitude_spectrum(std::vector<double>{1.0}, kDt); })
                .find("at least 2"),
            std::string::npos);
  EXPECT_NE(thrown_message([] {
              (void)amplitude_spectrum(std::vector<double>{1.0, std::nan(""), 2.0}, kDt);
            }).find("sample 1 is not finite"),
            std::string::npos);
  const std::vector<double> x(8, 1.0);
  for (double dt : {0.0, -1e-3, std::nan("")})
    EXPECT_NE(thrown_message([&] { (void)amplitude_spectrum(x, dt); }).find("sample_interval_s"),
              std::string::npos)
        << "dt = " << dt;
}

TEST(PowerSpectralDensity, IntegralEqualsVarianceOfWhiteNoise) {
  // Parseval: sum_k P_k df = window-weighted mean square ~ variance.
  const double sigma = 0.7;
  const std::size_t L = 1024;
  const auto x = white_noise(1u << 16, sigma, 2024);
  const auto psd = pw::signal::power_spectral_density(x, kDt, L);
  ASSERT_EQ(psd.size(), L / 2 + 1);
  const double df = 1.0 / (static_cast<double>(L) * kDt);
  double integral = 0;
  for (double p : psd) integral += p * df;
  EXPECT_NEAR(integral, sigma * sigma, 0.03 * sigma * sigma);
  // One-sided white level is sigma^2 / (f_s / 2) = 2 sigma^2 dt.
  double level = 0;
  for (std::size_t k = 10; k < L / 2 - 10; ++k) level += psd[k];
  level /= static_cast<double>(L / 2 - 20);
  EXPECT_NEAR(level, 2 * sigma * sigma * kDt, 0.03 * 2 * sigma * sigma * kDt);
}

TEST(PowerSpectralDensity, SinePowerIsHalfSquaredAmplitude) {
  const double A = 2.0;
  const std::size_t L = 512;
  const double df = 1.0 / (static_cast<double>(L) * kDt);
  const auto psd = pw::signal::power_spectral_density(sine(1u << 14, kDt, A, 37.3 * df), kDt, L);
  double integral = 0;
  for (double p : psd) integral += p * df;
  EXPECT_NEAR(integral, A * A / 2, 0.02 * A * A / 2);
  const auto peak = std::max_element(psd.begin(), psd.end()) - psd.begin();
  EXPECT_EQ(peak, 37);
}

TEST(PowerSpectralDensity, RejectsSegmentLongerThanSignal) {
  const std::vector<double> x(100, 0.0);
  EXPECT_NE(thrown_message([&] { (void)pw::signal::power_spectral_density(x, kDt, 101); })
                .find("segment_length: must lie in [2, 100]"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)pw::signal::power_spectral_density(x, kDt, 1); })
                .find("segment_length"),
            std::string::npos);
}

TEST(DominantPeaks, InterpolatedFrequencyOfOffBinToneWithinFiveHundredthsOfABin) {
  const std::size_t n = 4096;
  const double df = 1.0 / (static_cast<double>(n) * kDt);
  double worst = 0;
  for (int i = 0; i <= 10; ++i) {
    const double f = (211 + 0.1 * i) * df;  // 0 .. 1 bin off, both sides of the half
    const auto s = pw::signal::amplitude_spectrum(sine(n, kDt, 1.0, f, 0.2), kDt, Window::Hann);
    const auto peaks = pw::signal::dominant_peaks(s, 1, 0.0);
    ASSERT_EQ(peaks.size(), 1u);
    const double error_bins = std::abs(peaks[0].frequency_Hz - f) / df;
    worst = std::max(worst, error_bins);
    EXPECT_LT(error_bins, 0.05) << "tone at bin " << f / df << ", found " << peaks[0].frequency_Hz / df;
  }
  RecordProperty("hann_worst_interpolation_error_bins", std::to_string(worst));
}

TEST(DominantPeaks, ReturnsLargestFirstAndHonoursSeparation) {
  auto x = sine(kN, kDt, 1.0, 100 * kDf);
  for (const auto& [a, k] : {std::pair{0.5, 300.0}, std::pair{0.8, 104.0}, std::pair{0.3, 20.0}}) {
    const auto y = sine(kN, kDt, a, k * kDf);
    for (std::size_t j = 0; j < kN; ++j) x[j] += y[j];
  }
  const auto s = pw::signal::amplitude_spectrum(x, kDt, Window::Hann);
  const auto all = pw::signal::dominant_peaks(s, 4, 0.0);
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[0].bin, 100u);
  EXPECT_EQ(all[1].bin, 104u);
  EXPECT_EQ(all[2].bin, 300u);
  EXPECT_EQ(all[3].bin, 20u);
  EXPECT_NEAR(all[0].amplitude, 1.0, 1e-10);
  // 104 lies 4 bins (39 Hz) from the larger 100: a 50 Hz separation drops it.
  const auto separated = pw::signal::dominant_peaks(s, 3, 50.0);
  ASSERT_EQ(separated.size(), 3u);
  EXPECT_EQ(separated[0].bin, 100u);
  EXPECT_EQ(separated[1].bin, 300u);
  EXPECT_EQ(separated[2].bin, 20u);
  // Asking for more peaks than exist returns what there is.
  pw::signal::Spectrum tiny{{0, 1, 2, 3, 4}, {0, 1, 0, 2, 0}, "hann", ""};
  EXPECT_EQ(pw::signal::dominant_peaks(tiny, 10, 0.0).size(), 2u);
}

TEST(DominantPeaks, RejectsBadArguments) {
  pw::signal::Spectrum s{{0, 1, 2}, {0, 1, 0}, "hann", ""};
  EXPECT_NE(thrown_message([&] { (void)pw::signal::dominant_peaks(s, 0, 0.0); }).find("count"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { (void)pw::signal::dominant_peaks(s, 1, -1.0); })
                .find("min_separation_Hz"),
            std::string::npos);
  s.amplitude.pop_back();
  EXPECT_NE(thrown_message([&] { (void)pw::signal::dominant_peaks(s, 1, 0.0); })
                .find("3 frequencies but 2 amplitudes"),
            std::string::npos);
}

TEST(WindowCoefficients, AreThePeriodicWindowsWithKnownGains) {
  const std::size_t n = 1000;
  auto sum = [](const std::vector<double>& w) {
    double s = 0;
    for (double v : w) s += v;
    return s;
  };
  // Coherent gains (sum w / n): 1, 1/2 and, for HFT95, its constant term 1
  // (Heinzel et al. 2002).
  EXPECT_NEAR(sum(pw::signal::window_coefficients(Window::Rectangular, n)), 1000.0, 1e-9);
  EXPECT_NEAR(sum(pw::signal::window_coefficients(Window::Hann, n)), 500.0, 1e-9);
  EXPECT_NEAR(sum(pw::signal::window_coefficients(Window::FlatTop, n)), 1000.0, 1e-9);
  // ENBW = n sum w^2 / (sum w)^2 [bins]: 1.5 for Hann, 3.8112 for HFT95.
  auto enbw = [&sum](const std::vector<double>& w) {
    double s2 = 0;
    for (double v : w) s2 += v * v;
    return static_cast<double>(w.size()) * s2 / (sum(w) * sum(w));
  };
  EXPECT_NEAR(enbw(pw::signal::window_coefficients(Window::Hann, n)), 1.5, 1e-12);
  EXPECT_NEAR(enbw(pw::signal::window_coefficients(Window::FlatTop, n)), 3.8112, 1e-4);
  const auto hann = pw::signal::window_coefficients(Window::Hann, 4);
  EXPECT_NEAR(hann[0], 0.0, 1e-15);  // periodic: 0, 1/2, 1, 1/2 (no closing zero)
  EXPECT_NEAR(hann[1], 0.5, 1e-15);
  EXPECT_NEAR(hann[2], 1.0, 1e-15);
  EXPECT_NEAR(hann[3], 0.5, 1e-15);
}

} // namespace
