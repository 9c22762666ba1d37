// Recording reader (io/recording_reader.hpp): DAQ-style CSV (units in the
// header, delimiters, comments, decimal commas), HDF5, the JSON sidecar, unit
// conversion to SI and every check with its message.
#include "io/recording_reader.hpp"

#include "io/hdf5_file.hpp"
#include "io/io_error.hpp"
#include "test_support.hpp"

#include "core/error.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <functional>
#include <numbers>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

using namespace pw;
using diagnose::Quantity;
using test::contains;
using test::thrown;

namespace {

constexpr double kPi = std::numbers::pi;
// Default gear set (Zs 21, Zr 81) at 3000 rpm: mesh 833.8 Hz, so the reader
// needs >= 6253 Hz; 2 Zs = 42 mesh cycles last 0.05037 s.
constexpr double kRpm = 3000;
constexpr double kFs = 10000;
const double kSunRadS = kRpm * 2 * kPi / 60;
const double kCarrierRadS = kSunRadS * 21.0 / 102.0;

/// One column of a generated CSV: header text and value at time t.
struct Col {
  std::string header;
  std::function<double(double)> value;
};

/// CSV text: header, then rows t = k / fs for k < rows.
std::string make_csv(const std::vector<Col>& cols, std::size_t rows, char delim = ',', double fs = kFs,
                     const std::string& preamble = "", bool decimal_comma = false) {
  std::ostringstream s;
  s.precision(17);
  s << preamble;
  for (std::size_t i = 0; i < cols.size(); ++i) s << (i ? std::string(1, delim) : "") << cols[i].header;
  s << "\n";
  for (std::size_t k = 0; k < rows; ++k) {
    const double t = static_cast<double>(k) / fs;
    for (std::size_t i = 0; i < cols.size(); ++i) {
      std::ostringstream v;
      v.precision(17);
      v << cols[i].value(t);
      std::string text = v.str();
      if (decimal_comma)
        for (char& c : text)
          if (c == '.') c = ',';
      s << (i ? std::string(1, delim) : "") << text;
    }
    s << "\n";
  }
  return s.str();
}

double time_of(double t) { return t; }
double acc(double t) { return 3.0 * std::sin(2 * kPi * 833.8 * t) + 0.5; }

io::RecordingMeta base_meta() {
  io::RecordingMeta m;
  m.input_speed_rpm = kRpm;
  m.input_power_W = 1000;
  m.source = "test";
  return m;
}

io::ColumnSpec column(std::string name, Quantity q, std::string unit = "") {
  io::ColumnSpec c;
  c.name = std::move(name);
  c.quantity = q;
  c.unit = std::move(unit);
  if (q == Quantity::HousingAcceleration) c.sensor_angle_rad = 0.5;
  return c;
}

/// The standard file: time, housing acceleration [g], sun speed [rpm].
std::string standard_csv(std::size_t rows = 3500) {
  return make_csv({{"time [s]", time_of},
                   {"acc_housing [g]", acc},
                   {"w_sun [rpm]", [](double t) { return kRpm + 2 * std::sin(2 * kPi * 50 * t); }}},
                  rows);
}

io::RecordingMeta standard_meta() {
  io::RecordingMeta m = base_meta();
  m.columns = {column("acc_housing", Quantity::HousingAcceleration), column("w_sun", Quantity::SunSpeed)};
  return m;
}

model::SimulationConfig config() { return model::SimulationConfig{}; }

/// The InputError message of reading `text` as a CSV with `meta` (empty if it reads).
std::string csv_error(const std::string& text, const io::RecordingMeta& meta) {
  test::TempDir dir;
  test::write_text(dir / "rec.csv", text);
  const auto e = thrown<InputError>([&] { (void)io::read_recording(dir / "rec.csv", meta, config()); });
  return e ? std::string(e->what()) : std::string();
}

} // namespace

TEST(RecordingReader, ConvertsHeaderUnitsToSI) {
  test::TempDir dir;
  test::write_text(dir / "rec.csv",
                   make_csv({{"time [s]", time_of},
                             {"acc_housing [g]", acc},
                             {"acc sp (mm/s^2)", [](double t) { return 1000 * acc(t); }},
                             // Speeds fluctuate (a constant column is refused as a dead sensor): 0 at t = 0.
                             {"w_sun [rpm]", [](double t) { return kRpm * (1 + 1e-3 * std::sin(2 * kPi * 50 * t)); }},
                             {"w_carrier [Hz]", [](double t) { return kCarrierRadS / (2 * kPi) * (1 + 1e-3 * std::sin(2 * kPi * 50 * t)); }},
                             {"tacho [V]", [](double t) { return std::fmod(t * 50, 1.0) < 0.05 ? 5.0 : 0.0; }}},
                            3500));
  io::RecordingMeta m = base_meta();
  m.columns = {column("acc_housing", Quantity::HousingAcceleration), column("acc sp", Quantity::MeshAccelerationSunPlanet),
               column("w_sun", Quantity::SunSpeed), column("w_carrier", Quantity::CarrierSpeed),
               column("tacho", Quantity::Tacho)};
  m.columns[1].planet = 2;
  const diagnose::Recording r = io::read_recording(dir / "rec.csv", m, config());
  ASSERT_EQ(r.time_s.size(), 3500u);
  EXPECT_NEAR(r.sample_interval_s(), 1e-4, 1e-16);
  EXPECT_EQ(r.operating.input_speed_rpm, kRpm);
  EXPECT_EQ(r.operating.input_power_W, 1000);
  ASSERT_EQ(r.channels.size(), 5u);
  const auto* h = r.find(Quantity::HousingAcceleration);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->unit, "m/s^2");
  EXPECT_EQ(h->sensor_angle_rad, 0.5);
  for (std::size_t k = 0; k < 3500; k += 123) {
    const double t = static_cast<double>(k) / kFs;
    EXPECT_NEAR(h->values[k], 9.80665 * acc(t), 1e-12) << "g -> m/s^2";
    EXPECT_NEAR(r.channels[1].values[k], acc(t), 1e-12) << "mm/s^2 -> m/s^2";
  }
  EXPECT_EQ(r.channels[1].planet, 2);
  EXPECT_NEAR(r.find(Quantity::SunSpeed)->values[0], kSunRadS, 1e-12) << "rpm -> rad/s";
  EXPECT_EQ(r.find(Quantity::SunSpeed)->unit, "rad/s");
  EXPECT_NEAR(r.find(Quantity::CarrierSpeed)->values[7], kCarrierRadS * (1 + 1e-3 * std::sin(2 * kPi * 50 * 7 / kFs)), 1e-12)
      << "Hz (rev/s) -> rad/s";
  EXPECT_EQ(r.find(Quantity::Tacho)->unit, "1");
}

TEST(RecordingReader, UnitConversionTable) {
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::SunSpeed, "rpm"), 2 * kPi / 60);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::SunSpeed, "1/min"), 2 * kPi / 60);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::CarrierSpeed, "deg/s"), kPi / 180);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::CarrierSpeed, "rev/s"), 2 * kPi);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::SunSpeed, "rad/s"), 1.0);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::HousingAcceleration, "g"), 9.80665);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::HousingAcceleration, " G "), 9.80665);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::MeshAccelerationPlanetRing, "m/s²"), 1.0);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::MeshAccelerationPlanetRing, "m s^-2"), 1.0);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::HousingAcceleration, "mm/s^2"), 1e-3);
  EXPECT_DOUBLE_EQ(*io::si_factor(Quantity::Tacho, "V"), 1.0);
  EXPECT_FALSE(io::si_factor(Quantity::HousingAcceleration, "rpm"));
  EXPECT_FALSE(io::si_factor(Quantity::SunSpeed, "g"));
  EXPECT_FALSE(io::si_factor(Quantity::SunSpeed, "m/s"));
  EXPECT_FALSE(io::si_factor(Quantity::Tacho, "rpm"));
}

TEST(RecordingReader, SemicolonDelimiterDecimalCommaCommentsPreambleAndQuotedHeader) {
  // A European DAQ export: BOM, a preamble, comments, quoted names, ';' and
  // decimal commas, CRLF line ends, a blank line and a comment between rows.
  std::string text = make_csv({{"\"Zeit [s]\"", time_of}, {"\"acc; housing (g)\"", acc}}, 3500, ';', kFs,
                              "\xEF\xBB\xBF" "DAQ export v2.1\nSample rate: 10000 Hz\n# channel 2 = housing\n", true);
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  const auto pos = crlf.find("\r\n", crlf.find("\r\n", crlf.find("Zeit")) + 2) + 2;  // after the 1st data row
  crlf.insert(pos, "\r\n% a comment between rows\r\n");
  test::TempDir dir;
  test::write_text(dir / "export.txt", crlf);
  io::RecordingMeta m = base_meta();
  m.time_column = "Zeit";
  m.columns = {column("acc; housing", Quantity::HousingAcceleration)};
  const auto r = io::read_recording(dir / "export.txt", m, config());
  ASSERT_EQ(r.time_s.size(), 3500u);
  EXPECT_NEAR(r.channels[0].values[17], 9.80665 * acc(17 / kFs), 1e-9);
  EXPECT_NEAR(r.time_s.back(), 3499 / kFs, 1e-12);
}

TEST(RecordingReader, TabDelimiterUnitRowAndTrailingDelimiter) {
  // Header, a row of units below it, tab-separated, each row ending in a tab.
  std::ostringstream s;
  s << "t\tacc_housing\t\n[s]\t[m/s^2]\t\n";
  s.precision(17);
  for (int k = 0; k < 3500; ++k) s << k / kFs << "\t" << acc(k / kFs) << "\t\n";
  test::TempDir dir;
  test::write_text(dir / "rec.tsv", s.str());
  io::RecordingMeta m = base_meta();
  m.columns = {column("acc_housing", Quantity::HousingAcceleration)};
  const auto r = io::read_recording(dir / "rec.tsv", m, config());
  EXPECT_NEAR(r.channels[0].values[100], acc(100 / kFs), 1e-12);
}

TEST(RecordingReader, UnitsFromTheSidecarAndContradictions) {
  const std::string text = make_csv({{"time", time_of}, {"acc", acc}}, 3500);
  io::RecordingMeta m = base_meta();
  m.columns = {column("acc", Quantity::HousingAcceleration)};
  EXPECT_TRUE(contains(csv_error(text, m), "column 'acc' (housing_acceleration): no unit"));
  m.columns[0].unit = "g";
  test::TempDir dir;
  test::write_text(dir / "rec.csv", text);
  EXPECT_NEAR(io::read_recording(dir / "rec.csv", m, config()).channels[0].values[3], 9.80665 * acc(3 / kFs), 1e-12);
  // The header says m/s^2, the sidecar g: refuse rather than guess.
  const std::string with_unit = make_csv({{"time", time_of}, {"acc [m/s^2]", acc}}, 3500);
  EXPECT_TRUE(contains(csv_error(with_unit, m), "contradicts the file's 'm/s^2'"));
  // Same unit spelt differently is fine.
  m.columns[0].unit = "m/s2";
  EXPECT_EQ(csv_error(with_unit, m), "");
}

TEST(RecordingReader, RejectsUnitsThatCannotBeRightForTheQuantity) {
  io::RecordingMeta m = standard_meta();
  const std::string text = make_csv({{"time [s]", time_of}, {"acc_housing [rpm]", acc},
                                     {"w_sun [rpm]", [](double) { return kRpm; }}}, 3500);
  const std::string e = csv_error(text, m);
  EXPECT_TRUE(contains(e, "rec.csv"));
  EXPECT_TRUE(contains(e, "column 'acc_housing' (housing_acceleration): unit 'rpm' cannot be right"));
  EXPECT_TRUE(contains(e, "a speed unit"));
  m.columns[1].unit = "m/s^2";
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "column 'w_sun' (sun_speed): unit 'm/s^2' cannot be right"));
  m.columns[1].unit = "furlongs";
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "not a unit planetwear knows"));
  // Time in a speed unit.
  const std::string bad_time = make_csv({{"time [rpm]", time_of}, {"acc_housing [g]", acc}}, 3500);
  io::RecordingMeta one = base_meta();
  one.columns = {column("acc_housing", Quantity::HousingAcceleration)};
  EXPECT_TRUE(contains(csv_error(bad_time, one), "time column 'time [rpm]': unit 'rpm' is not a time unit"));
}

TEST(RecordingReader, TimeInMillisecondsIsConverted) {
  const std::string text = make_csv({{"time [ms]", [](double t) { return 1000 * t; }}, {"acc [g]", acc}}, 3500);
  io::RecordingMeta m = base_meta();
  m.columns = {column("acc", Quantity::HousingAcceleration)};
  test::TempDir dir;
  test::write_text(dir / "rec.csv", text);
  EXPECT_NEAR(io::read_recording(dir / "rec.csv", m, config()).sample_interval_s(), 1e-4, 1e-15);
}

TEST(RecordingReader, ImplausibleSpeedMeansAWrongUnit) {
  // rpm values declared as rad/s: 9.55x the nominal speed.
  const std::string text =
      make_csv({{"time [s]", time_of}, {"w_sun [rad/s]", [](double) { return kRpm; }}, {"acc [g]", acc}}, 3500);
  io::RecordingMeta m = base_meta();
  m.columns = {column("w_sun", Quantity::SunSpeed), column("acc", Quantity::HousingAcceleration)};
  const std::string e = csv_error(text, m);
  EXPECT_TRUE(contains(e, "column 'w_sun' (sun_speed): mean 3000 rad/s"));
  EXPECT_TRUE(contains(e, "Wrong unit?"));
  // An encoder counting backwards: scale -1 fixes it.
  const std::string neg =
      make_csv({{"time [s]", time_of}, {"w_sun [rpm]", [](double t) { return -kRpm - std::sin(2 * kPi * 50 * t); }},
                {"acc [g]", acc}},
               3500);
  EXPECT_TRUE(contains(csv_error(neg, m), "scale = -1"));
  m.columns[0].scale = -1;
  EXPECT_EQ(csv_error(neg, m), "");
}

TEST(RecordingReader, MissingColumnIsNamedWithTheAvailableOnes) {
  io::RecordingMeta m = standard_meta();
  m.columns.push_back(column("acc_ring", Quantity::MeshAccelerationPlanetRing));
  const std::string e = csv_error(standard_csv(), m);
  EXPECT_TRUE(contains(e, "column 'acc_ring' (mesh_acceleration_planet_ring, described in test) is missing"));
  EXPECT_TRUE(contains(e, "'acc_housing [g]'"));
  io::RecordingMeta t = standard_meta();
  t.time_column = "zeit";
  EXPECT_TRUE(contains(csv_error(standard_csv(), t), "time column 'zeit'"));
  const std::string no_time = make_csv({{"x [s]", time_of}, {"acc_housing [g]", acc}}, 3500);
  io::RecordingMeta one = base_meta();
  one.columns = {column("acc_housing", Quantity::HousingAcceleration)};
  EXPECT_TRUE(contains(csv_error(no_time, one), "no time column"));
}

TEST(RecordingReader, NaNAndInfinityNameTheLineAndColumn) {
  std::string text = standard_csv();
  // Data row k is on line k + 2; replace the acceleration of row 100 (line 102).
  auto replace_field = [&](std::string s, int line, int field, const std::string& value) {
    std::size_t pos = 0;
    for (int l = 1; l < line; ++l) pos = s.find('\n', pos) + 1;
    for (int f = 0; f < field; ++f) pos = s.find(',', pos) + 1;
    const std::size_t end = s.find_first_of(",\n", pos);
    return s.replace(pos, end - pos, value);
  };
  EXPECT_TRUE(contains(csv_error(replace_field(text, 102, 1, "nan"), standard_meta()),
                       "line 102, column 'acc_housing [g]': NaN"));
  EXPECT_TRUE(contains(csv_error(replace_field(text, 250, 2, "inf"), standard_meta()),
                       "line 250, column 'w_sun [rpm]': infinite value"));
  EXPECT_TRUE(contains(csv_error(replace_field(text, 300, 1, ""), standard_meta()), "line 300, column 'acc_housing [g]': empty value"));
  EXPECT_TRUE(contains(csv_error(replace_field(text, 301, 1, "1.2.3"), standard_meta()), "'1.2.3' is not a number"));
  EXPECT_TRUE(contains(csv_error(replace_field(text, 400, 2, "3000,5"), standard_meta()), "line 400 has 4 fields"));
}

TEST(RecordingReader, AConstantColumnOfAnyQuantityIsRefusedNamingItAndHowToLeaveItOut) {
  // A speed channel exported as a constant (session 60: the diagnosis then divided by a noise
  // of 0 and reported chi2 of 1e30) is refused like a dead accelerometer.
  const io::RecordingMeta m = standard_meta();
  const std::string flat_speed = make_csv({{"time [s]", time_of}, {"acc_housing [g]", acc}, {"w_sun [rpm]", [](double) {
                                             return kRpm;
                                           }}},
                                           3500);
  const std::string e = csv_error(flat_speed, m);
  EXPECT_TRUE(contains(e, "column 'w_sun")) << e;
  EXPECT_TRUE(contains(e, "carries no signal")) << e;
  EXPECT_TRUE(contains(e, "leave the column out of the sidecar")) << e;
  const std::string dead_acc = make_csv({{"time [s]", time_of}, {"acc_housing [g]", [](double) { return 0.25; }},
                                         {"w_sun [rpm]", [](double t) { return kRpm + 2 * std::sin(2 * kPi * 50 * t); }}},
                                        3500);
  EXPECT_TRUE(contains(csv_error(dead_acc, m), "column 'acc_housing")) << csv_error(dead_acc, m);
  EXPECT_EQ(csv_error(standard_csv(), m), "");  // the same columns with a signal read
}

TEST(RecordingReader, TimeMustIncreaseUniformly) {
  // Row 500 repeated: time does not increase.
  std::string text = standard_csv();
  std::size_t pos = 0;
  for (int l = 1; l < 502; ++l) pos = text.find('\n', pos) + 1;
  const std::size_t end = text.find('\n', pos) + 1;
  const std::string row = text.substr(pos, end - pos);
  EXPECT_TRUE(contains(csv_error(text.substr(0, end) + row + text.substr(end), standard_meta()),
                       "line 503: time 0.05 does not increase"));
  // Row 500 dropped: the samples leave the uniform grid.
  const std::string e = csv_error(text.substr(0, pos) + text.substr(end), standard_meta());
  EXPECT_TRUE(contains(e, "non-uniform time at line"));
  EXPECT_TRUE(contains(e, "Dropped samples?"));
}

TEST(RecordingReader, SampleRateBelowTheAnalysedMeshHarmonicsIsRejected) {
  // 5 kHz < 2.5 x 3 x 833.8 Hz = 6253 Hz.
  const std::string text =
      make_csv({{"time [s]", time_of}, {"acc_housing [g]", acc}, {"w_sun [rpm]", [](double) { return kRpm; }}}, 1750,
               ',', 5000);
  const std::string e = csv_error(text, standard_meta());
  EXPECT_TRUE(contains(e, "sample rate 5000 Hz is too low"));
  EXPECT_TRUE(contains(e, "6253"));
  EXPECT_NEAR(io::required_sample_rate_Hz(config(), kRpm), 2.5 * 3 * 21.0 * 81.0 / 102.0 * kRpm / 60, 1e-9);
}

TEST(RecordingReader, FewerMeshCyclesThanTwoSunPeriodsAreRejected) {
  // 0.045 s = 37.52 mesh cycles at 833.8 Hz < 2 Zs = 42 mesh cycles = 0.05037 s at 3000 rpm.
  const std::string e = csv_error(standard_csv(450), standard_meta());
  EXPECT_TRUE(contains(e, "needs at least 42 mesh cycles")) << e;
  EXPECT_TRUE(contains(e, "holds 37.52")) << e;
  EXPECT_TRUE(contains(e, "0.05037")) << e;
  // 0.25 s (2.57 carrier revolutions, refused before the short-recording analysis) is accepted.
  EXPECT_EQ(csv_error(standard_csv(2500), standard_meta()), "");
}

TEST(RecordingReader, DescriptionErrors) {
  io::RecordingMeta m = standard_meta();
  m.input_speed_rpm.reset();
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "operating.input_speed_rpm is missing"));
  m = standard_meta();
  m.input_torque_Nm = 3;
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "not both"));
  m = standard_meta();
  m.input_power_W.reset();
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "input_power_W (or input_torque_Nm) is missing"));
  m = standard_meta();
  m.columns.clear();
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "no signal column is described"));
  m.columns = {column("tacho", Quantity::Tacho)};
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "no usable signal column"));
  m = standard_meta();
  m.columns[0].sensor_angle_rad.reset();
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "needs its angle"));
  m = standard_meta();
  m.columns.push_back(column("acc_x", Quantity::MeshAccelerationSunPlanet));
  m.columns.back().planet = 3;
  EXPECT_TRUE(contains(csv_error(standard_csv(), m), "planet 3 does not exist (stage.planet_count = 3"));
}

TEST(RecordingReader, TorqueGivesThePower) {
  io::RecordingMeta m = standard_meta();
  m.input_power_W.reset();
  m.input_torque_Nm = 10;
  test::TempDir dir;
  test::write_text(dir / "rec.csv", standard_csv());
  EXPECT_NEAR(io::read_recording(dir / "rec.csv", m, config()).operating.input_power_W, 10 * kSunRadS, 1e-9);
}

TEST(RecordingReader, FilesWithoutHeaderOrDataOrAtAll) {
  const io::RecordingMeta m = standard_meta();
  EXPECT_TRUE(contains(csv_error("", m), "the file is empty"));
  EXPECT_TRUE(contains(csv_error("# only\n# comments\n", m), "no numeric data rows"));
  EXPECT_TRUE(contains(csv_error("0,1,2\n0.1,1,2\n", m), "no header row"));
  const auto e = thrown<io::IoError>([&] { (void)io::read_recording("/nonexistent/rec.csv", m, config()); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "/nonexistent/rec.csv"));
}

TEST(RecordingReader, SampleRateReplacesAMissingTimeColumn) {
  const std::string text = make_csv({{"acc_housing (g)", acc}}, 3500);
  io::RecordingMeta m = base_meta();
  m.sample_rate_Hz = kFs;
  m.columns = {column("acc_housing", Quantity::HousingAcceleration)};
  test::TempDir dir;
  test::write_text(dir / "rec.csv", text);
  const auto r = io::read_recording(dir / "rec.csv", m, config());
  EXPECT_EQ(r.time_s.front(), 0.0);
  EXPECT_NEAR(r.sample_interval_s(), 1e-4, 1e-18);
  EXPECT_NEAR(r.channels[0].values[5], 9.80665 * acc(5 / kFs), 1e-12);
}

TEST(RecordingReader, ReadsALongFileInOnePassFromAPipe) {
  // 200 000 rows through a FIFO: a reader that seeks or reads the file twice
  // cannot work on a pipe.
  test::TempDir dir;
  const auto fifo = dir / "long.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::signal(SIGPIPE, SIG_IGN);
  const std::size_t rows = 200000;
  std::thread writer([&] {
    std::FILE* f = std::fopen(fifo.c_str(), "w");
    if (!f) return;
    std::fprintf(f, "# long recording\ntime [s],acc_housing [m/s^2],w_sun [rpm],acc_sp [g]\n");
    for (std::size_t k = 0; k < rows; ++k) {
      const double t = static_cast<double>(k) / kFs;
      std::fprintf(f, "%.17g,%.17g,%.17g,%.17g\n", t, acc(t), kRpm + std::sin(t), 0.1 * acc(t));
    }
    std::fclose(f);
  });
  io::RecordingMeta m = standard_meta();
  m.columns.push_back(column("acc_sp", Quantity::MeshAccelerationSunPlanet));
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<diagnose::Recording> r;
  std::string error;
  try {
    r = io::read_recording(fifo, m, config());
  } catch (const std::exception& e) {
    error = e.what();
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  // Unblock the writer if the reader never opened the pipe.
  const int fd = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  if (fd >= 0) ::close(fd);
  writer.join();
  ASSERT_TRUE(r) << error;
  ASSERT_EQ(r->time_s.size(), rows);
  EXPECT_NEAR(r->time_s.back(), (rows - 1) / kFs, 1e-9);
  EXPECT_NEAR(r->channels[0].values[123456], acc(123456 / kFs), 1e-12);
  EXPECT_NEAR(r->channels[2].values[199999], 0.1 * 9.80665 * acc(199999 / kFs), 1e-12);
  EXPECT_LT(seconds, 10.0) << "200k rows took " << seconds << " s";
}

TEST(RecordingReader, Hdf5DatasetsWithUnitAttributes) {
  test::TempDir dir;
  const auto path = dir / "rec.h5";
  const std::size_t n = 3500;
  std::vector<double> t(n), a(n), w(n);
  for (std::size_t k = 0; k < n; ++k) {
    t[k] = static_cast<double>(k) / kFs;
    a[k] = acc(t[k]);
    w[k] = kRpm * (1 + 1e-3 * std::sin(2 * kPi * 50 * t[k]));  // a constant column is refused
  }
  {
    auto f = io::H5File::create(path);
    f.write("/time", t);
    f.set_attribute("/time", "unit", "s");
    f.write("/sensors/acc_housing", a);
    f.set_attribute("/sensors/acc_housing", "unit", "g");
    f.write("/w_sun", w);
    f.set_attribute("/w_sun", "unit", "rpm");
    f.close();
  }
  io::RecordingMeta m = base_meta();
  m.columns = {column("/sensors/acc_housing", Quantity::HousingAcceleration), column("w_sun", Quantity::SunSpeed)};
  const auto r = io::read_recording(path, m, config());
  EXPECT_NEAR(r.channels[0].values[9], 9.80665 * a[9], 1e-12);
  EXPECT_NEAR(r.channels[1].values[9], kSunRadS * (1 + 1e-3 * std::sin(2 * kPi * 50 * t[9])), 1e-12);
  // Missing dataset, NaN at a sample.
  m.columns.push_back(column("acc_ring", Quantity::MeshAccelerationPlanetRing, "g"));
  auto e = thrown<InputError>([&] { (void)io::read_recording(path, m, config()); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "column 'acc_ring' (mesh_acceleration_planet_ring"));
  a[77] = std::nan("");
  {
    auto f = io::H5File::create(path);
    f.write("/time", t);
    f.write("/acc", a);
    f.set_attribute("/acc", "unit", "m/s^2");
    f.close();
  }
  m.columns = {column("acc", Quantity::HousingAcceleration)};
  e = thrown<InputError>([&] { (void)io::read_recording(path, m, config()); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "sample 77, column 'acc': NaN"));
}

TEST(RecordingMeta, ParsesTheDocumentedSidecar) {
  const auto m = io::parse_recording_meta(R"({
    "description": "rig run 12",
    "operating": {"input_speed_rpm": 400, "input_power_W": 1000},
    "time_column": "time",
    "columns": {
      "acc_housing": {"quantity": "housing_acceleration", "unit": "m/s^2", "sensor_angle_deg": 30},
      "w_sun": {"quantity": "sun_speed", "unit": "rpm"},
      "a_pr": {"quantity": "mesh_acceleration_planet_ring", "unit": "g", "planet": 1},
      "enc": {"quantity": "carrier_speed", "unit": "rpm", "scale": -1}
    }
  })", "rec.json");
  EXPECT_EQ(*m.input_speed_rpm, 400);
  EXPECT_EQ(*m.input_power_W, 1000);
  EXPECT_FALSE(m.input_torque_Nm);
  EXPECT_EQ(m.time_column, "time");
  ASSERT_EQ(m.columns.size(), 4u);
  EXPECT_EQ(m.columns[0].name, "acc_housing");  // file order kept
  EXPECT_EQ(m.columns[0].quantity, Quantity::HousingAcceleration);
  EXPECT_NEAR(*m.columns[0].sensor_angle_rad, kPi / 6, 1e-15);
  EXPECT_EQ(m.columns[1].unit, "rpm");
  EXPECT_EQ(m.columns[2].planet, 1);
  EXPECT_EQ(m.columns[3].scale, -1);
  EXPECT_EQ(m.source, "rec.json");
}

TEST(RecordingMeta, ErrorsNameTheKey) {
  auto error = [](const std::string& text) {
    const auto e = thrown<InputError>([&] { (void)io::parse_recording_meta(text, "rec.json"); });
    return e ? std::string(e->what()) : std::string();
  };
  EXPECT_TRUE(contains(error("{"), "rec.json: JSON syntax error"));
  EXPECT_TRUE(contains(error("[]"), "expected a JSON object"));
  EXPECT_TRUE(contains(error(R"({"operating": {"speed": 3}})"), "rec.json: operating.speed: unknown key"));
  EXPECT_TRUE(contains(error(R"({"operating": {"input_speed_rpm": "fast"}})"),
                       "operating.input_speed_rpm: expected a number, got string"));
  EXPECT_TRUE(contains(error(R"({"columns": {"a": {"quantity": "acceleration"}}})"),
                       "columns.a.quantity: 'acceleration' is not one of sun_speed"));
  EXPECT_TRUE(contains(error(R"({"columns": {"a": {"unit": "g"}}})"), "columns.a.quantity: missing"));
  EXPECT_TRUE(contains(error(R"({"columns": {"a": {"quantity": "housing_acceleration", "unit": "rpm"}}})"),
                       "columns.a.unit: 'rpm' cannot be right for housing_acceleration"));
  EXPECT_TRUE(contains(error(R"({"columns": {"a": {"quantity": "sun_speed", "planet": -1}}})"), "columns.a.planet"));
  EXPECT_TRUE(contains(error(R"({"colums": {}})"), "colums: unknown key"));
  EXPECT_TRUE(contains(error(R"({"time_unit": "rpm"})"), "time_unit: 'rpm' is not a time unit"));
  const auto e = thrown<io::IoError>([] { (void)io::read_recording_meta("/nonexistent/rec.json"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "/nonexistent/rec.json"));
}

TEST(RecordingMeta, CommandLineColumnsAndMerge) {
  const auto c = io::parse_column_option("acc = housing_acceleration, unit=g, sensor_angle_deg=90");
  EXPECT_EQ(c.name, "acc");
  EXPECT_EQ(c.quantity, Quantity::HousingAcceleration);
  EXPECT_EQ(c.unit, "g");
  EXPECT_NEAR(*c.sensor_angle_rad, kPi / 2, 1e-15);
  const auto p = io::parse_column_option("a_sp=mesh_acceleration_sun_planet,planet=2,scale=0.5");
  EXPECT_EQ(p.planet, 2);
  EXPECT_EQ(p.scale, 0.5);
  auto error = [](const std::string& text) {
    const auto e = thrown<InputError>([&] { (void)io::parse_column_option(text); });
    return e ? std::string(e->what()) : std::string();
  };
  EXPECT_TRUE(contains(error("acc"), "--column: 'acc': expected NAME=QUANTITY"));
  EXPECT_TRUE(contains(error("acc=speed"), "quantity 'speed' is not one of"));
  EXPECT_TRUE(contains(error("acc=housing_acceleration,unit=rpm"), "unit 'rpm' cannot be right"));
  EXPECT_TRUE(contains(error("acc=housing_acceleration,angle=3"), "unknown key 'angle'"));
  EXPECT_TRUE(contains(error("a=sun_speed,planet=1.5"), "planet must be an integer"));

  io::RecordingMeta file = io::parse_recording_meta(
      R"({"operating": {"input_speed_rpm": 400, "input_torque_Nm": 20},
          "columns": {"acc": {"quantity": "housing_acceleration", "unit": "m/s^2", "sensor_angle_deg": 0},
                      "w": {"quantity": "sun_speed", "unit": "rpm"}}})",
      "rec.json");
  io::RecordingMeta cli;
  cli.source = "command line";
  cli.input_power_W = 2000;
  cli.columns = {c};
  const auto m = io::merge(file, cli);
  EXPECT_EQ(*m.input_speed_rpm, 400);
  EXPECT_EQ(*m.input_power_W, 2000);
  EXPECT_FALSE(m.input_torque_Nm) << "power on the command line replaces the sidecar's torque";
  ASSERT_EQ(m.columns.size(), 2u);
  EXPECT_EQ(m.columns[0].unit, "g") << "same column: the command line wins";
  EXPECT_EQ(m.columns[1].name, "w");
  EXPECT_EQ(m.source, "rec.json and command line");
}

TEST(RecordingMeta, EncoderLinesOfASpeedColumnBecomeTheModelsEncoderAndConflictsAreNamed) {
  const auto m = io::parse_recording_meta(R"({
    "operating": {"input_speed_rpm": 400, "input_power_W": 1000},
    "columns": {
      "w_sun": {"quantity": "sun_speed", "unit": "rpm", "encoder_lines": 1024},
      "w_c": {"quantity": "carrier_speed", "unit": "rpm", "encoder_lines": 2048}
    }
  })", "rec.json");
  ASSERT_EQ(m.columns.size(), 2u);
  EXPECT_EQ(*m.columns[0].encoder_lines, 1024);
  model::SimulationConfig c;
  io::apply_encoder_lines(m, c);
  EXPECT_EQ(c.sensor.sun_encoder_lines, 1024);
  EXPECT_EQ(c.sensor.carrier_encoder_lines, 2048);
  // The same count in the configuration is no conflict; another one is, naming the key and both.
  io::apply_encoder_lines(m, c);
  c.sensor.sun_encoder_lines = 1000;
  const auto conflict = thrown<InputError>([&] { io::apply_encoder_lines(m, c); });
  ASSERT_TRUE(conflict);
  EXPECT_TRUE(contains(conflict->what(), "sensor.sun_encoder_lines")) << conflict->what();
  EXPECT_TRUE(contains(conflict->what(), "1000")) << conflict->what();
  EXPECT_TRUE(contains(conflict->what(), "1024")) << conflict->what();
  // A column without a count leaves the configuration's.
  model::SimulationConfig d;
  d.sensor.carrier_encoder_lines = 500;
  io::apply_encoder_lines(standard_meta(), d);
  EXPECT_EQ(d.sensor.carrier_encoder_lines, 500);
  EXPECT_EQ(d.sensor.sun_encoder_lines, 0);

  auto error = [](const std::string& text) {
    const auto e = thrown<InputError>([&] { (void)io::parse_recording_meta(text, "rec.json"); });
    return e ? std::string(e->what()) : std::string();
  };
  EXPECT_TRUE(contains(error(R"({"columns": {"w": {"quantity": "sun_speed", "encoder_lines": 0}}})"),
                       "columns.w.encoder_lines: expected an integer in [1, 16777216]"));
  EXPECT_TRUE(contains(error(R"({"columns": {"w": {"quantity": "sun_speed", "encoder_lines": 10.5}}})"),
                       "columns.w.encoder_lines"));
  const auto cli = io::parse_column_option("w=carrier_speed,unit=rpm,encoder_lines=2000");
  EXPECT_EQ(*cli.encoder_lines, 2000);
  const auto bad = thrown<InputError>([] { (void)io::parse_column_option("w=sun_speed,encoder_lines=-3"); });
  ASSERT_TRUE(bad);
  EXPECT_TRUE(contains(bad->what(), "encoder_lines must be an integer in [1, 16777216]"));
  // Only speed columns have encoder lines.
  io::RecordingMeta acc = standard_meta();
  acc.columns[0].encoder_lines = 100;
  EXPECT_TRUE(contains(csv_error(standard_csv(), acc), "encoder_lines applies only to sun_speed and carrier_speed"));
}
