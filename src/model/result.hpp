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

struct SimulationResult {
  double time_step_s = 0;
  std::vector<double> time_s;       ///< sample times of every channel [s]
  std::vector<Channel> channels;    ///< all equally long as time_s
  std::vector<Scalar> scalars;
  std::vector<Curve> curves;

  const Channel* find(const std::string& name) const {
    for (const auto& c : channels)
      if (c.name == name) return &c;
    return nullptr;
  }
};

} // namespace pw::model
