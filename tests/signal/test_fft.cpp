// RealFft: agreement with a naive DFT, explicit 1/n round trip, and a
// poisoned output buffer (cf. AMReX Tests/FFT/R2C) so that a bin the wrapper
// forgets to write, or a write past the n/2+1 bins, shows up.
#include "core/error.hpp"
#include "signal/fft.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace {

using pw::signal::RealFft;
using cplx = std::complex<double>;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Deterministic test signal in [-1, 1] (splitmix64; the standard
// distributions are not bit-reproducible across library implementations).
std::vector<double> test_signal(std::size_t n, std::uint64_t seed) {
  std::vector<double> x(n);
  std::uint64_t s = seed;
  for (auto& v : x) {
    s += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = s;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    v = 2.0 * static_cast<double>(z >> 11) * 0x1.0p-53 - 1.0;
  }
  return x;
}

std::vector<cplx> naive_dft(const std::vector<double>& x) {
  const std::size_t n = x.size();
  std::vector<cplx> X(n / 2 + 1);
  for (std::size_t k = 0; k < X.size(); ++k) {
    cplx sum = 0;
    for (std::size_t j = 0; j < n; ++j) {
      // Reduce jk mod n before forming the angle: keeps the reference accurate.
      const double phase = -2.0 * std::numbers::pi * static_cast<double>((j * k) % n) /
                           static_cast<double>(n);
      sum += x[j] * cplx(std::cos(phase), std::sin(phase));
    }
    X[k] = sum;
  }
  return X;
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

class RealFftLengths : public ::testing::TestWithParam<std::size_t> {};

TEST_P(RealFftLengths, ForwardMatchesNaiveDft) {
  const std::size_t n = GetParam();
  const auto x = test_signal(n, 17 + n);
  const auto X = pw::signal::real_fft(x);
  const auto ref = naive_dft(x);
  ASSERT_EQ(X.size(), n / 2 + 1);
  const double tol = 1e-13 * static_cast<double>(n);
  for (std::size_t k = 0; k < X.size(); ++k)
    EXPECT_LT(std::abs(X[k] - ref[k]), tol) << "n = " << n << ", bin " << k << ": fft " << X[k]
                                            << " vs naive " << ref[k];
}

TEST_P(RealFftLengths, PoisonedOutputBuffersAreFullyWrittenAndNotOverrun) {
  const std::size_t n = GetParam();
  RealFft fft(n);
  const auto x = test_signal(n, 3 * n + 1);

  // One guard element past the end of each output: it must stay poisoned.
  std::vector<cplx> X(fft.bins() + 1, cplx(kNaN, kNaN));
  fft.forward(x, std::span<cplx>(X).first(fft.bins()));
  for (std::size_t k = 0; k < fft.bins(); ++k)
    EXPECT_TRUE(std::isfinite(X[k].real()) && std::isfinite(X[k].imag()))
        << "bin " << k << " of " << fft.bins() << " left unwritten (n = " << n << ")";
  EXPECT_TRUE(std::isnan(X.back().real())) << "forward wrote past bin n/2 (n = " << n << ")";

  std::vector<double> y(n + 1, kNaN);
  fft.inverse(std::span<const cplx>(X).first(fft.bins()), std::span<double>(y).first(n));
  for (std::size_t j = 0; j < n; ++j)
    EXPECT_TRUE(std::isfinite(y[j])) << "sample " << j << " left unwritten (n = " << n << ")";
  EXPECT_TRUE(std::isnan(y.back())) << "inverse wrote past sample n-1 (n = " << n << ")";
}

TEST_P(RealFftLengths, RoundTripWithOneOverNScalingRecoversSignal) {
  const std::size_t n = GetParam();
  const auto x = test_signal(n, 99 + n);
  const auto X = pw::signal::real_fft(x);
  const auto y = pw::signal::inverse_real_fft(X, n);
  ASSERT_EQ(y.size(), n);
  for (std::size_t j = 0; j < n; ++j)
    EXPECT_NEAR(y[j], x[j], 1e-14 * static_cast<double>(n) + 1e-15) << "n = " << n << ", j = " << j;
}

INSTANTIATE_TEST_SUITE_P(EvenOddAndPrime, RealFftLengths,
                         ::testing::Values(1, 2, 3, 4, 7, 8, 15, 64, 97, 1000));

TEST(RealFft, PlanIsReusableAcrossCalls) {
  RealFft fft(16);
  for (int trial = 0; trial < 3; ++trial) {
    const auto x = test_signal(16, static_cast<std::uint64_t>(trial));
    std::vector<cplx> X(fft.bins());
    fft.forward(x, X);
    const auto ref = naive_dft(x);
    for (std::size_t k = 0; k < X.size(); ++k) EXPECT_LT(std::abs(X[k] - ref[k]), 1e-12);
  }
}

TEST(RealFft, ConcurrentPlanningOnSeparateObjectsIsSafe) {
  // Plan creation/destruction is serialized inside RealFft; run it from
  // several threads at once and check every result (a data race in the
  // planner typically shows as a crash or garbage here, and under TSan).
  const auto x = test_signal(60, 5);
  const auto ref = naive_dft(x);
  std::vector<double> worst(4, 0.0);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < worst.size(); ++t)
    threads.emplace_back([&, t] {
      for (int rep = 0; rep < 50; ++rep) {
        RealFft fft(x.size());
        std::vector<cplx> X(fft.bins());
        fft.forward(x, X);
        for (std::size_t k = 0; k < X.size(); ++k)
          worst[t] = std::max(worst[t], std::abs(X[k] - ref[k]));
      }
    });
  for (auto& th : threads) th.join();
  for (std::size_t t = 0; t < worst.size(); ++t) EXPECT_LT(worst[t], 1e-12) << "thread " << t;
}

TEST(RealFft, MovedFromObjectIsRejectedAndMovedToWorks) {
  RealFft a(8);
  RealFft b(std::move(a));
  EXPECT_EQ(b.size(), 8u);
  std::vector<double> x(8, 1.0);
  std::vector<cplx> X(5);
  b.forward(x, X);
  EXPECT_NEAR(X[0].real(), 8.0, 1e-14);
  EXPECT_EQ(a.size(), 0u);  // NOLINT(bugprone-use-after-move): checking the documented state
  EXPECT_NE(thrown_message([&] { a.forward(x, X); }).find("used after move"), std::string::npos);
}

TEST(RealFft, RejectsZeroLengthAndMismatchedBuffers) {
  EXPECT_NE(thrown_message([] { RealFft f(0); }).find("fft length"), std::string::npos);
  EXPECT_NE(thrown_message([] { (void)pw::signal::real_fft(std::vector<double>{}); }).find("signal"),
            std::string::npos);
  RealFft fft(8);
  std::vector<double> x7(7), x8(8);
  std::vector<cplx> X4(4), X5(5);
  EXPECT_NE(thrown_message([&] { fft.forward(x7, X5); }).find("has 7 samples, the plan expects 8"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { fft.forward(x8, X4); }).find("expected n/2+1 = 5"),
            std::string::npos);
  EXPECT_NE(thrown_message([&] { fft.inverse(X4, x8); }).find("inverse fft input"),
            std::string::npos);
}

TEST(RfftFrequencies, AreBinIndexOverRecordLength) {
  const auto f = pw::signal::rfft_frequencies_Hz(10, 0.01);  // 0.1 s record -> 10 Hz bins
  ASSERT_EQ(f.size(), 6u);
  for (std::size_t k = 0; k < f.size(); ++k) EXPECT_NEAR(f[k], 10.0 * static_cast<double>(k), 1e-12);
  EXPECT_NE(thrown_message([] { (void)pw::signal::rfft_frequencies_Hz(10, 0.0); })
                .find("sample_interval_s"),
            std::string::npos);
}

// thread_real_fft keeps one plan per length and thread: asking again for a length returns the
// same object, its transform equals a freshly planned one to the last bit (also of a length with
// a large prime factor, 7 x 6379 x 8 as a simulation's record has), and more lengths than it
// keeps replace the least recently used one without changing any result.
TEST(ThreadRealFft, KeepsOnePlanPerLengthWhoseTransformIsAFreshPlansBitForBit) {
  auto signal_of = [](std::size_t n) {
    std::vector<double> x(n);
    for (std::size_t j = 0; j < n; ++j) x[j] = std::sin(0.37 * static_cast<double>(j)) + 1e-3 * static_cast<double>(j % 7);
    return x;
  };
  auto transform = [](pw::signal::RealFft& fft, const std::vector<double>& x) {
    std::vector<cplx> X(fft.bins());
    fft.forward(x, X);
    return X;
  };
  const std::size_t odd = 8 * 7 * 6379;
  pw::signal::RealFft& a = pw::signal::thread_real_fft(odd);
  EXPECT_EQ(&a, &pw::signal::thread_real_fft(odd));
  pw::signal::RealFft fresh(odd);
  const auto x = signal_of(odd);
  EXPECT_EQ(transform(a, x), transform(fresh, x));
  // More lengths than are kept: each still transforms as a fresh plan does.
  for (std::size_t k = 0; k < pw::signal::kThreadFftPlans + 3; ++k) {
    const std::size_t n = 64 + 2 * k;
    pw::signal::RealFft reference(n);
    const auto y = signal_of(n);
    EXPECT_EQ(transform(pw::signal::thread_real_fft(n), y), transform(reference, y)) << n;
  }
  // The inverse direction is planned on first use and inverts the forward one.
  pw::signal::RealFft& b = pw::signal::thread_real_fft(96);
  const auto y = signal_of(96);
  std::vector<double> back(96);
  b.inverse(transform(b, y), back);
  for (std::size_t j = 0; j < y.size(); ++j) EXPECT_NEAR(back[j], y[j], 1e-12) << j;
}

} // namespace
