// round_trip (core/format.hpp): the text of a --set line or a file reads back as
// exactly the double that was written, and is no longer than needed.
#include "core/format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

TEST(RoundTrip, ReadsBackBitForBit) {
  const double values[] = {0.1 + 0.2, 1.0 / 3.0, 2.0 / 3.0 * 1e-6, 1e-300, 4.9e-324 /* denormal */,
                           std::numeric_limits<double>::max(), -123.456, 2.6675871498734e-5};
  for (double v : values) EXPECT_EQ(std::strtod(pw::round_trip(v).c_str(), nullptr), v) << pw::round_trip(v);
}

TEST(RoundTrip, IsTheShortestText) {
  EXPECT_EQ(pw::round_trip(123.5), "123.5");
  EXPECT_EQ(pw::round_trip(0.1), "0.1");
  EXPECT_EQ(pw::round_trip(2.0), "2");
  // %.9g would have written 0.333333333, which reads back as another double.
  EXPECT_NE(std::stod("0.333333333"), 1.0 / 3.0);
  EXPECT_EQ(pw::round_trip(1.0 / 3.0).size(), 18u);  // "0.3333333333333333"
}
