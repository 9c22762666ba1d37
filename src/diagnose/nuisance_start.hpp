// Where the nuisance fit starts (docs/diagnose.md §5, step 3). The stiffness level moves the
// response through resonances, so chi2 is far from quadratic in it and LM, a local method, needs
// a start near the right basin: a coarse geometric scan over the first nuisance parameter's box
// (the others at their start values) picks it, unless the nominal model (every parameter
// 'absent') fits better. A rig element fitted as nuisance (calibration) then starts present or
// absent, whichever fits better: LM only accepts improvements, so it ends no worse than that.
// A later parameter flagged ParameterSpec::scan_at_start (a rig shaft's stiffness, which moves
// the shaft's mode through the lines) gets a scan of its own, the others held where they are,
// as fine as its ParameterSpec::scan_step_ratio asks.
// An earlier fit of the same recording with fewer parameters (a calibration's fit without its
// calibration-only rig elements) is a second start (nuisance_start_from), refined by the same
// flips and scans; the diagnosis fits from both and keeps the lower end (a lower start does not
// mean a lower end, docs/diagnose-log.md session 46).
// Pure over a chi2 function, so the choice is tested without simulating. Internal to src/diagnose.
#pragma once

#include "diagnose/candidates/candidate.hpp"

#include <functional>
#include <vector>

namespace pw::diagnose {

/// Points of the coarse scan, and how far inside the box it stays (factor on each end).
inline constexpr int kNuisanceScanPoints = 7;
inline constexpr double kNuisanceScanInset = 1.4;

/// Points of a geometric scan over [lo, hi] whose neighbours lie at most `step_ratio` apart
/// (ParameterSpec::scan_step_ratio), at least kNuisanceScanPoints; kNuisanceScanPoints when
/// step_ratio <= 1 (the coarse grid).
int scan_points(double lo, double hi, double step_ratio);

/// The grid a scan_at_start parameter is scanned over: geometric between its bounds pulled in by
/// kNuisanceScanInset (scan_points) on a log scale, uniform over its whole box at its scan_step
/// on a linear one.
std::vector<double> scan_grid(const ParameterSpec& p);

/// chi2 of the fit half at nuisance parameters x (thread-safe: the scan runs in parallel).
using NuisanceChi2 = std::function<double(const std::vector<double>& x)>;

/// The start of the nuisance fit for `specs` (the first one scanned, log-spaced over
/// [lower * inset, upper / inset]); `chi2_nominal` is the nominal model's chi2.
std::vector<double> nuisance_start(const std::vector<ParameterSpec>& specs, double chi2_nominal,
                                   const NuisanceChi2& chi2, int threads);

/// The start from `earlier`, a point of the same size as `specs` (an earlier fit's values, the
/// parameters it lacked at their 'absent' values), clamped into the boxes, then the rig elements'
/// flips and scans as for nuisance_start. Empty when the sizes differ.
std::vector<double> nuisance_start_from(const std::vector<ParameterSpec>& specs, const std::vector<double>& earlier,
                                        const NuisanceChi2& chi2, int threads);

} // namespace pw::diagnose
