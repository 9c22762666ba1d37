// Campaign files: the shipped campaigns parse and every case is valid; the
// base case (config file relative to the campaign, [base.set] overrides);
// factor keys, types and units checked against io::config_keys(); every
// case's configuration validated up front with the first bad case named;
// hashes that detect changed inputs; unknown keys rejected with the key named.
#include "sweep/campaign.hpp"

#include "core/error.hpp"
#include "io/config_toml.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <string>

namespace pw::sweep {
namespace {

using pw::test::contains;
using pw::test::thrown;

/// The InputError parse_campaign() throws for `text`, naming `param`.
::testing::AssertionResult rejected(const std::string& text, const std::string& param, const std::string& part) {
  const auto e = thrown<InputError>([&] { (void)parse_campaign(text, ".", "c.toml"); });
  if (!e) return ::testing::AssertionFailure() << "accepted; expected an error naming " << param;
  if (e->parameter() != param)
    return ::testing::AssertionFailure() << "named '" << e->parameter() << "' instead of '" << param << "': " << e->what();
  return contains(e->what(), part);
}

const std::string kSpeed = R"(
[[factors]]
key = "operating.input_speed_rpm"
unit = "rpm"
levels = [100.0, 400.0]
)";
const std::string kFactorial = "[design]\ntype = \"full_factorial\"\n";

TEST(Campaign, ShippedCampaignsParseAndEveryCaseIsValid) {
  const auto dir = test::source_dir() / "sweep" / "campaigns";
  const Campaign seed = read_campaign(dir / "seed_speeds.toml");
  EXPECT_NO_THROW(validate_cases(seed));
  ASSERT_EQ(seed.cases.size(), 3u);
  EXPECT_EQ(seed.cases[0].values[0], 100.0);
  EXPECT_EQ(seed.cases[2].values[0], 400.0);
  EXPECT_EQ(seed.base.wear.mesh_cycles, 2e5);
  EXPECT_EQ(seed.base.operating.input_power_W, 1000.0);
  const Campaign demo = read_campaign(dir / "demo_lhs.toml");
  EXPECT_NO_THROW(validate_cases(demo));
  EXPECT_EQ(demo.cases.size(), 16u);
  EXPECT_EQ(demo.design.type, DesignType::LatinHypercube);
  EXPECT_EQ(demo.factors[2].scale, Scale::Log);
  const Campaign uncertain = read_campaign(dir / "saltelli_uncertain.toml");
  EXPECT_NO_THROW(validate_cases(uncertain));
  EXPECT_EQ(uncertain.cases.size(), 8u * (3 + 2));
  EXPECT_EQ(uncertain.factors[2].distribution.kind, DistributionKind::LogNormal);
  for (const auto& p : uncertain.cases) {
    EXPECT_GE(p.values[0], 0.0);  // the normal friction truncated to [0, 0.2]
    EXPECT_LE(p.values[0], 0.2);
    EXPECT_GE(p.values[1], 0.02);  // the triangular damping on its support
    EXPECT_LE(p.values[1], 0.1);
  }
}

TEST(Campaign, BaseConfigIsRelativeToTheCampaignAndBaseSetOverridesIt) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "sub");
  test::write_text(dir / "sub" / "base.toml", "[operating]\ninput_power_W = 1500.0\n[solver]\nrecord_mesh_cycles = 7\n");
  test::write_text(dir / "c.toml", R"(
[base]
config = "sub/base.toml"
[base.set]
solver.record_mesh_cycles = 3
"contact.friction_coefficient" = 0.05
solver.level = "lateral_torsional"
)" + kSpeed + kFactorial);
  const Campaign c = read_campaign(dir / "c.toml");
  EXPECT_EQ(c.base.operating.input_power_W, 1500.0);
  EXPECT_EQ(c.base.solver.record_mesh_cycles, 3);
  EXPECT_EQ(c.base.contact.friction_coefficient, 0.05);
  EXPECT_EQ(c.base.solver.level, model::ModelLevel::LateralTorsional);
  EXPECT_EQ(c.base_config_file, dir / "sub" / "base.toml");
  const model::SimulationConfig case1 = case_config(c, 1);
  EXPECT_EQ(case1.operating.input_speed_rpm, 400.0);
  EXPECT_EQ(case1.operating.input_power_W, 1500.0);
}

TEST(Campaign, BaseSetKeysAreCheckedLikeSetOverrides) {
  EXPECT_TRUE(rejected("[base.set]\noperating.input_sped_rpm = 3.0\n" + kSpeed + kFactorial, "base.set",
                       "did you mean 'operating.input_speed_rpm'"));
  EXPECT_TRUE(rejected("[base.set]\nsolver.record_mesh_cycles = 2.5\n" + kSpeed + kFactorial, "base.set",
                       "solver.record_mesh_cycles"));
}

TEST(Campaign, FactorKeysMustBeNumericConfigurationKeys) {
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_sped_rpm\"\nunit = \"rpm\"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].key", "unknown configuration key 'operating.input_sped_rpm' (c.toml:2:7); did you "
                                         "mean 'operating.input_speed_rpm'?"));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"solver.level\"\nunit = \"-\"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].key", "is a key of type string; factors must be numeric"));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"imperfections.pin_error_m\"\nunit = \"m\"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].key", "array of floats"));
  EXPECT_TRUE(rejected(kSpeed + kSpeed + kFactorial, "factors[1].key", "is already factors[0]"));
  // Indexed keys of tooth modifiers are configuration keys too.
  const Campaign c = parse_campaign(
      "[[factors]]\nkey = \"imperfections.teeth[0].stiffness_factor\"\nunit = \"-\"\nlevels = [0.5, 1.0]\n" + kFactorial,
      ".", "c.toml");
  ASSERT_NO_THROW(validate_cases(c));
  EXPECT_EQ(case_config(c, 0).imperfections.teeth.at(0).stiffness_factor, 0.5);
}

TEST(Campaign, UnitsMustMatchTheDocumentedUnit) {
  EXPECT_EQ(documented_unit("operating.input_speed_rpm"), "rpm");
  EXPECT_EQ(documented_unit("wear.coefficient_m2_N"), "m^2/N");
  EXPECT_EQ(documented_unit("imperfections.teeth[3].profile_deviation_m"), "m");
  EXPECT_EQ(documented_unit("contact.mesh_damping_ratio"), "-");
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_power_W\"\nunit = \"kW\"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].unit", "\"kW\" does not match the unit of operating.input_power_W, which is \"W\""));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_power_W\"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].unit", "missing: the unit of operating.input_power_W (documented: \"W\")"));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_power_W\"\nunit = \"  \"\nlevels = [1.0]\n" + kFactorial,
                       "factors[0].unit", "missing"));
  for (const char* dimensionless : {"-", "1"})
    EXPECT_NO_THROW((void)parse_campaign("[[factors]]\nkey = \"contact.mesh_damping_ratio\"\nunit = \"" +
                                             std::string(dimensionless) + "\"\nlevels = [0.05]\n" + kFactorial,
                                         ".", "c.toml"));
}

TEST(Campaign, AssignmentsPrintIntegersWholeAndFloatsRoundTrip) {
  const Campaign c = parse_campaign(R"(
[[factors]]
key = "stage.planet_count"
unit = "-"
levels = [3, 6]
[[factors]]
key = "contact.friction_coefficient"
unit = "-"
levels = [0.1]
)" + kFactorial, ".", "c.toml");
  EXPECT_EQ(case_assignments(c, 1), (std::vector<std::string>{"stage.planet_count=6", "contact.friction_coefficient=0.1"}));
  EXPECT_EQ(describe_case(c, 1), "stage.planet_count = 6 -, contact.friction_coefficient = 0.1 -");
  EXPECT_EQ(case_config(c, 1).stage.planet_count, 6);
}

TEST(Campaign, ValidateCasesNamesTheFirstInvalidCaseAndItsFactorValues) {
  const Campaign c = parse_campaign("[[factors]]\nkey = \"stage.planet_count\"\nunit = \"-\"\nlevels = [3, 4, 5]\n" +
                                        kFactorial,
                                    ".", "c.toml");
  const auto e = thrown<InputError>([&] { validate_cases(c); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "case 1 (stage.planet_count = 4 -)");
  EXPECT_TRUE(contains(e->what(), "(Zs + Zr)/N to be an integer"));
  // Ranges of model::validate too.
  const Campaign d = parse_campaign("[[factors]]\nkey = \"contact.friction_coefficient\"\nunit = \"-\"\nlevels = [0.1, "
                                    "-1.0]\n" + kFactorial,
                                    ".", "c.toml");
  const auto f = thrown<InputError>([&] { validate_cases(d); });
  ASSERT_TRUE(f);
  EXPECT_TRUE(contains(f->what(), "case 1 (contact.friction_coefficient = -1 -): contact.friction_coefficient"));
}

TEST(Campaign, InputHashFollowsTheTextDesignHashTheResolvedCases) {
  const Campaign a = parse_campaign(kSpeed + kFactorial, ".", "c.toml");
  const Campaign comment = parse_campaign("# note\n" + kSpeed + kFactorial, ".", "c.toml");
  EXPECT_NE(a.input_hash, comment.input_hash);
  EXPECT_EQ(a.design_hash, comment.design_hash);
  std::string other = kSpeed;
  other.replace(other.find("400.0"), 5, "300.0");
  const Campaign b = parse_campaign(other + kFactorial, ".", "c.toml");
  EXPECT_NE(a.input_hash, b.input_hash);
  EXPECT_NE(a.design_hash, b.design_hash);
  EXPECT_EQ(hex64(0x0123456789abcdefULL), "0123456789abcdef");
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);  // FNV-1a 64 test vector
}

TEST(Campaign, UnknownKeysAndWrongTypesAreNamed) {
  EXPECT_TRUE(rejected(kSpeed + "[desing]\ntype = \"full_factorial\"\n", "desing", "did you mean 'design'"));
  EXPECT_TRUE(rejected(kSpeed + "[design]\ntype = \"full_factorial\"\nsamples = 3\n", "design.samples",
                       "unknown key for full_factorial designs"));
  EXPECT_TRUE(rejected(kSpeed + "[design]\ntype = \"sobol\"\n", "design.type", "is not a design type"));
  EXPECT_TRUE(rejected(kSpeed, "design", "missing"));
  EXPECT_TRUE(rejected(kFactorial, "factors", "at least one"));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_speed_rpm\"\nunit = \"rpm\"\nlevels = \"fast\"\n" + kFactorial,
                       "factors[0].levels", "must be an array"));
  EXPECT_TRUE(rejected("[[factors]]\nkey = \"operating.input_speed_rpm\"\nunit = \"rpm\"\nmin = 1.0\nmax = 2.0\nscale = "
                       "\"ln\"\n" + kFactorial,
                       "factors[0].scale", "must be \"linear\" or \"log\""));
  EXPECT_TRUE(rejected(kSpeed + "[design]\ntype = \"latin_hypercube\"\nsamples = 2.5\n", "design.samples",
                       "must be an integer"));
  EXPECT_TRUE(rejected(kSpeed + kFactorial + "[output]\ntime_history_decimation = -1\n", "output.time_history_decimation",
                       "must be in [0, 1000000]"));
  EXPECT_TRUE(rejected(kSpeed + kFactorial + "[output]\nspectrum_max_frequency_Hz = -1.0\n",
                       "output.spectrum_max_frequency_Hz", "must be >= 0"));
  EXPECT_EQ(parse_campaign(kSpeed + kFactorial + "[output]\nspectrum_max_frequency_Hz = 2e3\n", ".", "c.toml")
                .output.spectrum_max_frequency_Hz,
            2000.0);
  const auto syntax = thrown<InputError>([&] { (void)parse_campaign("[design\n", ".", "c.toml"); });
  ASSERT_TRUE(syntax);
  EXPECT_TRUE(contains(syntax->what(), "c.toml:1:"));
}

TEST(Campaign, DistributionsAndCorrelationParseAndMisspellingsAreNamed) {
  const std::string friction = "[[factors]]\nkey = \"contact.friction_coefficient\"\nunit = \"1\"\n";
  const std::string power = "[[factors]]\nkey = \"operating.input_power_W\"\nunit = \"W\"\n";
  const std::string lhs = "[design]\ntype = \"latin_hypercube\"\nsamples = 64\nseed = 1\n";
  const Campaign c = parse_campaign(friction + "distribution = \"normal\"\nmean = 0.06\nstd_dev = 0.01\nmin = 0.0\n" +
                                        power + "distribution = \"triangular\"\nmin = 500.0\nmode = 1000.0\nmax = 2000.0\n" +
                                        lhs + "correlation = [[1.0, -0.5], [-0.5, 1.0]]\n",
                                    ".", "c.toml");
  EXPECT_EQ(c.factors[0].distribution.kind, DistributionKind::Normal);
  EXPECT_EQ(c.factors[1].distribution.mode, 1000.0);
  EXPECT_EQ(c.design.correlation.size, 2);
  const auto report = rank_correlation_report(c);
  ASSERT_EQ(report.size(), 3u);
  EXPECT_TRUE(contains(report[1], "[-0.500]"));
  EXPECT_TRUE(rejected(friction + "distribution = \"gauss\"\n" + lhs, "factors[0].distribution", "\"normal\""));
  EXPECT_TRUE(rejected(friction + "distribution = \"normal\"\nmean = 0.06\n" + lhs, "factors[0].std_dev", "missing"));
  EXPECT_TRUE(rejected(friction + "min = 0.0\nmax = 0.1\nmean = 0.06\n" + lhs, "factors[0].mean", "not of this one"));
  EXPECT_TRUE(rejected(friction + "distribution = \"triangular\"\nmin = 0.0\nmax = 0.1\n" + lhs, "factors[0].mode",
                       "missing"));
  const std::string two = friction + "min = 0.0\nmax = 0.1\n" + power + "min = 500.0\nmax = 2000.0\n";
  EXPECT_TRUE(rejected(two + lhs + "correlation = [[1.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 1.0]]\n",
                       "design.correlation", "2 factors"));
  EXPECT_TRUE(rejected(two + lhs + "correlation = [[1.0, 0.5], [0.5]]\n", "design.correlation", "square"));
  EXPECT_TRUE(rejected(two + "[design]\ntype = \"saltelli\"\nbase_samples = 8\ncorrelation = [[1.0, 0.5], [0.5, 1.0]]\n",
                       "design.correlation", "saltelli"));
}

TEST(Campaign, ListDesignReadsItsCsvBesideTheCampaign) {
  test::TempDir dir;
  test::write_text(dir / "cases.csv", "operating.input_speed_rpm\n150\n250\n");
  test::write_text(dir / "c.toml", "[[factors]]\nkey = \"operating.input_speed_rpm\"\nunit = \"rpm\"\n[design]\ntype = "
                                   "\"list\"\nfile = \"cases.csv\"\n");
  const Campaign c = read_campaign(dir / "c.toml");
  ASSERT_EQ(c.cases.size(), 2u);
  EXPECT_EQ(c.cases[1].values[0], 250.0);
  EXPECT_EQ(c.design.list_text, "operating.input_speed_rpm\n150\n250\n");
  // The case list is part of the inputs: editing it changes the input hash.
  test::write_text(dir / "cases.csv", "operating.input_speed_rpm\n150\n260\n");
  EXPECT_NE(read_campaign(dir / "c.toml").input_hash, c.input_hash);
}

} // namespace
} // namespace pw::sweep
