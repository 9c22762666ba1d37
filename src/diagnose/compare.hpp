// Model against recording in the order domain (docs/diagnose.md §2-3).
//
// The recording is analysed once (order_analysis.hpp): two windows of R whole
// carrier revolutions (the fit half and the held-out half), the amplitude
// A_i = |c_k| of every feature cell i (a DFT bin carrying a labelled line, per
// channel) and the noise variance s_i^2 = E|noise in bin|^2.
//
// A model (one simulation at the recording's speed, cached) predicts the
// noise-free amplitude a_i (housing channels times a gain g that is
// profiled on the fit half). The residual r_i = A_i - E[A_i | a_i] uses the
// Rician mean, since A_i = |a_i e^{i phi} + noise|. Its covariance is
//
//   V = D + U U^T,   D_i = Var_Rice(A_i) + v_ns,i,   U = fidelity directions:
//
//  * Var_Rice(A_i): the Rician variance of an amplitude a_ref,i in white noise
//    of total variance s_i^2 in the bin, a_ref from a reference model (the
//    nominal, then the nuisance-fitted model; fixed while candidates are
//    compared, so every chi2 uses the same V). Strong lines also leak the
//    angle reference's error into their neighbours (order_analysis.hpp):
//    part of s_i^2;
//  * v_ns,i: non-stationarity. Lines that are not integer carrier orders
//    (sun, planet, input-shaft families) beat with their neighbours inside a
//    window of a few revolutions, so their bins depend on where the window
//    starts; a cell whose two halves differ by more than the 1 - alpha
//    quantile of the noise (|A_1 - A_2|^2 > chi2_1(1-alpha) (V_1 + V_2))
//    gets v_ns = (A_1 - A_2)^2, else 0;
//  * dispersion: when the unflagged cells' halves differ by more than the
//    noise floor predicts (mean (A_1 - A_2)^2 / (V_1 + V_2) significantly
//    above 1), the channel's noise variance is scaled by that mean;
//  * U: model fidelity, estimated, not tuned. Each column is the change of
//    every feature between two runs of the same baseline model that the
//    recording cannot tell apart: a second discretization
//    (solver.steps_per_mode_period 32 -> 48, or time step x 0.7) and the
//    recording's speed +- its standard error (half the difference). A column
//    is a coherent pattern (a discretization error moves all resonant
//    lines together), so it is a low-rank term with a N(0, 1) weight, not a
//    diagonal variance;
//  * one more column per window when the recording's angle reference is an
//    integrated speed channel: the window's linear angle drift (standard
//    deviation sqrt(D T), order_analysis.hpp) times the derivative of the
//    recording's amplitudes in it. Its leaks from the strong mesh harmonics
//    into their neighbours are one random number for every cell and
//    channel: correlated, so a column, not noise. WindowScore::fidelity_z
//    ends with its weight.
//
// chi2 = r^T V^{-1} r = min_z |D^{-1/2}(r - U z)|^2 + |z|^2 (Woodbury), so
// the whitened residual handed to the least-squares fit is
// [D^{-1/2}(r - U z*); z*], of fixed length (features + fidelity columns).
// Under "the model explains the data", chi2 is close to chi2(m); its exact
// null distribution (Rician cells, the profiled fidelity weights) is drawn by
// Monte Carlo from the model's own amplitudes (null_quantile).
#pragma once

#include "config/stage.hpp"
#include "diagnose/order_analysis.hpp"
#include "diagnose/recording.hpp"

#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

namespace pw::diagnose {

/// Model discrepancy of one kind of channel and one line family (calibration.hpp): a healthy
/// recording's amplitudes differ from the calibrated model's by a relative error of standard
/// deviation relative_std on the lines the model has, plus an excess variance
/// absolute_variance of the amplitude residual A_i - E[A_i] where the model predicts (almost)
/// nothing. Enters V as (relative_std a_ref,i)^2 + absolute_variance per cell, and the null's
/// draws as a factor (1 + relative_std n), n ~ N(0, 1), on the model amplitude and a term
/// sqrt(absolute_variance) n' added to the residual.
struct DiscrepancyEntry {
  Quantity quantity = Quantity::SunSpeed;
  Component family = Component::Mesh;
  double relative_std = 0;       ///< [-]
  double absolute_variance = 0;  ///< [channel unit^2]
  /// relative_std not measured for this family (the healthy model had no line in it above the
  /// noise) but inherited from the measured families of the same kind of channel
  /// (Calibration::budgets): it matters only for a model that adds lines here.
  bool relative_inherited = false;
};

/// One feature cell of a healthy baseline recording (differential diagnosis, baseline.hpp): what
/// the model fitted to the baseline misses there. The comparison takes `transfer` times the
/// model's noise-free amplitude of the cell with the same channel and carrier order plus
/// `offset`, and adds `variance` (the offset's own estimation error) to V and to the null's draws.
struct BaselineCell {
  std::string channel;
  double order = 0;     ///< carrier order of the cell
  /// [channel unit] de-biased baseline amplitude - transfer x fitted model amplitude
  double offset = 0;
  /// [-] factor on the model's amplitude and so on its change from the baseline's model: 1 for an
  /// additive offset, the rig's measured-to-model line ratio at this frequency under
  /// BaselineTransfer::LineRatio (docs/diagnose.md section 6b item 9)
  double transfer = 1;
  double variance = 0;  ///< [channel unit^2]
  double model = 0;     ///< [channel unit] the baseline's fitted model amplitude (gain applied)
  /// [channel unit] the baseline model's discretization direction (CalibrationCell::discretization)
  double discretization = 0;
};

struct CompareOptions {
  OrderAnalysisOptions analysis{};
  double alpha = 0.01;                 ///< for the non-stationarity flag
  int null_draws = 2000;               ///< Monte Carlo draws of the null distribution
  std::uint64_t seed = 20240611;       ///< of those draws (the result is deterministic)
  /// Runs a prepared simulation elsewhere (another MPI rank: sweep/simulation_pool.hpp) and
  /// returns what ModelComparison::evaluate would return there, or nullopt when it has no
  /// idle capacity (the simulation then runs in this process). Empty: always here. Called
  /// concurrently from the diagnosis's threads. Errors are rethrown as the same types.
  std::function<std::optional<ModelSpectra>(const model::SimulationConfig&, bool keep_sensor_inputs)> remote;
  /// Calibrated model discrepancy (empty: none; the noise, non-stationarity and fidelity alone).
  /// A cell carrying lines of several families takes the largest of theirs. With a baseline the
  /// relative part applies to the model's change from the baseline's fitted model (what does not
  /// cancel), and the absolute part is not used (content the model lacks is in both recordings).
  std::vector<DiscrepancyEntry> discrepancy;
  /// Differential diagnosis: the baseline's per-cell offsets (empty: absolute comparison). Every
  /// cell of the recording must have its counterpart (the same analysis windows).
  std::vector<BaselineCell> baseline;
  /// Differential diagnosis: the baseline recording's lines at no gear order; those the recording
  /// shares with it are the rig's, and V carries their leak (carry_baseline_alien_lines). Empty
  /// (no baseline): none is carried.
  BaselineAlienLines baseline_alien_lines;
};

/// The two halves of a recording (docs/diagnose.md §2): the candidates are fitted on the first,
/// the verdict is tested on the second. Index k of the per-window arrays is the k-th half.
enum class Half { Fit, HeldOut };
constexpr int window_index(Half h) { return h == Half::Fit ? 0 : 1; }
constexpr Half half_of_window(int w) { return w == 0 ? Half::Fit : Half::HeldOut; }

/// Whether a score fits the housing sensors' gains on its half or takes them as given.
enum class HousingGains { Profile, Given };
/// How a null draw's model-fidelity weights z enter the drawn amplitudes (null_quantile).
/// Folded: into the line, |a + z u| (a model line moved by its own discretization or speed
/// change cannot go below 0). Linear: added to the amplitude residual, r + z u -- the form
/// chi2_of profiles z in, so the drawn statistic is the one its own algebra assumes.
/// Where |u| is small beside a the two agree to first order; where it is not, the fold leaves
/// a residual the linear profile cannot remove and the folded null grows with |u|.
enum class FidelityDraw { Folded, Linear };

/// One model scored on one window.
struct WindowScore {
  double chi2 = 0;                        ///< r^T V^{-1} r
  int features = 0;                       ///< m
  std::vector<double> residual;           ///< whitened: [D^{-1/2}(r - U z*); z*]
  std::vector<double> rho;                ///< per feature (channel-major): (r - U z*)_i / sqrt(D_i)
  std::vector<double> chi2_per_channel;   ///< sum of rho^2 per channel
  std::vector<int> features_per_channel;
  std::vector<double> fidelity_z;         ///< z*
  std::vector<double> gains;              ///< per channel (1 unless housing)
  std::vector<double> gain_std;           ///< standard error of profiled gains (0 if not profiled)
  /// Per channel: the profiled gain ended within the search's final bracket of an edge of its
  /// initial bracket (ln g of the weighted least-squares start +- 0.4): not an interior optimum.
  std::vector<bool> gain_at_edge;
};

class ModelComparison {
public:
  /// Analyses the recording and prepares `config` at the recording's speed.
  ModelComparison(const Recording& recording, const model::SimulationConfig& config, CompareOptions options = {});
  /// The comparison keeps a reference to the recording: a temporary would dangle (found
  /// 2026-11-28: tests that passed temporaries read freed memory, and crashed once the layout moved).
  ModelComparison(Recording&&, const model::SimulationConfig&, CompareOptions = {}) = delete;

  const Recording& recording() const { return rec_; }
  const RecordingSpectra& spectra() const { return spec_; }
  const Kinematics& kinematics() const { return spec_.kinematics; }
  /// The configuration at the recording's speed (operating.input_speed_rpm replaced).
  const model::SimulationConfig& base() const { return base_; }
  int channels() const { return static_cast<int>(spec_.channels.size()); }
  int cells() const { return static_cast<int>(spec_.layout.cells.size()); }
  int features() const { return channels() * cells(); }
  bool is_housing(int c) const;

  /// Simulates `config` (warm-up + R carrier revolutions or Q mesh cycles, + 3 mesh cycles; cached) and extracts
  /// its spectra. keep_sensor_inputs: also keep the ring forces for sensor-only changes.
  /// tally (optional): incremented when this call ran a simulation (a cache miss), so a caller
  /// can count its own simulations while others run on other threads.
  std::shared_ptr<const ModelSpectra> simulate(const model::SimulationConfig& config,
                                               bool keep_sensor_inputs = false,
                                               std::atomic<long>* tally = nullptr) const;
  /// validate + simulate + model_spectra of an already prepared configuration (what
  /// simulate() runs on a cache miss; a remote rank runs this for its requests). Uncached.
  ModelSpectra evaluate(const model::SimulationConfig& prepared, bool keep_sensor_inputs) const;
  long simulations() const;
  double simulation_seconds() const;

  /// The reference model whose amplitudes set the Rician variances in D (the
  /// same for every model scored afterwards, so their chi2 compare): the
  /// nominal model first, the nuisance-fitted one after the nuisance fit.
  void set_reference(const std::vector<std::vector<double>>& model_amplitude, const std::vector<double>& gains);
  /// As above, and the model's window-start variance (ModelSpectra::leak_variance, halves of Q
  /// mesh cycles) enters V as a variance of the residual (and the null's draws) until the next
  /// call of this overload.
  void set_reference(const ModelSpectra& model, const std::vector<double>& gains);
  /// Only the calibrated relative discrepancy's term of V (and of the null's draws) taken at
  /// `model_amplitude`; the Rician variances stay at set_reference's model. A verdict tests
  /// "the recording is this candidate's model plus the calibrated discrepancy": the relative
  /// model-form error scales with the lines of the model under test, in V and in the draws
  /// alike (one allowance, charged and drawn consistently). set_reference restores it.
  void set_discrepancy_reference(const std::vector<std::vector<double>>& model_amplitude,
                                 const std::vector<double>& gains);
  /// The model and gains the discrepancy term of V was last taken at (set_reference or
  /// set_discrepancy_reference; empty before either).
  const std::vector<std::vector<double>>& discrepancy_reference_model() const { return disc_ref_model_; }
  const std::vector<double>& discrepancy_reference_gains() const { return disc_ref_gains_; }

  /// Fidelity columns (per feature, at gain 1) and their names.
  /// The model-fidelity directions (columns [feature], raw amplitude changes without gains) and
  /// their names. discretization_column: the column that is the model's discretization error
  /// (-1: none). Differential (a baseline), the baseline's model has the same discretization
  /// error, which cancels in the change: that column acts as its difference from the baseline's.
  void set_fidelity(std::vector<std::vector<double>> columns, std::vector<std::string> names,
                    int discretization_column = -1);
  int discretization_column() const { return u_discretization_; }
  const std::vector<std::string>& fidelity_names() const { return u_names_; }
  const std::vector<std::vector<double>>& fidelity_columns() const { return u_; }
  /// Standard deviation [rad] of the angle reference's linear drift over a window, carried as a
  /// last column of U (0: none, the angle does not come from an integrated speed channel).
  double angle_drift_std_rad() const { return drift_[0].empty() ? 0.0 : std::sqrt(spec_.angle_diffusion_T); }

  /// Scores model amplitudes ([channel][bin], housing at gain 1) on one half.
  /// HousingGains::Profile: fit the housing gains on this half (starting at `gains`);
  /// HousingGains::Given: use `gains` (empty = 1).
  WindowScore score(const std::vector<std::vector<double>>& model_amplitude, Half half, std::vector<double> gains,
                    HousingGains housing_gains) const;

  /// 1 - alpha quantile of chi2 under "the model explains the recording" on
  /// window w (Monte Carlo with the model's own amplitudes, see the top). A calibrated relative
  /// discrepancy is drawn with the standard deviation V holds, relative to the reference
  /// model's amplitudes (set_reference), not the scored model's.
  /// fitted_parameters = k > 0: the model's k parameters were fitted on the OTHER window,
  /// and each draw adds 2 chi2(k). Why: linearized, the held-out residual is e + J_h d with
  /// d ~ N(0, (J_f'J_f)^-1) from the fit window, J_h ~ J_f, so its chi2 is
  /// |(I-P)e|^2 + 2|P u|^2 = chi2(m-k) + 2 chi2(k) (P: projection on J's range, u ~ N(0, I)),
  /// which the draw |e|^2 + 2 chi2(k) dominates stochastically: a correct model exceeds
  /// the returned quantile with probability <= alpha. k = 0 leaves the draws unchanged.
  /// draw: how the fidelity weights enter each draw (FidelityDraw); both modes use the same
  /// random numbers, so their quantiles differ only by the fold.
  double null_quantile(const std::vector<std::vector<double>>& model_amplitude, const std::vector<double>& gains,
                       Half half, double alpha, int fitted_parameters = 0,
                       FidelityDraw draw = FidelityDraw::Folded) const;
  /// A fitted model's own null: the smaller of the folded and the linear null_quantile
  /// (`bound`), and the folded one alone (`folded`, for the report). A pass owed to the fold at
  /// 0 is no evidence: where the fidelity directions are of the size of the lines the folded
  /// null grows with them, which the linear profile in chi2_of does not (docs/diagnose.md §5 (a)).
  struct OwnNull {
    double bound = 0, folded = 0;
  };
  OwnNull own_null(const std::vector<std::vector<double>>& model_amplitude, const std::vector<double>& gains,
                   Half half, double alpha, int fitted_parameters) const;
  /// The folded and the linear null_quantile of one model from one pass over the draws (both
  /// forms take the same random numbers): each equals its null_quantile to the last bit.
  struct NullPair {
    double folded = 0, linear = 0;
  };
  NullPair null_quantiles(const std::vector<std::vector<double>>& model_amplitude, const std::vector<double>& gains,
                          Half half, double alpha, int fitted_parameters = 0) const;

  /// chi2 of the recording's fit half used as the prediction of its held-out half
  /// (r = A_held - A_fit, the held-out window's V, housing gains `gains` for the fidelity
  /// columns): a model-free benchmark, E ~ 2m (noise in both halves) for a stationary recording.
  double replicate_chi2(const std::vector<double>& gains) const;

  /// Per feature: the recording's amplitude in window w, its Rician variance, v_ns.
  double recording_amplitude(int window, int feature) const { return a_rec_[static_cast<std::size_t>(window)][static_cast<std::size_t>(feature)]; }
  double noise_variance(int feature) const { return s2_[static_cast<std::size_t>(feature)]; }
  /// D_i of window w at the current reference (Rician + non-stationarity + discrepancy).
  double diagonal_variance(int window, int feature) const {
    return d_[static_cast<std::size_t>(window)][static_cast<std::size_t>(feature)];
  }
  /// D_i of window w without the calibrated discrepancy's terms (Rician + non-stationarity +
  /// leak): what the noise alone explains, the yardstick a discrepancy is estimated against
  /// (calibration_cells) also when V carries one (HealthyFit::ModelForm). Equal to
  /// diagonal_variance without a discrepancy.
  double noise_diagonal_variance(int window, int feature) const {
    const std::size_t f = static_cast<std::size_t>(feature);
    return d_[static_cast<std::size_t>(window)][f] - disc_sd_[f] * disc_sd_[f] - disc_abs_[f];
  }
  /// The model-form errors the comparison budgets (CompareOptions::discrepancy) as systematic
  /// shifts of the whitened residual of the fit half, one per discrepancy entry (kind of channel,
  /// line family) that has cells: the residual's change when every cell of that entry is off by
  /// one relative standard deviation in the same direction, i.e. relative_std times the model's
  /// amplitude (absolute) or times its change from the baseline's model (differential), through
  /// the Rician mean's slope, whitened as score() whitens (housing gains `gains`, not profiled
  /// again). Empty without a discrepancy. Why one direction per entry: a model that gets a
  /// line's transfer wrong gets its neighbours' wrong alike, so the error does not average out
  /// over the cells as noise does; carried through LmResult::sensitivity it is the fitted
  /// values' model-form uncertainty (FittedParameter::model_form_std).
  std::vector<std::vector<double>> model_form_shifts(const std::vector<std::vector<double>>& model_amplitude,
                                                     const std::vector<double>& gains) const;
  /// Per feature: the calibrated relative discrepancy (0 without a calibration).
  double relative_discrepancy(int feature) const { return disc_[static_cast<std::size_t>(feature)]; }
  double nonstationary_variance(int feature) const { return vns_[static_cast<std::size_t>(feature)]; }
  /// Per feature: the baseline's offset added to the model amplitude (0 without a baseline).
  double baseline_offset(int feature) const { return offset_[static_cast<std::size_t>(feature)]; }
  /// Per feature: the baseline's factor on the model amplitude (1 without a baseline, BaselineCell::transfer).
  double baseline_transfer(int feature) const { return transfer_[static_cast<std::size_t>(feature)]; }
  int nonstationary_cells() const { return ns_cells_; }
  /// Per channel: the noise-variance scale phi measured between the recording's halves (1 when
  /// the halves agree within the noise floor's prediction; see the constructor).
  double dispersion(int channel) const { return dispersion_.at(static_cast<std::size_t>(channel)); }

private:
  double chi2_of(const std::vector<double>& r, int window, const std::vector<double>& gains,
                 const std::vector<double>& response, WindowScore* out) const;
  /// chi2_of's per-feature constants for residuals scored alike on one window with one response,
  /// and its work space: planned once for the many draws of a null; chi2_of plans for one call.
  struct Chi2Plan;
  Chi2Plan chi2_plan(int window, const std::vector<double>& response) const;
  double chi2_planned(Chi2Plan& plan, const std::vector<double>& r, const std::vector<double>& gains,
                      WindowScore* out) const;
  /// The null's chi2 draws (before sorting) in the folded and/or the linear form.
  struct NullDraws {
    std::vector<double> folded, linear;
  };
  NullDraws null_draws(const std::vector<std::vector<double>>& model_amplitude, const std::vector<double>& gains,
                       Half half, int fitted_parameters, bool folded, bool linear) const;
  /// Per feature: how the compared amplitude responds to a change of the model's raw amplitude,
  /// the channel's gain, or 0 where a baseline's offset clips the model amplitude of `model` at
  /// 0 (null model: nothing clipped).
  std::vector<double> fidelity_response(const std::vector<std::vector<double>>* model, const std::vector<double>& gains) const;
  /// Fidelity column col at feature f as it acts on the compared amplitude (response: fidelity_response).
  double fidelity_value(std::size_t col, std::size_t f, const std::vector<double>& response) const;
  std::vector<double> residual_vector(const std::vector<std::vector<double>>& m, int window,
                                      const std::vector<double>& gains) const;
  /// Noise-free amplitude of feature f = (channel c, cell i) the model predicts at gain g: g m
  /// plus the baseline's offset (differential diagnosis), never below 0.
  double model_amplitude(const std::vector<std::vector<double>>& m, int c, int i, double g) const;
  /// The same without the baseline offset: the model's own amplitude of cell i (gain g applied).
  double raw_model_amplitude(const std::vector<std::vector<double>>& m, int c, int i, double g) const;
  void match_baseline();
  /// Variance the baseline offset's error adds to feature f's residual at compared amplitude
  /// `amplitude` (0 without a baseline).
  double offset_variance(std::size_t f, double amplitude) const;
  /// Variance the unknown phases of the lines at no gear order (RecordingSpectra::alien_leak)
  /// leave in channel c's cell i at compared amplitude `amplitude` (0 without such lines).
  double alien_variance(int c, int i, double amplitude) const;

  const Recording& rec_;
  CompareOptions opt_;
  RecordingSpectra spec_;
  model::SimulationConfig base_;
  /// The constructor chose the time step (the analysed band's, base_.solver.accuracy_band_Hz):
  /// a simulation that fails at it is run again at the model's own step (evaluate()).
  bool band_step_ = false;
  std::vector<bool> housing_;
  std::vector<std::vector<double>> a_rec_;   // [window][feature]
  std::vector<double> s2_;                   // [feature]
  std::vector<std::vector<double>> d_;       // [window][feature]: D_i
  std::vector<double> vns_;
  std::vector<double> disc_;                 // [feature]: relative discrepancy (CompareOptions::discrepancy)
  std::vector<int> disc_entry_;              // [feature]: the entry disc_ came from (-1: none)
  std::vector<double> disc_abs_;             // [feature]: absolute discrepancy variance
  std::vector<double> disc_sd_;              // [feature]: relative discrepancy x the reference amplitude (set_reference)
  std::vector<double> leak_;                 // [feature]: the reference model's window-start variance (empty: none)
  std::vector<double> rice_ref_;             // [feature]: Rician variance at the reference amplitude
  std::vector<double> offset_, offset_var_;  // [feature]: baseline offset and its variance
  std::vector<double> transfer_;             // [feature]: the baseline's factor on the model (1: none)
  std::vector<double> base_model_;           // [feature]: the baseline's fitted model amplitude
  std::vector<double> dispersion_;           // [channel]
  int ns_cells_ = 0;
  std::vector<std::vector<double>> u_;       // [column][feature]
  std::vector<std::vector<double>> drift_;   // [window][feature]: angle-drift column (empty: none)
  std::vector<double> bridge_;               // [feature x kBridgeBins]: the angle bridge's leak in s2_ (empty: none)
  std::vector<std::string> u_names_;
  int u_discretization_ = -1;
  std::vector<double> base_discretization_;  // [feature]: the baseline model's discretization direction
  std::vector<std::vector<double>> disc_ref_model_;  // set_discrepancy_reference's model
  std::vector<double> disc_ref_gains_;               // and its gains

  mutable std::mutex mutex_;
  mutable std::map<std::string, std::shared_ptr<const ModelSpectra>> cache_;
  mutable long sims_ = 0;
  mutable double sim_seconds_ = 0;
};

/// The discrepancy term of a comparison's V taken at one model for a scope, and put back at the
/// model it was taken at before when the scope ends (however it ends). A hypothesis is judged
/// by its own V: the calibrated relative discrepancy scales with the lines of the model under
/// test (differential: with their change from the baseline's model), not with those of the
/// model the comparison last fitted.
class ScopedDiscrepancyReference {
public:
  ScopedDiscrepancyReference(ModelComparison& cmp, const std::vector<std::vector<double>>& model_amplitude,
                             const std::vector<double>& gains);
  ~ScopedDiscrepancyReference();
  ScopedDiscrepancyReference(const ScopedDiscrepancyReference&) = delete;
  ScopedDiscrepancyReference& operator=(const ScopedDiscrepancyReference&) = delete;

private:
  ModelComparison& cmp_;
  std::vector<std::vector<double>> model_;
  std::vector<double> gains_;
};

/// Variance of the difference of two amplitudes |G + sum_l L_l e^{i phi_l}| whose phases phi_l are
/// independent and uniform in each (a recording's lines at no gear order leaking into a cell, in
/// the recording and in the model or baseline it is compared with): P - D, P = G^2 + sum_l L_l^2,
/// D the largest of G^2 and the L_l^2 [amplitude^2]. `leak_power_sum` = sum_l L_l^2,
/// `leak_power_max` = max_l L_l^2 (RecordingSpectra::alien_leak).
double unknown_phase_difference_variance(double gear_amplitude, double leak_power_sum, double leak_power_max);

/// The simulation cache key: every key of the configuration schema
/// (config/schema.hpp) with its value, so no key can be left out of it.
std::string builtin_config_key(const model::SimulationConfig& c);

} // namespace pw::diagnose
