// Lumped-parameter planetary stage, assembled from rigid-body kinematics.
//
// Every body (sun, ring, carrier, planets) moves in the plane; its small
// displacement (dx, dy, dtheta) is a linear map of the generalized coordinates
// q: d_b = B_b q (3 x n). Coordinates are perturbations about the nominal
// motion, expressed in the frame rotating with the carrier at its nominal speed
// (Lin & Parker 1999; Coriolis and centripetal terms neglected, as there).
//
// From the maps alone we get, for any model level:
//   mass matrix        M = sum_b B_b^T diag(m_b, m_b, I_b) B_b,
//   mesh deflection    delta = n . (u_A(C) - u_B(C)) = g . q            (1)
//   sliding speed      v_s = t . (v_A(C) - v_B(C)) = (h0 + xi h1) . qdot (2)
// with C = T_A + xi n the contact point, n the unit normal along which A pushes
// B and t = z x n. (1) does not depend on xi because a rotation moves every
// point of the line of action by the same amount along n; (2) is linear in xi
// because the friction moment arms are the flank radii of curvature (the
// seed's rho terms). Generalized forces then follow by virtual work:
//   Q = -F g  (normal force F >= 0 compressing the mesh),
//   Q = -mu F sgn(v_s) (h0 + xi h1)  (friction opposing A's sliding on B).
// The torsional model (seed Eq. 1) and the lateral-torsional model (Lin &
// Parker 1999) differ only in the maps B_b and the bearing springs.
// Derivation and sign conventions: docs/derivation.md §3.
#pragma once

#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace pw::dynamics {

/// Planar rigid body: mass properties and the map from q to its displacement.
struct Body {
  std::string name;
  double mass_kg = 0;
  double inertia_kgm2 = 0;            ///< about its own centre
  Eigen::Vector2d centre_m{0, 0};     ///< nominal centre in the carrier frame [m]
  Eigen::MatrixXd map;                ///< 3 x n: (dx [m], dy [m], dtheta [rad]) per unit q
};

/// One gear mesh between driving body A and driven body B.
struct MeshCoupling {
  std::string name;                  ///< e.g. "sun_planet/0"
  int body_a = -1, body_b = -1;
  Eigen::Vector2d normal{0, 1};      ///< n: direction A pushes B (unit)
  Eigen::Vector2d tangent_point_a{0, 0};  ///< T_A in the carrier frame [m]
  Eigen::VectorXd g;                 ///< delta = g . q, Eq. (1)
  Eigen::VectorXd h0, h1;            ///< sliding speed = (h0 + xi h1) . qdot, Eq. (2)
  /// Mesh roll distance s = s_nominal(t) + roll . q [m] (pairs advance with s).
  Eigen::VectorXd roll;
  double nominal_roll_rate_m_s = 0;  ///< ds/dt of the nominal motion [m/s]
  /// Sliding speed of the nominal motion in the carrier frame [m/s]:
  /// v_s0(xi) = nominal_slide0 + xi nominal_slide1. Zero at the pitch point.
  double nominal_slide0_m_s = 0, nominal_slide1_1_s = 0;
  /// Nominal speeds of A and B relative to the carrier [rad/s], CCW positive.
  double nominal_speed_a_rad_s = 0, nominal_speed_b_rad_s = 0;
};

/// A mesh's coupling vectors restricted to the coordinates the mesh touches:
/// the union of the non-zeros of g, h0, h1 and roll (Eqs. 1, 2), in ascending
/// coordinate order. A torsional mesh touches 3 coordinates (sun or ring,
/// carrier, planet), a lateral-torsional one 7; the time step works on these
/// instead of the length-n vectors (rank-1 tangent updates of kMaxEntries^2
/// instead of n^2 entries, no allocation).
struct SparseCoupling {
  static constexpr int kMaxEntries = 12;
  int entries = 0;
  std::array<int, kMaxEntries> dof{};
  std::array<double, kMaxEntries> g{}, h0{}, h1{}, roll{};
};

/// The sparse form of `mesh`; throws pw::SolverError if it touches more than
/// SparseCoupling::kMaxEntries coordinates.
SparseCoupling sparse_coupling(const MeshCoupling& mesh);

/// Linear spring between a body point and ground (body_b < 0) or another body.
struct Spring {
  std::string name;
  int body_a = -1, body_b = -1;
  Eigen::Vector2d point_m{0, 0};   ///< where it acts (carrier frame) [m]
  Eigen::Vector2d direction{1, 0}; ///< for translational springs (unit)
  bool torsional = false;          ///< torsional: acts on dtheta_a - dtheta_b [N m/rad]
  double stiffness = 0;            ///< [N/m] or [N m/rad]
  double damping = 0;              ///< viscous damper in parallel [N s/m] or [N m s/rad]
};

/// The two kinds of gear pair of a planetary stage.
enum class MeshKind { SunPlanet, PlanetRing };

/// One mesh of the stage by what it is: planet `planet`'s sun-planet or
/// planet-ring mesh. Every array over meshes (LumpedStructure::meshes, the mesh
/// states and channels) holds sun-planet i at 2i and planet-ring i at 2i + 1;
/// of() and index() are the only places that numbering is spelled out.
struct MeshId {
  int planet = 0;
  MeshKind kind = MeshKind::SunPlanet;

  static constexpr MeshId of(int index) {
    return {index / 2, index % 2 == 0 ? MeshKind::SunPlanet : MeshKind::PlanetRing};
  }
  static constexpr MeshId of(std::size_t index) { return of(static_cast<int>(index)); }
  constexpr int index() const { return 2 * planet + (kind == MeshKind::PlanetRing ? 1 : 0); }
  constexpr bool sun_planet() const { return kind == MeshKind::SunPlanet; }
};

struct LumpedStructure {
  int dofs = 0;
  std::vector<std::string> dof_names;
  std::vector<Body> bodies;
  std::vector<MeshCoupling> meshes;  ///< indexed by MeshId::index(): sun-planet i at 2i, planet-ring i at 2i+1
  std::vector<Spring> springs;
  Eigen::MatrixXd mass;              ///< assembled M
  Eigen::MatrixXd support_stiffness; ///< assembled bearing / support springs
  Eigen::MatrixXd support_damping;   ///< assembled dampers of the springs (rig shafts; supports when bearings.damping_ratio > 0)
  int sun_body = 0, carrier_body = 0, ring_body = 0;
  /// Bodies the input and load torques act on: the motor and load machine when they sit
  /// behind flexible shafts (RigLayout), else the sun and carrier themselves.
  int input_body = 0, output_body = 0;
  /// False when a shaft ties the stage to a speed-controlled machine: no free rotation.
  bool has_rigid_mode = true;
  /// The spring (index into `springs`) that ties the stage to the speed reference turning at the
  /// nominal speed: the ideal speed control's shaft or the speed loop's P-I spring; -1 without one.
  /// Its mean torque plus the feed-forward is the torque of the machine that holds the speed:
  /// the motor's when `speed_reference_at_input`, else the load machine's.
  int speed_reference_spring = -1;
  bool speed_reference_at_input = false;
  std::vector<int> planet_bodies;
};

/// Velocity (or displacement) of the material point p of body b per unit q:
/// 2 x n matrix P with v(p) = P qdot. Pure function of the map.
Eigen::MatrixXd point_map(const Body& body, const Eigen::Vector2d& point_m);

/// Assembles M, support stiffness and the mesh vectors g, h0, h1 from the
/// bodies, springs and each mesh's geometry (normal, T_A). Call after filling
/// bodies/springs/meshes' geometric fields.
void assemble(LumpedStructure& s);

/// Geometry and inertia needed to build either model level (all SI).
struct StageLayout {
  double sun_base_radius_m = 0, planet_base_radius_m = 0, ring_base_radius_m = 0;
  double carrier_radius_m = 0;                 ///< planet centre radius a' [m]
  double sun_planet_pressure_angle_rad = 0;    ///< working alpha' of the external mesh
  double planet_ring_pressure_angle_rad = 0;   ///< working alpha' of the internal mesh
  std::vector<double> planet_angles_rad;
  double sun_mass_kg = 0, sun_inertia_kgm2 = 0;
  double planet_mass_kg = 0, planet_inertia_kgm2 = 0;
  double carrier_mass_kg = 0, carrier_inertia_kgm2 = 0;
  double ring_mass_kg = 0, ring_inertia_kgm2 = 0;
  /// Nominal speeds relative to the carrier frame [rad/s], CCW positive:
  /// sun and ring; planets follow from rolling.
  double sun_speed_rel_rad_s = 0, ring_speed_rel_rad_s = 0;
};

/// How a rig machine is controlled (docs/derivation.md §3.6). In the perturbation coordinates
/// (deviations from the nominal rotation) a PI speed controller
/// T = -K_p (w - Omega) - K_i \int (w - Omega) dt is exactly a torsional spring K_i and damper K_p
/// from its machine to ground: the integral of the speed error is the machine's angle
/// perturbation.
enum class MachineControl {
  Torque,      ///< by its torque (the motor's constant power or torque, the load's constant torque): a free inertia
  IdealSpeed,  ///< its shaft's far end turns at exactly the nominal speed (the shaft: a spring to ground)
  SpeedLoop,   ///< a PI speed controller on the machine's own speed (K_i, K_p to ground)
};

/// One end of the test rig: a machine behind a shaft. A shaft of stiffness 0 is absent (the
/// machine's inertia is then part of StageLayout's sun or carrier inertia).
struct RigEnd {
  double machine_inertia_kgm2 = 0;  ///< used behind a flexible shaft, unless IdealSpeed [kg m^2]
  double shaft_N_m_rad = 0;         ///< [N m/rad]; 0 = rigid
  double shaft_N_m_s_rad = 0;       ///< shaft damping [N m s/rad]
  MachineControl control = MachineControl::Torque;
  double loop_integral_N_m_rad = 0;        ///< K_i of a SpeedLoop [N m/rad] (per rad of angle error)
  double loop_proportional_N_m_s_rad = 0;  ///< K_p of a SpeedLoop [N m s/rad] (per rad/s of speed error)
  bool holds_speed() const { return control != MachineControl::Torque; }
};

/// The test rig's shafts and machines in lumped form (model::RigSettings):
///   motor (theta_m) --k_in, c_in-- sun        input torque on the motor, or
///   sun --k_in, c_in-- ground                  the motor's far end at the nominal speed (IdealSpeed)
///   motor (or sun) --K_i, K_p-- ground         a PI speed loop on the motor (SpeedLoop)
///   carrier --k_out, c_out-- load (theta_L)    load torque on the load machine, or
///   carrier --k_out, c_out-- ground            the load's far end at the nominal speed (IdealSpeed)
///   load (or carrier) --K_i, K_p-- ground      a PI speed loop on the load machine (SpeedLoop)
/// At most one end holds the speed.
struct RigLayout {
  RigEnd input, output;
};

/// Bearing supports of the lateral-torsional model (Lin & Parker 1999).
struct Bearings {
  double sun_N_m = 0, ring_N_m = 0, carrier_N_m = 0, planet_N_m = 0;
  double sun_torsional_N_m = 0;      ///< k_su on u = r_bs theta [N/m] (0: free)
  double ring_torsional_N_m = 0;     ///< k_ru on u = r_br theta [N/m]
  double carrier_torsional_N_m = 0;  ///< k_cu on u = a theta [N/m]
  /// Damping ratio of every support [-]: c = 2 zeta sqrt(k m), m the held body's mass (inertia
  /// for a torsional support), the reduced mass of planet and carrier for a planet bearing.
  double damping_ratio = 0;
};

/// Purely torsional model (seed Eq. 1 re-derived): q = (theta_s, theta_c,
/// theta_p1..N) [rad]; ring fixed; planet pins rigid on the carrier.
LumpedStructure build_torsional(const StageLayout& layout, const RigLayout& rig = {});

/// Lateral-torsional model (Lin & Parker 1999): q = (x, y, theta) of sun,
/// ring, carrier, then per planet (zeta, eta, theta) with zeta radial and eta
/// tangential translations in the planet's own carrier-fixed frame.
LumpedStructure build_lateral_torsional(const StageLayout& layout, const Bearings& bearings,
                                        const RigLayout& rig = {});

/// Coordinates the rig adds to the stage's: one per machine behind a flexible shaft
/// (theta_motor, theta_load, appended after the stage's coordinates).
int rig_dofs(const RigLayout& rig);

} // namespace pw::dynamics
