// write_simulation(): the documented layout (docs/output-format.md) with
// units on every numeric dataset, provenance on the root, and the config.
#include "io/result_writer.hpp"

#include "io/config_toml.hpp"
#include "io/io_error.hpp"

#include "io/config_compare.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <regex>
#include <stdexcept>

namespace pw::io {
namespace {

using pw::test::contains;
using pw::test::thrown;

model::SimulationResult small_result() {
  model::SimulationResult r;
  r.time_step_s = 1e-4;
  r.time_s = {0.0, 1e-4, 2e-4, 3e-4};
  r.channels = {
      {"sun_planet/0/deflection", "m", "mesh deflection along the LOA", {1e-6, 2e-6, 3e-6, 4e-6}},
      {"sun_planet/1/deflection", "m", "mesh deflection along the LOA", {5e-6, 6e-6, 7e-6, 8e-6}},
      {"sun/acceleration", "m/s^2", "sun acceleration", {0.1, -0.2, 0.3, -0.4}},
  };
  r.scalars = {{"mesh_frequency", "Hz", "mesh frequency f_m", 27.794}};
  r.curves = {{"sun_planet/single_pair", "roll", "m", "stiffness", "N/m", "single pair mesh stiffness",
               {0.0, 1e-3, 2e-3}, {1e8, 2e8, 1.5e8}}};
  return r;
}

std::vector<SpectrumRecord> small_spectra() {
  return {{"sun_planet/0/deflection", "m", "hann", "peak amplitude", {0.0, 10.0, 20.0}, {1e-7, 2e-7, 3e-8}}};
}

TEST(ResultWriter, LayoutHasTheDocumentedPathsValuesAndUnits) {
  test::TempDir dir;
  const auto path = dir / "run.h5";
  const auto config = test::nondefault_config();
  const auto result = small_result();
  {
    auto f = H5File::create(path);
    write_simulation(f, config, result, small_spectra());
    f.close();
  }
  const auto f = H5File::open(path);

  // Provenance on the root.
  EXPECT_EQ(f.read_string_attribute("/", "units_convention"), "SI");
  EXPECT_EQ(f.read_string_attribute("/", "format"), kOutputFormat);
  EXPECT_EQ(f.read_int_attribute("/", "format_version"), kOutputFormatVersion);
  EXPECT_EQ(f.read_string_attribute("/", "software_version"), software_version());
  EXPECT_FALSE(software_version().empty());
  EXPECT_EQ(f.read_string_attribute("/", "build_flags"), build_flags());
  EXPECT_TRUE(std::regex_match(f.read_string_attribute("/", "created_utc"),
                               std::regex(R"(\d{4}-\d{2}-\d{2}T\d{2}:\d{2}:\d{2}Z)")));

  // The stored configuration is the resolved one and reproduces the run.
  test::expect_config_eq(parse_config(f.read_string("/config/toml"), "stored"), config);

  // Time histories.
  EXPECT_EQ(f.read_doubles("/time_history/time"), result.time_s);
  EXPECT_EQ(f.read_string_attribute("/time_history/time", "unit"), "s");
  EXPECT_EQ(f.read_double_attribute("/time_history", "time_step_s"), 1e-4);
  for (const auto& c : result.channels) {
    SCOPED_TRACE(c.name);
    const std::string p = "/time_history/" + c.name;
    EXPECT_EQ(f.read_doubles(p), c.values);
    EXPECT_EQ(f.read_string_attribute(p, "unit"), c.unit);
    EXPECT_EQ(f.read_string_attribute(p, "description"), c.description);
  }
  EXPECT_EQ(f.members("/time_history/sun_planet"), (std::vector<std::string>{"0", "1"}));

  // Scalars: 0-d with unit.
  EXPECT_TRUE(f.shape("/scalars/mesh_frequency").empty());
  EXPECT_EQ(f.read_scalar("/scalars/mesh_frequency"), 27.794);
  EXPECT_EQ(f.read_string_attribute("/scalars/mesh_frequency", "unit"), "Hz");

  // Curves.
  const std::string curve = "/curves/sun_planet/single_pair";
  EXPECT_EQ(f.read_doubles(curve + "/x"), result.curves[0].x);
  EXPECT_EQ(f.read_doubles(curve + "/y"), result.curves[0].y);
  EXPECT_EQ(f.read_string_attribute(curve, "x_name"), "roll");
  EXPECT_EQ(f.read_string_attribute(curve, "x_unit"), "m");
  EXPECT_EQ(f.read_string_attribute(curve, "y_name"), "stiffness");
  EXPECT_EQ(f.read_string_attribute(curve, "y_unit"), "N/m");
  EXPECT_EQ(f.read_string_attribute(curve + "/y", "unit"), "N/m");

  // Spectra.
  const std::string spectrum = "/spectra/sun_planet/0/deflection";
  EXPECT_EQ(f.read_doubles(spectrum + "/frequency"), (std::vector<double>{0.0, 10.0, 20.0}));
  EXPECT_EQ(f.read_string_attribute(spectrum + "/frequency", "unit"), "Hz");
  EXPECT_EQ(f.read_doubles(spectrum + "/amplitude"), (std::vector<double>{1e-7, 2e-7, 3e-8}));
  EXPECT_EQ(f.read_string_attribute(spectrum + "/amplitude", "unit"), "m");
  EXPECT_EQ(f.read_string_attribute(spectrum, "window"), "hann");
  EXPECT_EQ(f.read_string_attribute(spectrum, "scaling"), "peak amplitude");
}

TEST(ResultWriter, EmptyResultStillHasEveryTopLevelGroup) {
  test::TempDir dir;
  auto f = H5File::create(dir / "empty.h5");
  write_simulation(f, model::SimulationConfig{}, model::SimulationResult{}, {});
  for (const char* group : {"/config", "/time_history", "/scalars", "/curves", "/spectra"})
    EXPECT_TRUE(f.is_group(group)) << group;
  EXPECT_TRUE(f.read_doubles("/time_history/time").empty());
}

TEST(ResultWriter, InconsistentResultIsRejectedBeforeAnythingIsWritten) {
  test::TempDir dir;
  auto f = H5File::create(dir / "bad.h5");
  auto r = small_result();
  r.channels[1].values.pop_back();
  auto e = thrown<std::invalid_argument>([&] { write_simulation(f, {}, r, {}); });
  ASSERT_TRUE(e) << "short channel accepted";
  EXPECT_TRUE(contains(e->what(), "sun_planet/1/deflection"));
  EXPECT_FALSE(f.exists("/config")) << "partial layout written";

  for (const std::string bad : {"/abs", "a//b", "a/../b", "trailing/", "time"}) {
    auto named = small_result();
    named.channels[0].name = bad;
    EXPECT_TRUE(thrown<std::invalid_argument>([&] { write_simulation(f, {}, named, {}); })) << bad;
  }
  auto spectra = small_spectra();
  spectra[0].amplitude.pop_back();
  EXPECT_TRUE(thrown<std::invalid_argument>([&] { write_simulation(f, {}, small_result(), spectra); }));
  EXPECT_FALSE(f.exists("/config"));
}

TEST(ResultWriter, DuplicateChannelNamesAreAnIoError) {
  test::TempDir dir;
  auto f = H5File::create(dir / "dup.h5");
  auto r = small_result();
  r.channels[1].name = r.channels[0].name;
  const auto e = thrown<IoError>([&] { write_simulation(f, {}, r, {}); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "/time_history/sun_planet/0/deflection"));
}

// The promise of docs/output-format.md: h5py reads a channel by its path and
// gets the unit as a str. Skipped where python3 + h5py are not installed.
TEST(ResultWriter, PythonH5pyReadsChannelsByPathWithUnits) {
  std::string python;
  for (const std::string candidate : {"python3", "/usr/bin/python3"}) {
    if (std::system((candidate + " -c 'import h5py' >/dev/null 2>&1").c_str()) == 0) {
      python = candidate;
      break;
    }
  }
  if (python.empty()) GTEST_SKIP() << "no python3 with h5py";
  test::TempDir dir;
  const auto path = dir / "py.h5";
  {
    auto f = H5File::create(path);
    write_simulation(f, model::SimulationConfig{}, small_result(), small_spectra());
    f.close();
  }
  const std::string script =
      "import h5py, sys\n"
      "f = h5py.File(sys.argv[1], 'r')\n"
      "d = f['time_history/sun_planet/0/deflection']\n"
      "assert list(d[:]) == [1e-6, 2e-6, 3e-6, 4e-6], d[:]\n"
      "assert d.attrs['unit'] == 'm', repr(d.attrs['unit'])\n"
      "assert f.attrs['units_convention'] == 'SI'\n"
      "assert float(f['scalars/mesh_frequency'][()]) == 27.794\n"
      "assert 'input_speed_rpm' in f['config/toml'].asstr()[()]\n";
  test::write_text(dir / "check.py", script);
  const std::string command = python + " " + (dir / "check.py").string() + " " + path.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

} // namespace
} // namespace pw::io
