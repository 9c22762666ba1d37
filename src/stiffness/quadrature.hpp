// Gauss-Legendre quadrature on a finite interval.
//
// The beam-energy integrals of tooth_compliance.cpp have smooth (analytic)
// integrands once the involute is parametrised by its roll angle, so
// Gauss-Legendre converges exponentially; tests/stiffness shows the
// convergence. Rules are built once at set-up (they allocate) and reused.
#pragma once

#include <vector>

namespace pw::stiffness {

/// n-point Gauss-Legendre rule on [-1, 1]: nodes x_i (ascending) and weights w_i.
struct GaussLegendreRule {
  std::vector<double> nodes;
  std::vector<double> weights;
  int size() const { return static_cast<int>(nodes.size()); }
};

/// Builds the n-point rule (n >= 1) by Newton iteration on P_n from the
/// Tricomi initial guesses; nodes and weights are accurate to ~1e-15.
/// Throws pw::InputError for n < 1 or n > 512.
GaussLegendreRule gauss_legendre(int n);

/// Integral of f over [a, b] with the rule mapped affinely onto [a, b]
/// (b < a gives the negative of the integral over [b, a], as usual).
template <class F>
double integrate(const GaussLegendreRule& rule, double a, double b, const F& f) {
  const double half = 0.5 * (b - a);
  const double mid = 0.5 * (a + b);
  double sum = 0.0;
  for (int i = 0; i < rule.size(); ++i) sum += rule.weights[i] * f(mid + half * rule.nodes[i]);
  return half * sum;
}

} // namespace pw::stiffness
