// Independent reference for the lateral-torsional planetary model of
//
//   J. Lin, R. G. Parker, "Analytical characterization of the unique
//   properties of planetary gear free vibration", J. Vib. Acoust. 121(3):
//   316-321, 1999. https://doi.org/10.1115/1.2893982
//
// built directly from the paper's block matrices, NOT from planetwear's
// generic model assembly, so that the two can be compared (test-only code,
// header-only, no dependency on src/dynamics).
//
// Model (time-invariant, Omega = 0: gyroscopic G and centripetal K_Omega
// terms dropped, as for the paper's free-vibration example):
//   M q'' + (K_b + K_m) q = 0,
//   q = [x_c y_c u_c | x_r y_r u_r | x_s y_s u_s | zeta_1 eta_1 u_1 | ... | zeta_N eta_N u_N],
// with x, y translations of the carrier (c), ring (r) and sun (s) in the
// carrier-fixed frame, zeta_n (radial) and eta_n (tangential) the translation
// of planet n relative to its nominal position at angle psi_n, and u = r theta
// the rotation of each body times its base radius (carrier: the radius of the
// circle through the planet centres). Because every rotational coordinate is
// a length, inertias enter as I/r^2 [kg] and torsional supports as k_u =
// k_theta / r^2 [N/m]; no radius is needed once these are given.
//
// Deflections underlying the blocks (all compressive-positive) [m]:
//   sun-planet n mesh   d_sn = -x_s sin psi_sn + y_s cos psi_sn - zeta_n sin a_s
//                              - eta_n cos a_s + u_s + u_n,     psi_sn = psi_n - a_s
//   ring-planet n mesh  d_rn = -x_r sin psi_rn + y_r cos psi_rn + zeta_n sin a_r
//                              - eta_n cos a_r + u_r - u_n,     psi_rn = psi_n + a_r
//   carrier-planet n bearing, radial     d_pz = zeta_n - (x_c cos psi_n + y_c sin psi_n)
//                             tangential d_pe = eta_n - (-x_c sin psi_n + y_c cos psi_n + u_c)
// Strain energy V = 1/2 sum_n [k_sp d_sn^2 + k_rp d_rn^2 + k_p (d_pz^2 + d_pe^2)]
// + the central bearings gives K_m = d^2 V / dq^2. mesh_stiffness() writes the
// resulting sub-matrices out explicitly in the paper's block layout;
// stiffness_from_deflections() assembles the same energy numerically as
// sum k d d^T, and the test checks the two agree. The blocks also agree with
// the independent transcription in gfsReboucas/Drivetrain (Lin_Parker_99.m).
#pragma once

#include <Eigen/Dense>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

namespace pw::test::lin_parker {

/// Parameters in the paper's notation; units [kg], [N/m], [rad].
struct Parameters {
  double m_c = 0, m_r = 0, m_s = 0, m_p = 0;  ///< masses [kg]
  double J_c = 0, J_r = 0, J_s = 0, J_p = 0;  ///< I / r^2 [kg] (r: base radius; carrier: centre circle)
  double k_sp = 0, k_rp = 0;                  ///< sun-planet, ring-planet mesh stiffness [N/m]
  double k_c = 0, k_r = 0, k_s = 0;           ///< central-member bearing stiffness (x and y) [N/m]
  double k_p = 0;                             ///< planet bearing stiffness (zeta and eta) [N/m]
  double k_cu = 0, k_ru = 0, k_su = 0;        ///< torsional supports k_theta / r^2 [N/m]
  double alpha_s = 0, alpha_r = 0;            ///< sun-planet, ring-planet pressure angles [rad]
  std::vector<double> psi;                    ///< planet angles psi_n [rad]
};

/// The example system of the paper (its Table 1) with `planets` equally
/// spaced planets: m_s, m_r, m_c, m_p = 0.4, 2.35, 5.43, 0.66 kg; I/r^2 =
/// 0.39, 3.00, 6.29, 0.61 kg; k_sp = k_rp = 5e8 N/m; all bearings 1e8 N/m;
/// k_ru = 1e9 N/m; k_su = k_cu = 0; alpha_s = alpha_r = 24.6 deg.
inline Parameters table1_example(int planets = 3) {
  Parameters p;
  p.m_s = 0.4;
  p.m_r = 2.35;
  p.m_c = 5.43;
  p.m_p = 0.66;
  p.J_s = 0.39;
  p.J_r = 3.00;
  p.J_c = 6.29;
  p.J_p = 0.61;
  p.k_sp = p.k_rp = 5e8;
  p.k_c = p.k_r = p.k_s = p.k_p = 1e8;
  p.k_ru = 1e9;
  p.k_su = p.k_cu = 0;
  p.alpha_s = p.alpha_r = 24.6 * std::numbers::pi / 180.0;
  for (int n = 0; n < planets; ++n) p.psi.push_back(2.0 * std::numbers::pi * n / planets);
  return p;
}

/// Index of the first coordinate of each body in q.
inline constexpr Eigen::Index kCarrier = 0, kRing = 3, kSun = 6;
inline Eigen::Index planet_offset(std::size_t n) { return 9 + 3 * static_cast<Eigen::Index>(n); }
inline Eigen::Index dof_count(const Parameters& p) { return planet_offset(p.psi.size()); }

/// M = diag(M_c, M_r, M_s, M_p, ..., M_p), M_h = diag(m_h, m_h, I_h / r_h^2).
inline Eigen::MatrixXd mass_matrix(const Parameters& p) {
  Eigen::VectorXd d(dof_count(p));
  d.segment<3>(kCarrier) << p.m_c, p.m_c, p.J_c;
  d.segment<3>(kRing) << p.m_r, p.m_r, p.J_r;
  d.segment<3>(kSun) << p.m_s, p.m_s, p.J_s;
  for (std::size_t n = 0; n < p.psi.size(); ++n) d.segment<3>(planet_offset(n)) << p.m_p, p.m_p, p.J_p;
  return d.asDiagonal();
}

/// K_b = diag(K_c, K_r, K_s, 0, ..., 0), K_h = diag(k_h, k_h, k_hu).
inline Eigen::MatrixXd bearing_stiffness(const Parameters& p) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(dof_count(p));
  d.segment<3>(kCarrier) << p.k_c, p.k_c, p.k_cu;
  d.segment<3>(kRing) << p.k_r, p.k_r, p.k_ru;
  d.segment<3>(kSun) << p.k_s, p.k_s, p.k_su;
  return d.asDiagonal();
}

/// K_m in the paper's block layout:
///   [ sum K_c1^n   0            0            K_c2^1 ... K_c2^N ]
///   [              sum K_r1^n   0            K_r2^1 ... K_r2^N ]
///   [                           sum K_s1^n   K_s2^1 ... K_s2^N ]
///   [ sym                                    diag(K_c3 + K_r3^n + K_s3^n) ]
inline Eigen::MatrixXd mesh_stiffness(const Parameters& p) {
  using M3 = Eigen::Matrix3d;
  const Eigen::Index n_dof = dof_count(p);
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n_dof, n_dof);
  const double sas = std::sin(p.alpha_s), cas = std::cos(p.alpha_s);
  const double sar = std::sin(p.alpha_r), car = std::cos(p.alpha_r);

  // Planet-planet blocks, the same for every planet.
  M3 Kc3, Kr3, Ks3;
  Kc3 << 1, 0, 0,
         0, 1, 0,
         0, 0, 0;
  Kr3 << sar * sar, -sar * car, -sar,
         -sar * car, car * car, car,
         -sar, car, 1;
  Ks3 << sas * sas, sas * cas, -sas,
         sas * cas, cas * cas, -cas,
         -sas, -cas, 1;
  const M3 Kpp = p.k_p * Kc3 + p.k_rp * Kr3 + p.k_sp * Ks3;

  for (std::size_t n = 0; n < p.psi.size(); ++n) {
    const double sp = std::sin(p.psi[n]), cp = std::cos(p.psi[n]);
    const double psr = p.psi[n] + p.alpha_r, pss = p.psi[n] - p.alpha_s;
    const double sr = std::sin(psr), cr = std::cos(psr);
    const double ss = std::sin(pss), cs = std::cos(pss);

    M3 Kc1, Kc2, Kr1, Kr2, Ks1, Ks2;
    Kc1 << 1, 0, -sp,
           0, 1, cp,
           -sp, cp, 1;
    Kc2 << -cp, sp, 0,
           -sp, -cp, 0,
           0, -1, 0;
    Kr1 << sr * sr, -sr * cr, -sr,
           -sr * cr, cr * cr, cr,
           -sr, cr, 1;
    Kr2 << -sr * sar, sr * car, sr,
           cr * sar, -cr * car, -cr,
           sar, -car, -1;
    Ks1 << ss * ss, -ss * cs, -ss,
           -ss * cs, cs * cs, cs,
           -ss, cs, 1;
    Ks2 << ss * sas, ss * cas, -ss,
           -cs * sas, -cs * cas, cs,
           -sas, -cas, 1;

    const Eigen::Index j = planet_offset(n);
    K.block<3, 3>(kCarrier, kCarrier) += p.k_p * Kc1;
    K.block<3, 3>(kRing, kRing) += p.k_rp * Kr1;
    K.block<3, 3>(kSun, kSun) += p.k_sp * Ks1;
    K.block<3, 3>(kCarrier, j) += p.k_p * Kc2;
    K.block<3, 3>(kRing, j) += p.k_rp * Kr2;
    K.block<3, 3>(kSun, j) += p.k_sp * Ks2;
    K.block<3, 3>(j, kCarrier) += p.k_p * Kc2.transpose();
    K.block<3, 3>(j, kRing) += p.k_rp * Kr2.transpose();
    K.block<3, 3>(j, kSun) += p.k_sp * Ks2.transpose();
    K.block<3, 3>(j, j) += Kpp;
  }
  return K;
}

/// K = K_b + K_m (Omega = 0).
inline Eigen::MatrixXd stiffness_matrix(const Parameters& p) {
  return bearing_stiffness(p) + mesh_stiffness(p);
}

/// Second, independent route to the same K: every spring contributes
/// k d d^T, where d is the gradient of its deflection (header comment).
inline Eigen::MatrixXd stiffness_from_deflections(const Parameters& p) {
  const Eigen::Index n_dof = dof_count(p);
  Eigen::MatrixXd K = bearing_stiffness(p);
  auto add = [&K](double k, const Eigen::VectorXd& d) { K += k * d * d.transpose(); };
  for (std::size_t n = 0; n < p.psi.size(); ++n) {
    const Eigen::Index z = planet_offset(n), e = z + 1, u = z + 2;
    const double psi = p.psi[n];
    const double pss = psi - p.alpha_s, psr = psi + p.alpha_r;

    Eigen::VectorXd d = Eigen::VectorXd::Zero(n_dof);  // sun-planet mesh
    d(kSun) = -std::sin(pss);
    d(kSun + 1) = std::cos(pss);
    d(kSun + 2) = 1;
    d(z) = -std::sin(p.alpha_s);
    d(e) = -std::cos(p.alpha_s);
    d(u) = 1;
    add(p.k_sp, d);

    d.setZero();  // ring-planet mesh
    d(kRing) = -std::sin(psr);
    d(kRing + 1) = std::cos(psr);
    d(kRing + 2) = 1;
    d(z) = std::sin(p.alpha_r);
    d(e) = -std::cos(p.alpha_r);
    d(u) = -1;
    add(p.k_rp, d);

    d.setZero();  // planet bearing, radial
    d(z) = 1;
    d(kCarrier) = -std::cos(psi);
    d(kCarrier + 1) = -std::sin(psi);
    add(p.k_p, d);

    d.setZero();  // planet bearing, tangential
    d(e) = 1;
    d(kCarrier) = std::sin(psi);
    d(kCarrier + 1) = -std::cos(psi);
    d(kCarrier + 2) = -1;
    add(p.k_p, d);
  }
  return K;
}

/// One natural frequency and the modes belonging to it.
struct ModeGroup {
  double frequency_Hz = 0;
  int multiplicity = 0;
  Eigen::MatrixXd shapes;  ///< n_dof x multiplicity, M-orthonormal
};

/// Solves K phi = omega^2 M phi (Eigen::GeneralizedSelfAdjointEigenSolver)
/// and groups eigenvalues whose omega^2 differ by less than rel_tol (relative
/// to the largest) into one degenerate frequency.
inline std::vector<ModeGroup> natural_modes(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K,
                                            double rel_tol = 1e-8) {
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(K, M);
  const Eigen::VectorXd& lambda = es.eigenvalues();  // ascending
  const double scale = lambda.cwiseAbs().maxCoeff();
  std::vector<ModeGroup> groups;
  Eigen::Index i = 0;
  while (i < lambda.size()) {
    Eigen::Index j = i + 1;
    while (j < lambda.size() && lambda(j) - lambda(i) < rel_tol * scale) ++j;
    ModeGroup g;
    const double omega2 = lambda.segment(i, j - i).mean();
    g.frequency_Hz = omega2 > 0 ? std::sqrt(omega2) / (2 * std::numbers::pi) : 0.0;
    g.multiplicity = static_cast<int>(j - i);
    g.shapes = es.eigenvectors().middleCols(i, j - i);
    groups.push_back(std::move(g));
    i = j;
  }
  return groups;
}

} // namespace pw::test::lin_parker
