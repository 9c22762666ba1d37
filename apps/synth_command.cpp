// planetwear synth (see synth_command.hpp and docs/recordings.md):
//   1. configuration + overrides; the duration sets solver.record_mesh_cycles
//   2. simulate (warm-up, then the recorded mesh cycles)
//   3. channels a rig records: sun/speed, carrier/speed,
//      sun_planet/0/acceleration, planet_ring/0/acceleration,
//      housing/acceleration (+ tacho from sun/angle)
//   4. anti-alias filter and decimation (--decimate k)
//   5. white Gaussian noise, std = noise x RMS about the mean, per channel;
//      accelerometers also get a DC offset of dc_offset x RMS
//   6. CSV + JSON sidecar (operating point and columns only)
#include "synth_command.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "diagnose/recording.hpp"
#include "io/config_toml.hpp"
#include "io/io_error.hpp"
#include "io/recording_reader.hpp"
#include "io/recording_writer.hpp"
#include "model/memory_estimate.hpp"
#include "model/simulation.hpp"
#include "model/validate.hpp"
#include "signal/decimate.hpp"
#include "wear/simulation.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>

namespace pw::app {
namespace {

constexpr double kTachoHigh_V = 5.0;       ///< tacho pulse level [V]
constexpr double kTachoDutyCycle = 0.05;  ///< pulse length / revolution

std::string toml_float(double v) {
  std::array<char, 64> buf{};
  const auto end = std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr;
  return std::string(buf.data(), end);
}

double rms_about_mean(const std::vector<double>& x) {
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(x.size());
  double s = 0;
  for (double v : x) s += (v - mean) * (v - mean);
  return std::sqrt(s / static_cast<double>(x.size()));
}

/// Refuses a duration whose simulation cannot be held in memory, before the
/// warm-up: synth simulates every time step of the whole duration and
/// decimates only afterwards, so the simulated rate sets the memory.
void check_synth_memory(const model::SimulationConfig& config, double seconds, const model::OutputSelection& columns) {
  const model::PreparedStage p = model::prepare(config);
  const std::size_t channels = columns.channels.size();
  // The stored channels, then the decimated copies (at most as long again).
  const double bytes = 1.5 * model::record_bytes(config, p.steps_per_mesh, 1, channels);
  require_memory(bytes, "--seconds",
                 detail::concat(seconds, " s at ", config.operating.input_speed_rpm, " rpm (",
                                config.solver.record_mesh_cycles, " mesh cycles x ", p.steps_per_mesh,
                                " time steps, ", channels, " channels)"),
                 "use a shorter --seconds (--decimate thins the recording only after the simulation)");
}

/// A once-per-revolution tacho of the sun shaft at simulated samples first + j k, j < n:
/// kTachoHigh_V during the first kTachoDutyCycle of each turn, else 0.
diagnose::SignalChannel tacho_channel(const model::SimulationResult& r, std::size_t first, std::size_t k,
                                      std::size_t n) {
  const model::Channel* angle = r.find("sun/angle");
  if (!angle) throw SolverError("simulation produced no channel 'sun/angle'");
  diagnose::SignalChannel sc;
  sc.name = "tacho";
  sc.quantity = diagnose::Quantity::Tacho;
  sc.unit = "V";
  for (std::size_t j = 0; j < n; ++j) {
    const double turn = angle->values[first + j * k] / (2 * kPi);
    sc.values.push_back(turn - std::floor(turn) < kTachoDutyCycle ? kTachoHigh_V : 0.0);
  }
  return sc;
}

} // namespace

CLI::App* add_synth_command(CLI::App& app, SynthOptions& o) {
  CLI::App* s = app.add_subcommand(
      "synth", "Synthesize a measurement: simulate (with any --set effects), add measurement noise and "
               "accelerometer offsets, write a CSV recording and its JSON sidecar (docs/recordings.md)");
  s->add_option("-c,--config", o.common.config, "TOML configuration (default: the seed paper's case)")
      ->check(CLI::ExistingFile);
  s->add_option("--set", o.common.assignments,
                "override any configuration key (effects to conceal, e.g. --set imperfections.pin_error_m=[0,1e-6,0])")
      ->take_all();
  s->add_option("--speed-rpm", o.speed_rpm, "input (sun) speed [rpm]; overrides operating.input_speed_rpm");
  s->add_option("--power-w", o.power_W, "input power [W]; overrides operating.input_power_W");
  s->add_option("--seconds", o.seconds,
                "recorded duration [s] after the warm-up; 0 (default) = 4 carrier revolutions (the reader needs "
                ">= 2 Zs mesh cycles; below 2 carrier revolutions the diagnosis compares only the families "
                "resolved in halves of whole mesh cycles, docs/diagnose.md)");
  s->add_option("--noise", o.noise,
                "white Gaussian noise per channel, std as a fraction of the channel's RMS about its mean "
                "(default 0.05)");
  s->add_option("--dc-offset", o.dc_offset,
                "DC offset added to accelerometer channels, as a fraction of their RMS (default 0)");
  s->add_option("--seed", o.seed, "noise generator seed (mt19937_64; same seed, same file)");
  s->add_option("--sensor-angle-deg", o.sensor_angle_deg,
                "housing accelerometer angle [deg], CCW from planet 0 at t = 0; overrides sensor.angle_rad");
  s->add_option("--decimate", o.decimate,
                "keep every k-th simulated sample after a zero-phase anti-alias FIR (Blackman-windowed sinc, "
                "32k+1 taps, cutoff 0.4 x the new sample rate); 1 to 1e6, default 1")
      ->check(CLI::PositiveNumber);
  s->add_option("--start-mesh-cycle", o.start_mesh_cycle,
                "start the recording at absolute time W x mesh period (simulating on after the warm-up), so that "
                "recordings of different configurations at one speed start at the same time; 0 (default) = right "
                "after the warm-up");
  s->add_flag("--tacho", o.tacho, "add a once-per-revolution tacho column of the sun shaft (5 V pulses)");
  s->add_option("-o,--output", o.output, "recording (CSV); the sidecar goes beside it with extension .json")
      ->required();
  s->add_flag("-q,--quiet", o.common.quiet, "no progress on stderr");
  s->footer(
      "Columns: time [s], sun_speed [rad/s], carrier_speed [rad/s], sun_planet_0_acc [m/s^2], planet_ring_0_acc "
      "[m/s^2], housing_acc [m/s^2] (+ tacho [V]). Time is the simulation's absolute time, so planet 0 is at the "
      "housing angle 0 at t = 0. The simulation samples every time step (2.8 us for the seed gears, 355 kHz); "
      "--decimate 32 gives 11 kHz. Noise std = --noise x RMS (about the mean) of each channel after decimation; "
      "offsets on the three accelerations only. The sidecar states the operating point and the columns, not the "
      "configuration's effects.\nExample: planetwear synth --speed-rpm 400 --set imperfections.pin_error_m=[0,2e-7,0] "
      "--noise 0.05 --dc-offset 0.2 --seed 1 --sensor-angle-deg 30 --decimate 32 -o rec.csv");
  return s;
}

int run_synth(const SynthOptions& o) {
  // 1. Options and configuration.
  require(std::isfinite(o.noise) && o.noise >= 0, "--noise", "must be a finite number >= 0, got ", o.noise);
  require(std::isfinite(o.dc_offset), "--dc-offset", "must be a finite number, got ", o.dc_offset);
  require(std::isfinite(o.seconds) && o.seconds >= 0, "--seconds", "must be >= 0 (0 = automatic), got ", o.seconds);
  // The filter has 32 k + 1 taps (decimation_margin, int): k is bounded so that its
  // length cannot overflow; 1e6 already thins 355 kHz to 0.4 Hz.
  require(o.decimate >= 1 && o.decimate <= 1000000, "--decimate", "must be an integer in [1, 1000000], got ",
          o.decimate);
  std::vector<std::string> sets = o.common.assignments;
  if (o.speed_rpm) sets.push_back("operating.input_speed_rpm=" + toml_float(*o.speed_rpm));
  if (o.power_W) sets.push_back("operating.input_power_W=" + toml_float(*o.power_W));
  if (o.sensor_angle_deg) {
    require(std::isfinite(*o.sensor_angle_deg), "--sensor-angle-deg", "must be finite, got ", *o.sensor_angle_deg);
    sets.push_back("sensor.angle_rad=" + toml_float(*o.sensor_angle_deg * kPi / 180));
  }
  model::SimulationConfig config = o.common.config.empty() ? model::SimulationConfig{} : io::read_config(o.common.config);
  io::apply_overrides(config, sets);
  const double rpm = config.operating.input_speed_rpm;
  const double seconds = o.seconds > 0 ? o.seconds : io::required_duration_s(config, rpm) * 4.0 / 3.0;
  const double fm = io::mesh_frequency_Hz(config, rpm);
  // The anti-alias filter needs decimation_margin(k) samples beyond each end;
  // the time step is at most T_mesh / 8 (validated), which bounds the margin.
  const int k = o.decimate;
  const double margin_s = 2.0 * decimation_margin(k) / (8 * fm);
  // With --start-mesh-cycle W the record must also cover the cycles from the
  // end of the warm-up (unknown beforehand, at most W) to W.
  require(o.start_mesh_cycle >= 0 && o.start_mesh_cycle <= 1e5, "--start-mesh-cycle",
          "must be in [0, 1e5] mesh cycles, got ", o.start_mesh_cycle);
  const double cycles = std::ceil((seconds + margin_s) * fm) + 1 + o.start_mesh_cycle;
  require(cycles <= 1e6, "--seconds", seconds, " s at ", rpm, " rpm is ", cycles,
          " mesh cycles, more than solver.record_mesh_cycles allows (1e6)");
  config.solver.record_mesh_cycles = static_cast<int>(cycles);
  model::validate(config);
  const std::filesystem::path out(o.output);
  const std::filesystem::path dir = out.has_parent_path() ? out.parent_path() : std::filesystem::path(".");
  if (!std::filesystem::is_directory(dir))
    throw io::IoError(detail::concat("cannot write '", o.output, "': directory '", dir.string(), "' does not exist"));
  if (io::sidecar_path(out) == out) throw io::IoError(o.output + ": the recording must not end in .json");

  // 2. Simulate.
  const auto clock0 = std::chrono::steady_clock::now();
  model::ProgressFn progress;
  if (!o.common.quiet)
    progress = [last = clock0](double f, const std::string& phase) mutable {
      const auto now = std::chrono::steady_clock::now();
      if (f < 1.0 && now - last < std::chrono::milliseconds(500)) return;
      last = now;
      std::fprintf(stderr, "\r[%-9s] %5.1f %%", phase.c_str(), 100 * f);
      if (f >= 1.0) std::fprintf(stderr, "\n");
    };
  // Only what the recording's columns come from is stored (simulation.hpp's OutputSelection).
  const model::OutputSelection columns{{"sun/speed", "carrier/speed", "sun_planet/0/acceleration",
                                        "planet_ring/0/acceleration", "housing/acceleration", "sun/angle"},
                                       1};
  check_synth_memory(config, seconds, columns);
  const model::SimulationResult r = wear::simulate(config, progress, columns);

  // 3. Channels, at the simulation's rate; output j is simulated sample
  //    first + j k, n_out of them. first: the filter's margin after the
  //    warm-up, or the sample at absolute time W T_mesh (--start-mesh-cycle W).
  const double dt = r.time_step_s;
  const model::Scalar* start = r.find_scalar("record_start_time");
  const double t_start = start ? start->value : 0.0;
  const std::size_t margin = static_cast<std::size_t>(decimation_margin(k));
  const signal::DecimationFilter filter = signal::decimation_filter(k, 16);  // 2 margin + 1 taps
  std::size_t first = margin;
  if (o.start_mesh_cycle > 0) {
    // Absolute time of sample i is t_start + time_s[i].
    const double target = o.start_mesh_cycle / fm - t_start;
    first = static_cast<std::size_t>(std::lower_bound(r.time_s.begin(), r.time_s.end(), target - 0.5 * dt) -
                                     r.time_s.begin());
    if (first < margin)
      throw InputError("--start-mesh-cycle",
                       detail::concat("the warm-up took ", std::llround(t_start * fm), " mesh cycles", margin > 0 ? " (plus " + std::to_string(margin) + " samples for the decimation filter)" : "",
                                      ", so the recording cannot start at mesh cycle ", o.start_mesh_cycle,
                                      "; use a larger value"));
  }
  if (r.time_s.size() < first + margin + 1)
    throw SolverError(detail::concat("the simulation recorded ", r.time_s.size(), " samples, fewer than the ",
                                     first + margin + 1, " needed"));
  const std::size_t n_out = std::min(static_cast<std::size_t>(std::llround(seconds / (dt * k))),
                                     (r.time_s.size() - first - margin - 1) / static_cast<std::size_t>(k) + 1);
  struct Source {
    const char* channel;
    const char* column;
    diagnose::Quantity quantity;
  };
  const std::array<Source, 5> sources{{{"sun/speed", "sun_speed", diagnose::Quantity::SunSpeed},
                                       {"carrier/speed", "carrier_speed", diagnose::Quantity::CarrierSpeed},
                                       {"sun_planet/0/acceleration", "sun_planet_0_acc",
                                        diagnose::Quantity::MeshAccelerationSunPlanet},
                                       {"planet_ring/0/acceleration", "planet_ring_0_acc",
                                        diagnose::Quantity::MeshAccelerationPlanetRing},
                                       {"housing/acceleration", "housing_acc", diagnose::Quantity::HousingAcceleration}}};
  diagnose::Recording rec;
  rec.source = o.output;
  rec.operating = config.operating;
  for (std::size_t j = 0; j < n_out; ++j) rec.time_s.push_back(t_start + r.time_s[first + j * k]);
  std::mt19937_64 rng(o.seed);
  for (const Source& s : sources) {
    const model::Channel* ch = r.find(s.channel);
    if (!ch) throw SolverError(detail::concat("simulation produced no channel '", s.channel, "'"));
    diagnose::SignalChannel sc;
    sc.name = s.column;
    sc.quantity = s.quantity;
    sc.unit = io::si_unit(s.quantity);
    sc.planet = 0;
    sc.sensor_angle_rad = s.quantity == diagnose::Quantity::HousingAcceleration ? config.sensor.angle_rad : 0.0;
    // 4. Anti-alias filter and decimation.
    sc.values = signal::decimate(ch->values, filter, first, n_out);
    // 5. Measurement noise and accelerometer offset.
    const double rms = rms_about_mean(sc.values);
    std::normal_distribution<double> noise(0.0, o.noise * rms);
    const bool accelerometer = s.quantity != diagnose::Quantity::SunSpeed && s.quantity != diagnose::Quantity::CarrierSpeed;
    const double offset = accelerometer ? o.dc_offset * rms : 0.0;
    for (double& v : sc.values) v += offset + (o.noise > 0 ? noise(rng) : 0.0);
    rec.channels.push_back(std::move(sc));
  }
  if (o.tacho) rec.channels.push_back(tacho_channel(r, first, static_cast<std::size_t>(k), n_out));

  // 6. Write.
  const double fs = 1.0 / (dt * k);
  io::RecordingWriteOptions wo;
  wo.description = detail::concat("synthesized by ", version_string(), " synth: simulated stage, white noise ",
                                  100 * o.noise, " % of each channel's RMS", o.dc_offset != 0 ? ", accelerometer DC offsets" : "",
                                  ", sample rate ", fs, " Hz");
  wo.sun_encoder_lines = config.sensor.sun_encoder_lines;  // the encoders the speeds were measured with
  wo.carrier_encoder_lines = config.sensor.carrier_encoder_lines;
  io::write_recording(out, rec, wo);
  if (!o.common.quiet) {
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
    std::fprintf(stderr, "wrote %s and %s: %zu samples at %.6g Hz (%.4g s, %.3g carrier revolutions), wall %.2f s\n",
                 o.output.c_str(), io::sidecar_path(out).c_str(), rec.time_s.size(), fs,
                 static_cast<double>(rec.time_s.size()) / fs,
                 static_cast<double>(rec.time_s.size()) / fs * io::mesh_frequency_Hz(config, rpm) /
                     config.stage.ring.teeth,
                 wall);
    if (fs < io::required_sample_rate_Hz(config, rpm))
      std::fprintf(stderr, "planetwear: warning: %.6g Hz is below the %.6g Hz the recording reader requires\n", fs,
                   io::required_sample_rate_Hz(config, rpm));
    if (static_cast<double>(rec.time_s.size()) / fs < io::required_duration_s(config, rpm))
      std::fprintf(stderr, "planetwear: warning: %.4g s is shorter than the %.4g s (%d mesh cycles) the "
                           "recording reader requires\n",
                   static_cast<double>(rec.time_s.size()) / fs, io::required_duration_s(config, rpm),
                   io::required_mesh_cycles(config));
  }
  return 0;
}

} // namespace pw::app
