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
// tip of that gear (docs/derivation-geometry.md §1-§3).
#pragma once

#include "config/stage.hpp"
#include "geometry/gear.hpp"

#include <string>
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
  /// Form radius r_F of A / of B [m]: where the generated involute meets the
  /// root fillet (ISO 21771 d_Ff for rack generation with the tool tip radius
  /// rho_f* m; for the internal B the rack limit of a shaper cutter, the
  /// involute's outer end). Diagnostic, see fillet_overlap_*.
  double form_radius_a_m = 0;
  double form_radius_b_m = 0;
  /// Length of the path of contact [m] that lies beyond A's / B's form circle,
  /// i.e. where the mate's tip meets the fillet rather than the involute (0 for
  /// a clean mesh). Not an error: the fillet estimate depends on tool data the
  /// seed does not give, and the seed's own planet-ring mesh has ~1 mm of it
  /// (docs/derivation-geometry.md §2.4). Contact below a base circle is an error.
  double fillet_overlap_a_m = 0;
  double fillet_overlap_b_m = 0;
};

/// Mesh of driving gear `a` with driven gear `b` at working centre distance
/// `centre_distance_m` (<= 0: the zero-backlash distance from the profile
/// shifts). `label_a` / `label_b` prefix the parameter names in error messages
/// (e.g. "stage.sun" gives "stage.sun.profile_shift"). Throws pw::InputError on
/// mismatched module / pressure angle / kind, a centre distance at which the
/// teeth would overlap, tip-to-root clearance < 0, contact reaching below a base circle (interference), or
/// contact ratio < 1.
MeshGeometry make_mesh(const GearSpec& a, const GearSpec& b, double centre_distance_m = 0.0,
                       const std::string& label_a = "", const std::string& label_b = "");

/// Zero-backlash working centre distance [m] of gears `a` (external) and `b`:
/// a' = m (z_a + z_b)/2 cos(alpha)/cos(alpha') (external b) or
/// m (z_b - z_a)/2 cos(alpha)/cos(alpha') (internal b), alpha' from the profile
/// shifts (docs/derivation-geometry.md §2.1). Assumes equal module and
/// pressure angle.
double zero_backlash_centre_distance(const GearSpec& a, const GearSpec& b);

/// Signed roll distance rho_F [m] of the form point (where the generated
/// involute meets the root fillet) of a gear cut by the basic rack of its
/// dedendum h_f* m and tool tip radius rho_f* m (ISO 21771 d_Ff); the form
/// radius is sqrt(r_b^2 + rho_F^2). External gear: where the rack undercuts the
/// tooth (z < 2 (h_f* - rho_f* (1 - sin a0) - x) / sin^2 a0, the straight flank
/// ending beyond T) the involute starts where the cut of the flank's end point
/// ends: that roll distance (>= 0; 0.0077 m for z = 17, x = 0, m = 1 m, 20 deg).
/// Internal gear: the rack limit of a shaper cutter (an upper estimate of the
/// involute's outer end; a finite shaper ends it lower).
double form_roll_distance(const GearSpec& spec, const GearGeometry& g);

/// Radius on A / on B of the contact point at roll coordinate xi [m].
double contact_radius_a(const MeshGeometry& mesh, double xi_m);
double contact_radius_b(const MeshGeometry& mesh, double xi_m);
/// Radius of curvature of A's / B's flank at xi [m]. Inline: the mesh-load summary evaluates them
/// for every loaded pair of every recorded step (call overhead ~3 % of a recorded step, session 41).
inline double curvature_radius_a(const MeshGeometry&, double xi_m) { return xi_m; }
inline double curvature_radius_b(const MeshGeometry& mesh, double xi_m) {
  return mesh.kind == GearKind::Internal ? mesh.tangent_distance_m + xi_m : mesh.tangent_distance_m - xi_m;
}

/// Both meshes of the stage (identical for every planet).
struct StageGeometry {
  GearGeometry sun, planet, ring;
  MeshGeometry sun_planet;   ///< A = sun, B = planet
  MeshGeometry planet_ring;  ///< A = planet, B = ring
  double carrier_radius_m = 0;  ///< planet centre distance from the sun axis [m]
  std::vector<double> planet_angles_rad;  ///< psi_i [rad], always filled (equal spacing if the spec is empty)
};

/// Builds and checks the whole stage (errors name the TOML key, "stage.*"):
///  * gear kinds, modules and pressure angles; every check of make_mesh();
///  * a common carrier radius: the zero-backlash centre distances of the
///    sun-planet and planet-ring meshes agree within 1e-6 (relative); for
///    unshifted gears this is Zr = Zs + 2 Zp ("stage.ring.teeth"), otherwise
///    "stage.ring.profile_shift" (the message gives the matching x_r);
///  * assembly (Parker & Lin 2004): equal spacing needs (Zs + Zr) / N integer
///    ("stage.planet_count"); given angles need psi_i (Zs + Zr) / 2 pi integer
///    within 1e-6 ("stage.planet_angles_rad");
///  * neighbouring planets' tip circles do not touch: 2 a' sin(dpsi/2) > 2 r_a,p.
StageGeometry make_stage_geometry(const model::StageSpec& spec);

/// Tooth numbering (docs/derivation-geometry.md §4). Each body's teeth are
/// numbered against its rotation relative to the carrier, so that they enter
/// every mesh in increasing order: tooth k of a body has its centreline at
/// angle tooth0 + direction * 2 pi k / z about the body's own axis (fixed
/// frame, counter-clockwise positive). The sun turns counter-clockwise
/// relative to the carrier, so it is numbered clockwise; planets and ring turn
/// clockwise relative to the carrier, so they are numbered counter-clockwise.
inline constexpr int kSunToothDirection = -1;
inline constexpr int kPlanetToothDirection = +1;
inline constexpr int kRingToothDirection = +1;

/// Angular positions of tooth 0 at assembly (all rotations zero) [rad], in [-pi, pi].
struct AssemblyLayout {
  /// 0 by definition: sun tooth 0's centreline points at planet 0 (psi_0 = 0).
  double sun_tooth0_rad = 0;
  /// Per planet, about its own centre: the planet turned until it meshes with
  /// the sun (zero backlash). Tooth 0 is the tooth nearest to the angle
  /// psi_i + pi - pi/Zp, i.e. for planet 0 the tooth on the counter-clockwise
  /// side of the tooth space that faces the sun (it meets sun tooth 0).
  std::vector<double> planet_tooth0_rad;
  /// The ring turned until it meshes with planet 0: a ring tooth on planet 0's
  /// centre line for Zp even (tooth 0 at angle 0), a ring tooth space there
  /// for Zp odd (tooth 0 is the tooth clockwise of it, at -pi/Zr).
  double ring_tooth0_rad = 0;
};
AssemblyLayout assembly_layout(const model::StageSpec& spec, const StageGeometry& geo);

/// Phase of one mesh: pair n (an integer that grows by one each time a new
/// tooth pair enters) has its contact point at xi_n(s) = xi0 + s - n p_b,
/// where s [m] is the mesh roll distance (sun-planet: r_bs (theta_s - theta_c);
/// planet-ring: r_br theta_c; sun and carrier angles counter-clockwise). Pair n
/// engages tooth (tooth_a0 + n) mod z_A of A and tooth (tooth_b0 + n) mod z_B
/// of B, numbered as in AssemblyLayout. Pair 0 is the pair with
/// start <= xi0 < start + p_b at s = 0.
struct MeshPhase {
  double xi0_m = 0;
  int tooth_a0 = 0;
  int tooth_b0 = 0;
};

/// Phases of the sun-planet and planet-ring meshes of every planet, from the
/// involute flank positions at assembly (theta = 0, AssemblyLayout). For
/// equally loaded rigid motion the relative phases follow Parker & Lin (2004):
/// planet i's sun-planet mesh lags planet 0's by Zs psi_i / 2 pi mesh cycles,
/// its planet-ring mesh by -Zr psi_i / 2 pi (mod 1). Throws pw::InputError
/// ("stage.planet_angles_rad") if a planet cannot mesh with sun and ring at once.
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
/// written into `out` (cleared first, capacity reused; no allocation when
/// out.capacity() >= the number of pairs, which is at most ceil(epsilon) + 1).
/// Ordered by n, i.e. the pair nearest to leaving (largest xi) first. Returns
/// their number. Tooth indices are in [0, z). A margin > 0 widens the window
/// to [start - margin, end + margin] (pairs about to enter or just left, for
/// engagement_weight; at most ceil(epsilon + 2 margin / p_b) + 1 pairs).
int pairs_in_contact(const MeshGeometry& mesh, const MeshPhase& phase, int teeth_a, int teeth_b, double s_m,
                     std::vector<ContactPair>& out, double margin_m = 0.0);

/// Share of a time step during which a pair at roll coordinate xi is in
/// contact, when the step covers a roll distance 2 h centred on xi: a ramp
/// from 0 at start - h to 1 at start + h, and back to 0 from end - h to end + h
/// (1 inside, 0 outside, for h = 0). A time-stepping model that switches a
/// pair on at the first step after it reaches `start` quantizes the instant of
/// engagement to the step; the stiffness jump then lands up to one step late,
/// by an amount that varies from event to event, an O(dt) error that is
/// erratic in dt. Weighting the pair by the share of the step it spends in
/// contact makes the mesh force a continuous function of the engagement
/// instant (its impulse over the step is exact to first order); the ramp
/// vanishes as dt -> 0 (docs/derivation.md §3.4).
double engagement_weight(const MeshGeometry& mesh, double xi_m, double half_width_m);

} // namespace pw::geometry
