// One diagnosis on 1..P MPI ranks: `mpirun -np P planetwear diagnose ...`.
//
//   rank 0, main thread       moves messages (all MPI calls: MPI_THREAD_FUNNELED),
//                             polling with ~1 ms sleeps, so it needs almost no CPU;
//   rank 0, diagnosis thread  runs the whole diagnosis (src/diagnose) with its
//                             OpenMP threads. Every simulation it needs goes through
//                             CompareOptions::remote: to an idle rank if there is one
//                             (the calling thread waits), else it runs in place;
//   ranks 1..P-1              set up the same comparison (same files), then simulate
//                             one prepared configuration at a time and send its order
//                             spectra back, until rank 0 is done.
//
// Results do not depend on the number of ranks: a configuration travels as TOML
// (exact round trip) and every rank computes bit-identical spectra from it, which
// travel back as raw doubles; the diagnosis's decisions only see those spectra.
// The physics library stays free of MPI: simulation_pool.cpp is the only diagnose code using it.
#pragma once

#include "config/stage.hpp"
#include "diagnose/order_analysis.hpp"

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace pw::sweep {

/// What rank 0's diagnosis calls for a simulation (CompareOptions::remote).
using RemoteSimulation =
    std::function<std::optional<diagnose::ModelSpectra>(const model::SimulationConfig&, bool keep_sensor_inputs)>;
/// What a serving rank runs for a request (ModelComparison::evaluate).
using Evaluate = std::function<diagnose::ModelSpectra(const model::SimulationConfig&, bool keep_sensor_inputs)>;

/// Runs `drive` on rank 0 with a RemoteSimulation that uses ranks 1..P-1 (on one
/// rank it always answers nullopt), and serves simulations on the other ranks with
/// the Evaluate that `make_evaluate` returns (called once per serving rank; if it
/// throws, that rank tells rank 0 and serves nothing). MPI_Init_thread and
/// MPI_Finalize happen in here. An exception from `drive` is rethrown on rank 0
/// after MPI_Finalize; the other ranks return normally (so that mpirun reports rank
/// 0's status). Returns the number of ranks.
int run_with_simulation_pool(const std::function<void(const RemoteSimulation&, int ranks)>& drive,
                             const std::function<Evaluate()>& make_evaluate);

/// ModelSpectra <-> bytes (native doubles: an exact copy between ranks of one machine type).
std::vector<char> encode_spectra(const diagnose::ModelSpectra& s);
diagnose::ModelSpectra decode_spectra(std::span<const char> bytes);

} // namespace pw::sweep
