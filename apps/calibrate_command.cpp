// planetwear calibrate (calibrate_command.hpp):
//   1. per healthy recording: inputs as for diagnose, the nuisance-only diagnosis
//   2. the calibration: median model, discrepancy estimates (diagnose/calibration.hpp)
//   3. the file (io/calibration_file.hpp) and a table on stdout
#include "calibrate_command.hpp"

#include "core/error.hpp"
#include "diagnose/calibration.hpp"
#include "diagnose/candidates/candidate.hpp"
#include "diagnose/locate.hpp"
#include "diagnose_command.hpp"
#include "io/calibration_file.hpp"
#include "io/config_toml.hpp"
#include "io/recording_writer.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace pw::app {

CLI::App* add_calibrate_command(CLI::App& app, CalibrateCommandOptions& o) {
  CLI::App* c = app.add_subcommand(
      "calibrate",
      "Calibrate the model on healthy recordings: fit the nuisance and rig parameters of each, estimate the "
      "systematic residual a healthy recording leaves (per channel kind and line family), and write both for "
      "'diagnose --calibration' (docs/diagnose.md section 6a)");
  c->add_option("-c,--config", o.common.config, "TOML configuration of the gear set (default: the seed paper's case)")
      ->check(CLI::ExistingFile);
  c->add_option("--set", o.common.assignments, "override any configuration key: --set section.key=value")->take_all();
  c->add_option("-r,--recording", o.recordings, "a healthy recording (CSV or HDF5); repeat for several")
      ->required()
      ->check(CLI::ExistingFile);
  c->add_option("--meta", o.metas,
                "JSON sidecars, one per --recording in the same order (default: each recording's name with .json)");
  c->add_option("-o,--output", o.output, "calibration file to write (TOML)")->required();
  c->add_option("--rig-elements", o.rig_elements,
                "candidates fitted as nuisance parameters when the recording can see them (default: "
                "encoder_bandwidth; motor_inertia, load_inertia (rigidly coupled machines) or input_shaft, "
                "output_shaft (machines behind flexible shafts), tip_relief, engagement_ramp and "
                "mesh_stiffness_harmonics (the gears' tips and stiffness law), housing_mount (the housing's "
                "resonance on its mount), bearing_damping (solver.level = lateral_torsional) may be added, "
                "docs/diagnose.md section 6a; 'none' for none)")
      ->delimiter(',');
  c->add_option("--healthy-fit", o.healthy_fit,
                "how each recording's nuisance fit weights its cells: 'noise' (default) by the noise alone; "
                "'model_form' refits once with that recording's own model-form discrepancy as weights, so that "
                "lines the model's form misses by far more than the noise do not decide the fitted values "
                "(docs/diagnose.md section 6a item 7)")
      ->check(CLI::IsMember({"noise", "model_form"}));
  c->add_flag("--ring-body", o.ring_body,
              "also try the lateral-torsional model's ring body (supports damped, bearing_damping fitted) as the "
              "housing accelerometer's path where neither the planet-pass window nor the ring's translation explains "
              "the healthy housing channels; each simulation then costs 3-5 times more (docs/diagnose.md section 6a "
              "item 12)");
  c->add_option("--rig-structure", o.rig_structure,
                "the calibration-only rig elements (shafts, the housing's mount, the engagement ramp): 'shared' "
                "(default) refits every recording with every other's fitted structure and with their pooled one, and "
                "holds the one of the largest joint profile likelihood on all of them, unless a recording's own "
                "structure fits it "
                "better than chance allows (F test; then each keeps its own, and calibrate says so); "
                "'per_recording' keeps each recording's own fit without the refits (docs/diagnose.md section 6a "
                "item 8)")
      ->check(CLI::IsMember({"shared", "per_recording"}));
  c->add_option("--threads", o.threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores)")
      ->check(CLI::Range(0, 1024));
  c->add_option("--alpha", o.alpha, "one-sided level of the budgets' upper confidence limits (default 0.01)")
      ->check(CLI::Range(1e-6, 0.5));
  c->add_flag("-q,--quiet", o.common.quiet, "no progress on stderr");
  c->footer("Example: planetwear calibrate -c gearset.toml -r healthy_1000rpm.csv -r healthy_1500rpm.csv "
            "-o calibration.toml\n         planetwear diagnose -c gearset.toml --calibration calibration.toml "
            "-r suspect.csv -o report/\n\n"
            "The calibrated model's mesh follows the gears' roll unless every healthy recording fits better with it "
            "locked to nominal time (the k(t) of many simulators): then the file says mesh_phase = \"nominal_time\". "
            "Its housing accelerometer sees the planets pass through a window unless every healthy recording fits "
            "better with it on the ring's rigid-body translation: then housing_path = \"ring_translation\"; with "
            "--ring-body, also on the lateral-torsional model's ring body with damped supports: then housing_path = "
            "\"ring_body\" (the model becomes lateral_torsional, 3-5 times slower per simulation). "
            "diagnose --calibration uses the form the file says (docs/diagnose.md section 6a items 10 to 12).");
  return c;
}

namespace {

void print_table(const diagnose::Calibration& cal) {
  std::printf("%-30s %-12s %12s %12s %6s %14s %6s\n", "channel kind", "family", "sigma_rel", "budget", "cells",
              "sigma_abs^2", "cells");
  const std::vector<diagnose::DiscrepancyEntry> budgets = cal.budgets();
  for (std::size_t k = 0; k < cal.discrepancy.size(); ++k) {
    const diagnose::DiscrepancyEstimate& d = cal.discrepancy[k];
    const double s = d.relative_variance > 0 ? std::sqrt(d.relative_variance) : 0.0;
    std::printf("%-30s %-12s %12.4g %12.4g %6d %14.4g %6d%s\n", diagnose::to_string(d.quantity),
                diagnose::to_string(d.family), s, budgets[k].relative_std, d.relative_cells, d.absolute_variance,
                d.absolute_cells, budgets[k].relative_inherited ? "  (relative budget inherited)" : "");
  }
  if (std::any_of(budgets.begin(), budgets.end(), [](const diagnose::DiscrepancyEntry& b) { return b.relative_inherited; }))
    std::printf("relative budget inherited: the healthy model had no line of that family above the noise; a model "
              "that adds lines there gets the largest relative budget measured on the same kind of channel\n");
  // Where the discrepancy was measured: a fault's lines outside these spans reach the sensors
  // through a transfer no healthy line tested (line_coverage.hpp).
  for (const diagnose::LineCoverage& l : cal.coverage)
    std::printf("lines tested on %s: %.4g Hz (at %.6g rpm) to %.4g Hz (at %.6g rpm), %d cells\n",
                diagnose::to_string(l.quantity), l.lowest_Hz, l.lowest_speed_rpm, l.highest_Hz, l.highest_speed_rpm,
                l.lines);
  // Each recording's fit: the spread is what the median hides.
  if (cal.healthy_fit == diagnose::HealthyFit::ModelForm)
    std::printf("values from each recording's model-form weighted refit; chi2 and bound from its noise-weighted fit\n");
  for (std::size_t r = 0; r < cal.fits.size() && r < cal.recordings.size(); ++r) {
    const diagnose::CalibrationFit& f = cal.fits[r];
    std::printf("recording %zu (%.6g rpm): held-out chi2 %.4g against a noise bound of %.4g (%.3g times);", r + 1,
                r < cal.speeds_rpm.size() ? cal.speeds_rpm[r] : 0.0, f.nuisance_chi2_held_out,
                f.noise_bound_held_out, f.nuisance_chi2_held_out / f.noise_bound_held_out);
    for (const std::string& v : f.values) {
      const std::string key = v.substr(0, v.find('='));
      const bool edge = std::find(f.at_bound.begin(), f.at_bound.end(), key) != f.at_bound.end();
      std::printf(" %s%s", v.c_str(), edge ? " (at a bound)" : "");
    }
    std::printf("\n");
  }
  std::printf("calibrated model:");
  for (const std::string& s : diagnose::model_form_settings(cal.form)) std::printf(" --set %s", s.c_str());
  for (const std::string& s : cal.overrides) std::printf(" --set %s", s.c_str());
  std::printf("\n");
  for (const std::string& s : cal.at_bound)
    std::printf("not a fit but a limit: %s (the rig lies beyond the model's range there; the discrepancy "
                "budget carries the rest)\n", s.c_str());
}

std::string absolute_path(const std::string& p) { return std::filesystem::absolute(p).lexically_normal().string(); }

/// One recording's nuisance-only diagnosis with the rig elements `rig` (fit_healthy: the values
/// and cells of fits.fit(), the noise test of fits.noise_weighted), and its gear-set configuration.
struct RecordingFit {
  model::SimulationConfig config;
  diagnose::HealthyFitResult fits;
  const diagnose::Diagnosis& diagnosis() const { return fits.fit(); }
  const diagnose::Diagnosis& noise_test() const { return fits.noise_weighted; }
};

/// The nuisance parameters (sensor gains excepted) of `with` that `without` lacks: what the
/// calibration-only rig elements add.
std::vector<std::string> added_parameters(const RecordingFit& with, const RecordingFit& without) {
  std::vector<std::string> out;
  const auto& w = without.diagnosis().nuisance.parameters;
  for (const diagnose::FittedParameter& p : with.diagnosis().nuisance.parameters)
    if (!p.sensor_gain &&
        std::none_of(w.begin(), w.end(), [&](const diagnose::FittedParameter& q) { return q.name == p.name; }))
      out.push_back(p.name);
  return out;
}

/// Recording i's nuisance-only fit with the rig elements `rig`. `earlier`: null, or a fit of the same
/// recording (with fewer rig elements, or another structure) whose nuisance values are a second start
/// (DiagnoseOptions::nuisance_start_values). `held`: "key=value" lines applied after --set (a rig
/// structure held, shared_structure below).
RecordingFit fit_recording(const CalibrateCommandOptions& o, std::size_t i, const std::vector<std::string>& rig,
                           diagnose::HealthyFit weighting, const RecordingFit* earlier,
                           const std::vector<std::string>& held = {}) {
  // Inputs and the nuisance-only diagnosis, as `diagnose` would start.
  DiagnoseCommandOptions d;
  d.common = o.common;
  for (const std::string& h : held) d.common.assignments.push_back(h);
  d.recording = o.recordings[i];
  if (!o.metas.empty()) d.meta = o.metas[i];
  d.threads = o.threads;
  d.alpha = o.alpha;
  const DiagnoseInputs in = read_diagnose_inputs(d);
  diagnose::DiagnoseOptions opt;
  opt.alpha = o.alpha;
  opt.threads = o.threads;
  opt.nuisance_only = true;
  opt.probe_ring_body = o.ring_body;
  opt.extra_nuisance = visible_rig_elements(rig, in.recording);
  opt.compare.alpha = o.alpha;
  if (earlier)
    for (const diagnose::FittedParameter& p : earlier->diagnosis().nuisance.parameters)
      if (!p.sensor_gain) opt.nuisance_start_values[p.name] = p.value;
  if (!o.common.quiet) {
    std::fprintf(stderr, "[calibrate] recording %zu of %zu: %s (rig elements: %zu%s)\n", i + 1, o.recordings.size(),
                 d.recording.c_str(), opt.extra_nuisance.size(), held.empty() ? "" : "; a rig structure held");
    opt.progress = [](const std::string& s) { std::fprintf(stderr, "[calibrate]   %s\n", s.c_str()); };
  }
  RecordingFit f{in.config, diagnose::fit_healthy(in.recording, in.config, opt, weighting)};
  if (!o.common.quiet)
    std::fprintf(stderr, "[calibrate]   nuisance-fitted chi2 %.4g (fit) / %.4g (held out), noise bounds %.4g / %.4g\n",
                 f.noise_test().nuisance.fit.chi2, f.noise_test().nuisance.held_out.chi2, f.noise_test().bound_fit,
                 f.noise_test().bound_held_out);
  return f;
}

/// Each recording's fit (fit_recording), `earlier` empty or one fit per recording.
std::vector<RecordingFit> fit_recordings(const CalibrateCommandOptions& o, const std::vector<std::string>& rig,
                                         diagnose::HealthyFit weighting, const std::vector<RecordingFit>& earlier = {}) {
  std::vector<RecordingFit> out;
  for (std::size_t i = 0; i < o.recordings.size(); ++i)
    out.push_back(fit_recording(o, i, rig, weighting, i < earlier.size() ? &earlier[i] : nullptr));
  return out;
}

/// The calibration-only elements' settings a recording's fit holds (structural_rig_settings of a
/// calibration holding only that fit).
std::vector<std::string> structure_of(const std::vector<diagnose::FittedParameter>& params,
                                      const std::vector<std::string>& rig, const model::SimulationConfig& base_config) {
  diagnose::Calibration one;
  one.rig_elements = rig;
  one.fits.push_back(diagnose::calibration_fit(params, 0, 0));
  return diagnose::structural_rig_settings(one, base_config, std::size_t{0});
}

/// One rig structure for all operating points (docs/diagnose.md section 6a item 8). The candidates:
/// each recording's fitted structure and their pooled one (diagnose::pooled_structure, the inverse-
/// variance mean of the recordings' estimates). Every recording is refitted with every candidate
/// other than its own held (its other nuisance values refitted, from its own fit's values as a
/// second start), and the candidate of the largest joint profile likelihood
/// (diagnose::choose_shared_structure) is taken. When no recording rejects it by the F test, each
/// recording's fit is replaced by its fit under that structure, the structure's values carried
/// over so that the file's per-recording values, the medians and a calibrated reference all hold
/// the same structure. Costs n^2 nuisance fits with fewer parameters (n(n-1) without a pooled
/// candidate). `structure_names`: the parameters the calibration-only elements add (the F test's p
/// is their number).
void share_rig_structure(const CalibrateCommandOptions& o, const std::vector<std::string>& rig,
                         diagnose::HealthyFit weighting, const model::SimulationConfig& base_config,
                         const std::vector<std::string>& structure_names, std::vector<RecordingFit>& fits) {
  const std::size_t n = fits.size();
  std::vector<std::string> plain;
  for (const std::string& r : rig)
    if (!diagnose::find_candidate(r)->calibration_only()) plain.push_back(r);
  // Candidate k's parameters (their values; the other nuisance values are refitted) and settings.
  std::vector<std::vector<diagnose::FittedParameter>> candidate;
  for (const RecordingFit& f : fits) candidate.push_back(f.diagnosis().nuisance.parameters);
  std::vector<std::vector<std::string>> structure;
  for (const auto& params : candidate) structure.push_back(structure_of(params, rig, base_config));
  if (structure.front().empty()) return;
  if (const auto pooled = diagnose::pooled_structure(candidate, structure_names)) {
    std::vector<diagnose::FittedParameter> params = candidate.front();
    for (const diagnose::FittedParameter& q : *pooled)
      for (diagnose::FittedParameter& p : params)
        if (p.name == q.name) p = q;
    std::vector<std::string> settings = structure_of(params, rig, base_config);
    if (std::find(structure.begin(), structure.end(), settings) == structure.end()) {
      candidate.push_back(std::move(params));
      structure.push_back(std::move(settings));
    }
  }
  const std::size_t kc = structure.size();
  std::vector<std::vector<double>> chi2(n, std::vector<double>(kc, 0.0));
  std::vector<std::vector<std::optional<RecordingFit>>> refit(n);
  std::vector<int> features;
  for (std::size_t j = 0; j < n; ++j) {
    refit[j].resize(kc);
    features.push_back(fits[j].noise_test().nuisance.held_out.features);
    for (std::size_t k = 0; k < kc; ++k) {
      if (k == j || structure[k] == structure[j]) {
        chi2[j][k] = fits[j].noise_test().nuisance.held_out.chi2;
        continue;
      }
      refit[j][k] = fit_recording(o, j, plain, weighting, &fits[j], structure[k]);
      chi2[j][k] = refit[j][k]->noise_test().nuisance.held_out.chi2;
    }
  }
  const int p = static_cast<int>(structure_names.size());
  const diagnose::SharedStructure s = diagnose::choose_shared_structure(chi2, features, p, o.alpha);
  const auto name = [&](std::size_t k) {
    return k < n ? "recording " + std::to_string(k + 1) + "'s" : std::string("the recordings' pooled");
  };
  std::fprintf(stderr, "[calibrate] one rig structure for every operating point: %s (", name(s.from).c_str());
  for (std::size_t m = 0; m < structure[s.from].size(); ++m)
    std::fprintf(stderr, "%s%s", m ? ", " : "", structure[s.from][m].c_str());
  std::fprintf(stderr, "); joint profile log-likelihood loss per candidate (");
  for (std::size_t k = 0; k < kc; ++k) std::fprintf(stderr, "%s%s", k ? ", " : "", name(k).c_str());
  std::fprintf(stderr, "):");
  for (double l : s.loss) std::fprintf(stderr, " %.4g", l);
  std::fprintf(stderr, " nats\n");
  for (std::size_t j = 0; j < n; ++j)
    std::fprintf(stderr, "[calibrate]   recording %zu: held-out chi2 %.4g with the shared structure, %.4g with its own%s\n",
                 j + 1, chi2[j][s.from], chi2[j][j],
                 s.rejects_shared[j] ? " -- its own fits better than its parameters buy by chance (F test)" : "");
  // A structure is the rig's only where every operating point accepts it (the same F test that
  // keeps the elements at all, rig_elements_improve). Where one rejects it, the operating points
  // disagree on the structure beyond chance: what the elements fit there is the model's form
  // error, which differs per operating point, and holding one structure then moves that error
  // into the nuisance values and the references (measured: docs/diagnose-log.md, session 51).
  if (std::find(s.rejects_shared.begin(), s.rejects_shared.end(), true) != s.rejects_shared.end()) {
    std::fprintf(stderr, "[calibrate] the operating points disagree on the rig's structure beyond chance: each "
                         "recording keeps the structure its own fit measured\n");
    return;
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (!refit[j][s.from]) continue;
    RecordingFit f = std::move(*refit[j][s.from]);
    // Carry the held structure's values into this recording's fit (names the refit lacks).
    auto& params = f.fits.noise_weighted.nuisance.parameters;
    std::vector<diagnose::FittedParameter> carried;
    for (const diagnose::FittedParameter& q : candidate[s.from])
      if (!q.sensor_gain &&
          std::none_of(params.begin(), params.end(), [&](const diagnose::FittedParameter& r) { return r.name == q.name; }))
        carried.push_back(q);
    for (auto* d : {&f.fits.noise_weighted, f.fits.model_form_weighted ? &*f.fits.model_form_weighted : nullptr})
      if (d) d->nuisance.parameters.insert(d->nuisance.parameters.end(), carried.begin(), carried.end());
    f.config = fits[j].config;
    fits[j] = std::move(f);
  }
}

/// The calibrated model's form, one part at a time. A model whose form differs from the rig's
/// cannot reproduce its recordings, and its discrepancy budget would carry that form error into
/// every diagnosis of the rig. Where every recording's nuisance model failed the noise test and
/// its probe of the other form fits better (diagnose::form_probes_pass), every recording is
/// refitted in that form from its own values; the form is taken only if each refit leaves less
/// held-out chi2 (diagnose::form_refits_improve). Then `fits` are the refits and `o` holds the
/// form for every later fit. Costs one simulation per recording that failed the noise test, and
/// one nuisance fit per recording where the probes pass.
bool choose_model_form(CalibrateCommandOptions& o, std::vector<std::string>& rig, diagnose::HealthyFit weighting,
                       std::vector<RecordingFit>& fits, const diagnose::ModelFormPart& choice,
                       const diagnose::ModelForm& chosen) {
  // A rig element the form brings (the ring body's support damping) is fitted in its refits and
  // joins the calibration's rig elements if the form is taken.
  std::vector<std::string> form_rig = rig;
  int extra = 1;
  if (choice.rig_element && std::find(rig.begin(), rig.end(), choice.rig_element) == rig.end()) {
    form_rig.emplace_back(choice.rig_element);
    diagnose::ModelForm changed = choice.changed(diagnose::ModelForm{});
    model::SimulationConfig in_form = fits.front().config;
    diagnose::apply_model_form(in_form, changed);
    extra += static_cast<int>(diagnose::find_candidate(choice.rig_element)->parameters(in_form).size());
  }
  std::vector<diagnose::ModelFormFits> form;
  for (const RecordingFit& f : fits) {
    const diagnose::Diagnosis& d = f.noise_test();
    form.push_back({.fit_chi2 = d.nuisance.fit.chi2, .probe_fit_chi2 = d.*choice.probe,
                    .fit_features = d.nuisance.fit.features, .held_out_chi2 = d.nuisance.held_out.chi2,
                    .refit_held_out_chi2 = std::nullopt, .held_out_features = d.nuisance.held_out.features,
                    .extra_parameters = extra});
  }
  if (!diagnose::form_probes_pass(form, o.alpha)) return false;
  CalibrateCommandOptions other = o;
  other.common.assignments = diagnose::assignments_in_form(o.common.assignments, chosen, choice);
  if (!o.common.quiet)
    std::fprintf(stderr, "[calibrate] every recording fits better with the %s %s: each refitted in that form\n",
                 choice.part, choice.other);
  std::vector<RecordingFit> refits = fit_recordings(other, form_rig, weighting, fits);
  for (std::size_t i = 0; i < fits.size(); ++i) form[i].refit_held_out_chi2 = refits[i].noise_test().nuisance.held_out.chi2;
  const bool taken = diagnose::form_refits_improve(form, o.alpha);
  if (!o.common.quiet) {
    for (std::size_t i = 0; i < fits.size(); ++i)
      std::fprintf(stderr, "[calibrate]   recording %zu: held-out chi2 %.4g %s, %.4g %s\n", i + 1,
                   *form[i].refit_held_out_chi2, choice.other, form[i].held_out_chi2, choice.own);
    std::fprintf(stderr, "[calibrate] the calibrated model's %s: %s%s\n", choice.part, taken ? choice.other : choice.own,
                 taken ? "" : " (not every recording's held-out half fits the other form better than chance)");
  }
  if (!taken) return false;
  fits = std::move(refits);
  o = std::move(other);
  rig = std::move(form_rig);
  return true;
}

/// The parts of the form in turn (the mesh first: the housing path's probes then come from the
/// refits in the chosen mesh form), each part changed in `form` where the recordings chose it.
/// A part already changed is not probed again (the diagnoses probe only a part at its default).
void choose_model_form(CalibrateCommandOptions& o, std::vector<std::string>& rig, diagnose::HealthyFit weighting,
                       std::vector<RecordingFit>& fits, diagnose::ModelForm& form) {
  // The ring body last and only with --ring-body, probed from the window's fits or, where the ring's
  // translation was taken, from those refits; it also brings the lateral-torsional model.
  for (const diagnose::ModelFormPart* c :
       {&diagnose::kTimeLockedMesh, &diagnose::kRingTranslationHousing, &diagnose::kRingBodyHousing})
    if ((c != &diagnose::kRingBodyHousing || o.ring_body) && choose_model_form(o, rig, weighting, fits, *c, form))
      form = c->changed(form);
}

/// A housing mount among the kept rig elements that no recording can measure -- no housing line
/// above the noise in any of them (diagnose::housing_lines_heard) -- is held at its 'absent'
/// values in `params`: its fit only wandered over a flat chi2 (on indepsim4's setC3, three planets
/// in phase whose ring stays still, it ended at 2.2 Hz with 1 % damping, a resonance on the
/// carrier's first order that any later fault's lines there would pass through; docs/diagnose-log.md,
/// session 71).
void hold_unmeasured_mount(const std::vector<std::string>& rig, const model::SimulationConfig& base_config,
                           const std::vector<std::vector<diagnose::CalibrationCell>>& cells,
                           const CalibrateCommandOptions& o, std::vector<std::vector<diagnose::FittedParameter>>& params) {
  const std::string mount = "housing_mount";
  if (std::find(rig.begin(), rig.end(), mount) == rig.end() || diagnose::housing_lines_heard(cells, o.alpha)) return;
  std::vector<std::pair<std::string, double>> nulls;
  std::string text;
  for (const diagnose::ParameterSpec& p : diagnose::find_candidate(mount)->parameters(base_config)) {
    nulls.emplace_back(p.name, p.null_value);
    text += " " + p.name + "=" + diagnose::format_value(p.null_value);
  }
  diagnose::hold_at_null(params, nulls);
  if (!o.common.quiet)
    std::fprintf(stderr,
                 "[calibrate] no recording's housing channel holds a line above the noise: the housing's mount "
                 "cannot be measured and is held at 'absent' (%s)\n",
                 text.c_str() + 1);
}

} // namespace

int run_calibrate(const CalibrateCommandOptions& o_in) {
  CalibrateCommandOptions o = o_in;  // the calibrated model's form joins its assignments (choose_model_form)
  require(o.metas.empty() || o.metas.size() == o.recordings.size(), "--meta", "give one sidecar per --recording (",
          o.recordings.size(), " recordings, ", o.metas.size(), " sidecars) or none");
  std::vector<std::string> rig = o.rig_elements;
  if (rig.size() == 1 && rig[0] == "none") rig.clear();
  for (const std::string& r : rig)
    require(diagnose::find_candidate(r) != nullptr, "--rig-elements", "unknown candidate '", r, "'");

  diagnose::Calibration cal;
  cal.alpha = o.alpha;
  cal.healthy_fit = diagnose::healthy_fit_from_string(o.healthy_fit, "--healthy-fit");
  // Calibration-only rig elements (a shaft behind a speed source) have no value without effect,
  // so LM cannot fall back to the model without them: they are kept only if the fit with them
  // beats the fit without on every recording's held-out half by more than chance
  // (rig_elements_improve). The fit without comes first and is a start of the fit with them: a
  // scan of one element at a time from the nominal start can end in a basin worse than the model
  // without them (the four-planet baselines of docs/diagnose.md §6a, indepsim2's rigA3 with the
  // encoder's low-pass and the input shaft: docs/diagnose-log.md, session 46); from the fit
  // without, the shaft's own scan runs with the other nuisance values where they fit.
  std::vector<std::string> plain;
  for (const std::string& r : rig)
    if (!diagnose::find_candidate(r)->calibration_only()) plain.push_back(r);
  std::vector<RecordingFit> fits;
  if (plain.size() == rig.size()) {
    fits = fit_recordings(o, rig, cal.healthy_fit);
    choose_model_form(o, rig, cal.healthy_fit, fits, cal.form);
  } else {
    std::vector<RecordingFit> without = fit_recordings(o, plain, cal.healthy_fit);
    choose_model_form(o, plain, cal.healthy_fit, without, cal.form);
    for (const std::string& r : plain)  // an element the form brought (choose_model_form)
      if (std::find(rig.begin(), rig.end(), r) == rig.end()) rig.push_back(r);
    fits = fit_recordings(o, rig, cal.healthy_fit, without);
    for (std::size_t i = 0; i < fits.size(); ++i) {
      const diagnose::NestedFits nested{.chi2_without = without[i].noise_test().nuisance.held_out.chi2,
                                        .chi2_with = fits[i].noise_test().nuisance.held_out.chi2,
                                        .features = fits[i].noise_test().nuisance.held_out.features,
                                        .extra_parameters = static_cast<int>(added_parameters(fits[i], without[i]).size())};
      if (!diagnose::rig_elements_improve(nested, o.alpha)) {
        std::string ended;  // where the fit with them ended: a rig engineer's lead even when it is not kept
        for (const diagnose::FittedParameter& p : fits[i].diagnosis().nuisance.parameters)
          if (p.name.rfind("rig.", 0) == 0) ended += " " + p.name + "=" + diagnose::format_value(p.value);
        std::fprintf(stderr,
                     "[calibrate] the calibration-only rig elements are left out: on recording %zu the fit with them "
                     "leaves held-out chi2 %.4g, without them %.4g, not lower by more than their %d parameters buy "
                     "by chance (F test at alpha %.3g over %d features; the fit with them ended at%s)\n",
                     i + 1, nested.chi2_with, nested.chi2_without, nested.extra_parameters, o.alpha, nested.features,
                     ended.empty() ? " no rig value" : ended.c_str());
        fits = std::move(without);
        rig = plain;
        break;
      }
    }
    // The form again with the rig's elements: a form error can hide behind one the elements
    // remove (measured, session 67: indepsim4's setD4, whose ring's translation fitted 1 % better
    // than the window without the input shaft and 2.6 times better with it).
    if (rig.size() != plain.size()) choose_model_form(o, rig, cal.healthy_fit, fits, cal.form);
    if (rig.size() != plain.size() && fits.size() > 1 && o.rig_structure == "shared")
      share_rig_structure(o, rig, cal.healthy_fit, fits.front().config, added_parameters(fits.front(), without.front()),
                          fits);
  }
  cal.rig_elements = rig;
  std::vector<std::vector<diagnose::CalibrationCell>> cells;
  std::vector<std::vector<diagnose::FittedParameter>> params;
  const model::SimulationConfig& base_config = fits.front().config;  // the gear set's, for the rig elements' settings
  for (std::size_t i = 0; i < fits.size(); ++i) {
    const diagnose::Diagnosis& r = fits[i].diagnosis();
    const diagnose::Diagnosis& noise = fits[i].noise_test();
    // Absolute paths: `diagnose --calibration` finds the recording at its operating point again
    // from wherever it runs (docs/diagnose.md §6a item 6).
    cal.recordings.push_back(absolute_path(o.recordings[i]));
    cal.sidecars.push_back(absolute_path(o.metas.empty() ? io::sidecar_path(o.recordings[i]).string() : o.metas[i]));
    cal.speeds_rpm.push_back(r.speed.input_rpm);
    cal.verdicts.push_back(diagnose::to_string(noise.verdict));
    cells.push_back(r.calibration_cells);
    params.push_back(r.nuisance.parameters);
  }
  hold_unmeasured_mount(rig, base_config, cells, o, params);
  for (std::size_t i = 0; i < fits.size(); ++i) {
    // The noise-weighted fit's chi2 and bound (how far the model's form is from this recording),
    // the values of the fit whose cells the discrepancy is estimated from.
    const diagnose::Diagnosis& noise = fits[i].noise_test();
    cal.fits.push_back(diagnose::calibration_fit(params[i], noise.nuisance.held_out.chi2, noise.bound_held_out));
  }
  // 2. The calibration.
  cal.discrepancy = diagnose::estimate_discrepancy(cells);
  cal.coverage = diagnose::line_coverage(cells, cal.speeds_rpm);
  cal.overrides = diagnose::median_overrides(params);
  for (std::string& line : diagnose::rig_element_settings(rig, base_config, cal.overrides))
    cal.overrides.push_back(std::move(line));
  cal.at_bound = diagnose::parameters_at_bound(params);
  // 3. The file and the table.
  io::write_calibration(cal, o.output);
  print_table(cal);
  if (!o.common.quiet) std::fprintf(stderr, "wrote %s\n", o.output.c_str());
  return 0;
}

} // namespace pw::app
