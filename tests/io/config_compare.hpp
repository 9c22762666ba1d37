// Field-by-field comparison of SimulationConfig, written out by hand (not
// through io/'s schema) so that a key missing from the reader or writer shows
// up as a difference, and a valid configuration with every field off its
// default.
#pragma once

#include "config/stage.hpp"

#include <gtest/gtest.h>

namespace pw::test {

inline void expect_gear_eq(const geometry::GearSpec& a, const geometry::GearSpec& b, const char* which) {
  SCOPED_TRACE(which);
  EXPECT_EQ(a.teeth, b.teeth);
  EXPECT_EQ(a.module_m, b.module_m);
  EXPECT_EQ(a.pressure_angle_rad, b.pressure_angle_rad);
  EXPECT_EQ(a.profile_shift, b.profile_shift);
  EXPECT_EQ(a.addendum_coef, b.addendum_coef);
  EXPECT_EQ(a.dedendum_coef, b.dedendum_coef);
  EXPECT_EQ(a.root_fillet_coef, b.root_fillet_coef);
  EXPECT_EQ(a.face_width_m, b.face_width_m);
  EXPECT_EQ(a.kind, b.kind);
  EXPECT_EQ(a.material.youngs_modulus_Pa, b.material.youngs_modulus_Pa);
  EXPECT_EQ(a.material.shear_modulus_Pa, b.material.shear_modulus_Pa);
  EXPECT_EQ(a.material.poisson_ratio, b.material.poisson_ratio);
  EXPECT_EQ(a.material.density_kg_m3, b.material.density_kg_m3);
}

/// Exact equality of every field (doubles bit for bit, up to -0 == 0).
inline void expect_config_eq(const model::SimulationConfig& a, const model::SimulationConfig& b) {
  expect_gear_eq(a.stage.sun, b.stage.sun, "stage.sun");
  expect_gear_eq(a.stage.planet, b.stage.planet, "stage.planet");
  expect_gear_eq(a.stage.ring, b.stage.ring, "stage.ring");
  EXPECT_EQ(a.stage.planet_count, b.stage.planet_count);
  EXPECT_EQ(a.stage.planet_angles_rad, b.stage.planet_angles_rad);
  EXPECT_EQ(a.stage.carrier_inertia_kgm2, b.stage.carrier_inertia_kgm2);
  EXPECT_EQ(a.stage.carrier_mass_kg, b.stage.carrier_mass_kg);
  EXPECT_EQ(a.stage.input_inertia_kgm2, b.stage.input_inertia_kgm2);
  EXPECT_EQ(a.stage.output_inertia_kgm2, b.stage.output_inertia_kgm2);
  EXPECT_EQ(a.stage.bore_ratio, b.stage.bore_ratio);

  EXPECT_EQ(a.operating.input_speed_rpm, b.operating.input_speed_rpm);
  EXPECT_EQ(a.operating.input_power_W, b.operating.input_power_W);

  EXPECT_EQ(a.stiffness.samples_per_pair, b.stiffness.samples_per_pair);
  EXPECT_EQ(a.stiffness.include_fillet_foundation, b.stiffness.include_fillet_foundation);
  EXPECT_EQ(a.stiffness.scale, b.stiffness.scale);
  EXPECT_EQ(a.stiffness.mesh_phase, b.stiffness.mesh_phase);
  for (int h = 0; h < model::StiffnessSettings::Harmonics::kCount; ++h) {
    EXPECT_EQ(a.stiffness.sun_planet_harmonics.cos[h], b.stiffness.sun_planet_harmonics.cos[h]);
    EXPECT_EQ(a.stiffness.sun_planet_harmonics.sin[h], b.stiffness.sun_planet_harmonics.sin[h]);
    EXPECT_EQ(a.stiffness.planet_ring_harmonics.cos[h], b.stiffness.planet_ring_harmonics.cos[h]);
    EXPECT_EQ(a.stiffness.planet_ring_harmonics.sin[h], b.stiffness.planet_ring_harmonics.sin[h]);
  }

  EXPECT_EQ(a.contact.friction_coefficient, b.contact.friction_coefficient);
  EXPECT_EQ(a.contact.friction_smoothing_m_s, b.contact.friction_smoothing_m_s);
  EXPECT_EQ(a.contact.mesh_damping_ratio, b.contact.mesh_damping_ratio);
  EXPECT_EQ(a.contact.backlash_sun_planet_m, b.contact.backlash_sun_planet_m);
  EXPECT_EQ(a.contact.backlash_planet_ring_m, b.contact.backlash_planet_ring_m);
  EXPECT_EQ(a.contact.mesh_error_sun_planet_m, b.contact.mesh_error_sun_planet_m);
  EXPECT_EQ(a.contact.mesh_error_planet_ring_m, b.contact.mesh_error_planet_ring_m);
  EXPECT_EQ(a.contact.tip_relief_m, b.contact.tip_relief_m);
  EXPECT_EQ(a.contact.tip_relief_extent, b.contact.tip_relief_extent);
  EXPECT_EQ(a.contact.engagement_ramp, b.contact.engagement_ramp);

  const auto& ia = a.imperfections;
  const auto& ib = b.imperfections;
  EXPECT_EQ(ia.pin_error_m, ib.pin_error_m);
  EXPECT_EQ(ia.sun_eccentricity_m, ib.sun_eccentricity_m);
  EXPECT_EQ(ia.sun_eccentricity_phase_rad, ib.sun_eccentricity_phase_rad);
  EXPECT_EQ(ia.carrier_eccentricity_m, ib.carrier_eccentricity_m);
  EXPECT_EQ(ia.carrier_eccentricity_phase_rad, ib.carrier_eccentricity_phase_rad);
  EXPECT_EQ(ia.torque_ripple_fraction, ib.torque_ripple_fraction);
  EXPECT_EQ(ia.torque_ripple_order, ib.torque_ripple_order);
  EXPECT_EQ(ia.worn_profile_depth_m, ib.worn_profile_depth_m);
  ASSERT_EQ(ia.teeth.size(), ib.teeth.size());
  for (std::size_t i = 0; i < ia.teeth.size(); ++i) {
    SCOPED_TRACE("imperfections.teeth[" + std::to_string(i) + "]");
    EXPECT_EQ(ia.teeth[i].body, ib.teeth[i].body);
    EXPECT_EQ(ia.teeth[i].planet, ib.teeth[i].planet);
    EXPECT_EQ(ia.teeth[i].tooth, ib.teeth[i].tooth);
    EXPECT_EQ(ia.teeth[i].stiffness_factor, ib.teeth[i].stiffness_factor);
    EXPECT_EQ(ia.teeth[i].profile_deviation_m, ib.teeth[i].profile_deviation_m);
  }

  EXPECT_EQ(a.bearings.sun_N_m, b.bearings.sun_N_m);
  EXPECT_EQ(a.bearings.carrier_N_m, b.bearings.carrier_N_m);
  EXPECT_EQ(a.bearings.ring_N_m, b.bearings.ring_N_m);
  EXPECT_EQ(a.bearings.planet_N_m, b.bearings.planet_N_m);
  EXPECT_EQ(a.bearings.ring_torsional_N_m, b.bearings.ring_torsional_N_m);

  EXPECT_EQ(a.solver.level, b.solver.level);
  EXPECT_EQ(a.solver.time_step_s, b.solver.time_step_s);
  EXPECT_EQ(a.solver.min_steps_per_mesh, b.solver.min_steps_per_mesh);
  EXPECT_EQ(a.solver.steps_per_mode_period, b.solver.steps_per_mode_period);
  EXPECT_EQ(a.solver.newmark_beta, b.solver.newmark_beta);
  EXPECT_EQ(a.solver.newmark_gamma, b.solver.newmark_gamma);
  EXPECT_EQ(a.solver.newton_tolerance, b.solver.newton_tolerance);
  EXPECT_EQ(a.solver.newton_max_iterations, b.solver.newton_max_iterations);
  EXPECT_EQ(a.solver.warmup_max_mesh_cycles, b.solver.warmup_max_mesh_cycles);
  EXPECT_EQ(a.solver.periodicity_tolerance, b.solver.periodicity_tolerance);
  EXPECT_EQ(a.solver.record_mesh_cycles, b.solver.record_mesh_cycles);
  EXPECT_EQ(a.solver.engagement_smoothing, b.solver.engagement_smoothing);

  EXPECT_EQ(a.wear.mesh_cycles, b.wear.mesh_cycles);
  EXPECT_EQ(a.wear.coefficient_m2_N, b.wear.coefficient_m2_N);
  EXPECT_EQ(a.wear.archard_K, b.wear.archard_K);
  EXPECT_EQ(a.wear.hardness_Pa, b.wear.hardness_Pa);
  EXPECT_EQ(a.wear.elements_per_flank, b.wear.elements_per_flank);
  EXPECT_EQ(a.wear.window_mesh_cycles, b.wear.window_mesh_cycles);
  EXPECT_EQ(a.wear.max_increment_fraction, b.wear.max_increment_fraction);
  EXPECT_EQ(a.wear.max_wear_fraction_of_thickness, b.wear.max_wear_fraction_of_thickness);
  EXPECT_EQ(a.wear.snapshot_mesh_cycles, b.wear.snapshot_mesh_cycles);
  EXPECT_EQ(a.wear.snapshot_record_mesh_cycles, b.wear.snapshot_record_mesh_cycles);

  EXPECT_EQ(a.sensor.angle_rad, b.sensor.angle_rad);
  EXPECT_EQ(a.sensor.gain_m_s2_per_N, b.sensor.gain_m_s2_per_N);
  EXPECT_EQ(a.sensor.window_width_rad, b.sensor.window_width_rad);
  EXPECT_EQ(a.sensor.housing_path, b.sensor.housing_path);
  EXPECT_EQ(a.sensor.window, b.sensor.window);
  EXPECT_EQ(a.sensor.encoder_bandwidth_Hz, b.sensor.encoder_bandwidth_Hz);
  EXPECT_EQ(a.sensor.encoder_filter_order, b.sensor.encoder_filter_order);
  EXPECT_EQ(a.sensor.sun_encoder_lines, b.sensor.sun_encoder_lines);
  EXPECT_EQ(a.sensor.carrier_encoder_lines, b.sensor.carrier_encoder_lines);
  EXPECT_EQ(a.sensor.sun_encoder_phase_rad, b.sensor.sun_encoder_phase_rad);
  EXPECT_EQ(a.sensor.carrier_encoder_phase_rad, b.sensor.carrier_encoder_phase_rad);
  EXPECT_EQ(a.sensor.housing_mount_frequency_Hz, b.sensor.housing_mount_frequency_Hz);
  EXPECT_EQ(a.sensor.housing_mount_damping_ratio, b.sensor.housing_mount_damping_ratio);

  EXPECT_EQ(a.rig.input_control, b.rig.input_control);
  EXPECT_EQ(a.rig.input_shaft_stiffness_N_m_rad, b.rig.input_shaft_stiffness_N_m_rad);
  EXPECT_EQ(a.rig.input_shaft_damping_N_m_s_rad, b.rig.input_shaft_damping_N_m_s_rad);
  EXPECT_EQ(a.rig.load_control, b.rig.load_control);
  EXPECT_EQ(a.rig.output_shaft_stiffness_N_m_rad, b.rig.output_shaft_stiffness_N_m_rad);
  EXPECT_EQ(a.rig.output_shaft_damping_N_m_s_rad, b.rig.output_shaft_damping_N_m_s_rad);
  EXPECT_EQ(a.rig.load_speed_loop_proportional_N_m_s_rad, b.rig.load_speed_loop_proportional_N_m_s_rad);
  EXPECT_EQ(a.rig.load_speed_loop_integral_N_m_rad, b.rig.load_speed_loop_integral_N_m_rad);
  EXPECT_EQ(a.rig.input_speed_loop_proportional_N_m_s_rad, b.rig.input_speed_loop_proportional_N_m_s_rad);
  EXPECT_EQ(a.rig.input_speed_loop_integral_N_m_rad, b.rig.input_speed_loop_integral_N_m_rad);
}

/// Valid, and every field differs from its default (doubles chosen to need all
/// 17 significant digits, e.g. 0.1 + 0.2).
inline model::SimulationConfig nondefault_config() {
  model::SimulationConfig c;
  auto gear = [](geometry::GearSpec& g, int teeth, double offset) {
    g.teeth = teeth;
    g.module_m = 2.5e-3;
    g.pressure_angle_rad = 0.3490658503988659;  // 20 deg exactly
    g.profile_shift = 0.05 + offset;
    g.addendum_coef = 0.95;
    g.dedendum_coef = 1.2 + offset;
    g.root_fillet_coef = 0.3;
    g.face_width_m = 0.04 + offset / 10;
    g.material.youngs_modulus_Pa = 200e9 + offset * 1e10;
    g.material.shear_modulus_Pa = 78e9 + offset * 1e10;
    g.material.poisson_ratio = 0.29;
    g.material.density_kg_m3 = 7800 + offset * 10;
  };
  gear(c.stage.sun, 19, 0.01);
  gear(c.stage.planet, 29, 0.02);
  gear(c.stage.ring, 77, 0.03);
  c.stage.planet_count = 4;
  c.stage.planet_angles_rad = {0.0, 1.5, 0.1 + 3.0, 4.7};
  c.stage.carrier_inertia_kgm2 = 0.1 / 3;
  c.stage.carrier_mass_kg = 2.5;
  c.stage.input_inertia_kgm2 = 0.02;
  c.stage.output_inertia_kgm2 = 0.5;
  c.stage.bore_ratio = 0.25;

  c.operating.input_speed_rpm = (0.1 + 0.2) * 1000;
  c.operating.input_power_W = 1234.5;

  c.stiffness.samples_per_pair = 150;
  c.stiffness.include_fillet_foundation = false;
  c.stiffness.scale = 0.01;

  c.contact.friction_coefficient = 0.07;
  c.contact.friction_smoothing_m_s = 2e-3;
  c.contact.mesh_damping_ratio = 0.03;
  c.contact.backlash_sun_planet_m = 1e-5;
  c.contact.backlash_planet_ring_m = 2e-5;
  c.contact.mesh_error_sun_planet_m = -3e-6;
  c.contact.mesh_error_planet_ring_m = 4e-6;
  c.contact.tip_relief_m = 5e-6;
  c.contact.tip_relief_extent = 0.5;
  c.contact.engagement_ramp = 0.2;

  c.imperfections.pin_error_m = {1e-5, -1e-5, 0.0, 2e-6};
  c.imperfections.sun_eccentricity_m = 1e-5;
  c.imperfections.sun_eccentricity_phase_rad = 0.5;
  c.imperfections.carrier_eccentricity_m = 2e-5;
  c.imperfections.carrier_eccentricity_phase_rad = -1.0;
  c.imperfections.torque_ripple_fraction = 0.05;
  c.imperfections.torque_ripple_order = 2.0;
  c.imperfections.worn_profile_depth_m = (0.1 + 0.2) * 1e-5;
  c.imperfections.teeth = {{model::Body::Planet, 1, 3, 0.5, 1e-5}, {model::Body::Ring, 0, 76, 0.9, 0.0}};

  c.bearings = {2e8, 3e8, 4e8, 5e8, 6e9};

  c.solver.level = model::ModelLevel::LateralTorsional;
  c.solver.time_step_s = 1e-5;
  c.solver.min_steps_per_mesh = 100;
  c.solver.steps_per_mode_period = 40;
  c.solver.newmark_beta = 0.3;
  c.solver.newmark_gamma = 0.6;
  c.solver.newton_tolerance = 1e-9;
  c.solver.newton_max_iterations = 50;
  c.solver.warmup_max_mesh_cycles = 300;
  c.solver.periodicity_tolerance = 1e-7;
  c.solver.record_mesh_cycles = 12;
  c.solver.engagement_smoothing = false;

  c.wear.mesh_cycles = 2e5 + 0.1;
  c.wear.coefficient_m2_N = (0.1 + 0.2) * 1e-16;
  c.wear.archard_K = 1e-4 / 3;
  c.wear.hardness_Pa = 5.5e9;
  c.wear.elements_per_flank = 48;
  c.wear.window_mesh_cycles = 30;
  c.wear.max_increment_fraction = 0.05;
  c.wear.max_wear_fraction_of_thickness = 0.2;
  c.wear.snapshot_mesh_cycles = {0.0, 1e5 / 3, 2e5};
  c.wear.snapshot_record_mesh_cycles = 250;

  c.sensor.angle_rad = 1.0 / 3;
  c.sensor.gain_m_s2_per_N = 2e-3 / 3;
  c.sensor.window_width_rad = 0.1 + 0.2;
  c.sensor.window = model::SensorWindow::Hann;
  c.sensor.housing_path = model::HousingPath::RingTranslation;
  c.sensor.encoder_bandwidth_Hz = 1000.0 / 3;
  c.sensor.encoder_filter_order = 1;
  c.sensor.housing_mount_frequency_Hz = 1500;
  c.sensor.housing_mount_damping_ratio = 0.03 / 7;

  c.rig.input_control = model::InputControl::Torque;
  c.rig.input_shaft_stiffness_N_m_rad = 2e5 / 3;
  c.rig.input_shaft_damping_N_m_s_rad = 0.1 + 15;
  c.rig.load_control = model::LoadControl::SpeedLoop;
  c.rig.output_shaft_stiffness_N_m_rad = 1e6 / 3;
  c.rig.output_shaft_damping_N_m_s_rad = 60.0 / 7;
  c.rig.load_speed_loop_proportional_N_m_s_rad = 95.0 / 3;
  c.rig.load_speed_loop_integral_N_m_rad = 600.0 / 7;
  return c;
}

} // namespace pw::test
