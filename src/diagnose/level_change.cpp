#include "diagnose/level_change.hpp"

#include "core/golden_section.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace pw::diagnose {

LevelChange fit_level_change(const FitContext& ctx, std::size_t index, const std::vector<double>& gains) {
  LevelChange out;
  const Candidate* cand = ctx.nuisance[index];
  out.candidate = cand->name();
  const std::vector<ParameterSpec> specs = ctx.nuisance_specs();
  // The position of this candidate's parameter in the nuisance vector.
  std::size_t k = 0;
  for (std::size_t n = 0; n < index; ++n) k += ctx.nuisance[n]->parameters(ctx.base).size();
  if (cand->parameters(ctx.base).size() != 1) {
    out.failed = true;
    return out;
  }
  const ParameterSpec& ps = specs[k];
  out.parameter = ps.name;
  out.baseline_value = ps.initial;
  // Every other nuisance value as the baseline's (its configured values: ctx.base carries them).
  std::vector<double> nx;
  for (const ParameterSpec& s : specs) nx.push_back(s.initial);
  const double lo = std::log(ps.lower / ps.initial), hi = std::log(ps.upper / ps.initial);

  std::atomic<long> sims{0};
  auto config_at = [&](double ln_rho, std::vector<std::string>* overrides) {
    std::vector<double> x = nx;
    x[k] = std::clamp(ps.initial * std::exp(ln_rho), ps.lower, ps.upper);
    return ctx.make(nullptr, Variant{}, {}, x, overrides);
  };
  auto chi2 = [&](double ln_rho, Half h) {
    try {
      const auto amp = ctx.amplitudes(config_at(ln_rho, nullptr), false, &sims);
      return ctx.cmp.score(amp, h, gains, HousingGains::Given).chi2;
    } catch (const SolverError&) {
      return std::numeric_limits<double>::infinity();  // never chosen as the best point
    }
  };
  auto chi2_fit = [&](double ln_rho) { return chi2(ln_rho, Half::Fit); };

  // The scan: the centres of kLevelScanPoints equal cells of [lo, hi].
  const double cell = (hi - lo) / kLevelScanPoints;
  std::vector<double> scan(kLevelScanPoints);
  parallel_for(kLevelScanPoints, ctx.threads, [&](int i) {
    scan[static_cast<std::size_t>(i)] = chi2_fit(lo + (i + 0.5) * cell);
  });
  for (int i = 0; i < kLevelScanPoints; ++i) out.scan_rho.push_back(std::exp(lo + (i + 0.5) * cell));
  out.scan_chi2_fit = scan;
  const auto best = std::min_element(scan.begin(), scan.end());
  if (!std::isfinite(*best)) {
    out.failed = true;
    out.simulations = static_cast<int>(sims.load());
    return out;
  }
  // The golden section over the best cell and its neighbours (the box's edge where it has none).
  const double b = lo + (static_cast<double>(best - scan.begin()) + 0.5) * cell;
  const double a0 = std::max(lo, b - 1.5 * cell), a1 = std::min(hi, b + 1.5 * cell);
  const BracketedMinimum m = golden_section_minimum(chi2_fit, a0, a1, kLevelGoldenIterations);
  // The final bracket (0.3 % of a cell) can still be wide against a steep chi2 (four4p's stiffness:
  // +240 at 0.2 % from the minimum): one parabolic step through the curvature's three points, and
  // the best point evaluated (the bracket's midpoint, that step, the scan's best) is the fit.
  // Evaluations repeat configurations the comparison has cached.
  const double h = kLevelCurvatureStep;
  const double f0 = chi2_fit(m.x), fp = chi2_fit(m.x + h), fm = chi2_fit(m.x - h);
  double x = m.x, fx = f0;
  if (const double second = fp - 2 * f0 + fm; second > 0) {
    const double xp = std::clamp(m.x - h * (fp - fm) / (2 * second), a0, a1);
    if (const double fxp = chi2_fit(xp); fxp < fx) x = xp, fx = fxp;
  }
  if (*best < fx) x = b, fx = *best;
  out.rho = std::exp(x);
  // At the box's edge only when the bracket touches the edge the box has: a bracket edge inside
  // the box is the scan's choice of cells, and the scan put the minimum in its middle cell.
  out.at_box_edge = m.at_edge && (m.x - lo <= m.width || hi - m.x <= m.width);
  out.ln_rho_std = chi2_curvature_std(chi2_fit, x, h);
  out.chi2_fit_1 = chi2(0.0, Half::Fit);
  out.chi2_fit = chi2(x, Half::Fit);
  out.chi2_held_1 = chi2(0.0, Half::HeldOut);
  out.chi2_held = chi2(x, Half::HeldOut);
  out.config = config_at(x, &out.overrides);
  out.simulations = static_cast<int>(sims.load());
  return out;
}

} // namespace pw::diagnose
