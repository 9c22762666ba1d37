// TOML configuration: defaults, strictness (unknown keys, types, ranges),
// exact round trip, command-line overrides, and the checked-in sample.
#include "io/config_toml.hpp"
#include "config/schema.hpp"
#include "io/io_error.hpp"
#include "model/validate.hpp"

#include "core/error.hpp"
#include "io/config_compare.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

namespace pw::io {
namespace {

using pw::test::contains;
using pw::test::thrown;

std::optional<InputError> parse_error(const std::string& text, const std::string& source = "case.toml") {
  return thrown<InputError>([&] { (void)parse_config(text, source); });
}

// --- defaults and the sample file ------------------------------------------

TEST(ConfigToml, EmptyFileGivesTheDefaults) {
  test::expect_config_eq(parse_config("", "empty.toml"), model::SimulationConfig{});
}

TEST(ConfigToml, SeedTomlEqualsTheDefaults) {
  const auto config = read_config(test::source_dir() / "config" / "seed.toml");
  test::expect_config_eq(config, model::SimulationConfig{});
}

TEST(ConfigToml, FourPlanetsTomlIsTheSeedWithFourPlanetsAndItsOwnTeethAndValidates) {
  // config/four_planets.toml: the second gear set (generality checks, make_corpus --gearset).
  const auto config = read_config(test::source_dir() / "config" / "four_planets.toml");
  model::SimulationConfig expected;
  expected.stage.planet_count = 4;
  expected.stage.sun.teeth = 20;
  expected.stage.planet.teeth = 30;
  expected.stage.ring.teeth = 80;
  test::expect_config_eq(config, expected);
  EXPECT_NO_THROW(model::validate(config));
}

TEST(ConfigToml, SeedTomlWritesOutEveryKey) {
  // Collect "section.key" from the "key = value" lines of the sample.
  std::istringstream in(test::read_text(test::source_dir() / "config" / "seed.toml"));
  std::set<std::string> present;
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line[0] == '[') {
      section = line.substr(1, line.find(']') - 1);
      continue;
    }
    const auto eq = line.find(" =");
    if (eq != std::string::npos) present.insert(section + "." + line.substr(0, eq));
  }
  for (const auto& key : config_keys()) {
    if (key.path.find("pressure_angle_deg") != std::string::npos) continue;  // alternative spelling
    if (key.path.find("[]") != std::string::npos) continue;                  // shown as a comment
    EXPECT_TRUE(present.count(key.path)) << key.path << " missing from config/seed.toml";
  }
}

TEST(ConfigToml, DocsConfigMdDocumentsEveryKey) {
  const std::string docs = test::read_text(test::source_dir() / "docs" / "config.md");
  ASSERT_FALSE(docs.empty());
  for (const auto& key : config_keys())
    EXPECT_TRUE(contains(docs, "`" + key.path + "`")) << "document " << key.path << " in docs/config.md";
}

TEST(ConfigToml, KeyListNamesEveryKeyOnceWithItsDefault) {
  std::set<std::string> seen;
  for (const auto& key : config_keys()) {
    EXPECT_TRUE(seen.insert(key.path).second) << key.path << " listed twice";
    EXPECT_FALSE(key.doc.empty()) << key.path;
    EXPECT_FALSE(key.default_value.empty()) << key.path;
  }
  EXPECT_TRUE(seen.count("operating.input_speed_rpm"));
  EXPECT_TRUE(seen.count("stage.ring.pressure_angle_deg"));
  EXPECT_TRUE(seen.count("imperfections.teeth[].stiffness_factor"));
}

// The schema in io/config_toml.cpp must list every field of SimulationConfig.
// A new field changes these sizes: add it to visit_config(), config/seed.toml,
// docs/config.md and tests/io/config_compare.hpp, then update the number here.
TEST(ConfigToml, ConfigStructsHaveNoFieldsUnknownToTheSchema) {
  if constexpr (sizeof(void*) == 8 && sizeof(int) == 4) {
    EXPECT_EQ(sizeof(geometry::GearSpec), 104u);
    EXPECT_EQ(sizeof(model::StageSpec), 3 * 104u + 72u + 4 * 8u);  // + sun and ring mass and inertia
    EXPECT_EQ(sizeof(model::OperatingPoint), 16u);
    EXPECT_EQ(sizeof(model::StiffnessSettings), 16u + 4 * 3 * 8u + 8u);  // + the harmonic corrections, mesh_phase
    EXPECT_EQ(sizeof(model::ContactSettings), 80u);  // + engagement_ramp
    EXPECT_EQ(sizeof(model::ToothModifier), 32u);
    EXPECT_EQ(sizeof(model::Imperfections), 104u);
    EXPECT_EQ(sizeof(model::BearingSettings), 48u);  // + damping_ratio
    EXPECT_EQ(sizeof(model::SolverSettings), 80u);
    EXPECT_EQ(sizeof(model::WearSettings), 88u);  // + snapshot_record_mesh_cycles (int, padded)
    EXPECT_EQ(sizeof(model::SensorSettings), 88u);  // + the mount's damping ratio
    EXPECT_EQ(sizeof(model::RigSettings), 80u);  // + the two speed loops' gains
    EXPECT_EQ(sizeof(model::SimulationConfig), sizeof(model::StageSpec) + sizeof(model::OperatingPoint) +
                                                   sizeof(model::StiffnessSettings) + sizeof(model::ContactSettings) +
                                                   sizeof(model::Imperfections) + sizeof(model::BearingSettings) +
                                                   sizeof(model::SolverSettings) + sizeof(model::WearSettings) +
                                                   sizeof(model::SensorSettings) + sizeof(model::RigSettings))
        << "a new section in SimulationConfig";
  } else {
    GTEST_SKIP() << "sizes recorded for LP64 only";
  }
}

// --- strictness --------------------------------------------------------------

TEST(ConfigToml, UnknownKeyIsRejectedNamingKeyFileLineAndClosestKey) {
  const auto e = parse_error("[operating]\ninput_sped_rpm = 200\n");
  ASSERT_TRUE(e) << "typo accepted";
  EXPECT_EQ(e->parameter(), "operating.input_sped_rpm");
  EXPECT_TRUE(contains(e->what(), "unknown key"));
  EXPECT_TRUE(contains(e->what(), "case.toml:2:1"));
  EXPECT_TRUE(contains(e->what(), "did you mean 'operating.input_speed_rpm'"));
}

TEST(ConfigToml, UnknownSectionIsRejected) {
  const auto e = parse_error("[operation]\ninput_speed_rpm = 200\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operation");
  EXPECT_TRUE(contains(e->what(), "unknown section [operation]"));
  EXPECT_TRUE(contains(e->what(), "did you mean 'operating'"));
}

TEST(ConfigToml, UnknownNestedSectionIsRejected) {
  const auto e = parse_error("[stage.moon]\nteeth = 3\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.moon");
}

TEST(ConfigToml, KeyInTheWrongSectionPointsToItsSection) {
  const auto e = parse_error("[stage]\ninput_speed_rpm = 200\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "did you mean 'operating.input_speed_rpm'"));
}

TEST(ConfigToml, UnknownKeyInToothModifierIsRejectedWithItsIndex) {
  const auto e = parse_error("[[imperfections.teeth]]\nbody = \"sun\"\n\n[[imperfections.teeth]]\nstifness_factor = 0.5\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "imperfections.teeth[1].stifness_factor");
  EXPECT_TRUE(contains(e->what(), "did you mean 'imperfections.teeth[1].stiffness_factor'"));
}

TEST(ConfigToml, WrongTypesAreRejectedNamingTheExpectedType) {
  auto e = parse_error("[stage.sun]\nteeth = 21.0\n");
  ASSERT_TRUE(e) << "float accepted for an integer";
  EXPECT_EQ(e->parameter(), "stage.sun.teeth");
  EXPECT_TRUE(contains(e->what(), "expected an integer, got a float"));

  e = parse_error("[operating]\ninput_speed_rpm = \"fast\"\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "expected a float, got a string"));
  EXPECT_TRUE(contains(e->what(), "case.toml:2:"));

  e = parse_error("[stiffness]\ninclude_fillet_foundation = 1\n");
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "expected a boolean"));

  e = parse_error("[stage]\nplanet_angles_rad = [0.0, \"2\"]\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.planet_angles_rad[1]");

  e = parse_error("operating = 5\n");
  ASSERT_TRUE(e) << "value accepted where a section is expected";
  EXPECT_EQ(e->parameter(), "operating");
  EXPECT_TRUE(contains(e->what(), "must be a table"));
}

TEST(ConfigToml, IntegerIsAcceptedWhereAFloatIsExpected) {
  const auto c = parse_config("[operating]\ninput_speed_rpm = 200\n");
  EXPECT_EQ(c.operating.input_speed_rpm, 200.0);
}

TEST(ConfigToml, SyntaxErrorReportsFileLineAndColumn) {
  const auto e = parse_error("[operating]\ninput_speed_rpm = = 3\n", "bad.toml");
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "bad.toml:2:")) << e->what();
  EXPECT_TRUE(contains(e->what(), "TOML syntax error"));
}

TEST(ConfigToml, NaNAndNegativeSpeedAreRejectedWithValueRangeAndLine) {
  auto e = parse_error("[operating]\ninput_speed_rpm = nan\n");
  ASSERT_TRUE(e) << "NaN speed accepted";
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "got nan"));
  EXPECT_TRUE(contains(e->what(), "case.toml:2:"));

  e = parse_error("[operating]\ninput_speed_rpm = -100.0\n");
  ASSERT_TRUE(e) << "negative speed accepted";
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "got -100"));
  EXPECT_TRUE(contains(e->what(), "(0, 100000]"));

  e = parse_error("[operating]\ninput_power_W = inf\n");
  ASSERT_TRUE(e) << "infinite power accepted";
  EXPECT_EQ(e->parameter(), "operating.input_power_W");
}

TEST(ConfigToml, ValidationErrorOfAToothModifierNamesItsIndexAndLine) {
  const auto e = parse_error("[[imperfections.teeth]]\nbody = \"sun\"\ntooth = 21\n");
  ASSERT_TRUE(e) << "tooth 21 of a 21-tooth sun accepted";
  EXPECT_EQ(e->parameter(), "imperfections.teeth[0].tooth");
  EXPECT_TRUE(contains(e->what(), "[0, 20]"));
  EXPECT_TRUE(contains(e->what(), "case.toml:3:"));
}

TEST(ConfigToml, PressureAngleInDegreesIsConvertedToRadians) {
  const auto c = parse_config("[stage.sun]\npressure_angle_deg = 25\n[stage.planet]\npressure_angle_deg = 20.0\n");
  EXPECT_DOUBLE_EQ(c.stage.sun.pressure_angle_rad, 25.0 * std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(c.stage.planet.pressure_angle_rad, 20.0 * std::numbers::pi / 180.0);
  EXPECT_EQ(c.stage.ring.pressure_angle_rad, model::SimulationConfig{}.stage.ring.pressure_angle_rad);
}

TEST(ConfigToml, PressureAngleGivenTwiceIsRejected) {
  const auto e = parse_error("[stage.sun]\npressure_angle_rad = 0.35\npressure_angle_deg = 20\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.sun.pressure_angle_deg");
  EXPECT_TRUE(contains(e->what(), "not both"));
}

TEST(ConfigToml, PressureAngleOutOfRangeInDegreesPointsAtTheDegreeKey) {
  const auto e = parse_error("[stage.ring]\n\npressure_angle_deg = 50\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.ring.pressure_angle_deg");  // the key the user wrote
  EXPECT_TRUE(contains(e->what(), "stage.ring.pressure_angle_rad = stage.ring.pressure_angle_deg x pi/180"));
  EXPECT_TRUE(contains(e->what(), "case.toml:3:"));
}

TEST(ConfigToml, PressureAngleOverrideOutOfRangeInDegreesNamesTheDegreeKey) {
  model::SimulationConfig c{};
  try {
    apply_overrides(c, {"stage.sun.pressure_angle_deg=80"});
    FAIL() << "a pressure angle of 80 deg was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.parameter(), "stage.sun.pressure_angle_deg");
    EXPECT_TRUE(contains(e.what(), "after the command-line overrides"));
  }
  try {  // given in radians, the radian key is named
    apply_overrides(c, {"stage.sun.pressure_angle_rad=1.4"});
    FAIL() << "a pressure angle of 1.4 rad was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.parameter(), "stage.sun.pressure_angle_rad");
  }
}

TEST(ConfigToml, EnumerationsAreStringsAndMisspellingsAreSuggested) {
  EXPECT_EQ(parse_config("[solver]\nlevel = \"lateral_torsional\"\n").solver.level, model::ModelLevel::LateralTorsional);
  const auto e = parse_error("[solver]\nlevel = \"lateral_torsonal\"\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "solver.level");
  EXPECT_TRUE(contains(e->what(), "did you mean \"lateral_torsional\""));
}

TEST(ConfigToml, ToothModifiersAreReadInOrder) {
  const auto c = parse_config(R"(
[[imperfections.teeth]]
body = "planet"
planet = 2
tooth = 7
stiffness_factor = 0.6
profile_deviation_m = 1e-5

[[imperfections.teeth]]
body = "ring"
tooth = 80
)");
  ASSERT_EQ(c.imperfections.teeth.size(), 2u);
  EXPECT_EQ(c.imperfections.teeth[0].body, model::Body::Planet);
  EXPECT_EQ(c.imperfections.teeth[0].planet, 2);
  EXPECT_EQ(c.imperfections.teeth[0].tooth, 7);
  EXPECT_EQ(c.imperfections.teeth[0].stiffness_factor, 0.6);
  EXPECT_EQ(c.imperfections.teeth[0].profile_deviation_m, 1e-5);
  EXPECT_EQ(c.imperfections.teeth[1].body, model::Body::Ring);
  EXPECT_EQ(c.imperfections.teeth[1].tooth, 80);
  EXPECT_EQ(c.imperfections.teeth[1].stiffness_factor, 1.0);
}

TEST(ConfigToml, WearSectionIsReadWithTheFileTypeRules) {
  const auto c = parse_config(R"(
[wear]
mesh_cycles = 2e5
coefficient_m2_N = 5e-17
elements_per_flank = 32
window_mesh_cycles = 30
snapshot_mesh_cycles = [0, 1e5, 200000]
)");
  EXPECT_EQ(c.wear.mesh_cycles, 2e5);
  EXPECT_EQ(c.wear.coefficient_m2_N, 5e-17);
  EXPECT_EQ(c.wear.elements_per_flank, 32);
  EXPECT_EQ(c.wear.window_mesh_cycles, 30);
  EXPECT_EQ(c.wear.snapshot_mesh_cycles, (std::vector<double>{0.0, 1e5, 2e5}));
  EXPECT_EQ(c.wear.hardness_Pa, model::WearSettings{}.hardness_Pa) << "missing key must keep its default";

  auto e = parse_error("[wear]\nelements_per_flank = 64.0\n");
  ASSERT_TRUE(e) << "float accepted for an integer";
  EXPECT_EQ(e->parameter(), "wear.elements_per_flank");
  EXPECT_TRUE(contains(e->what(), "expected an integer, got a float"));

  e = parse_error("[wear]\nmesh_cycle = 2e5\n");
  ASSERT_TRUE(e) << "typo accepted";
  EXPECT_TRUE(contains(e->what(), "did you mean 'wear.mesh_cycles'"));

  e = parse_error("[solver]\nmesh_cycles = 2e5\n");
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "did you mean 'wear.mesh_cycles'"));
}

TEST(ConfigToml, WearRangeErrorNamesTheKeyAndLine) {
  auto e = parse_error("[wear]\n\nmesh_cycles = -2e5\n");
  ASSERT_TRUE(e) << "negative mesh cycles accepted";
  EXPECT_EQ(e->parameter(), "wear.mesh_cycles");
  EXPECT_TRUE(contains(e->what(), "must be >= 0 (0 = no wear)"));
  EXPECT_TRUE(contains(e->what(), "case.toml:3:"));

  e = parse_error("[wear]\ncoefficient_m2_N = -5e-17\n");
  ASSERT_TRUE(e) << "negative kappa accepted";
  EXPECT_EQ(e->parameter(), "wear.coefficient_m2_N");
  EXPECT_TRUE(contains(e->what(), "case.toml:2:"));

  e = parse_error("[wear]\nmesh_cycles = 100.0\nsnapshot_mesh_cycles = [0.0, 50.0, 150.0]\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "wear.snapshot_mesh_cycles[2]");
}

TEST(ConfigToml, MissingFileIsAnIoErrorNamingThePath) {
  const auto e = thrown<IoError>([] { (void)read_config("/nonexistent/planetwear.toml"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "/nonexistent/planetwear.toml"));
}

// --- round trip --------------------------------------------------------------

TEST(ConfigToml, ToTomlThenParseReproducesEveryFieldExactly) {
  const auto original = test::nondefault_config();
  ASSERT_NO_THROW(model::validate(original));
  const std::string text = to_toml(original);
  const auto parsed = parse_config(text, "roundtrip.toml");
  test::expect_config_eq(parsed, original);
  EXPECT_EQ(to_toml(parsed), text);
}

TEST(ConfigToml, ToTomlOfTheDefaultsRoundTrips) {
  const model::SimulationConfig defaults{};
  test::expect_config_eq(parse_config(to_toml(defaults)), defaults);
}

TEST(ConfigToml, RingBodyHousingPathParsesWritesAndReadsBack) {
  // The third housing path (model/sensor.hpp Eq. S3) is a string like the other two, written back
  // under its own name; it is valid with the lateral-torsional model only (model/validate.cpp).
  const auto c = parse_config("[solver]\nlevel = \"lateral_torsional\"\n[sensor]\nhousing_path = \"ring_body\"\n");
  EXPECT_EQ(c.sensor.housing_path, model::HousingPath::RingBody);
  EXPECT_EQ(std::string(model::housing_path_name(c.sensor.housing_path)), "ring_body");
  const std::string text = to_toml(c);
  EXPECT_TRUE(contains(text, "housing_path = 'ring_body'") || contains(text, "housing_path = \"ring_body\""));
  test::expect_config_eq(parse_config(text, "ring_body.toml"), c);
  model::SimulationConfig o;
  o.solver.level = model::ModelLevel::LateralTorsional;
  apply_overrides(o, {"sensor.housing_path=ring_body"});
  EXPECT_EQ(o.sensor.housing_path, model::HousingPath::RingBody);
  const auto e = parse_error("[sensor]\nhousing_path = \"ring_bdy\"\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "sensor.housing_path");
  EXPECT_TRUE(contains(e->what(), "did you mean \"ring_body\""));
}

TEST(ConfigToml, ToTomlWritesEveryKey) {
  const std::string text = to_toml(model::SimulationConfig{});
  for (const auto& key : config_keys()) {
    if (key.path.find("pressure_angle_deg") != std::string::npos || key.path.find("[]") != std::string::npos)
      continue;
    const std::string name = key.path.substr(key.path.rfind('.') + 1);
    EXPECT_TRUE(contains(text, "\n" + name + " = ")) << key.path;
  }
}

// --- overrides ---------------------------------------------------------------

TEST(ConfigToml, OverrideSetsTheKeyWithTheFileTypeRules) {
  model::SimulationConfig c;
  apply_override(c, "operating.input_speed_rpm", "200");
  EXPECT_EQ(c.operating.input_speed_rpm, 200.0);
  apply_override(c, "solver.level", "lateral_torsional");  // bare word
  EXPECT_EQ(c.solver.level, model::ModelLevel::LateralTorsional);
  apply_override(c, "solver.level", "\"torsional\"");
  EXPECT_EQ(c.solver.level, model::ModelLevel::Torsional);
  apply_override(c, "stage.sun.pressure_angle_deg", "25");
  EXPECT_DOUBLE_EQ(c.stage.sun.pressure_angle_rad, 25.0 * std::numbers::pi / 180.0);
  apply_override(c, "stage.planet_angles_rad", "[0, 2.0, 4.0]");
  EXPECT_EQ(c.stage.planet_angles_rad, (std::vector<double>{0.0, 2.0, 4.0}));
  apply_override(c, "stiffness.include_fillet_foundation", "false");
  EXPECT_FALSE(c.stiffness.include_fillet_foundation);
  apply_override(c, "wear.mesh_cycles", "2e5");
  EXPECT_EQ(c.wear.mesh_cycles, 2e5);
  apply_override(c, "wear.coefficient_m2_N", "3e-17");
  EXPECT_EQ(c.wear.coefficient_m2_N, 3e-17);
  apply_override(c, "wear.snapshot_mesh_cycles", "[0, 1e5]");
  EXPECT_EQ(c.wear.snapshot_mesh_cycles, (std::vector<double>{0.0, 1e5}));
  EXPECT_NO_THROW(model::validate(c));
}

TEST(ConfigToml, OverrideOfAToothModifierFieldAppendsAtTheNextIndex) {
  model::SimulationConfig c;
  apply_override(c, "imperfections.teeth[0].stiffness_factor", "0.5");
  apply_override(c, "imperfections.teeth[0].tooth", "4");
  ASSERT_EQ(c.imperfections.teeth.size(), 1u);
  EXPECT_EQ(c.imperfections.teeth[0].stiffness_factor, 0.5);
  EXPECT_EQ(c.imperfections.teeth[0].tooth, 4);
  const auto e = thrown<InputError>([&] { apply_override(c, "imperfections.teeth[2].tooth", "1"); });
  ASSERT_TRUE(e) << "gap in the modifier list accepted";
  EXPECT_EQ(e->parameter(), "imperfections.teeth[2].tooth");
  EXPECT_EQ(c.imperfections.teeth.size(), 1u);

  apply_override(c, "imperfections.teeth", R"([{body = "ring", tooth = 9}, {body = "sun"}])");
  ASSERT_EQ(c.imperfections.teeth.size(), 2u);
  EXPECT_EQ(c.imperfections.teeth[0].body, model::Body::Ring);
  EXPECT_EQ(c.imperfections.teeth[0].tooth, 9);
}

TEST(ConfigToml, OverrideOfAnUnknownKeyNamesItAndSuggests) {
  model::SimulationConfig c;
  auto e = thrown<InputError>([&] { apply_override(c, "operating.input_sped_rpm", "200"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operating.input_sped_rpm");
  EXPECT_TRUE(contains(e->what(), "did you mean 'operating.input_speed_rpm'"));

  e = thrown<InputError>([&] { apply_override(c, "input_speed_rpm", "200"); });
  ASSERT_TRUE(e);
  EXPECT_TRUE(contains(e->what(), "did you mean 'operating.input_speed_rpm'"));
}

TEST(ConfigToml, FailedOverrideLeavesTheConfigUnchanged) {
  model::SimulationConfig c;
  const auto e = thrown<InputError>([&] { apply_override(c, "operating.input_speed_rpm", "fast"); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "expected a float"));
  EXPECT_TRUE(contains(e->what(), "--set operating.input_speed_rpm=fast"));
  test::expect_config_eq(c, model::SimulationConfig{});
}

TEST(ConfigToml, OverridesAreValidatedOnceAfterTheLast) {
  model::SimulationConfig c;
  // planet_angles_rad before planet_count is inconsistent in between.
  apply_overrides(c, {"stage.planet_angles_rad=[0, 3.0]", "stage.planet_count = 2"});
  EXPECT_EQ(c.stage.planet_count, 2);

  model::SimulationConfig d;
  const auto e = thrown<InputError>([&] { apply_overrides(d, {"solver.newmark_beta=0.2", "operating.input_speed_rpm=-1"}); });
  ASSERT_TRUE(e) << "negative speed accepted from --set";
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  test::expect_config_eq(d, model::SimulationConfig{});

  EXPECT_TRUE(thrown<InputError>([&] { apply_overrides(d, {"operating.input_speed_rpm"}); }));
}

// config::find_number (config/schema.hpp), through which the diagnosis's
// candidates write their parameters, reaches exactly the schema's float keys,
// and each one is the field the reader fills for that key.
TEST(ConfigToml, FindNumberReachesEveryFloatKeyAsTheReaderFillsItAndNoOtherKey) {
  int floats = 0;
  for (const auto& key : io::config_keys()) {
    model::SimulationConfig via_finder{};
    double* field = config::find_number(via_finder, key.path);
    const bool is_float = key.type == "float" && key.path.find("[]") == std::string::npos &&
                          key.path.find("_deg") == std::string::npos;
    if (!is_float) {
      EXPECT_EQ(field, nullptr) << key.path;
      continue;
    }
    ASSERT_NE(field, nullptr) << key.path;
    ++floats;
    *field = 0.123456789;
    model::SimulationConfig via_reader{};
    io::apply_override(via_reader, key.path, "0.123456789");
    EXPECT_EQ(io::to_toml(via_finder), io::to_toml(via_reader)) << key.path;
  }
  EXPECT_GT(floats, 50);
  model::SimulationConfig c{};
  EXPECT_EQ(config::find_number(c, "contact.friction"), nullptr);
  EXPECT_EQ(config::find_number(c, "friction_coefficient"), nullptr);
  EXPECT_EQ(config::find_number(c, ""), nullptr);
}

} // namespace
} // namespace pw::io
