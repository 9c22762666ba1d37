// Writes a diagnose::Recording as a CSV file plus its JSON sidecar, in the
// form io/recording_reader.hpp reads back (docs/recordings.md):
//
//   rec.csv   time [s],sun_speed [rad/s],housing_acc [m/s^2],...
//             2.5,41.88,0.0123,...          (shortest round-trip doubles)
//   rec.json  {"operating": {"input_speed_rpm": 400, "input_power_W": 1000},
//              "time_column": "time",
//              "columns": {"housing_acc": {"quantity": "housing_acceleration",
//                                          "unit": "m/s^2", "sensor_angle_deg": 30}, ...}}
//
// Both files are written atomically (AtomicOutput): on error neither is left
// behind and existing files are untouched.
#pragma once

#include "diagnose/recording.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>

namespace pw::io {

struct RecordingWriteOptions {
  std::string description;  ///< free text stored as "description" in the sidecar (optional)
  /// Lines per revolution of the encoders the speed columns were measured with (period method,
  /// sensor.sun_encoder_lines / carrier_encoder_lines), stated as the columns' encoder_lines;
  /// 0 = ideal encoders, not stated.
  int sun_encoder_lines = 0;
  int carrier_encoder_lines = 0;
};

/// The sidecar's path for a recording file: same name, extension ".json".
std::filesystem::path sidecar_path(const std::filesystem::path& recording_path);

/// The sidecar text (pretty-printed JSON, keys in the order above).
std::string recording_meta_json(const diagnose::Recording& recording, const RecordingWriteOptions& options = {});

/// CSV text of the samples to `out`. Throws std::invalid_argument if a channel
/// is not as long as the time axis.
void write_recording_csv(std::ostream& out, const diagnose::Recording& recording);

/// Writes `csv_path` and sidecar_path(csv_path); returns the sidecar's path.
/// Throws pw::io::IoError for file-system failures.
std::filesystem::path write_recording(const std::filesystem::path& csv_path, const diagnose::Recording& recording,
                                      const RecordingWriteOptions& options = {});

} // namespace pw::io
