// Angle-domain resampling and time-synchronous averaging (see resample.hpp).
#include "signal/resample.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

namespace pw::signal {

namespace {

void require_strictly_increasing(std::span<const double> v, const std::string& name) {
  for (std::size_t j = 0; j < v.size(); ++j) {
    require(std::isfinite(v[j]), name, "sample ", j, " is not finite (", v[j], ")");
    if (j > 0)
      require(v[j] > v[j - 1], name, "must increase strictly, but sample ", j, " (", v[j],
              ") follows ", v[j - 1]);
  }
}


/// The cubic stencil of grid angle theta in interval [angle_i, angle_(i+1)]: the centred 4-point
/// stencil i-1 .. i+2, shifted inwards at the ends; returns its first sample and writes its
/// Lagrange weights. One function for angular_resample and CubicResamplePlan, so that both
/// compute the same weights.
std::size_t cubic_stencil(std::span<const double> angle_rad, std::size_t i, double theta, std::array<double, 4>& w) {
  const std::size_t n = angle_rad.size();
  const std::size_t b = std::min(i > 0 ? i - 1 : 0, n - 4);
  for (std::size_t q = 0; q < 4; ++q) {
    w[q] = 1.0;
    for (std::size_t r = 0; r < 4; ++r)
      if (r != q) w[q] *= (theta - angle_rad[b + r]) / (angle_rad[b + q] - angle_rad[b + r]);
  }
  return b;
}

/// Grid points of angular_resample's uniform grid from angle_rad.front() to angle_rad.back().
std::size_t grid_points(std::span<const double> angle_rad, double dtheta) {
  // The 1e-9 keeps a grid point that lands on angle_rad.back() up to rounding
  // (e.g. a record of exactly R revolutions gives R*samples_per_rev + 1 points).
  return static_cast<std::size_t>(std::floor((angle_rad.back() - angle_rad.front()) / dtheta + 1e-9)) + 1;
}
} // namespace

AngleDomainSignal angular_resample(std::span<const double> time_s, std::span<const double> signal,
                                   std::span<const double> angle_rad, int samples_per_rev,
                                   Interpolation method) {
  const std::size_t n = time_s.size();
  require(signal.size() == n, "signal", "has ", signal.size(), " samples but time_s has ", n);
  require(angle_rad.size() == n, "angle_rad", "has ", angle_rad.size(),
          " samples but time_s has ", n);
  const std::size_t stencil = method == Interpolation::Cubic ? 4 : 2;
  require(n >= stencil, "signal", "has ", n, " samples, the interpolation needs at least ",
          stencil);
  require(samples_per_rev >= 2, "samples_per_rev", "must be at least 2, got ", samples_per_rev);
  require_strictly_increasing(time_s, "time_s");
  require_strictly_increasing(angle_rad, "angle_rad");
  for (std::size_t j = 0; j < n; ++j)
    require(std::isfinite(signal[j]), "signal", "sample ", j, " is not finite (", signal[j], ")");

  const double dtheta = 2.0 * std::numbers::pi / static_cast<double>(samples_per_rev);
  const double theta0 = angle_rad.front();
  const std::size_t m = grid_points(angle_rad, dtheta);

  AngleDomainSignal out;
  out.samples_per_rev = samples_per_rev;
  out.angle_rad.resize(m);
  out.time_s.resize(m);
  out.values.resize(m);

  std::size_t i = 0;  // interval [angle_i, angle_{i+1}] containing theta; theta grows with j
  for (std::size_t j = 0; j < m; ++j) {
    const double theta = theta0 + static_cast<double>(j) * dtheta;
    while (i + 2 < n && angle_rad[i + 1] <= theta) ++i;

    double t = 0, x = 0;
    if (method == Interpolation::Linear) {
      const double s = (theta - angle_rad[i]) / (angle_rad[i + 1] - angle_rad[i]);
      t = (1 - s) * time_s[i] + s * time_s[i + 1];
      x = (1 - s) * signal[i] + s * signal[i + 1];
    } else {
      std::array<double, 4> w{};
      const std::size_t b = cubic_stencil(angle_rad, i, theta, w);
      for (std::size_t q = 0; q < 4; ++q) {
        t += w[q] * time_s[b + q];
        x += w[q] * signal[b + q];
      }
    }
    out.angle_rad[j] = theta;
    out.time_s[j] = t;
    out.values[j] = x;
  }
  return out;
}

CubicResamplePlan::CubicResamplePlan(std::span<const double> angle_rad, int samples_per_rev, std::size_t max_points)
    : samples_(angle_rad.size()) {
  const std::size_t n = angle_rad.size();
  require(n >= 4, "signal", "has ", n, " samples, the interpolation needs at least ", 4);
  require(samples_per_rev >= 2, "samples_per_rev", "must be at least 2, got ", samples_per_rev);
  require_strictly_increasing(angle_rad, "angle_rad");
  const double dtheta = 2.0 * std::numbers::pi / static_cast<double>(samples_per_rev);
  const double theta0 = angle_rad.front();
  record_points_ = grid_points(angle_rad, dtheta);
  const std::size_t m = max_points == 0 ? record_points_ : std::min(max_points, record_points_);
  base_.resize(m);
  weight_.resize(m);
  std::size_t i = 0;  // as in angular_resample
  for (std::size_t j = 0; j < m; ++j) {
    const double theta = theta0 + static_cast<double>(j) * dtheta;
    while (i + 2 < n && angle_rad[i + 1] <= theta) ++i;
    base_[j] = cubic_stencil(angle_rad, i, theta, weight_[j]);
  }
}

std::vector<double> CubicResamplePlan::apply(std::span<const double> signal) const {
  require(signal.size() == samples_, "signal", "has ", signal.size(), " samples but the angle record has ", samples_);
  for (std::size_t j = 0; j < signal.size(); ++j)
    require(std::isfinite(signal[j]), "signal", "sample ", j, " is not finite (", signal[j], ")");
  std::vector<double> out(base_.size());
  for (std::size_t j = 0; j < base_.size(); ++j) {
    const double* y = signal.data() + base_[j];
    const std::array<double, 4>& w = weight_[j];
    double x = 0;
    for (std::size_t q = 0; q < 4; ++q) x += w[q] * y[q];
    out[j] = x;
  }
  return out;
}

std::vector<double> time_synchronous_average(std::span<const double> angle_resampled,
                                             int samples_per_rev) {
  require(samples_per_rev >= 1, "samples_per_rev", "must be at least 1, got ", samples_per_rev);
  const auto per_rev = static_cast<std::size_t>(samples_per_rev);
  require(angle_resampled.size() >= per_rev, "angle_resampled", "has ", angle_resampled.size(),
          " samples, fewer than one revolution (", per_rev, ")");
  const std::size_t revolutions = angle_resampled.size() / per_rev;
  std::vector<double> avg(per_rev, 0.0);
  for (std::size_t r = 0; r < revolutions; ++r)
    for (std::size_t j = 0; j < per_rev; ++j) avg[j] += angle_resampled[r * per_rev + j];
  for (double& v : avg) v /= static_cast<double>(revolutions);
  return avg;
}

} // namespace pw::signal
