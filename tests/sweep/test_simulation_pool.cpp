// The diagnosis's simulation pool ships order spectra between ranks as bytes; a
// diagnosis is rank-count independent only if they arrive bit-identical.
#include "sweep/simulation_pool.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace pw::sweep {
namespace {

diagnose::ModelSpectra sample_spectra() {
  diagnose::ModelSpectra s;
  s.amplitude = {{0.0, 1.0 / 3.0, 2e-300}, {}, {std::numeric_limits<double>::denorm_min(), -0.0}};
  s.mean_input_rpm = 1199.999999999;
  s.time_step_s = 2.5e-6;
  s.steps_per_mesh = 173;
  s.warmup_mesh_cycles = 412;
  s.ring_force = {{1.0, -2.0}, {3.5}, {}};
  s.carrier_angle = {0.0, std::nextafter(1.0, 2.0)};
  s.planet_angles_rad = {0.0, 2.0943951023931953, 4.1887902047863905};
  s.angle_theta = {0.0, 1e-9};
  s.leak_variance = {{0.25, 1e-310}, {}, {3.0}};
  s.ring_pressure_angle_rad = 0.3937;
  s.ring_acceleration_x = {0.5, -1e-200};
  s.ring_acceleration_y = {std::nextafter(2.0, 3.0), 0.0};
  s.ring_mass_kg = 1.0 / 3.0;
  return s;
}

TEST(SimulationPool, SpectraSurviveTheRoundTripBitForBit) {
  const diagnose::ModelSpectra a = sample_spectra();
  const std::vector<char> bytes = encode_spectra(a);
  const diagnose::ModelSpectra b = decode_spectra(bytes);
  EXPECT_EQ(a.amplitude, b.amplitude);
  EXPECT_TRUE(std::signbit(b.amplitude[2][1]));  // -0.0 stays negative: bits, not values, travel
  EXPECT_EQ(a.mean_input_rpm, b.mean_input_rpm);
  EXPECT_EQ(a.time_step_s, b.time_step_s);
  EXPECT_EQ(a.steps_per_mesh, b.steps_per_mesh);
  EXPECT_EQ(a.warmup_mesh_cycles, b.warmup_mesh_cycles);
  EXPECT_EQ(a.ring_force, b.ring_force);
  EXPECT_EQ(a.carrier_angle, b.carrier_angle);
  EXPECT_EQ(a.planet_angles_rad, b.planet_angles_rad);
  EXPECT_EQ(a.angle_theta, b.angle_theta);
  EXPECT_EQ(a.leak_variance, b.leak_variance);
  // The housing paths' inputs: ring_translation's pressure angle, ring_body's accelerations and mass.
  EXPECT_EQ(a.ring_pressure_angle_rad, b.ring_pressure_angle_rad);
  EXPECT_EQ(a.ring_acceleration_x, b.ring_acceleration_x);
  EXPECT_EQ(a.ring_acceleration_y, b.ring_acceleration_y);
  EXPECT_EQ(a.ring_mass_kg, b.ring_mass_kg);
}

TEST(SimulationPool, TruncatedBytesAreRejectedNotMisread) {
  std::vector<char> bytes = encode_spectra(sample_spectra());
  bytes.resize(bytes.size() - 4);
  EXPECT_ANY_THROW(decode_spectra(bytes));
}

} // namespace
} // namespace pw::sweep
