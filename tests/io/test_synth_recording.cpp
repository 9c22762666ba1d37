// End to end: what `planetwear synth` writes, io::read_recording reads
// (needs the planetwear executable of this build: $PW_BINARY_DIR/apps, else
// apps/ beside this test's tests/ directory).
#include "io/recording_reader.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

using namespace pw;
using diagnose::Quantity;

TEST(SynthRecording, ReaderTakesWhatSynthWrites) {
  const char* bin = std::getenv("PW_BINARY_DIR");
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path exe = bin && *bin ? std::filesystem::path(bin) / "apps" / "planetwear"
                                                : self.parent_path().parent_path() / "apps" / "planetwear";
  if (!std::filesystem::exists(exe)) GTEST_SKIP() << "planetwear executable not found: " << exe;
  test::TempDir dir;
  const auto csv = dir / "rec.csv";
  const std::string cmd = exe.string() +
                          " synth -q --speed-rpm 1200 --power-w 20000 --seconds 0.8 --decimate 40 --noise 0.05 "
                          "--dc-offset 0.3 --seed 3 --sensor-angle-deg 45 --start-mesh-cycle 80 --tacho "
                          "--set solver.periodicity_tolerance=0.05 --set 'imperfections.teeth=[{body=\"ring\",tooth=3,"
                          "stiffness_factor=0.7}]' -o " + csv.string();
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  const io::RecordingMeta meta = io::read_recording_meta(dir / "rec.json");
  const diagnose::Recording r = io::read_recording(csv, meta, model::SimulationConfig{});
  EXPECT_EQ(r.operating.input_speed_rpm, 1200);
  EXPECT_EQ(r.operating.input_power_W, 20000);
  ASSERT_EQ(r.channels.size(), 6u);
  for (Quantity q : {Quantity::SunSpeed, Quantity::CarrierSpeed, Quantity::MeshAccelerationSunPlanet,
                     Quantity::MeshAccelerationPlanetRing, Quantity::HousingAcceleration, Quantity::Tacho})
    EXPECT_TRUE(r.find(q)) << diagnose::to_string(q);
  EXPECT_NEAR(r.find(Quantity::HousingAcceleration)->sensor_angle_rad, std::numbers::pi / 4, 1e-12);
  const double fm = 21.0 * 81.0 / 102.0 * 1200 / 60;
  EXPECT_NEAR(r.time_s.front(), 80 / fm, 1e-9) << "starts at absolute mesh cycle 80";
  EXPECT_NEAR(static_cast<double>(r.time_s.size()) * r.sample_interval_s(), 0.8, 2 * r.sample_interval_s());
  double mean = 0;
  for (double w : r.find(Quantity::SunSpeed)->values) mean += w / static_cast<double>(r.time_s.size());
  EXPECT_NEAR(mean, 1200 * 2 * std::numbers::pi / 60, 0.01 * 125.66);
}
