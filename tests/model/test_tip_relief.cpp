// Linear tip relief (contact.tip_relief_m, contact.tip_relief_extent; applied
// in model::prepare): its shape on every flank family, written here from the
// definition (ISO 21771 linear tip relief over the double-contact zone at the
// tip), and its effect on the contact: a pair inside the relief is unloaded by
// the relief of its two flanks, a pair at the pitch point is not.
#include "model/simulation.hpp"

#include "imposed_deflection.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace pw::model;

namespace {

/// C_a max(0, 1 - u / L): u the roll distance from the gear's tip, L the relief length.
double relief(double amount, double from_tip, double length) {
  return amount * std::max(0.0, 1.0 - from_tip / length);
}

} // namespace

TEST(TipRelief, IsLinearFromEachGearsTipOverTheDoubleContactZone) {
  SimulationConfig c;
  c.contact.tip_relief_m = 8e-6;
  c.contact.tip_relief_extent = 0.5;  // short relief: half the double-contact zone
  PreparedStage p = prepare(c);
  const ToothSurfaces& s = p.dynamics->surfaces();
  const auto& gs = p.geometry.sun_planet;
  const auto& gr = p.geometry.planet_ring;
  const double ls = 0.5 * (gs.contact_ratio - 1) * gs.base_pitch_m;
  const double lr = 0.5 * (gr.contact_ratio - 1) * gr.base_pitch_m;
  // Driving member A's tip ends the path of contact, B's starts it (sun -> planet,
  // planet -> ring): the sun's and the planets' ring-side flanks are relieved
  // towards end_active, the planets' sun-side flanks and the ring towards start_active.
  for (int e = 0; e < s.sun.elements(); ++e) {
    const double xs = s.sun.element_xi_m(e), xr = s.ring.element_xi_m(e);
    for (int t = 0; t < s.sun.teeth(); ++t)
      ASSERT_NEAR(s.sun.tooth_deviation(t)[e], relief(8e-6, gs.end_active_m - xs, ls), 1e-18) << e;
    for (int t = 0; t < s.ring.teeth(); ++t)
      ASSERT_NEAR(s.ring.tooth_deviation(t)[e], relief(8e-6, xr - gr.start_active_m, lr), 1e-18) << e;
    for (std::size_t i = 0; i < s.planet_sun_side.size(); ++i) {
      ASSERT_NEAR(s.planet_sun_side[i].tooth_deviation(0)[e], relief(8e-6, xs - gs.start_active_m, ls), 1e-18);
      ASSERT_NEAR(s.planet_ring_side[i].tooth_deviation(0)[e], relief(8e-6, gr.end_active_m - xr, lr), 1e-18);
    }
  }
  // No relief at the pitch point (the short relief stays in the double-contact zones),
  // nearly the whole amount at the tip element (half an element from the tip).
  const int tip = s.sun.elements() - 1;
  EXPECT_EQ(s.sun.deviation_m(0, gs.pitch_point_m), 0.0);
  EXPECT_GT(s.sun.tooth_deviation(0)[tip], 8e-6 * (1 - s.sun.element_width_m() / ls));
  EXPECT_EQ(s.sun.tooth_deviation(0)[0], 0.0);
}

TEST(TipRelief, ZeroAmountLeavesTheFlanksUntouched) {
  SimulationConfig c;
  c.contact.tip_relief_extent = 0.3;  // the length alone changes nothing
  PreparedStage p = prepare(c);
  EXPECT_EQ(p.dynamics->surfaces().sun.max_deviation_m(), 0.0);
  EXPECT_EQ(p.dynamics->surfaces().ring.max_deviation_m(), 0.0);
}

TEST(TipRelief, RelievedPairsCarryLessLoadAndPitchPointPairsTheSame) {
  // The same imposed 4 um deflection on relieved (3 um, long relief) and unmodified gears:
  // a pair within the relief zone of a tip carries k_j (4 um - d_A - d_B) instead of
  // k_j 4 um; at the pitch point (single contact, outside both reliefs) nothing changes.
  SimulationConfig plain, relieved;
  relieved.contact.tip_relief_m = 3e-6;
  relieved.contact.tip_relief_extent = 1.0;
  PreparedStage pp = prepare(plain), pr = prepare(relieved);
  const auto& g = pp.geometry.sun_planet;
  const double len = (g.contact_ratio - 1) * g.base_pitch_m;
  bool saw_tip = false, saw_pitch = false;
  for (double t = 0; t < 2 / pp.mesh_frequency_Hz; t += 1e-5) {
    const MeshState st[2] = {pw::test::sun_mesh_under_deflection(pp, t, 4e-6),
                             pw::test::sun_mesh_under_deflection(pr, t, 4e-6)};
    ASSERT_EQ(st[0].pairs, st[1].pairs);
    for (int j = 0; j < st[0].pairs; ++j) {
      const double xi = st[0].pair[j].xi_m, f0 = st[0].pair_force_N[j], f1 = st[1].pair_force_N[j];
      const double d = relief(3e-6, g.end_active_m - xi, len) + relief(3e-6, xi - g.start_active_m, len);
      // Well inside a relief: force ratio (4 - d) / 4. The flanks sample the relief at 64 element
      // centres, linear in between and constant in the last half element: <= 0.1 um of 4 um off.
      if (d > 0.5e-6 && f0 > 0) {
        saw_tip = true;
        EXPECT_NEAR(f1 / f0, std::max(0.0, (4e-6 - d) / 4e-6), 0.025) << "xi " << xi;
      }
      if (std::fabs(xi - g.pitch_point_m) < 0.02 * g.base_pitch_m) {
        saw_pitch = true;
        EXPECT_NEAR(f1, f0, 1e-9 * f0);
      }
    }
  }
  EXPECT_TRUE(saw_tip && saw_pitch);
}

TEST(TipRelief, ShortReliefKeepsALightlyLoadedMeshInContactWhereALongOneSeparatesIt) {
  // Relief 3 um against a 1 um deflection. Short relief (the default, half the double-contact
  // zone): at every roll position one pair is unrelieved, so the mesh always carries force.
  // Long relief: mid double-contact both pairs are relieved by 1.5 um > 1 um, the mesh separates.
  SimulationConfig shortr, longr;
  shortr.contact.tip_relief_m = longr.contact.tip_relief_m = 3e-6;
  longr.contact.tip_relief_extent = 1.0;
  ASSERT_EQ(shortr.contact.tip_relief_extent, 0.5);
  PreparedStage ps = prepare(shortr), pl = prepare(longr);
  double least_short = 1e300, least_long = 1e300;
  for (double t = 0; t < 2 / ps.mesh_frequency_Hz; t += 2e-6) {
    const MeshState s = pw::test::sun_mesh_under_deflection(ps, t, 1e-6);
    const MeshState l = pw::test::sun_mesh_under_deflection(pl, t, 1e-6);
    double fs = 0, fl = 0;
    for (int j = 0; j < s.pairs; ++j) fs += s.pair_force_N[j];
    for (int j = 0; j < l.pairs; ++j) fl += l.pair_force_N[j];
    least_short = std::min(least_short, fs), least_long = std::min(least_long, fl);
  }
  // Short: at least an unmodified single pair's force at 1 um (k_single >= 1e8 N/m for the seed).
  EXPECT_GT(least_short, 1e8 * 1e-6);
  EXPECT_EQ(least_long, 0.0);
}
