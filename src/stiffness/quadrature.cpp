#include "stiffness/quadrature.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw::stiffness {

GaussLegendreRule gauss_legendre(int n) {
  require(n >= 1 && n <= 512, "quadrature_points", "must be in [1, 512], got ", n);
  GaussLegendreRule rule;
  rule.nodes.resize(n);
  rule.weights.resize(n);
  const int half = (n + 1) / 2;
  for (int i = 0; i < half; ++i) {
    // Tricomi's asymptotic guess for the i-th largest root, then Newton on
    // P_n evaluated by the three-term recurrence
    // j P_j = (2j - 1) x P_{j-1} - (j - 1) P_{j-2}.
    const double k = i + 1.0;
    double x = std::cos(std::numbers::pi * (k - 0.25) / (n + 0.5));
    double dp = 0.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int j = 2; j <= n; ++j) {
        const double p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
      }
      // p1 = P_n(x), p0 = P_{n-1}(x); P_n' = n (x P_n - P_{n-1}) / (x^2 - 1).
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::fabs(dx) < 1e-16) break;
    }
    {
      // Recompute the derivative at the converged root for the weight.
      double p0 = 1.0, p1 = x;
      for (int j = 2; j <= n; ++j) {
        const double p2 = ((2.0 * j - 1.0) * x * p1 - (j - 1.0) * p0) / j;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
    }
    const double w = 2.0 / ((1.0 - x * x) * dp * dp);
    rule.nodes[n - 1 - i] = x;
    rule.nodes[i] = -x;
    rule.weights[n - 1 - i] = w;
    rule.weights[i] = w;
  }
  if (n % 2 == 1) rule.nodes[n / 2] = 0.0;  // exact centre node for odd n
  return rule;
}

} // namespace pw::stiffness
