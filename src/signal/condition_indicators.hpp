// Gear condition indicators of a time-synchronous average (TSA): the metrics
// of the gear-diagnostics literature and of MATLAB's gearConditionMetrics,
// as pure functions over one revolution of a TSA. docs/indicators.md has the
// definitions, conventions and examples.
//
// A TSA here is one revolution of a gear sampled at n equally spaced angles;
// the gear has Z teeth, so its mesh order is Z (Z mesh periods per
// revolution) and DFT bin k of the TSA is shaft order k exactly (the TSA is
// periodic: no window, no leakage). Amplitudes A_k are single-sided peak
// amplitudes, A_k = 2 |X_k| / n (k < n/2), |X_{n/2}| / n at the Nyquist bin.
//
// Signals derived from the TSA x (Lebold, McIntyre, Li & Byington 2000, §3):
//   regular    r = the mesh harmonics kZ (k >= 1), their first-order
//                  sidebands kZ +- 1, and the shaft orders 1 .. H;
//   difference d = x - mean(x) - r;
//   residual   e = x - mean(x) - (mesh harmonics kZ + shaft orders 1 .. H),
//                  i.e. the difference signal with the first-order sidebands
//                  kept.
// H = shaft_harmonics (default 2: once- and twice-per-revolution
// eccentricity/misalignment; the sources say "the shaft frequency and its
// harmonics" without a count). MATLAB's tsadifference removes the same
// components (NumSidebands = 1); its tsaregular leaves the sidebands out of
// the regular signal, so its energy ratio differs where sidebands are strong.
//
// Moments are about the mean: m_k = (1/n) sum (x_j - mean)^k.
//
// References:
//  * R. M. Stewart, "Some useful data analysis techniques for gearbox
//    diagnostics", Univ. Southampton ISVR MHM/R/10/77, 1977 (FM0, FM4).
//  * J. J. Zakrajsek, D. P. Townsend, H. J. Decker, "An analysis of gear
//    fault detection methods as applied to pitting fatigue failure data",
//    NASA TM-105950, 1993 (NA4, NB4, FM4, M6A, M8A over a run).
//  * M. Lebold, K. McClintic, R. Campbell, C. Byington, K. Maynard, "Review of
//    vibration analysis methods for gearbox diagnostics and prognostics",
//    Proc. 54th MFPT, 2000, pp. 623-634 (regular/difference/residual, energy
//    ratio, sideband level factor, crest factor, kurtosis, M6A, M8A, NB4).
//  * H. J. Decker, "Crack detection for aerospace quality spur gears", NASA
//    TM-2002-211491, 2002 (NA4, NB4 on the residual and envelope).
//  * H. R. Martin, "Statistical moment analysis as a means of surface damage
//    detection", Proc. 7th IMAC, 1989 (M6A, M8A), as summarized by Lebold et
//    al. 2000; N. S. Swansson, 1980 (energy ratio), likewise.
//  * P. D. McFadden, "A revised model for the extraction of periodic
//    waveforms by time domain averaging", MSSP 1(1):83-95, 1987 (TSA).
//  * P. D. McFadden, J. D. Smith, "An explanation for the asymmetry of the
//    modulation sidebands about the tooth meshing frequency in epicyclic gear
//    vibration", Proc. IMechE C 199(1):65-70, 1985; P. D. McFadden, "A
//    technique for calculating the time domain averages of the vibration of
//    the individual planet gears and the sun gear in an epicyclic gearbox",
//    J. Sound Vib. 144(1):163-172, 1991, and "Window functions for the
//    calculation of the time domain averages of the vibration of the
//    individual planet gears and sun gear in an epicyclic gearbox", J. Vib.
//    Acoust. 116:179-187, 1994 (planet separation: weighted_synchronous_average
//    with a window around each planet's passage).
#pragma once

#include <cstddef>
#include <limits>
#include <span>
#include <vector>

namespace pw::signal {

/// What is removed from a TSA to form the regular, difference and residual signals.
struct GearOrders {
  int mesh_order = 0;       ///< Z: teeth of the gear = mesh periods per TSA revolution (>= 1)
  int shaft_harmonics = 2;  ///< H: shaft orders 1 .. H removed as shaft components (>= 0)
};

/// The signals derived from one TSA revolution (each of the TSA's length n).
struct TsaDecomposition {
  std::vector<double> tsa;         ///< the input
  std::vector<double> regular;     ///< r: mesh harmonics, first-order sidebands, shaft orders 1..H
  std::vector<double> difference;  ///< d = tsa - mean - r
  std::vector<double> residual;    ///< e = tsa - mean - mesh harmonics - shaft orders 1..H
};

/// Splits a TSA as described in the file comment. Requires n >= 4, finite
/// values, 1 <= mesh_order < n/2 (the mesh fundamental below Nyquist) and
/// 0 <= shaft_harmonics < mesh_order - 1 (pw::InputError otherwise).
TsaDecomposition decompose_tsa(std::span<const double> tsa, const GearOrders& orders);

/// Single-sided peak amplitude of every shaft order k = 0 .. n/2 of a periodic
/// record (one revolution): A_0 = |mean|, A_k = 2|X_k|/n, A_{n/2} = |X_{n/2}|/n.
std::vector<double> order_amplitudes(std::span<const double> x);

/// Root mean square about zero, sqrt((1/n) sum x^2), in the signal's unit.
double rms(std::span<const double> x);
/// Standard deviation about the mean, sqrt(m_2) (population, 1/n).
double standard_deviation(std::span<const double> x);
/// max(x) - min(x), in the signal's unit.
double peak_to_peak(std::span<const double> x);

/// Normalized central moment of order k >= 2: m_k / m_2^(k/2)
///   = n^(k/2 - 1) sum (x - mean)^k / (sum (x - mean)^2)^(k/2).
/// NaN if m_2 == 0 (a constant). k = 4: kurtosis (Gaussian 3, sinusoid 1.5);
/// k = 6: 15 and k = 8: 105 for a Gaussian (its moments (k-1)!!).
double normalized_moment(std::span<const double> x, int k);

/// Kurtosis m_4 / m_2^2 (not the excess): 3 for a Gaussian, 1.5 for a sinusoid
/// sampled over whole periods; its standard error for N Gaussian samples is
/// about sqrt(24 / N).
double kurtosis(std::span<const double> x);

/// Crest factor max |x - mean| / standard_deviation(x) (Lebold et al. 2000;
/// MATLAB's peak / RMS on a zero-mean signal): sqrt(2) for a sinusoid sampled
/// at its peak. The mean is removed because an accelerometer's DC offset is
/// not vibration. NaN for a constant.
double crest_factor(std::span<const double> x);

/// FM0 = peak_to_peak(tsa) / sum_{k >= 1, kZ <= n/2} A_{kZ} (Stewart 1977;
/// Zakrajsek et al. 1993): the TSA's peak to peak over the summed amplitudes
/// of the mesh frequency and its harmonics. A pure mesh harmonic gives
/// 2 A / A = 2. NaN if the mesh harmonics have zero amplitude.
double fm0(std::span<const double> tsa, int mesh_order);

/// FM4 = kurtosis of the difference signal (Stewart 1977): about 3 for a
/// healthy gear (Gaussian-like difference signal), larger when one or two
/// teeth produce an isolated peak.
double fm4(std::span<const double> difference);
/// M6A = m_6 / m_2^3 of the difference signal (Martin 1989): Gaussian 15.
double m6a(std::span<const double> difference);
/// M8A = m_8 / m_2^4 of the difference signal (Martin 1989): Gaussian 105.
double m8a(std::span<const double> difference);

/// NA4 of run record M (Zakrajsek et al. 1993):
///   NA4 = m_4(e_M) / ( (1/M) sum_{j=1}^{M} m_2(e_j) )^2,
/// the residual's fourth moment over the squared mean of the residual
/// variances of all records so far in the run (this one included).
/// `earlier_variances` are m_2 of records 1 .. M-1 (empty: a single record,
/// where NA4 is the residual's kurtosis). A stationary Gaussian residual
/// gives 3. NaN if the mean variance is 0.
double na4(std::span<const double> residual, std::span<const double> earlier_variances);

/// NB4 of run record M (Zakrajsek et al. 1993): as NA4, on the envelope of the
/// TSA band-passed about the mesh frequency (band_envelope()).
double nb4(std::span<const double> envelope, std::span<const double> earlier_variances);

/// Central second moment m_2 (population variance) of x, the quantity NA4 and
/// NB4 average over a run.
double central_variance(std::span<const double> x);

/// Envelope |x_b + i H(x_b)| of x band-passed to the orders
/// [centre - half_width, centre + half_width] (clipped to 1 .. n/2 - 1),
/// H the Hilbert transform (X_k -> -i X_k for k > 0), both evaluated by
/// inverse real FFTs. A band holding a single order gives a constant
/// envelope equal to that order's amplitude. Requires 1 <= centre < n/2 and
/// half_width >= 0.
std::vector<double> band_envelope(std::span<const double> x, int centre_order, int half_width_orders);

/// Half-width of the NB4 band about the mesh order Z: floor(Z / 2) orders,
/// half-way to the neighbouring mesh harmonics (our choice; Zakrajsek et al.
/// 1993 band-pass "about the primary mesh frequency" without a width).
int nb4_half_band(int mesh_order);

/// Energy ratio ER = rms(difference) / rms(regular) (Swansson 1980 via
/// Lebold et al. 2000). NaN if the regular signal is zero.
double energy_ratio(std::span<const double> difference, std::span<const double> regular);

/// Sideband level factor SLF = (A_{Z-1} + A_{Z+1}) / standard_deviation(tsa)
/// (Lebold et al. 2000): the first-order sidebands of the mesh fundamental
/// over the TSA's standard deviation. NaN for a constant TSA.
double sideband_level_factor(std::span<const double> tsa, int mesh_order);

/// Every indicator of one TSA revolution. Units: rms, peak_to_peak in the
/// signal's unit; every other field is dimensionless. NaN = undefined (see
/// condition_indicators()).
struct ConditionIndicators {
  double rms = 0;                    ///< of the TSA about zero [signal unit]
  double peak_to_peak = 0;           ///< of the TSA [signal unit]
  double kurtosis = 0;               ///< of the TSA [-]
  double crest_factor = 0;           ///< of the TSA [-]
  double fm0 = 0;                    ///< [-]
  double fm4 = 0;                    ///< kurtosis of the difference signal [-]
  double m6a = 0;                    ///< [-]
  double m8a = 0;                    ///< [-]
  double na4 = 0;                    ///< [-]
  double nb4 = 0;                    ///< [-]
  double energy_ratio = 0;           ///< [-]
  double sideband_level_factor = 0;  ///< [-]
  double residual_variance = 0;      ///< m_2 of the residual, for NA4 of later records [signal unit^2]
  double envelope_variance = 0;      ///< m_2 of the NB4 envelope, for NB4 of later records [signal unit^2]
};

/// Relative floor below which a derived signal counts as zero: a difference,
/// residual or envelope whose RMS is below kRoundoffFloor * rms(tsa) is FFT
/// round-off (O(eps log n), eps = 2.2e-16; 1e-12 leaves a margin of ~10^3),
/// and the indicators normalized by it are NaN (undefined), not noise.
inline constexpr double kRoundoffFloor = 1e-12;

/// All indicators of `tsa`. `earlier_residual_variances` and
/// `earlier_envelope_variances` are the residual_variance / envelope_variance
/// of the earlier records of the same run (empty for a single record).
/// Requirements as decompose_tsa.
ConditionIndicators condition_indicators(std::span<const double> tsa, const GearOrders& orders,
                                         std::span<const double> earlier_residual_variances = {},
                                         std::span<const double> earlier_envelope_variances = {});

/// A weighted synchronous average: y_j = sum_r w_{j+rP} x_{j+rP} / sum_r w_{j+rP}
/// over the R = floor(n / P) complete periods of P samples, with the weight
/// sums W_j = sum_r w_{j+rP}. With w = 1 it is time_synchronous_average().
/// Planet separation (McFadden & Smith 1985; McFadden 1991, 1994): x is a housing
/// signal resampled to the planet's mesh cycles, P = Zp samples_per_mesh,
/// and w a window centred where the planet passes the sensor, so that each
/// planet tooth's average is taken from the revolutions in which it meshed
/// near the sensor. McFadden requires windows whose shifted copies sum to a
/// constant (equal weight per revolution); dividing by W_j gives the same
/// average when they do and stays unbiased when they do not.
struct WeightedAverage {
  std::vector<double> average;       ///< y_j, NaN where W_j == 0
  std::vector<double> weight_sum;    ///< W_j
  int periods = 0;                   ///< R
};
/// Requires period >= 1, x and w of equal length n >= period, w >= 0 and finite.
WeightedAverage weighted_synchronous_average(std::span<const double> x, std::span<const double> w, int period);

/// Hann window in an angle d [rad] (wrapped to (-pi, pi]): cos^2(pi d / (2 h))
/// for |d| < h, else 0; h = half_width_rad in (0, pi].
double hann_angle_window(double d_rad, double half_width_rad);

} // namespace pw::signal
