#include "diagnose/level_change.hpp"

#include "core/golden_section.hpp"
#include "core/statistics.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
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

  // The scan over the box's cells (in parallel), the golden section and the parabolic step
  // (core/golden_section.hpp); evaluations repeat configurations the comparison has cached.
  auto scan = [&](const std::vector<double>& xs) {
    std::vector<double> values(xs.size());
    parallel_for(static_cast<int>(xs.size()), ctx.threads,
                 [&](int i) { values[static_cast<std::size_t>(i)] = chi2_fit(xs[static_cast<std::size_t>(i)]); });
    return values;
  };
  const ScannedMinimum m =
      scanned_minimum(chi2_fit, scan, lo, hi, kLevelScanPoints, kLevelGoldenIterations, kLevelCurvatureStep);
  for (const double x : m.scan_x) out.scan_rho.push_back(std::exp(x));
  out.scan_chi2_fit = m.scan_value;
  if (m.failed) {
    out.failed = true;
    out.simulations = static_cast<int>(sims.load());
    return out;
  }
  const double x = m.x, h = kLevelCurvatureStep;
  out.rho = std::exp(x);
  out.at_box_edge = m.at_edge;
  out.ln_rho_std = chi2_curvature_std(chi2_fit, x, h);
  out.chi2_fit_1 = chi2(0.0, Half::Fit);
  out.chi2_fit = chi2(x, Half::Fit);
  out.chi2_held_1 = chi2(0.0, Half::HeldOut);
  out.chi2_held = chi2(x, Half::HeldOut);
  out.config = config_at(x, &out.overrides);
  out.simulations = static_cast<int>(sims.load());
  return out;
}

LevelMoveTest level_move_test(double ln_rho_std, double spread_ln, int recordings, double alpha) {
  LevelMoveTest t;
  const double a = ln_rho_std * ln_rho_std;
  const double b = recordings >= 2 && std::isfinite(spread_ln) ? 2 * spread_ln * spread_ln : 0.0;
  t.scatter_ln = std::sqrt(b);
  t.ln_std = std::sqrt(a + b);
  if (b > 0) {
    t.dof = (a + b) * (a + b) / (b * b / static_cast<double>(recordings - 1));
    t.quantile = student_t_quantile(t.dof, alpha / 2);
  } else {
    t.dof = std::numeric_limits<double>::infinity();
    t.quantile = normal_quantile(alpha / 2);
  }
  t.threshold_ln = t.quantile * t.ln_std;
  return t;
}

double healthy_level_scatter_ln(const std::string& level_candidate, double calibration_spread_ln) {
  return level_candidate == "stiffness_level" ? 0.0 : calibration_spread_ln;
}

std::string one_sided_ratio_note(const std::string& parameter, double baseline_value, double rho, int end) {
  if (end == 0) return {};
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "the baseline's %s = %.4g is the %s edge of its box, a limit and not a fit: against the level the "
                "baseline's fit asked for, beyond that edge, the ratio would be %s than x%.3g, so x%.3g is a bound "
                "on the change, not its size",
                parameter.c_str(), baseline_value, end > 0 ? "upper" : "lower", end > 0 ? "smaller" : "larger", rho,
                rho);
  return buf;
}

} // namespace pw::diagnose
