// Minimum of a unimodal scalar function by golden-section search, of one that need not be
// unimodal by a scan first, and the standard error a chi-square's curvature gives its minimiser:
// the one implementation of each that the diagnosis's one-parameter searches (a housing gain, a
// sensor's change since a baseline, a level's change) use.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

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

/// golden_section_minimum over [x0 - h, x0 + h]; while its result is at an edge, the bracket is
/// centred again on that result and its half-width doubled (h 2^k, `iterations` + k reductions:
/// the final bracket keeps its relative resolution), at most `doublings` times, stopping early
/// when a wider bracket ends at an edge again having lowered f by less than `resolution` (an f
/// that flattens out towards the edge has no minimum there to find). The result's at_edge is that
/// of the last bracket kept: a minimum outside every bracket, or f flat to within `resolution`
/// beyond the last one.
template <class F>
BracketedMinimum expanding_golden_section_minimum(F&& f, double x0, double h, int iterations, int doublings,
                                                  double resolution) {
  BracketedMinimum best = golden_section_minimum(f, x0 - h, x0 + h, iterations);
  for (int k = 1; best.at_edge && k <= doublings; ++k) {
    const double half_width = h * std::ldexp(1.0, k);
    const BracketedMinimum wider = golden_section_minimum(f, best.x - half_width, best.x + half_width, iterations + k);
    // An interior minimum of a bracket around the last result is the one sought, however little
    // lower; one at an edge again counts only if it went down by the resolution.
    if (!wider.at_edge || wider.value < best.value - resolution) best = wider;
    else break;
  }
  return best;
}

/// Standard error of the minimiser x of a chi-square chi2(x): sqrt(2 / chi2''(x)) (the
/// curvature of a chi-square is twice the inverse variance), chi2'' by central differences of
/// step h. Infinite when the curvature is not positive (a flat or non-convex chi2 there) or not
/// finite (chi2 not finite at a neighbour).
template <class F>
double chi2_curvature_std(F&& chi2, double x, double h) {
  const double curv = (chi2(x + h) - 2 * chi2(x) + chi2(x - h)) / (h * h);
  // A failed neighbour (chi2 infinite) is no curvature: it would give a standard error of 0.
  return std::isfinite(curv) && curv > 0 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity();
}

/// Where scanned_minimum ended.
struct ScannedMinimum {
  double x = 0;                  ///< the best point evaluated
  double value = 0;              ///< f(x)
  bool at_edge = false;          ///< the golden section's final bracket touches an edge of [lo, hi]
  bool failed = false;           ///< f was not finite at any scan point (nothing else evaluated)
  std::vector<double> scan_x, scan_value;  ///< the scan's points and values
};

/// Minimum of f over [lo, hi] where f need not be unimodal (a chi-square in a stiffness level
/// moves resonances through the lines): f at the centres of `cells` equal cells (evaluated by
/// scan(xs), which returns f at each and may run them in parallel), then `iterations`
/// golden-section reductions over the best cell and its neighbours (the interval's edge where it
/// has none), then one parabolic step through f at the bracket's midpoint m and m +- h: the final
/// bracket can still be wide against a steep f. The result is the best point evaluated (that
/// midpoint, the parabola's vertex, the scan's best). A non-finite f (a failed evaluation) is
/// never chosen, and no vertex is taken through one. Evaluations: cells + iterations + 2 + 3 (+1 for the vertex).
template <class F, class Scan>
ScannedMinimum scanned_minimum(F&& f, Scan&& scan, double lo, double hi, int cells, int iterations, double h) {
  ScannedMinimum out;
  const double cell = (hi - lo) / cells;
  for (int i = 0; i < cells; ++i) out.scan_x.push_back(lo + (i + 0.5) * cell);
  out.scan_value = scan(out.scan_x);
  const auto best = std::min_element(out.scan_value.begin(), out.scan_value.end());
  if (best == out.scan_value.end() || !std::isfinite(*best)) {
    out.failed = true;
    return out;
  }
  const double b = out.scan_x[static_cast<std::size_t>(best - out.scan_value.begin())];
  const double a0 = std::max(lo, b - 1.5 * cell), a1 = std::min(hi, b + 1.5 * cell);
  const BracketedMinimum m = golden_section_minimum(f, a0, a1, iterations);
  const double f0 = f(m.x), fp = f(m.x + h), fm = f(m.x - h);
  double x = m.x, fx = f0;
  // Only through three finite values: a failed neighbour would put the vertex at NaN.
  const bool finite = std::isfinite(f0) && std::isfinite(fp) && std::isfinite(fm);
  if (const double second = fp - 2 * f0 + fm; finite && second > 0) {
    const double xp = std::clamp(m.x - h * (fp - fm) / (2 * second), a0, a1);
    if (const double fxp = f(xp); fxp < fx) x = xp, fx = fxp;
  }
  if (*best < fx) x = b, fx = *best;
  out.x = x;
  out.value = fx;
  // At the interval's edge only when the bracket touches an edge the interval has: a bracket
  // edge inside it is the scan's choice of cells.
  out.at_edge = m.at_edge && (m.x - lo <= m.width || hi - m.x <= m.width);
  return out;
}

} // namespace pw
