#include "io/calibration_file.hpp"

#include "core/error.hpp"
#include "io/atomic_output.hpp"
#include "io/io_error.hpp"

#include <toml++/toml.h>

#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <sstream>

namespace pw::io {
namespace {

using diagnose::Component;
using diagnose::Quantity;

constexpr Quantity kQuantities[] = {Quantity::SunSpeed, Quantity::CarrierSpeed, Quantity::MeshAccelerationSunPlanet,
                                    Quantity::MeshAccelerationPlanetRing, Quantity::HousingAcceleration};

template <class T>
toml::array to_array(const std::vector<T>& v) {
  toml::array a;
  for (const T& x : v) {
    if constexpr (std::is_same_v<T, double>)
      a.push_back(std::isfinite(x) ? x : std::numeric_limits<double>::quiet_NaN());
    else
      a.push_back(x);
  }
  return a;
}

std::string where(const std::filesystem::path& p, const std::string& key) { return p.string() + ": " + key; }

template <class T>
std::vector<T> read_array(const toml::array* a, const std::filesystem::path& p, const std::string& key) {
  std::vector<T> out;
  if (!a) throw InputError(where(p, key), "must be an array");
  for (const toml::node& x : *a) {
    if constexpr (std::is_same_v<T, double>) {
      const auto v = x.value<double>();
      if (!v) throw InputError(where(p, key), "must hold numbers");
      out.push_back(*v);
    } else {
      const auto v = x.value<std::string>();
      if (!v) throw InputError(where(p, key), "must hold strings");
      out.push_back(*v);
    }
  }
  return out;
}

/// An optional key of the calibration naming one of a form part's values by `name` (the
/// configuration's names: model::mesh_phase_name, model::housing_path_name); `absent` when the file
/// predates it. Any other name is an input error naming the key and every name.
template <class View, class E>
E read_form_part(const View& cal, const char* key, const std::filesystem::path& p,
                 E absent, std::initializer_list<E> others, const char* (*name)(E)) {
  const auto v = cal[key].template value<std::string>();
  if (!v || *v == name(absent)) return absent;
  std::string names = std::string("\"") + name(absent) + "\"";
  std::size_t i = 0;
  for (const E e : others) {
    if (*v == name(e)) return e;
    names += std::string(++i == others.size() ? " or \"" : ", \"") + name(e) + "\"";
  }
  throw InputError(where(p, std::string("calibration.") + key), "must be " + names + ", got '" + *v + "'");
}

double read_number(const toml::table& t, const char* key, const std::filesystem::path& p, const std::string& ctx) {
  const auto v = t[key].value<double>();
  if (!v) throw InputError(where(p, ctx + "." + key), "missing or not a number");
  return *v;
}

Quantity read_quantity(const toml::table& t, const std::filesystem::path& p, const std::string& ctx) {
  const std::string q = t["quantity"].value_or(std::string());
  for (Quantity x : kQuantities)
    if (q == diagnose::to_string(x)) return x;
  throw InputError(where(p, ctx + ".quantity"), "unknown quantity '" + q + "'");
}

/// One [[coverage]] entry: a span lowest_Hz <= highest_Hz > 0 with positive speeds.
diagnose::LineCoverage read_coverage(const toml::table* t, const std::filesystem::path& p, const std::string& ctx) {
  if (!t) throw InputError(where(p, ctx), "must be a table");
  diagnose::LineCoverage l;
  l.quantity = read_quantity(*t, p, ctx);
  l.lowest_Hz = read_number(*t, "lowest_Hz", p, ctx);
  l.lowest_speed_rpm = read_number(*t, "lowest_speed_rpm", p, ctx);
  l.highest_Hz = read_number(*t, "highest_Hz", p, ctx);
  l.highest_speed_rpm = read_number(*t, "highest_speed_rpm", p, ctx);
  l.lines = static_cast<int>((*t)["lines"].value_or(0));
  require(l.lowest_Hz > 0 && l.lowest_Hz <= l.highest_Hz && std::isfinite(l.highest_Hz), where(p, ctx),
          "needs 0 < lowest_Hz <= highest_Hz, got ", l.lowest_Hz, " and ", l.highest_Hz, " Hz");
  require(l.lowest_speed_rpm > 0 && l.highest_speed_rpm > 0, where(p, ctx), "speeds must be > 0 rpm");
  require(l.lines > 0, where(p, ctx + ".lines"), "must be > 0, got ", l.lines);
  return l;
}

/// One [[discrepancy]] entry.
toml::table discrepancy_table(const diagnose::DiscrepancyEstimate& d) {
  return toml::table{{"quantity", std::string(diagnose::to_string(d.quantity))},
                     {"family", std::string(diagnose::to_string(d.family))},
                     {"relative_variance", d.relative_variance},
                     {"relative_variance_se", d.relative_variance_se},
                     {"relative_cells", d.relative_cells},
                     {"absolute_variance", d.absolute_variance},
                     {"absolute_variance_se", d.absolute_variance_se},
                     {"absolute_cells", d.absolute_cells},
                     {"relative_variance_per_recording", to_array(d.relative_variance_per_recording)}};
}

/// One [[coverage]] entry (read_coverage reads it back).
toml::table coverage_table(const diagnose::LineCoverage& l) {
  return toml::table{{"quantity", std::string(diagnose::to_string(l.quantity))},
                     {"lowest_Hz", l.lowest_Hz},
                     {"lowest_speed_rpm", l.lowest_speed_rpm},
                     {"highest_Hz", l.highest_Hz},
                     {"highest_speed_rpm", l.highest_speed_rpm},
                     {"lines", l.lines}};
}

} // namespace

void write_calibration(const diagnose::Calibration& c, const std::filesystem::path& path) {
  toml::table cal;
  cal.insert("alpha", c.alpha);
  cal.insert("recordings", to_array(c.recordings));
  if (!c.sidecars.empty()) cal.insert("sidecars", to_array(c.sidecars));
  cal.insert("speeds_rpm", to_array(c.speeds_rpm));
  cal.insert("verdicts", to_array(c.verdicts));
  cal.insert("rig_elements", to_array(c.rig_elements));
  cal.insert("healthy_fit", std::string(diagnose::to_string(c.healthy_fit)));
  cal.insert("mesh_phase", std::string(model::mesh_phase_name(c.form.mesh_phase)));
  cal.insert("housing_path", std::string(model::housing_path_name(c.form.housing_path)));
  cal.insert("at_bound", to_array(c.at_bound));
  cal.insert("overrides", to_array(c.overrides));
  toml::array disc;
  for (const diagnose::DiscrepancyEstimate& d : c.discrepancy) disc.push_back(discrepancy_table(d));
  toml::array coverage;
  for (const diagnose::LineCoverage& l : c.coverage) coverage.push_back(coverage_table(l));
  toml::array fits;
  for (const diagnose::CalibrationFit& f : c.fits) {
    toml::table t;
    t.insert("nuisance_chi2_held_out", f.nuisance_chi2_held_out);
    t.insert("noise_bound_held_out", f.noise_bound_held_out);
    t.insert("values", to_array(f.values));
    t.insert("at_bound", to_array(f.at_bound));
    fits.push_back(std::move(t));
  }
  toml::table root;
  root.insert("calibration", std::move(cal));
  root.insert("discrepancy", std::move(disc));
  if (!coverage.empty()) root.insert("coverage", std::move(coverage));
  if (!fits.empty()) root.insert("fit", std::move(fits));
  std::ostringstream text;
  text << "# planetwear calibration (docs/diagnose.md section 6a): the calibrated model and its discrepancy budget\n"
       << root << "\n";
  write_text_atomically(path, text.str());
}

diagnose::Calibration read_calibration(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw IoError("cannot open calibration file '" + path.string() + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  toml::table root;
  try {
    root = toml::parse(ss.str(), path.string());
  } catch (const toml::parse_error& e) {
    throw InputError(path.string(), std::string("not valid TOML: ") + std::string(e.description()));
  }
  diagnose::Calibration c;
  const auto cal = root["calibration"];
  if (!cal.as_table()) throw InputError(where(path, "calibration"), "missing [calibration] table");
  c.alpha = cal["alpha"].value_or(0.01);
  require(c.alpha > 0 && c.alpha < 0.5, where(path, "calibration.alpha"), "must be in (0, 0.5), got ", c.alpha);
  c.recordings = read_array<std::string>(cal["recordings"].as_array(), path, "calibration.recordings");
  if (cal["sidecars"]) {  // optional: written since session 25
    c.sidecars = read_array<std::string>(cal["sidecars"].as_array(), path, "calibration.sidecars");
    require(c.sidecars.size() == c.recordings.size(), where(path, "calibration.sidecars"), "has ", c.sidecars.size(),
            " entries for ", c.recordings.size(), " recordings");
  }
  c.speeds_rpm = read_array<double>(cal["speeds_rpm"].as_array(), path, "calibration.speeds_rpm");
  c.verdicts = read_array<std::string>(cal["verdicts"].as_array(), path, "calibration.verdicts");
  c.rig_elements = read_array<std::string>(cal["rig_elements"].as_array(), path, "calibration.rig_elements");
  c.overrides = read_array<std::string>(cal["overrides"].as_array(), path, "calibration.overrides");
  if (const auto h = cal["healthy_fit"].value<std::string>())  // optional: written since session 43
    c.healthy_fit = diagnose::healthy_fit_from_string(*h, where(path, "calibration.healthy_fit"));
  // Optional: mesh_phase written since session 66, housing_path since session 67.
  c.form.mesh_phase = read_form_part(cal, "mesh_phase", path, model::MeshPhase::Rotation,
                                     {model::MeshPhase::NominalTime}, &model::mesh_phase_name);
  c.form.housing_path =
      read_form_part(cal, "housing_path", path, model::HousingPath::PlanetPass,
                     {model::HousingPath::RingTranslation, model::HousingPath::RingBody}, &model::housing_path_name);
  if (cal["at_bound"])  // optional: files written before it existed have none
    c.at_bound = read_array<std::string>(cal["at_bound"].as_array(), path, "calibration.at_bound");
  const toml::array* disc = root["discrepancy"].as_array();
  if (!disc) throw InputError(where(path, "discrepancy"), "missing [[discrepancy]] entries");
  for (std::size_t i = 0; i < disc->size(); ++i) {
    const std::string ctx = "discrepancy[" + std::to_string(i) + "]";
    const toml::table* t = (*disc)[i].as_table();
    if (!t) throw InputError(where(path, ctx), "must be a table");
    diagnose::DiscrepancyEstimate d;
    d.quantity = read_quantity(*t, path, ctx);
    const std::string f = (*t)["family"].value_or(std::string());
    bool fok = false;
    for (Component x : diagnose::kAllComponents)
      if (f == diagnose::to_string(x)) d.family = x, fok = true;
    if (!fok) throw InputError(where(path, ctx + ".family"), "unknown family '" + f + "'");
    d.relative_variance = read_number(*t, "relative_variance", path, ctx);
    d.relative_variance_se = read_number(*t, "relative_variance_se", path, ctx);
    d.absolute_variance = read_number(*t, "absolute_variance", path, ctx);
    d.absolute_variance_se = read_number(*t, "absolute_variance_se", path, ctx);
    require(d.relative_variance_se >= 0 && d.absolute_variance_se >= 0, where(path, ctx),
            "standard errors must be >= 0");
    d.relative_cells = static_cast<int>((*t)["relative_cells"].value_or(0));
    d.absolute_cells = static_cast<int>((*t)["absolute_cells"].value_or(0));
    if ((*t)["relative_variance_per_recording"])
      d.relative_variance_per_recording =
          read_array<double>((*t)["relative_variance_per_recording"].as_array(), path, ctx + ".relative_variance_per_recording");
    c.discrepancy.push_back(std::move(d));
  }
  if (const toml::array* cov = root["coverage"].as_array())  // optional: written since session 74
    for (std::size_t i = 0; i < cov->size(); ++i)
      c.coverage.push_back(read_coverage((*cov)[i].as_table(), path, "coverage[" + std::to_string(i) + "]"));
  if (const toml::array* fits = root["fit"].as_array()) {  // optional: written since session 18
    for (std::size_t i = 0; i < fits->size(); ++i) {
      const std::string ctx = "fit[" + std::to_string(i) + "]";
      const toml::table* t = (*fits)[i].as_table();
      if (!t) throw InputError(where(path, ctx), "must be a table");
      diagnose::CalibrationFit f;
      f.nuisance_chi2_held_out = read_number(*t, "nuisance_chi2_held_out", path, ctx);
      f.noise_bound_held_out = read_number(*t, "noise_bound_held_out", path, ctx);
      f.values = read_array<std::string>((*t)["values"].as_array(), path, ctx + ".values");
      f.at_bound = read_array<std::string>((*t)["at_bound"].as_array(), path, ctx + ".at_bound");
      c.fits.push_back(std::move(f));
    }
  }
  return c;
}

} // namespace pw::io
