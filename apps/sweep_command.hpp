// `planetwear sweep`: a design-of-experiments campaign over configuration
// keys, on 1..P MPI ranks, into one crash-safe HDF5 archive
// (docs/campaigns.md, docs/archive-format.md).
//
//   planetwear sweep CAMPAIGN.toml -o results.h5 [--resume | --force] [--quiet]
//                    [--checkpoint-cases k] [--checkpoint-seconds t] [--dry-run]
//   mpirun -np 4 planetwear sweep sweep/campaigns/demo_lhs.toml -o demo.h5
#pragma once

#include <CLI/CLI.hpp>

#include <string>

namespace pw::app {

struct SweepCommandOptions {
  std::string campaign, output;
  bool resume = false, force = false, quiet = false, dry_run = false;
  int checkpoint_cases = 32;
  double checkpoint_seconds = 60;
  std::string cases;  ///< "BEGIN:END" slice (array jobs); empty = all
};

/// Adds the subcommand and its options to `app`.
CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& options);

/// --dry-run: prints the cases and exits (no MPI, no files); otherwise runs
/// the campaign (MPI_Init happens in here). Returns the exit code.
int run_sweep(const SweepCommandOptions& options);

} // namespace pw::app
