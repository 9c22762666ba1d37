// Decimation through the anti-alias FIR (signal/decimate.hpp). Tolerances from
// the Blackman window's properties (Oppenheim & Schafer, DTSP 3rd ed., Table
// 7.2: pass-band ripple and stop-band level both about -74 dB, transition
// width about 9.2 pi / M, M = 2 half): with half = 16 k the stop band starts
// near 0.47 of the new sample rate, so a line at 0.7 of it must be at least
// 60 dB down and a line at 0.1 of it must pass within 1e-3.
#include "signal/decimate.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace pw::signal {
namespace {

std::vector<double> sine(std::size_t n, double cycles_per_sample, double phase = 0.3) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i)
    x[i] = std::sin(2 * std::numbers::pi * cycles_per_sample * static_cast<double>(i) + phase);
  return x;
}

double peak(const std::vector<double>& y) {
  double p = 0;
  for (double v : y) p = std::max(p, std::abs(v));
  return p;
}

TEST(Decimate, TapsSumToOneSoAConstantPassesUnchanged) {
  for (int k : {2, 5, 32}) {
    const DecimationFilter f = decimation_filter(k, 16);
    EXPECT_EQ(f.half, 16 * k);
    ASSERT_EQ(f.taps.size(), 32u * static_cast<std::size_t>(k) + 1);
    const std::vector<double> x(200 * static_cast<std::size_t>(k), 2.5);
    for (double v : decimate(x, f, static_cast<std::size_t>(f.half), 10)) EXPECT_NEAR(v, 2.5, 1e-13);
  }
}

TEST(Decimate, ALineWellInsideTheNewBandPassesInPhaseAtItsInputSample) {
  const int k = 8;
  const DecimationFilter f = decimation_filter(k, 16);
  const double fin = 0.1 / k;  // 0.1 of the new sample rate, in cycles per input sample
  const auto x = sine(4000, fin);
  const std::size_t first = static_cast<std::size_t>(f.half) + 3;
  const auto y = decimate(x, f, first, 100);
  for (std::size_t j = 0; j < y.size(); ++j) EXPECT_NEAR(y[j], x[first + j * k], 1e-3) << j;  // zero phase
}

TEST(Decimate, ALineThatWouldAliasIsAtLeast60dBDown) {
  const int k = 8;
  const DecimationFilter f = decimation_filter(k, 16);
  const auto x = sine(8000, 0.7 / k);  // 0.7 of the new rate: would fold to 0.3
  const auto y = decimate(x, f, static_cast<std::size_t>(f.half), 200);
  EXPECT_LT(peak(y), 1e-3);
}

TEST(Decimate, FactorOneIsTheIdentity) {
  const auto x = sine(50, 0.31);
  const DecimationFilter f = decimation_filter(1, 16);
  EXPECT_EQ(decimate(x, f, 0, x.size()), x);
}

TEST(Decimate, AKernelOutsideTheSignalOrABadFactorIsRejected) {
  const auto x = sine(100, 0.01);
  const DecimationFilter f = decimation_filter(2, 16);  // half = 32
  EXPECT_THROW(decimate(x, f, 31, 1), InputError);      // kernel starts before sample 0
  EXPECT_THROW(decimate(x, f, 32, 19), InputError);     // last kernel ends at sample 100
  EXPECT_NO_THROW(decimate(x, f, 32, 18));              // ... and at 99
  EXPECT_THROW(decimation_filter(0, 16), InputError);
  EXPECT_THROW(decimation_filter(2, 0), InputError);
}

} // namespace
} // namespace pw::signal
