// bench_wear: wall-clock cost of one full seed wear case (Bai & Ning 2023:
// 1 kW at the sun, 2e5 mesh cycles of Archard wear) through model::simulate,
// on 1 and 2 OpenMP threads.
//
//   bench_wear [--threads "1 2"] [--mesh-cycles N] [--repeat R] [--set key=value ...] [rpm ...]
//
// Default speeds 100 and 400 rpm. For each speed and thread count it runs
// model::simulate (no file output) and splits the wall time with the
// progress callbacks, which simulate calls once per warm-up mesh period, once
// per wear update and once per recorded mesh period (phases in CPU seconds of
// the main thread, which runs all of simulate except the OpenMP update loop,
// so that other processes on the machine do not distort the split):
//
//   prepare    geometry, stiffness curves, modal analysis (timed separately)
//   warm-up    pure dynamics: warmup_mesh_cycles x steps_per_mesh_period steps
//   wear loop  per update: 2 settle cycles + a window of W mesh cycles of
//              dynamics with per-step wear bookkeeping, then the microelement
//              update (the only OpenMP loop) and the backlash update
//   recording  final snapshot + solver.record_mesh_cycles recorded cycles
//
// The dynamics' share of the wear loop is estimated as (its time steps) x
// (ns per step measured in the warm-up); the rest is wear bookkeeping
// (FlankWearAccumulator::accumulate per step, snapshot spectra, updates). The
// microelement update is also timed on its own: the same loop
// (d[e] += rate[e] * dN over every element of every flank family, OpenMP
// static schedule) repeated on arrays of the same size.
//
// Mesh cycles integrated = time_steps / steps_per_mesh_period; worn mesh
// cycles = wear.mesh_cycles reached (the extrapolated ones). Core-seconds =
// process CPU time (all threads, including OpenMP workers spin-waiting).
// ns/step = main-thread CPU time of simulate / time steps. Documented in
// docs/benchmark.md.
#include "core/error.hpp"
#include "io/config_toml.hpp"
#include "model/simulation.hpp"
#include "wear/simulation.hpp"

#include <Eigen/Core>
#include <omp.h>

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

namespace {

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

/// CPU time of the calling thread: the phase split below uses it, so that
/// other processes competing for the cores do not distort it (wall time
/// would count the time the thread waits for a core).
double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double scalar(const pw::model::SimulationResult& r, const std::string& name) {
  for (const auto& s : r.scalars)
    if (s.name == name) return s.value;
  throw std::runtime_error("simulate returned no scalar '" + name + "'");
}

double max_natural_frequency(const pw::model::SimulationResult& r) {
  double f = 0;
  for (const auto& s : r.scalars)
    if (s.name.starts_with("natural_frequency/")) f = std::max(f, s.value);
  return f;
}

struct Row {
  double rpm = 0;
  int threads = 0;
  double f_mesh = 0, dt = 0, f_max = 0;
  int spm = 0, warm = 0, rec = 0, window = 0, updates = 0;
  long elements = 0;
  double steps = 0, worn = 0;
  double wall = 1e300, cpu = 1e300, prepare = 0;
  double t_warm = 0, t_loop = 0, t_rest = 0;  ///< main-thread CPU seconds
  double t_main = 0;                          ///< main-thread CPU seconds of simulate
  double update_us = 0;  ///< one microelement update, micro-timed
  double max_wear = 0;
  std::string stop;
};

[[noreturn]] void usage(int code) {
  std::fprintf(code ? stderr : stdout,
               "usage: bench_wear [--threads \"1 2\"] [--mesh-cycles N] [--repeat R] [--set key=value ...] [rpm ...]\n"
               "  Times one full wear case (default 2e5 mesh cycles, 100 and 400 rpm, 1000 W) through\n"
               "  model::simulate on each OpenMP thread count; prints wall/CPU time, time steps, wear updates,\n"
               "  mesh cycles integrated and worn per second, ns per step and where the time goes.\n");
  std::exit(code);
}

/// Microelement update on arrays of the simulation's size: the loop of
/// model::run_wear, timed over many repetitions [s per update].
double time_update(long elements, int families) {
  std::vector<std::vector<double>> d(families), rate(families);
  const long per = (elements + families - 1) / families;
  for (int f = 0; f < families; ++f) {
    d[f].assign(per, 0.0);
    rate[f].assign(per, 1e-15);
  }
  const int reps = 2000;
  const double dN = 25000.0;
  const double t0 = now_seconds();
  for (int k = 0; k < reps; ++k)
    for (int f = 0; f < families; ++f) {
      double* dd = d[f].data();
      const double* rf = rate[f].data();
      const long n = per;
#pragma omp parallel for schedule(static)
      for (long e = 0; e < n; ++e) dd[e] += rf[e] * dN;
    }
  const double t = (now_seconds() - t0) / reps;
  volatile double sink = d[0][0];
  (void)sink;
  return t;
}

} // namespace

int main(int argc, char** argv) {
  Eigen::setNbThreads(1);
  std::vector<double> speeds;
  std::vector<int> threads;
  std::vector<std::string> overrides;
  double mesh_cycles = 2e5;
  int repeat = 1;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto next = [&]() -> std::string {
        if (i + 1 >= argc) usage(1);
        return argv[++i];
      };
      if (a == "-h" || a == "--help") usage(0);
      else if (a == "--threads") {
        std::istringstream in(next());
        int t;
        while (in >> t) threads.push_back(t);
      } else if (a == "--mesh-cycles") mesh_cycles = std::stod(next());
      else if (a == "--repeat") repeat = std::stoi(next());
      else if (a == "--set") overrides.push_back(next());
      else if (!a.empty() && a[0] != '-') speeds.push_back(std::stod(a));
      else usage(1);
    }
  } catch (const std::exception&) {
    usage(1);
  }
  if (speeds.empty()) speeds = {100, 400};
  if (threads.empty()) threads = {1, 2};
  if (repeat < 1 || mesh_cycles <= 0) usage(1);
  for (int t : threads)
    if (t < 1) usage(1);

  std::vector<Row> rows;
  try {
    for (double rpm : speeds) {
      pw::model::SimulationConfig c{};
      std::vector<std::string> all = overrides;
      all.push_back("operating.input_speed_rpm=" + std::to_string(rpm));
      all.push_back("wear.mesh_cycles=" + std::to_string(mesh_cycles));
      pw::io::apply_overrides(c, all);
      if (c.operating.input_power_W <= 0) throw std::runtime_error("input power must be > 0");

      for (int nt : threads) {
        omp_set_num_threads(nt);
        Row row;
        row.rpm = rpm;
        row.threads = nt;
        pw::model::SimulationResult r;
        for (int k = 0; k < repeat; ++k) {
          double w0 = now_seconds();
          { const pw::model::PreparedStage p = pw::model::prepare(c); }
          const double prep = now_seconds() - w0;

          // Phase boundaries from the progress callbacks.
          double last_warm = 0, last_wear = 0;
          int wear_reports = 0;
          auto progress = [&](double, const std::string& phase) {
            const double t = thread_cpu_seconds();
            if (phase == "warm-up") last_warm = t;
            else if (phase.rfind("wear", 0) == 0) {
              last_wear = t;
              ++wear_reports;
            }
          };
          w0 = now_seconds();
          const double c0 = cpu_seconds(), m0 = thread_cpu_seconds();
          r = pw::wear::simulate(c, progress);
          const double wall = now_seconds() - w0, cpu = cpu_seconds() - c0, main = thread_cpu_seconds() - m0;
          if (wall < row.wall) {
            row.wall = wall;
            row.cpu = cpu;
            row.t_main = main;
            row.prepare = prep;
            row.t_warm = last_warm - m0;
            row.t_loop = last_wear - last_warm;
            row.t_rest = m0 + main - last_wear;
            row.updates = wear_reports;
          }
        }
        row.f_mesh = scalar(r, "mesh_frequency");
        row.dt = scalar(r, "time_step");
        row.spm = static_cast<int>(scalar(r, "steps_per_mesh_period"));
        row.warm = static_cast<int>(scalar(r, "warmup_mesh_cycles"));
        row.rec = c.solver.record_mesh_cycles;
        row.steps = scalar(r, "time_steps");
        row.worn = scalar(r, "worn_mesh_cycles");
        row.f_max = max_natural_frequency(r);
        const int N = c.stage.planet_count;
        row.window = c.wear.window_mesh_cycles > 0
                         ? c.wear.window_mesh_cycles
                         : std::max({c.stage.planet.teeth, (c.stage.ring.teeth + N - 1) / N,
                                     (c.stage.sun.teeth + N - 1) / N}) + 1;
        row.elements = static_cast<long>(c.wear.elements_per_flank) *
                       (c.stage.sun.teeth + 2L * N * c.stage.planet.teeth + c.stage.ring.teeth);
        row.update_us = 1e6 * time_update(row.elements, 2 * N + 2);
        for (const auto& fh : r.wear.flanks) {
          const std::size_t per = static_cast<std::size_t>(fh.teeth) * fh.elements;
          for (std::size_t k = fh.depth_m.size() - per; k < fh.depth_m.size(); ++k)
            row.max_wear = std::max(row.max_wear, fh.depth_m[k]);
        }
        row.stop = r.wear.stop_reason;
        rows.push_back(row);
        std::fprintf(stderr, "%.0f rpm, %d thread(s): %.2f s wall, %.2f s CPU\n", rpm, nt, row.wall, row.cpu);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_wear: error: %s\n", e.what());
    return 1;
  }

  std::printf("\nplanetwear bench_wear: full wear case, %.3g mesh cycles, best of %d (Release build, Eigen 1 thread)\n",
              mesh_cycles, repeat);
  std::printf("%5s %3s %8s %8s %8s %10s %6s %4s %4s %7s %10s %8s %8s %11s %11s %8s\n", "rpm", "thr", "wall[s]",
              "cpu[s]", "main[s]", "steps", "steps/", "upd", "W", "cycles", "cycles/", "worn/s", "ns/step", "dyn ns/",
              "max wear", "");
  std::printf("%5s %3s %8s %8s %8s %10s %6s %4s %4s %7s %10s %8s %8s %11s %11s %8s\n", "", "", "", "all thr", "thread",
              "", "T_z", "", "[T_z]", "integr.", "core-s", "[wall]", "(main)", "step warm", "[m]", "");
  for (const Row& r : rows) {
    const double cycles = r.steps / r.spm;
    const double steps_warm = static_cast<double>(r.warm) * r.spm;
    std::printf("%5.0f %3d %8.3f %8.3f %8.3f %10.0f %6d %4d %4d %7.0f %10.2f %8.0f %8.0f %11.0f %11.4g %8s\n",
                r.rpm, r.threads, r.wall, r.cpu, r.t_main, r.steps, r.spm, r.updates, r.window, cycles, cycles / r.cpu,
                r.worn / r.wall, 1e9 * r.t_main / r.steps, 1e9 * r.t_warm / steps_warm, r.max_wear,
                r.stop.empty() ? "" : "STOPPED");
  }

  std::printf("\nwhere the time goes (CPU seconds of the main thread; prepare: wall, outside simulate):\n");
  std::printf("%5s %3s %8s %8s %9s %10s %10s %10s %9s %12s\n", "rpm", "thr", "prepare", "warm-up", "wear loop",
              "  dynamics", "  wear book", "  updates", "rec+snap", "steps check");
  for (const Row& r : rows) {
    const double steps_warm = static_cast<double>(r.warm) * r.spm;
    const double ns_step = r.t_warm / steps_warm;  // pure dynamics (warm-up includes prepare, < 1 ms)
    const double steps_loop = static_cast<double>(r.updates) * (2 + r.window) * r.spm;
    const double steps_rest = static_cast<double>(8 + r.rec) * r.spm;  // final snapshot + recording
    const double dyn = steps_loop * ns_step;
    const double upd = r.updates * r.update_us * 1e-6;
    std::printf("%5.0f %3d %8.4f %8.3f %9.3f %10.3f %10.3f %10.5f %9.3f %12s\n", r.rpm, r.threads, r.prepare,
                r.t_warm, r.t_loop, dyn, r.t_loop - dyn - upd, upd, r.t_rest,
                std::fabs(steps_warm + steps_loop + steps_rest - r.steps) < 0.5 ? "ok" : "MISMATCH");
  }
  std::printf("\n  dynamics   = wear-loop steps (updates x (2 + W) x steps/T_z) x ns/step of the warm-up\n"
              "  wear book  = the rest of the wear loop: per-step accumulation, snapshots and their spectra\n"
              "  updates    = microelement update loop, micro-timed (%ld elements): per update",
              rows.empty() ? 0L : rows.front().elements);
  for (const Row& r : rows) std::printf(" %.1f us (%d thr)", r.update_us, r.threads);
  std::printf("\n  steps/T_z  = 32 f_max / f_z (f_max = %.0f Hz); W = window (hunting: Z_p + 1)\n",
              rows.empty() ? 0.0 : rows.front().f_max);
  std::printf("\nlower bound at this cost per step, same algorithm: time_steps x ns/step (warm-up)\n");
  for (const Row& r : rows) {
    const double ns_step = r.t_warm / (static_cast<double>(r.warm) * r.spm);
    std::printf("  %5.0f rpm, %d thr: %.0f steps x %.0f ns = %.2f s (measured: main thread %.2f s CPU, %.2f s wall; "
                "target 10 s)\n",
                r.rpm, r.threads, r.steps, 1e9 * ns_step, r.steps * ns_step, r.t_main, r.wall);
  }
  return 0;
}
