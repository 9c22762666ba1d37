// Reading a recording as the commands that analyse one (diagnose, indicators)
// take it: the gear set (--config, --set), the sidecar (--meta, default the
// recording's name with .json) and command-line column/operating-point
// descriptions (--column, --speed-rpm, --power-w) merged over it.
#pragma once

#include "commands.hpp"
#include "diagnose/recording.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pw::app {

struct RecordingInputs {
  model::SimulationConfig config;
  diagnose::Recording recording;
};

/// The gear set's configuration (-c, default the seed's) with the command line's --set applied.
model::SimulationConfig read_gear_set_config(const CommonOptions& common);

/// Throws pw::InputError naming the option (--meta when no sidecar exists and the
/// command line does not describe the recording on its own).
RecordingInputs read_recording_inputs(const CommonOptions& common, const std::string& recording,
                                      const std::string& meta, const std::vector<std::string>& columns,
                                      std::optional<double> speed_rpm, std::optional<double> power_W);

} // namespace pw::app
