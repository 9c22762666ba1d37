#include "io/result_writer.hpp"

#include "io/config_toml.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <stdexcept>

#ifndef PLANETWEAR_VERSION
#define PLANETWEAR_VERSION "unknown"
#endif
#ifndef PLANETWEAR_BUILD_FLAGS
#define PLANETWEAR_BUILD_FLAGS "unknown"
#endif

namespace pw::io {
namespace {

/// A relative '/'-path with no empty, "." or ".." component.
void check_name(const std::string& name, std::string_view what) {
  bool ok = !name.empty() && name.front() != '/' && name.back() != '/';
  std::size_t start = 0;
  while (ok && start <= name.size()) {
    const std::size_t slash = std::min(name.find('/', start), name.size());
    const std::string_view part = std::string_view(name).substr(start, slash - start);
    ok = !part.empty() && part != "." && part != "..";
    start = slash + 1;
  }
  if (!ok)
    throw std::invalid_argument(std::string(what) + " name '" + name +
                                "' must be a relative path of non-empty components other than '.' and '..'");
}

/// Names directly below /wear that flank names may not take.
constexpr std::array<std::string_view, 3> kWearReserved{"mesh_cycles", "backlash", "snapshots"};

void check_channels(const std::vector<model::Channel>& channels, std::size_t samples, std::string_view where) {
  for (const auto& c : channels) {
    check_name(c.name, std::string(where) + "channel");
    if (c.name == "time")
      throw std::invalid_argument(std::string(where) + "channel name 'time' is reserved for the time base");
    if (c.values.size() != samples)
      throw std::invalid_argument(std::string(where) + "channel '" + c.name + "' has " +
                                  std::to_string(c.values.size()) + " samples but time_s has " +
                                  std::to_string(samples));
  }
}

/// Sizes and names of a wear history, checked before anything is written.
void check_wear(const model::WearHistory& w) {
  const std::size_t updates = w.mesh_cycles.size();
  if (updates == 0) {
    if (!w.flanks.empty() || !w.backlash_m.empty() || !w.snapshots.empty())
      throw std::invalid_argument("wear history has no updates (mesh_cycles is empty) but " +
                                  std::to_string(w.flanks.size()) + " flanks, " + std::to_string(w.backlash_m.size()) +
                                  " backlash values and " + std::to_string(w.snapshots.size()) + " snapshots");
    return;
  }
  if (w.backlash_m.size() != 2 * updates)
    throw std::invalid_argument("wear backlash has " + std::to_string(w.backlash_m.size()) + " values, expected " +
                                std::to_string(updates) + " updates x 2 meshes = " + std::to_string(2 * updates));
  std::vector<std::string_view> seen;
  for (const auto& flank : w.flanks) {
    check_name(flank.name, "wear flank");
    const std::string_view first = std::string_view(flank.name).substr(0, flank.name.find('/'));
    if (std::find(kWearReserved.begin(), kWearReserved.end(), first) != kWearReserved.end())
      throw std::invalid_argument("wear flank name '" + flank.name + "' collides with /wear/" + std::string(first));
    if (std::find(seen.begin(), seen.end(), flank.name) != seen.end())
      throw std::invalid_argument("wear flank name '" + flank.name + "' is used twice");
    seen.push_back(flank.name);
    const std::string what = "wear flank '" + flank.name + "'";
    if (flank.teeth < 1 || flank.elements < 1)
      throw std::invalid_argument(what + " has " + std::to_string(flank.teeth) + " teeth and " +
                                  std::to_string(flank.elements) + " elements; both must be >= 1");
    const auto teeth = static_cast<std::size_t>(flank.teeth);
    const auto elements = static_cast<std::size_t>(flank.elements);
    if (flank.distance_from_pitch_point_m.size() != elements)
      throw std::invalid_argument(what + " has " + std::to_string(flank.distance_from_pitch_point_m.size()) +
                                  " element positions but " + std::to_string(elements) + " elements");
    if (flank.depth_m.size() != updates * teeth * elements)
      throw std::invalid_argument(what + " has " + std::to_string(flank.depth_m.size()) + " depths, expected " +
                                  std::to_string(updates) + " updates x " + std::to_string(teeth) + " teeth x " +
                                  std::to_string(elements) + " elements = " +
                                  std::to_string(updates * teeth * elements));
  }
  for (std::size_t k = 0; k < w.snapshots.size(); ++k) {
    const std::string where = "wear snapshot " + std::to_string(k) + ": ";
    check_channels(w.snapshots[k].channels, w.snapshots[k].time_s.size(), where);
    for (const auto& c : w.snapshots[k].spectra) {
      check_name(c.name, where + "spectrum");
      if (c.x.size() != c.y.size())
        throw std::invalid_argument(where + "spectrum '" + c.name + "' has " + std::to_string(c.x.size()) +
                                    " frequencies but " + std::to_string(c.y.size()) + " amplitudes");
    }
  }
}

/// Largest depth of each update over all teeth and elements; NaN if any is NaN.
std::vector<double> max_depth_per_update(const model::FlankWearHistory& flank, std::size_t updates) {
  const std::size_t per_update = flank.depth_m.size() / updates;
  std::vector<double> out(updates, -std::numeric_limits<double>::infinity());
  for (std::size_t u = 0; u < updates; ++u) {
    for (std::size_t i = 0; i < per_update; ++i) {
      const double d = flank.depth_m[u * per_update + i];
      if (std::isnan(d)) {
        out[u] = d;
        break;
      }
      out[u] = std::max(out[u], d);
    }
  }
  return out;
}

void write_dataset_attributes(H5File& file, const std::string& path, std::string_view unit,
                              std::string_view description) {
  file.set_units(path, unit);
  file.set_attribute(path, "description", description);
}

/// `<group>/time` and one dataset per channel below `group`, the time made
/// the dimension scale of every channel (docs/output-format.md).
void write_time_history(H5File& file, const std::string& group, const std::vector<double>& time_s,
                        const std::vector<model::Channel>& channels, const DatasetOptions& options) {
  const std::string time = group + "/time";
  file.write(time, time_s, options);
  write_dataset_attributes(file, time, "s", "sample time");
  file.make_dimension_scale(time, "time");
  for (const auto& c : channels) {
    const std::string path = group + "/" + c.name;
    file.write(path, c.values, options);
    write_dataset_attributes(file, path, c.unit, c.description);
    file.attach_dimension_scale(path, time, 0);
  }
}

/// Makes `<group>/frequency` the dimension scale of `<group>/amplitude`.
void attach_frequency_scale(H5File& file, const std::string& spectrum_group) {
  file.make_dimension_scale(spectrum_group + "/frequency", "frequency");
  file.attach_dimension_scale(spectrum_group + "/amplitude", spectrum_group + "/frequency", 0);
}

/// /wear (docs/output-format.md, "Wear"); `w` has been checked by check_wear().
void write_wear(H5File& file, const model::WearHistory& w, const DatasetOptions& large) {
  const std::size_t updates = w.mesh_cycles.size();
  file.create_group("/wear");
  file.set_attribute("/wear", "stop_reason", w.stop_reason);
  file.set_attribute("/wear", "description",
                     "Archard wear of every flank family at each wear update (update 0 = unworn); stop_reason is "
                     "empty if wear.mesh_cycles was reached");

  file.write("/wear/mesh_cycles", w.mesh_cycles);
  write_dataset_attributes(file, "/wear/mesh_cycles", "1", "mesh cycles run at each wear update");
  file.make_dimension_scale("/wear/mesh_cycles", "mesh_cycles");

  const std::size_t backlash_dims[] = {updates, 2};
  file.write_nd("/wear/backlash", w.backlash_m, backlash_dims);
  write_dataset_attributes(file, "/wear/backlash", "m",
                           "backlash along the line of action at each update; columns sun_planet, planet_ring");
  file.set_attribute("/wear/backlash", "columns", "sun_planet,planet_ring");
  file.attach_dimension_scale("/wear/backlash", "/wear/mesh_cycles", 0);
  file.set_dimension_label("/wear/backlash", 1, "mesh");

  for (const auto& flank : w.flanks) {
    const std::string group = "/wear/" + flank.name;
    const std::size_t depth_dims[] = {updates, static_cast<std::size_t>(flank.teeth),
                                      static_cast<std::size_t>(flank.elements)};
    file.write_nd(group + "/depth", flank.depth_m, depth_dims, large);
    write_dataset_attributes(file, group + "/depth", "m", "wear depth, shape (updates, teeth, elements)");
    file.write(group + "/distance_from_pitch_point", flank.distance_from_pitch_point_m);
    write_dataset_attributes(file, group + "/distance_from_pitch_point", "m",
                             "signed distance of each element centre from the pitch point along the line of action, "
                             "positive towards this gear's tip");
    file.write(group + "/max_depth", max_depth_per_update(flank, updates));
    write_dataset_attributes(file, group + "/max_depth", "m", "largest wear depth over all teeth and elements");
    file.make_dimension_scale(group + "/distance_from_pitch_point", "distance_from_pitch_point");
    file.attach_dimension_scale(group + "/depth", "/wear/mesh_cycles", 0);
    file.set_dimension_label(group + "/depth", 1, "tooth");
    file.attach_dimension_scale(group + "/depth", group + "/distance_from_pitch_point", 2);
    file.attach_dimension_scale(group + "/max_depth", "/wear/mesh_cycles", 0);
    file.set_attribute(group, "teeth", std::int64_t{flank.teeth});
    file.set_attribute(group, "elements", std::int64_t{flank.elements});
  }

  file.create_group("/wear/snapshots");
  for (std::size_t k = 0; k < w.snapshots.size(); ++k) {
    const model::WearSnapshot& snapshot = w.snapshots[k];
    const std::string group = "/wear/snapshots/" + std::to_string(k);
    file.create_group(group);
    file.set_attribute(group, "mesh_cycles", snapshot.mesh_cycles);
    file.set_attribute(group, "description", "dynamic state at the wear update nearest to mesh_cycles");
    write_time_history(file, group + "/time_history", snapshot.time_s, snapshot.channels, large);
    // As /spectra, with the window and scaling stated in the description.
    file.create_group(group + "/spectra");
    for (const auto& c : snapshot.spectra) {
      const std::string spectrum = group + "/spectra/" + c.name;
      file.write(spectrum + "/frequency", c.x, large);
      file.write(spectrum + "/amplitude", c.y, large);
      file.set_units(spectrum, c.y_unit);
      file.set_attribute(spectrum, "description", c.description);
      write_dataset_attributes(file, spectrum + "/frequency", c.x_unit, c.x_name);
      write_dataset_attributes(file, spectrum + "/amplitude", c.y_unit, c.y_name);
      attach_frequency_scale(file, spectrum);
    }
  }
}

std::string utc_now() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  std::array<char, 32> buf{};
  const std::size_t n = std::strftime(buf.data(), buf.size(), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return std::string(buf.data(), n);
}

} // namespace

std::string_view software_version() { return PLANETWEAR_VERSION; }
std::string_view build_flags() { return PLANETWEAR_BUILD_FLAGS; }

void write_simulation(H5File& file, const model::SimulationConfig& config, const model::SimulationResult& result,
                      const std::vector<SpectrumRecord>& spectra, const WriteOptions& options) {
  // Check the whole result before writing anything.
  if (options.compression_level < 0 || options.compression_level > 9)
    throw std::invalid_argument("compression level must be in [0, 9] (0 = none), got " +
                                std::to_string(options.compression_level));
  check_channels(result.channels, result.time_s.size(), "");
  check_wear(result.wear);
  for (const auto& s : result.scalars) check_name(s.name, "scalar");
  for (const auto& c : result.curves) {
    check_name(c.name, "curve");
    if (c.x.size() != c.y.size())
      throw std::invalid_argument("curve '" + c.name + "' has " + std::to_string(c.x.size()) + " x but " +
                                  std::to_string(c.y.size()) + " y values");
  }
  for (const auto& s : spectra) {
    check_name(s.name, "spectrum");
    if (s.frequency_Hz.size() != s.amplitude.size())
      throw std::invalid_argument("spectrum '" + s.name + "' has " + std::to_string(s.frequency_Hz.size()) +
                                  " frequencies but " + std::to_string(s.amplitude.size()) + " amplitudes");
  }

  // Provenance.
  file.set_attribute("/", "format", kOutputFormat);
  file.set_attribute("/", "format_version", kOutputFormatVersion);
  file.set_attribute("/", "software_version", software_version());
  file.set_attribute("/", "build_flags", build_flags());
  file.set_attribute("/", "created_utc", utc_now());
  file.set_attribute("/", "units_convention", "SI");

  file.write_string("/config/toml", to_toml(config));
  file.set_attribute("/config/toml", "description",
                     "resolved configuration, every key (docs/config.md); re-run with planetwear simulate");

  // Time histories.
  DatasetOptions large;
  large.compress = options.compression_level > 0;
  large.deflate_level = std::max(options.compression_level, 1);
  file.create_group("/time_history");
  file.set_attribute("/time_history", "time_step_s", result.time_step_s);
  file.set_attribute("/time_history", "description", "sampled channels, all on the time base ./time");
  write_time_history(file, "/time_history", result.time_s, result.channels, large);

  file.create_group("/scalars");
  for (const auto& s : result.scalars) {
    const std::string path = "/scalars/" + s.name;
    file.write_scalar(path, s.value);
    write_dataset_attributes(file, path, s.unit, s.description);
  }

  file.create_group("/curves");
  for (const auto& c : result.curves) {
    const std::string group = "/curves/" + c.name;
    file.write(group + "/x", c.x, large);
    file.write(group + "/y", c.y, large);
    file.set_attribute(group, "x_name", c.x_name);
    file.set_attribute(group, "x_unit", c.x_unit);
    file.set_attribute(group, "y_name", c.y_name);
    file.set_attribute(group, "y_unit", c.y_unit);
    file.set_attribute(group, "description", c.description);
    write_dataset_attributes(file, group + "/x", c.x_unit, c.x_name);
    write_dataset_attributes(file, group + "/y", c.y_unit, c.y_name);
    file.make_dimension_scale(group + "/x", "x");
    file.attach_dimension_scale(group + "/y", group + "/x", 0);
  }

  file.create_group("/spectra");
  for (const auto& s : spectra) {
    const std::string group = "/spectra/" + s.name;
    file.write(group + "/frequency", s.frequency_Hz, large);
    file.write(group + "/amplitude", s.amplitude, large);
    file.set_units(group, s.unit);
    file.set_attribute(group, "window", s.window);
    file.set_attribute(group, "scaling", s.scaling);
    write_dataset_attributes(file, group + "/frequency", "Hz", "frequency of the bin");
    write_dataset_attributes(file, group + "/amplitude", s.unit, s.scaling);
    attach_frequency_scale(file, group);
  }

  if (!result.wear.mesh_cycles.empty()) write_wear(file, result.wear, large);
  file.flush();
}

} // namespace pw::io
