#include "io/diagnosis_report.hpp"

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

void write_text(const std::filesystem::path& path, const std::string& text) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.temp_path(), std::ios::binary);
    if (!f) throw IoError("cannot write '" + out.temp_path().string() + "'");
    f << text;
    f.close();
    if (!f) throw IoError("cannot write '" + out.temp_path().string() + "'");
  }
  out.commit();
}

double finite_or_null(double v) { return std::isfinite(v) ? v : 0.0; }

json num(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json score_json(const dg::WindowScore& s, const std::vector<std::string>& channels) {
  json j;
  j["chi2"] = num(s.chi2);
  j["dof"] = s.dof;
  j["chi2_per_dof"] = num(s.dof > 0 ? s.chi2 / s.dof : 0.0);
  json per = json::object();
  for (std::size_t c = 0; c < channels.size() && c < s.chi2_per_channel.size(); ++c)
    per[channels[c]] = {{"chi2", num(s.chi2_per_channel[c])}, {"dof", s.dof_per_channel[c]}};
  j["channels"] = per;
  return j;
}

json candidate_json(const dg::CandidateResult& r, const std::vector<std::string>& channels) {
  json j;
  j["name"] = r.name;
  j["physics"] = r.physics;
  j["variant"] = r.variant;
  j["families"] = r.families;
  j["evidence_z"] = num(r.evidence_z);
  json ps = json::array();
  for (const auto& p : r.parameters)
    ps.push_back({{"name", p.name}, {"unit", p.unit}, {"value", num(p.value)}, {"std_error", num(p.std_error)},
                  {"lower", num(p.lower)}, {"upper", num(p.upper)}, {"initial", num(p.initial)},
                  {"at_bound", p.at_bound}, {"nuisance", p.nuisance}});
  j["parameters"] = ps;
  j["overrides"] = r.overrides;
  j["fit_window"] = score_json(r.fit, channels);
  j["held_out_window"] = score_json(r.held_out, channels);
  j["delta_chi2_fit"] = num(r.delta_chi2_fit);
  j["delta_chi2_held_out"] = num(r.delta_chi2_held_out);
  j["likelihood_ratio_threshold"] = num(r.lr_threshold);
  j["aic"] = num(r.aic);
  j["bic"] = num(r.bic);
  j["significant"] = r.significant;
  j["holds_on_held_out"] = r.holds;
  j["simulations"] = r.simulations;
  j["lm"] = r.lm_message;
  j["reason"] = r.reason;
  return j;
}

std::string g(double v, int prec = 4) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

std::string param_cell(const dg::FittedParameter& p) {
  std::string s = g(p.value) + " ± " + (std::isfinite(p.std_error) ? g(p.std_error, 2) : std::string("n/a"));
  if (p.unit != "1" && !p.unit.empty()) s += " " + p.unit;
  if (p.at_bound) s += " (at bound)";
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

Doc build(const dg::Diagnosis& d, const ReportContext& ctx) {
  Doc doc;
  doc.h1("planetwear diagnose");
  doc.p("**Finding:** " + d.summary);
  doc.p("Verdict: `" + std::string(dg::to_string(d.verdict)) + "`. Recording `" + ctx.recording_path +
        "`, configuration `" + (ctx.config_path.empty() ? "(seed defaults)" : ctx.config_path) + "`, " + ctx.version +
        ".");
  const auto& k = d.kinematics;
  doc.h2("Kinematics");
  doc.table({{"f_s (sun)", "f_c (carrier)", "f_sr = f_s - f_c", "f_pr = f_m/Zp", "f_m (mesh)"},
             {g(k.sun_Hz) + " Hz", g(k.carrier_Hz) + " Hz", g(k.sun_relative_Hz) + " Hz",
              g(k.planet_relative_Hz) + " Hz", g(k.mesh_Hz) + " Hz"}});
  doc.p("Fit window: samples " + std::to_string(d.fit_window.begin) + "+" + std::to_string(d.fit_window.count) +
        " (t = " + g(d.fit_window.t_begin_s, 6) + " .. " + g(d.fit_window.t_end_s, 6) + " s); held-out window: t = " +
        g(d.held_out_window.t_begin_s, 6) + " .. " + g(d.held_out_window.t_end_s, 6) +
        " s; each one carrier revolution. Bins " + std::to_string(d.fit_window.k_min) + ".." +
        std::to_string(d.fit_window.k_max) + " (up to " + g(d.fit_window.k_max / (d.fit_window.t_end_s - d.fit_window.t_begin_s)) +
        " Hz).");

  doc.h2("Residual before and after");
  std::vector<std::vector<std::string>> rows{{"model", "chi2 fit window", "chi2 held out", "noise bound (fit / held out)"}};
  rows.push_back({"nominal (as configured)", g(d.nominal_fit.chi2, 6), g(d.nominal_held_out.chi2, 6),
                  g(d.bound_fit, 5) + " / " + g(d.bound_held_out, 5)});
  rows.push_back({"nuisance fitted", g(d.nuisance.fit.chi2, 6), g(d.nuisance.held_out.chi2, 6), ""});
  if (d.winner == 0)
    rows.push_back({"with " + d.candidates.front().name, g(d.candidates.front().fit.chi2, 6),
                    g(d.candidates.front().held_out.chi2, 6), ""});
  doc.table(rows);
  {
    std::vector<std::vector<std::string>> pc{{"channel", "noise std", "chi2/dof nominal (fit, held out)",
                                              "chi2/dof final (fit, held out)"}};
    const dg::CandidateResult& fin = d.winner == 0 ? d.candidates.front() : d.nuisance;
    for (std::size_t c = 0; c < d.channels.size(); ++c) {
      auto r = [&](const dg::WindowScore& s) {
        return c < s.chi2_per_channel.size() ? g(s.chi2_per_channel[c] / s.dof_per_channel[c], 4) : std::string("");
      };
      pc.push_back({d.channels[c], g(std::sqrt(d.noise[c].variance), 3), r(d.nominal_fit) + ", " + r(d.nominal_held_out),
                    r(fin.fit) + ", " + r(fin.held_out)});
    }
    doc.table(pc);
  }
  if (!d.tsa_names.empty()) {
    std::vector<std::vector<std::string>> t{{"synchronous average (whole recording)", "residual RMS before", "after"}};
    for (std::size_t i = 0; i < d.tsa_names.size(); ++i)
      t.push_back({d.tsa_names[i], g(d.tsa_rms_before[i], 3), g(d.tsa_rms_after[i], 3)});
    doc.table(t);
  }
  doc.p("Decision rule: " + d.rule);

  doc.h2("Nuisance parameters (fitted first)");
  {
    std::vector<std::vector<std::string>> t{{"parameter", "fitted", "start"}};
    for (const auto& p : d.nuisance.parameters) t.push_back({p.name, param_cell(p), g(p.initial)});
    doc.table(t);
  }

  if (d.located) {
    doc.h2("Where the residual lives");
    std::vector<std::vector<std::string>> t{{"rank", "family", "z", "strongest channel", "meaning"}};
    int rank = 1;
    for (const auto& f : d.location.families)
      t.push_back({std::to_string(rank++), dg::to_string(f.family), g(f.z, 3), f.strongest_channel, f.meaning});
    doc.table(t);
    doc.p("A family counts as located above z = " + g(d.location.significance_z, 3) + ".");
    std::vector<std::vector<std::string>> l{{"frequency [Hz]", "channel", "excess [noise units]", "kinematic lines"}};
    for (const auto& line : d.location.lines) {
      std::string lab;
      for (const auto& s : line.labels) lab += (lab.empty() ? "" : "; ") + s;
      l.push_back({g(line.frequency_Hz, 6), line.channel, g(line.excess, 3), lab});
    }
    doc.table(l);
    std::vector<std::vector<std::string>> r{{"rotation", "channel", "revolutions averaged", "peak at mesh cycle",
                                             "angle [rad]", "peak/mean", "nearest tooth"}};
    for (const auto& re : d.location.rotations)
      r.push_back({dg::to_string(re.component), re.channel, std::to_string(re.averages), g(re.peak_mesh_cycle, 4),
                   g(re.peak_angle_rad, 4), g(re.peak_to_mean, 3),
                   (re.component == dg::Component::Sun ? "sun " : re.component == dg::Component::Planet
                                                                      ? "planet " + std::to_string(re.planet) + " "
                                                                      : "ring ") +
                       std::to_string(re.tooth)});
    doc.table(r);
    if (!d.location.input_orders.empty()) {
      std::string s;
      for (double o : d.location.input_orders) s += (s.empty() ? "" : ", ") + g(o);
      doc.p("Strongest input-shaft orders in the residual (low-frequency speed fluctuation): " + s + ".");
    }
  }

  if (!d.candidates.empty()) {
    doc.h2("Candidates");
    std::vector<std::vector<std::string>> t{{"rank", "candidate", "variant", "parameters", "Δchi2 fit", "Δchi2 held out",
                                             "BIC", "why"}};
    int rank = 1;
    for (const auto& c : d.candidates) {
      std::string ps;
      for (const auto& p : c.parameters)
        if (!p.nuisance) ps += (ps.empty() ? "" : "; ") + p.name + " = " + param_cell(p);
      t.push_back({std::to_string(rank++), c.name, c.variant, ps, g(c.delta_chi2_fit, 5), g(c.delta_chi2_held_out, 5),
                   g(c.bic, 6), c.reason});
    }
    doc.table(t);
    if (d.winner == 0) {
      doc.p("Fitted model, reproducible with `planetwear simulate`:");
      std::string s;
      for (const auto& o : d.final_overrides) s += "--set '" + o + "' ";
      doc.pre(s);
    }
  }

  doc.h2("Plots");
  if (!ctx.plots_available) doc.p("No plots: " + ctx.plots_note + " (the data are in data/*.csv).");
  for (const auto& ps : d.plots) doc.img(series_file_stem(ps.name) + ".png");
  doc.h2("Time");
  doc.p("Total " + g(d.timing.total_s, 3) + " s on " + std::to_string(d.timing.threads) + " thread(s): " +
        std::to_string(d.timing.simulations) + " simulations (" + g(d.timing.simulate_s, 3) +
        " s summed over threads), features " + g(d.timing.compare_s, 3) + " s, locate " + g(d.timing.locate_s, 3) +
        " s, fitting overhead " + g(d.timing.fit_overhead_s, 3) + " s.");
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
  write_text(dir / "report.md", to_markdown(doc));
  write_text(dir / "report.html", to_html(doc));
}

void write_diagnosis_report(const std::filesystem::path& dir, const dg::Diagnosis& d, const ReportContext& ctx) {
  std::error_code ec;
  std::filesystem::create_directories(dir / "data", ec);
  if (ec) throw IoError("cannot create '" + (dir / "data").string() + "': " + ec.message());
  // Plot data.
  for (const auto& ps : d.plots) {
    std::ostringstream o;
    o.precision(10);
    o << "# " << ps.name << "; x in " << ps.x_unit << ", values in " << ps.y_unit << "\n";
    o << "x,recording,before,after\n";
    for (std::size_t i = 0; i < ps.x.size(); ++i)
      o << ps.x[i] << "," << ps.recording[i] << "," << ps.before[i] << "," << ps.after[i] << "\n";
    write_text(dir / "data" / (series_file_stem(ps.name) + ".csv"), o.str());
  }
  // JSON.
  json j;
  j["tool"] = ctx.version;
  j["recording"] = ctx.recording_path;
  j["config"] = ctx.config_path;
  j["command_line"] = ctx.command_line;
  j["verdict"] = dg::to_string(d.verdict);
  j["summary"] = d.summary;
  j["missing_physics"] = d.winner == 0 ? json(d.candidates.front().name) : json(nullptr);
  j["variant"] = d.winner == 0 ? json(d.candidates.front().variant) : json(nullptr);
  j["decision_rule"] = d.rule;
  const auto& k = d.kinematics;
  j["kinematics"] = {{"sun_Hz", k.sun_Hz}, {"carrier_Hz", k.carrier_Hz}, {"sun_relative_Hz", k.sun_relative_Hz},
                     {"planet_relative_Hz", k.planet_relative_Hz}, {"mesh_Hz", k.mesh_Hz}};
  json noise = json::object();
  for (std::size_t c = 0; c < d.channels.size(); ++c)
    noise[d.channels[c]] = {{"std", std::sqrt(d.noise[c].variance)},
                            {"relative_uncertainty_of_variance", d.noise[c].relative_uncertainty}};
  j["noise"] = noise;
  auto win = [](const dg::AnalysisWindow& w) {
    return json{{"first_sample", w.begin}, {"samples", w.count}, {"t_begin_s", w.t_begin_s}, {"t_end_s", w.t_end_s},
                {"bins", {w.k_min, w.k_max}}};
  };
  j["windows"] = {{"fit", win(d.fit_window)}, {"held_out", win(d.held_out_window)}};
  j["noise_bound"] = {{"fit", d.bound_fit}, {"held_out", d.bound_held_out}};
  j["residual"] = {{"nominal", {{"fit", score_json(d.nominal_fit, d.channels)},
                                {"held_out", score_json(d.nominal_held_out, d.channels)}}},
                   {"nuisance_fitted", {{"fit", score_json(d.nuisance.fit, d.channels)},
                                        {"held_out", score_json(d.nuisance.held_out, d.channels)}}}};
  if (d.winner == 0)
    j["residual"]["final"] = {{"fit", score_json(d.candidates.front().fit, d.channels)},
                              {"held_out", score_json(d.candidates.front().held_out, d.channels)}};
  json tsa = json::array();
  for (std::size_t i = 0; i < d.tsa_names.size(); ++i)
    tsa.push_back({{"name", d.tsa_names[i]}, {"rms_before", d.tsa_rms_before[i]}, {"rms_after", d.tsa_rms_after[i]}});
  j["residual"]["synchronous_average"] = tsa;
  j["nuisance"] = candidate_json(d.nuisance, d.channels);
  if (d.winner == 0) {
    json ps = json::array();
    for (const auto& p : d.candidates.front().parameters)
      ps.push_back({{"name", p.name}, {"value", num(p.value)}, {"std_error", num(p.std_error)}, {"unit", p.unit},
                    {"nuisance", p.nuisance}});
    j["fitted_parameters"] = ps;
  }
  j["final_overrides"] = d.final_overrides;
  if (d.located) {
    json fam = json::array();
    for (const auto& f : d.location.families)
      fam.push_back({{"family", dg::to_string(f.family)}, {"z", num(f.z)}, {"lines", f.lines},
                     {"strongest_channel", f.strongest_channel}, {"meaning", f.meaning}});
    json lines = json::array();
    for (const auto& l : d.location.lines)
      lines.push_back({{"frequency_Hz", l.frequency_Hz}, {"channel", l.channel}, {"excess", l.excess},
                       {"labels", l.labels}});
    json rot = json::array();
    for (const auto& r : d.location.rotations)
      rot.push_back({{"component", dg::to_string(r.component)}, {"channel", r.channel}, {"planet", r.planet},
                     {"averages", r.averages}, {"peak_mesh_cycle", r.peak_mesh_cycle},
                     {"peak_angle_rad", r.peak_angle_rad}, {"peak_to_mean", r.peak_to_mean}, {"tooth", r.tooth}});
    j["location"] = {{"families", fam}, {"significance_z", d.location.significance_z}, {"lines", lines},
                     {"rotations", rot}, {"input_orders", d.location.input_orders}};
  }
  json cands = json::array();
  for (const auto& c : d.candidates) cands.push_back(candidate_json(c, d.channels));
  j["candidates"] = cands;
  j["timing"] = {{"total_s", d.timing.total_s}, {"simulate_s_summed", d.timing.simulate_s},
                 {"simulations", d.timing.simulations}, {"features_s", d.timing.compare_s},
                 {"locate_s", d.timing.locate_s}, {"fit_overhead_s", d.timing.fit_overhead_s},
                 {"threads", d.timing.threads}};
  json plots = json::array();
  for (const auto& ps : d.plots)
    plots.push_back({{"name", ps.name}, {"csv", "data/" + series_file_stem(ps.name) + ".csv"},
                     {"png", series_file_stem(ps.name) + ".png"}, {"x_unit", ps.x_unit}, {"y_unit", ps.y_unit}});
  j["plots"] = plots;
  (void)finite_or_null;
  write_text(dir / "report.json", j.dump(2) + "\n");
  write_diagnosis_documents(dir, d, ctx);
}

} // namespace pw::io
