#include "core/statistics.hpp"

#include "core/error.hpp"

#include <boost/math/distributions/normal.hpp>

#include <cmath>

namespace pw {

double normal_quantile(double p) {
  // Upper quantile: z with P(Z > z) = p, i.e. Phi^-1(1 - p) taken without forming 1 - p.
  require(p > 0 && p < 1, "p", "must be in (0, 1), got ", p);
  return boost::math::quantile(boost::math::complement(boost::math::normal_distribution<>(), p));
}

double chi2_quantile(double nu, double alpha) {
  require(nu > 0, "nu", "must be > 0, got ", nu);
  const double z = normal_quantile(alpha);
  const double h = 2.0 / (9.0 * nu);
  const double t = 1 - h + z * std::sqrt(h);
  return nu * t * t * t;
}

} // namespace pw
