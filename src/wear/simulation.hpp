// The coupled wear loop of a simulation (docs/derivation.md §5): between the
// warm-up and the recording of model::simulate(), repeated dynamic windows
// give each flank element's wear rate (FlankWearAccumulator), extrapolated
// over many mesh cycles with a bounded increment; profiles and backlash are
// updated and dynamic snapshots recorded. This is the layer above model/: it
// hands the loop to model::simulate() as its wear phase.
#pragma once

#include "model/result.hpp"
#include "model/simulation.hpp"

namespace pw::wear {

/// The wear loop on a warmed-up integration (model::simulate's wear phase):
/// runs wear.mesh_cycles mesh cycles or until
/// wear.max_wear_fraction_of_thickness is exceeded (WearHistory::stop_reason),
/// reporting progress in [f0, f1]. Throws pw::InputError (wear.window_mesh_cycles)
/// if a window lets some flank family complete no contact pass.
model::WearHistory run_wear(model::Integration& run, const model::ProgressFn& progress, double f0, double f1);

/// model::simulate() with the wear loop: every simulation whose configuration may
/// have wear.mesh_cycles > 0 goes through here. Same arguments and results.
model::SimulationResult simulate(const model::SimulationConfig& config, const model::ProgressFn& progress = {},
                                 const model::OutputSelection& output = {});

} // namespace pw::wear
