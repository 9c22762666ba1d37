// One tooth's compliance (stiffness/tooth_compliance.hpp): the beam-energy
// integral against closed forms, its quadrature convergence, the load
// geometry against the flank's own normal, and the monotonicity along the
// profile that every potential-energy model must show.
#include "stiffness/tooth_compliance.hpp"

#include "config/stage.hpp"
#include "core/error.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

using namespace pw;
using namespace pw::stiffness;
using geometry::GearKind;
using geometry::GearSpec;

namespace {

ToothModelOptions options_for(const GearSpec& g) {
  ToothModelOptions o;
  if (g.kind == GearKind::Internal) o.body_ratio = 1.4;
  return o;
}

/// Radii on the involute flank from the beam root towards the tip, n points.
std::vector<double> flank_radii(const ToothModel& m, int n) {
  const auto& g = m.geometry();
  const bool internal = m.spec().kind == GearKind::Internal;
  const double from = internal ? g.root_radius_m : std::fmax(g.base_radius_m, g.root_radius_m);
  const double to = g.tip_radius_m;
  std::vector<double> r(n);
  for (int i = 0; i < n; ++i) r[i] = from + (to - from) * i / (n - 1);
  return r;
}

} // namespace

TEST(Quadrature, GaussLegendreIsExactForPolynomialsOfDegreeUpTo2nMinus1) {
  // An n-point rule integrates x^k exactly for k <= 2n-1 (and not x^{2n},
  // whose error, ~4^-n, is checked where it is above round-off: n <= 12).
  for (int n = 1; n <= 24; ++n) {
    const GaussLegendreRule rule = gauss_legendre(n);
    for (int k = 0; k <= 2 * n - 1; ++k) {
      const double exact = (k % 2 == 1) ? 0.0 : 2.0 / (k + 1);
      const double got = integrate(rule, -1.0, 1.0, [k](double x) { return std::pow(x, k); });
      EXPECT_NEAR(got, exact, 2e-15 * (1 + n)) << "n = " << n << ", k = " << k;
    }
    const double exact2n = 2.0 / (2 * n + 1);
    const double got2n = integrate(rule, -1.0, 1.0, [n](double x) { return std::pow(x, 2 * n); });
    if (n <= 12) {
      EXPECT_GT(std::fabs(got2n - exact2n), 1e-9 * exact2n) << "degree 2n must not be exact, n = " << n;
    }
  }
}

TEST(BeamIntegral, UniformCantileverMatchesClosedFormBendingShearAndAxial) {
  // A prismatic cantilever (thickness t = 2h, length L, width b) loaded at its
  // free end: tip deflection F L^3 / (3 E I) = 4 F L^3 / (E b t^3) for a force
  // normal to the axis; shear kappa L / (G b t); axial L / (E b t). With the
  // force at angle a1 and offset h_c the bending integral is the closed form
  // int_0^L [cos(a1)(L - s) - sin(a1) h_c]^2 ds / (E I). Tolerance 1e-12:
  // the integrands are polynomials of degree <= 2, exact for any rule n >= 2.
  const double L = 7e-3, h = 2.5e-3, t = 2 * h, b = 0.05, E = 2.1e11, G = 8.1e10;
  const auto uniform = [&](double s) { return BeamSection{s, h, 1.0}; };
  const BeamElasticity el{E, G, 1.2, b};
  const GaussLegendreRule rule = gauss_legendre(4);

  const ToothCompliance c0 = beam_compliance(uniform, 0.0, L, BeamLoad{L, 0.0, 0.0}, el, rule);
  EXPECT_NEAR(c0.bending_m_N, 4 * L * L * L / (E * b * t * t * t), 1e-12 * c0.bending_m_N);
  EXPECT_NEAR(c0.shear_m_N, 1.2 * L / (G * b * t), 1e-12 * c0.shear_m_N);
  EXPECT_EQ(c0.axial_m_N, 0.0);

  const double a1 = 0.3, hc = h;
  const ToothCompliance c1 = beam_compliance(uniform, L, 0.0, BeamLoad{L, hc, a1}, el, rule);  // reversed limits
  const double ca = std::cos(a1), sa = std::sin(a1);
  const double I = b * t * t * t / 12;
  const double bend = (ca * ca * L * L * L / 3 - ca * sa * hc * L * L + sa * sa * hc * hc * L) / (E * I);
  EXPECT_NEAR(c1.bending_m_N, bend, 1e-12 * bend);
  EXPECT_NEAR(c1.shear_m_N, 1.2 * ca * ca * L / (G * b * t), 1e-12 * c1.shear_m_N);
  EXPECT_NEAR(c1.axial_m_N, sa * sa * L / (E * b * t), 1e-12 * c1.axial_m_N);
}

TEST(BeamIntegral, ToothComplianceConvergesExponentiallyWithGaussPoints) {
  // The roll-angle parametrisation makes the integrand analytic, so the error
  // must fall geometrically: below 1e-3 at 8 points, 1e-6 at 12, and to
  // round-off (1e-12) at 24, the default. Reference: 200 points. Seed gears,
  // contact at the tip (the longest lever, the hardest case).
  const model::StageSpec st;
  for (const GearSpec* g : {&st.sun, &st.planet, &st.ring}) {
    ToothModelOptions o = options_for(*g);
    o.quadrature_points = 200;
    const ToothModel ref(*g, o);
    const double r = ref.geometry().tip_radius_m;
    const double c_ref = ref.compliance(r).total_m_N();
    double previous = 1.0;
    for (int n : {4, 8, 12, 16, 24}) {
      o.quadrature_points = n;
      const double err = std::fabs(ToothModel(*g, o).compliance(r).total_m_N() / c_ref - 1.0);
      if (n == 8) {
        EXPECT_LT(err, 1e-3) << "z = " << g->teeth;
      }
      if (n == 12) {
        EXPECT_LT(err, 1e-6) << "z = " << g->teeth;
      }
      if (n == 24) {
        EXPECT_LT(err, 1e-12) << "z = " << g->teeth;
      }
      if (previous > 1e-13) {
        EXPECT_LT(err, previous) << "z = " << g->teeth << ", n = " << n;
      }
      previous = err;
    }
  }
}

TEST(ToothLoad, LoadAngleIsTheAngleOfTheFlankNormalToTheCentrelineNormal) {
  // alpha1 (Tian 2004: alpha_r - theta_r for an external tooth; alpha_r +
  // theta_r for a ring tooth, derived in docs/stiffness.md §1.2) must be the
  // angle between the flank normal, computed here by differentiating the
  // flank point r (cos theta(r), sin theta(r)) numerically, and the normal to
  // the centreline. Central differences with dr = 1e-7 r: error ~1e-9 rad.
  const model::StageSpec st;
  for (const GearSpec* g : {&st.sun, &st.planet, &st.ring}) {
    const ToothModel m(*g, options_for(*g));
    for (double r : flank_radii(m, 9)) {
      const auto& geo = m.geometry();
      if (r <= geo.base_radius_m * (1 + 1e-6)) continue;
      const double dr = 1e-7 * r;
      const auto flank = [&](double rr) {
        const double th = geometry::half_tooth_angle_at(*g, geo, rr);
        return std::array<double, 2>{rr * std::cos(th), rr * std::sin(th)};
      };
      const auto p1 = flank(r + dr), p0 = flank(r - dr);
      const double tx = p1[0] - p0[0], ty = p1[1] - p0[1];
      // The tangent's angle from the centreline equals the normal's angle from
      // the centreline's normal.
      const double expected_alpha1 = std::atan2(std::fabs(ty), std::fabs(tx));
      EXPECT_NEAR(m.load_at(r).beam.angle_rad, expected_alpha1, 1e-7) << "z = " << g->teeth << ", r = " << r;
    }
  }
}

TEST(ToothStiffness, DecreasesAsTheContactMovesTowardsTheTipOfThatGear) {
  // The total compliance of the tooth must rise strictly from root to tip:
  // outward for sun and planet, inward for the ring tooth. (The bending part
  // alone is not monotone next to the root, where the axial component's
  // moment -F sin(a1) h_c outweighs the short lever; over the outer half of
  // the flank the lever dominates and bending rises too.)
  const model::StageSpec st;
  for (const GearSpec* g : {&st.sun, &st.planet, &st.ring}) {
    const ToothModel m(*g, options_for(*g));
    const std::vector<double> radii = flank_radii(m, 41);
    double prev_total = 0, prev_bending = -1;
    for (std::size_t i = 0; i < radii.size(); ++i) {
      const ToothCompliance c = m.compliance(radii[i]);
      EXPECT_GT(c.total_m_N(), prev_total) << "z = " << g->teeth << ", r = " << radii[i];
      if (i >= radii.size() / 2) {
        EXPECT_GT(c.bending_m_N, prev_bending) << "z = " << g->teeth << ", r = " << radii[i];
      }
      prev_total = c.total_m_N();
      prev_bending = c.bending_m_N;
    }
  }
}

TEST(ToothStiffness, PlaneStrainScalesTheEModulusTermsByOneMinusNuSquared) {
  // Plane strain replaces E by E/(1-nu^2) in bending, axial and fillet terms
  // and leaves the shear term (G) alone: ratio 1 - nu^2 = 0.91 to round-off.
  const model::StageSpec st;
  ToothModelOptions strain, stress;
  strain.elastic_state = ElasticState::PlaneStrain;
  stress.elastic_state = ElasticState::PlaneStress;
  const double r = 45e-3;  // planet pitch radius
  const ToothCompliance a = ToothModel(st.planet, strain).compliance(r);
  const ToothCompliance b = ToothModel(st.planet, stress).compliance(r);
  const double f = 1 - 0.3 * 0.3;
  EXPECT_NEAR(a.bending_m_N / b.bending_m_N, f, 1e-13);
  EXPECT_NEAR(a.axial_m_N / b.axial_m_N, f, 1e-13);
  EXPECT_NEAR(a.fillet_m_N / b.fillet_m_N, f, 1e-13);
  EXPECT_NEAR(a.shear_m_N / b.shear_m_N, 1.0, 1e-13);
}

TEST(Hertz, ComplianceIsYangLinFourOneMinusNuSquaredOverPiEb) {
  // Yang & Lin (1987): k_h = pi E b / (4 (1 - nu^2)). Seed: E 206 GPa, nu 0.3,
  // b 50 mm -> 1/k_h = 4 * 0.91 / (pi * 206e9 * 0.05) = 1.12491e-10 m/N.
  geometry::Material steel;
  const double hand = 4 * 0.91 / (std::numbers::pi * 206e9 * 0.05);
  EXPECT_NEAR(hertz_compliance(steel, steel, 0.05), hand, 1e-15 * hand);
  EXPECT_NEAR(hand, 1.12491e-10, 1e-15);
  // Two materials: the compliance is the mean of the equal-material values.
  geometry::Material soft = steel;
  soft.youngs_modulus_Pa = 103e9;
  const double mixed = 0.5 * (hertz_compliance(steel, steel, 0.05) + hertz_compliance(soft, soft, 0.05));
  EXPECT_NEAR(hertz_compliance(steel, soft, 0.05), mixed, 1e-15 * mixed);
}

TEST(Fillet, HalfAngleAtTheRootIsWhereTheRackTipRoundMeetsTheRootCircle) {
  // theta_f = (2/z)[pi/4 + h_f* tan a0 + rho_f* (1 - sin a0)/cos a0]; for z 17,
  // ISO 53 rack (1.25, 0.38), 20 deg: 0.17723 rad, the value an independent
  // plane-strain FE study of the generated z 17 tooth quotes (0.177).
  GearSpec g{17};
  g.pressure_angle_rad = 20 * std::numbers::pi / 180;
  const double a0 = g.pressure_angle_rad;
  const double hand = 2.0 / 17 * (std::numbers::pi / 4 + 1.25 * std::tan(a0) + 0.38 * (1 - std::sin(a0)) / std::cos(a0));
  EXPECT_NEAR(fillet_half_angle(g), hand, 1e-15);
  EXPECT_NEAR(hand, 0.17723, 5e-5);
  // Profile shift moves the root circle, not the rack abscissa of the round.
  g.profile_shift = 0.4;
  EXPECT_NEAR(fillet_half_angle(g), hand, 1e-15);
}

TEST(Fillet, SainsotPolynomialReproducesTheTabulatedCoefficientsAtAHandPoint) {
  // Sainsot et al. 2004 Table 1 at h_f = 2, theta_f = 0.1 rad, evaluated by
  // hand term by term (A/th^2 + B h^2 + C h/th + D/th + E h + F).
  const FilletCoefficients c = sainsot_coefficients(2.0, 0.1);
  EXPECT_NEAR(c.L, -5.574e-3 - 7.9944e-3 - 4.6030e-3 + 4.7702e-2 + 0.0542 + 6.8045, 1e-12);
  EXPECT_NEAR(c.M, 6.0111e-2 + 0.1124 - 0.166862 - 9.9256e-2 + 0.3248 + 0.9086, 1e-12);
  EXPECT_NEAR(c.P, -5.0952e-2 + 0.742 + 1.076e-4 + 0.533 + 0.579 + 0.9236, 1e-12);
  EXPECT_NEAR(c.Q, -6.2042e-3 + 3.63556e-2 - 8.1928e-3 + 7.8297e-2 - 0.2944 + 0.6904, 1e-12);
}

TEST(ToothModel, RejectsAContactRadiusOffTheFlank) {
  const model::StageSpec st;
  const ToothModel sun(st.sun);
  try {
    (void)sun.compliance(sun.geometry().tip_radius_m * 1.01);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(e.parameter(), "contact_radius_m");
  }
  const ToothModel ring(st.ring, options_for(st.ring));
  EXPECT_THROW((void)ring.compliance(ring.geometry().tip_radius_m * 0.99), InputError);
  ToothModelOptions bad;
  bad.quadrature_points = 1;
  EXPECT_THROW(ToothModel(st.sun, bad), InputError);
}
