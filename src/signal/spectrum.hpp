// Spectra of sampled time histories: windowed single-sided amplitude spectrum,
// Welch power spectral density and peak picking. Pure functions over value
// types; formulas and conventions in docs/spectra.md.
//
// References:
//  * F. J. Harris, "On the use of windows for harmonic analysis with the
//    discrete Fourier transform", Proc. IEEE 66(1):51-83, 1978.
//  * G. Heinzel, A. Ruediger, R. Schilling, "Spectrum and spectral density
//    estimation by the DFT, including a comprehensive list of window functions
//    and some new flat-top windows", MPI Hannover, 2002 (coherent gain, ENBW).
//  * P. D. Welch, "The use of fast Fourier transform for the estimation of
//    power spectra", IEEE Trans. Audio Electroacoust. 15(2):70-73, 1967.
//  * J. O. Smith, X. Serra, "PARSHL", Proc. ICMC 1987 (quadratic peak
//    interpolation on log magnitude).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pw::signal {

/// Data windows, all *periodic* (DFT-even, length n, w_j = f(j/n)): a tone
/// on a bin then leaks into no other bin except through the window's own
/// +-1 (Hann) or +-4 (flat top) side bins, so on-bin amplitudes are exact.
///  * Rectangular: w = 1. Exact for on-bin tones, up to 36% low off-bin.
///  * Hann: w = 0.5 - 0.5 cos(2 pi j/n). Good leakage suppression; up to
///    15% (1.42 dB) low for a tone half-way between bins.
///  * FlatTop: Heinzel et al.'s HFT95, w = 1 - 1.9383379 cos z
///    + 1.3045202 cos 2z - 0.4028270 cos 3z + 0.0350665 cos 4z (z = 2 pi j/n);
///    amplitude error below 0.05% anywhere between bins, at the price of a
///    3.81-bin ENBW. (MATLAB/scipy's flat top errs by 0.11% half-way between
///    bins, hence not used.)
enum class Window { Rectangular, Hann, FlatTop };

/// "rectangular", "hann" or "flattop" (the string stored in Spectrum::window).
std::string_view to_string(Window w);

/// The n periodic window coefficients (n >= 1).
std::vector<double> window_coefficients(Window w, std::size_t n);

/// A single-sided spectrum on the DFT bins f_k = k / (n dt), k = 0 .. n/2.
struct Spectrum {
  std::vector<double> frequency_Hz;
  std::vector<double> amplitude;  ///< in the unit of the input signal
  std::string window;             ///< to_string(Window) of the window used
  std::string scaling;            ///< how `amplitude` is normalized (see below)
};

/// Scaling string of amplitude_spectrum().
inline constexpr std::string_view kPeakAmplitudeScaling =
    "peak amplitude, single-sided, coherent-gain corrected";

/// Single-sided amplitude spectrum of x sampled every `sample_interval_s` [s]:
///   A_k = c_k |sum_j w_j x_j e^{-2 pi i jk/n}| / sum_j w_j,
/// c_k = 1 for k = 0 and (n even) k = n/2, else 2. A sinusoid A sin(2 pi f t)
/// with f on bin k gives A_k = A exactly, unless 2k is within the window's
/// main-lobe half-width (0 bins Rectangular, 1 Hann, 4 FlatTop) of 0 or n,
/// where the tone's negative-frequency image overlaps; a constant c gives
/// A_0 = c (if remove_mean is false).
/// remove_mean subtracts the sample mean before windowing, which keeps a
/// large static offset (e.g. mean mesh deflection) from leaking into the
/// low bins through the window's side lobes.
/// Throws pw::InputError for empty or non-finite x, fewer than 2 samples, or a
/// non-positive / non-finite interval.
Spectrum amplitude_spectrum(std::span<const double> x, double sample_interval_s,
                            Window w = Window::Hann, bool remove_mean = true);

/// amplitude_spectrum() of each signal in `xs`, computed `threads` at a time
/// (0 = OpenMP's default; results do not depend on it: each is exactly what
/// amplitude_spectrum() returns for that signal). The first error, in the
/// order of `xs`, is rethrown.
std::vector<Spectrum> amplitude_spectra(std::span<const std::span<const double>> xs, double sample_interval_s,
                                        Window w = Window::Hann, int threads = 0, bool remove_mean = true);

/// Welch estimate of the one-sided power spectral density [unit^2/Hz] on the
/// bins f_k = k / (L dt), k = 0 .. L/2 (see rfft_frequencies_Hz(L, dt)).
/// Segments of `segment_length` L samples, periodic Hann window, 50% overlap
/// (hop floor(L/2)); samples after the last full segment are not used. Each
/// segment's mean is removed first if remove_mean. Per segment
///   P_k = c_k |sum_j w_j x_j e^{-2 pi i jk/L}|^2 / (f_s sum_j w_j^2),
/// with c_k as above, f_s = 1/dt; the estimate is the mean over segments. The
/// 1/(f_s sum w^2) is the power-spectrum scaling 1/(sum w)^2 divided by the
/// equivalent noise bandwidth ENBW = f_s sum w^2 / (sum w)^2 [Hz], so that
/// sum_k P_k f_s / L equals the window-weighted mean square (Parseval).
/// Requires 2 <= L <= x.size(); throws pw::InputError otherwise.
std::vector<double> power_spectral_density(std::span<const double> x, double sample_interval_s,
                                           std::size_t segment_length, bool remove_mean = true);

/// A spectral peak.
struct Peak {
  double frequency_Hz = 0;  ///< interpolated peak frequency [Hz]
  double amplitude = 0;     ///< the spectrum's value at the maximal bin
  std::size_t bin = 0;      ///< index of the maximal bin
};

/// The `count` largest local maxima of s.amplitude (interior bins k with
/// a_{k-1} < a_k >= a_{k+1}), largest first, each at least
/// `min_separation_Hz` from every larger peak already taken. Fewer are returned
/// if the spectrum has fewer. The frequency is refined by fitting a parabola
/// through the logarithms of the three bins around the maximum (exact for a
/// Gaussian main lobe, within ~0.02 bin for Hann); the amplitude is the bin
/// value, not interpolated: use Window::FlatTop when amplitudes matter.
/// Throws pw::InputError for count < 1, a negative/non-finite separation, or
/// frequency/amplitude vectors of different lengths.
std::vector<Peak> dominant_peaks(const Spectrum& s, int count, double min_separation_Hz);

} // namespace pw::signal
