// The test rig around the stage (model::RigSettings, docs/derivation.md §3.6):
// shafts to the input motor and the load machine, ideal speed control, and the
// speed encoders' bandwidth (model::ButterworthFilter). Closed forms: a soft shaft's
// mode against k / J of the rigid stage, the filter's gain against its bilinear
// transfer function, the mean speed that ideal speed control holds.
#include "core/constants.hpp"
#include "core/error.hpp"
#include "geometry/mesh.hpp"
#include "model/sensor.hpp"
#include "model/simulation.hpp"
#include "model/validate.hpp"
#include "simulation_fixture.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <vector>

using namespace pw::model;

namespace {

using pw::kPi;

using pw::test::channel;
using pw::test::fast_seed;
using pw::test::mean;
using pw::test::scalar;

/// Inertia of the rigid stage reflected to the body whose rotation row is `row`:
/// r' M r with the rigid mode r scaled to a unit rotation of that body (Rayleigh).
double reflected_inertia(const PreparedStage& p, const Eigen::RowVectorXd& row) {
  const Eigen::VectorXd r = p.rigid_mode / row.dot(p.rigid_mode);
  return r.dot(p.dynamics->mass() * r);
}

/// Lowest positive natural frequency [Hz].
double lowest_frequency_Hz(const PreparedStage& p) {
  const Eigen::VectorXd& f = p.natural_frequencies_Hz;
  for (Eigen::Index i = 0; i < f.size(); ++i)
    if (f(i) > 1e-6 * f.maxCoeff()) return f(i);
  return NAN;
}

/// Steady-state gain of `filter` for a sinusoid of frequency f [Hz] at step dt: run 40
/// periods of the slowest transient, then take the amplitude of the last whole periods
/// by projection on sin/cos.
double measured_gain(ButterworthFilter filter, double f_Hz, double dt_s) {
  const int per_period = static_cast<int>(std::lround(1.0 / (f_Hz * dt_s)));
  const double t_settle = filter.settling_time_s(1e-14);
  const long settle = static_cast<long>(std::ceil(t_settle / dt_s));
  const long periods = 20;
  const long n = settle + periods * per_period;
  double s = 0, c = 0;
  filter.reset(0.0);
  for (long k = 0; k < n; ++k) {
    const double ph = 2 * kPi * f_Hz * dt_s * static_cast<double>(k);
    const double y = filter.step(std::sin(ph));
    if (k >= n - periods * per_period) {
      s += y * std::sin(ph);
      c += y * std::cos(ph);
    }
  }
  return 2.0 * std::hypot(s, c) / static_cast<double>(periods * per_period);
}

/// |H(e^{j 2 pi f dt})| of the prewarped bilinear Butterworth: the analog magnitude at the
/// warped frequency, 1 / sqrt(1 + (tan(pi f dt) / tan(pi f_c dt))^(2 n)).
double bilinear_butterworth_gain(double f_Hz, double fc_Hz, int order, double dt_s) {
  const double ratio = std::tan(kPi * f_Hz * dt_s) / std::tan(kPi * fc_Hz * dt_s);
  return 1.0 / std::sqrt(1.0 + std::pow(ratio, 2 * order));
}

/// Amplitude of the component at exactly frequency f in `x` sampled at dt, over a
/// record of whole periods of f (no leakage), mean removed.
double amplitude_at(const std::vector<double>& x, double f_Hz, double dt_s) {
  const double m = mean(x);
  std::complex<double> acc = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    acc += (x[k] - m) * std::polar(1.0, -2 * kPi * f_Hz * dt_s * static_cast<double>(k));
  return 2.0 * std::abs(acc) / static_cast<double>(x.size());
}

double sinc(double x) { return x == 0 ? 1.0 : std::sin(kPi * x) / (kPi * x); }

/// The Hann-windowed DTFT of x at frequency f (complex; mean removed).
std::complex<double> hann_dtft(const std::vector<double>& x, double f_Hz, double dt_s) {
  const double m = mean(x);
  const double n = static_cast<double>(x.size());
  std::complex<double> acc = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double w = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(k) / n);
    acc += w * (x[k] - m) * std::polar(1.0, -2 * kPi * f_Hz * dt_s * static_cast<double>(k));
  }
  return acc;
}

/// Amplitude of the component at frequency f in `x` sampled at dt, Hann-windowed (for a line
/// that is not a whole number of periods of the record: its leakage beyond a few bins is
/// negligible), mean removed: 2 |DTFT| over the window's sum.
double hann_amplitude_at(const std::vector<double>& x, double f_Hz, double dt_s) {
  const double n = static_cast<double>(x.size());
  double wsum = 0;
  for (std::size_t k = 0; k < x.size(); ++k) wsum += 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(k) / n);
  return 2.0 * std::abs(hann_dtft(x, f_Hz, dt_s)) / wsum;
}

} // namespace

TEST(ButterworthFilter, GainEqualsTheBilinearButterworthMagnitudeAtEveryFrequency) {
  // Sampled at 20 kHz, cutoff 1 kHz: the steady-state gain of a sinusoid equals the
  // closed form to round-off (the projection over whole periods is exact; 1e-9 covers
  // the 1e-14 of the start transient left and the sum's round-off).
  const double dt = 5e-5, fc = 1000;
  for (int order : {1, 2}) {
    const ButterworthFilter filter(fc, order, dt);
    ASSERT_FALSE(filter.passes());
    for (double f : {50.0, 250.0, 1000.0, 2000.0, 5000.0}) {
      const double g = measured_gain(filter, f, dt);
      EXPECT_NEAR(g, bilinear_butterworth_gain(f, fc, order, dt), 1e-9) << "order " << order << ", f " << f;
    }
    // The -3 dB point sits exactly at the cutoff (prewarping).
    EXPECT_NEAR(measured_gain(filter, fc, dt), 1 / std::sqrt(2.0), 1e-9) << "order " << order;
  }
}

TEST(ButterworthFilter, HoldsAConstantFromResetAndIsTheIdentityWhenIdealOrBeyondNyquist) {
  ButterworthFilter f(300, 2, 1e-4);
  f.reset(12.5);
  // To round-off: the coefficients' DC gain is 1 within a few ulp.
  for (int k = 0; k < 1000; ++k) EXPECT_NEAR(f.step(12.5), 12.5, 1e-12 * 12.5);
  EXPECT_TRUE(ButterworthFilter(0, 2, 1e-4).passes());
  EXPECT_TRUE(ButterworthFilter(5000, 1, 1e-4).passes());   // f_c = Nyquist
  EXPECT_FALSE(ButterworthFilter(4999, 1, 1e-4).passes());
  EXPECT_THROW(ButterworthFilter(100, 3, 1e-4), std::invalid_argument);
}

TEST(ButterworthFilter, PeriodicStateGivesTheSettledOutputFromTheFirstSample) {
  // An input repeating a 97-sample period (a fundamental, its 3rd harmonic and a mean) through
  // a filter whose slowest pole decays by 1/e over 20 periods: the settled reference is the
  // output after a reset and as many periods as the start transient needs to fall below 1e-14
  // (settling_time_s), and set_periodic_state must give it from the first sample, to round-off
  // (1e-9 of the amplitude: (I - Phi) is ill-conditioned by ~1/(sigma T) = 20).
  const int n = 97;
  const double dt = 1e-4;
  std::vector<double> period(n);
  for (int j = 0; j < n; ++j)
    period[static_cast<std::size_t>(j)] =
        std::sin(2 * kPi * j / n) + 0.3 * std::cos(6 * kPi * j / n + 0.4) + 0.05;
  for (const int order : {1, 2}) {
    const double fc = 1.0 / (2 * kPi * 20 * n * dt) * (order == 2 ? std::numbers::sqrt2 : 1.0);
    ButterworthFilter settled(fc, order, dt);
    settled.reset(0.0);
    const int periods = static_cast<int>(std::ceil(settled.settling_time_s(1e-14) / (n * dt)));
    std::vector<double> reference(n);
    for (int k = 0; k < periods; ++k)
      for (int j = 0; j < n; ++j) reference[static_cast<std::size_t>(j)] = settled.step(period[static_cast<std::size_t>(j)]);
    ButterworthFilter started(fc, order, dt);
    started.set_periodic_state(period);
    double amplitude = 0;
    for (const double y : reference) amplitude = std::max(amplitude, std::fabs(y));
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < n; ++j)
        EXPECT_NEAR(started.step(period[static_cast<std::size_t>(j)]), reference[static_cast<std::size_t>(j)],
                    1e-9 * amplitude)
            << "order " << order << ", period " << k << ", sample " << j;
  }
}

TEST(Rig, ASlowEncoderStartsTheRecordInItsPeriodicSteadyState) {
  // 1 Hz at 400 rpm: settling to 1e-12 takes 6.2 s, 694 mesh periods. With the warm-up limited
  // to 100 periods the record starts from the periodic state of one pre-roll period instead
  // (docs/derivation.md §3.6); it must agree with the settled filter of the full pre-roll. Both
  // runs hold the periodic steady state to 1e-11, so their speeds' mesh ripple agrees to the
  // dynamics' own difference (measured 8e-7 of the filtered ripple at 100 rpm), far below the
  // 1.6 % the absolute-speed filter left before (its DC gain is 1 only to 1e-6 at this K).
  SimulationConfig c = fast_seed(4);
  c.sensor.encoder_bandwidth_Hz = 1.0;
  c.solver.periodicity_tolerance = 1e-11;
  c.solver.warmup_max_mesh_cycles = 1000;
  const SimulationResult settled = simulate(c);
  c.solver.warmup_max_mesh_cycles = 100;
  const SimulationResult started = simulate(c);
  // The shortened pre-roll is what made the difference in cost: 600+ mesh periods fewer steps.
  const double steps_per_period = scalar(settled, "steps_per_mesh_period");
  EXPECT_GT(scalar(settled, "time_steps") - scalar(started, "time_steps"), 600 * steps_per_period);
  for (const char* ch : {"sun/speed", "carrier/speed"}) {
    const std::vector<double>& a = channel(settled, ch);
    const std::vector<double>& b = channel(started, ch);
    ASSERT_EQ(a.size(), b.size());
    const auto [lo, hi] = std::minmax_element(a.begin(), a.end());
    double diff = 0;
    for (std::size_t k = 0; k < a.size(); ++k) diff = std::max(diff, std::fabs(a[k] - b[k]));
    EXPECT_LT(diff, 1e-4 * (*hi - *lo)) << ch;
  }
}

TEST(Rig, EncoderBandwidthAttenuatesTheSpeedChannelsMeshHarmonicByTheFilterGainOnly) {
  // The encoder acts on the measured speed only: the mesh forces are unchanged, and the
  // speed's mesh-frequency line is the ideal one times the filter's gain at f_m. Same
  // periodic steady state, so the ratio holds to the periodicity left (~1e-6).
  SimulationConfig c = fast_seed(12);
  const SimulationResult ideal = simulate(c);
  c.sensor.encoder_bandwidth_Hz = 150;  // f_m = 112 Hz at 400 rpm
  const SimulationResult measured = simulate(c);
  const double dt = scalar(ideal, "time_step"), fm = scalar(ideal, "mesh_frequency");
  for (const char* ch : {"sun/speed", "carrier/speed"}) {
    const double a0 = amplitude_at(channel(ideal, ch), fm, dt), a1 = amplitude_at(channel(measured, ch), fm, dt);
    EXPECT_NEAR(a1 / a0, bilinear_butterworth_gain(fm, 150, 2, dt), 1e-4) << ch;
  }
  const double f0 = amplitude_at(channel(ideal, "sun_planet/0/force"), fm, dt);
  const double f1 = amplitude_at(channel(measured, "sun_planet/0/force"), fm, dt);
  EXPECT_NEAR(f1 / f0, 1.0, 1e-4);
}

TEST(Rig, LineCountingEncodersPutEachSpeedLineAtSincSquaredAndAnImageAtTheLineCountMinusItsOrder) {
  // The period method samples the speed's average over each line pitch N times per revolution
  // and holds it (model/sensor.hpp LineEncoder). For a line at shaft order o, with x = o / N:
  // the line itself keeps sinc(x)^2 of its amplitude (pitch average times hold) and an image
  // appears at shaft order N - o with sinc(x) sinc(1 - x) of it. Checked on both shafts at the
  // mesh frequency against the ideal encoder's amplitude (the same run otherwise: the encoder
  // changes no force). Sun 110 lines, carrier 200 lines, few enough that the image of the mesh
  // line lands inside the simulated band, away from every mesh harmonic. Tolerance 1 % (measured
  // 0.003-0.15 %): the closed form is first order in the speed's ripple (1e-3 of the mean here)
  // and the hold switches at the first time step after an edge (a delay jitter of up to dt,
  // 2 pi f dt = 1e-2 at the image, whose mean the average delay takes; its spread only scatters
  // amplitude).
  SimulationConfig c = fast_seed(40);
  const SimulationResult ideal = simulate(c);
  c.sensor.sun_encoder_lines = 110;
  c.sensor.carrier_encoder_lines = 200;
  const SimulationResult measured = simulate(c);
  const double dt = scalar(ideal, "time_step"), fm = scalar(ideal, "mesh_frequency");
  const double zs = c.stage.sun.teeth, zr = c.stage.ring.teeth;
  struct Shaft {
    const char* channel;
    int lines;
    double mesh_order;  // the mesh frequency in orders of this shaft's absolute rotation
  };
  for (const Shaft& s : {Shaft{"sun/speed", 110, zs * zr / (zs + zr)}, Shaft{"carrier/speed", 200, zr}}) {
    const double f_shaft = fm / s.mesh_order;
    const double x = s.mesh_order / s.lines;
    const double a0 = hann_amplitude_at(channel(ideal, s.channel), fm, dt);
    const double line = hann_amplitude_at(channel(measured, s.channel), fm, dt);
    const double image = hann_amplitude_at(channel(measured, s.channel), (s.lines - s.mesh_order) * f_shaft, dt);
    const double image_ideal = hann_amplitude_at(channel(ideal, s.channel), (s.lines - s.mesh_order) * f_shaft, dt);
    EXPECT_NEAR(line / a0, sinc(x) * sinc(x), 0.01 * sinc(x) * sinc(x)) << s.channel;
    EXPECT_NEAR(image / a0, sinc(x) * sinc(1 - x), 0.01 * sinc(x) * sinc(1 - x)) << s.channel;
    EXPECT_LT(image_ideal, 1e-3 * image) << s.channel << ": the image is the encoder's, not the stage's";
  }
  // The forces do not see the encoder.
  EXPECT_EQ(channel(ideal, "sun_planet/0/force"), channel(measured, "sun_planet/0/force"));
}

TEST(Rig, TurningAnEncodersLinesByDeltaTurnsItsImagesByNDeltaAndLeavesTheLinesAlone) {
  // sensor.sun_encoder_phase_rad: the lines sampled a quarter pitch later sample every image a
  // quarter of its period later in the angle domain, a phase of N delta = pi/2 against the
  // speed's own lines, whose phase and amplitude do not move (the first-order picture of
  // model/sensor.hpp; tolerances 0.5 % and 0.02 rad against the 1e-4 and 5e-4 rad measured).
  SimulationConfig c = fast_seed(40);
  c.sensor.sun_encoder_lines = 110;
  const SimulationResult a = simulate(c);
  c.sensor.sun_encoder_phase_rad = 2 * kPi / 110 / 4;
  const SimulationResult b = simulate(c);
  const double dt = scalar(a, "time_step"), fm = scalar(a, "mesh_frequency");
  const double zs = c.stage.sun.teeth, zr = c.stage.ring.teeth;
  const double o = zs * zr / (zs + zr), f_image = (110 - o) * fm / o;
  const std::complex<double> la = hann_dtft(channel(a, "sun/speed"), fm, dt), lb = hann_dtft(channel(b, "sun/speed"), fm, dt);
  const std::complex<double> ia = hann_dtft(channel(a, "sun/speed"), f_image, dt);
  const std::complex<double> ib = hann_dtft(channel(b, "sun/speed"), f_image, dt);
  EXPECT_NEAR(std::abs(lb) / std::abs(la), 1.0, 5e-3);
  EXPECT_NEAR(std::arg(lb / la), 0.0, 0.02);
  EXPECT_NEAR(std::abs(ib) / std::abs(ia), 1.0, 5e-3);
  EXPECT_NEAR(std::fabs(std::arg(ib / ia)), kPi / 2, 0.02) << "the image turns by N delta";
}

TEST(Rig, SoftOutputShaftToASpeedControlledMachineHasTheModeSqrtKOverReflectedInertia) {
  // With the load machine ideally speed-controlled, the shaft holds the whole stage:
  // for k far below the meshes' torsional stiffness the lowest mode is the rigid stage
  // turning on the shaft, omega^2 = k / J_c with J_c = r'Mr (rigid mode per unit carrier
  // rotation). The mesh compliance lowers it by O(k / k_mesh) ~ 1e-5 here: tolerance 1e-4.
  SimulationConfig c = fast_seed();
  const PreparedStage rigid = prepare(c);
  const double J_c = reflected_inertia(rigid, rigid.dynamics->carrier_theta_row());
  c.rig.load_control = LoadControl::Speed;
  c.rig.output_shaft_stiffness_N_m_rad = 20.0;
  const PreparedStage held = prepare(c);
  EXPECT_FALSE(held.dynamics->structure().has_rigid_mode);
  EXPECT_EQ(held.dynamics->size(), rigid.dynamics->size());  // the machine adds no coordinate
  const double f = std::sqrt(20.0 / J_c) / (2 * kPi);
  EXPECT_NEAR(lowest_frequency_Hz(held) / f, 1.0, 1e-4) << "closed form " << f << " Hz";
}

TEST(Rig, ASpeedLoopBehindAShaftGivesTheTwoModesOfStageShaftMachineAndLoop) {
  // A PI speed loop is a spring K_i and a damper K_p from its machine to the speed reference
  // (docs/derivation.md §3.6). Stage J_c (rigid, reflected to the carrier) -- shaft k -- machine
  // J_L -- K_i -- reference: the undamped modes solve det(K - w^2 M) = 0 with
  // M = diag(J_c, J_L), K = [[k, -k], [-k, k + K_i]]. The mesh compliance shifts them by
  // O(k / k_mesh) ~ 1e-5 here: tolerance 1e-4.
  SimulationConfig c = fast_seed();
  const PreparedStage rigid = prepare(c);
  const double J_c = reflected_inertia(rigid, rigid.dynamics->carrier_theta_row());
  const double J_L = 0.05, k = 40.0, K_i = 15.0;
  c.stage.output_inertia_kgm2 = J_L;
  c.rig.output_shaft_stiffness_N_m_rad = k;
  c.rig.load_control = LoadControl::SpeedLoop;
  c.rig.load_speed_loop_integral_N_m_rad = K_i;
  c.rig.load_speed_loop_proportional_N_m_s_rad = 2.0;
  validate(c);
  const PreparedStage p = prepare(c);
  EXPECT_FALSE(p.dynamics->structure().has_rigid_mode);
  EXPECT_EQ(p.dynamics->size(), rigid.dynamics->size() + 1);  // the machine's coordinate
  // w^4 J_c J_L - w^2 (k J_L + (k + K_i) J_c) + k K_i = 0
  const double a = J_c * J_L, b = -(k * J_L + (k + K_i) * J_c), cc = k * K_i;
  const double disc = std::sqrt(b * b - 4 * a * cc);
  const double f1 = std::sqrt((-b - disc) / (2 * a)) / (2 * kPi), f2 = std::sqrt((-b + disc) / (2 * a)) / (2 * kPi);
  const Eigen::VectorXd& f = p.natural_frequencies_Hz;
  EXPECT_NEAR(f(0) / f1, 1.0, 1e-4) << "closed form " << f1 << " Hz";
  EXPECT_NEAR(f(1) / f2, 1.0, 1e-4) << "closed form " << f2 << " Hz";
}

TEST(Rig, ASpeedLoopHoldsTheMeanCarrierSpeedAndItsIntegralCarriesTheLosses) {
  // Integral action: in the periodic steady state the loop's machine turns at exactly the
  // nominal mean speed (to the periodicity tolerance 1e-6 over whole mesh periods), and the
  // integral's mean torque K_i <theta> takes up the friction losses, so the efficiency agrees
  // with the torque-controlled stage's to 1e-3 (as for ideal speed control above). Loop on a
  // rigid machine (on the carrier) and behind a shaft, critically damped at w_n = 2 pi 20 Hz
  // on the train's inertia.
  SimulationConfig base = fast_seed(24);
  const SimulationResult torque_held = simulate(base);
  const PreparedStage rigid = prepare(base);
  const double J_c = reflected_inertia(rigid, rigid.dynamics->carrier_theta_row());
  const double w_n = 2 * kPi * 20;
  for (const double shaft : {0.0, 2e4}) {
    SimulationConfig c = base;
    c.rig.load_control = LoadControl::SpeedLoop;
    c.rig.load_speed_loop_integral_N_m_rad = J_c * w_n * w_n;
    c.rig.load_speed_loop_proportional_N_m_s_rad = 2 * J_c * w_n;
    if (shaft > 0) {
      c.stage.output_inertia_kgm2 = 0.01;
      c.rig.output_shaft_stiffness_N_m_rad = shaft;
      c.rig.output_shaft_damping_N_m_s_rad = 5;
    }
    const SimulationResult r = simulate(c);
    EXPECT_NEAR(mean(channel(r, "carrier/speed")) / scalar(r, "carrier_speed"), 1.0, 1e-6) << "shaft " << shaft;
    EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6) << "shaft " << shaft;
    const double eta = scalar(r, "efficiency"), eta0 = scalar(torque_held, "efficiency");
    EXPECT_LT(eta, 1.0);
    EXPECT_NEAR(eta, eta0, 1e-3) << "shaft " << shaft;
  }
}

TEST(Rig, ATorqueRippleDrivesTheSpeedLoopAsTheRigidTrainsClosedForm) {
  // A torque-controlled motor with ripple a T_s sin(w t), the load machine rigidly on the
  // carrier under a PI loop (K_i, K_p). Far below the first elastic mode (6.7 Hz against
  // 181 Hz) the train turns rigidly: J_s th'' + k_r^2 (K_p th' + K_i th) = a T_s sin(w t),
  // th the sun's angle, J_s the train's inertia reflected to the sun, k_r the carrier turn per
  // sun turn. Sun speed amplitude w a T_s / |k_r^2 K_i - J_s w^2 + i w k_r^2 K_p|. The loop's
  // mode is put at 5 Hz with damping ratio 0.3, so the response differs from a free train's
  // (a T_s / (J_s w)) by a factor 1.6: the loop, not the inertia, decides it. Friction off (its
  // torque ripples with the load). A 0.5 % ripple keeps the speed ripple at 2.7 % of the speed,
  // so the mesh's own modulation stays linear (a 5 % ripple, 27 % of the speed, is 1.6 % off the
  // linear closed form). Tolerance 2e-3: the elastic modes' O((f/f_1)^2) = 1.4e-3, the record's
  // 3 ripple periods being whole only to 1e-3 (1.5e-4 measured).
  SimulationConfig c = fast_seed();
  c.contact.friction_coefficient = 0;
  c.rig.input_control = InputControl::Torque;
  c.imperfections.torque_ripple_fraction = 0.005;
  c.imperfections.torque_ripple_order = 1;
  const PreparedStage rigid = prepare(c);
  const double J_s = reflected_inertia(rigid, rigid.dynamics->sun_theta_row());
  const double k_r = rigid.dynamics->carrier_theta_row().dot(rigid.rigid_mode) /
                     rigid.dynamics->sun_theta_row().dot(rigid.rigid_mode);
  const double J_c = J_s / (k_r * k_r);
  const double w_n = 2 * kPi * 5, zeta = 0.3;
  c.rig.load_control = LoadControl::SpeedLoop;
  c.rig.load_speed_loop_integral_N_m_rad = J_c * w_n * w_n;
  c.rig.load_speed_loop_proportional_N_m_s_rad = 2 * zeta * J_c * w_n;
  const double Omega = c.operating.input_speed_rpm * 2 * kPi / 60, w = Omega;
  const double f_ripple = w / (2 * kPi);
  const PreparedStage p = prepare(c);
  // Whole ripple periods: mesh periods per sun revolution = Z_s (1 - k_r).
  const double cycles_per_period = p.mesh_frequency_Hz / f_ripple;
  c.solver.record_mesh_cycles = static_cast<int>(std::lround(3 * cycles_per_period));
  const SimulationResult r = simulate(c);
  const double T_s = scalar(r, "input_torque"), a = c.imperfections.torque_ripple_fraction;
  const std::complex<double> impedance(k_r * k_r * c.rig.load_speed_loop_integral_N_m_rad - J_s * w * w,
                                       w * k_r * k_r * c.rig.load_speed_loop_proportional_N_m_s_rad);
  const double expected = w * a * T_s / std::abs(impedance);
  const double dt = scalar(r, "time_step");
  const double got = amplitude_at(channel(r, "sun/speed"), f_ripple, dt);
  EXPECT_NEAR(got / expected, 1.0, 2e-3) << "closed form " << expected << " rad/s; free train "
                                         << a * T_s / (J_s * w) << " rad/s";
}

TEST(Rig, UnderConstantPowerARippleReachesTheMeshInTheShareOfTheTrainDownstreamOfTheSun) {
  // The seed's constant-power input T = P / w (1 + a sin(w_r t)) and a constant load torque. Far
  // below the first elastic mode the train turns rigidly: J th'' + c th' = a T_s sin(w_r t), J
  // the train's inertia reflected to the sun, c = P / Omega^2 = T_s / Omega the power law's
  // damping (dT/dw = -T / w). Sun speed amplitude a T_s / |c + i w_r J|. The sun-planet meshes
  // pass on what accelerates the train beyond the sun: N r_bs F_sp = (J - J_sun) th'', so each
  // planet's mesh force ripples by (J - J_sun) w_r |dw_s| / (N r_bs): the meshes carry the share
  // (J - J_sun) w_r / |c + i w_r J| of the ripple torque. Measured here: 0.24 without a load
  // machine (w_r J = 0.17 against c = 0.57 N m s: the power law takes most of the ripple), 0.99
  // with one of 50 times the carrier's own inertia on the carrier (stage.output_inertia_kgm2) --
  // what diagnose's torque_ripple candidate fits the load inertia for
  // (src/diagnose/candidates/torque_ripple.cpp). Friction off (its torque ripples with the
  // load); a 0.5 % ripple keeps the response linear. Tolerance 3e-3: the elastic modes'
  // O((f/f_1)^2) (1.4e-3 at 6.7 Hz against 181 Hz without the machine) and the record's
  // ripple periods being whole only to 1e-3.
  SimulationConfig c = fast_seed();
  c.contact.friction_coefficient = 0;
  c.imperfections.torque_ripple_fraction = 0.005;
  c.imperfections.torque_ripple_order = 1;
  const pw::geometry::StageGeometry g = pw::geometry::make_stage_geometry(c.stage);
  const MassProperties m = mass_properties(c, g);
  const double carrier_own = m.carrier_inertia_kgm2 + c.stage.planet_count * m.planet_mass_kg *
                                                          g.carrier_radius_m * g.carrier_radius_m;
  const double Omega = c.operating.input_speed_rpm * 2 * kPi / 60, w = Omega, f_ripple = w / (2 * kPi);
  for (const double J_load : {0.0, 50 * carrier_own}) {
    SCOPED_TRACE(J_load > 0 ? "with a load machine" : "without a load machine");
    c.stage.output_inertia_kgm2 = J_load;
    const PreparedStage p = prepare(c);
    const double J = reflected_inertia(p, p.dynamics->sun_theta_row());
    const double J_down = J - m.sun_inertia_kgm2;
    c.solver.record_mesh_cycles = static_cast<int>(std::lround(3 * p.mesh_frequency_Hz / f_ripple));
    const SimulationResult r = simulate(c);
    const double T_s = scalar(r, "input_torque"), a = c.imperfections.torque_ripple_fraction;
    const double dw = a * T_s / std::abs(std::complex<double>(T_s / Omega, w * J));
    const double dt = scalar(r, "time_step");
    const double got_w = amplitude_at(channel(r, "sun/speed"), f_ripple, dt);
    EXPECT_NEAR(got_w / dw, 1.0, 3e-3) << "closed form " << dw << " rad/s";
    const double F = J_down * w * dw / (c.stage.planet_count * g.sun.base_radius_m);
    const double got_F = amplitude_at(channel(r, "sun_planet/0/force"), f_ripple, dt);
    EXPECT_NEAR(got_F / F, 1.0, 3e-3) << "closed form " << F << " N";
  }
}

TEST(Rig, SoftInputShaftGivesTheTwoInertiaModeOfMotorAndStage) {
  // Motor J_m on a shaft k to the sun, the stage free (constant load torque): besides the
  // rigid mode, motor against stage, omega^2 = k (1/J_m + 1/J_s), J_s the rigid stage's
  // inertia reflected to the sun. Same O(k / k_mesh) tolerance as above.
  SimulationConfig c = fast_seed();
  const PreparedStage stage_only = prepare(c);
  const double J_s = reflected_inertia(stage_only, stage_only.dynamics->sun_theta_row());
  const double J_m = 0.01, k = 50.0;
  c.stage.input_inertia_kgm2 = J_m;
  c.rig.input_shaft_stiffness_N_m_rad = k;
  const PreparedStage p = prepare(c);
  EXPECT_TRUE(p.dynamics->structure().has_rigid_mode);
  EXPECT_EQ(p.dynamics->size(), stage_only.dynamics->size() + 1);
  const double f = std::sqrt(k * (1 / J_m + 1 / J_s)) / (2 * kPi);
  EXPECT_NEAR(lowest_frequency_Hz(p) / f, 1.0, 1e-4) << "closed form " << f << " Hz";
}

TEST(Rig, IdealSpeedControlHoldsTheMeanCarrierSpeedAndTheShaftCarriesTheLosses) {
  // No speed loop in the warm-up: the shaft to the machine at the nominal speed holds the
  // mean speed by itself (the angle perturbation stays bounded). Over whole mesh periods of
  // the periodic steady state the mean speeds are nominal to the periodicity tolerance 1e-6.
  // The load torque is then the feed-forward plus the shaft's mean twist; the friction
  // losses, hence the efficiency, agree with the torque-controlled stage to 1e-3 (the shaft
  // changes the dynamics, not the sliding).
  SimulationConfig c = fast_seed(24);
  const SimulationResult torque_held = simulate(c);
  c.rig.load_control = LoadControl::Speed;
  c.rig.output_shaft_stiffness_N_m_rad = 2e4;
  c.rig.output_shaft_damping_N_m_s_rad = 5;
  const SimulationResult r = simulate(c);
  const double w_c = scalar(r, "carrier_speed"), w_s = scalar(r, "sun_speed");
  EXPECT_NEAR(mean(channel(r, "carrier/speed")) / w_c, 1.0, 1e-6);
  EXPECT_NEAR(mean(channel(r, "sun/speed")) / w_s, 1.0, 1e-6);
  const double eta = scalar(r, "efficiency"), eta0 = scalar(torque_held, "efficiency");
  EXPECT_LT(eta, 1.0);
  EXPECT_NEAR(eta, eta0, 1e-3);
}

TEST(Rig, SoftInputShaftToASpeedControlledMotorHasTheModeSqrtKOverTheTrainsInertia) {
  // The motor ideally speed-controlled (rig.input_control = "speed"), the load torque-controlled:
  // the input shaft holds the whole train, whose lowest mode is the rigid stage turning on it,
  // omega^2 = k / J_s with J_s the train's inertia reflected to the sun (rigid mode per unit sun
  // rotation). Same O(k / k_mesh) tolerance as the output side's.
  SimulationConfig c = fast_seed();
  const PreparedStage free_train = prepare(c);
  const double J_s = reflected_inertia(free_train, free_train.dynamics->sun_theta_row());
  c.rig.input_control = InputControl::Speed;
  c.rig.input_shaft_stiffness_N_m_rad = 20.0;
  validate(c);
  const PreparedStage held = prepare(c);
  EXPECT_FALSE(held.dynamics->structure().has_rigid_mode);
  EXPECT_EQ(held.dynamics->size(), free_train.dynamics->size());  // the motor adds no coordinate
  const double f = std::sqrt(20.0 / J_s) / (2 * kPi);
  EXPECT_NEAR(lowest_frequency_Hz(held) / f, 1.0, 1e-4) << "closed form " << f << " Hz";
}

TEST(Rig, AMotorThatHoldsTheSpeedTakesUpTheLossesAndTheLoadKeepsItsTorque) {
  // Input speed control, ideal (through a shaft) or a PI loop (on the sun, motor rigid): the mean
  // speeds are nominal to the periodicity tolerance 1e-6; the load keeps the nominal torque
  // P / Omega_c; the motor's torque is P / Omega_s plus what its speed control adds, the friction
  // losses, so the efficiency T_L Omega_c / (T_s Omega_s) agrees with the torque-controlled
  // stage's to 1e-3 (the losses are ~2 % of the power and the mesh forces differ by as much,
  // so the loss fraction differs by ~4e-4).
  SimulationConfig base = fast_seed(24);
  const SimulationResult torque_held = simulate(base);
  const PreparedStage rigid = prepare(base);
  const double J_s = reflected_inertia(rigid, rigid.dynamics->sun_theta_row());
  const double w_n = 2 * kPi * 20;
  for (const InputControl control : {InputControl::Speed, InputControl::SpeedLoop}) {
    SimulationConfig c = base;
    c.rig.input_control = control;
    if (control == InputControl::Speed) {
      c.rig.input_shaft_stiffness_N_m_rad = 2e3;
      c.rig.input_shaft_damping_N_m_s_rad = 0.5;
    } else {
      c.rig.input_speed_loop_integral_N_m_rad = J_s * w_n * w_n;
      c.rig.input_speed_loop_proportional_N_m_s_rad = 2 * J_s * w_n;
    }
    validate(c);
    const SimulationResult r = simulate(c);
    const char* name = control == InputControl::Speed ? "speed" : "speed_loop";
    EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6) << name;
    EXPECT_NEAR(mean(channel(r, "carrier/speed")) / scalar(r, "carrier_speed"), 1.0, 1e-6) << name;
    const double P = c.operating.input_power_W;
    EXPECT_DOUBLE_EQ(scalar(r, "load_torque"), P / scalar(r, "carrier_speed")) << name;
    EXPECT_GT(scalar(r, "input_torque"), P / scalar(r, "sun_speed")) << name;  // it supplies the losses
    EXPECT_NEAR(mean(channel(r, "sun/input_torque")) / scalar(r, "input_torque"), 1.0, 1e-6) << name;
    const double eta = scalar(r, "efficiency"), eta0 = scalar(torque_held, "efficiency");
    EXPECT_LT(eta, 1.0);
    EXPECT_NEAR(eta, eta0, 1e-3) << name;
  }
}

TEST(Rig, TheSpeedControlsActAlikeInTheLateralTorsionalModel) {
  // The rig's springs are the same at either model level (dynamics::add_rig). Lateral-torsional
  // (Lin & Parker), seed stage: a soft output shaft to an ideally speed-controlled machine gives
  // the rigid stage's mode omega^2 = k / J_c (bearings of 1e8 N/m and meshes of ~1e9 N/m shift it
  // by O(k / k) ~ 1e-7: tolerance 1e-4); a motor's PI loop holds the mean sun speed to the
  // periodicity tolerance and the efficiency agrees with the torque-controlled stage's to 1e-3.
  SimulationConfig base = fast_seed(24);
  base.solver.level = ModelLevel::LateralTorsional;
  const PreparedStage rigid = prepare(base);
  const double J_c = reflected_inertia(rigid, rigid.dynamics->carrier_theta_row());
  const double J_s = reflected_inertia(rigid, rigid.dynamics->sun_theta_row());
  SimulationConfig held = base;
  held.rig.load_control = LoadControl::Speed;
  held.rig.output_shaft_stiffness_N_m_rad = 20.0;
  const double f = std::sqrt(20.0 / J_c) / (2 * kPi);
  EXPECT_NEAR(lowest_frequency_Hz(prepare(held)) / f, 1.0, 1e-4) << "closed form " << f << " Hz";

  const SimulationResult torque_held = simulate(base);
  SimulationConfig loop = base;
  const double w_n = 2 * kPi * 20;
  loop.rig.input_control = InputControl::SpeedLoop;
  loop.rig.input_speed_loop_integral_N_m_rad = J_s * w_n * w_n;
  loop.rig.input_speed_loop_proportional_N_m_s_rad = 2 * J_s * w_n;
  validate(loop);
  const SimulationResult r = simulate(loop);
  EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6);
  EXPECT_NEAR(scalar(r, "efficiency"), scalar(torque_held, "efficiency"), 1e-3);
}

TEST(Rig, AHeavyMotorOnASoftInputShaftReachesTheNominalMeanSpeed) {
  // A 6 kg m^2 motor (1e4 times the sun's disc) on a 2000 N m/rad shaft, 0.5 N m s/rad: the
  // stage's mode on the shaft sits near the mesh frequency at 400 rpm. The warm-up's speed loop
  // must act on the rigid mode's own speed, not on the sun's, which carries that slow mode
  // (docs/derivation.md §3.6): acting on the sun's speed with the whole train's inertia (the
  // motor included) diverged (Newton failed at t = 0.126 s). Over whole mesh periods of the
  // periodic steady state the mean sun speed is nominal to the periodicity tolerance 1e-6.
  SimulationConfig c = fast_seed(24);
  c.stage.input_inertia_kgm2 = 6.0;
  c.rig.input_shaft_stiffness_N_m_rad = 2000.0;
  c.rig.input_shaft_damping_N_m_s_rad = 0.5;
  const SimulationResult r = simulate(c);
  EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6);
  EXPECT_LT(scalar(r, "periodicity_residual"), c.solver.periodicity_tolerance);
}

TEST(Rig, ATorqueControlledMotorReachesTheNominalMeanSpeedWithAndWithoutAShaft) {
  // rig.input_control = "torque": T_s = P / Omega_s at any speed, so the rigid mode has no speed
  // feedback of its own and the warm-up's load-torque update alone holds the speed. The update
  // once carried the constant-power term T_s (mean w / Omega - 1) for this motor too and
  // diverged (the seed case: sun speed -8e16 rad/s after 10 mesh periods, then Newton failed).
  // Steady state: mean sun speed nominal to the periodicity tolerance, and the input torque the
  // constant P / Omega_s.
  for (const double shaft : {0.0, 2000.0}) {
    SimulationConfig c = fast_seed(24);
    c.rig.input_control = InputControl::Torque;
    if (shaft > 0) {
      c.stage.input_inertia_kgm2 = 6.0;
      c.rig.input_shaft_stiffness_N_m_rad = shaft;
      c.rig.input_shaft_damping_N_m_s_rad = 0.5;
    }
    const SimulationResult r = simulate(c);
    EXPECT_NEAR(mean(channel(r, "sun/speed")) / scalar(r, "sun_speed"), 1.0, 1e-6) << "shaft " << shaft;
    EXPECT_LT(scalar(r, "periodicity_residual"), c.solver.periodicity_tolerance) << "shaft " << shaft;
  }
}

TEST(Rig, VeryStiffShaftsApproachTheRigidlyCoupledMachines) {
  // The rigid coupling (stage.input/output_inertia_kgm2 added to sun and carrier) is the
  // limit of stiff shafts: every natural frequency of the rigid model reappears, shifted by
  // O((f_i / f_shaft)^2); with k = 1e11 N m/rad the shaft modes sit above 300 kHz and the
  // stage's (at most 7.2 kHz) move by < 1e-4 relative. The two extra modes are the shafts'.
  SimulationConfig c = fast_seed();
  c.stage.input_inertia_kgm2 = 0.002;
  c.stage.output_inertia_kgm2 = 0.05;
  const PreparedStage rigid = prepare(c);
  c.rig.input_shaft_stiffness_N_m_rad = 1e11;
  c.rig.output_shaft_stiffness_N_m_rad = 1e11;
  const PreparedStage shafts = prepare(c);
  const Eigen::VectorXd& f0 = rigid.natural_frequencies_Hz;
  const Eigen::VectorXd& f1 = shafts.natural_frequencies_Hz;
  ASSERT_EQ(f1.size(), f0.size() + 2);
  for (Eigen::Index i = 1; i < f0.size(); ++i) EXPECT_NEAR(f1(i) / f0(i), 1.0, 1e-4) << "mode " << i;
  EXPECT_GT(f1(f1.size() - 2), 10 * f0.maxCoeff());
}

TEST(Rig, ShaftWithoutAMachineInertiaSpeedControlWithoutAShaftOrALoopWithoutItsGainsIsAnInputErrorNamingTheKey) {
  SimulationConfig c = fast_seed();
  c.rig.input_shaft_stiffness_N_m_rad = 1e5;
  try {
    validate(c);
    FAIL() << "accepted a motor without inertia behind a shaft";
  } catch (const pw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.input_shaft_stiffness_N_m_rad"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("stage.input_inertia_kgm2"), std::string::npos) << e.what();
  }
  c = fast_seed();
  c.rig.load_control = LoadControl::Speed;
  try {
    validate(c);
    FAIL() << "accepted speed control through a rigid shaft";
  } catch (const pw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.output_shaft_stiffness_N_m_rad"), std::string::npos) << e.what();
  }
  c = fast_seed();
  c.sensor.encoder_filter_order = 3;
  EXPECT_THROW(validate(c), pw::InputError);
  // A speed loop needs both gains; a gain without the loop would be ignored, so it is refused.
  c = fast_seed();
  c.rig.load_control = LoadControl::SpeedLoop;
  c.rig.load_speed_loop_proportional_N_m_s_rad = 10;
  try {
    validate(c);
    FAIL() << "accepted a speed loop without integral gain";
  } catch (const pw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.load_speed_loop_integral_N_m_rad"), std::string::npos) << e.what();
  }
  c = fast_seed();
  c.rig.input_control = InputControl::Speed;
  c.rig.input_shaft_stiffness_N_m_rad = 1e4;
  c.rig.load_control = LoadControl::Speed;
  c.rig.output_shaft_stiffness_N_m_rad = 1e4;
  try {
    validate(c);
    FAIL() << "accepted two machines holding the speed";
  } catch (const pw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.load_control"), std::string::npos) << e.what();
  }
  c = fast_seed();
  c.rig.load_speed_loop_integral_N_m_rad = 100;
  try {
    validate(c);
    FAIL() << "accepted a speed-loop gain under torque control";
  } catch (const pw::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rig.load_speed_loop_integral_N_m_rad"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("speed_loop"), std::string::npos) << e.what();
  }
}

TEST(Rig, StatedSunAndRingMassPropertiesReplaceTheDerivedOnesAndARigidMotorAddsToTheSun) {
  // stage.sun_* and stage.ring_* (0 = derived) state what turns with the gear (a sun shaft or hub,
  // a ring's housing); a motor on a rigid input shaft still adds to the sun's stated inertia.
  SimulationConfig c = fast_seed();
  const pw::geometry::StageGeometry g = pw::geometry::make_stage_geometry(c.stage);
  const MassProperties derived = mass_properties(c, g);
  c.stage.sun_inertia_kgm2 = 3 * derived.sun_inertia_kgm2;
  c.stage.sun_mass_kg = 3 * derived.sun_mass_kg;
  c.stage.ring_inertia_kgm2 = 2 * derived.ring_inertia_kgm2;
  c.stage.ring_mass_kg = 2 * derived.ring_mass_kg + 5.0;
  const MassProperties stated = mass_properties(c, g);
  EXPECT_EQ(stated.sun_inertia_kgm2, 3 * derived.sun_inertia_kgm2);
  EXPECT_EQ(stated.sun_mass_kg, 3 * derived.sun_mass_kg);
  EXPECT_EQ(stated.ring_inertia_kgm2, 2 * derived.ring_inertia_kgm2);
  EXPECT_EQ(stated.ring_mass_kg, 2 * derived.ring_mass_kg + 5.0);
  EXPECT_EQ(stated.planet_inertia_kgm2, derived.planet_inertia_kgm2) << "the planets stay derived";
  c.stage.input_inertia_kgm2 = 0.01;  // rigid input shaft: the motor turns with the sun
  EXPECT_DOUBLE_EQ(mass_properties(c, g).sun_inertia_kgm2, 3 * derived.sun_inertia_kgm2 + 0.01);
}
