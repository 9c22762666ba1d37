#include "diagnose/baseline.hpp"

#include "diagnose/calibration.hpp"
#include "diagnose/order_analysis.hpp"
#include "diagnose/ranking.hpp"

#include "core/format.hpp"
#include "core/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace pw::diagnose {

BaselineCell baseline_cell(const CalibrationCell& c) {
  BaselineCell b;
  b.channel = c.channel;
  b.order = c.order;
  double a = 0;
  for (int w = 0; w < 2; ++w) a += 0.5 * debiased_amplitude(c.recording[w], c.noise_variance);
  b.offset = a - c.model;
  b.variance = 0.25 * (c.variance[0] + c.variance[1]);
  b.model = c.model;
  b.discretization = c.discretization;
  return b;
}

void line_ratio_transfer(std::vector<BaselineCell>& cells, const std::vector<CalibrationCell>& source, double alpha) {
  const double z = normal_quantile(alpha / 2);  // upper quantile: z_{1-alpha/2}
  std::map<std::string, std::vector<std::size_t>> by_channel;  // cell indices, in order of carrier order
  for (std::size_t i = 0; i < cells.size(); ++i) by_channel[cells[i].channel].push_back(i);
  for (auto& [name, idx] : by_channel) {
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return cells[a].order < cells[b].order; });
    // Measured ratios, ln(A_base / M_base), where both lines are detectable at the diagnosis's alpha.
    std::vector<std::pair<double, double>> known;  // (order, ln ratio)
    for (std::size_t i : idx) {
      const double floor = z * std::sqrt(source[i].noise_variance);
      const double a = cells[i].offset + cells[i].model;  // the de-biased baseline amplitude
      if (a > floor && cells[i].model > floor) known.emplace_back(cells[i].order, std::log(a / cells[i].model));
    }
    if (known.empty()) continue;
    std::size_t k = 0;
    for (std::size_t i : idx) {
      const double o = cells[i].order;
      while (k + 1 < known.size() && known[k + 1].first <= o) ++k;
      double ln_t = known[k].second;  // at or beyond the last measured line, or below the first: its ratio
      if (o > known[k].first && k + 1 < known.size()) {
        const double u = (o - known[k].first) / (known[k + 1].first - known[k].first);
        ln_t = (1 - u) * known[k].second + u * known[k + 1].second;
      }
      const double a = cells[i].offset + cells[i].model;
      cells[i].transfer = std::exp(ln_t);
      cells[i].offset = a - cells[i].transfer * cells[i].model;
    }
  }
}

std::vector<std::string> bound_texts(const std::vector<FittedParameter>& parameters) {
  std::vector<std::string> out;
  for (const FittedParameter& p : parameters) {
    if (!p.at_bound || p.sensor_gain) continue;
    const double b = p.nearer_bound();
    out.push_back(p.name + " at its " + (b == p.upper ? "upper" : "lower") + " bound " + fmt("%.4g", b));
  }
  return out;
}

std::map<std::string, int> bound_ends(const std::vector<FittedParameter>& parameters) {
  std::map<std::string, int> out;
  for (const FittedParameter& p : parameters)
    if (p.at_bound && !p.sensor_gain) out[p.name] = p.nearer_bound() == p.upper ? 1 : -1;
  return out;
}

BaselineReference fit_baseline(const Recording& baseline, const model::SimulationConfig& config,
                               DiagnoseOptions options, BaselineTransfer transfer, HealthyFit weighting) {
  const HealthyFitResult fits = fit_healthy(baseline, config, options, weighting);
  const Diagnosis& d = fits.fit();
  const Diagnosis& noise = fits.noise_weighted;
  BaselineReference ref;
  ref.overrides = d.final_overrides;
  for (const CalibrationCell& c : d.calibration_cells) ref.cells.push_back(baseline_cell(c));
  if (transfer == BaselineTransfer::LineRatio) line_ratio_transfer(ref.cells, d.calibration_cells, options.alpha);
  // The baseline's relative model-form error, estimated as a calibration on it alone would
  // (calibration.hpp), is the budget for how far the model's predicted change may be off: a
  // fault's change reaches the sensors through the same model-form error as the healthy lines.
  Calibration cal;
  cal.alpha = options.alpha;
  cal.discrepancy = estimate_discrepancy({d.calibration_cells});
  ref.budgets = cal.budgets();
  ref.coverage = line_coverage({d.calibration_cells}, {d.speed.input_rpm});
  for (std::size_t c = 0; c < d.channels.size() && c < d.nuisance.gains.size(); ++c)
    ref.gains[d.channels[c]] = d.nuisance.gains[c];
  ref.speed_rpm = d.speed.input_rpm;
  ref.revolutions = d.window_revolutions;
  ref.noise_test = noise.verdict;
  ref.at_bound = bound_texts(d.nuisance.parameters);
  ref.limits = bound_ends(d.nuisance.parameters);
  for (std::size_t c = 0; c < d.channels.size() && c < d.alien_lines.size(); ++c)
    for (const auto& a : d.alien_lines[c]) ref.alien_lines.orders[d.channels[c]].push_back(a.order);
  ref.alien_lines.tolerance = d.alien_tolerance;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "baseline at %.6g rpm, %zu cells; its nuisance-fitted model leaves chi2 %.0f (held out) against a "
                "noise bound of %.0f%s: what the model misses there becomes the reference",
                ref.speed_rpm, ref.cells.size(), noise.nuisance.held_out.chi2, noise.bound_held_out,
                fits.model_form_weighted ? " (its values refitted with that residual's own discrepancy as weights)" : "");
  ref.summary = buf;
  return ref;
}

OperatingPointDistance operating_point_distance(double speed_rpm, double power_W, double reference_speed_rpm,
                                                double reference_power_W, double zeta) {
  OperatingPointDistance d;
  d.speed = std::fabs(reference_speed_rpm - speed_rpm) / speed_rpm;
  d.power = std::fabs(reference_power_W - power_W) / power_W;
  d.same = d.speed <= zeta && d.power <= kRecalibration;
  return d;
}

} // namespace pw::diagnose
