// Sizes computed from user input (mesh cycles x steps per mesh, teeth x
// elements, ...) in 64-bit arithmetic that refuses to overflow: an overflow
// is an input too large to run, reported as pw::InputError naming the key,
// never a wrapped int that later aborts in std::vector (issue 19, point 7).
#pragma once

#include "core/error.hpp"

#include <cstdint>
#include <limits>
#include <string>

namespace pw {

/// a * b for counts a, b >= 0; throws InputError naming `param` if the
/// product does not fit in std::int64_t or a factor is negative.
inline std::int64_t checked_mul(std::int64_t a, std::int64_t b, const std::string& param) {
  std::int64_t product = 0;
  if (a < 0 || b < 0 || __builtin_mul_overflow(a, b, &product))
    throw InputError(param, detail::concat("the count ", a, " x ", b, " is negative or exceeds a 64-bit integer"));
  return product;
}

/// a + b for counts a, b >= 0, checked as checked_mul().
inline std::int64_t checked_add(std::int64_t a, std::int64_t b, const std::string& param) {
  std::int64_t sum = 0;
  if (a < 0 || b < 0 || __builtin_add_overflow(a, b, &sum))
    throw InputError(param, detail::concat("the count ", a, " + ", b, " is negative or exceeds a 64-bit integer"));
  return sum;
}

/// v as int; throws InputError naming `param` when it does not fit (loop
/// counters and indices of the physics code are int).
inline int checked_int(std::int64_t v, const std::string& param) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    throw InputError(param, detail::concat("the count ", v, " exceeds the range of int (", std::numeric_limits<int>::max(), ")"));
  return static_cast<int>(v);
}

} // namespace pw
