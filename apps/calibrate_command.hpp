// planetwear calibrate: the model and its discrepancy budget from healthy recordings
// (docs/diagnose.md §6a, src/diagnose/calibration.hpp).
//
//   planetwear calibrate --config gearset.toml -r healthy1.csv [-r healthy2.csv ...]
//       [--meta healthy1.json ...] -o calibration.toml [--set key=value ...]
//       [--rig-elements encoder_bandwidth] [--healthy-fit noise|model_form] [--threads N]
//       [--alpha 0.01] [--quiet]
//
// Each recording is diagnosed up to its nuisance fit (with the rig elements fitted as
// nuisance parameters); the file holds the median fitted model and the per-(channel kind,
// family) discrepancy with its upper confidence limit. `planetwear diagnose --calibration
// calibration.toml` then judges a recording against it. Exit codes as for every subcommand.
#pragma once

#include "commands.hpp"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pw::app {

struct CalibrateCommandOptions {
  CommonOptions common;
  std::vector<std::string> recordings, metas;
  std::string output;
  std::vector<std::string> rig_elements{"encoder_bandwidth"};
  int threads = 0;
  double alpha = 0.01;
  /// --healthy-fit: "noise" or "model_form" (diagnose::HealthyFit).
  std::string healthy_fit = "noise";
  /// --rig-structure: "shared" (one structure of the calibration-only rig elements for every
  /// recording) or "per_recording" (docs/diagnose.md section 6a item 8).
  std::string rig_structure = "shared";
  /// --ring-body: also try the lateral-torsional model's ring body as the housing path
  /// (docs/diagnose.md section 6a item 12); off by default: its fits cost 3-5 times more per
  /// simulation, and on indepsim4's setD4 it fitted the healthy recordings far better without
  /// naming more faults (docs/diagnose-log.md, session 73).
  bool ring_body = false;
};

CLI::App* add_calibrate_command(CLI::App& app, CalibrateCommandOptions& options);
int run_calibrate(const CalibrateCommandOptions& options);

} // namespace pw::app
