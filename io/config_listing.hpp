// The configuration schema (config_keys()) as text for people and programs:
//  * keys_json()       - `planetwear keys --format json`: every key with its
//                        type, unit, default and doc, one JSON array;
//  * config_template() - `planetwear config --template`: a commented TOML file
//                        of every key at its default (deal.II .prm style) that
//                        reads back as the defaults.
#pragma once

#include <string>
#include <string_view>

namespace pw::io {

/// The unit of a key's doc string: the last non-empty "[...]" in it ("[rpm]"
/// -> "rpm", "[-]" -> "-", "[rad]; [] = none" -> "rad"), "" when the doc names
/// none (booleans, choices).
std::string unit_of_doc(std::string_view doc);

/// JSON array of {"key", "type", "unit", "default", "doc"} objects in file
/// order; "default" is the TOML text of the default, as `keys` prints it.
std::string keys_json();

/// Every key as "key = default" under its [section], each preceded by its doc
/// as a comment. Alternatives (pressure_angle_deg) and the tooth-modifier
/// fields are commented out, so that parse_config(config_template()) gives
/// the default configuration.
std::string config_template();

} // namespace pw::io
