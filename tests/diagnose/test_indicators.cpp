// Gear averages of a planetary stage's signals (diagnose/indicators.hpp):
// the planet-separated TSA recovers each planet's own pattern from a housing
// signal in which the planets take turns, the plain TSAs have the right mesh
// orders, and too-short signals are reported, not averaged.
#include "core/error.hpp"
#include "diagnose/indicators.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace {

namespace dg = pw::diagnose;
constexpr double kPi = std::numbers::pi;

/// Planet i's own vibration pattern, periodic in Zp mesh cycles (v in mesh cycles).
double pattern(int i, double v, int zp) { return (i + 1) * std::cos(2 * kPi * 3 * v / zp + i) + 0.2 * i; }

struct Synthetic {
  std::vector<double> t, theta, x;
};

/// A housing signal in which the planet nearest the sensor (within pi/N) is all the sensor sees:
/// x = pattern of that planet. S samples per mesh cycle, constant speed, `revs` carrier revolutions.
Synthetic planets_take_turns(const pw::model::SimulationConfig& c, int s, int revs, double sensor_rad) {
  const int zp = c.stage.planet.teeth, zr = c.stage.ring.teeth, n = c.stage.planet_count;
  Synthetic y;
  const double dt = 1e-4;  // [s]; only the angle matters
  for (int j = 0; j < revs * zr * s; ++j) {
    const double u = static_cast<double>(j) / s;  // mesh cycles
    const double theta = 2 * kPi * u / zr;
    int nearest = 0;
    double best = 10;
    for (int i = 0; i < n; ++i) {
      const double d = std::abs(std::remainder(2 * kPi * i / n + theta - sensor_rad, 2 * kPi));
      if (d < best) best = d, nearest = i;
    }
    y.t.push_back(j * dt);
    y.theta.push_back(theta);
    y.x.push_back(pattern(nearest, std::fmod(u, zp), zp));
  }
  return y;
}

TEST(GearAverages, PlanetSeparatedAverageRecoversEachPlanetsPattern) {
  const pw::model::SimulationConfig c;  // seed: Zs 21, Zp 30, Zr 81, 3 planets
  const int s = 32, zp = c.stage.planet.teeth;
  const double sensor = 0.3;
  const Synthetic y = planets_take_turns(c, s, 6, sensor);
  const dg::ChannelSignal ch{"acc", dg::Quantity::HousingAcceleration, "m/s^2", 0, sensor, y.x};
  dg::IndicatorOptions o;
  o.samples_per_mesh = s;
  std::vector<dg::SkippedAverage> skipped;
  const auto avg = dg::gear_averages(y.t, y.theta, ch, c, o, &skipped);
  EXPECT_TRUE(skipped.empty()) << skipped.front().reason;
  int planets_seen = 0;
  for (const dg::GearAverage& a : avg) {
    if (a.gear != "planet") continue;
    ++planets_seen;
    ASSERT_EQ(a.tsa.size(), static_cast<std::size_t>(zp * s));
    EXPECT_EQ(a.teeth, zp);
    // The window is non-zero exactly where this planet is the nearest: every sample it weighs is the
    // planet's own pattern, sampled on the input grid (interpolation at the nodes): exact to round-off.
    for (std::size_t j = 0; j < a.tsa.size(); ++j)
      EXPECT_NEAR(a.tsa[j], pattern(a.planet, static_cast<double>(j) / s, zp), 1e-9) << a.planet << " " << j;
  }
  EXPECT_EQ(planets_seen, c.stage.planet_count);
}

TEST(GearAverages, PlainAveragesHaveTheGearsMeshOrderAndReportShortSignals) {
  const pw::model::SimulationConfig c;
  const int s = 16;
  const Synthetic y = planets_take_turns(c, s, 2, 0.0);
  const dg::ChannelSignal sp{"sp", dg::Quantity::MeshAccelerationSunPlanet, "m/s^2", 1, 0.0, y.x};
  dg::IndicatorOptions o;
  o.samples_per_mesh = s;
  const auto avg = dg::gear_averages(y.t, y.theta, sp, c, o, nullptr);
  ASSERT_EQ(avg.size(), 2u);
  EXPECT_EQ(avg[0].gear, "sun");
  EXPECT_EQ(avg[0].teeth, c.stage.sun.teeth);
  EXPECT_EQ(avg[0].revolutions, 2 * c.stage.ring.teeth / c.stage.sun.teeth);  // 162 / 21 = 7 whole revolutions
  EXPECT_EQ(avg[1].gear, "planet");
  EXPECT_EQ(avg[1].planet, 1);
  // Half a carrier revolution: no carrier average (81 mesh cycles), planet-ring channel says so.
  const std::size_t half = y.t.size() / 4;
  const dg::ChannelSignal pr{"pr", dg::Quantity::MeshAccelerationPlanetRing, "m/s^2", 0, 0.0,
                             std::span<const double>(y.x).first(half)};
  std::vector<dg::SkippedAverage> skipped;
  const auto short_avg = dg::gear_averages(std::span<const double>(y.t).first(half),
                                           std::span<const double>(y.theta).first(half), pr, c, o, &skipped);
  ASSERT_EQ(short_avg.size(), 1u);
  EXPECT_EQ(short_avg[0].gear, "planet");
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0].gear, "carrier");
  EXPECT_NE(skipped[0].reason.find("81 mesh cycles"), std::string::npos) << skipped[0].reason;
}

TEST(GearAverages, RejectsOptionsOutOfRangeNamingTheOption) {
  const pw::model::SimulationConfig c;
  const Synthetic y = planets_take_turns(c, 16, 1, 0.0);
  const dg::ChannelSignal ch{"acc", dg::Quantity::HousingAcceleration, "m/s^2", 0, 0.0, y.x};
  auto message = [&](dg::IndicatorOptions o) -> std::string {
    try {
      dg::gear_averages(y.t, y.theta, ch, c, o, nullptr);
    } catch (const pw::InputError& e) {
      return e.what();
    }
    return "<none>";
  };
  dg::IndicatorOptions o;
  o.samples_per_mesh = 3;
  EXPECT_NE(message(o).find("--samples-per-mesh"), std::string::npos);
  o = {};
  o.shaft_harmonics = 9;
  EXPECT_NE(message(o).find("--shaft-harmonics"), std::string::npos);
  o = {};
  o.planet_window_half_width_rad = 4.0;
  EXPECT_NE(message(o).find("--planet-window-deg"), std::string::npos);
}

} // namespace
