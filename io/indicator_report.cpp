// Gear condition indicators as files and tables (indicator_report.hpp).
#include "io/indicator_report.hpp"

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/config_toml.hpp"
#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>

namespace pw::io {

namespace {

using json = nlohmann::ordered_json;
namespace dg = pw::diagnose;

/// Which snapshot datasets are analysed, and as what.
bool classify(const std::string& name, dg::Quantity& q, int& planet) {
  if (name == "housing/acceleration") {
    q = dg::Quantity::HousingAcceleration;
    planet = 0;
    return true;
  }
  for (const auto& [prefix, quantity] : {std::pair{std::string("sun_planet/"), dg::Quantity::MeshAccelerationSunPlanet},
                                         std::pair{std::string("planet_ring/"), dg::Quantity::MeshAccelerationPlanetRing}}) {
    if (!name.starts_with(prefix) || !name.ends_with("/acceleration")) continue;
    const std::string idx = name.substr(prefix.size(), name.size() - prefix.size() - std::string("/acceleration").size());
    if (idx.empty() || !std::all_of(idx.begin(), idx.end(), [](char ch) { return ch >= '0' && ch <= '9'; })) continue;
    q = quantity;
    planet = std::stoi(idx);
    return true;
  }
  return false;
}

/// Dataset names below `group`, recursively ("sun_planet/0/acceleration").
void list_datasets(const H5File& f, const std::string& group, const std::string& prefix, std::vector<std::string>& out) {
  for (const std::string& m : f.members(group)) {
    const std::string path = group + "/" + m;
    if (f.is_group(path))
      list_datasets(f, path, prefix + m + "/", out);
    else
      out.push_back(prefix + m);
  }
}


std::string number(double v) {
  if (!std::isfinite(v)) return "nan";
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string short_number(double v) {
  if (!std::isfinite(v)) return "-";
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

std::string gear_label(const dg::GearAverage& a) {
  return a.planet >= 0 ? a.gear + " " + std::to_string(a.planet) : a.gear;
}

} // namespace

std::vector<SnapshotSignals> read_wear_snapshots(const std::filesystem::path& path, model::SimulationConfig& config,
                                                 const std::string& option) {
  {
    // An HDF5 file starts with its 8-byte signature (planetwear writes no user block).
    std::ifstream in(path, std::ios::binary);
    if (!in) throw IoError("cannot open '" + path.string() + "'");
    char sig[8] = {};
    in.read(sig, sizeof sig);
    require(in.gcount() == 8 && std::string(sig, 8) == std::string("\x89HDF\r\n\x1a\n", 8), option, "'",
            path.string(), "' is not an HDF5 file: give the output of `planetwear simulate --mesh-cycles N`");
  }
  const H5File f = H5File::open(path);
  require(f.exists("/config/toml"), option, "'", path.string(), "' has no /config/toml: not a planetwear simulate file");
  config = parse_config(f.read_string("/config/toml"), path.string() + ":/config/toml");
  require(f.exists("/wear/snapshots") && f.is_group("/wear/snapshots"), option, "'", path.string(),
          "' has no /wear/snapshots: run `planetwear simulate --mesh-cycles N --set "
          "wear.snapshot_record_mesh_cycles=M ...` (docs/indicators.md)");
  const double omega_c = model::carrier_speed(config.stage, config.operating.input_speed_rpm * 2 * std::numbers::pi / 60);
  std::vector<SnapshotSignals> out;
  for (const std::string& k : f.members("/wear/snapshots")) {
    const std::string g = "/wear/snapshots/" + k;
    SnapshotSignals s;
    s.mesh_cycles = f.read_double_attribute(g, "mesh_cycles");
    s.time_s = f.read_doubles(g + "/time_history/time");
    std::vector<std::string> names;
    list_datasets(f, g + "/time_history", "", names);
    for (const std::string& n : names) {
      SnapshotChannel c;
      if (n == "carrier/angle") {
        s.carrier_angle_rad = f.read_doubles(g + "/time_history/" + n);
        s.absolute_angle = true;
      } else if (classify(n, c.quantity, c.planet)) {
        c.name = n;
        const std::string p = g + "/time_history/" + n;
        c.unit = f.has_attribute(p, "unit") ? f.read_string_attribute(p, "unit") : "";
        c.values = f.read_doubles(p);
        s.channels.push_back(std::move(c));
      }
    }
    if (!s.absolute_angle) {
      s.carrier_angle_rad.resize(s.time_s.size());
      for (std::size_t j = 0; j < s.time_s.size(); ++j) s.carrier_angle_rad[j] = omega_c * s.time_s[j];
      // Without the absolute angle no planet position is known: the housing channel cannot be separated.
      std::erase_if(s.channels, [](const SnapshotChannel& c) { return c.quantity == dg::Quantity::HousingAcceleration; });
    }
    require(!s.channels.empty(), option, "'", path.string(), "' snapshot ", k,
            " holds no housing or mesh-line acceleration channel");
    out.push_back(std::move(s));
  }
  require(!out.empty(), option, "'", path.string(), "' has no wear snapshots");
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.mesh_cycles < b.mesh_cycles; });
  return out;
}

std::string indicator_table(const IndicatorReport& r) {
  std::ostringstream o;
  const bool sim = r.kind == "simulation";
  char b[256];
  if (sim) o << "mesh_cycles ";
  std::snprintf(b, sizeof b, "%-28s %-9s %3s %4s %-6s", "channel", "gear", "Z", "revs", "unit");
  o << b;
  for (const auto& f : dg::indicator_fields()) {
    std::snprintf(b, sizeof b, " %11s", f.name == std::string("sideband_level_factor") ? "slf"
                                        : f.name == std::string("energy_ratio")        ? "er"
                                        : f.name == std::string("crest_factor")        ? "crest"
                                        : f.name == std::string("peak_to_peak")        ? "p2p"
                                                                                       : f.name);
    o << b;
  }
  o << "\n";
  for (const IndicatorRecord& rec : r.records) {
    const dg::IndicatorRow& row = rec.row;
    if (sim) {
      std::snprintf(b, sizeof b, "%11.4g ", rec.mesh_cycles);
      o << b;
    }
    std::snprintf(b, sizeof b, "%-28s %-9s %3d %4d %-6s", row.channel.c_str(), gear_label(row.average).c_str(),
                  row.average.teeth, row.average.revolutions, row.unit.c_str());
    o << b;
    for (const auto& f : dg::indicator_fields()) {
      std::snprintf(b, sizeof b, " %11s", short_number(row.values.*(f.member)).c_str());
      o << b;
    }
    o << "\n";
  }
  o << "rms, p2p in the channel's unit; every other indicator dimensionless; '-' = undefined (docs/indicators.md)\n";
  for (const auto& s : r.skipped) o << "not computed: " << s.gear << (s.planet >= 0 ? " " + std::to_string(s.planet) : "")
                                    << ": " << s.reason << "\n";
  return o.str();
}

std::string indicator_json(const IndicatorReport& r) {
  json j;
  j["format"] = "planetwear.indicators";
  j["format_version"] = 1;
  j["software_version"] = r.version;
  j["kind"] = r.kind;
  j["source"] = r.source;
  j["angle_reference"] = r.angle_source;
  j["options"] = {{"samples_per_mesh", r.options.samples_per_mesh},
                  {"shaft_harmonics", r.options.shaft_harmonics},
                  {"planet_window_half_width_rad", r.options.planet_window_half_width_rad},
                  {"min_planet_window_weight", r.options.min_planet_window_weight}};
  json units = json::object();
  for (const auto& f : dg::indicator_fields()) units[f.name] = f.unit;
  j["units"] = units;
  json rows = json::array();
  for (const IndicatorRecord& rec : r.records) {
    const dg::IndicatorRow& row = rec.row;
    json e;
    if (std::isfinite(rec.mesh_cycles)) e["mesh_cycles"] = rec.mesh_cycles;
    e["channel"] = row.channel;
    e["quantity"] = row.quantity;
    e["unit"] = row.unit;
    e["gear"] = row.average.gear;
    e["planet"] = row.average.planet >= 0 ? json(row.average.planet) : json(nullptr);
    e["teeth"] = row.average.teeth;
    e["revolutions"] = row.average.revolutions;
    e["samples_per_mesh"] = row.average.samples_per_mesh;
    e["method"] = row.average.method;
    json v = json::object();
    for (const auto& f : dg::indicator_fields()) {
      const double x = row.values.*(f.member);
      v[f.name] = std::isfinite(x) ? json(x) : json(nullptr);
    }
    e["indicators"] = v;
    rows.push_back(e);
  }
  j["rows"] = rows;
  json sk = json::array();
  for (const auto& s : r.skipped)
    sk.push_back({{"gear", s.gear}, {"planet", s.planet >= 0 ? json(s.planet) : json(nullptr)}, {"reason", s.reason}});
  j["not_computed"] = sk;
  return j.dump(2) + "\n";
}

std::string indicator_csv(const IndicatorReport& r) {
  std::ostringstream o;
  const bool sim = r.kind == "simulation";
  if (sim) o << "mesh_cycles [1],";
  // Indicators in the channel's unit (rms, peak to peak) say "[unit]": the value of the unit column.
  o << "channel,quantity,unit,gear,planet,teeth,revolutions,samples_per_mesh";
  for (const auto& f : dg::indicator_fields()) o << "," << f.name << " [" << (std::string(f.unit) == "signal" ? "unit" : f.unit) << "]";
  o << "\n";
  for (const IndicatorRecord& rec : r.records) {
    const dg::IndicatorRow& row = rec.row;
    if (sim) o << number(rec.mesh_cycles) << ",";
    o << row.channel << "," << row.quantity << "," << row.unit << "," << row.average.gear << ","
      << (row.average.planet >= 0 ? std::to_string(row.average.planet) : "") << "," << row.average.teeth << ","
      << row.average.revolutions << "," << row.average.samples_per_mesh;
    for (const auto& f : dg::indicator_fields()) o << "," << number(row.values.*(f.member));
    o << "\n";
  }
  return o.str();
}

void write_indicator_report(const std::filesystem::path& path, const IndicatorReport& r) {
  const std::string ext = path.extension().string();
  require(ext == ".json" || ext == ".csv", "-o", "'", path.string(),
          "': the output's extension must be .json or .csv (it chooses the format)");
  write_text_atomically(path, ext == ".json" ? indicator_json(r) : indicator_csv(r));
}

} // namespace pw::io
