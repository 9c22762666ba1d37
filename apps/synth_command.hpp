// planetwear synth: a synthetic measurement. Simulates the stage (possibly
// with concealed effects given through --set), takes the channels a test rig
// would record (shaft speeds, mesh-line accelerations of planet 0, a housing
// accelerometer, optionally a tacho), optionally decimates them through an
// anti-alias filter, adds seeded white measurement noise and accelerometer DC
// offsets, and writes a CSV recording plus its JSON sidecar (the operating
// point and the columns, never the effect). docs/recordings.md.
//
//   planetwear synth -c gearset.toml --set imperfections.pin_error_m=[0,1e-6,0]
//       --seconds 2.5 --noise 0.05 --dc-offset 0.2 --seed 1 --sensor-angle-deg 30
//       --decimate 32 -o rec.csv            (writes rec.csv and rec.json)
#pragma once

#include "commands.hpp"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace pw::app {

struct SynthOptions {
  CommonOptions common;
  std::optional<double> speed_rpm, power_W;
  std::optional<double> sensor_angle_deg;  ///< overrides sensor.angle_rad
  double seconds = 0;          ///< recorded duration [s]; 0 = four carrier revolutions
  double noise = 0.05;         ///< noise std / RMS of each channel (about its mean)
  double dc_offset = 0.0;      ///< accelerometer offset / RMS of that channel
  std::uint64_t seed = 1;      ///< noise generator seed
  int decimate = 1;            ///< keep every k-th sample after the anti-alias filter
  /// > 0: the recording starts at absolute time W T_mesh (the same for every
  /// configuration at one speed, however long its warm-up took).
  int start_mesh_cycle = 0;
  bool tacho = false;          ///< add a once-per-revolution tacho column of the sun shaft
  std::string output;          ///< CSV path; the sidecar is written beside it (.json)
};

/// Registers the "synth" subcommand on `app`, filling `options`.
CLI::App* add_synth_command(CLI::App& app, SynthOptions& options);

int run_synth(const SynthOptions& options);

/// Input samples the anti-alias filter (signal::decimation_filter(k, 16): 32k + 1
/// taps) needs on each side of an output sample: 16k (0 for k = 1).
inline int decimation_margin(int k) { return k > 1 ? 16 * k : 0; }

} // namespace pw::app
