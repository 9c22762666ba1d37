// A campaign: a base simulation case, the factors varied around it and the
// design that combines them (docs/campaigns.md). Reading and checking only,
// no MPI: every rank-independent decision about the cases is made here,
// before any rank starts computing.
//
// Example campaign file:
//
//   [campaign]
//   name = "speed x power"
//
//   [base]
//   config = "../../config/seed.toml"     # relative to this file; optional
//   [base.set]                            # planetwear simulate --set key=value
//   "solver.record_mesh_cycles" = 4
//   wear.mesh_cycles = 2e4                # dotted keys work too
//
//   [[factors]]
//   key = "operating.input_speed_rpm"
//   unit = "rpm"
//   levels = [100, 200, 400]
//
//   [[factors]]
//   key = "operating.input_power_W"
//   unit = "W"
//   min = 500.0
//   max = 2000.0
//
//   [design]
//   type = "full_factorial"
//   points = 3            # for factors without levels
//
//   [output]
//   time_history_decimation = 4   # every 4th sample of planet 0's meshes; 0 = none
//   spectrum_max_frequency_Hz = 5000.0   # cut the stored spectra; 0 = all bins
//
// Usage:
//   const Campaign c = read_campaign("campaign.toml");   // throws pw::InputError
//   validate_cases(c);                                   // every case's config
//   model::SimulationConfig config = case_config(c, 17);
#pragma once

#include "design.hpp"

#include "config/stage.hpp"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace pw::sweep {

/// The [output] table.
struct OutputOptions {
  /// Store every k-th sample of the recorded time histories of planet 0's
  /// meshes and the transmission error; 0 = no time histories.
  int time_history_decimation = 0;
  /// Keep the acceleration spectra up to this frequency [Hz]; 0 = every bin
  /// (up to the Nyquist frequency of the time step, often tens of kHz).
  double spectrum_max_frequency_Hz = 0;
};

struct Campaign {
  std::filesystem::path file;          ///< the campaign file ("" when parsed from text)
  std::string text;                    ///< its TOML text, verbatim
  std::string name, description;       ///< [campaign] (optional)
  std::filesystem::path base_config_file;  ///< [base] config resolved against the campaign's directory; "" = defaults
  std::string base_config_text;        ///< its text ("" = the defaults)
  std::vector<std::string> base_set;   ///< [base.set] as "key=value" assignments
  model::SimulationConfig base;        ///< base config after [base.set], validated
  std::vector<Factor> factors;
  DesignSpec design;
  std::filesystem::path list_file;     ///< list designs: the CSV file
  OutputOptions output;
  std::vector<DesignPoint> cases;      ///< make_design(factors, design)
  /// FNV-1a 64 of the campaign text, the base config text and the list text:
  /// a resumed run refuses an archive written for other inputs.
  std::uint64_t input_hash = 0;
  /// FNV-1a 64 of the resolved base config (io::to_toml) and every case's
  /// assignments: catches a software change that resolves the same inputs
  /// differently.
  std::uint64_t design_hash = 0;
};

/// Reads a campaign file; relative paths in it are relative to its directory.
/// Throws pw::io::IoError for unreadable files and pw::InputError naming the
/// campaign key ("factors[1].key", "design.type", "base.set.solver.level") for
/// TOML syntax errors, unknown or mistyped keys, factor keys that are not
/// numeric configuration keys (io::config_keys()), units that differ from the
/// key's documented unit, and every design error of make_design().
Campaign read_campaign(const std::filesystem::path& file);

/// As read_campaign() for TOML text; `base_dir` resolves relative paths.
Campaign parse_campaign(std::string_view text, const std::filesystem::path& base_dir,
                        std::string_view source_name = "<campaign>");

/// The documented unit of a configuration key, from io::config_keys() (the
/// first "[...]" of its description, "-" for dimensionless), or "" if none.
/// Indices in the path ("imperfections.teeth[2].tooth") are ignored.
std::string documented_unit(std::string_view key_path);

/// Case `index` as `planetwear simulate --set` assignments, one per factor,
/// e.g. "operating.input_speed_rpm=200". Integer keys are printed as whole
/// numbers, floats in shortest round-trip form.
std::vector<std::string> case_assignments(const Campaign& c, std::size_t index);

/// The configuration of case `index`: base + case_assignments(), validated.
/// Throws pw::InputError from model::validate().
model::SimulationConfig case_config(const Campaign& c, std::size_t index);

/// "operating.input_speed_rpm = 200 rpm, operating.input_power_W = 1000 W".
std::string describe_case(const Campaign& c, std::size_t index);

/// Builds and validates every case's configuration (model::validate, then
/// the stage geometry and planet assembly, geometry::make_stage_geometry);
/// throws pw::InputError "case <i> (<factor values>): <reason>" for the first
/// invalid one.
void validate_cases(const Campaign& c);

/// FNV-1a 64-bit hash, and as 16 lowercase hex digits.
std::uint64_t fnv1a64(std::string_view data, std::uint64_t hash = 0xcbf29ce484222325ULL);
std::string hex64(std::uint64_t value);

std::string_view to_string(DesignType type);

/// What a sampled design achieved, as lines for the user (empty for other designs or
/// one factor): a latin_hypercube's Spearman rank correlations between the factors'
/// values, each with its target (0 without design.correlation), and the largest
/// deviation from the target. Plain Latin hypercubes carry spurious correlations of
/// order 1/sqrt(samples); printed so that nobody reads an effect into them.
std::vector<std::string> rank_correlation_report(const Campaign& c);
std::string_view to_string(Scale scale);

} // namespace pw::sweep
