// Differential diagnosis: has a housing sensor's path changed since the baseline?
// (docs/diagnose.md section 6b item 6.) A sensor whose sensitivity, mounting, cable or
// conditioning changed reads everything it read in the baseline rho times as strongly, the
// model-form part of it too; so the hypothesis is the baseline's own compared amplitudes in that
// channel times rho, every other channel as the baseline's.
#pragma once

#include "diagnose/compare.hpp"

#include <vector>

namespace pw::diagnose {

/// rho fitted for one housing channel, and the scores that decide whether it is a finding.
struct SensorScale {
  double rho = 1;          ///< [-] the channel reads the baseline's lines rho times as strongly
  double ln_rho_std = 0;   ///< standard error of ln rho (curvature of the fit half's chi2)
  double chi2_fit_1 = 0;   ///< fit half at rho = 1 (the baseline as it was)
  double chi2_fit = 0;     ///< fit half at the fitted rho
  double chi2_held_1 = 0;  ///< held-out half at rho = 1
  double chi2_held = 0;    ///< held-out half at the fitted rho
  double bound_held = 0;   ///< 1 - alpha/2 Monte-Carlo null of chi2_held (one fitted parameter): min(folded, linear)
  double bound_held_folded = 0;  ///< the same with FidelityDraw::Folded alone (the report's)
  /// rho within the search's final bracket of kMinSensorScale or kMaxSensorScale: the channel
  /// reads more than 12x off the baseline, a broken channel rather than a changed path, and rho
  /// is only a bound.
  bool at_bracket_edge = false;
};

/// The range rho is searched over [-]: a sensor off by more than 12x is a broken channel (wrong
/// unit, a lost or shorted cable, a sensor off its mount), not a drift of its path.
inline constexpr double kMinSensorScale = 1.0 / 12, kMaxSensorScale = 12;

/// Model amplitudes ([channel][bin], housing at gain 1) whose compared amplitudes in housing
/// channel ch are rho (g0 a_i + e_i): the bins of ch's cells set to rho a + (rho - 1) e / g0
/// (ModelComparison::score adds the baseline's offset e to g0 a). Other channels unchanged.
std::vector<std::vector<double>> scaled_housing(const ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                                                double g0, int ch, double rho);

/// rho fitted on the fit half of `cmp` (which must hold a baseline) to the baseline's model
/// `amp` at the baseline's gains: golden section in ln rho over [kMinSensorScale,
/// kMaxSensorScale], its standard error from the curvature as compare.cpp profiles a housing
/// gain; then both halves at rho = 1 and at the fit, and the held-out null at the fit.
///
/// Every score is taken with the hypothesis's own V: the discrepancy term at `amp`
/// (ScopedDiscrepancyReference; the caller's reference is back when this returns). Under the
/// hypothesis the gears are as in the baseline, so the model is the baseline's at this speed,
/// its change from the baseline's model is the speed's alone, and every other channel is judged
/// against the baseline recording with the two recordings' noise. Taken at the nuisance fit's
/// model instead (session 37), the budget sat on that model's change from the baseline's: a
/// stiffness level 1.4 % lower, with the baseline's 95 % relative budget on the sun encoder's
/// mesh lines (its model's lines 17 times the rig's), let a 22 % rise of those lines (z ~ 170
/// against the noise) pass as "as in the baseline"; a stiffness change x0.85 and a friction
/// change were named the housing sensor's gain, and a true gain x0.6 read x0.32 (fresh corpus
/// rec_15, rec_16, rec_08; docs/diagnose-log.md, session 38).
SensorScale fit_sensor_scale(ModelComparison& cmp, const std::vector<std::vector<double>>& amp,
                             const std::vector<double>& gains, int ch, double alpha);

} // namespace pw::diagnose
