// The subcommands of the planetwear executable. Each run_* validates its
// options, calls the library and returns the process exit code; errors
// propagate as pw::InputError / pw::SolverError / pw::io::IoError.
#pragma once

#include "model/simulation.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pw::app {

struct CommonOptions {
  std::string config;                    ///< TOML file; empty = defaults (seed case)
  std::vector<std::string> assignments;  ///< "section.key=value"
  bool quiet = false;
};

struct SimulateOptions {
  CommonOptions common;
  std::optional<double> speed_rpm, power_W;
  std::optional<double> mesh_cycles;  ///< wear.mesh_cycles
  std::optional<double> kappa_m2_N;   ///< wear.coefficient_m2_N
  std::string output, csv;
  model::OutputSelection output_selection;  ///< --time-history-decimation, --channels
  int compression_level = 0;                ///< --compression: 0 none, 1..9 shuffle + deflate
  std::string report;                       ///< --report: the engineering summary as Markdown
  double allowable_contact_stress_Pa = 0;   ///< --allowable-contact-stress-pa [Pa]
};

struct StiffnessOptions {
  CommonOptions common;
  std::string output, csv;
};

struct ConfigOptions {
  CommonOptions common;
  bool template_only = false;  ///< --template: the commented defaults
};

std::string version_string();
int run_simulate(const SimulateOptions& options);
int run_stiffness(const StiffnessOptions& options);
/// `keys`: the text table, or with format "json" keys_json().
int run_keys(const std::string& format);
/// `planetwear candidates`: the diagnosis's candidate library as a table or JSON (io/candidate_listing.hpp).
int run_candidates(const std::string& format);
/// `config`: the resolved configuration as TOML, or with --template the
/// commented defaults (io/config_listing.hpp).
int run_config(const ConfigOptions& options);

} // namespace pw::app
