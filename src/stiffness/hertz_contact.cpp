#include "stiffness/hertz_contact.hpp"

#include <cmath>
#include <numbers>

namespace pw::stiffness {

double contact_modulus(double E1, double nu1, double E2, double nu2) {
  return 1.0 / ((1 - nu1 * nu1) / E1 + (1 - nu2 * nu2) / E2);
}

HertzLineContact hertz_line_contact(double w, double R, double Es) {
  HertzLineContact h;
  if (w <= 0) return h;
  h.half_width_m = std::sqrt(4 * w * R / (std::numbers::pi * Es));
  h.max_pressure_Pa = 2 * w / (std::numbers::pi * h.half_width_m);
  h.mean_pressure_Pa = w / (2 * h.half_width_m);
  return h;
}

} // namespace pw::stiffness
