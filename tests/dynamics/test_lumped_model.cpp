// The kinematic assembly (lumped_model.cpp) against published and closed-form
// natural frequencies.
#include "dynamics/lumped_model.hpp"
#include "dynamics/modal.hpp"

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

using namespace pw::dynamics;

namespace {

/// Lin & Parker 1999 (J. Vib. Acoust. 121:316), Table 1 example, in our
/// rotational coordinates: I = (I/r^2) r^2 with any consistent radius, since
/// the eigenvalues do not depend on the choice of r in u = r theta.
StageLayout lin_parker_layout() {
  StageLayout l;
  const double alpha = 24.6 * std::numbers::pi / 180;
  l.sun_base_radius_m = 0.5 * 77.4e-3;
  l.planet_base_radius_m = 0.5 * 100.3e-3;
  l.carrier_radius_m = (l.sun_base_radius_m + l.planet_base_radius_m) / std::cos(alpha);
  l.ring_base_radius_m = l.carrier_radius_m * std::cos(alpha) + l.planet_base_radius_m;
  l.sun_planet_pressure_angle_rad = alpha;
  l.planet_ring_pressure_angle_rad = alpha;
  l.planet_angles_rad = {0, 2 * std::numbers::pi / 3, 4 * std::numbers::pi / 3};
  l.sun_mass_kg = 0.4;
  l.ring_mass_kg = 2.35;
  l.carrier_mass_kg = 5.43;
  l.planet_mass_kg = 0.66;
  l.sun_inertia_kgm2 = 0.39 * std::pow(l.sun_base_radius_m, 2);
  l.ring_inertia_kgm2 = 3.00 * std::pow(l.ring_base_radius_m, 2);
  l.carrier_inertia_kgm2 = 6.29 * std::pow(l.carrier_radius_m, 2);
  l.planet_inertia_kgm2 = 0.61 * std::pow(l.planet_base_radius_m, 2);
  return l;
}

std::vector<double> sorted(const Eigen::VectorXd& v) {
  std::vector<double> s(v.data(), v.data() + v.size());
  std::sort(s.begin(), s.end());
  return s;
}

// MeshId names each mesh by planet and kind; the structure's mesh array is in
// MeshId's order for both model levels (the names the builders give agree).
TEST(LumpedModel, MeshIdIndexesTheStructuresMeshesByPlanetAndKindForBothLevels) {
  StageLayout l = lin_parker_layout();
  for (const LumpedStructure& s : {build_torsional(l), build_lateral_torsional(l, Bearings{})}) {
    ASSERT_EQ(s.meshes.size(), 2 * l.planet_angles_rad.size());
    for (int i = 0; i < static_cast<int>(l.planet_angles_rad.size()); ++i) {
      const MeshId sp{i, MeshKind::SunPlanet}, pr{i, MeshKind::PlanetRing};
      EXPECT_EQ(s.meshes[static_cast<std::size_t>(sp.index())].name, "sun_planet/" + std::to_string(i));
      EXPECT_EQ(s.meshes[static_cast<std::size_t>(pr.index())].name, "planet_ring/" + std::to_string(i));
      for (const MeshId id : {sp, pr}) {
        const MeshId back = MeshId::of(id.index());
        EXPECT_EQ(back.planet, id.planet);
        EXPECT_EQ(back.kind, id.kind);
      }
    }
  }
}

} // namespace

TEST(LumpedModel, LateralTorsionalMatchesLinParker1999TableWithin0p1Percent) {
  const StageLayout l = lin_parker_layout();
  Bearings b;
  b.sun_N_m = b.ring_N_m = b.carrier_N_m = b.planet_N_m = 1e8;
  b.ring_torsional_N_m = 1e9;
  const LumpedStructure s = build_lateral_torsional(l, b);
  ASSERT_EQ(s.dofs, 18);
  const Eigen::MatrixXd K = s.support_stiffness + mesh_stiffness_matrix(s, std::vector<double>(6, 5e8));
  const std::vector<double> f = sorted(natural_frequencies(s.mass, K).frequencies_Hz);
  // Published: rotational (single) and translational (double) modes, Hz.
  std::vector<double> expected = {0.0, 1475.7, 1930.3, 2658.3, 7462.8, 11775.3};
  for (double d : {743.2, 1102.4, 1896.0, 2276.4, 6986.3, 9647.9}) {
    expected.push_back(d);
    expected.push_back(d);
  }
  std::sort(expected.begin(), expected.end());
  ASSERT_EQ(f.size(), expected.size());
  EXPECT_LT(f[0], 1e-3) << "rigid-body rotation of sun + carrier";
  for (std::size_t i = 1; i < f.size(); ++i)
    EXPECT_NEAR(f[i], expected[i], 1e-3 * expected[i]) << "mode " << i;
}

TEST(LumpedModel, TorsionalPlanetModeMatchesClosedFormWithMultiplicityNMinus1) {
  // With the sun and carrier held (very large inertia does the same), planet
  // i is a rotor between two springs: omega^2 = (k_sp + k_rp) r_bp^2 / I_p,
  // multiplicity N - 1 in the full model (REFERENCE.md, Lin & Parker 1999).
  StageLayout l = lin_parker_layout();
  l.planet_angles_rad = {0, 0.5 * std::numbers::pi, std::numbers::pi, 1.5 * std::numbers::pi};
  const LumpedStructure s = build_torsional(l);
  const double k = 4e8;
  const Eigen::MatrixXd K = mesh_stiffness_matrix(s, std::vector<double>(8, k));
  const std::vector<double> f = sorted(natural_frequencies(s.mass, K).frequencies_Hz);
  const double fp = std::sqrt(2 * k * std::pow(l.planet_base_radius_m, 2) / l.planet_inertia_kgm2) /
                    (2 * std::numbers::pi);
  int count = 0;
  for (double x : f) count += std::fabs(x - fp) < 1e-9 * fp;
  EXPECT_EQ(count, 3) << "planet mode " << fp << " Hz must appear N-1 = 3 times";
}

TEST(LumpedModel, NominalPlanetSpeedRollsOnBothSunAndRing) {
  // Planet speed is set from the sun mesh; with the ring at the kinematically
  // consistent speed it must also roll on the ring: w_p r_bp = w_r r_br.
  StageLayout l = lin_parker_layout();
  l.sun_speed_rel_rad_s = 10.0;
  l.ring_speed_rel_rad_s = -l.sun_base_radius_m / l.ring_base_radius_m * l.sun_speed_rel_rad_s;
  for (const LumpedStructure& s : {build_torsional(l), build_lateral_torsional(l, Bearings{})})
    for (std::size_t i = 0; i < s.planet_bodies.size(); ++i) {
      const auto& sp = s.meshes[2 * i];
      const auto& pr = s.meshes[2 * i + 1];
      EXPECT_NEAR(sp.nominal_speed_b_rad_s, -l.sun_speed_rel_rad_s * l.sun_base_radius_m / l.planet_base_radius_m,
                  1e-12);
      EXPECT_DOUBLE_EQ(pr.nominal_speed_a_rad_s, sp.nominal_speed_b_rad_s);
      EXPECT_NEAR(pr.nominal_speed_a_rad_s * l.planet_base_radius_m,
                  pr.nominal_speed_b_rad_s * l.ring_base_radius_m, 1e-12);
      EXPECT_GT(sp.nominal_roll_rate_m_s, 0);
      EXPECT_NEAR(sp.nominal_roll_rate_m_s, pr.nominal_roll_rate_m_s, 1e-12) << "one mesh frequency";
    }
}

TEST(LumpedModel, FrictionArmsAreFlankCurvatureRadiiAndVanishAtPitchPoint) {
  // Nominal sliding speed must vanish at the pitch point xi_P = r_bA tan(alpha)
  // and grow linearly away from it: external (w_A + w_B)(xi - xi_P), internal
  // (w_A - w_B)(xi - xi_P) with relative speeds (REFERENCE.md, "Kinematics").
  StageLayout l = lin_parker_layout();
  l.sun_speed_rel_rad_s = 10.0;
  l.ring_speed_rel_rad_s = -l.sun_base_radius_m / l.ring_base_radius_m * l.sun_speed_rel_rad_s;
  const LumpedStructure s = build_torsional(l);
  const double a = l.sun_planet_pressure_angle_rad;
  const auto& sp = s.meshes[0];
  const auto& pr = s.meshes[1];
  auto vs = [](const MeshCoupling& m, double xi) { return m.nominal_slide0_m_s + xi * m.nominal_slide1_1_s; };
  const double xi_sp = l.sun_base_radius_m * std::tan(a), xi_pr = l.planet_base_radius_m * std::tan(a);
  EXPECT_NEAR(vs(sp, xi_sp), 0.0, 1e-12);
  EXPECT_NEAR(vs(pr, xi_pr), 0.0, 1e-12);
  const double wA = l.sun_speed_rel_rad_s, wB = wA * l.sun_base_radius_m / l.planet_base_radius_m;
  EXPECT_NEAR(std::fabs(vs(sp, xi_sp + 1e-3)), (wA + wB) * 1e-3, 1e-12);
  const double wR = std::fabs(l.ring_speed_rel_rad_s);
  EXPECT_NEAR(std::fabs(vs(pr, xi_pr + 1e-3)), std::fabs(wB - wR) * 1e-3, 1e-12);
  // The friction moment arm vectors h agree with the nominal sliding: the
  // sun's entry of h(xi) is the sun flank's radius of curvature, xi.
  EXPECT_NEAR(std::fabs((sp.h0 + 0.02 * sp.h1)(0)), 0.02, 1e-12);
}

// bearings.damping_ratio: every support gets c = 2 zeta sqrt(k m). With the meshes at zero
// stiffness the sun's and the ring's supports hold single bodies, so each of their modes is a
// one-degree-of-freedom oscillator whose damped eigenvalues satisfy |lambda| = sqrt(k/m) and
// -Re(lambda)/|lambda| = zeta exactly (closed form); the state-space eigenvalues of the
// assembled M, C, K must show both. zeta = 0 must leave the support damping exactly zero (the
// default reproduces Lin & Parker's undamped supports bit for bit).
TEST(LumpedModel, SupportDampingRatioGivesEachSingleBodySupportModeThatRatio) {
  const StageLayout l = lin_parker_layout();
  Bearings b;
  b.sun_N_m = b.ring_N_m = b.carrier_N_m = b.planet_N_m = 1e8;
  b.ring_torsional_N_m = 1e9;
  EXPECT_EQ(build_lateral_torsional(l, b).support_damping.norm(), 0.0);
  const double zeta = 0.05;
  b.damping_ratio = zeta;
  const LumpedStructure s = build_lateral_torsional(l, b);
  const int n = s.dofs;
  const Eigen::MatrixXd K = s.support_stiffness + mesh_stiffness_matrix(s, std::vector<double>(6, 0.0));
  const Eigen::MatrixXd Minv = s.mass.inverse();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n) = Eigen::MatrixXd::Identity(n, n);
  A.bottomLeftCorner(n, n) = -Minv * K;
  A.bottomRightCorner(n, n) = -Minv * s.support_damping;
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues();
  // sun lateral, ring lateral, ring torsional (k_ru r^2 on I_r = m_eq r^2): sqrt(k/m) [rad/s]
  const double omega[] = {std::sqrt(b.sun_N_m / l.sun_mass_kg), std::sqrt(b.ring_N_m / l.ring_mass_kg),
                          std::sqrt(b.ring_torsional_N_m * std::pow(l.ring_base_radius_m, 2) / l.ring_inertia_kgm2)};
  for (double w : omega) {
    int found = 0;
    for (Eigen::Index i = 0; i < lambda.size(); ++i)
      if (std::abs(std::abs(lambda[i]) / w - 1) < 1e-9) {
        ++found;
        EXPECT_NEAR(-lambda[i].real() / std::abs(lambda[i]), zeta, 1e-9) << "mode at " << w << " rad/s";
      }
    EXPECT_GE(found, 2) << "no conjugate pair at the closed-form " << w << " rad/s";
  }
}
