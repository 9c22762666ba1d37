// Recording writer (io/recording_writer.hpp): CSV + JSON sidecar that the
// reader takes back unchanged.
#include "io/recording_writer.hpp"

#include "io/io_error.hpp"
#include "io/recording_reader.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

using namespace pw;
using diagnose::Quantity;
using test::contains;

namespace {

constexpr double kPi = std::numbers::pi;

/// 0.4 s at 10 kHz of every quantity, at 3000 rpm (the reader's checks pass).
diagnose::Recording sample_recording() {
  diagnose::Recording r;
  r.operating.input_speed_rpm = 3000;
  r.operating.input_power_W = 1234.5;
  const std::size_t n = 4000;
  const double ws = 3000 * 2 * kPi / 60, wc = ws * 21.0 / 102.0;
  auto channel = [&](std::string name, Quantity q, std::string unit, auto f) {
    diagnose::SignalChannel c;
    c.name = std::move(name);
    c.quantity = q;
    c.unit = std::move(unit);
    for (std::size_t k = 0; k < n; ++k) c.values.push_back(f(0.1 + static_cast<double>(k) * 1e-4));
    return c;
  };
  for (std::size_t k = 0; k < n; ++k) r.time_s.push_back(0.1 + static_cast<double>(k) * 1e-4);
  r.channels.push_back(channel("sun_speed", Quantity::SunSpeed, "rad/s", [&](double t) { return ws + 0.1 * std::sin(t); }));
  r.channels.push_back(channel("carrier_speed", Quantity::CarrierSpeed, "rad/s", [&](double t) { return wc + 0.05 * std::cos(t); }));
  r.channels.push_back(channel("a, sp \"1\"", Quantity::MeshAccelerationSunPlanet, "m/s^2",
                               [](double t) { return 7.0 * std::sin(2 * kPi * 834 * t) + 1.0 / 3; }));
  r.channels.back().planet = 1;
  r.channels.push_back(channel("a_pr", Quantity::MeshAccelerationPlanetRing, "m/s^2",
                               [](double t) { return std::cos(2 * kPi * 834 * t); }));
  r.channels.push_back(channel("housing", Quantity::HousingAcceleration, "m/s^2",
                               [](double t) { return 1e-3 * std::sin(2 * kPi * 834 * t) + 0.1; }));
  r.channels.back().sensor_angle_rad = 30 * kPi / 180;
  r.channels.push_back(channel("tacho", Quantity::Tacho, "1", [](double t) { return std::fmod(t, 0.02) < 0.001 ? 1.0 : 0.0; }));
  return r;
}

} // namespace

TEST(RecordingWriter, RoundTripsThroughTheReader) {
  test::TempDir dir;
  const diagnose::Recording r = sample_recording();
  const auto json = io::write_recording(dir / "rec.csv", r, {"unit test"});
  EXPECT_EQ(json, dir / "rec.json");
  const io::RecordingMeta meta = io::read_recording_meta(json);
  EXPECT_EQ(*meta.input_speed_rpm, 3000);
  EXPECT_EQ(*meta.input_power_W, 1234.5);
  const diagnose::Recording back = io::read_recording(dir / "rec.csv", meta, model::SimulationConfig{});
  ASSERT_EQ(back.time_s.size(), r.time_s.size());
  for (std::size_t k = 0; k < r.time_s.size(); ++k) ASSERT_NEAR(back.time_s[k], r.time_s[k], 1e-15);
  ASSERT_EQ(back.channels.size(), r.channels.size());
  for (std::size_t i = 0; i < r.channels.size(); ++i) {
    SCOPED_TRACE(r.channels[i].name);
    EXPECT_EQ(back.channels[i].name, r.channels[i].name);
    EXPECT_EQ(back.channels[i].quantity, r.channels[i].quantity);
    EXPECT_EQ(back.channels[i].unit, r.channels[i].unit);
    EXPECT_EQ(back.channels[i].planet, r.channels[i].planet);
    EXPECT_NEAR(back.channels[i].sensor_angle_rad, r.channels[i].sensor_angle_rad, 1e-15);
    EXPECT_EQ(back.channels[i].values, r.channels[i].values) << "values must survive bit for bit";
  }
}

TEST(RecordingWriter, SidecarStatesTheOperatingPointAndColumnsOnly) {
  const std::string text = io::recording_meta_json(sample_recording(), {"synthetic"});
  EXPECT_TRUE(contains(text, "\"description\": \"synthetic\""));
  EXPECT_TRUE(contains(text, "\"input_speed_rpm\": 3000.0"));
  EXPECT_TRUE(contains(text, "\"sensor_angle_deg\": 30.0"));
  EXPECT_TRUE(contains(text, "\"quantity\": \"mesh_acceleration_sun_planet\""));
  EXPECT_TRUE(contains(text, "\"planet\": 1"));
  // The sidecar parses with the reader's strict schema.
  const auto m = io::parse_recording_meta(text, "x.json");
  EXPECT_EQ(m.columns.size(), 6u);
}

TEST(RecordingWriter, SidecarStatesTheEncodersLinesOnTheSpeedColumnsAndTheReaderTakesThemBack) {
  io::RecordingWriteOptions o;
  o.sun_encoder_lines = 1000;
  o.carrier_encoder_lines = 2000;
  const auto m = io::parse_recording_meta(io::recording_meta_json(sample_recording(), o), "x.json");
  ASSERT_EQ(m.columns.size(), 6u);
  EXPECT_EQ(m.columns[0].encoder_lines, 1000);
  EXPECT_EQ(m.columns[1].encoder_lines, 2000);
  for (std::size_t i = 2; i < m.columns.size(); ++i) EXPECT_FALSE(m.columns[i].encoder_lines) << m.columns[i].name;
  model::SimulationConfig c;
  io::apply_encoder_lines(m, c);
  EXPECT_EQ(c.sensor.sun_encoder_lines, 1000);
  EXPECT_EQ(c.sensor.carrier_encoder_lines, 2000);
  // Ideal encoders: nothing stated.
  EXPECT_FALSE(contains(io::recording_meta_json(sample_recording(), {"x"}), "encoder_lines"));
}

TEST(RecordingWriter, CsvHeaderHasUnitsAndQuotesWhereNeeded) {
  std::ostringstream out;
  io::write_recording_csv(out, sample_recording());
  const std::string text = out.str();
  EXPECT_EQ(text.substr(0, text.find('\n')),
            "time [s],sun_speed [rad/s],carrier_speed [rad/s],\"a, sp \"\"1\"\" [m/s^2]\",a_pr [m/s^2],"
            "housing [m/s^2],tacho [1]");
  diagnose::Recording bad = sample_recording();
  bad.channels[0].values.pop_back();
  std::ostringstream sink;
  EXPECT_THROW(io::write_recording_csv(sink, bad), std::invalid_argument);
}

TEST(RecordingWriter, FailureLeavesNothingBehind) {
  test::TempDir dir;
  EXPECT_THROW(io::write_recording(dir / "missing" / "rec.csv", sample_recording()), io::IoError);
  EXPECT_THROW(io::write_recording(dir / "rec.json", sample_recording()), io::IoError);
  diagnose::Recording bad = sample_recording();
  bad.channels[2].values.resize(3);
  EXPECT_THROW(io::write_recording(dir / "rec.csv", bad), std::invalid_argument);
  EXPECT_EQ(dir.count(), 0u);
}
