#include "stiffness/iso6336.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pw::stiffness {

using geometry::GearKind;
using geometry::GearSpec;

namespace {

/// ISO 6336-1:2006 clause 9 (method B): basic rack factor C_B of one gear.
double basic_rack_factor(const GearSpec& g) {
  const double alpha_deg = g.pressure_angle_rad * 180.0 / std::numbers::pi;
  return (1.0 + 0.5 * (1.2 - g.dedendum_coef)) * (1.0 - 0.02 * (20.0 - alpha_deg));
}

} // namespace

IsoMeshStiffness iso6336_stiffness(const GearSpec& a, const GearSpec& b, double eps_alpha,
                                   const IsoStiffnessOptions& o) {
  require(a.kind == GearKind::External, "kind", "the first gear of an ISO 6336 pair must be external");
  require(eps_alpha >= 1.0 && std::isfinite(eps_alpha), "contact_ratio", "must be >= 1, got ", eps_alpha);
  require(o.C_M > 0 && o.C_R > 0, "C_M", "C_M and C_R must be > 0");
  // ISO 6336-1:2006 clause 9, method B: coefficients of q' [mm um / N].
  constexpr double C1 = 0.04723, C2 = 0.15551, C3 = 0.25791, C4 = -0.00635, C5 = -0.11654, C6 = -0.00193,
                   C7 = -0.24188, C8 = 0.00529, C9 = 0.00182;
  const double zn1 = a.teeth;  // spur: z_n = z
  const double x1 = a.profile_shift;
  const double x2 = b.profile_shift;
  // 1/z_n2 = 0 for an internal gear (z_n2 = infinity).
  const double inv_zn2 = b.kind == GearKind::Internal ? 0.0 : 1.0 / b.teeth;

  IsoMeshStiffness r;
  r.q_prime_mm_um_N = C1 + C2 / zn1 + C3 * inv_zn2 + C4 * x1 + C5 * x1 / zn1 + C6 * x2 + C7 * x2 * inv_zn2 +
                      C8 * x1 * x1 + C9 * x2 * x2;
  r.c_th_N_mm_um = 1.0 / r.q_prime_mm_um_N;
  r.C_B = 0.5 * (basic_rack_factor(a) + basic_rack_factor(b));
  r.load_factor = o.line_load_N_mm > 0 && o.line_load_N_mm < 100.0 ? std::pow(o.line_load_N_mm / 100.0, 0.25) : 1.0;
  const double cos_beta = 1.0;  // spur
  r.c_prime_N_mm_um = r.c_th_N_mm_um * o.C_M * o.C_R * r.C_B * cos_beta * r.load_factor;
  r.c_gamma_alpha_N_mm_um = r.c_prime_N_mm_um * (0.75 * eps_alpha + 0.25);
  // N/(mm um) x b [mm] = N/um = 1e6 N/m.
  const double b_mm = 1e3 * std::min(a.face_width_m, b.face_width_m);
  r.c_prime_N_m = r.c_prime_N_mm_um * b_mm * 1e6;
  r.c_gamma_alpha_N_m = r.c_gamma_alpha_N_mm_um * b_mm * 1e6;
  return r;
}

} // namespace pw::stiffness
