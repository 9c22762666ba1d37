// Transfer path from the planet-ring meshes to an accelerometer fixed on the
// ring/housing (McFadden & Smith 1985; Inalpolat & Kahraman 2009).
//
// A planet's ring-mesh force reaches a housing sensor at angle phi_s through a
// path whose gain falls with the planet's angular distance from the sensor,
// so the sensor sees each planet as it passes (the "planet-pass" modulation):
//
//   a_s(t) = G sum_i w(wrap(psi_i + theta_c(t) - phi_s)) (F_pr,i(t) - Fbar_pr,i)       (S1)
//
//  * psi_i      carrier angle of planet i (psi_0 = 0), counter-clockwise [rad]
//  * theta_c(t) absolute carrier angle, Omega_c t + perturbation [rad]; planet i
//               is at psi_i + theta_c in the housing frame
//  * phi_s      sensor angle in the housing frame [rad] (SensorSettings::angle_rad)
//  * wrap       to (-pi, pi]
//  * w          window, w(0) = 1 (SensorWindow): wrapped Gaussian of standard
//               deviation sigma, or Hann of half-width sqrt(2 pi) sigma (the
//               same area, so switching the shape keeps the mean gain over a
//               revolution)
//  * Fbar_pr,i  mean of planet i's ring-mesh force over the record: the static
//               load is not vibration
//  * G          gain [m/s^2 per N] (SensorSettings::gain_m_s2_per_N)
//
// With N equal planets whose ring meshes are in phase, the window sum is
// periodic at N f_c, so the mesh harmonics carry sidebands at k f_m +- j N f_c
// (McFadden & Smith's Fig. 3); turning the sensor by d phi delays the
// envelope by d phi / Omega_c.
//
// The second path (SensorSettings::housing_path = ring_translation): a stiff ring
// that moves as one body on a compliant housing (the lumped models of Lin &
// Parker 1999, whose ring has two translations). Planet i pushes the ring along
// its ring mesh's line of action n = sin a' e_r - cos a' e_t at its position
// psi_i + theta_c (docs/derivation.md section 3.2), and a radial sensor at phi_s
// reads the projection of the net force, n . e_r(phi_s) = sin(d_i + a'):
//
//   a_s(t) = G sum_i F_pr,i(t) sin(psi_i + theta_c(t) - phi_s + alpha'_pr)          (S2)
//
//  * alpha'_pr  working pressure angle of the planet-ring mesh [rad]
//  * G          1 / (ring mass) [m/s^2 per N]
//  * F_pr,i     the whole force: static loads are included. Equal loads of equally
//               spaced planets cancel (sum_i sin(2 pi i / N + c) = 0 for N >= 2);
//               unequal ones (a pin error, a runout) turn with the carrier and
//               appear at carrier orders.
// No window: every planet moves the ring wherever it is. With N equal planets in
// phase the mesh lines cancel too, and only what differs between the planets moves
// the ring. The housing mount (its high-pass) applies to either path: the ring on
// its support is the mass on the mount's stiffness.
//
// The third path (housing_path = ring_body, solver.level = lateral_torsional only): the
// lateral-torsional model's ring body itself, (S2)'s net force after the ring's dynamics on its
// support (bearings.ring_N_m) and through the stage's translational modes:
//
//   a_s(t) = G m_r (a_x(t) cos phi_s + a_y(t) sin phi_s)                                  (S3)
//
//  * (a_x, a_y) the ring's translational acceleration in the fixed (housing) frame [m/s^2]
//               (RingBodyAcceleration; the simulation's channels ring/acceleration_x, _y)
//  * m_r        the ring's mass as the model uses it [kg]: G = 1 / m_r reads the ring's own
//               acceleration, and G keeps (S2)'s scale: with the ring's support far below a
//               line, m_r a = sum_i F_pr,i n_i - k_r x_r - c_r v_r ~ sum_i F_pr,i n_i there, (S2).
// Pure functions, no state.
#pragma once

#include "config/stage.hpp"

#include <numbers>
#include <span>
#include <vector>

namespace pw::model {

/// Angle wrapped to (-pi, pi] [rad].
double wrap_angle(double angle_rad);

/// The window w(d) of one shape and width (SensorWindow; width sigma [rad]), its
/// normalization w(0) = 1 computed once: a record's history calls it for every
/// sample and planet (the wrapped Gaussian's five-image normalization had been
/// half of a diagnosis's exp calls, docs/benchmark.md session 27).
class WindowWeight {
public:
  WindowWeight(SensorWindow window, double width_rad);
  /// w(d) in [0, 1] for the angular distance d [rad] of a planet from the sensor
  /// (any angle; wrapped internally).
  double operator()(double distance_rad) const;

private:
  /// An image whose exponent lies this far below a term already in the sum (or the one it is
  /// added to) is below 2^-54 of it, e^-1 to spare: adding it cannot change the double (54 ln 2 + 1).
  static constexpr double kNegligibleExponentGap = 54 * std::numbers::ln2 + 1;
  SensorWindow window_;
  double width_rad_;
  double s2_;        ///< 2 sigma^2 [rad^2]
  double w0_ = 0;    ///< the wrapped Gaussian's image sum at d = 0
  bool outer_images_negligible_ = false;  ///< the images at +-4 pi never change the sum
  double negligible_gap_times_s2_ = 0;    ///< kNegligibleExponentGap s2 [rad^2]
};

/// Window weight w(d) in [0, 1], w(0) = 1, for the angular distance d [rad]
/// of a planet from the sensor (any angle; wrapped internally).
double sensor_window(double distance_rad, SensorWindow window, double width_rad);

/// Eq. (S1) at one instant: `planet_angles_rad` psi_i, `carrier_angle_rad`
/// theta_c, `force_deviation_N` F_pr,i - Fbar_pr,i (one per planet).
/// Returns the housing acceleration [m/s^2].
double housing_acceleration(const SensorSettings& sensor, std::span<const double> planet_angles_rad,
                            double carrier_angle_rad, std::span<const double> force_deviation_N);

/// The ring body's translational acceleration over a record in the fixed (housing) frame, what
/// Eq. (S3) reads: `x_m_s2[k]`, `y_m_s2[k]` at sample k [m/s^2], and the ring's mass [kg].
struct RingBodyAcceleration {
  double mass_kg = 0;
  std::span<const double> x_m_s2, y_m_s2;
};

/// Eq. (S1), (S2) or (S3) (SensorSettings::housing_path) over a record: `carrier_angle_rad[k]` and
/// `ring_force_N[i][k]` (planet i's ring-mesh force at sample k, all as long as the angles),
/// samples `sample_interval_s` apart; `ring_pressure_angle_rad` alpha'_pr enters (S2) only.
/// (S1) subtracts the mean of each planet's force over the record; (S2) takes the whole force;
/// (S3) reads `ring` only (the forces are still checked), which must be as long as the angles.
/// With a housing mount (SensorSettings::housing_mount_frequency_Hz > 0) the result passes
/// the mount's second-order high-pass, started in the periodic steady state of the record
/// (ButterworthFilter::set_periodic_state). Throws std::invalid_argument for mismatched sizes,
/// pw::SolverError for a mount frequency at or above 1 / (2 sample_interval_s).
std::vector<double> housing_acceleration_history(const SensorSettings& sensor,
                                                 std::span<const double> planet_angles_rad,
                                                 double ring_pressure_angle_rad,
                                                 std::span<const double> carrier_angle_rad,
                                                 const std::vector<std::span<const double>>& ring_force_N,
                                                 double sample_interval_s, const RingBodyAcceleration& ring = {});

/// The housing path's gain at frequency `f_Hz` [m/s^2 per N]: `gain` G times the mount's
/// high-pass magnitude, G r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2) with r = f/f0 and zeta the
/// mount's damping ratio (G (f/f0)^2 / sqrt(1 + (f/f0)^4) at the default zeta = 1/sqrt2, the
/// analog second-order Butterworth), the analog prototype whose bilinear image
/// housing_acceleration_history applies (the two agree to (pi f dt)^2
/// relative: 3e-4 at 2 kHz for a 2.8 us step); G itself without a mount (`mount_Hz` = 0).
/// What a recording measures is this product at its lines, not G: with f0 above every line
/// the lines see G (f/f0)^2, and G alone grows as f0^2 (a stiff mount, the housing following
/// its quasi-static deflection), so a bound on G is a bound on the transfer only through it.
double housing_transfer_gain(double gain_m_s2_per_N, double mount_Hz, double f_Hz,
                             double damping_ratio = SensorSettings::kButterworthDampingRatio);

/// A line-counting speed encoder read by the period method (SensorSettings::sun_encoder_lines,
/// carrier_encoder_lines). Its N lines give an edge each time the shaft angle passes a multiple
/// of the line pitch p = 2 pi / N; the counter times the edges, and the speed it reports is the
/// pitch over the time between the last two edges, held until the next edge (the "T method" or
/// period measurement of incremental encoders: Briz, Cancelas and Diez, IEEE Trans. Instrum.
/// Meas. 43 (1994) 509; Petrella, Tursini, Peretti and Zigliotto, IEEE Trans. Ind. Electron. 54
/// (2007) 2594). That is the speed averaged over each pitch of angle, sampled N times per shaft
/// revolution: a speed line at shaft order o (o < N/2) is attenuated by the pitch average,
/// |sinc(o/N)| (sinc x = sin(pi x)/(pi x)), and appears again at the images k N +- o with the
/// attenuation sinc(o/N) as well (angle-domain sampling; a zero-order hold in time on top).
/// On a planetary stage the j-th mesh harmonic is the sun shaft's order j Zs Zr/(Zs + Zr); its
/// image N - j Zs Zr/(Zs + Zr) is carrier order N (Zs + Zr)/Zs - j Zr, in general not an order
/// of any gear family (a 1000-line sun encoder on 35/75 teeth: 3142.86 - 75 j, e.g. 142.86 for
/// j = 40), and the mesh harmonics near N carry strong images down into the analysed band.
///
/// Edge times are found inside each time step on the cubic Hermite interpolant of the angle
/// through both ends' angles and speeds (error O(dt^4) in the angle against linear
/// interpolation's O(dt^2): test LineEncoder.ReportsThePitchOverTheTimeBetweenItsLastTwoEdges…
/// fails with the linear estimate alone), by Newton's method from the linear estimate. Edges are counted forward only:
/// a shaft turning back gives no edge until it passes its last counted one again. The counter's
/// clock (the resolution of the edge times) is not modelled: it adds broadband quantization
/// noise, which the diagnosis measures with the recording's own noise.
class LineEncoder {
public:
  /// lines = 0: an ideal encoder (passes() == true); its lines at phase_rad + n 2 pi / lines.
  /// Throws std::invalid_argument for lines < 0 or a phase that is not finite.
  explicit LineEncoder(int lines, double phase_rad = 0.0);
  /// True when the encoder reports the true speed (no lines given).
  bool passes() const { return lines_ == 0; }
  /// Starts at time t [s] with the shaft at angle [rad] turning at speed [rad/s]: the last edge
  /// where a constant speed would have put it, the held speed that speed.
  void start(double t_s, double angle_rad, double speed_rad_s);
  /// Advances to time t [s] with the shaft's angle [rad] and speed [rad/s] there (the previous
  /// call's values are the step's start) and returns the speed the encoder reports [rad/s].
  double step(double t_s, double angle_rad, double speed_rad_s);

private:
  /// Time of the angle `target_rad` inside the current step [t_, t_s] (cubic Hermite, Newton).
  double crossing_time(double target_rad, double t_s, double angle_rad, double speed_rad_s) const;
  int lines_ = 0;
  double phase_rad_ = 0;  ///< angle of line 0 [rad]
  double pitch_rad_ = 0, inv_pitch_ = 0;
  double t_ = 0, angle_ = 0, speed_ = 0;  ///< the last sample
  double next_edge_ = 0;                  ///< index of the next edge: its angle is phase + next_edge_ * pitch
  double t_edge_ = 0;                     ///< time of the last edge [s]
  double held_ = 0;                       ///< the speed reported [rad/s]
};

/// Which side of its cutoff a ButterworthFilter passes.
enum class FilterPass { Low, High };

/// A speed encoder's bandwidth (SensorSettings::encoder_bandwidth_Hz): a Butterworth
/// low-pass of order 1 or 2, cutoff f_c (-3 dB), discretized at the time step dt by the
/// bilinear transform with the cutoff prewarped, K = tan(pi f_c dt), so that the gain at f_c
/// is exactly 1/sqrt(2) (Oppenheim & Schafer, Discrete-Time Signal Processing, §7.1):
///   order 1: H(z) = K (1 + z^-1) / ((1 + K) + (K - 1) z^-1)
///   order 2: H(z) = K^2 (1 + z^-1)^2 / ((1 + sqrt2 K + K^2) + 2 (K^2 - 1) z^-1 + (1 - sqrt2 K + K^2) z^-2)
/// Unit gain at DC. A cutoff at or above the Nyquist frequency 1/(2 dt) cannot be
/// represented and is what the simulation cannot resolve anyway: the filter is then the
/// identity (passes() == true). Direct form II transposed; one step is 5 multiplications.
/// FilterPass::High (a housing's mount, SensorSettings::housing_mount_frequency_Hz): the same
/// denominators with the numerators (1 - z^-1) and (1 - z^-1)^2 (s -> 1/s before the
/// transform): unit gain at Nyquist, gain (f/f_c)^order far below f_c, zero at DC. A high-pass
/// cutoff at or above Nyquist would stop every frequency the record holds: it throws.
class ButterworthFilter {
public:
  /// bandwidth_Hz = 0: identity. Throws std::invalid_argument for order outside {1, 2},
  /// a negative bandwidth, a non-positive dt, or a high-pass cutoff at or above 1/(2 dt).
  /// damping_ratio (order 2 only): zeta of the denominator s^2 + 2 zeta w_c s + w_c^2; 1/sqrt2 is
  /// the Butterworth filter, a smaller one a resonance of gain 1/(2 zeta) at f_c (a housing's
  /// mount, SensorSettings::housing_mount_damping_ratio). Throws std::invalid_argument for <= 0.
  ButterworthFilter(double bandwidth_Hz, int order, double dt_s, FilterPass pass = FilterPass::Low,
                    double damping_ratio = SensorSettings::kButterworthDampingRatio);
  /// True when the filter passes its input unchanged.
  bool passes() const { return identity_; }
  /// Sets the state to the steady state of a constant input x (the output is x low-pass, 0 high-pass).
  void reset(double x);
  /// Sets the state to the periodic steady state of an input that repeats `period` (one whole
  /// period, at least one sample): the state z with z = Phi z + z_f after the period, Phi the
  /// state transition over it and z_f the response from rest, solved exactly ((I - Phi) is
  /// invertible: both poles lie inside the unit circle). Filtering `period` from there returns
  /// to the same state, so the output has no start transient, however slow the filter: what a
  /// settling run of many 1/(2 pi f_c) would reach.
  void set_periodic_state(std::span<const double> period);
  /// Filters one sample.
  double step(double x) {
    if (identity_) return x;
    const double y = b0_ * x + z1_;
    z1_ = b1_ * x - a1_ * y + z2_;
    z2_ = b2_ * x - a2_ * y;
    return y;
  }
  /// Time after which a transient has decayed below `fraction` of its start [s]: the slowest
  /// pole's envelope exp(-sigma t), sigma = 2 pi f_c (order 1) or 2 pi f_c / sqrt2 (order 2).
  double settling_time_s(double fraction) const;

private:
  bool identity_ = true;
  double sigma_1_s_ = 0;
  double b0_ = 1, b1_ = 0, b2_ = 0, a1_ = 0, a2_ = 0;
  double z1_ = 0, z2_ = 0;
  double dc_gain_ = 1;  ///< H(1): 1 low-pass, 0 high-pass
};

} // namespace pw::model
