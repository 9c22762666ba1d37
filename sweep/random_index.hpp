// Bounded random integers and shuffles for the designs (design.cpp, rank_correlation.cpp): built from
// std::mt19937_64's output, whose sequence the C++ standard fixes, so a seed gives the same
// design with every compiler (std::uniform_int_distribution's algorithm is unspecified).
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace pw::sweep {

/// Uniform integer in [0, n) by rejection (no modulo bias), n >= 1.
inline std::uint64_t below(std::mt19937_64& engine, std::uint64_t n) {
  const std::uint64_t max = std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t limit = max - (max % n + 1) % n;  // values above `limit` are rejected
  std::uint64_t x;
  do {
    x = engine();
  } while (x > limit);
  return x % n;
}

/// Fisher-Yates shuffle of v in place with below(): every permutation equally likely, the same
/// one for a seed with every compiler (std::shuffle's algorithm is unspecified).
template <class T>
void shuffle(std::vector<T>& v, std::mt19937_64& engine) {
  for (std::size_t k = v.size(); k > 1; --k) std::swap(v[k - 1], v[below(engine, k)]);
}

} // namespace pw::sweep
