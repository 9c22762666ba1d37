#include "diagnose/line_coverage.hpp"

#include "core/format.hpp"

#include <algorithm>
#include <cmath>

namespace pw::diagnose {
namespace {

const LineCoverage* coverage_of(const std::vector<LineCoverage>& coverage, Quantity q) {
  for (const LineCoverage& c : coverage)
    if (c.quantity == q && c.lines > 0) return &c;
  return nullptr;
}

/// The speed at which a healthy recording carries the tested end nearest to f at f: a line of a
/// fixed carrier order moves in proportion to the speed.
double covering_speed(const LineCoverage& c, double f_Hz) {
  if (f_Hz < c.lowest_Hz) return c.lowest_speed_rpm * f_Hz / c.lowest_Hz;
  return c.highest_speed_rpm * f_Hz / c.highest_Hz;
}

std::string span_text(const LineCoverage& c) {
  return c.lowest_Hz == c.highest_Hz ? fmt("%.0f Hz", c.lowest_Hz)
                                     : fmt("%.0f", c.lowest_Hz) + "-" + fmt("%.0f Hz", c.highest_Hz);
}

} // namespace

CoverageGap coverage_gap(const std::vector<LocatedLine>& lines, const std::vector<LineCoverage>& coverage,
                         double resolution_Hz) {
  const double half_cell = 0.5 * std::max(0.0, resolution_Hz);
  CoverageGap gap;
  if (coverage.empty()) return gap;
  gap.known = true;
  gap.coverage = coverage;
  double total = 0, outside = 0;
  for (const LocatedLine& l : lines) {
    const double excess = std::max(0.0, l.chi2 - 1.0);
    total += excess;
    const LineCoverage* c = coverage_of(coverage, l.quantity);
    if (c && l.frequency_Hz >= c->lowest_Hz - half_cell && l.frequency_Hz <= c->highest_Hz + half_cell) continue;
    outside += excess;
    if (excess <= 0) continue;
    gap.lines.push_back({l.channel, l.quantity, l.frequency_Hz, l.order, excess, c ? covering_speed(*c, l.frequency_Hz) : 0.0});
  }
  gap.share = total > 0 ? outside / total : 0.0;
  std::stable_sort(gap.lines.begin(), gap.lines.end(),
                   [](const UncoveredLine& a, const UncoveredLine& b) { return a.excess > b.excess; });
  return gap;
}

std::string coverage_gap_text(const CoverageGap& gap) {
  if (!gap.known || gap.lines.empty()) return "";
  // Presentation only: the three strongest uncovered lines (report.json lists them all).
  constexpr std::size_t kLinesNamed = 3;
  std::string where, spans;
  std::vector<Quantity> named;
  for (std::size_t i = 0; i < gap.lines.size() && i < kLinesNamed; ++i) {
    const UncoveredLine& l = gap.lines[i];
    where += (where.empty() ? "" : ", ") + fmt("%.0f Hz", l.frequency_Hz) + " (" + l.channel + ")";
    if (std::find(named.begin(), named.end(), l.quantity) != named.end()) continue;
    named.push_back(l.quantity);
    const LineCoverage* c = coverage_of(gap.coverage, l.quantity);
    spans += (spans.empty() ? "" : ", ") + std::string(to_string(l.quantity)) + " " +
             (c ? span_text(*c) : std::string("none"));
  }
  const UncoveredLine& top = gap.lines.front();
  std::string s = "; " + fmt("%.0f", 100 * gap.share) + " % of the strongest lines' excess lies where no healthy line " +
                  "tested the calibrated model (" + where + "; tested: " + spans +
                  "): a fit there is judged through the model's transfer to the sensor at frequencies no healthy " +
                  "recording checked";
  if (top.covering_speed_rpm > 0)
    s += " — a healthy recording at about " + fmt("%.0f", top.covering_speed_rpm) + " rpm would test " +
         fmt("%.0f Hz", top.frequency_Hz) + " on " + top.channel;
  return s;
}

} // namespace pw::diagnose
