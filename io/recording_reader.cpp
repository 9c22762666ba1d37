// Recording reader: JSON sidecar, CSV (streaming, one pass) and HDF5, unit
// conversion to SI, and the checks of docs/recordings.md.
#include "io/recording_reader.hpp"

#include "io/csv_fields.hpp"

#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"
#include "diagnose/order_analysis.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "config/schema.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <numbers>
#include <set>
#include <sstream>

namespace pw::io {
namespace {

using diagnose::Quantity;
using json = nlohmann::ordered_json;

constexpr double kStandardGravity = 9.80665;  ///< m/s^2 per g (CGPM 1901)
/// Mean encoder speed within this fraction of the nominal speed.
constexpr double kSpeedTolerance = 0.2;
/// No accelerometer on a gearbox reads 10^4 g RMS: a unit mistake.
constexpr double kMaxAccelerationRms = 1e5;
/// Lines before the header and first data row (DAQ preambles).
constexpr std::size_t kMaxPreambleLines = 1000;

constexpr std::array kAllQuantities{Quantity::SunSpeed,
                                    Quantity::CarrierSpeed,
                                    Quantity::MeshAccelerationSunPlanet,
                                    Quantity::MeshAccelerationPlanetRing,
                                    Quantity::HousingAcceleration,
                                    Quantity::Tacho};

// ---------------------------------------------------------------------------
// Units.

struct UnitEntry {
  std::string_view name;  ///< lower case, no spaces
  double factor;          ///< to SI
};

constexpr double kRpm = 2 * kPi / 60;
constexpr std::array kSpeedUnits{UnitEntry{"rad/s", 1.0},     UnitEntry{"rad/sec", 1.0},  UnitEntry{"rpm", kRpm},
                                 UnitEntry{"1/min", kRpm},    UnitEntry{"min^-1", kRpm},  UnitEntry{"min-1", kRpm},
                                 UnitEntry{"r/min", kRpm},    UnitEntry{"rev/min", kRpm}, UnitEntry{"u/min", kRpm},
                                 UnitEntry{"hz", 2 * kPi},    UnitEntry{"rev/s", 2 * kPi}, UnitEntry{"rps", 2 * kPi},
                                 UnitEntry{"deg/s", kPi / 180}, UnitEntry{"°/s", kPi / 180}};
constexpr std::array kAccelerationUnits{
    UnitEntry{"m/s^2", 1.0},     UnitEntry{"m/s²", 1.0},     UnitEntry{"m/s2", 1.0},      UnitEntry{"ms^-2", 1.0},
    UnitEntry{"m*s^-2", 1.0},    UnitEntry{"m.s^-2", 1.0},   UnitEntry{"mm/s^2", 1e-3},   UnitEntry{"mm/s²", 1e-3},
    UnitEntry{"mm/s2", 1e-3},    UnitEntry{"g", kStandardGravity}, UnitEntry{"gn", kStandardGravity},
    UnitEntry{"g0", kStandardGravity}};
constexpr std::array kTachoUnits{UnitEntry{"1", 1.0},  UnitEntry{"-", 1.0},      UnitEntry{"v", 1.0},
                                 UnitEntry{"mv", 1e-3}, UnitEntry{"counts", 1.0}, UnitEntry{"pulse", 1.0}};
constexpr std::array kTimeUnits{UnitEntry{"s", 1.0},   UnitEntry{"sec", 1.0}, UnitEntry{"second", 1.0},
                                UnitEntry{"seconds", 1.0}, UnitEntry{"ms", 1e-3}, UnitEntry{"us", 1e-6},
                                UnitEntry{"µs", 1e-6}, UnitEntry{"μs", 1e-6}, UnitEntry{"ns", 1e-9},
                                UnitEntry{"min", 60.0}};

std::string normalize_unit(std::string_view u) {
  std::string out;
  for (const char c : u)
    if (!std::isspace(static_cast<unsigned char>(c))) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  // Brackets left around a unit ("[g]") are not part of it.
  while (out.size() >= 2 && ((out.front() == '[' && out.back() == ']') || (out.front() == '(' && out.back() == ')')))
    out = out.substr(1, out.size() - 2);
  return out;
}

template <std::size_t N>
std::optional<double> lookup(const std::array<UnitEntry, N>& table, std::string_view unit) {
  const std::string u = normalize_unit(unit);
  for (const auto& e : table)
    if (e.name == u) return e.factor;
  return std::nullopt;
}

template <std::size_t N>
std::string list_units(const std::array<UnitEntry, N>& table) {
  std::string out;
  for (const auto& e : table) out += (out.empty() ? "" : ", ") + std::string(e.name);
  return out;
}

bool is_speed(Quantity q) { return q == Quantity::SunSpeed || q == Quantity::CarrierSpeed; }
bool is_acceleration(Quantity q) {
  return q == Quantity::MeshAccelerationSunPlanet || q == Quantity::MeshAccelerationPlanetRing ||
         q == Quantity::HousingAcceleration;
}

std::string accepted_units(Quantity q) {
  if (is_speed(q)) return list_units(kSpeedUnits);
  if (is_acceleration(q)) return list_units(kAccelerationUnits);
  return list_units(kTachoUnits);
}

/// What kind of unit `unit` is, for messages ("a speed unit").
std::string kind_of_unit(std::string_view unit) {
  if (lookup(kSpeedUnits, unit)) return "a speed unit";
  if (lookup(kAccelerationUnits, unit)) return "an acceleration unit";
  if (lookup(kTimeUnits, unit)) return "a time unit";
  if (lookup(kTachoUnits, unit)) return "a voltage / count unit";
  return "not a unit planetwear knows";
}

bool is_unit_token(std::string_view token) {
  const std::string u = normalize_unit(token);
  return u.empty() || lookup(kSpeedUnits, u) || lookup(kAccelerationUnits, u) || lookup(kTachoUnits, u) ||
         lookup(kTimeUnits, u);
}

// ---------------------------------------------------------------------------
// Small text helpers.

std::string_view trim(std::string_view s) { return trim_space(s); }

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool is_comment(std::string_view trimmed) {
  return trimmed.starts_with('#') || trimmed.starts_with('%') || trimmed.starts_with("//");
}

/// Parses one numeric field: spaces and surrounding quotes ignored, a leading
/// '+' allowed, a decimal comma accepted unless ',' is the delimiter.
/// Returns false for anything that is not entirely a number (NaN and inf are
/// numbers here; the caller rejects them with their row).
bool parse_number(std::string_view field, char delim, double& out) {
  std::string_view f = trim(field);
  if (f.size() >= 2 && f.front() == '"' && f.back() == '"') f = trim(f.substr(1, f.size() - 2));
  if (!f.empty() && f.front() == '+') f.remove_prefix(1);
  if (f.empty()) return false;
  std::array<char, 64> buf{};
  if (delim != ',' && f.find(',') != std::string_view::npos) {
    if (f.size() >= buf.size()) return false;
    std::copy(f.begin(), f.end(), buf.begin());
    std::replace(buf.begin(), buf.begin() + static_cast<std::ptrdiff_t>(f.size()), ',', '.');
    f = std::string_view(buf.data(), f.size());
  }
  const auto r = std::from_chars(f.data(), f.data() + f.size(), out);
  return r.ec == std::errc{} && r.ptr == f.data() + f.size();
}

/// Number of fields if every field of `line` split at `delim` is a number, else 0.
std::size_t numeric_fields(std::string_view line, char delim) {
  std::size_t count = 0, pos = 0;
  double v = 0;
  for (;;) {
    std::size_t end = line.find(delim, pos);
    if (end == std::string_view::npos) end = line.size();
    const std::string_view f = line.substr(pos, end - pos);
    const bool last = end == line.size();
    if (!parse_number(f, delim, v)) {
      if (!(last && trim(f).empty() && count > 0)) return 0;  // a trailing delimiter is allowed
    } else {
      ++count;
    }
    if (last) return count;
    pos = end + 1;
  }
}

std::string source_of(const std::filesystem::path& p) { return p.string(); }

// ---------------------------------------------------------------------------
// JSON sidecar.

[[noreturn]] void json_error(std::string_view source, const std::string& key, const std::string& message) {
  throw InputError(std::string(source) + ": " + key, message);
}

const char* json_type(const json& j) { return j.type_name(); }

double json_number(const json& j, std::string_view source, const std::string& key) {
  if (!j.is_number()) json_error(source, key, detail::concat("expected a number, got ", json_type(j)));
  const double v = j.get<double>();
  if (!std::isfinite(v)) json_error(source, key, detail::concat("must be finite, got ", v));
  return v;
}

std::string json_string(const json& j, std::string_view source, const std::string& key) {
  if (!j.is_string()) json_error(source, key, detail::concat("expected a string, got ", json_type(j)));
  return j.get<std::string>();
}

void check_json_keys(const json& obj, std::string_view source, const std::string& where,
                     std::initializer_list<std::string_view> allowed) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    if (std::find(allowed.begin(), allowed.end(), it.key()) != allowed.end()) continue;
    std::string list;
    for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
    json_error(source, where.empty() ? it.key() : where + "." + it.key(),
               "unknown key; allowed " + std::string(where.empty() ? "at the top level" : "in " + where) + ": " + list);
  }
}

std::string quantity_list() {
  std::string out;
  for (Quantity q : kAllQuantities) out += (out.empty() ? "" : ", ") + std::string(diagnose::to_string(q));
  return out;
}

// ---------------------------------------------------------------------------
// Reading: raw columns from CSV or HDF5, then one common conversion and check.

struct RawColumn {
  const ColumnSpec* spec = nullptr;
  std::string file_unit;  ///< unit found in the file (header / attribute), may be empty
  std::vector<double> values;
};

struct RawTable {
  bool has_time = false;
  std::string time_name, time_unit;
  std::vector<double> time;
  std::vector<RawColumn> columns;
  /// Row label of sample k for messages ("line 12" in a CSV, "sample 11" in HDF5).
  std::vector<std::uint32_t> line_of_sample;  ///< CSV only
  bool csv = true;
  std::string row_label(std::size_t k) const {
    if (csv && k < line_of_sample.size()) return detail::concat("line ", line_of_sample[k]);
    return detail::concat("sample ", k);
  }
};

/// Index of `name` among header names: exact bare name, exact full text, then
/// case-insensitive bare name (if unique). -1 if none.
struct HeaderField {
  std::string full, name, unit;
};

HeaderField split_header_field(const std::string& text) {
  HeaderField h{text, text, ""};
  const std::string_view t = trim(text);
  if (t.size() >= 3 && (t.back() == ']' || t.back() == ')')) {
    const char open = t.back() == ']' ? '[' : '(';
    const auto pos = t.rfind(open);
    if (pos != std::string_view::npos && pos > 0) {
      h.name = std::string(trim(t.substr(0, pos)));
      h.unit = std::string(trim(t.substr(pos + 1, t.size() - pos - 2)));
    }
  }
  return h;
}

int find_header(const std::vector<HeaderField>& header, std::string_view name) {
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i].name == name || header[i].full == name) return static_cast<int>(i);
  int found = -1;
  const std::string ln = lower(name);
  for (std::size_t i = 0; i < header.size(); ++i)
    if (lower(header[i].name) == ln) {
      if (found >= 0) return -1;
      found = static_cast<int>(i);
    }
  return found;
}

std::string header_list(const std::vector<HeaderField>& header) {
  std::string out;
  for (const auto& h : header) out += (out.empty() ? "'" : ", '") + h.full + "'";
  return out;
}

constexpr std::array<std::string_view, 5> kTimeNames{"time", "time_s", "t", "time_sec", "seconds"};

/// Which file column feeds which slot of `table` (slot 0 = time when the file has a time
/// column and no sample rate is given; -1: not read); fills table.has_time, its name and
/// unit, and one entry of table.columns per column the sidecar describes.
std::vector<int> assign_columns(const std::vector<HeaderField>& header, const RecordingMeta& meta,
                                const std::string& src, RawTable& table) {
  std::vector<int> slot(header.size(), -1);
  int time_col = -1;
  if (!meta.time_column.empty()) {
    time_col = find_header(header, meta.time_column);
    if (time_col < 0)
      throw InputError(src, detail::concat("time column '", meta.time_column, "' (time_column in ", meta.source,
                                           ") is not in the header; columns: ", header_list(header)));
  } else {
    for (auto n : kTimeNames)
      if ((time_col = find_header(header, n)) >= 0) break;
    if (time_col < 0 && !meta.sample_rate_Hz)
      throw InputError(src, detail::concat("no time column (looked for 'time', 'time_s', 't'); columns: ",
                                           header_list(header),
                                           ". Name it with time_column, or give sample_rate_Hz for a file "
                                           "without time"));
  }
  int slots = 0;
  if (time_col >= 0 && !meta.sample_rate_Hz) {
    table.has_time = true;
    table.time_name = header[time_col].full;
    table.time_unit = header[time_col].unit;
    slot[time_col] = slots++;
  }
  for (const ColumnSpec& spec : meta.columns) {
    const int c = find_header(header, spec.name);
    if (c < 0)
      throw InputError(src, detail::concat("column '", spec.name, "' (", diagnose::to_string(spec.quantity),
                                           ", described in ", meta.source, ") is missing from the file; columns: ",
                                           header_list(header)));
    if (slot[c] >= 0)
      throw InputError(src, detail::concat("column '", header[c].full, "' is used twice (as '", spec.name,
                                           "' and as the time or another column)"));
    slot[c] = slots++;
    table.columns.push_back({&spec, header[c].unit, {}});
  }
  return slot;
}

RawTable read_csv(const std::filesystem::path& path, const RecordingMeta& meta) {
  const std::string src = source_of(path);
  std::vector<char> buffer(1 << 20);
  std::ifstream in;
  in.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
  in.open(path, std::ios::binary);
  if (!in) throw IoError(detail::concat("cannot open recording '", src, "': ", std::strerror(errno)));

  // 1. Preamble: skip comments and blank lines; the first line whose fields
  //    are all numbers is the first data row, the line before it the header
  //    (or a row of units under the header).
  std::string line;
  std::size_t line_no = 0;
  std::vector<std::pair<std::size_t, std::string>> pre;
  char delim = 0;
  std::size_t data_fields = 0, first_data_line = 0;
  std::string first_data;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line_no == 1 && line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);  // UTF-8 BOM
    const std::string_view t = trim(line);
    if (t.empty() || is_comment(t)) continue;
    std::array<std::pair<char, std::size_t>, 3> cand{{{',', numeric_fields(t, ',')},
                                                      {';', numeric_fields(t, ';')},
                                                      {'\t', numeric_fields(t, '\t')}}};
    std::size_t best = 0;
    for (const auto& [d, n] : cand) {
      if (n == 0) continue;
      const std::size_t header_n = pre.empty() ? 0 : split_fields(pre.back().second, d).size();
      const bool matches = header_n == n || header_n == n + 1;
      const std::size_t score = n * 2 + (matches ? 1 : 0);
      if (score > best) {
        best = score;
        delim = d;
        data_fields = n;
      }
    }
    if (best > 0) {
      first_data = line;
      first_data_line = line_no;
      break;
    }
    pre.emplace_back(line_no, line);
    if (pre.size() > kMaxPreambleLines)
      throw InputError(src, detail::concat("no numeric data row in the first ", kMaxPreambleLines,
                                           " non-comment lines; is this a CSV recording?"));
  }
  if (in.bad()) throw IoError(src + ": read error");
  if (first_data_line == 0)
    throw InputError(src, line_no == 0 ? std::string("the file is empty")
                                       : "no numeric data rows (every line is a comment, blank or text)");
  if (pre.empty())
    throw InputError(src, detail::concat("no header row before the first data row (line ", first_data_line,
                                         "): the first line must name the columns, e.g. 'time [s],acc [m/s^2]'"));

  // 2. Header (and optional unit row).
  auto fields_of = [&](const std::string& text) {
    std::vector<std::string> f = split_fields(text, delim);
    if (f.size() == data_fields + 1 && f.back().empty()) f.pop_back();  // trailing delimiter
    return f;
  };
  std::size_t header_index = pre.size() - 1;
  std::vector<std::string> units_row;
  {
    const std::vector<std::string> last = fields_of(pre.back().second);
    const bool all_units = std::all_of(last.begin(), last.end(), [](const std::string& s) { return is_unit_token(s); });
    if (pre.size() >= 2 && last.size() == data_fields && all_units &&
        fields_of(pre[pre.size() - 2].second).size() == data_fields) {
      units_row = last;
      header_index = pre.size() - 2;
    }
  }
  const std::vector<std::string> names = fields_of(pre[header_index].second);
  if (names.size() != data_fields)
    throw InputError(src, detail::concat("the header (line ", pre[header_index].first, ") has ", names.size(),
                                         " columns but the first data row (line ", first_data_line, ") has ",
                                         data_fields, "; delimiter '", delim == '\t' ? std::string("tab")
                                                                                      : std::string(1, delim),
                                         "'"));
  std::vector<HeaderField> header;
  for (std::size_t i = 0; i < names.size(); ++i) {
    HeaderField h = split_header_field(names[i]);
    if (h.unit.empty() && !units_row.empty()) h.unit = std::string(trim(units_row[i]));
    header.push_back(std::move(h));
  }

  // 3. Which file column feeds which slot (slot 0 = time if present).
  RawTable table;
  const std::vector<int> slot = assign_columns(header, meta, src, table);

  // 4. Data rows, one pass. Capacity from the first row's length.
  std::vector<std::vector<double>*> out;
  if (table.has_time) out.push_back(&table.time);
  for (auto& c : table.columns) out.push_back(&c.values);
  std::error_code ec;
  if (std::filesystem::is_regular_file(path, ec)) {
    const auto size = std::filesystem::file_size(path, ec);
    if (!ec && !first_data.empty()) {
      const std::size_t rows = static_cast<std::size_t>(static_cast<double>(size) / static_cast<double>(first_data.size() + 1) * 1.1) + 16;
      for (auto* v : out) v->reserve(rows);
      table.line_of_sample.reserve(rows);
    }
  }
  std::vector<std::string_view> column_name(header.size());
  for (std::size_t i = 0; i < header.size(); ++i) column_name[i] = header[i].full;
  auto parse_row = [&](std::string_view row, std::size_t at) {
    std::size_t field = 0, pos = 0;
    for (;;) {
      std::size_t end = row.find(delim, pos);
      if (end == std::string_view::npos) end = row.size();
      if (field < slot.size() && slot[field] >= 0) {
        const std::string_view f = row.substr(pos, end - pos);
        double v = 0;
        if (!parse_number(f, delim, v))
          throw InputError(src, detail::concat("line ", at, ", column '", column_name[field], "': ",
                                               trim(f).empty() ? std::string("empty value")
                                                               : "'" + std::string(trim(f)) + "' is not a number"));
        if (!std::isfinite(v))
          throw InputError(src, detail::concat("line ", at, ", column '", column_name[field], "': ",
                                               std::isnan(v) ? "NaN" : "infinite value",
                                               " (a dropout?); cut the recording or fill the gap"));
        out[static_cast<std::size_t>(slot[field])]->push_back(v);
      }
      ++field;
      if (end == row.size()) break;
      pos = end + 1;
    }
    const bool trailing = field == header.size() + 1 && trim(row.substr(pos)).empty();
    if (field != header.size() && !trailing)
      throw InputError(src, detail::concat("line ", at, " has ", field, " fields, the header has ", header.size()));
    if (table.has_time) {
      const std::size_t n = table.time.size();
      if (n >= 2 && !(table.time[n - 1] > table.time[n - 2]))
        throw InputError(src, detail::concat("line ", at, ": time ", table.time[n - 1],
                                             " does not increase (previous sample ", table.time[n - 2], ")"));
    }
    table.line_of_sample.push_back(static_cast<std::uint32_t>(at));
  };
  parse_row(trim(first_data), first_data_line);
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view t = trim(line);
    if (t.empty() || is_comment(t)) continue;
    parse_row(t, line_no);
  }
  if (in.bad()) throw IoError(src + ": read error");
  return table;
}

bool has_hdf5_signature(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, 8> sig{};
  in.read(sig.data(), sig.size());
  return in.gcount() == 8 && std::memcmp(sig.data(), "\x89HDF\r\n\x1a\n", 8) == 0;
}

RawTable read_hdf5(const std::filesystem::path& path, const RecordingMeta& meta) {
  const std::string src = source_of(path);
  H5File f = H5File::open(path);
  RawTable table;
  table.csv = false;
  auto absolute = [](std::string_view name) { return name.starts_with('/') ? std::string(name) : "/" + std::string(name); };
  auto find_dataset = [&](std::string_view name) -> std::string {
    for (const std::string& p : {absolute(name), "/time_history" + absolute(name)})
      if (f.exists(p) && !f.is_group(p)) return p;
    return {};
  };
  auto read_1d = [&](const std::string& p, const std::string& what) {
    const auto shape = f.shape(p);
    if (shape.size() != 1)
      throw InputError(src, detail::concat(what, " '", p, "' must be a 1-D dataset, it has rank ", shape.size()));
    return f.read_doubles(p);
  };
  auto unit_of = [&](const std::string& p) {
    return f.has_attribute(p, "unit") ? f.read_string_attribute(p, "unit") : std::string();
  };
  if (!meta.sample_rate_Hz) {
    std::string tp;
    if (!meta.time_column.empty()) {
      tp = find_dataset(meta.time_column);
      if (tp.empty())
        throw InputError(src, detail::concat("time dataset '", meta.time_column, "' (time_column in ", meta.source,
                                             ") does not exist"));
    } else {
      for (const char* n : {"/time", "/t", "/time_history/time"})
        if (f.exists(n) && !f.is_group(n)) {
          tp = n;
          break;
        }
      if (tp.empty())
        throw InputError(src, "no time dataset ('/time' or '/time_history/time'); name it with time_column, or "
                              "give sample_rate_Hz");
    }
    table.has_time = true;
    table.time_name = tp;
    table.time_unit = unit_of(tp);
    table.time = read_1d(tp, "time");
  }
  std::set<std::string> used;
  for (const ColumnSpec& spec : meta.columns) {
    const std::string p = find_dataset(spec.name);
    if (p.empty())
      throw InputError(src, detail::concat("column '", spec.name, "' (", diagnose::to_string(spec.quantity),
                                           ", described in ", meta.source, "): no such dataset"));
    if (!used.insert(p).second || p == table.time_name)
      throw InputError(src, detail::concat("dataset '", p, "' is used twice"));
    table.columns.push_back({&spec, unit_of(p), read_1d(p, "column")});
  }
  for (std::size_t k = 1; k < table.time.size(); ++k)
    if (!(table.time[k] > table.time[k - 1]) && std::isfinite(table.time[k]))
      throw InputError(src, detail::concat("sample ", k, ": time ", table.time[k], " does not increase (previous ",
                                           table.time[k - 1], ")"));
  auto check_finite = [&](const std::vector<double>& v, const std::string& name) {
    for (std::size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k]))
        throw InputError(src, detail::concat("sample ", k, ", column '", name, "': ",
                                             std::isnan(v[k]) ? "NaN" : "infinite value",
                                             " (a dropout?); cut the recording or fill the gap"));
  };
  if (table.has_time) check_finite(table.time, table.time_name);
  for (const auto& c : table.columns) {
    check_finite(c.values, c.spec->name);
    if (table.has_time && c.values.size() != table.time.size())
      throw InputError(src, detail::concat("column '", c.spec->name, "' has ", c.values.size(),
                                           " samples, the time has ", table.time.size()));
  }
  if (!table.has_time && !table.columns.empty()) {
    for (const auto& c : table.columns)
      if (c.values.size() != table.columns.front().values.size())
        throw InputError(src, detail::concat("column '", c.spec->name, "' has ", c.values.size(), " samples, '",
                                             table.columns.front().spec->name, "' has ",
                                             table.columns.front().values.size()));
  }
  return table;
}

/// Checks of the description that need no samples.
void check_meta(const RecordingMeta& meta, const model::SimulationConfig& config, const std::string& src) {
  const std::string from = meta.source.empty() ? std::string("the recording description") : meta.source;
  if (!meta.input_speed_rpm)
    throw InputError(src, "operating.input_speed_rpm is missing: give the nominal input (sun) speed in the "
                          "sidecar ({\"operating\": {\"input_speed_rpm\": 400, ...}}) or on the command line");
  if (!(*meta.input_speed_rpm > 0) || *meta.input_speed_rpm > 1e5)
    throw InputError(src, detail::concat("operating.input_speed_rpm must be in (0, 1e5] rpm, got ",
                                         *meta.input_speed_rpm, " (", from, ")"));
  if (meta.input_power_W && meta.input_torque_Nm)
    throw InputError(src, detail::concat("give operating.input_power_W or operating.input_torque_Nm, not both (",
                                         from, ")"));
  if (!meta.input_power_W && !meta.input_torque_Nm)
    throw InputError(src, "operating.input_power_W (or input_torque_Nm) is missing: the diagnosis needs the load");
  if (meta.input_power_W && !(*meta.input_power_W > 0))
    throw InputError(src, detail::concat("operating.input_power_W must be > 0 W, got ", *meta.input_power_W));
  if (meta.input_torque_Nm && !(*meta.input_torque_Nm > 0))
    throw InputError(src, detail::concat("operating.input_torque_Nm must be > 0 N m, got ", *meta.input_torque_Nm));
  if (meta.sample_rate_Hz && !(*meta.sample_rate_Hz > 0))
    throw InputError(src, detail::concat("sample_rate_Hz must be > 0, got ", *meta.sample_rate_Hz));
  if (meta.columns.empty())
    throw InputError(src, detail::concat("no signal column is described (", from, "): list at least one under "
                                                                                 "\"columns\" or with --column; "
                                                                                 "quantities: ",
                                         quantity_list()));
  if (std::all_of(meta.columns.begin(), meta.columns.end(),
                  [](const ColumnSpec& c) { return c.quantity == Quantity::Tacho; }))
    throw InputError(src, "no usable signal column: only tacho columns are described; add a speed or "
                          "acceleration column");
  std::set<std::string> names;
  for (const ColumnSpec& c : meta.columns) {
    const std::string col = detail::concat("column '", c.name, "' (", diagnose::to_string(c.quantity), ")");
    if (!names.insert(c.name).second) throw InputError(src, col + " is described twice");
    if (c.quantity == Quantity::MeshAccelerationSunPlanet || c.quantity == Quantity::MeshAccelerationPlanetRing) {
      if (c.planet < 0 || c.planet >= config.stage.planet_count)
        throw InputError(src, detail::concat(col, ": planet ", c.planet, " does not exist (stage.planet_count = ",
                                             config.stage.planet_count, ", planets are numbered from 0)"));
    }
    if (c.quantity == Quantity::HousingAcceleration && !c.sensor_angle_rad)
      throw InputError(src, col + ": a housing accelerometer needs its angle (sensor_angle_deg: counter-clockwise "
                                  "from planet 0's position at t = 0)");
    if (c.quantity != Quantity::HousingAcceleration && c.sensor_angle_rad)
      throw InputError(src, col + ": sensor_angle applies only to housing_acceleration columns");
    if (c.sensor_angle_rad && !std::isfinite(*c.sensor_angle_rad))
      throw InputError(src, col + ": sensor angle must be finite");
    if (!std::isfinite(c.scale) || c.scale == 0)
      throw InputError(src, detail::concat(col, ": scale must be finite and non-zero, got ", c.scale));
    if (c.encoder_lines && c.quantity != Quantity::SunSpeed && c.quantity != Quantity::CarrierSpeed)
      throw InputError(src, col + ": encoder_lines applies only to sun_speed and carrier_speed columns");
    if (c.encoder_lines && (*c.encoder_lines < 1 || *c.encoder_lines > config::kMaxEncoderLines))
      throw InputError(src, detail::concat(col, ": encoder_lines must lie in [1, ", config::kMaxEncoderLines, "], got ",
                                           *c.encoder_lines));
    if (!c.unit.empty() && !si_factor(c.quantity, c.unit))
      throw InputError(src, detail::concat(col, ": unit '", c.unit, "' cannot be right for ",
                                           diagnose::to_string(c.quantity), " (it is ", kind_of_unit(c.unit),
                                           "); accepted: ", accepted_units(c.quantity)));
  }
}

diagnose::Recording finish(RawTable&& t, const RecordingMeta& meta, const model::SimulationConfig& config,
                           const std::string& src) {
  const double rpm = *meta.input_speed_rpm;
  diagnose::Recording rec;
  rec.source = src;
  rec.operating.input_speed_rpm = rpm;
  rec.operating.input_power_W =
      meta.input_power_W ? *meta.input_power_W : *meta.input_torque_Nm * rpm * 2 * kPi / 60;

  // Time axis.
  std::size_t n = t.has_time ? t.time.size() : (t.columns.empty() ? 0 : t.columns.front().values.size());
  if (n < 2) throw InputError(src, detail::concat("only ", n, " samples; a recording needs many carrier revolutions"));
  double t0 = 0, dt = 0;
  if (t.has_time) {
    std::string unit = !meta.time_unit.empty() ? meta.time_unit : t.time_unit;
    if (!meta.time_unit.empty() && !t.time_unit.empty() && lookup(kTimeUnits, meta.time_unit) &&
        lookup(kTimeUnits, t.time_unit) && *lookup(kTimeUnits, meta.time_unit) != *lookup(kTimeUnits, t.time_unit))
      throw InputError(src, detail::concat("time column '", t.time_name, "': unit '", t.time_unit,
                                           "' in the file contradicts time_unit '", meta.time_unit, "' of ",
                                           meta.source));
    if (unit.empty()) unit = "s";
    const auto factor = lookup(kTimeUnits, unit);
    if (!factor)
      throw InputError(src, detail::concat("time column '", t.time_name, "': unit '", unit,
                                           "' is not a time unit (it is ", kind_of_unit(unit),
                                           "); accepted: ", list_units(kTimeUnits)));
    if (*factor != 1.0)
      for (double& x : t.time) x *= *factor;
    t0 = t.time.front();
    dt = (t.time.back() - t0) / static_cast<double>(n - 1);
    // Every sample on the uniform grid: within 1e-6 of the duration (the
    // printed precision of DAQ exports) but never more than 5 % of a step
    // (a dropped or repeated sample moves the grid by half a step or more).
    const double tol = std::min(1e-6 * (t.time.back() - t0), 0.05 * dt);
    for (std::size_t k = 0; k < n; ++k) {
      const double dev = t.time[k] - (t0 + static_cast<double>(k) * dt);
      if (std::fabs(dev) > tol)
        throw InputError(src, detail::concat("non-uniform time at ", t.row_label(k), ": t = ", t.time[k],
                                             " s is ", dev, " s off the uniform grid (dt = ", dt,
                                             " s from the first and last sample; tolerance ", tol,
                                             " s). Dropped samples? If the time column is just printed "
                                             "coarsely, drop it and give sample_rate_Hz"));
    }
  } else {
    dt = 1.0 / *meta.sample_rate_Hz;
  }
  rec.time_s.resize(n);
  for (std::size_t k = 0; k < n; ++k) rec.time_s[k] = t0 + static_cast<double>(k) * dt;

  // Sample rate and duration against the gear set at this speed.
  const double fs = 1.0 / dt, fm = mesh_frequency_Hz(config, rpm);
  const double fs_min = required_sample_rate_Hz(config, rpm);
  if (fs < fs_min)
    throw InputError(src, detail::concat("sample rate ", fs, " Hz is too low: the diagnosis analyses up to the ",
                                         kAnalysedMeshHarmonics, "rd mesh harmonic (", kAnalysedMeshHarmonics, " x ",
                                         fm, " Hz at ", rpm, " rpm) and needs ", kSampleRateMargin, " x that = ",
                                         fs_min, " Hz"));
  const double duration = static_cast<double>(n) * dt, d_min = required_duration_s(config, rpm);
  if (duration < d_min)
    throw InputError(src, detail::concat("recording is ", duration, " s long and holds ", duration * fm,
                                         " mesh cycles at ", rpm, " rpm input; the diagnosis needs at least ",
                                         required_mesh_cycles(config), " mesh cycles (", d_min,
                                         " s): a fit and a held-out half of one sun period (Zs = ",
                                         config.stage.sun.teeth, " mesh cycles) each"));

  // Channels: units, conversion, plausibility.
  const double w_sun = rpm * 2 * kPi / 60, w_carrier = model::carrier_speed(config.stage, w_sun);
  for (RawColumn& c : t.columns) {
    const ColumnSpec& s = *c.spec;
    const std::string col = detail::concat("column '", s.name, "' (", diagnose::to_string(s.quantity), ")");
    std::string unit = s.unit.empty() ? c.file_unit : s.unit;
    if (!s.unit.empty() && !c.file_unit.empty()) {
      const auto a = si_factor(s.quantity, s.unit), b = si_factor(s.quantity, c.file_unit);
      if (!b || *a != *b)
        throw InputError(src, detail::concat(col, ": unit '", s.unit, "' of ", meta.source,
                                             " contradicts the file's '", c.file_unit, "'"));
    }
    if (unit.empty()) {
      if (s.quantity != Quantity::Tacho)
        throw InputError(src, col + ": no unit; give it in the header ('" + s.name + " [unit]') or in the "
                                    "sidecar (accepted: " + accepted_units(s.quantity) + ")");
      unit = "1";
    }
    const auto factor = si_factor(s.quantity, unit);
    if (!factor)
      throw InputError(src, detail::concat(col, ": unit '", unit, "' cannot be right for ",
                                           diagnose::to_string(s.quantity), " (it is ", kind_of_unit(unit),
                                           "); accepted: ", accepted_units(s.quantity)));
    const double k = *factor * s.scale;
    if (k != 1.0)
      for (double& x : c.values) x *= k;

    double mean = 0;
    for (double x : c.values) mean += x;
    mean /= static_cast<double>(n);
    double ms = 0;
    for (double x : c.values) ms += (x - mean) * (x - mean);
    const double rms = std::sqrt(ms / static_cast<double>(n));
    if (is_speed(s.quantity)) {
      const double nominal = s.quantity == Quantity::SunSpeed ? w_sun : w_carrier;
      if (std::fabs(mean / nominal - 1.0) > kSpeedTolerance)
        throw InputError(src, detail::concat(col, ": mean ", mean, " rad/s (read as '", unit, "'",
                                             s.scale != 1 ? detail::concat(", scale ", s.scale) : std::string(),
                                             ") is not within ", 100 * kSpeedTolerance, " % of the nominal ",
                                             nominal, " rad/s at ", rpm, " rpm input. ",
                                             mean < 0 ? "Counting the other way? Give scale = -1. "
                                                      : "Wrong unit? ",
                                             "(rpm read as rad/s is 9.55x too large)"));
    }
    // A constant column (a dead sensor, a drive's speed exported as its setpoint) has no noise to
    // judge anything against: its periodogram is 0 and every comparison would divide by it. Any
    // quantity, speeds too (a speed channel carries the mesh harmonics' speed fluctuation).
    // Compared with the first value, not through the RMS: the mean of n equal values need not
    // equal them in floating point, and the RMS of a constant is then a round-off, not 0.
    if (std::all_of(c.values.begin(), c.values.end(), [v0 = c.values.front()](double x) { return x == v0; }))
      throw InputError(src, col + ": carries no signal (every value is the same): a dead sensor or a constant "
                                  "export; leave the column out of the sidecar's \"columns\" to diagnose without it");
    if (is_acceleration(s.quantity)) {
      if (rms > kMaxAccelerationRms)
        throw InputError(src, detail::concat(col, ": RMS ", rms, " m/s^2 (read as '", unit, "') is over ",
                                             kMaxAccelerationRms, " m/s^2 (10^4 g); wrong unit?"));
    }
    diagnose::SignalChannel ch;
    ch.name = s.name;
    ch.quantity = s.quantity;
    ch.unit = si_unit(s.quantity);
    ch.planet = s.planet;
    ch.sensor_angle_rad = s.sensor_angle_rad.value_or(0.0);
    ch.values = std::move(c.values);
    rec.channels.push_back(std::move(ch));
  }
  return rec;
}

} // namespace

// ---------------------------------------------------------------------------

std::optional<Quantity> quantity_from_string(std::string_view name) {
  for (Quantity q : kAllQuantities)
    if (name == diagnose::to_string(q)) return q;
  return std::nullopt;
}

std::optional<double> si_factor(Quantity q, std::string_view unit) {
  if (is_speed(q)) return lookup(kSpeedUnits, unit);
  if (is_acceleration(q)) return lookup(kAccelerationUnits, unit);
  return lookup(kTachoUnits, unit);
}

const char* si_unit(Quantity q) {
  if (is_speed(q)) return "rad/s";
  if (is_acceleration(q)) return "m/s^2";
  return "1";
}

double mesh_frequency_Hz(const model::SimulationConfig& c, double speed_rpm) {
  return model::mesh_frequency_Hz(c.stage, speed_rpm);
}

double required_sample_rate_Hz(const model::SimulationConfig& c, double speed_rpm) {
  return kSampleRateMargin * kAnalysedMeshHarmonics * mesh_frequency_Hz(c, speed_rpm);
}

int required_mesh_cycles(const model::SimulationConfig& c) {
  return diagnose::min_recording_mesh_cycles(c.stage.sun.teeth);
}

double required_duration_s(const model::SimulationConfig& c, double speed_rpm) {
  return required_mesh_cycles(c) / mesh_frequency_Hz(c, speed_rpm);
}

RecordingMeta parse_recording_meta(std::string_view text, std::string_view source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    throw InputError(std::string(source), detail::concat("JSON syntax error: ", e.what()));
  }
  if (!j.is_object())
    throw InputError(std::string(source), detail::concat("expected a JSON object, got ", json_type(j)));
  check_json_keys(j, source, "",
                  {"operating", "time_column", "time_unit", "sample_rate_Hz", "columns", "description", "generator"});
  RecordingMeta m;
  m.source = std::string(source);
  if (j.contains("operating")) {
    const json& op = j["operating"];
    if (!op.is_object()) json_error(source, "operating", detail::concat("expected an object, got ", json_type(op)));
    check_json_keys(op, source, "operating", {"input_speed_rpm", "input_power_W", "input_torque_Nm"});
    if (op.contains("input_speed_rpm"))
      m.input_speed_rpm = json_number(op["input_speed_rpm"], source, "operating.input_speed_rpm");
    if (op.contains("input_power_W"))
      m.input_power_W = json_number(op["input_power_W"], source, "operating.input_power_W");
    if (op.contains("input_torque_Nm"))
      m.input_torque_Nm = json_number(op["input_torque_Nm"], source, "operating.input_torque_Nm");
  }
  if (j.contains("time_column")) m.time_column = json_string(j["time_column"], source, "time_column");
  if (j.contains("time_unit")) {
    m.time_unit = json_string(j["time_unit"], source, "time_unit");
    if (!lookup(kTimeUnits, m.time_unit))
      json_error(source, "time_unit", "'" + m.time_unit + "' is not a time unit; accepted: " + list_units(kTimeUnits));
  }
  if (j.contains("sample_rate_Hz")) m.sample_rate_Hz = json_number(j["sample_rate_Hz"], source, "sample_rate_Hz");
  if (j.contains("description") && !j["description"].is_string())
    json_error(source, "description", "expected a string");
  if (j.contains("columns")) {
    const json& cols = j["columns"];
    if (!cols.is_object())
      json_error(source, "columns",
                 detail::concat("expected an object {\"<column name>\": {\"quantity\": ...}, ...}, got ",
                                json_type(cols)));
    for (auto it = cols.begin(); it != cols.end(); ++it) {
      const std::string key = "columns." + it.key();
      const json& c = it.value();
      if (!c.is_object()) json_error(source, key, detail::concat("expected an object, got ", json_type(c)));
      check_json_keys(c, source, key,
                      {"quantity", "unit", "planet", "sensor_angle_deg", "sensor_angle_rad", "scale", "encoder_lines",
                       "description"});
      ColumnSpec s;
      s.name = it.key();
      if (!c.contains("quantity")) json_error(source, key + ".quantity", "missing; one of " + quantity_list());
      const std::string q = json_string(c["quantity"], source, key + ".quantity");
      const auto quantity = quantity_from_string(q);
      if (!quantity) json_error(source, key + ".quantity", "'" + q + "' is not one of " + quantity_list());
      s.quantity = *quantity;
      if (c.contains("unit")) {
        s.unit = json_string(c["unit"], source, key + ".unit");
        if (!si_factor(s.quantity, s.unit))
          json_error(source, key + ".unit",
                     detail::concat("'", s.unit, "' cannot be right for ", q, " (it is ", kind_of_unit(s.unit),
                                    "); accepted: ", accepted_units(s.quantity)));
      }
      if (c.contains("planet")) {
        const json& p = c["planet"];
        if (!p.is_number_integer() || p.get<long long>() < 0)
          json_error(source, key + ".planet", "expected an integer >= 0 (0-based planet index)");
        s.planet = static_cast<int>(p.get<long long>());
      }
      if (c.contains("sensor_angle_deg") && c.contains("sensor_angle_rad"))
        json_error(source, key + ".sensor_angle_deg", "give sensor_angle_deg or sensor_angle_rad, not both");
      if (c.contains("sensor_angle_deg"))
        s.sensor_angle_rad = json_number(c["sensor_angle_deg"], source, key + ".sensor_angle_deg") * kPi / 180;
      if (c.contains("sensor_angle_rad"))
        s.sensor_angle_rad = json_number(c["sensor_angle_rad"], source, key + ".sensor_angle_rad");
      if (c.contains("scale")) s.scale = json_number(c["scale"], source, key + ".scale");
      if (c.contains("encoder_lines")) {
        const json& n = c["encoder_lines"];
        if (!n.is_number_integer() || n.get<long long>() < 1 || n.get<long long>() > config::kMaxEncoderLines)
          json_error(source, key + ".encoder_lines",
                     detail::concat("expected an integer in [1, ", config::kMaxEncoderLines,
                                    "] (lines per revolution of the encoder)"));
        s.encoder_lines = static_cast<int>(n.get<long long>());
      }
      m.columns.push_back(std::move(s));
    }
  }
  return m;
}

RecordingMeta read_recording_meta(const std::filesystem::path& json_path) {
  std::ifstream in(json_path, std::ios::binary);
  if (!in)
    throw IoError(detail::concat("cannot open recording sidecar '", json_path.string(), "': ", std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_recording_meta(text.str(), json_path.string());
}

ColumnSpec parse_column_option(std::string_view text, std::string_view option) {
  const std::string opt(option);
  std::vector<std::string> parts;
  {
    std::size_t pos = 0;
    for (;;) {
      const auto comma = text.find(',', pos);
      parts.emplace_back(trim(text.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos)));
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
  }
  const std::string usage =
      "expected NAME=QUANTITY[,unit=U][,planet=I][,sensor_angle_deg=A][,scale=S][,encoder_lines=N], e.g. "
      "'acc=housing_acceleration,unit=g,sensor_angle_deg=30'";
  const auto eq = parts[0].find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(opt, detail::concat("'", text, "': ", usage));
  ColumnSpec s;
  s.name = std::string(trim(std::string_view(parts[0]).substr(0, eq)));
  const std::string q(trim(std::string_view(parts[0]).substr(eq + 1)));
  const auto quantity = quantity_from_string(q);
  if (!quantity) throw InputError(opt, detail::concat("'", text, "': quantity '", q, "' is not one of ", quantity_list()));
  s.quantity = *quantity;
  auto number = [&](const std::string& key, const std::string& value) {
    double v = 0;
    if (!parse_number(value, ',', v) || !std::isfinite(v))
      throw InputError(opt, detail::concat("'", text, "': ", key, " = '", value, "' is not a finite number"));
    return v;
  };
  for (std::size_t i = 1; i < parts.size(); ++i) {
    const auto e = parts[i].find('=');
    if (e == std::string::npos) throw InputError(opt, detail::concat("'", text, "': '", parts[i], "': ", usage));
    const std::string key(trim(std::string_view(parts[i]).substr(0, e)));
    const std::string value(trim(std::string_view(parts[i]).substr(e + 1)));
    if (key == "unit") {
      if (!si_factor(s.quantity, value))
        throw InputError(opt, detail::concat("'", text, "': unit '", value, "' cannot be right for ", q, " (it is ",
                                             kind_of_unit(value), "); accepted: ", accepted_units(s.quantity)));
      s.unit = value;
    } else if (key == "planet") {
      const double p = number(key, value);
      if (p < 0 || p != std::floor(p)) throw InputError(opt, detail::concat("'", text, "': planet must be an integer >= 0"));
      s.planet = static_cast<int>(p);
    } else if (key == "sensor_angle_deg") {
      s.sensor_angle_rad = number(key, value) * kPi / 180;
    } else if (key == "sensor_angle_rad") {
      s.sensor_angle_rad = number(key, value);
    } else if (key == "scale") {
      s.scale = number(key, value);
    } else if (key == "encoder_lines") {
      const double n = number(key, value);
      if (n < 1 || n > config::kMaxEncoderLines || n != std::floor(n))
        throw InputError(opt, detail::concat("'", text, "': encoder_lines must be an integer in [1, ",
                                             config::kMaxEncoderLines, "]"));
      s.encoder_lines = static_cast<int>(n);
    } else {
      throw InputError(opt, detail::concat("'", text, "': unknown key '", key, "'; ", usage));
    }
  }
  return s;
}

void apply_encoder_lines(const RecordingMeta& meta, model::SimulationConfig& config) {
  for (const ColumnSpec& c : meta.columns) {
    if (!c.encoder_lines) continue;
    const bool sun = c.quantity == Quantity::SunSpeed;
    if (!sun && c.quantity != Quantity::CarrierSpeed) continue;  // check_meta refuses it
    int& lines = sun ? config.sensor.sun_encoder_lines : config.sensor.carrier_encoder_lines;
    const char* key = sun ? "sensor.sun_encoder_lines" : "sensor.carrier_encoder_lines";
    if (lines != 0 && lines != *c.encoder_lines)
      throw InputError(key, detail::concat("the configuration gives ", lines, " lines, ", meta.source, "'s column '",
                                           c.name, "' ", *c.encoder_lines,
                                           ": they describe one encoder; correct one of them"));
    lines = *c.encoder_lines;
  }
}

RecordingMeta merge(RecordingMeta base, const RecordingMeta& o) {
  if (o.input_speed_rpm) base.input_speed_rpm = o.input_speed_rpm;
  if (o.input_power_W) {
    base.input_power_W = o.input_power_W;
    base.input_torque_Nm.reset();
  }
  if (o.input_torque_Nm) {
    base.input_torque_Nm = o.input_torque_Nm;
    base.input_power_W.reset();
  }
  if (!o.time_column.empty()) base.time_column = o.time_column;
  if (!o.time_unit.empty()) base.time_unit = o.time_unit;
  if (o.sample_rate_Hz) base.sample_rate_Hz = o.sample_rate_Hz;
  for (const ColumnSpec& c : o.columns) {
    auto it = std::find_if(base.columns.begin(), base.columns.end(), [&](const ColumnSpec& b) { return b.name == c.name; });
    if (it != base.columns.end()) *it = c;
    else base.columns.push_back(c);
  }
  if (!o.source.empty()) base.source = base.source.empty() ? o.source : base.source + " and " + o.source;
  return base;
}

diagnose::Recording read_recording(const std::filesystem::path& path, const RecordingMeta& meta,
                                   const model::SimulationConfig& config) {
  const std::string src = source_of(path);
  check_meta(meta, config, src);
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw IoError(detail::concat("cannot open recording '", src, "': no such file"));
  const std::string ext = lower(path.extension().string());
  bool hdf5 = false;
  if (ext == ".h5" || ext == ".hdf5" || ext == ".hdf" || ext == ".he5") hdf5 = true;
  else if (ext == ".csv" || ext == ".txt" || ext == ".dat" || ext == ".tsv") hdf5 = false;
  else hdf5 = has_hdf5_signature(path);
  RawTable table = hdf5 ? read_hdf5(path, meta) : read_csv(path, meta);
  return finish(std::move(table), meta, config, src);
}

} // namespace pw::io
