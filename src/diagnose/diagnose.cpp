#include "diagnose/diagnose.hpp"

#include "core/error.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "signal/spectrum.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <numbers>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace pw::diagnose {

const char* to_string(Verdict v) {
  switch (v) {
  case Verdict::NoMissingPhysics: return "no_missing_physics";
  case Verdict::MissingPhysicsFound: return "missing_physics_found";
  case Verdict::Unexplained: return "unexplained_residual";
  }
  return "unknown";
}

namespace {

/// Runs body(i) for i in [0, n) on up to `threads` OpenMP threads; the first
/// exception thrown by any iteration is rethrown after the loop (an exception
/// must not leave an OpenMP region).
template <class F>
void parallel_for(int n, int threads, F&& body) {
  std::exception_ptr error;
  std::mutex m;
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, std::min(threads, n)))
  for (int i = 0; i < n; ++i) {
    try {
      body(i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(m);
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

using Clock = std::chrono::steady_clock;
constexpr double kMinWarmupCycles = 24;  ///< mesh cycles the model may warm up before the fit window
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

WindowScore score(const WindowComparison& w) {
  WindowScore s;
  s.chi2 = w.chi2;
  s.chi2_per_channel = w.chi2_per_channel;
  s.dof_per_channel = w.dof_per_channel;
  for (int d : w.dof_per_channel) s.dof += d;
  return s;
}

/// Everything a fit needs, shared by all candidates of one diagnosis.
struct Context {
  const ModelComparison& cmp;
  model::SimulationConfig base;
  double t_fit_end = 0, t_all_end = 0;
  std::vector<const Candidate*> nuisance;
  std::vector<double> nuisance_x;  // fitted values (after the nuisance fit)
  int threads = 1;
  std::mutex mutex;
  double compare_s = 0;

  /// base + nuisance values + candidate (may be null).
  model::SimulationConfig make(const Candidate* cand, const Variant& v, std::span<const double> cx,
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
  WindowComparison evaluate(const model::SimulationConfig& c, int window, bool profile, double fixed_dt = 0) {
    const double t_end = window == 0 ? t_fit_end : t_all_end;
    const auto sim = cmp.simulate(c, t_end, fixed_dt);
    const auto t0 = Clock::now();
    auto out = cmp.compare(*sim, c, window, profile);
    std::lock_guard<std::mutex> lock(mutex);
    compare_s += seconds_since(t0);
    return out;
  }
};

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
    out.push_back(p);
  }
  return out;
}

/// Fits candidate `cand` (null: nuisance only) with variant v.
CandidateResult fit_model(Context& ctx, const Candidate* cand, const Variant& v, bool joint, const DiagnoseOptions& o) {
  const long sims0 = ctx.cmp.simulations();
  std::vector<ParameterSpec> cspec = cand ? cand->parameters(ctx.base) : std::vector<ParameterSpec>{};
  std::vector<ParameterSpec> nspec;
  for (const Candidate* n : ctx.nuisance)
    for (auto& p : n->parameters(ctx.base)) nspec.push_back(p);
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
  const std::size_t nc = cspec.size();
  auto split = [&](const std::vector<double>& x, std::vector<double>& cx, std::vector<double>& nx) {
    cx.assign(x.begin(), x.begin() + static_cast<long>(nc));
    if (fit_nuisance)
      nx.assign(x.begin() + static_cast<long>(nc), x.end());
    else
      nx = ctx.nuisance_x;
  };
  ResidualFn f = [&](const std::vector<double>& x, const std::vector<double>* centre) {
    std::vector<double> cx, nx;
    double dt = 0;
    if (centre) {  // Jacobian column: the centre's time step (a cache hit)
      split(*centre, cx, nx);
      dt = ctx.cmp.simulate(ctx.make(cand, v, cx, nx, nullptr), ctx.t_fit_end)->dt_s;
    }
    split(x, cx, nx);
    return ctx.evaluate(ctx.make(cand, v, cx, nx, nullptr), 0, true, dt).residual;
  };
  LmOptions lo;
  lo.max_iterations = o.max_iterations;
  lo.covariance_scale = kHannChi2Scale;
  lo.threads = ctx.threads;
  const LmResult lm = levenberg_marquardt(f, bounds, x0, lo);

  CandidateResult res;
  res.name = cand ? cand->name() : "nuisance_only";
  res.physics = cand ? cand->physics() : "the model as it is, with the nuisance parameters fitted";
  res.variant = v.label;
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
  const WindowComparison fit_cmp = ctx.evaluate(res.config, 0, true);
  res.sensor_gain = fit_cmp.sensor_gain;
  res.config.sensor.gain_m_s2_per_N = fit_cmp.sensor_gain > 0 ? fit_cmp.sensor_gain : res.config.sensor.gain_m_s2_per_N;
  bool housing = false;
  for (int c : ctx.cmp.channels())
    housing = housing || ctx.cmp.recording().channels[static_cast<std::size_t>(c)].quantity == Quantity::HousingAcceleration;
  if (housing) {
    res.overrides.push_back("sensor.gain_m_s2_per_N=" + format_value(res.config.sensor.gain_m_s2_per_N));
    FittedParameter g;
    g.name = "sensor.gain_m_s2_per_N";
    g.unit = "m/s^2 per N";
    g.value = fit_cmp.sensor_gain;
    g.std_error = fit_cmp.sensor_gain_std;
    g.lower = 0;
    g.upper = 1;
    g.initial = ctx.base.sensor.gain_m_s2_per_N;
    g.nuisance = true;
    res.parameters.push_back(g);
  }
  res.fit = score(fit_cmp);
  res.held_out = score(ctx.evaluate(res.config, 1, false));
  res.lm_message = lm.message;
  res.simulations = static_cast<int>(ctx.cmp.simulations() - sims0);
  return res;
}

double noise_bound(const ModelComparison& cmp, int w, double alpha) {
  const double m = cmp.dof(w);
  const double per = m / static_cast<double>(cmp.channels().size());
  double var_sigma = 0;
  for (const auto& n : cmp.noise()) var_sigma += (per * n.relative_uncertainty) * (per * n.relative_uncertainty);
  return kHannChi2Scale * chi2_quantile(m / kHannChi2Scale, alpha) + normal_quantile(alpha) * std::sqrt(var_sigma);
}

std::string param_text(const FittedParameter& p) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s = %.4g ± %.2g %s", p.name.c_str(), p.value, p.std_error,
                p.unit == "1" ? "" : p.unit.c_str());
  std::string s = buf;
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s;
}

} // namespace

Diagnosis diagnose(const Recording& recording, const model::SimulationConfig& config_in, const DiagnoseOptions& o) {
  const auto t_start = Clock::now();
  auto say = [&](const std::string& s) {
    if (o.progress) o.progress(s);
  };
  model::SimulationConfig config = config_in;
  config.operating = recording.operating;
  model::validate(config);
  int threads = o.threads;
#ifdef _OPENMP
  if (threads <= 0) threads = omp_get_max_threads();
#else
  threads = 1;
#endif

  Diagnosis d;
  // The model's own warm-up must end before the fit window: leave it kMinWarmupCycles mesh cycles.
  const double f_mesh = kinematics(config.stage, config.operating.input_speed_rpm).mesh_Hz;
  ModelComparison cmp(recording, config, std::max(recording.time_s.front(), kMinWarmupCycles / f_mesh), o.compare);
  d.kinematics = cmp.kinematics();
  for (int c : cmp.channels()) d.channels.push_back(recording.channels[static_cast<std::size_t>(c)].name);
  d.noise = cmp.noise();
  d.fit_window = cmp.window(0);
  d.held_out_window = cmp.window(1);
  d.bound_fit = noise_bound(cmp, 0, o.alpha);
  d.bound_held_out = noise_bound(cmp, 1, o.alpha);
  d.timing.threads = threads;

  Context ctx{cmp, config, 0.0, 0.0, {}, {}, 1, {}, 0.0};
  const double dt = recording.sample_interval_s();
  ctx.t_fit_end = cmp.window(0).t_end_s + dt;
  ctx.t_all_end = recording.time_s.back() + dt;
  ctx.threads = threads;
  auto allowed = [&](const Candidate& c) {
    return o.only_candidates.empty() ||
           std::find(o.only_candidates.begin(), o.only_candidates.end(), c.name()) != o.only_candidates.end();
  };
  for (const auto& c : candidate_library())
    if (c->nuisance() && allowed(*c)) ctx.nuisance.push_back(c.get());

  // 1. The nominal model, both windows (run in parallel: two independent simulations).
  say("nominal model");
  WindowComparison nom[2];
  parallel_for(2, threads, [&](int w) { nom[w] = ctx.evaluate(config, w, false); });
  d.nominal_fit = score(nom[0]);
  d.nominal_held_out = score(nom[1]);

  // 2. Nuisance parameters.
  say("fitting the nuisance parameters");
  d.nuisance = fit_model(ctx, nullptr, Variant{}, true, o);
  for (const auto& p : d.nuisance.parameters)
    if (p.name != "sensor.gain_m_s2_per_N") ctx.nuisance_x.push_back(p.value);
  ctx.base.sensor.gain_m_s2_per_N = d.nuisance.config.sensor.gain_m_s2_per_N;

  // 3. Noise test.
  const bool consistent = d.nuisance.fit.chi2 <= d.bound_fit && d.nuisance.held_out.chi2 <= d.bound_held_out;
  char rule[900];
  std::snprintf(rule, sizeof rule,
                "chi2 of the whitened Hann-bin residual (bins %d..%d of each %d-sample window, %zu channels) is "
                "c chi2(m/c)-distributed under the noise-only hypothesis, c = %.3f; bound at alpha = %.3g: "
                "%.1f (fit window, m = %d) and %.1f (held-out window, m = %d), including the uncertainty of the "
                "noise estimates. A candidate counts when its improvement over the nuisance-only model exceeds "
                "c chi2_{1-alpha}(k) (k = its parameters) on the fit window and on the held-out window; the lowest "
                "BIC among those wins.",
                d.fit_window.k_min, d.fit_window.k_max, static_cast<int>(d.fit_window.count), d.channels.size(),
                kHannChi2Scale, o.alpha, d.bound_fit, cmp.dof(0), d.bound_held_out, cmp.dof(1));
  d.rule = rule;

  const model::SimulationConfig* final_config = &d.nuisance.config;
  if (!consistent || o.always_fit_candidates) {
    // 4. Locate on the nuisance-fitted model over the whole recording.
    say("locating the residual");
    const auto t_loc = Clock::now();
    const auto full = cmp.simulate(d.nuisance.config, ctx.t_all_end);
    const auto t_loc1 = Clock::now();
    d.location = locate(cmp, *full, d.nuisance.config, d.nuisance.config.sensor.gain_m_s2_per_N, o.locate);
    d.timing.locate_s += seconds_since(t_loc1);
    (void)t_loc;
    d.located = true;

    // Shortlist by located evidence.
    struct Pick {
      const Candidate* c;
      double z;
    };
    std::vector<Pick> picks;
    for (const auto& c : candidate_library()) {
      if (c->nuisance() || !allowed(*c)) continue;
      double z = -1e300;
      for (Component f : c->families()) z = std::max(z, d.location.evidence.family_z[static_cast<int>(f)]);
      picks.push_back({c.get(), z});
    }
    std::stable_sort(picks.begin(), picks.end(), [](const Pick& a, const Pick& b) { return a.z > b.z; });
    std::vector<Pick> shortlist;
    int heavy = 0;
    for (const Pick& p : picks) {
      if (p.c->sensor_only()) {
        shortlist.push_back(p);
        continue;
      }
      if (heavy < o.max_candidates) {
        shortlist.push_back(p);
        ++heavy;
      }
    }
    const ToothMap map(ctx.base);
    for (const Pick& p : shortlist) {
      say("fitting candidate " + p.c->name());
      // Screen the discrete variants at the start values (in parallel).
      const auto variants = p.c->variants(d.location.evidence, ctx.base, map);
      Variant best = variants.front();
      if (variants.size() > 1) {
        std::vector<double> chi(variants.size());
        std::vector<double> cx;
        for (const auto& s : p.c->parameters(ctx.base)) cx.push_back(s.initial);
        parallel_for(static_cast<int>(variants.size()), threads, [&](int i) {
          chi[static_cast<std::size_t>(i)] =
              ctx.evaluate(ctx.make(p.c, variants[static_cast<std::size_t>(i)], cx, ctx.nuisance_x, nullptr), 0, true)
                  .chi2;
        });
        best = variants[static_cast<std::size_t>(std::min_element(chi.begin(), chi.end()) - chi.begin())];
      }
      CandidateResult r = fit_model(ctx, p.c, best, o.joint_nuisance && !p.c->sensor_only(), o);
      r.evidence_z = p.z;
      const int k = std::max(1, r.own_parameters);
      r.lr_threshold = kHannChi2Scale * chi2_quantile(k, o.alpha);
      r.delta_chi2_fit = d.nuisance.fit.chi2 - r.fit.chi2;
      r.delta_chi2_held_out = d.nuisance.held_out.chi2 - r.held_out.chi2;
      r.significant = r.delta_chi2_fit > r.lr_threshold;
      r.holds = r.delta_chi2_held_out > r.lr_threshold;
      int k_total = 0;
      for (const auto& fp : r.parameters) k_total += 1, (void)fp;
      const double m_eff = cmp.dof(0) / kHannChi2Scale;
      r.aic = r.fit.chi2 / kHannChi2Scale + 2.0 * k_total;
      r.bic = r.fit.chi2 / kHannChi2Scale + k_total * std::log(m_eff);
      d.candidates.push_back(std::move(r));
    }
    d.nuisance.aic = d.nuisance.fit.chi2 / kHannChi2Scale + 2.0 * static_cast<double>(d.nuisance.parameters.size());
    d.nuisance.bic = d.nuisance.fit.chi2 / kHannChi2Scale +
                     static_cast<double>(d.nuisance.parameters.size()) * std::log(cmp.dof(0) / kHannChi2Scale);
    // 5. Rank.
    std::stable_sort(d.candidates.begin(), d.candidates.end(), [](const CandidateResult& a, const CandidateResult& b) {
      const bool ga = a.significant && a.holds, gb = b.significant && b.holds;
      if (ga != gb) return ga;
      return a.bic < b.bic;
    });
    if (!d.candidates.empty() && d.candidates.front().significant && d.candidates.front().holds) d.winner = 0;
    const double best_bic = d.winner == 0 ? d.candidates.front().bic : 0;
    for (std::size_t i = 0; i < d.candidates.size(); ++i) {
      CandidateResult& r = d.candidates[i];
      char buf[400];
      if (static_cast<int>(i) == d.winner)
        std::snprintf(buf, sizeof buf,
                      "lowest BIC among the candidates that improve significantly on both windows (fit: -%.1f, "
                      "held-out: -%.1f; threshold %.1f)",
                      r.delta_chi2_fit, r.delta_chi2_held_out, r.lr_threshold);
      else if (!r.significant)
        std::snprintf(buf, sizeof buf, "improvement on the fit window %.1f is below the threshold %.1f",
                      r.delta_chi2_fit, r.lr_threshold);
      else if (!r.holds)
        std::snprintf(buf, sizeof buf,
                      "fits the first window (-%.1f) but does not hold on the held-out window (%+.1f; threshold "
                      "%.1f)",
                      r.delta_chi2_fit, -r.delta_chi2_held_out, r.lr_threshold);
      else
        std::snprintf(buf, sizeof buf, "BIC %.1f higher than the winner's", r.bic - best_bic);
      r.reason = buf;
    }
    if (d.winner == 0) final_config = &d.candidates.front().config;
  }

  // Verdict and summary.
  auto nuisance_text = [&]() {
    std::string s;
    for (const auto& p : d.nuisance.parameters) s += (s.empty() ? "" : ", ") + param_text(p);
    return s;
  };
  if (consistent && d.winner < 0) {
    d.verdict = Verdict::NoMissingPhysics;
    d.summary = "No missing physics found: with the nuisance parameters fitted (" + nuisance_text() +
                ") the residual is consistent with the measurement noise (chi2 " + fmt("%.0f", d.nuisance.fit.chi2) +
                " <= " + fmt("%.0f", d.bound_fit) + " on the fit window, " + fmt("%.0f", d.nuisance.held_out.chi2) +
                " <= " + fmt("%.0f", d.bound_held_out) + " held out).";
  } else if (d.winner == 0) {
    const CandidateResult& w = d.candidates.front();
    d.verdict = Verdict::MissingPhysicsFound;
    std::string ps;
    for (const auto& p : w.parameters)
      if (!p.nuisance) ps += (ps.empty() ? "" : ", ") + param_text(p);
    d.summary = "Missing physics: " + w.name + (w.variant.empty() ? "" : " (" + w.variant + ")") + " — " + w.physics +
                "; fitted " + ps + "; chi2 " + fmt("%.0f", d.nominal_fit.chi2) + " -> " + fmt("%.0f", w.fit.chi2) +
                " on the fit window and " + fmt("%.0f", d.nominal_held_out.chi2) + " -> " +
                fmt("%.0f", w.held_out.chi2) + " held out (noise bound " + fmt("%.0f", d.bound_held_out) + ").";
  } else {
    d.verdict = Verdict::Unexplained;
    std::string where = d.located && !d.location.families.empty()
                            ? std::string(to_string(d.location.families.front().family)) + " family (z = " +
                                  fmt("%.1f", d.location.families.front().z) + ")"
                            : "the mesh harmonics";
    d.summary = "The recording differs from the model beyond the noise (chi2 " + fmt("%.0f", d.nuisance.fit.chi2) +
                " > " + fmt("%.0f", d.bound_fit) + " after the nuisance fit), mostly in the " + where +
                ", but no candidate in the library explains it on held-out data.";
  }
  d.final_overrides = d.winner == 0 ? d.candidates.front().overrides : d.nuisance.overrides;

  // Plots and the TSA domain: nominal (before) and final (after) over the whole recording.
  say("spectra and synchronous averages before/after");
  std::shared_ptr<const SimulatedSignals> full_before, full_after;
  parallel_for(2, threads, [&](int i) {
    if (i == 0)
      full_before = cmp.simulate(config, ctx.t_all_end);
    else
      full_after = cmp.simulate(*final_config, ctx.t_all_end);
  });
  const auto t_feat = Clock::now();
  const double f_max = o.compare.max_mesh_harmonic * d.kinematics.mesh_Hz;
  const AnalysisWindow& hw = cmp.window(1);
  const double gain_after = final_config->sensor.gain_m_s2_per_N;
  for (std::size_t c = 0; c < cmp.channels().size(); ++c) {
    const int ci = static_cast<int>(c);
    const auto r = cmp.recording_band_limited(ci, hw.begin, hw.count, f_max);
    const auto b = cmp.model_on_recording(*full_before, config, config.sensor.gain_m_s2_per_N, ci, hw.begin, hw.count, f_max);
    const auto a = cmp.model_on_recording(*full_after, *final_config, gain_after, ci, hw.begin, hw.count, f_max);
    const auto sr = signal::amplitude_spectrum(r, dt), sb = signal::amplitude_spectrum(b, dt),
               sa = signal::amplitude_spectrum(a, dt);
    PlotSeries ps;
    ps.name = "spectrum/" + d.channels[c];
    ps.x_unit = "Hz";
    ps.y_unit = recording.channels[static_cast<std::size_t>(cmp.channels()[c])].unit;
    for (std::size_t k = 0; k < sr.frequency_Hz.size() && sr.frequency_Hz[k] <= f_max; ++k) {
      ps.x.push_back(sr.frequency_Hz[k]);
      ps.recording.push_back(sr.amplitude[k]);
      ps.before.push_back(sb.amplitude[k]);
      ps.after.push_back(sa.amplitude[k]);
    }
    d.plots.push_back(std::move(ps));
  }
  // TSA per component on the preferred channel (as locate chooses), whole usable span.
  {
    const std::size_t begin = cmp.window(0).begin;
    std::size_t end = recording.time_s.size();
    const double t_cover = std::min(full_before->t_end_s(), full_after->t_end_s()) - dt;
    while (end > begin && recording.time_s[end - 1] > t_cover) --end;
    const std::size_t count = end - begin;
    const struct {
      Component comp;
      Quantity q1, q2;
    } rot[] = {{Component::Sun, Quantity::MeshAccelerationSunPlanet, Quantity::MeshAccelerationPlanetRing},
               {Component::Planet, Quantity::MeshAccelerationSunPlanet, Quantity::MeshAccelerationPlanetRing},
               {Component::Carrier, Quantity::MeshAccelerationPlanetRing, Quantity::MeshAccelerationSunPlanet}};
    for (const auto& rr : rot) {
      int ci = -1;
      for (Quantity q : {rr.q1, rr.q2, Quantity::HousingAcceleration}) {
        for (std::size_t c = 0; c < cmp.channels().size() && ci < 0; ++c)
          if (recording.channels[static_cast<std::size_t>(cmp.channels()[c])].quantity == q) ci = static_cast<int>(c);
        if (ci >= 0) break;
      }
      if (ci < 0 || count < 64) continue;
      const int period = static_cast<int>(std::lround(d.kinematics.period_mesh_cycles(rr.comp)));
      const int spc = 16;
      const double t0 = recording.time_s[begin];
      const auto r = cmp.recording_band_limited(ci, begin, count, f_max);
      const auto b = cmp.model_on_recording(*full_before, config, config.sensor.gain_m_s2_per_N, ci, begin, count, f_max);
      const auto a = cmp.model_on_recording(*full_after, *final_config, gain_after, ci, begin, count, f_max);
      const auto tr = synchronous_average(r, t0, dt, d.kinematics.mesh_Hz, period, spc);
      const auto tb = synchronous_average(b, t0, dt, d.kinematics.mesh_Hz, period, spc);
      const auto ta = synchronous_average(a, t0, dt, d.kinematics.mesh_Hz, period, spc);
      if (tr.averages < 1) continue;
      PlotSeries ps;
      ps.name = std::string("tsa/") + to_string(rr.comp) + "/" + d.channels[static_cast<std::size_t>(ci)];
      ps.x_unit = "mesh cycles";
      ps.y_unit = recording.channels[static_cast<std::size_t>(cmp.channels()[static_cast<std::size_t>(ci)])].unit;
      double eb = 0, ea = 0;
      for (std::size_t j = 0; j < tr.values.size(); ++j) {
        ps.x.push_back(static_cast<double>(j) / spc);
        ps.recording.push_back(tr.values[j]);
        ps.before.push_back(tb.values[j]);
        ps.after.push_back(ta.values[j]);
        eb += (tr.values[j] - tb.values[j]) * (tr.values[j] - tb.values[j]);
        ea += (tr.values[j] - ta.values[j]) * (tr.values[j] - ta.values[j]);
      }
      d.tsa_names.push_back(ps.name);
      d.tsa_rms_before.push_back(std::sqrt(eb / static_cast<double>(tr.values.size())));
      d.tsa_rms_after.push_back(std::sqrt(ea / static_cast<double>(tr.values.size())));
      d.plots.push_back(std::move(ps));
    }
  }
  const double feat_s = seconds_since(t_feat);
  d.timing.total_s = seconds_since(t_start);
  d.timing.simulate_s = cmp.simulation_seconds();
  d.timing.simulations = cmp.simulations();
  d.timing.compare_s = ctx.compare_s + feat_s;
  d.timing.fit_overhead_s = std::max(0.0, d.timing.total_s - d.timing.simulate_s / threads - d.timing.compare_s / threads -
                                              d.timing.locate_s);
  return d;
}

} // namespace pw::diagnose
