#include "diagnose/nuisance_start.hpp"

#include "diagnose/fit.hpp"
#include "diagnose/fit_context.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pw::diagnose {

int scan_points(double lo, double hi, double step_ratio) {
  if (!(step_ratio > 1) || !(hi > lo) || !(lo > 0)) return kNuisanceScanPoints;
  const double steps = std::ceil(std::log(hi / lo) / std::log(step_ratio));
  return std::max(kNuisanceScanPoints, static_cast<int>(steps) + 1);
}

std::vector<double> scan_grid(const ParameterSpec& p) {
  if (p.log_scale) {
    const double lo = p.lower * kNuisanceScanInset, hi = p.upper / kNuisanceScanInset;
    return geometric_grid(lo, hi, scan_points(lo, hi, p.scan_step_ratio));
  }
  // A linear box has ends that are values like any other (an engagement ramp of 0 is the sharp
  // involute): the grid spans it, ends included.
  const int n = p.scan_step > 0 ? std::max(kNuisanceScanPoints, static_cast<int>(std::ceil((p.upper - p.lower) / p.scan_step)) + 1)
                                : kNuisanceScanPoints;
  std::vector<double> g(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) g[static_cast<std::size_t>(i)] = p.lower + (p.upper - p.lower) * i / (n - 1);
  return g;
}

namespace {

/// A start and its chi2.
struct Start {
  std::vector<double> x;
  double chi2 = std::numeric_limits<double>::infinity();
};

/// The coarse scan of the first parameter (the others at their start values), or the nominal
/// model (every parameter 'absent') when that fits better.
Start scan_first(const std::vector<ParameterSpec>& specs, double chi2_nominal, const NuisanceChi2& chi2, int threads) {
  Start s;
  for (const auto& p : specs) s.x.push_back(p.initial);
  const ParameterSpec& p0 = specs.front();
  const std::vector<double> grid =
      geometric_grid(p0.lower * kNuisanceScanInset, p0.upper / kNuisanceScanInset, kNuisanceScanPoints);
  std::vector<double> chi(grid.size(), std::numeric_limits<double>::infinity());
  parallel_for(static_cast<int>(grid.size()), threads, [&](int i) {
    std::vector<double> x = s.x;
    x[0] = grid[static_cast<std::size_t>(i)];
    chi[static_cast<std::size_t>(i)] = chi2(x);
  });
  const std::size_t b = static_cast<std::size_t>(std::min_element(chi.begin(), chi.end()) - chi.begin());
  if (chi[b] < chi2_nominal) {
    s.x[0] = grid[b];
    s.chi2 = chi[b];
  } else {
    for (std::size_t k = 0; k < specs.size(); ++k) s.x[k] = specs[k].null_value;
    s.chi2 = chi2_nominal;
  }
  return s;
}

/// From a start: each rig element the other way round (present <-> absent) if that is better,
/// then each later parameter that moves a resonance scanned over its box, the others where they
/// are now, kept if a grid point beats the start so far.
Start refine(const std::vector<ParameterSpec>& specs, Start s, const NuisanceChi2& chi2, int threads) {
  for (std::size_t k = 1; k < specs.size(); ++k) {
    if (specs[k].initial == specs[k].null_value) continue;
    std::vector<double> x = s.x;
    x[k] = s.x[k] == specs[k].null_value ? specs[k].initial : specs[k].null_value;
    const double c = chi2(x);
    if (c < s.chi2) s.x = x, s.chi2 = c;
  }
  for (std::size_t k = 1; k < specs.size(); ++k) {
    if (!specs[k].scan_at_start) continue;
    const std::vector<double> g = scan_grid(specs[k]);
    const double follow = k + 1 < specs.size() ? specs[k + 1].scan_follows_previous_power : 0.0;
    const auto at = [&](double v) {  // the start with parameter k at v (and its follower moved with it)
      std::vector<double> x = s.x;
      x[k] = v;
      if (follow != 0) {
        const ParameterSpec& f = specs[k + 1];
        x[k + 1] = std::clamp(s.x[k + 1] * std::pow(v / s.x[k], follow), f.lower, f.upper);
      }
      return x;
    };
    std::vector<double> c(g.size(), std::numeric_limits<double>::infinity());
    parallel_for(static_cast<int>(g.size()), threads,
                 [&](int i) { c[static_cast<std::size_t>(i)] = chi2(at(g[static_cast<std::size_t>(i)])); });
    const std::size_t j = static_cast<std::size_t>(std::min_element(c.begin(), c.end()) - c.begin());
    if (c[j] < s.chi2) s.x = at(g[j]), s.chi2 = c[j];
  }
  return s;
}

} // namespace

std::vector<double> nuisance_start(const std::vector<ParameterSpec>& specs, double chi2_nominal,
                                   const NuisanceChi2& chi2, int threads) {
  if (specs.empty()) return {};
  return refine(specs, scan_first(specs, chi2_nominal, chi2, threads), chi2, threads).x;
}

std::vector<double> nuisance_start_from(const std::vector<ParameterSpec>& specs, const std::vector<double>& earlier,
                                        const NuisanceChi2& chi2, int threads) {
  if (specs.empty() || earlier.size() != specs.size()) return {};
  Start e;
  for (std::size_t k = 0; k < specs.size(); ++k) e.x.push_back(std::clamp(earlier[k], specs[k].lower, specs[k].upper));
  e.chi2 = chi2(e.x);
  return refine(specs, std::move(e), chi2, threads).x;
}

} // namespace pw::diagnose
