#include "diagnose/recording.hpp"

namespace pw::diagnose {

// These names are the "quantity" values of the JSON sidecar (docs/recordings.md).
const char* to_string(Quantity q) {
  switch (q) {
  case Quantity::SunSpeed: return "sun_speed";
  case Quantity::CarrierSpeed: return "carrier_speed";
  case Quantity::MeshAccelerationSunPlanet: return "mesh_acceleration_sun_planet";
  case Quantity::MeshAccelerationPlanetRing: return "mesh_acceleration_planet_ring";
  case Quantity::HousingAcceleration: return "housing_acceleration";
  case Quantity::Tacho: return "tacho";
  }
  return "unknown";
}

} // namespace pw::diagnose
