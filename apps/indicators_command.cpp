// planetwear indicators (indicators_command.hpp):
//   recording: configuration + sidecar -> diagnose::Recording -> diagnose::recording_indicators
//   simulation: /wear/snapshots -> diagnose::channel_indicators per snapshot (NA4/NB4 over the run)
//   -> table on stdout, -o JSON/CSV (io/indicator_report.hpp, atomic)
#include "indicators_command.hpp"

#include "recording_input.hpp"

#include "core/error.hpp"
#include "diagnose/indicators.hpp"
#include "io/config_toml.hpp"
#include "io/indicator_report.hpp"
#include "io/recording_writer.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <numbers>

namespace pw::app {

CLI::App* add_indicators_command(CLI::App& app, IndicatorsOptions& o) {
  CLI::App* d = app.add_subcommand(
      "indicators", "Gear condition indicators (FM0, FM4, NA4, NB4, M6A, M8A, energy ratio, sideband level factor, "
                    "kurtosis, crest factor) of the time-synchronous averages of sun, planets and carrier, for a "
                    "recording or for each wear snapshot of a simulation (docs/indicators.md)");
  d->add_option("-c,--config", o.common.config, "TOML configuration of the gear set (default: the seed paper's case)")
      ->check(CLI::ExistingFile);
  d->add_option("--set", o.common.assignments, "override any configuration key: --set section.key=value")->take_all();
  CLI::Option* rec = d->add_option("-r,--recording", o.recording, "recording (CSV or HDF5, docs/recordings.md)")
                         ->check(CLI::ExistingFile);
  CLI::Option* sim = d->add_option("--simulation", o.simulation,
                                   "a wear run of `planetwear simulate --mesh-cycles N` (HDF5): indicators of every "
                                   "wear snapshot, i.e. their trend as the flanks wear")
                         ->check(CLI::ExistingFile);
  rec->excludes(sim);
  d->add_option("--meta", o.meta, "JSON sidecar describing the recording (default: the recording's name with .json)")
      ->needs(rec);
  d->add_option("--column", o.columns,
                "describe a recording column on the command line (repeatable): "
                "NAME=QUANTITY[,unit=U][,planet=I][,sensor_angle_deg=A][,scale=S] (docs/recordings.md)")
      ->needs(rec);
  d->add_option("--speed-rpm", o.speed_rpm, "nominal input (sun) speed [rpm]; replaces the sidecar's")->needs(rec);
  d->add_option("--power-w", o.power_W, "input power [W]; replaces the sidecar's power or torque")->needs(rec);
  d->add_option("-o,--output", o.output, "write the indicators to this .json or .csv file (atomically)");
  d->add_option("--samples-per-mesh", o.samples_per_mesh,
                "angle-domain samples per mesh cycle of the averages; 0 = the signal's own samples per mesh cycle "
                "rounded up, at least " + std::to_string(diagnose::kMinSamplesPerMesh) + " (default 0)");
  d->add_option("--shaft-harmonics", o.shaft_harmonics,
                "shaft orders 1..H removed with the mesh harmonics from the difference and residual signals "
                "(default 2)");
  d->add_option("--planet-window-deg", o.planet_window_deg,
                "half-width of the planet-separation window in carrier angle [deg]; 0 = 180/N (default 0)");
  d->add_flag("-q,--quiet", o.common.quiet, "no table on stdout");
  d->footer("Examples:\n  planetwear indicators -r rec.csv -o indicators.json\n"
            "  planetwear indicators --simulation worn.h5 -o trend.csv   (then scripts/plot_indicator_trend.py)");
  return d;
}

namespace {

diagnose::IndicatorOptions indicator_options(const IndicatorsOptions& o) {
  diagnose::IndicatorOptions opt;
  opt.samples_per_mesh = o.samples_per_mesh;
  opt.shaft_harmonics = o.shaft_harmonics;
  require(o.planet_window_deg >= 0 && o.planet_window_deg <= 180, "--planet-window-deg",
          "must be 0 (automatic) or in (0, 180] deg, got ", o.planet_window_deg);
  opt.planet_window_half_width_rad = o.planet_window_deg * std::numbers::pi / 180;
  return opt;
}

io::IndicatorReport recording_report(const IndicatorsOptions& o) {
  const RecordingInputs in = read_recording_inputs(o.common, o.recording, o.meta, o.columns, o.speed_rpm, o.power_W);
  io::IndicatorReport r;
  r.kind = "recording";
  r.source = o.recording;
  r.options = indicator_options(o);
  for (diagnose::IndicatorRow& row :
       diagnose::recording_indicators(in.recording, in.config, r.options, &r.skipped, &r.angle_source))
    r.records.push_back({std::numeric_limits<double>::quiet_NaN(), std::move(row)});
  return r;
}

io::IndicatorReport simulation_report(const IndicatorsOptions& o) {
  require(o.common.config.empty() && o.common.assignments.empty(), "--config",
          "a simulation file carries its own configuration (/config/toml); --config and --set apply to recordings");
  model::SimulationConfig config;
  const std::vector<io::SnapshotSignals> snaps = io::read_wear_snapshots(o.simulation, config);
  io::IndicatorReport r;
  r.kind = "simulation";
  r.source = o.simulation;
  r.options = indicator_options(o);
  r.angle_source = snaps.front().absolute_angle ? "carrier/angle of each snapshot"
                                                : "nominal carrier speed (the snapshots store no carrier/angle)";
  diagnose::RunHistory history;
  for (const io::SnapshotSignals& s : snaps)
    for (const io::SnapshotChannel& c : s.channels) {
      const diagnose::ChannelSignal ch{c.name, c.quantity, c.unit, c.planet, config.sensor.angle_rad, c.values};
      std::vector<diagnose::SkippedAverage> skipped;
      for (diagnose::IndicatorRow& row :
           diagnose::channel_indicators(s.time_s, s.carrier_angle_rad, ch, config, r.options, &skipped, &history))
        r.records.push_back({s.mesh_cycles, std::move(row)});
      for (auto& k : skipped) {
        k.reason = "snapshot at " + std::to_string(static_cast<long long>(s.mesh_cycles)) + " mesh cycles, " + k.reason;
        r.skipped.push_back(std::move(k));
      }
    }
  return r;
}

} // namespace

int run_indicators(const IndicatorsOptions& o) {
  require(o.recording.empty() != o.simulation.empty(), "--recording",
          "give either -r/--recording REC or --simulation RUN.h5 (exactly one)");
  if (!o.output.empty()) {
    // Writing the indicators over the input (e.g. -o rec.json beside rec.csv: the sidecar) would destroy it.
    namespace fs = std::filesystem;
    const fs::path out = fs::weakly_canonical(o.output);
    std::vector<fs::path> inputs;
    if (!o.recording.empty()) {
      inputs = {o.recording, o.meta.empty() ? io::sidecar_path(o.recording) : fs::path(o.meta)};
    } else {
      inputs = {o.simulation};
    }
    for (const fs::path& in : inputs)
      require(out != fs::weakly_canonical(in), "-o", "'", o.output, "' is an input of this command ('", in.string(),
              "'); choose another output name, e.g. indicators.json");
  }
  io::IndicatorReport r = o.recording.empty() ? simulation_report(o) : recording_report(o);
  r.version = version_string();
  if (r.records.empty()) {
    std::string why;
    for (const auto& s : r.skipped) why += "\n  " + s.reason;
    throw InputError(o.recording.empty() ? "--simulation" : "--recording",
                     "no gear average could be formed (needs housing or mesh-line acceleration channels over at "
                     "least one revolution of the gear):" + why);
  }
  if (!o.output.empty()) io::write_indicator_report(o.output, r);
  if (!o.common.quiet) {
    std::cout << "gear condition indicators of " << r.source << " (angle reference: " << r.angle_source << ")\n"
              << io::indicator_table(r);
  }
  if (!o.output.empty() && !o.common.quiet) std::fprintf(stderr, "wrote %s\n", o.output.c_str());
  return 0;
}

} // namespace pw::app
