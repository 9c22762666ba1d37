#include "diagnose/compare.hpp"

#include "config/schema.hpp"

#include "core/error.hpp"
#include "core/golden_section.hpp"
#include "core/statistics.hpp"
#include "model/simulation.hpp"
#include "model/validate.hpp"
#include "wear/simulation.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <string_view>
#include <type_traits>

namespace pw::diagnose {

namespace {
/// Appends every value of the schema (config/schema.hpp) to one string: two
/// configurations share a key exactly when every key has the same value.
class CacheKeyBuilder {
public:
  std::string key;

  void section(std::string_view path) {
    key += '[';
    key += path;
    key += ']';
  }
  template <class T>
  void field(std::string_view /*key*/, const T& value, std::string_view /*doc*/, const config::Range& = {}) {
    using U = std::remove_cv_t<T>;
    if constexpr (std::is_same_v<U, std::vector<double>>) {
      key += '(';
      for (double v : value) append(v);
      key += ')';
    } else {
      append(static_cast<double>(value));  // bool, int, enumeration, double
    }
  }
  void angle(std::string_view key_rad, std::string_view /*key_deg*/, const double& value_rad, std::string_view doc, const config::Range& = {}) {
    field(key_rad, value_rad, doc);
  }
  void teeth(std::string_view /*key*/, const std::vector<model::ToothModifier>& teeth, std::string_view /*doc*/) {
    for (const auto& t : teeth) {
      key += '{';
      config::visit_tooth(*this, t);
      key += '}';
    }
  }

private:
  void append(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g,", v);  // round-trip exact
    key += buf;
  }
};
} // namespace

std::string builtin_config_key(const model::SimulationConfig& c) {
  CacheKeyBuilder builder;
  config::visit_config(builder, c);
  return builder.key;
}

namespace {
/// The upper end of solver.record_mesh_cycles (model::validate).
constexpr double kMaxModelRecordCycles = 1e6;
/// How often a housing gain's profile search that ended at an edge of its bracket is centred on
/// that end and doubled (ModelComparison::score): 8 doublings of ln g0 +- 0.4 reach +-102 in ln g.
constexpr int kGainBracketDoublings = 8;
/// A wider bracket that lowers chi2 by less than this found nothing: a chi2 change of 0.01 is a
/// tenth of a standard error of the gain (chi2 rises by (delta / se)^2 from its minimum).
constexpr double kGainChi2Resolution = 0.01;
/// Relative margin below the configuration's largest housing gain at which a profile search that
/// runs into it stops: far below any fit's precision, far above the round-off between two
/// evaluations of the bound (a few units in the last place).
constexpr double kGainBoundMargin = 1e-6;
} // namespace

ModelComparison::ModelComparison(const Recording& recording, const model::SimulationConfig& config,
                                 CompareOptions options)
    : rec_(recording), opt_(std::move(options)) {
  spec_ = analyse_recording(rec_, config.stage, opt_.analysis);
  if (!opt_.baseline.empty()) carry_baseline_alien_lines(spec_, opt_.baseline_alien_lines, spec_.alien_tolerance);
  base_ = config;
  base_.operating = rec_.operating;
  base_.operating.input_speed_rpm = spec_.speed.input_rpm;
  // The model records as many mesh cycles as the recording holds; counted in
  // double so that a very long recording is refused, not wrapped in int.
  // In halves of Q mesh cycles, (kLeakWindows - 1) Q / kLeakWindows more: the windows that
  // start elsewhere in the gear pattern (ModelSpectra::leak_variance).
  const int Q = spec_.layout.mesh_cycles;
  const double cycles = (Q > 0 ? Q + std::ceil(static_cast<double>(Q) * (kLeakWindows - 1) / kLeakWindows)
                               : std::ceil(spec_.layout.revolutions * spec_.kinematics.ring_teeth)) +
                        3;
  require(cycles <= kMaxModelRecordCycles, "--recording", "covers ", cycles - 3, " mesh cycles; the model records at most ",
          kMaxModelRecordCycles, " (solver.record_mesh_cycles); diagnose a shorter excerpt");
  base_.solver.record_mesh_cycles = static_cast<int>(cycles);
  // The model's automatic step resolves the analysed band (0.3 f_s, order_analysis.hpp), not the
  // stiffest mode above it: the comparison sees no line there, a mode far above a line acts on
  // it quasi-statically, and the fidelity direction of a second discretization (fit_context.hpp)
  // carries what the coarser step changes into V. Measured: a 2 s cracked-sun-tooth diagnosis
  // 3.5x faster, the own corpus's scores unchanged (docs/benchmark.md, session 18). A
  // configuration that states its step or band keeps it.
  if (base_.solver.time_step_s == 0 && base_.solver.accuracy_band_Hz == 0) {
    base_.solver.accuracy_band_Hz = opt_.analysis.layout.band_fraction / rec_.sample_interval_s();
    band_step_ = true;
  }
  model::validate(base_);
  const int nc = channels(), ncell = cells();
  for (int c = 0; c < nc; ++c)
    housing_.push_back(rec_.channels[static_cast<std::size_t>(spec_.channels[static_cast<std::size_t>(c)])].quantity ==
                       Quantity::HousingAcceleration);
  const std::size_t m = static_cast<std::size_t>(features());
  a_rec_.assign(2, std::vector<double>(m));
  s2_.assign(m, 0.0);
  d_.assign(2, std::vector<double>(m));
  vns_.assign(m, 0.0);
  disc_.assign(m, 0.0);
  disc_entry_.assign(m, -1);
  disc_abs_.assign(m, 0.0);
  disc_sd_.assign(m, 0.0);
  for (std::size_t k = 0; k < opt_.discrepancy.size(); ++k) {
    const DiscrepancyEntry& e = opt_.discrepancy[k];
    for (int c = 0; c < nc; ++c) {
      if (rec_.channels[static_cast<std::size_t>(spec_.channels[static_cast<std::size_t>(c)])].quantity != e.quantity)
        continue;
      for (int i = 0; i < ncell; ++i)
        for (int l : spec_.layout.cells[static_cast<std::size_t>(i)].lines)
          if (spec_.layout.lines[static_cast<std::size_t>(l)].family == e.family) {
            const std::size_t f = static_cast<std::size_t>(c * ncell + i);
            if (e.relative_std > disc_[f]) {
              disc_[f] = e.relative_std;
              disc_entry_[f] = static_cast<int>(k);
            }
            disc_abs_[f] = std::max(disc_abs_[f], e.absolute_variance);
          }
    }
  }
  match_baseline();
  // Differential: what the model lacks in absolute terms is in the baseline too and cancels.
  if (!opt_.baseline.empty()) disc_abs_.assign(m, 0.0);
  const double flag = chi2_quantile(1.0, opt_.alpha);
  for (int c = 0; c < nc; ++c)
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      const int bin = spec_.layout.cells[static_cast<std::size_t>(i)].bin;
      s2_[f] = spec_.noise_variance[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
      for (int w = 0; w < 2; ++w)
        a_rec_[static_cast<std::size_t>(w)][f] =
            spec_.amplitude[static_cast<std::size_t>(w)][static_cast<std::size_t>(c)][static_cast<std::size_t>(bin)];
    }
  // Per-cell Rician variances of the recording's amplitudes and the non-stationarity flag.
  auto classify = [&](int c, std::vector<double>* ratios) {
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      double v[2];
      for (int w = 0; w < 2; ++w) {
        const double A = a_rec_[static_cast<std::size_t>(w)][f];
        v[w] = rice_variance(debiased_amplitude(A, s2_[f]), s2_[f]);
      }
      const double d = a_rec_[0][f] - a_rec_[1][f];
      vns_[f] = d * d > flag * (v[0] + v[1]) ? d * d : 0.0;
      if (ratios && vns_[f] == 0.0 && v[0] + v[1] > 0) ratios->push_back(d * d / (v[0] + v[1]));
      for (int w = 0; w < 2; ++w) d_[static_cast<std::size_t>(w)][f] = v[w] + vns_[f];
    }
  };
  // Dispersion: the recording's two halves are two draws of the same stationary features, so
  // (A_1 - A_2)^2 / (V_1 + V_2) has mean 1 over the unflagged cells when the noise model is
  // right. Phase jitter, slow load or speed changes and non-periodic content (a rig's, or
  // another simulator's) make the halves differ by more than the noise floor between the
  // sideband groups predicts; the mean ratio phi then estimates how much more (quasi-likelihood
  // overdispersion). A channel whose phi exceeds 1 beyond its sampling error (one-sided
  // z_{1-alpha}) has its noise variance scaled by phi, and phi's relative error enters the
  // null's noise-estimate error. Stationary gear content, faults included, cancels in A_1 - A_2.
  dispersion_.assign(static_cast<std::size_t>(nc), 1.0);
  const double z = normal_quantile(opt_.alpha);  // upper quantile
  for (int c = 0; c < nc; ++c) {
    std::vector<double> r;
    classify(c, &r);
    if (r.size() < 16) continue;
    double mean = 0, var = 0;
    for (double x : r) mean += x / static_cast<double>(r.size());
    for (double x : r) var += (x - mean) * (x - mean) / static_cast<double>(r.size() - 1);
    const double se = std::sqrt(var / static_cast<double>(r.size()));
    if (mean <= 1 + z * se) continue;
    dispersion_[static_cast<std::size_t>(c)] = mean;
    for (int i = 0; i < ncell; ++i) {
      s2_[static_cast<std::size_t>(c * ncell + i)] *= mean;
      double& rse = spec_.noise_relative_se[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
      rse = std::hypot(rse, se / mean);
      spec_.noise_variance[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)] *= mean;
    }
    spec_.noise_floor[static_cast<std::size_t>(c)] *= mean;
    classify(c, nullptr);
  }
  for (double v : vns_) ns_cells_ += v > 0 ? 1 : 0;
  // The angle reference's Brownian bridge leaks into the cells next to strong lines
  // (order_analysis.hpp): part of s2_, scaled with it by the dispersion.
  bridge_.clear();
  if (!spec_.bridge_leak.empty()) {
    constexpr std::size_t kD = RecordingSpectra::kBridgeBins;
    bridge_.assign(m * kD, 0.0);
    for (int c = 0; c < nc; ++c)
      for (int i = 0; i < ncell; ++i)
        for (std::size_t d = 0; d < kD; ++d)
          bridge_[static_cast<std::size_t>(c * ncell + i) * kD + d] =
              spec_.bridge_leak[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)][d] *
              dispersion_[static_cast<std::size_t>(c)];
  }
  // The angle reference's linear drift (order_analysis.hpp): one N(0, D T) number per window
  // that moves every amplitude along amplitude_drift; a column with a N(0, 1) weight.
  drift_.assign(2, {});
  if (!spec_.amplitude_drift.empty() && spec_.angle_diffusion_T > 0) {
    const double sd = std::sqrt(spec_.angle_diffusion_T);
    for (int w = 0; w < 2; ++w) {
      auto& col = drift_[static_cast<std::size_t>(w)];
      col.assign(m, 0.0);
      for (int c = 0; c < nc; ++c)
        for (int i = 0; i < ncell; ++i)
          col[static_cast<std::size_t>(c * ncell + i)] =
              sd * spec_.amplitude_drift[static_cast<std::size_t>(w)][static_cast<std::size_t>(c)]
                                        [static_cast<std::size_t>(spec_.layout.cells[static_cast<std::size_t>(i)].bin)];
    }
  }
}

void ModelComparison::set_reference(const std::vector<std::vector<double>>& m, const std::vector<double>& gains_in) {
  const int nc = channels(), ncell = cells();
  std::vector<double> gains = gains_in;
  if (gains.empty()) gains.assign(static_cast<std::size_t>(nc), 1.0);
  rice_ref_.assign(static_cast<std::size_t>(features()), 0.0);
  for (int c = 0; c < nc; ++c)
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      const double g = is_housing(c) ? gains[static_cast<std::size_t>(c)] : 1.0;
      rice_ref_[f] = rice_variance(model_amplitude(m, c, i, g), s2_[f]);
    }
  set_discrepancy_reference(m, gains);
}

void ModelComparison::set_reference(const ModelSpectra& m, const std::vector<double>& gains) {
  // The window-start variance (halves of Q mesh cycles; order_analysis.hpp) of the reference model:
  // fixed with the Rician variances while candidates are compared.
  leak_.assign(static_cast<std::size_t>(features()), 0.0);
  if (!m.leak_variance.empty())
    for (int c = 0; c < channels(); ++c)
      for (int i = 0; i < cells(); ++i) {
        const std::size_t f = static_cast<std::size_t>(c * cells() + i);
        const double g = is_housing(c) && !gains.empty() ? gains[static_cast<std::size_t>(c)] : 1.0;
        leak_[f] = g * g *
                   m.leak_variance[static_cast<std::size_t>(c)][static_cast<std::size_t>(spec_.layout.cells[static_cast<std::size_t>(i)].bin)];
      }
  set_reference(m.amplitude, gains);
}

double unknown_phase_difference_variance(double gear_amplitude, double leak_power_sum, double leak_power_max) {
  // The cell holds |G + sum_l L_l e^{i phi_l}|. Over independent uniform phases an amplitude
  // varies by about half the power of all but its largest term (exact to first order for small
  // terms beside a large one), and the difference of two independent such amplitudes by twice
  // that: P - D. For two equal terms it is conservative: P - D = L^2 against 0.758 L^2 (the
  // difference of two 2 L |cos(phi/2)|; test UnknownPhaseVariance.*).
  const double g2 = gear_amplitude * gear_amplitude;
  return g2 + leak_power_sum - std::max(g2, leak_power_max);
}

double ModelComparison::alien_variance(int c, int i, double amplitude) const {
  // Lines at no gear order (RecordingSpectra::alien_lines) leak into the cell with a phase the
  // model cannot know, and the recording and the model (or the baseline) each have phases of
  // their own; G is the compared model amplitude.
  if (spec_.alien_leak.empty() || spec_.alien_leak[static_cast<std::size_t>(c)].empty()) return 0.0;
  const auto& l = spec_.alien_leak[static_cast<std::size_t>(c)][static_cast<std::size_t>(i)];
  return unknown_phase_difference_variance(amplitude, l[0], l[1]);
}

void ModelComparison::set_discrepancy_reference(const std::vector<std::vector<double>>& m,
                                                const std::vector<double>& gains_in) {
  const int nc = channels(), ncell = cells();
  std::vector<double> gains = gains_in;
  if (gains.empty()) gains.assign(static_cast<std::size_t>(nc), 1.0);
  disc_ref_model_ = m;
  disc_ref_gains_ = gains;
  for (int c = 0; c < nc; ++c)
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      const double g = is_housing(c) ? gains[static_cast<std::size_t>(c)] : 1.0;
      // Relative to the line, or, differential, to the line's change from the baseline's model:
      // a model-form error common to both recordings cancels, its effect on a change does not.
      disc_sd_[f] = disc_[f] * (opt_.baseline.empty() ? model_amplitude(m, c, i, g)
                                                      : transfer_[f] * std::fabs(raw_model_amplitude(m, c, i, g) - base_model_[f]));
      const double a = model_amplitude(m, c, i, g);
      const double v = rice_ref_[f] + disc_sd_[f] * disc_sd_[f] + disc_abs_[f] + offset_variance(f, a) +
                       (leak_.empty() ? 0.0 : leak_[f]) + alien_variance(c, i, a);
      for (int w = 0; w < 2; ++w) d_[static_cast<std::size_t>(w)][f] = v + vns_[f];
    }
}

ScopedDiscrepancyReference::ScopedDiscrepancyReference(ModelComparison& cmp,
                                                       const std::vector<std::vector<double>>& model_amplitude,
                                                       const std::vector<double>& gains)
    : cmp_(cmp), model_(cmp.discrepancy_reference_model()), gains_(cmp.discrepancy_reference_gains()) {
  cmp_.set_discrepancy_reference(model_amplitude, gains);
}

ScopedDiscrepancyReference::~ScopedDiscrepancyReference() {
  if (!model_.empty()) cmp_.set_discrepancy_reference(model_, gains_);
}

std::vector<std::vector<double>> ModelComparison::model_form_shifts(const std::vector<std::vector<double>>& m,
                                                                    const std::vector<double>& gains_in) const {
  const int nc = channels(), ncell = cells();
  std::vector<double> gains = gains_in;
  if (gains.empty()) gains.assign(static_cast<std::size_t>(nc), 1.0);
  std::vector<std::vector<double>> shifts;
  for (std::size_t k = 0; k < opt_.discrepancy.size(); ++k) {
    std::vector<double> e(static_cast<std::size_t>(features()), 0.0);
    bool any = false;
    for (int c = 0; c < nc; ++c)
      for (int i = 0; i < ncell; ++i) {
        const std::size_t f = static_cast<std::size_t>(c * ncell + i);
        if (disc_entry_[f] != static_cast<int>(k)) continue;
        const double g = is_housing(c) ? gains[static_cast<std::size_t>(c)] : 1.0;
        const double a = model_amplitude(m, c, i, g);
        // The budgeted amplitude error (signed, so that the cells of an entry move together),
        // as set_discrepancy_reference sizes it, and its effect on the expected amplitude.
        const double line = opt_.baseline.empty() ? a : transfer_[f] * (raw_model_amplitude(m, c, i, g) - base_model_[f]);
        e[f] = -rice_mean_slope(a, s2_[f]) * disc_[f] * line;
        any = any || e[f] != 0;
      }
    if (!any) continue;
    WindowScore w;
    chi2_of(e, window_index(Half::Fit), gains, fidelity_response(&m, gains), &w);
    shifts.push_back(std::move(w.residual));
  }
  return shifts;
}

double ModelComparison::offset_variance(std::size_t f, double amplitude) const {
  // The offset e enters the comparison inside the Rician mean, mu(max(0, g a + e)): its error
  // moves the expected amplitude by mu'(amplitude) times itself. Where the compared amplitude is
  // below the noise (mu' -> 0: most cells, whose baseline line is estimated at 0) the error
  // hardly moves it; taken whole there, V was half as large again as the residual's variance,
  // and a recording like its baseline scored chi2/m = 0.6-0.8 against a null of 1 (the
  // independent corpus's controls, session 23), costing the test its sensitivity.
  if (offset_var_[f] <= 0) return 0.0;
  const double k = rice_mean_slope(amplitude, s2_[f]);
  return k * k * offset_var_[f];
}

double ModelComparison::raw_model_amplitude(const std::vector<std::vector<double>>& m, int c, int i, double g) const {
  return g * m[static_cast<std::size_t>(c)][static_cast<std::size_t>(spec_.layout.cells[static_cast<std::size_t>(i)].bin)];
}

double ModelComparison::model_amplitude(const std::vector<std::vector<double>>& m, int c, int i, double g) const {
  const std::size_t f = static_cast<std::size_t>(c * cells() + i);
  const double a = raw_model_amplitude(m, c, i, g);
  return offset_[f] == 0 && transfer_[f] == 1 ? a : std::max(0.0, transfer_[f] * a + offset_[f]);
}

void ModelComparison::match_baseline() {
  const std::size_t m = static_cast<std::size_t>(features());
  offset_.assign(m, 0.0);
  offset_var_.assign(m, 0.0);
  transfer_.assign(m, 1.0);
  base_model_.assign(m, 0.0);
  base_discretization_.assign(m, 0.0);
  if (opt_.baseline.empty()) return;
  const int ncell = cells();
  for (int c = 0; c < channels(); ++c)
    for (int i = 0; i < ncell; ++i) {
      const double order = spec_.layout.cells[static_cast<std::size_t>(i)].order;
      const std::string& name = spec_.channel_names[static_cast<std::size_t>(c)];
      // Cells are at exact multiples of 1/R carrier orders: equal orders agree to round-off.
      const auto it = std::find_if(opt_.baseline.begin(), opt_.baseline.end(), [&](const BaselineCell& b) {
        return b.channel == name && std::fabs(b.order - order) <= 1e-9 * std::max(1.0, std::fabs(order));
      });
      if (it == opt_.baseline.end())
        throw InputError("--baseline", "the baseline has no cell at carrier order " + std::to_string(order) +
                                           " of channel '" + name + "': the recording and its baseline must be analysed "
                                           "in the same windows (the same channels, duration and speed, so that "
                                           "their halves hold the same whole carrier revolutions)");
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      offset_[f] = it->offset;
      offset_var_[f] = it->variance;
      transfer_[f] = it->transfer;
      base_model_[f] = it->model;
      base_discretization_[f] = it->transfer * it->discretization;
    }
}

bool ModelComparison::is_housing(int c) const { return housing_.at(static_cast<std::size_t>(c)); }

namespace {
/// solver.periodicity_tolerance of simulations whose only tooth-level feature is a torque ripple.
constexpr double kRippleSpeedTolerance = 1e-4;
} // namespace

std::shared_ptr<const ModelSpectra> ModelComparison::simulate(const model::SimulationConfig& config, bool keep,
                                                              std::atomic<long>* tally) const {
  model::SimulationConfig c = config;
  c.solver.record_mesh_cycles = base_.solver.record_mesh_cycles;
  // Damaged teeth and a sun runout keep the configured periodicity tolerance: the model settles
  // without them to it first (model::simulate), so a feature of size zero is the nuisance model
  // itself. Until session 64 the tolerance was relaxed to 1e-4 for them too, and that first phase
  // then stopped with a lightly damped rig mode still ringing (docs/diagnose.md section 2). A
  // torque ripple alone keeps session 63's warm-up from the static start and its tolerance: the
  // warm-up runs until the mean speed holds to 1e-4; every signal is analysed against its own
  // angle reference, so a mean speed off by 1e-4 moves no line off its bin.
  if (c.imperfections.torque_ripple_fraction != 0 && !model::settles_without_tooth_level_features(c))
    c.solver.periodicity_tolerance = std::max(c.solver.periodicity_tolerance, kRippleSpeedTolerance);
  const std::string key = builtin_config_key(c) + (keep ? "#keep" : "");
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<ModelSpectra> remote = opt_.remote ? opt_.remote(c, keep) : std::nullopt;
  auto s = std::make_shared<const ModelSpectra>(remote ? std::move(*remote) : evaluate(c, keep));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (tally) ++*tally;
  std::lock_guard<std::mutex> lock(mutex_);
  ++sims_;
  sim_seconds_ += secs;
  cache_[key] = s;
  return s;
}

ModelSpectra ModelComparison::evaluate(const model::SimulationConfig& c, bool keep) const {
  const auto run = [&](const model::SimulationConfig& cfg) {
    model::validate(cfg);
    return model_spectra(wear::simulate(cfg, {}, model_channels(rec_, spec_, cfg)), rec_, spec_, cfg, keep);
  };
  try {
    return run(c);
  } catch (const SolverError&) {
    // The band step is this class's choice, not the configuration's: where it fails (a response
    // that diverges at the coarser step, model::Integration::step; measured on the seed stage at
    // 100 rpm and 10 kW with tooth-level features, docs/diagnose.md §2) the simulation is run
    // again at the model's own step, the one `simulate` takes. Deterministic: the same
    // configuration fails or passes the same way on any rank or thread. A failure there is the
    // model's, and is rethrown.
    if (!band_step_ || c.solver.time_step_s != 0 || c.solver.accuracy_band_Hz != base_.solver.accuracy_band_Hz) throw;
    model::SimulationConfig own_step = c;
    own_step.solver.accuracy_band_Hz = 0;
    return run(own_step);
  }
}

long ModelComparison::simulations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sims_;
}

double ModelComparison::simulation_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sim_seconds_;
}

void ModelComparison::set_fidelity(std::vector<std::vector<double>> columns, std::vector<std::string> names,
                                   int discretization_column) {
  for (const auto& u : columns)
    require(u.size() == static_cast<std::size_t>(features()), "fidelity", "column of ", u.size(), " values for ",
            features(), " features");
  u_ = std::move(columns);
  u_names_ = std::move(names);
  u_discretization_ = discretization_column >= 0 && discretization_column < static_cast<int>(u_.size())
                          ? discretization_column
                          : -1;
}

std::vector<double> ModelComparison::residual_vector(const std::vector<std::vector<double>>& m, int w,
                                                     const std::vector<double>& gains) const {
  const int nc = channels(), ncell = cells();
  require(static_cast<int>(m.size()) == nc, "model", "has ", m.size(), " channels, the recording ", nc);
  std::vector<double> r(static_cast<std::size_t>(features()));
  for (int c = 0; c < nc; ++c) {
    const double g = gains[static_cast<std::size_t>(c)];
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      const double a = model_amplitude(m, c, i, g);
      r[f] = a_rec_[static_cast<std::size_t>(w)][f] - rice_mean(a, s2_[f]);
    }
  }
  return r;
}

std::vector<double> ModelComparison::fidelity_response(const std::vector<std::vector<double>>* model,
                                                       const std::vector<double>& gains) const {
  const std::size_t nf = static_cast<std::size_t>(features());
  const int ncell = cells();
  std::vector<double> k(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const int c = static_cast<int>(f / static_cast<std::size_t>(ncell)), i = static_cast<int>(f % static_cast<std::size_t>(ncell));
    const double g = gains[static_cast<std::size_t>(c)];
    // Differential: the compared amplitude is max(0, g a + offset). Where the baseline's offset
    // takes a model line to 0 (the model has a line the baseline recording lacks), a small
    // change of the line does not move it: the fidelity direction does not act there, and drawn
    // there the null would fold z u at 0 into a bias the linear fidelity fit cannot take out.
    // (Alone this did not lower the inflated bounds of session 23; fidelity_value's cancelling did.)
    const bool live = model == nullptr || offset_[f] == 0 || model_amplitude(*model, c, i, g) > 0;
    k[f] = live ? g * transfer_[f] : 0.0;
  }
  return k;
}

double ModelComparison::fidelity_value(std::size_t col, std::size_t f, const std::vector<double>& response) const {
  const double u = u_[col][f] * response[f];
  // Differential: the baseline's model was simulated with the same discretization, so its error
  // is in the baseline's offset with the opposite sign and cancels in the change; what remains
  // is the difference of the two models' errors. Measured without it (session 23): on speed
  // channels whose lines the independent rig's encoders remove, the model's raw lines (30 times
  // the recording's) carried discretization directions 25 times the noise, and the null, folding
  // them at 0, put its bound at 4.8 m for a statistic of 1.1 m.
  if (static_cast<int>(col) == u_discretization_ && !opt_.baseline.empty() && response[f] != 0)
    return u - base_discretization_[f];
  return u;
}

struct ModelComparison::Chi2Plan {
  std::size_t q = 0;                 // fidelity columns + the drift column
  std::vector<double> inv_d, sqrt_d;  // [feature]: 1 / D_i, sqrt(D_i) of the window
  std::vector<double> u;              // [feature * q + column]: chi2_of's uval
  Eigen::MatrixXd A;
  Eigen::VectorXd b, z;
  Eigen::LDLT<Eigen::MatrixXd, Eigen::Lower> ldlt;
};

ModelComparison::Chi2Plan ModelComparison::chi2_plan(int w, const std::vector<double>& response) const {
  // The per-feature constants of residuals scored on one window with one response (1 / D,
  // sqrt D, the fidelity columns): computed once for the many draws of a null.
  Chi2Plan p;
  const auto& drift = drift_[static_cast<std::size_t>(w)];
  const auto& D = d_[static_cast<std::size_t>(w)];
  const std::size_t m = D.size();
  p.q = u_.size() + (drift.empty() ? 0 : 1);
  p.inv_d.resize(m);
  p.sqrt_d.resize(m);
  p.u.resize(m * p.q);
  for (std::size_t f = 0; f < m; ++f) {
    p.inv_d[f] = 1.0 / D[f];
    p.sqrt_d[f] = std::sqrt(D[f]);
    for (std::size_t a = 0; a < p.q; ++a) p.u[f * p.q + a] = a < u_.size() ? fidelity_value(a, f, response) : drift[f];
  }
  const auto qi = static_cast<Eigen::Index>(p.q);
  p.A.resize(qi, qi);
  p.b.resize(qi);
  p.z.resize(qi);
  p.ldlt = Eigen::LDLT<Eigen::MatrixXd, Eigen::Lower>(qi);
  return p;
}

double ModelComparison::chi2_planned(Chi2Plan& p, const std::vector<double>& r, const std::vector<double>& gains,
                                     WindowScore* out) const {
  // z* = (I + U' D^-1 U)^-1 U' D^-1 r, with the fidelity columns' rows scaled by the channel
  // gains (they are model changes, and act only where the model's amplitude responds:
  // fidelity_response); the drift column is the recording's own, unscaled.
  const std::size_t m = r.size(), q = p.q;
  const int ncell = cells();
  p.A.setIdentity();
  p.b.setZero();
  for (std::size_t f = 0; f < m; ++f) {
    const double id = p.inv_d[f];
    const double* uf = &p.u[f * q];
    for (std::size_t a = 0; a < q; ++a) {
      const double ua = uf[a];
      p.b(static_cast<Eigen::Index>(a)) += ua * id * r[f];
      for (std::size_t bb = 0; bb <= a; ++bb) p.A(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(bb)) += ua * id * uf[bb];
    }
  }
  p.z.setZero();
  if (q > 0) p.z = p.ldlt.compute(p.A).solve(p.b);
  const Eigen::VectorXd& z = p.z;
  double chi2 = z.squaredNorm();
  if (out) {
    out->rho.assign(m, 0.0);
    out->chi2_per_channel.assign(static_cast<std::size_t>(channels()), 0.0);
    out->features_per_channel.assign(static_cast<std::size_t>(channels()), ncell);
    out->fidelity_z.assign(z.data(), z.data() + q);
  }
  for (std::size_t f = 0; f < m; ++f) {
    double e = r[f];
    const double* uf = &p.u[f * q];
    for (std::size_t a = 0; a < q; ++a) e -= uf[a] * z(static_cast<Eigen::Index>(a));
    const double rho = e / p.sqrt_d[f];
    chi2 += rho * rho;
    if (out) {
      out->rho[f] = rho;
      out->chi2_per_channel[f / static_cast<std::size_t>(ncell)] += rho * rho;
    }
  }
  if (out) {
    out->residual = out->rho;
    for (std::size_t a = 0; a < q; ++a) out->residual.push_back(z(static_cast<Eigen::Index>(a)));
    out->chi2 = chi2;
    out->features = static_cast<int>(m);
    out->gains = gains;
  }
  return chi2;
}

double ModelComparison::chi2_of(const std::vector<double>& r, int w, const std::vector<double>& gains,
                                const std::vector<double>& response, WindowScore* out) const {
  Chi2Plan plan = chi2_plan(w, response);
  return chi2_planned(plan, r, gains, out);
}

WindowScore ModelComparison::score(const std::vector<std::vector<double>>& m, Half half, std::vector<double> gains,
                                   HousingGains housing_gains) const {
  const int w = window_index(half);
  const bool profile_gain = housing_gains == HousingGains::Profile;
  const int nc = channels(), ncell = cells();
  if (gains.empty()) gains.assign(static_cast<std::size_t>(nc), 1.0);
  for (int c = 0; c < nc; ++c)
    if (!is_housing(c)) gains[static_cast<std::size_t>(c)] = 1.0;
  std::vector<double> gain_se(static_cast<std::size_t>(nc), 0.0);
  std::vector<bool> gain_edge(static_cast<std::size_t>(nc), false);
  if (profile_gain) {
    const auto& D = d_[static_cast<std::size_t>(w)];
    for (int c = 0; c < nc; ++c) {
      if (!is_housing(c)) continue;
      // Start: weighted least squares A_rec ~ g a; then a golden-section search on the full chi2.
      double num = 0, den = 0;
      double strongest = 0;  // the model's strongest line at unit gain over its cell's noise
      for (int i = 0; i < ncell; ++i) {
        const std::size_t f = static_cast<std::size_t>(c * ncell + i);
        const double a = transfer_[f] * m[static_cast<std::size_t>(c)][static_cast<std::size_t>(spec_.layout.cells[static_cast<std::size_t>(i)].bin)];
        num += (a_rec_[static_cast<std::size_t>(w)][f] - offset_[f]) * a / D[f];
        den += a * a / D[f];
        strongest = std::max(strongest, std::fabs(a) / std::sqrt(D[f]));
      }
      if (!(den > 0)) continue;
      double g0 = num / den;
      // A gain is positive. The start can come out <= 0 when a baseline's offsets exceed the
      // recording's amplitudes (a model far from both recordings; found with rig keys the
      // baseline was fitted under, session 23), and its logarithm then made every chi2 NaN.
      // The search then starts from the gain given (the configuration's, or the last fit's).
      if (!(g0 > 0) || !std::isfinite(g0)) g0 = gains[static_cast<std::size_t>(c)];
      if (!(g0 > 0) || !std::isfinite(g0)) continue;
      auto cost = [&](double lg) {
        std::vector<double> gg = gains;
        gg[static_cast<std::size_t>(c)] = std::exp(lg);
        return chi2_of(residual_vector(m, w, gg), w, gg, fidelity_response(&m, gg), nullptr);
      };
      // 30 reductions of a bracket of ln g0 +- 0.4: 0.618^30 ~ 5e-7 of its width. The
      // least-squares start is usually within it; where the search ends at an edge (a model whose
      // housing lines differ from the recording's in shape, so the weighted start is far off: a
      // differential fit's offsets), the bracket is centred again on that end and doubled, up to
      // kGainBracketDoublings times (+-0.4 * 2^8 = +-102 in ln g: any gain a double holds), so that
      // the profile is the minimum over the gain and "at the edge of its profile search" means the
      // chi2 still falls beyond any gain, not that the first bracket was short (session 48:
      // indepsim2 rigB5 rec_06, a planet tooth's fit ended at the edge with g = 0.0014).
      // A chi2 that falls towards g -> 0 without a minimum (the recording's housing lines below
      // what the model's shape can match) flattens out there, and the search ends wherever its
      // differences drop below rounding: such a gain is at its edge when every model line it
      // scales lies below its cell's noise (g < 1 / max_i (a_i / sqrt(D_i))), as it is above the
      // configuration's largest gain. The doubling also stops once a wider bracket lowers chi2 by
      // less than kGainChi2Resolution.
      BracketedMinimum best =
          expanding_golden_section_minimum(cost, std::log(g0), 0.4, 30, kGainBracketDoublings, kGainChi2Resolution);
      // The configuration's largest gain bounds the transfer through the mount at the mesh
      // frequency, so that the gain of a mount held far above the lines (a stiff mount: G grows
      // as f0^2) is not an edge while what the lines hear is in range.
      // Above that gain the search stops at it: a model whose housing lines are all but zero (an
      // in-phase stage on the ring's translation, its lines at round-off) otherwise fits the
      // recording's lines with a gain of 10^5..10^9 m/s^2 per N, which the configuration then
      // refuses as a unit mistake and the diagnosis ended in an error (session 72: indepsim4's
      // setC3 rec_10 on the ring's translation).
      // A millionth below the bound, not exp(log(bound)): the configuration's check recomputes it
      // at the simulated speed, and either can round a unit above the other.
      const double largest = model::largest_housing_gain_m_s2_per_N(base_) * (1.0 - kGainBoundMargin);
      const bool above = best.x > std::log(largest);
      if (above) {
        best.x = std::log(largest);
        best.at_edge = true;
      }
      if (strongest > 0 && best.x < -std::log(strongest)) best.at_edge = true;
      const double lg = best.x;
      gains[static_cast<std::size_t>(c)] = above ? largest : std::exp(lg);
      // Within the final bracket of an initial edge: the optimum may lie beyond it.
      gain_edge[static_cast<std::size_t>(c)] = best.at_edge;
      // Standard error from the curvature of chi2 in ln g (step 1e-3 in ln g).
      const double se_ln = chi2_curvature_std(cost, lg, 1e-3);
      gain_se[static_cast<std::size_t>(c)] = std::isfinite(se_ln) ? std::exp(lg) * se_ln : 0.0;
    }
  }
  WindowScore s;
  chi2_of(residual_vector(m, w, gains), w, gains, fidelity_response(&m, gains), &s);
  s.gain_std = gain_se;
  s.gain_at_edge = gain_edge;
  return s;
}

double ModelComparison::replicate_chi2(const std::vector<double>& gains_in) const {
  std::vector<double> gains = gains_in;
  if (gains.empty()) gains.assign(static_cast<std::size_t>(channels()), 1.0);
  std::vector<double> r(static_cast<std::size_t>(features()));
  for (std::size_t f = 0; f < r.size(); ++f) r[f] = a_rec_[1][f] - a_rec_[0][f];
  return chi2_of(r, 1, gains, fidelity_response(nullptr, gains), nullptr);
}

namespace {
/// The angle reference's Brownian bridge in the null's draws. Its Fourier coefficients c_d
/// (d = 1 .. kBridgeBins bins) are independent circular complex normals (their real parts come
/// from the odd terms of the bridge's Karhunen-Loeve series, their imaginary parts from the even
/// ones, and the odd terms' projections on different d are orthogonal), so each window's leak at
/// distance d is its expectation times g_d = |c_d|^2 / E|c_d|^2 ~ Exp(1), one number per draw
/// shared by every cell of every channel. A random stream of its own, so that the other numbers
/// of a draw stay those of a recording without the bridge; and a distribution of its own too:
/// std::normal_distribution keeps the second deviate of each pair it makes, so one object
/// shared by two engines hands one stream's numbers to the other.
class BridgeFactors {
public:
  static constexpr std::size_t kD = RecordingSpectra::kBridgeBins;
  /// seed: the null's own seed + window; leak: [feature x kD] expected leak (empty: no bridge).
  BridgeFactors(std::uint64_t seed, const std::vector<double>& leak) : rng_(seed + kStreamOffset), leak_(leak) {}
  /// The next draw's g_d - 1 (nothing without a bridge).
  void draw() {
    if (leak_.empty()) return;
    for (double& v : g_) {
      const double x = nd_(rng_), y = nd_(rng_);
      v = 0.5 * (x * x + y * y) - 1.0;
    }
  }
  /// Half the noise variance of feature f in this draw: its expectation half_s2 with the
  /// bridge's leak at this draw's g_d instead of at 1.
  double half_variance(std::size_t f, double half_s2) const {
    if (leak_.empty()) return half_s2;
    double extra = 0;
    for (std::size_t k = 0; k < kD; ++k) extra += g_[k] * leak_[f * kD + k];
    return std::max(0.0, half_s2 + 0.5 * extra);
  }

private:
  /// 2^64 / golden ratio, the usual odd constant that separates seeds: the stream never starts
  /// where the null's main stream (seed + window) does.
  static constexpr std::uint64_t kStreamOffset = 0x9e3779b97f4a7c15ULL;
  std::mt19937_64 rng_;
  std::normal_distribution<double> nd_{0.0, 1.0};
  const std::vector<double>& leak_;
  std::array<double, kD> g_{};
};

/// |x + i y| of a null draw's cell. sqrt(x^2 + y^2) is within about one ulp of std::hypot
/// (three roundings and a correctly rounded sqrt) at a third of glibc's cost: hypot was 15 % of
/// a control's diagnosis (perf, session 42). A quantile moves by ~1e-16 of itself, against a
/// Monte-Carlo error of ~1 % at 2000 draws. Below 1e150 the squares cannot overflow; beyond,
/// hypot's scaling decides.
inline double rice_magnitude(double x, double y) {
  constexpr double kSquareSafe = 1e150;
  if (std::fabs(x) < kSquareSafe && std::fabs(y) < kSquareSafe) return std::sqrt(x * x + y * y);
  return std::hypot(x, y);
}

/// The (1 - alpha) quantile of sorted draws, as every null of this file takes it.
double upper_quantile(std::vector<double>& chi, double alpha) {
  std::sort(chi.begin(), chi.end());
  const std::size_t idx =
      std::min(chi.size() - 1, static_cast<std::size_t>(std::ceil((1 - alpha) * static_cast<double>(chi.size()))));
  return chi[idx];
}
} // namespace

ModelComparison::NullDraws ModelComparison::null_draws(const std::vector<std::vector<double>>& m,
                                                       const std::vector<double>& gains_in, Half half,
                                                       int fitted_parameters, bool folded, bool linear) const {
  const int w = window_index(half);
  const int nc = channels(), ncell = cells();
  std::vector<double> gains = gains_in;
  if (gains.empty()) gains.assign(static_cast<std::size_t>(nc), 1.0);
  const std::size_t nf = static_cast<std::size_t>(features()), q = u_.size();
  const auto& drift = drift_[static_cast<std::size_t>(w)];
  std::vector<double> a(nf), mu(nf);
  const std::vector<double> response = fidelity_response(&m, gains);
  // The noise estimates are uncertain too: each draw scales the true noise of every group of
  // cells that shares one estimate by 1 + eps, eps ~ N(0, relative standard error^2).
  int groups = 1;
  for (const auto& g : spec_.noise_group)
    for (int v : g) groups = std::max(groups, v + 1);
  // What every draw shares, per feature f = (channel c, cell i): fixed before the draws (the
  // same values the draw loop computed per draw before, so the draws keep their numbers).
  struct Feature {
    double half_s2 = 0, noise_rse = 0, disc_sd = 0, abs_sd = 0, offset_sd = 0, leak_sd = 0, alien_sd = 0, drift = 0;
    std::size_t eps_index = 0;
    bool disc = false, abs = false, offset = false, leak = false, alien = false;
  };
  std::vector<Feature> ft(nf);
  std::vector<double> fid(nf * q);  // fidelity column k at feature f: fid[f q + k]
  for (int c = 0; c < nc; ++c)
    for (int i = 0; i < ncell; ++i) {
      const std::size_t f = static_cast<std::size_t>(c * ncell + i);
      a[f] = model_amplitude(m, c, i, gains[static_cast<std::size_t>(c)]);
      mu[f] = rice_mean(a[f], s2_[f]);
      Feature& e = ft[f];
      e.half_s2 = 0.5 * s2_[f];
      e.noise_rse = spec_.noise_relative_se[c][i];
      e.eps_index = static_cast<std::size_t>(c) * static_cast<std::size_t>(groups) +
                    static_cast<std::size_t>(spec_.noise_group[c][i]);
      e.disc = disc_[f] > 0;
      e.disc_sd = disc_sd_[f];
      e.abs = disc_abs_[f] > 0;
      if (e.abs) e.abs_sd = std::sqrt(disc_abs_[f]);
      e.offset = offset_var_[f] > 0;
      if (e.offset) e.offset_sd = std::sqrt(offset_variance(f, a[f]));
      e.leak = !leak_.empty() && leak_[f] > 0;
      if (e.leak) e.leak_sd = std::sqrt(leak_[f]);
      const double alien = alien_variance(c, i, a[f]);
      e.alien = alien > 0;
      if (e.alien) e.alien_sd = std::sqrt(alien);
      e.drift = drift.empty() ? 0.0 : drift[f];
      for (std::size_t k = 0; k < q; ++k) fid[f * q + k] = fidelity_value(k, f, response);
    }
  std::mt19937_64 rng(opt_.seed + static_cast<std::uint64_t>(w));
  std::normal_distribution<double> nd(0.0, 1.0);
  NullDraws out;
  const auto draws = static_cast<std::size_t>(opt_.null_draws);
  if (folded) out.folded.resize(draws);
  if (linear) out.linear.resize(draws);
  std::vector<double> r_fold(folded ? nf : 0), r_lin(linear ? nf : 0);
  std::vector<double> eps(static_cast<std::size_t>(nc * groups));
  std::vector<double> z(q);
  Chi2Plan plan = chi2_plan(w, response);
  BridgeFactors bridge(opt_.seed + static_cast<std::uint64_t>(w), bridge_);
  // Both fidelity forms (FidelityDraw) from one sequence of random numbers: each number is drawn
  // once, in the order a single form's draw takes it, and enters both, so each form's draws are
  // those a call for it alone makes.
  for (std::size_t d = 0; d < draws; ++d) {
    for (double& v : z) v = nd(rng);
    for (double& v : eps) v = nd(rng);
    const double zd = drift.empty() ? 0.0 : nd(rng);
    bridge.draw();
    for (std::size_t f = 0; f < nf; ++f) {
      const Feature& e = ft[f];
      const double* uf = &fid[f * q];
      // Accumulated term by term into the line as before the linear mode existed, so the folded
      // null keeps its numbers to the last bit.
      double af_fold = a[f], af_lin = a[f], fidelity = 0;
      if (folded)
        for (std::size_t k = 0; k < q; ++k) af_fold += z[k] * uf[k];
      if (linear)
        for (std::size_t k = 0; k < q; ++k) fidelity += z[k] * uf[k];
      // Calibrated discrepancy: a relative amplitude error per cell (drawn only when present,
      // so that uncalibrated draws keep their random sequence), of the size V allows for it:
      // relative to the reference model's amplitude. Drawn relative to the scored model's own
      // amplitude, a candidate that adds strong lines where the calibrated healthy model has
      // weak ones would widen its own null by (discrepancy x its lines)^2 that chi2, weighted
      // by V, never charges: measured, an independent recording's pin errors, fitted far from
      // the truth with 96x the noise bound left, passed their own bound of 850x the noise bound
      // (docs/diagnose-log.md, session 16).
      if (e.disc) {
        const double nd_disc = nd(rng);
        af_fold += e.disc_sd * nd_disc;
        af_lin += e.disc_sd * nd_disc;
      }
      af_fold = std::fabs(af_fold);
      af_lin = std::fabs(af_lin);
      const double scale = std::max(0.1, 1 + e.noise_rse * eps[e.eps_index]);
      const double s = std::sqrt(bridge.half_variance(f, e.half_s2) * scale);
      const double nx = nd(rng);
      const double y = s * nd(rng);
      const double drift_term = drift.empty() ? 0.0 : zd * e.drift;
      double extra[4];  // the additive terms below, in their order of drawing
      int n_extra = 0;
      // Calibrated absolute discrepancy: excess variance of the amplitude residual itself.
      if (e.abs) extra[n_extra++] = e.abs_sd * nd(rng);
      // The baseline offset's estimation error (differential diagnosis; drawn only when present).
      if (e.offset) extra[n_extra++] = e.offset_sd * nd(rng);
      // The model's window-start variance (halves of Q mesh cycles; drawn only when present).
      if (e.leak) extra[n_extra++] = e.leak_sd * nd(rng);
      // Lines at no gear order leaking with unknown phases (drawn only when present).
      if (e.alien) extra[n_extra++] = e.alien_sd * nd(rng);
      if (folded) {
        double rf = rice_magnitude(af_fold + s * nx, y) - mu[f] + drift_term;
        for (int k = 0; k < n_extra; ++k) rf += extra[k];
        r_fold[f] = rf;
      }
      if (linear) {
        double rl = rice_magnitude(af_lin + s * nx, y) - mu[f] + drift_term;
        rl += fidelity;
        for (int k = 0; k < n_extra; ++k) rl += extra[k];
        r_lin[f] = rl;
      }
    }
    if (folded) out.folded[d] = chi2_planned(plan, r_fold, gains, nullptr);
    if (linear) out.linear[d] = chi2_planned(plan, r_lin, gains, nullptr);
    // Parameters fitted on the other window (see the header): + 2 chi2(k), drawn after this
    // draw's other numbers so that k = 0 reproduces the plain null exactly.
    for (int k = 0; k < fitted_parameters; ++k) {
      const double v = nd(rng);
      if (folded) out.folded[d] += 2 * v * v;
      if (linear) out.linear[d] += 2 * v * v;
    }
  }
  return out;
}

double ModelComparison::null_quantile(const std::vector<std::vector<double>>& m, const std::vector<double>& gains,
                                      Half half, double alpha, int fitted_parameters, FidelityDraw draw) const {
  const bool folded = draw == FidelityDraw::Folded;
  NullDraws d = null_draws(m, gains, half, fitted_parameters, folded, !folded);
  return upper_quantile(folded ? d.folded : d.linear, alpha);
}

ModelComparison::NullPair ModelComparison::null_quantiles(const std::vector<std::vector<double>>& m,
                                                          const std::vector<double>& gains, Half half, double alpha,
                                                          int fitted_parameters) const {
  NullDraws d = null_draws(m, gains, half, fitted_parameters, true, true);
  return {upper_quantile(d.folded, alpha), upper_quantile(d.linear, alpha)};
}

ModelComparison::OwnNull ModelComparison::own_null(const std::vector<std::vector<double>>& m,
                                                   const std::vector<double>& gains, Half half, double alpha,
                                                   int fitted_parameters) const {
  const NullPair p = null_quantiles(m, gains, half, alpha, fitted_parameters);
  OwnNull n;
  n.folded = p.folded;
  n.bound = std::min(n.folded, p.linear);
  return n;
}

} // namespace pw::diagnose
