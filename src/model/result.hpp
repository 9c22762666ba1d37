// What a simulation returns: named, unit-carrying channels that writers (HDF5,
// CSV) and post-processing iterate over without knowing the physics.
#pragma once

#include <string>
#include <vector>

namespace pw::model {

/// One sampled time history. `name` is a '/'-separated path, e.g.
/// "sun_planet/0/deflection" (mesh of planet 0), used verbatim as the HDF5
/// dataset path below /time_history.
struct Channel {
  std::string name;
  std::string unit;         ///< SI unit, e.g. "m", "N", "m/s^2", "rad/s", "1"
  std::string description;  ///< one sentence, stored as an HDF5 attribute
  std::vector<double> values;
};

/// A named scalar result (mesh frequency, time step, natural frequencies...).
struct Scalar {
  std::string name;
  std::string unit;
  std::string description;
  double value = 0;
};

/// A curve y(x) such as a mesh-stiffness curve over one mesh period.
struct Curve {
  std::string name;         ///< e.g. "sun_planet/single_pair"
  std::string x_name, x_unit, y_name, y_unit, description;
  std::vector<double> x, y;
};

/// Wear of one flank family (sun drive flanks, planet i sun-side or
/// ring-side flanks, ring flanks) at every wear update.
struct FlankWearHistory {
  std::string name;                    ///< "sun", "planet_0/sun_side", "planet_0/ring_side", "ring"
  int teeth = 0, elements = 0;
  /// Signed distance of each element centre from the pitch point along the
  /// line of action [m], positive towards this gear's tip (seed Fig. 9 axis).
  std::vector<double> distance_from_pitch_point_m;
  /// Wear depth [m], updates x teeth x elements, row-major (update 0 = start).
  std::vector<double> depth_m;
};

/// The dynamic state at one wear update, kept for output.
struct WearSnapshot {
  double mesh_cycles = 0;
  std::vector<double> time_s;
  std::vector<Channel> channels;
  /// Amplitude spectra of the channels (x: frequency [Hz], y: amplitude in
  /// the channel's unit; Hann window, peak-amplitude scaling).
  std::vector<Curve> spectra;
};

struct WearHistory {
  std::vector<double> mesh_cycles;      ///< at each update [-] (0 first)
  std::vector<FlankWearHistory> flanks;
  /// Backlash of each mesh family at each update [m]: rows = updates,
  /// columns = (sun_planet, planet_ring).
  std::vector<double> backlash_m;
  std::vector<WearSnapshot> snapshots;
  std::string stop_reason;              ///< empty if mesh_cycles was reached
};

struct SimulationResult {
  double time_step_s = 0;           ///< sample interval of the channels [s] (the time step times the decimation)
  std::vector<double> time_s;       ///< sample times of every channel [s]
  std::vector<Channel> channels;    ///< all equally long as time_s
  std::vector<Scalar> scalars;
  std::vector<Curve> curves;
  WearHistory wear;                 ///< empty unless wear.mesh_cycles > 0

  const Channel* find(const std::string& name) const {
    for (const auto& c : channels)
      if (c.name == name) return &c;
    return nullptr;
  }
  const Scalar* find_scalar(const std::string& name) const {
    for (const auto& s : scalars)
      if (s.name == name) return &s;
    return nullptr;
  }
};

} // namespace pw::model
