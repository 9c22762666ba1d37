// Stage kinematics with the ring fixed (config/stage.hpp): the closed forms of Willis'
// equation and the two ways of counting the teeth that pass one mesh.
#include "config/stage.hpp"

#include <gtest/gtest.h>

#include <array>

namespace {

using pw::model::StageSpec;

StageSpec stage(int zs, int zp, int zr) {
  StageSpec s;
  s.sun.teeth = zs;
  s.planet.teeth = zp;
  s.ring.teeth = zr;
  return s;
}

// Seed gears 21/30/81 (Bai & Ning 2023, Table 1): w_c / w_s = 21 / 102.
TEST(StageKinematics, CarrierRatioOfSeedGearsIsZsOverZsPlusZr) {
  const StageSpec s = stage(21, 30, 81);
  EXPECT_DOUBLE_EQ(pw::model::carrier_to_sun_ratio(s), 21.0 / 102.0);
  EXPECT_DOUBLE_EQ(pw::model::carrier_speed(s, 102.0), 21.0);
}

// f_m = Z_r f_c (ring teeth passing a planet fixed to the carrier) = Z_s (f_s - f_c) (sun
// teeth passing it): both counts give the same frequency, to round-off.
TEST(StageKinematics, MeshFrequencyCountsRingTeethAndSunTeethAlike) {
  constexpr std::array<std::array<int, 3>, 3> kSets{{{21, 30, 81}, {18, 27, 72}, {17, 31, 79}}};
  for (const auto& [zs, zp, zr] : kSets) {
    const StageSpec s = stage(zs, zp, zr);
    const double rpm = 1234.5, fs = rpm / 60.0, fc = pw::model::carrier_speed(s, fs);
    const double fm = pw::model::mesh_frequency_Hz(s, rpm);
    EXPECT_NEAR(fm, zr * fc, 1e-12 * fm);
    EXPECT_NEAR(fm, zs * (fs - fc), 1e-12 * fm);
  }
}

// 100 rpm on the seed gears: f_m = 21 * 81 / 102 * 100 / 60 = 27.794... Hz (seed §5: 27.8 Hz).
TEST(StageKinematics, SeedMeshFrequencyAt100RpmIs27point8Hz) {
  EXPECT_NEAR(pw::model::mesh_frequency_Hz(stage(21, 30, 81), 100.0), 21.0 * 81.0 / 102.0 * 100.0 / 60.0, 1e-12);
  EXPECT_NEAR(pw::model::mesh_frequency_Hz(stage(21, 30, 81), 100.0), 27.79, 0.01);
}

TEST(StageKinematics, SunSpeedInvertsCarrierSpeed) {
  const StageSpec s = stage(18, 27, 72);
  for (double w : {0.1, 1.0, 104.7, 3000.0}) EXPECT_NEAR(pw::model::sun_speed(s, pw::model::carrier_speed(s, w)), w, 1e-14 * w);
}

} // namespace
