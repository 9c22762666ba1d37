// Oversized runs are refused before anything large is allocated or computed
// (issue 19, point 7): the message names the key to change and the estimate.
#include "model/memory_estimate.hpp"
#include "model/simulation.hpp"

#include "core/error.hpp"
#include "core/memory_env.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace pw::model {
namespace {

using pw::test::contains;
using pw::test::thrown;

TEST(MemoryEstimate, RecordBytesGrowWithCyclesAndChannelsAndShrinkWithDecimation) {
  SimulationConfig c;
  c.solver.record_mesh_cycles = 1'000'000;
  const double all = record_bytes(c, 12'800, 1, 40);
  // 1e6 x 12800 steps overflowed int; as a double it is exact enough to refuse.
  EXPECT_DOUBLE_EQ(all, 2.0 * 1e6 * 12'800 * 41 * 8);
  EXPECT_DOUBLE_EQ(record_bytes(c, 12'800, 32, 40), 2.0 * 1e6 * 400 * 41 * 8);
  EXPECT_LT(record_bytes(c, 12'800, 1, 2), all / 10);
}

TEST(MemoryEstimate, SimulateRefusesAnOversizedRecordingBeforeTheWarmUp) {
  test::MemoryLimitOverride limit("64M");
  SimulationConfig c;
  c.solver.record_mesh_cycles = 1'000'000;
  const auto t0 = std::chrono::steady_clock::now();
  const auto e = thrown<InputError>([&] { (void)simulate(c); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "solver.record_mesh_cycles");
  EXPECT_TRUE(contains(e->what(), "recording 1000000 mesh cycles"));
  EXPECT_TRUE(contains(e->what(), "--time-history-decimation"));
  // Refused at the estimate, not after minutes of warm-up.
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 30.0);
}

TEST(MemoryEstimate, DecimationAndChannelSelectionBringARecordingUnderTheLimit) {
  SimulationConfig c;
  c.solver.record_mesh_cycles = 1000;
  const int spm = prepare(c).steps_per_mesh;
  test::MemoryLimitOverride limit(std::to_string(static_cast<long long>(record_bytes(c, spm, 1, 2) * 1.01)));
  EXPECT_TRUE(thrown<InputError>([&] { check_run_memory(c, spm, 1, 40); }));
  EXPECT_FALSE(thrown<InputError>([&] { check_run_memory(c, spm, 1, 2); }));
  EXPECT_FALSE(thrown<InputError>([&] { check_run_memory(c, spm, 20, 40); }));
}

TEST(MemoryEstimate, TheFlankStateIsRefusedNamingElementsPerFlank) {
  test::MemoryLimitOverride limit("1M");
  SimulationConfig c;
  c.wear.elements_per_flank = 10'000;
  c.wear.mesh_cycles = 1e5;
  const auto e = thrown<InputError>([&] { (void)prepare(c); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "wear.elements_per_flank");
}

TEST(MemoryEstimate, ManySnapshotsAreRefusedNamingTheSnapshotList) {
  test::MemoryLimitOverride limit("16M");
  SimulationConfig c;
  c.wear.mesh_cycles = 1e5;
  c.wear.snapshot_mesh_cycles.assign(10'000, 0.0);
  const auto e = thrown<InputError>([&] { check_run_memory(c, 12'800, 1, 1); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "wear.snapshot_mesh_cycles");
}

TEST(MemoryEstimate, StepsPerMeshBeyondIntRangeNameTheTimeStepOrTheSpeed) {
  SimulationConfig c;
  c.solver.time_step_s = 1e-12;  // valid (<= T_mesh / 8) but 3.6e10 steps per mesh period
  auto e = thrown<InputError>([&] { (void)prepare(c); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "solver.time_step_s");
  c = SimulationConfig{};
  c.operating.input_speed_rpm = 1e-4;  // in range; a mesh period of hours
  e = thrown<InputError>([&] { (void)prepare(c); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_EQ(checked_steps_per_mesh(SimulationConfig{}, 1.0, 0.25), 4);
}

} // namespace
} // namespace pw::model
