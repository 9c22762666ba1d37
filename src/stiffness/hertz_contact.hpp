// Hertzian line contact of two cylinders (Johnson, Contact Mechanics, 1985,
// §4.2): the contact pressure of a loaded tooth pair, and the equivalent
// radius of two involute flanks at their contact point.
#pragma once

namespace pw::stiffness {

struct HertzLineContact {
  double half_width_m = 0;       ///< a
  double max_pressure_Pa = 0;    ///< p0 = 2 F' / (pi a) = sqrt(F' E* / (pi R))
  double mean_pressure_Pa = 0;   ///< F' / (2a) = (pi/4) p0
};

/// Contact modulus E* [Pa]: 1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2.
double contact_modulus(double E1_Pa, double nu1, double E2_Pa, double nu2);

/// Equivalent radius [m]: 1/R = 1/rho_a + 1/rho_b (external, convex-convex)
/// or 1/rho_a - 1/rho_b (internal: the ring flank is concave, rho_b > rho_a). Inline for the
/// mesh-load summary's per-pair, per-step use (see geometry::curvature_radius_a).
inline double equivalent_radius(double rho_a_m, double rho_b_m, bool internal) {
  return internal ? 1.0 / (1.0 / rho_a_m - 1.0 / rho_b_m) : 1.0 / (1.0 / rho_a_m + 1.0 / rho_b_m);
}

/// a = sqrt(4 F' R / (pi E*)) for load per unit width F' [N/m] >= 0 (Johnson Eq. 4.45).
HertzLineContact hertz_line_contact(double load_per_width_N_m, double radius_m, double contact_modulus_Pa);

} // namespace pw::stiffness
