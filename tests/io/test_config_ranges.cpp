// docs/config.md's "Range" column against model::validate: for every key whose
// range is a plain interval ("> 0", "≥ 0", "[a, b)", "(0, m_sun)", ...), the
// value just outside each end is refused naming that key, the value just inside
// is accepted, and the end itself as the bracket says. A range changed in the code but not in the docs (or the other way)
// fails here. Ranges in words (lists of names, "[0, z-1] of that gear", "0, or
// (0, T_mesh/8]") are not parsed; ends that the docs state but another check
// also decides (the default gears' geometry) are listed in kGeometryDecides with the reason.
#include "io/config_toml.hpp"

#include "core/error.hpp"
#include "io/test_support.hpp"
#include "model/validate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <limits>
#include <map>
#include <optional>
#include <regex>
#include <set>
#include <utility>
#include <sstream>
#include <string>
#include <vector>

namespace pw::io {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct DocumentedRange {
  std::string key;
  bool integer = false;
  double lo = -kInf, hi = kInf;
  bool lo_closed = false, hi_closed = false;
};

/// A number of the Range column, the sun's module (the default configuration's) for "m_sun",
/// or pi/4 for "π/4".
std::optional<double> number(std::string s) {
  const double m_sun = model::SimulationConfig{}.stage.sun.module_m;
  if (s == "m_sun") return m_sun;
  if (s == "π/4") return std::numbers::pi / 4;
  if (s == "-m_sun") return -m_sun;
  try {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used == s.size()) return v;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

/// A plain interval as docs/config.md's Range column or the schema's listing writes it
/// ("> 0", "≥ 0", ">= 0", "(0, 1e5]", "in [16, 100000]"); nullopt for anything else.
std::optional<DocumentedRange> parse_range(std::string range) {
  const std::regex above(R"(^(>|≥|>=) (\S+)$)");
  const std::regex interval(R"(^(?:in )?([\[(])(\S+), (\S+)([\])])$)");
  DocumentedRange r;
  std::smatch b;
  if (std::regex_match(range, b, above)) {
    const auto lo = number(b[2]);
    if (!lo) return std::nullopt;
    r.lo = *lo;
    r.lo_closed = b[1] != ">";
  } else if (std::regex_match(range, b, interval)) {
    const auto lo = number(b[2]), hi = number(b[3]);
    if (!lo || !hi) return std::nullopt;
    r.lo = *lo, r.hi = *hi;
    r.lo_closed = b[1] == "[";
    r.hi_closed = b[4] == "]";
  } else {
    return std::nullopt;
  }
  return r;
}

/// Every key of docs/config.md whose Range cell is a plain interval.
std::vector<DocumentedRange> documented_ranges() {
  std::istringstream doc(test::read_text(test::source_dir() / "docs" / "config.md"));
  const std::regex row(R"(^\| (`[^|]+`) \| (float|integer) \| [^|]* \| [^|]* \| ([^|]+) \|)");
  const std::regex key_re(R"(`([A-Za-z_.\[\]0-9]+)`)");
  std::vector<DocumentedRange> out;
  std::string line;
  while (std::getline(doc, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, row)) continue;
    const std::string keys = m[1], type = m[2];
    std::string range = m[3];
    range.erase(range.find_last_not_of(' ') + 1);
    range.erase(0, range.find_first_not_of(' '));
    std::optional<DocumentedRange> parsed = parse_range(range);
    if (!parsed) continue;
    DocumentedRange r = *parsed;
    r.integer = type == "integer";
    for (auto it = std::sregex_iterator(keys.begin(), keys.end(), key_re); it != std::sregex_iterator(); ++it) {
      r.key = (*it)[1];
      out.push_back(r);
    }
  }
  return out;
}

/// "" if validate() accepts `key = value` on the defaults, else the key its InputError names.
std::string refusal(const std::string& key, double value, bool integer) {
  model::SimulationConfig c;
  std::ostringstream text;
  text.precision(17);
  if (integer)
    text << static_cast<long long>(value);
  else
    text << value;
  try {
    apply_override(c, key, text.str());
    model::validate(c);
  } catch (const InputError& e) {
    return e.parameter().empty() ? "?" : e.parameter();
  }
  return "";
}

/// A value just outside `bound`, on the side `direction` (-1 below, +1 above).
double outside(double bound, int direction, bool integer) {
  if (integer) return bound + direction;
  return bound + direction * std::max(1e-12, 1e-9 * std::fabs(bound));
}

TEST(ConfigRanges, TheDocumentedIntervalsAreTheOnesValidateEnforces) {
  const std::vector<DocumentedRange> ranges = documented_ranges();
  ASSERT_GE(ranges.size(), 60u) << "docs/config.md's table was not parsed";
  // Closed ends where the default gears' geometry, not the key's range, decides: the value is in
  // range, and validate() then refuses it naming the geometric quantity that fails (a pointed
  // tip, a dedendum no deeper than the addendum). Their refusal just outside the end is checked.
  enum class End { Lower, Upper };
  const std::set<std::pair<std::string, End>> kGeometryDecides = {
      {"stage.ring.teeth", End::Lower},                  // 3 ring teeth: no room for the addendum
      {"stage.sun.pressure_angle_deg", End::Upper},       // 45 deg: the sun's tip becomes pointed
      {"stage.planet.pressure_angle_deg", End::Upper},
      {"stage.ring.pressure_angle_deg", End::Lower},      // ~0 deg: the internal addendum leaves the base circle
      {"stage.sun.pressure_angle_rad", End::Upper},       // the same angles in radians
      {"stage.planet.pressure_angle_rad", End::Upper},
      {"stage.ring.pressure_angle_rad", End::Lower},
      {"stage.sun.profile_shift", End::Upper},            // x = 1.5: pointed tip
      {"stage.ring.profile_shift", End::Lower},
      {"stage.sun.addendum_coef", End::Upper},            // h_a* = 2 reaches the default h_f* = 1.25
      {"stage.planet.addendum_coef", End::Upper},
      {"stage.ring.addendum_coef", End::Upper},
  };
  // Lower ends where a rule with another key decides on the defaults: a flexible shaft needs an
  // inertia at its far end, shaft damping needs a flexible shaft (docs/config.md's Meaning column).
  const std::set<std::pair<std::string, End>> kOtherKeysDecide = {
      {"rig.input_shaft_stiffness_N_m_rad", End::Lower},
      {"rig.input_shaft_damping_N_m_s_rad", End::Lower},
      {"rig.output_shaft_stiffness_N_m_rad", End::Lower},
      {"rig.output_shaft_damping_N_m_s_rad", End::Lower},
      {"rig.load_speed_loop_proportional_N_m_s_rad", End::Lower},  // gains need rig.load_control = speed_loop
      {"rig.load_speed_loop_integral_N_m_rad", End::Lower},
      {"rig.input_speed_loop_proportional_N_m_s_rad", End::Lower},  // gains need rig.input_control = speed_loop
      {"rig.input_speed_loop_integral_N_m_rad", End::Lower},
  };
  // The degree keys are aliases: validate() sees (and names) the radian key they set.
  auto named = [](const std::string& key) {
    const std::string deg = "_deg";
    return key.size() > deg.size() && key.compare(key.size() - deg.size(), deg.size(), deg) == 0
               ? key.substr(0, key.size() - deg.size()) + "_rad"
               : key;
  };
  int checked = 0;
  std::vector<std::string> mismatches;
  auto expect = [&](const DocumentedRange& r, double value, bool accepted, const char* where) {
    const std::string got = refusal(r.key, value, r.integer);
    if (accepted ? got.empty() : got == named(r.key)) return;
    std::ostringstream m;
    m.precision(10);
    m << r.key << " = " << value << " (" << where << "): docs say " << (accepted ? "accepted" : "refused")
      << ", validate " << (got.empty() ? "accepts" : "refuses naming " + got);
    mismatches.push_back(m.str());
  };
  for (const DocumentedRange& r : ranges) {
    if (r.key.find("[]") != std::string::npos) continue;  // an element of a list the defaults leave empty
    if (std::isfinite(r.lo)) {
      expect(r, outside(r.lo, -1, r.integer), false, "just below the lower end");
      if (!kGeometryDecides.count({r.key, End::Lower})) {
        expect(r, r.lo, r.lo_closed, "the lower end");
        if (!kOtherKeysDecide.count({r.key, End::Lower}))
          expect(r, outside(r.lo, +1, r.integer), true, "just above the lower end");
      }
    }
    if (std::isfinite(r.hi)) {
      expect(r, outside(r.hi, +1, r.integer), false, "just above the upper end");
      if (!kGeometryDecides.count({r.key, End::Upper})) {
        expect(r, r.hi, r.hi_closed, "the upper end");
        expect(r, outside(r.hi, -1, r.integer), true, "just below the upper end");
      }
    }
    ++checked;
  }
  std::string all;
  for (const auto& m : mismatches) all += "\n  " + m;
  EXPECT_TRUE(mismatches.empty()) << mismatches.size() << " disagreements:" << all;
  EXPECT_GE(checked, 60);
}

TEST(ConfigRanges, EveryNumberOfTheSchemaStatesItsRange) {
  // A new numeric key must say what it accepts: an interval, "finite", or the rule (with other
  // keys) that model::validate checks (config/range.hpp).
  int numbers = 0;
  for (const KeyInfo& k : config_keys()) {
    if (k.type != "integer" && k.type != "float" && k.type != "array of floats") continue;
    ++numbers;
    EXPECT_FALSE(k.range.empty()) << k.path << " states no range in config/schema.hpp";
  }
  EXPECT_GE(numbers, 80);
}

TEST(ConfigRanges, TheSchemaIntervalsAreTheDocumentedOnes) {
  // Every interval the schema states is the one docs/config.md's Range column gives, ends included
  // (the column may round: 1e5 for 100000).
  std::map<std::string, DocumentedRange> documented;
  for (const DocumentedRange& r : documented_ranges()) documented[r.key] = r;
  // Documented as the interval and a rule with another key ("[0, 1), and archard_K / hardness_Pa
  // < 1e-10 m²/N"): the interval is compared by hand here.
  DocumentedRange archard{"wear.archard_K", false, 0, 1, true, false};
  documented.emplace(archard.key, archard);
  int compared = 0;
  for (const KeyInfo& k : config_keys()) {
    const std::optional<DocumentedRange> schema = parse_range(k.range);
    if (!schema) continue;
    const auto it = documented.find(k.path);
    if (it == documented.end()) {
      ADD_FAILURE() << k.path << ": the schema states " << k.range << ", docs/config.md no plain interval";
      continue;
    }
    const DocumentedRange& d = it->second;
    // The listing prints 10 significant digits (range.hpp describe): equal to 5e-10 relative.
    const auto same = [](double a, double b) { return a == b || std::fabs(a - b) <= 5e-10 * std::fabs(b); };
    EXPECT_PRED2(same, schema->lo, d.lo) << k.path;
    EXPECT_PRED2(same, schema->hi, d.hi) << k.path;
    if (std::isfinite(d.lo)) {
      EXPECT_EQ(schema->lo_closed, d.lo_closed) << k.path << " lower end";
    }
    if (std::isfinite(d.hi)) {
      EXPECT_EQ(schema->hi_closed, d.hi_closed) << k.path << " upper end";
    }
    ++compared;
  }
  EXPECT_GE(compared, 40);
}

} // namespace
} // namespace pw::io
