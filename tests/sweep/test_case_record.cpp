// Per-case records: the summary of a simulation result against closed-form
// values (RMS and peak of a sinusoid, its frequency, mean force, final wear
// mean/max over teeth, backlash growth, decimation), a real short simulation,
// and the byte serialization (exact round trip, malformed bytes rejected).
#include "sweep/case_record.hpp"

#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pw::sweep {
namespace {

/// 1 s at 1 kHz: accelerations A sin(2 pi f t) with f on a bin, constant forces.
model::SimulationResult synthetic(double amplitude, double frequency_Hz) {
  model::SimulationResult r;
  r.time_step_s = 1e-3;
  const int n = 1000;
  for (int k = 0; k < n; ++k) r.time_s.push_back(k * 1e-3);
  auto channel = [&](std::string name, std::string unit, auto f) {
    model::Channel c{std::move(name), std::move(unit), "test", {}};
    for (int k = 0; k < n; ++k) c.values.push_back(f(k * 1e-3));
    r.channels.push_back(std::move(c));
  };
  const double w = 2 * std::numbers::pi * frequency_Hz;
  channel("sun_planet/0/deflection", "m", [](double) { return 2e-6; });
  channel("sun_planet/0/force", "N", [](double t) { return 500.0 + 10 * std::sin(t); });
  channel("sun_planet/0/acceleration", "m/s^2", [&](double t) { return amplitude * std::sin(w * t); });
  channel("planet_ring/0/deflection", "m", [](double) { return 1e-6; });
  channel("planet_ring/0/force", "N", [](double) { return -300.0; });
  channel("planet_ring/0/acceleration", "m/s^2", [&](double t) { return 0.5 * amplitude * std::sin(2 * w * t); });
  channel("transmission_error", "m", [&](double t) { return 3e-6 * std::sin(w * t); });
  r.scalars.push_back({"efficiency", "1", "test", 0.98});
  return r;
}

TEST(CaseRecord, SummarizesPlanetZeroMeshesInClosedForm) {
  const CaseRecord rec = make_case_record(synthetic(4.0, 50.0), {});
  EXPECT_EQ(rec.status, CaseStatus::Done);
  EXPECT_EQ(rec.message, "");
  auto value = [&](const char* name) {
    const NamedScalar* s = rec.find_scalar(name);
    EXPECT_NE(s, nullptr) << name;
    return s ? s->value : NAN;
  };
  EXPECT_EQ(value("efficiency"), 0.98);
  EXPECT_NEAR(value("sun_planet/0/acceleration_rms"), 4.0 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(value("sun_planet/0/acceleration_peak"), 4.0, 1e-9);
  EXPECT_DOUBLE_EQ(value("sun_planet/0/acceleration_dominant_frequency"), 50.0);
  EXPECT_DOUBLE_EQ(value("planet_ring/0/acceleration_dominant_frequency"), 100.0);
  EXPECT_NEAR(value("planet_ring/0/force_mean"), -300.0, 1e-9);
  EXPECT_NEAR(value("planet_ring/0/force_peak"), 300.0, 1e-12);
  EXPECT_NEAR(value("sun_planet/0/deflection_mean"), 2e-6, 1e-18);
  EXPECT_NEAR(value("transmission_error/peak_to_peak"), 6e-6, 1e-9);
  EXPECT_EQ(rec.find_scalar("backlash_growth/sun_planet"), nullptr);  // no wear run
  EXPECT_EQ(rec.find_scalar("sun_planet/0/acceleration_rms")->unit, "m/s^2");
  ASSERT_EQ(rec.spectra.size(), 2u);
  EXPECT_EQ(rec.spectra[0].channel, "sun_planet/0/acceleration");
  EXPECT_EQ(rec.spectra[0].frequency_Hz, rec.spectra[1].frequency_Hz);
  EXPECT_EQ(rec.spectra[0].amplitude.size(), 501u);
  EXPECT_NEAR(rec.spectra[0].amplitude[50], 4.0, 1e-6);  // peak amplitude scaling
  EXPECT_TRUE(rec.wear.empty());
  EXPECT_TRUE(rec.time_history.time_s.empty());
}

TEST(CaseRecord, FinalWearIsMeanAndMaxOverTeethAndBacklashGrowthIsLastMinusFirst) {
  model::SimulationResult r = synthetic(1.0, 10.0);
  model::FlankWearHistory sun{"sun", 2, 3, {-1e-3, 0.0, 1e-3}, {}};
  // update 0: zeros; update 1 (final): tooth 0 = 1,2,3 um; tooth 1 = 3,2,1 um.
  sun.depth_m = {0, 0, 0, 0, 0, 0, 1e-6, 2e-6, 3e-6, 3e-6, 2e-6, 1e-6};
  r.wear.mesh_cycles = {0.0, 1e5};
  r.wear.flanks = {sun};
  r.wear.backlash_m = {1e-5, 2e-5, 1.5e-5, 2.25e-5};
  r.wear.stop_reason = "wear stopped after 1e5 mesh cycles";
  const CaseRecord rec = make_case_record(r, {});
  ASSERT_EQ(rec.wear.size(), 1u);
  EXPECT_EQ(rec.wear[0].family, "sun");
  EXPECT_EQ(rec.wear[0].distance_from_pitch_point_m, (std::vector<double>{-1e-3, 0.0, 1e-3}));
  for (int e = 0; e < 3; ++e) EXPECT_NEAR(rec.wear[0].mean_depth_m[e], 2e-6, 1e-20) << e;
  EXPECT_EQ(rec.wear[0].max_depth_m, (std::vector<double>{3e-6, 2e-6, 3e-6}));
  EXPECT_DOUBLE_EQ(rec.find_scalar("backlash_growth/sun_planet")->value, 0.5e-5);
  EXPECT_DOUBLE_EQ(rec.find_scalar("backlash_growth/planet_ring")->value, 0.25e-5);
  EXPECT_EQ(rec.message, "wear stopped after 1e5 mesh cycles");
}

TEST(CaseRecord, DecimationKeepsEveryKthSampleOfPlanetZeroChannels) {
  const model::SimulationResult r = synthetic(1.0, 10.0);
  const CaseRecord rec = make_case_record(r, {7});
  ASSERT_EQ(rec.time_history.time_s.size(), 143u);  // ceil(1000 / 7)
  EXPECT_EQ(rec.time_history.time_s[2], r.time_s[14]);
  ASSERT_EQ(rec.time_history.channels.size(), 7u);
  for (const auto& c : rec.time_history.channels) {
    EXPECT_EQ(c.values.size(), 143u) << c.name;
    EXPECT_EQ(c.values[3], r.find(c.name)->values[21]) << c.name;
  }
}

TEST(CaseRecord, SpectraCanBeCutAtAMaximumFrequency) {
  const CaseRecord rec = make_case_record(synthetic(4.0, 50.0), {0, 60.0});
  ASSERT_EQ(rec.spectra.size(), 2u);
  EXPECT_EQ(rec.spectra[0].frequency_Hz.size(), 61u);  // 0, 1, ..., 60 Hz
  EXPECT_EQ(rec.spectra[0].frequency_Hz.back(), 60.0);
  EXPECT_EQ(rec.spectra[1].amplitude.size(), 61u);
  // The statistics still use every bin: planet-ring's 100 Hz line is beyond the cut.
  EXPECT_DOUBLE_EQ(rec.find_scalar("planet_ring/0/acceleration_dominant_frequency")->value, 100.0);
}

TEST(CaseRecord, MissingPlanetZeroChannelsAreAnError) {
  model::SimulationResult r = synthetic(1.0, 10.0);
  r.channels.erase(r.channels.begin() + 2);
  EXPECT_THROW((void)make_case_record(r, {}), std::invalid_argument);
}

TEST(CaseRecord, RealShortSimulationGivesTheDocumentedRecord) {
  model::SimulationConfig c;
  c.operating.input_speed_rpm = 400;
  c.solver.record_mesh_cycles = 2;
  c.solver.warmup_max_mesh_cycles = 10;
  const CaseRecord rec = make_case_record(model::simulate(c), {4});
  for (const char* name : {"efficiency", "mesh_frequency", "load_sharing_factor/0", "sun_planet/0/acceleration_rms",
                           "planet_ring/0/acceleration_dominant_frequency", "sun_planet/0/force_mean"}) {
    const NamedScalar* s = rec.find_scalar(name);
    ASSERT_NE(s, nullptr) << name;
    EXPECT_TRUE(std::isfinite(s->value)) << name;
  }
  EXPECT_GT(rec.find_scalar("sun_planet/0/force_mean")->value, 0.0);
  ASSERT_EQ(rec.spectra.size(), 2u);
  EXPECT_GT(rec.spectra[0].amplitude.size(), 10u);
  EXPECT_FALSE(rec.time_history.time_s.empty());
}

TEST(CaseRecord, SerializationRoundTripsExactly) {
  model::SimulationResult r = synthetic(2.5, 30.0);
  r.wear.mesh_cycles = {0.0};
  r.wear.flanks = {{"planet_0/sun_side", 1, 2, {-1e-3, 1e-3}, {0.1, 0.2}}};
  r.wear.backlash_m = {0.0, 0.0};
  CaseRecord rec = make_case_record(r, {3});
  rec.index = 42;
  rec.rank = 3;
  rec.wall_time_s = 1.25;
  rec.message = "note \xc2\xb5m";
  const std::vector<char> bytes = serialize(rec);
  const CaseRecord back = deserialize(bytes);
  EXPECT_EQ(serialize(back), bytes);
  EXPECT_EQ(back.index, 42);
  EXPECT_EQ(back.rank, 3);
  EXPECT_EQ(back.wall_time_s, 1.25);
  EXPECT_EQ(back.message, rec.message);
  ASSERT_EQ(back.scalars.size(), rec.scalars.size());
  for (std::size_t k = 0; k < rec.scalars.size(); ++k) {
    EXPECT_EQ(back.scalars[k].name, rec.scalars[k].name);
    EXPECT_EQ(back.scalars[k].unit, rec.scalars[k].unit);
    EXPECT_EQ(back.scalars[k].value, rec.scalars[k].value);
  }
  EXPECT_EQ(back.wear[0].max_depth_m, rec.wear[0].max_depth_m);
  EXPECT_EQ(back.spectra[1].amplitude, rec.spectra[1].amplitude);
  EXPECT_EQ(back.time_history.channels[6].values, rec.time_history.channels[6].values);

  const CaseRecord failed = deserialize(serialize(failed_record(7, "diverged")));
  EXPECT_EQ(failed.status, CaseStatus::Failed);
  EXPECT_EQ(failed.message, "diverged");
  EXPECT_EQ(failed.index, 7);
}

TEST(CaseRecord, MalformedBytesAreRejected) {
  const std::vector<char> bytes = serialize(make_case_record(synthetic(1.0, 10.0), {}));
  for (const std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{20}, bytes.size() / 2, bytes.size() - 1})
    EXPECT_THROW((void)deserialize(std::span<const char>(bytes.data(), cut)), RecordFormatError) << cut;
  std::vector<char> bad = bytes;
  bad[0] ^= 0x5a;
  EXPECT_THROW((void)deserialize(bad), RecordFormatError);
  std::vector<char> longer = bytes;
  longer.push_back(0);
  EXPECT_THROW((void)deserialize(longer), RecordFormatError);
}

TEST(CaseRecord, StatusNamesRoundTrip) {
  for (const auto s : {CaseStatus::Pending, CaseStatus::Done, CaseStatus::Failed})
    EXPECT_EQ(case_status_from(to_string(s)), s);
  EXPECT_THROW((void)case_status_from("running"), std::invalid_argument);
}

} // namespace
} // namespace pw::sweep
