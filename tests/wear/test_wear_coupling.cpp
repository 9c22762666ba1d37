// Wear coupled to the dynamics (wear::simulate with wear.mesh_cycles > 0).
#include "wear/simulation.hpp"

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>

using namespace pw::model;

namespace {

SimulationConfig worn(double rpm, double cycles) {
  SimulationConfig c;
  c.operating.input_speed_rpm = rpm;
  c.solver.record_mesh_cycles = 1;
  c.wear.mesh_cycles = cycles;
  return c;
}

const FlankWearHistory& family(const SimulationResult& r, const std::string& name) {
  for (const auto& f : r.wear.flanks)
    if (f.name == name) return f;
  throw std::runtime_error("no flank family " + name);
}

/// Wear of tooth t at the last update [m] per element.
std::vector<double> last(const FlankWearHistory& f, int tooth) {
  const std::size_t per = static_cast<std::size_t>(f.teeth) * f.elements;
  const auto begin = f.depth_m.end() - static_cast<long>(per) + static_cast<long>(tooth) * f.elements;
  return {begin, begin + f.elements};
}

double max_of(const FlankWearHistory& f) {
  const std::size_t per = static_cast<std::size_t>(f.teeth) * f.elements;
  return *std::max_element(f.depth_m.end() - static_cast<long>(per), f.depth_m.end());
}

constexpr double kPi = std::numbers::pi;

} // namespace

TEST(WearCoupling, SingleContactZoneWearEqualsClosedFormArchard) {
  // No friction (no step at the pitch point), 100 rpm: in the single-contact
  // zone the pair carries F = T_s/(N r_bs) and the sun flank point at roll
  // coordinate xi loses, per pass, kappa (F/b) (1 + Zs/Zp) |xi - xi_P| / xi
  // (W1 with v_s = (w_s + w_p)(xi - xi_P), v_r = w_s xi, relative speeds);
  // each sun tooth makes N/Zs passes per mesh cycle. Element values are
  // arc-length averages over the element (weight xi dxi). Tolerance 3 %:
  // residual dynamic force in the zone (< 2 % after the entry transient).
  SimulationConfig c = worn(100, 1e5);
  c.contact.friction_coefficient = 0;
  const SimulationResult r = pw::wear::simulate(c);
  const FlankWearHistory& sun = family(r, "sun");
  const double rb = 0.5 * 3e-3 * 21 * std::cos(0.349066);
  const double xi_p = rb * std::tan(0.349066);
  const double Ts = 1000.0 / (100 * 2 * kPi / 60);
  const double F = Ts / (3 * rb), kappa = 5e-17, b = 0.05;
  const std::vector<double> w = last(sun, 0);
  int checked = 0;
  for (int e = 0; e < sun.elements; ++e) {
    const double d = sun.distance_from_pitch_point_m[e];
    // single-contact zone of the seed sun mesh: xi in [8.87, 12.31] mm;
    // stay 0.5 mm clear of the pitch point and of the zone's ends.
    const double xi = xi_p + d;
    if (xi < 9.6e-3 || xi > 11.8e-3 || std::fabs(d) < 0.5e-3) continue;
    const double half = 0.5 * (sun.distance_from_pitch_point_m[1] - sun.distance_from_pitch_point_m[0]);
    double num = 0, den = 0;
    for (int q = 0; q < 200; ++q) {  // midpoint rule over the element
      const double x = xi - half + (q + 0.5) * 2 * half / 200;
      num += kappa * F / b * (1 + 21.0 / 30.0) * std::fabs(x - xi_p) / x * x;
      den += x;
    }
    const double expected = num / den * 3.0 / 21.0 * 1e5;
    EXPECT_NEAR(w[e], expected, 0.03 * expected) << "distance from pitch point " << d * 1e3 << " mm";
    ++checked;
  }
  EXPECT_GE(checked, 4);
}

TEST(WearCoupling, NoWearAtPitchPointAndWearGrowsTowardsTipAndRoot) {
  const SimulationResult r = pw::wear::simulate(worn(400, 1e5));
  for (const char* name : {"sun", "planet_0/sun_side", "planet_0/ring_side", "ring"}) {
    const FlankWearHistory& f = family(r, name);
    const std::vector<double> w = last(f, 0);
    const double mx = *std::max_element(w.begin(), w.end());
    ASSERT_GT(mx, 0) << name;
    int ep = 0;
    for (int e = 0; e < f.elements; ++e)
      if (std::fabs(f.distance_from_pitch_point_m[e]) < std::fabs(f.distance_from_pitch_point_m[ep])) ep = e;
    // The element holding the pitch point sees sliding only over its width
    // (|xi - xi_P| < half an element): far below the flank maximum.
    EXPECT_LT(w[ep], 0.1 * mx) << name;
    // Away from the pitch point wear grows on both sides over the next
    // elements (sliding speed ~ distance, load constant within a zone).
    EXPECT_GT(w[ep + 3], w[ep + 1]) << name;
    EXPECT_GT(w[ep - 3], w[ep - 1]) << name;
  }
}

TEST(WearCoupling, SameNumbersForOneAndTwoThreads) {
  SimulationConfig c = worn(400, 5e4);
  omp_set_num_threads(1);
  const SimulationResult a = pw::wear::simulate(c);
  omp_set_num_threads(2);
  const SimulationResult b = pw::wear::simulate(c);
  ASSERT_EQ(a.wear.flanks.size(), b.wear.flanks.size());
  for (std::size_t f = 0; f < a.wear.flanks.size(); ++f)
    EXPECT_EQ(a.wear.flanks[f].depth_m, b.wear.flanks[f].depth_m) << a.wear.flanks[f].name;
  EXPECT_EQ(a.wear.backlash_m, b.wear.backlash_m);
}

TEST(WearCoupling, HalvingTheUpdateBoundChangesFinalMaxWearByLessThanTwoPercent) {
  // Wear made larger than the elastic deflection (kappa x 200: ~2 um of sun
  // wear against ~0.3 um static deflection at 400 rpm), so the increment
  // bound, not the minimum number of updates, sets dN and the coupling
  // matters. Short windows keep the test fast.
  SimulationConfig c = worn(400, 2e5);
  c.wear.coefficient_m2_N = 1e-14;
  c.wear.window_mesh_cycles = 6;
  c.wear.max_increment_fraction = 0.4;
  const SimulationResult coarse = pw::wear::simulate(c);
  c.wear.max_increment_fraction = 0.2;
  const SimulationResult fine = pw::wear::simulate(c);
  EXPECT_GT(fine.wear.mesh_cycles.size(), coarse.wear.mesh_cycles.size()) << "the bound must be active";
  EXPECT_GT(coarse.wear.mesh_cycles.size(), 9u) << "more than the minimum 8 updates";
  const double wc = max_of(family(coarse, "sun")), wf = max_of(family(fine, "sun"));
  std::cout << "max sun wear: bound 0.4 -> " << wc << " m (" << coarse.wear.mesh_cycles.size() - 1
            << " updates), bound 0.2 -> " << wf << " m (" << fine.wear.mesh_cycles.size() - 1
            << " updates), change " << 100 * (wc - wf) / wf << " %\n";
  EXPECT_NEAR(wc, wf, 0.02 * wf);
}

TEST(WearCoupling, WearIsMonotoneInKappaAndInLoad) {
  SimulationConfig c = worn(400, 5e4);
  const double w0 = max_of(family(pw::wear::simulate(c), "sun"));
  c.wear.coefficient_m2_N *= 2;
  const double wk = max_of(family(pw::wear::simulate(c), "sun"));
  c.wear.coefficient_m2_N /= 2;
  c.operating.input_power_W *= 2;
  const double wl = max_of(family(pw::wear::simulate(c), "sun"));
  EXPECT_NEAR(wk, 2 * w0, 0.01 * w0);  // wear << deflection: linear in kappa
  EXPECT_GT(wl, 1.5 * w0);
}

TEST(WearCoupling, BacklashGrowsByTheMeanFlankWearOfBothGears) {
  const SimulationResult r = pw::wear::simulate(worn(400, 1e5));
  const auto mean_last = [&](const std::string& name) {
    const FlankWearHistory& f = family(r, name);
    const std::size_t per = static_cast<std::size_t>(f.teeth) * f.elements;
    double s = 0;
    for (auto it = f.depth_m.end() - static_cast<long>(per); it != f.depth_m.end(); ++it) s += *it;
    return s / static_cast<double>(per);
  };
  double planets = 0;
  for (int i = 0; i < 3; ++i) planets += mean_last("planet_" + std::to_string(i) + "/sun_side") / 3;
  const double b_sp = r.wear.backlash_m[r.wear.backlash_m.size() - 2];
  EXPECT_GT(b_sp, 0);
  EXPECT_NEAR(b_sp, mean_last("sun") + planets, 1e-12 * b_sp + 1e-18);
  EXPECT_EQ(r.wear.backlash_m[0], 0.0);
}

TEST(WearCoupling, ExcessiveWearStopsEarlyAndKeepsTheHistory) {
  SimulationConfig c = worn(400, 2e5);
  c.wear.max_wear_fraction_of_thickness = 1e-6;  // ~5 nm of a 4.7 mm tooth
  const SimulationResult r = pw::wear::simulate(c);
  EXPECT_NE(r.wear.stop_reason.find("wear.max_wear_fraction_of_thickness"), std::string::npos) << r.wear.stop_reason;
  EXPECT_LT(r.wear.mesh_cycles.back(), 2e5);
  EXPECT_GE(r.wear.mesh_cycles.size(), 2u);
}
