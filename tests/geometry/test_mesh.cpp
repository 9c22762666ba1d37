// Properties of meshes, stage assembly and mesh phasing (geometry/mesh.hpp).
// Reference numbers are closed forms evaluated by hand (docs/derivation-geometry.md);
// the phasing tests check the flank construction against an independent
// Cartesian one built from gear.hpp's tooth-thickness function alone.
#include "core/error.hpp"
#include "config/stage.hpp"
#include "geometry/mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace pw::geometry {
namespace {

constexpr double kPi = std::numbers::pi;

model::StageSpec stage(int zs, int zp, int zr, int n) {
  model::StageSpec s;  // seed defaults: m = 3 mm, 20 deg, standard teeth
  s.sun.teeth = zs;
  s.planet.teeth = zp;
  s.ring.teeth = zr;
  s.planet_count = n;
  return s;
}

/// Seed stage with the planet shifted by +0.2 and the ring by the +0.4 that
/// restores a common carrier radius (zr - zp = zs + zp makes alpha'' = alpha').
model::StageSpec shifted_seed() {
  model::StageSpec s;
  s.planet.profile_shift = 0.2;
  s.ring.profile_shift = 0.4;
  return s;
}

/// Zs = 22, Zp = 29 (odd), Zr = 80, planets at unequal assemblable angles
/// 2 pi {0, 33, 70} / (Zs + Zr).
model::StageSpec unequal_stage() {
  model::StageSpec s = stage(22, 29, 80, 3);
  s.planet_angles_rad = {0.0, 2 * kPi * 33 / 102, 2 * kPi * 70 / 102};
  return s;
}

/// Signed distance of x to the nearest integer (phases are defined mod 1).
double cyc(double x) { return x - std::round(x); }
/// Angle difference wrapped to [-pi, pi].
double ang(double a) { return std::remainder(a, 2 * kPi); }

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

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// ---------------------------------------------------------------- seed mesh numbers

TEST(SeedStage, SunPlanetMeshHasTheClosedFormPathOfContactAndContactRatio1_6113) {
  // Unshifted: a' = m (Zs + Zp)/2 = 76.5 mm, alpha' = alpha; L = a' sin a;
  // start = L - sqrt(r_ap^2 - r_bp^2), end = sqrt(r_as^2 - r_bs^2). Numbers
  // evaluated from these formulas; 1e-12 m is round-off.
  const StageGeometry g = make_stage_geometry(model::StageSpec{});
  const MeshGeometry& m = g.sun_planet;
  EXPECT_EQ(m.kind, GearKind::External);
  EXPECT_NEAR(g.carrier_radius_m, 76.5e-3, 1e-12);
  EXPECT_NEAR(m.working_pressure_angle_rad, 0.349066, 1e-12);
  EXPECT_NEAR(m.tangent_distance_m, 26.164551718713e-3, 1e-12);
  EXPECT_NEAR(m.pitch_point_m, 10.773638943000e-3, 1e-12);
  EXPECT_NEAR(m.start_active_m, 3.451555525572e-3, 1e-12);
  EXPECT_NEAR(m.end_active_m, 17.722056767602e-3, 1e-12);
  EXPECT_NEAR(m.contact_ratio, 1.611321891505, 1e-9);
  // Ends of the path of contact are the tips: B's tip at start, A's at end.
  EXPECT_NEAR(contact_radius_b(m, m.start_active_m), g.planet.tip_radius_m, 1e-12);
  EXPECT_NEAR(contact_radius_a(m, m.end_active_m), g.sun.tip_radius_m, 1e-12);
  // The pitch point lies on both working pitch circles (= reference circles here).
  EXPECT_NEAR(contact_radius_a(m, m.pitch_point_m), g.sun.reference_radius_m, 1e-12);
  EXPECT_NEAR(contact_radius_b(m, m.pitch_point_m), g.planet.reference_radius_m, 1e-12);
}

TEST(SeedStage, PlanetRingMeshHasTheClosedFormPathOfContactAndContactRatio1_9361) {
  // Internal: start = sqrt(r_ar^2 - r_br^2) - L, end = sqrt(r_ap^2 - r_bp^2).
  const StageGeometry g = make_stage_geometry(model::StageSpec{});
  const MeshGeometry& m = g.planet_ring;
  EXPECT_EQ(m.kind, GearKind::Internal);
  EXPECT_NEAR(m.centre_distance_m, 76.5e-3, 1e-12);
  EXPECT_NEAR(m.tangent_distance_m, 26.164551718713e-3, 1e-12);
  EXPECT_NEAR(m.pitch_point_m, 15.390912775714e-3, 1e-12);
  EXPECT_NEAR(m.start_active_m, 5.566452509763e-3, 1e-12);
  EXPECT_NEAR(m.end_active_m, 22.712996193141e-3, 1e-12);
  EXPECT_NEAR(m.contact_ratio, 1.936063823694, 1e-9);
  EXPECT_NEAR(contact_radius_b(m, m.start_active_m), g.ring.tip_radius_m, 1e-12);
  EXPECT_NEAR(contact_radius_a(m, m.end_active_m), g.planet.tip_radius_m, 1e-12);
  EXPECT_NEAR(contact_radius_a(m, m.pitch_point_m), g.planet.reference_radius_m, 1e-12);
  EXPECT_NEAR(contact_radius_b(m, m.pitch_point_m), g.ring.reference_radius_m, 1e-12);
}

TEST(SeedStage, OnlyThePlanetRingMeshReachesAFilletAndOnlyOnThePlanet) {
  // ISO 53 profile A tool (rho_f* = 0.38): the planet's involute starts at
  // rho_F = r sin a - m/sin a = 6.6198 mm of roll, the ring tip meets it at
  // 5.5665 mm, i.e. 1.0534 mm of the path lies on the planet's fillet; the
  // sun-planet mesh stays on the involutes (docs/derivation-geometry.md §2.4).
  const StageGeometry g = make_stage_geometry(model::StageSpec{});
  EXPECT_EQ(g.sun_planet.fillet_overlap_a_m, 0.0);
  EXPECT_EQ(g.sun_planet.fillet_overlap_b_m, 0.0);
  EXPECT_EQ(g.planet_ring.fillet_overlap_b_m, 0.0);
  const double rho_f = 45e-3 * std::sin(0.349066) - (1.25 - 0.38 * (1 - std::sin(0.349066))) * 3e-3 / std::sin(0.349066);
  EXPECT_NEAR(g.planet_ring.fillet_overlap_a_m, rho_f - g.planet_ring.start_active_m, 1e-12);
  EXPECT_NEAR(g.planet_ring.fillet_overlap_a_m, 1.0534e-3, 1e-7);
  EXPECT_GT(g.planet_ring.form_radius_a_m, g.planet.base_radius_m);
}

// ---------------------------------------------------------------- line-of-action geometry

TEST(LineOfAction, CurvatureRadiiSumToTangentLengthExternalAndDifferInternal) {
  // rho_A + rho_B = L (external), rho_B - rho_A = L (internal), and the
  // contact radii agree with a Cartesian construction of the line of action
  // from the centre distance (1e-12 m: round-off of mm-sized lengths).
  const StageGeometry g = make_stage_geometry(shifted_seed());
  for (const MeshGeometry* m : {&g.sun_planet, &g.planet_ring}) {
    const bool internal = m->kind == GearKind::Internal;
    const double aw = m->working_pressure_angle_rad, a = m->centre_distance_m, L = m->tangent_distance_m;
    // A at the origin, B at (a, 0) (external) or (-a, 0) (internal); T_A and
    // the LOA direction t from the drive-flank analysis (§3.1).
    const double phi = internal ? aw : -aw;
    const double ta[2] = {m->base_radius_a_m * std::cos(phi), m->base_radius_a_m * std::sin(phi)};
    const double t[2] = {std::sin(aw), internal ? -std::cos(aw) : std::cos(aw)};
    const double ob = internal ? -a : a;
    for (double xi = m->start_active_m; xi <= m->end_active_m; xi += 1e-4) {
      const double sum = internal ? curvature_radius_b(*m, xi) - curvature_radius_a(*m, xi)
                                  : curvature_radius_b(*m, xi) + curvature_radius_a(*m, xi);
      EXPECT_NEAR(sum, L, 1e-15);
      const double c[2] = {ta[0] + xi * t[0], ta[1] + xi * t[1]};
      EXPECT_NEAR(std::hypot(c[0], c[1]), contact_radius_a(*m, xi), 1e-12);
      EXPECT_NEAR(std::hypot(c[0] - ob, c[1]), contact_radius_b(*m, xi), 1e-12);
    }
  }
}

TEST(WorkingPressureAngle, ShiftedExternalTeethFillTheWorkingPitchWithoutBacklash) {
  // Zero backlash: s'_a + s'_b = p' on the working pitch circles r' = r_b/cos a'
  // (ISO 21771); thicknesses from gear.hpp, independent of the inv formula.
  GearSpec a, b;
  a.teeth = 18;
  a.profile_shift = 0.4;
  b.teeth = 45;
  b.profile_shift = 0.1;
  const MeshGeometry m = make_mesh(a, b);
  const GearGeometry ga = make_geometry(a), gb = make_geometry(b);
  const double ra = ga.base_radius_m / std::cos(m.working_pressure_angle_rad);
  const double rb = gb.base_radius_m / std::cos(m.working_pressure_angle_rad);
  EXPECT_NEAR(ra + rb, m.centre_distance_m, 1e-15);
  const double pitch = 2 * kPi * ra / a.teeth;
  EXPECT_NEAR(2 * ra * half_tooth_angle_at(a, ga, ra) + 2 * rb * half_tooth_angle_at(b, gb, rb), pitch, 1e-13);
  EXPECT_GT(m.centre_distance_m, 0.5 * a.module_m * (a.teeth + b.teeth));  // positive shifts push apart
}

TEST(WorkingPressureAngle, ShiftedPlanetToothFillsTheRingSpaceWithoutBacklash) {
  // Internal, gear.hpp convention (x_ring > 0 thins the ring tooth): the planet
  // tooth equals the ring tooth space on the working pitch circles.
  GearSpec p, r;
  p.teeth = 30;
  p.profile_shift = 0.2;
  r.teeth = 81;
  r.kind = GearKind::Internal;
  r.profile_shift = 0.5;
  const MeshGeometry m = make_mesh(p, r);
  const GearGeometry gp = make_geometry(p), gr = make_geometry(r);
  const double rp = gp.base_radius_m / std::cos(m.working_pressure_angle_rad);
  const double rr = gr.base_radius_m / std::cos(m.working_pressure_angle_rad);
  EXPECT_NEAR(rr - rp, m.centre_distance_m, 1e-15);
  const double pitch = 2 * kPi * rp / p.teeth;
  const double ring_space = pitch - 2 * rr * half_tooth_angle_at(r, gr, rr);
  EXPECT_NEAR(2 * rp * half_tooth_angle_at(p, gp, rp), ring_space, 1e-13);
  // x_r - x_p > 0 widens the ring spaces: the planet sinks in, a' grows.
  EXPECT_GT(m.centre_distance_m, 0.5 * p.module_m * (r.teeth - p.teeth));
}

TEST(WorkingPressureAngle, GivenCentreDistanceSetsCosAlphaToBaseRadiiOverDistance) {
  GearSpec s, p;
  p.teeth = 30;
  const MeshGeometry m = make_mesh(s, p, 76.6e-3);
  const double rb = make_geometry(s).base_radius_m + make_geometry(p).base_radius_m;
  EXPECT_NEAR(std::cos(m.working_pressure_angle_rad), rb / 76.6e-3, 1e-15);
  EXPECT_NEAR(m.tangent_distance_m, 76.6e-3 * std::sin(m.working_pressure_angle_rad), 1e-15);
  // Closer than zero backlash the teeth would overlap.
  const std::string msg = input_error([&] { make_mesh(s, p, 76.4e-3); }, "centre_distance_m");
  EXPECT_TRUE(contains(msg, "zero-backlash")) << msg;
}

// ---------------------------------------------------------------- contact ratio

TEST(ContactRatio, TextbookTwentyFortyPairMatchesClosedFormAndDoubleContactFraction) {
  // 20/40 teeth, 20 deg full depth, m = 5 mm (Shigley/Budynas Eq. 13-8 form):
  // eps = [sqrt(ra1^2-rb1^2) + sqrt(ra2^2-rb2^2) - a sin a]/(pi m cos a)
  //     = 1.6351856 (hand evaluation).
  GearSpec a, b;
  a.teeth = 20;
  b.teeth = 40;
  a.module_m = b.module_m = 5e-3;
  const MeshGeometry m = make_mesh(a, b);
  EXPECT_NEAR(m.contact_ratio, 1.6351856041, 1e-9);
  // Independent: over one base pitch, two pairs are in contact during a
  // fraction eps - 1 of the time (1e-3: the sweep resolves 1/200000 of p_b).
  std::vector<ContactPair> pairs;
  pairs.reserve(8);
  const MeshPhase phase{m.start_active_m, 0, 0};
  const int n = 200000;
  int doubles = 0;
  for (int k = 0; k < n; ++k) {
    const int np = pairs_in_contact(m, phase, a.teeth, b.teeth, (k + 0.5) / n * m.base_pitch_m, pairs);
    ASSERT_TRUE(np == 1 || np == 2) << np;
    doubles += np == 2;
  }
  EXPECT_NEAR(static_cast<double>(doubles) / n, m.contact_ratio - 1.0, 1e-3);
}

// ---------------------------------------------------------------- input errors

TEST(StageErrors, RingTeethOtherThanZsPlusTwoZpNameRingTeeth) {
  const std::string msg = input_error([] { make_stage_geometry(stage(21, 30, 80, 1)); }, "stage.ring.teeth");
  EXPECT_TRUE(contains(msg, "Zs + 2 Zp = 81")) << msg;
}

TEST(StageErrors, ShiftedGearsWithUnequalCentreDistancesNameRingProfileShiftAndTheFix) {
  model::StageSpec s;
  s.planet.profile_shift = 0.2;  // sun-planet a' grows, planet-ring a' shrinks
  const std::string msg = input_error([&] { make_stage_geometry(s); }, "stage.ring.profile_shift");
  EXPECT_TRUE(contains(msg, "stage.ring.profile_shift = 0.4")) << msg;
  EXPECT_NO_THROW(make_stage_geometry(shifted_seed()));  // the suggested fix assembles
}

TEST(StageErrors, EqualSpacingWithNonIntegerZsPlusZrOverNNamesPlanetCount) {
  const std::string msg = input_error([] { make_stage_geometry(stage(20, 30, 80, 3)); }, "stage.planet_count");
  EXPECT_TRUE(contains(msg, "(20 + 80)/3")) << msg;
}

TEST(StageErrors, UnequalAnglesOffTheAssemblyGridNamePlanetAngles) {
  model::StageSpec s;
  s.planet_angles_rad = {0.0, 2.0, 4.0};  // 2.0 * 102 / 2 pi = 32.47, not an integer
  const std::string msg = input_error([&] { make_stage_geometry(s); }, "stage.planet_angles_rad");
  EXPECT_TRUE(contains(msg, "must be an integer")) << msg;
  EXPECT_NO_THROW(make_stage_geometry(unequal_stage()));
}

TEST(StageErrors, SevenLargePlanetsCollideAndNamePlanetCount) {
  // Zs = 19, Zp = 30, Zr = 79: (19 + 79)/7 = 14 assembles, but the tip circles
  // (r_a = 48 mm) need 96 mm while neighbours are 2 a sin(pi/7) = 63.8 mm apart.
  const std::string msg = input_error([] { make_stage_geometry(stage(19, 30, 79, 7)); }, "stage.planet_count");
  EXPECT_TRUE(contains(msg, "collide")) << msg;
  EXPECT_NO_THROW(make_stage_geometry(stage(19, 30, 79, 2)));
}

TEST(MeshErrors, ContactRatioBelowOneNamesAddendum) {
  GearSpec a, b;
  a.teeth = b.teeth = 30;
  a.addendum_coef = b.addendum_coef = 0.5;  // eps = 0.892
  const std::string msg = input_error([&] { make_mesh(a, b, 0.0, "pinion", "wheel"); }, "pinion.addendum_coef");
  EXPECT_TRUE(contains(msg, "contact ratio 0.89")) << msg;
}

TEST(MeshErrors, AnUndercutReachingIntoThePathOfContactNamesTheTeeth) {
  // z_min = 2 (1.25 - 0.38 (1 - sin 20)) / sin^2 20 = 17.1. Two 13-tooth gears: the rack's cut ends
  // 0.317 m up each involute (module 1 m), the mate's tips reach down to 0.094 m (an independent
  // scan, session 66): contact on a flank the rack removed.
  GearSpec z13;
  z13.teeth = 13;
  z13.module_m = 1.0;
  const std::string msg = input_error([&] { make_mesh(z13, z13, 0.0, "pinion", "wheel"); }, "pinion.teeth");
  EXPECT_TRUE(contains(msg, "undercut")) << msg;
  EXPECT_TRUE(contains(msg, "(h_FfP* - x)/sin^2(alpha) = 17.09")) << msg;
  // A ten-tooth sun against a 30-tooth planet meets the flank below the base circle before that.
  input_error([] { make_stage_geometry(stage(10, 30, 70, 2)); }, "stage.sun.profile_shift");
}

TEST(Mesh, ASlightlyUndercutGearMeshesWhereItsMatesTipsStayAboveTheCut) {
  // z = 17 at x = 0 is just below z_min = 17.1: the straight flank ends 0.0166 m (module 1 m) beyond
  // T, and its end cuts the involute up to roll 0.0077 m -- far below any mate's tips. z = 18 is not
  // undercut: its form point is rho_F = r sin a - h_FfP / sin a, as before.
  GearSpec z18, z17, wheel;
  z18.teeth = 18;
  z17.teeth = 17;
  wheel.teeth = 40;
  for (GearSpec* g : {&z18, &z17, &wheel}) g->module_m = 1.0;
  EXPECT_NO_THROW(make_mesh(z18, wheel));
  const MeshGeometry m = make_mesh(z17, wheel);
  const GearGeometry g17 = make_geometry(z17), g18 = make_geometry(z18);
  const double sa = std::sin(z17.pressure_angle_rad);
  const double h_ff = z17.dedendum_coef - z17.root_fillet_coef * (1 - sa);
  EXPECT_NEAR(form_roll_distance(z18, g18), g18.reference_radius_m * sa - h_ff / sa, 1e-12);
  // Independent check: a vectorized scan of the trochoid by roll distance at 2e6 points (session 66)
  // gave 0.0082517; the two agree to 5e-6 m (the scan's resolution near the crossing).
  EXPECT_NEAR(form_roll_distance(z17, g17), 0.0082517, 5e-6);
  EXPECT_GT(m.start_active_m, 0.1);
  EXPECT_EQ(m.fillet_overlap_a_m, 0.0);
  // A 17-tooth sun in a stage (refused before session 66 as undercut).
  EXPECT_NO_THROW(make_stage_geometry(stage(17, 30, 77, 2)));
  // A 17-tooth planet in a standard internal ring is refused, but for the ring's tips reaching below
  // its base circle (involute interference), not for the undercut (the 28/17/62 stage of an
  // independent simulator: contact would start 1.57 mm below the planet's base circle).
  input_error([] { make_stage_geometry(stage(28, 17, 62, 3)); }, "stage.planet.profile_shift");
}

TEST(Mesh, TheUndercutGrowsAsTeethAreRemovedAndVanishesWithTheProfileShiftThatRemovesIt) {
  // Roll distance of the cut's end against the flank end's overshoot |rho_F| (module 1 m): 0.38-0.49
  // of it for z = 8..17 (scan, session 66); a shift x >= h_FfP* - z sin^2(a)/2 removes it.
  double previous = 0;
  for (int z : {17, 16, 15, 14, 12, 10, 8}) {
    GearSpec g;
    g.teeth = z;
    g.module_m = 1.0;
    const GearGeometry gg = make_geometry(g);
    const double sa = std::sin(g.pressure_angle_rad);
    const double overshoot = (g.dedendum_coef - g.root_fillet_coef * (1 - sa)) / sa - gg.reference_radius_m * sa;
    const double cut = form_roll_distance(g, gg);
    EXPECT_GT(cut, 0.35 * overshoot) << z;
    EXPECT_LT(cut, 0.5 * overshoot) << z;
    EXPECT_GT(cut, previous) << z;
    previous = cut;
    g.profile_shift = (g.dedendum_coef - g.root_fillet_coef * (1 - sa)) - 0.5 * z * sa * sa + 1e-9;
    EXPECT_GE(form_roll_distance(g, make_geometry(g)), 0.0);
    EXPECT_LT(form_roll_distance(g, make_geometry(g)), 1e-6) << z;
  }
}

TEST(MeshErrors, WheelTipsBelowPinionBaseCircleAreInterferenceNamingPinionShift) {
  // 18-tooth pinion (not undercut) with a 100-tooth wheel of addendum 1.2 m:
  // the wheel tip meets the line of action 0.16 mm before T_A.
  GearSpec p, w;
  p.teeth = 18;
  p.module_m = w.module_m = 1e-3;
  w.teeth = 100;
  w.addendum_coef = 1.2;
  const std::string msg = input_error([&] { make_mesh(p, w, 0.0, "pinion", "wheel"); }, "pinion.profile_shift");
  EXPECT_TRUE(contains(msg, "interference")) << msg;
  p.profile_shift = 0.2;  // moves the pinion's flank outwards: clears it
  EXPECT_NO_THROW(make_mesh(p, w, 0.0, "pinion", "wheel"));
}

TEST(MeshErrors, UnequalModulesNameTheDrivenGearsModule) {
  GearSpec a, b;
  b.teeth = 30;
  b.module_m = 2e-3;
  input_error([&] { make_mesh(a, b, 0.0, "stage.sun", "stage.planet"); }, "stage.planet.module_m");
}

// ---------------------------------------------------------------- mesh phasing

TEST(Phasing, PlanetZeroHasAToothSpaceOnTheSunAndTheRingMeshesSymmetrically) {
  // Zero backlash + sun tooth 0 on the centre line => a planet tooth space
  // faces the sun and, on the ring side, a ring tooth (Zp even) or a ring
  // space (Zp odd) lies on the same line. This holds only if the
  // zero-backlash centre distances are right, shifted gears included.
  for (const model::StageSpec& spec : {model::StageSpec{}, shifted_seed(), unequal_stage(), stage(21, 31, 83, 4)}) {
    const StageGeometry g = make_stage_geometry(spec);
    const AssemblyLayout lay = assembly_layout(spec, g);
    const double zp = spec.planet.teeth, zr = spec.ring.teeth;
    EXPECT_NEAR(ang(lay.planet_tooth0_rad[0] - (kPi - kPi / zp)), 0.0, 1e-12) << zp;
    const double ring0 = spec.planet.teeth % 2 == 0 ? 0.0 : -kPi / zr;
    EXPECT_NEAR(ang(lay.ring_tooth0_rad - ring0), 0.0, 1e-12) << zp;
    // ...and, by the numbering, sun tooth 0 meets planet tooth 0.
    const PlanetPhases ph = mesh_phases(spec, g)[0];
    EXPECT_EQ((ph.sun_planet.tooth_b0 - ph.sun_planet.tooth_a0 + 100 * spec.planet.teeth) % spec.planet.teeth, 0);
  }
}

TEST(Phasing, SunPlanetMeshOfPlanetILagsPlanetZeroByZsPsiOverTwoPi) {
  // Parker & Lin 2004, Eq. (10): gamma_si = Zs psi_i / 2 pi (mod 1), here from
  // the flank construction: xi0_0 - xi0_i = gamma_si p_b (mod p_b).
  for (const model::StageSpec& spec : {model::StageSpec{}, stage(22, 29, 80, 3), unequal_stage(), stage(21, 31, 83, 4)}) {
    const StageGeometry g = make_stage_geometry(spec);
    const auto ph = mesh_phases(spec, g);
    const double pb = g.sun_planet.base_pitch_m;
    for (std::size_t i = 0; i < ph.size(); ++i) {
      const double gamma = spec.sun.teeth * g.planet_angles_rad[i] / (2 * kPi);
      EXPECT_NEAR(cyc((ph[0].sun_planet.xi0_m - ph[i].sun_planet.xi0_m) / pb - gamma), 0.0, 1e-9) << i;
      EXPECT_GE(ph[i].sun_planet.xi0_m, g.sun_planet.start_active_m);
      EXPECT_LT(ph[i].sun_planet.xi0_m, g.sun_planet.start_active_m + pb);
    }
  }
}

TEST(Phasing, PlanetRingMeshOfPlanetILagsPlanetZeroByMinusZrPsiOverTwoPi) {
  // Parker & Lin 2004: gamma_ri = -Zr psi_i / 2 pi (mod 1) (planet i reaches
  // a ring tooth psi_i earlier), equal to gamma_si for assemblable stages.
  for (const model::StageSpec& spec : {model::StageSpec{}, stage(22, 29, 80, 3), unequal_stage(), stage(21, 31, 83, 4)}) {
    const StageGeometry g = make_stage_geometry(spec);
    const auto ph = mesh_phases(spec, g);
    const double pb = g.planet_ring.base_pitch_m;
    for (std::size_t i = 0; i < ph.size(); ++i) {
      const double gamma = -spec.ring.teeth * g.planet_angles_rad[i] / (2 * kPi);
      EXPECT_NEAR(cyc((ph[0].planet_ring.xi0_m - ph[i].planet_ring.xi0_m) / pb - gamma), 0.0, 1e-9) << i;
      EXPECT_GE(ph[i].planet_ring.xi0_m, g.planet_ring.start_active_m);
      EXPECT_LT(ph[i].planet_ring.xi0_m, g.planet_ring.start_active_m + pb);
    }
  }
}

TEST(Phasing, RingMeshPassesThePitchPointHalfACycleAfterTheSunMeshForEvenZpAndInPhaseForOdd) {
  // Unshifted gears: a sun drive flank is p_b/4 past the pitch point at
  // assembly; the loaded ring flank is p_b/4 before it for Zp even (ring tooth
  // centred) and p_b/4 past it for Zp odd (ring space centred) (§4.4).
  for (const model::StageSpec& spec : {model::StageSpec{}, stage(22, 29, 80, 3), stage(21, 31, 83, 4)}) {
    const StageGeometry g = make_stage_geometry(spec);
    const auto ph = mesh_phases(spec, g);
    const double pb = g.sun_planet.base_pitch_m;
    const double expected = spec.planet.teeth % 2 == 0 ? 0.5 : 0.0;
    for (const PlanetPhases& p : ph) {
      const double s_sun = g.sun_planet.pitch_point_m - p.sun_planet.xi0_m;  // roll at which a pair passes P
      const double s_ring = g.planet_ring.pitch_point_m - p.planet_ring.xi0_m;
      EXPECT_NEAR(cyc((s_ring - s_sun) / pb - expected), 0.0, 1e-9) << spec.planet.teeth;
    }
  }
}

/// Every pair that pairs_in_contact reports at roll s lies, in a Cartesian
/// picture of the rigidly turning stage, on the drive flanks of exactly the
/// teeth it names. Flanks from half_tooth_angle_at() only: sun and planet
/// touch with the counter-clockwise side of their teeth in the sun mesh, the
/// planet with the clockwise side and the ring with the counter-clockwise side
/// in the ring mesh. 1e-9 rad: round-off of atan2 and the involute function.
void expect_pairs_on_named_flanks(const model::StageSpec& spec, double s) {
  const StageGeometry g = make_stage_geometry(spec);
  const AssemblyLayout lay = assembly_layout(spec, g);
  const auto ph = mesh_phases(spec, g);
  const GearGeometry &gs = g.sun, &gp = g.planet, &gr = g.ring;
  const int zs = spec.sun.teeth, zp = spec.planet.teeth, zr = spec.ring.teeth;
  // Rigid kinematics with the ring fixed: both meshes roll the same s.
  const double th_c = s / gr.base_radius_m;            // s = r_br theta_c
  const double th_s = th_c + s / gs.base_radius_m;     // s = r_bs (theta_s - theta_c)
  const double th_p = th_c - s / gp.base_radius_m;     // planet turns back relative to the carrier
  std::vector<ContactPair> pairs;
  for (std::size_t i = 0; i < ph.size(); ++i) {
    const double psi = g.planet_angles_rad[i] + th_c;
    const double op[2] = {g.carrier_radius_m * std::cos(psi), g.carrier_radius_m * std::sin(psi)};
    const auto planet_tooth = [&](int j) { return lay.planet_tooth0_rad[i] + th_p + kPlanetToothDirection * 2 * kPi * j / zp; };

    const MeshGeometry& sp = g.sun_planet;
    double phi = psi - sp.working_pressure_angle_rad;  // T_A on the sun's base circle
    int np = pairs_in_contact(sp, ph[i].sun_planet, zs, zp, s, pairs);
    ASSERT_GE(np, 1);
    for (const ContactPair& c : pairs) {
      const double x = gs.base_radius_m * std::cos(phi) - c.xi_m * std::sin(phi);
      const double y = gs.base_radius_m * std::sin(phi) + c.xi_m * std::cos(phi);
      const double r_s = std::hypot(x, y);
      const double sun_tooth = lay.sun_tooth0_rad + th_s + kSunToothDirection * 2 * kPi * c.tooth_a / zs;
      EXPECT_NEAR(ang(std::atan2(y, x) - sun_tooth - half_tooth_angle_at(spec.sun, gs, r_s)), 0.0, 1e-9)
          << "planet " << i << " s " << s << " sun tooth " << c.tooth_a;
      const double r_p = std::hypot(x - op[0], y - op[1]);
      EXPECT_NEAR(ang(std::atan2(y - op[1], x - op[0]) - planet_tooth(c.tooth_b) -
                      half_tooth_angle_at(spec.planet, gp, r_p)),
                  0.0, 1e-9)
          << "planet " << i << " s " << s << " planet tooth " << c.tooth_b;
      EXPECT_NEAR(r_s, contact_radius_a(sp, c.xi_m), 1e-12);
      EXPECT_NEAR(r_p, contact_radius_b(sp, c.xi_m), 1e-12);
    }

    const MeshGeometry& pr = g.planet_ring;
    phi = psi + pr.working_pressure_angle_rad;  // T_A on the planet's base circle
    np = pairs_in_contact(pr, ph[i].planet_ring, zp, zr, s, pairs);
    ASSERT_GE(np, 1);
    for (const ContactPair& c : pairs) {
      const double x = op[0] + gp.base_radius_m * std::cos(phi) + c.xi_m * std::sin(phi);
      const double y = op[1] + gp.base_radius_m * std::sin(phi) - c.xi_m * std::cos(phi);
      const double r_p = std::hypot(x - op[0], y - op[1]);
      EXPECT_NEAR(ang(std::atan2(y - op[1], x - op[0]) - planet_tooth(c.tooth_a) +
                      half_tooth_angle_at(spec.planet, gp, r_p)),
                  0.0, 1e-9)
          << "planet " << i << " s " << s << " planet tooth " << c.tooth_a;
      const double r_r = std::hypot(x, y);
      const double ring_tooth = lay.ring_tooth0_rad + kRingToothDirection * 2 * kPi * c.tooth_b / zr;
      EXPECT_NEAR(ang(std::atan2(y, x) - ring_tooth - half_tooth_angle_at(spec.ring, gr, r_r)), 0.0, 1e-9)
          << "planet " << i << " s " << s << " ring tooth " << c.tooth_b;
      EXPECT_NEAR(r_p, contact_radius_a(pr, c.xi_m), 1e-12);
      EXPECT_NEAR(r_r, contact_radius_b(pr, c.xi_m), 1e-12);
    }
  }
}

TEST(Phasing, ReportedPairsLieOnTheInvoluteFlanksOfTheNamedTeethAsTheStageTurns) {
  const double pb = make_stage_geometry(model::StageSpec{}).sun_planet.base_pitch_m;
  for (const model::StageSpec& spec : {model::StageSpec{}, shifted_seed(), unequal_stage(), stage(21, 31, 83, 4)}) {
    for (double s : {0.0, 0.37 * pb, 1.5 * pb, 7.2 * pb, 45.9 * pb, -3.3 * pb}) {
      SCOPED_TRACE(testing::Message() << "Zp " << spec.planet.teeth << " s/pb " << s / pb);
      expect_pairs_on_named_flanks(spec, s);
    }
  }
}

// ---------------------------------------------------------------- pairs in contact

TEST(PairsInContact, SeedMeshesAlwaysHaveOneOrTwoPairsAndEachContactPointMovesWithTheRoll) {
  // 1 < eps < 2 for both seed meshes; a pair keeps its teeth while its xi
  // grows by exactly ds, enters at the start and leaves at the end of the
  // path of contact (1e-12 m: round-off of xi0 + s - n p_b).
  const model::StageSpec spec;
  const StageGeometry g = make_stage_geometry(spec);
  const auto ph = mesh_phases(spec, g);
  const double pb = g.sun_planet.base_pitch_m;
  const double ds = pb / 997;
  std::vector<ContactPair> prev, cur;
  prev.reserve(8);
  cur.reserve(8);
  for (const PlanetPhases& p : ph) {
    for (int mesh = 0; mesh < 2; ++mesh) {
      const MeshGeometry& m = mesh == 0 ? g.sun_planet : g.planet_ring;
      const MeshPhase& phase = mesh == 0 ? p.sun_planet : p.planet_ring;
      const int za = mesh == 0 ? spec.sun.teeth : spec.planet.teeth;
      const int zb = mesh == 0 ? spec.planet.teeth : spec.ring.teeth;
      pairs_in_contact(m, phase, za, zb, 0.0, prev);
      for (int k = 1; k <= 5 * 997; ++k) {
        const int np = pairs_in_contact(m, phase, za, zb, k * ds, cur);
        ASSERT_TRUE(np == 1 || np == 2) << np;
        for (const ContactPair& c : cur) {
          EXPECT_GE(c.xi_m, m.start_active_m - 1e-12);
          EXPECT_LE(c.xi_m, m.end_active_m + 1e-12);
          bool continued = false;
          for (const ContactPair& q : prev) {
            if (q.tooth_a == c.tooth_a) {
              EXPECT_EQ(q.tooth_b, c.tooth_b);
              EXPECT_NEAR(c.xi_m - q.xi_m, ds, 1e-12);
              continued = true;
            }
          }
          if (!continued) {
            EXPECT_LT(c.xi_m, m.start_active_m + ds + 1e-12);  // newly entered
          }
        }
        for (const ContactPair& q : prev) {
          bool kept = false;
          for (const ContactPair& c : cur) kept = kept || c.tooth_a == q.tooth_a;
          if (!kept) {
            EXPECT_GT(q.xi_m, m.end_active_m - ds - 1e-12);  // left at the tip of A
          }
        }
        std::swap(prev, cur);
      }
    }
  }
}

TEST(PairsInContact, NextPairEngagesTheNextToothOnBothGears) {
  const model::StageSpec spec;
  const StageGeometry g = make_stage_geometry(spec);
  const MeshPhase phase = mesh_phases(spec, g)[1].planet_ring;
  std::vector<ContactPair> out;
  // s chosen so that two pairs are in contact: n and n + 1.
  const double s = g.planet_ring.end_active_m - phase.xi0_m - 1e-6;
  ASSERT_EQ(pairs_in_contact(g.planet_ring, phase, 30, 81, s, out), 2);
  EXPECT_GT(out[0].xi_m, out[1].xi_m);  // older pair first
  EXPECT_NEAR(out[0].xi_m - out[1].xi_m, g.planet_ring.base_pitch_m, 1e-15);
  EXPECT_EQ(out[1].tooth_a, (out[0].tooth_a + 1) % 30);
  EXPECT_EQ(out[1].tooth_b, (out[0].tooth_b + 1) % 81);
}

TEST(PairsInContact, ReusesTheCallersBufferAndKeepsIndicesInRangeForAnyRoll) {
  // Allocation-free in the integrator loop: with capacity reserved, the
  // buffer is never reallocated (same data pointer and capacity).
  const model::StageSpec spec;
  const StageGeometry g = make_stage_geometry(spec);
  const MeshPhase phase = mesh_phases(spec, g)[2].sun_planet;
  std::vector<ContactPair> out;
  out.reserve(8);
  const ContactPair* data = out.data();
  for (int k = -5000; k < 5000; ++k) {
    const double s = k * 0.0123456;  // up to +-62 m of roll, ~7000 mesh cycles
    const int np = pairs_in_contact(g.sun_planet, phase, 21, 30, s, out);
    ASSERT_TRUE(np == 1 || np == 2);
    for (const ContactPair& c : out) {
      ASSERT_GE(c.tooth_a, 0);
      ASSERT_LT(c.tooth_a, 21);
      ASSERT_GE(c.tooth_b, 0);
      ASSERT_LT(c.tooth_b, 30);
    }
  }
  EXPECT_EQ(out.data(), data);
  EXPECT_EQ(out.capacity(), 8u);
}

} // namespace

TEST(EngagementWeight, RampsLinearlyOverOneStepCentredOnTheEngagementPointsAndIsSharpForZeroWidth) {
  const model::StageSpec spec;
  const StageGeometry g = make_stage_geometry(spec);
  const MeshGeometry& m = g.sun_planet;
  const double a = m.start_active_m, b = m.end_active_m, h = 20e-6;
  EXPECT_DOUBLE_EQ(engagement_weight(m, a - h, h), 0.0);
  EXPECT_DOUBLE_EQ(engagement_weight(m, a - 2 * h, h), 0.0);
  EXPECT_NEAR(engagement_weight(m, a, h), 0.5, 1e-12);
  EXPECT_NEAR(engagement_weight(m, a + 0.5 * h, h), 0.75, 1e-9);
  EXPECT_DOUBLE_EQ(engagement_weight(m, a + h, h), 1.0);
  EXPECT_DOUBLE_EQ(engagement_weight(m, 0.5 * (a + b), h), 1.0);
  EXPECT_NEAR(engagement_weight(m, b, h), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(engagement_weight(m, b + h, h), 0.0);
  // h = 0: the indicator of the active path.
  EXPECT_DOUBLE_EQ(engagement_weight(m, a - 1e-9, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(engagement_weight(m, a, 0.0), 1.0);
  EXPECT_DOUBLE_EQ(engagement_weight(m, b + 1e-9, 0.0), 0.0);
}

TEST(EngagementWeight, WeightedPairCountAveragedOverTheRollEqualsTheContactRatio) {
  // The ramps are centred on the engagement points, so smoothing moves no contact
  // time: the mean of sum_j w_j over a mesh cycle stays the contact ratio (path
  // length / base pitch), for any margin below half the path.
  const model::StageSpec spec;
  const StageGeometry g = make_stage_geometry(spec);
  for (int fam = 0; fam < 2; ++fam) {
    const MeshGeometry& m = fam == 0 ? g.sun_planet : g.planet_ring;
    const MeshPhase phase = fam == 0 ? mesh_phases(spec, g)[0].sun_planet : mesh_phases(spec, g)[0].planet_ring;
    const int za = fam == 0 ? 21 : 30, zb = fam == 0 ? 30 : 81;
    const double eps = (m.end_active_m - m.start_active_m) / m.base_pitch_m;
    std::vector<ContactPair> out;
    for (double h : {0.0, 1e-5, 2e-4}) {
      const int n = 20000;
      double sum = 0;
      for (int k = 0; k < n; ++k) {
        const double s = (k + 0.5) / n * m.base_pitch_m;
        pairs_in_contact(m, phase, za, zb, s, out, h);
        for (const ContactPair& c : out) sum += engagement_weight(m, c.xi_m, h);
      }
      EXPECT_NEAR(sum / n, eps, 2.0 / n) << "family " << fam << ", h = " << h;
    }
  }
}

} // namespace pw::geometry
