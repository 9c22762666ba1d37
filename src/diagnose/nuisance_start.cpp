#include "diagnose/nuisance_start.hpp"

#include "diagnose/fit.hpp"
#include "diagnose/fit_context.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pw::diagnose {

int scan_points(double lo, double hi, double step_ratio) {
  if (!(step_ratio > 1) || !(hi > lo) || !(lo > 0)) return kNuisanceScanPoints;
  const double steps = std::ceil(std::log(hi / lo) / std::log(step_ratio));
  return std::max(kNuisanceScanPoints, static_cast<int>(steps) + 1);
}

std::vector<double> nuisance_start(const std::vector<ParameterSpec>& specs, double chi2_nominal,
                                   const NuisanceChi2& chi2, int threads) {
  std::vector<double> x0;
  for (const auto& p : specs) x0.push_back(p.initial);
  if (x0.empty()) return x0;
  const ParameterSpec& p0 = specs.front();
  const std::vector<double> grid =
      geometric_grid(p0.lower * kNuisanceScanInset, p0.upper / kNuisanceScanInset, kNuisanceScanPoints);
  std::vector<double> chi(grid.size(), std::numeric_limits<double>::infinity());
  parallel_for(static_cast<int>(grid.size()), threads, [&](int i) {
    std::vector<double> x = x0;
    x[0] = grid[static_cast<std::size_t>(i)];
    chi[static_cast<std::size_t>(i)] = chi2(x);
  });
  const std::size_t b = static_cast<std::size_t>(std::min_element(chi.begin(), chi.end()) - chi.begin());
  double best = chi[b];
  if (chi[b] < chi2_nominal) {
    x0[0] = grid[b];
  } else {  // the nominal model (every parameter at its 'absent' value) is the better start
    for (std::size_t k = 0; k < specs.size(); ++k) x0[k] = specs[k].null_value;
    best = chi2_nominal;
  }
  // Each rig element the other way round (present <-> absent) if that is better.
  for (std::size_t k = 1; k < specs.size(); ++k) {
    if (specs[k].initial == specs[k].null_value) continue;
    std::vector<double> x = x0;
    x[k] = x0[k] == specs[k].null_value ? specs[k].initial : specs[k].null_value;
    const double c = chi2(x);
    if (c < best) x0 = x, best = c;
  }
  // Each later parameter that moves a resonance: a scan of its own over its box, the others
  // where they are now, kept if a grid point beats the start so far.
  for (std::size_t k = 1; k < specs.size(); ++k) {
    if (!specs[k].scan_at_start) continue;
    const double lo = specs[k].lower * kNuisanceScanInset, hi = specs[k].upper / kNuisanceScanInset;
    const std::vector<double> g = geometric_grid(lo, hi, scan_points(lo, hi, specs[k].scan_step_ratio));
    const double follow = k + 1 < specs.size() ? specs[k + 1].scan_follows_previous_power : 0.0;
    const auto at = [&](double v) {  // x0 with parameter k at v (and its follower moved with it)
      std::vector<double> x = x0;
      x[k] = v;
      if (follow != 0) {
        const ParameterSpec& f = specs[k + 1];
        x[k + 1] = std::clamp(x0[k + 1] * std::pow(v / x0[k], follow), f.lower, f.upper);
      }
      return x;
    };
    std::vector<double> c(g.size(), std::numeric_limits<double>::infinity());
    parallel_for(static_cast<int>(g.size()), threads,
                 [&](int i) { c[static_cast<std::size_t>(i)] = chi2(at(g[static_cast<std::size_t>(i)])); });
    const std::size_t j = static_cast<std::size_t>(std::min_element(c.begin(), c.end()) - c.begin());
    if (c[j] < best) x0 = at(g[j]), best = c[j];
  }
  return x0;
}

} // namespace pw::diagnose
