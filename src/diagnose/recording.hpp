// A measured (or synthesized) recording of a planetary stage, in SI units,
// as the diagnosis sees it: uniformly sampled channels, each with its
// physical meaning. Readers in io/ build it from CSV / HDF5 files and a JSON
// sidecar and convert units; everything downstream assumes SI.
#pragma once

#include "config/stage.hpp"

#include <string>
#include <vector>

namespace pw::diagnose {

/// What a channel measures. Speeds are absolute shaft speeds.
enum class Quantity {
  SunSpeed,                    ///< input (sun) shaft speed [rad/s], e.g. from an encoder
  CarrierSpeed,                ///< output (carrier) shaft speed [rad/s]
  MeshAccelerationSunPlanet,   ///< relative acceleration along a sun-planet line of action [m/s^2] (seed's quantity)
  MeshAccelerationPlanetRing,  ///< same for a planet-ring mesh [m/s^2]
  HousingAcceleration,         ///< accelerometer fixed on the ring/housing [m/s^2]
  Tacho,                       ///< once-per-revolution pulse train of the input shaft [1]
};

const char* to_string(Quantity q);

struct SignalChannel {
  std::string name;            ///< column name as in the file
  Quantity quantity = Quantity::HousingAcceleration;
  std::string unit;            ///< SI unit after conversion ("rad/s", "m/s^2", "1")
  int planet = 0;              ///< mesh accelerations: which planet's mesh
  double sensor_angle_rad = 0; ///< housing accelerometer: angle from planet 0's position at t = 0, CCW
  std::vector<double> values;
};

struct Recording {
  std::string source;                  ///< file name, for messages
  std::vector<double> time_s;          ///< uniform sampling (checked by the reader)
  std::vector<SignalChannel> channels;
  model::OperatingPoint operating;     ///< nominal operating point of the recording
  double sample_interval_s() const { return time_s.size() > 1 ? time_s[1] - time_s[0] : 0.0; }
  const SignalChannel* find(Quantity q) const {
    for (const auto& c : channels)
      if (c.quantity == q) return &c;
    return nullptr;
  }
};

} // namespace pw::diagnose
