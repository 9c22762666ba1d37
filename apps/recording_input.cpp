// Reading a recording for diagnose / indicators (recording_input.hpp).
#include "recording_input.hpp"

#include "core/error.hpp"
#include "io/config_toml.hpp"
#include "io/recording_reader.hpp"
#include "io/recording_writer.hpp"

#include <filesystem>

namespace pw::app {

model::SimulationConfig read_gear_set_config(const CommonOptions& common) {
  model::SimulationConfig config = common.config.empty() ? model::SimulationConfig{} : io::read_config(common.config);
  io::apply_overrides(config, common.assignments);
  return config;
}

RecordingInputs read_recording_inputs(const CommonOptions& common, const std::string& recording,
                                      const std::string& meta, const std::vector<std::string>& columns,
                                      std::optional<double> speed_rpm, std::optional<double> power_W) {
  namespace fs = std::filesystem;
  model::SimulationConfig config = read_gear_set_config(common);
  const fs::path meta_path = meta.empty() ? io::sidecar_path(recording) : fs::path(meta);
  // The command line describes the recording on its own (no sidecar needed) or
  // replaces parts of the sidecar (io::merge: the command line wins).
  io::RecordingMeta cli;
  cli.source = "command line";
  cli.input_speed_rpm = speed_rpm;
  cli.input_power_W = power_W;
  for (const std::string& c : columns) cli.columns.push_back(io::parse_column_option(c, "--column"));
  const bool described_here = !cli.columns.empty() && speed_rpm && power_W;
  const bool have_sidecar = fs::exists(meta_path);
  if (!have_sidecar && (!meta.empty() || !described_here))
    throw InputError("--meta", "no sidecar '" + meta_path.string() +
                                   "': give the JSON description of the recording's columns (docs/recordings.md), "
                                   "or describe it with --column, --speed-rpm and --power-w");
  const io::RecordingMeta m = have_sidecar ? io::merge(io::read_recording_meta(meta_path), cli) : cli;
  diagnose::Recording rec = io::read_recording(recording, m, config);
  io::apply_encoder_lines(m, config);  // the model measures the speeds as the rig's encoders did
  return RecordingInputs{std::move(config), std::move(rec)};
}

} // namespace pw::app
