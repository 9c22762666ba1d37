// planetwear diagnose: where do a recording and the model differ, which
// physics is missing, fitted and checked on held-out data (docs/diagnose.md).
//
//   planetwear diagnose --config gearset.toml --recording rec.csv [--meta rec.json] -o report/
//       [--set key=value ...] [--threads N] [--alpha 0.01] [--max-candidates 4]
//       [--candidates a,b,...] [--calibration calibration.toml [--calibration-reference auto|none]
//       | --baseline healthy.csv [--baseline-meta healthy.json]] [--no-plots] [--quiet]
//
// Writes report/report.{md,html,json}, report/data/*.csv and, through
// scripts/plot_diagnosis.py (Debian's /usr/bin/python3 + matplotlib), the PNGs.
// Exit codes as for every subcommand: 0 ok (whatever the verdict), 1 bad input,
// 2 solver failure, 3 I/O failure.
#pragma once

#include "commands.hpp"

#include "diagnose/calibration.hpp"
#include "diagnose/recording.hpp"

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pw::app {

struct DiagnoseCommandOptions {
  CommonOptions common;
  std::string recording, meta, output;
  std::vector<std::string> columns;          ///< --column NAME=QUANTITY[,unit=U]...: replace/add sidecar columns
  std::optional<double> speed_rpm, power_W;  ///< --speed-rpm, --power-w: replace the sidecar's operating point
  int threads = 0;
  double alpha = 0.01;
  int max_candidates = 4;
  std::vector<std::string> candidates;
  bool no_plots = false;
  bool always_fit = false;
  std::string calibration;  ///< --calibration FILE (planetwear calibrate): calibrated model + discrepancy budget
  /// --baseline FILE: a healthy recording at the same operating point (differential diagnosis,
  /// src/diagnose/baseline.hpp); --baseline-meta its sidecar (default: its name with .json).
  std::string baseline, baseline_meta;
  /// --baseline-transfer: "additive" (default) or "line_ratio" (diagnose::BaselineTransfer).
  std::string baseline_transfer = "additive";
  /// --calibration-reference: "auto" takes the calibration's own healthy recording at the
  /// recording's operating point as the reference (docs/diagnose.md §6a item 7), "none" judges
  /// against the calibration's budget alone.
  std::string calibration_reference = "auto";
  /// --healthy-fit: how the healthy reference is fitted, "noise" or "model_form"
  /// (diagnose::HealthyFit); empty: the calibration's own setting, else "noise".
  std::string healthy_fit;
};

/// What a diagnosis starts from: the configuration (file, calibration overrides, --set, in that
/// order) and the recording in SI, validated.
struct DiagnoseInputs {
  model::SimulationConfig config;
  diagnose::Recording recording;
  std::optional<diagnose::Calibration> calibration;  ///< --calibration, read once
};

/// Reads and validates the inputs of `options` (used by diagnose and calibrate); throws
/// InputError naming the option.
DiagnoseInputs read_diagnose_inputs(const DiagnoseCommandOptions& options);

/// The rig elements a recording can see (an encoder's bandwidth only through a speed channel):
/// those `calibrate` fits on it, and a calibrated reference is fitted with.
std::vector<std::string> visible_rig_elements(const std::vector<std::string>& rig, const diagnose::Recording& r);

CLI::App* add_diagnose_command(CLI::App& app, DiagnoseCommandOptions& options);
int run_diagnose(const DiagnoseCommandOptions& options, const std::string& command_line);

} // namespace pw::app
