// Mesh stiffness by ISO 6336-1:2006, method B (clause 9), for spur gears.
//
//   q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2
//        + C8 x1^2 + C9 x2^2                                   [mm um / N]
//   c'_th = 1/q'                  theoretical single stiffness  [N/(mm um)]
//   c'    = c'_th C_M C_R C_B cos(beta)       single stiffness (max of one pair)
//   c_ga  = c' (0.75 eps_alpha + 0.25)        mesh stiffness (mean over the mesh)
// with C1..C9 = 0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193,
// -0.24188, 0.00529, 0.00182; C_M = 0.8 (measured over theory); C_R = 1 for
// solid blanks; C_B = [1 + 0.5 (1.2 - h_fP/m)][1 - 0.02 (20 deg - alpha_P)]
// averaged over the two gears' basic racks. For an internal gear the virtual
// tooth number z_n2 is taken as infinite (the rack limit, as ISO 6336-1
// prescribes for internal gears), so the C3 and C7 terms vanish; C6 x2 and
// C9 x2^2 stay. Below a line load of 100 N/mm the
// standard scales c' by (F_t K_A / b / 100)^0.25 (optional here).
#pragma once

#include "geometry/gear.hpp"

namespace pw::stiffness {

struct IsoStiffnessOptions {
  double C_M = 0.8;           ///< theoretical-to-measured correction [-]
  double C_R = 1.0;           ///< gear blank factor; 1 for solid discs [-]
  /// F_t K_A / b [N/mm]; <= 0 means "at least 100 N/mm" (no reduction).
  double line_load_N_mm = 0.0;
};

struct IsoMeshStiffness {
  double q_prime_mm_um_N = 0;          ///< q' [mm um/N]
  double c_th_N_mm_um = 0;             ///< c'_th [N/(mm um)]
  double C_B = 0;                      ///< basic rack factor [-]
  double load_factor = 1;              ///< (line load / 100)^0.25 or 1 [-]
  double c_prime_N_mm_um = 0;          ///< c' per face width [N/(mm um)]
  double c_gamma_alpha_N_mm_um = 0;    ///< c_gamma_alpha per face width [N/(mm um)]
  double c_prime_N_m = 0;              ///< c' b [N/m]
  double c_gamma_alpha_N_m = 0;        ///< c_gamma_alpha b [N/m]
};

/// Gear `a` is the external member (pinion or planet); `b` may be external or
/// internal. `contact_ratio` is eps_alpha (geometry::MeshGeometry). Face width:
/// the smaller of the two. Throws pw::InputError for an internal `a` or
/// eps_alpha < 1.
IsoMeshStiffness iso6336_stiffness(const geometry::GearSpec& a, const geometry::GearSpec& b, double contact_ratio,
                                   const IsoStiffnessOptions& options = {});

} // namespace pw::stiffness
