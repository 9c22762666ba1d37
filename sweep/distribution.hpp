// The distribution of a sampled campaign factor (latin_hypercube, saltelli):
// a unit-cube value u in [0, 1) becomes a factor value through the inverse
// cumulative distribution function, so the design's stratification carries
// over to any distribution (McKay, Beckman & Conover 1979). The kinds and
// their parameters are Dakota's common "uncertain" variables (Dakota 6
// reference manual: normal_uncertain, lognormal_uncertain,
// triangular_uncertain); the quantiles come from Boost.Math.
//
//   uniform     on [min, max] (linear, or log-uniform for scale = "log": design.hpp)
//   normal      mean, std_dev; optional truncation to [min, max]
//   lognormal   mean, std_dev of the value itself (> 0): ln(value) is normal with
//               zeta^2 = ln(1 + (std_dev/mean)^2), lambda = ln(mean) - zeta^2/2;
//               optional truncation to [min, max]
//   triangular  min, mode, max
//
// Truncation maps u to F^-1(F(min) + u (F(max) - F(min))). An untruncated tail
// would send u = 0 (row 0 of a Saltelli design without a digital shift) to
// -infinity; probabilities of a normal or lognormal are therefore kept in
// [2^-33, 1 - 2^-33], half a cell of the 32-bit Sobol' grid, which no Latin
// hypercube of at most kMaxCases strata reaches either (6.34 standard
// deviations for a normal). A finite truncation bound is reached exactly.
#pragma once

#include <limits>
#include <string_view>

namespace pw::sweep {

enum class DistributionKind { Uniform, Normal, LogNormal, Triangular };

struct Distribution {
  DistributionKind kind = DistributionKind::Uniform;
  double mean = 0;     ///< normal, lognormal: mean of the value [the factor's unit]
  double std_dev = 0;  ///< normal, lognormal: standard deviation of the value [the factor's unit]
  double mode = 0;     ///< triangular: the most likely value [the factor's unit]
};

/// "uniform", "normal", "lognormal", "triangular".
std::string_view to_string(DistributionKind kind);

/// Smallest and largest probability the inverse CDF is evaluated at (see above).
inline constexpr double kTailProbability = 0x1p-33;

/// The value at unit-cube coordinate u in [0, 1) of `d` truncated to [lo, hi]
/// (infinite bounds: no truncation; triangular: its support). Normal,
/// lognormal and triangular only (uniform factors map in design.cpp's
/// from_unit). Parameters must have been checked (check_distribution in design.cpp).
double inverse_cdf(const Distribution& d, double u, double lo = -std::numeric_limits<double>::infinity(),
                   double hi = std::numeric_limits<double>::infinity());

} // namespace pw::sweep
