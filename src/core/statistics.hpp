// Quantiles of the normal and chi-square distributions: the one implementation
// every significance threshold of the diagnosis uses (noise test, locate,
// heteroscedasticity, verdict, calibration); and the modified Bessel functions
// the Rician moments of the comparison need.
#pragma once

namespace pw {

/// Upper quantile of the standard normal: z with P(Z > z) = p, p in (0, 1)
/// (Boost.Math; until 2026-11 Acklam's approximation with a Halley step, which
/// agreed to < 1e-12 with the tables in tests/core/test_statistics.cpp).
/// Throws pw::InputError ("p") outside (0, 1).
double normal_quantile(double p);

/// Upper quantile of chi2(nu): the value exceeded with probability alpha, by
/// the Wilson-Hilferty cube of a normal quantile, nu (1 - h + z sqrt(h))^3 with
/// h = 2/(9 nu). An approximation: 0.8 % low at nu = 1, alpha = 0.01; 0.13 % at
/// nu = 10; 2e-4 at nu = 100. Throws pw::InputError ("nu") for nu <= 0.
/// *Why not Boost.Math's exact chi-squared quantile:* the diagnosis's verdict
/// thresholds and its corpus results were measured with these values; moving
/// to the exact ones is a behaviour change to make with a corpus re-run.
double chi2_quantile(double nu, double alpha);

/// Upper quantile of the F distribution F(nu1, nu2): the value exceeded with probability
/// alpha (Boost.Math, exact). The extra-sum-of-squares test of nested least-squares models
/// compares an improvement per added parameter with the residual per degree of freedom
/// against it. Throws pw::InputError ("nu1", "nu2", "alpha") for nu <= 0 or alpha outside (0, 1).
double f_quantile(double nu1, double nu2, double alpha);

/// Upper quantile of Student's t with nu degrees of freedom: the value exceeded with
/// probability alpha (Boost.Math, exact; nu may be fractional, as a Welch-Satterthwaite
/// effective number is). A difference judged against a standard deviation estimated from nu
/// degrees of freedom (a calibration's few healthy recordings) is a t variable, not a normal one.
/// Throws pw::InputError ("nu", "alpha") for nu <= 0 or alpha outside (0, 1).
double student_t_quantile(double nu, double alpha);

/// Modified Bessel functions of the first kind I_0(x) and I_1(x), x >= 0 (Boost.Math's
/// rational approximations for these orders, evaluated in double: within a few ulp, 3e-15
/// relative of std::cyl_bessel_i over [0, 160], at a tenth of its cost: 55 against 630 ns per
/// pair, session 42; the Rician mean of every compared cell of every score calls them).
double bessel_i0(double x);
double bessel_i1(double x);

} // namespace pw
