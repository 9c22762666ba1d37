// bench_simulate: wall-clock cost of model::simulate for the seed case
// (Bai & Ning 2023: 1 kW at the sun, default configuration = seed Table 1).
//
//   bench_simulate [--power-w P] [--repeat N] [--record-cycles N] [--set key=value ...] [rpm ...]
//
// Default speeds 100, 200, 400 rpm. For each speed it times model::prepare
// (geometry, stiffness curves, modal analysis) alone and the whole
// model::simulate (prepare + warm-up + recording), best of N repeats, and
// prints why the time step is what it is (scalars time_step,
// steps_per_mesh_period, natural frequencies) and the cost per step and per
// simulated mesh cycle. The dynamics is serial: the benchmark pins Eigen to one
// thread and reports process CPU time beside wall time to show it.
// Documented in docs/benchmark.md.
#include "core/error.hpp"
#include "io/config_toml.hpp"
#include "model/simulation.hpp"
#include "wear/simulation.hpp"

#include <Eigen/Core>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace {

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// Minor page faults of this process so far: first touches of fresh memory. On a virtual machine
/// each costs the host's backing of the page (docs/benchmark.md, session 45: ~2 ms per MiB here),
/// so a run that stores every channel pays for its output's pages on top of the step.
long minor_faults() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double scalar(const pw::model::SimulationResult& r, const std::string& name) {
  for (const auto& s : r.scalars)
    if (s.name == name) return s.value;
  throw std::runtime_error("simulate returned no scalar '" + name + "'");
}

std::vector<double> natural_frequencies(const pw::model::SimulationResult& r) {
  std::vector<double> f;
  for (const auto& s : r.scalars)
    if (s.name.starts_with("natural_frequency/")) f.push_back(s.value);
  std::sort(f.begin(), f.end());
  return f;
}

struct Row {
  double rpm = 0, f_mesh = 0, dt = 0, f_max = 0;
  int spm = 0, warm = 0, rec = 0;
  long steps = 0;
  long faults = 0;  ///< minor page faults of the fastest repeat's simulate
  double wall = 0, cpu = 0, prepare_wall = 0, newton = 0;
  std::string limit, level;
};

[[noreturn]] void usage(int code) {
  std::fprintf(code ? stderr : stdout,
               "usage: bench_simulate [--power-w P] [--repeat N] [--record-cycles N] [--set key=value ...] "
               "[rpm ...]\n"
               "  Times model::simulate for the seed case (default 100 200 400 rpm, 1000 W), best of N\n"
               "  repeats (default 1), single-threaded; prints time step, steps, wall/CPU time, mesh cycles\n"
               "  per core-second, ns per step and mean force evaluations (Newton residuals) per step.\n");
  std::exit(code);
}

} // namespace

int main(int argc, char** argv) {
  Eigen::setNbThreads(1);
  std::vector<double> speeds;
  std::vector<std::string> overrides;
  double power = 1000.0;
  int repeat = 1, record_cycles = -1;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) usage(1);
        return argv[++i];
      };
      if (a == "-h" || a == "--help") usage(0);
      else if (a == "--power-w") power = std::stod(next());
      else if (a == "--repeat") repeat = std::stoi(next());
      else if (a == "--record-cycles") record_cycles = std::stoi(next());
      else if (a == "--set") overrides.push_back(next());
      else if (!a.empty() && a[0] != '-') speeds.push_back(std::stod(a));
      else usage(1);
    }
  } catch (const std::exception&) {
    usage(1);
  }
  if (speeds.empty()) speeds = {100, 200, 400};
  if (repeat < 1) usage(1);

  std::vector<Row> rows;
  try {
    for (double rpm : speeds) {
      pw::model::SimulationConfig c{};
      std::vector<std::string> all = overrides;
      all.push_back("operating.input_speed_rpm=" + std::to_string(rpm));
      all.push_back("operating.input_power_W=" + std::to_string(power));
      if (record_cycles > 0) all.push_back("solver.record_mesh_cycles=" + std::to_string(record_cycles));
      pw::io::apply_overrides(c, all);

      Row row;
      row.rpm = rpm;
      row.wall = row.cpu = row.prepare_wall = 1e300;
      pw::model::SimulationResult r;
      for (int k = 0; k < repeat; ++k) {
        double w0 = now_seconds();
        { const pw::model::PreparedStage p = pw::model::prepare(c); }
        row.prepare_wall = std::min(row.prepare_wall, now_seconds() - w0);

        r = {};  // the previous repeat's output freed first: each repeat maps its own
        w0 = now_seconds();
        const double c0 = cpu_seconds();
        const long f0 = minor_faults();
        r = pw::wear::simulate(c);
        const double cpu = cpu_seconds() - c0;
        row.wall = std::min(row.wall, now_seconds() - w0);
        if (cpu < row.cpu) {
          row.cpu = cpu;
          row.faults = minor_faults() - f0;
        }
      }
      row.f_mesh = scalar(r, "mesh_frequency");
      row.dt = scalar(r, "time_step");
      row.spm = static_cast<int>(scalar(r, "steps_per_mesh_period"));
      row.warm = static_cast<int>(scalar(r, "warmup_mesh_cycles"));
      row.rec = c.solver.record_mesh_cycles;
      row.steps = static_cast<long>(row.warm + row.rec) * row.spm;
      row.newton = scalar(r, "mean_force_evaluations");
      const std::vector<double> fn = natural_frequencies(r);
      row.f_max = fn.empty() ? 0.0 : fn.back();
      // Which limit chose the step (simulation.cpp): mesh period / min_steps_per_mesh
      // or the highest natural period / steps_per_mode_period.
      const double dt_mesh = 1.0 / (row.f_mesh * c.solver.min_steps_per_mesh);
      const double dt_mode = 1.0 / (row.f_max * c.solver.steps_per_mode_period);
      char why[160];
      if (c.solver.time_step_s > 0)
        std::snprintf(why, sizeof why, "set by solver.time_step_s");
      else if (dt_mode <= dt_mesh)
        std::snprintf(why, sizeof why, "1/(%d x f_max %.0f Hz)", c.solver.steps_per_mode_period, row.f_max);
      else
        std::snprintf(why, sizeof why, "T_mesh/%d", c.solver.min_steps_per_mesh);
      row.limit = why;
      row.level = c.solver.level == pw::model::ModelLevel::Torsional ? "torsional" : "lateral_torsional";
      rows.push_back(row);
      std::fprintf(stderr, "%.0f rpm: %.3f s wall\n", rpm, row.wall);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_simulate: error: %s\n", e.what());
    return 1;
  }

  std::printf("\nplanetwear bench_simulate: seed case, %.0f W, %s model, best of %d, 1 thread\n", power,
              rows.empty() ? "?" : rows.front().level.c_str(), repeat);
  std::printf("%6s %9s %10s %-28s %6s %6s %4s %9s %8s %8s %8s %9s %12s %8s %7s %9s\n", "rpm", "f_z[Hz]", "dt[s]",
              "dt chosen by", "steps/", "warm", "rec", "steps", "wall[s]", "cpu[s]", "prep[ms]", "cycles",
              "cycles/core-s", "ns/step", "force", "page");
  std::printf("%6s %9s %10s %-28s %6s %6s %4s %9s %8s %8s %8s %9s %12s %8s %7s %9s\n", "", "", "", "", "T_z", "[T_z]",
              "[T_z]", "", "", "", "", "[T_z]", "", "", "evals/step", "faults");
  for (const Row& r : rows) {
    const int cycles = r.warm + r.rec;
    const double integ = std::max(r.cpu - r.prepare_wall, 1e-12);  // CPU time of the time stepping
    std::printf("%6.0f %9.3f %10.4g %-28s %6d %6d %4d %9ld %8.3f %8.3f %8.2f %9d %12.2f %8.0f %7.3f %9ld\n", r.rpm,
                r.f_mesh, r.dt, r.limit.c_str(), r.spm, r.warm, r.rec, r.steps, r.wall, r.cpu, 1e3 * r.prepare_wall, cycles,
                cycles / r.cpu, 1e9 * integ / static_cast<double>(r.steps), r.newton, r.faults);
  }
  std::printf("\ncycles/core-s = simulated mesh cycles (warm-up + recording) / CPU time of simulate;\n"
              "ns/step = (CPU time - prepare wall time) / steps, storing every channel of the recorded steps;\n"
              "page faults = minor faults of that simulate: first touches of its output's memory, which a virtual\n"
              "machine may charge far more than the step (--record-cycles 1 keeps them small);\n"
              "seed's 2e5 mesh cycles would take about:\n");
  for (const Row& r : rows) {
    const double per_cycle = (r.cpu - r.prepare_wall) / (r.warm + r.rec);
    std::printf("  %6.0f rpm: %.3g core-hours\n", r.rpm, 2e5 * per_cycle / 3600.0);
  }
  return 0;
}
