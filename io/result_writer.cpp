#include "io/result_writer.hpp"

#include "io/config_toml.hpp"

#include <array>
#include <chrono>
#include <ctime>
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
                      const std::vector<SpectrumRecord>& spectra) {
  // Check the whole result before writing anything.
  for (const auto& c : result.channels) {
    check_name(c.name, "channel");
    if (c.name == "time") throw std::invalid_argument("channel name 'time' is reserved for /time_history/time");
    if (c.values.size() != result.time_s.size())
      throw std::invalid_argument("channel '" + c.name + "' has " + std::to_string(c.values.size()) +
                                  " samples but time_s has " + std::to_string(result.time_s.size()));
  }
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
  large.compress = true;
  file.create_group("/time_history");
  file.set_attribute("/time_history", "time_step_s", result.time_step_s);
  file.set_attribute("/time_history", "description", "sampled channels, all on the time base ./time");
  file.write("/time_history/time", result.time_s, large);
  file.set_attribute("/time_history/time", "unit", "s");
  file.set_attribute("/time_history/time", "description", "sample time");
  for (const auto& c : result.channels) {
    const std::string path = "/time_history/" + c.name;
    file.write(path, c.values, large);
    file.set_attribute(path, "unit", c.unit);
    file.set_attribute(path, "description", c.description);
  }

  file.create_group("/scalars");
  for (const auto& s : result.scalars) {
    const std::string path = "/scalars/" + s.name;
    file.write_scalar(path, s.value);
    file.set_attribute(path, "unit", s.unit);
    file.set_attribute(path, "description", s.description);
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
    file.set_attribute(group + "/x", "unit", c.x_unit);
    file.set_attribute(group + "/x", "description", c.x_name);
    file.set_attribute(group + "/y", "unit", c.y_unit);
    file.set_attribute(group + "/y", "description", c.y_name);
  }

  file.create_group("/spectra");
  for (const auto& s : spectra) {
    const std::string group = "/spectra/" + s.name;
    file.write(group + "/frequency", s.frequency_Hz, large);
    file.write(group + "/amplitude", s.amplitude, large);
    file.set_attribute(group, "unit", s.unit);
    file.set_attribute(group, "window", s.window);
    file.set_attribute(group, "scaling", s.scaling);
    file.set_attribute(group + "/frequency", "unit", "Hz");
    file.set_attribute(group + "/frequency", "description", "frequency of the bin");
    file.set_attribute(group + "/amplitude", "unit", s.unit);
    file.set_attribute(group + "/amplitude", "description", s.scaling);
  }
  file.flush();
}

} // namespace pw::io
