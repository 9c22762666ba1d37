// A level changed since the baseline (level_change.hpp) when the baseline's own value of that level
// is an edge of its box: the ratio is then a bound on the change, and the text says which way.
#include "diagnose/level_change.hpp"

#include "diagnose/baseline.hpp"
#include "diagnose/verdict.hpp"

#include <gtest/gtest.h>

namespace pw::diagnose {
namespace {

FittedParameter parameter(const std::string& name, double value, double lower, double upper, bool at_bound) {
  FittedParameter p;
  p.name = name;
  p.value = value;
  p.lower = lower;
  p.upper = upper;
  p.at_bound = at_bound;
  return p;
}

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

TEST(BoundEnds, ListsTheBaselinesParametersAtAnEdgeByKeyWithTheEndAndSkipsGainsAndFits) {
  const FittedParameter k = parameter("stiffness.scale", 2.0, 0.5, 2.0, true);
  const FittedParameter z = parameter("contact.mesh_damping_ratio", 0.002, 0.002, 0.25, true);
  const FittedParameter inside = parameter("sensor.encoder_bandwidth_Hz", 800, 10, 1e6, false);
  FittedParameter gain = parameter("sensor.gain_m_s2_per_N", 3, 0, 1e6, true);
  gain.sensor_gain = true;
  const std::map<std::string, int> ends = bound_ends({k, z, inside, gain});
  ASSERT_EQ(ends.size(), 2u);
  EXPECT_EQ(ends.at("stiffness.scale"), +1);
  EXPECT_EQ(ends.at("contact.mesh_damping_ratio"), -1);
  // The same parameters as the report's texts.
  EXPECT_EQ(bound_texts({k, z, inside, gain}).size(), 2u);
}

} // namespace
} // namespace pw::diagnose

namespace pw::diagnose {
namespace {

TEST(LimitedReference, NamesEachLimitWithItsEdgeAndNothingWithoutLimits) {
  EXPECT_TRUE(limited_reference_text({}).empty());
  EXPECT_EQ(limited_reference_text({{"stiffness.scale", -1}}),
            "the reference's model with stiffness.scale at the lower edge of its box (a limit, not a fit)");
  EXPECT_EQ(limited_reference_text({{"stiffness.scale", +1}, {"contact.mesh_damping_ratio", -1}}),
            "the reference's model with contact.mesh_damping_ratio at the lower edge of its box and stiffness.scale "
            "at the upper edge of its box (limits, not fits)");
}

} // namespace
} // namespace pw::diagnose
