#include "signal/decimate.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw::signal {

DecimationFilter decimation_filter(int k, int half_taps_per_factor) {
  if (k < 1) throw InputError("decimation factor", detail::concat("must be >= 1, got ", k));
  if (half_taps_per_factor < 1)
    throw InputError("decimation filter length", detail::concat("taps per factor must be >= 1, got ",
                                                                half_taps_per_factor));
  DecimationFilter f;
  f.factor = k;
  if (k == 1) {
    f.taps = {1.0};
    return f;
  }
  constexpr double pi = std::numbers::pi;
  f.half = half_taps_per_factor * k;
  const double fc = 0.4 / k;  // cutoff / input sample rate
  f.taps.resize(2 * static_cast<std::size_t>(f.half) + 1);
  double sum = 0;
  for (int m = -f.half; m <= f.half; ++m) {
    const double sinc = m == 0 ? 2 * fc : std::sin(2 * pi * fc * m) / (pi * m);
    const double a = pi * (m + f.half) / f.half;  // Blackman over the 2 half + 1 taps
    const double w = 0.42 - 0.5 * std::cos(a) + 0.08 * std::cos(2 * a);
    f.taps[static_cast<std::size_t>(m + f.half)] = sinc * w;
    sum += sinc * w;
  }
  for (double& h : f.taps) h /= sum;  // unit DC gain
  return f;
}

std::vector<double> decimate(std::span<const double> x, const DecimationFilter& filter, std::size_t first,
                             std::size_t count) {
  const std::size_t half = static_cast<std::size_t>(filter.half);
  const std::size_t k = static_cast<std::size_t>(filter.factor);
  if (count == 0) return {};
  if (first < half || first + (count - 1) * k + half >= x.size())
    throw InputError("decimation", detail::concat("outputs ", count, " from input sample ", first, " with ",
                                                  filter.taps.size(), " taps need ",
                                                  first + (count - 1) * k + half + 1, " samples, have ", x.size()));
  std::vector<double> y(count);
  for (std::size_t j = 0; j < count; ++j) {
    const double* xi = x.data() + (first + j * k - half);
    double acc = 0;
    for (std::size_t m = 0; m < filter.taps.size(); ++m) acc += filter.taps[m] * xi[m];
    y[j] = acc;
  }
  return y;
}

} // namespace pw::signal
