// Measured (or synthesized) recordings of a planetary stage: CSV or HDF5
// files plus a description of what each column measures (a JSON sidecar
// and/or command-line options), read into a diagnose::Recording in SI units.
// Formats, the sidecar schema, accepted units and every check:
// docs/recordings.md.
//
// CSV, as DAQ software exports it:
//   # comment lines start with '#' or '%' (anywhere; also preamble lines
//   # before the header that are not comments are skipped)
//   time [s];acc_housing (g);w_sun [rpm]
//   0,0000;0,012;400,1            <- ';' or tab delimited: decimal commas accepted
// Delimiter (',', ';', tab) detected from the header and the first data row;
// header fields may be quoted; units in "name [unit]" or "name (unit)";
// an optional row of units right below the header; one pass over the file
// (std::getline + std::from_chars), nothing loaded twice.
// HDF5: a time dataset ("/time", or "/time_history/time" as planetwear
// simulate writes it) and one 1-D dataset per column; the "unit" attribute is
// honoured.
//
// Example:
//   auto meta = pw::io::read_recording_meta("rec.json");
//   meta = pw::io::merge(meta, cli_meta);          // command line wins
//   auto config = pw::io::read_config("gearset.toml");
//   pw::diagnose::Recording r = pw::io::read_recording("rec.csv", meta, config);
//
// Every problem throws pw::InputError naming the file and, where it applies,
// the column and row (file line number for CSV, sample index for HDF5);
// a file that cannot be opened throws pw::io::IoError.
#pragma once

#include "config/stage.hpp"
#include "diagnose/recording.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace pw::io {

/// How to read one column.
struct ColumnSpec {
  std::string name;  ///< CSV header name without its unit, or HDF5 dataset path
  diagnose::Quantity quantity = diagnose::Quantity::HousingAcceleration;
  std::string unit;  ///< as written ("rpm", "g", ...); empty: from the header / "unit" attribute
  int planet = 0;    ///< mesh accelerations: which planet's mesh, 0-based
  /// Housing accelerations (required there): angle in the housing frame,
  /// counter-clockwise from planet 0's position at t = 0 [rad].
  std::optional<double> sensor_angle_rad;
  /// Multiplies the raw values before the unit conversion (-1 for an encoder
  /// counting the other way; a sensitivity). Default 1.
  double scale = 1.0;
  /// Speed columns (optional): lines per revolution of a line-counting encoder read by the
  /// period method, in [1, 2^24]. The model then measures that shaft's speed the same way
  /// (sensor.sun_encoder_lines / carrier_encoder_lines; apply_encoder_lines).
  std::optional<int> encoder_lines;
};

/// Everything about a recording that is not in its samples.
struct RecordingMeta {
  std::optional<double> input_speed_rpm;  ///< nominal sun speed [rpm] (required)
  std::optional<double> input_power_W;    ///< give power or torque (required)
  std::optional<double> input_torque_Nm;  ///< mean input torque [N m]; power = torque * speed
  std::string time_column;  ///< empty: "time", "time_s" or "t" (CSV); "/time" or "/time_history/time" (HDF5)
  std::string time_unit;    ///< empty: from the header / attribute, else "s"
  /// For files without a time column: samples are 1 / sample_rate_Hz apart, t0 = 0.
  std::optional<double> sample_rate_Hz;
  std::vector<ColumnSpec> columns;
  std::string source;  ///< where this came from ("rec.json", "command line"), for messages
};

/// The encoders a recording's speed columns state (ColumnSpec::encoder_lines) as the model's
/// sensor.sun_encoder_lines / sensor.carrier_encoder_lines, so that the model measures the
/// speeds as the rig did. A count the configuration already sets to another non-zero value is
/// an InputError naming both (the configuration and the sidecar describe one rig); a column
/// without a count leaves the configuration's.
void apply_encoder_lines(const RecordingMeta& meta, model::SimulationConfig& config);

/// The sidecar (docs/recordings.md "JSON sidecar"). Unknown keys, wrong types
/// and unknown quantities are errors naming the key ("rec.json: columns.acc.unit").
RecordingMeta parse_recording_meta(std::string_view json_text, std::string_view source_name = "<json>");
RecordingMeta read_recording_meta(const std::filesystem::path& json_path);

/// A column from the command line:
///   NAME=QUANTITY[,unit=U][,planet=I][,sensor_angle_deg=A][,sensor_angle_rad=A][,scale=S]
/// e.g. "acc_housing=housing_acceleration,unit=g,sensor_angle_deg=30". Throws
/// pw::InputError naming `option` (e.g. "--column").
ColumnSpec parse_column_option(std::string_view text, std::string_view option = "--column");

/// `base` with everything `overrides` sets replacing it (operating point
/// values, time settings; columns of the same name replaced, new ones
/// appended). Setting power clears a torque of `base` and vice versa.
RecordingMeta merge(RecordingMeta base, const RecordingMeta& overrides);

/// Quantity from its sidecar name ("housing_acceleration", ...).
std::optional<diagnose::Quantity> quantity_from_string(std::string_view name);

/// Factor to SI of `unit` for quantity q (e.g. rpm -> 2 pi / 60 for speeds,
/// g -> 9.80665 for accelerations), case-insensitive, spaces ignored; nothing
/// if the unit cannot be right for q.
std::optional<double> si_factor(diagnose::Quantity q, std::string_view unit);
/// SI unit of q: "rad/s", "m/s^2" or "1".
const char* si_unit(diagnose::Quantity q);

/// Checks a recording must pass (docs/recordings.md "Checks").
inline constexpr int kAnalysedMeshHarmonics = 3;        ///< highest mesh harmonic the diagnosis analyses
inline constexpr double kSampleRateMargin = 2.5;        ///< sample rate >= margin * that harmonic
/// Mesh frequency Zs Zr / (Zs + Zr) n / 60 [Hz] of `config`'s gears at `speed_rpm`.
double mesh_frequency_Hz(const model::SimulationConfig& config, double speed_rpm);
/// kSampleRateMargin * kAnalysedMeshHarmonics * mesh frequency [Hz].
double required_sample_rate_Hz(const model::SimulationConfig& config, double speed_rpm);
/// Fewest mesh cycles a usable recording holds: two halves (fit, held-out) of one sun period
/// Zs each, 2 Zs (diagnose::min_recording_mesh_cycles; docs/diagnose.md §2 "Short recordings").
int required_mesh_cycles(const model::SimulationConfig& config);
/// required_mesh_cycles at the mesh frequency [s].
double required_duration_s(const model::SimulationConfig& config, double speed_rpm);

/// Reads `path` (CSV or HDF5: by extension .csv/.txt/.dat/.h5/.hdf5, else by
/// the HDF5 signature) as described by `meta`, converts to SI and checks it
/// against the gear set of `config` (mesh frequency, carrier speed, planet
/// count). The returned time axis is the uniform grid t0 + k dt through the
/// first and last sample (after checking the file's times lie on it).
diagnose::Recording read_recording(const std::filesystem::path& path, const RecordingMeta& meta,
                                   const model::SimulationConfig& config);

} // namespace pw::io
