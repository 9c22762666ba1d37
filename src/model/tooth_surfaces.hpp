// State of every loaded tooth flank: its profile deviation (material removed
// by wear or damage, [m] along the flank normal = along the line of action)
// and its stiffness factor. This is the one place where tooth-level state
// lives; the dynamics reads it, the wear model (and diagnosis fits) write it.
//
// A flank set belongs to one gear flank family: the sun's drive flanks (met by
// every planet's sun mesh), each planet's sun-side and ring-side flanks (two
// different flanks of the same teeth) and the ring's flanks (met by every
// planet's ring mesh). Deviations are sampled on a uniform grid of microelements
// over the mesh's active roll range [xi_min, xi_max] (mesh.hpp), so that the
// grid is the same for every tooth of the family.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace pw::model {

class FlankSet {
public:
  FlankSet() = default;
  /// `teeth` teeth, `elements` >= 2 microelements per flank over [xi_min, xi_max].
  FlankSet(int teeth, int elements, double xi_min_m, double xi_max_m);

  int teeth() const { return teeth_; }
  int elements() const { return elements_; }
  double xi_min_m() const { return xi_min_; }
  double xi_max_m() const { return xi_max_; }
  /// Roll coordinate of element e's centre [m].
  double element_xi_m(int e) const { return xi_min_ + (e + 0.5) * dxi_; }
  double element_width_m() const { return dxi_; }

  /// Where a roll coordinate falls on the element-centre grid: between centres i and i + 1 at
  /// fraction f, or beyond an end centre (`clamped` then holds that end's index). The same for
  /// every flank set of one grid (same_grid), so a mesh computes it once for both its flanks.
  struct GridPoint {
    int i = 0;
    double f = 0;
    int clamped = -1;  ///< the end element's index beyond an end centre, else -1
  };
  GridPoint grid_point(double xi_m) const {
    const double u = (xi_m - xi_min_) * inv_dxi_ - 0.5;  // position in element-centre units
    if (u <= 0) return {0, 0.0, 0};
    if (u >= elements_ - 1) return {0, 0.0, elements_ - 1};
    const int i = static_cast<int>(u);
    return {i, u - i, -1};
  }
  /// Deviation of `tooth` at a grid point [m]: linear between element centres, constant beyond
  /// the end centres.
  double deviation_m(int tooth, const GridPoint& g) const {
    const double* d = tooth_deviation(tooth);
    if (g.clamped >= 0) return d[g.clamped];
    return (1 - g.f) * d[g.i] + g.f * d[g.i + 1];
  }
  /// Deviation of `tooth` at roll coordinate xi [m]. O(1), no allocation; inline because the
  /// time step calls it for both flanks of every pair.
  double deviation_m(int tooth, double xi_m) const { return deviation_m(tooth, grid_point(xi_m)); }
  /// Element index containing xi (clamped to [0, elements - 1]). Inline: the wear model calls
  /// it for both flanks of every loaded pair at every step.
  int element_at(double xi_m) const {
    // floor(u) clamped, with the floor taken by truncation inside the grid: the default x86-64
    // build has no rounding instruction, and the library's floor was a call per flank per step.
    // The same index for every u (NaN included: element 0).
    const double u = (xi_m - xi_min_) / dxi_;
    if (!(u > 0)) return 0;
    if (u >= elements_ - 1) return elements_ - 1;
    return static_cast<int>(u);
  }
  /// True when `other` has the same microelement grid (range and count): an xi then falls in
  /// the same element of both.
  bool same_grid(const FlankSet& other) const {
    return elements_ == other.elements_ && xi_min_ == other.xi_min_ && dxi_ == other.dxi_;
  }

  double* tooth_deviation(int tooth) {
    pristine_ = false;
    return deviation_.data() + static_cast<std::size_t>(tooth) * elements_;
  }
  const double* tooth_deviation(int tooth) const {
    return deviation_.data() + static_cast<std::size_t>(tooth) * elements_;
  }
  std::vector<double>& deviations() {  ///< teeth x elements, row-major
    pristine_ = false;
    return deviation_;
  }
  const std::vector<double>& deviations() const { return deviation_; }
  double stiffness_factor(int tooth) const { return factor_[tooth]; }
  void set_stiffness_factor(int tooth, double f) {
    pristine_ = false;
    if (f != 1.0) unit_factors_ = false;
    factor_[tooth] = f;
  }
  /// True while every tooth's stiffness factor is 1 (no factor other than 1 was ever set): the
  /// time step then skips the factors' look-ups and multiplications, which would be by exactly 1
  /// (worn flanks keep their factors: wear changes the deviations only).
  bool unit_factors() const { return unit_factors_; }
  /// True while nothing has had write access to the deviations or factors since construction:
  /// every deviation is then 0 and every factor 1, and the time step skips their look-ups
  /// (same numbers: adding 0 and multiplying by 1 are exact). Any non-const accessor clears it
  /// for good, whether or not it writes.
  bool pristine() const { return pristine_; }
  /// Adds a uniform deviation to every element of one tooth [m].
  void add_uniform(int tooth, double deviation_m);
  double max_deviation_m() const;

private:
  int teeth_ = 0, elements_ = 0;
  double xi_min_ = 0, xi_max_ = 0, dxi_ = 0;
  double inv_dxi_ = 0;  // 1 / dxi_: deviation_m multiplies (it runs for every pair at every step)
  std::vector<double> deviation_;
  std::vector<double> factor_;
  bool pristine_ = true;
  bool unit_factors_ = true;
};

struct ToothSurfaces {
  FlankSet sun;                            ///< sun drive flanks (sun-planet roll grid)
  std::vector<FlankSet> planet_sun_side;   ///< per planet (sun-planet roll grid)
  std::vector<FlankSet> planet_ring_side;  ///< per planet (planet-ring roll grid)
  FlankSet ring;                           ///< ring flanks (planet-ring roll grid)
};

} // namespace pw::model
