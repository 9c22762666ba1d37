#include "campaign.hpp"

#include "core/error.hpp"
#include "core/format.hpp"
#include "geometry/mesh.hpp"
#include "io/config_toml.hpp"
#include "io/io_error.hpp"
#include "model/validate.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <tuple>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

namespace pw::sweep {
namespace {

std::string read_file(const std::filesystem::path& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::IoError(detail::concat("cannot open ", what, " '", path.string(), "': ", std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw io::IoError(detail::concat("cannot read ", what, " '", path.string(), "'"));
  return text.str();
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

/// "; did you mean 'x'?" for the closest candidate within a few edits.
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::max<std::size_t>(3, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best.empty() ? std::string() : "; did you mean '" + best + "'?";
}

/// Reads one campaign TOML document, with positions in messages.
class Reader {
public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  std::string at(const toml::node& n) const {
    const auto& s = n.source();
    return detail::concat(" (", source_, ":", s.begin.line, ":", s.begin.column, ")");
  }

  /// Every key of `table` is one of `allowed`.
  void check_keys(const toml::table& table, const std::string& section, const std::vector<std::string>& allowed,
                  const std::string& context = {}) const {
    for (const auto& [key, node] : table) {
      const std::string k(key.str());
      if (std::find(allowed.begin(), allowed.end(), k) != allowed.end()) continue;
      const std::string path = section.empty() ? k : section + "." + k;
      throw InputError(path, detail::concat("unknown key", context, at(node), suggestion(k, allowed),
                                            allowed.empty() ? "" : " Allowed: " + join(allowed)));
    }
  }

  const toml::table* table(const toml::table& parent, const std::string& key, const std::string& path) const {
    const toml::node* n = parent.get(key);
    if (!n) return nullptr;
    if (!n->is_table()) throw InputError(path, "must be a table" + at(*n));
    return n->as_table();
  }

  std::optional<std::string> string(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_string()) throw InputError(path, detail::concat("must be a string", at(*n)));
    return n->as_string()->get();
  }

  std::optional<double> number(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    return number(*n, path);
  }

  double number(const toml::node& n, const std::string& path) const {
    if (n.is_integer()) return static_cast<double>(n.as_integer()->get());
    if (n.is_floating_point()) return n.as_floating_point()->get();
    throw InputError(path, detail::concat("must be a number", at(n)));
  }

  std::optional<long long> integer(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_integer()) throw InputError(path, detail::concat("must be an integer", at(*n)));
    return static_cast<long long>(n->as_integer()->get());
  }

  static std::string join(const std::vector<std::string>& items) {
    std::string s;
    for (const auto& i : items) s += (s.empty() ? "" : ", ") + i;
    return s + ".";
  }

private:
  std::string source_;
};

/// [base.set] as "key=value" assignments: nested tables (dotted keys) are
/// flattened, values printed as TOML (floats keep a '.' or exponent so that
/// the type checks of the configuration see a float).
void flatten_set(const toml::table& t, const std::string& prefix, std::vector<std::string>& out) {
  for (const auto& [key, node] : t) {
    const std::string path = prefix.empty() ? std::string(key.str()) : prefix + "." + std::string(key.str());
    if (node.is_table()) {
      flatten_set(*node.as_table(), path, out);
      continue;
    }
    std::ostringstream value;
    if (node.is_floating_point()) {
      const double v = node.as_floating_point()->get();
      std::array<char, 64> buf{};
      std::string s(buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr);
      if (std::isfinite(v) && s.find_first_of(".e") == std::string::npos) s += ".0";
      if (std::isnan(v)) s = "nan";
      if (std::isinf(v)) s = v > 0 ? "inf" : "-inf";
      value << s;
    } else {
      node.visit([&](const auto& v) { value << v; });
    }
    out.push_back(path + "=" + value.str());
  }
}

const io::KeyInfo* find_key(std::string_view key_path, const std::vector<io::KeyInfo>& keys) {
  // "imperfections.teeth[3].tooth" -> "imperfections.teeth[].tooth"
  std::string normalized;
  for (std::size_t k = 0; k < key_path.size(); ++k) {
    normalized += key_path[k];
    if (key_path[k] == '[') {
      while (k + 1 < key_path.size() && key_path[k + 1] != ']') ++k;
    }
  }
  for (const auto& info : keys)
    if (info.path == normalized) return &info;
  return nullptr;
}

std::string normalize_unit(std::string_view unit) {
  std::string out;
  bool space = false;
  for (const char c : unit) {
    if (c == ' ' || c == '\t') {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += c;
  }
  if (out == "1") out = "-";
  return out;
}

std::string format_value(double v, bool integer) {
  if (integer) return std::to_string(static_cast<long long>(v));
  return round_trip(v);
}

/// [design] correlation = [[1, 0.5], [0.5, 1]]: a square array of numbers (checked in make_design).
SquareMatrix read_correlation(const Reader& r, const toml::node& n) {
  const std::string p = "design.correlation";
  const toml::array* rows = n.as_array();
  require(rows && !rows->empty(), p, "must be a square array of arrays of numbers, one row per factor",
          r.at(n));
  SquareMatrix c;
  c.size = static_cast<int>(rows->size());
  for (std::size_t i = 0; i < rows->size(); ++i) {
    const toml::array* row = (*rows)[i].as_array();
    require(row && row->size() == rows->size(), p, "row ", i, " must be an array of ", rows->size(),
            " numbers (the matrix is square)", r.at((*rows)[i]));
    for (const toml::node& v : *row) c.values.push_back(r.number(v, p));
  }
  return c;
}

Factor read_factor(const Reader& r, const toml::table& t, std::size_t i, const std::vector<io::KeyInfo>& keys) {
  const std::string p = "factors[" + std::to_string(i) + "]";
  r.check_keys(t, p, {"key", "unit", "min", "max", "levels", "points", "scale", "distribution", "mean", "std_dev", "mode"});
  Factor f;
  const auto key = r.string(t, "key", p + ".key");
  require(key.has_value() && !key->empty(), p + ".key", "missing: the configuration key to vary, e.g. key = "
                                                        "\"operating.input_speed_rpm\" (planetwear keys lists them)");
  f.key = *key;
  const io::KeyInfo* info = find_key(f.key, keys);
  if (!info) {
    std::vector<std::string> paths;
    for (const auto& k : keys) paths.push_back(k.path);
    throw InputError(p + ".key", detail::concat("unknown configuration key '", f.key, "'", r.at(*t.get("key")),
                                                suggestion(f.key, paths), " (planetwear keys lists them)"));
  }
  require(info->type == "float" || info->type == "integer", p + ".key", "'", f.key, "' is a key of type ", info->type,
          "; factors must be numeric (integer or float keys)", r.at(*t.get("key")));
  f.integer = info->type == "integer";

  const auto unit = r.string(t, "unit", p + ".unit");
  const std::string documented = documented_unit(f.key);
  require(unit.has_value() && !normalize_unit(*unit).empty(), p + ".unit", "missing: the unit of ", f.key,
          documented.empty() ? std::string() : " (documented: \"" + documented + "\")");
  f.unit = *unit;
  if (!documented.empty())
    require(normalize_unit(f.unit) == normalize_unit(documented), p + ".unit", "\"", f.unit, "\" does not match the unit of ",
            f.key, ", which is \"", documented, "\"", r.at(*t.get("unit")));

  f.min = r.number(t, "min", p + ".min");
  f.max = r.number(t, "max", p + ".max");
  if (const toml::node* n = t.get("levels")) {
    if (!n->is_array()) throw InputError(p + ".levels", "must be an array of numbers" + r.at(*n));
    const toml::array& a = *n->as_array();
    require(!a.empty(), p + ".levels", "is empty", r.at(*n));
    for (std::size_t k = 0; k < a.size(); ++k) f.levels.push_back(r.number(a[k], p + ".levels"));
  }
  if (const auto points = r.integer(t, "points", p + ".points")) {
    require(*points >= 2 && *points <= 1'000'000, p + ".points", "must be in [2, 1000000], got ", *points);
    f.points = static_cast<int>(*points);
  }
  if (const auto scale = r.string(t, "scale", p + ".scale")) {
    if (*scale == "linear") f.scale = Scale::Linear;
    else if (*scale == "log") f.scale = Scale::Log;
    else throw InputError(p + ".scale", detail::concat("must be \"linear\" or \"log\", got \"", *scale, "\"",
                                                       r.at(*t.get("scale"))));
  }
  if (const auto dist = r.string(t, "distribution", p + ".distribution")) {
    if (*dist == "uniform") f.distribution.kind = DistributionKind::Uniform;
    else if (*dist == "normal") f.distribution.kind = DistributionKind::Normal;
    else if (*dist == "lognormal") f.distribution.kind = DistributionKind::LogNormal;
    else if (*dist == "triangular") f.distribution.kind = DistributionKind::Triangular;
    else throw InputError(p + ".distribution", detail::concat("must be \"uniform\", \"normal\", \"lognormal\" or "
                                                              "\"triangular\", got \"", *dist, "\"",
                                                              r.at(*t.get("distribution"))));
  }
  // Each distribution's parameters, and only those (a stray one is a mistake worth naming).
  const DistributionKind kind = f.distribution.kind;
  const bool moments = kind == DistributionKind::Normal || kind == DistributionKind::LogNormal;
  const std::string named = " (distribution = \"" + std::string(to_string(kind)) + "\")";
  for (const char* name : {"mean", "std_dev"}) {
    const auto v = r.number(t, name, p + "." + name);
    require(moments || !v, p + "." + name, name, " is a parameter of normal and lognormal factors, not of this one",
            named);
    require(!moments || v, p + "." + name, "missing: a ", to_string(kind), " factor needs mean and std_dev, in ",
            f.unit.empty() ? std::string("its unit") : f.unit);
    if (v) (std::string(name) == "mean" ? f.distribution.mean : f.distribution.std_dev) = *v;
  }
  const auto mode = r.number(t, "mode", p + ".mode");
  require(kind == DistributionKind::Triangular || !mode, p + ".mode",
          "mode is a parameter of triangular factors, not of this one", named);
  require(kind != DistributionKind::Triangular || mode, p + ".mode", "missing: a triangular factor needs min, mode and max");
  if (mode) f.distribution.mode = *mode;
  return f;
}

} // namespace

std::uint64_t fnv1a64(std::string_view data, std::uint64_t hash) {
  for (const char c : data) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

std::string hex64(std::uint64_t value) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string s(16, '0');
  for (int k = 15; k >= 0; --k, value >>= 4) s[static_cast<std::size_t>(k)] = digits[value & 0xf];
  return s;
}

std::string_view to_string(DesignType type) {
  switch (type) {
  case DesignType::FullFactorial: return "full_factorial";
  case DesignType::List: return "list";
  case DesignType::LatinHypercube: return "latin_hypercube";
  case DesignType::Saltelli: return "saltelli";
  }
  return "?";
}

std::vector<std::string> rank_correlation_report(const Campaign& c) {
  const int d = static_cast<int>(c.factors.size());
  if (c.design.type != DesignType::LatinHypercube || d < 2 || c.cases.size() < 2) return {};
  const SquareMatrix achieved = achieved_rank_correlation(c.cases, d);
  auto target = [&](int i, int j) { return c.design.correlation.size == d ? c.design.correlation(i, j) : 0.0; };
  std::vector<std::string> lines;
  lines.push_back(detail::concat("rank correlations of the ", c.cases.size(), " cases (Spearman; target in brackets",
                                 c.design.correlation.size == d ? ", imposed by Iman-Conover" : ", none imposed",
                                 "):"));
  double worst = 0;
  int wi = 0, wj = 1;
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j) {
      const double dev = std::fabs(achieved(i, j) - target(i, j));
      if (dev > worst) std::tie(worst, wi, wj) = std::make_tuple(dev, i, j);
      char buf[64];
      std::snprintf(buf, sizeof buf, "%+.3f [%+.3f]", achieved(i, j), target(i, j));
      if (d <= 8) lines.push_back("  " + c.factors[i].key + " ~ " + c.factors[j].key + ": " + buf);
    }
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", worst);
  lines.push_back(detail::concat("  largest deviation from the target: ", buf, " (", c.factors[wi].key, " ~ ",
                                 c.factors[wj].key, ")"));
  return lines;
}

std::string_view to_string(Scale scale) { return scale == Scale::Log ? "log" : "linear"; }

std::string documented_unit(std::string_view key_path) {
  static const std::vector<io::KeyInfo> keys = io::config_keys();
  const io::KeyInfo* info = find_key(key_path, keys);
  if (!info) return {};
  const auto open = info->doc.find('[');
  const auto close = open == std::string::npos ? std::string::npos : info->doc.find(']', open);
  if (close == std::string::npos) return {};
  return info->doc.substr(open + 1, close - open - 1);
}

Campaign parse_campaign(std::string_view text, const std::filesystem::path& base_dir, std::string_view source_name) {
  const Reader r{std::string(source_name)};
  toml::table root;
  try {
    root = toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& s = e.source();
    throw InputError("", detail::concat(source_name, ":", s.begin.line, ":", s.begin.column,
                                        ": TOML syntax error: ", e.description()));
  }
  r.check_keys(root, "", {"campaign", "base", "factors", "design", "output"}, " in the campaign file");

  Campaign c;
  c.text = std::string(text);
  if (const toml::table* t = r.table(root, "campaign", "campaign")) {
    r.check_keys(*t, "campaign", {"name", "description"});
    c.name = r.string(*t, "name", "campaign.name").value_or("");
    c.description = r.string(*t, "description", "campaign.description").value_or("");
  }

  // Base case: a config file (optional) plus overrides.
  if (const toml::table* t = r.table(root, "base", "base")) {
    r.check_keys(*t, "base", {"config", "set"});
    if (const auto config = r.string(*t, "config", "base.config")) {
      require(!config->empty(), "base.config", "is empty; leave it out for the built-in defaults");
      c.base_config_file = std::filesystem::path(*config).is_absolute() ? std::filesystem::path(*config)
                                                                         : base_dir / *config;
      c.base_config_text = read_file(c.base_config_file, "base configuration");
      c.base = io::parse_config(c.base_config_text, c.base_config_file.string());
    }
    if (const toml::table* set = r.table(*t, "set", "base.set")) flatten_set(*set, "", c.base_set);
  }
  try {
    for (const auto& a : c.base_set) {
      const auto eq = a.find('=');
      io::apply_override(c.base, std::string_view(a).substr(0, eq), std::string_view(a).substr(eq + 1));
    }
    model::validate(c.base);
  } catch (const InputError& e) {
    throw InputError("base.set", detail::concat(e.what(), " (the campaign's base case: [base] config + [base.set])"));
  }

  // Factors.
  const std::vector<io::KeyInfo> keys = io::config_keys();
  if (const toml::node* n = root.get("factors")) {
    if (!n->is_array_of_tables()) throw InputError("factors", "must be an array of tables, [[factors]]" + r.at(*n));
    const toml::array& a = *n->as_array();
    for (std::size_t i = 0; i < a.size(); ++i) {
      c.factors.push_back(read_factor(r, *a[i].as_table(), i, keys));
      for (std::size_t k = 0; k < i; ++k)
        require(c.factors[k].key != c.factors[i].key, "factors[" + std::to_string(i) + "].key", "'",
                c.factors[i].key, "' is already factors[", k, "]");
    }
  }
  require(!c.factors.empty(), "factors", "a campaign needs at least one [[factors]] table (key, unit, bounds or levels)");

  // Design.
  const toml::table* d = r.table(root, "design", "design");
  require(d != nullptr, "design", "missing: add a [design] table with type = \"full_factorial\", \"list\", "
                                  "\"latin_hypercube\" or \"saltelli\"");
  const auto type = r.string(*d, "type", "design.type");
  require(type.has_value(), "design.type", "missing: \"full_factorial\", \"list\", \"latin_hypercube\" or \"saltelli\"");
  if (*type == "full_factorial") {
    c.design.type = DesignType::FullFactorial;
    r.check_keys(*d, "design", {"type", "points"}, " for full_factorial designs");
    if (const auto points = r.integer(*d, "points", "design.points")) {
      require(*points >= 2 && *points <= 1'000'000, "design.points", "must be in [2, 1000000], got ", *points);
      c.design.points = static_cast<int>(*points);
    }
  } else if (*type == "list") {
    c.design.type = DesignType::List;
    r.check_keys(*d, "design", {"type", "file"}, " for list designs");
    const auto file = r.string(*d, "file", "design.file");
    require(file.has_value() && !file->empty(), "design.file", "missing: the CSV file of cases (header = factor keys)");
    c.list_file = std::filesystem::path(*file).is_absolute() ? std::filesystem::path(*file) : base_dir / *file;
    c.design.list_text = read_file(c.list_file, "case list");
    c.design.list_name = c.list_file.string();
  } else if (*type == "latin_hypercube") {
    c.design.type = DesignType::LatinHypercube;
    r.check_keys(*d, "design", {"type", "samples", "seed", "correlation"}, " for latin_hypercube designs");
    const auto samples = r.integer(*d, "samples", "design.samples");
    require(samples.has_value(), "design.samples", "missing: the number of cases");
    c.design.samples = *samples;
    if (const toml::node* n = d->get("correlation")) c.design.correlation = read_correlation(r, *n);
  } else if (*type == "saltelli") {
    c.design.type = DesignType::Saltelli;
    r.check_keys(*d, "design", {"type", "base_samples", "seed"}, " for saltelli designs");
    const auto n = r.integer(*d, "base_samples", "design.base_samples");
    require(n.has_value(), "design.base_samples", "missing: N, giving N (factors + 2) cases");
    c.design.base_samples = *n;
  } else {
    throw InputError("design.type", detail::concat("\"", *type, "\" is not a design type: \"full_factorial\", \"list\", "
                                                   "\"latin_hypercube\" or \"saltelli\"", r.at(*d->get("type"))));
  }
  if (const auto seed = r.integer(*d, "seed", "design.seed")) {
    require(*seed >= 0, "design.seed", "must be >= 0, got ", *seed);
    c.design.seed = static_cast<std::uint64_t>(*seed);
  }

  if (const toml::table* t = r.table(root, "output", "output")) {
    r.check_keys(*t, "output", {"time_history_decimation", "spectrum_max_frequency_Hz"});
    if (const auto f = r.number(*t, "spectrum_max_frequency_Hz", "output.spectrum_max_frequency_Hz")) {
      require(std::isfinite(*f) && *f >= 0, "output.spectrum_max_frequency_Hz", "must be >= 0 (0 = every bin), got ",
              *f);
      c.output.spectrum_max_frequency_Hz = *f;
    }
    if (const auto k = r.integer(*t, "time_history_decimation", "output.time_history_decimation")) {
      require(*k >= 0 && *k <= 1'000'000, "output.time_history_decimation", "must be in [0, 1000000] (0 = none), got ",
              *k);
      c.output.time_history_decimation = static_cast<int>(*k);
    }
  }

  c.cases = make_design(c.factors, c.design);

  std::uint64_t h = fnv1a64("planetwear campaign\n");
  h = fnv1a64(c.text, h);
  h = fnv1a64(std::string_view("\0base\0", 6), h);
  h = fnv1a64(c.base_config_text, h);
  h = fnv1a64(std::string_view("\0list\0", 6), h);
  c.input_hash = fnv1a64(c.design.list_text, h);
  std::uint64_t dh = fnv1a64(io::to_toml(c.base));
  for (std::size_t i = 0; i < c.cases.size(); ++i) {
    for (const auto& a : case_assignments(c, i)) dh = fnv1a64(a + "\n", dh);
    dh = fnv1a64(c.cases[i].role + "|" + std::to_string(c.cases[i].row) + "\n", dh);
  }
  dh = fnv1a64(std::to_string(c.output.time_history_decimation) + "|", dh);
  c.design_hash = fnv1a64(format_value(c.output.spectrum_max_frequency_Hz, false), dh);
  return c;
}

Campaign read_campaign(const std::filesystem::path& file) {
  const std::string text = read_file(file, "campaign file");
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  Campaign c = parse_campaign(text, dir, file.string());
  c.file = file;
  return c;
}

std::vector<std::string> case_assignments(const Campaign& c, std::size_t index) {
  const DesignPoint& p = c.cases.at(index);
  std::vector<std::string> out;
  for (std::size_t k = 0; k < c.factors.size(); ++k)
    out.push_back(c.factors[k].key + "=" + format_value(p.values[k], c.factors[k].integer));
  return out;
}

model::SimulationConfig case_config(const Campaign& c, std::size_t index) {
  model::SimulationConfig config = c.base;
  for (const auto& a : case_assignments(c, index)) {
    const auto eq = a.find('=');
    io::apply_override(config, std::string_view(a).substr(0, eq), std::string_view(a).substr(eq + 1));
  }
  model::validate(config);
  return config;
}

std::string describe_case(const Campaign& c, std::size_t index) {
  const DesignPoint& p = c.cases.at(index);
  std::string s;
  for (std::size_t k = 0; k < c.factors.size(); ++k)
    s += (k ? ", " : "") + c.factors[k].key + " = " + format_value(p.values[k], c.factors[k].integer) + " " +
         c.factors[k].unit;
  return s;
}

void validate_cases(const Campaign& c) {
  for (std::size_t i = 0; i < c.cases.size(); ++i) {
    try {
      // Ranges (model::validate) and the stage's geometry and assembly.
      (void)geometry::make_stage_geometry(case_config(c, i).stage);
    } catch (const InputError& e) {
      throw InputError(detail::concat("case ", i, " (", describe_case(c, i), ")"), e.what());
    }
  }
}

} // namespace pw::sweep
