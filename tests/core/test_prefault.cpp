// resize_prefaulted (core/prefault.hpp) only changes how the pages of a buffer appear, never what
// it holds: the same values as std::vector::resize, on both sides of the size threshold.
#include "core/prefault.hpp"

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

namespace pw {
namespace {

constexpr std::size_t kLarge = 3 * kPrefaultMinBytes / sizeof(double) + 7;  // beyond the threshold, odd length

TEST(Prefault, AnEmptyBufferResizedPastTheThresholdHoldsOnlyZeros) {
  std::vector<double> v;
  resize_prefaulted(v, kLarge);
  ASSERT_EQ(v.size(), kLarge);
  for (double x : v) ASSERT_EQ(x, 0.0);
}

TEST(Prefault, GrowingKeepsTheValuesAndZeroFillsTheRestLikeResize) {
  for (const std::size_t n : {std::size_t{10}, kLarge}) {
    std::vector<double> v{1.5, -2.0, 3.25}, expected = v;
    expected.resize(n);
    resize_prefaulted(v, n);
    EXPECT_EQ(v, expected) << n;
  }
}

TEST(Prefault, ShrinkingIsResize) {
  std::vector<double> v(kLarge, 4.0);
  resize_prefaulted(v, 5);
  EXPECT_EQ(v, std::vector<double>(5, 4.0));
}

} // namespace
} // namespace pw
