// write_simulation(): the documented layout (docs/output-format.md) with
// units on every numeric dataset, provenance on the root, and the config.
#include "io/result_writer.hpp"

#include "io/config_toml.hpp"
#include "io/io_error.hpp"

#include "io/config_compare.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <regex>
#include <stdexcept>
#include <string>
#include <vector>

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

/// 3 wear updates; depth = 1e-6 (update + 1) (10 tooth + element + 1) on
/// the sun, so every value is distinct and its position checkable.
model::WearHistory small_wear() {
  model::WearHistory w;
  w.mesh_cycles = {0.0, 1e5, 2e5};
  model::FlankWearHistory sun{"sun", 2, 3, {-2e-3, 0.0, 2e-3}, {}};
  for (int u = 0; u < 3; ++u)
    for (int t = 0; t < 2; ++t)
      for (int e = 0; e < 3; ++e) sun.depth_m.push_back(u == 0 ? 0.0 : 1e-6 * (u + 1) * (10 * t + e + 1));
  model::FlankWearHistory planet{"planet_0/sun_side", 1, 2, {-1e-3, 1e-3}, {0, 0, 1e-7, 3e-7, 2e-7, 5e-7}};
  w.flanks = {sun, planet};
  w.backlash_m = {0.0, 0.0, 1e-6, 5e-7, 2e-6, 1e-6};
  const model::Curve spectrum{"sun_planet/0/deflection", "frequency", "Hz", "amplitude", "m",
                              "amplitude spectrum, Hann window, peak amplitude", {0.0, 5e3}, {1e-7, 2e-8}};
  w.snapshots = {
      {0.0, {0.0, 1e-4}, {{"sun_planet/0/deflection", "m", "mesh deflection", {1e-6, 2e-6}}}, {spectrum}},
      {2e5,
       {0.0, 1e-4, 2e-4},
       {{"sun_planet/0/deflection", "m", "mesh deflection", {3e-6, 4e-6, 5e-6}},
        {"sun/acceleration", "m/s^2", "sun acceleration", {0.1, 0.2, 0.3}}},
       {}}};
  w.stop_reason = "";
  return w;
}

model::SimulationResult result_with_wear() {
  auto r = small_result();
  r.wear = small_wear();
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

TEST(ResultWriter, WearHistoryIsWrittenWithShapesUnitsAndAttributes) {
  test::TempDir dir;
  const auto path = dir / "wear.h5";
  auto result = result_with_wear();
  result.wear.stop_reason = "wear exceeded 0.1 of the tooth thickness on flank 'sun' at 2e5 mesh cycles";
  {
    auto f = H5File::create(path);
    write_simulation(f, test::nondefault_config(), result, small_spectra());
    f.close();
  }
  const auto f = H5File::open(path);
  const auto& w = result.wear;
  EXPECT_EQ(f.read_string_attribute("/wear", "stop_reason"), w.stop_reason);

  EXPECT_EQ(f.read_doubles("/wear/mesh_cycles"), w.mesh_cycles);
  EXPECT_EQ(f.read_string_attribute("/wear/mesh_cycles", "unit"), "1");

  EXPECT_EQ(f.shape("/wear/backlash"), (std::vector<std::size_t>{3, 2}));
  EXPECT_EQ(f.read_doubles("/wear/backlash"), w.backlash_m);
  EXPECT_EQ(f.read_string_attribute("/wear/backlash", "unit"), "m");
  EXPECT_EQ(f.read_string_attribute("/wear/backlash", "columns"), "sun_planet,planet_ring");

  for (const auto& flank : w.flanks) {
    SCOPED_TRACE(flank.name);
    const std::string g = "/wear/" + flank.name;
    const std::vector<std::size_t> shape{3, static_cast<std::size_t>(flank.teeth),
                                         static_cast<std::size_t>(flank.elements)};
    EXPECT_EQ(f.shape(g + "/depth"), shape);
    EXPECT_EQ(f.read_doubles(g + "/depth"), flank.depth_m);
    EXPECT_EQ(f.read_string_attribute(g + "/depth", "unit"), "m");
    EXPECT_EQ(f.read_doubles(g + "/distance_from_pitch_point"), flank.distance_from_pitch_point_m);
    EXPECT_EQ(f.read_string_attribute(g + "/distance_from_pitch_point", "unit"), "m");
    EXPECT_EQ(f.read_string_attribute(g + "/max_depth", "unit"), "m");
    EXPECT_EQ(f.read_int_attribute(g, "teeth"), flank.teeth);
    EXPECT_EQ(f.read_int_attribute(g, "elements"), flank.elements);
  }
  // Sun: largest of update u is tooth 1, element 2: 1e-6 (u + 1) 13.
  EXPECT_EQ(f.read_doubles("/wear/sun/max_depth"), (std::vector<double>{0.0, 1e-6 * 2 * 13, 1e-6 * 3 * 13}));
  EXPECT_EQ(f.read_doubles("/wear/planet_0/sun_side/max_depth"), (std::vector<double>{0.0, 3e-7, 5e-7}));

  EXPECT_EQ(f.members("/wear/snapshots"), (std::vector<std::string>{"0", "1"}));
  for (std::size_t k = 0; k < w.snapshots.size(); ++k) {
    SCOPED_TRACE("snapshot " + std::to_string(k));
    const auto& snapshot = w.snapshots[k];
    const std::string g = "/wear/snapshots/" + std::to_string(k);
    EXPECT_EQ(f.read_double_attribute(g, "mesh_cycles"), snapshot.mesh_cycles);
    EXPECT_EQ(f.read_doubles(g + "/time_history/time"), snapshot.time_s);
    EXPECT_EQ(f.read_string_attribute(g + "/time_history/time", "unit"), "s");
    for (const auto& c : snapshot.channels) {
      EXPECT_EQ(f.read_doubles(g + "/time_history/" + c.name), c.values) << c.name;
      EXPECT_EQ(f.read_string_attribute(g + "/time_history/" + c.name, "unit"), c.unit) << c.name;
      EXPECT_EQ(f.read_string_attribute(g + "/time_history/" + c.name, "description"), c.description) << c.name;
    }
    EXPECT_TRUE(f.is_group(g + "/spectra"));
    for (const auto& c : snapshot.spectra) {
      const std::string sp = g + "/spectra/" + c.name;
      EXPECT_EQ(f.read_doubles(sp + "/frequency"), c.x) << c.name;
      EXPECT_EQ(f.read_doubles(sp + "/amplitude"), c.y) << c.name;
      EXPECT_EQ(f.read_string_attribute(sp + "/frequency", "unit"), "Hz") << c.name;
      EXPECT_EQ(f.read_string_attribute(sp + "/amplitude", "unit"), "m") << c.name;
      EXPECT_EQ(f.read_string_attribute(sp, "unit"), "m") << c.name;
      EXPECT_EQ(f.read_string_attribute(sp, "description"), c.description) << c.name;
    }
  }
  EXPECT_TRUE(f.exists("/wear/snapshots/0/spectra/sun_planet/0/deflection/amplitude"));
  // The rest of the layout is unchanged by wear.
  EXPECT_EQ(f.read_doubles("/time_history/time"), result.time_s);
}

/// Paths of every object (groups and datasets) below `group`.
void collect_objects(const H5File& f, const std::string& group, std::vector<std::string>& out) {
  for (const auto& m : f.members(group)) {
    const std::string path = (group == "/" ? "" : group) + "/" + m;
    out.push_back(path);
    if (f.is_group(path)) collect_objects(f, path, out);
  }
}

// docs/output-format.md, "Conventions": the CF name `units` beside `unit`,
// and time, frequency, curve x, mesh cycles and element positions as the
// dimension scales of the datasets they index (what xarray reads as coordinates).
TEST(ResultWriter, UnitsAndDimensionScalesFollowTheCfConventions) {
  test::TempDir dir;
  const auto path = dir / "cf.h5";
  const auto result = result_with_wear();
  {
    auto f = H5File::create(path);
    write_simulation(f, model::SimulationConfig{}, result, small_spectra());
    f.close();
  }
  const auto f = H5File::open(path);
  std::vector<std::string> objects;
  collect_objects(f, "/", objects);
  std::size_t with_unit = 0;
  for (const auto& p : objects) {
    if (!f.has_attribute(p, "unit")) continue;
    ++with_unit;
    ASSERT_TRUE(f.has_attribute(p, "units")) << p;
    EXPECT_EQ(f.read_string_attribute(p, "units"), f.read_string_attribute(p, "unit")) << p;
  }
  EXPECT_GT(with_unit, result.channels.size()) << "too few objects with a unit: the walk is broken";

  const auto scales = [&](const std::string& p, unsigned dim) { return f.dimension_scales(p, dim); };
  using Paths = std::vector<std::string>;
  EXPECT_TRUE(f.is_dimension_scale("/time_history/time"));
  for (const auto& c : result.channels) EXPECT_EQ(scales("/time_history/" + c.name, 0), Paths{"/time_history/time"});
  const std::string spectrum = "/spectra/sun_planet/0/deflection";
  EXPECT_EQ(scales(spectrum + "/amplitude", 0), Paths{spectrum + "/frequency"});
  const std::string curve = "/curves/sun_planet/single_pair";
  EXPECT_EQ(scales(curve + "/y", 0), Paths{curve + "/x"});

  EXPECT_EQ(scales("/wear/backlash", 0), Paths{"/wear/mesh_cycles"});
  EXPECT_EQ(f.dimension_label("/wear/backlash", 1), "mesh");
  for (const auto& flank : result.wear.flanks) {
    const std::string g = "/wear/" + flank.name;
    EXPECT_EQ(scales(g + "/depth", 0), Paths{"/wear/mesh_cycles"}) << g;
    EXPECT_EQ(f.dimension_label(g + "/depth", 1), "tooth") << g;
    EXPECT_EQ(scales(g + "/depth", 2), Paths{g + "/distance_from_pitch_point"}) << g;
    EXPECT_EQ(scales(g + "/max_depth", 0), Paths{"/wear/mesh_cycles"}) << g;
  }
  for (std::size_t k = 0; k < result.wear.snapshots.size(); ++k) {
    const std::string g = "/wear/snapshots/" + std::to_string(k);
    for (const auto& c : result.wear.snapshots[k].channels)
      EXPECT_EQ(scales(g + "/time_history/" + c.name, 0), Paths{g + "/time_history/time"}) << c.name;
    for (const auto& c : result.wear.snapshots[k].spectra)
      EXPECT_EQ(scales(g + "/spectra/" + c.name + "/amplitude", 0), Paths{g + "/spectra/" + c.name + "/frequency"});
  }
}

TEST(ResultWriter, WearGroupExistsOnlyWithWearUpdates) {
  test::TempDir dir;
  auto f = H5File::create(dir / "nowear.h5");
  write_simulation(f, model::SimulationConfig{}, small_result(), {});
  EXPECT_FALSE(f.exists("/wear"));
}

TEST(ResultWriter, LargeDatasetsAreCompressedOnlyWhenAskedAndExactEitherWay) {
  test::TempDir dir;
  auto r = small_result();
  r.wear.mesh_cycles = {0.0, 1.0, 2.0, 3.0};
  r.wear.backlash_m.assign(8, 0.0);
  model::FlankWearHistory ring{"ring", 81, 64, std::vector<double>(64, 0.0), std::vector<double>(4 * 81 * 64)};
  for (std::size_t n = 0; n < ring.depth_m.size(); ++n) ring.depth_m[n] = 1e-9 * static_cast<double>(n % 640);
  r.wear.flanks = {ring};
  const std::size_t raw_bytes = 4 * 81 * 64 * sizeof(double);
  for (const int level : {0, 4}) {
    const auto path = dir / ("ring" + std::to_string(level) + ".h5");
    {
      auto f = H5File::create(path);
      write_simulation(f, {}, r, {}, {.compression_level = level});
      f.close();
    }
    EXPECT_EQ(H5File::open(path).read_doubles("/wear/ring/depth"), ring.depth_m) << "level " << level;
    if (level == 0)
      EXPECT_GT(std::filesystem::file_size(path), raw_bytes) << "level 0 stores the depths as they are";
    else
      EXPECT_LT(std::filesystem::file_size(path), raw_bytes) << "depth not compressed at level " << level;
  }
}

TEST(ResultWriter, CompressionLevelOutsideZeroToNineIsRejectedBeforeAnythingIsWritten) {
  test::TempDir dir;
  for (const int level : {-1, 10}) {
    auto f = H5File::create(dir / "level.h5");
    const auto e = thrown<std::invalid_argument>(
        [&] { write_simulation(f, {}, small_result(), {}, {.compression_level = level}); });
    ASSERT_TRUE(e) << "level " << level;
    EXPECT_TRUE(contains(e->what(), "compression level must be in [0, 9]"));
    EXPECT_FALSE(f.exists("/time_history"));
    f.close();
    std::filesystem::remove(dir / "level.h5");
  }
}

TEST(ResultWriter, InconsistentWearHistoryIsRejectedBeforeAnythingIsWritten) {
  test::TempDir dir;
  auto f = H5File::create(dir / "badwear.h5");
  const auto rejected = [&](const std::function<void(model::WearHistory&)>& edit, const std::string& part) {
    auto r = result_with_wear();
    edit(r.wear);
    const auto e = thrown<std::invalid_argument>([&] { write_simulation(f, {}, r, {}); });
    if (!e) return ::testing::AssertionFailure() << "accepted; expected an error mentioning " << part;
    return contains(e->what(), part);
  };
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[0].depth_m.pop_back(); },
                       "wear flank 'sun' has 17 depths, expected 3 updates x 2 teeth x 3 elements = 18"));
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[1].distance_from_pitch_point_m.push_back(0); }, "planet_0/sun_side"));
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[0].teeth = 0; }, "wear flank 'sun'"));
  EXPECT_TRUE(rejected([](auto& w) { w.backlash_m.pop_back(); }, "backlash"));
  EXPECT_TRUE(rejected([](auto& w) { w.mesh_cycles.push_back(3e5); }, "expected 4 updates"));
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[1].name = "sun"; }, "used twice"));
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[1].name = "snapshots/0"; }, "collides"));
  EXPECT_TRUE(rejected([](auto& w) { w.flanks[1].name = "../x"; }, "wear flank name"));
  EXPECT_TRUE(rejected([](auto& w) { w.snapshots[1].channels[1].values.pop_back(); },
                       "wear snapshot 1: channel 'sun/acceleration'"));
  EXPECT_TRUE(rejected([](auto& w) { w.snapshots[0].channels[0].name = "time"; }, "wear snapshot 0"));
  EXPECT_TRUE(rejected([](auto& w) { w.snapshots[0].spectra[0].y.pop_back(); }, "wear snapshot 0: spectrum"));
  EXPECT_TRUE(rejected([](auto& w) { w.snapshots[0].spectra[0].name = ""; }, "wear snapshot 0: spectrum"));
  EXPECT_TRUE(rejected([](auto& w) { w.mesh_cycles.clear(); }, "no updates"));
  EXPECT_FALSE(f.exists("/config")) << "partial layout written";
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

/// A python3 that imports h5py and numpy, or "".
std::string python_with_h5py() {
  for (const std::string candidate : {"python3", "/usr/bin/python3"})
    if (std::system((candidate + " -c 'import h5py, numpy' >/dev/null 2>&1").c_str()) == 0) return candidate;
  return "";
}

// The promise of docs/output-format.md: h5py reads a channel by its path and
// gets the unit as a str. Skipped where python3 + h5py are not installed.
TEST(ResultWriter, PythonH5pyReadsChannelsByPathWithUnits) {
  const std::string python = python_with_h5py();
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

// docs/output-format.md, "Wear": the h5py recipe reshapes nothing (depth is
// stored 3-D), indexes the last update and finds the snapshots' time bases.
TEST(ResultWriter, PythonH5pyReadsTheWearLayout) {
  const std::string python = python_with_h5py();
  if (python.empty()) GTEST_SKIP() << "no python3 with h5py";
  test::TempDir dir;
  const auto path = dir / "wear-py.h5";
  {
    auto f = H5File::create(path);
    write_simulation(f, model::SimulationConfig{}, result_with_wear(), small_spectra());
    f.close();
  }
  const std::string script =
      "import h5py, sys\n"
      "import numpy as np\n"
      "f = h5py.File(sys.argv[1], 'r')\n"
      "w = f['wear']\n"
      "assert w.attrs['stop_reason'] == '', repr(w.attrs['stop_reason'])\n"
      "assert list(w['mesh_cycles'][:]) == [0.0, 1e5, 2e5]\n"
      "b = w['backlash']\n"
      "assert b.shape == (3, 2) and b.attrs['columns'].split(',') == ['sun_planet', 'planet_ring']\n"
      "assert b[2, 1] == 1e-6, b[:]\n"
      "sun = w['sun']\n"
      "assert sun.attrs['teeth'] == 2 and sun.attrs['elements'] == 3\n"
      "d = sun['depth']\n"
      "assert d.shape == (3, 2, 3) and d.attrs['unit'] == 'm', (d.shape, d.attrs['unit'])\n"
      "assert d[2, 1, 0] == 1e-6 * 3 * 11, d[2, 1, 0]\n"
      "assert np.array_equal(sun['max_depth'][:], d[:].max(axis=(1, 2)))\n"
      "x = sun['distance_from_pitch_point'][:]\n"
      "assert x.shape == (3,) and x[0] < 0 < x[2]\n"
      "assert w['planet_0/sun_side/depth'].shape == (3, 1, 2)\n"
      "s = w['snapshots']\n"
      "last = max(s.values(), key=lambda g: g.attrs['mesh_cycles'])\n"
      "assert last.attrs['mesh_cycles'] == 2e5\n"
      "th = last['time_history']\n"
      "assert list(th['sun/acceleration'][:]) == [0.1, 0.2, 0.3]\n"
      "assert th['sun/acceleration'].attrs['unit'] == 'm/s^2'\n"
      "assert len(th['time'][:]) == 3 and th['time'].attrs['unit'] == 's'\n";
  test::write_text(dir / "check_wear.py", script);
  const std::string command = python + " " + (dir / "check_wear.py").string() + " " + path.string();
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
}

} // namespace
} // namespace pw::io
