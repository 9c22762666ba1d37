// Sobol' low-discrepancy sequence in up to 64 dimensions, for the Saltelli
// design (design.hpp). Pure C++, no dependencies.
//
// Construction (Bratley & Fox 1988, ACM TOMS 14(1) 88-100; Joe & Kuo 2008,
// SIAM J. Sci. Comput. 30(5) 2635-2654, doi:10.1137/070709359):
//   * dimension 1: v_k = 2^-k (van der Corput in base 2);
//   * dimension j > 1: primitive polynomial x^s + a_1 x^(s-1) + ... +
//     a_(s-1) x + 1 and initial numbers m_1..m_s (odd, m_k < 2^k) from Joe &
//     Kuo's table "new-joe-kuo-6.21201" (https://web.maths.unsw.edu.au/~fkuo/sobol/),
//     then m_k = 2 a_1 m_(k-1) ^ 4 a_2 m_(k-2) ^ ... ^ 2^s m_(k-s) ^ m_(k-s)
//     and v_k = m_k / 2^k, stored as 32-bit integers V_k = m_k 2^(32-k);
//   * point i, Gray-code order (Antonov & Saleev 1979): x_j(i) = XOR of
//     V_k over the set bits k of gray(i) = i ^ (i >> 1), divided by 2^32.
// Point 0 is the origin. The order and values equal Joe & Kuo's reference
// program and scipy.stats.qmc.Sobol(d, scramble=False) (checked in
// tests/sweep/test_sobol.cpp).
//
// Example: SobolSequence s(4); std::vector<double> x = s.point(5);  // in [0, 1)^4
#pragma once

#include <cstdint>
#include <vector>

namespace pw::sweep {

class SobolSequence {
public:
  /// Dimensions with direction numbers in this file (Joe & Kuo rows 1..64).
  static constexpr int kMaxDimensions = 64;
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
  std::vector<std::uint32_t> directions_;  ///< dimensions x 32, row-major
};

} // namespace pw::sweep
