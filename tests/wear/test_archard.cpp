// Archard wear formulas (src/wear/archard.hpp).
#include "wear/archard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pw::wear;

TEST(Archard, SweptElementBookingIntegratesToTheClosedFormPerPass) {
  // Constant load and sliding: a contact sweeping over an involute flank at
  // rolling speed v_r books kappa F' |v_s| dt / l_e into the element it is in
  // (W2). Over one pass every element must hold kappa F' |v_s| / v_r (W1),
  // whatever the element size, up to the dt discretization at its edges.
  const double kappa = 5e-17, w = 2e4, vs = 0.05, rb = 0.03, omega = 10.0;
  const double rho0 = 0.005, rho1 = 0.02;
  const int E = 16;
  std::vector<double> l(E), h(E, 0.0);
  const double drho = (rho1 - rho0) / E;
  for (int e = 0; e < E; ++e) l[e] = involute_arc_length(rb, rho0 + e * drho, rho0 + (e + 1) * drho);
  // On the involute the contact moves along the line of action at
  // omega r_b, so rho(t) = rho0 + omega r_b t; over the flank at omega rho.
  const double dt = 1e-7;
  for (double t = 0;; t += dt) {
    const double rho = rho0 + omega * rb * (t + 0.5 * dt);
    if (rho >= rho1) break;
    const int e = std::min(E - 1, static_cast<int>((rho - rho0) / drho));
    h[e] += kappa * w * vs * dt / l[e];
  }
  // The flank is crossed at v_r = omega rho, which varies along it: the
  // element value is the arc-length average of kappa w vs / (omega rho).
  for (int e = 0; e < E; ++e) {
    const double a = rho0 + e * drho, b = a + drho;
    const double expected = kappa * w * vs / omega * (b - a) / ((b * b - a * a) / 2);  // <1/rho> weighted by rho
    EXPECT_NEAR(h[e], expected, 2e-4 * expected) << "element " << e;
  }
  EXPECT_NEAR(wear_per_pass(kappa, w, vs, omega * 0.01), kappa * w * vs / (omega * 0.01), 1e-30);
}
