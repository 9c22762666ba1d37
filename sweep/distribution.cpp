#include "distribution.hpp"

#include <boost/math/distributions/lognormal.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/triangular.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pw::sweep {
namespace {

/// Boost.Math's lognormal of the value with the given mean and standard deviation
/// (Dakota's lognormal_uncertain parametrization).
boost::math::lognormal_distribution<> lognormal(const Distribution& d) {
  const double cv = d.std_dev / d.mean;
  const double zeta2 = std::log1p(cv * cv);
  return boost::math::lognormal_distribution<>(std::log(d.mean) - 0.5 * zeta2, std::sqrt(zeta2));
}

template <class Dist>
double truncated_quantile(const Dist& dist, double u, double lo, double hi) {
  const double p_lo = std::isfinite(lo) ? boost::math::cdf(dist, std::max(lo, boost::math::support(dist).first)) : 0.0;
  const double p_hi = std::isfinite(hi) ? boost::math::cdf(dist, std::min(hi, boost::math::support(dist).second)) : 1.0;
  // An unbounded tail (no truncation, or one too far out to have a probability in double) is
  // cut at kTailProbability; a finite bound's own probability is kept, so u = 0 gives the bound.
  const double p = std::clamp(p_lo + u * (p_hi - p_lo), std::max(p_lo, kTailProbability),
                              std::min(p_hi, 1.0 - kTailProbability));
  // Clamped to the bounds: guards the last ulp of cdf/quantile (as from_unit does for uniform factors).
  return std::clamp(boost::math::quantile(dist, p), lo, hi);
}

} // namespace

std::string_view to_string(DistributionKind kind) {
  switch (kind) {
  case DistributionKind::Uniform: return "uniform";
  case DistributionKind::Normal: return "normal";
  case DistributionKind::LogNormal: return "lognormal";
  case DistributionKind::Triangular: return "triangular";
  }
  return "uniform";
}

double inverse_cdf(const Distribution& d, double u, double lo, double hi) {
  switch (d.kind) {
  case DistributionKind::Normal:
    return truncated_quantile(boost::math::normal_distribution<>(d.mean, d.std_dev), u, lo, hi);
  case DistributionKind::LogNormal: return truncated_quantile(lognormal(d), u, lo, hi);
  case DistributionKind::Triangular: {
    // Bounded: min + u (max - min) in probability, no tail to cut.
    const boost::math::triangular_distribution<> dist(lo, d.mode, hi);
    return std::clamp(boost::math::quantile(dist, u), lo, hi);
  }
  case DistributionKind::Uniform: break;
  }
  throw std::logic_error("inverse_cdf: uniform factors map in from_unit");
}

} // namespace pw::sweep
