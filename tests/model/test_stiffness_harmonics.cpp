// The mesh-stiffness harmonic correction (stiffness.<family>_h<n>_{cos,sin}, config/stage.hpp
// StiffnessSettings::Harmonics; model/planetary_system.cpp): the combined stiffness of a mesh,
// sampled over one mesh cycle of its contact coordinate, changes by exactly the configured
// harmonics times the mean stiffness, keeps its mean, and never loses more than 90 % of what is
// in contact.
#include "model/simulation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

using namespace pw::model;

namespace {

constexpr int kSamples = 240;  // per mesh cycle: exact DFT of harmonics 1..3 (and far beyond)

/// Combined stiffness [N/m] of mesh `mesh` at kSamples times evenly spread over one of its
/// mesh cycles, with every body at rest (the contact geometry alone).
std::vector<double> stiffness_over_one_cycle(const SimulationConfig& c, int mesh) {
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const int n = sys.size();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), v = Eigen::VectorXd::Zero(n), g(n);
  const double period_s = sys.family(mesh).geometry.base_pitch_m / sys.structure().meshes[mesh].nominal_roll_rate_m_s;
  std::vector<double> k;
  for (int i = 0; i < kSamples; ++i) {
    sys.set_roll_reference(q);
    sys.force(period_s * i / kSamples, q, v, g, nullptr, nullptr);
    k.push_back(sys.mesh_states()[mesh].stiffness_N_m);
  }
  return k;
}

/// a_h - i b_h of x over one period: x = a0 + sum_h a_h cos(h w) + b_h sin(h w).
std::complex<double> fourier(const std::vector<double>& x, int h) {
  std::complex<double> z = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    z += x[i] * std::polar(1.0, -h * 2 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(x.size()));
  return 2.0 * z / static_cast<double>(x.size());
}

} // namespace

TEST(StiffnessHarmonics, ChangeEachMeshFamilysStiffnessByExactlyTheConfiguredHarmonicsAndKeepItsMean) {
  SimulationConfig plain;
  SimulationConfig c = plain;
  c.stiffness.sun_planet_harmonics.cos = {0.05, -0.02, 0.01};
  c.stiffness.sun_planet_harmonics.sin = {-0.03, 0.04, 0.0};
  c.stiffness.planet_ring_harmonics.cos = {0.0, 0.06, -0.01};
  c.stiffness.planet_ring_harmonics.sin = {0.08, 0.0, 0.02};
  for (int mesh : {0, 1, 2, 3}) {  // sun-planet and planet-ring meshes of planets 0 and 1
    const auto& h = mesh % 2 == 0 ? c.stiffness.sun_planet_harmonics : c.stiffness.planet_ring_harmonics;
    const std::vector<double> k0 = stiffness_over_one_cycle(plain, mesh), k1 = stiffness_over_one_cycle(c, mesh);
    PreparedStage p = prepare(plain);
    const double kbar = p.dynamics->family(mesh).mean_stiffness_N_m;
    std::vector<double> dk(k0.size());
    double mean0 = 0, mean1 = 0;
    for (std::size_t i = 0; i < k0.size(); ++i) {
      dk[i] = k1[i] - k0[i];
      mean0 += k0[i] / kSamples;
      mean1 += k1[i] / kSamples;
    }
    EXPECT_NEAR(mean1 / mean0, 1.0, 1e-12) << mesh;
    // The change is K sum_n Re[(c_n - i s_n) e^{i n (theta0 + w t)}], theta0 the phase of the mesh's
    // contact coordinate at t = 0: its n-th Fourier coefficient is (c_n - i s_n) e^{i n theta0}.
    // theta0 from the first harmonic; the others must follow with n theta0 (the recurrence).
    const std::complex<double> e1 = fourier(dk, 1) / (kbar * std::complex<double>(h.cos[0], -h.sin[0]));
    EXPECT_NEAR(std::abs(e1), 1.0, 1e-10) << mesh;
    for (int n = 2; n <= 3; ++n) {
      const std::complex<double> want = kbar * std::complex<double>(h.cos[n - 1], -h.sin[n - 1]) * std::pow(e1, n);
      EXPECT_NEAR(std::abs(fourier(dk, n) - want), 0.0, 1e-10 * kbar) << "mesh " << mesh << " harmonic " << n;
    }
    double amplitude_left = 0;
    for (int n = 4; n <= 20; ++n) {  // ... and nothing else changes
      amplitude_left = std::max(amplitude_left, std::abs(fourier(dk, n)));
    }
    EXPECT_LT(amplitude_left, 1e-10 * kbar) << mesh;
  }
}

TEST(StiffnessHarmonics, NeverRemoveMoreThanNinetyPercentOfTheStiffnessInContact) {
  SimulationConfig plain;
  SimulationConfig c = plain;
  c.stiffness.sun_planet_harmonics.cos = {-0.5, -0.5, -0.5};  // the configuration's extremes
  c.stiffness.sun_planet_harmonics.sin = {0.5, -0.5, 0.5};
  const std::vector<double> k0 = stiffness_over_one_cycle(plain, 0), k1 = stiffness_over_one_cycle(c, 0);
  double lowest = 1;
  for (std::size_t i = 0; i < k0.size(); ++i) lowest = std::min(lowest, k1[i] / k0[i]);
  EXPECT_NEAR(lowest, 0.1, 1e-12);  // reached: the correction's trough is -3 K at the extremes
}
