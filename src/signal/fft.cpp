// FFTW3 wrapper: the only translation unit of planetwear that includes fftw3.h.
//
// Thread safety (FFTW 3.3 manual, §5.4 "Thread safety"): only fftw_execute*
// is thread-safe; plan creation and destruction touch the planner's global
// state and must be serialized. Every fftw_plan_* / fftw_destroy_plan call
// below therefore holds planner_mutex(). Buffers come from fftw_alloc_* so
// that SIMD codelets chosen by the planner see the alignment they assume.
#include "signal/fft.hpp"

#include "core/error.hpp"

#include <fftw3.h>

#include <climits>
#include <limits>
#include <cmath>
#include <mutex>
#include <new>

namespace pw::signal {

namespace {

std::mutex& planner_mutex() {
  static std::mutex m;
  return m;
}

} // namespace

struct RealFft::Impl {
  std::size_t n = 0;
  double* real = nullptr;        // n doubles, fftw_alloc_real
  fftw_complex* spec = nullptr;  // n/2 + 1 complex, fftw_alloc_complex
  fftw_plan forward_plan = nullptr;
  fftw_plan inverse_plan = nullptr;

  explicit Impl(std::size_t length) : n(length) {
    // FFTW's plan takes an int length: refuse longer records instead of wrapping.
    require(n <= static_cast<std::size_t>(std::numeric_limits<int>::max()), "solver.record_mesh_cycles", "a spectrum of ",
            n, " samples exceeds the ", std::numeric_limits<int>::max(),
            " FFTW can transform; record fewer samples (solver.record_mesh_cycles, --time-history-decimation)");
    real = fftw_alloc_real(n);
    spec = fftw_alloc_complex(n / 2 + 1);
    if (real == nullptr || spec == nullptr) {
      release_buffers();
      throw std::bad_alloc();
    }
    {
      const std::lock_guard<std::mutex> lock(planner_mutex());
      // FFTW_ESTIMATE never overwrites the arrays during planning.
      forward_plan = fftw_plan_dft_r2c_1d(static_cast<int>(n), real, spec, FFTW_ESTIMATE);
    }
    if (forward_plan == nullptr) {
      destroy_plans();
      release_buffers();
      throw SolverError(detail::concat("FFTW could not plan a real transform of length ", n));
    }
  }
  ~Impl() {
    destroy_plans();
    release_buffers();
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  /// The inverse plan on first use: most transforms are forward only (spectra), and planning
  /// is the dearer part of a transform used once (the twiddle factors' sincos).
  void plan_inverse() {
    if (inverse_plan != nullptr) return;
    {
      const std::lock_guard<std::mutex> lock(planner_mutex());
      inverse_plan = fftw_plan_dft_c2r_1d(static_cast<int>(n), spec, real, FFTW_ESTIMATE);
    }
    if (inverse_plan == nullptr)
      throw SolverError(detail::concat("FFTW could not plan an inverse real transform of length ", n));
  }
  void destroy_plans() noexcept {
    const std::lock_guard<std::mutex> lock(planner_mutex());
    if (forward_plan != nullptr) fftw_destroy_plan(forward_plan);
    if (inverse_plan != nullptr) fftw_destroy_plan(inverse_plan);
    forward_plan = inverse_plan = nullptr;
  }
  void release_buffers() noexcept {
    fftw_free(real);
    fftw_free(spec);
    real = nullptr;
    spec = nullptr;
  }
};

RealFft::RealFft(std::size_t n) {
  require(n >= 1, "fft length", "must be at least 1, got ", n);
  require(n <= static_cast<std::size_t>(INT_MAX), "fft length", "must not exceed ", INT_MAX,
          " (FFTW 1-D interface), got ", n);
  impl_ = std::make_unique<Impl>(n);
}

RealFft::~RealFft() = default;
RealFft::RealFft(RealFft&&) noexcept = default;
RealFft& RealFft::operator=(RealFft&&) noexcept = default;

std::size_t RealFft::size() const noexcept { return impl_ ? impl_->n : 0; }

void RealFft::forward(std::span<const double> x, std::span<std::complex<double>> X) {
  require(impl_ != nullptr, "RealFft", "used after move");
  const std::size_t n = impl_->n;
  require(x.size() == n, "fft input", "has ", x.size(), " samples, the plan expects ", n);
  require(X.size() == n / 2 + 1, "fft output", "has ", X.size(), " bins, expected n/2+1 = ", n / 2 + 1);
  for (std::size_t j = 0; j < n; ++j) impl_->real[j] = x[j];
  fftw_execute(impl_->forward_plan);
  for (std::size_t k = 0; k < X.size(); ++k) X[k] = {impl_->spec[k][0], impl_->spec[k][1]};
}

void RealFft::inverse(std::span<const std::complex<double>> X, std::span<double> x) {
  require(impl_ != nullptr, "RealFft", "used after move");
  const std::size_t n = impl_->n;
  require(X.size() == n / 2 + 1, "inverse fft input", "has ", X.size(), " bins, expected n/2+1 = ",
          n / 2 + 1);
  require(x.size() == n, "inverse fft output", "has ", x.size(), " samples, the plan expects ", n);
  impl_->plan_inverse();
  // c2r destroys its input by default, so the copy into the work buffer is
  // needed anyway; it also keeps the caller's X const.
  for (std::size_t k = 0; k < X.size(); ++k) {
    impl_->spec[k][0] = X[k].real();
    impl_->spec[k][1] = X[k].imag();
  }
  fftw_execute(impl_->inverse_plan);
  // FFTW's c2r is unnormalized (returns n x); apply the 1/n here.
  const double scale = 1.0 / static_cast<double>(n);
  for (std::size_t j = 0; j < n; ++j) x[j] = impl_->real[j] * scale;
}

RealFft& thread_real_fft(std::size_t n) {
  struct Entry {
    RealFft fft;
    unsigned long long last_use;
  };
  thread_local std::vector<Entry> cache;
  thread_local unsigned long long uses = 0;
  ++uses;
  for (Entry& e : cache)
    if (e.fft.size() == n) {
      e.last_use = uses;
      return e.fft;
    }
  if (cache.size() < kThreadFftPlans) {
    cache.push_back({RealFft(n), uses});
    return cache.back().fft;
  }
  // Replace the least recently used length.
  Entry* oldest = &cache.front();
  for (Entry& e : cache)
    if (e.last_use < oldest->last_use) oldest = &e;
  oldest->fft = RealFft(n);
  oldest->last_use = uses;
  return oldest->fft;
}

std::vector<std::complex<double>> real_fft(std::span<const double> x) {
  require(!x.empty(), "signal", "is empty");
  RealFft fft(x.size());
  std::vector<std::complex<double>> X(fft.bins());
  fft.forward(x, X);
  return X;
}

std::vector<double> inverse_real_fft(std::span<const std::complex<double>> X, std::size_t n) {
  require(n >= 1, "fft length", "must be at least 1, got ", n);
  RealFft fft(n);
  std::vector<double> x(n);
  fft.inverse(X, x);
  return x;
}

std::vector<double> rfft_frequencies_Hz(std::size_t n, double sample_interval_s) {
  require(n >= 1, "fft length", "must be at least 1, got ", n);
  require(std::isfinite(sample_interval_s) && sample_interval_s > 0, "sample_interval_s",
          "must be a positive, finite time step [s], got ", sample_interval_s);
  const double df = 1.0 / (static_cast<double>(n) * sample_interval_s);
  std::vector<double> f(n / 2 + 1);
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = static_cast<double>(k) * df;
  return f;
}

} // namespace pw::signal
