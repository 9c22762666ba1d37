#include "io/diagnosis_report.hpp"

#include "diagnose/verdict.hpp"
#include "io/atomic_output.hpp"
#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace pw::io {
namespace {

using json = nlohmann::ordered_json;
namespace dg = pw::diagnose;


double finite_or_null(double v) { return std::isfinite(v) ? v : 0.0; }

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json score_json(const dg::ScoreSummary& s, const std::vector<std::string>& channels) {
  json j;
  j["chi2"] = num(s.chi2);
  j["features"] = s.features;
  j["chi2_per_feature"] = num(s.features > 0 ? s.chi2 / s.features : 0.0);
  json per = json::object();
  for (std::size_t c = 0; c < channels.size() && c < s.chi2_per_channel.size(); ++c)
    per[channels[c]] = {{"chi2", num(s.chi2_per_channel[c])}, {"features", s.features_per_channel[c]}};
  j["channels"] = per;
  j["fidelity_weights"] = s.fidelity_z;
  return j;
}

json candidate_json(const dg::CandidateResult& r, const std::vector<std::string>& channels) {
  json j;
  j["name"] = r.name;
  j["physics"] = r.physics;
  j["variant"] = r.variant;
  j["families"] = r.families;
  j["evidence_z"] = num(r.evidence_z);
  j["predicted_improvement"] = num(r.predicted_improvement);
  j["start_step_fraction"] = num(r.start_step_fraction);
  json ps = json::array();
  for (const auto& p : r.parameters) {
    json pj = {{"name", p.name}, {"unit", p.unit}, {"value", num(p.value)}, {"std_error", num(p.std_error)},
               {"lower", num(p.lower)}, {"upper", num(p.upper)}, {"initial", num(p.initial)},
               {"model_form_std", num(p.model_form_std)},
               {"model_form_range", {num(p.model_form_lower), num(p.model_form_upper)}},
               {"level_spread_std", num(p.level_spread_std)}, {"level_spread_of", p.level_spread_of}, {"at_bound", p.at_bound},
               {"nuisance", p.nuisance}, {"moved", p.moved}};
    // Saturating: only a lower limit is identifiable (null when it was not profiled).
    if (p.saturates) {
      pj["saturates"] = true;
      pj["lower_limit"] = num(p.lower_limit);
    }
    if (p.transfer) pj["transfer"] = true;  // how the physics reaches the sensors, not the finding
    if (!p.size_conditional_on.empty()) pj["size_conditional_on"] = p.size_conditional_on;
    ps.push_back(std::move(pj));
  }
  j["parameters"] = ps;
  j["overrides"] = r.overrides;
  j["fit_half"] = score_json(r.fit, channels);
  j["held_out_half"] = score_json(r.held_out, channels);
  j["delta_chi2_fit"] = num(r.delta_chi2_fit);
  j["delta_chi2_held_out"] = num(r.delta_chi2_held_out);
  j["likelihood_ratio_threshold"] = num(r.lr_threshold);
  j["aic"] = num(r.aic);
  j["bic"] = num(r.bic);
  j["bic_held_out"] = num(r.bic_held_out);
  j["significant"] = r.significant;
  j["holds_on_held_out"] = r.holds;
  j["parameters_differ_from_absent"] = r.non_null;
  if (std::isfinite(r.null_chi2_fit)) j["chi2_fit_at_absent"] = num(r.null_chi2_fit);
  j["simulations"] = r.simulations;
  j["seconds"] = r.seconds;
  if (!r.failed.empty()) j["failed"] = r.failed;
  j["lm"] = r.lm_message;
  j["reason"] = r.reason;
  if (!r.hold_refit.empty()) j["hold_refit"] = r.hold_refit;
  return j;
}

std::string g(double v, int prec = 4) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// "halves of 3 whole carrier revolution(s)" or "halves of 42 whole mesh cycles (0.519 carrier
/// revolutions each)" (recordings too short for two whole carrier revolutions).
std::string halves_text(const dg::Diagnosis& d) {
  if (d.window_mesh_cycles == 0) return "Halves of " + std::to_string(d.revolutions) + " whole carrier revolution(s)";
  return "Halves of " + std::to_string(d.window_mesh_cycles) + " whole mesh cycles (" + g(d.window_revolutions, 3) +
         " carrier revolutions each; the recording holds " + g(d.recording_revolutions, 3) + ")";
}

std::string param_cell(const dg::FittedParameter& p) {
  const std::string unit = (p.unit != "1" && !p.unit.empty()) ? " " + p.unit : "";
  if (p.saturates && std::isfinite(p.lower_limit))
    return ">= " + g(p.lower_limit, 3) + unit + " (lower limit; fitted " + g(p.value) + ", any larger value fits as well)";
  if (p.saturates) return g(p.value) + unit + " (saturating: only a lower limit is identifiable)";
  std::string s = g(p.value) + " ± " + (std::isfinite(p.std_error) ? g(p.std_error, 2) : std::string("n/a")) + unit;
  if (p.model_form_std > 0 && !p.nuisance && std::isfinite(p.model_form_lower))
    s += " (model form ± " + g(p.model_form_std, 2) + unit + ": " + g(p.model_form_lower, 3) + " to " +
         g(p.model_form_upper, 3) + unit + ")";
  if (p.level_spread_std > 0 && !p.nuisance && std::isfinite(p.model_form_lower))
    s += " (± " + g(p.level_spread_std, 2) + unit + " of it from how far the calibration's healthy recordings scatter " +
         p.level_spread_of + ")";
  if (p.at_bound) s += " (at bound)";
  if (p.transfer) s += " (how it reaches the sensors, not its size)";
  if (!p.size_conditional_on.empty()) s += " (the size for " + p.size_conditional_on + ")";
  return s;
}

/// Markdown body (also turned into HTML below).
struct Doc {
  std::vector<std::pair<std::string, std::string>> blocks;  // (kind, text): "h1","h2","p","table","img","pre"
  void h1(std::string s) { blocks.push_back({"h1", std::move(s)}); }
  void h2(std::string s) { blocks.push_back({"h2", std::move(s)}); }
  void p(std::string s) { blocks.push_back({"p", std::move(s)}); }
  void pre(std::string s) { blocks.push_back({"pre", std::move(s)}); }
  void img(std::string s) { blocks.push_back({"img", std::move(s)}); }
  void table(const std::vector<std::vector<std::string>>& rows) {
    std::string t;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      t += "|";
      for (const auto& c : rows[i]) t += " " + c + " |";
      t += "\n";
      if (i == 0) {
        t += "|";
        for (std::size_t k = 0; k < rows[i].size(); ++k) t += "---|";
        t += "\n";
      }
    }
    blocks.push_back({"table", t});
  }
};

std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

// The report's sections, in order (build() below).
void add_header(Doc& doc, const dg::Diagnosis& d, const ReportContext& ctx) {
  doc.h1("planetwear diagnose");
  doc.p("**Finding:** " + d.summary);
  doc.p("Verdict: `" + std::string(dg::to_string(d.verdict)) + "`. Recording `" + ctx.recording_path +
        "`, configuration `" + (ctx.config_path.empty() ? "(seed defaults)" : ctx.config_path) + "`" +
        (ctx.calibration_path.empty() ? std::string() : ", calibration `" + ctx.calibration_path + "`") +
        (ctx.baseline_path.empty() ? std::string() : ", healthy baseline `" + ctx.baseline_path + "`") + ", " +
        ctx.version + ".");
  if (!ctx.calibration_at_bound.empty()) {
    std::string list;
    for (const auto& s : ctx.calibration_at_bound) list += (list.empty() ? "" : "; ") + s;
    doc.p("The calibrated model is at the edge of its range: " + list +
          ". Those values are limits, not fits; the calibration's discrepancy budget carries what they could not.");
  }
  if (!ctx.calibration_reference.empty()) doc.p("Calibration: " + ctx.calibration_reference + ".");
  if (!ctx.baseline_path.empty())
    doc.p("Differential diagnosis: the recording is compared with the model fitted to the baseline plus what that "
          "model missed on the baseline, cell by cell (" + ctx.baseline_summary +
          "). Findings are changes from the baseline; a fault already present in the baseline cannot be seen." +
          (ctx.baseline_operating_point.empty() ? std::string() : " Operating point: " + ctx.baseline_operating_point + "."));
  if (!ctx.baseline_at_bound.empty()) {
    std::string list;
    for (const auto& s : ctx.baseline_at_bound) list += (list.empty() ? "" : "; ") + s;
    doc.p("The model fitted to the baseline is at the edge of its range: " + list +
          ". Those values are limits, not fits: the model cannot reach the baseline's level there, and the recording's "
          "change is judged, and a finding's size stated, against that limited model.");
  }
}

void add_kinematics(Doc& doc, const dg::Diagnosis& d) {
  const auto& k = d.kinematics;
  doc.h2("Operating point and kinematics");
  doc.p("Speed " + g(d.speed.input_rpm, 7) + " rpm (± " + g(d.speed.relative_std, 2) + " relative) from the " +
        d.speed.source + "; carrier angle from the " + d.angle_source + ". The model is simulated at that speed (its " +
        "record's mean: " + g(d.model_speed_rpm, 7) + " rpm).");
  doc.table({{"f_s (sun)", "f_c (carrier)", "f_sr = f_s - f_c", "f_pr = f_m/Zp", "f_m (mesh)"},
             {g(k.sun_Hz) + " Hz", g(k.carrier_Hz) + " Hz", g(k.sun_relative_Hz) + " Hz",
              g(k.planet_relative_Hz) + " Hz", g(k.mesh_Hz) + " Hz"},
             {"order " + g(k.sun_Hz / k.carrier_Hz), "order 1", "order " + g(k.sun_relative_Hz / k.carrier_Hz),
              "order " + g(k.planet_relative_Hz / k.carrier_Hz), "order " + g(k.mesh_Hz / k.carrier_Hz)}});
  doc.p(halves_text(d) + ": fit t = " +
        g(d.fit_window.t_begin_s, 6) + " .. " + g(d.fit_window.t_end_s, 6) + " s, held out t = " +
        g(d.held_out_window.t_begin_s, 6) + " .. " + g(d.held_out_window.t_end_s, 6) + " s. " +
        std::to_string(d.cells) + " feature bins per channel up to carrier order " + g(d.max_order) + " (" +
        g(d.max_frequency_Hz) + " Hz, " + std::to_string(d.mesh_harmonics) + " mesh harmonics), " +
        std::to_string(d.features) + " features; " + std::to_string(d.nonstationary_features) +
        " differ between the halves beyond the noise (non-stationary).");
  if (!d.unresolved_families.empty())
    doc.p("**Could not be resolved in " + g(d.recording_revolutions, 3) + " carrier revolutions:** the " +
          join(d.unresolved_families) + " families complete no whole period in " +
          std::to_string(d.window_mesh_cycles) + " mesh cycles, so their lines are not compared" +
          (d.unresolved_candidates.empty() ? std::string(".")
                                           : "; candidates not fitted: " + join(d.unresolved_candidates) + ".") +
          (d.dropped_channels.empty() ? std::string()
                                      : " Channels not compared (their lines are all carrier-family lines): " +
                                            join(d.dropped_channels) + "."));

}

/// "a or b or c".
std::string join_members(const std::vector<std::string>& members) {
  std::string s;
  for (const std::string& m : members) s += (s.empty() ? "" : " or ") + m;
  return s;
}

void add_residual(Doc& doc, const dg::Diagnosis& d) {
  doc.h2("Residual before and after");
  std::vector<std::vector<std::string>> rows{{"model", "chi2 fit half", "chi2 held out", "null bound (fit / held out)"}};
  rows.push_back({"nominal (as configured, at the recording's speed)", g(d.nominal_fit.chi2, 6),
                  g(d.nominal_held_out.chi2, 6), g(d.bound_fit, 5) + " / " + g(d.bound_held_out, 5)});
  rows.push_back({"nuisance fitted", g(d.nuisance.fit.chi2, 6), g(d.nuisance.held_out.chi2, 6), ""});
  if (d.lead.candidate == 0)
    rows.push_back({(d.winner == 0 ? "with " : "lead (not a finding): with ") + d.candidates.front().name,
                    g(d.candidates.front().fit.chi2, 6), g(d.candidates.front().held_out.chi2, 6),
                    "its own (its fidelity): " + g(d.lead.held_out_chi2, 6) + " vs " + g(d.lead.bound_held_out, 5) +
                        " held out"});
  doc.table(rows);
  if (d.lead.candidate == 0)
    doc.p("Best candidate `" + d.candidates.front().name + "`: explains " +
          (std::isfinite(d.lead.explained_fraction) ? g(100 * d.lead.explained_fraction, 3) + " %" : std::string("n/a")) +
          " of the held-out excess over the noise bound; " +
          (d.lead.failed.empty()       ? std::string("named (within its own bound, no parameter at a bound).")
           : !d.lead.named_class.empty() ? "named as its class " + d.lead.named_class + " (" +
                                               join_members(d.lead.class_members) +
                                               "), not alone: " + d.lead.failed + "."
                                         : "not named: " + d.lead.failed + "."));
  if (!d.excess_by_channel.empty() && d.verdict != dg::Verdict::NoMissingPhysics) {
    std::vector<std::vector<std::string>> ex{{"channel", "held-out chi2 excess (nuisance fitted)", "share"}};
    for (const auto& e : d.excess_by_channel) ex.push_back({e.channel, g(e.excess, 5), g(100 * e.share, 3) + " %"});
    doc.table(ex);
  }
  {
    std::vector<std::vector<std::string>> pc{{"channel", "noise per bin (rms)", "chi2/m nominal (fit, held out)",
                                              "chi2/m final (fit, held out)"}};
    const dg::CandidateResult& fin = d.winner == 0 ? d.candidates.front() : d.nuisance;
    for (std::size_t c = 0; c < d.channels.size(); ++c) {
      auto r = [&](const dg::ScoreSummary& s) {
        return c < s.chi2_per_channel.size() ? g(s.chi2_per_channel[c] / s.features_per_channel[c], 4)
                                              : std::string("");
      };
      pc.push_back({d.channels[c], g(d.noise_std[c], 3) + (d.noise_coloured[c] ? " (coloured)" : "") +
                                    (d.noise_dispersion[c] != 1.0 ? " (halves: x" + g(d.noise_dispersion[c], 3) + ")" : ""),
                    r(d.nominal_fit) + ", " + r(d.nominal_held_out), r(fin.fit) + ", " + r(fin.held_out)});
    }
    doc.table(pc);
  }
  doc.p("Decision rule: " + d.rule);

}

void add_nuisance(Doc& doc, const dg::Diagnosis& d) {
  doc.h2("Nuisance parameters (fitted first)");
  {
    std::vector<std::vector<std::string>> t{{"parameter", "fitted", "start", "recalibrated"}};
    for (const auto& p : d.nuisance.parameters)
      t.push_back({p.name, param_cell(p), g(p.initial), p.moved ? "yes" : "no"});
    doc.table(t);
    doc.p("Recalibrated: differs from its start by more than z_{1-alpha/2} standard errors and by more than 5 % "
          "(smaller shifts are within the model's own fidelity).");
  }

}

void add_location(Doc& doc, const dg::Diagnosis& d) {
  if (d.located) {
    doc.h2("Where the residual lives");
    std::vector<std::vector<std::string>> t{
        {"rank", "family", "z", "share of excess", "rotation", "strongest channel", "meaning"}};
    int rank = 1;
    for (const auto& f : d.location.families)
      t.push_back({std::to_string(rank++), dg::to_string(f.family), g(f.z, 3), g(100 * f.share, 3) + " %",
                   g(f.frequency_Hz, 4) + " Hz (order " + g(f.carrier_orders, 4) + ")", f.strongest_channel,
                   f.meaning});
    doc.table(t);
    doc.p("A family counts as located above z = " + g(d.location.significance_z, 3) + ". With " +
          (d.window_mesh_cycles == 0 ? "halves of " + std::to_string(d.revolutions) + " revolution(s)"
                                     : "halves of " + std::to_string(d.window_mesh_cycles) + " mesh cycles") +
          " the lines of different families share bins (z by labels); " +
          (d.location.screened_family >= 0
               ? "by the candidates' own signatures (screening below) the residual is located in the **" +
                     std::string(dg::to_string(static_cast<dg::Component>(d.location.screened_family))) +
                     "** family (" + d.location.screened_candidate + ", S = " + g(d.location.screened_S, 4) + ")."
               : std::string("no candidate's signature explains it at first order.")));
    std::vector<std::vector<std::string>> l{
        {"order", "frequency [Hz]", "channel", "rho^2 (mean of halves)", "recording / model", "kinematic lines"}};
    for (const auto& line : d.location.lines) {
      std::string lab;
      for (const auto& s : line.labels) lab += (lab.empty() ? "" : "; ") + s;
      l.push_back({g(line.order, 5), g(line.frequency_Hz, 6), line.channel, g(line.chi2, 3),
                   g(line.recording_amplitude, 3) + " / " + g(line.model_amplitude, 3), lab});
    }
    doc.table(l);
    for (const auto& re : d.location.rotations)
      doc.p("Rotation: " + std::string(dg::to_string(re.component)) + " (period " +
            std::to_string(re.period_mesh_cycles) + " mesh cycles), synchronous average of `" + re.channel + "` over " +
            std::to_string(re.averages) + " periods: energy peak at " + g(re.peak_angle_rad, 3) +
            " rad of its rotation from " + re.reference + " (peak/mean " + g(re.peak_to_mean, 3) + "); " +
            re.tooth_note + ".");
    if (!d.location.input_orders.empty()) {
      std::string s;
      for (double o : d.location.input_orders) s += (s.empty() ? "" : ", ") + g(o);
      doc.p("Input-shaft orders with the largest excess: " + s + ".");
    }
  }

}

void add_screening_and_candidates(Doc& doc, const dg::Diagnosis& d) {
  if (!d.screening.empty()) {
    doc.h2("Screening");
    doc.p("Every candidate moved from its no-effect value to a moderate one from the nuisance-fitted model; S = "
          "r'J(J'J)^-1 J'r is the chi2 improvement its linearized step predicts (score statistic, ~chi2(k) if "
          "the physics is absent). The largest are fitted. A candidate with transfer parameters (how its size "
          "reaches the sensors) is screened with them at 'absent' and at their screening values, and keeps the "
          "larger S (marked *).");
    std::vector<std::vector<std::string>> t{{"candidate", "best variant", "S", "fitted"}};
    for (const auto& sr : d.screening)
      t.push_back({sr.name, sr.variant,
                   sr.failed ? "simulation failed" : g(sr.predicted_improvement, 5) + (sr.at_transfer_values ? " *" : ""),
                   sr.fitted ? "yes" : "no"});
    doc.table(t);
  }
  if (!d.candidates.empty()) {
    doc.h2("Candidates");
    std::vector<std::vector<std::string>> t{
        {"rank", "candidate", "variant", "parameters", "Δchi2 fit", "Δchi2 held out", "BIC fit + held out", "why"}};
    int rank = 1;
    for (const auto& c : d.candidates) {
      std::string ps;
      for (const auto& p : c.parameters)
        if (!p.nuisance) ps += (ps.empty() ? "" : "; ") + p.name + " = " + param_cell(p);
      t.push_back({std::to_string(rank++), c.name, c.variant, ps, g(c.delta_chi2_fit, 5), g(c.delta_chi2_held_out, 5),
                   g(c.bic + c.bic_held_out, 6),
                   c.hold_refit.empty() ? c.reason : c.reason + "; " + c.hold_refit});
    }
    doc.table(t);
  }
  doc.p("Fitted model, reproducible with `planetwear simulate`:");
  {
    std::string s;
    for (const auto& o : d.final_overrides) s += "--set '" + o + "' ";
    doc.pre(s);
  }

}

void add_plots_and_time(Doc& doc, const dg::Diagnosis& d, const ReportContext& ctx) {
  doc.h2("Plots");
  // Link only what was drawn: a report that points at missing PNGs reads as a broken run.
  if (!ctx.plots_available) doc.p("No plots: " + ctx.plots_note + " (the data are in data/*.csv).");
  else
    for (const auto& ps : d.plots) doc.img(series_file_stem(ps.name) + ".png");
  doc.h2("Time");
  const auto& tm = d.timing;
  doc.p("Total " + g(tm.total_s, 3) + " s on " + std::to_string(ctx.ranks) + " rank(s), " +
        std::to_string(tm.threads) + " simulation slot(s): order analysis " +
        g(tm.analysis_s, 3) + " s, baseline + fidelity " + g(tm.baseline_s, 3) + " s, nuisance " + g(tm.nuisance_s, 3) +
        " s, locate " + g(tm.locate_s, 3) + " s, screening " + g(tm.screening_s, 3) + " s, candidates " + g(tm.candidates_s, 3) + " s, phase variants " + g(tm.phase_s, 3) + " s, plot data " +
        g(tm.report_s, 3) + " s; " + std::to_string(tm.simulations) +
        " simulations (" + g(tm.simulate_s, 3) + " s summed over threads).");
}

Doc build(const dg::Diagnosis& d, const ReportContext& ctx) {
  Doc doc;
  add_header(doc, d, ctx);
  add_kinematics(doc, d);
  add_residual(doc, d);
  add_nuisance(doc, d);
  add_location(doc, d);
  add_screening_and_candidates(doc, d);
  add_plots_and_time(doc, d, ctx);
  return doc;
}

std::string to_markdown(const Doc& doc) {
  std::ostringstream o;
  for (const auto& [kind, text] : doc.blocks) {
    if (kind == "h1") o << "# " << text << "\n\n";
    else if (kind == "h2") o << "## " << text << "\n\n";
    else if (kind == "p") o << text << "\n\n";
    else if (kind == "pre") o << "```\n" << text << "\n```\n\n";
    else if (kind == "img") o << "![" << text << "](" << text << ")\n\n";
    else o << text << "\n";
  }
  return o.str();
}

std::string inline_md(const std::string& s) {
  // **bold** and `code` only.
  std::string e = html_escape(s), o;
  bool bold = false, code = false;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (e[i] == '*' && i + 1 < e.size() && e[i + 1] == '*') {
      o += bold ? "</b>" : "<b>";
      bold = !bold;
      ++i;
    } else if (e[i] == '`') {
      o += code ? "</code>" : "<code>";
      code = !code;
    } else {
      o += e[i];
    }
  }
  return o;
}

std::string to_html(const Doc& doc) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>planetwear diagnose</title>\n"
       "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;}table{border-collapse:collapse;"
       "margin:1em 0;}td,th{border:1px solid #bbb;padding:3px 6px;font-size:90%;}img{max-width:100%;}"
       "pre{background:#f4f4f4;padding:8px;white-space:pre-wrap;}</style></head><body>\n";
  for (const auto& [kind, text] : doc.blocks) {
    if (kind == "h1") o << "<h1>" << html_escape(text) << "</h1>\n";
    else if (kind == "h2") o << "<h2>" << html_escape(text) << "</h2>\n";
    else if (kind == "p") o << "<p>" << inline_md(text) << "</p>\n";
    else if (kind == "pre") o << "<pre>" << html_escape(text) << "</pre>\n";
    else if (kind == "img") o << "<p><img src=\"" << html_escape(text) << "\" alt=\"" << html_escape(text) << "\"></p>\n";
    else {
      std::istringstream in(text);
      std::string line;
      int row = 0;
      o << "<table>\n";
      while (std::getline(in, line)) {
        if (line.rfind("|---", 0) == 0) continue;
        o << "<tr>";
        std::size_t pos = 1;
        while (pos < line.size()) {
          const std::size_t next = line.find(" |", pos);
          if (next == std::string::npos) break;
          std::string cell = line.substr(pos, next - pos);
          if (!cell.empty() && cell.front() == ' ') cell.erase(0, 1);
          o << (row == 0 ? "<th>" : "<td>") << inline_md(cell) << (row == 0 ? "</th>" : "</td>");
          pos = next + 2;
        }
        o << "</tr>\n";
        ++row;
      }
      o << "</table>\n";
    }
  }
  o << "</body></html>\n";
  return o.str();
}

} // namespace

std::string series_file_stem(const std::string& name) {
  std::string s = name;
  for (char& c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) c = '_';
  return s;
}

void write_diagnosis_documents(const std::filesystem::path& dir, const dg::Diagnosis& d, const ReportContext& ctx) {
  const Doc doc = build(d, ctx);
  write_text_atomically(dir / "report.md", to_markdown(doc));
  write_text_atomically(dir / "report.html", to_html(doc));
}

namespace {

/// data/<series>.csv for every plot series.
void write_plot_data(const std::filesystem::path& data_dir, const dg::Diagnosis& d) {
  for (const auto& ps : d.plots) {
    std::ostringstream o;
    o.precision(10);
    o << "# " << ps.name << "; x: " << ps.x_label << "; values: " << ps.y_label << "\n";
    o << "x";
    for (const auto& [name, v] : ps.columns) o << "," << name;
    o << "\n";
    for (std::size_t i = 0; i < ps.x.size(); ++i) {
      o << ps.x[i];
      for (const auto& [name, v] : ps.columns) o << "," << v[i];
      o << "\n";
    }
    write_text_atomically(data_dir / (series_file_stem(ps.name) + ".csv"), o.str());
  }
}

/// Location::planet_pattern (planet_pattern.hpp): null where the split does not apply.
json planet_pattern_json(const dg::PlanetPattern& p) {
  if (!p.applies) return nullptr;
  json orders = json::array();
  for (const dg::PatternOrderExcess& o : p.orders)
    orders.push_back({{"order", o.order}, {"excess", num(o.excess)}, {"cells", o.cells}, {"z", num(o.z)},
                      {"mesh_harmonics", o.harmonics}});
  return {{"orders", orders}, {"significance_z", num(p.significance_z)}};
}

/// report.json's "location": families, lines, rotations.
json location_json(const dg::Diagnosis& d) {
  json fam = json::array();
  for (const auto& f : d.location.families)
    fam.push_back({{"family", dg::to_string(f.family)}, {"z", num(f.z)}, {"share", num(f.share)},
                   {"cells", f.cells}, {"frequency_Hz", f.frequency_Hz}, {"carrier_orders", f.carrier_orders},
                   {"strongest_channel", f.strongest_channel}, {"meaning", f.meaning}});
  json lines = json::array();
  for (const auto& l : d.location.lines)
    lines.push_back({{"order", l.order}, {"frequency_Hz", l.frequency_Hz}, {"channel", l.channel},
                     {"chi2", l.chi2}, {"recording_amplitude", l.recording_amplitude},
                     {"model_amplitude", l.model_amplitude}, {"labels", l.labels}});
  json rot = json::array();
  for (const auto& r : d.location.rotations)
    rot.push_back({{"component", dg::to_string(r.component)}, {"channel", r.channel},
                   {"period_mesh_cycles", r.period_mesh_cycles}, {"averages", r.averages},
                   {"peak_angle_rad", r.peak_angle_rad}, {"peak_to_mean", r.peak_to_mean},
                   {"reference", r.reference}, {"tooth", r.tooth}, {"tooth_note", r.tooth_note}});
  return {{"families", fam}, {"significance_z", d.location.significance_z}, {"lines", lines},
                   {"screened_family", d.location.screened_family >= 0
                                           ? json(dg::to_string(static_cast<dg::Component>(d.location.screened_family)))
                                           : json(nullptr)},
                   {"screened_candidate", d.location.screened_candidate},
                   {"rotations", rot}, {"input_orders", d.location.input_orders},
                   {"planet_pattern", planet_pattern_json(d.location.planet_pattern)}};
}

/// report.json "finding_class": the class a class finding named (null otherwise).
json finding_class_json(const dg::Diagnosis& d) {
  if (d.winner != 0 || d.lead.named_class.empty()) return nullptr;
  json size = json::array();
  for (std::size_t i = 0; i < d.lead.class_size.size(); ++i) {
    const auto& [name, value] = d.lead.class_size[i];
    json e = {{"name", name}, {"value", num(value)}};
    if (i < d.lead.class_size_range.size())
      e["model_form_range"] = {num(d.lead.class_size_range[i].first), num(d.lead.class_size_range[i].second)};
    size.push_back(e);
  }
  return {{"name", d.lead.named_class}, {"members", d.lead.class_members}, {"posterior", num(d.lead.class_posterior)},
          {"covers", d.lead.class_covers}, {"size", size}, {"size_unit", d.lead.class_size_unit}};
}

/// report.json's "noise": per channel the noise per bin, whether coloured, the halves' dispersion
/// and the lines found at no gear order (reported; V does not carry them, docs/diagnose.md §2).
/// Diagnosis::excess_by_channel: each channel's share of the nuisance fit's held-out excess.
json excess_by_channel_json(const dg::Diagnosis& d) {
  json exc = json::array();
  for (const auto& e : d.excess_by_channel)
    exc.push_back({{"channel", e.channel}, {"excess", num(e.excess)}, {"share", num(e.share)}});
  return exc;
}

/// Diagnosis::coverage_gap (line_coverage.hpp): null when no calibration or baseline tested any
/// line, else the uncovered share of the located lines' excess, those lines and the spans tested.
json coverage_gap_json(const dg::CoverageGap& gap) {
  if (!gap.known) return nullptr;
  json lines = json::array(), spans = json::array();
  for (const dg::UncoveredLine& l : gap.lines)
    lines.push_back({{"channel", l.channel}, {"frequency_Hz", l.frequency_Hz}, {"carrier_order", l.order},
                     {"excess", num(l.excess)}, {"covering_speed_rpm", num(l.covering_speed_rpm)}});
  for (const dg::LineCoverage& c : gap.coverage)
    spans.push_back({{"quantity", dg::to_string(c.quantity)}, {"lowest_Hz", c.lowest_Hz},
                     {"lowest_speed_rpm", c.lowest_speed_rpm}, {"highest_Hz", c.highest_Hz},
                     {"highest_speed_rpm", c.highest_speed_rpm}, {"lines", c.lines}});
  return {{"share", num(gap.share)}, {"lines", lines}, {"tested", spans}};
}

json noise_json(const dg::Diagnosis& d) {
  json noise = json::object();
  for (std::size_t c = 0; c < d.channels.size(); ++c) {
    noise[d.channels[c]] = {{"rms_per_bin", d.noise_std[c]}, {"coloured", static_cast<bool>(d.noise_coloured[c])},
                            {"dispersion_from_halves", d.noise_dispersion[c]}};
    json alien = json::array();
    if (c < d.alien_lines.size())
      for (const auto& a : d.alien_lines[c]) alien.push_back({{"carrier_order", a.order}, {"amplitude", a.amplitude},
                          {"in_other_channels", a.in_other_channels}, {"in_baseline", a.in_baseline}});
    noise[d.channels[c]]["lines_at_no_gear_order"] = alien;
  }
  return noise;
}

/// The best candidate of an unexplained or named verdict and its tests (null without one).
json lead_json(const dg::Diagnosis& d) {
  if (d.lead.candidate != 0) return nullptr;
  const dg::CandidateResult& l = d.candidates.front();
  return json{{"name", l.name}, {"variant", l.variant}, {"named", d.winner == 0}, {"counts", d.lead.counts},
               {"held_out_chi2", num(d.lead.held_out_chi2)}, {"bound_held_out", num(d.lead.bound_held_out)},
               {"bound_held_out_folded", num(d.lead.bound_folded)},
               {"replicate_chi2", num(d.lead.replicate_chi2)}, {"within_bound", d.lead.within_bound}, {"explained_fraction", num(d.lead.explained_fraction)},
               {"at_bound", d.lead.at_bound}, {"silent_channels", d.lead.silent_channels}, {"posterior", num(d.lead.posterior)},
               {"class_posterior", num(d.lead.class_posterior)}, {"rival", d.lead.rival},
               {"failed", d.lead.failed},
               // The share of the speed channels' mesh-harmonic excess at planet pattern orders
               // k >= 1 that a lead acting on every planet alike cannot make (0: no conflict).
               {"planet_pattern_conflict_share", dg::planet_pattern_conflict_share(d)}};
}

} // namespace

void write_diagnosis_report(const std::filesystem::path& dir, const dg::Diagnosis& d, const ReportContext& ctx) {
  std::error_code ec;
  std::filesystem::create_directories(dir / "data", ec);
  if (ec) throw IoError("cannot create '" + (dir / "data").string() + "': " + ec.message());
  write_plot_data(dir / "data", d);
  json j;
  j["tool"] = ctx.version;
  j["recording"] = ctx.recording_path;
  j["config"] = ctx.config_path;
  j["calibration"] = ctx.calibration_path;
  j["calibration_at_bound"] = ctx.calibration_at_bound;
  j["baseline"] = ctx.baseline_path;
  j["baseline_at_bound"] = ctx.baseline_at_bound;
  j["calibration_reference"] = ctx.calibration_reference;
  j["baseline_operating_point"] = ctx.baseline_operating_point;
  j["command_line"] = ctx.command_line;
  j["verdict"] = dg::to_string(d.verdict);
  j["summary"] = d.summary;
  // A class finding (src/diagnose/verdict.hpp) names the class; the lead that was fitted is "lead".
  j["missing_physics"] = d.winner != 0                  ? json(nullptr)
                         : !d.lead.named_class.empty() ? json(d.lead.named_class)
                                                       : json(d.candidates.front().name);
  j["finding_class"] = finding_class_json(d);
  j["variant"] = d.winner == 0 ? json(d.candidates.front().variant) : json(nullptr);
  json moved = json::array();
  for (const auto& p : d.nuisance.parameters)
    if (p.moved) moved.push_back(p.name);
  j["recalibrated_nuisance"] = moved;
  // The candidate from whose fitted nuisance values the nuisance-only model was refitted, when that
  // fitted better (docs/diagnose.md §5 step 10); null when step 3's fit stood.
  j["nuisance_refitted_from"] = d.nuisance_refitted_from.empty() ? json(nullptr) : json(d.nuisance_refitted_from);
  // What the nuisance model's mesh stiffness follows (docs/diagnose.md §5 step 4b).
  j["nuisance_mesh_phase"] = model::mesh_phase_name(d.nuisance_mesh_phase);
  j["nuisance_housing_path"] = model::housing_path_name(d.nuisance_housing_path);
  j["decision_rule"] = d.rule;
  j["lead"] = lead_json(d);
  // Differential, after a "no missing physics": each single change since the baseline tested on
  // the baseline's own terms (docs/diagnose.md section 6b item 7); empty when the check did not run.
  json changes = json::array();
  for (const dg::BaselineChange& c : d.baseline_changes)
    changes.push_back({{"name", c.name}, {"parameter", c.parameter}, {"ratio", num(c.ratio)},
                       {"ratio_std_error", num(c.ratio_std_error)},
                       {"ln_ratio_healthy_scatter", num(c.ln_ratio_healthy_scatter)},
                       {"ln_ratio_threshold", num(c.ln_ratio_threshold)},
                       {"chi2_fit", {{"unchanged", num(c.chi2_fit_unchanged)}, {"fitted", num(c.chi2_fit)}}},
                       {"chi2_held_out", {{"unchanged", num(c.chi2_held_unchanged)}, {"fitted", num(c.chi2_held)}}},
                       {"own_model_held_out_chi2", num(c.own_held_out_chi2)}, {"own_model_bound", num(c.own_bound)},
                       {"own_model_replicate_chi2", num(c.own_replicate_chi2)},
                       {"at_edge", c.at_edge}, {"explains", c.explains}, {"passes", c.passes},
                       {"posterior", num(c.posterior)}});
  j["changes_since_baseline"] = changes;
  // A "no missing physics" whose nuisance fit moved a level that no reference at this operating
  // point tested (docs/diagnose.md section 6b item 7): what the verdict does not rule out.
  json untested = json::array();
  for (const dg::UntestedLevel& l : d.untested_levels)
    untested.push_back({{"parameter", l.parameter}, {"value", num(l.value)}, {"initial", num(l.initial)},
                        {"at_bound", l.at_bound}});
  j["levels_not_tested"] = untested;
  j["explained_fraction"] = num(d.lead.explained_fraction);
  j["at_bound"] = d.lead.at_bound;
  j["excess_by_channel"] = excess_by_channel_json(d);
  j["coverage_gap"] = coverage_gap_json(d.coverage_gap);
  j["speed"] = {{"input_rpm", d.speed.input_rpm}, {"relative_std", d.speed.relative_std}, {"source", d.speed.source},
                {"model_input_rpm", d.model_speed_rpm}};
  j["angle_source"] = d.angle_source;
  const auto& k = d.kinematics;
  j["kinematics"] = {{"sun_Hz", k.sun_Hz}, {"carrier_Hz", k.carrier_Hz}, {"sun_relative_Hz", k.sun_relative_Hz},
                     {"planet_relative_Hz", k.planet_relative_Hz}, {"mesh_Hz", k.mesh_Hz}};
  j["noise"] = noise_json(d);
  auto win = [](const dg::OrderWindow& w) {
    return json{{"first_sample", w.first_sample}, {"last_sample", w.last_sample}, {"t_begin_s", w.t_begin_s},
                {"t_end_s", w.t_end_s}, {"carrier_angle_begin_rad", w.angle_begin_rad}};
  };
  j["halves"] = {{"fit", win(d.fit_window)}, {"held_out", win(d.held_out_window)},
                 {"carrier_revolutions_each", d.revolutions}};
  if (d.window_mesh_cycles > 0) {
    j["halves"]["mesh_cycles_each"] = d.window_mesh_cycles;
    j["halves"]["window_carrier_revolutions"] = d.window_revolutions;
    j["halves"]["recording_carrier_revolutions"] = d.recording_revolutions;
  }
  j["unresolved"] = {{"families", d.unresolved_families},
                     {"candidates", d.unresolved_candidates},
                     {"channels", d.dropped_channels}};
  j["features"] = {{"cells_per_channel", d.cells}, {"total", d.features}, {"max_carrier_order", d.max_order},
                   {"max_frequency_Hz", d.max_frequency_Hz}, {"mesh_harmonics", d.mesh_harmonics},
                   {"non_stationary", d.nonstationary_features}, {"fidelity_directions", d.fidelity}};
  j["noise_bound"] = {{"fit", d.bound_fit},
                      {"held_out", d.bound_held_out},
                      {"fit_linear", d.bound_fit_linear},
                      {"held_out_linear", d.bound_held_out_linear}};
  j["residual"] = {{"nominal", {{"fit", score_json(d.nominal_fit, d.channels)},
                                {"held_out", score_json(d.nominal_held_out, d.channels)}}},
                   {"nuisance_fitted", {{"fit", score_json(d.nuisance.fit, d.channels)},
                                        {"held_out", score_json(d.nuisance.held_out, d.channels)}}}};
  if (d.winner == 0)
    j["residual"]["final"] = {{"fit", score_json(d.candidates.front().fit, d.channels)},
                              {"held_out", score_json(d.candidates.front().held_out, d.channels)}};
  j["nuisance"] = candidate_json(d.nuisance, d.channels);
  if (d.winner == 0) {
    json ps = json::array();
    for (const auto& p : d.candidates.front().parameters) {
      json pj = {{"name", p.name}, {"value", num(p.value)}, {"std_error", num(p.std_error)},
                 {"model_form_std", num(p.model_form_std)},
                 {"model_form_range", {num(p.model_form_lower), num(p.model_form_upper)}},
               {"level_spread_std", num(p.level_spread_std)}, {"level_spread_of", p.level_spread_of}, {"unit", p.unit},
                 {"nuisance", p.nuisance}};
      if (p.saturates) {
        pj["saturates"] = true;
        pj["lower_limit"] = num(p.lower_limit);
      }
      if (p.transfer) pj["transfer"] = true;
      if (!p.size_conditional_on.empty()) pj["size_conditional_on"] = p.size_conditional_on;
      ps.push_back(std::move(pj));
    }
    j["fitted_parameters"] = ps;
  }
  j["final_overrides"] = d.final_overrides;
  if (d.located) j["location"] = location_json(d);
  json cands = json::array();
  for (const auto& c : d.candidates) cands.push_back(candidate_json(c, d.channels));
  j["candidates"] = cands;
  json scr = json::array();
  for (const auto& sr : d.screening)
    scr.push_back({{"name", sr.name}, {"variant", sr.variant}, {"predicted_improvement", num(sr.predicted_improvement)},
                   {"failed", sr.failed}, {"fitted", sr.fitted}, {"at_transfer_values", sr.at_transfer_values}});
  j["screening"] = scr;
  const auto& tm = d.timing;
  j["timing"] = {{"total_s", tm.total_s}, {"analysis_s", tm.analysis_s}, {"baseline_s", tm.baseline_s},
                 {"nuisance_s", tm.nuisance_s}, {"locate_s", tm.locate_s}, {"screening_s", tm.screening_s}, {"candidates_s", tm.candidates_s},
                 {"phase_s", tm.phase_s}, {"report_s", tm.report_s}, {"simulate_s_summed", tm.simulate_s},
                 {"simulations", tm.simulations}, {"threads", tm.threads}, {"ranks", ctx.ranks}};
  json plots = json::array();
  for (const auto& ps : d.plots) {
    json cols = json::array();
    for (const auto& [name, v] : ps.columns) cols.push_back(name);
    plots.push_back({{"name", ps.name}, {"kind", ps.kind}, {"csv", "data/" + series_file_stem(ps.name) + ".csv"},
                     {"png", series_file_stem(ps.name) + ".png"}, {"x_label", ps.x_label},
                     {"y_label", ps.y_label}, {"columns", cols}});
  }
  j["plots"] = plots;
  (void)finite_or_null;
  write_text_atomically(dir / "report.json", j.dump(2) + "\n");
  write_diagnosis_documents(dir, d, ctx);
}

} // namespace pw::io
