#include "model/tooth_surfaces.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace pw::model {

FlankSet::FlankSet(int teeth, int elements, double xi_min_m, double xi_max_m)
    : teeth_(teeth), elements_(elements), xi_min_(xi_min_m), xi_max_(xi_max_m) {
  require(teeth >= 1, "teeth", "a flank set needs >= 1 tooth, got ", teeth);
  require(elements >= 2, "wear.elements_per_flank", "must be >= 2, got ", elements);
  require(xi_max_m > xi_min_m, "flank range", "empty active roll range [", xi_min_m, ", ", xi_max_m, "] m");
  dxi_ = (xi_max_ - xi_min_) / elements_;
  inv_dxi_ = 1.0 / dxi_;
  deviation_.assign(static_cast<std::size_t>(teeth_) * elements_, 0.0);
  factor_.assign(teeth_, 1.0);
}

void FlankSet::add_uniform(int tooth, double deviation_m) {
  double* d = tooth_deviation(tooth);
  for (int e = 0; e < elements_; ++e) d[e] += deviation_m;
}

double FlankSet::max_deviation_m() const {
  return deviation_.empty() ? 0.0 : *std::max_element(deviation_.begin(), deviation_.end());
}

} // namespace pw::model
