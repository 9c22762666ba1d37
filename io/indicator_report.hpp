// Gear condition indicators as files and tables (docs/indicators.md §4):
// the wear snapshots of a `planetwear simulate --mesh-cycles` file read as
// signals, and the indicator rows of diagnose/indicators.hpp written as a
// JSON document, a CSV table (both atomically) or a text table.
#pragma once

#include "config/stage.hpp"
#include "diagnose/indicators.hpp"

#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace pw::io {

/// One snapshot's channel, in SI units.
struct SnapshotChannel {
  std::string name;  ///< dataset name below time_history, e.g. "housing/acceleration"
  diagnose::Quantity quantity = diagnose::Quantity::HousingAcceleration;
  std::string unit;
  int planet = 0;
  std::vector<double> values;
};

/// The dynamic state at one wear update (docs/output-format.md "Wear").
struct SnapshotSignals {
  double mesh_cycles = 0;
  std::vector<double> time_s;
  /// Absolute carrier angle [rad] (the snapshot's carrier/angle channel; for
  /// files without it the nominal Omega_c t, which fixes no planet position).
  std::vector<double> carrier_angle_rad;
  bool absolute_angle = false;  ///< true if carrier/angle was stored
  std::vector<SnapshotChannel> channels;  ///< housing and mesh-line accelerations found
};

/// The configuration (/config/toml) and every snapshot of a wear run, sorted
/// by mesh cycles. Throws pw::InputError naming `option` if the file is not a
/// wear run (no /wear/snapshots) or a snapshot has no usable channel;
/// pw::io::IoError if it cannot be read.
std::vector<SnapshotSignals> read_wear_snapshots(const std::filesystem::path& path, model::SimulationConfig& config,
                                                 const std::string& option = "--simulation");

/// One output row: an indicator row and, for simulations, its snapshot.
struct IndicatorRecord {
  double mesh_cycles = std::numeric_limits<double>::quiet_NaN();  ///< NaN for recordings
  diagnose::IndicatorRow row;
};

struct IndicatorReport {
  std::string kind;          ///< "recording" or "simulation"
  std::string source;        ///< input file
  std::string angle_source;  ///< how the carrier angle was obtained
  std::string version;       ///< software version
  diagnose::IndicatorOptions options;
  std::vector<IndicatorRecord> records;
  std::vector<diagnose::SkippedAverage> skipped;
};

/// Fixed-width text table, one line per record, units in the header.
std::string indicator_table(const IndicatorReport& report);
/// JSON document (docs/indicators.md §4); NaN as null.
std::string indicator_json(const IndicatorReport& report);
/// CSV, one row per record, header "name [unit]"; NaN as "nan".
std::string indicator_csv(const IndicatorReport& report);
/// Writes indicator_json (".json") or indicator_csv (".csv") atomically;
/// any other extension is a pw::InputError naming "-o".
void write_indicator_report(const std::filesystem::path& path, const IndicatorReport& report);

} // namespace pw::io
