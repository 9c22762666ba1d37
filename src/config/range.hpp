// The allowed values of a configuration key, stated once, in the schema (schema.hpp), beside the
// key, its field and its doc. model::validate checks every stated interval (a visitor over the
// schema) and, by hand, only the rules that involve other keys; `planetwear keys` lists the
// ranges; tests/io/test_config_ranges.cpp holds docs/config.md's Range column to them.
//
// Every number of the schema states one of:
//  * an interval (possibly half-infinite), with the ends that belong to it;
//  * any finite value (angles, signed quantities);
//  * a rule: the range depends on other keys (below the module, at most the mesh period / 8,
//    a tooth index below that gear's tooth count) or has a message of its own; model::validate
//    checks it with the keys it depends on, and the rule's text says which.
// A test fails when a number states none (tests/io/test_config_ranges.cpp).
#pragma once

#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <string_view>

namespace pw::config {

/// Which ends of [lower, upper] belong to the allowed interval.
enum class Ends { Closed, Open, OpenLow, OpenHigh };

enum class RangeKind : std::uint8_t {
  Unstated,  ///< not a number (booleans, enumerations: their reader accepts only their values)
  Interval,  ///< lower..upper, ends as `ends`
  Finite,    ///< any finite value
  Rule,      ///< depends on other keys or has its own message: model::validate
};

struct Range {
  RangeKind kind = RangeKind::Unstated;
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  Ends ends = Ends::Closed;
  std::string_view note;  ///< the unit and what a message adds to it ("kg m^2; 0 = derived"); a rule's text

  bool lower_open() const { return ends == Ends::Open || ends == Ends::OpenLow; }
  bool upper_open() const { return ends == Ends::Open || ends == Ends::OpenHigh; }
  bool bounded_above() const { return upper != std::numeric_limits<double>::infinity(); }
  /// Whether `value` lies in the interval (NaN and +-inf never do).
  bool contains(double value) const {
    if (!(value == value) || value == std::numeric_limits<double>::infinity() ||
        value == -std::numeric_limits<double>::infinity())
      return false;
    if (kind != RangeKind::Interval) return true;
    return (lower_open() ? value > lower : value >= lower) &&
           (!bounded_above() || (upper_open() ? value < upper : value <= upper));
  }
};

/// [lower, upper] with the given ends.
constexpr Range interval(double lower, double upper, Ends ends, std::string_view note) {
  return Range{RangeKind::Interval, lower, upper, ends, note};
}
/// >= lower.
constexpr Range at_least(double lower, std::string_view note) {
  return interval(lower, std::numeric_limits<double>::infinity(), Ends::Closed, note);
}
/// > lower.
constexpr Range above(double lower, std::string_view note) {
  return interval(lower, std::numeric_limits<double>::infinity(), Ends::OpenLow, note);
}
/// An integer key's [lower, upper].
constexpr Range integers(int lower, int upper) { return interval(lower, upper, Ends::Closed, "-"); }
/// Any finite value.
constexpr Range any_finite(std::string_view unit) {
  return Range{RangeKind::Finite, 0, 0, Ends::Closed, unit};
}
/// Checked by model::validate with the keys it depends on; `rule` says how ("m; below the module").
constexpr Range rule(std::string_view rule_text) { return Range{RangeKind::Rule, 0, 0, Ends::Closed, rule_text}; }

/// "in (0, 1]", ">= 0", "> 0" as messages and the key listing write it (numbers as error
/// messages print them: 10 significant digits).
inline std::string describe(const Range& r) {
  std::ostringstream os;
  os.precision(10);
  switch (r.kind) {
  case RangeKind::Unstated: return "";
  case RangeKind::Finite: return "finite";
  case RangeKind::Rule: return std::string(r.note);
  case RangeKind::Interval: break;
  }
  if (!r.bounded_above()) {
    os << (r.lower_open() ? "> " : ">= ") << r.lower;
  } else {
    os << "in " << (r.lower_open() ? "(" : "[") << r.lower << ", " << r.upper << (r.upper_open() ? ")" : "]");
  }
  return os.str();
}

} // namespace pw::config
