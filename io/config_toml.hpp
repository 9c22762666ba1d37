// TOML configuration: reading (with defaults, unknown-key and type checks),
// writing the fully resolved configuration, and command-line overrides.
//
// Key names are the C++ field names of model::SimulationConfig, grouped in the
// sections [stage], [stage.sun], [stage.planet], [stage.ring], [operating],
// [stiffness], [contact], [imperfections] (+ [[imperfections.teeth]]),
// [bearings], [solver] and [wear]; docs/config.md lists every key with its
// type, unit, default and range, and config/seed.toml is a complete commented
// sample.
//
// Rules:
//  * Every key is optional; a missing key keeps its default (the seed case).
//  * Unknown keys and sections are errors naming the key, the file position
//    and the closest valid key.
//  * Types are strict: an integer is accepted where a float is expected, not
//    the reverse; enumerations are strings ("torsional", "sun", ...).
//  * A gear's pressure angle may be given as pressure_angle_rad or
//    pressure_angle_deg (converted with pi/180), not both.
//  * After reading, model::validate() checks every range; its errors carry the
//    key path as InputError::parameter() and the file position of the key.
//
// Example:
//   auto config = pw::io::read_config("config/seed.toml");
//   pw::io::apply_overrides(config, {"operating.input_speed_rpm=200"});
//   std::string resolved = pw::io::to_toml(config);  // stored in the output
#pragma once

#include "config/stage.hpp"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace pw::io {

/// Reads and validates a configuration file. Throws pw::io::IoError if the file
/// cannot be read, pw::InputError for syntax errors ("file:line:col: ..."),
/// unknown keys, wrong types and out-of-range values.
model::SimulationConfig read_config(const std::filesystem::path& path);

/// As read_config() for TOML text; `source_name` is used in messages.
model::SimulationConfig parse_config(std::string_view toml_text, std::string_view source_name = "<string>");

/// The fully resolved configuration as TOML: every key, doubles in shortest
/// round-trip form, so parse_config(to_toml(c)) reproduces c exactly. Does not
/// validate (it can print an invalid configuration for an error report).
std::string to_toml(const model::SimulationConfig& config);

/// Sets one key from its TOML value text, e.g. ("operating.input_speed_rpm",
/// "200"), ("solver.level", "lateral_torsional") (quotes optional for strings),
/// ("stage.planet_angles_rad", "[0, 2.0, 4.0]"),
/// ("imperfections.teeth[0].stiffness_factor", "0.5") (index == current count
/// appends a default modifier) or ("imperfections.teeth", "[{body = \"sun\",
/// tooth = 3, stiffness_factor = 0.6}]"). Same key names and type rules as the
/// file. Does NOT run validate(): several overrides may be needed to reach a
/// consistent state (planet_count and planet_angles_rad), so validate once after
/// the last one, or use apply_overrides(). Throws pw::InputError naming the key.
void apply_override(model::SimulationConfig& config, std::string_view key_path, std::string_view value);

/// Applies "key=value" assignments in order (as for `--set key=value`), then
/// validates the result once. Throws pw::InputError.
void apply_overrides(model::SimulationConfig& config, const std::vector<std::string>& assignments);

/// One configuration key, for listings (`--help`-style) and documentation tests.
struct KeyInfo {
  std::string path;           ///< "operating.input_speed_rpm"; tooth modifiers as "imperfections.teeth[].tooth"
  std::string type;           ///< "integer", "float", "boolean", "string", "array of floats", "array of tables"
  std::string default_value;  ///< TOML text of the default
  std::string doc;            ///< one line, with the unit
  std::string range;          ///< allowed values as the schema states them ("in (0, 1]", ">= 0", a rule's text; "" for none)
};

/// Every accepted key in file order, including the alternative
/// pressure_angle_deg keys.
std::vector<KeyInfo> config_keys();

} // namespace pw::io
