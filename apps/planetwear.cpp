// planetwear: command-line front end. Each subcommand reads a configuration
// (TOML, defaults = the seed paper's case), runs the physics library and
// writes one output file atomically (nothing is left behind on error).
//
//   planetwear simulate [--config FILE] [--speed-rpm X] [--power-w P]
//                       [--mesh-cycles N] [--kappa K]
//                       [--set key=value ...] -o out.h5 [--csv out.csv]
//   e.g. the seed's wear run: planetwear simulate --mesh-cycles 2e5 -o wear.h5
//   planetwear stiffness [--config FILE] [--set ...] [-o stiffness.h5]
//   planetwear keys [--format text|json]  (every configuration key with unit and default)
//   planetwear config [--template] [--config FILE] [--set ...]
//                       (the resolved configuration as TOML; --template: every key commented, at its default)
//   planetwear synth [--config FILE] [--set ...] [--seconds S] [--noise F] [--dc-offset F]
//                    [--seed N] [--sensor-angle-deg A] [--decimate K] [--tacho] -o rec.csv
//                       (a synthetic recording + rec.json sidecar, docs/recordings.md)
//   planetwear diagnose [--config FILE] [--set ...] --recording rec.csv [--meta rec.json] -o report/
//                       (where a recording and the model differ, the missing physics, docs/diagnose.md)
//   planetwear calibrate [--config FILE] -r healthy.csv [-r ...] -o calibration.toml
//                       (the model and its discrepancy budget from healthy recordings)
//   planetwear indicators -r rec.csv [--meta rec.json] [-o ind.json|ind.csv]
//   planetwear indicators --simulation worn.h5 [-o trend.csv]
//                       (gear condition indicators FM0, FM4, NA4, ... of sun, planets, carrier, docs/indicators.md)
//   [mpirun -np P] planetwear sweep CAMPAIGN.toml -o results.h5 [--resume|--force]
//                       (a design-of-experiments campaign, docs/campaigns.md)
//
// Exit codes (io/exit_code.hpp, table in docs/cli.md): 0 success, 1 bad input
// including command-line parse errors (the message names the parameter),
// 2 solver failure, 3 I/O failure, 4 wear stopped early at the safe wear limit
// (results up to then are written); sweep: 4 = the campaign finished but some
// cases failed (their reasons are in the archive); 5 an unexpected failure.
// Every error line starts with "planetwear: error: ".
#include "commands.hpp"
#include "engineering_summary.hpp"
#include "calibrate_command.hpp"
#include "diagnose_command.hpp"
#include "indicators_command.hpp"
#include "sweep_command.hpp"
#include "synth_command.hpp"

#include "core/error.hpp"
#include "io/exit_code.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  CLI::App app{"planetwear: dynamics and wear of planetary gear stages (SI units throughout)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", pw::app::version_string());
  app.footer("Exit codes: 0 ok, 1 bad input (also a command-line error), 2 solver failure, 3 I/O failure, 4 wear "
             "stopped early (sweep: some cases failed), 5 unexpected failure; docs/cli.md. Memory: a run whose "
             "estimate exceeds half the physical memory is refused; PLANETWEAR_MEMORY_LIMIT (e.g. 8G) overrides.\n");

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
  s->add_option("--compression", sim.compression_level,
                "deflate level of the large datasets: 0 = none (default; fastest, about twice the file size), "
                "1..9 = chunked, shuffle + deflate (9 smallest; level 4 costs ~2 s per 100 MB of time histories)")
      ->check(CLI::Range(0, 9));
  s->add_option("--channels", sim.output_selection.channels,
                "store only these time-history channels (comma-separated names as in docs/output-format.md; a "
                "name ending in '/' selects everything below it, e.g. --channels sun_planet/0/,housing/acceleration)")
      ->delimiter(',');
  s->add_option("--report", sim.report,
                "also write the engineering summary (mesh forces, dynamic factor, contact pressure, load sharing, "
                "efficiency, wear) as Markdown to this file; it is printed on stdout unless --quiet");
  sim.allowable_contact_stress_Pa = pw::app::kDefaultAllowableContactStressPa;
  s->add_option("--allowable-contact-stress-pa", sim.allowable_contact_stress_Pa,
                "allowable contact stress the summary compares the largest Hertzian pressure with [Pa] (default "
                "1.5e9: ISO 6336-5 sigma_Hlim, case-hardened wrought steel, quality MQ)")
      ->check(CLI::PositiveNumber);
  s->add_flag("-q,--quiet", sim.common.quiet, "no progress on stderr and no summary on stdout");

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

  pw::app::CalibrateCommandOptions cal;
  CLI::App* cl = pw::app::add_calibrate_command(app, cal);
  pw::app::IndicatorsOptions ind;
  CLI::App* in = pw::app::add_indicators_command(app, ind);

  CLI::App* keys = app.add_subcommand("keys", "List every configuration key with its type, default and unit");
  std::string keys_format = "text";
  keys->add_option("--format", keys_format, "text (a table) or json (an array of {key, type, unit, default, doc})")
      ->check(CLI::IsMember({"text", "json"}));

  CLI::App* cands = app.add_subcommand(
      "candidates", "List the physics `diagnose` can name or fit: each candidate's role, the line families its "
                    "signature lives in (what a report's \"located in the sun family\" can stand for), its class of "
                    "findings and its physics\n\nExamples:\n  planetwear candidates\n  planetwear candidates --format json");
  std::string candidates_format = "text";
  cands->add_option("--format", candidates_format,
                    "text (a table) or json (an array of {name, role, families, finding_class, physics})")
      ->check(CLI::IsMember({"text", "json"}));

  pw::app::ConfigOptions cfg;
  CLI::App* cf = app.add_subcommand("config", "Print the resolved configuration as TOML (every key), or with "
                                              "--template every key at its default with its doc as a comment");
  cf->add_option("-c,--config", cfg.common.config, "TOML configuration")->check(CLI::ExistingFile);
  cf->add_option("--set", cfg.common.assignments, "override a configuration key: --set section.key=value")
      ->take_all();
  cf->add_flag("--template", cfg.template_only, "a commented TOML file of every key at its default");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are successes (exit 0); every other parse error is
    // bad input: exit 1 with the one error prefix, not CLI11's own codes.
    if (e.get_exit_code() == 0) return app.exit(e);
    std::cerr << pw::io::kErrorPrefix << e.what() << "\nRun with --help for more information.\n";
    return pw::io::to_int(pw::io::ExitCode::BadInput);
  }
  try {
    if (*s) return pw::app::run_simulate(sim);
    if (*k) return pw::app::run_stiffness(stf);
    if (*keys) return pw::app::run_keys(keys_format);
    if (*cands) return pw::app::run_candidates(candidates_format);
    if (*cf) return pw::app::run_config(cfg);
    if (*sw) return pw::app::run_sweep(swp);
    if (*sy) return pw::app::run_synth(syn);
    if (*cl) return pw::app::run_calibrate(cal);
    if (*in) return pw::app::run_indicators(ind);
    if (*dg) {
      std::string line;
      for (int i = 0; i < argc; ++i) line += (i ? " " : "") + std::string(argv[i]);
      return pw::app::run_diagnose(dgn, line);
    }
  } catch (...) {
    // One mapping for every subcommand (io/exit_code.hpp); std::bad_alloc and
    // other surprises exit 5 with a message instead of aborting.
    const std::exception_ptr e = std::current_exception();
    std::cerr << pw::io::error_message(e) << "\n";
    return pw::io::to_int(pw::io::exit_code_of(e));
  }
  return pw::io::to_int(pw::io::ExitCode::Ok);
}
