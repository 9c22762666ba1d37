#include "diagnose/sensor_change.hpp"

#include <cmath>
#include <limits>

namespace pw::diagnose {

std::vector<std::vector<double>> scaled_housing(const ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                                                double g0, int ch, double rho) {
  auto m = amp;
  const std::size_t c = static_cast<std::size_t>(ch);
  const auto& cells = cmp.spectra().layout.cells;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t b = static_cast<std::size_t>(cells[i].bin);
    const double e = cmp.baseline_offset(ch * cmp.cells() + static_cast<int>(i));
    m[c][b] = rho * amp[c][b] + (rho - 1) * e / g0;
  }
  return m;
}

SensorScale fit_sensor_scale(const ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                             const std::vector<double>& gains, int ch, double alpha) {
  const double g0 = gains[static_cast<std::size_t>(ch)];
  auto chi2 = [&](double ln_rho, Half h) {
    return cmp.score(scaled_housing(cmp, amp, g0, ch, std::exp(ln_rho)), h, gains, HousingGains::Given).chi2;
  };
  constexpr double kLnRange = 2.4849066497880004;  // ln 12
  constexpr int kIterations = 40;                  // bracket 0.618^40 ~ 5e-9 of its width
  double lo = -kLnRange, hi = kLnRange;
  const double gr = (std::sqrt(5.0) - 1) / 2;
  double x1 = hi - gr * (hi - lo), x2 = lo + gr * (hi - lo), f1 = chi2(x1, Half::Fit), f2 = chi2(x2, Half::Fit);
  for (int it = 0; it < kIterations; ++it) {
    if (f1 < f2) {
      hi = x2, x2 = x1, f2 = f1, x1 = hi - gr * (hi - lo), f1 = chi2(x1, Half::Fit);
    } else {
      lo = x1, x1 = x2, f1 = f2, x2 = lo + gr * (hi - lo), f2 = chi2(x2, Half::Fit);
    }
  }
  SensorScale s;
  const double x = 0.5 * (lo + hi);
  s.rho = std::exp(x);
  // se(ln rho) = sqrt(2 / chi2''), chi2'' by central differences of step 1e-3 in ln rho.
  const double h = 1e-3;
  const double curv = (chi2(x + h, Half::Fit) - 2 * chi2(x, Half::Fit) + chi2(x - h, Half::Fit)) / (h * h);
  s.ln_rho_std = curv > 0 ? std::sqrt(2.0 / curv) : std::numeric_limits<double>::infinity();
  s.chi2_fit_1 = chi2(0.0, Half::Fit);
  s.chi2_fit = chi2(x, Half::Fit);
  s.chi2_held_1 = chi2(0.0, Half::HeldOut);
  s.chi2_held = chi2(x, Half::HeldOut);
  s.bound_held = cmp.null_quantile(scaled_housing(cmp, amp, g0, ch, s.rho), gains, Half::HeldOut, alpha / 2, 1);
  return s;
}

} // namespace pw::diagnose
