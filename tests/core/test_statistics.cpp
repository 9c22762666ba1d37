// The one implementation of the normal and chi-square quantiles
// (core/statistics.hpp) against published table values. Table values: the
// inverse normal CDF and chi-square percentage points (Abramowitz & Stegun
// 26.2, 26.4; to the digits given there and by Python's
// statistics.NormalDist / scipy.stats.chi2).
#include "core/statistics.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pw {
namespace {

/// |got - want| <= tol |want|, printing both on failure.
void expect_relative(double got, double want, double tol) {
  EXPECT_NEAR(got, want, tol * std::fabs(want)) << "relative tolerance " << tol;
}

TEST(NormalQuantile, MatchesTablesToOneInABillion) {
  // normal_quantile(p) is the UPPER quantile: P(Z > z) = p.
  expect_relative(normal_quantile(0.025), 1.959963984540054, 1e-9);
  expect_relative(normal_quantile(0.05), 1.6448536269514715, 1e-9);
  expect_relative(normal_quantile(0.01), 2.3263478740408408, 1e-9);
  expect_relative(normal_quantile(0.005), 2.5758293035489004, 1e-9);
  expect_relative(normal_quantile(0.001), 3.090232306167813, 1e-9);  // Acklam's lower tail region
  expect_relative(normal_quantile(1e-7), 5.199337582290662, 1e-9);
  expect_relative(normal_quantile(0.99), -2.3263478740408408, 1e-9);  // upper tail region
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-15);
}

TEST(NormalQuantile, AgreesWithBisectionOfTheCdf) {
  // The bisection on erfc that order_analysis.cpp used before there was one implementation.
  for (double p : {1e-6, 1e-4, 0.001, 0.0025, 0.01, 0.02425, 0.05, 0.1, 0.3, 0.6, 0.9, 0.97575, 0.999}) {
    double lo = -10, hi = 10;
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (0.5 * std::erfc(-mid / std::numbers::sqrt2) < 1 - p) lo = mid; else hi = mid;
    }
    const double z = 0.5 * (lo + hi);
    EXPECT_NEAR(normal_quantile(p), z, 1e-9 * std::fabs(z) + 1e-15) << "p = " << p;
  }
}

TEST(NormalQuantile, RejectsProbabilitiesOutsideZeroOne) {
  EXPECT_THROW((void)normal_quantile(0.0), InputError);
  EXPECT_THROW((void)normal_quantile(1.0), InputError);
}

TEST(Chi2Quantile, IsTheWilsonHilfertyCubeOfTheNormalQuantile) {
  for (double nu : {1.0, 2.0, 10.0, 100.0})
    for (double alpha : {0.05, 0.01, 0.005}) {
      const double z = normal_quantile(alpha), h = 2 / (9 * nu), t = 1 - h + z * std::sqrt(h);
      expect_relative(chi2_quantile(nu, alpha), nu * t * t * t, 1e-15);
    }
}

TEST(Chi2Quantile, IsWithinTheWilsonHilfertyErrorOfTheTables) {
  // An approximation, exact only as nu grows: the diagnosis's thresholds are these values,
  // so the tolerances are the approximation's own error, not 1e-6.
  expect_relative(chi2_quantile(1, 0.01), 6.634896601021214, 8e-3);    // W-H: 6.5858, 0.74 % low
  expect_relative(chi2_quantile(10, 0.01), 23.209251158954356, 1.5e-3);  // W-H: 23.2394, 0.13 % high
  expect_relative(chi2_quantile(100, 0.005), 140.1694894423138, 2e-4);   // W-H: 140.1933, 1.7e-4 high
  expect_relative(chi2_quantile(5, 0.05), 11.070497693516351, 3e-3);    // W-H: 11.0443, 0.24 % low
}

TEST(Chi2Quantile, KeepsTheValuesTheDiagnosisWasCalibratedWith) {
  // Regression values of the implementation before the two copies were merged.
  expect_relative(chi2_quantile(1, 0.01), 6.585773097, 1e-9);
  expect_relative(chi2_quantile(10, 0.01), 23.239351218, 1e-9);
  expect_relative(chi2_quantile(100, 0.005), 140.193287620, 1e-9);
}

TEST(Chi2Quantile, RejectsNonPositiveDegreesOfFreedom) { EXPECT_THROW((void)chi2_quantile(0, 0.01), InputError); }

TEST(FQuantile, MatchesTheTablesToTheirPrintedDigits) {
  // NIST/SEMATECH e-Handbook of Statistical Methods, section 1.3.6.7.3 (upper critical values of
  // the F distribution, 3 decimals): the tolerance is half the last printed digit.
  EXPECT_NEAR(f_quantile(2, 10, 0.05), 4.103, 5e-4);
  EXPECT_NEAR(f_quantile(3, 20, 0.05), 3.098, 5e-4);
  EXPECT_NEAR(f_quantile(1, 10, 0.01), 10.044, 5e-4);
  EXPECT_NEAR(f_quantile(2, 100, 0.01), 4.824, 5e-4);
}

TEST(FQuantile, TendsToTheChiSquareQuantilePerDegreeOfFreedomAndSwapsItsTails) {
  // nu1 F(nu1, nu2) -> chi2(nu1) as nu2 -> infinity: chi2_{0.99}(2) = -2 ln 0.01 exactly.
  expect_relative(2 * f_quantile(2, 1e9, 0.01), -2 * std::log(0.01), 1e-6);
  // F_{1-a}(n1, n2) = 1 / F_a(n2, n1).
  expect_relative(f_quantile(3, 7, 0.05), 1 / f_quantile(7, 3, 0.95), 1e-10);
  EXPECT_THROW((void)f_quantile(0, 5, 0.01), InputError);
  EXPECT_THROW((void)f_quantile(2, 5, 1.0), InputError);
}

TEST(StudentTQuantile, MatchesTheTablesToTheirPrintedDigits) {
  // NIST/SEMATECH e-Handbook of Statistical Methods, section 1.3.6.7.2 (upper critical values of
  // Student's t, 3 decimals): the tolerance is half the last printed digit.
  EXPECT_NEAR(student_t_quantile(1, 0.005), 63.657, 5e-4);
  EXPECT_NEAR(student_t_quantile(3, 0.005), 5.841, 5e-4);
  EXPECT_NEAR(student_t_quantile(10, 0.025), 2.228, 5e-4);
  EXPECT_NEAR(student_t_quantile(30, 0.05), 1.697, 5e-4);
}

TEST(StudentTQuantile, TendsToTheNormalQuantileAndIsTheSquareRootOfF1) {
  // t(nu) -> N(0, 1) as nu -> infinity; t^2(nu) = F(1, nu), so t_{a/2}(nu)^2 = F_a(1, nu).
  expect_relative(student_t_quantile(1e9, 0.005), normal_quantile(0.005), 1e-6);
  expect_relative(student_t_quantile(4.5, 0.005) * student_t_quantile(4.5, 0.005), f_quantile(1, 4.5, 0.01), 1e-9);
  EXPECT_THROW((void)student_t_quantile(0, 0.01), InputError);
  EXPECT_THROW((void)student_t_quantile(3, 0.0), InputError);
}

} // namespace
// I0 and I1 at tabulated points (Abramowitz & Stegun, Table 9.8, 10 digits: e^-x I_n(x) there,
// multiplied back here) and within 1e-14 of the standard library's over the range the Rician
// mean evaluates them (y = (nu / 2 s)^2 up to 156).
TEST(BesselI, MatchesTablesAndTheStandardLibrary) {
  EXPECT_EQ(pw::bessel_i0(0.0), 1.0);
  EXPECT_EQ(pw::bessel_i1(0.0), 0.0);
  EXPECT_NEAR(pw::bessel_i0(1.0), 1.266065878, 1e-9);
  EXPECT_NEAR(pw::bessel_i1(1.0), 0.565159104, 1e-9);
  EXPECT_NEAR(pw::bessel_i0(10.0) / 2815.716628, 1.0, 1e-9);
  EXPECT_NEAR(pw::bessel_i1(10.0) / 2670.988304, 1.0, 1e-9);
  for (double y = 0.01; y < 160; y *= 1.07) {
    EXPECT_NEAR(pw::bessel_i0(y) / std::cyl_bessel_i(0.0, y), 1.0, 1e-14) << y;
    EXPECT_NEAR(pw::bessel_i1(y) / std::cyl_bessel_i(1.0, y), 1.0, 1e-14) << y;
  }
}

} // namespace pw
