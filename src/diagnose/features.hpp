// Features of sampled signals that the diagnosis compares between a recording
// and the model: amplitudes of known spectral lines, DFT bins of an analysis
// window, the white-noise floor, time-synchronous averages in the mesh-cycle
// coordinate, and envelope spectra. Pure functions over spans.
//
// Conventions: times in s, frequencies in Hz; complex amplitudes are peak
// amplitudes with the phase of A cos(2 pi f t + phi) at the signal's own time
// t. The comparison itself is in the order domain (order_analysis.hpp); these
// helpers serve the locate step (synchronous averages, envelope, periodogram).
#pragma once

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

namespace pw::diagnose {

/// x(t) of a signal sampled every dt from t0, by 4-point Lagrange
/// interpolation (2-point at the ends); t outside [t0, t0 + (n-1) dt] throws
/// pw::InputError.
double interpolate_uniform(std::span<const double> x, double t0, double dt, double t);

/// A line fitted at a known frequency.
struct LineAmplitude {
  double frequency_Hz = 0;
  std::complex<double> amplitude;  ///< A e^{i phi}: x contains A cos(2 pi f t + phi)
};

/// Amplitudes of the lines at `frequencies_Hz` in x (sampled every dt from t0)
/// by Hann-weighted linear least squares on cos/sin pairs of all the
/// frequencies at once, plus a constant (an offset does not bias the lines).
/// Exact for a signal that consists of these lines (plus a constant), up to
/// rounding; with white noise of variance s^2 each amplitude has a standard
/// error of about s sqrt(2 ENBW / n) (ENBW = 1.5 for Hann). Frequencies closer
/// than ~1 / record length are not separable and make the system singular:
/// throws pw::InputError naming `frequencies_Hz` then.
std::vector<LineAmplitude> fit_lines(std::span<const double> x, double t0, double dt,
                                     std::span<const double> frequencies_Hz);

/// DFT bins k = 1 .. max_bin of the mean-removed window x (rectangular
/// window, unnormalized: X_k = sum_j x_j e^{-2 pi i j k / n}). With white
/// noise of variance s^2 the real and imaginary parts of each bin are
/// independent N(0, n s^2 / 2): the basis of the chi-square residual.
std::vector<std::complex<double>> window_bins(std::span<const double> x, std::size_t max_bin);

/// White measurement noise of one channel, estimated from the median of the
/// Hann periodogram over bins [first_bin, last_bin] of the whole record: a
/// periodogram bin of white noise is exponential with mean s^2 sum w^2, so the
/// median is ln 2 times that; the deterministic lines of a gear signal occupy
/// few bins and barely move the median (a robust estimate).
struct NoiseEstimate {
  double variance = 0;              ///< s^2 per sample [unit^2]
  double relative_uncertainty = 0;  ///< standard error of the estimate of s^2 / s^2
  std::size_t bins = 0;             ///< periodogram bins used
};
/// `band` = fraction of the Nyquist band to use, from `low_fraction` to 1
/// (the low end carries the strong gear lines). Throws for fewer than 64
/// samples.
NoiseEstimate estimate_white_noise(std::span<const double> x, double low_fraction = 0.05);

/// Time-synchronous average in the mesh-cycle coordinate u = f_m t (docs/
/// diagnose.md §2): x is resampled (cubic) onto u = i / samples_per_cycle and
/// averaged over whole periods of `period_cycles` mesh cycles (an integer:
/// Zs, Zp or Zr). Element j of the result is at u = j / samples_per_cycle mod
/// period (absolute phase: 0 = where every mesh's roll is zero). Returns an
/// empty vector if x covers less than one period.
struct SynchronousAverage {
  std::vector<double> values;   ///< period_cycles * samples_per_cycle samples
  int samples_per_cycle = 0;
  int period_cycles = 0;
  int averages = 0;             ///< whole periods averaged
};
SynchronousAverage synchronous_average(std::span<const double> x, double t0, double dt, double mesh_Hz,
                                       int period_cycles, int samples_per_cycle);

/// Squared-envelope peak of a synchronous average: the mesh-cycle position u
/// in [0, period) where the energy, smoothed over one mesh cycle, is largest,
/// and that energy over its mean (peak-to-mean ratio, 1 for a flat TSA).
struct TsaPeak {
  double mesh_cycle = 0;
  double peak_to_mean = 0;
};
TsaPeak tsa_energy_peak(const SynchronousAverage& tsa);

/// Envelope spectrum: x band-passed to [f_lo, f_hi] (ideal FFT filter),
/// |analytic signal|, mean removed, Hann amplitude spectrum on the bins of
/// the record. Returns (frequency, amplitude) pairs up to max_Hz.
struct EnvelopeSpectrum {
  std::vector<double> frequency_Hz, amplitude;
};
EnvelopeSpectrum envelope_spectrum(std::span<const double> x, double dt, double f_lo, double f_hi, double max_Hz);

/// Hann-windowed periodogram |X_k|^2 / (sum w^2) of the mean-removed x,
/// bins 0 .. n/2: white noise of variance s^2 reads s^2 on average.
std::vector<double> normalized_periodogram(std::span<const double> x);

} // namespace pw::diagnose
