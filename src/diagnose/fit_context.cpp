#include "diagnose/fit_context.hpp"

#include "core/constants.hpp"
#include "core/statistics.hpp"
#include "model/validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>

namespace pw::diagnose {

ScoreSummary summarize(const WindowScore& w) {
  ScoreSummary s;
  s.chi2 = w.chi2;
  s.features = w.features;
  s.chi2_per_channel = w.chi2_per_channel;
  s.features_per_channel = w.features_per_channel;
  s.fidelity_z = w.fidelity_z;
  return s;
}

bool is_sensor_gain(const FittedParameter& p) { return p.sensor_gain; }

bool any_saturates(const std::vector<ParameterSpec>& specs) {
  return std::any_of(specs.begin(), specs.end(), [](const ParameterSpec& p) { return p.saturates; });
}

bool any_transfer(const std::vector<ParameterSpec>& specs) {
  return std::any_of(specs.begin(), specs.end(), [](const ParameterSpec& p) { return p.transfer; });
}

std::vector<double> absent_with_transfer_as_fitted(const std::vector<ParameterSpec>& specs,
                                                   const std::vector<double>& fitted) {
  std::vector<double> x;
  for (std::size_t i = 0; i < specs.size(); ++i)
    x.push_back(specs[i].transfer && i < fitted.size() ? fitted[i] : specs[i].null_value);
  return x;
}

std::vector<ParameterSpec> FitContext::nuisance_specs() const {
  std::vector<ParameterSpec> out;
  for (const Candidate* n : nuisance)
    for (auto& p : n->parameters(base)) out.push_back(p);
  return out;
}

model::SimulationConfig FitContext::make(const Candidate* cand, const Variant& v, std::span<const double> cx,
                                         std::span<const double> nx, std::vector<std::string>* overrides) const {
  model::SimulationConfig c = base;
  std::size_t k = 0;
  for (const Candidate* n : nuisance) {
    const std::size_t np = n->parameters(base).size();
    n->apply(c, Variant{}, nx.subspan(k, np), overrides);
    k += np;
  }
  if (cand) cand->apply(c, v, cx, overrides);
  return c;
}

std::vector<std::vector<double>> FitContext::amplitudes(const model::SimulationConfig& c, bool sensor_only,
                                                        std::atomic<long>* tally) const {
  if (!sensor_only) return cmp.simulate(c, false, tally)->amplitude;
  auto a = nuisance_sim->amplitude;
  const Recording& rec = cmp.recording();
  for (int ch = 0; ch < cmp.channels(); ++ch)
    if (cmp.is_housing(ch))
      a[static_cast<std::size_t>(ch)] = housing_spectrum(
          *nuisance_sim, c.sensor,
          rec.channels[static_cast<std::size_t>(cmp.spectra().channels[static_cast<std::size_t>(ch)])].sensor_angle_rad,
          cmp.spectra().layout.window_revolutions, cmp.spectra().layout.max_bin);
  return a;
}

double FitContext::fit_chi2(const Candidate* cand, const Variant& v, std::span<const double> cx,
                            std::span<const double> nx, bool sensor_only, std::atomic<long>* tally) const {
  try {
    const auto c = make(cand, v, cx, nx, nullptr);
    return cmp.score(amplitudes(c, sensor_only, tally), Half::Fit, nuisance_gains, HousingGains::Profile).chi2;
  } catch (const SolverError&) {
    return std::numeric_limits<double>::infinity();
  }
}

std::vector<double> FitContext::fit_residual(const Candidate* cand, const Variant& v, std::span<const double> cx,
                                             std::span<const double> nx, bool sensor_only,
                                             std::atomic<long>* tally) const {
  try {
    const auto c = make(cand, v, cx, nx, nullptr);
    return cmp.score(amplitudes(c, sensor_only, tally), Half::Fit, nuisance_gains, HousingGains::Profile).residual;
  } catch (const SolverError&) {
    return {};
  }
}

SizeRange model_form_range(double value, double absent, double std_error, double model_form_std, double z,
                           double box_lower, double box_upper) {
  const double se = std::isfinite(std_error) ? std_error : 0.0;
  const double s = value - absent;
  double near = value, far = value;
  if (model_form_std > 0 && s != 0) {
    const double r = z * model_form_std / std::fabs(s);
    near = absent + s / (1 + r);
    far = r < 1 ? absent + s / (1 - r) : (s > 0 ? box_upper : box_lower);
  }
  SizeRange out;
  out.lower = std::clamp(std::min(near, far) - z * se, box_lower, box_upper);
  out.upper = std::clamp(std::max(near, far) + z * se, box_lower, box_upper);
  return out;
}

SplitParameters split_parameters(const CandidateResult& r, const std::vector<double>& fixed_nuisance) {
  SplitParameters s;
  for (const auto& p : r.parameters)
    if (!p.nuisance)
      s.own.push_back(p.value);
    else if (!is_sensor_gain(p))
      s.nuisance.push_back(p.value);
  if (s.nuisance.size() != fixed_nuisance.size()) s.nuisance = fixed_nuisance;
  return s;
}

HeldNuisance hold_nuisance(const std::vector<std::vector<ParameterSpec>>& specs, const std::vector<bool>& hold,
                           std::span<const double> fitted, std::span<const double> start) {
  HeldNuisance h;
  std::size_t k = 0;
  for (std::size_t c = 0; c < specs.size(); ++c) {
    const bool held = c < hold.size() && hold[c];
    if (!held) h.free.push_back(c);
    for (const ParameterSpec& ps : specs[c]) {
      if (k >= fitted.size() || k >= start.size())
        throw SolverError("hold_nuisance: " + std::to_string(fitted.size()) + " fitted and " +
                          std::to_string(start.size()) + " start values for more nuisance parameters");
      if (held) {
        h.held.push_back(ps.name + "=" + format_value(ps.initial));
      } else {
        h.fitted.push_back(fitted[k]);
        h.start.push_back(start[k]);
      }
      ++k;
    }
  }
  return h;
}

namespace {

std::vector<FittedParameter> describe(const std::vector<ParameterSpec>& specs, const LmResult& r, std::size_t offset,
                                      bool nuisance) {
  std::vector<FittedParameter> out;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    FittedParameter p;
    p.name = specs[i].name;
    p.unit = specs[i].unit;
    p.value = r.x[offset + i];
    p.std_error = r.std_error[offset + i];
    p.lower = specs[i].lower;
    p.upper = specs[i].upper;
    p.initial = specs[i].initial;
    p.at_bound = r.at_bound[offset + i];
    p.nuisance = nuisance;
    p.saturates = specs[i].saturates;
    p.transfer = specs[i].transfer;
    p.size_conditional_on = specs[i].size_conditional_on;
    out.push_back(p);
  }
  return out;
}

/// Each fitted parameter's model-form standard deviation: the shifts of the residual the
/// comparison's budget allows (one per discrepancy entry, each moving its cells together),
/// carried into the estimate by the fit's sensitivity. How the entries' errors correlate the
/// calibration does not measure (each entry is estimated on its own), so the larger of the two
/// readings is kept: independent entries (they average down over the channels and families a
/// finding shows in), or all moving together (one relative error delta of the model's whole
/// change, model_form_range's own reading). *Why:* a model that gets the transfer of a fault's
/// signature wrong can get it wrong in every channel alike, and independent entries then
/// understate it. Measured on the three-planet rig of docs/diagnose-log.md, session 59: a sun
/// runout's model-form std 0.52 -> 0.82 um (7.9 um fitted, for 4 um), a planet tooth's 0.018 ->
/// 0.034 (0.784 for 0.5); neither range reaches the truth yet.
void set_model_form_std(const ModelComparison& cmp, const LmResult& lm,
                        const std::vector<std::vector<double>>& amplitudes, const std::vector<double>& gains,
                        std::vector<FittedParameter>& parameters) {
  const std::vector<std::vector<double>> shifts = cmp.model_form_shifts(amplitudes, gains);
  if (shifts.empty()) return;
  const std::vector<double> independent = propagated_std(lm, shifts);
  const std::vector<double> together = propagated_std_correlated(lm, shifts);
  for (std::size_t i = 0; i < independent.size() && i < parameters.size(); ++i)
    parameters[i].model_form_std = std::isnan(independent[i]) ? independent[i] : std::max(independent[i], together[i]);
}

/// The calibration's spread of the nuisance levels fitted jointly with a finding, carried into the
/// finding's own parameters (level_spread_std, fit.hpp) and added to their model-form std in
/// quadrature. *Why:* a level the model needs at different values on different healthy
/// recordings of one rig (a stiffness level of 0.53 at 150 rpm and 1.30 at 900 rpm) is fitted
/// here once more, and a size that trades against it (a runout's lines scale with the mesh
/// stiffness it acts through) is then stated for that one value: measured on the three-planet rig
/// of docs/diagnose-log.md session 60, a 4 um sun runout fitted at 7.9 um with the stiffness level
/// at 0.52: the level's spread over the calibration's three recordings (0.46 in ln) carries
/// +- 4.5 um into it, and its range (3.1 to 40 um) then holds the truth, where 6.7 to 9.6 um did not.
void add_level_spread(const std::map<std::string, double>& spread_ln, const LmResult& lm,
                      const std::vector<ParameterSpec>& nspec, std::size_t nc, std::vector<FittedParameter>& parameters) {
  if (spread_ln.empty()) return;
  std::vector<LevelSpread> levels;
  std::vector<std::string> names;
  for (std::size_t j = 0; j < nspec.size(); ++j)
    if (const auto it = spread_ln.find(nspec[j].name); it != spread_ln.end() && it->second > 0 && nc + j < lm.x.size()) {
      levels.push_back({nc + j, std::fabs(lm.x[nc + j]) * it->second});
      names.push_back(nspec[j].name);
    }
  if (levels.empty()) return;
  std::string of;
  for (const std::string& n : names) of += (of.empty() ? "" : ", ") + n;
  for (std::size_t i = 0; i < nc && i < parameters.size(); ++i) {
    FittedParameter& p = parameters[i];
    const double s = level_spread_std(lm, i, levels);
    if (!(s > 0) || std::isnan(p.model_form_std)) continue;
    p.level_spread_std = s;
    p.model_form_std = std::hypot(p.model_form_std, s);
    p.level_spread_of = of;
  }
}

/// The profiled housing-sensor gains of a fit, as nuisance parameters with their `--set` line.
void append_gains(const FitContext& ctx, const WindowScore& fit, CandidateResult& res) {
  int housing_channels = 0;
  for (int k = 0; k < ctx.cmp.channels(); ++k) housing_channels += ctx.cmp.is_housing(k) ? 1 : 0;
  for (int ch = 0; ch < ctx.cmp.channels(); ++ch) {
    if (!ctx.cmp.is_housing(ch)) continue;
    const std::size_t c = static_cast<std::size_t>(ch);
    FittedParameter g;
    g.name = "sensor.gain_m_s2_per_N";
    if (housing_channels > 1) g.name += "[" + ctx.cmp.spectra().channel_names[c] + "]";
    g.unit = "m/s^2 per N";
    g.value = fit.gains[c];
    g.std_error = fit.gain_std[c];
    g.lower = 0;
    g.upper = model::largest_housing_gain_m_s2_per_N(ctx.base);  // through the mount at the mesh frequency
    g.initial = ctx.base.sensor.gain_m_s2_per_N;
    g.at_bound = fit.gain_at_edge[c];
    g.nuisance = true;
    g.sensor_gain = true;
    res.parameters.push_back(g);
    res.overrides.push_back("sensor.gain_m_s2_per_N=" + format_value(g.value));
  }
}

} // namespace

CandidateResult fit_model(FitContext& ctx, const Candidate* cand, const Variant& v, bool joint, int lm_threads,
                          int max_iterations, const std::vector<double>* x_start) {
  std::atomic<long> sims{0};  // this fit's own simulations, whatever runs beside it
  const bool sensor_only = cand && cand->sensor_only();
  const std::vector<ParameterSpec> cspec = cand ? cand->parameters(ctx.base) : std::vector<ParameterSpec>{};
  const std::vector<ParameterSpec> nspec = ctx.nuisance_specs();
  const bool fit_nuisance = !cand || joint;
  std::vector<Bound> bounds;
  std::vector<double> x0;
  for (const auto& p : cspec) {
    bounds.push_back({p.lower, p.upper, p.log_scale});
    x0.push_back(p.initial);
  }
  if (fit_nuisance)
    for (std::size_t i = 0; i < nspec.size(); ++i) {
      bounds.push_back({nspec[i].lower, nspec[i].upper, nspec[i].log_scale});
      x0.push_back(ctx.nuisance_x.empty() ? nspec[i].initial : ctx.nuisance_x[i]);
    }
  if (x_start && x_start->size() == x0.size()) x0 = *x_start;
  const std::size_t nc = cspec.size();
  auto split = [&](const std::vector<double>& x, std::vector<double>& cx, std::vector<double>& nx) {
    cx.assign(x.begin(), x.begin() + static_cast<long>(nc));
    if (fit_nuisance)
      nx.assign(x.begin() + static_cast<long>(nc), x.end());
    else
      nx = ctx.nuisance_x;
  };
  const bool sensor_path_only = sensor_only && !fit_nuisance;  // the nuisance simulation is reused
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>*) {
    std::vector<double> cx, nx;
    split(x, cx, nx);
    const auto c = ctx.make(cand, v, cx, nx, nullptr);
    return ctx.cmp.score(ctx.amplitudes(c, sensor_path_only, &sims), Half::Fit, ctx.nuisance_gains, HousingGains::Profile).residual;
  };
  LmOptions lo;
  lo.max_iterations = max_iterations;
  lo.threads = lm_threads;
  const LmResult lm = levenberg_marquardt(f, bounds, x0, lo);

  CandidateResult res;
  res.name = cand ? cand->name() : "nuisance_only";
  res.physics = cand ? cand->physics() : "the model as it is, with the nuisance parameters fitted";
  res.variant = v.label;
  res.chosen = v;
  if (cand)
    for (Component c : cand->families()) res.families.push_back(to_string(c));
  res.own_parameters = static_cast<int>(nc);
  res.parameters = describe(cspec, lm, 0, false);
  std::vector<double> cx, nx;
  split(lm.x, cx, nx);
  if (fit_nuisance) {
    auto np = describe(nspec, lm, nc, true);
    res.parameters.insert(res.parameters.end(), np.begin(), np.end());
  }
  res.config = ctx.make(cand, v, cx, nx, &res.overrides);
  const auto amp = ctx.amplitudes(res.config, sensor_path_only, &sims);
  const WindowScore fit = ctx.cmp.score(amp, Half::Fit, ctx.nuisance_gains, HousingGains::Profile);
  const WindowScore held = ctx.cmp.score(amp, Half::HeldOut, fit.gains, HousingGains::Given);
  res.gains = fit.gains;
  set_model_form_std(ctx.cmp, lm, amp, fit.gains, res.parameters);
  if (fit_nuisance) add_level_spread(ctx.level_spread_ln, lm, nspec, nc, res.parameters);
  const double z = normal_quantile(ctx.alpha / 2);
  for (std::size_t i = 0; i < nc && i < res.parameters.size(); ++i) {
    FittedParameter& p = res.parameters[i];
    if (!(p.model_form_std > 0) || cspec[i].saturates) continue;
    const SizeRange range = model_form_range(p.value, cspec[i].null_value, p.std_error, p.model_form_std, z,
                                             std::min(p.lower, p.upper), std::max(p.lower, p.upper));
    p.model_form_lower = range.lower;
    p.model_form_upper = range.upper;
  }
  append_gains(ctx, fit, res);
  res.fit = summarize(fit);
  res.held_out = summarize(held);
  // The likelihood-ratio test of 'absent' (CandidateResult::null_chi2_fit): one simulation, run
  // only where it can decide -- a fit that does not improve on the nuisance-only model by
  // chi2_{1-alpha}(k) does not count whatever the ratio says (ranking.hpp).
  const double nuisance_fit_chi2 =
      ctx.nuisance_sim ? ctx.cmp.score(ctx.nuisance_sim->amplitude, Half::Fit, ctx.nuisance_gains, HousingGains::Profile).chi2
                       : std::numeric_limits<double>::infinity();
  if (!cspec.empty() &&
      nuisance_fit_chi2 - res.fit.chi2 > chi2_quantile(std::max<int>(1, static_cast<int>(nc)), ctx.alpha)) {
    const std::vector<double> null_x = absent_with_transfer_as_fitted(cspec, cx);
    const auto c0 = ctx.make(cand, v, null_x, nx, nullptr);
    res.null_chi2_fit = ctx.cmp.score(ctx.amplitudes(c0, sensor_path_only, &sims), Half::Fit, ctx.nuisance_gains, HousingGains::Profile).chi2;
  }
  res.lm_message = lm.message;
  res.simulations = static_cast<int>(sims.load());
  return res;
}

std::optional<CandidateResult> try_fit_model(FitContext& ctx, const Candidate* cand, const Variant& v, bool joint,
                                             int lm_threads, int max_iterations, const std::vector<double>& x_start) {
  try {
    return fit_model(ctx, cand, v, joint, lm_threads, max_iterations, &x_start);
  } catch (const SolverError&) {
    return std::nullopt;
  }
}

namespace {

/// Encoder phases the reference model is simulated at besides its own (line-counting encoders
/// only; model/sensor.hpp LineEncoder): the images of every mesh harmonic turn together by N
/// times the encoder's angle, so a phase phi = N * angle covers them all. Four equally spaced
/// phases give the variance of an amplitude |G + I e^{i phi}| over a uniform phi to a relative
/// error of order (|I| / |G|)^2 where |I| << |G| (three leave one of order |I| / |G|: the
/// amplitude's second harmonic in phi aliases onto its first; test EncoderPhaseVariance.*).
constexpr int kEncoderPhases = 4;

bool has_line_encoders(const model::SimulationConfig& c) {
  return c.sensor.sun_encoder_lines > 0 || c.sensor.carrier_encoder_lines > 0;
}

/// c with both encoders' lines turned by k / kEncoderPhases of a line pitch.
model::SimulationConfig encoder_phase_variant(model::SimulationConfig c, int k) {
  const double turn = 2 * kPi * k / kEncoderPhases;
  if (c.sensor.sun_encoder_lines > 0) c.sensor.sun_encoder_phase_rad += turn / c.sensor.sun_encoder_lines;
  if (c.sensor.carrier_encoder_lines > 0) c.sensor.carrier_encoder_phase_rad += turn / c.sensor.carrier_encoder_lines;
  return c;
}

} // namespace

std::shared_ptr<const ModelSpectra> with_encoder_phase_variance(const ModelSpectra& centre,
                                                                std::span<const ModelSpectra* const> phases) {
  auto m = std::make_shared<ModelSpectra>(centre);
  if (m->leak_variance.empty()) {
    m->leak_variance.resize(m->amplitude.size());
    for (std::size_t ch = 0; ch < m->amplitude.size(); ++ch) m->leak_variance[ch].assign(m->amplitude[ch].size(), 0.0);
  }
  for (std::size_t ch = 0; ch < m->amplitude.size(); ++ch)
    for (std::size_t b = 0; b < m->amplitude[ch].size() && b < m->leak_variance[ch].size(); ++b) {
      double mean = 0, sq = 0;
      for (const ModelSpectra* p : phases) mean += p->amplitude[ch][b] / static_cast<double>(phases.size());
      for (const ModelSpectra* p : phases) {
        const double d = p->amplitude[ch][b] - mean;
        sq += d * d / static_cast<double>(phases.size());
      }
      m->leak_variance[ch][b] += 2 * sq;
    }
  return m;
}

void set_fidelity(FitContext& ctx, const model::SimulationConfig& c, std::shared_ptr<const ModelSpectra>* centre) {
  ModelComparison& cmp = ctx.cmp;
  // 0: c itself; 1: a second discretization; 2, 3: the speed +- its relative standard error;
  // with line-counting encoders 4 .. 6: c with the encoders' lines turned by a quarter, a half
  // and three quarters of a pitch (their images' unknown phase).
  const bool encoders = has_line_encoders(c);
  std::vector<model::SimulationConfig> v(encoders ? 4 + kEncoderPhases - 1 : 4, c);
  for (int k = 1; encoders && k < kEncoderPhases; ++k) v[static_cast<std::size_t>(3 + k)] = encoder_phase_variant(c, k);
  std::string disc;
  if (c.solver.time_step_s > 0) {
    v[1].solver.time_step_s *= 0.7;
    disc = "time step x 0.7";
  } else {
    v[1].solver.steps_per_mode_period = static_cast<int>(std::lround(1.5 * c.solver.steps_per_mode_period));
    disc = "solver.steps_per_mode_period " + std::to_string(c.solver.steps_per_mode_period) + " -> " +
           std::to_string(v[1].solver.steps_per_mode_period);
  }
  const double u = std::max(cmp.spectra().speed.relative_std, 1e-9);
  v[2].operating.input_speed_rpm *= 1 + u;
  v[3].operating.input_speed_rpm *= 1 - u;
  std::vector<std::shared_ptr<const ModelSpectra>> s(v.size());
  parallel_for(static_cast<int>(v.size()), ctx.threads, [&](int i) {
    s[static_cast<std::size_t>(i)] = cmp.simulate(v[static_cast<std::size_t>(i)], i == 0);
  });
  const int nc = cmp.channels(), ncell = cmp.cells();
  std::vector<std::vector<double>> cols(2, std::vector<double>(static_cast<std::size_t>(cmp.features())));
  for (int ch = 0; ch < nc; ++ch)
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(ch * ncell + i);
      const std::size_t b = static_cast<std::size_t>(cmp.spectra().layout.cells[static_cast<std::size_t>(i)].bin);
      const std::size_t cc = static_cast<std::size_t>(ch);
      cols[0][f] = s[1]->amplitude[cc][b] - s[0]->amplitude[cc][b];
      cols[1][f] = 0.5 * (s[2]->amplitude[cc][b] - s[3]->amplitude[cc][b]);
    }
  char buf[96];
  std::snprintf(buf, sizeof buf, "speed +- %.2g (its relative standard error)", u);
  cmp.set_fidelity(std::move(cols), {disc, buf}, 0);  // column 0: the discretization
  if (centre) {
    *centre = s[0];
    if (encoders) {
      std::vector<const ModelSpectra*> phases{s[0].get()};
      for (std::size_t k = 4; k < s.size(); ++k) phases.push_back(s[k].get());
      *centre = with_encoder_phase_variance(*s[0], std::span<const ModelSpectra* const>(phases));
    }
  }
}

} // namespace pw::diagnose
