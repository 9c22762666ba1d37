#include "commands.hpp"
#include "engineering_summary.hpp"

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/candidate_listing.hpp"
#include "io/config_listing.hpp"
#include "io/config_toml.hpp"
#include "io/csv_writer.hpp"
#include "io/exit_code.hpp"
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"
#include "io/result_writer.hpp"
#include "model/simulation.hpp"
#include "wear/simulation.hpp"
#include "signal/spectrum.hpp"
#include "stiffness/iso6336.hpp"

#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>

namespace pw::app {
namespace {

model::SimulationConfig load(const CommonOptions& o, std::vector<std::string> extra = {}) {
  model::SimulationConfig c = o.config.empty() ? model::SimulationConfig{} : io::read_config(o.config);
  std::vector<std::string> all = o.assignments;
  all.insert(all.end(), extra.begin(), extra.end());
  io::apply_overrides(c, all);  // validates once
  return c;
}

/// Progress on stderr, at most every 0.5 s: phase, percent, elapsed, ETA.
class ProgressPrinter {
public:
  explicit ProgressPrinter(bool quiet) : quiet_(quiet), start_(clock::now()), last_(start_) {}
  void operator()(double f, const std::string& phase) {
    if (quiet_) return;
    const auto now = clock::now();
    if (f < 1.0 && now - last_ < std::chrono::milliseconds(500)) return;
    last_ = now;
    const double el = std::chrono::duration<double>(now - start_).count();
    const double eta = f > 1e-3 ? el * (1 - f) / f : 0.0;
    std::fprintf(stderr, "\r[%-9s] %5.1f %%  elapsed %7.1f s  ETA %7.1f s", phase.c_str(), 100 * f, el, eta);
    if (f >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }

private:
  using clock = std::chrono::steady_clock;
  bool quiet_;
  clock::time_point start_, last_;
};

/// Spectra of every mesh-line acceleration and deflection and of the
/// transmission error: Hann window, peak-amplitude scaling (docs/spectra.md).
std::vector<io::SpectrumRecord> spectra_of(const model::SimulationResult& r) {
  std::vector<const model::Channel*> wanted;
  for (const auto& ch : r.channels)
    if (ch.name.ends_with("/acceleration") || ch.name.ends_with("/deflection") || ch.name == "transmission_error")
      wanted.push_back(&ch);
  std::vector<std::span<const double>> signals;
  for (const model::Channel* ch : wanted) signals.emplace_back(ch->values);
  const std::vector<signal::Spectrum> s =
      signal::amplitude_spectra(signals, r.time_step_s, signal::Window::Hann);
  std::vector<io::SpectrumRecord> out;
  for (std::size_t i = 0; i < wanted.size(); ++i)
    out.push_back({wanted[i]->name, wanted[i]->unit, s[i].window, s[i].scaling, s[i].frequency_Hz, s[i].amplitude});
  return out;
}

/// A double as TOML text that parses back to the same value ("2e+05", "nan").
std::string toml_float(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::array<char, 64> buf{};
  const auto end = std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr;
  return std::string(buf.data(), end);
}

} // namespace

std::string version_string() { return std::string("planetwear ") + std::string(io::software_version()); }

int run_simulate(const SimulateOptions& o) {
  // Shortcut options are --set overrides applied after the user's own.
  std::vector<std::string> extra;
  if (o.speed_rpm) extra.push_back("operating.input_speed_rpm=" + toml_float(*o.speed_rpm));
  if (o.power_W) extra.push_back("operating.input_power_W=" + toml_float(*o.power_W));
  // Asking for wear on the command line means a positive count (the config
  // key's 0 means "no wear", which needs no option).
  if (o.mesh_cycles)
    require(*o.mesh_cycles > 0, "--mesh-cycles", "must be > 0 mesh cycles (omit it for no wear), got ",
            *o.mesh_cycles);
  if (o.mesh_cycles) extra.push_back("wear.mesh_cycles=" + toml_float(*o.mesh_cycles));
  if (o.kappa_m2_N) extra.push_back("wear.coefficient_m2_N=" + toml_float(*o.kappa_m2_N));
  const model::SimulationConfig config = load(o.common, extra);

  // Output names are checked before the (possibly long) run.
  io::AtomicOutput h5(o.output);
  if (!o.report.empty()) io::AtomicOutput check_report_directory(o.report);
  ProgressPrinter progress(o.common.quiet);
  using clock = std::chrono::steady_clock;
  auto seconds_since = [](clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); };
  const auto t0 = clock::now();
  for (const std::string& name : o.output_selection.channels)
    require(!name.empty(), "--channels", "an empty channel name (check for a doubled comma)");
  const model::SimulationResult result = wear::simulate(config, std::ref(progress), o.output_selection);
  const double t_sim = seconds_since(t0);
  const auto t1 = clock::now();
  const std::vector<io::SpectrumRecord> spectra = spectra_of(result);
  const double t_spectra = seconds_since(t1);
  const auto t2 = clock::now();
  {
    io::H5File f = io::H5File::create(h5.temp_path());
    io::write_simulation(f, config, result, spectra, {.compression_level = o.compression_level});
    f.close();
  }
  if (!o.csv.empty()) io::write_csv(o.csv, result);
  h5.commit();
  const double t_write = seconds_since(t2);
  if (!o.common.quiet) {
    const auto* fm = result.find_scalar("mesh_frequency");
    const auto* dt = result.find_scalar("time_step");
    std::fprintf(stderr,
                 "wrote %s: %zu samples x %zu channels every %.3g s (time step %.3g s), mesh frequency %.4g Hz, "
                 "wall time %.2f s (simulate %.2f s, spectra %.2f s, write %.2f s)\n",
                 o.output.c_str(), result.time_s.size(), result.channels.size(), result.time_step_s,
                 dt ? dt->value : 0.0, fm ? fm->value : 0.0, seconds_since(t0), t_sim, t_spectra, t_write);
    const model::Scalar* residual = result.find_scalar("periodicity_residual");
    if (!reached_steady_state(config, result))
      std::fprintf(stderr,
                   "warning: the warm-up did not reach a steady state (periodicity residual %.3g > "
                   "solver.periodicity_tolerance %.3g): the recording is of a transient\n",
                   residual ? residual->value : NAN, config.solver.periodicity_tolerance);
    const model::WearHistory& w = result.wear;
    if (!w.mesh_cycles.empty())
      std::fprintf(stderr, "wear: %zu updates to %.6g mesh cycles\n", w.mesh_cycles.size() - 1, w.mesh_cycles.back());
  }
  const std::string summary = engineering_summary(config, result, o.allowable_contact_stress_Pa);
  if (!o.common.quiet) std::fputs(summary.c_str(), stdout);
  if (!o.report.empty()) io::write_text_atomically(o.report, summary);
  if (!result.wear.stop_reason.empty()) {
    // Kept what was computed (written above); tell scripts it is incomplete.
    std::fprintf(stderr, "%s%s; results up to then are in %s\n", io::kErrorPrefix, result.wear.stop_reason.c_str(),
                 o.output.c_str());
    return io::to_int(io::ExitCode::Incomplete);
  }
  return io::to_int(io::ExitCode::Ok);
}

int run_stiffness(const StiffnessOptions& o) {
  const model::SimulationConfig config = load(o.common);
  const model::PreparedStage stage = model::prepare(config);
  std::printf("%-34s %14s %14s\n", "quantity [unit]", "sun-planet", "planet-ring");
  const auto sc = model::stiffness_scalars(stage);
  const std::size_t per = sc.size() / 2;
  for (std::size_t i = 0; i < per; ++i) {
    const std::string label = sc[i].name.substr(sc[i].name.find('/') + 1) + " [" + sc[i].unit + "]";
    std::printf("%-34s %14.5g %14.5g\n", label.c_str(), sc[i].value, sc[i + per].value);
  }
  const auto& st = config.stage;
  const auto iso_sp = stiffness::iso6336_stiffness(st.sun, st.planet, stage.geometry.sun_planet.contact_ratio);
  const auto iso_pr = stiffness::iso6336_stiffness(st.planet, st.ring, stage.geometry.planet_ring.contact_ratio);
  std::printf("%-34s %14.5g %14.5g\n", "ISO 6336-1 c' b [N/m]", iso_sp.c_prime_N_m, iso_pr.c_prime_N_m);
  std::printf("%-34s %14.5g %14.5g\n", "ISO 6336-1 c_gamma_alpha b [N/m]", iso_sp.c_gamma_alpha_N_m,
              iso_pr.c_gamma_alpha_N_m);
  model::SimulationResult r;
  r.curves = model::stiffness_curves(stage);
  r.scalars = sc;
  if (!o.output.empty()) {
    io::AtomicOutput out(o.output);
    {
      io::H5File f = io::H5File::create(out.temp_path());
      io::write_simulation(f, config, r, {});
      f.close();
    }
    out.commit();
  }
  if (!o.csv.empty()) {
    // One CSV of all curves: name, x, y.
    io::AtomicOutput out(o.csv);
    {
      std::FILE* f = std::fopen(out.temp_path().c_str(), "w");
      if (!f) throw io::IoError("cannot write " + o.csv);
      std::fprintf(f, "curve,x_name,x,x_unit,stiffness_N_m\n");
      for (const auto& c : r.curves)
        for (std::size_t i = 0; i < c.x.size(); ++i)
          std::fprintf(f, "%s,%s,%.17g,%s,%.17g\n", c.name.c_str(), c.x_name.c_str(), c.x[i], c.x_unit.c_str(),
                       c.y[i]);
      if (std::fclose(f) != 0) throw io::IoError("cannot write " + o.csv);
    }
    out.commit();
  }
  return 0;
}

int run_keys(const std::string& format) {
  if (format == "json") {
    std::fputs(io::keys_json().c_str(), stdout);
    return 0;
  }
  for (const auto& k : io::config_keys())
    std::printf("%-48s %-16s %-22s %s\n", k.path.c_str(), k.type.c_str(), k.default_value.c_str(), k.doc.c_str());
  return 0;
}

int run_candidates(const std::string& format) {
  std::fputs((format == "json" ? io::candidates_json() : io::candidates_text()).c_str(), stdout);
  return 0;
}

int run_config(const ConfigOptions& o) {
  if (o.template_only) {
    require(o.common.config.empty() && o.common.assignments.empty(), "--template",
            "prints the defaults; it takes no --config or --set");
    std::fputs(io::config_template().c_str(), stdout);
    return 0;
  }
  std::fputs(io::to_toml(load(o.common)).c_str(), stdout);
  return 0;
}

} // namespace pw::app
