// One simulation case, from configuration to results:
//   1. geometry and assembly checks           (geometry/mesh.hpp)
//   2. single-pair mesh stiffness curves       (stiffness/mesh_stiffness.hpp)
//   3. lumped model of the chosen level        (dynamics/lumped_model.hpp)
//   4. time step from the mesh period and the highest natural frequency
//   5. warm-up to the steady periodic state (seed Fig. 7): integrate whole
//      mesh periods, set the carrier load torque that holds the nominal speed
//      against the friction losses, stop when the mesh deflections repeat
//   6. record whole mesh periods into named channels (model/result.hpp).
// With wear.mesh_cycles > 0 the coupled wear loop runs between 5 and 6; it
// lives in the wear layer above this one: call wear::simulate()
// (wear/simulation.hpp), which hands it to simulate() below as a phase.
#pragma once

#include "config/stage.hpp"
#include "model/planetary_system.hpp"
#include "model/result.hpp"

#include <functional>
#include <memory>
#include <string>

namespace pw::model {

/// Progress callback: fraction done in [0, 1] and a short phase label.
using ProgressFn = std::function<void(double fraction, const std::string& phase)>;

/// Mass properties derived from the gear bodies where the config leaves them
/// unset (docs/derivation.md, "Assumptions").
struct MassProperties {
  double sun_mass_kg = 0, sun_inertia_kgm2 = 0;
  double planet_mass_kg = 0, planet_inertia_kgm2 = 0;
  double carrier_mass_kg = 0, carrier_inertia_kgm2 = 0;  ///< without planets
  double ring_mass_kg = 0, ring_inertia_kgm2 = 0;
};
MassProperties mass_properties(const SimulationConfig& config, const geometry::StageGeometry& geo);

/// Everything derived from a configuration before time integration.
struct PreparedStage {
  geometry::StageGeometry geometry;
  MassProperties masses;
  double sun_speed_rad_s = 0;      ///< nominal absolute sun speed Omega_s [rad/s]
  double carrier_speed_rad_s = 0;  ///< nominal carrier speed Omega_c = Omega_s Zs/(Zs+Zr) [rad/s]
  double mesh_frequency_Hz = 0;    ///< Zs (Omega_s - Omega_c) / 2 pi [Hz]
  std::unique_ptr<PlanetaryDynamics> dynamics;
  Eigen::VectorXd natural_frequencies_Hz;  ///< linearized at the mean mesh stiffness
  /// The rigid-body (kinematic) mode, scaled to unit sun rotation: the motion
  /// the applied torques accelerate and the warm-up controls.
  Eigen::VectorXd rigid_mode;
  double time_step_s = 0;
  int steps_per_mesh = 0;
};

/// The automatic time step [s] (solver.time_step_s = 0) for a mesh period T_mesh [s] and a
/// highest natural frequency f_max [Hz]: the smaller of T_mesh / min_steps_per_mesh and one
/// steps_per_mode_period-th of the period of min(f_max, accuracy_band_Hz) (f_max when the band
/// is 0), and never above one max(8, steps_per_mode_period / 4)-th of the highest mode's period
/// (8: the validity check of prepare()).
double automatic_time_step(double T_mesh, double f_max, const SolverSettings& solver);

/// True when the warm-up settles the stage without its tooth-level features before switching them
/// on (a damaged tooth or a sun runout; a torque ripple alone keeps the warm-up from the static
/// start): simulation.cpp, warm_up_from_static().
bool settles_without_tooth_level_features(const SimulationConfig& config);

/// Steps 1-4; throws pw::InputError for impossible geometry or an unusable
/// time step (naming solver.time_step_s and the limit).
PreparedStage prepare(const SimulationConfig& config);

/// The widest contact.engagement_ramp [base pitches] prepare() accepts for this stage's gears:
/// ContactSettings::kMaxEngagementRamp, or less where a mesh's contact ratio plus the ramp would
/// put more than the model's most pairs in one mesh (the boxes of fits, so that no fit can reach
/// a ramp the simulation refuses). Throws pw::InputError for impossible geometry.
double largest_engagement_ramp(const SimulationConfig& config);

/// Mesh stiffness curves of both mesh families (single pair vs distance from
/// the pitch point; combined vs time in mesh periods) and their summary.
std::vector<Curve> stiffness_curves(const PreparedStage& stage);
std::vector<Scalar> stiffness_scalars(const PreparedStage& stage);

/// What simulate() stores of the recorded mesh periods. The default stores
/// every channel (docs/output-format.md) at every time step. Unstored channels
/// cost nothing: their samples are neither computed nor allocated.
struct OutputSelection {
  /// Channel names to store ("sun_planet/0/force", "housing/acceleration", ...); a name
  /// ending in '/' selects every channel below it ("planet_ring/1/"). Empty = all.
  std::vector<std::string> channels;
  /// Store every k-th time step [-], k >= 1 (campaigns' output.time_history_decimation).
  /// SimulationResult::time_step_s is then k times the integration step.
  int decimation = 1;
  /// The mesh-load scalars (mesh_load/*: mean and largest force, dynamic factor, Hertzian
  /// contact pressure; load_sharing_factor/*), gathered over every loaded tooth pair at every
  /// recorded step. false skips that pass and leaves those scalars out (the diagnosis, which
  /// reads only time histories: 4 % of its time, perf, docs/benchmark.md session 27).
  bool mesh_load_summary = true;
  bool selects(const std::string& channel) const;
};

/// Integration state of one case after prepare(): the solver, its state and
/// statistics, advanced by the phases of simulate() (static start, warm-up,
/// wear, recording) one time step at a time.
struct Integration {
  PreparedStage& p;
  const SimulationConfig& c;
  dynamics::NewmarkSolver solver;
  dynamics::NewmarkState st;

  Integration(PreparedStage& prep, const SimulationConfig& cfg)
      : p(prep), c(cfg), solver(*prep.dynamics, prep.time_step_s, {cfg.solver.newmark_beta, cfg.solver.newmark_gamma},
                                {cfg.solver.newton_tolerance, cfg.solver.newton_max_iterations}) {}
  PlanetaryDynamics& sys() { return *p.dynamics; }
  void step() {
    solver.step(st);
    p.dynamics->set_roll_reference(st.q);
    // The sun must keep turning forward: the model's contact geometry follows the nominal
    // rotation (pair windows advance, the roll reference lags one step) and a constant input
    // power P / w is singular at w = 0. A sun speed at or below zero (or not finite) is a
    // response that diverged, never a steady operating point: stop here with an error instead of
    // returning its record (measured, 2026-11-28: the four-planet stage of docs/diagnose.md's
    // independent corpus at 100 rpm and 10 kW ran on to -2.8e6 rad/s and was written as a result).
    if (const double ws = p.sun_speed_rad_s + p.dynamics->sun_rotation(st.v); !(ws > 0)) throw_reversed(ws);
  }

private:
  [[noreturn]] void throw_reversed(double sun_speed_rad_s) const;
};

/// The lateral-torsional ring body's translational acceleration in the fixed (housing) frame, what
/// the housing path ring_body reads (model/sensor.hpp, Eq. S3). Built once before a record loop
/// (it copies the ring's coordinate rows): reading allocates nothing. The torsional model's ring
/// has no translation (mass_kg() is then still the ring's, the accelerations 0).
class RingBodyReader {
public:
  explicit RingBodyReader(const dynamics::LumpedStructure& S);
  /// The ring's mass as the model's mass matrix holds it [kg] (stage.ring_mass_kg or derived).
  double mass_kg() const { return mass_kg_; }
  /// (a_x, a_y) [m/s^2] in the fixed frame from the coordinate accelerations `a` at the absolute
  /// carrier angle `carrier_angle_rad` (Omega_c t + perturbation, as the channel carrier/angle).
  Eigen::Vector2d fixed_frame(const Eigen::VectorXd& a, double carrier_angle_rad) const;

private:
  Eigen::RowVectorXd x_, y_;  ///< the ring centre's translation rows in the carrier frame
  double mass_kg_ = 0;
};

/// The wear loop between the warm-up and the recording: advances `run` and
/// fills `result.wear`, reporting progress in [f0, f1] (wear/simulation.hpp).
using WearPhase = std::function<void(Integration& run, SimulationResult& result, const ProgressFn& progress,
                                     double f0, double f1)>;

/// Steps 1-6; `wear` runs between 5 and 6 when config.wear.mesh_cycles > 0
/// and is required then (std::logic_error without it: call wear::simulate()).
SimulationResult simulate(const SimulationConfig& config, const ProgressFn& progress = {},
                          const OutputSelection& output = {}, const WearPhase& wear = {});

} // namespace pw::model
