#include "model/memory_estimate.hpp"

#include "core/error.hpp"
#include "core/memory_budget.hpp"

#include <algorithm>
#include <cmath>

namespace pw::model {
namespace {

constexpr double kDouble = sizeof(double);
/// Wear updates the loop makes at least (simulation.cpp's kMinWearUpdates),
/// each storing one copy of the flank state in the history.
constexpr double kMinWearUpdates = 8;
/// Copies of the flank state besides the history: the deviations, the
/// initial state and the wear rates.
constexpr double kWorkingCopies = 3;
/// Snapshot arrays per sample: time, 4 mesh channels, housing acceleration and
/// carrier angle, 5 spectra of half length (frequency and amplitude each); plus
/// one ring-force array per planet while the housing signal is formed.
constexpr double kSnapshotArrays = 1 + 6 + 5;

} // namespace

int checked_steps_per_mesh(const SimulationConfig& c, double mesh_period_s, double time_step_s) {
  const double steps = std::ceil(mesh_period_s / time_step_s - 1e-9);
  if (steps <= static_cast<double>(kMaxStepsPerMesh)) return static_cast<int>(steps);
  if (c.solver.time_step_s > 0)
    throw InputError("solver.time_step_s",
                     detail::concat(c.solver.time_step_s, " s gives ", steps, " time steps per mesh period (",
                                    mesh_period_s, " s), more than ", kMaxStepsPerMesh, "; use a larger step or 0 for automatic"));
  throw InputError("operating.input_speed_rpm",
                   detail::concat(c.operating.input_speed_rpm, " rpm gives a mesh period of ", mesh_period_s,
                                  " s, which needs ", steps, " time steps of ", time_step_s,
                                  " s (solver.min_steps_per_mesh, solver.steps_per_mode_period), more than ",
                                  kMaxStepsPerMesh, "; use a higher speed or fewer steps per period"));
}

double flank_state_bytes(const SimulationConfig& c) {
  const StageSpec& s = c.stage;
  const double teeth = s.sun.teeth + s.ring.teeth + 2.0 * s.planet_count * s.planet.teeth;
  const double copies = c.wear.mesh_cycles > 0 ? kWorkingCopies + kMinWearUpdates + 1 : 1;
  return teeth * c.wear.elements_per_flank * kDouble * copies;
}

double record_bytes(const SimulationConfig& c, int steps_per_mesh, int decimation, std::size_t stored_channels) {
  const double steps = static_cast<double>(c.solver.record_mesh_cycles) * steps_per_mesh;
  const double samples = std::ceil(steps / std::max(1, decimation));
  return 2 * samples * (static_cast<double>(stored_channels) + 1) * kDouble;
}

double snapshot_bytes(const SimulationConfig& c, int steps_per_mesh) {
  if (c.wear.mesh_cycles <= 0) return 0;
  // An empty list means the two default snapshots (start and end).
  const double count = std::max<double>(2, static_cast<double>(c.wear.snapshot_mesh_cycles.size()));
  return count * c.wear.snapshot_record_mesh_cycles * steps_per_mesh * (kSnapshotArrays + c.stage.planet_count) *
         kDouble;
}

void check_flank_memory(const SimulationConfig& c) {
  require_memory(flank_state_bytes(c), "wear.elements_per_flank", "the tooth-flank state (teeth x elements per flank)",
                 "use fewer wear.elements_per_flank");
}

void check_run_memory(const SimulationConfig& c, int steps_per_mesh, int decimation, std::size_t stored_channels) {
  require_memory(record_bytes(c, steps_per_mesh, decimation, stored_channels), "solver.record_mesh_cycles",
                 detail::concat("recording ", c.solver.record_mesh_cycles, " mesh cycles x ", steps_per_mesh,
                                " steps of ", stored_channels, " channels"),
                 "lower solver.record_mesh_cycles, or store fewer samples (--time-history-decimation, "
                 "output.time_history_decimation) or channels (--channels)");
  require_memory(snapshot_bytes(c, steps_per_mesh), "wear.snapshot_mesh_cycles",
                 detail::concat(std::max<std::size_t>(2, c.wear.snapshot_mesh_cycles.size()), " wear snapshots of ",
                                c.wear.snapshot_record_mesh_cycles, " mesh cycles x ", steps_per_mesh, " steps"),
                 "list fewer wear.snapshot_mesh_cycles or lower wear.snapshot_record_mesh_cycles");
}

} // namespace pw::model
