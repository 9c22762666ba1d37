// Planet pattern: which pattern over the planets the excess at the mesh harmonics of the speed
// channels needs (docs/diagnose.md §3 item 5).
//
// Planet i meshes i Zs / N cycles after planet 0 (equally spaced planets, Zs sun teeth, N planets;
// Parker & Lin 2004, J. Mech. Des. 126:365). The torque the sun and the carrier feel at mesh
// harmonic h sums the planets' mesh forces with the phases exp(-2 pi i h i Zs / N). Equal planets
// cancel unless h Zs is a multiple of N; planets that differ by eps_i (a load share, a mesh
// stiffness, a pin's offset) leave N times the DFT of eps at k = h Zs mod N. So a line at mesh
// harmonic h in a speed channel needs a planet pattern of order k(h) = min(r, N - r),
// r = h Zs mod N (eps real: k and N - k are one order), whatever the stiffness law and whatever
// the rig's transfer to the sensor:
//   * k = 0 only: something every planet shares (a level, a profile, the friction);
//   * k = 1 only: a first-order pattern, as a carrier runout makes (eps_i ~ cos(psi_i - phi));
//   * k >= 2: not a first-order pattern; one planet alone (a pin error, a planet's defect) fills
//     every k.
// Stationary patterns only: a defect that meets the planets in turn (a sun or ring tooth) adds
// sidebands, not mesh harmonics, and is read by the families (§3 item 1). With N | Zs (planets in
// phase) every h maps to k = 0 and the split says nothing; it is then not made.
#pragma once

#include "diagnose/kinematics.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

/// k(h) = min(r, N - r), r = h Zs mod N (h >= 1, Zs >= 1, N >= 1).
int planet_pattern_order(int mesh_harmonic, int sun_teeth, int planets);

/// The excess of one pattern order.
struct PatternOrderExcess {
  int order = 0;                 ///< k
  double excess = 0;             ///< sum of rho^2 - 1 over its cells, both halves [-]
  int cells = 0;                 ///< cells (per speed channel, both halves)
  double z = 0;                  ///< excess / sqrt(2 cells): ~N(0, 1) when the model explains them
  std::vector<int> harmonics;    ///< the mesh harmonics h analysed, ascending
};

struct PlanetPattern {
  /// false: planets in phase (N | Zs), a single planet, or no speed channel's mesh harmonic analysed.
  bool applies = false;
  std::vector<PatternOrderExcess> orders;  ///< k = 0 .. N/2
  /// z above which an order counts: the upper alpha / (number of orders) normal quantile
  /// (Bonferroni over the orders, as the families are over theirs).
  double significance_z = 0;
};

/// One mesh-harmonic cell of a speed channel: its harmonic h and its excess rho^2 - 1 in each half.
struct MeshHarmonicCell {
  int harmonic = 0;
  double excess[2] = {0, 0};
};

/// The split of `cells` by pattern order for a stage of `kin`'s teeth and planets, each order
/// tested at the family-wise false-alarm probability `alpha` (LocateOptions::family_alpha).
PlanetPattern planet_pattern(const std::vector<MeshHarmonicCell>& cells, const Kinematics& kin, double alpha);

/// A sentence on the orders whose z exceeds p.significance_z, and what they allow; "" when the
/// split does not apply or no order is significant.
std::string planet_pattern_text(const PlanetPattern& p);

} // namespace pw::diagnose
