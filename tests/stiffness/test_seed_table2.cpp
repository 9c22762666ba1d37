// Why is the seed's Table 2 (Bai & Ning 2023) about 100x below ISO 6336?
//
// Seed Table 2: max single-pair stiffness 6.372e6 N/m (both meshes), max
// combined ("general") stiffness 7.776e6 (sun-planet) / 7.033e6 (planet-ring),
// first stiffness excitation 1.558e6 / 1.561e6 N/m. This file evaluates the
// candidate explanations numerically (docs/stiffness.md §4 reproduces the
// printed table: run `build-stiff/tests/test_stiffness --gtest_filter='SeedTable2*'`)
// and pins the conclusions that hold whatever the explanation:
//  * no constant factor (unit slip) maps a physical single-pair curve onto
//    Table 2: the ratios combined-max/single-max and first-harmonic/single-max
//    of Table 2 differ from every potential-energy curve;
//  * the seed's Eq. (9), K1 K2 KH / (K1 + K2 + KH), scales as K^2 (not a
//    stiffness), so its value depends on the unit it is evaluated in;
//  * the seed's own Eqs. (10)-(12) with consistent SI units give a stiffness
//    of order 1e9 N/m, i.e. above, not below, ISO.
#include "stiffness/mesh_stiffness.hpp"

#include "config/stage.hpp"
#include "geometry/mesh.hpp"
#include "stiffness/iso6336.hpp"
#include "stiffness/quadrature.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

using namespace pw;
using namespace pw::stiffness;
using geometry::GearKind;
using geometry::GearSpec;
using geometry::MeshGeometry;

namespace {

struct Table2 {
  double single_sp, single_pr, comb_sp, comb_pr, h1_sp, h1_pr;
};
constexpr Table2 kSeed{6.372e6, 6.372e6, 7.776e6, 7.033e6, 1.558e6, 1.561e6};

struct Stage {
  model::StageSpec st;
  MeshGeometry sp = geometry::make_mesh(st.sun, st.planet);
  MeshGeometry pr = geometry::make_mesh(st.planet, st.ring);
};
const Stage& stage() {
  static const Stage s;
  return s;
}

/// Tabulates any single-pair law k(mesh, xi) like single_pair_stiffness.
PairStiffnessCurve tabulate(const MeshGeometry& m, const std::function<double(double)>& k, int n = 400) {
  PairStiffnessCurve c;
  for (int i = 0; i < n; ++i) {
    const double xi = i == n - 1 ? m.end_active_m : m.start_active_m + (m.end_active_m - m.start_active_m) * i / (n - 1);
    c.xi_m.push_back(xi);
    c.k_N_m.push_back(k(xi));
  }
  return c;
}

Table2 table_of(const PairStiffnessCurve& sp, const PairStiffnessCurve& pr) {
  const MeshStiffnessSummary a = summarize(sp, stage().sp), b = summarize(pr, stage().pr);
  return {a.max_single_pair_N_m, b.max_single_pair_N_m, a.combined_max_N_m,
          b.combined_max_N_m,    a.first_harmonic_N_m,  b.first_harmonic_N_m};
}

Table2 scaled(const Table2& t, double f) {
  return {t.single_sp * f, t.single_pr * f, t.comb_sp * f, t.comb_pr * f, t.h1_sp * f, t.h1_pr * f};
}

/// Our PE model with the given options.
Table2 pe_table(ElasticState state, bool fillet) {
  const Stage& s = stage();
  model::StiffnessSettings set;
  set.include_fillet_foundation = fillet;
  MeshStiffnessOptions o;
  o.elastic_state = state;
  return table_of(single_pair_stiffness(s.sp, s.st.sun, s.st.planet, set, o),
                  single_pair_stiffness(s.pr, s.st.planet, s.st.ring, set, o));
}

/// The seed's Eqs. (10)-(12) taken literally for one tooth at contact radius
/// r_p: chordal thickness eps(y) = 2 tan(theta_p) y (a wedge with the tooth's
/// half angle at P, y the distance from the gear axis), load angle alpha_p
/// (the pressure angle at P), C_s = 1.5, beam from the root circle to P; SI.
double seed_tooth_stiffness(const GearSpec& s, double rp) {
  const geometry::GearGeometry g = geometry::make_geometry(s);
  const double ap = std::acos(g.base_radius_m / rp);
  const double thp = geometry::half_tooth_angle_at(s, g, rp);
  const double t = std::tan(thp);
  const double E = s.material.youngs_modulus_Pa, G = s.material.shear_modulus_Pa, B = s.face_width_m;
  const double lo = std::min(g.root_radius_m, rp), hi = std::max(g.root_radius_m, rp);
  static const GaussLegendreRule rule = gauss_legendre(64);
  const double ix = integrate(rule, lo, hi, [&](double y) {
    const double e = 2 * t * y;
    const double m = std::fabs(rp - y) * std::cos(ap) - rp * std::sin(thp) * std::sin(ap);
    return m * m / (e * e * e);
  });
  const double in = integrate(rule, lo, hi, [&](double y) { return 1 / (2 * t * y); });
  const double cx = 12 / (E * B) * ix;
  const double cn = std::sin(ap) * std::sin(ap) / (E * B) * in;
  const double cs = 1.5 * std::cos(ap) * std::cos(ap) / (G * B) * in;
  return 1 / (cx + cn + cs);
}

double kh_yang_lin(const GearSpec& s) {
  const double nu = s.material.poisson_ratio;
  return std::numbers::pi * s.material.youngs_modulus_Pa * s.face_width_m / (4 * (1 - nu * nu));
}

/// Seed single-pair law: series (physical) or Eq. (9), in unit `u` [N/m per unit].
Table2 seed_table(bool eq9, double unit_N_m) {
  const Stage& s = stage();
  const auto law = [&](const MeshGeometry& m, const GearSpec& a, const GearSpec& b) {
    return [&m, &a, &b, eq9, unit_N_m](double xi) {
      const double k1 = seed_tooth_stiffness(a, geometry::contact_radius_a(m, xi)) / unit_N_m;
      const double k2 = seed_tooth_stiffness(b, geometry::contact_radius_b(m, xi)) / unit_N_m;
      const double kh = kh_yang_lin(a) / unit_N_m;
      return eq9 ? k1 * k2 * kh / (k1 + k2 + kh) : 1 / (1 / k1 + 1 / k2 + 1 / kh);
    };
  };
  return table_of(tabulate(s.sp, law(s.sp, s.st.sun, s.st.planet)), tabulate(s.pr, law(s.pr, s.st.planet, s.st.ring)));
}

/// Geometric-mean factor f mapping t onto the seed, and the largest remaining
/// relative deviation max |f t_i / seed_i - 1| (0 = a pure unit slip).
std::pair<double, double> best_factor(const Table2& t) {
  const double v[6] = {t.single_sp, t.single_pr, t.comb_sp, t.comb_pr, t.h1_sp, t.h1_pr};
  const double w[6] = {kSeed.single_sp, kSeed.single_pr, kSeed.comb_sp, kSeed.comb_pr, kSeed.h1_sp, kSeed.h1_pr};
  double lf = 0;
  for (int i = 0; i < 6; ++i) lf += std::log(w[i] / v[i]) / 6;
  const double f = std::exp(lf);
  double dev = 0;
  for (int i = 0; i < 6; ++i) dev = std::max(dev, std::fabs(f * v[i] / w[i] - 1));
  return {f, dev};
}

void print(const char* name, const Table2& t) {
  const auto [f, dev] = best_factor(t);
  std::printf("[ TABLE2 ] %-44s %10.4e %10.4e %10.4e %10.4e %10.4e %10.4e | factor %9.3e, residual %5.1f %%\n", name,
              t.single_sp, t.single_pr, t.comb_sp, t.comb_pr, t.h1_sp, t.h1_pr, f, 100 * dev);
}

} // namespace

TEST(SeedTable2, CandidateExplanationsPrintedAndNoneIsAPureUnitSlip) {
  const Stage& s = stage();
  std::printf("[ TABLE2 ] %-44s %10s %10s %10s %10s %10s %10s\n", "candidate [N/m]", "single sp", "single pr",
              "comb sp", "comb pr", "h1 sp", "h1 pr");
  print("seed Table 2", kSeed);
  const Table2 pe = pe_table(ElasticState::PlaneStrain, true);
  print("PE (plane strain, Sainsot fillet)", pe);
  print("PE (plane stress, Sainsot fillet)", pe_table(ElasticState::PlaneStress, true));
  const Table2 pe_stress = pe_table(ElasticState::PlaneStress, false);
  print("PE (plane stress, no fillet)", pe_stress);
  const IsoMeshStiffness iso_sp = iso6336_stiffness(s.st.sun, s.st.planet, s.sp.contact_ratio);
  const IsoMeshStiffness iso_pr = iso6336_stiffness(s.st.planet, s.st.ring, s.pr.contact_ratio);
  std::printf("[ TABLE2 ] %-44s %10.4e %10.4e   (c_gamma_alpha %10.4e %10.4e)\n", "ISO 6336-1 c'", iso_sp.c_prime_N_m,
              iso_pr.c_prime_N_m, iso_sp.c_gamma_alpha_N_m, iso_pr.c_gamma_alpha_N_m);
  print("PE x StiffnessSettings::scale 0.01", scaled(pe, 0.01));
  print("PE per mm of face width (/50)", scaled(pe, 1.0 / 50));
  print("PE plane stress no fillet per mm (/50)", scaled(pe_stress, 1.0 / 50));
  print("PE in N/mm labelled N/m (/1e3)", scaled(pe, 1e-3));
  print("PE with E in MPa, SI lengths (/1e6)", scaled(pe, 1e-6));
  print("PE with b = 50 (mm taken as m) (x1e3)", scaled(pe, 1e3));
  {
    // Torsional stiffness on the driver's base radius, k r_b^2 [N m/rad].
    Table2 t = pe;
    const double rs = s.sp.base_radius_a_m, rp = s.pr.base_radius_a_m;
    t = {pe.single_sp * rs * rs, pe.single_pr * rp * rp, pe.comb_sp * rs * rs,
         pe.comb_pr * rp * rp,   pe.h1_sp * rs * rs,     pe.h1_pr * rp * rp};
    print("PE per radian, k r_bA^2 [N m/rad]", t);
  }
  const Table2 seed_series = seed_table(false, 1.0);
  print("seed Eqs (10)-(12) literal, series, SI", seed_series);
  print("seed Eqs (10)-(12), series, per mm (/50)", scaled(seed_series, 1.0 / 50));
  print("seed Eqs (10)-(12) + Eq (9), SI", seed_table(true, 1.0));
  print("seed Eqs (10)-(12) + Eq (9), K in N/mm", seed_table(true, 1e3));
  print("seed Eqs (10)-(12) + Eq (9), K in N/um", seed_table(true, 1e6));

  // Whatever the unit slip, a pure factor cannot reproduce Table 2's shape:
  // the best common factor leaves > 30 % on some entry for every candidate
  // built on a physical curve.
  for (const Table2& t : {pe, pe_stress, seed_series}) EXPECT_GT(best_factor(t).second, 0.30);
}

TEST(SeedTable2, CombinedToSingleRatioOfTheSeedIsBelowEveryPotentialEnergyCurve) {
  // Table 2: combined max / single max = 1.220 (sun-planet), 1.104
  // (planet-ring). With eps = 1.61 and 1.94 the double-contact zones put two
  // pairs of comparable stiffness in parallel; the PE curves give > 1.5.
  const Table2 pe = pe_table(ElasticState::PlaneStrain, true);
  EXPECT_NEAR(kSeed.comb_sp / kSeed.single_sp, 1.220, 1e-3);
  EXPECT_NEAR(kSeed.comb_pr / kSeed.single_pr, 1.104, 1e-3);
  EXPECT_GT(pe.comb_sp / pe.single_sp, 1.5);
  EXPECT_GT(pe.comb_pr / pe.single_pr, 1.5);
}

TEST(SeedTable2, EqualSinglePairPeaksOfBothMeshesAreNotReproducedByToothModels) {
  // The sun (z 21) and the ring (z 81) teeth differ, so the single-pair peaks
  // of the two meshes differ (PE: by ~20 %); Table 2 lists the same 6.372e6.
  const Table2 pe = pe_table(ElasticState::PlaneStrain, true);
  EXPECT_GT(std::fabs(pe.single_pr / pe.single_sp - 1), 0.10);
  const Table2 lit = seed_table(false, 1.0);
  EXPECT_GT(std::fabs(lit.single_pr / lit.single_sp - 1), 0.02);
}

TEST(SeedTable2, Equation9IsNotAStiffnessItsValueDependsOnTheUnit) {
  // K1 K2 KH / (K1 + K2 + KH) is homogeneous of degree 2 in the stiffnesses:
  // evaluated with every K in unit u (N/m per unit) and the result converted
  // back to N/m, it equals the SI evaluation divided by u. A series
  // combination 1/(1/K1 + 1/K2 + 1/KH) is homogeneous of degree 1, the same
  // in every unit.
  const double k1 = 2.5e9, k2 = 2.6e9, kh = 8.9e9;
  const auto eq9 = [](double a, double b, double c) { return a * b * c / (a + b + c); };
  const auto series = [](double a, double b, double c) { return 1 / (1 / a + 1 / b + 1 / c); };
  const double si = eq9(k1, k2, kh);
  const double in_n_mm = eq9(k1 / 1e3, k2 / 1e3, kh / 1e3) * 1e3;  // back to N/m
  EXPECT_NEAR(si / in_n_mm, 1e3, 1e-9 * 1e3);
  EXPECT_NEAR(series(k1, k2, kh), series(k1 / 1e3, k2 / 1e3, kh / 1e3) * 1e3, 1e-3);
}

TEST(SeedTable2, SeedsOwnEquationsInSiUnitsGiveStiffnessAboveIso) {
  // The literal Eqs. (10)-(12) (wedge tooth, C_s = 1.5) with E = 206 GPa,
  // G = 79.4 GPa, B = 0.05 m give a single-pair peak of order 1e9 N/m, above
  // ISO's c' = 6.2e8 N/m (the wedge overstates the thickness near P's radius
  // less than it understates the root, and the load angle alpha_p ignores the
  // tooth's half angle), i.e. the model itself is not 100x too soft.
  const Stage& s = stage();
  const Table2 lit = seed_table(false, 1.0);
  const IsoMeshStiffness iso = iso6336_stiffness(s.st.sun, s.st.planet, s.sp.contact_ratio);
  EXPECT_GT(lit.single_sp, iso.c_prime_N_m);
  EXPECT_GT(lit.single_pr, iso.c_prime_N_m);
  EXPECT_LT(lit.single_sp, 10 * iso.c_prime_N_m);
}
