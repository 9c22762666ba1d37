// Range checks of a whole simulation configuration (config/stage.hpp). Here,
// above the geometry, because a gear is checked by building it
// (geometry::make_geometry).
#pragma once

#include "config/stage.hpp"

namespace pw::model {

/// Range checks of every field of `config`; throws pw::InputError naming the TOML key.
void validate(const SimulationConfig& config);

} // namespace pw::model
