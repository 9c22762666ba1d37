#include "core/statistics.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw {

double normal_quantile(double p) {
  // Upper quantile: z with P(Z > z) = p.
  require(p > 0 && p < 1, "p", "must be in (0, 1), got ", p);
  const double q = 1 - p;  // lower-tail probability
  // Acklam's approximation of the inverse normal CDF.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  double x;
  if (q < 0.02425) {
    const double t = std::sqrt(-2 * std::log(q));
    x = (((((c[0] * t + c[1]) * t + c[2]) * t + c[3]) * t + c[4]) * t + c[5]) /
        ((((d[0] * t + d[1]) * t + d[2]) * t + d[3]) * t + 1);
  } else if (q > 1 - 0.02425) {
    const double t = std::sqrt(-2 * std::log(1 - q));
    x = -(((((c[0] * t + c[1]) * t + c[2]) * t + c[3]) * t + c[4]) * t + c[5]) /
        ((((d[0] * t + d[1]) * t + d[2]) * t + d[3]) * t + 1);
  } else {
    const double t = q - 0.5, r = t * t;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * t /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  // One Newton step on the CDF.
  const double e = 0.5 * std::erfc(-x / std::numbers::sqrt2) - q;
  const double u = e * std::sqrt(2 * kPi) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

double chi2_quantile(double nu, double alpha) {
  require(nu > 0, "nu", "must be > 0, got ", nu);
  const double z = normal_quantile(alpha);
  const double h = 2.0 / (9.0 * nu);
  const double t = 1 - h + z * std::sqrt(h);
  return nu * t * t * t;
}

} // namespace pw
