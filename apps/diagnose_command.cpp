// planetwear diagnose (diagnose_command.hpp):
//   1. configuration (+ --set), recording + sidecar -> diagnose::Recording in SI
//   2. diagnose::diagnose (src/diagnose/diagnose.hpp)
//   3. report files (io/diagnosis_report.hpp), then the PNGs (scripts/plot_diagnosis.py)
#include "diagnose_command.hpp"

#include "core/error.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/diagnose.hpp"
#include "io/config_toml.hpp"
#include "io/diagnosis_report.hpp"
#include "io/io_error.hpp"
#include "io/recording_reader.hpp"
#include "io/recording_writer.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#ifndef PLANETWEAR_SOURCE_DIR
#define PLANETWEAR_SOURCE_DIR ""
#endif

namespace pw::app {
namespace {

std::filesystem::path find_plot_script() {
  namespace fs = std::filesystem;
  if (const char* e = std::getenv("PLANETWEAR_SCRIPTS")) {
    fs::path p = fs::path(e) / "plot_diagnosis.py";
    if (fs::exists(p)) return p;
  }
  const fs::path src = fs::path(PLANETWEAR_SOURCE_DIR) / "scripts" / "plot_diagnosis.py";
  if (!std::string(PLANETWEAR_SOURCE_DIR).empty() && fs::exists(src)) return src;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    for (fs::path d = exe.parent_path(); !d.empty() && d != d.root_path(); d = d.parent_path())
      if (fs::exists(d / "scripts" / "plot_diagnosis.py")) return d / "scripts" / "plot_diagnosis.py";
  return {};
}

std::string shell_quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) {
    if (c == '\'') o += "'\\''";
    else o += c;
  }
  return o + "'";
}

} // namespace

CLI::App* add_diagnose_command(CLI::App& app, DiagnoseCommandOptions& o) {
  CLI::App* d = app.add_subcommand(
      "diagnose", "Compare a recording with the model: locate where they differ, fit candidate physics (tooth "
                  "damage, pin errors, runout, torque ripple, worn profiles, ...), check the fit on held-out data "
                  "and write a report (docs/diagnose.md)");
  d->add_option("-c,--config", o.common.config, "TOML configuration of the gear set (default: the seed paper's case)")
      ->check(CLI::ExistingFile);
  d->add_option("--set", o.common.assignments, "override any configuration key: --set section.key=value")->take_all();
  d->add_option("-r,--recording", o.recording, "recording (CSV or HDF5, docs/recordings.md)")
      ->required()
      ->check(CLI::ExistingFile);
  d->add_option("--meta", o.meta, "JSON sidecar describing the recording (default: the recording's name with .json)");
  d->add_option("-o,--output", o.output, "report directory (created if missing)")->required();
  d->add_option("--threads", o.threads, "OpenMP threads for simulations in parallel (default: OMP_NUM_THREADS or all)");
  d->add_option("--alpha", o.alpha, "false-alarm probability of the noise and improvement tests (default 0.01)")
      ->check(CLI::Range(1e-9, 0.5));
  d->add_option("--max-candidates", o.max_candidates, "candidates fitted after the nuisance parameters (default 4)")
      ->check(CLI::Range(1, 20));
  d->add_option("--candidates", o.candidates, "restrict the library to these candidates (comma separated)")
      ->delimiter(',');
  d->add_flag("--always-fit", o.always_fit, "fit candidates even when the residual is consistent with the noise");
  d->add_flag("--no-plots", o.no_plots, "do not run scripts/plot_diagnosis.py");
  d->add_flag("-q,--quiet", o.common.quiet, "no progress on stderr");
  std::string names;
  for (const auto& c : diagnose::candidate_library()) names += (names.empty() ? "" : ", ") + c->name();
  d->footer("Candidates: " + names +
            ".\nExample: planetwear diagnose --config gearset.toml --recording rec.csv -o report/");
  return d;
}

int run_diagnose(const DiagnoseCommandOptions& o, const std::string& command_line) {
  namespace fs = std::filesystem;
  // 1. Inputs.
  model::SimulationConfig config = o.common.config.empty() ? model::SimulationConfig{} : io::read_config(o.common.config);
  io::apply_overrides(config, o.common.assignments);
  const fs::path meta_path = o.meta.empty() ? io::sidecar_path(o.recording) : fs::path(o.meta);
  if (!fs::exists(meta_path))
    throw InputError("--meta", "no sidecar '" + meta_path.string() +
                                   "': give the JSON description of the recording's columns (docs/recordings.md)");
  for (const auto& name : o.candidates)
    require(diagnose::find_candidate(name) != nullptr, "--candidates", "unknown candidate '", name, "'");
  const io::RecordingMeta meta = io::read_recording_meta(meta_path);
  const diagnose::Recording rec = io::read_recording(o.recording, meta, config);

  // 2. Diagnose.
  diagnose::DiagnoseOptions opt;
  opt.alpha = o.alpha;
  opt.max_candidates = o.max_candidates;
  opt.threads = o.threads;
  opt.only_candidates = o.candidates;
  opt.always_fit_candidates = o.always_fit;
  // The simulation cache keys on the complete configuration (every key of the TOML schema).
  opt.compare.config_key = [](const model::SimulationConfig& c) { return io::to_toml(c); };
  if (!o.common.quiet) opt.progress = [](const std::string& s) { std::fprintf(stderr, "[diagnose] %s\n", s.c_str()); };
  const diagnose::Diagnosis d = diagnose::diagnose(rec, config, opt);

  // 3. Report.
  io::ReportContext ctx;
  ctx.recording_path = o.recording;
  ctx.config_path = o.common.config;
  ctx.command_line = command_line;
  ctx.version = version_string();
  ctx.plots_available = false;
  ctx.plots_note = "plots not drawn yet";
  const fs::path dir(o.output);
  io::write_diagnosis_report(dir, d, ctx);
  if (o.no_plots) {
    ctx.plots_note = "--no-plots was given";
  } else {
    const fs::path script = find_plot_script();
    if (script.empty()) {
      ctx.plots_note = "scripts/plot_diagnosis.py was not found (set PLANETWEAR_SCRIPTS)";
    } else {
      const std::string cmd = "/usr/bin/python3 " + shell_quote(script.string()) + " " + shell_quote(dir.string()) +
                              (o.common.quiet ? " >/dev/null 2>&1" : " 1>&2");
      const int rc = std::filesystem::exists("/usr/bin/python3") ? std::system(cmd.c_str()) : -1;
      ctx.plots_available = rc == 0;
      if (rc != 0)
        ctx.plots_note = "Python with matplotlib is not available or scripts/plot_diagnosis.py failed (exit " +
                         std::to_string(rc) + ")";
    }
  }
  io::write_diagnosis_documents(dir, d, ctx);
  std::cout << d.summary << "\n";
  if (!o.common.quiet)
    std::fprintf(stderr, "wrote %s/report.{md,html,json}%s in %.1f s\n", o.output.c_str(),
                 ctx.plots_available ? " and plots" : "", d.timing.total_s);
  return 0;
}

} // namespace pw::app
