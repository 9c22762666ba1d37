// planetwear diagnose (diagnose_command.hpp):
//   1. configuration (+ --set), recording + sidecar -> diagnose::Recording in SI
//   2. diagnose::diagnose (src/diagnose/diagnose.hpp)
//   3. report files (io/diagnosis_report.hpp), then the PNGs (scripts/plot_diagnosis.py)
#include "diagnose_command.hpp"
#include "recording_input.hpp"

#include "core/error.hpp"
#include "diagnose/baseline.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/diagnose.hpp"
#include "diagnose/order_analysis.hpp"
#include "diagnose/ranking.hpp"
#include "io/calibration_file.hpp"
#include "io/config_toml.hpp"
#include "io/diagnosis_report.hpp"
#include "io/io_error.hpp"
#include "io/recording_reader.hpp"
#include "io/recording_writer.hpp"
#include "sweep/simulation_pool.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>

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

std::vector<std::string> visible_rig_elements(const std::vector<std::string>& rig, const diagnose::Recording& r) {
  std::vector<std::string> out;
  for (const std::string& e : rig)
    if (diagnose::find_candidate(e)->observable_in(r)) out.push_back(e);
  return out;
}

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
  d->add_option("--column", o.columns,
                "describe a column on the command line (repeatable; replaces a sidecar column of the same name): "
                "NAME=QUANTITY[,unit=U][,planet=I][,sensor_angle_deg=A][,scale=S], e.g. "
                "--column acc=housing_acceleration,unit=g,sensor_angle_deg=30 (docs/recordings.md)");
  d->add_option("--speed-rpm", o.speed_rpm, "nominal input (sun) speed [rpm]; replaces the sidecar's");
  d->add_option("--power-w", o.power_W, "input power [W]; replaces the sidecar's power or torque");
  d->add_option("-o,--output", o.output, "report directory (created if missing)")->required();
  d->add_option("--threads", o.threads,
                "OpenMP threads simulating in parallel on rank 0 (default: OMP_NUM_THREADS or all); under "
                "`mpirun -np P` every other rank adds one simulation slot (use --threads 1 with one rank per core)")
      ->check(CLI::Range(0, 1024));
  d->add_option("--alpha", o.alpha, "false-alarm probability of the noise and improvement tests (default 0.01)")
      ->check(CLI::Range(1e-9, 0.5));
  d->add_option("--max-candidates", o.max_candidates, "candidates fitted after the nuisance parameters (default 4)")
      ->check(CLI::Range(1, 20));
  d->add_option("--candidates", o.candidates, "restrict the library to these candidates (comma separated); the nuisance parameters are candidates too: name stiffness_level,damping_level to keep them fitted, e.g. --candidates stiffness_level,damping_level,torque_ripple")
      ->delimiter(',');
  d->add_flag("--always-fit", o.always_fit, "fit candidates even when the residual is consistent with the noise");
  d->add_option("--calibration", o.calibration,
                "calibration file from 'planetwear calibrate': its calibrated model (applied before --set) and its "
                "model-discrepancy budget (added to the noise in every comparison)")
      ->check(CLI::ExistingFile);
  d->add_option("--calibration-reference", o.calibration_reference,
                "with --calibration: 'auto' (default) takes the calibration's own healthy recording at this "
                "recording's operating point (speed within the mesh damping ratio, power within 5 %; not the "
                "recording itself) as the reference, where the calibration's residual is known, and compares "
                "differentially as --baseline does; 'none' judges against the calibration's budget alone "
                "(docs/diagnose.md section 6a item 6)")
      ->check(CLI::IsMember({"auto", "none"}));
  d->add_option("--baseline", o.baseline,
                "healthy recording at the same operating point (same channels, duration, speed and load): "
                "differential diagnosis, the recording's change from it against the model's change from the "
                "model fitted to it, so that model-form errors common to both cancel (docs/diagnose.md section 6b)")
      ->check(CLI::ExistingFile);
  d->add_option("--baseline-meta", o.baseline_meta,
                "JSON sidecar of the baseline (default: the baseline's name with .json)");
  d->add_option("--baseline-transfer", o.baseline_transfer,
                "how the model's change from the reference's model is compared: 'additive' (default) as it is; "
                "'line_ratio' scaled per cell by the reference's measured-to-model line ratio at that frequency, "
                "for a rig whose transfer the model gets wrong by a factor (experimental: docs/diagnose.md "
                "section 6b item 9)")
      ->check(CLI::IsMember({"additive", "line_ratio"}));
  d->add_option("--healthy-fit", o.healthy_fit,
                "how the healthy reference (--baseline, or the calibration's recording) is fitted: 'noise' weights "
                "its cells by the noise alone; 'model_form' refits once with its own model-form discrepancy as "
                "weights (default: the calibration's setting, else 'noise'; docs/diagnose.md section 6a item 7)")
      ->check(CLI::IsMember({"noise", "model_form"}));
  d->add_flag("--no-plots", o.no_plots, "do not run scripts/plot_diagnosis.py");
  d->add_flag("-q,--quiet", o.common.quiet, "no progress on stderr");
  std::string names;
  for (const auto& c : diagnose::candidate_library()) names += (names.empty() ? "" : ", ") + c->name();
  d->footer("Candidates: " + names +
            ".\nExamples:\n  planetwear diagnose --config gearset.toml --recording rec.csv -o report/\n"
            "  planetwear diagnose --config gearset.toml --recording rec.csv --baseline healthy.csv -o report/\n"
            "  planetwear calibrate --config gearset.toml -r healthy400.csv -r healthy800.csv -o cal.toml\n"
            "  planetwear diagnose --config gearset.toml --recording rec.csv --calibration cal.toml -o report/");
  return d;
}

DiagnoseInputs read_diagnose_inputs(const DiagnoseCommandOptions& o) {
  for (const auto& name : o.candidates) {
    const diagnose::Candidate* c = diagnose::find_candidate(name);
    require(c != nullptr, "--candidates", "unknown candidate '", name, "'");
    require(!c->calibration_only(), "--candidates", "'", name,
            "' is a calibration-only rig element, never screened as a finding: fit it with "
            "`planetwear calibrate --rig-elements ", name, "` and diagnose with --calibration");
  }
  require(o.baseline.empty() || o.calibration.empty(), "--baseline",
          "give either --baseline (differential) or --calibration (absolute with a discrepancy budget), not both");
  require(o.baseline_meta.empty() || !o.baseline.empty(), "--baseline-meta", "given without --baseline");
  require(o.baseline_transfer == "additive" || !o.baseline.empty() ||
              (!o.calibration.empty() && o.calibration_reference != "none"),
          "--baseline-transfer", "'", o.baseline_transfer,
          "' acts on a reference recording: give --baseline (or --calibration with --calibration-reference auto)");
  require(o.healthy_fit.empty() || !o.baseline.empty() || (!o.calibration.empty() && o.calibration_reference != "none"),
          "--healthy-fit", "'", o.healthy_fit,
          "' acts on a reference recording: give --baseline (or --calibration with --calibration-reference auto)");
  if (!o.baseline.empty()) {
    const std::filesystem::path meta = o.baseline_meta.empty() ? io::sidecar_path(o.baseline) : std::filesystem::path(o.baseline_meta);
    require(std::filesystem::exists(meta), "--baseline-meta", "no sidecar '", meta.string(),
            "' for the baseline: give the JSON description of its columns (docs/recordings.md)");
    read_recording_inputs(o.common, o.baseline, meta.string(), {}, {}, {});  // its input errors now, not after a fit
  }
  // A calibration's model first, the command line's --set after it (the user's word wins).
  CommonOptions common = o.common;
  std::optional<diagnose::Calibration> calibration;
  if (!o.calibration.empty()) {
    calibration = io::read_calibration(o.calibration);
    common.assignments = diagnose::model_form_settings(calibration->form);
    common.assignments.insert(common.assignments.end(), calibration->overrides.begin(), calibration->overrides.end());
    common.assignments.insert(common.assignments.end(), o.common.assignments.begin(), o.common.assignments.end());
  }
  RecordingInputs in = read_recording_inputs(common, o.recording, o.meta, o.columns, o.speed_rpm, o.power_W);
  return DiagnoseInputs{std::move(in.config), std::move(in.recording), std::move(calibration)};
}

namespace {

using Inputs = DiagnoseInputs;
Inputs read_inputs(const DiagnoseCommandOptions& o) { return read_diagnose_inputs(o); }

/// The healthy recording a diagnosis is compared against differentially: --baseline, or the
/// calibration's own recording at the operating point; both analysed in the same windows
/// (common_windows).
struct Reference {
  std::string recording, meta;
  diagnose::OrderAnalysisOptions analysis{};
  /// The calibration's recording it is (its index in Calibration::recordings); none for --baseline.
  std::optional<std::size_t> calibration_recording;
  /// At the recording's operating point (operating_point_distance); a calibration's reference always is.
  bool at_operating_point = true;
};

std::string resolve_calibration_path(const std::string& p, const std::string& calibration_file) {
  namespace fs = std::filesystem;
  if (fs::path(p).is_absolute() || fs::exists(p)) return p;
  const fs::path beside = fs::path(calibration_file).parent_path() / p;  // files written before paths were absolute
  return fs::exists(beside) ? beside.string() : p;
}

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::equivalent(a, b, ec)) return true;
  // A copy of the same data is the same recording: it would compare with itself.
  std::ifstream fa(a, std::ios::binary), fb(b, std::ios::binary);
  if (!fa || !fb || std::filesystem::file_size(a, ec) != std::filesystem::file_size(b, ec)) return false;
  return std::equal(std::istreambuf_iterator<char>(fa), std::istreambuf_iterator<char>(),
                    std::istreambuf_iterator<char>(fb));
}

diagnose::RecordingSpectra analyse(const RecordingInputs& r, const diagnose::OrderAnalysisOptions& o = {}) {
  return diagnose::analyse_recording(r.recording, r.config.stage, o);
}

/// `a` is analyse(self) with the default windows (computed once by the caller).
std::optional<diagnose::OrderAnalysisOptions> common_windows(const RecordingInputs& self,
                                                             const diagnose::RecordingSpectra& a,
                                                             const RecordingInputs& ref) {
  return diagnose::common_analysis_options(self.recording, self.config.stage, a, ref.recording, ref.config.stage);
}

RecordingInputs read_self(const DiagnoseCommandOptions& o) {
  return read_recording_inputs(o.common, o.recording, o.meta, o.columns, o.speed_rpm, o.power_W);
}

diagnose::OperatingPointDistance operating_point_distance(const RecordingInputs& self, const RecordingInputs& ref) {
  return diagnose::operating_point_distance(self.recording.operating.input_speed_rpm,
                                            self.recording.operating.input_power_W,
                                            ref.recording.operating.input_speed_rpm,
                                            ref.recording.operating.input_power_W,
                                            self.config.contact.mesh_damping_ratio);
}

/// --baseline: its windows shared with the recording's, or an input error before any fit; its
/// operating point against the recording's, said in `note`. A baseline at another operating point
/// is still compared (the user's choice), but its model-form error need not cancel, and a level's
/// change since it is not tested (DiagnoseOptions::baseline_at_operating_point).
Reference given_baseline(const DiagnoseCommandOptions& o, std::string& note) {
  Reference r;
  r.recording = o.baseline;
  r.meta = o.baseline_meta.empty() ? io::sidecar_path(o.baseline).string() : o.baseline_meta;
  const RecordingInputs self = read_self(o);
  const RecordingInputs ref = read_recording_inputs(o.common, r.recording, r.meta, {}, {}, {});
  const auto w = common_windows(self, analyse(self), ref);
  require(w.has_value(), "--baseline", "'", o.baseline, "' and the recording cannot be analysed in the same windows "
          "(the same channels and sample rate): a cell-by-cell comparison needs them (docs/diagnose.md section 6b)");
  r.analysis = *w;
  const diagnose::OperatingPointDistance d = operating_point_distance(self, ref);
  r.at_operating_point = d.same;
  char buf[600];
  std::snprintf(buf, sizeof buf,
                "the baseline is at %.6g rpm and %.6g W, the recording at %.6g rpm and %.6g W (speed %.3g %% apart, "
                "the same within the mesh damping ratio %.3g; power %.3g %% apart, the same within %.3g %%)%s",
                ref.recording.operating.input_speed_rpm, ref.recording.operating.input_power_W,
                self.recording.operating.input_speed_rpm, self.recording.operating.input_power_W, 100 * d.speed,
                self.config.contact.mesh_damping_ratio, 100 * d.power, 100 * diagnose::kRecalibration,
                d.same ? ": the same operating point"
                       : ": another operating point, where the model's form error need not cancel in the difference; "
                         "the mesh stiffness and damping levels move with the operating point, so their change since "
                         "the baseline is not tested (docs/diagnose.md section 6b)");
  note = buf;
  return r;
}

/// docs/diagnose.md §6a item 6. At an operating point the calibration has a healthy recording of,
/// the model's discrepancy there is no longer a budget but a measurement: the calibration's
/// residual on that recording (in Kennedy and O'Hagan's terms, the discrepancy's posterior mean at
/// a calibration input, known to within the recording's noise). The recording is then compared
/// with it differentially (§6b), the nearest in speed at the same operating point
/// (operating_point_distance). The recording itself (or a copy) is never its own reference: a
/// held-out check stays held out.
std::optional<Reference> calibrated_reference(const DiagnoseCommandOptions& o, const diagnose::Calibration& cal,
                                              std::string& note) {
  if (o.calibration_reference == "none") {
    note = "--calibration-reference none: judged against the calibration's budget alone";
    return std::nullopt;
  }
  const RecordingInputs self = read_self(o);
  const double n = self.recording.operating.input_speed_rpm, P = self.recording.operating.input_power_W;
  const double zeta = self.config.contact.mesh_damping_ratio;
  std::optional<diagnose::RecordingSpectra> self_analysis;  // once, when a candidate is at the operating point
  std::optional<Reference> best;
  double best_dn = 0;
  std::string missing, other_windows;
  for (std::size_t i = 0; i < cal.recordings.size(); ++i) {
    Reference r;
    r.recording = resolve_calibration_path(cal.recordings[i], o.calibration);
    r.meta = i < cal.sidecars.size() ? resolve_calibration_path(cal.sidecars[i], o.calibration)
                                     : io::sidecar_path(r.recording).string();
    if (!std::filesystem::exists(r.recording) || !std::filesystem::exists(r.meta)) {
      missing += (missing.empty() ? "" : ", ") + r.recording;
      continue;
    }
    if (same_file(r.recording, o.recording)) continue;
    const RecordingInputs c = read_recording_inputs(o.common, r.recording, r.meta, {}, {}, {});
    const diagnose::OperatingPointDistance d = operating_point_distance(self, c);
    const double dn = d.speed;
    if (!d.same || (best && dn >= best_dn)) continue;
    if (!self_analysis) self_analysis = analyse(self);
    const auto w = common_windows(self, *self_analysis, c);
    if (!w) {
      other_windows += (other_windows.empty() ? "" : ", ") + r.recording;
      continue;
    }
    r.analysis = *w;
    r.calibration_recording = i;
    best = r;
    best_dn = dn;
  }
  char buf[400];
  const double power_pct = 100 * diagnose::kRecalibration;
  if (best)
    std::snprintf(buf, sizeof buf,
                  "the calibration's healthy recording at this operating point is the reference: %s (speed within "
                  "%.3g %% of %.6g rpm, power within %.3g %% of %.6g W)",
                  best->recording.c_str(), 100 * best_dn, n, power_pct, P);
  else
    std::snprintf(buf, sizeof buf,
                  "the calibration has no healthy recording at this operating point (speed within the mesh damping "
                  "ratio %.3g of %.6g rpm, power within %.3g %% of %.6g W): judged against its budget",
                  zeta, n, power_pct, P);
  note = buf;
  if (!other_windows.empty())
    note += "; at this operating point but not comparable cell by cell (other channels or band): " + other_windows;
  if (!missing.empty()) note += "; not found: " + missing;
  return best;
}

/// --baseline, else (with --calibration) the calibration's recording at the operating point, if any.
std::optional<Reference> choose_reference(const DiagnoseCommandOptions& o,
                                          const std::optional<diagnose::Calibration>& calibration, std::string& note) {
  if (!o.baseline.empty()) return given_baseline(o, note);
  if (calibration) return calibrated_reference(o, *calibration, note);
  return std::nullopt;
}

/// The comparison's options: a reference's windows and no budget (the reference's own comes with
/// its fit), else the calibration's budget if any.
diagnose::CompareOptions comparison_options(const DiagnoseCommandOptions& o, const std::optional<Reference>& reference,
                                            const std::optional<diagnose::Calibration>& calibration) {
  diagnose::CompareOptions co;
  co.alpha = o.alpha;
  if (reference) co.analysis = reference->analysis;
  else if (calibration) co.discrepancy = calibration->budgets();
  return co;
}

/// The healthy reference fitted as --baseline's is (§6b): the gear set's configuration and
/// --set, its nuisance parameters only. A calibration's recording is fitted the same way, not
/// with the calibration's values or rig elements (docs/diagnose.md §6a item 6: at a measured
/// operating point the residual holds what they would model).
diagnose::BaselineReference fit_reference(const DiagnoseCommandOptions& o, const Reference& ref,
                                          const diagnose::DiagnoseOptions& opt, diagnose::HealthyFit weighting) {
  const RecordingInputs b = read_recording_inputs(o.common, ref.recording, ref.meta, {}, {}, {});
  diagnose::DiagnoseOptions bo = opt;
  if (opt.progress) bo.progress = [p = opt.progress](const std::string& s) { p("reference: " + s); };
  const diagnose::BaselineTransfer transfer = o.baseline_transfer == "line_ratio"
                                                  ? diagnose::BaselineTransfer::LineRatio
                                                  : diagnose::BaselineTransfer::Additive;
  return diagnose::fit_baseline(b.recording, b.config, bo, transfer, weighting);
}

/// Rank 0: the diagnosis (simulations through `remote` when other ranks serve) and the report.
void diagnose_and_report(const DiagnoseCommandOptions& o_in, const std::string& command_line,
                         const sweep::RemoteSimulation& remote, int ranks) {
  namespace fs = std::filesystem;
  DiagnoseCommandOptions o = o_in;
  const std::optional<diagnose::Calibration> calibration = read_inputs(o).calibration;  // every input error first

  // 2. Diagnose. One simulation slot per local thread plus one per serving rank.
  diagnose::DiagnoseOptions opt;
  opt.alpha = o.alpha;
  opt.max_candidates = o.max_candidates;
  opt.threads = o.threads;
  opt.remote_slots = ranks - 1;
  opt.only_candidates = o.candidates;
  opt.always_fit_candidates = o.always_fit;
  // How far the calibration's healthy recordings scatter each nuisance level: the sizes fitted
  // jointly with those levels carry it (calibration.hpp nuisance_level_spread_ln).
  if (calibration) {
    opt.nuisance_level_spread_ln = diagnose::nuisance_level_spread_ln(*calibration);
    opt.nuisance_level_spread_recordings = static_cast<int>(calibration->fits.size());
  }
  if (!o.common.quiet) opt.progress = [](const std::string& s) { std::fprintf(stderr, "[diagnose] %s\n", s.c_str()); };
  std::string reference_note;
  const std::optional<Reference> reference = choose_reference(o, calibration, reference_note);
  if ((calibration || reference) && !o.common.quiet) std::fprintf(stderr, "[diagnose] %s\n", reference_note.c_str());
  if (reference) opt.baseline_at_operating_point = reference->at_operating_point;
  if (calibration && !reference)  // refitted from their calibrated values, except those a diagnosis holds
    for (const std::string& e : calibration->rig_elements)
      if (const diagnose::Candidate* c = diagnose::find_candidate(e); c && !c->held_after_calibration())
        opt.extra_nuisance.push_back(e);
  opt.compare = comparison_options(o, reference, calibration);
  opt.compare.remote = remote;
  std::optional<diagnose::BaselineReference> baseline;
  if (reference) {
    // The reference's fitted model first, the command line's --set after it (the user's word
    // wins); a calibrated reference replaces the calibration's model and budget (read_inputs
    // below then reads without them).
    const diagnose::HealthyFit weighting =
        !o.healthy_fit.empty() ? diagnose::healthy_fit_from_string(o.healthy_fit, "--healthy-fit")
                               : calibration ? calibration->healthy_fit : diagnose::HealthyFit::Noise;
    // The rig's structure the calibration identified on every one of its healthy recordings (a
    // shaft's mode: the calibration-only elements it kept) is the rig's at the reference too:
    // held at the values the calibration fitted on this reference, not refitted here nor taken
    // from the medians over the other operating points (§6a item 6).
    // The calibrated model's mesh form first (calibration.hpp model_form_settings): the reference
    // is fitted in the form the calibration chose, as the recording is.
    const std::vector<std::string> form =
        calibration ? diagnose::model_form_settings(calibration->form) : std::vector<std::string>{};
    std::vector<std::string> structure;
    if (calibration) {
      const model::SimulationConfig gear_set = read_gear_set_config(o.common);
      structure = diagnose::structural_rig_settings(*calibration, gear_set, reference->calibration_recording);
      // Its design elements (an encoder's bandwidth) too, where the calibration's fit of this
      // recording measured them within their boxes (calibration.hpp reference_design_settings).
      if (reference->calibration_recording)
        for (std::string& line :
             diagnose::reference_design_settings(*calibration, gear_set, *reference->calibration_recording))
          structure.push_back(std::move(line));
    }
    DiagnoseCommandOptions ro = o;
    ro.common.assignments = form;
    ro.common.assignments.insert(ro.common.assignments.end(), structure.begin(), structure.end());
    ro.common.assignments.insert(ro.common.assignments.end(), o.common.assignments.begin(), o.common.assignments.end());
    // The calibration's own fit of this recording is a second start of the reference's fit (LM is
    // local; calibration.hpp fitted_values), for the reference alone: the recording's own fit
    // starts from the reference's values.
    diagnose::DiagnoseOptions reference_opt = opt;
    if (calibration && reference->calibration_recording)
      reference_opt.nuisance_start_values = diagnose::fitted_values(*calibration, *reference->calibration_recording);
    baseline = fit_reference(ro, *reference, reference_opt, weighting);
    if (!structure.empty()) {
      std::string lines;
      for (const std::string& l : structure) lines += (lines.empty() ? "" : ", ") + l;
      reference_note += "; the rig's structure as the calibration identified it, held: " + lines;
      if (!o.common.quiet) std::fprintf(stderr, "[diagnose] reference with the calibrated rig structure: %s\n", lines.c_str());
    }
    std::vector<std::string> a = form;
    a.insert(a.end(), structure.begin(), structure.end());
    a.insert(a.end(), baseline->overrides.begin(), baseline->overrides.end());
    a.insert(a.end(), o_in.common.assignments.begin(), o_in.common.assignments.end());
    o.common.assignments = a;
    o.calibration.clear();
    opt.compare.baseline = baseline->cells;
    opt.compare.baseline_alien_lines = baseline->alien_lines;
    opt.compare.discrepancy = baseline->budgets;
    opt.baseline_gains = baseline->gains;
    opt.baseline_limits = baseline->limits;
  }
  // Where healthy lines tested the model (line_coverage.hpp): the calibration's recordings, else
  // the baseline's own lines.
  if (calibration && !calibration->coverage.empty()) opt.line_coverage = calibration->coverage;
  else if (baseline) opt.line_coverage = baseline->coverage;
  const Inputs in = read_inputs(o);
  const diagnose::Diagnosis d = diagnose::diagnose(in.recording, in.config, opt);

  // 3. Report.
  io::ReportContext ctx;
  ctx.recording_path = o.recording;
  ctx.config_path = o.common.config;
  ctx.calibration_path = o_in.calibration;
  if (calibration) ctx.calibration_reference = reference_note;
  else if (reference) ctx.baseline_operating_point = reference_note;
  if (calibration && !baseline) ctx.calibration_at_bound = calibration->at_bound;
  if (reference) ctx.baseline_path = reference->recording;
  if (baseline) ctx.baseline_summary = baseline->summary;
  if (baseline) ctx.baseline_at_bound = baseline->at_bound;
  ctx.command_line = command_line;
  ctx.version = version_string();
  ctx.plots_available = false;
  ctx.plots_note = "plots not drawn yet";
  ctx.ranks = ranks;
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
}

} // namespace

int run_diagnose(const DiagnoseCommandOptions& o, const std::string& command_line) {
  // A serving rank (mpirun -np P, P > 1) sets up the same comparison and simulates on request.
  const auto make_evaluate = [&o]() -> sweep::Evaluate {
    auto in = std::make_shared<const Inputs>(read_inputs(o));
    std::string note;  // the same reference and windows as rank 0's: its simulations are compared in them
    const std::optional<Reference> reference = choose_reference(o, in->calibration, note);
    auto cmp = std::make_shared<const diagnose::ModelComparison>(in->recording, in->config,
                                                                 comparison_options(o, reference, in->calibration));
    return [in, cmp](const model::SimulationConfig& c, bool keep) { return cmp->evaluate(c, keep); };
  };
  sweep::run_with_simulation_pool(
      [&](const sweep::RemoteSimulation& remote, int ranks) { diagnose_and_report(o, command_line, remote, ranks); },
      make_evaluate);
  return 0;
}

} // namespace pw::app
