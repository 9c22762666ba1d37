// planetwear diagnose, the numerics (docs/diagnose.md): where does a
// recording differ from the model, which physics is missing, with which
// parameters, and does the fix hold on data it was not fitted to?
//
//   1. analyse the recording in the order domain (order_analysis.hpp): its
//      speed, its carrier angle, a fit half and a held-out half of R whole
//      carrier revolutions each (of Q whole mesh cycles when fewer than two
//      revolutions are recorded: only the families resolved in Q are compared,
//      the candidates of the others are listed as unresolved, not fitted),
//      feature cells at the labelled lines, noise;
//   2. simulate the model at the recording's speed, and the same model at a
//      second discretization and at the speed +- its standard error: the
//      model-fidelity directions (compare.hpp);
//   3. fit the nuisance parameters (mesh stiffness level from a coarse
//      geometric scan, then LM with the damping ratio; the housing-sensor gain
//      is profiled by a one-dimensional search) on the fit half;
//   4. noise test: if the nuisance-fitted model's chi2 on the held-out half is
//      below the 1 - alpha/2 quantile of its Monte-Carlo null distribution ->
//      "no missing physics found" (an excess on the fit half alone did not
//      replicate and is only reported);
//   5. otherwise locate the residual (locate.hpp), screen every candidate
//      and its discrete variants by one joint Gauss-Newton step (with the
//      nuisance parameters' secants), fit the best few jointly with the
//      nuisance parameters by bounded LM (fit.hpp) on the fit half, score
//      them on the held-out half;
//   6. rank: a candidate counts if its chi2 improvement over the
//      nuisance-only model exceeds chi2_{1-alpha}(k) (k = its parameters) on
//      the fit half AND on the held-out half; among those the lowest BIC
//      summed over both halves wins; its phase variants (which tooth, which
//      planet) are tried last.
//   7. verdict (verdict.hpp): the winner is named only if its own fitted model
//      explains the held-out half within its budget and nothing it rests on
//      sits at a bound; otherwise "unexplained residual" with it as a lead.
//
// docs/diagnose.md §5 numbers the same steps 1-12 (5 above is its 5-9, 6 its
// 10-12); the comments of the code use those numbers. Where the steps live:
// diagnose.cpp (DiagnosisRun::run() calls them in this order), fit_context.hpp (what the fits share, the bounded fit), screening.hpp
// (step 5's screening and starts), phase_search.hpp (the winner's place and a
// saturating parameter's lower limit), verdict.hpp, diagnosis_plots.hpp.
#pragma once

#include "config/stage.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/fit.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/line_coverage.hpp"
#include "diagnose/locate.hpp"
#include "diagnose/recording.hpp"

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace pw::diagnose {

struct DiagnoseOptions {
  CompareOptions compare{};
  LocateOptions locate{};
  double alpha = 0.01;          ///< false-alarm probability of every test
  int max_iterations = 4;       ///< LM Jacobians per fit (the screening step is a good start)
  int max_candidates = 4;       ///< candidates fitted after the screening (sensor-only ones come free)
  bool always_fit_candidates = false;  ///< fit candidates even when the noise test passes
  std::vector<std::string> only_candidates;  ///< restrict the library (tests, expert use); empty = all
  /// Differential diagnosis: the baseline's fitted housing-sensor gain per channel name [m/s^2 per
  /// N] (BaselineReference::gains). A recording whose model needs another gain, and fits with it,
  /// has a changed sensor path (DiagnosisRun::check_changes_since_baseline). Empty: no baseline.
  std::map<std::string, double> baseline_gains;
  /// Differential diagnosis: the baseline's nuisance values that ended at an edge of their box, by
  /// configuration key (+1 the upper edge, -1 the lower; BaselineReference::limits). A level
  /// changed since the baseline is then a ratio to a limit, not to a fit: one-sided.
  std::map<std::string, int> baseline_limits;
  /// Differential diagnosis: whether the baseline is at the recording's operating point (speed
  /// within the mesh damping ratio, power within kRecalibration; diagnose_command.cpp
  /// same_operating_point). A level's change since a baseline at another operating point holds
  /// the level's dependence on the operating point, which no recording here measures: the levels
  /// are then not tested as changes (docs/diagnose.md section 6b item 7).
  bool baseline_at_operating_point = true;
  /// Candidates fitted with the nuisance parameters instead of screened as findings (calibration
  /// fits the rig elements the documentation is silent on, e.g. "encoder_bandwidth").
  std::vector<std::string> extra_nuisance;
  /// Stop after the nuisance fit and its noise test (calibration): no location, no candidates;
  /// Diagnosis::calibration_cells holds the per-cell data the discrepancy is estimated from.
  bool nuisance_only = false;
  /// With nuisance_only: also probe the lateral-torsional ring body as the housing path
  /// (Diagnosis::ring_body_probe_chi2; `calibrate --ring-body`, docs/diagnose.md §6a item 12).
  bool probe_ring_body = false;
  /// The model at which the calibrated discrepancy's relative term of V is taken during the
  /// nuisance fit, with its housing gains per analysed channel: an earlier fit of the same
  /// recording (fit_healthy, calibration.hpp). Unset: the nominal model, as always.
  struct DiscrepancyReference {
    model::SimulationConfig config;
    std::vector<double> gains;
  };
  std::optional<DiscrepancyReference> discrepancy_reference;
  /// Nuisance values of an earlier fit of the same recording with fewer parameters, by key (a
  /// calibration's fit without its calibration-only rig elements): a further start of the nuisance
  /// fit, the parameters it does not name at their 'absent' values (nuisance_start.hpp). Empty: none.
  std::map<std::string, double> nuisance_start_values;
  /// A calibration's spread of each nuisance value over its healthy recordings, by key: the
  /// standard deviation of ln(value) [-] (nuisance_level_spread_ln, calibration.hpp). A finding's
  /// size range carries what that spread of the levels it is fitted jointly with moves it by
  /// (FittedParameter::level_spread_std). Empty: no calibration, or one recording.
  std::map<std::string, double> nuisance_level_spread_ln;
  /// The number of healthy recordings that spread is taken over (its degrees of freedom + 1); a
  /// level changed since the baseline is judged against it (level_move_test, level_change.hpp).
  int nuisance_level_spread_recordings = 0;
  /// Where a calibration's (or a baseline's) healthy lines tested the model, per kind of channel
  /// (line_coverage.hpp): the report says which part of a located excess lies outside. Empty:
  /// nothing tested, nothing said.
  std::vector<LineCoverage> line_coverage;
  int threads = 0;              ///< OpenMP threads (0: default)
  /// Simulation slots served elsewhere (compare.remote, e.g. other MPI ranks): that many more
  /// simulations run side by side, their threads mostly waiting.
  int remote_slots = 0;
  /// Progress messages; may be empty.
  std::function<void(const std::string&)> progress;
};

struct FittedParameter {
  std::string name, unit;
  double value = 0, std_error = 0, lower = 0, upper = 0, initial = 0;
  /// [unit] Standard deviation of the value from the model-form error the comparison budgets (a
  /// calibration's or a baseline's discrepancy, ModelComparison::model_form_shifts): how far the
  /// value moves if the model gets the lines it was fitted to wrong by one budgeted relative
  /// error. 0 without a budget (std_error is then all the value's uncertainty); NaN where the
  /// parameter has no standard error.
  double model_form_std = 0;
  /// [unit] The part of model_form_std that the calibration's spread of the nuisance levels
  /// fitted jointly with the finding carries into it (DiagnoseOptions::nuisance_level_spread_ln,
  /// level_spread_std in fit.hpp); 0 without a calibration of two or more recordings.
  double level_spread_std = 0;
  /// The nuisance keys whose spread it carries, comma-separated.
  std::string level_spread_of;
  /// [unit] A finding's own parameter under a budget: the values the noise and the model-form
  /// budget allow at 1 - alpha (model_form_range in fit_context.hpp; lopsided, since a relative
  /// error of the model's change scales the size). NaN without a budget.
  double model_form_lower = std::numeric_limits<double>::quiet_NaN();
  double model_form_upper = std::numeric_limits<double>::quiet_NaN();
  bool at_bound = false;
  bool nuisance = false;
  /// A housing-sensor gain, profiled in closed form on every model rather than fitted
  /// (nuisance too; "sensor.gain_m_s2_per_N[channel]" with several housing channels).
  bool sensor_gain = false;
  bool moved = false;           ///< nuisance: differs from its start by > z_{1-alpha/2} standard errors and > 5 %
  bool saturates = false;       ///< ParameterSpec::saturates: only a lower limit is identifiable
  /// ParameterSpec::transfer: how the candidate reaches the sensors (a rig property), not the finding.
  bool transfer = false;
  /// ParameterSpec::size_conditional_on: the configured rig element the value is the size for.
  std::string size_conditional_on;
  /// Saturating parameter of the winner: the smallest value whose fit-half chi2 is within
  /// chi2_{1-alpha}(1) of the fit (profile along the line from 'absent' to the fit); NaN if not computed.
  double lower_limit = std::numeric_limits<double>::quiet_NaN();
  /// The end of the box nearer the value (upper on a tie): which bound an at_bound parameter is at.
  double nearer_bound() const { return std::fabs(value - upper) <= std::fabs(value - lower) ? upper : lower; }
};

/// Chi-square of one model on one half.
struct ScoreSummary {
  double chi2 = 0;
  int features = 0;
  std::vector<double> chi2_per_channel;
  std::vector<int> features_per_channel;
  std::vector<double> fidelity_z;
};

struct CandidateResult {
  std::string name, physics, variant;
  std::vector<std::string> families;
  double evidence_z = 0;                 ///< located evidence for its families
  double predicted_improvement = 0;      ///< screening: linearized chi2 improvement S
  /// Fraction of the screening's step its fit started at: 1, or less where that step fitted
  /// worse than the candidate's absence and was backtracked (Screening::backtrack_starts).
  double start_step_fraction = 1;
  std::vector<FittedParameter> parameters;  ///< its own, then the nuisance ones
  std::vector<std::string> overrides;    ///< `--set` assignments reproducing the fitted model
  int own_parameters = 0;
  ScoreSummary fit, held_out;
  double delta_chi2_fit = 0, delta_chi2_held_out = 0;  ///< improvement over the nuisance-only model
  double lr_threshold = 0;               ///< chi2_{1-alpha}(own_parameters)
  double aic = 0, bic = 0;               ///< fit half
  double bic_held_out = 0;               ///< held-out half, same penalty
  bool significant = false, holds = false;
  /// Some own parameter differs from its null value (no such physics) by more than
  /// z_{1-alpha/(2k)} standard errors (Wald, Bonferroni over the k own parameters): a
  /// chi2 gain with a parameter indistinguishable from "absent" is the nuisance fit
  /// converging further, not evidence for this physics.
  bool non_null = false;
  /// Fit-half chi2 with the candidate's own parameters at their 'absent' values (transfer ones as
  /// fitted) and the nuisance parameters as fitted: the likelihood-ratio test of 'absent' (NaN
  /// where it was not simulated: then the Wald test decides). Why not the standard errors: the
  /// Wald test is not invariant to how the parameters are written, and fails where the likelihood
  /// ratio is 10^4-10^5 -- a ripple fraction on a ridge with the motor's inertia (indepsim4 setC3
  /// rec_15: 0.062 +- 0.15, chi2 lowered by 2.9e5 on both halves), a carrier runout's Cartesian pair
  /// whose phase the amplitudes barely fix (setD4 rec_10: y = 7e-8 +- 3.5e-5 m, chi2 lowered by
  /// 2.1e4); a saturating parameter has no meaningful standard error at all
  /// (docs/diagnose-log.md, session 68).
  double null_chi2_fit = std::numeric_limits<double>::quiet_NaN();
  bool counts() const { return significant && holds && non_null; }
  /// Simulations its own fit ran (cache hits not counted; a configuration another fit had
  /// already simulated is free). The run's total is timing.simulations.
  int simulations = 0;
  double seconds = 0;                    ///< wall time of its fit
  std::string lm_message;
  std::string failed;                    ///< non-empty: why it could not be fitted
  std::string reason;                    ///< why it won or lost
  /// The lead refitted with its nuisance levels at a box edge held (docs/diagnose.md §5, step
  /// 12b): what was held and how the refit did; empty when there was no such refit.
  std::string hold_refit;
  model::SimulationConfig config;
  Variant chosen;                        ///< the variant fitted
  std::vector<double> gains;             ///< per channel (housing gain factors on the model's 1 N -> m/s^2)
};

enum class Verdict { NoMissingPhysics, MissingPhysicsFound, Unexplained };
const char* to_string(Verdict v);

/// A plot's data: x and named columns (io/diagnosis_report.hpp writes them as CSV).
struct PlotSeries {
  std::string name;           ///< "spectrum/<channel>", "residual/<channel>", "tsa/<component>/<channel>"
  std::string kind;           ///< "spectrum", "residual", "tsa"
  std::string x_label, y_label;
  std::vector<double> x;
  std::vector<std::pair<std::string, std::vector<double>>> columns;
};

/// Screening of one candidate (its best variant): the score statistic S.
struct ScreenResult {
  std::string name, variant;
  double predicted_improvement = 0;  ///< S = r'J(J'J)^-1 J'r at the nuisance-fitted model
  bool failed = false;               ///< its screening simulation failed
  bool fitted = false;               ///< shortlisted
  /// S is the screening's at the transfer parameters' screening values (Screen::
  /// screened_at_transfer_values), not at their 'absent'.
  bool at_transfer_values = false;
};

/// The best candidate and why it is, or is not, named (verdict.hpp).
struct LeadAssessment {
  int candidate = -1;                 ///< index into Diagnosis::candidates; -1: no lead
  /// Its held-out chi2 with the fidelity directions recomputed at its own fitted model (the
  /// discretization and speed changes of the lines it adds; verdict.hpp).
  double held_out_chi2 = std::numeric_limits<double>::quiet_NaN();
  /// B_lead: 1 - alpha/2 quantile of that chi2 under "its fitted model is the truth".
  double bound_held_out = std::numeric_limits<double>::quiet_NaN();
  /// The folded own null (VerdictInputs::lead_bound_folded); >= bound_held_out.
  double bound_folded = std::numeric_limits<double>::quiet_NaN();
  /// Share of the held-out excess over the noise bound it removes:
  /// (chi2_nuisance,h - chi2_lead,h) / (chi2_nuisance,h - bound_held_out); NaN without an excess.
  double explained_fraction = std::numeric_limits<double>::quiet_NaN();
  bool counts = false;                ///< CandidateResult::counts()
  /// chi2 of the recording's fit half as the prediction of its held-out half (model-free budget).
  double replicate_chi2 = std::numeric_limits<double>::quiet_NaN();
  bool within_bound = false;          ///< condition (a): chi2_lead,h <= max(B_lead, replicate_chi2)
  std::vector<std::string> at_bound;  ///< condition (b) failures: "stiffness.scale at its bound 2"
  /// Housing gains at the low end of their profile search (condition (b)'s exception): channels
  /// that hear none of the lead's model lines above the noise, so the finding rests on the others.
  std::vector<std::string> silent_channels;
  /// Condition (d): BIC posterior probability of the lead among the counting candidates of other
  /// names (1 without rivals), and the strongest rival's name (empty: none).
  double posterior = 1.0;
  std::string rival;
  std::string failed;                 ///< which condition failed, with numbers (empty: named)
  /// Class finding (verdict.hpp): the lead's FindingClass name when its only failed conditions
  /// are (d) and (e) against members of its own class, which is then named; empty otherwise.
  std::string named_class;
  std::vector<std::string> class_members;  ///< the lead, then the members that blocked its own name
  /// Every physics the named class stands for (FindingClass::covers), its members among them.
  std::vector<std::string> class_covers;
  /// BIC posterior probability of the lead's class among the lead and its rivals of condition (d).
  double class_posterior = 1.0;
  /// The class's size: the lead's fitted parameters mapped onto the class's canonical member
  /// (FindingClass::canonical, Candidate::start_from), "name" and value in its unit.
  std::vector<std::pair<std::string, double>> class_size;
  std::string class_size_unit;
  /// Per class_size entry, the values the lead's model-form budget allows at 1 - alpha
  /// (model_form_range, fit_context.hpp) [class_size_unit]; empty without a budget. The mapping
  /// onto the canonical member is linear and homogeneous (a carrier runout's tangential part at
  /// each planet), so a relative error delta of the lead's whole change is the same delta of the
  /// mapped size: r = |model_form_std| / |change| over the lead's own parameters (all in one unit),
  /// the range s / (1 + z r) ... s / (1 - z r). The noise's standard error is not mapped (the
  /// model form's is 8 to 18 000 times it in the eight class sizes of docs/diagnose-log.md session 60).
  std::vector<std::pair<double, double>> class_size_range;
};

/// A channel's share of the held-out chi2 excess of the nuisance-fitted model.
struct ChannelExcess {
  std::string channel;
  double excess = 0;  ///< chi2 - features on that channel (the null's mean), >= 0
  double share = 0;   ///< of the summed excess
};

/// One feature cell after the nuisance fit, for the discrepancy estimate (calibration.hpp).
struct CalibrationCell {
  std::string channel;
  double order = 0;                 ///< carrier order of the cell
  double frequency_Hz = 0;          ///< the cell's frequency at the recording's speed [Hz]
  Quantity quantity = Quantity::SunSpeed;
  std::vector<Component> families;  ///< of the lines the cell carries
  double model = 0;                 ///< nuisance-fitted model amplitude, gain applied
  double recording[2] = {0, 0};     ///< the recording's amplitude in the fit and held-out halves
  double variance[2] = {0, 0};      ///< D_i per half: Rician noise variance + non-stationarity
  double noise_variance = 0;        ///< s_i^2, noise in the bin
  /// The model's discretization direction at this cell (the amplitude's change with a finer
  /// time step, gain applied; ModelComparison::discretization_column), 0 if none was set.
  double discretization = 0;
};

/// One single-parameter explanation of a change since the baseline (differential, after a "no
/// missing physics": docs/diagnose.md section 6b item 7), tested on the baseline's own terms.
struct BaselineChange {
  std::string name;        ///< sensor_transfer_path, stiffness_level, damping_level
  std::string parameter;   ///< housing_gain_ratio[<channel>] or the level's configuration key
  double ratio = 1;        ///< [-] fitted value / the baseline's (rho)
  double ratio_std_error = 0;  ///< [-] standard error of rho (curvature of the fit half's chi2)
  /// [-] A level's healthy scatter of ln rho, sqrt(2) s (s the calibration's spread of that level
  /// over its recordings, level_move_test in level_change.hpp); 0 for a sensor's gain, without a
  /// calibration or with one of a single recording.
  double ln_ratio_healthy_scatter = 0;
  /// [-] |ln rho| beyond which a level is a change: the noise and healthy scatter's quantile
  /// (level_move_test); NaN for a sensor's gain.
  double ln_ratio_threshold = std::numeric_limits<double>::quiet_NaN();
  double chi2_fit_unchanged = 0, chi2_fit = 0;    ///< fit half at rho = 1 and at the fitted rho
  double chi2_held_unchanged = 0, chi2_held = 0;  ///< held-out half at rho = 1 and at the fitted rho
  /// Its own model's held-out test: chi2 and the null's 1 - alpha/2 quantile (NaN where not run:
  /// it runs only for one that explains, moved and is off its range's edge).
  double own_held_out_chi2 = std::numeric_limits<double>::quiet_NaN();
  double own_bound = std::numeric_limits<double>::quiet_NaN();
  /// A level's own test is condition (a)'s budget, max(own_bound, this): the recording's fit half
  /// as the prediction of its held-out half (NaN for a sensor's gain, or where not run).
  double own_replicate_chi2 = std::numeric_limits<double>::quiet_NaN();
  bool at_edge = false;    ///< rho at the edge of its range: a bound, not a size
  bool explains = false;   ///< improves both halves by more than chi2_{1-alpha}(1): a rival
  bool passes = false;     ///< every test of its own
  /// Posterior probability among the rivals (equal priors, one parameter each); NaN if no rival.
  double posterior = std::numeric_limits<double>::quiet_NaN();
};

/// A mesh stiffness or damping level that a "no missing physics" nuisance fit moved where no
/// healthy reference at the recording's operating point tested it as a change (docs/diagnose.md
/// section 6b item 7): the verdict stands, but cannot rule out a change these levels absorb.
struct UntestedLevel {
  std::string parameter;  ///< its configuration key (stiffness.scale, contact.mesh_damping_ratio)
  double value = 0;       ///< [-] the nuisance fit's value
  double initial = 0;     ///< [-] where the fit started: the calibration's value, else the configuration's
  bool at_bound = false;  ///< at an edge of its box: the fit asked for more (a limit, no standard error)
};

struct Timing {
  double total_s = 0, analysis_s = 0, baseline_s = 0, nuisance_s = 0, locate_s = 0, screening_s = 0, candidates_s = 0,
         phase_s = 0,
         report_s = 0;
  double simulate_s = 0;   ///< summed over threads
  long simulations = 0;
  int threads = 1;
};

struct Diagnosis {
  Verdict verdict = Verdict::NoMissingPhysics;
  std::string summary;                   ///< the finding in one sentence
  std::string rule;                      ///< the decision rule, with its numbers
  SpeedEstimate speed;
  std::string angle_source;
  Kinematics kinematics;
  std::vector<std::string> channels;
  std::vector<double> noise_std;         ///< per channel: sqrt(mean noise variance per bin)
  std::vector<bool> noise_coloured;
  std::vector<double> noise_dispersion;  ///< per channel: noise variance scale from the halves (1 = floor as measured)
  /// Per channel: the lines found at no gear order (RecordingSpectra::alien_lines), strongest first.
  std::vector<std::vector<RecordingSpectra::AlienLine>> alien_lines;
  double alien_tolerance = 0;            ///< [carrier orders] RecordingSpectra::alien_tolerance
  OrderWindow fit_window, held_out_window;
  int revolutions = 0;                   ///< R per half (0: halves of Q mesh cycles)
  int window_mesh_cycles = 0;            ///< Q per half when the recording is too short for R >= 1
  double window_revolutions = 0;         ///< carrier revolutions per half (R, or Q / Zr)
  double recording_revolutions = 0;      ///< carrier revolutions of the whole recording
  /// Families without a whole period in a half, whose lines are not compared (halves of Q mesh
  /// cycles only), and the candidates whose evidence lies only in them (not fitted).
  std::vector<std::string> unresolved_families, unresolved_candidates;
  std::vector<std::string> dropped_channels;  ///< housing channels not compared in halves of Q mesh cycles
  double max_order = 0, max_frequency_Hz = 0;
  int mesh_harmonics = 0, cells = 0, features = 0, nonstationary_features = 0;
  std::vector<std::string> fidelity;     ///< names of the fidelity directions
  double bound_fit = 0, bound_held_out = 0;  ///< null quantiles (1 - alpha/2) of the nuisance-fitted model
  /// The same quantiles with the fidelity weights drawn linearly (FidelityDraw::Linear), reported
  /// beside the folded bounds above, which decide (diagnose.md §5 step 4): not yet acted on.
  double bound_fit_linear = 0, bound_held_out_linear = 0;
  double model_speed_rpm = 0;            ///< mean speed of the simulated baseline
  ScoreSummary nominal_fit, nominal_held_out;
  CandidateResult nuisance;              ///< nuisance-only model
  /// Non-empty when the nuisance-only model was fitted again from this candidate's fitted
  /// nuisance values and fitted better there (diagnose.md §5, step 9b); the rule says so.
  std::string nuisance_refitted_from;
  /// What the nuisance model's mesh stiffness follows: the configuration's form (the gears' roll by
  /// default; a calibration's choice, §6a item 10), or nominal time where only that form explains
  /// the recording (diagnose.md §5 step 4b).
  model::MeshPhase nuisance_mesh_phase = model::MeshPhase::Rotation;
  /// A calibration's recording (nuisance_only) whose nuisance model failed the noise test: the
  /// fit-half chi2 of that model at its fitted values with the mesh stiffness locked to nominal
  /// time (diagnose.md §5 step 4b's probe; the calibration chooses the form, §6a). Empty otherwise.
  std::optional<double> time_locked_probe_chi2;
  /// What the nuisance model's housing accelerometer reads (sensor.housing_path): the
  /// configuration's path (a calibration's choice, §6a item 11).
  model::HousingPath nuisance_housing_path = model::HousingPath::PlanetPass;
  /// A calibration's recording with a housing channel whose nuisance model failed the noise test:
  /// the fit-half chi2 of that model at its fitted values with the ring's translation as the
  /// housing path (diagnose.md §5 step 4c's probe; the calibration chooses the path, §6a). Empty otherwise.
  std::optional<double> ring_translation_probe_chi2;
  /// The same with the lateral-torsional model's ring body as the housing path (sensor.housing_path
  /// = ring_body, solver.level = lateral_torsional; its supports damped at bearing_damping's start
  /// where the gear set states no damping). Only in a calibration of a torsional gear set; empty otherwise.
  std::optional<double> ring_body_probe_chi2;
  bool located = false;
  Location location;
  std::vector<ScreenResult> screening;    ///< every candidate, largest S first
  std::vector<CandidateResult> candidates;  ///< fitted ones, ranked, best first
  int winner = -1;                       ///< index into candidates, -1 if none
  LeadAssessment lead;                   ///< the best candidate, named or not (verdict.hpp)
  std::vector<ChannelExcess> excess_by_channel;  ///< largest share first
  /// The located lines outside the frequencies the calibration (or the baseline) tested
  /// (DiagnoseOptions::line_coverage); not known without either.
  CoverageGap coverage_gap;
  std::vector<BaselineChange> baseline_changes;  ///< the change check's hypotheses (empty: not run)
  std::vector<UntestedLevel> untested_levels;    ///< "no missing physics" only (untested_level_moves)
  std::vector<std::string> final_overrides;
  std::vector<PlotSeries> plots;
  std::vector<CalibrationCell> calibration_cells;  ///< DiagnoseOptions::nuisance_only only
  Timing timing;
};

/// Diagnoses `recording` against the stage `config` at the recording's
/// operating point. Throws pw::InputError for unusable recordings.
Diagnosis diagnose(const Recording& recording, const model::SimulationConfig& config,
                   const DiagnoseOptions& options = {});

} // namespace pw::diagnose
