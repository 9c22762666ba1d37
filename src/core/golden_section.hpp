// Minimum of a unimodal scalar function by golden-section search, and the standard error a
// chi-square's curvature gives its minimiser: the one implementation of both that the
// diagnosis's one-parameter searches (a housing gain, a sensor's change since a baseline) use.
#pragma once

#include <cmath>
#include <limits>

namespace pw {

/// Where golden_section_minimum ended.
struct BracketedMinimum {
  double x = 0;          ///< midpoint of the final bracket
  double value = 0;      ///< f at the last interior point kept (not at x: no extra evaluation)
  double width = 0;      ///< width of the final bracket
  bool at_edge = false;  ///< x within one final bracket of either initial edge: the true
                         ///< minimum may lie beyond the search interval
};

/// Golden-section search for the minimum of f over [lo, hi] in `iterations` reductions of the
/// bracket by 0.618 each (Kiefer 1953). f must be unimodal there for the answer to be the
/// minimum; otherwise it is a local one.
template <class F>
BracketedMinimum golden_section_minimum(F&& f, double lo, double hi, int iterations) {
  const double lo0 = lo, hi0 = hi;
  const double gr = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < iterations; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - gr * (hi - lo), f1 = f(x1);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + gr * (hi - lo), f2 = f(x2);
    }
  }
  BracketedMinimum m;
  m.x = 0.5 * (lo + hi);
  m.width = hi - lo;
  m.value = f1 < f2 ? f1 : f2;
  m.at_edge = m.x - lo0 <= m.width || hi0 - m.x <= m.width;
  return m;
}

/// Standard error of the minimiser x of a chi-square chi2(x): sqrt(2 / chi2''(x)) (the
/// curvature of a chi-square is twice the inverse variance), chi2'' by central differences of
/// step h. Infinite when the curvature is not positive (a flat or non-convex chi2 there).
template <class F>
double chi2_curvature_std(F&& chi2, double x, double h) {
  const double curv = (chi2(x + h) - 2 * chi2(x) + chi2(x - h)) / (h * h);
  return curv > 0 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity();
}

} // namespace pw
