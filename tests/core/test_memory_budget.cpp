// Checked size arithmetic and the memory limit (issue 19, point 7): an
// overflowing or oversized count is an InputError naming the key, and the
// limit comes from the machine unless PLANETWEAR_MEMORY_LIMIT overrides it.
#include "core/checked_size.hpp"
#include "core/memory_budget.hpp"

#include "core/memory_env.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <limits>

namespace pw {
namespace {

using pw::test::contains;
using pw::test::thrown;

TEST(CheckedSize, ProductsThatFitAreExact) {
  EXPECT_EQ(checked_mul(1'000'000, 12'800, "k"), 12'800'000'000LL);
  EXPECT_EQ(checked_add(std::numeric_limits<std::int64_t>::max() - 1, 1, "k"), std::numeric_limits<std::int64_t>::max());
  EXPECT_EQ(checked_int(2'000'000'000, "k"), 2'000'000'000);
}

TEST(CheckedSize, OverflowAndNegativeCountsNameTheKey) {
  const std::int64_t big = std::int64_t{1} << 40;
  for (const auto& e : {thrown<InputError>([&] { (void)checked_mul(big, big, "solver.record_mesh_cycles"); }),
                        thrown<InputError>([&] { (void)checked_mul(-1, 3, "solver.record_mesh_cycles"); }),
                        thrown<InputError>([&] { (void)checked_add(std::numeric_limits<std::int64_t>::max(), 1,
                                                                   "solver.record_mesh_cycles"); }),
                        thrown<InputError>([&] { (void)checked_int(big, "solver.record_mesh_cycles"); })}) {
    ASSERT_TRUE(e);
    EXPECT_EQ(e->parameter(), "solver.record_mesh_cycles");
  }
}

TEST(MemoryBudget, ByteSizesTakeBinarySuffixes) {
  EXPECT_EQ(parse_byte_size("4096", "x"), 4096u);
  EXPECT_EQ(parse_byte_size("512M", "x"), 512ull << 20);
  EXPECT_EQ(parse_byte_size("1.5G", "x"), 3ull << 29);
  EXPECT_EQ(parse_byte_size("2GiB", "x"), 2ull << 30);
  EXPECT_EQ(parse_byte_size("1t", "x"), 1ull << 40);
  for (const char* bad : {"", "G", "0", "-1G", "5X", "1e30", "nan"}) {
    const auto e = thrown<InputError>([&] { (void)parse_byte_size(bad, "PLANETWEAR_MEMORY_LIMIT"); });
    ASSERT_TRUE(e) << bad;
    EXPECT_EQ(e->parameter(), "PLANETWEAR_MEMORY_LIMIT");
  }
}

TEST(MemoryBudget, DefaultLimitIsAtMostHalfThePhysicalMemory) {
  test::MemoryLimitOverride none("");  // empty = unset
  const double physical = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGE_SIZE));
  const auto limit = static_cast<double>(memory_limit_bytes());
  EXPECT_GT(limit, 0.0);
  EXPECT_LE(limit, 0.5 * physical + 1);
}

TEST(MemoryBudget, EnvironmentVariableOverridesTheLimit) {
  test::MemoryLimitOverride limit("3M");
  EXPECT_EQ(memory_limit_bytes(), 3u << 20);
}

TEST(MemoryBudget, AnEstimateOverTheLimitIsRefusedWithEstimateLimitAndRemedy) {
  test::MemoryLimitOverride limit("1M");
  EXPECT_NO_THROW(require_memory(1024.0 * 1024.0, "solver.record_mesh_cycles", "recording", "lower it"));
  const auto e = thrown<InputError>(
      [] { require_memory(3.0 * 1024 * 1024, "solver.record_mesh_cycles", "recording 5 mesh cycles", "lower it"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "solver.record_mesh_cycles");
  EXPECT_TRUE(contains(e->what(), "recording 5 mesh cycles would need about 3 MiB"));
  EXPECT_TRUE(contains(e->what(), "memory limit 1 MiB"));
  EXPECT_TRUE(contains(e->what(), "PLANETWEAR_MEMORY_LIMIT"));
  EXPECT_TRUE(contains(e->what(), "lower it"));
}

TEST(MemoryBudget, AMalformedEnvironmentVariableIsAnInputErrorNamingIt) {
  test::MemoryLimitOverride limit("lots");
  const auto e = thrown<InputError>([] { (void)memory_limit_bytes(); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "PLANETWEAR_MEMORY_LIMIT");
}

} // namespace
} // namespace pw
