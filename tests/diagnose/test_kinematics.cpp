// Kinematic frequencies and tooth passages of the seed stage, by hand.
#include "diagnose/kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace pw::diagnose {
namespace {

TEST(Kinematics, SeedFrequenciesByHand) {
  // Seed: Zs = 21, Zp = 30, Zr = 81, N = 3; 400 rpm input.
  const Kinematics k = kinematics(model::StageSpec{}, 400.0);
  const double fs = 400.0 / 60.0;                  // 6.6667 Hz
  const double fc = fs * 21.0 / (21.0 + 81.0);     // 1.37255 Hz
  EXPECT_NEAR(k.sun_Hz, fs, 1e-12);
  EXPECT_NEAR(k.carrier_Hz, fc, 1e-12);
  EXPECT_NEAR(k.sun_relative_Hz, fs - fc, 1e-12);  // 5.29412 Hz
  EXPECT_NEAR(k.mesh_Hz, 81.0 * fc, 1e-12);        // 111.176 Hz
  EXPECT_NEAR(k.mesh_Hz, 21.0 * (fs - fc), 1e-9);  // the same from the sun side
  EXPECT_NEAR(k.planet_relative_Hz, k.mesh_Hz / 30.0, 1e-12);
  EXPECT_NEAR(k.mesh_Hz, 111.17647058823529, 1e-9);
  EXPECT_NEAR(k.period_mesh_cycles(Component::Sun), 21.0, 1e-9);
  EXPECT_NEAR(k.period_mesh_cycles(Component::Planet), 30.0, 1e-9);
  EXPECT_NEAR(k.period_mesh_cycles(Component::Carrier), 81.0, 1e-9);
}

TEST(Kinematics, FamilyLinesAreMeshHarmonicsPlusSidebands) {
  const Kinematics k = kinematics(model::StageSpec{}, 400.0);
  const auto lines = family_lines(k, Component::Sun, 1, 2, 1000.0);
  // a = 0: f_sr, 2 f_sr; a = 1: f_m +- f_sr, f_m +- 2 f_sr.
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_NEAR(lines[0].frequency_Hz, k.sun_relative_Hz, 1e-12);
  EXPECT_EQ(lines[0].label, "1 f_sr");
  bool found = false;
  for (const auto& l : lines)
    if (l.mesh_harmonic == 1 && l.sideband == -2) {
      EXPECT_NEAR(l.frequency_Hz, k.mesh_Hz - 2 * k.sun_relative_Hz, 1e-12);
      EXPECT_EQ(l.label, "1 f_m - 2 f_sr");
      found = true;
    }
  EXPECT_TRUE(found);
  const auto mesh = family_lines(k, Component::Mesh, 3, 5, 1000.0);
  ASSERT_EQ(mesh.size(), 3u);
  EXPECT_NEAR(mesh[2].frequency_Hz, 3 * k.mesh_Hz, 1e-12);
}

TEST(Kinematics, OrderLinesDoNotDependOnTheSpeed) {
  // In carrier orders: mesh Zr = 81, sun Zr/Zs = 27/7, planet Zr/Zp = 2.7, input (Zs+Zr)/Zs.
  for (double rpm : {200.0, 400.0, 1800.0}) {
    const Kinematics k = kinematics(model::StageSpec{}, rpm);
    EXPECT_NEAR(carrier_orders(k, Component::Mesh), 81.0, 1e-9);
    EXPECT_NEAR(carrier_orders(k, Component::Sun), 27.0 / 7.0, 1e-9);
    EXPECT_NEAR(carrier_orders(k, Component::Planet), 2.7, 1e-9);
    EXPECT_NEAR(carrier_orders(k, Component::InputShaft), 102.0 / 21.0, 1e-9);
    const auto lines = order_lines(k, Component::Sun, 1, 1, 100.0);
    ASSERT_EQ(lines.size(), 3u);  // 27/7, 81 - 27/7, 81 + 27/7
    EXPECT_NEAR(lines[1].order, 81 - 27.0 / 7.0, 1e-9);
    EXPECT_EQ(lines[1].label, "1 f_m - 1 f_sr");
  }
}

TEST(Kinematics, ConsecutiveTeethPassOneMeshCycleApart) {
  const model::SimulationConfig c;
  const ToothMap map(c);
  for (auto [body, mesh, z] : {std::tuple{model::Body::Sun, ToothMap::Mesh::SunPlanet, 21},
                               std::tuple{model::Body::Planet, ToothMap::Mesh::SunPlanet, 30},
                               std::tuple{model::Body::Planet, ToothMap::Mesh::PlanetRing, 30},
                               std::tuple{model::Body::Ring, ToothMap::Mesh::PlanetRing, 81}}) {
    for (int j = 0; j < z; ++j) {
      const double u0 = map.passage_mesh_cycle(body, 0, j, mesh);
      const double u1 = map.passage_mesh_cycle(body, 0, (j + 1) % z, mesh);
      EXPECT_NEAR(std::fmod(u1 - u0 + z, z), 1.0, 1e-9) << "tooth " << j;
      EXPECT_EQ(map.nearest_tooth(body, 0, mesh, u0 + 0.3), j);
    }
  }
}

} // namespace
} // namespace pw::diagnose
