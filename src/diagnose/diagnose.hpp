// planetwear diagnose, the numerics (docs/diagnose.md): where does a
// recording differ from the model, which physics is missing, with which
// parameters, and does the fix hold on data it was not fitted to?
//
//   1. compare the nominal model with the recording (compare.hpp): the fit
//      window (first carrier revolution) and the held-out window (last one);
//   2. fit the nuisance parameters (mesh stiffness level, damping ratio; the
//      housing-sensor gain is profiled in closed form) on the fit window;
//   3. noise test: if the nuisance-fitted model's chi-square is within the
//      noise bound on both windows -> "no missing physics found";
//   4. otherwise locate the residual (locate.hpp), shortlist the candidates
//      whose families carry it, screen their discrete variants, fit each
//      (with the nuisance parameters) by bounded LM (fit.hpp), evaluate the
//      fit on the held-out window;
//   5. rank: a candidate counts if its improvement over the nuisance-only
//      model is significant on the fit window AND on the held-out window
//      (likelihood-ratio test at level alpha); among those the lowest BIC wins.
//
// Decision rule (stated in every report): with m real residuals and the
// Hann-bin correlation factor c = 1.944 (compare.hpp), chi2 / c ~ chi2(m / c)
// when the model is right; the noise bound is
//   B = c chi2_{1-alpha}(m / c) + z_{1-alpha} sqrt(sum_c (m_c eps_c)^2)
// with eps_c the relative uncertainty of channel c's noise estimate. Nothing in
// it is tuned to any corpus: alpha = 0.01 is the only setting.
#pragma once

#include "diagnose/compare.hpp"
#include "diagnose/fit.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/locate.hpp"
#include "diagnose/recording.hpp"
#include "model/stage.hpp"

#include <functional>
#include <string>
#include <vector>

namespace pw::diagnose {

struct DiagnoseOptions {
  CompareOptions compare{};
  LocateOptions locate{};
  double alpha = 0.01;          ///< false-alarm probability of every test
  int max_iterations = 6;       ///< LM Jacobians per fit
  int max_candidates = 4;       ///< non-nuisance candidates fitted (sensor-only ones come free)
  bool joint_nuisance = true;   ///< refit the nuisance parameters together with each candidate
  bool always_fit_candidates = false;  ///< fit candidates even when the noise test passes
  std::vector<std::string> only_candidates;  ///< restrict the library (tests, expert use); empty = all
  int threads = 0;              ///< OpenMP threads (0: default)
  /// Progress messages (phase, detail); may be empty.
  std::function<void(const std::string&)> progress;
};

struct FittedParameter {
  std::string name, unit;
  double value = 0, std_error = 0, lower = 0, upper = 0, initial = 0;
  bool at_bound = false;
  bool nuisance = false;
};

/// Chi-square of one model on one window, per channel.
struct WindowScore {
  double chi2 = 0;
  int dof = 0;
  std::vector<double> chi2_per_channel;
  std::vector<int> dof_per_channel;
};

struct CandidateResult {
  std::string name, physics, variant;
  std::vector<std::string> families;
  double evidence_z = 0;                 ///< located evidence for its families
  std::vector<FittedParameter> parameters;  ///< its own, then the nuisance ones
  std::vector<std::string> overrides;    ///< `--set` assignments reproducing the fitted model
  int own_parameters = 0;
  WindowScore fit, held_out;
  double delta_chi2_fit = 0, delta_chi2_held_out = 0;  ///< improvement over the nuisance-only model
  double lr_threshold = 0;               ///< c chi2_{1-alpha}(own_parameters)
  double aic = 0, bic = 0;               ///< on the fit window, effective chi-square units
  bool significant = false, holds = false;
  int simulations = 0;
  std::string lm_message;
  std::string reason;                    ///< why it won or lost
  model::SimulationConfig config;
  double sensor_gain = 0;
};

enum class Verdict { NoMissingPhysics, MissingPhysicsFound, Unexplained };
const char* to_string(Verdict v);

/// Spectra and synchronous averages before/after, for plots (io/diagnosis_report.hpp).
struct PlotSeries {
  std::string name;           ///< channel or "tsa/<component>/<channel>"
  std::string x_unit, y_unit;
  std::vector<double> x, recording, before, after;
};

struct Timing {
  double total_s = 0, simulate_s = 0, compare_s = 0, locate_s = 0, fit_overhead_s = 0;
  long simulations = 0;
  int threads = 1;
};

struct Diagnosis {
  Verdict verdict = Verdict::NoMissingPhysics;
  std::string summary;                   ///< the finding in one sentence
  std::string rule;                      ///< the decision rule, with its numbers
  Kinematics kinematics;
  std::vector<std::string> channels;
  std::vector<NoiseEstimate> noise;
  AnalysisWindow fit_window, held_out_window;
  double bound_fit = 0, bound_held_out = 0;
  WindowScore nominal_fit, nominal_held_out;
  CandidateResult nuisance;              ///< nuisance-only model
  bool located = false;
  Location location;
  std::vector<CandidateResult> candidates;  ///< ranked, best first
  int winner = -1;                       ///< index into candidates, -1 if none
  std::vector<std::string> final_overrides;
  std::vector<PlotSeries> plots;
  /// RMS of the residual synchronous average per component (TSA domain), before (nominal) and after.
  std::vector<std::string> tsa_names;
  std::vector<double> tsa_rms_before, tsa_rms_after;
  Timing timing;
};

/// Diagnoses `recording` against the stage `config` at the recording's
/// operating point. Throws pw::InputError for unusable recordings.
Diagnosis diagnose(const Recording& recording, const model::SimulationConfig& config,
                   const DiagnoseOptions& options = {});

} // namespace pw::diagnose
