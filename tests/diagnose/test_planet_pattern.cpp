// Planet pattern (diagnose/planet_pattern.hpp): the order k(h) = min(r, N - r), r = h Zs mod N,
// checked against the phase sum it stands for (sum over the planets of exp(-2 pi i h i Zs / N)
// times a pattern eps_i vanishes unless eps has a DFT component at k); the split of a
// mesh-harmonic excess by order, its z, and the sentence for the three cases.
#include "diagnose/planet_pattern.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <string>

using namespace pw::diagnose;

namespace {

/// |sum_i eps_i exp(-2 pi i h i Zs / N)| for the pattern eps_i = cos(2 pi k i / N) (k = 0: 1).
double phase_sum(int h, int zs, int n, int k) {
  std::complex<double> s = 0;
  for (int i = 0; i < n; ++i) {
    const double eps = std::cos(2 * std::numbers::pi * k * i / n);
    s += eps * std::exp(std::complex<double>(0, -2 * std::numbers::pi * h * i * zs / static_cast<double>(n)));
  }
  return std::abs(s);
}

Kinematics stage(int zs, int n) {
  Kinematics k;
  k.sun_teeth = zs;
  k.planet_teeth = 21;
  k.ring_teeth = 69;
  k.planets = n;
  return k;
}

} // namespace

TEST(PlanetPattern, TheOrderOfAHarmonicIsThePatternWhosePhaseSumOverThePlanetsDoesNotVanish) {
  // Every (h, Zs, N) of a few stages: the pattern of order k(h) survives the phase sum, every
  // other order of the same stage cancels to round-off.
  for (int n : {3, 4, 5, 6})
    for (int zs : {17, 21, 27, 28, 31})
      for (int h = 1; h <= 12; ++h) {
        const int k = planet_pattern_order(h, zs, n);
        ASSERT_GE(k, 0);
        ASSERT_LE(k, n / 2);
        for (int j = 0; j <= n / 2; ++j) {
          const double s = phase_sum(h, zs, n, j);
          if (j == k)
            EXPECT_GT(s, 0.4 * n) << "h " << h << " Zs " << zs << " N " << n << " k " << k;
          else
            EXPECT_LT(s, 1e-9 * n) << "h " << h << " Zs " << zs << " N " << n << " j " << j << " k " << k;
        }
      }
  // setD4 (27 sun teeth, 4 planets): odd harmonics need k = 1, h = 2, 6, 10 need k = 2, h = 4, 8 none.
  EXPECT_EQ(planet_pattern_order(1, 27, 4), 1);
  EXPECT_EQ(planet_pattern_order(2, 27, 4), 2);
  EXPECT_EQ(planet_pattern_order(4, 27, 4), 0);
  EXPECT_EQ(planet_pattern_order(7, 27, 4), 1);
}

TEST(PlanetPattern, SplitsTheExcessByOrderWithItsZAndSaysWhatTheOrdersAllow) {
  // setD4's pin error: h = 1 and 2 and 6 in excess, h = 4 and 8 (the healthy lines) explained.
  const std::vector<MeshHarmonicCell> cells = {{1, {5000, 5200}}, {2, {300, 310}}, {4, {0.5, -0.8}},
                                               {6, {40, 38}}, {8, {-0.3, 1.1}}, {3, {0.2, -0.4}}};
  const PlanetPattern p = planet_pattern(cells, stage(27, 4), 0.01);
  ASSERT_TRUE(p.applies);
  ASSERT_EQ(p.orders.size(), 3u);
  EXPECT_EQ(p.orders[1].harmonics, (std::vector<int>{1, 3}));
  EXPECT_EQ(p.orders[2].harmonics, (std::vector<int>{2, 6}));
  EXPECT_EQ(p.orders[0].harmonics, (std::vector<int>{4, 8}));
  EXPECT_DOUBLE_EQ(p.orders[2].excess, 688.0);
  EXPECT_EQ(p.orders[2].cells, 4);
  EXPECT_DOUBLE_EQ(p.orders[2].z, 688.0 / std::sqrt(8.0));
  EXPECT_NEAR(p.significance_z, 2.7131, 1e-4);  // alpha 0.01 over 3 orders: the upper 0.01/3 normal quantile
  const std::string pin = planet_pattern_text(p);
  EXPECT_NE(pin.find("k = 1 (h 1, 3;"), std::string::npos) << pin;
  EXPECT_NE(pin.find("k = 2 (h 2, 6;"), std::string::npos) << pin;
  EXPECT_EQ(pin.find("k = 0"), std::string::npos) << pin;  // not significant
  EXPECT_NE(pin.find("not in a first-order pattern alone"), std::string::npos) << pin;
  // A carrier runout: odd harmonics alone.
  const PlanetPattern runout = planet_pattern({{1, {9000, 9100}}, {7, {30, 28}}, {2, {0.1, 0.3}}}, stage(27, 4), 0.01);
  EXPECT_NE(planet_pattern_text(runout).find("a first-order pattern (as a carrier runout makes)"), std::string::npos);
  // A change every planet shares: only the harmonics that survive the phasing.
  const PlanetPattern shared = planet_pattern({{4, {800, 790}}, {8, {90, 95}}, {1, {-0.5, 0.2}}}, stage(27, 4), 0.01);
  EXPECT_NE(planet_pattern_text(shared).find(": a change every planet shares"), std::string::npos);
}

TEST(PlanetPattern, PlanetsInPhaseOrNoSpeedChannelLeaveTheSplitUnmade) {
  const std::vector<MeshHarmonicCell> cells = {{1, {5000, 5200}}};
  EXPECT_FALSE(planet_pattern(cells, stage(28, 4), 0.01).applies);  // 4 | 28: every h maps to k = 0
  EXPECT_FALSE(planet_pattern(cells, stage(27, 1), 0.01).applies);
  EXPECT_FALSE(planet_pattern({}, stage(27, 4), 0.01).applies);
  EXPECT_EQ(planet_pattern_text(planet_pattern(cells, stage(28, 4), 0.01)), "");
}
