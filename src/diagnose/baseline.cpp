#include "diagnose/baseline.hpp"

#include "diagnose/calibration.hpp"
#include "diagnose/order_analysis.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

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

std::vector<std::string> bound_texts(const std::vector<FittedParameter>& parameters) {
  std::vector<std::string> out;
  for (const FittedParameter& p : parameters) {
    if (!p.at_bound || p.sensor_gain) continue;
    const double b = p.nearer_bound();
    out.push_back(p.name + " at its " + (b == p.upper ? "upper" : "lower") + " bound " + fmt("%.4g", b));
  }
  return out;
}

BaselineReference fit_baseline(const Recording& baseline, const model::SimulationConfig& config,
                               DiagnoseOptions options) {
  options.nuisance_only = true;
  const Diagnosis d = diagnose(baseline, config, options);
  BaselineReference ref;
  ref.overrides = d.final_overrides;
  for (const CalibrationCell& c : d.calibration_cells) ref.cells.push_back(baseline_cell(c));
  // The baseline's relative model-form error, estimated as a calibration on it alone would
  // (calibration.hpp), is the budget for how far the model's predicted change may be off: a
  // fault's change reaches the sensors through the same model-form error as the healthy lines.
  Calibration cal;
  cal.alpha = options.alpha;
  cal.discrepancy = estimate_discrepancy({d.calibration_cells});
  ref.budgets = cal.budgets();
  for (std::size_t c = 0; c < d.channels.size() && c < d.nuisance.gains.size(); ++c)
    ref.gains[d.channels[c]] = d.nuisance.gains[c];
  ref.speed_rpm = d.speed.input_rpm;
  ref.revolutions = d.window_revolutions;
  ref.noise_test = d.verdict;
  ref.at_bound = bound_texts(d.nuisance.parameters);
  char buf[300];
  std::snprintf(buf, sizeof buf,
                "baseline at %.6g rpm, %zu cells; its nuisance-fitted model leaves chi2 %.0f (held out) against a "
                "noise bound of %.0f: what the model misses there becomes the reference",
                ref.speed_rpm, ref.cells.size(), d.nuisance.held_out.chi2, d.bound_held_out);
  ref.summary = buf;
  return ref;
}

} // namespace pw::diagnose
