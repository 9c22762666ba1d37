// Gear condition indicators (see condition_indicators.hpp, docs/indicators.md).
#include "signal/condition_indicators.hpp"

#include "core/error.hpp"
#include "signal/fft.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <numeric>

namespace pw::signal {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean(std::span<const double> x) {
  return x.empty() ? 0.0 : std::accumulate(x.begin(), x.end(), 0.0) / static_cast<double>(x.size());
}

/// Central moment m_k = (1/n) sum (x - mean)^k.
double central_moment(std::span<const double> x, int k) {
  if (x.empty()) return kNaN;
  const double mu = mean(x);
  double s = 0;
  for (double v : x) s += std::pow(v - mu, k);
  return s / static_cast<double>(x.size());
}

/// The TSA's spectrum with only the listed orders kept (mean dropped), back in the angle domain.
std::vector<double> keep_orders(const std::vector<std::complex<double>>& X, std::size_t n,
                                const std::vector<bool>& keep) {
  std::vector<std::complex<double>> Y(X.size());
  for (std::size_t k = 1; k < X.size(); ++k)
    if (keep[k]) Y[k] = X[k];
  return inverse_real_fft(Y, n);
}

void require_finite(std::span<const double> x, const char* name) {
  for (std::size_t j = 0; j < x.size(); ++j)
    require(std::isfinite(x[j]), name, "sample ", j, " is not finite (", x[j], ")");
}

} // namespace

TsaDecomposition decompose_tsa(std::span<const double> tsa, const GearOrders& orders) {
  const std::size_t n = tsa.size();
  require(n >= 4, "tsa", "needs at least 4 samples per revolution, got ", n);
  require_finite(tsa, "tsa");
  const int z = orders.mesh_order;
  require(z >= 1 && 2 * static_cast<std::size_t>(z) < n, "mesh_order",
          "must lie in [1, n/2) = [1, ", (n + 1) / 2, ") for a TSA of n = ", n, " samples, got ", z);
  require(orders.shaft_harmonics >= 0 && orders.shaft_harmonics < std::max(z - 1, 1), "shaft_harmonics",
          "must lie in [0, Z - 2] = [0, ", std::max(z - 2, 0),
          "] so that the shaft orders stay clear of the mesh sideband Z - 1, got ", orders.shaft_harmonics);
  const std::vector<std::complex<double>> X = real_fft(tsa);
  const std::size_t bins = X.size();
  std::vector<bool> mesh(bins, false), sidebands(bins, false), shaft(bins, false);
  for (std::size_t k = static_cast<std::size_t>(z); k < bins; k += static_cast<std::size_t>(z)) {
    mesh[k] = true;
    sidebands[k - 1] = true;
    if (k + 1 < bins) sidebands[k + 1] = true;
  }
  for (int k = 1; k <= orders.shaft_harmonics && static_cast<std::size_t>(k) < bins; ++k)
    shaft[static_cast<std::size_t>(k)] = true;
  std::vector<bool> regular(bins), removed_for_residual(bins);
  for (std::size_t k = 0; k < bins; ++k) {
    regular[k] = mesh[k] || sidebands[k] || shaft[k];
    removed_for_residual[k] = mesh[k] || shaft[k];
  }
  TsaDecomposition d;
  d.tsa.assign(tsa.begin(), tsa.end());
  d.regular = keep_orders(X, n, regular);
  const std::vector<double> mesh_and_shaft = keep_orders(X, n, removed_for_residual);
  const double mu = mean(tsa);
  d.difference.resize(n);
  d.residual.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    d.difference[j] = tsa[j] - mu - d.regular[j];
    d.residual[j] = tsa[j] - mu - mesh_and_shaft[j];
  }
  return d;
}

std::vector<double> order_amplitudes(std::span<const double> x) {
  const std::size_t n = x.size();
  require(n >= 2, "x", "needs at least 2 samples, got ", n);
  const std::vector<std::complex<double>> X = real_fft(x);
  std::vector<double> a(X.size());
  for (std::size_t k = 0; k < X.size(); ++k) {
    const bool single = k == 0 || (n % 2 == 0 && k == n / 2);
    a[k] = (single ? 1.0 : 2.0) * std::abs(X[k]) / static_cast<double>(n);
  }
  return a;
}

double rms(std::span<const double> x) {
  if (x.empty()) return kNaN;
  double s = 0;
  for (double v : x) s += v * v;
  return std::sqrt(s / static_cast<double>(x.size()));
}

double standard_deviation(std::span<const double> x) { return std::sqrt(central_moment(x, 2)); }

double central_variance(std::span<const double> x) { return central_moment(x, 2); }

double peak_to_peak(std::span<const double> x) {
  if (x.empty()) return kNaN;
  const auto [lo, hi] = std::minmax_element(x.begin(), x.end());
  return *hi - *lo;
}

double normalized_moment(std::span<const double> x, int k) {
  require(k >= 2, "k", "the moment order must be at least 2, got ", k);
  const double m2 = central_moment(x, 2);
  if (!(m2 > 0)) return kNaN;
  return central_moment(x, k) / std::pow(m2, 0.5 * k);
}

double kurtosis(std::span<const double> x) { return normalized_moment(x, 4); }

double crest_factor(std::span<const double> x) {
  const double sd = standard_deviation(x);
  if (!(sd > 0)) return kNaN;
  const double mu = mean(x);
  double peak = 0;
  for (double v : x) peak = std::max(peak, std::abs(v - mu));
  return peak / sd;
}

double fm0(std::span<const double> tsa, int mesh_order) {
  require(mesh_order >= 1 && 2 * static_cast<std::size_t>(mesh_order) < tsa.size() + 1, "mesh_order",
          "must lie in [1, n/2] for n = ", tsa.size(), " samples, got ", mesh_order);
  const std::vector<double> a = order_amplitudes(tsa);
  double sum = 0;
  for (std::size_t k = static_cast<std::size_t>(mesh_order); k < a.size(); k += static_cast<std::size_t>(mesh_order))
    sum += a[k];
  return sum > 0 ? peak_to_peak(tsa) / sum : kNaN;
}

double fm4(std::span<const double> difference) { return normalized_moment(difference, 4); }
double m6a(std::span<const double> difference) { return normalized_moment(difference, 6); }
double m8a(std::span<const double> difference) { return normalized_moment(difference, 8); }

double na4(std::span<const double> residual, std::span<const double> earlier_variances) {
  double sum = central_moment(residual, 2);
  for (double v : earlier_variances) {
    require(std::isfinite(v) && v >= 0, "earlier_variances", "must be finite and >= 0, got ", v);
    sum += v;
  }
  const double mean_var = sum / static_cast<double>(earlier_variances.size() + 1);
  if (!(mean_var > 0)) return kNaN;
  return central_moment(residual, 4) / (mean_var * mean_var);
}

double nb4(std::span<const double> envelope, std::span<const double> earlier_variances) {
  return na4(envelope, earlier_variances);  // the same statistic, on the envelope
}

std::vector<double> band_envelope(std::span<const double> x, int centre_order, int half_width_orders) {
  const std::size_t n = x.size();
  require(n >= 4, "x", "needs at least 4 samples, got ", n);
  require(centre_order >= 1 && 2 * static_cast<std::size_t>(centre_order) < n, "centre_order",
          "must lie in [1, n/2) for n = ", n, ", got ", centre_order);
  require(half_width_orders >= 0, "half_width_orders", "must be >= 0, got ", half_width_orders);
  const std::vector<std::complex<double>> X = real_fft(x);
  const std::size_t lo = static_cast<std::size_t>(std::max(1, centre_order - half_width_orders));
  // Bins strictly below Nyquist: the Hilbert transform of the Nyquist bin is not representable.
  const std::size_t hi = std::min(static_cast<std::size_t>(centre_order + half_width_orders), (n - 1) / 2);
  std::vector<std::complex<double>> B(X.size()), H(X.size());
  const std::complex<double> minus_i(0.0, -1.0);
  for (std::size_t k = lo; k <= hi; ++k) {
    B[k] = X[k];
    H[k] = minus_i * X[k];
  }
  const std::vector<double> xb = inverse_real_fft(B, n);
  const std::vector<double> xh = inverse_real_fft(H, n);
  std::vector<double> env(n);
  for (std::size_t j = 0; j < n; ++j) env[j] = std::hypot(xb[j], xh[j]);
  return env;
}

int nb4_half_band(int mesh_order) { return std::max(mesh_order / 2, 1); }

double energy_ratio(std::span<const double> difference, std::span<const double> regular) {
  const double r = rms(regular);
  return r > 0 ? rms(difference) / r : kNaN;
}

double sideband_level_factor(std::span<const double> tsa, int mesh_order) {
  const std::vector<double> a = order_amplitudes(tsa);
  const std::size_t z = static_cast<std::size_t>(mesh_order);
  require(mesh_order >= 2 && z + 1 < a.size(), "mesh_order",
          "the sidebands Z +- 1 must lie in [1, n/2] for n = ", tsa.size(), ", got Z = ", mesh_order);
  const double sd = standard_deviation(tsa);
  return sd > 0 ? (a[z - 1] + a[z + 1]) / sd : kNaN;
}

ConditionIndicators condition_indicators(std::span<const double> tsa, const GearOrders& orders,
                                         std::span<const double> earlier_residual_variances,
                                         std::span<const double> earlier_envelope_variances) {
  const TsaDecomposition d = decompose_tsa(tsa, orders);
  const double floor = kRoundoffFloor * rms(tsa);
  const bool has_difference = rms(d.difference) > floor;
  const bool has_residual = rms(d.residual) > floor;
  const int z = orders.mesh_order;
  const std::vector<double> env = band_envelope(tsa, z, nb4_half_band(z));
  const bool has_envelope = standard_deviation(env) > floor;
  ConditionIndicators c;
  c.rms = rms(tsa);
  c.peak_to_peak = peak_to_peak(tsa);
  c.kurtosis = kurtosis(tsa);
  c.crest_factor = crest_factor(tsa);
  c.fm0 = fm0(tsa, z);
  c.fm4 = has_difference ? fm4(d.difference) : kNaN;
  c.m6a = has_difference ? m6a(d.difference) : kNaN;
  c.m8a = has_difference ? m8a(d.difference) : kNaN;
  c.residual_variance = has_residual ? central_variance(d.residual) : 0.0;
  c.na4 = has_residual ? na4(d.residual, earlier_residual_variances) : kNaN;
  c.envelope_variance = has_envelope ? central_variance(env) : 0.0;
  c.nb4 = has_envelope ? nb4(env, earlier_envelope_variances) : kNaN;
  // A difference signal at round-off level is zero energy, not an undefined ratio.
  c.energy_ratio = !(rms(d.regular) > 0) ? kNaN : has_difference ? energy_ratio(d.difference, d.regular) : 0.0;
  c.sideband_level_factor = 2 * static_cast<std::size_t>(z) + 2 <= tsa.size() ? sideband_level_factor(tsa, z) : kNaN;
  return c;
}

WeightedAverage weighted_synchronous_average(std::span<const double> x, std::span<const double> w, int period) {
  require(period >= 1, "period", "must be at least 1 sample, got ", period);
  require(w.size() == x.size(), "weights", "has ", w.size(), " samples but the signal has ", x.size());
  const std::size_t p = static_cast<std::size_t>(period);
  require(x.size() >= p, "signal", "has ", x.size(), " samples, fewer than one period of ", p);
  WeightedAverage a;
  a.periods = static_cast<int>(x.size() / p);
  a.average.assign(p, 0.0);
  a.weight_sum.assign(p, 0.0);
  for (std::size_t r = 0; r < static_cast<std::size_t>(a.periods); ++r)
    for (std::size_t j = 0; j < p; ++j) {
      const double wj = w[r * p + j];
      require(std::isfinite(wj) && wj >= 0, "weights", "sample ", r * p + j, " must be finite and >= 0, got ", wj);
      a.average[j] += wj * x[r * p + j];
      a.weight_sum[j] += wj;
    }
  for (std::size_t j = 0; j < p; ++j) a.average[j] = a.weight_sum[j] > 0 ? a.average[j] / a.weight_sum[j] : kNaN;
  return a;
}

double hann_angle_window(double d_rad, double half_width_rad) {
  constexpr double pi = std::numbers::pi;
  require(half_width_rad > 0 && half_width_rad <= pi, "half_width_rad", "must lie in (0, pi], got ", half_width_rad);
  const double d = std::remainder(d_rad, 2 * pi);  // in [-pi, pi]
  if (std::abs(d) >= half_width_rad) return 0.0;
  const double c = std::cos(pi * d / (2 * half_width_rad));
  return c * c;
}

} // namespace pw::signal
