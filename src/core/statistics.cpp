#include "core/statistics.hpp"

#include "core/error.hpp"

#include <boost/math/distributions/fisher_f.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <boost/math/special_functions/bessel.hpp>

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

double f_quantile(double nu1, double nu2, double alpha) {
  require(nu1 > 0, "nu1", "must be > 0, got ", nu1);
  require(nu2 > 0, "nu2", "must be > 0, got ", nu2);
  require(alpha > 0 && alpha < 1, "alpha", "must be in (0, 1), got ", alpha);
  return boost::math::quantile(boost::math::complement(boost::math::fisher_f_distribution<>(nu1, nu2), alpha));
}

double student_t_quantile(double nu, double alpha) {
  require(nu > 0, "nu", "must be > 0, got ", nu);
  require(alpha > 0 && alpha < 1, "alpha", "must be in (0, 1), got ", alpha);
  return boost::math::quantile(boost::math::complement(boost::math::students_t_distribution<>(nu), alpha));
}

namespace {
/// Double arithmetic throughout: Boost.Math's default promotes double to long double, which
/// costs three times as much here and is not needed at the accuracy the comparison uses.
using DoublePolicy = boost::math::policies::policy<boost::math::policies::promote_double<false>>;
} // namespace

double bessel_i0(double x) { return boost::math::cyl_bessel_i(0, x, DoublePolicy()); }
double bessel_i1(double x) { return boost::math::cyl_bessel_i(1, x, DoublePolicy()); }

} // namespace pw
