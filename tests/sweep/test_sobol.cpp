// Sobol' sequence: the Joe & Kuo (2008) direction numbers and Gray-code
// order reproduce the reference values (scipy.stats.qmc.Sobol(d,
// scramble=False), which uses the same new-joe-kuo-6.21201 table), and every
// dimension has the (0, m, 1) net property: the first 2^m points put exactly
// one point in each interval [k/2^m, (k+1)/2^m).
#include "sweep/sobol.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace pw::sweep {
namespace {

TEST(Sobol, First16PointsIn32DimensionsMatchTheReference) {
  // 16 x point, from scipy.stats.qmc.Sobol(d=32, scramble=False).random(16).
  const int expected[16][32] = {
      {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
      {8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8, 8},
      {12, 4, 4, 4, 12, 12, 4, 12, 12, 12, 12, 12, 4, 4, 12, 4, 12, 4, 12, 4, 4, 12, 4, 4, 4, 12, 4, 12, 4, 12, 4, 4},
      {4, 12, 12, 12, 4, 4, 12, 4, 4, 4, 4, 4, 12, 12, 4, 12, 4, 12, 4, 12, 12, 4, 12, 12, 12, 4, 12, 4, 12, 4, 12, 12},
      {6, 6, 10, 14, 6, 2, 6, 14, 14, 10, 14, 6, 6, 10, 6, 14, 6, 14, 14, 2, 2, 2, 6, 14, 14, 14, 6, 10, 2, 2, 6, 2},
      {14, 14, 2, 6, 14, 10, 14, 6, 6, 2, 6, 14, 14, 2, 14, 6, 14, 6, 6, 10, 10, 10, 14, 6, 6, 6, 14, 2, 10, 10, 14, 10},
      {10, 2, 14, 10, 10, 14, 2, 2, 2, 6, 2, 10, 2, 14, 10, 10, 10, 10, 2, 6, 6, 14, 2, 10, 10, 2, 2, 6, 6, 14, 2, 6},
      {2, 10, 6, 2, 2, 6, 10, 10, 10, 14, 10, 2, 10, 6, 2, 2, 2, 2, 10, 14, 14, 6, 10, 2, 2, 10, 10, 14, 14, 6, 10, 14},
      {3, 5, 15, 7, 9, 5, 7, 15, 15, 5, 11, 1, 15, 15, 13, 15, 13, 13, 15, 5, 3, 11, 3, 15, 7, 1, 9, 3, 11, 15, 7, 13},
      {11, 13, 7, 15, 1, 13, 15, 7, 7, 13, 3, 9, 7, 7, 5, 7, 5, 5, 7, 13, 11, 3, 11, 7, 15, 9, 1, 11, 3, 7, 15, 5},
      {15, 1, 11, 3, 5, 9, 3, 3, 3, 9, 7, 13, 11, 11, 1, 11, 1, 9, 3, 1, 7, 7, 7, 11, 3, 13, 13, 15, 15, 3, 3, 9},
      {7, 9, 3, 11, 13, 1, 11, 11, 11, 1, 15, 5, 3, 3, 9, 3, 9, 1, 11, 9, 15, 15, 15, 3, 11, 5, 5, 7, 7, 11, 11, 1},
      {5, 3, 5, 9, 15, 7, 1, 1, 1, 15, 5, 7, 9, 5, 11, 1, 11, 3, 1, 7, 1, 9, 5, 1, 9, 15, 15, 9, 9, 13, 1, 15},
      {13, 11, 13, 1, 7, 15, 9, 9, 9, 7, 13, 15, 1, 13, 3, 9, 3, 11, 9, 15, 9, 1, 13, 9, 1, 7, 7, 1, 1, 5, 9, 7},
      {9, 7, 1, 13, 3, 11, 5, 13, 13, 3, 9, 11, 13, 1, 7, 5, 7, 7, 13, 3, 5, 5, 1, 5, 13, 3, 11, 5, 13, 1, 5, 11},
      {1, 15, 9, 5, 11, 3, 13, 5, 5, 11, 1, 3, 5, 9, 15, 13, 15, 15, 5, 11, 13, 13, 9, 13, 5, 11, 3, 13, 5, 9, 13, 3},
  };
  const SobolSequence s(32);
  for (int i = 0; i < 16; ++i) {
    const auto x = s.point(static_cast<std::uint64_t>(i));
    for (int j = 0; j < 32; ++j) EXPECT_EQ(x[j] * 16, expected[i][j]) << "point " << i << ", dimension " << j;
  }
}

TEST(Sobol, Point1000In64DimensionsMatchesTheReference) {
  // 1024 x point 1000, from scipy.stats.qmc.Sobol(d=64, scramble=False).
  const int expected[64] = {225, 99, 531, 693, 287, 929, 47, 921, 513, 71, 87, 261, 165, 393, 147, 379, 737, 353, 1015, 743, 535, 563, 973, 553, 597, 929, 41, 1003, 61, 349, 151, 149, 303, 607, 821, 789, 869, 851, 315, 491, 935, 261, 983, 719, 861, 95, 893, 941, 1023, 491, 361, 529, 771, 449, 129, 913, 465, 81, 905, 585, 457, 617, 265, 457};
  const auto x = SobolSequence(64).point(1000);
  for (int j = 0; j < 64; ++j) EXPECT_EQ(x[j] * 1024, expected[j]) << "dimension " << j;
}

TEST(Sobol, EveryDimensionStratifiesTheFirst1024Points) {
  constexpr int m = 10, n = 1 << m;
  const SobolSequence s(SobolSequence::kMaxDimensions);
  std::vector<std::vector<int>> hits(SobolSequence::kMaxDimensions, std::vector<int>(n, 0));
  for (int i = 0; i < n; ++i) {
    const auto bits = s.point_bits(static_cast<std::uint64_t>(i));
    for (int j = 0; j < s.dimensions(); ++j) ++hits[j][bits[j] >> (32 - m)];
  }
  for (int j = 0; j < s.dimensions(); ++j)
    for (int k = 0; k < n; ++k) ASSERT_EQ(hits[j][k], 1) << "dimension " << j << ", interval " << k;
}

TEST(Sobol, PointsLieInTheHalfOpenUnitCube) {
  const SobolSequence s(8);
  for (std::uint64_t i : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{12345}, SobolSequence::kMaxPoints - 1})
    for (const double x : s.point(i)) {
      EXPECT_GE(x, 0.0);
      EXPECT_LT(x, 1.0);
    }
}

TEST(Sobol, RejectsDimensionsOutsideTheTableAndIndicesBeyond2To32) {
  EXPECT_THROW(SobolSequence(0), std::invalid_argument);
  EXPECT_THROW(SobolSequence(SobolSequence::kMaxDimensions + 1), std::invalid_argument);
  EXPECT_THROW(SobolSequence(2).point(SobolSequence::kMaxPoints), std::out_of_range);
}

} // namespace
} // namespace pw::sweep
