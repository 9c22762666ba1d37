// planetwear: command-line front end. Each subcommand reads a configuration
// (TOML, defaults = the seed paper's case), runs the physics library and
// writes one output file atomically (nothing is left behind on error).
//
//   planetwear simulate [--config FILE] [--speed-rpm X] [--power-w P]
//                       [--mesh-cycles N] [--kappa K]
//                       [--set key=value ...] -o out.h5 [--csv out.csv]
//   e.g. the seed's wear run: planetwear simulate --mesh-cycles 2e5 -o wear.h5
//   planetwear stiffness [--config FILE] [--set ...] [-o stiffness.h5]
//   planetwear keys     (every configuration key with unit and default)
//   planetwear synth [--config FILE] [--set ...] [--seconds S] [--noise F] [--dc-offset F]
//                    [--seed N] [--sensor-angle-deg A] [--decimate K] [--tacho] -o rec.csv
//                       (a synthetic recording + rec.json sidecar, docs/recordings.md)
//   planetwear diagnose [--config FILE] [--set ...] --recording rec.csv [--meta rec.json] -o report/
//                       (where a recording and the model differ, the missing physics, docs/diagnose.md)
//   planetwear indicators -r rec.csv [--meta rec.json] [-o ind.json|ind.csv]
//   planetwear indicators --simulation worn.h5 [-o trend.csv]
//                       (gear condition indicators FM0, FM4, NA4, ... of sun, planets, carrier, docs/indicators.md)
//   [mpirun -np P] planetwear sweep CAMPAIGN.toml -o results.h5 [--resume|--force]
//                       (a design-of-experiments campaign, docs/campaigns.md)
//
// Exit codes: 0 success, 1 bad input (the message names the parameter),
// 2 solver failure, 3 I/O failure, 4 wear stopped early at the safe wear limit
// (results up to then are written); sweep: 4 = the campaign finished but some
// cases failed (their reasons are in the archive).
#include "commands.hpp"
#include "diagnose_command.hpp"
#include "indicators_command.hpp"
#include "sweep_command.hpp"
#include "synth_command.hpp"

#include "core/error.hpp"
#include "io/io_error.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  CLI::App app{"planetwear: dynamics and wear of planetary gear stages (SI units throughout)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", pw::app::version_string());

  pw::app::SimulateOptions sim;
  CLI::App* s = app.add_subcommand("simulate", "Simulate one operating point; write time histories, stiffness "
                                               "curves and spectra (and, with --mesh-cycles, the flank wear "
                                               "history) to one HDF5 file");
  s->add_option("-c,--config", sim.common.config, "TOML configuration (default: the seed paper's case)")
      ->check(CLI::ExistingFile);
  s->add_option("--speed-rpm", sim.speed_rpm, "input (sun) speed [rpm]; overrides operating.input_speed_rpm");
  s->add_option("--power-w", sim.power_W, "input power [W]; overrides operating.input_power_W");
  s->add_option("--mesh-cycles", sim.mesh_cycles,
                "wear the flanks through N mesh cycles (e.g. 2e5, the seed's run; 0 = no wear); overrides "
                "wear.mesh_cycles");
  s->add_option("--kappa", sim.kappa_m2_N,
                "Archard wear coefficient kappa = K/H [m^2/N] (default 5e-17); overrides wear.coefficient_m2_N");
  s->add_option("--set", sim.common.assignments, "override any configuration key: --set section.key=value")
      ->take_all();
  s->add_option("-o,--output", sim.output, "output HDF5 file")->required();
  s->add_option("--csv", sim.csv, "also write the time histories as CSV");
  s->add_option("--time-history-decimation", sim.output_selection.decimation,
                "store every k-th time step of the recorded mesh periods (as a campaign's "
                "output.time_history_decimation; default 1 = every step)")
      ->check(CLI::Range(1, 1000000));
  s->add_option("--channels", sim.output_selection.channels,
                "store only these time-history channels (comma-separated names as in docs/output-format.md; a "
                "name ending in '/' selects everything below it, e.g. --channels sun_planet/0/,housing/acceleration)")
      ->delimiter(',');
  s->add_flag("-q,--quiet", sim.common.quiet, "no progress on stderr");

  pw::app::StiffnessOptions stf;
  CLI::App* k = app.add_subcommand("stiffness", "Mesh stiffness of both mesh types by the potential energy method "
                                                "(seed Fig. 8, Table 2) beside ISO 6336-1");
  k->add_option("-c,--config", stf.common.config, "TOML configuration")->check(CLI::ExistingFile);
  k->add_option("--set", stf.common.assignments, "override a configuration key: --set section.key=value")
      ->take_all();
  k->add_option("-o,--output", stf.output, "write the curves to this HDF5 file");
  k->add_option("--csv", stf.csv, "write the curves to this CSV file");

  pw::app::SweepCommandOptions swp;
  CLI::App* sw = pw::app::add_sweep_command(app, swp);

  pw::app::SynthOptions syn;
  CLI::App* sy = pw::app::add_synth_command(app, syn);

  pw::app::DiagnoseCommandOptions dgn;
  CLI::App* dg = pw::app::add_diagnose_command(app, dgn);

  pw::app::IndicatorsOptions ind;
  CLI::App* in = pw::app::add_indicators_command(app, ind);

  CLI::App* keys = app.add_subcommand("keys", "List every configuration key with its type, default and unit");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    if (*s) return pw::app::run_simulate(sim);
    if (*k) return pw::app::run_stiffness(stf);
    if (*keys) return pw::app::run_keys();
    if (*sw) return pw::app::run_sweep(swp);
    if (*sy) return pw::app::run_synth(syn);
    if (*in) return pw::app::run_indicators(ind);
    if (*dg) {
      std::string line;
      for (int i = 0; i < argc; ++i) line += (i ? " " : "") + std::string(argv[i]);
      return pw::app::run_diagnose(dgn, line);
    }
  } catch (const pw::InputError& e) {
    std::cerr << "planetwear: error: " << e.what() << "\n";
    return 1;
  } catch (const pw::SolverError& e) {
    std::cerr << "planetwear: solver failed: " << e.what() << "\n";
    return 2;
  } catch (const pw::io::IoError& e) {
    std::cerr << "planetwear: I/O error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
