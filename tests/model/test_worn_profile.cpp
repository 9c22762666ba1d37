// Pre-existing worn profile (imperfections.worn_profile_depth_m, applied in
// model::prepare): Archard shape from the slide-to-roll ratio
// (docs/derivation.md §5, W1), its normalization, and its effect on the
// contact: pairs far from the pitch point carry less load.
#include "model/simulation.hpp"

#include "imposed_deflection.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace pw::model;

namespace {

/// Slide-to-roll ratio of A's flank for the external sun mesh from the
/// angular speeds (carrier-relative), written independently of simulation.cpp:
/// |v_s| / (w_A rho_A) with v_s = (w_A + w_B)(xi - xi_P), w_B / w_A = r_bA / r_bB.
double sun_flank_ratio(const pw::geometry::MeshGeometry& g, double xi) {
  const double wa = 1.0, wb = g.base_radius_a_m / g.base_radius_b_m;
  return (wa + wb) * std::fabs(xi - g.pitch_point_m) / (wa * xi);
}

/// ... and of B's flank (the planet's sun side): rho_B = L - xi.
double planet_flank_ratio(const pw::geometry::MeshGeometry& g, double xi) {
  const double wa = 1.0, wb = g.base_radius_a_m / g.base_radius_b_m;
  return (wa + wb) * std::fabs(xi - g.pitch_point_m) / (wb * (g.tangent_distance_m - xi));
}

} // namespace

TEST(WornProfile, IsArchardShapedWithTheGivenMaximumOnEveryFlankFamily) {
  SimulationConfig c;
  c.imperfections.worn_profile_depth_m = 1.5e-6;
  PreparedStage p = prepare(c);
  const ToothSurfaces& s = p.dynamics->surfaces();
  const auto& gs = p.geometry.sun_planet;
  std::vector<const FlankSet*> families{&s.sun, &s.ring};
  for (const auto& f : s.planet_sun_side) families.push_back(&f);
  for (const auto& f : s.planet_ring_side) families.push_back(&f);
  for (const FlankSet* f : families) {
    EXPECT_NEAR(f->max_deviation_m(), 1.5e-6, 1e-18);
    // Every tooth alike.
    for (int t = 1; t < f->teeth(); ++t)
      for (int e = 0; e < f->elements(); ++e) ASSERT_EQ(f->tooth_deviation(t)[e], f->tooth_deviation(0)[e]);
  }
  // Sun and planet (sun side): depth / max = ratio / max ratio, from the speeds.
  double rs = 0, rp = 0;
  for (int e = 0; e < s.sun.elements(); ++e) {
    rs = std::max(rs, sun_flank_ratio(gs, s.sun.element_xi_m(e)));
    rp = std::max(rp, planet_flank_ratio(gs, s.sun.element_xi_m(e)));
  }
  int near_pitch = 0;
  for (int e = 0; e < s.sun.elements(); ++e) {
    const double xi = s.sun.element_xi_m(e);
    EXPECT_NEAR(s.sun.tooth_deviation(0)[e], 1.5e-6 * sun_flank_ratio(gs, xi) / rs, 1e-15) << e;
    EXPECT_NEAR(s.planet_sun_side[0].tooth_deviation(0)[e], 1.5e-6 * planet_flank_ratio(gs, xi) / rp, 1e-15) << e;
    if (std::fabs(xi - gs.pitch_point_m) < std::fabs(s.sun.element_xi_m(near_pitch) - gs.pitch_point_m))
      near_pitch = e;
  }
  // Zero at the pitch point (within half an element), deepest towards the
  // sun's root (small xi: the dedendum slides fastest relative to its roll).
  EXPECT_LT(s.sun.tooth_deviation(0)[near_pitch], 0.05 * 1.5e-6);
  EXPECT_EQ(s.sun.tooth_deviation(0)[0], 1.5e-6);
  EXPECT_EQ(s.planet_sun_side[0].tooth_deviation(0)[s.sun.elements() - 1], 1.5e-6);
}

TEST(WornProfile, ZeroDepthLeavesTheFlanksUntouched) {
  SimulationConfig c;
  PreparedStage p = prepare(c);
  EXPECT_EQ(p.dynamics->surfaces().sun.max_deviation_m(), 0.0);
  EXPECT_EQ(p.dynamics->surfaces().ring.max_deviation_m(), 0.0);
}

TEST(WornProfile, PairsFarFromThePitchPointCarryLessLoad) {
  // Same imposed deflection on worn and unworn gears: near the ends of
  // contact the worn pair's force drops by about k_j (d_A + d_B); at the
  // pitch point (d ~ 0) it hardly changes.
  SimulationConfig unworn, worn;
  worn.imperfections.worn_profile_depth_m = 1e-6;
  PreparedStage pu = prepare(unworn), pworn = prepare(worn);
  const auto& g = pu.geometry.sun_planet;
  const double xi_p = g.pitch_point_m, L = g.end_active_m - g.start_active_m;
  double drop_far = 0, force_far = 0, drop_pitch = 1, force_pitch = 0;
  bool saw_far = false, saw_pitch = false;
  for (double t = 0; t < 2 / pu.mesh_frequency_Hz; t += 1e-5) {
    const MeshState st[2] = {pw::test::sun_mesh_under_deflection(pu, t, 4e-6),
                             pw::test::sun_mesh_under_deflection(pworn, t, 4e-6)};
    ASSERT_EQ(st[0].pairs, st[1].pairs);
    for (int j = 0; j < st[0].pairs; ++j) {
      const double xi = st[0].pair[j].xi_m, f0 = st[0].pair_force_N[j], f1 = st[1].pair_force_N[j];
      ASSERT_EQ(st[1].pair[j].xi_m, xi);
      if (std::fabs(xi - xi_p) > 0.35 * L) {  // near either end of contact
        saw_far = true;
        drop_far = std::max(drop_far, (f0 - f1) / f0);
        force_far = f0;
      }
      if (std::fabs(xi - xi_p) < 0.02 * L) {
        saw_pitch = true;
        drop_pitch = std::min(drop_pitch, std::fabs(f0 - f1) / f0);
        force_pitch = f0;
      }
    }
  }
  ASSERT_TRUE(saw_far && saw_pitch);
  // Far from the pitch point the depth of both flanks is a good part of the
  // 1 um maximum against a 4 um deflection: well over 10 % less force.
  EXPECT_GT(drop_far, 0.1) << "force " << force_far;
  EXPECT_LT(drop_pitch, 0.02) << "force " << force_pitch;
}
