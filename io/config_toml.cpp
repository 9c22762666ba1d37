// TOML <-> SimulationConfig.
//
// One schema (config::visit_config, src/config/schema.hpp: every key once, with
// its section, name, field reference and doc string), four uses here, run with
//  * Reader    - file -> config (type checks, unknown keys per section),
//  * Writer    - config -> TOML text (to_toml),
//  * Setter    - one "key = value" -> config (apply_override),
//  * KeyLister - the list of keys, their defaults and the allowed keys of each
//                section (unknown-key detection, suggestions, config_keys()).
// Adding a field to model::SimulationConfig means adding one line to the schema (plus
// config/seed.toml and docs/config.md; tests/io/test_config_toml.cpp checks
// both against config_keys()).
#include "io/config_toml.hpp"

#include "core/format.hpp"

#include "config/schema.hpp"
#include "io/io_error.hpp"
#include "model/validate.hpp"

#include "core/error.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <type_traits>
#include <utility>

namespace pw::io {
namespace {

using model::Body;
using model::ModelLevel;
using model::SensorWindow;
using model::SimulationConfig;
using model::ToothModifier;
using config::visit_config;
using config::visit_tooth;

// ---------------------------------------------------------------------------
// Enumerations as strings.

template <class E>
struct EnumNames;
template <>
struct EnumNames<ModelLevel> {
  static constexpr std::array<std::pair<ModelLevel, std::string_view>, 2> values{
      {{ModelLevel::Torsional, "torsional"}, {ModelLevel::LateralTorsional, "lateral_torsional"}}};
};
template <>
struct EnumNames<Body> {
  static constexpr std::array<std::pair<Body, std::string_view>, 3> values{
      {{Body::Sun, model::body_name(Body::Sun)},
       {Body::Planet, model::body_name(Body::Planet)},
       {Body::Ring, model::body_name(Body::Ring)}}};
};

template <>
struct EnumNames<SensorWindow> {
  static constexpr std::array<std::pair<SensorWindow, std::string_view>, 2> values{
      {{SensorWindow::Gaussian, "gaussian"}, {SensorWindow::Hann, "hann"}}};
};

template <>
struct EnumNames<model::HousingPath> {
  static constexpr std::array<std::pair<model::HousingPath, std::string_view>, 3> values{
      {{model::HousingPath::PlanetPass, model::housing_path_name(model::HousingPath::PlanetPass)},
       {model::HousingPath::RingTranslation, model::housing_path_name(model::HousingPath::RingTranslation)},
       {model::HousingPath::RingBody, model::housing_path_name(model::HousingPath::RingBody)}}};
};

template <>
struct EnumNames<model::InputControl> {
  static constexpr std::array<std::pair<model::InputControl, std::string_view>, 4> values{
      {{model::InputControl::Power, "power"},
       {model::InputControl::Torque, "torque"},
       {model::InputControl::Speed, "speed"},
       {model::InputControl::SpeedLoop, "speed_loop"}}};
};

template <>
struct EnumNames<model::LoadControl> {
  static constexpr std::array<std::pair<model::LoadControl, std::string_view>, 3> values{
      {{model::LoadControl::Torque, "torque"},
       {model::LoadControl::Speed, "speed"},
       {model::LoadControl::SpeedLoop, "speed_loop"}}};
};

template <>
struct EnumNames<model::MeshPhase> {
  static constexpr std::array<std::pair<model::MeshPhase, std::string_view>, 2> values{
      {{model::MeshPhase::Rotation, model::mesh_phase_name(model::MeshPhase::Rotation)},
       {model::MeshPhase::NominalTime, model::mesh_phase_name(model::MeshPhase::NominalTime)}}};
};

template <class E>
std::string_view enum_name(E e) {
  for (const auto& [value, name] : EnumNames<E>::values)
    if (value == e) return name;
  return "?";
}

// ---------------------------------------------------------------------------
// Suggestions for misspelt keys and enum values.

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitute});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// The candidate closest to `word`, or "" if none is plausibly a typo of it.
std::string closest(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

std::string join_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

// ---------------------------------------------------------------------------
// Value formatting (TOML text) and type names.

std::string format_double(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::string s = round_trip(v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";  // keep it a TOML float
  return s;
}

template <class T>
std::string format_value(const T& v) {
  using U = std::remove_cv_t<T>;
  if constexpr (std::is_same_v<U, bool>) {
    return v ? "true" : "false";
  } else if constexpr (std::is_same_v<U, int>) {
    return std::to_string(v);
  } else if constexpr (std::is_same_v<U, double>) {
    return format_double(v);
  } else if constexpr (std::is_same_v<U, std::vector<double>>) {
    std::string s = "[";
    for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + format_double(v[i]);
    return s + "]";
  } else {
    static_assert(std::is_enum_v<U>);
    return "\"" + std::string(enum_name(v)) + "\"";
  }
}

template <class T>
std::string_view type_name() {
  using U = std::remove_cv_t<T>;
  if constexpr (std::is_same_v<U, bool>) return "boolean";
  else if constexpr (std::is_same_v<U, int>) return "integer";
  else if constexpr (std::is_same_v<U, double>) return "float";
  else if constexpr (std::is_same_v<U, std::vector<double>>) return "array of floats";
  else return "string";
}

std::string_view node_type_name(const toml::node& n) {
  switch (n.type()) {
  case toml::node_type::table: return "a table";
  case toml::node_type::array: return "an array";
  case toml::node_type::string: return "a string";
  case toml::node_type::integer: return "an integer";
  case toml::node_type::floating_point: return "a float";
  case toml::node_type::boolean: return "a boolean";
  case toml::node_type::date: return "a date";
  case toml::node_type::time: return "a time";
  case toml::node_type::date_time: return "a date-time";
  default: return "nothing";
  }
}

// ---------------------------------------------------------------------------
// Where a value came from, for messages: "file:line:col" or "--set key=value".

struct Origin {
  bool from_file = true;
  std::string label;  ///< file name, or the override text

  std::string at(const toml::node& n) const { return at(n.source()); }
  std::string at(const toml::source_region& r) const {
    if (!from_file) return label;
    const std::string file = r.path ? *r.path : label;
    return detail::concat(file, ":", r.begin.line, ":", r.begin.column);
  }
};

std::string join_key(std::string_view section, std::string_view key) {
  return section.empty() ? std::string(key) : std::string(section) + "." + std::string(key);
}

// ---------------------------------------------------------------------------
// TOML node -> C++ value, with strict types.

template <class T>
T convert(const toml::node& n, const std::string& key, const Origin& origin) {
  using U = std::remove_cv_t<T>;
  auto wrong_type = [&](std::string_view expected) {
    return InputError(key, detail::concat("expected ", expected, ", got ", node_type_name(n), " (", origin.at(n), ")"));
  };
  if constexpr (std::is_same_v<U, bool>) {
    if (const auto* b = n.as_boolean()) return b->get();
    throw wrong_type("a boolean (true or false)");
  } else if constexpr (std::is_same_v<U, int>) {
    const auto* i = n.as_integer();
    if (!i) throw wrong_type("an integer");
    const std::int64_t v = i->get();
    if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
      throw InputError(key, detail::concat("integer ", v, " is out of range (", origin.at(n), ")"));
    return static_cast<int>(v);
  } else if constexpr (std::is_same_v<U, double>) {
    if (const auto* f = n.as_floating_point()) return f->get();
    if (const auto* i = n.as_integer()) return static_cast<double>(i->get());
    throw wrong_type("a float");
  } else if constexpr (std::is_same_v<U, std::vector<double>>) {
    const auto* arr = n.as_array();
    if (!arr) throw wrong_type("an array of floats");
    std::vector<double> out;
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i)
      out.push_back(convert<double>(*arr->get(i), detail::concat(key, "[", i, "]"), origin));
    return out;
  } else {
    static_assert(std::is_enum_v<U>);
    std::vector<std::string> names, quoted;
    for (const auto& [value, name] : EnumNames<U>::values) {
      names.emplace_back(name);
      quoted.push_back("\"" + std::string(name) + "\"");
    }
    const auto* s = n.as_string();
    if (!s) throw wrong_type("a string, one of " + join_list(quoted));
    for (const auto& [value, name] : EnumNames<U>::values)
      if (s->get() == name) return value;
    const std::string guess = closest(s->get(), names);
    throw InputError(key, detail::concat("\"", s->get(), "\" is not one of ", join_list(quoted),
                                         guess.empty() ? "" : "; did you mean \"" + guess + "\"?", " (",
                                         origin.at(n), ")"));
  }
}

constexpr std::string_view kTeethElement = "imperfections.teeth[]";

// ---------------------------------------------------------------------------
// KeyLister: the schema as data.

struct Schema {
  std::vector<KeyInfo> keys;
  /// Allowed keys of every table: "" (root), "stage", "stage.sun", ...,
  /// "imperfections.teeth[]" (one tooth modifier).
  std::map<std::string, std::vector<std::string>, std::less<>> allowed;
  std::set<std::string, std::less<>> sections;      ///< full paths of tables
  std::vector<std::string> all_fields;               ///< full paths of keys
};

class KeyLister {
public:
  explicit KeyLister(Schema& s) : s_(s) {}

  void section(std::string_view path) {
    section_ = std::string(path);
    s_.allowed[section_];
    // Register the section (and its parents) as keys of their parent tables.
    std::string child = section_;
    while (!child.empty() && s_.sections.insert(child).second) {
      const auto dot = child.rfind('.');
      const std::string parent = dot == std::string::npos ? "" : child.substr(0, dot);
      s_.allowed[parent].push_back(child.substr(dot == std::string::npos ? 0 : dot + 1));
      child = parent;
    }
  }

  template <class T>
  void field(std::string_view key, const T& value, std::string_view doc, const config::Range& range = {}) {
    add(key, std::string(type_name<T>()), format_value(value), doc, config::describe(range));
  }

  void angle(std::string_view key_rad, std::string_view key_deg, const double& value_rad, std::string_view doc,
             const config::Range& range = {}) {
    field(key_rad, value_rad, doc, range);
    add(key_deg, "float", format_double(value_rad * 180.0 / std::numbers::pi),
        "alternative to " + std::string(key_rad) + " [deg]; give only one", config::describe(range) + " (in rad)");
  }

  void teeth(std::string_view key, const std::vector<ToothModifier>& /*value*/, std::string_view doc) {
    add(key, "array of tables", "[]", doc, "");
    const std::string outer = section_;
    section_ = std::string(kTeethElement);
    s_.allowed[section_];
    const ToothModifier defaults{};
    visit_tooth(*this, defaults);
    section_ = outer;
  }

private:
  void add(std::string_view key, std::string type, std::string default_value, std::string_view doc,
           std::string range) {
    s_.allowed[section_].emplace_back(key);
    const std::string path = join_key(section_, key);
    s_.all_fields.push_back(path);
    s_.keys.push_back({path, std::move(type), std::move(default_value), std::string(doc), std::move(range)});
  }

  Schema& s_;
  std::string section_;
};

const Schema& schema() {
  static const Schema s = [] {
    Schema out;
    KeyLister lister(out);
    const SimulationConfig defaults{};
    visit_config(lister, defaults);
    return out;
  }();
  return s;
}

/// Throws for the first key of `table` that the schema does not allow there.
/// `schema_section` is the schema path ("imperfections.teeth[]"), `shown` the
/// path as the user wrote it ("imperfections.teeth[2]").
void check_keys(const toml::table& table, std::string_view schema_section, std::string_view shown,
                const Origin& origin) {
  const Schema& s = schema();
  const auto allowed_it = s.allowed.find(schema_section);
  const std::vector<std::string>& allowed = allowed_it->second;
  for (auto&& [k, node] : table) {
    const std::string key(k.str());
    const std::string path = join_key(shown, key);
    const std::string schema_path = join_key(schema_section, key);
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) {
      if (s.sections.count(schema_path) && !node.is_table())
        throw InputError(path, detail::concat("must be a table ([", schema_path, "]), got ", node_type_name(node),
                                              " (", origin.at(node), ")"));
      continue;
    }
    // Unknown: suggest the same key in another section, else the closest key here.
    std::string hint;
    for (const auto& field : s.all_fields) {
      const auto dot = field.rfind('.');
      if (field.compare(dot + 1, std::string::npos, key) == 0 && field.find("[]") == std::string::npos) {
        hint = "; did you mean '" + field + "'?";
        break;
      }
    }
    if (hint.empty()) {
      const std::string guess = closest(key, allowed);
      hint = guess.empty() ? "; valid keys here: " + join_list(allowed)
                           : "; did you mean '" + join_key(shown, guess) + "'?";
    }
    const bool is_section = node.is_table();
    throw InputError(path, detail::concat("unknown ", is_section ? "section [" + path + "]" : "key '" + path + "'",
                                          " (", origin.at(k.source()), ")", hint));
  }
}

// ---------------------------------------------------------------------------
// Reader: TOML table -> config.

std::vector<ToothModifier> read_teeth(const toml::node& n, const std::string& key, const Origin& origin);

class Reader {
public:
  Reader(const toml::table& root, Origin origin) : root_(&root), origin_(std::move(origin)) {}

  /// Reads one table directly (a tooth modifier), shown as `shown`.
  Reader(const toml::table& table, std::string shown, Origin origin)
      : root_(nullptr), table_(&table), shown_(std::move(shown)), origin_(std::move(origin)) {}

  void section(std::string_view path) {
    shown_ = std::string(path);
    table_ = root_;
    std::string_view rest = path;
    while (table_ && !rest.empty()) {
      const auto dot = rest.find('.');
      const toml::node* child = table_->get(rest.substr(0, dot));
      table_ = child ? child->as_table() : nullptr;
      rest = dot == std::string_view::npos ? std::string_view{} : rest.substr(dot + 1);
    }
    if (table_) check_keys(*table_, path, path, origin_);
  }

  template <class T>
  void field(std::string_view key, T& value, std::string_view /*doc*/, const config::Range& = {}) {
    if (!table_) return;
    if (const toml::node* n = table_->get(key)) value = convert<T>(*n, join_key(shown_, key), origin_);
  }

  void angle(std::string_view key_rad, std::string_view key_deg, double& value_rad, std::string_view /*doc*/, const config::Range& = {}) {
    if (!table_) return;
    const toml::node* rad = table_->get(key_rad);
    const toml::node* deg = table_->get(key_deg);
    if (rad && deg)
      throw InputError(join_key(shown_, key_deg),
                       detail::concat("give either ", key_rad, " or ", key_deg, ", not both (", origin_.at(*rad),
                                      " and ", origin_.at(*deg), ")"));
    if (rad) value_rad = convert<double>(*rad, join_key(shown_, key_rad), origin_);
    if (deg) value_rad = convert<double>(*deg, join_key(shown_, key_deg), origin_) * (std::numbers::pi / 180.0);
  }

  void teeth(std::string_view key, std::vector<ToothModifier>& value, std::string_view /*doc*/) {
    if (!table_) return;
    if (const toml::node* n = table_->get(key)) value = read_teeth(*n, join_key(shown_, key), origin_);
  }

private:
  const toml::table* root_;
  const toml::table* table_ = nullptr;
  std::string shown_;
  Origin origin_;
};

std::vector<ToothModifier> read_teeth(const toml::node& n, const std::string& key, const Origin& origin) {
  const auto* arr = n.as_array();
  if (!arr)
    throw InputError(key, detail::concat("expected an array of tables ([[", key, "]]), got ", node_type_name(n), " (",
                                         origin.at(n), ")"));
  std::vector<ToothModifier> teeth;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node& element = *arr->get(i);
    const std::string shown = detail::concat(key, "[", i, "]");
    const auto* table = element.as_table();
    if (!table)
      throw InputError(shown, detail::concat("expected a table (body, planet, tooth, ...), got ",
                                             node_type_name(element), " (", origin.at(element), ")"));
    check_keys(*table, kTeethElement, shown, origin);
    ToothModifier t{};
    Reader reader(*table, shown, origin);
    visit_tooth(reader, t);
    teeth.push_back(t);
  }
  return teeth;
}

// ---------------------------------------------------------------------------
// Writer: config -> TOML text.

class Writer {
public:
  std::string text;

  void section(std::string_view path) {
    section_ = std::string(path);
    text += "\n[" + section_ + "]\n";
  }

  template <class T>
  void field(std::string_view key, const T& value, std::string_view /*doc*/, const config::Range& = {}) {
    text += std::string(key) + " = " + format_value(value) + "\n";
  }

  void angle(std::string_view key_rad, std::string_view /*key_deg*/, const double& value_rad, std::string_view doc, const config::Range& = {}) {
    field(key_rad, value_rad, doc);
  }

  void teeth(std::string_view key, const std::vector<ToothModifier>& value, std::string_view /*doc*/) {
    if (value.empty()) {
      text += std::string(key) + " = []\n";
      return;
    }
    for (const auto& t : value) {
      text += "\n[[" + join_key(section_, key) + "]]\n";
      visit_tooth(*this, t);
    }
  }

private:
  std::string section_;
};

// ---------------------------------------------------------------------------
// Setter: one key path = one TOML value.

class Setter {
public:
  Setter(std::string target, const toml::node& value, Origin origin)
      : target_(std::move(target)), value_(value), origin_(std::move(origin)) {}

  bool found() const { return found_; }

  void section(std::string_view path) { section_ = std::string(path); }

  template <class T>
  void field(std::string_view key, T& value, std::string_view /*doc*/, const config::Range& = {}) {
    if (join_key(section_, key) != target_) return;
    value = convert<T>(value_, target_, origin_);
    found_ = true;
  }

  void angle(std::string_view key_rad, std::string_view key_deg, double& value_rad, std::string_view doc, const config::Range& = {}) {
    field(key_rad, value_rad, doc);
    if (join_key(section_, key_deg) == target_) {
      value_rad = convert<double>(value_, target_, origin_) * (std::numbers::pi / 180.0);
      found_ = true;
    }
  }

  void teeth(std::string_view key, std::vector<ToothModifier>& value, std::string_view /*doc*/) {
    const std::string whole = join_key(section_, key);
    if (target_ == whole) {
      value = read_teeth(value_, whole, origin_);
      found_ = true;
      return;
    }
    // "imperfections.teeth[<i>].<field>"
    if (target_.rfind(whole + "[", 0) != 0) return;
    const std::size_t open = whole.size() + 1;
    const std::size_t close = target_.find("].", open);
    std::size_t index = 0;
    const char* first = target_.data() + open;
    const char* last = target_.data() + (close == std::string::npos ? open : close);
    const auto parsed = std::from_chars(first, last, index);
    if (close == std::string::npos || close == open || parsed.ptr != last || parsed.ec != std::errc{})
      throw InputError(target_, detail::concat("expected ", whole, "[<index>].<key> with a 0-based index"));
    if (index > value.size())
      throw InputError(target_, detail::concat("index ", index, " is beyond the ", value.size(),
                                               " tooth modifiers; use index ", value.size(), " to add one"));
    if (index == value.size()) value.emplace_back();
    Setter element(target_, value_, origin_);
    element.section(target_.substr(0, close + 1));
    visit_tooth(element, value[index]);
    if (!element.found()) {
      const std::string field = target_.substr(close + 2);
      const std::string guess = closest(field, schema().allowed.find(kTeethElement)->second);
      throw InputError(target_, detail::concat("unknown key '", field, "' of a tooth modifier",
                                               guess.empty() ? "" : "; did you mean '" + guess + "'?"));
    }
    found_ = true;
  }

private:
  std::string target_;
  const toml::node& value_;
  Origin origin_;
  std::string section_;
  bool found_ = false;
};

/// Message of an InputError without its "parameter: " prefix.
std::string bare_message(const InputError& e) {
  const std::string what = e.what();
  const std::string prefix = e.parameter() + ": ";
  if (!e.parameter().empty() && what.rfind(prefix, 0) == 0) return what.substr(prefix.size());
  return what;
}

/// The `_deg` spelling of an angle key `..._rad`, or "" for any other key.
std::string degree_alias(const std::string& key) {
  constexpr std::string_view rad = "_rad";
  if (key.size() <= rad.size() || key.compare(key.size() - rad.size(), rad.size(), rad) != 0) return {};
  return key.substr(0, key.size() - rad.size()) + "_deg";
}

/// A range error of an angle the user gave in degrees, named by the key they wrote: the range
/// is checked (and stated) in radians, so the message says how the two relate.
InputError in_degrees(const InputError& e, const std::string& deg_key, const std::string& where) {
  return InputError(deg_key, bare_message(e) + " (" + e.parameter() + " = " + deg_key + " x pi/180; " + where + ")");
}

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

} // namespace

// ---------------------------------------------------------------------------

model::SimulationConfig parse_config(std::string_view toml_text, std::string_view source_name) {
  const Origin origin{true, std::string(source_name)};
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    throw InputError("", detail::concat(origin.at(e.source()), ": TOML syntax error: ", e.description()));
  }

  model::SimulationConfig config{};
  check_keys(root, "", "", origin);
  Reader reader(root, origin);
  visit_config(reader, config);

  try {
    model::validate(config);
  } catch (const InputError& e) {
    // Point at the offending line if the key is in the file.
    const toml::table& croot = root;
    if (const auto at = toml::at_path(croot, e.parameter()))
      throw InputError(e.parameter(), bare_message(e) + " (" + origin.at(*at.node()) + ")");
    const std::string deg = degree_alias(e.parameter());
    if (const auto at = deg.empty() ? toml::node_view<const toml::node>{} : toml::at_path(croot, deg))
      throw in_degrees(e, deg, origin.at(*at.node()));
    throw InputError(e.parameter(), bare_message(e) + " (in " + origin.label + ")");
  }
  return config;
}

model::SimulationConfig read_config(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(detail::concat("cannot open configuration file '", path.string(), "': ", std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw IoError(detail::concat("cannot read configuration file '", path.string(), "'"));
  return parse_config(text.str(), path.string());
}

std::string to_toml(const model::SimulationConfig& config) {
  Writer writer;
  writer.text = "# planetwear configuration, fully resolved (every key; SI units; see docs/config.md).\n";
  visit_config(writer, config);
  return writer.text;
}

void apply_override(model::SimulationConfig& config, std::string_view key_path, std::string_view value) {
  const std::string key(trim(key_path));
  const std::string text(trim(value));
  const Origin origin{false, "--set " + key + "=" + text};

  // The value as TOML; a bare word (no quotes) is taken as a string so that
  // --set solver.level=lateral_torsional works without shell quoting.
  toml::table holder;
  try {
    const std::string doc = "value = " + text;
    holder = toml::parse(std::string_view(doc), std::string_view("--set"));
  } catch (const toml::parse_error&) {
    const bool bare_word = !text.empty() && text.find_first_of("\"'\\\n[]{}=#") == std::string::npos;
    if (!bare_word)
      throw InputError(key, detail::concat("'", text, "' is not a TOML value (", origin.label, ")"));
    const std::string doc = "value = \"" + text + "\"";
    holder = toml::parse(std::string_view(doc), std::string_view("--set"));
  }

  model::SimulationConfig updated = config;  // strong guarantee
  Setter setter(key, *holder.get("value"), origin);
  visit_config(setter, updated);
  if (!setter.found()) {
    const Schema& s = schema();
    std::string guess = closest(key, s.all_fields);
    if (guess.empty()) {
      const std::string last = key.substr(key.rfind('.') == std::string::npos ? 0 : key.rfind('.') + 1);
      for (const auto& field : s.all_fields)
        if (field.size() > last.size() && field.compare(field.size() - last.size(), last.size(), last) == 0 &&
            field[field.size() - last.size() - 1] == '.')
          guess = field;
    }
    throw InputError(key, detail::concat("unknown key (", origin.label, ")",
                                         guess.empty() ? "; docs/config.md lists the keys"
                                                       : "; did you mean '" + guess + "'?"));
  }
  config = std::move(updated);
}

void apply_overrides(model::SimulationConfig& config, const std::vector<std::string>& assignments) {
  model::SimulationConfig updated = config;
  for (const auto& assignment : assignments) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos)
      throw InputError("", detail::concat("override '", assignment, "' must have the form key=value"));
    apply_override(updated, std::string_view(assignment).substr(0, eq), std::string_view(assignment).substr(eq + 1));
  }
  try {
    model::validate(updated);
  } catch (const InputError& e) {
    const std::string deg = degree_alias(e.parameter());
    const bool given_in_degrees =
        !deg.empty() && std::any_of(assignments.begin(), assignments.end(), [&](const std::string& a) {
          return trim(std::string_view(a).substr(0, a.find('='))) == deg;
        });
    if (given_in_degrees) throw in_degrees(e, deg, "after the command-line overrides");
    throw InputError(e.parameter(), bare_message(e) + " (after the command-line overrides)");
  }
  config = std::move(updated);
}

std::vector<KeyInfo> config_keys() { return schema().keys; }

} // namespace pw::io
