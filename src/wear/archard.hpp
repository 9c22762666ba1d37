// Archard sliding wear of involute flanks (seed §4, Eqs. 13-17; Flodin &
// Andersson 1997, "Simulation of mild wear in spur gears", Wear 207:16).
//
//   dh/dt = kappa p v_s          (seed Eq. 15; kappa = K/H [m^2/N])
//
// A material point of flank i lies inside the Hertzian band of half-width a
// for the time 2a / v_i, where v_i = w_i rho_i is the speed at which the
// contact moves over flank i (its rolling speed). With the mean Hertzian
// pressure p = F' / (2a) (F' = F/b, the seed's p = F_N/A, Eq. 14) the wear of
// that point per pass is
//
//   dh_pass = kappa p v_s 2a / v_i = kappa F' v_s / v_i                 (W1)
//
// independent of a: wear scales with the line load, the slide-to-roll ratio
// of the flank, and kappa. Over a time step dt the contact point sweeps
// v_i dt of the flank; spreading each pass's wear on the element it crosses
// gives the rate for the element of arc length l_e that holds the contact:
//
//   dh_e = kappa F' |v_s| dt / l_e                                      (W2)
//
// which integrates to (W1) over one pass (tested). The involute arc between
// radii of curvature rho_1, rho_2 on a base circle r_b is
// |rho_2^2 - rho_1^2| / (2 r_b).
#pragma once

namespace pw::wear {

/// Involute arc length between radii of curvature rho_1 and rho_2 [m].
double involute_arc_length(double base_radius_m, double rho_1_m, double rho_2_m);

/// Wear depth of one flank point per contact pass, (W1) [m].
double wear_per_pass(double kappa_m2_N, double load_per_width_N_m, double sliding_speed_m_s,
                     double rolling_speed_m_s);

} // namespace pw::wear
