// Sobol' low-discrepancy sequence for the Saltelli design (design.hpp), read from
// Boost.Random's sobol_engine (Debian's libboost-dev).
//
// Construction (Bratley & Fox 1988, ACM TOMS 14(1) 88-100; Joe & Kuo 2008,
// SIAM J. Sci. Comput. 30(5) 2635-2654, doi:10.1137/070709359): direction
// numbers of Joe & Kuo's table "new-joe-kuo-6.21201", 32-bit, points in
// Gray-code order (Antonov & Saleev 1979). Point 0 is the origin, which Boost's
// engine skips (its first point is this class's point 1). The order and values
// equal Joe & Kuo's reference program and scipy.stats.qmc.Sobol(d,
// scramble=False) (checked in tests/sweep/test_sobol.cpp; until 2026-11 this
// file held its own copy of the table, and its first 4096 points in 64
// dimensions were identical to Boost's).
//
// Example: SobolSequence s(4); std::vector<double> x = s.point(5);  // in [0, 1)^4
#pragma once

#include <cstdint>
#include <vector>

namespace pw::sweep {

class SobolSequence {
public:
  /// Dimensions with direction numbers in Boost.Random's table (Joe & Kuo rows 1..3667).
  static constexpr int kMaxDimensions = 3667;
  /// Points per dimension that fit 32-bit direction numbers.
  static constexpr std::uint64_t kMaxPoints = std::uint64_t{1} << 32;

  /// Throws std::invalid_argument unless 1 <= dimensions <= kMaxDimensions.
  explicit SobolSequence(int dimensions);

  int dimensions() const noexcept { return dimensions_; }

  /// Point `index` (0-based, < kMaxPoints) as 32-bit integers x_j 2^32.
  std::vector<std::uint32_t> point_bits(std::uint64_t index) const;
  /// Point `index` in [0, 1)^d. Throws std::out_of_range past kMaxPoints.
  std::vector<double> point(std::uint64_t index) const;

private:
  int dimensions_;
};

} // namespace pw::sweep
