// Real-input discrete Fourier transform behind a small RAII type, so that no
// file outside src/signal/fft.cpp includes fftw3.h (FFTW3 is a PRIVATE
// dependency of the physics library).
//
// Conventions (docs/spectra.md §1), identical to FFTW's r2c/c2r:
//   forward  X_k = sum_{j=0}^{n-1} x_j exp(-2 pi i j k / n),  k = 0 .. n/2
//            (unnormalized; the n/2+1 non-redundant bins of a real signal),
//   inverse  x_j = (1/n) sum_{k=0}^{n-1} X_k exp(+2 pi i j k / n)
//            (the 1/n is applied here, so inverse(forward(x)) == x).
// Bin k lies at frequency k / (n dt) [Hz] for sample interval dt [s].
#pragma once

#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace pw::signal {

/// A reusable forward/inverse real FFT of one length n (an FFTW plan pair and
/// its aligned work buffers). Create it once and call forward()/inverse() many
/// times (Welch segments, per-channel spectra). Construction and destruction
/// are serialized internally because FFTW's planner is not thread-safe;
/// forward() only calls fftw_execute and inverse() plans its direction on first use (under the
/// same serialization); both may run concurrently on
/// *different* RealFft objects. One object must not be used by two threads at
/// once (it owns the work buffers), hence the non-const members.
class RealFft {
public:
  /// Plans transforms of length n >= 1 (FFTW_ESTIMATE: no timing runs, the
  /// plan is deterministic and cheap). Throws pw::InputError for n == 0 or
  /// n > INT_MAX (FFTW's 1-D interface takes an int).
  explicit RealFft(std::size_t n);
  ~RealFft();
  RealFft(RealFft&&) noexcept;
  RealFft& operator=(RealFft&&) noexcept;
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  std::size_t size() const noexcept;                          ///< n
  std::size_t bins() const noexcept { return size() / 2 + 1; } ///< n/2 + 1

  /// X = forward DFT of x. Requires x.size() == n and X.size() == n/2 + 1
  /// (pw::InputError otherwise); every element of X is written.
  void forward(std::span<const double> x, std::span<std::complex<double>> X);

  /// x = inverse DFT of the Hermitian half-spectrum X, including the 1/n.
  /// Requires X.size() == n/2 + 1 and x.size() == n. The imaginary parts of
  /// X_0 (and of X_{n/2} for even n) are ignored, as for any real signal.
  void inverse(std::span<const std::complex<double>> X, std::span<double> x);

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// How many transform lengths thread_real_fft keeps per thread.
inline constexpr std::size_t kThreadFftPlans = 8;

/// A RealFft of length n owned by the calling thread and kept for its later calls: transforms
/// of one length repeated many times (each channel of each simulation of a diagnosis) are
/// planned once per thread instead of once per call. Planning a length that is not a product of
/// small primes costs more than the transform itself (FFTW's twiddle factors: 5.7 % of a
/// diagnosis's time, perf, session 42); a kept plan gives the numbers a fresh one gives (FFTW_ESTIMATE
/// plans deterministically). The reference is valid until the thread has asked for
/// kThreadFftPlans other lengths; it must not be handed to another thread.
RealFft& thread_real_fft(std::size_t n);

/// One-shot forward transform (see RealFft::forward); returns n/2 + 1 bins.
std::vector<std::complex<double>> real_fft(std::span<const double> x);

/// One-shot inverse transform to n real samples (see RealFft::inverse);
/// requires X.size() == n/2 + 1.
std::vector<double> inverse_real_fft(std::span<const std::complex<double>> X, std::size_t n);

/// Frequencies of the n/2 + 1 bins: f_k = k / (n dt) [Hz]. Throws
/// pw::InputError for n == 0 or dt <= 0 (or not finite).
std::vector<double> rfft_frequencies_Hz(std::size_t n, double sample_interval_s);

} // namespace pw::signal
