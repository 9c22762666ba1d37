// Line coverage: at which frequencies a calibration compared the calibrated model's lines with
// a rig, and which part of a located excess lies elsewhere (docs/diagnose.md §6a item 13).
//
// A calibration measures the model-form discrepancy on the lines a healthy recording carries
// (calibration.hpp), and a budget carries it to other lines of the same family as a relative
// error. That presumes the model's transfer from the mesh to the sensor is as right at the
// other line's frequency as at the measured ones. Between two measured lines that is an
// interpolation; outside them it is an extrapolation past what any healthy recording tested:
// a rig's shaft mode, a speed loop or a mount resonance there changes a fault's lines by any
// factor and the calibration cannot know. A healthy stage with sequentially phased planets
// makes it common: its speed channels carry only the mesh harmonics that are multiples of the
// planet count (the others cancel over the planets, Parker & Lin 2004, J. Mech. Des. 126:365),
// while a planet-to-planet asymmetry (a pin position error, a carrier runout, one damaged
// tooth) brings the others back, below the lowest tested line.
//
// Nothing here changes a verdict: it states where the comparison was never tested and which
// healthy recording would test it.
#pragma once

#include "diagnose/locate.hpp"
#include "diagnose/recording.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

/// The frequency span of the lines a calibration's healthy recordings carried on one kind of
/// channel where the calibrated model had a line above the noise (the cells that measure the
/// relative discrepancy), with the input speed of the recording each end came from.
struct LineCoverage {
  Quantity quantity = Quantity::SunSpeed;
  double lowest_Hz = 0;          ///< [Hz]
  double lowest_speed_rpm = 0;   ///< input speed of the recording with the lowest line [rpm]
  double highest_Hz = 0;         ///< [Hz]
  double highest_speed_rpm = 0;  ///< [rpm]
  int lines = 0;                 ///< cells over all recordings
};

/// One located line outside the coverage of its kind of channel.
struct UncoveredLine {
  std::string channel;
  Quantity quantity = Quantity::SunSpeed;
  double frequency_Hz = 0;
  double order = 0;              ///< carrier order
  double excess = 0;             ///< rho^2 - 1, mean of both halves [-]
  /// Input speed at which a healthy recording would carry the nearest tested line (the same
  /// carrier order as the coverage's end) at this frequency [rpm]; 0 if the kind of channel has
  /// no tested line at all.
  double covering_speed_rpm = 0;
};

/// The part of a located excess at frequencies no tested line reached.
struct CoverageGap {
  bool known = false;            ///< false: no coverage was given (no calibration or baseline)
  double share = 0;              ///< of the located lines' excess, outside their coverage [-]
  std::vector<UncoveredLine> lines;  ///< outside, largest excess first
  std::vector<LineCoverage> coverage;  ///< what they were compared with
};

/// The coverage of `lines` against `coverage`: each located line whose frequency lies outside
/// [lowest_Hz - resolution_Hz / 2, highest_Hz + resolution_Hz / 2] of its kind of channel (or
/// whose kind has no tested line) is uncovered; lines weigh by their excess rho^2 - 1 (those at
/// or below 1 weigh nothing). `resolution_Hz` is the recording's cell spacing (carrier frequency
/// over the carrier revolutions of an analysis window): a line within half of it of a tested end
/// falls in the same cell as that end's line would, the recordings' speeds differing by their
/// estimation error (the same carrier order at 1552.5002 Hz against a tested 1552.5000 Hz).
CoverageGap coverage_gap(const std::vector<LocatedLine>& lines, const std::vector<LineCoverage>& coverage,
                         double resolution_Hz);

/// A sentence for the verdict: the uncovered share, the strongest uncovered lines and their
/// channels' tested spans, and the speed that would test the strongest one; "" if nothing is
/// uncovered or nothing is known.
std::string coverage_gap_text(const CoverageGap& gap);

} // namespace pw::diagnose
