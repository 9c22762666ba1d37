// Range checks of a whole simulation configuration (config/stage.hpp). Here,
// above the geometry, because a gear is checked by building it
// (geometry::make_geometry).
#pragma once

#include "config/stage.hpp"

namespace pw::model {

/// Range checks of every field of `config`; throws pw::InputError naming the TOML key.
void validate(const SimulationConfig& config);

/// The largest sensor.gain_m_s2_per_N `config` allows [m/s^2 per N]:
/// config::kMaxSensorGain_m_s2_per_N divided by the mount's high-pass at the mesh frequency
/// (model::housing_transfer_gain at unit gain), so that what the lines hear stays below the
/// unit-mistake bound; the bound itself without a mount. validate() and the diagnosis's gain
/// profile both hold a gain to it.
double largest_housing_gain_m_s2_per_N(const SimulationConfig& config);

} // namespace pw::model
