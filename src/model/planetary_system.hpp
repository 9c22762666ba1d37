// The planetary stage as a second-order system for the Newmark integrator:
// nonlinear tooth-pair contact forces with profile deviations and backlash,
// viscous mesh damping, Coulomb tooth friction that reverses at the pitch
// point, constant input power on the sun and a load torque on the carrier.
//
// Contact law (docs/derivation.md §3.3), for each mesh m with deflection
// delta = g . q + delta_err(t) (Eq. 1 of lumped_model.hpp plus imposed
// errors) and each tooth pair j in contact at roll coordinate xi_j:
//   F_j = k_j(xi_j) max(0, delta - e_j)            drive flanks
//   e_j = d_A(tooth, xi_j) + d_B(tooth, xi_j) + e_mesh   profile deviations
//   F_back = K(t) min(0, delta + b)                coast flanks, backlash b
//   F_d = c delta_dot while any flank is in contact, c = 2 zeta sqrt(k_mean m_eq)
// The seed's single dead zone (its Eq. 2-4) is the special case of one pair
// and e_j = e. Per-pair forces give the load sharing between pairs (the seed's
// load ratio, Eq. 19) without assuming it, and let worn profiles act pair by
// pair. Friction on pair j: mu (F_j + F_d k_j/K) tanh(v_s / v_eps), v_s the
// sliding speed at xi_j (lumped_model.hpp Eq. 2).
#pragma once

#include "config/stage.hpp"
#include "dynamics/lumped_model.hpp"
#include "dynamics/newmark.hpp"
#include "geometry/mesh.hpp"
#include "model/tooth_surfaces.hpp"
#include "stiffness/mesh_stiffness.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace pw::model {

/// What one mesh did at the last force evaluation (all SI).
struct MeshState {
  static constexpr int kMaxPairs = 4;
  double roll_m = 0;            ///< mesh roll distance s [m]
  double deflection_m = 0;      ///< delta along the LOA (incl. imposed errors) [m]
  double velocity_m_s = 0;      ///< d delta / dt [m/s]
  double force_N = 0;           ///< total normal force: elastic + damping [N]
  double damping_force_N = 0;   ///< [N]
  double stiffness_N_m = 0;     ///< sum of k_j over the pairs geometrically in mesh [N/m]
  double friction_N = 0;        ///< sum of signed friction forces [N]
  int pairs = 0;                ///< pairs in the (engagement-widened) window: pair[0 .. pairs)
  /// Sequence number of pair[0] along the run (pair[j] is pair first_pair + j): a tooth pair keeps
  /// its number while it stays in the window, so a bookkeeper can follow pairs without comparing
  /// their teeth (wear::FlankWearAccumulator). Meaningful only while pairs > 0.
  long long first_pair = 0;
  /// Pairs with engagement weight >= 1/2: the sharp count at the step's midpoint (output).
  int pairs_engaged = 0;
  std::array<geometry::ContactPair, kMaxPairs> pair{};
  std::array<double, kMaxPairs> pair_force_N{};    ///< normal force incl. its damping share [N]
  std::array<double, kMaxPairs> sliding_m_s{};     ///< sliding speed of A on B [m/s]
};

/// One mesh family (sun-planet or planet-ring): geometry and stiffness, shared
/// by every planet.
struct MeshFamily {
  geometry::MeshGeometry geometry;
  stiffness::PairStiffnessCurve stiffness;
  double mean_stiffness_N_m = 0;  ///< time-averaged combined mesh stiffness [N/m]
  int teeth_a = 0, teeth_b = 0;
  /// StiffnessSettings::Harmonics times the mean stiffness [N/m]; `corrected` when any is non-zero.
  std::array<double, StiffnessSettings::Harmonics::kCount> harmonic_cos_N_m{}, harmonic_sin_N_m{};
  bool corrected = false;
  /// Half the width of the pairs' stiffness ramp at each end of the path of contact
  /// (contact.engagement_ramp times p_b / 2) [m]; 0 = sharp entry.
  double engagement_ramp_half_width_m = 0;
  /// The correction of the combined stiffness at contact coordinate u [N/m] (zero mean over p_b).
  double stiffness_correction_N_m(double u_m) const;
};

/// A body's rotation perturbation row . x (row: its map's theta row), taken as the row's one
/// non-zero times its entry when it has one (the sun's, carrier's and machines' own coordinates):
/// a dynamic-size dot product costs ~40 instructions for the 5 entries of a torsional stage, and
/// the loops of the simulation take several per step. Exact: the other products are zeros, which
/// do not change the sum (only a zero result's sign may differ); otherwise the dot product.
class RotationRow {
public:
  RotationRow() = default;
  explicit RotationRow(const Eigen::RowVectorXd& row);
  double of(const Eigen::VectorXd& x) const { return unit_ >= 0 ? c_ * x[unit_] : row_.dot(x); }

private:
  Eigen::RowVectorXd row_;
  int unit_ = -1;  // the one non-zero's index, -1 for none or several
  double c_ = 0;
};

class PlanetaryDynamics final : public dynamics::SecondOrderSystem {
public:
  /// `structure` from dynamics::build_torsional / build_lateral_torsional;
  /// `phases` from geometry::mesh_phases; `surfaces` sized to the meshes.
  PlanetaryDynamics(const SimulationConfig& config, dynamics::LumpedStructure structure, MeshFamily sun_planet,
                    MeshFamily planet_ring, std::vector<geometry::PlanetPhases> phases, ToothSurfaces surfaces,
                    double sun_speed_abs_rad_s, double carrier_speed_abs_rad_s);

  int size() const override { return structure_.dofs; }
  const Eigen::MatrixXd& mass() const override { return structure_.mass; }
  /// Applied torques [N m] set the scale of the generalized forces.
  double force_scale() const override { return std::fabs(nominal_input_torque_Nm()) + std::fabs(load_torque_); }
  void force(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& g, Eigen::MatrixXd* K,
             Eigen::MatrixXd* C) override;

  /// Fixes the state that sets the mesh roll distances (which tooth pairs are
  /// in contact, and where) for the next step. The roll is thus lagged by one
  /// step (an error of r w dt^2, far below a microelement) so that the pair
  /// set does not change inside Newton's iterations, where the jump of a pair
  /// entering contact would stall convergence. Call after every accepted step.
  /// With stiffness.mesh_phase = nominal_time the roll stays the nominal rotation's (q_roll_ = 0).
  void set_roll_reference(const Eigen::VectorXd& q) {
    if (roll_follows_rotation_) q_roll_ = q;
    ++contact_epoch_;
  }

  const dynamics::LumpedStructure& structure() const { return structure_; }
  const MeshFamily& family(int mesh) const {
    return dynamics::MeshId::of(mesh).sun_planet() ? sun_planet_ : planet_ring_;
  }
  /// States of all 2N meshes at the last force evaluation (sun-planet i at
  /// 2i, planet-ring i at 2i+1).
  const std::vector<MeshState>& mesh_states() const { return states_; }
  /// Mutable flank state (wear, tests). Changing the surfaces through a reference kept
  /// from here is seen from the next set_roll_reference() on (the contact geometry is
  /// evaluated once per step, see force()).
  ToothSurfaces& surfaces() {
    ++contact_epoch_;
    return surfaces_;
  }
  const ToothSurfaces& surfaces() const { return surfaces_; }

  /// Load torque [N m] on the carrier (or the load machine behind a flexible output shaft),
  /// acting against the rotation; under speed control the feed-forward part of the shaft torque.
  double load_torque_Nm() const { return load_torque_; }
  void set_load_torque_Nm(double t) { load_torque_ = t; }
  /// Input torque on the sun [N m]: P / w_s (1 + r sin(order theta_s)), with
  /// the actual sun speed w_s and angle theta_s (absolute).
  double input_torque_Nm(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v) const;
  /// Mean input torque P / Omega_s at the nominal speed [N m].
  double nominal_input_torque_Nm() const { return power_ / sun_speed_; }
  double mesh_damping_N_s_m(int mesh) const { return mesh_[mesh].damping_N_s_m; }
  /// Backlash of mesh m [m] (initial; grows with wear).
  double backlash_m(int mesh) const { return mesh_[mesh].backlash_m; }
  void set_backlash_m(int mesh, double b) { mesh_[mesh].backlash_m = b; }
  /// The excitations held in the dynamics that do not repeat every mesh period: the input torque
  /// ripple's fraction and the sun runout's eccentricity (a tooth modifier's lives in the
  /// surfaces). The warm-up settles the stage without them first (simulation.cpp, settle()).
  struct AperiodicExcitation {
    double torque_ripple_fraction = 0;
    double sun_eccentricity_m = 0;
  };
  AperiodicExcitation aperiodic_excitation() const { return {ripple_, sun_ecc_}; }
  void set_aperiodic_excitation(const AperiodicExcitation& e) {
    ripple_ = e.torque_ripple_fraction;
    sun_ecc_ = e.sun_eccentricity_m;
    ++contact_epoch_;  // the runout enters the cached contact geometry (imposed deflection)
  }
  /// Spreads each pair's entry into and exit from contact over the roll distance
  /// the mesh covers in dt_s at its nominal speed (geometry::engagement_weight):
  /// the force then depends continuously on the engagement instant instead of
  /// jumping at the first step past it. 0 = sharp switching. The simulation sets
  /// its time step (docs/derivation.md §3.4). The gears' own ramp
  /// (MeshFamily::engagement_ramp_half_width_m) is used where it is the wider.
  void set_engagement_smoothing(double dt_s);
  double engagement_half_width_m(int mesh) const { return mesh_[mesh].engage_half_width_m; }
  /// Absolute sun angle perturbation row: theta_s = Omega_s t + row . q.
  const Eigen::RowVectorXd& sun_theta_row() const { return sun_row_; }
  const Eigen::RowVectorXd& carrier_theta_row() const { return carrier_row_; }
  /// sun_theta_row() . x and carrier_theta_row() . x (RotationRow).
  double sun_rotation(const Eigen::VectorXd& x) const { return sun_rotation_.of(x); }
  double carrier_rotation(const Eigen::VectorXd& x) const { return carrier_rotation_.of(x); }
  /// Rows of the bodies the input and load torques act on (the motor and load machine
  /// behind flexible shafts, else the sun and carrier): theta = Omega t + row . q.
  const Eigen::RowVectorXd& input_theta_row() const { return input_row_; }
  const Eigen::RowVectorXd& output_theta_row() const { return output_row_; }

private:
  /// What the step's contact geometry fixes for one tooth pair: with the roll
  /// lagged (set_roll_reference) the pairs, their roll coordinates, stiffnesses,
  /// profile deviations and friction directions do not change within a step.
  struct PairGeometry {
    double k_N_m = 0;          ///< engagement-weighted, damage-scaled pair stiffness [N/m]
    double deviation_m = 0;    ///< e_j: profile deviations of both flanks + mesh error [m]
    double slide_nominal_m_s = 0;  ///< sliding speed of the nominal motion at xi [m/s]
    double share = 0;          ///< k_j / sum of the mesh's k: the pair's share of the damping force
    std::array<double, dynamics::SparseCoupling::kMaxEntries> h{};  ///< h0 + xi h1 on the mesh's entries
  };
  /// First pair of mesh m's contact window at roll s (geometry::pairs_in_contact):
  /// xi_j = u - (n_first + j) p_b with teeth tooth_a + j, tooth_b + j (mod z), j < count.
  struct PairWindow {
    double u_m = 0, n_first = 0;
    int count = 0, tooth_a = 0, tooth_b = 0;
  };
  /// The window's first pair index and its teeth at the previous call (per mesh).
  struct ToothCursor {
    long long k0 = 0;
    int tooth_a = 0, tooth_b = 0;
    bool valid = false;
  };
  /// Beyond this many pairs' advance since the last call the teeth are found by modulo.
  static constexpr long long kCursorMaxAdvance = 4;
  PairWindow pair_window(int m, double s_m);
  /// Per-mesh reciprocals of the contact geometry's divisors, fixed at construction (and by
  /// set_engagement_smoothing): the per-step geometry multiplies instead of dividing.
  struct MeshScales {
    double inv_base_pitch_1_m = 0;     ///< 1 / p_b [1/m]
    double inv_engage_width_1_m = 0;   ///< 1 / (2 h), h the engagement half width (0: sharp) [1/m]
    double stiffness_index_1_m = 0;    ///< (n - 1) / (xi_n - xi_0) of the pair stiffness table [1/m]
    /// The table's ends xi_0, xi_n [m] and its last interval n - 2; a table of fewer than two
    /// points keeps the empty range [NaN, NaN], outside which the stiffness is 0.
    double stiffness_x0_m = std::numeric_limits<double>::quiet_NaN(), stiffness_x1_m = std::numeric_limits<double>::quiet_NaN();
    std::size_t stiffness_last = 0;
  };
  /// Evaluates the contact geometry of every mesh at time t (once per step).
  void update_contact_geometry(double t);
  /// update_contact_geometry for mesh m of NE coupled coordinates (0: any, SparseCoupling::entries).
  template <int NE>
  void update_mesh_geometry(int m, double t, const Eigen::Vector2d& sun_runout_m);
  /// Adds mesh m's normal, damping and friction forces at (q, v) to g (and tangents), for meshes
  /// of NE coupled coordinates (0: any, SparseCoupling::entries); `coordinates` reads entry k's
  /// q and v and accumulates its generalized force (planetary_system.cpp).
  template <int NE, class Coordinates>
  void add_mesh_force_n(int m, Coordinates& coordinates, Eigen::MatrixXd* K, Eigen::MatrixXd* C);
  /// add_mesh_force_n of every mesh of a torsional stage (EntryPattern::Torsional), no tangents:
  /// the coordinates each mesh touches follow from its planet (q, v, g the vectors' data).
  void add_torsional_mesh_forces(const double* __restrict q, const double* __restrict v, double* __restrict g);
  const FlankSet& flank_a(int mesh) const;
  const FlankSet& flank_b(int mesh) const;
  /// Displacement of the sun by its runout at time t (carrier frame) [m]; zero without one.
  Eigen::Vector2d sun_runout_m(double t) const;
  double imposed_deflection(int mesh, const Eigen::Vector2d& sun_runout_m) const;

  dynamics::LumpedStructure structure_;
  MeshFamily sun_planet_, planet_ring_;
  std::vector<geometry::PlanetPhases> phases_;
  ToothSurfaces surfaces_;
  std::vector<MeshState> states_;
  double inv_v_eps_ = 1;            // 1 / friction smoothing speed [s/m]
  Eigen::RowVectorXd sun_row_, carrier_row_, input_row_, output_row_;
  RotationRow sun_rotation_, carrier_rotation_, input_rotation_;
  Eigen::VectorXd q_roll_;          // state that fixes the roll distances
  bool roll_follows_rotation_ = true;  // stiffness.mesh_phase = rotation (false: nominal_time)
  /// Everything the step reads and writes for one mesh besides its MeshState, in one record: the
  /// mesh loops then walk one array instead of a dozen vectors indexed by mesh (their base
  /// pointers and index arithmetic were a sixth of the contact geometry's instructions,
  /// callgrind, session 43).
  struct MeshRecord {
    dynamics::SparseCoupling sparse;  ///< g, h0, h1, roll on the coordinates it touches
    std::array<PairGeometry, MeshState::kMaxPairs> pairs{};  ///< this step's pairs
    double imposed_m = 0;             ///< imposed deflection at the step's time [m]
    double backlash_m = 0;            ///< [m]
    double damping_N_s_m = 0;         ///< [N s/m]
    double mesh_error_m = 0;          ///< [m]
    double static_offset_m = 0;       ///< imposed deflection constant in the carrier frame [m]
    double engage_half_width_m = 0;   ///< half the roll per smoothing step [m]
    MeshScales scales;
    ToothCursor cursor;               ///< pair_window's tooth indices of the last call
    Eigen::Vector2d normal{0, 0};     ///< line of action (sun runout) [-]
  };
  std::vector<MeshRecord> mesh_;  // per mesh
  /// How many coordinates the meshes touch, in mesh order, for the mesh loops' dispatch: the
  /// torsional stage's sun-planet meshes 3 and its planet-ring meshes 2 (ring fixed), every
  /// lateral-torsional mesh 7; anything else goes through a switch per mesh.
  /// Torsional: SunPlanet3Ring2 on the torsional coordinates, sun-planet i on (theta_s, theta_c,
  /// theta_p_i) = (0, 1, 2 + i) and planet-ring i on (1, 2 + i): the forces without tangents then
  /// go through add_torsional_mesh_forces.
  enum class EntryPattern { Torsional, SunPlanet3Ring2, All7, Mixed };
  /// True when the meshes' couplings are EntryPattern::Torsional's.
  static bool torsional_coordinates(const std::vector<MeshRecord>& meshes);
  EntryPattern entry_pattern_ = EntryPattern::Mixed;
  std::vector<int> input_row_nz_, output_row_nz_;  // coordinates of the non-zeros of input_row_, output_row_
  struct SupportEntry {
    int row, col;
    double k;
  };
  std::vector<SupportEntry> support_nz_;       // non-zeros of the support stiffness, column by column
  std::vector<SupportEntry> damping_nz_;       // non-zeros of the support damping (rig shafts)
  long contact_epoch_ = 0, geometry_epoch_ = -1;  // geometry_epoch_ == contact_epoch_: geometry valid at geometry_t_
  double geometry_t_ = 0;
  double power_ = 0, sun_speed_ = 0, carrier_speed_ = 0, sun_speed_rel_ = 0;
  double load_torque_ = 0;
  bool constant_power_ = true;  // rig.input_control: power (P / w) or torque (P / Omega_s)
  double mu_ = 0, v_eps_ = 1;
  double ripple_ = 0, ripple_order_ = 1;
  double sun_ecc_ = 0, sun_ecc_phase_ = 0;
};

} // namespace pw::model
