// model::validate(): every range check names the TOML key, the value and the
// allowed range; NaN and infinity never pass.
#include "model/validate.hpp"

#include "config/schema.hpp"
#include "core/error.hpp"
#include "model/sensor.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace pw::model {
namespace {

using pw::test::contains;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

/// The InputError validate() throws for the defaults changed by `edit`.
std::optional<InputError> error_after(const std::function<void(SimulationConfig&)>& edit) {
  SimulationConfig c;
  edit(c);
  return test::thrown<InputError>([&] { validate(c); });
}

/// validate() rejects the edit and names `key`.
::testing::AssertionResult rejected_naming(const std::function<void(SimulationConfig&)>& edit,
                                           const std::string& key) {
  const auto e = error_after(edit);
  if (!e) return ::testing::AssertionFailure() << "accepted; expected an error naming " << key;
  if (e->parameter() != key)
    return ::testing::AssertionFailure() << "named '" << e->parameter() << "' instead of '" << key << "': " << e->what();
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult accepted(const std::function<void(SimulationConfig&)>& edit) {
  const auto e = error_after(edit);
  if (e) return ::testing::AssertionFailure() << e->what();
  return ::testing::AssertionSuccess();
}

TEST(Validate, DefaultConfigurationIsValid) { EXPECT_NO_THROW(validate(SimulationConfig{})); }

TEST(Validate, RingBodyHousingPathNeedsTheLateralTorsionalModel) {
  // The torsional model holds the ring fixed: there is no ring translation for ring_body to read.
  const auto e = error_after([](SimulationConfig& c) { c.sensor.housing_path = HousingPath::RingBody; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "sensor.housing_path");
  EXPECT_TRUE(contains(e->what(), "ring_body"));
  EXPECT_TRUE(contains(e->what(), "solver.level"));
  EXPECT_TRUE(contains(e->what(), "lateral_torsional"));
  SimulationConfig lt;
  lt.solver.level = ModelLevel::LateralTorsional;
  lt.sensor.housing_path = HousingPath::RingBody;
  EXPECT_NO_THROW(validate(lt));
}

TEST(Validate, NonPositiveSpeedIsRejectedWithKeyValueAndRange) {
  const auto e = error_after([](auto& c) { c.operating.input_speed_rpm = -5; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "operating.input_speed_rpm");
  EXPECT_TRUE(contains(e->what(), "got -5"));
  EXPECT_TRUE(contains(e->what(), "(0, 100000]"));
  EXPECT_TRUE(contains(e->what(), "rpm"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.operating.input_speed_rpm = 0; }, "operating.input_speed_rpm"));
}

TEST(Validate, NaNAndInfinityAreRejectedInEveryKindOfField) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.operating.input_speed_rpm = kNaN; }, "operating.input_speed_rpm"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.operating.input_power_W = kInf; }, "operating.input_power_W"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stiffness.scale = kNaN; }, "stiffness.scale"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newmark_beta = kNaN; }, "solver.newmark_beta"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.bearings.sun_N_m = kInf; }, "bearings.sun_N_m"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.sun_eccentricity_phase_rad = kNaN; },
                              "imperfections.sun_eccentricity_phase_rad"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.carrier_mass_kg = kNaN; }, "stage.carrier_mass_kg"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.time_step_s = kNaN; }, "solver.time_step_s"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.ring.material.poisson_ratio = kNaN; },
                              "stage.ring.poisson_ratio"));
}

TEST(Validate, GearErrorsCarryTheirSectionPrefix) {
  const auto e = error_after([](auto& c) { c.stage.sun.module_m = 0; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "stage.sun.module_m");
  EXPECT_TRUE(contains(e->what(), "got 0"));
  EXPECT_EQ(std::string(e->what()).find("stage.sun.module_m: module_m"), std::string::npos)
      << "inner prefix kept: " << e->what();
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.ring.teeth = 2; }, "stage.ring.teeth"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet.material.youngs_modulus_Pa = -1; },
                              "stage.planet.youngs_modulus_Pa"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet.pressure_angle_rad = 1.0; },
                              "stage.planet.pressure_angle_rad"));
}

TEST(Validate, GearKindsAreFixedBySection) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.ring.kind = geometry::GearKind::External; }, "stage.ring"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.sun.kind = geometry::GearKind::Internal; }, "stage.sun"));
}

TEST(Validate, PlanetCountAndAnglesMustAgree) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet_count = 0; }, "stage.planet_count"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet_angles_rad = {0.0, 2.0}; }, "stage.planet_angles_rad"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet_angles_rad = {0.1, 2.0, 4.0}; },
                              "stage.planet_angles_rad[0]"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet_angles_rad = {0.0, 4.0, 2.0}; },
                              "stage.planet_angles_rad[2]"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.planet_angles_rad = {0.0, 2.0, 7.0}; },
                              "stage.planet_angles_rad[2]"));
  EXPECT_TRUE(accepted([](auto& c) { c.stage.planet_angles_rad = {0.0, 2.0, 4.0}; }));
}

TEST(Validate, ZeroMeansDerivedButNegativeInertiaIsRejected) {
  EXPECT_TRUE(accepted([](auto& c) { c.stage.carrier_inertia_kgm2 = 0.0; }));
  EXPECT_TRUE(accepted([](auto& c) { c.stage.carrier_inertia_kgm2 = 0.05; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stage.carrier_inertia_kgm2 = -1; }, "stage.carrier_inertia_kgm2"));
}

TEST(Validate, ToothModifierIndicesMustExist) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.teeth = {{Body::Sun, 0, 21, 0.5, 0}}; },
                              "imperfections.teeth[0].tooth"));
  EXPECT_TRUE(accepted([](auto& c) { c.imperfections.teeth = {{Body::Sun, 0, 20, 0.5, 0}}; }));
  EXPECT_TRUE(accepted([](auto& c) { c.imperfections.teeth = {{Body::Ring, 0, 80, 0.5, 0}}; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.teeth = {{Body::Ring, 0, 81, 0.5, 0}}; },
                              "imperfections.teeth[0].tooth"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.teeth = {{Body::Planet, 3, 0, 0.5, 0}}; },
                              "imperfections.teeth[0].planet"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.teeth = {{Body::Planet, -1, 0, 0.5, 0}}; },
                              "imperfections.teeth[0].planet"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.teeth = {{Body::Sun, 1, 0, 0.5, 0}}; },
                              "imperfections.teeth[0].planet"));
  EXPECT_TRUE(rejected_naming(
      [](auto& c) { c.imperfections.teeth = {{Body::Sun, 0, 3, 0.5, 0}, {Body::Sun, 0, 4, 0.5, 0}, {Body::Sun, 0, 3, 0.9, 0}}; },
      "imperfections.teeth[2]"));
}

TEST(Validate, StiffnessFactorIsInZeroExclusiveToOne) {
  auto with_factor = [](double f) { return [f](SimulationConfig& c) { c.imperfections.teeth = {{Body::Sun, 0, 0, f, 0}}; }; };
  EXPECT_TRUE(rejected_naming(with_factor(0.0), "imperfections.teeth[0].stiffness_factor"));
  EXPECT_TRUE(rejected_naming(with_factor(1.5), "imperfections.teeth[0].stiffness_factor"));
  EXPECT_TRUE(rejected_naming(with_factor(kNaN), "imperfections.teeth[0].stiffness_factor"));
  EXPECT_TRUE(accepted(with_factor(1.0)));
  EXPECT_TRUE(accepted(with_factor(1e-3)));
}

TEST(Validate, ProfileDeviationIsNonNegativeAndBelowTheModule) {
  auto with_deviation = [](double d) {
    return [d](SimulationConfig& c) { c.imperfections.teeth = {{Body::Planet, 2, 5, 1.0, d}}; };
  };
  EXPECT_TRUE(rejected_naming(with_deviation(-1e-6), "imperfections.teeth[0].profile_deviation_m"));
  EXPECT_TRUE(rejected_naming(with_deviation(3e-3), "imperfections.teeth[0].profile_deviation_m"));
  EXPECT_TRUE(accepted(with_deviation(0.0)));
  EXPECT_TRUE(accepted(with_deviation(2.9e-3)));
}

TEST(Validate, PinErrorsAreNoneOrOnePerPlanet) {
  EXPECT_TRUE(accepted([](auto& c) { c.imperfections.pin_error_m = {1e-5, 0.0, -1e-5}; }));
  const auto e = error_after([](auto& c) { c.imperfections.pin_error_m = {1e-5, 0.0}; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "imperfections.pin_error_m");
  EXPECT_TRUE(contains(e->what(), "got 2 values"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.pin_error_m = {1e-5, kNaN, 0.0}; },
                              "imperfections.pin_error_m[1]"));
}

TEST(Validate, SolverSettingsHaveSensibleRanges) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newmark_beta = 0.0; }, "solver.newmark_beta"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newmark_beta = 0.6; }, "solver.newmark_beta"));
  EXPECT_TRUE(accepted([](auto& c) { c.solver.newmark_beta = 0.5; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newmark_gamma = 0.49; }, "solver.newmark_gamma"));
  EXPECT_TRUE(accepted([](auto& c) { c.solver.newmark_gamma = 1.0; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.min_steps_per_mesh = 7; }, "solver.min_steps_per_mesh"));
  EXPECT_TRUE(accepted([](auto& c) { c.solver.min_steps_per_mesh = 8; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.record_mesh_cycles = 0; }, "solver.record_mesh_cycles"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newton_tolerance = 0; }, "solver.newton_tolerance"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.newton_max_iterations = 0; }, "solver.newton_max_iterations"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.periodicity_tolerance = -1e-6; },
                              "solver.periodicity_tolerance"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.level = static_cast<ModelLevel>(7); }, "solver.level"));
}

TEST(Validate, ExplicitTimeStepMustResolveTheMeshPeriod) {
  // 100 rpm, Zs = 21, Zr = 81: f_mesh = 21*81/102 * 100/60 = 27.79 Hz, T = 36.0 ms.
  const auto e = error_after([](auto& c) { c.solver.time_step_s = 5e-3; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "solver.time_step_s");
  EXPECT_TRUE(contains(e->what(), "0.035978")) << "mesh period not stated";
  EXPECT_TRUE(accepted([](auto& c) { c.solver.time_step_s = 4e-3; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.solver.time_step_s = -1e-5; }, "solver.time_step_s"));
}

TEST(Validate, ContactAndImperfectionMagnitudesAreChecked) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.contact.friction_coefficient = -0.1; }, "contact.friction_coefficient"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.contact.friction_coefficient = 1.0; }, "contact.friction_coefficient"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.contact.mesh_damping_ratio = 1.5; }, "contact.mesh_damping_ratio"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.contact.backlash_sun_planet_m = -1e-6; }, "contact.backlash_sun_planet_m"));
  // 3 mm of backlash with a 3 mm module is a unit slip (mm typed as m).
  EXPECT_TRUE(rejected_naming([](auto& c) { c.contact.backlash_planet_ring_m = 3e-3; }, "contact.backlash_planet_ring_m"));
  EXPECT_TRUE(accepted([](auto& c) { c.contact.mesh_error_sun_planet_m = -5e-6; }));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.torque_ripple_fraction = 1.0; },
                              "imperfections.torque_ripple_fraction"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.imperfections.sun_eccentricity_m = -1e-6; },
                              "imperfections.sun_eccentricity_m"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.stiffness.samples_per_pair = 4; }, "stiffness.samples_per_pair"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.bearings.planet_N_m = 0; }, "bearings.planet_N_m"));
}

// --- [wear] -------------------------------------------------------------------

TEST(Validate, WearMeshCyclesIsZeroForNoWearOrPositiveUpToTenToTheTwelve) {
  EXPECT_EQ(SimulationConfig{}.wear.mesh_cycles, 0.0) << "wear must be off by default";
  const auto e = error_after([](auto& c) { c.wear.mesh_cycles = -1; });
  ASSERT_TRUE(e) << "negative mesh cycles accepted";
  EXPECT_EQ(e->parameter(), "wear.mesh_cycles");
  EXPECT_TRUE(contains(e->what(), "wear.mesh_cycles: must be >= 0 (0 = no wear)"));
  EXPECT_TRUE(contains(e->what(), "got -1"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.mesh_cycles = kNaN; }, "wear.mesh_cycles"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.mesh_cycles = kInf; }, "wear.mesh_cycles"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.mesh_cycles = 2e12; }, "wear.mesh_cycles"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.mesh_cycles = 2e5; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.mesh_cycles = 1e12; }));
}

TEST(Validate, WearCoefficientIsNonNegativeAndBelowTenToTheMinusTen) {
  const auto e = error_after([](auto& c) { c.wear.coefficient_m2_N = -5e-17; });
  ASSERT_TRUE(e) << "negative kappa accepted";
  EXPECT_EQ(e->parameter(), "wear.coefficient_m2_N");
  EXPECT_TRUE(contains(e->what(), "wear.coefficient_m2_N: "));
  EXPECT_TRUE(contains(e->what(), "got -5e-17"));
  EXPECT_TRUE(contains(e->what(), "m^2/N"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.coefficient_m2_N = 1e-10; }, "wear.coefficient_m2_N"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.coefficient_m2_N = kNaN; }, "wear.coefficient_m2_N"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.coefficient_m2_N = 0.0; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.coefficient_m2_N = 9.9e-11; }));
}

TEST(Validate, ArchardKIsNonNegativeAndHardnessPositive) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.archard_K = -1e-4; }, "wear.archard_K"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.archard_K = kNaN; }, "wear.archard_K"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.hardness_Pa = 0.0; }, "wear.hardness_Pa"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.hardness_Pa = -6e9; }, "wear.hardness_Pa"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.hardness_Pa = kInf; }, "wear.hardness_Pa"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.archard_K = 1e-4; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.archard_K = 0.0; }));
}

TEST(Validate, ArchardKOverHardnessObeysTheLimitOfTheWearCoefficient) {
  // K = 0.9, H = 6e9 Pa: kappa = 1.5e-10 m^2/N, as absurd as coefficient_m2_N = 1.5e-10.
  const auto e = error_after([](auto& c) { c.wear.archard_K = 0.9; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "wear.archard_K");
  EXPECT_TRUE(contains(e->what(), "1.5e-10"));
  EXPECT_TRUE(contains(e->what(), "hardness_Pa = 6000000000"));
}

TEST(Validate, ElementsPerFlankIsAtLeastTwoAndAtMostTenThousand) {
  const auto e = error_after([](auto& c) { c.wear.elements_per_flank = 1; });
  ASSERT_TRUE(e) << "one element per flank accepted";
  EXPECT_EQ(e->parameter(), "wear.elements_per_flank");
  EXPECT_TRUE(contains(e->what(), "wear.elements_per_flank: "));
  EXPECT_TRUE(contains(e->what(), "element counts < 2"));
  EXPECT_TRUE(contains(e->what(), "got 1"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.elements_per_flank = 0; }, "wear.elements_per_flank"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.elements_per_flank = 10001; }, "wear.elements_per_flank"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.elements_per_flank = 2; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.elements_per_flank = 10000; }));
}

TEST(Validate, WindowMeshCyclesIsZeroForAutomaticOrPositive) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.window_mesh_cycles = -1; }, "wear.window_mesh_cycles"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.window_mesh_cycles = 0; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.window_mesh_cycles = 30; }));
}

TEST(Validate, SnapshotRecordMeshCyclesIsAtLeastOne) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.snapshot_record_mesh_cycles = 0; },
                              "wear.snapshot_record_mesh_cycles"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.snapshot_record_mesh_cycles = 100001; },
                              "wear.snapshot_record_mesh_cycles"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.snapshot_record_mesh_cycles = 1; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.snapshot_record_mesh_cycles = 250; }));
}

TEST(Validate, MaxIncrementFractionIsInZeroExclusiveToOne) {
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.max_increment_fraction = 0.0; }, "wear.max_increment_fraction"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.max_increment_fraction = 1.01; }, "wear.max_increment_fraction"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.max_increment_fraction = kNaN; }, "wear.max_increment_fraction"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.max_increment_fraction = 1.0; }));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.max_increment_fraction = 1e-3; }));
}

TEST(Validate, MaxWearFractionOfThicknessIsInZeroExclusiveToOneHalf) {
  const auto e = error_after([](auto& c) { c.wear.max_wear_fraction_of_thickness = 0.6; });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "wear.max_wear_fraction_of_thickness");
  EXPECT_TRUE(contains(e->what(), "(0, 0.5]"));
  EXPECT_TRUE(rejected_naming([](auto& c) { c.wear.max_wear_fraction_of_thickness = 0.0; },
                              "wear.max_wear_fraction_of_thickness"));
  EXPECT_TRUE(accepted([](auto& c) { c.wear.max_wear_fraction_of_thickness = 0.5; }));
}

TEST(Validate, SnapshotMeshCyclesAreFiniteNonNegativeAndWithinTheRun) {
  auto with = [](double cycles, std::vector<double> snapshots) {
    return [=](SimulationConfig& c) {
      c.wear.mesh_cycles = cycles;
      c.wear.snapshot_mesh_cycles = snapshots;
    };
  };
  EXPECT_TRUE(accepted(with(2e5, {0.0, 1e5, 2e5})));
  EXPECT_TRUE(accepted(with(2e5, {})));
  const auto e = error_after(with(2e5, {0.0, 3e5}));
  ASSERT_TRUE(e) << "snapshot beyond the end of the run accepted";
  EXPECT_EQ(e->parameter(), "wear.snapshot_mesh_cycles[1]");
  EXPECT_TRUE(contains(e->what(), "got 300000"));
  EXPECT_TRUE(contains(e->what(), "wear.mesh_cycles"));
  EXPECT_TRUE(rejected_naming(with(2e5, {-1.0}), "wear.snapshot_mesh_cycles[0]"));
  EXPECT_TRUE(rejected_naming(with(2e5, {1e5, kNaN}), "wear.snapshot_mesh_cycles[1]"));
  EXPECT_TRUE(rejected_naming(with(0.0, {1.0}), "wear.snapshot_mesh_cycles[0]"));
}

TEST(Validate, TheHousingGainIsBoundedThroughTheMountAtTheMeshFrequency) {
  // config::kMaxSensorGain_m_s2_per_N bounds what the accelerometer hears: G without a mount,
  // G |H(f_m)| with one (model::housing_transfer_gain), f_m the mesh frequency.
  const double top = config::kMaxSensorGain_m_s2_per_N;
  auto gain = [](double g, double mount_Hz) {
    return [=](SimulationConfig& c) {
      c.sensor.gain_m_s2_per_N = g;
      c.sensor.housing_mount_frequency_Hz = mount_Hz;
    };
  };
  EXPECT_TRUE(accepted(gain(top, 0.0)));
  EXPECT_TRUE(rejected_naming(gain(top * (1 + 1e-9), 0.0), "sensor.gain_m_s2_per_N"));
  EXPECT_TRUE(rejected_naming(gain(0.0, 0.0), "sensor.gain_m_s2_per_N"));
  EXPECT_TRUE(rejected_naming(gain(-1.0, 2e4), "sensor.gain_m_s2_per_N"));
  EXPECT_TRUE(rejected_naming(gain(kNaN, 2e4), "sensor.gain_m_s2_per_N"));
  const SimulationConfig d;
  const double fm = mesh_frequency_Hz(d.stage, d.operating.input_speed_rpm);
  const double limit = top / housing_transfer_gain(1.0, 2e4, fm);  // ~ 1e3 (2e4 / f_m)^2
  EXPECT_GT(limit, 1e3 * top);
  EXPECT_TRUE(accepted(gain(0.999 * limit, 2e4)));
  const auto e = error_after(gain(1.001 * limit, 2e4));
  ASSERT_TRUE(e) << "a gain heard above the top through the mount accepted";
  EXPECT_EQ(e->parameter(), "sensor.gain_m_s2_per_N");
  EXPECT_TRUE(contains(e->what(), "through the mount")) << e->what();
  // A soft mount (far below the mesh frequency) is flat there: the bound is G's own again.
  EXPECT_TRUE(rejected_naming(gain(1.01 * top, 1.0), "sensor.gain_m_s2_per_N"));
}

} // namespace
} // namespace pw::model
