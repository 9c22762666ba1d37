// A level changed since the baseline (level_change.hpp) when the baseline's own value of that level
// is an edge of its box: the ratio is then a bound on the change, and the text says which way.
#include "diagnose/level_change.hpp"

#include <gtest/gtest.h>

#include <string>

namespace pw::diagnose {
namespace {

TEST(OneSidedRatio, ABaselineLevelInsideItsBoxGivesNoNote) {
  EXPECT_TRUE(one_sided_ratio_note("stiffness.scale", 1.2, 0.8, 0).empty());
}

TEST(OneSidedRatio, AnUpperEdgeMakesTheRatioAnUpperBoundAndALowerEdgeALowerBound) {
  // fresh4p rec_13 (session 56): stiffness.scale 1.742 against a baseline at its upper bound 2.
  const std::string up = one_sided_ratio_note("stiffness.scale", 2.0, 0.871, +1);
  EXPECT_NE(up.find("stiffness.scale = 2 is the upper edge"), std::string::npos) << up;
  EXPECT_NE(up.find("smaller than x0.871"), std::string::npos) << up;
  EXPECT_NE(up.find("a bound on the change, not its size"), std::string::npos) << up;
  const std::string down = one_sided_ratio_note("contact.mesh_damping_ratio", 0.002, 2.5, -1);
  EXPECT_NE(down.find("lower edge"), std::string::npos) << down;
  EXPECT_NE(down.find("larger than x2.5"), std::string::npos) << down;
}

} // namespace
} // namespace pw::diagnose
