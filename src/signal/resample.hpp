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

#include <array>
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

/// angular_resample's cubic interpolation for one angle record, planned once: its stencils and
/// Lagrange weights depend on the angles only, so every signal sampled at those angles (the
/// channels of one simulation share its carrier angle) is resampled with four products per grid
/// point instead of the weights' twelve divisions again. apply() returns the values
/// angular_resample(t, signal, angle_rad, samples_per_rev, Interpolation::Cubic) returns, bit
/// for bit (the same arithmetic in the same order). Requirements as angular_resample's, checked
/// here (angles) and in apply() (the signal).
class CubicResamplePlan {
public:
  /// The first `max_points` grid points only (all when 0 or more than the record has).
  CubicResamplePlan(std::span<const double> angle_rad, int samples_per_rev, std::size_t max_points = 0);
  /// Grid points of the whole record (angular_resample's values.size()).
  std::size_t record_points() const { return record_points_; }
  /// Grid points this plan resamples: min(max_points, record_points()).
  std::size_t points() const { return base_.size(); }
  /// The first points() values of the resampled `signal` (angle_rad.size() samples).
  std::vector<double> apply(std::span<const double> signal) const;

private:
  std::size_t samples_ = 0, record_points_ = 0;
  std::vector<std::size_t> base_;             // first sample of each point's 4-sample stencil
  std::vector<std::array<double, 4>> weight_;  // its Lagrange weights
};

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
