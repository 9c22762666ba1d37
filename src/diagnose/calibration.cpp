#include "diagnose/calibration.hpp"

#include "core/error.hpp"
#include "core/statistics.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/locate.hpp"
#include "diagnose/order_analysis.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <utility>

namespace pw::diagnose {
namespace {

/// Sums of one (quantity, family) over cells, for the moment estimates.
struct Moments {
  std::vector<double> e_low;               // excess of cells the model predicts below the noise
  std::vector<std::pair<double, double>> e_line;  // (excess, a^2) of cells with a model line
  std::vector<std::vector<std::pair<double, double>>> per_recording;
};

/// Mean of the two halves' excess (A - mu)^2 - D over what the noise explains.
double cell_excess(const CalibrationCell& c) {
  const double mu = rice_mean(c.model, c.noise_variance);
  double e = 0;
  for (int w = 0; w < 2; ++w) {
    const double r = c.recording[w] - mu;
    e += 0.5 * (r * r - c.variance[w]);
  }
  return e;
}

/// A cell where the model has a line at or above the noise: it measures the relative discrepancy.
bool measures_relative(const CalibrationCell& c) {
  const double a2 = c.model * c.model;
  return a2 >= c.noise_variance && a2 > 0;
}

double mean_of(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

} // namespace

DiscrepancyEntry DiscrepancyEstimate::budget(double z) const {
  DiscrepancyEntry e;
  e.quantity = quantity;
  e.family = family;
  e.relative_std = std::sqrt(std::max(0.0, relative_variance + z * relative_variance_se));
  e.absolute_variance = std::max(0.0, absolute_variance + z * absolute_variance_se);
  return e;
}

std::vector<DiscrepancyEstimate> estimate_discrepancy(const std::vector<std::vector<CalibrationCell>>& recordings) {
  std::map<std::pair<int, int>, Moments> by_key;
  const std::size_t nr = recordings.size();
  for (std::size_t r = 0; r < nr; ++r)
    for (const CalibrationCell& c : recordings[r]) {
      const double e = cell_excess(c);
      const double a2 = c.model * c.model;
      for (Component f : c.families) {
        Moments& m = by_key[{static_cast<int>(c.quantity), static_cast<int>(f)}];
        m.per_recording.resize(nr);
        if (measures_relative(c)) {
          m.e_line.emplace_back(e, a2);
          m.per_recording[r].emplace_back(e, a2);
        } else {
          m.e_low.push_back(e);
        }
      }
    }
  std::vector<DiscrepancyEstimate> out;
  for (const auto& [key, m] : by_key) {
    DiscrepancyEstimate d;
    d.quantity = static_cast<Quantity>(key.first);
    d.family = static_cast<Component>(key.second);
    d.absolute_cells = static_cast<int>(m.e_low.size());
    d.absolute_variance = mean_of(m.e_low);
    if (m.e_low.size() > 1) {
      double v = 0;
      for (double x : m.e_low) v += (x - d.absolute_variance) * (x - d.absolute_variance);
      d.absolute_variance_se = std::sqrt(v / static_cast<double>(m.e_low.size() - 1) / static_cast<double>(m.e_low.size()));
    }
    // The lines carry the absolute part too (content the model lacks lands on its lines as
    // well): sigma_rel^2 = sum (e - sigma_abs^2) / sum a^2, its s.e. from the residual spread.
    const double floor = std::max(0.0, d.absolute_variance);
    auto relative = [&](const std::vector<std::pair<double, double>>& cells, double* se) {
      double num = 0, den = 0;
      for (const auto& [e, a2] : cells) num += e - floor, den += a2;
      if (den <= 0) return std::numeric_limits<double>::quiet_NaN();
      const double s2 = num / den;
      if (se) {
        double v = 0;
        for (const auto& [e, a2] : cells) v += (e - floor - s2 * a2) * (e - floor - s2 * a2);
        *se = std::sqrt(v) / den;
      }
      return s2;
    };
    d.relative_cells = static_cast<int>(m.e_line.size());
    if (!m.e_line.empty()) d.relative_variance = relative(m.e_line, &d.relative_variance_se);
    for (const auto& cells : m.per_recording) d.relative_variance_per_recording.push_back(relative(cells, nullptr));
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<LineCoverage> line_coverage(const std::vector<std::vector<CalibrationCell>>& recordings,
                                        const std::vector<double>& speeds_rpm) {
  std::vector<LineCoverage> out;
  for (std::size_t r = 0; r < recordings.size(); ++r) {
    const double speed = r < speeds_rpm.size() ? speeds_rpm[r] : 0.0;
    for (const CalibrationCell& c : recordings[r]) {
      if (!measures_relative(c) || !(c.frequency_Hz > 0)) continue;
      auto it = std::find_if(out.begin(), out.end(), [&](const LineCoverage& x) { return x.quantity == c.quantity; });
      if (it == out.end()) {
        out.push_back({c.quantity, c.frequency_Hz, speed, c.frequency_Hz, speed, 0});
        it = out.end() - 1;
      }
      if (c.frequency_Hz < it->lowest_Hz) it->lowest_Hz = c.frequency_Hz, it->lowest_speed_rpm = speed;
      if (c.frequency_Hz > it->highest_Hz) it->highest_Hz = c.frequency_Hz, it->highest_speed_rpm = speed;
      ++it->lines;
    }
  }
  return out;
}

bool housing_lines_heard(const std::vector<std::vector<CalibrationCell>>& recordings, double alpha) {
  std::size_t m = 0;
  for (const auto& cells : recordings)
    for (const CalibrationCell& c : cells) m += c.quantity == Quantity::HousingAcceleration ? 1 : 0;
  if (m == 0) return false;
  const double t = std::log(static_cast<double>(m) / alpha);
  for (const auto& cells : recordings)
    for (const CalibrationCell& c : cells) {
      if (c.quantity != Quantity::HousingAcceleration || !(c.noise_variance > 0)) continue;
      const double level = t * c.noise_variance;
      if (c.recording[0] * c.recording[0] > level && c.recording[1] * c.recording[1] > level) return true;
    }
  return false;
}

void hold_at_null(std::vector<std::vector<FittedParameter>>& per_recording,
                  const std::vector<std::pair<std::string, double>>& null_values) {
  for (auto& params : per_recording)
    for (FittedParameter& p : params)
      for (const auto& [name, value] : null_values)
        if (p.name == name) {
          p.value = value;
          p.at_bound = false;
        }
}

CalibrationFit calibration_fit(const std::vector<FittedParameter>& nuisance, double chi2_held_out,
                               double bound_held_out) {
  CalibrationFit f;
  f.nuisance_chi2_held_out = chi2_held_out;
  f.noise_bound_held_out = bound_held_out;
  for (const FittedParameter& p : nuisance) {
    if (p.sensor_gain) continue;
    f.values.push_back(p.name + "=" + format_value(p.value));
    if (p.at_bound) f.at_bound.push_back(p.name);
  }
  return f;
}

std::vector<std::string> median_overrides(const std::vector<std::vector<FittedParameter>>& per_recording) {
  std::map<std::string, std::vector<double>> values;
  std::vector<std::string> order;
  for (const auto& params : per_recording)
    for (const FittedParameter& p : params) {
      if (p.sensor_gain) continue;
      if (!values.count(p.name)) order.push_back(p.name);
      values[p.name].push_back(p.value);
    }
  std::vector<std::string> out;
  for (const std::string& name : order) {
    std::vector<double> v = values[name];
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const double med = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    out.push_back(name + "=" + format_value(med));
  }
  return out;
}

namespace {
std::string key_of(const std::string& line) { return line.substr(0, line.find('=')); }

/// "key=value" lines with a numeric value as a map key -> value. A setting that is not a number
/// (solver.level=lateral_torsional, a housing path: a model form the calibration's file may carry
/// among its settings) is no rig element's parameter and is left out; std::stod threw on it and
/// the diagnosis ended in an internal error (session 72).
std::map<std::string, double> override_values(const std::vector<std::string>& overrides) {
  std::map<std::string, double> value;
  for (const std::string& line : overrides) {
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) continue;
    const char* first = line.data() + eq + 1;
    const char* last = line.data() + line.size();
    double v = 0;
    const auto [end, ec] = std::from_chars(first, last, v);
    if (ec == std::errc() && end == last) value[key_of(line)] = v;
  }
  return value;
}

/// Every line candidate `c`'s apply() writes at its parameters' values in `value`; nothing when
/// `value` lacks one of them (the recordings could not see the element).
std::vector<std::string> applied_lines(const Candidate& c, const model::SimulationConfig& config,
                                       const std::map<std::string, double>& value) {
  const std::vector<ParameterSpec> specs = c.parameters(config);
  std::vector<double> x;
  for (const ParameterSpec& p : specs)
    if (const auto it = value.find(p.name); it != value.end()) x.push_back(it->second);
  std::vector<std::string> lines;
  if (x.size() != specs.size()) return lines;
  model::SimulationConfig applied = config;
  c.apply(applied, Variant{}, x, &lines);
  return lines;
}
} // namespace

std::vector<std::string> rig_element_settings(const std::vector<std::string>& rig_elements,
                                              const model::SimulationConfig& config,
                                              const std::vector<std::string>& overrides) {
  std::map<std::string, double> value = override_values(overrides);
  std::vector<std::string> out;
  for (const std::string& name : rig_elements) {
    const Candidate* c = find_candidate(name);
    if (!c) continue;
    for (const std::string& line : applied_lines(*c, config, value))
      if (!value.count(key_of(line))) {
        value[key_of(line)] = 0;  // once
        out.push_back(line);
      }
  }
  return out;
}

std::map<std::string, double> fitted_values(const Calibration& calibration, std::size_t at_recording) {
  return at_recording < calibration.fits.size() ? override_values(calibration.fits[at_recording].values)
                                                : std::map<std::string, double>{};
}

std::map<std::string, double> nuisance_level_spread_ln(const Calibration& calibration) {
  std::map<std::string, double> out;
  if (calibration.fits.size() < 2) return out;
  std::map<std::string, std::vector<double>> logs;
  for (const CalibrationFit& fit : calibration.fits)
    for (const auto& [key, value] : override_values(fit.values))
      logs[key].push_back(value > 0 ? std::log(value) : std::numeric_limits<double>::quiet_NaN());
  for (const auto& [key, v] : logs) {
    if (v.size() != calibration.fits.size() || !std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); }))
      continue;
    double mean = 0;
    for (double x : v) mean += x;
    mean /= static_cast<double>(v.size());
    double ss = 0;
    for (double x : v) ss += (x - mean) * (x - mean);
    out[key] = std::sqrt(ss / static_cast<double>(v.size() - 1));
  }
  return out;
}

std::vector<std::string> structural_rig_settings(const Calibration& calibration, const model::SimulationConfig& config,
                                                 std::optional<std::size_t> at_recording) {
  const std::map<std::string, double> median = override_values(calibration.overrides);
  const std::map<std::string, double> own =
      at_recording ? fitted_values(calibration, *at_recording) : std::map<std::string, double>{};
  std::vector<std::string> out;
  for (const std::string& name : calibration.rig_elements)
    if (const Candidate* c = find_candidate(name); c && c->calibration_only()) {
      std::vector<std::string> lines = applied_lines(*c, config, own);
      if (lines.empty()) lines = applied_lines(*c, config, median);
      for (std::string& line : lines) out.push_back(std::move(line));
    }
  return out;
}

std::vector<std::string> reference_design_settings(const Calibration& calibration, const model::SimulationConfig& config,
                                                   std::size_t at_recording) {
  std::vector<std::string> out;
  if (at_recording >= calibration.fits.size()) return out;
  const CalibrationFit& fit = calibration.fits[at_recording];
  const std::map<std::string, double> own = override_values(fit.values);
  for (const std::string& name : calibration.rig_elements) {
    const Candidate* c = find_candidate(name);
    if (!c || !c->rig_design()) continue;
    const std::vector<ParameterSpec> specs = c->parameters(config);
    const bool limit = std::any_of(specs.begin(), specs.end(), [&](const ParameterSpec& p) {
      return std::find(fit.at_bound.begin(), fit.at_bound.end(), p.name) != fit.at_bound.end();
    });
    if (limit) continue;
    for (std::string& line : applied_lines(*c, config, own)) out.push_back(std::move(line));
  }
  return out;
}

std::vector<std::string> model_form_settings(const ModelForm& form) {
  std::vector<std::string> out;  // the configuration's defaults need no line
  if (form.mesh_phase != model::MeshPhase::Rotation)
    out.push_back(std::string("stiffness.mesh_phase=") + model::mesh_phase_name(form.mesh_phase));
  // The level first: the ring body's path is valid only in the lateral-torsional model.
  if (form.housing_path == model::HousingPath::RingBody)
    out.push_back(std::string("solver.level=") + model::model_level_name(model::ModelLevel::LateralTorsional));
  if (form.housing_path != model::HousingPath::PlanetPass)
    out.push_back(std::string("sensor.housing_path=") + model::housing_path_name(form.housing_path));
  return out;
}

void apply_model_form(model::SimulationConfig& config, const ModelForm& form) {
  config.stiffness.mesh_phase = form.mesh_phase;
  config.sensor.housing_path = form.housing_path;
  if (form.housing_path == model::HousingPath::RingBody) config.solver.level = model::ModelLevel::LateralTorsional;
}

std::vector<std::string> assignments_in_form(const std::vector<std::string>& assignments, const ModelForm& chosen,
                                             const ModelFormPart& part) {
  const std::vector<std::string> lines = model_form_settings(part.changed(ModelForm{}));
  const auto key = [](const std::string& line) { return line.substr(0, line.find('=')); };
  std::vector<std::string> rest = assignments;
  for (const std::string& earlier : model_form_settings(chosen)) {
    const bool set_again =
        std::any_of(lines.begin(), lines.end(), [&](const std::string& l) { return key(l) == key(earlier); });
    if (const auto it = std::find(rest.begin(), rest.end(), earlier); set_again && it != rest.end()) rest.erase(it);
  }
  std::vector<std::string> out = lines;
  out.insert(out.end(), rest.begin(), rest.end());
  return out;
}

ModelForm model_form_of(const model::SimulationConfig& config) {
  return {.mesh_phase = config.stiffness.mesh_phase, .housing_path = config.sensor.housing_path};
}

bool form_probes_pass(const std::vector<ModelFormFits>& fits, double alpha) {
  return !fits.empty() && std::all_of(fits.begin(), fits.end(), [&](const ModelFormFits& f) {
    return f.probe_fit_chi2 && rig_elements_improve({.chi2_without = f.fit_chi2, .chi2_with = *f.probe_fit_chi2,
                                                      .features = f.fit_features, .extra_parameters = f.extra_parameters}, alpha);
  });
}

bool form_refits_improve(const std::vector<ModelFormFits>& fits, double alpha) {
  return !fits.empty() && std::all_of(fits.begin(), fits.end(), [&](const ModelFormFits& f) {
    return f.refit_held_out_chi2 &&
           rig_elements_improve({.chi2_without = f.held_out_chi2, .chi2_with = *f.refit_held_out_chi2,
                                 .features = f.held_out_features, .extra_parameters = f.extra_parameters}, alpha);
  });
}

bool rig_elements_improve(const NestedFits& f, double alpha) {
  if (f.extra_parameters <= 0 || f.features <= 0 || !(f.chi2_with > 0) || !(f.chi2_without > f.chi2_with)) return false;
  const double p = f.extra_parameters, m = f.features;
  return (f.chi2_without - f.chi2_with) / p > f_quantile(p, m, alpha) * f.chi2_with / m;
}

SharedStructure choose_shared_structure(const std::vector<std::vector<double>>& held_out_chi2,
                                        const std::vector<int>& features, int structure_parameters, double alpha) {
  const std::size_t n = held_out_chi2.size();
  if (n == 0 || features.size() != n)
    throw InputError("held_out_chi2", "choose_shared_structure needs one row of chi2 and one feature count per recording");
  const std::size_t candidates = held_out_chi2.front().size();
  for (const auto& row : held_out_chi2)
    if (row.size() != candidates || candidates < n)
      throw InputError("held_out_chi2", "choose_shared_structure needs one chi2 per recording and candidate structure, "
                                        "the recordings' own structures first (at least as many columns as rows)");
  SharedStructure out;
  out.loss.assign(candidates, 0.0);
  const auto usable = [](double c) { return std::isfinite(c) && c > 0; };
  for (std::size_t k = 0; k < candidates; ++k)
    for (std::size_t j = 0; j < n; ++j) {
      const double own = held_out_chi2[j][j], with = held_out_chi2[j][k];
      if (!usable(own) || !usable(with)) {
        out.loss[k] = std::numeric_limits<double>::infinity();
        break;
      }
      out.loss[k] += 0.5 * features[j] * std::log(with / own);
    }
  out.from = static_cast<std::size_t>(std::min_element(out.loss.begin(), out.loss.end()) - out.loss.begin());
  for (std::size_t j = 0; j < n; ++j)
    out.rejects_shared.push_back(rig_elements_improve(NestedFits{.chi2_without = held_out_chi2[j][out.from],
                                                                 .chi2_with = held_out_chi2[j][j],
                                                                 .features = features[j],
                                                                 .extra_parameters = structure_parameters},
                                                      alpha));
  return out;
}

std::optional<std::vector<FittedParameter>> pooled_structure(const std::vector<std::vector<FittedParameter>>& per_recording,
                                                             const std::vector<std::string>& names) {
  if (per_recording.size() < 2 || names.empty()) return std::nullopt;
  std::vector<FittedParameter> out;
  for (const std::string& name : names) {
    std::vector<const FittedParameter*> estimates;
    for (const auto& params : per_recording) {
      const auto it = std::find_if(params.begin(), params.end(), [&](const FittedParameter& p) { return p.name == name; });
      if (it == params.end()) return std::nullopt;  // a recording without the element: nothing to pool
      estimates.push_back(&*it);
    }
    const bool positive =
        std::all_of(estimates.begin(), estimates.end(), [](const FittedParameter* p) { return p->value > 0; });
    double weights = 0, sum = 0;
    for (const FittedParameter* p : estimates) {
      // A value at a bound is a limit, not a measurement, and a missing standard error says the
      // recording does not see the parameter: neither carries a weight.
      if (p->at_bound || !(std::isfinite(p->std_error) && p->std_error > 0)) continue;
      const double x = positive ? std::log(p->value) : p->value;
      const double se = positive ? p->std_error / p->value : p->std_error;
      const double w = 1.0 / (se * se);
      weights += w;
      sum += w * x;
    }
    if (!(weights > 0)) return std::nullopt;
    FittedParameter q = *estimates.front();
    const double mean = sum / weights, se = 1.0 / std::sqrt(weights);
    q.value = positive ? std::exp(mean) : mean;
    q.std_error = positive ? q.value * se : se;
    q.at_bound = false;
    out.push_back(std::move(q));
  }
  return out;
}

std::vector<std::string> parameters_at_bound(const std::vector<std::vector<FittedParameter>>& per_recording) {
  struct Count {
    int lower = 0, upper = 0;
    double lower_value = 0, upper_value = 0;
  };
  std::map<std::string, Count> counts;
  std::vector<std::string> order;
  for (const auto& params : per_recording)
    for (const FittedParameter& p : params) {
      if (p.sensor_gain) continue;
      if (!counts.count(p.name)) order.push_back(p.name);
      Count& c = counts[p.name];
      if (!p.at_bound) continue;
      // at_bound does not say which end: the nearer one.
      if (p.nearer_bound() == p.upper) ++c.upper, c.upper_value = p.upper;
      else ++c.lower, c.lower_value = p.lower;
    }
  std::vector<std::string> out;
  const std::string n = std::to_string(per_recording.size());
  for (const std::string& name : order) {
    const Count& c = counts[name];
    if (c.upper > 0)
      out.push_back(name + " at its upper bound " + format_value(c.upper_value) + " on " + std::to_string(c.upper) +
                    " of " + n + " recordings");
    if (c.lower > 0)
      out.push_back(name + " at its lower bound " + format_value(c.lower_value) + " on " + std::to_string(c.lower) +
                    " of " + n + " recordings");
  }
  return out;
}

std::vector<DiscrepancyEntry> Calibration::budgets() const {
  const double z = normal_quantile(alpha);
  std::vector<DiscrepancyEntry> out;
  for (const DiscrepancyEstimate& d : discrepancy) out.push_back(d.budget(z));
  // A family whose lines the healthy model never had above the noise has no relative estimate
  // (its budget would be 0): a model that adds lines there (a fault's sidebands) would have them
  // judged against the noise alone, though they reach the sensor through the same model-form
  // error (stiffness law, damping, rig) as the lines that were measured. Such a family takes
  // the largest relative budget measured on the same kind of channel: each budget is already
  // an upper confidence limit, and the largest is the upper end of what the calibration saw
  // there, not a value chosen for any corpus. Absolute budgets stay per family.
  std::map<Quantity, double> largest;
  for (std::size_t k = 0; k < out.size(); ++k)
    if (discrepancy[k].relative_cells > 0)
      largest[out[k].quantity] = std::max(largest[out[k].quantity], out[k].relative_std);
  for (std::size_t k = 0; k < out.size(); ++k)
    if (discrepancy[k].relative_cells == 0 && largest.count(out[k].quantity)) {
      out[k].relative_std = largest[out[k].quantity];
      out[k].relative_inherited = true;
    }
  return out;
}

std::vector<CalibrationCell> calibration_cells(const ModelComparison& cmp,
                                               const std::vector<std::vector<double>>& model_amplitude,
                                               const std::vector<double>& gains) {
  const RecordingSpectra& sp = cmp.spectra();
  std::vector<CalibrationCell> out;
  for (int c = 0; c < cmp.channels(); ++c)
    for (int i = 0; i < cmp.cells(); ++i) {
      const FeatureCell& cell = sp.layout.cells[static_cast<std::size_t>(i)];
      const int f = c * cmp.cells() + i;
      CalibrationCell x;
      x.channel = sp.channel_names[static_cast<std::size_t>(c)];
      x.order = cell.order;
      x.frequency_Hz = cell.order * cmp.kinematics().carrier_Hz;
      x.quantity = cmp.recording().channels[static_cast<std::size_t>(sp.channels[static_cast<std::size_t>(c)])].quantity;
      for (int l : cell.lines) {
        const Component fam = sp.layout.lines[static_cast<std::size_t>(l)].family;
        if (std::find(x.families.begin(), x.families.end(), fam) == x.families.end()) x.families.push_back(fam);
      }
      const double g = cmp.is_housing(c) ? gains[static_cast<std::size_t>(c)] : 1.0;
      x.model = g * model_amplitude[static_cast<std::size_t>(c)][static_cast<std::size_t>(cell.bin)];
      for (int w = 0; w < 2; ++w) {
        x.recording[w] = cmp.recording_amplitude(w, f);
        x.variance[w] = cmp.noise_diagonal_variance(w, f);
      }
      x.noise_variance = cmp.noise_variance(f);
      if (const int k = cmp.discretization_column(); k >= 0)
        x.discretization = g * cmp.fidelity_columns()[static_cast<std::size_t>(k)][static_cast<std::size_t>(f)];
      out.push_back(std::move(x));
    }
  return out;
}

const char* to_string(HealthyFit f) { return f == HealthyFit::Noise ? "noise" : "model_form"; }

HealthyFit healthy_fit_from_string(const std::string& s, const std::string& parameter) {
  if (s == "noise") return HealthyFit::Noise;
  if (s == "model_form") return HealthyFit::ModelForm;
  throw InputError(parameter, "'" + s + "' is not a weighting: give 'noise' or 'model_form'");
}

HealthyFitResult fit_healthy(const Recording& recording, const model::SimulationConfig& config,
                             DiagnoseOptions options, HealthyFit weighting) {
  require(options.compare.discrepancy.empty() && options.compare.baseline.empty(), "healthy fit",
          "a healthy recording is fitted without a discrepancy budget or a baseline of its own");
  options.nuisance_only = true;
  options.discrepancy_reference.reset();
  HealthyFitResult out{diagnose(recording, config, options), std::nullopt};
  if (weighting == HealthyFit::Noise) return out;
  // Why a second fit: the first weights every cell by the noise, so where the model's form
  // misses a line by orders of magnitude more than the noise (another stiffness law, a sensor
  // chain the model lacks) that line's chi2 decides the nuisance values -- e.g. the stiffness
  // level pushed to an end of its box to shrink one speed harmonic. The discrepancy estimated
  // from the first fit's residual is the covariance those cells actually have; weighting by it
  // is the feasible GLS estimate (one step: its estimate is consistent, iterating further does
  // not change its first-order efficiency).
  const Diagnosis& first = out.noise_weighted;
  if (first.nuisance.parameters.empty()) return out;
  for (const DiscrepancyEstimate& e : estimate_discrepancy({first.calibration_cells}))
    options.compare.discrepancy.push_back(e.budget(0.0));
  options.discrepancy_reference = DiagnoseOptions::DiscrepancyReference{first.nuisance.config, first.nuisance.gains};
  if (options.progress) options.progress = [p = options.progress](const std::string& s) { p("model-form weighted refit: " + s); };
  out.model_form_weighted = diagnose(recording, config, options);
  return out;
}

} // namespace pw::diagnose
