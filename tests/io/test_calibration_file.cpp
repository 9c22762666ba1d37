// The calibration file: what `calibrate` writes, `diagnose --calibration` reads back exactly;
// a malformed file is an InputError naming the file and the key.
#include "core/error.hpp"
#include "io/calibration_file.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace pw;

namespace {
/// A minimal calibration file: its [calibration] table with `extra` lines (keys of that table) and
/// one discrepancy entry, written to `path`. `recordings`: its two recordings named, or none.
void write_minimal_calibration(const std::filesystem::path& path, const std::string& extra, bool recordings) {
  std::ofstream f(path);
  f << "[calibration]\nalpha = 0.01\n"
    << (recordings ? "recordings = [\"a.csv\", \"b.csv\"]\nspeeds_rpm = [1.0, 2.0]\n" : "recordings = []\nspeeds_rpm = []\n")
    << "verdicts = []\nrig_elements = []\noverrides = []\n"
    << extra
    << "[[discrepancy]]\nquantity = \"sun_speed\"\nfamily = \"mesh\"\nrelative_variance = 0\n"
       "relative_variance_se = 0\nabsolute_variance = 0\nabsolute_variance_se = 0\n";
}
} // namespace

TEST(CalibrationFile, WrittenCalibrationReadsBackExactly) {
  test::TempDir dir;
  diagnose::Calibration c;
  c.alpha = 0.02;
  c.recordings = {"/data/a.csv", "/data/b.csv"};
  c.sidecars = {"/data/a.json", "/meta/b.json"};
  c.speeds_rpm = {1000.0 / 3, 1500.0};
  c.verdicts = {"unexplained_residual", "no_missing_physics"};
  c.rig_elements = {"encoder_bandwidth"};
  c.form.mesh_phase = model::MeshPhase::NominalTime;
  c.form.housing_path = model::HousingPath::RingTranslation;
  c.overrides = {"stiffness.scale=1.2345", "sensor.encoder_bandwidth_Hz=987.5"};
  c.at_bound = {"contact.mesh_damping_ratio at its upper bound 0.25 on 2 of 3 recordings"};
  diagnose::DiscrepancyEstimate d;
  d.quantity = diagnose::Quantity::HousingAcceleration;
  d.family = diagnose::Component::Planet;
  d.relative_variance = 0.1 / 3;
  d.relative_variance_se = 1e-3 / 7;
  d.relative_cells = 26;
  d.absolute_variance = -1.5e-9;
  d.absolute_variance_se = 2e-10 / 3;
  d.absolute_cells = 106;
  d.relative_variance_per_recording = {0.03, 0.1 / 3};
  c.discrepancy = {d};
  c.coverage = {{diagnose::Quantity::SunSpeed, 776.25 / 3, 600.0 / 7, 1552.5, 1200.0, 3},
                {diagnose::Quantity::HousingAcceleration, 12.5, 600.0, 2400.125, 1200.0 / 9, 41}};
  diagnose::CalibrationFit f;
  f.nuisance_chi2_held_out = 12345.6789 / 7;
  f.noise_bound_held_out = 3401.25;
  f.values = {"stiffness.scale=2", "contact.mesh_damping_ratio=0.1234567890123"};
  f.at_bound = {"stiffness.scale"};
  c.fits = {f, diagnose::CalibrationFit{}};
  io::write_calibration(c, dir / "cal.toml");
  const diagnose::Calibration r = io::read_calibration(dir / "cal.toml");
  EXPECT_EQ(r.alpha, c.alpha);
  EXPECT_EQ(r.recordings, c.recordings);
  EXPECT_EQ(r.sidecars, c.sidecars);
  EXPECT_EQ(r.speeds_rpm, c.speeds_rpm);
  EXPECT_EQ(r.verdicts, c.verdicts);
  EXPECT_EQ(r.rig_elements, c.rig_elements);
  EXPECT_EQ(r.form, c.form);
  EXPECT_EQ(r.overrides, c.overrides);
  EXPECT_EQ(r.at_bound, c.at_bound);
  ASSERT_EQ(r.discrepancy.size(), 1u);
  const auto& e = r.discrepancy[0];
  EXPECT_EQ(e.quantity, d.quantity);
  EXPECT_EQ(e.family, d.family);
  EXPECT_EQ(e.relative_variance, d.relative_variance);
  EXPECT_EQ(e.relative_variance_se, d.relative_variance_se);
  EXPECT_EQ(e.relative_cells, d.relative_cells);
  EXPECT_EQ(e.absolute_variance, d.absolute_variance);
  EXPECT_EQ(e.absolute_variance_se, d.absolute_variance_se);
  EXPECT_EQ(e.absolute_cells, d.absolute_cells);
  EXPECT_EQ(e.relative_variance_per_recording, d.relative_variance_per_recording);
  ASSERT_EQ(r.coverage.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(r.coverage[k].quantity, c.coverage[k].quantity);
    EXPECT_EQ(r.coverage[k].lowest_Hz, c.coverage[k].lowest_Hz);
    EXPECT_EQ(r.coverage[k].lowest_speed_rpm, c.coverage[k].lowest_speed_rpm);
    EXPECT_EQ(r.coverage[k].highest_Hz, c.coverage[k].highest_Hz);
    EXPECT_EQ(r.coverage[k].highest_speed_rpm, c.coverage[k].highest_speed_rpm);
    EXPECT_EQ(r.coverage[k].lines, c.coverage[k].lines);
  }
  ASSERT_EQ(r.fits.size(), 2u);
  EXPECT_EQ(r.fits[0].nuisance_chi2_held_out, f.nuisance_chi2_held_out);
  EXPECT_EQ(r.fits[0].noise_bound_held_out, f.noise_bound_held_out);
  EXPECT_EQ(r.fits[0].values, f.values);
  EXPECT_EQ(r.fits[0].at_bound, f.at_bound);
  EXPECT_TRUE(r.fits[1].values.empty());
}

TEST(CalibrationFile, UnknownFamilyIsAnInputErrorNamingFileAndKey) {
  test::TempDir dir;
  {
    std::ofstream f(dir / "bad.toml");
    f << "[calibration]\nalpha = 0.01\nrecordings = []\nspeeds_rpm = []\nverdicts = []\nrig_elements = []\n"
         "overrides = []\n[[discrepancy]]\nquantity = \"sun_speed\"\nfamily = \"gearbox\"\nrelative_variance = 0\n"
         "relative_variance_se = 0\nabsolute_variance = 0\nabsolute_variance_se = 0\n";
  }
  const auto e = test::thrown<InputError>([&] { io::read_calibration(dir / "bad.toml"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(test::contains(e->what(), "bad.toml"));
  EXPECT_TRUE(test::contains(e->what(), "discrepancy[0].family"));
}

TEST(CalibrationFile, AFileWithoutSidecarsReadsAndOneWithTheWrongCountIsAnInputError) {
  // Files written before session 25 have no sidecars (the default names apply); a list of
  // another length than the recordings' cannot be matched to them.
  test::TempDir dir;
  write_minimal_calibration(dir / "old.toml", "", true);
  EXPECT_TRUE(io::read_calibration(dir / "old.toml").sidecars.empty());
  write_minimal_calibration(dir / "bad.toml", "sidecars = [\"a.json\"]\n", true);
  const auto e = test::thrown<InputError>([&] { io::read_calibration(dir / "bad.toml"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(test::contains(e->what(), "calibration.sidecars"));
}

TEST(CalibrationFile, AFileWithoutAFormIsRollLockedAndPlanetPassAndAnUnknownFormIsAnInputError) {
  // Files written before session 66 have no mesh_phase (their models were roll-locked), before
  // session 67 no housing_path (planet-pass).
  test::TempDir dir;
  write_minimal_calibration(dir / "old.toml", "", false);
  EXPECT_EQ(io::read_calibration(dir / "old.toml").form, diagnose::ModelForm{});
  write_minimal_calibration(dir / "bad.toml", "mesh_phase = \"time\"\n", false);
  const auto e = test::thrown<InputError>([&] { io::read_calibration(dir / "bad.toml"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(test::contains(e->what(), "calibration.mesh_phase"));
  EXPECT_TRUE(test::contains(e->what(), "nominal_time"));
  write_minimal_calibration(dir / "bad_path.toml", "housing_path = \"ring\"\n", false);
  const auto p = test::thrown<InputError>([&] { io::read_calibration(dir / "bad_path.toml"); });
  ASSERT_TRUE(p);
  EXPECT_TRUE(test::contains(p->what(), "calibration.housing_path"));
  EXPECT_TRUE(test::contains(p->what(), "ring_translation"));
  EXPECT_TRUE(test::contains(p->what(), "ring_body"));
}

TEST(CalibrationFile, ARingBodyFormReadsBack) {
  // A calibration of a lateral-torsional model read through the ring body (sensor.housing_path =
  // ring_body) names that path, and reads back as it.
  test::TempDir dir;
  write_minimal_calibration(dir / "ring_body.toml", "housing_path = \"ring_body\"\n", false);
  EXPECT_EQ(io::read_calibration(dir / "ring_body.toml").form.housing_path, model::HousingPath::RingBody);
}

TEST(CalibrationFile, AFileWithoutCoverageReadsAndAnInvertedSpanIsAnInputError) {
  // Files written before session 74 have no [[coverage]]: nothing is said about tested lines. A
  // span whose lowest line lies above its highest cannot have come from calibrate.
  test::TempDir dir;
  write_minimal_calibration(dir / "old.toml", "", false);
  EXPECT_TRUE(io::read_calibration(dir / "old.toml").coverage.empty());
  write_minimal_calibration(dir / "bad.toml", "", false);
  {
    std::ofstream f(dir / "bad.toml", std::ios::app);
    f << "[[coverage]]\nquantity = \"sun_speed\"\nlowest_Hz = 1552.0\nlowest_speed_rpm = 600.0\n"
         "highest_Hz = 776.0\nhighest_speed_rpm = 600.0\nlines = 2\n";
  }
  const auto e = test::thrown<InputError>([&] { io::read_calibration(dir / "bad.toml"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(test::contains(e->what(), "coverage[0]"));
  EXPECT_TRUE(test::contains(e->what(), "lowest_Hz <= highest_Hz"));
}
