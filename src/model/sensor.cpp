#include "model/sensor.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace pw::model {
namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;

/// kTwoPi split into a head of 25 significant bits (its low 27 bits cleared) and the exact rest
/// kTwoPi - head, 23 significant bits: n times either part is exact for |n| < 2^26, so
/// a - n head - n tail is a - n kTwoPi computed exactly (wrap_angle).
constexpr double kTwoPiHead =
    std::bit_cast<double>(std::bit_cast<std::uint64_t>(kTwoPi) & ~((std::uint64_t{1} << 27) - 1));
constexpr double kTwoPiTail = kTwoPi - kTwoPiHead;
/// Largest |a| [rad] wrap_angle reduces itself: |n| <= 2^24 / (2 pi) + 1 < 2^22 turns, far inside
/// the 2^26 the split needs; beyond (and for NaN, the infinities) std::remainder decides.
constexpr double kExactWrapLimit_rad = 0x1p24;

/// std::remainder(a, kTwoPi) wrapped to (-pi, pi], reference for wrap_angle's fast path.
double wrap_by_remainder(double a) {
  double r = std::remainder(a, kTwoPi);  // [-pi, pi]
  if (r <= -kPi) r += kTwoPi;
  return r;
}
} // namespace

double wrap_angle(double a) {
  // The same double as wrap_by_remainder without the library's remainder (glibc's is a bit-wise
  // long division: 53 M of a 1 334 M-instruction record run, where the housing window wraps every
  // sample and planet; callgrind, session 66). The wrapped angle is a - n kTwoPi for an integer n;
  // that exact value is a double (IEEE remainder is exact), and each operation below has an exact
  // result that is a double, so none rounds:
  //  - n is a rounded to the nearest turn via a / kTwoPi, within one rounding of the true quotient:
  //    |a - n kTwoPi| <= pi + a few ulp, so n != 0 needs |a| >= ~pi;
  //  - n kTwoPiHead and n kTwoPiTail are exact (see the split);
  //  - n = 0 leaves a as it is. Otherwise |a| >= 2, so ulp(a) >= 2^-51 (2^-50 for |a| >= 4):
  //  - a - n kTwoPiHead is a multiple of ulp(a) (the head is a multiple of 2^-23) of magnitude
  //    below pi + |n kTwoPiTail| < 4: it fits 53 bits. Subtracting n kTwoPiTail (a multiple of
  //    2^-50) leaves a multiple of min(ulp(a), 2^-50) below pi + a few ulp: fits likewise;
  //  - the last turn added or taken away lands within (-pi, pi], again such a multiple below 4.
  // So r is a - n kTwoPi in (-pi, pi] exactly, the one such double, as remainder's result after
  // the same wrap. A zero result takes a's sign, as remainder's does.
  // Checked bit for bit against wrap_by_remainder on 5.3e8 angles when written (session 69: random
  // over 80 binades, and the eight nearest doubles on each side of k 2 pi and (k + 1/2) 2 pi for
  // |k| <= 2e6); the unit test SensorWindow.WrapAngleIsTheLibraryRemainderBitForBit repeats a subset.
  if (!(std::fabs(a) <= kExactWrapLimit_rad)) return wrap_by_remainder(a);
  const double n = static_cast<double>(static_cast<long long>(a * (1 / kTwoPi) + (a >= 0 ? 0.5 : -0.5)));
  double r = (a - n * kTwoPiHead) - n * kTwoPiTail;
  if (r > kPi)
    r -= kTwoPi;
  else if (r <= -kPi)
    r += kTwoPi;
  return r == 0 ? std::copysign(0.0, a) : r;
}

WindowWeight::WindowWeight(SensorWindow window, double width_rad)
    : window_(window), width_rad_(width_rad), s2_(2 * width_rad * width_rad) {
  // The images' sum at d = 0: the normalization w(0) = 1, the same for every distance.
  for (int k = -2; k <= 2; ++k) {
    const double zk = kTwoPi * k;
    w0_ += std::exp(-zk * zk / s2_);
  }
  // See operator(): the images at +-4 pi are negligible for every distance when their exponent
  // lies 4 pi^2 / sigma^2 (the least gap, at d = +-pi) below their neighbours' by more than
  // kNegligibleExponentGap (sigma below ~1.03 rad; the default is 0.5).
  outer_images_negligible_ = 4 * kPi * kPi / (width_rad * width_rad) > kNegligibleExponentGap;
  negligible_gap_times_s2_ = kNegligibleExponentGap * s2_;
}

double WindowWeight::operator()(double distance_rad) const {
  const double d = wrap_angle(distance_rad);
  if (window_ == SensorWindow::Hann) {
    const double h = std::sqrt(2 * kPi) * width_rad_;  // same area as the Gaussian
    if (std::fabs(d) >= h) return 0.0;
    const double c = std::cos(kPi * d / (2 * h));
    return c * c;
  }
  // Wrapped Gaussian: periodic and smooth for any width; the images at
  // +-2 pi, +-4 pi matter only for wide windows. Normalized to w(0) = 1.
  // The image at 2 pi k; every sum below adds them in the order of k.
  const auto image = [&](int k) {
    const double dk = d + kTwoPi * k;
    return std::exp(-dk * dk / s2_);
  };
  double w = 0;
  if (!outer_images_negligible_) {
    for (int k = -2; k <= 2; ++k) w += image(k);
    return w / w0_;
  }
  // The same sum, bit for bit, without the images that cannot change it (a record's history
  // evaluates this for every sample and planet: 5 exp each were ~6 % of a diagnosis, perf,
  // session 32). Under round-to-nearest a term t >= 0 added to a partial sum S with
  // t < 2^-54 S leaves S unchanged (t is below half an ulp of S). The terms are added in the
  // order k = -2, -1, 0, 1, 2, and with |d| <= pi:
  //  - the k = -2 term is exp(-((d - 4 pi)^2 - (d - 2 pi)^2) / s2) <= exp(-4 pi^2 / sigma^2) times
  //    the k = -1 term it is added to first, the k = 2 term as much below the k = 1 term already
  //    in the sum: negligible for every d when outer_images_negligible_;
  //  - the k = -1 term lies (4 pi^2 - 4 pi d) / s2 below the k = 0 term in the exponent, the
  //    k = 1 term (4 pi^2 + 4 pi d) / s2: each is skipped where that gap exceeds
  //    kNegligibleExponentGap (then every term after the k = 0 one is below 2^-54 of the sum too).
  // The gap's margin (one unit beyond 54 ln 2) covers the rounding of exp and of the exponents.
  if (4 * kPi * (kPi - d) <= negligible_gap_times_s2_) w += image(-1);
  w += image(0);
  if (4 * kPi * (kPi + d) <= negligible_gap_times_s2_) w += image(1);
  return w / w0_;
}

double sensor_window(double distance_rad, SensorWindow window, double width_rad) {
  return WindowWeight(window, width_rad)(distance_rad);
}

namespace {
double housing_acceleration(const SensorSettings& s, const WindowWeight& w, std::span<const double> psi,
                            double theta_c, std::span<const double> dF) {
  double a = 0;
  for (std::size_t i = 0; i < psi.size(); ++i) a += w(psi[i] + theta_c - s.angle_rad) * dF[i];
  return s.gain_m_s2_per_N * a;
}
} // namespace

double housing_acceleration(const SensorSettings& s, std::span<const double> psi, double theta_c,
                            std::span<const double> dF) {
  return housing_acceleration(s, WindowWeight(s.window, s.window_width_rad), psi, theta_c, dF);
}

LineEncoder::LineEncoder(int lines, double phase_rad) : lines_(lines), phase_rad_(phase_rad) {
  if (lines < 0) throw std::invalid_argument("LineEncoder: lines must be >= 0, got " + std::to_string(lines));
  if (!std::isfinite(phase_rad)) throw std::invalid_argument("LineEncoder: the phase must be finite");
  if (lines > 0) {
    pitch_rad_ = kTwoPi / lines;
    inv_pitch_ = lines / kTwoPi;
  }
}

void LineEncoder::start(double t_s, double angle_rad, double speed_rad_s) {
  t_ = t_s;
  angle_ = angle_rad;
  speed_ = speed_rad_s;
  held_ = speed_rad_s;
  if (passes()) return;
  const double last = std::floor((angle_rad - phase_rad_) * inv_pitch_);
  next_edge_ = last + 1;
  // The last edge where a constant speed would have put it; at rest, now.
  t_edge_ = speed_rad_s > 0 ? t_s - (angle_rad - phase_rad_ - last * pitch_rad_) / speed_rad_s : t_s;
}

double LineEncoder::crossing_time(double target_rad, double t_s, double angle_rad, double speed_rad_s) const {
  // theta(s) on s in [0, 1] over the step: the cubic Hermite interpolant of the angles and speeds
  // at both ends; target lies between angle_ and angle_rad (an edge was passed), so a root exists.
  const double h = t_s - t_;
  const double a0 = angle_, a1 = angle_rad, m0 = h * speed_, m1 = h * speed_rad_s;
  const double span = a1 - a0;
  double s = span > 0 ? (target_rad - a0) / span : 1.0;
  constexpr int kNewtonSteps = 3;  // from the linear estimate: quadratic convergence, 1e-15 in three
  for (int it = 0; it < kNewtonSteps; ++it) {
    const double s2 = s * s, s3 = s2 * s;
    const double f = (2 * s3 - 3 * s2 + 1) * a0 + (s3 - 2 * s2 + s) * m0 + (3 * s2 - 2 * s3) * a1 + (s3 - s2) * m1 -
                     target_rad;
    const double df = (6 * s2 - 6 * s) * (a0 - a1) + (3 * s2 - 4 * s + 1) * m0 + (3 * s2 - 2 * s) * m1;
    if (!(df > 0)) break;  // not monotonic here: keep the estimate
    s = std::clamp(s - f / df, 0.0, 1.0);
  }
  return t_ + s * h;
}

double LineEncoder::step(double t_s, double angle_rad, double speed_rad_s) {
  if (passes()) return speed_rad_s;
  const double last = std::floor((angle_rad - phase_rad_) * inv_pitch_);  // the highest edge passed by now
  if (last >= next_edge_) {
    // Only the last two edges matter for the speed reported: earlier ones in this step are
    // overwritten before anyone reads them.
    const double t_last = crossing_time(phase_rad_ + last * pitch_rad_, t_s, angle_rad, speed_rad_s);
    const double t_before = last - 1 >= next_edge_
                                ? crossing_time(phase_rad_ + (last - 1) * pitch_rad_, t_s, angle_rad, speed_rad_s)
                                : t_edge_;
    if (t_last > t_before) held_ = pitch_rad_ / (t_last - t_before);
    t_edge_ = t_last;
    next_edge_ = last + 1;
  }
  t_ = t_s;
  angle_ = angle_rad;
  speed_ = speed_rad_s;
  return held_;
}

double housing_transfer_gain(double gain_m_s2_per_N, double mount_Hz, double f_Hz, double damping_ratio) {
  if (!(mount_Hz > 0)) return gain_m_s2_per_N;
  const double r2 = (f_Hz / mount_Hz) * (f_Hz / mount_Hz);
  // |s^2 / (s^2 + 2 zeta w0 s + w0^2)| at s = i w: r^2 / sqrt((1 - r^2)^2 + (2 zeta r)^2), which
  // is r^2 / sqrt(1 + r^4) at the Butterworth ratio, kept in that form (the same doubles as before
  // the damping ratio was a parameter).
  if (damping_ratio == SensorSettings::kButterworthDampingRatio) return gain_m_s2_per_N * r2 / std::sqrt(1.0 + r2 * r2);
  const double damping_term = 4 * damping_ratio * damping_ratio * r2;  // (2 zeta r)^2
  return gain_m_s2_per_N * r2 / std::sqrt((1.0 - r2) * (1.0 - r2) + damping_term);
}

namespace {
/// Eq. (S1) at every sample: the window over each planet's force about its record mean.
void planet_pass_history(const SensorSettings& s, std::span<const double> psi, std::span<const double> theta_c,
                         const std::vector<std::span<const double>>& force, std::vector<double>& out) {
  const std::size_t n = theta_c.size();
  std::vector<double> mean(psi.size(), 0.0);
  for (std::size_t i = 0; i < psi.size(); ++i) {
    double m = 0;
    for (double f : force[i]) m += f;
    mean[i] = n > 0 ? m / static_cast<double>(n) : 0.0;
  }
  std::vector<double> dF(psi.size());
  const WindowWeight w(s.window, s.window_width_rad);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t i = 0; i < psi.size(); ++i) dF[i] = force[i][k] - mean[i];
    out[k] = housing_acceleration(s, w, psi, theta_c[k], dF);
  }
}

/// Eq. (S2) at every sample: each planet's whole force projected on the sensor's radial direction.
void ring_translation_history(const SensorSettings& s, std::span<const double> psi, double alpha_pr,
                              std::span<const double> theta_c, const std::vector<std::span<const double>>& force,
                              std::vector<double>& out) {
  for (std::size_t k = 0; k < theta_c.size(); ++k) {
    double a = 0;
    for (std::size_t i = 0; i < psi.size(); ++i) a += force[i][k] * std::sin(psi[i] + theta_c[k] - s.angle_rad + alpha_pr);
    out[k] = s.gain_m_s2_per_N * a;
  }
}

/// Eq. (S3) at every sample: the ring body's fixed-frame acceleration times its mass, projected on
/// the sensor's radial direction e_r(phi_s) = (cos phi_s, sin phi_s), the direction (S2) projects
/// the net force on (n_i . e_r(phi_s) = sin(psi_i + theta_c - phi_s + alpha'_pr)).
void ring_body_history(const SensorSettings& s, const RingBodyAcceleration& ring, std::vector<double>& out) {
  const double cx = std::cos(s.angle_rad), sy = std::sin(s.angle_rad);
  const double scale = s.gain_m_s2_per_N * ring.mass_kg;
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = scale * (ring.x_m_s2[k] * cx + ring.y_m_s2[k] * sy);
}
} // namespace

std::vector<double> housing_acceleration_history(const SensorSettings& s, std::span<const double> psi,
                                                 double ring_pressure_angle_rad, std::span<const double> theta_c,
                                                 const std::vector<std::span<const double>>& force,
                                                 double sample_interval_s, const RingBodyAcceleration& ring) {
  if (force.size() != psi.size())
    throw std::invalid_argument("housing_acceleration_history: " + std::to_string(force.size()) +
                                " force histories for " + std::to_string(psi.size()) + " planets");
  const std::size_t n = theta_c.size();
  for (std::size_t i = 0; i < psi.size(); ++i)
    if (force[i].size() != n)
      throw std::invalid_argument("housing_acceleration_history: planet " + std::to_string(i) + " force has " +
                                  std::to_string(force[i].size()) + " samples, carrier angle " + std::to_string(n));
  if (s.housing_path == HousingPath::RingBody &&
      (ring.x_m_s2.size() != n || ring.y_m_s2.size() != n || !(ring.mass_kg > 0)))
    throw std::invalid_argument("housing_acceleration_history: the ring body's accelerations have " +
                                std::to_string(ring.x_m_s2.size()) + " and " + std::to_string(ring.y_m_s2.size()) +
                                " samples for " + std::to_string(n) + " carrier angles, its mass " +
                                std::to_string(ring.mass_kg) + " kg (needs > 0)");
  std::vector<double> out(n);
  if (s.housing_path == HousingPath::RingBody)
    ring_body_history(s, ring, out);
  else if (s.housing_path == HousingPath::RingTranslation)
    ring_translation_history(s, psi, ring_pressure_angle_rad, theta_c, force, out);
  else
    planet_pass_history(s, psi, theta_c, force, out);
  if (s.housing_mount_frequency_Hz > 0 && n > 0) {
    // A model the record cannot represent, not a bad input: a fit that reaches it scores it as
    // failed (SolverError) and steps back; the configuration's own value is checked up front.
    if (!(s.housing_mount_frequency_Hz * sample_interval_s < 0.5))
      throw SolverError("sensor.housing_mount_frequency_Hz " + std::to_string(s.housing_mount_frequency_Hz) +
                        " Hz is at or above the Nyquist frequency " + std::to_string(0.5 / sample_interval_s) +
                        " Hz of the record");
    ButterworthFilter mount(s.housing_mount_frequency_Hz, 2, sample_interval_s, FilterPass::High,
                            s.housing_mount_damping_ratio);
    mount.set_periodic_state(out);
    for (double& a : out) a = mount.step(a);
  }
  return out;
}

ButterworthFilter::ButterworthFilter(double bandwidth_Hz, int order, double dt_s, FilterPass pass,
                                     double damping_ratio) {
  if (order != 1 && order != 2) throw std::invalid_argument("Butterworth filter order must be 1 or 2");
  if (!(bandwidth_Hz >= 0) || !(dt_s > 0)) throw std::invalid_argument("Butterworth filter: cutoff >= 0, dt > 0");
  if (!(damping_ratio > 0) || !std::isfinite(damping_ratio))
    throw std::invalid_argument("second-order filter: damping ratio " + std::to_string(damping_ratio) + " must be > 0");
  if (pass == FilterPass::High && bandwidth_Hz * dt_s >= 0.5)
    throw std::invalid_argument("high-pass cutoff " + std::to_string(bandwidth_Hz) + " Hz at or above the Nyquist frequency " +
                                std::to_string(0.5 / dt_s) + " Hz of the record");
  if (bandwidth_Hz == 0 || bandwidth_Hz * dt_s >= 0.5) return;  // ideal, or beyond Nyquist
  identity_ = false;
  dc_gain_ = pass == FilterPass::Low ? 1.0 : 0.0;
  const double K = std::tan(kPi * bandwidth_Hz * dt_s);
  if (order == 1) {
    const double n = 1.0 / (1.0 + K);
    b0_ = pass == FilterPass::Low ? K * n : n;
    b1_ = pass == FilterPass::Low ? b0_ : -b0_;
    a1_ = (K - 1.0) * n;
    sigma_1_s_ = kTwoPi * bandwidth_Hz;
  } else {
    // s^2 + 2 zeta w0 s + w0^2 with s -> (1 - z^-1) / (K (1 + z^-1)) [w0 = 1]: the coefficient
    // 2 zeta is sqrt2 exactly at the Butterworth ratio (doubling sqrt2 / 2 is exact).
    const double r2 = 2 * damping_ratio;
    const double n = 1.0 / (1.0 + r2 * K + K * K);
    b0_ = b2_ = pass == FilterPass::Low ? K * K * n : n;
    b1_ = pass == FilterPass::Low ? 2 * b0_ : -2 * b0_;
    a1_ = 2.0 * (K * K - 1.0) * n;
    a2_ = (1.0 - r2 * K + K * K) * n;
    // The slowest pole's decay rate: zeta w0 (underdamped; the Butterworth's w0 / sqrt2 in the
    // form it always had), w0 (zeta - sqrt(zeta^2 - 1)) overdamped.
    const double w0 = kTwoPi * bandwidth_Hz;
    sigma_1_s_ = damping_ratio == SensorSettings::kButterworthDampingRatio ? w0 / std::numbers::sqrt2
                 : damping_ratio < 1 ? damping_ratio * w0
                                     : w0 * (damping_ratio - std::sqrt(damping_ratio * damping_ratio - 1));
  }
}

void ButterworthFilter::reset(double x) {
  // The steady state of a constant input x: output y = H(1) x, x low-pass, 0 high-pass.
  if (dc_gain_ == 0) {
    z2_ = b2_ * x;
    z1_ = b1_ * x + z2_;
    return;
  }
  z2_ = (b2_ - a2_) * x;
  z1_ = (b1_ - a1_) * x + z2_;
}

void ButterworthFilter::set_periodic_state(std::span<const double> period) {
  if (identity_ || period.empty()) return;
  // The state after one period is affine in the state before it: z_N = Phi z_0 + z_f. Three
  // runs over the period give z_f (from rest, with the input) and Phi's columns (from unit
  // states, without it); the 2x2 system (I - Phi) z = z_f is then solved by Cramer's rule.
  const auto run = [&](double z1, double z2, bool with_input) {
    z1_ = z1;
    z2_ = z2;
    for (const double x : period) step(with_input ? x : 0.0);
    return std::pair{z1_, z2_};
  };
  const auto [f1, f2] = run(0.0, 0.0, true);
  const auto [a1, a2] = run(1.0, 0.0, false);
  const auto [b1, b2] = run(0.0, 1.0, false);
  const double m11 = 1.0 - a1, m12 = -b1, m21 = -a2, m22 = 1.0 - b2;
  const double det = m11 * m22 - m12 * m21;
  z1_ = (f1 * m22 - m12 * f2) / det;
  z2_ = (m11 * f2 - m21 * f1) / det;
}

double ButterworthFilter::settling_time_s(double fraction) const {
  if (identity_) return 0.0;
  return -std::log(fraction) / sigma_1_s_;
}

} // namespace pw::model
