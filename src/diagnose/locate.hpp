// Locate: where does the recording differ from the model? (docs/diagnose.md §3)
//
// From the whitened per-cell residuals rho_i of both halves (compare.hpp):
//  1. families: each cell carries the lines of one or more families
//     (kinematics.hpp). A family's excess z_F = sum_{i in F} (rho_i^2 - 1) /
//     sqrt(2 n_F) over its cells of both halves is ~N(0, 1) when the model
//     explains the data (rho_i^2 has mean 1 and, for Gaussian residuals,
//     variance 2); its share of the chi-square excess splits a shared cell
//     equally among its families. Families are ranked by z;
//  2. the cells (lines) with the largest rho^2, with every kinematic label;
//  3. the rotating component behind the leading family (sun relative to the
//     carrier, a planet's spin, the carrier, the input shaft) and the
//     angular position of the recording's synchronous average over that
//     component's period. The amplitudes compared carry no phase, and a
//     recording with encoder and tacho on the input shaft still has no
//     carrier-angle reference, so the position is relative to the start of
//     the recording and the tooth index is reported as unidentifiable;
//  4. the input-shaft orders with the largest excess (torque-ripple order).
#pragma once

#include "diagnose/candidates/candidate.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/kinematics.hpp"
#include "diagnose/planet_pattern.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

struct LocatedLine {
  double order = 0;                 ///< carrier orders
  double frequency_Hz = 0;
  std::string channel;
  Quantity quantity = Quantity::SunSpeed;  ///< the channel's
  double chi2 = 0;                  ///< rho^2, mean of both halves
  double recording_amplitude = 0;   ///< mean of both halves
  double model_amplitude = 0;       ///< model (with gain)
  std::vector<std::string> labels;  ///< e.g. "1 f_m + 2 f_sr (sun)"
};

struct FamilyEvidence {
  Component family = Component::Mesh;
  double z = 0;                     ///< excess z-score over all channels and both halves
  double share = 0;                 ///< share of the total chi-square excess
  int cells = 0;                    ///< cells (per channel, both halves)
  std::string strongest_channel;    ///< channel with the largest excess in this family
  std::string meaning;              ///< family_meaning()
  double frequency_Hz = 0;          ///< the component's fundamental
  double carrier_orders = 0;        ///< the same in carrier orders
};

struct RotationEvidence {
  Component component = Component::Sun;
  std::string channel;              ///< recording channel averaged
  int period_mesh_cycles = 0;       ///< Zs, Zp or Zr
  int averages = 0;                 ///< periods averaged
  double peak_angle_rad = 0;        ///< the component's rotation angle at the energy peak, from the reference
  double peak_to_mean = 0;          ///< 1 = flat
  std::string reference;            ///< what the angle is measured from
  int tooth = -1;                   ///< -1: unidentifiable
  std::string tooth_note;
  std::vector<double> tsa;          ///< the recording's synchronous average (for plots)
  int samples_per_cycle = 0;
};

struct Location {
  std::vector<FamilyEvidence> families;   ///< ranked, largest z first
  std::vector<LocatedLine> lines;         ///< strongest cells, largest chi2 first
  std::vector<RotationEvidence> rotations;
  std::vector<double> input_orders;       ///< input-shaft orders with the largest excess
  /// The speed channels' mesh-harmonic excess by the planets' pattern order (planet_pattern.hpp).
  PlanetPattern planet_pattern;
  LocatedEvidence evidence;               ///< the summary candidates use
  double significance_z = 0;              ///< z above which a family counts as located
  double excess = 0;                      ///< total chi-square excess (both halves)
  /// The family of the candidate whose signature (its screening direction in
  /// the residual space, diagnose.hpp) explains most of the residual: with
  /// windows of one revolution the lines of different families share bins, so
  /// the model's own signatures locate better than the labels; -1 before the
  /// screening.
  int screened_family = -1;
  std::string screened_candidate;
  double screened_S = 0;
};

struct LocateOptions {
  int max_lines_reported = 15;
  int samples_per_cycle = 16;
  double family_alpha = 0.01;   ///< family-wise false-alarm probability (Bonferroni over the 5 families)
  int rotation_family = -1;     ///< component for the synchronous average (-1: the leading family by z)
};

/// Locates the residual of a model scored on both halves (fit, held_out) with
/// amplitudes model_amplitude ([channel][bin], gains as in the scores).
Location locate(const ModelComparison& cmp, const WindowScore& fit, const WindowScore& held_out,
                const std::vector<std::vector<double>>& model_amplitude, const LocateOptions& options = {});


} // namespace pw::diagnose
