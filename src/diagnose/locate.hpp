// Locate: where does the recording differ from the model? (docs/diagnose.md §3)
//
// The residual e_c(t) = recording - model of every channel, band-limited to
// the analysed band, is examined over the whole usable recording:
//  1. its Hann periodogram normalized by the channel's noise variance (white
//     noise reads Exp(1) per bin) at the lines of each kinematic family
//     (kinematics.hpp); a family's excess
//        z_F = sum_lines (P_l - 1) / sqrt(n_lines)
//     is ~N(0, 1) when the model explains the data (mean 1, variance 1 per
//     line), so families are ranked by z_F;
//  2. the individual lines with the largest excess, with their kinematic
//     labels (one bin may carry lines of several families);
//  3. synchronous averages of the residual over the sun (Zs mesh cycles),
//     a planet (Zp) and the carrier (Zr): the energy peak gives the angular
//     position and, through the assembly phases, the tooth;
//  4. the input-shaft orders of the strongest lines j f_s in the speed
//     channels (low-frequency speed fluctuation).
#pragma once

#include "diagnose/candidates/candidate.hpp"
#include "diagnose/compare.hpp"
#include "diagnose/kinematics.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

struct LocatedLine {
  double frequency_Hz = 0;
  std::string channel;
  double excess = 0;               ///< P - 1 in noise units (P: normalized periodogram)
  std::vector<std::string> labels; ///< kinematic labels within half a bin, e.g. "1 f_m + 2 f_sr (sun)"
};

struct FamilyEvidence {
  Component family = Component::Mesh;
  double z = 0;                    ///< excess z-score over all channels
  int lines = 0;                   ///< lines tested (per channel, summed)
  std::string strongest_channel;   ///< channel with the largest share of the excess
  std::string meaning;             ///< family_meaning()
};

struct RotationEvidence {
  Component component = Component::Sun;  ///< Sun, Planet or Carrier
  std::string channel;             ///< channel whose residual TSA was used
  int planet = 0;                  ///< that channel's planet
  int averages = 0;                ///< revolutions averaged
  double peak_mesh_cycle = 0;      ///< u of the energy peak, mod period
  double peak_angle_rad = 0;       ///< the component's rotation angle at the peak (2 pi u / period)
  double peak_to_mean = 0;         ///< 1 = flat
  int tooth = -1;                  ///< nearest tooth (sun: of the sun; planet: of that planet; carrier: of the ring)
  std::vector<double> tsa_residual;  ///< the residual TSA (for plots)
  int samples_per_cycle = 0;
};

struct Location {
  std::vector<FamilyEvidence> families;   ///< ranked, largest z first
  std::vector<LocatedLine> lines;         ///< strongest lines, largest excess first
  std::vector<RotationEvidence> rotations;  ///< sun, planet, carrier
  std::vector<double> input_orders;       ///< strongest input-shaft orders in the speeds
  LocatedEvidence evidence;               ///< the summary candidates use
  double significance_z = 0;              ///< the z above which a family counts as located
};

struct LocateOptions {
  int max_sideband = 10;
  int max_lines_reported = 12;
  int samples_per_cycle = 16;
  double family_alpha = 0.01;   ///< family-wise false-alarm probability (Bonferroni over the families)
};

/// Locates the residual of `sim` (covering [first, last] of the recording)
/// against the recording. sensor_gain is used for housing channels.
Location locate(const ModelComparison& cmp, const SimulatedSignals& sim, const model::SimulationConfig& config,
                double sensor_gain, const LocateOptions& options = {});

/// Upper 1 - alpha quantile of the standard normal (Acklam's rational approximation refined by one Newton step).
double normal_quantile(double p);
/// Upper quantile of chi2(nu): the value exceeded with probability alpha (Wilson-Hilferty).
double chi2_quantile(double nu, double alpha);

} // namespace pw::diagnose
