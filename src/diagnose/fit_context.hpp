// What the fits of one diagnosis share (the phases of diagnose.cpp, screening.cpp and
// phase_search.cpp): the comparison with the recording, the nuisance candidates with
// their fitted values, and the bounded least-squares fit of a candidate jointly with
// them (docs/diagnose.md §5). Internal to src/diagnose.
#pragma once

#include "core/error.hpp"
#include "core/format.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/diagnose.hpp"
#include "diagnose/fit.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <memory>
#include <mutex>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pw::diagnose {

/// Runs body(i) for i in [0, n) on up to `threads` OpenMP threads; the first
/// exception thrown by any iteration is rethrown after the loop.
template <class F>
void parallel_for(int n, int threads, F&& body) {
  if (n <= 0) return;
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
inline double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

ScoreSummary summarize(const WindowScore& w);

/// The housing-sensor gains are profiled per channel by ModelComparison::score, not part of
/// the least-squares vector; they are reported among the nuisance parameters by this name.
bool is_sensor_gain(const FittedParameter& p);

bool any_saturates(const std::vector<ParameterSpec>& specs);
/// Whether some parameter is a transfer one (ParameterSpec::transfer).
bool any_transfer(const std::vector<ParameterSpec>& specs);
/// The parameter vector of the likelihood-ratio test of 'absent' (CandidateResult::null_chi2_fit):
/// every own parameter at its 'absent' value except the transfer ones, which keep their `fitted`
/// values -- how the excitation would reach the sensors, had there been one, is not what is
/// tested.
std::vector<double> absent_with_transfer_as_fitted(const std::vector<ParameterSpec>& specs,
                                                   const std::vector<double>& fitted);

/// Everything the fits of one diagnosis share.
struct FitContext {
  ModelComparison& cmp;
  model::SimulationConfig base;                      ///< at the recording's speed
  std::vector<const Candidate*> nuisance;            ///< fitted in every model
  std::vector<double> nuisance_x;                    ///< their fitted values (after the nuisance fit)
  std::shared_ptr<const ModelSpectra> nuisance_sim;  ///< the nuisance-fitted model, with sensor inputs
  std::vector<double> nuisance_gains;                ///< per channel
  int threads = 1;
  double alpha = 0.01;                               ///< the diagnosis's (DiagnoseOptions::alpha)
  /// DiagnoseOptions::nuisance_level_spread_ln: sd of ln(value) per nuisance key over a
  /// calibration's healthy recordings; a finding's size range carries it (fit_model).
  std::map<std::string, double> level_spread_ln = {};

  /// The parameters of every nuisance candidate, in the order of nuisance_x.
  std::vector<ParameterSpec> nuisance_specs() const;
  /// base with the nuisance values nx and the candidate's values cx (cand may be null).
  model::SimulationConfig make(const Candidate* cand, const Variant& v, std::span<const double> cx,
                               std::span<const double> nx, std::vector<std::string>* overrides) const;
  /// Model amplitudes of a configuration (sensor-only candidates: the nuisance simulation with new
  /// housing channels). tally: counts the simulations this call ran (ModelComparison::simulate).
  std::vector<std::vector<double>> amplitudes(const model::SimulationConfig& c, bool sensor_only,
                                              std::atomic<long>* tally = nullptr) const;
  /// Fit-half chi2 of the model (cand, v, cx, nx), with the nuisance gains; +inf where the solver
  /// cannot simulate it (such a point is never chosen as a start or a best point).
  double fit_chi2(const Candidate* cand, const Variant& v, std::span<const double> cx, std::span<const double> nx,
                  bool sensor_only = false, std::atomic<long>* tally = nullptr) const;
  /// Its whitened fit-half residual; empty where the solver cannot simulate it.
  std::vector<double> fit_residual(const Candidate* cand, const Variant& v, std::span<const double> cx,
                                   std::span<const double> nx, bool sensor_only = false,
                                   std::atomic<long>* tally = nullptr) const;
};

/// The values of an effect's size that the noise and the model-form budget allow at level
/// 1 - alpha (z = z_{1-alpha/2}). The budget is a relative error of the model's change: the rig's
/// change is (1 + delta) times the model's, so a size s = value - absent fitted to it stands for a
/// true size s / (1 + delta). delta's standard deviation relative to s is model_form_std / |s|
/// (the linearized propagation of FittedParameter::model_form_std), so the true size lies in
/// s / (1 + z r) ... s / (1 - z r), r = model_form_std / |s|, unbounded (the box's edge) when
/// z r >= 1; each end is widened by z std_error and kept in [box_lower, box_upper]. Without a
/// model-form term (model_form_std 0 or NaN) it is value +- z std_error.
struct SizeRange {
  double lower = std::numeric_limits<double>::quiet_NaN();
  double upper = std::numeric_limits<double>::quiet_NaN();
};
SizeRange model_form_range(double value, double absent, double std_error, double model_form_std, double z,
                           double box_lower, double box_upper);

/// A fitted model's parameter values split back into the candidate's own and the nuisance
/// vector (gains excluded: they are profiled). A nuisance vector of the wrong length (the model
/// was fitted with the nuisance parameters fixed) is replaced by `fixed_nuisance`.
struct SplitParameters {
  std::vector<double> own, nuisance;
};
SplitParameters split_parameters(const CandidateResult& r, const std::vector<double>& fixed_nuisance);

/// The nuisance vector with some nuisance candidates held (docs/diagnose.md §5, step 12b):
/// `specs[c]` the parameters of nuisance candidate c in the order of the vectors, `hold[c]` whether
/// it is held. Of `fitted` (ctx.nuisance_x) and `start` (a fit's nuisance values) the free
/// candidates' entries are kept, in order; each held parameter is listed as "key=value" at its
/// spec's initial value (ctx.base's, where ctx.make leaves a key that no fitted candidate sets).
struct HeldNuisance {
  std::vector<std::size_t> free;      ///< indices of the candidates still fitted
  std::vector<double> fitted, start;  ///< their entries of `fitted` and `start`
  std::vector<std::string> held;      ///< "key=value" of every held parameter
};
HeldNuisance hold_nuisance(const std::vector<std::vector<ParameterSpec>>& specs, const std::vector<bool>& hold,
                           std::span<const double> fitted, std::span<const double> start);

/// Fits `cand` (null: the nuisance parameters alone) with variant v by bounded LM on the fit
/// half. joint: the nuisance parameters are fitted too (else fixed at ctx.nuisance_x). Starts
/// at x_start if given (own values, then the nuisance ones). Throws SolverError if the model
/// cannot be simulated at the start.
CandidateResult fit_model(FitContext& ctx, const Candidate* cand, const Variant& v, bool joint, int lm_threads,
                          int max_iterations, const std::vector<double>* x_start = nullptr);

/// fit_model, or nothing where the solver fails on the way (the caller keeps what it has: a
/// second start or a further refinement is an attempt, not a requirement).
std::optional<CandidateResult> try_fit_model(FitContext& ctx, const Candidate* cand, const Variant& v, bool joint,
                                             int lm_threads, int max_iterations, const std::vector<double>& x_start);

/// The model-fidelity directions at configuration c (a second discretization and the speed
/// +- its standard error) set on ctx.cmp; *centre gets the simulation at c itself.
void set_fidelity(FitContext& ctx, const model::SimulationConfig& c, std::shared_ptr<const ModelSpectra>* centre);

/// `centre` with the variance its line-counting encoders' unknown phase leaves in each bin added
/// to its leak variance (ModelSpectra::leak_variance, which V carries; model/sensor.hpp
/// LineEncoder): `phases` are the same model with the encoders' lines turned by equally spaced
/// fractions of a pitch (centre among them), and each bin gets twice the amplitude's variance
/// over them. Twice, because the recording's images have a phase of their own, independent of the
/// model's (under a baseline: of the baseline's, while the model's own cancels there), and the
/// difference of two amplitudes at independent phases has twice the variance of one. Four phases
/// give the variance over a uniform phase to a relative error of order (|I| / |G|)^2 for an image
/// I beside content G (set_fidelity uses four).
std::shared_ptr<const ModelSpectra> with_encoder_phase_variance(const ModelSpectra& centre,
                                                                std::span<const ModelSpectra* const> phases);

} // namespace pw::diagnose
