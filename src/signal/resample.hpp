// Order analysis building blocks: resampling a time history onto a uniform
// shaft-angle grid (computed order tracking) and the time-synchronous average.
//
// References:
//  * K. R. Fyfe, E. D. S. Munck, "Analysis of computed order tracking",
//    Mech. Syst. Signal Process. 11(2):187-205, 1997 (angle-domain resampling;
//    interpolation order matters more than the sampling rate).
//  * P. D. McFadden, "A revised model for the extraction of periodic waveforms
//    by time domain averaging", Mech. Syst. Signal Process. 1(1):83-95, 1987
//    (TSA attenuates non-synchronous components; random noise by 1/sqrt(R)).
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace pw::signal {

enum class Interpolation {
  Linear,  ///< 2-point, error O(h^2): exact for signals linear in angle
  Cubic    ///< 4-point Lagrange on the (non-uniform) neighbouring samples, error O(h^4)
};

/// A signal on the uniform angle grid theta_j = theta_0 + j (2 pi / samples_per_rev).
struct AngleDomainSignal {
  std::vector<double> angle_rad;  ///< theta_j [rad], theta_0 = the first input angle
  std::vector<double> time_s;     ///< time at which the shaft reached theta_j [s]
  std::vector<double> values;     ///< signal at theta_j, in the input's unit
  int samples_per_rev = 0;        ///< grid points per revolution [-]
};

/// Resamples `signal`, sampled at `time_s` while the reference shaft was at
/// `angle_rad` (unwrapped, e.g. the carrier angle of a simulation), onto the
/// uniform angle grid from angle_rad.front() to angle_rad.back(). Because the
/// angle increases strictly, the signal is interpolated directly as a function
/// of angle; the returned time_s is interpolated the same way.
/// Requirements (pw::InputError otherwise): equal lengths; at least 2 samples
/// (Linear) or 4 (Cubic); time and angle strictly increasing and finite (for a
/// shaft turning in the negative sense, pass -angle); samples_per_rev >= 2.
AngleDomainSignal angular_resample(std::span<const double> time_s, std::span<const double> signal,
                                   std::span<const double> angle_rad, int samples_per_rev,
                                   Interpolation method = Interpolation::Cubic);

/// Time-synchronous average of an angle-domain signal: with R = floor(n /
/// samples_per_rev) complete revolutions, returns the samples_per_rev values
///   y_j = (1/R) sum_{r=0}^{R-1} x_{j + r samples_per_rev}.
/// A trailing partial revolution is ignored. Components synchronous with the
/// shaft (integer orders) pass unchanged; uncorrelated noise is reduced in
/// RMS by 1/sqrt(R). Throws pw::InputError if samples_per_rev < 1 or fewer
/// than samples_per_rev samples are given.
std::vector<double> time_synchronous_average(std::span<const double> angle_resampled,
                                             int samples_per_rev);

} // namespace pw::signal
