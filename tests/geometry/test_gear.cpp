// Properties of a single involute gear (geometry/gear.hpp).
#include "core/error.hpp"
#include "geometry/gear.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace pw::geometry {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSeedAlpha = 0.349066;  // seed Table 1, 20 deg

GearSpec seed_gear(int z, GearKind kind = GearKind::External) {
  GearSpec g;
  g.teeth = z;
  g.kind = kind;
  return g;
}

/// Runs fn, expects pw::InputError naming `param`; returns its message.
template <class Fn>
std::string input_error(Fn&& fn, const std::string& param) {
  try {
    fn();
  } catch (const InputError& e) {
    EXPECT_EQ(e.parameter(), param) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected pw::InputError naming " << param;
  return {};
}

TEST(Involute, InverseRoundTripIsExactToRoundOffFromOneToSeventyDegrees) {
  // Covers every pressure angle a gear pair produces (working angles < 45 deg,
  // tip pressure angles of small pinions < 50 deg). 1e-14 rad is the doc'd
  // accuracy; below ~1 deg tan(a) - a itself loses digits (inv ~ a^3/3), so
  // the round trip there measures the forward function's conditioning.
  for (double a = 0.02; a < 1.2; a += 1e-3) {
    ASSERT_NEAR(inverse_involute(involute(a)), a, 1e-14) << "alpha = " << a;
  }
  EXPECT_EQ(inverse_involute(0.0), 0.0);
}

// Known defect (reported to the lead): the Newton iteration in gear.cpp
// overshoots past pi/2 and diverges for alpha >~ 1.28 rad (73 deg), although
// gear.hpp promises [0, pi/2). Not reachable from gear geometry; enable when
// inverse_involute is bracketed.
TEST(Involute, InverseRoundTripHoldsUpToNearlyNinetyDegrees) {
  for (double a = 1.2; a < 1.55; a += 1e-3) {
    ASSERT_NEAR(inverse_involute(involute(a)), a, 1e-12) << "alpha = " << a;
  }
}

TEST(Involute, MatchesTabulatedValueAtTwentyDegrees) {
  // inv 20 deg = 0.014904383867336 (any involute table, e.g. ISO 21771 Annex).
  EXPECT_NEAR(involute(20.0 * kPi / 180.0), 0.014904383867336, 1e-14);
}

TEST(SeedGears, RadiiFollowTheStandardFormulas) {
  // Seed Table 1: m = 3 mm, 20 deg, Zs = 21, Zp = 30, Zr = 81, h_a* = 1,
  // h_f* = 1.25. r = m z/2, r_b = r cos a, r_a = r +- m, r_f = r -+ 1.25 m.
  // Expected values typed from the closed forms (1e-10 m = round-off of the
  // typed digits).
  const GearGeometry s = make_geometry(seed_gear(21));
  const GearGeometry p = make_geometry(seed_gear(30));
  const GearGeometry r = make_geometry(seed_gear(81, GearKind::Internal));
  const double tol = 1e-10;
  EXPECT_NEAR(s.reference_radius_m, 31.5e-3, tol);
  EXPECT_NEAR(s.base_radius_m, 29.600315944e-3, tol);  // 31.5 mm cos(0.349066)
  EXPECT_NEAR(s.tip_radius_m, 34.5e-3, tol);
  EXPECT_NEAR(s.root_radius_m, 27.75e-3, tol);
  EXPECT_NEAR(p.reference_radius_m, 45.0e-3, tol);
  EXPECT_NEAR(p.base_radius_m, 42.286165633e-3, tol);
  EXPECT_NEAR(p.tip_radius_m, 48.0e-3, tol);
  EXPECT_NEAR(p.root_radius_m, 41.25e-3, tol);
  EXPECT_NEAR(r.reference_radius_m, 121.5e-3, tol);
  EXPECT_NEAR(r.base_radius_m, 114.172647209e-3, tol);
  EXPECT_NEAR(r.tip_radius_m, 118.5e-3, tol);   // internal: tip inside the reference circle
  EXPECT_NEAR(r.root_radius_m, 125.25e-3, tol);
  EXPECT_NEAR(s.base_pitch_m, 8.856393820e-3, tol);  // pi m cos a
  EXPECT_EQ(s.base_pitch_m, p.base_pitch_m);
}

TEST(ToothThickness, UnshiftedToothFillsHalfThePitchOnTheReferenceCircle) {
  // x = 0: tooth and space are equal on the reference circle (ISO 21771), for
  // external and internal teeth alike.
  for (int z : {12, 21, 30, 81}) {
    for (GearKind kind : {GearKind::External, GearKind::Internal}) {
      if (kind == GearKind::Internal && z < 40) continue;  // tip inside base circle
      const GearSpec spec = seed_gear(z, kind);
      const GearGeometry g = make_geometry(spec);
      EXPECT_NEAR(half_tooth_angle_at(spec, g, g.reference_radius_m), kPi / (2 * z), 1e-15) << z;
    }
  }
}

TEST(ToothThickness, PositiveShiftThickensExternalAndThinsInternalTeethByTwoXTanAlpha) {
  // gear.hpp convention: the profile moves x m away from the axis, which adds
  // (external) or removes (internal) 2 x m tan(a) of circular thickness on
  // the reference circle.
  const double x = 0.4;
  GearSpec e = seed_gear(30);
  e.profile_shift = x;
  GearSpec i = seed_gear(81, GearKind::Internal);
  i.profile_shift = x;
  const GearGeometry ge = make_geometry(e), gi = make_geometry(i);
  const double m = e.module_m;
  const double ds = 2 * x * m * std::tan(kSeedAlpha);
  EXPECT_NEAR(2 * ge.reference_radius_m * half_tooth_angle_at(e, ge, ge.reference_radius_m), kPi * m / 2 + ds, 1e-15);
  EXPECT_NEAR(2 * gi.reference_radius_m * half_tooth_angle_at(i, gi, gi.reference_radius_m), kPi * m / 2 - ds, 1e-15);
}

TEST(ToothThickness, ExternalToothNarrowsAndInternalToothWidensOutwards) {
  const GearSpec e = seed_gear(30);
  const GearSpec i = seed_gear(81, GearKind::Internal);
  const GearGeometry ge = make_geometry(e), gi = make_geometry(i);
  EXPECT_GT(half_tooth_angle_at(e, ge, ge.base_radius_m), half_tooth_angle_at(e, ge, ge.tip_radius_m));
  EXPECT_LT(half_tooth_angle_at(i, gi, gi.tip_radius_m), half_tooth_angle_at(i, gi, gi.reference_radius_m));
  // On the base circle the half angle is the stored half_base_tooth_angle.
  EXPECT_NEAR(half_tooth_angle_at(e, ge, ge.base_radius_m), ge.half_base_tooth_angle_rad, 1e-15);
  EXPECT_NEAR(half_tooth_angle_at(i, gi, gi.base_radius_m), gi.half_base_tooth_angle_rad, 1e-15);
}

TEST(RollAngle, TimesBaseRadiusIsTheTangentLengthToTheBaseCircle) {
  // The involute's radius of curvature at r is the tangent length
  // sqrt(r^2 - r_b^2) (Litvin 2004, ch. 10); its pressure angle has tan = roll.
  const GearGeometry g = make_geometry(seed_gear(21));
  for (double r : {g.base_radius_m, g.reference_radius_m, g.tip_radius_m}) {
    const double rb = g.base_radius_m;
    EXPECT_NEAR(rb * roll_angle_at(g, r), std::sqrt(r * r - rb * rb), 1e-15);
    EXPECT_NEAR(std::tan(pressure_angle_at(g, r)), roll_angle_at(g, r), 1e-12);
  }
}

TEST(GearSpecErrors, NameTheOffendingField) {
  GearSpec g = seed_gear(2);
  input_error([&] { make_geometry(g); }, "teeth");
  g = seed_gear(21);
  g.pressure_angle_rad = 1.0;
  input_error([&] { make_geometry(g); }, "pressure_angle_rad");
  g = seed_gear(21);
  g.module_m = -1;
  input_error([&] { make_geometry(g); }, "module_m");
}

} // namespace
} // namespace pw::geometry
