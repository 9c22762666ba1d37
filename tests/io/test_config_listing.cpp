// `keys --format json` and `config --template`: every key, machine-readable;
// the template reads back as the defaults. And the one exit-code mapping.
#include "io/config_listing.hpp"
#include "io/config_toml.hpp"
#include "io/exit_code.hpp"
#include "io/io_error.hpp"

#include "core/error.hpp"
#include "io/config_compare.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <new>

namespace pw::io {
namespace {

using pw::test::contains;

TEST(ConfigListing, TheTemplateReadsBackAsTheDefaults) {
  test::expect_config_eq(parse_config(config_template(), "template.toml"), model::SimulationConfig{});
}

TEST(ConfigListing, TheTemplateShowsEveryKeyWithItsDoc) {
  const std::string t = config_template();
  for (const KeyInfo& k : config_keys()) {
    const std::string name = k.path.substr(k.path.rfind('.') + 1);
    EXPECT_TRUE(contains(t, name + " = " + k.default_value)) << k.path;
    EXPECT_TRUE(contains(t, "# " + k.doc)) << k.path;
  }
  EXPECT_TRUE(contains(t, "[stage.sun]"));
  EXPECT_TRUE(contains(t, "# pressure_angle_deg = "));  // an alternative spelling, not a second value
}

TEST(ConfigListing, KeysJsonListsEveryKeyWithTypeUnitDefaultAndDoc) {
  const auto keys = nlohmann::json::parse(keys_json());
  const auto expected = config_keys();
  ASSERT_EQ(keys.size(), expected.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    EXPECT_EQ(keys[i].at("key"), expected[i].path);
    EXPECT_EQ(keys[i].at("type"), expected[i].type);
    EXPECT_EQ(keys[i].at("default"), expected[i].default_value);
    EXPECT_EQ(keys[i].at("doc"), expected[i].doc);
    EXPECT_TRUE(keys[i].contains("unit"));
  }
  auto unit_of = [&](const std::string& key) {
    for (const auto& k : keys)
      if (k.at("key") == key) return k.at("unit").get<std::string>();
    return std::string("missing");
  };
  EXPECT_EQ(unit_of("operating.input_speed_rpm"), "rpm");
  EXPECT_EQ(unit_of("stage.sun.youngs_modulus_Pa"), "Pa");
  EXPECT_EQ(unit_of("solver.record_mesh_cycles"), "-");
  EXPECT_EQ(unit_of("imperfections.pin_error_m"), "m");
}

TEST(ConfigListing, UnitIsTheLastBracketOfTheDoc) {
  EXPECT_EQ(unit_of_doc("sun speed [rpm]"), "rpm");
  EXPECT_EQ(unit_of_doc("tooth index, 0-based (docs/derivation.md 1.4) [-]"), "-");
  EXPECT_EQ(unit_of_doc("include the fillet-foundation term"), "");
  EXPECT_EQ(unit_of_doc("planet angles psi_i [rad]; [] = equally spaced"), "rad");
  EXPECT_EQ(unit_of_doc("damaged or modified teeth; [] = none"), "");
}

template <class E>
std::exception_ptr as_ptr(const E& e) {
  return std::make_exception_ptr(e);
}

TEST(ExitCode, EachFailureClassHasOneCodeAndThePrefix) {
  EXPECT_EQ(exit_code_of(as_ptr(InputError("k", "bad"))), ExitCode::BadInput);
  EXPECT_EQ(exit_code_of(as_ptr(SolverError("diverged"))), ExitCode::SolverFailure);
  EXPECT_EQ(exit_code_of(as_ptr(IoError("cannot write"))), ExitCode::IoFailure);
  EXPECT_EQ(exit_code_of(as_ptr(std::bad_alloc())), ExitCode::Internal);
  EXPECT_EQ(to_int(ExitCode::Incomplete), 4);
  for (const auto& e : {as_ptr(InputError("k", "bad")), as_ptr(SolverError("diverged")), as_ptr(IoError("x")),
                        as_ptr(std::bad_alloc())})
    EXPECT_TRUE(contains(error_message(e), "planetwear: error: "));
  EXPECT_EQ(error_message(as_ptr(InputError("solver.level", "bad"))), "planetwear: error: solver.level: bad");
}

} // namespace
} // namespace pw::io
