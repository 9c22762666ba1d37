// Line coverage (diagnose/line_coverage.hpp, calibration.hpp line_coverage): the span of the
// frequencies where healthy lines tested the model is taken from exactly the cells that measure
// the relative discrepancy, and a located excess is split into the part inside and outside it,
// with the speed at which a healthy recording would test an uncovered line.
#include "diagnose/calibration.hpp"
#include "diagnose/line_coverage.hpp"

#include <gtest/gtest.h>

#include <string>

using namespace pw::diagnose;

namespace {

/// A cell of one family at frequency f with model amplitude a and noise variance 0.01; the
/// recording equals the model (no excess), which line_coverage does not look at.
CalibrationCell cell(Quantity q, double f_Hz, double a) {
  CalibrationCell c;
  c.quantity = q;
  c.frequency_Hz = f_Hz;
  c.order = f_Hz;  // any: the span is in hertz
  c.families = {Component::Mesh};
  c.model = a;
  c.noise_variance = 0.01;
  for (int w = 0; w < 2; ++w) {
    c.recording[w] = a;
    c.variance[w] = 0.01;
  }
  return c;
}

LocatedLine line(Quantity q, const std::string& channel, double f_Hz, double chi2) {
  LocatedLine l;
  l.quantity = q;
  l.channel = channel;
  l.frequency_Hz = f_Hz;
  l.order = f_Hz / 2.8125;
  l.chi2 = chi2;
  return l;
}

/// Sun speed tested from 776 Hz (at 600 rpm) to 1552 Hz (at 1200 rpm); nothing else.
std::vector<LineCoverage> sun_coverage() { return {{Quantity::SunSpeed, 776.0, 600.0, 1552.0, 1200.0, 3}}; }

} // namespace

TEST(LineCoverage, SpansTheCellsWithAModelLineAboveTheNoiseAndKeepsEachEndsSpeed) {
  const std::vector<std::vector<CalibrationCell>> cells = {
      // 600 rpm: a cancelled mesh harmonic (model 0) and a housing line below the noise do not count.
      {cell(Quantity::SunSpeed, 194.0, 0.0), cell(Quantity::SunSpeed, 776.0, 1.0), cell(Quantity::SunSpeed, 1552.0, 2.0),
       cell(Quantity::HousingAcceleration, 50.0, 0.05), cell(Quantity::HousingAcceleration, 100.0, 1.0)},
      // 1200 rpm
      {cell(Quantity::SunSpeed, 1552.0, 3.0), cell(Quantity::SunSpeed, 3104.0, 0.5)}};
  const std::vector<LineCoverage> cov = line_coverage(cells, {600.0, 1200.0});
  ASSERT_EQ(cov.size(), 2u);  // no carrier-speed cell: no entry
  const LineCoverage& sun = cov[0].quantity == Quantity::SunSpeed ? cov[0] : cov[1];
  const LineCoverage& housing = cov[0].quantity == Quantity::SunSpeed ? cov[1] : cov[0];
  EXPECT_EQ(sun.lowest_Hz, 776.0);
  EXPECT_EQ(sun.lowest_speed_rpm, 600.0);
  EXPECT_EQ(sun.highest_Hz, 3104.0);
  EXPECT_EQ(sun.highest_speed_rpm, 1200.0);
  EXPECT_EQ(sun.lines, 4);
  EXPECT_EQ(housing.lowest_Hz, 100.0);
  EXPECT_EQ(housing.highest_Hz, 100.0);
  EXPECT_EQ(housing.lines, 1);
  // The same cells as the relative discrepancy is measured on (one family per cell here).
  for (const DiscrepancyEstimate& d : estimate_discrepancy(cells))
    EXPECT_EQ(d.relative_cells, d.quantity == Quantity::SunSpeed ? sun.lines : housing.lines) << to_string(d.quantity);
}

TEST(CoverageGap, SharesTheExcessOfLinesOutsideTheTestedSpanAndNamesTheSpeedThatWouldTestThem) {
  const std::vector<LocatedLine> lines = {
      line(Quantity::SunSpeed, "sun_speed", 194.0, 101.0),          // below: excess 100
      line(Quantity::SunSpeed, "sun_speed", 1000.0, 51.0),          // inside: 50
      line(Quantity::CarrierSpeed, "carrier_speed", 194.0, 26.0),   // a kind never tested: 25
      line(Quantity::SunSpeed, "sun_speed", 3104.0, 0.5),           // no excess: weighs nothing
      line(Quantity::SunSpeed, "sun_speed", 1600.0, 26.0)};         // above: 25
  const CoverageGap gap = coverage_gap(lines, sun_coverage(), 0.0);
  ASSERT_TRUE(gap.known);
  EXPECT_DOUBLE_EQ(gap.share, 150.0 / 200.0);
  ASSERT_EQ(gap.lines.size(), 3u);
  EXPECT_EQ(gap.lines[0].frequency_Hz, 194.0);
  EXPECT_EQ(gap.lines[0].channel, "sun_speed");
  EXPECT_DOUBLE_EQ(gap.lines[0].excess, 100.0);
  // A line of fixed carrier order moves with the speed: 776 Hz at 600 rpm is at 194 Hz at 150 rpm.
  EXPECT_DOUBLE_EQ(gap.lines[0].covering_speed_rpm, 150.0);
  EXPECT_EQ(gap.lines[1].channel, "carrier_speed");  // equal excess: located order kept
  EXPECT_EQ(gap.lines[1].covering_speed_rpm, 0.0);   // nothing tested on that kind of channel
  EXPECT_DOUBLE_EQ(gap.lines[2].covering_speed_rpm, 1200.0 * 1600.0 / 1552.0);
  const std::string text = coverage_gap_text(gap);
  EXPECT_NE(text.find("75 % of the strongest lines' excess"), std::string::npos) << text;
  EXPECT_NE(text.find("194 Hz (sun_speed), 194 Hz (carrier_speed), 1600 Hz (sun_speed)"), std::string::npos) << text;
  EXPECT_NE(text.find("tested: sun_speed 776-1552 Hz, carrier_speed none"), std::string::npos) << text;
  EXPECT_NE(text.find("at about 150 rpm would test 194 Hz on sun_speed"), std::string::npos) << text;
}

TEST(CoverageGap, NothingIsSaidWithoutCoverageOrWhenEveryLineWasTested) {
  const std::vector<LocatedLine> lines = {line(Quantity::SunSpeed, "sun_speed", 194.0, 101.0)};
  const CoverageGap none = coverage_gap(lines, {}, 1.0);
  EXPECT_FALSE(none.known);
  EXPECT_EQ(coverage_gap_text(none), "");
  const CoverageGap inside = coverage_gap({line(Quantity::SunSpeed, "sun_speed", 776.0, 101.0),
                                           line(Quantity::SunSpeed, "sun_speed", 1552.0, 11.0)},
                                          sun_coverage(), 0.0);
  EXPECT_TRUE(inside.known);
  EXPECT_EQ(inside.share, 0.0);
  EXPECT_TRUE(inside.lines.empty());
  EXPECT_EQ(coverage_gap_text(inside), "");
}

TEST(CoverageGap, ALineWithinHalfACellOfATestedEndIsThatEndsLine) {
  // The same carrier order at another recording's speed estimate: 1552.5002 Hz against a tested
  // 1552.5 Hz is the same cell for a recording resolving 1.875 Hz (5.625 Hz carrier, 3
  // revolutions per window); half a cell beyond the end is not.
  const double resolution = 5.625 / 3;
  const CoverageGap same = coverage_gap({line(Quantity::SunSpeed, "sun_speed", 1552.0002, 101.0)},
                                        {{Quantity::SunSpeed, 776.0, 600.0, 1552.0, 1200.0, 3}}, resolution);
  EXPECT_TRUE(same.lines.empty());
  const CoverageGap next = coverage_gap({line(Quantity::SunSpeed, "sun_speed", 1552.0 + 0.51 * resolution, 101.0),
                                         line(Quantity::SunSpeed, "sun_speed", 776.0 - 0.51 * resolution, 101.0)},
                                        {{Quantity::SunSpeed, 776.0, 600.0, 1552.0, 1200.0, 3}}, resolution);
  EXPECT_EQ(next.lines.size(), 2u);
}
