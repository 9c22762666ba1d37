// Amplitude spectrum, Welch PSD and peak picking (formulas: spectrum.hpp and
// docs/spectra.md). All transforms go through RealFft (fft.hpp).
#include "signal/spectrum.hpp"

#include "core/error.hpp"
#include "signal/fft.hpp"
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <exception>
#include <limits>
#include <numbers>

namespace pw::signal {

namespace {

void require_samples(std::span<const double> x, std::size_t minimum) {
  require(!x.empty(), "signal", "is empty");
  require(x.size() >= minimum, "signal", "has ", x.size(), " samples, at least ", minimum,
          " are needed");
  for (std::size_t j = 0; j < x.size(); ++j)
    require(std::isfinite(x[j]), "signal", "sample ", j, " is not finite (", x[j], ")");
}

void require_interval(double sample_interval_s) {
  require(std::isfinite(sample_interval_s) && sample_interval_s > 0, "sample_interval_s",
          "must be a positive, finite time step [s], got ", sample_interval_s);
}

double mean_of(std::span<const double> x) {
  double sum = 0;
  for (double v : x) sum += v;
  return sum / static_cast<double>(x.size());
}

// Single-sided factor: the negative-frequency half folds onto bins
// 1 .. ceil(n/2)-1; DC and (even n) Nyquist have no mirror image.
double one_sided_factor(std::size_t k, std::size_t n) {
  return (k == 0 || (n % 2 == 0 && k == n / 2)) ? 1.0 : 2.0;
}

} // namespace

std::string_view to_string(Window w) {
  switch (w) {
    case Window::Rectangular: return "rectangular";
    case Window::Hann: return "hann";
    case Window::FlatTop: return "flattop";
  }
  return "unknown";
}

std::vector<double> window_coefficients(Window w, std::size_t n) {
  require(n >= 1, "window length", "must be at least 1, got ", n);
  std::vector<double> c(n, 1.0);
  const double step = 2.0 * std::numbers::pi / static_cast<double>(n);  // periodic: j/n, not j/(n-1)
  switch (w) {
    case Window::Rectangular: break;
    case Window::Hann:
      for (std::size_t j = 0; j < n; ++j) c[j] = 0.5 - 0.5 * std::cos(step * static_cast<double>(j));
      break;
    case Window::FlatTop: {
      // HFT95 from Heinzel, Ruediger & Schilling (2002), list of flat-top windows: amplitude
      // flatness 0.0044 dB (0.05%), ENBW 3.8112 bins, side lobes -95 dB. The
      // more common MATLAB/scipy flat top (D'Antona & Ferrero) is off by
      // 0.0097 dB = 0.11% half-way between bins, too much for a 0.1% budget.
      constexpr double c1 = 1.9383379, c2 = 1.3045202, c3 = 0.4028270, c4 = 0.0350665;
      for (std::size_t j = 0; j < n; ++j) {
        const double z = step * static_cast<double>(j);
        c[j] = 1.0 - c1 * std::cos(z) + c2 * std::cos(2 * z) - c3 * std::cos(3 * z) +
               c4 * std::cos(4 * z);
      }
      break;
    }
  }
  return c;
}

namespace {

/// amplitude_spectrum() with its window's coefficients given (`win.size() == x.size()`), so
/// that spectra of equally long signals share one window.
Spectrum windowed_amplitude_spectrum(std::span<const double> x, double sample_interval_s, Window w,
                                     std::span<const double> win, bool remove_mean) {
  const std::size_t n = x.size();
  double coherent_sum = 0;  // sum w_j = n x coherent gain
  for (double v : win) coherent_sum += v;

  const double offset = remove_mean ? mean_of(x) : 0.0;
  std::vector<double> xw(n);
  for (std::size_t j = 0; j < n; ++j) xw[j] = (x[j] - offset) * win[j];

  RealFft& fft = thread_real_fft(n);  // the channels of one simulation share their length
  std::vector<std::complex<double>> X(fft.bins());
  fft.forward(xw, X);

  Spectrum s;
  s.frequency_Hz = rfft_frequencies_Hz(n, sample_interval_s);
  s.window = std::string(to_string(w));
  s.scaling = std::string(kPeakAmplitudeScaling);
  // Poisoned on purpose: a bin the loop below failed to write shows as NaN.
  s.amplitude.assign(X.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t k = 0; k < X.size(); ++k)
    s.amplitude[k] = one_sided_factor(k, n) * std::abs(X[k]) / coherent_sum;
  return s;
}

} // namespace

Spectrum amplitude_spectrum(std::span<const double> x, double sample_interval_s, Window w,
                            bool remove_mean) {
  require_samples(x, 2);
  require_interval(sample_interval_s);
  return windowed_amplitude_spectrum(x, sample_interval_s, w, window_coefficients(w, x.size()), remove_mean);
}

std::vector<Spectrum> amplitude_spectra(std::span<const std::span<const double>> xs, double sample_interval_s,
                                        Window w, int threads, bool remove_mean) {
  std::vector<Spectrum> out(xs.size());
  std::vector<std::exception_ptr> errors(xs.size());
  const int n = static_cast<int>(xs.size());
  // The window of the first signal's length, computed once and shared (the channels of one
  // simulation are equally long); other lengths get their own, as amplitude_spectrum does.
  std::vector<double> shared_window;
  if (!xs.empty() && xs.front().size() >= 2) shared_window = window_coefficients(w, xs.front().size());
  // One signal per iteration: each owns its FFT plan and buffers (RealFft's
  // planner is serialized inside); the threads share only the read-only window.
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads > 0 ? threads : omp_get_max_threads()) if (n > 1)
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    try {
      if (xs[k].size() == shared_window.size()) {
        require_samples(xs[k], 2);
        require_interval(sample_interval_s);
        out[k] = windowed_amplitude_spectrum(xs[k], sample_interval_s, w, shared_window, remove_mean);
      } else {
        out[k] = amplitude_spectrum(xs[k], sample_interval_s, w, remove_mean);
      }
    } catch (...) {
      errors[k] = std::current_exception();  // rethrown below, outside the parallel region
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
  return out;
}

std::vector<double> power_spectral_density(std::span<const double> x, double sample_interval_s,
                                           std::size_t segment_length, bool remove_mean) {
  require_samples(x, 2);
  require_interval(sample_interval_s);
  const std::size_t L = segment_length;
  require(L >= 2 && L <= x.size(), "segment_length", "must lie in [2, ", x.size(),
          "] (the number of samples), got ", L);

  const std::size_t hop = L / 2;  // 50% overlap (Welch 1967 recommends it for Hann-type windows)
  const std::size_t segments = 1 + (x.size() - L) / hop;
  const std::vector<double> win = window_coefficients(Window::Hann, L);
  double energy_sum = 0;  // sum w_j^2
  for (double v : win) energy_sum += v * v;

  RealFft fft(L);
  std::vector<double> xw(L);
  std::vector<std::complex<double>> X(fft.bins());
  std::vector<double> psd(fft.bins(), 0.0);
  for (std::size_t s = 0; s < segments; ++s) {
    const std::span<const double> seg = x.subspan(s * hop, L);
    const double offset = remove_mean ? mean_of(seg) : 0.0;
    for (std::size_t j = 0; j < L; ++j) xw[j] = (seg[j] - offset) * win[j];
    fft.forward(xw, X);
    for (std::size_t k = 0; k < X.size(); ++k) psd[k] += std::norm(X[k]);
  }

  const double fs = 1.0 / sample_interval_s;
  const double scale = 1.0 / (fs * energy_sum * static_cast<double>(segments));
  for (std::size_t k = 0; k < psd.size(); ++k) psd[k] *= one_sided_factor(k, L) * scale;
  return psd;
}

std::vector<Peak> dominant_peaks(const Spectrum& s, int count, double min_separation_Hz) {
  require(count >= 1, "count", "must be at least 1, got ", count);
  require(std::isfinite(min_separation_Hz) && min_separation_Hz >= 0, "min_separation_Hz",
          "must be finite and >= 0 [Hz], got ", min_separation_Hz);
  require(s.frequency_Hz.size() == s.amplitude.size(), "spectrum", "has ", s.frequency_Hz.size(),
          " frequencies but ", s.amplitude.size(), " amplitudes");
  const std::vector<double>& a = s.amplitude;
  const std::vector<double>& f = s.frequency_Hz;

  // Candidates: strict rise into the bin, no rise out of it, so a plateau of
  // equal values yields one peak (its first bin). DC and the last bin are not
  // candidates: a peak there cannot be bracketed for interpolation.
  std::vector<std::size_t> candidates;
  for (std::size_t k = 1; k + 1 < a.size(); ++k)
    if (a[k - 1] < a[k] && a[k] >= a[k + 1]) candidates.push_back(k);
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&a](std::size_t i, std::size_t j) { return a[i] > a[j]; });

  std::vector<Peak> peaks;
  for (std::size_t k : candidates) {
    if (peaks.size() >= static_cast<std::size_t>(count)) break;
    // Parabola through (-1, ln a_{k-1}), (0, ln a_k), (1, ln a_{k+1}); its
    // vertex offset p in bins lies in [-1/2, 1/2] because a_k is the maximum.
    double p = 0;
    if (a[k - 1] > 0 && a[k + 1] > 0) {
      const double lm = std::log(a[k - 1]), l0 = std::log(a[k]), lp = std::log(a[k + 1]);
      const double curvature = lm - 2 * l0 + lp;
      if (curvature < 0) p = std::clamp(0.5 * (lm - lp) / curvature, -0.5, 0.5);
    }
    const double bin_width = 0.5 * (f[k + 1] - f[k - 1]);
    const double freq = f[k] + p * bin_width;
    const bool separated = std::all_of(peaks.begin(), peaks.end(), [&](const Peak& q) {
      return std::abs(q.frequency_Hz - freq) >= min_separation_Hz;
    });
    if (separated) peaks.push_back(Peak{freq, a[k], k});
  }
  return peaks;
}

} // namespace pw::signal
