// Mathematical constants shared by the whole code, one definition each.
#pragma once

#include <numbers>

namespace pw {

inline constexpr double kPi = std::numbers::pi;  ///< pi [-]

} // namespace pw
