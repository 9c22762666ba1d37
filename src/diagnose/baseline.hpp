// Differential diagnosis (docs/diagnose.md §6b): a healthy baseline recording at the same
// operating point tells what the model cannot reproduce there. The model is fitted to the
// baseline (nuisance parameters only, as in calibration); the per-cell difference between the
// baseline's de-biased amplitude and that fitted model is its model-form error e_i at this
// operating point. Diagnosing a recording against "model + e" compares the recording's change
// from the baseline with the model's change from the baseline's fitted values:
//   A_rec,i - (M_i(theta) + e_i) = (A_rec,i - A_base,i) - (M_i(theta) - M_i(theta_base)),
// so a model-form error that is the same in both recordings cancels to first order. Valid when
// e does not change between the two: the same rig, sensors and operating point (same speed
// and load; the speed difference enters only through the model), and a fault small enough
// that the model-form error does not depend on it. What it cannot do: see a fault that was
// already in the baseline.
#pragma once

#include "diagnose/calibration.hpp"
#include "diagnose/diagnose.hpp"

#include <map>
#include <string>
#include <vector>

namespace pw::diagnose {

/// How the model's change from the baseline's model reaches the compared amplitude
/// (docs/diagnose.md section 6b item 9).
enum class BaselineTransfer {
  /// Unscaled: A_rec - A_base against M(theta) - M(theta_base).
  Additive,
  /// Scaled per cell by the rig's measured-to-model ratio of the baseline's lines at that
  /// frequency (BaselineCell::transfer, line_ratio_transfer): a transfer the model gets wrong by
  /// a factor gets a fault's change near that frequency wrong by the same factor.
  LineRatio,
};

struct BaselineReference {
  std::vector<std::string> overrides;  ///< the nuisance values fitted to the baseline (`--set` lines)
  std::vector<BaselineCell> cells;     ///< per channel and carrier order: offset e_i and its variance
  /// The baseline's own discrepancy budgets (Calibration::budgets of a calibration on it alone):
  /// CompareOptions::discrepancy, applied to the model's change from the baseline's model.
  std::vector<DiscrepancyEntry> budgets;
  /// Where the baseline's lines tested the model (line_coverage, calibration.hpp):
  /// DiagnoseOptions::line_coverage when no calibration gives one.
  std::vector<LineCoverage> coverage;
  /// The baseline's fitted gain per compared channel name (1 for channels without one; housing
  /// sensors in m/s^2 per N): DiagnoseOptions::baseline_gains.
  std::map<std::string, double> gains;
  double speed_rpm = 0;                ///< the baseline's mean input speed
  double revolutions = 0;              ///< carrier revolutions per half of its analysis
  Verdict noise_test = Verdict::NoMissingPhysics;  ///< the baseline's own noise test (for the report)
  std::string summary;                 ///< one sentence on the baseline and its fit
  /// The baseline's nuisance values that ended at an edge of their box ("stiffness.scale at its
  /// upper bound 2"): limits, not fits. The model the recording's change is judged by then cannot
  /// reach the baseline's level, and a finding's size is stated against that limited model.
  std::vector<std::string> at_bound;
  /// The same parameters by configuration key: +1 at the upper end of the box, -1 at the lower
  /// (DiagnoseOptions::baseline_limits).
  std::map<std::string, int> limits;
  /// Its lines at no gear order by channel (CompareOptions::baseline_alien_lines).
  BaselineAlienLines alien_lines;
};

/// How far a healthy reference's operating point lies from the recording's, relative, and whether
/// it is "the same operating point" (docs/diagnose.md §6a item 6, §6b):
///  * speed within the mesh damping ratio zeta, relative: every line then keeps its place
///    relative to every mesh resonance to within that resonance's half-power half-width
///    (zeta f_n), so the dynamic amplification the reference was measured through is the one the
///    recording sees;
///  * power within kRecalibration (5 %), relative: the lines and their model-form error scale
///    with the load (parametric excitation), and a level change below kRecalibration is what the
///    diagnosis already treats as within the model's own fidelity.
struct OperatingPointDistance {
  double speed = 0;  ///< |n_ref - n| / n [-]
  double power = 0;  ///< |P_ref - P| / P [-]
  bool same = false;
};
/// Speeds in rpm, powers in W (both > 0 for the recording), zeta the mesh damping ratio [-].
OperatingPointDistance operating_point_distance(double speed_rpm, double power_W, double reference_speed_rpm,
                                                double reference_power_W, double zeta);

/// "<name> at its upper|lower bound <value>" for each parameter at a bound (the nearer end;
/// sensor gains have no box and are skipped).
std::vector<std::string> bound_texts(const std::vector<FittedParameter>& parameters);
/// The same parameters as bound_texts, by name: +1 at the upper bound, -1 at the lower.
std::map<std::string, int> bound_ends(const std::vector<FittedParameter>& parameters);

/// Offset of one cell: the mean over both halves of the de-biased amplitude sqrt(max(A^2 - s^2, 0))
/// (the estimator the comparison uses for the recording's own variances) minus the fitted model's
/// amplitude; its variance is that of a mean of two independent halves, (D_fit + D_held) / 4.
BaselineCell baseline_cell(const CalibrationCell& c);

/// Sets each cell's transfer to the ratio of the baseline's de-biased amplitude to its fitted
/// model's, measured where both lines stand above z_{1-alpha/2} noise standard deviations and
/// interpolated (linearly in the logarithm, over carrier order, within a channel) between the
/// nearest such cells elsewhere; 1 on a channel without one. Each offset becomes the baseline's
/// amplitude minus transfer x model, so the baseline's own lines are compared as before.
/// cells[i] is baseline_cell(source[i]) (fit_baseline builds them so); source gives the noise.
void line_ratio_transfer(std::vector<BaselineCell>& cells, const std::vector<CalibrationCell>& source, double alpha);

/// Fits the nuisance parameters to the healthy `baseline` (fit_healthy with `weighting`) and
/// returns the offsets the diagnosis of another recording takes as CompareOptions::baseline.
/// The noise test and its sentence are the noise-weighted fit's under either weighting.
BaselineReference fit_baseline(const Recording& baseline, const model::SimulationConfig& config,
                               DiagnoseOptions options, BaselineTransfer transfer = BaselineTransfer::Additive,
                               HealthyFit weighting = HealthyFit::Noise);

} // namespace pw::diagnose
