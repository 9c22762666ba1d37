// Geometry of one spur-gear mesh along its line of action (LOA), and the
// assembly of a planetary stage.
//
// Roll coordinate xi [m]: signed distance along the LOA measured from T_A, the
// point where the LOA touches the base circle of the *driving* member A (the
// sun in a sun-planet mesh; the planet in a planet-ring mesh, since in the
// carrier frame power flows sun -> planet -> ring). xi grows as the mesh
// advances. At roll coordinate xi the radii of curvature of the flanks are
// rho_A = xi and rho_B = L - xi (external) or L + xi (internal), with
// L = |T_A T_B| = a' sin(alpha'). The seed's Fig. 9 axis, "distance from the
// pitch point", is (xi - xi_P) on A and (xi_P - xi) on B, positive toward the
// tip of that gear (docs/derivation.md §1).
#pragma once

#include "geometry/gear.hpp"
#include "model/stage.hpp"

#include <vector>

namespace pw::geometry {

struct MeshGeometry {
  GearKind kind = GearKind::External;  ///< External: sun-planet; Internal: planet-ring
  double centre_distance_m = 0;        ///< working centre distance a' [m]
  double working_pressure_angle_rad = 0; ///< alpha' [rad]
  double base_pitch_m = 0;             ///< p_b [m]
  double base_radius_a_m = 0;          ///< r_bA [m], driving member
  double base_radius_b_m = 0;          ///< r_bB [m], driven member
  double tangent_distance_m = 0;       ///< L = |T_A T_B| = a' sin(alpha') [m]
  double pitch_point_m = 0;            ///< xi_P = r_bA tan(alpha') [m]
  double start_active_m = 0;           ///< xi where contact starts (tip of B) [m]
  double end_active_m = 0;             ///< xi where contact ends (tip of A) [m]
  double contact_ratio = 0;            ///< epsilon_alpha = (end - start) / p_b [-]
};

/// Mesh of driving gear `a` with driven gear `b` at working centre distance
/// `centre_distance_m` (<= 0: the zero-backlash distance from the profile
/// shifts). Throws pw::InputError on interference (contact reaching below a
/// base circle or into the fillet), contact ratio < 1, or mismatched module /
/// pressure angle.
MeshGeometry make_mesh(const GearSpec& a, const GearSpec& b, double centre_distance_m = 0.0);

/// Radius on A / on B of the contact point at roll coordinate xi [m].
double contact_radius_a(const MeshGeometry& mesh, double xi_m);
double contact_radius_b(const MeshGeometry& mesh, double xi_m);
/// Radius of curvature of A's / B's flank at xi [m].
double curvature_radius_a(const MeshGeometry& mesh, double xi_m);
double curvature_radius_b(const MeshGeometry& mesh, double xi_m);

/// Both meshes of the stage (identical for every planet).
struct StageGeometry {
  GearGeometry sun, planet, ring;
  MeshGeometry sun_planet;   ///< A = sun, B = planet
  MeshGeometry planet_ring;  ///< A = planet, B = ring
  double carrier_radius_m = 0;  ///< planet centre distance from the sun axis [m]
  std::vector<double> planet_angles_rad;  ///< psi_i [rad]
};

/// Builds and checks the whole stage: equal spacing needs (Zs + Zr) / N
/// integer (or, for unequal spacing, each psi_i Zs... see docs), Zr = Zs + 2 Zp
/// for standard (unshifted) gears / equal centre distances otherwise, no
/// interference, contact ratios >= 1, planets do not collide (tip circles).
/// Throws pw::InputError naming the parameter.
StageGeometry make_stage_geometry(const model::StageSpec& spec);

/// Phase of one mesh: pair n (an integer that grows by one each time a new
/// tooth pair enters) has its contact point at xi_n(s) = xi0 + s - n p_b,
/// where s [m] is the mesh roll distance (sun-planet: r_bs (theta_s - theta_c);
/// planet-ring: r_br theta_c). Pair n engages tooth (tooth_a0 + n) mod z_A of
/// A and tooth (tooth_b0 + n) mod z_B of B (numbering in docs/derivation.md).
struct MeshPhase {
  double xi0_m = 0;
  int tooth_a0 = 0;
  int tooth_b0 = 0;
};

/// Phases of the sun-planet and planet-ring meshes of every planet, from the
/// tooth positions at assembly (theta = 0): sun tooth 0 centred on planet 0.
struct PlanetPhases {
  MeshPhase sun_planet;
  MeshPhase planet_ring;
};
std::vector<PlanetPhases> mesh_phases(const model::StageSpec& spec, const StageGeometry& geo);

/// A tooth pair in contact: where, and which teeth.
struct ContactPair {
  double xi_m;      ///< roll coordinate of the contact point [m]
  int tooth_a;      ///< tooth index on A
  int tooth_b;      ///< tooth index on B
};

/// The pairs in contact at roll distance s (those with start <= xi_n <= end),
/// written into `out` (cleared first, capacity reused). Returns their number.
int pairs_in_contact(const MeshGeometry& mesh, const MeshPhase& phase, int teeth_a, int teeth_b, double s_m,
                     std::vector<ContactPair>& out);

} // namespace pw::geometry
