#include "diagnose/sensor_change.hpp"

#include "core/golden_section.hpp"

#include <cmath>

namespace pw::diagnose {

std::vector<std::vector<double>> scaled_housing(const ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                                                double g0, int ch, double rho) {
  auto m = amp;
  const std::size_t c = static_cast<std::size_t>(ch);
  const auto& cells = cmp.spectra().layout.cells;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const std::size_t b = static_cast<std::size_t>(cells[i].bin);
    // rho times the baseline's lines, T g0 a + e: the compared amplitude is T g0 m + e.
    const int f = ch * cmp.cells() + static_cast<int>(i);
    const double e = cmp.baseline_offset(f);
    m[c][b] = rho * amp[c][b] + (rho - 1) * e / (g0 * cmp.baseline_transfer(f));
  }
  return m;
}

SensorScale fit_sensor_scale(ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                             const std::vector<double>& gains, int ch, double alpha) {
  const ScopedDiscrepancyReference own_v(cmp, amp, gains);
  const double g0 = gains[static_cast<std::size_t>(ch)];
  auto chi2 = [&](double ln_rho, Half h) {
    return cmp.score(scaled_housing(cmp, amp, g0, ch, std::exp(ln_rho)), h, gains, HousingGains::Given).chi2;
  };
  auto chi2_fit = [&](double ln_rho) { return chi2(ln_rho, Half::Fit); };
  constexpr int kIterations = 40;  // bracket 0.618^40 ~ 5e-9 of its width
  const BracketedMinimum best =
      golden_section_minimum(chi2_fit, std::log(kMinSensorScale), std::log(kMaxSensorScale), kIterations);
  SensorScale s;
  const double x = best.x;
  s.rho = std::exp(x);
  s.at_bracket_edge = best.at_edge;
  s.ln_rho_std = chi2_curvature_std(chi2_fit, x, 1e-3);  // step 1e-3 in ln rho, as for a housing gain
  s.chi2_fit_1 = chi2(0.0, Half::Fit);
  s.chi2_fit = chi2(x, Half::Fit);
  s.chi2_held_1 = chi2(0.0, Half::HeldOut);
  s.chi2_held = chi2(x, Half::HeldOut);
  // Its own null as a lead's test (a) takes it (ModelComparison::own_null).
  const ModelComparison::OwnNull own =
      cmp.own_null(scaled_housing(cmp, amp, g0, ch, s.rho), gains, Half::HeldOut, alpha / 2, 1);
  s.bound_held = own.bound;
  s.bound_held_folded = own.folded;
  return s;
}

} // namespace pw::diagnose
