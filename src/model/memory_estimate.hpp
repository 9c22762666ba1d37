// Memory a simulation will need, estimated from the configuration before
// anything large is allocated, and refused (pw::InputError naming the key to
// change, nothing computed or written) when it exceeds the process's limit
// (core/memory_budget.hpp). The estimates are upper bounds of the dominant
// arrays, not of every byte: they exist to turn "1000000 typed for 100" into
// a clear message instead of std::bad_alloc after a long warm-up.
#pragma once

#include "config/stage.hpp"

#include <cstddef>
#include <cstdint>

namespace pw::model {

/// Most time steps per mesh period simulate() accepts. Loop counters of one
/// mesh period are int; 1e8 steps per period (hours of wall time per mesh
/// period) is far beyond any useful resolution, so the bound only catches a
/// mistyped time step or an absurdly slow speed.
inline constexpr std::int64_t kMaxStepsPerMesh = 100'000'000;

/// Time steps per mesh period for the mesh period and step; throws
/// InputError naming solver.time_step_s (if set) or operating.input_speed_rpm
/// when the count exceeds kMaxStepsPerMesh.
int checked_steps_per_mesh(const SimulationConfig& c, double mesh_period_s, double time_step_s);

/// Bytes of the tooth-flank state (every element of every flank of the 2N+2
/// flank families), times the copies the wear loop keeps when wear is on.
double flank_state_bytes(const SimulationConfig& c);

/// Bytes of the recorded time histories: stored samples x (channels + time),
/// doubled for the spectra and the writer's buffers.
double record_bytes(const SimulationConfig& c, int steps_per_mesh, int decimation, std::size_t stored_channels);

/// Bytes of the wear snapshots (8 mesh cycles of 4 channels and their spectra each).
double snapshot_bytes(const SimulationConfig& c, int steps_per_mesh);

/// Refuses the tooth-flank state (called before it is allocated).
void check_flank_memory(const SimulationConfig& c);

/// Refuses the recording and the wear snapshots (called before the warm-up).
void check_run_memory(const SimulationConfig& c, int steps_per_mesh, int decimation, std::size_t stored_channels);

} // namespace pw::model
