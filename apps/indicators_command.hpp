// planetwear indicators: gear condition indicators (FM0, FM4, NA4, NB4, M6A,
// M8A, energy ratio, sideband level factor, kurtosis, crest factor, RMS,
// peak to peak) of the time-synchronous averages of every gear, for a
// recording or for each wear snapshot of a simulation (docs/indicators.md).
//
//   planetwear indicators -r rec.csv [--meta rec.json] [-c gearset.toml] [--column ...] [-o ind.json|ind.csv]
//   planetwear indicators --simulation worn.h5 [-o trend.csv]
//
// Prints a table; -o writes JSON or CSV atomically (by extension). Exit codes
// as for every subcommand: 0 ok, 1 bad input, 3 I/O failure.
#pragma once

#include "commands.hpp"

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pw::app {

struct IndicatorsOptions {
  CommonOptions common;
  std::string recording, meta, simulation, output;
  std::vector<std::string> columns;          ///< --column: replace/add sidecar columns
  std::optional<double> speed_rpm, power_W;  ///< replace the sidecar's operating point
  int samples_per_mesh = 0;                  ///< 0 = automatic
  int shaft_harmonics = 2;
  double planet_window_deg = 0;              ///< 0 = 180/N
};

CLI::App* add_indicators_command(CLI::App& app, IndicatorsOptions& options);
int run_indicators(const IndicatorsOptions& options);

} // namespace pw::app
