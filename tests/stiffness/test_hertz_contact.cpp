// Hertzian line contact (src/stiffness/hertz_contact.hpp).
#include "stiffness/hertz_contact.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace pw::stiffness;

TEST(HertzContact, HertzLineContactMatchesJohnsonClosedForm) {
  // Johnson, Contact Mechanics (4.45): a = sqrt(4 w R / (pi E*)), p0 = 2w/(pi a).
  const double Es = contact_modulus(206e9, 0.3, 206e9, 0.3);
  EXPECT_NEAR(Es, 206e9 / (2 * (1 - 0.09)), 1.0);
  const auto h = hertz_line_contact(2e4, 0.01, Es);  // 20 N/mm on R = 10 mm
  EXPECT_NEAR(h.half_width_m, std::sqrt(4 * 2e4 * 0.01 / (std::numbers::pi * Es)), 1e-15);
  EXPECT_NEAR(h.mean_pressure_Pa * 2 * h.half_width_m, 2e4, 1e-6);  // mean pressure carries the load
  EXPECT_NEAR(h.max_pressure_Pa, 4 / std::numbers::pi * h.mean_pressure_Pa, 1e-3);
}

TEST(HertzContact, EquivalentRadiusOfConcaveRingFlankIsLarger) {
  EXPECT_NEAR(equivalent_radius(0.01, 0.03, false), 0.0075, 1e-15);
  EXPECT_NEAR(equivalent_radius(0.01, 0.03, true), 0.015, 1e-15);
}
