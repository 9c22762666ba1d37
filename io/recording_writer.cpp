#include "io/recording_writer.hpp"

#include "io/atomic_output.hpp"
#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <numbers>
#include <ostream>
#include <stdexcept>

namespace pw::io {
namespace {

using diagnose::Quantity;

/// RFC 4180 quoting, only where needed.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (const char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

void put_number(std::ostream& out, double v) {
  std::array<char, 64> buf{};
  const auto result = std::to_chars(buf.data(), buf.data() + buf.size(), v);  // shortest round trip
  out.write(buf.data(), result.ptr - buf.data());
}

void write_text_atomically(const std::filesystem::path& path, AtomicOutput& output, const std::string& text) {
  std::ofstream file(output.temp_path(), std::ios::binary | std::ios::trunc);
  if (!file) throw IoError(output.temp_path().string() + ": cannot create file");
  file << text;
  file.close();
  if (!file) throw IoError(path.string() + ": write failed (disk full?)");
}

} // namespace

std::filesystem::path sidecar_path(const std::filesystem::path& recording_path) {
  std::filesystem::path p = recording_path;
  p.replace_extension(".json");
  return p;
}

std::string recording_meta_json(const diagnose::Recording& r, const RecordingWriteOptions& options) {
  nlohmann::ordered_json j;
  if (!options.description.empty()) j["description"] = options.description;
  j["operating"]["input_speed_rpm"] = r.operating.input_speed_rpm;
  j["operating"]["input_power_W"] = r.operating.input_power_W;
  j["time_column"] = "time";
  j["time_unit"] = "s";
  nlohmann::ordered_json cols = nlohmann::ordered_json::object();
  for (const auto& c : r.channels) {
    nlohmann::ordered_json col;
    col["quantity"] = diagnose::to_string(c.quantity);
    col["unit"] = c.unit;
    if (c.quantity == Quantity::MeshAccelerationSunPlanet || c.quantity == Quantity::MeshAccelerationPlanetRing)
      col["planet"] = c.planet;
    if (c.quantity == Quantity::HousingAcceleration)
      // Rounded to 1e-9 deg so that 30 deg is written as 30, not 29.999999999999996.
      col["sensor_angle_deg"] = std::round(c.sensor_angle_rad * 180.0 / std::numbers::pi * 1e9) / 1e9;
    if (c.quantity == Quantity::SunSpeed && options.sun_encoder_lines > 0) col["encoder_lines"] = options.sun_encoder_lines;
    if (c.quantity == Quantity::CarrierSpeed && options.carrier_encoder_lines > 0)
      col["encoder_lines"] = options.carrier_encoder_lines;
    cols[c.name] = col;
  }
  j["columns"] = cols;
  return j.dump(2) + "\n";
}

void write_recording_csv(std::ostream& out, const diagnose::Recording& r) {
  for (const auto& c : r.channels)
    if (c.values.size() != r.time_s.size())
      throw std::invalid_argument("channel '" + c.name + "' has " + std::to_string(c.values.size()) +
                                  " samples but the time axis has " + std::to_string(r.time_s.size()));
  out << "time [s]";
  for (const auto& c : r.channels) out << ',' << csv_field(c.name + " [" + c.unit + "]");
  out << '\n';
  for (std::size_t i = 0; i < r.time_s.size(); ++i) {
    put_number(out, r.time_s[i]);
    for (const auto& c : r.channels) {
      out << ',';
      put_number(out, c.values[i]);
    }
    out << '\n';
  }
}

std::filesystem::path write_recording(const std::filesystem::path& csv_path, const diagnose::Recording& r,
                                      const RecordingWriteOptions& options) {
  const std::filesystem::path json_path = sidecar_path(csv_path);
  if (json_path == csv_path)
    throw IoError(csv_path.string() + ": the recording must not have the extension .json (its sidecar's)");
  AtomicOutput csv(csv_path), meta(json_path);
  {
    std::ofstream file(csv.temp_path(), std::ios::binary | std::ios::trunc);
    if (!file) throw IoError(csv.temp_path().string() + ": cannot create file");
    write_recording_csv(file, r);
    file.close();
    if (!file) throw IoError(csv_path.string() + ": write failed (disk full?)");
  }
  write_text_atomically(json_path, meta, recording_meta_json(r, options));
  csv.commit();
  meta.commit();
  return json_path;
}

} // namespace pw::io
