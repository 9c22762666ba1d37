// Differential diagnosis: has a mesh stiffness or damping level changed since the baseline?
// (docs/diagnose.md section 6b item 7.) Against a baseline the nuisance levels are the
// baseline's fitted values, and the recording's nuisance fit moves them freely: a level the
// gears really changed (a lubricant that lost its damping, a stiffness drop) is then absorbed
// and the verdict is "no missing physics". So, like a sensor's gain (sensor_change.hpp), each
// level is tested on the baseline's own terms: the baseline's model with that one level times
// rho, everything else (the other levels, the housing gains) as the baseline's, its compared
// amplitudes a_i(theta) + e_i (compare.hpp: the baseline recording's lines at rho = 1).
#pragma once

#include "diagnose/fit_context.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace pw::diagnose {

/// One nuisance level fitted alone from the baseline's value, and the scores that decide
/// whether its change is a finding.
struct LevelChange {
  std::string candidate;       ///< the nuisance candidate: "stiffness_level", "damping_level"
  std::string parameter;       ///< its configuration key
  double baseline_value = 0;   ///< the baseline's fitted value
  double rho = 1;              ///< [-] fitted value / baseline value
  double ln_rho_std = 0;       ///< standard error of ln rho (curvature of the fit half's chi2)
  double chi2_fit_1 = 0;       ///< fit half at rho = 1 (the baseline's model)
  double chi2_fit = 0;         ///< fit half at the fitted rho
  double chi2_held_1 = 0;      ///< held-out half at rho = 1
  double chi2_held = 0;        ///< held-out half at the fitted rho (the diagnosis's V; the verdict's
                               ///< test at its own model is the caller's, as for any lead)
  bool at_box_edge = false;    ///< rho within the final bracket of the nuisance box's edge: a bound, not a size
  bool failed = false;         ///< the solver failed at every point of the scan
  int simulations = 0;         ///< simulations the search ran (cache hits not counted)
  std::vector<double> scan_rho, scan_chi2_fit;  ///< the coarse scan: rho and the fit half's chi2
  model::SimulationConfig config;  ///< the baseline's model at the fitted rho
  std::vector<std::string> overrides;  ///< `--set` of the fitted value
};

/// Points of the coarse scan over ln rho (equal cells of the nuisance box; the chi2 of a
/// stiffness level is not unimodal: it moves resonances through the lines), and the
/// golden-section reductions of the bracket around the best of them (0.618^12 of a cell:
/// 0.3 % of it, below a level's 5 % recalibration threshold).
inline constexpr int kLevelScanPoints = 7;
inline constexpr int kLevelGoldenIterations = 12;
/// Step of the curvature in ln rho: 2 %, the nuisance secants' step (screening.hpp); a
/// smaller one meets the solver's tolerance.
inline constexpr double kLevelCurvatureStep = 0.02;

/// The nuisance candidate `index` of ctx (its one parameter) fitted alone on the fit half of
/// ctx.cmp (which holds a baseline; ctx.base carries the baseline's values) with the housing
/// `gains` given: the scan, the golden section in the best cell and its neighbours, the
/// curvature, both halves at rho = 1 and at the fit. The scan runs on ctx.threads threads.
/// A nuisance candidate of more than one parameter is not a level: failed.
LevelChange fit_level_change(const FitContext& ctx, std::size_t index, const std::vector<double>& gains);

/// How far a level's ln rho must lie from 0 to be a change since the baseline: beyond what the
/// noise and the rig's healthy scatter of that level allow at false-alarm probability alpha
/// (two-sided).
///
/// Why the scatter: the noise-only standard error (ln_rho_std, the fit half's chi2 curvature)
/// knows nothing of what moves a fitted level between two healthy recordings of one rig, and on
/// indepsim3's setB5 a healthy control's damping read x1.051 +- 0.013 of its baseline's (4
/// standard errors; session 62). A calibration of n >= 2 healthy recordings measures that
/// scatter: s, the sample std of ln(level) over them (nuisance_level_spread_ln, calibration.hpp).
/// Each of two healthy recordings carries it, so their ratio carries variance 2 s^2. The
/// calibration's recordings lie at different operating points, so s also holds the level's
/// speed-dependent model-form error, which cancels in a ratio at one operating point: 2 s^2 is
/// then an upper bound, and the test conservative. The variance is estimated from n - 1 degrees
/// of freedom, so the quantile is Student's t at the Welch-Satterthwaite effective number
/// nu = (a + b)^2 / (b^2 / (n - 1)), a = ln_rho_std^2 (known), b = 2 s^2 -- the normal quantile
/// when b = 0 (no calibration, or one recording: the test as it was).
struct LevelMoveTest {
  double scatter_ln = 0;  ///< sqrt(2) s: the healthy scatter of ln rho [-]
  double ln_std = 0;      ///< sqrt(ln_rho_std^2 + 2 s^2) [-]
  double dof = 0;         ///< the effective degrees of freedom (+infinity without scatter)
  double quantile = 0;    ///< t_{alpha/2}(dof), or z_{alpha/2}
  double threshold_ln = 0;  ///< quantile * ln_std: |ln rho| beyond it is a change
};
LevelMoveTest level_move_test(double ln_rho_std, double spread_ln, int recordings, double alpha);

/// The healthy scatter a level's change since a reference at the recording's operating point is
/// judged against: `calibration_spread_ln` (the calibration's spread of ln(level) over its
/// recordings, 0 without one) for the damping level, none for the stiffness level.
///
/// Why the two differ. The calibration's recordings lie at different operating points, so their
/// spread holds mostly the level's dependence on the operating point (the model-form error the
/// level absorbs there), which cancels against a reference at the recording's operating point
/// (speed within the mesh damping ratio: the same dynamic amplification; power within 5 %);
/// from two recordings it is also one degree of freedom, whose t quantile (63.7 at alpha = 0.01)
/// makes any change "within the scatter": indepsim4 setD4's stiffness x0.75 read x0.771 +- 0.0006
/// of its healthy reference at the same speed, against a threshold of |ln rho| > 34
/// (docs/diagnose-log.md, session 69). What is left between two healthy runs at one operating
/// point is the run-to-run change of the physics:
///   * the mesh stiffness is the steel teeth's: Young's modulus moves by -0.03 %/K (1.5 % over a
///     50 K change of the gear body's temperature), the tooth's bending, shear, compression and
///     foundation compliances are linear in the load, and the Hertzian approach of a line contact
///     nearly so (under 1 % over the reference's 5 % of load): all within kRecalibration (5 %),
///     which a change must exceed anyway;
///   * the mesh damping is the lubricant film's, whose viscosity halves with every 15-20 K of oil
///     temperature (Walther's law, ASTM D341, for mineral gear oils): no such bound, so the
///     calibration's spread, an upper bound of that scatter, stays.
/// `level_candidate`: "stiffness_level" or "damping_level".
double healthy_level_scatter_ln(const std::string& level_candidate, double calibration_spread_ln);

/// What a level's ratio rho means when the baseline's value is an edge of its box, not a fit
/// (`end`: +1 the upper edge, -1 the lower; 0: a fit, empty text). The baseline's own fit asked
/// for a level beyond the edge, so against that level the recording's (fitted inside its box)
/// would read a smaller ratio (upper edge) or a larger one (lower edge): rho is a bound on the
/// change, not its size. Why: on the independent corpus a stiffness level x0.75 read x0.871 of a
/// baseline whose stiffness.scale sat at its upper bound 2 (indepsim fresh4p rec_13, session 56),
/// and the summary stated it as a size.
std::string one_sided_ratio_note(const std::string& parameter, double baseline_value, double rho, int end);

} // namespace pw::diagnose
