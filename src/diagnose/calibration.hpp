// Calibration on healthy recordings (docs/diagnose.md §6a): the model discrepancy budget.
//
// A real rig is never the model. After the nuisance fit (stiffness level, damping, sensor
// gains, and the rig elements the documentation is silent on) a healthy recording still
// differs from the model by more than its noise: a systematic residual of the model's form.
// Calibration estimates it per kind of channel (Quantity) and line family (Component), as
//
//   A_i = |a_i (1 + delta_i) e^{i phi} + noise| + b_i,
//   delta_i ~ N(0, sigma_rel^2)   relative error of a line the model has (a_i^2 >= s_i^2),
//   b_i     ~ N(0, sigma_abs^2)   excess spread of the amplitude in every cell (content the
//                                 model lacks), seen alone where it predicts no line,
// both the same in the recording's two halves (systematic, not noise),
//
// by the method of moments on the per-cell excess e_i = mean_halves[(A_i - mu_i)^2 - D_i]
// (mu_i the Rician mean of the model amplitude, D_i its Rician variance plus
// non-stationarity: what the noise alone explains):
//   sigma_abs^2 = mean of e_i over the cells with a_i^2 < s_i^2,
//   sigma_rel^2 = sum (e_i - sigma_abs^2) / sum a_i^2 over the cells with a_i^2 >= s_i^2,
// pooled over the recordings, each with its standard error from the spread of the e_i. The
// budget a diagnosis then uses is the one-sided upper (1 - alpha) confidence limit,
// estimate + z_{1-alpha} se, clipped at 0: a healthy recording outside the calibration set
// exceeds it by chance with probability about alpha (statistics, not a tuned margin). The
// relative part carries across operating points (it scales with the line); the absolute part
// is in the channel's units at the calibration's operating points.
//
// The calibrated model parameters are the median over the recordings of each nuisance-fitted
// parameter (sensor gains excepted: they are re-profiled on every recording).
#pragma once

#include "diagnose/compare.hpp"
#include "diagnose/diagnose.hpp"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace pw::diagnose {

/// The discrepancy of one (channel kind, family), with its uncertainty.
struct DiscrepancyEstimate {
  Quantity quantity = Quantity::SunSpeed;
  Component family = Component::Mesh;
  double relative_variance = 0;      ///< sigma_rel^2 point estimate, may be < 0 (no excess) [-]
  double relative_variance_se = 0;   ///< its standard error [-]
  int relative_cells = 0;            ///< cells with a model line above the noise
  double absolute_variance = 0;      ///< sigma_abs^2 point estimate [unit^2]
  double absolute_variance_se = 0;   ///< [unit^2]
  int absolute_cells = 0;            ///< cells the model predicts below the noise
  /// Per recording (same order as the input): sigma_rel^2 point estimates (NaN without cells).
  std::vector<double> relative_variance_per_recording;
  /// The budget (upper confidence limits at z): what a diagnosis adds to V.
  DiscrepancyEntry budget(double z) const;
};

/// Discrepancy estimates for every (quantity, family) present in the recordings' cells.
/// `recordings[r]` are the calibration cells of recording r's nuisance-only diagnosis.
/// Per cell of every channel of `cmp`: what the discrepancy estimate (and a differential
/// diagnosis's baseline, baseline.hpp) needs, with the model amplitudes [channel][bin] at the
/// housing gains `gains`; D_i as set by the comparison's current reference, without the
/// discrepancy terms V may carry (ModelComparison::noise_diagonal_variance).
std::vector<CalibrationCell> calibration_cells(const ModelComparison& cmp,
                                               const std::vector<std::vector<double>>& model_amplitude,
                                               const std::vector<double>& gains);

std::vector<DiscrepancyEstimate> estimate_discrepancy(const std::vector<std::vector<CalibrationCell>>& recordings);

/// Per kind of channel, the frequency span of the cells that measure the relative discrepancy
/// (the model's line at or above the noise, as estimate_discrepancy selects them) over all
/// `recordings`, with the input speed `speeds_rpm[r]` of the recording each end came from
/// (line_coverage.hpp). Kinds without such a cell are left out.
std::vector<LineCoverage> line_coverage(const std::vector<std::vector<CalibrationCell>>& recordings,
                                        const std::vector<double>& speeds_rpm);

/// Median over the recordings of each nuisance parameter except the sensor gains, as
/// "key=value" overrides (key = the parameter's configuration key).
std::vector<std::string> median_overrides(const std::vector<std::vector<FittedParameter>>& per_recording);

/// The "key=value" lines the rig elements' apply() writes besides their parameters (the machine
/// inertia a shaft element assumes when the configuration states none, rig_shaft.cpp), at their
/// values in `overrides`, for keys `overrides` lacks: appended to the medians, they make the
/// calibrated model the one that was fitted. An element whose parameters are not all in
/// `overrides` (its recordings could not see it) adds nothing.
std::vector<std::string> rig_element_settings(const std::vector<std::string>& rig_elements,
                                              const model::SimulationConfig& config,
                                              const std::vector<std::string>& overrides);

/// One recording's held-out chi2 without and with the calibration-only rig elements (the fit
/// with them the lower of two starts, one of them the fit without's values).
struct NestedFits {
  double chi2_without = 0, chi2_with = 0;  ///< held-out chi2 [-]
  int features = 0;                        ///< held-out features the chi2 sums over
  int extra_parameters = 0;                ///< nuisance parameters the elements add
};

/// Whether the elements improve the held-out half by more than their parameters buy by chance:
/// the extra-sum-of-squares F test of nested least-squares models, (Δχ² / p) / (χ²_with / m) >
/// F_{1-alpha}(p, m). χ²_with / m is the residual per feature: 1 when the model is right (the
/// test is then the likelihood-ratio test's χ²(p)), far more when the model's form misses the
/// recording, and an improvement must then be as much larger. With a start at the fit without's
/// values the fit with them is rarely worse, so "lower" alone would keep them on almost any rig.
bool rig_elements_improve(const NestedFits& f, double alpha);

/// One rig structure for every operating point (docs/diagnose.md section 6a item 8). A shaft's
/// stiffness, a housing's mount, the gears' engagement ramp are properties of the rig, not of the
/// speed; fitted on each healthy recording alone they scatter (indepsim2's rigA3: an input shaft of
/// 1.1e4 and 2.0e3 N m/rad at 300 and 900 rpm; docs/diagnose-log.md, session 51), because each
/// operating point lets them absorb a different part of the model's form error. calibrate holds
/// the shared structure only where no recording rejects it (rejects_shared). Of the
/// structures the recordings fitted, the one shared is the maximum of the Gaussian profile
/// likelihood over all recordings, each with its own residual variance (the model-form error
/// differs per operating point, so one common variance would let the worst-fitted recording
/// decide): recording j's maximum-likelihood variance under structure k is chi2_jk / m_j, and
///   loss(k) = sum_j (m_j / 2) ln(chi2_jk / chi2_jj)      [nats],
/// chi2_jk the held-out chi2 of recording j with recording k's structure held and its other
/// nuisance parameters refitted, chi2_jj its own fit. Scale-free per recording: multiplying one
/// recording's chi2 row by a constant changes no choice.
struct SharedStructure {
  std::size_t from = 0;            ///< the recording whose fitted structure is shared
  std::vector<double> loss;        ///< per structure k (recording k's) [nats]; +inf where a chi2 is missing
  /// Per recording j: whether its own structure fits it better than the shared one by more than
  /// the structure's parameters buy by chance (rig_elements_improve, the F test): the operating
  /// points then disagree on the structure beyond chance, which the calibration reports.
  std::vector<bool> rejects_shared;
};
/// `held_out_chi2[j][k]` as above, n >= 1 rows of K >= n columns: columns 0 .. n-1 the recordings'
/// own fitted structures (chi2_jj recording j's own fit), further columns other candidates (the
/// pooled structure below); `features[j]` recording j's held-out features; `structure_parameters`
/// the parameters a structure holds (the F test's p). `from` indexes the columns.
SharedStructure choose_shared_structure(const std::vector<std::vector<double>>& held_out_chi2,
                                        const std::vector<int>& features, int structure_parameters, double alpha);

/// The structure parameters `names` pooled over the recordings' fits: per parameter the inverse-
/// variance weighted mean of the recordings' estimates (in ln value when every estimate is
/// positive: a shaft's stiffness is a scale, and its fits differ by factors), each weighted by its
/// own fit's standard error; a value at a bound or without a standard error carries no weight.
/// This is the one-step estimate of a joint fit's shared values when the recordings agree (each
/// recording's information about its own nuisance values profiled out in its standard errors,
/// their correlations across the structure's parameters neglected). It is a candidate of
/// choose_shared_structure beside the recordings' own structures, which each hold one recording's
/// estimation error: held on a recording that sees a parameter better than the one that fitted
/// it, a single recording's structure can be rejected although the rig is one (measured:
/// tests/diagnose/test_calibration_shared_structure.sh). Returns the parameters with the pooled
/// value and its standard error (the other fields the first recording's), or nothing with fewer
/// than two recordings, a recording without one of the parameters, or a parameter no recording
/// weighs.
std::optional<std::vector<FittedParameter>> pooled_structure(const std::vector<std::vector<FittedParameter>>& per_recording,
                                                             const std::vector<std::string>& names);

/// One line per nuisance parameter (sensor gains excepted) whose fit sat at a bound of its
/// box on at least one recording: "stiffness.scale at its upper bound 2 on 8 of 8 recordings".
/// A calibrated value at a bound is not a fit but a limit: the rig differs from the model by
/// more than that parameter's range, and the discrepancy budget carries the rest.
std::vector<std::string> parameters_at_bound(const std::vector<std::vector<FittedParameter>>& per_recording);

/// Whether any recording's housing channel holds a line the noise cannot explain: a housing cell
/// whose amplitude exceeds, in both halves, what the noise alone reaches with probability
/// alpha / m (m the housing cells over all recordings, Bonferroni). A bin of complex white noise
/// of variance s^2 has |n|^2 exponentially distributed with mean s^2, P(|n|^2 > t s^2) = e^-t, so
/// the level is A^2 > s^2 ln(m / alpha). False when there is no housing cell. Without such a
/// line nothing in the recordings depends on the housing's transfer beyond its gain, and a
/// fitted mount (sensor.housing_mount_*) is wherever the fit wandered: calibrate then holds it
/// at its 'absent' values (hold_at_null).
bool housing_lines_heard(const std::vector<std::vector<CalibrationCell>>& recordings, double alpha);

/// Every recording's parameters named in `null_values` set to that value and no longer at a bound
/// (a rig element the recordings cannot measure, held at 'absent').
void hold_at_null(std::vector<std::vector<FittedParameter>>& per_recording,
                  const std::vector<std::pair<std::string, double>>& null_values);

/// One healthy recording's nuisance fit within a calibration: what the median was taken over.
/// Their spread across the recordings shows how well the operating points agree on each value
/// (a parameter that scatters by a factor of two is not identified by these recordings).
struct CalibrationFit {
  double nuisance_chi2_held_out = 0;  ///< held-out chi2 of the nuisance-fitted model [-]
  double noise_bound_held_out = 0;    ///< its noise bound (Monte-Carlo 1 - alpha/2 quantile) [-]
  std::vector<std::string> values;    ///< "key=value" per nuisance parameter (sensor gains excepted)
  std::vector<std::string> at_bound;  ///< keys of those fitted at a bound of their box
};

/// The per-recording fits of calibrate's nuisance parameters (sensor gains excepted).
CalibrationFit calibration_fit(const std::vector<FittedParameter>& nuisance, double chi2_held_out,
                               double bound_held_out);

/// How a healthy recording's nuisance fit weights its cells (calibrate, and the healthy
/// reference of a differential diagnosis; docs/diagnose.md section 6a item 7).
enum class HealthyFit {
  /// V = noise + fidelity: every cell weighted by what the noise explains.
  Noise,
  /// Refit once with the first fit's own discrepancy point estimate in V (two-step feasible
  /// generalized least squares): cells the model's form misses by far more than the noise no
  /// longer decide where the nuisance parameters end.
  ModelForm,
};
const char* to_string(HealthyFit f);
/// "noise" or "model_form"; throws InputError naming `parameter` otherwise.
HealthyFit healthy_fit_from_string(const std::string& s, const std::string& parameter);

/// A calibration as written by `planetwear calibrate` and read by `diagnose --calibration`.
/// What a model's form is beyond its parameters: the two discrete choices a calibration makes
/// from its healthy recordings (docs/diagnose.md §6a items 10 and 11).
struct ModelForm {
  model::MeshPhase mesh_phase = model::MeshPhase::Rotation;            ///< stiffness.mesh_phase
  model::HousingPath housing_path = model::HousingPath::PlanetPass;   ///< sensor.housing_path
  bool operator==(const ModelForm&) const = default;
};

/// One part of a model's form, as the diagnosis tries it (docs/diagnose.md §5 steps 4b, 4c, 9c)
/// and the calibration chooses it (§6a items 10, 11), and as the log and the rule name it.
struct ModelFormPart {
  const char* part;     ///< "mesh stiffness", "housing accelerometer"
  const char* with;     ///< "with its mesh stiffness locked to nominal time"
  const char* other;    ///< the other form, short: "locked to nominal time"
  const char* own;      ///< the default form, short: "locked to the gears' roll"
  const char* variant;  ///< CandidateResult::variant's text of a fit in the other form
  const char* why;      ///< the rule's sentence on what the other form means
  ModelForm (*changed)(ModelForm);          ///< the form with this part in the other form
  std::optional<double> Diagnosis::*probe;  ///< where a calibration's nuisance-only probe of it is kept
  /// A rig element the other form brings (fitted with the nuisance parameters once the form is
  /// taken; the probe holds it at its start), or nullptr.
  const char* rig_element = nullptr;
};

/// The mesh stiffness locked to nominal time (stiffness.mesh_phase = nominal_time): the k(t) of the
/// lumped-parameter simulators of the literature, where a real gear's mesh follows its roll.
inline constexpr ModelFormPart kTimeLockedMesh{
    "mesh stiffness", "with its mesh stiffness locked to nominal time", "locked to nominal time",
    "locked to the gears' roll",
    "mesh stiffness locked to nominal time, not to the gears' roll (stiffness.mesh_phase = nominal_time)",
    "A real gear's mesh follows its roll; mesh lines locked to time come from a simulator that excites the mesh with k(t).",
    [](ModelForm f) {
      f.mesh_phase = model::MeshPhase::NominalTime;
      return f;
    },
    &Diagnosis::time_locked_probe_chi2};

/// The housing accelerometer on the ring's rigid-body translation (sensor.housing_path =
/// ring_translation, model/sensor.hpp Eq. S2): the lumped models in the manner of Lin & Parker.
inline constexpr ModelFormPart kRingTranslationHousing{
    "housing accelerometer", "with the housing accelerometer on the ring's translation", "on the ring's translation",
    "through the planet-pass window",
    "housing accelerometer on the ring's rigid-body translation, not the planet-pass window (sensor.housing_path = "
    "ring_translation)",
    "A stiff ring that translates as one body shows its accelerometer every planet's whole force, the static loads "
    "of unequal planets included; a flexible ring shows each planet as it passes.",
    [](ModelForm f) {
      f.housing_path = model::HousingPath::RingTranslation;
      return f;
    },
    &Diagnosis::ring_translation_probe_chi2};

/// The housing accelerometer on the lateral-torsional model's ring body (sensor.housing_path =
/// ring_body, model/sensor.hpp Eq. S3; solver.level = lateral_torsional): the ring on its supports
/// through the stage's translational modes, as the lumped models in the manner of Lin & Parker
/// record it. Measured (docs/diagnose-log.md, session 72): indepsim4's setC3 pin error, whose
/// housing lines pass through two translational mode pairs, explained 3-4 % through the window,
/// 0 % on the quasi-static ring translation, 96-97 % on the ring body. Its supports' damping
/// (bearing_damping) comes with it: Lin & Parker's undamped supports are no rig's. Chosen only by a
/// calibration asked for it (`calibrate --ring-body`; a torsional gear set's diagnosis does not
/// probe it: every later simulation would cost the lateral-torsional model's 3-5 times more).
inline constexpr ModelFormPart kRingBodyHousing{
    "housing accelerometer", "with the housing accelerometer on the lateral-torsional model's ring body",
    "on the ring body of the lateral-torsional model", "through the window or on the ring's quasi-static translation",
    "housing accelerometer on the lateral-torsional model's ring body, not the planet-pass window or the ring's "
    "quasi-static translation (solver.level = lateral_torsional, sensor.housing_path = ring_body)",
    "A ring on compliant supports shows its accelerometer the planets' ring forces through the stage's translational "
    "modes; a flexible ring shows each planet as it passes.",
    [](ModelForm f) {
      f.housing_path = model::HousingPath::RingBody;
      return f;
    },
    &Diagnosis::ring_body_probe_chi2, "bearing_damping"};

/// `config` with `form` applied (the keys model_form_settings writes; the ring body's housing path
/// brings the lateral-torsional model, which it needs).
void apply_model_form(model::SimulationConfig& config, const ModelForm& form);

/// The form `config` has.
ModelForm model_form_of(const model::SimulationConfig& config);

/// A calibration's --set lines once `part` is taken on top of the form `chosen` that the earlier
/// choices wrote into `assignments`: the part's lines first, in their order (the level before the
/// ring body's path), the other lines after them (the user's --set wins over a form); a line an
/// earlier choice wrote for a key the part sets again goes, or, coming later, it would win (the
/// ring body replacing the ring's translation).
std::vector<std::string> assignments_in_form(const std::vector<std::string>& assignments, const ModelForm& chosen,
                                             const ModelFormPart& part);

struct Calibration {
  std::vector<std::string> recordings;   ///< file names (absolute since session 25): the record, and the
                                         ///< reference at a calibrated operating point (docs/diagnose.md §6a item 6)
  std::vector<std::string> sidecars;     ///< their JSON sidecars (same order); empty in older files: the default name
  std::vector<double> speeds_rpm;        ///< their input speeds [rpm]
  std::vector<std::string> verdicts;     ///< each recording's nuisance-only verdict before calibration
  std::vector<std::string> overrides;    ///< calibrated model: "key=value"
  std::vector<std::string> rig_elements; ///< candidates fitted as nuisance (e.g. encoder_bandwidth)
  std::vector<std::string> at_bound;     ///< parameters_at_bound(): calibrated values that are limits
  std::vector<CalibrationFit> fits;      ///< per recording (same order); empty in files written before session 18
  double alpha = 0.01;                   ///< of the upper confidence limits
  /// How each recording's nuisance values were fitted; a calibrated reference is fitted the same
  /// way (files written before session 43: Noise).
  HealthyFit healthy_fit = HealthyFit::Noise;
  /// The calibrated model's form (docs/diagnose.md §6a items 10 and 11): what its mesh stiffness
  /// follows and what its housing accelerometer reads, each changed from the configuration's only
  /// where every healthy recording chose the other form (form_probes_pass, form_refits_improve).
  /// Files written before session 66 are roll-locked, before session 67 planet-pass.
  ModelForm form;
  std::vector<DiscrepancyEstimate> discrepancy;
  /// Where its healthy lines tested the model (line_coverage()); empty in files written before
  /// session 74.
  std::vector<LineCoverage> coverage;
  /// The budgets at z_{1-alpha}, for CompareOptions::discrepancy. A family without a relative
  /// estimate (relative_cells == 0) inherits the largest relative budget measured on its kind
  /// of channel (relative_inherited).
  std::vector<DiscrepancyEntry> budgets() const;
};

/// The "key=value" lines of a calibrated model's form (Calibration::form): one per part that
/// differs from the configuration's default (stiffness.mesh_phase=nominal_time,
/// sensor.housing_path=ring_translation), none for a real gear's roll-locked mesh seen through the
/// planet-pass window. Applied before the calibrated values wherever the calibrated model is simulated.
std::vector<std::string> model_form_settings(const ModelForm& form);

/// One healthy recording's two fits in the calibration's choice of one part of the model's form
/// (the mesh's phase, §6a item 10; the housing path, item 11).
struct ModelFormFits {
  double fit_chi2 = 0;                   ///< fit half, the configuration's form
  /// fit half, its values in the other form (Diagnosis::time_locked_probe_chi2, ring_translation_probe_chi2)
  std::optional<double> probe_fit_chi2;
  int fit_features = 0;
  double held_out_chi2 = 0;              ///< held-out half, the configuration's form
  std::optional<double> refit_held_out_chi2;  ///< held-out half, refitted in the other form
  int held_out_features = 0;
  /// The parameters the other form adds for the F tests: the discrete choice counts as one, each
  /// parameter of a rig element it brings (ModelFormPart::rig_element) as one more.
  int extra_parameters = 1;
};

/// Whether the other form is worth refitting every recording in (docs/diagnose.md §6a items 10, 11):
/// every recording was probed (its nuisance model failed the noise test) and its probe fits the fit
/// half better than one parameter buys by chance (rig_elements_improve's F test with p = 1: a
/// discrete choice between two models with the same parameters counted as one, the improvement
/// measured against the better model's chi2 per feature, so that on another simulator's
/// recordings, whose chi2 is many times the noise's, an improvement of the noise's size does not
/// count).
bool form_probes_pass(const std::vector<ModelFormFits>& fits, double alpha);

/// Whether the refits in the other form are the calibrated model's: on every recording the
/// refit's held-out chi2 is below the first form's by the same F test. One form for every
/// operating point, as for the rig's structure: a rig whose operating points disagree keeps the
/// configuration's form, and its recordings' discrepancy carries the rest.
bool form_refits_improve(const std::vector<ModelFormFits>& fits, double alpha);

/// The calibration's settings of the calibration-only rig elements it kept (a shaft behind a
/// machine: Candidate::calibration_only), as "key=value": every line their apply() writes at the
/// calibrated values, the machine's inertia included. These describe the rig's structure, kept
/// only because they lowered the held-out chi2 of every healthy recording (calibrate), so a
/// calibrated reference is fitted with them, held (docs/diagnose.md section 6a item 6). Empty when
/// the calibration kept none. `config` is the gear set's (without the calibration).
///
/// `at_recording`: the calibration recording the diagnosis takes as its reference (§6a item 6).
/// Its own fit's values (Calibration::fits) are then held, not the medians: at that operating
/// point they are what the healthy recording measured, while the median over operating points
/// can be a value no recording supports (rigA3 of indepsim2 fitted the input shaft at 1.1e4 and
/// 364 N m/rad at 300 and 900 rpm: a median of 5.8e3 holds neither; docs/diagnose-log.md,
/// session 48). Falls back to the medians when the file has no fit of that recording (written
/// before session 18) or the fit lacks an element's parameters.
std::vector<std::string> structural_rig_settings(const Calibration& calibration, const model::SimulationConfig& config,
                                                 std::optional<std::size_t> at_recording = std::nullopt);

/// The calibration's rig-design elements (Candidate::rig_design: an encoder's bandwidth, a
/// machine's inertia, tip relief) at the values its fit of the recording `at_recording` ended at,
/// as "key=value", for a calibrated reference at that recording (§6a item 6): each element only
/// where that fit found it within its box (not in the fit's at_bound: a value at a bound is a
/// limit, not a measurement). Without them the reference's own nuisance fit compensates for what
/// they model: on indepsim2's rigB5 at 400 rpm (seed-21 corpus, docs/diagnose-log.md session 55)
/// the reference without the calibration's 587 Hz encoder low-pass fitted stiffness.scale 2, the
/// top of its box, and left a held-out chi2 of 3.10e6; with it held, 0.713 and 1.66e6 (the
/// calibration's own fit of that recording: 0.712 and 1.66e6).
/// A fault's change is computed in that model, and its signature depends on the stiffness and
/// damping it is computed at. Empty without a fit of that recording.
std::vector<std::string> reference_design_settings(const Calibration& calibration, const model::SimulationConfig& config,
                                                   std::size_t at_recording);

/// The nuisance values the calibration's fit of its recording `at_recording` ended at, by key
/// (Calibration::fits; empty when the file has no fit of it). A calibrated diagnosis fits its
/// reference, that same recording, again (§6a item 6); LM is local, and from the gear set's
/// nominal start it can end in another basin than the calibration's fit did. These values are
/// therefore the reference fit's second start (DiagnoseOptions::nuisance_start_values: both fits
/// run, the lower on the fit half is kept): the reference is never fitted worse on its fit half
/// than from the nominal start alone.
std::map<std::string, double> fitted_values(const Calibration& calibration, std::size_t at_recording);

/// How far the calibration's healthy recordings scatter each nuisance value: per key fitted on
/// every one of at least two recordings (Calibration::fits), all values positive, the sample
/// standard deviation of ln(value) over the recordings (n - 1 in the denominator) [-]. A level
/// the model needs at 0.53 on one operating point and 1.30 on another is known to the rig no
/// better than that spread, whatever one fit's standard error says: a finding's size that is
/// conditional on it carries the spread (DiagnoseOptions::nuisance_level_spread_ln). Values at a
/// box edge count as they are (limits: the spread is then at least this). Empty with fewer than
/// two fits.
std::map<std::string, double> nuisance_level_spread_ln(const Calibration& calibration);


/// A healthy recording's nuisance-only diagnosis, and under HealthyFit::ModelForm its refit.
struct HealthyFitResult {
  Diagnosis noise_weighted;                      ///< V = noise + fidelity: its chi2 and verdict are the noise test
  std::optional<Diagnosis> model_form_weighted;  ///< the refit (HealthyFit::ModelForm)
  /// The fit whose values and cells are used: the refit when there is one.
  const Diagnosis& fit() const { return model_form_weighted ? *model_form_weighted : noise_weighted; }
};

/// Fits the nuisance parameters of the healthy `recording` (options.nuisance_only is forced;
/// options.compare.discrepancy must be empty: the healthy recording is what a discrepancy is
/// measured on). Under HealthyFit::ModelForm the first fit's per-family discrepancy (the point
/// estimates of estimate_discrepancy, not their upper confidence limits: weights, not a test)
/// enters V with its relative term at the first fit's model, the fit starts again from the
/// configuration (the same boxes), and the cells are those of the refit, their D_i the noise's.
HealthyFitResult fit_healthy(const Recording& recording, const model::SimulationConfig& config,
                             DiagnoseOptions options, HealthyFit weighting);

} // namespace pw::diagnose
