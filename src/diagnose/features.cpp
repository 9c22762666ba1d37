#include "diagnose/features.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "signal/fft.hpp"
#include "signal/spectrum.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pw::diagnose {
double interpolate_uniform(std::span<const double> x, double t0, double dt, double t) {
  const std::size_t n = x.size();
  require(n >= 2 && dt > 0, "signal", "need >= 2 samples and dt > 0 to interpolate");
  const double s = (t - t0) / dt;
  const double tol = 1e-6;
  require(s >= -tol && s <= static_cast<double>(n - 1) + tol, "time", "t = ", t, " s outside the signal [", t0,
          ", ", t0 + static_cast<double>(n - 1) * dt, "] s");
  if (n < 4) {
    const std::size_t i = std::min<std::size_t>(static_cast<std::size_t>(std::max(0.0, std::floor(s))), n - 2);
    const double f = s - static_cast<double>(i);
    return x[i] * (1 - f) + x[i + 1] * f;
  }
  // Cubic Lagrange on i-1 .. i+2, shifted inwards at the ends.
  long i = static_cast<long>(std::floor(s));
  i = std::clamp(i, 1L, static_cast<long>(n) - 3);
  const double f = s - static_cast<double>(i);  // position relative to node i
  const double fm1 = f + 1, f1 = f - 1, f2 = f - 2;
  const double w0 = -f * f1 * f2 / 6.0;   // node i-1
  const double w1 = fm1 * f1 * f2 / 2.0;  // node i
  const double w2 = -fm1 * f * f2 / 2.0;  // node i+1
  const double w3 = fm1 * f * f1 / 6.0;   // node i+2
  const std::size_t u = static_cast<std::size_t>(i);
  return w0 * x[u - 1] + w1 * x[u] + w2 * x[u + 1] + w3 * x[u + 2];
}

std::vector<LineAmplitude> fit_lines(std::span<const double> x, double t0, double dt,
                                     std::span<const double> freqs) {
  const std::size_t n = x.size();
  const std::size_t L = freqs.size();
  require(n >= 8, "signal", "need >= 8 samples, got ", n);
  require(L >= 1, "frequencies_Hz", "need at least one frequency");
  const std::size_t p = 2 * L + 1;
  Eigen::MatrixXd AtA = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(p));
  Eigen::VectorXd Atb = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p));
  Eigen::VectorXd row(static_cast<Eigen::Index>(p));
  for (std::size_t j = 0; j < n; ++j) {
    const double w = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(j) / static_cast<double>(n));
    if (w == 0) continue;
    const double t = t0 + static_cast<double>(j) * dt;
    for (std::size_t l = 0; l < L; ++l) {
      const double ph = 2 * kPi * freqs[l] * t;
      row(static_cast<Eigen::Index>(2 * l)) = std::cos(ph);
      row(static_cast<Eigen::Index>(2 * l + 1)) = std::sin(ph);
    }
    row(static_cast<Eigen::Index>(p - 1)) = 1.0;
    AtA.selfadjointView<Eigen::Lower>().rankUpdate(row, w);
    Atb += (w * x[j]) * row;
  }
  AtA = AtA.selfadjointView<Eigen::Lower>();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(AtA);
  const double emax = es.eigenvalues().maxCoeff(), emin = es.eigenvalues().minCoeff();
  require(emin > 1e-9 * emax, "frequencies_Hz",
          "lines too close to be separated in a record of ", static_cast<double>(n) * dt,
          " s (condition number ", emax / std::max(emin, 1e-300), ")");
  const Eigen::VectorXd c = AtA.ldlt().solve(Atb);
  std::vector<LineAmplitude> out(L);
  for (std::size_t l = 0; l < L; ++l) {
    // a cos + b sin = A cos(ph + phi) with A e^{i phi} = a - i b.
    const double a = c(static_cast<Eigen::Index>(2 * l)), b = c(static_cast<Eigen::Index>(2 * l + 1));
    out[l] = {freqs[l], {a, -b}};
  }
  return out;
}

std::vector<std::complex<double>> window_bins(std::span<const double> x, std::size_t max_bin) {
  const std::size_t n = x.size();
  require(n >= 2, "signal", "need >= 2 samples");
  require(max_bin <= n / 2, "max_bin", max_bin, " exceeds n/2 = ", n / 2);
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> y(n);
  for (std::size_t j = 0; j < n; ++j) y[j] = x[j] - mean;
  const auto X = signal::real_fft(y);
  return {X.begin() + 1, X.begin() + 1 + static_cast<long>(max_bin)};
}

std::vector<double> normalized_periodogram(std::span<const double> x) {
  const std::size_t n = x.size();
  require(n >= 2, "signal", "need >= 2 samples");
  const auto w = signal::window_coefficients(signal::Window::Hann, n);
  double mean = 0, sw2 = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> y(n);
  for (std::size_t j = 0; j < n; ++j) {
    y[j] = (x[j] - mean) * w[j];
    sw2 += w[j] * w[j];
  }
  const auto X = signal::real_fft(y);
  std::vector<double> p(X.size());
  for (std::size_t k = 0; k < X.size(); ++k) p[k] = std::norm(X[k]) / sw2;
  return p;
}

NoiseEstimate estimate_white_noise(std::span<const double> x, double low_fraction) {
  require(x.size() >= 64, "signal", "need >= 64 samples to estimate the noise, got ", x.size());
  require(low_fraction >= 0 && low_fraction < 1, "low_fraction", "must be in [0, 1), got ", low_fraction);
  std::vector<double> p = normalized_periodogram(x);
  const std::size_t last = p.size() - 2;  // skip Nyquist (real-valued, different distribution)
  const std::size_t first = std::max<std::size_t>(2, static_cast<std::size_t>(low_fraction * static_cast<double>(last)));
  std::vector<double> v(p.begin() + static_cast<long>(first), p.begin() + static_cast<long>(last) + 1);
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(m), v.end());
  NoiseEstimate e;
  e.bins = v.size();
  e.variance = v[m] / std::numbers::ln2;
  // Median of an exponential sample: relative standard error 1/(ln 2 sqrt(n_eff)); Hann makes
  // neighbouring bins correlated, n_eff ~ n / 1.5.
  e.relative_uncertainty = 1.0 / (std::numbers::ln2 * std::sqrt(static_cast<double>(v.size()) / 1.5));
  return e;
}

SynchronousAverage synchronous_average(std::span<const double> x, double t0, double dt, double fm, int period,
                                       int spc) {
  require(period >= 1 && spc >= 2, "period_cycles", "need period >= 1 and samples_per_cycle >= 2");
  SynchronousAverage s;
  s.samples_per_cycle = spc;
  s.period_cycles = period;
  const std::size_t n = x.size();
  if (n < 4) return s;
  const double u_first = t0 * fm, u_last = (t0 + static_cast<double>(n - 1) * dt) * fm;
  const long g_first = static_cast<long>(std::ceil(u_first * spc));
  const long g_last = static_cast<long>(std::floor(u_last * spc));
  const long per = static_cast<long>(period) * spc;
  const long count = g_last - g_first + 1;
  const long reps = count / per;
  if (reps < 1) return s;
  s.averages = static_cast<int>(reps);
  s.values.assign(static_cast<std::size_t>(per), 0.0);
  for (long g = g_first; g < g_first + reps * per; ++g) {
    const double t = static_cast<double>(g) / spc / fm;
    const long j = ((g % per) + per) % per;
    s.values[static_cast<std::size_t>(j)] += interpolate_uniform(x, t0, dt, t);
  }
  for (double& v : s.values) v /= static_cast<double>(reps);
  return s;
}

TsaPeak tsa_energy_peak(const SynchronousAverage& tsa) {
  TsaPeak pk;
  const std::size_t n = tsa.values.size();
  if (n == 0) return pk;
  double mean = 0;
  for (double v : tsa.values) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> e(n);
  for (std::size_t j = 0; j < n; ++j) e[j] = (tsa.values[j] - mean) * (tsa.values[j] - mean);
  // Circular moving average over one mesh cycle.
  const std::size_t w = static_cast<std::size_t>(tsa.samples_per_cycle);
  double acc = 0;
  for (std::size_t j = 0; j < w; ++j) acc += e[j % n];
  double best = -1, total = 0;
  std::size_t best_j = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const double centre = acc / static_cast<double>(w);
    total += centre;
    if (centre > best) {
      best = centre;
      best_j = (j + w / 2) % n;
    }
    acc += e[(j + w) % n] - e[j];
  }
  pk.mesh_cycle = static_cast<double>(best_j) / tsa.samples_per_cycle;
  pk.peak_to_mean = total > 0 ? best / (total / static_cast<double>(n)) : 0.0;
  return pk;
}

EnvelopeSpectrum envelope_spectrum(std::span<const double> x, double dt, double f_lo, double f_hi, double max_Hz) {
  const std::size_t n = x.size();
  require(n >= 16, "signal", "need >= 16 samples");
  require(0 <= f_lo && f_lo < f_hi, "band", "need 0 <= f_lo < f_hi");
  std::vector<double> y(x.begin(), x.end());
  auto X = signal::real_fft(y);
  const double df = 1.0 / (static_cast<double>(n) * dt);
  // Analytic signal of the band: z = x_b + i H[x_b], x_b the band-passed signal and H its Hilbert
  // transform (multiply the positive-frequency bins by -i).
  std::vector<std::complex<double>> Xr(X.size()), Xh(X.size());
  for (std::size_t k = 0; k < X.size(); ++k) {
    const double f = static_cast<double>(k) * df;
    const bool in = k > 0 && f >= f_lo && f <= f_hi;
    Xr[k] = in ? X[k] : std::complex<double>{0, 0};
    Xh[k] = in ? std::complex<double>{0, -1} * X[k] : std::complex<double>{0, 0};
  }
  const auto xr = signal::inverse_real_fft(Xr, n);
  const auto xh = signal::inverse_real_fft(Xh, n);
  std::vector<double> env(n);
  for (std::size_t j = 0; j < n; ++j) env[j] = std::hypot(xr[j], xh[j]);
  const auto s = signal::amplitude_spectrum(env, dt, signal::Window::Hann, true);
  EnvelopeSpectrum e;
  for (std::size_t k = 0; k < s.frequency_Hz.size() && s.frequency_Hz[k] <= max_Hz; ++k) {
    e.frequency_Hz.push_back(s.frequency_Hz[k]);
    e.amplitude.push_back(s.amplitude[k]);
  }
  return e;
}

} // namespace pw::diagnose
