#include "diagnose/order_analysis.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "core/statistics.hpp"
#include "diagnose/features.hpp"
#include "model/sensor.hpp"
#include "signal/fft.hpp"
#include "signal/resample.hpp"
#include "signal/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <numbers>
#include <optional>

namespace pw::diagnose {
namespace {

double mean_of(std::span<const double> x) {
  double s = 0;
  for (double v : x) s += v;
  return s / static_cast<double>(x.size());
}

/// Mean and the standard error of the mean from `blocks` block means.
std::pair<double, double> mean_and_error(std::span<const double> x, int blocks = 8) {
  const double m = mean_of(x);
  const std::size_t n = x.size() / static_cast<std::size_t>(blocks);
  if (n < 2) return {m, 0.0};
  std::vector<double> bm;
  for (int b = 0; b < blocks; ++b) bm.push_back(mean_of(x.subspan(static_cast<std::size_t>(b) * n, n)));
  const double mb = mean_of(bm);
  double v = 0;
  for (double y : bm) v += (y - mb) * (y - mb);
  v /= (blocks - 1);
  return {m, std::sqrt(v / blocks)};
}

/// Rising-edge times of a pulse train (threshold half-way between min and max).
std::vector<double> tacho_edges(const Recording& r, const SignalChannel& c) {
  const auto [lo, hi] = std::minmax_element(c.values.begin(), c.values.end());
  std::vector<double> e;
  if (!(*hi > *lo)) return e;
  const double thr = 0.5 * (*lo + *hi);
  for (std::size_t j = 1; j < c.values.size(); ++j)
    if (c.values[j - 1] < thr && c.values[j] >= thr) {
      const double f = (thr - c.values[j - 1]) / (c.values[j] - c.values[j - 1]);
      e.push_back(r.time_s[j - 1] + f * (r.time_s[j] - r.time_s[j - 1]));
    }
  return e;
}

/// |sum_j w_j x_j e^{-2 pi i f t_j}| with a Hann window over the record.
double hann_dtft_abs(std::span<const double> x, std::span<const double> t, double f) {
  const std::size_t n = x.size();
  std::complex<double> s = 0;
  const double t0 = t.front();
  for (std::size_t j = 0; j < n; ++j) {
    const double w = 0.5 - 0.5 * std::cos(2 * kPi * static_cast<double>(j) / static_cast<double>(n));
    const double ph = -2 * kPi * f * (t[j] - t0);
    s += w * x[j] * std::complex<double>(std::cos(ph), std::sin(ph));
  }
  return std::abs(s);
}

std::vector<double> cumulative_integral(std::span<const double> t, std::span<const double> w, double scale) {
  std::vector<double> th(t.size(), 0.0);
  for (std::size_t j = 1; j < t.size(); ++j) th[j] = th[j - 1] + 0.5 * (w[j] + w[j - 1]) * (t[j] - t[j - 1]) * scale;
  return th;
}

} // namespace

std::vector<double> mesh_period_average(std::span<const double> x, double width) {
  // y_j = (1/L) * integral of the piecewise-linear x over [j - L/2, j + L/2], from the
  // cumulative trapezoidal integral C interpolated linearly. Within half a period of either end
  // the interval is the full period that fits, shifted inwards, not a clipped shorter one: a
  // shorter interval does not null the mesh harmonics, so the angle reference integrated from it
  // wiggled at the mesh frequency there -- ~4e-4 rad of sun angle over the last half period of
  // a 100 rpm recording, 0.6 rad of phase at carrier order 6300, leaked into every cell of the
  // window that ends there (the held-out half) and into none of the model's (docs/diagnose-log.md,
  // session 43). The shifted interval follows the slow variations up to half a period early or
  // late, which for a speed that changes slowly over a mesh period is a second-order error.
  const std::size_t n = x.size();
  std::vector<double> C(n, 0.0), y(n);
  for (std::size_t j = 1; j < n; ++j) C[j] = C[j - 1] + 0.5 * (x[j] + x[j - 1]);
  auto at = [&](double s) {
    s = std::clamp(s, 0.0, static_cast<double>(n - 1));
    const std::size_t i = std::min(static_cast<std::size_t>(s), n - 2);
    const double f = s - static_cast<double>(i);
    // Integral of the linear interpolant from i to i + f.
    return C[i] + f * x[i] + 0.5 * f * f * (x[i + 1] - x[i]);
  };
  const double h = 0.5 * width, last = static_cast<double>(n - 1);
  const bool period_fits = width <= last;
  for (std::size_t j = 0; j < n; ++j) {
    double a = static_cast<double>(j) - h, b = static_cast<double>(j) + h;
    if (!period_fits) a = 0, b = last;  // the whole record, shorter than the period
    else if (a < 0) b -= a, a = 0;
    else if (b > last) a -= b - last, b = last;
    y[j] = b > a ? (at(b) - at(a)) / (b - a) : x[j];
  }
  return y;
}

namespace {
} // namespace

double exponential_mean(std::vector<double> p, double* relative_se) {
  require(!p.empty(), "noise", "no bins to estimate the noise from");
  const std::size_t mid = p.size() / 2;
  std::nth_element(p.begin(), p.begin() + static_cast<long>(mid), p.end());
  double mu = std::max(p[mid] / std::numbers::ln2, 1e-300);
  std::size_t used = p.size();
  // Mean of the bins below T = 4.6 mu (the 99 % point: lines and outliers excluded),
  // corrected for the truncation of an exponential distribution.
  for (int it = 0; it < 8; ++it) {
    const double T = 4.6 * mu;
    double sum = 0;
    used = 0;
    for (double v : p)
      if (v < T) sum += v, ++used;
    if (used < 4) break;
    const double m = sum / static_cast<double>(used);
    const double e = std::exp(-T / mu);
    mu = std::max(m + T * e / (1 - e), 1e-300);
  }
  if (relative_se) *relative_se = 1.05 / std::sqrt(static_cast<double>(std::max<std::size_t>(used, 1)));
  return mu;
}

double rice_mean(double nu, double s2) {
  nu = std::fabs(nu);
  if (!(s2 > 0)) return nu;
  const double s = std::sqrt(0.5 * s2);  // per-component standard deviation
  const double ratio = nu / s;
  if (ratio > 25) return nu + s * s / (2 * nu) + s * s * s * s / (8 * nu * nu * nu);
  const double y = ratio * ratio / 4;
  const double e = std::exp(-y);
  const double i0e = bessel_i0(y) * e, i1e = bessel_i1(y) * e;
  return s * std::sqrt(kPi / 2) * ((1 + 2 * y) * i0e + 2 * y * i1e);
}

double rice_mean_slope(double nu, double s2) {
  nu = std::fabs(nu);
  if (!(s2 > 0)) return 1.0;
  const double s = std::sqrt(0.5 * s2);  // per-component standard deviation
  const double ratio = nu / s;
  // d/dnu of the asymptotic form above: 1 - s^2/(2 nu^2) - 3 s^4/(8 nu^4).
  if (ratio > 25) return 1 - s * s / (2 * nu * nu) - 3 * s * s * s * s / (8 * nu * nu * nu * nu);
  // d mu/d nu = sqrt(pi/2) (nu / 2s) e^-y (I0(y) + I1(y)), y = nu^2/(4 s^2) (differentiating
  // the Laguerre form above; checked against central differences in the tests).
  const double y = ratio * ratio / 4;
  const double e = std::exp(-y);
  return std::sqrt(kPi / 2) * (ratio / 2) * (bessel_i0(y) + bessel_i1(y)) * e;
}

double rice_variance(double nu, double s2) {
  const double m = rice_mean(nu, s2);
  return std::max(nu * nu + s2 - m * m, 1e-300);
}

SpeedEstimate estimate_speed(const Recording& r, const model::StageSpec& st) {
  SpeedEstimate e;
  if (const SignalChannel* c = r.find(Quantity::SunSpeed)) {
    const auto [m, se] = mean_and_error(c->values);
    e.input_rpm = m * 60 / (2 * kPi);
    e.relative_std = std::fabs(se / m);
    e.source = "mean of the sun_speed channel '" + c->name + "'";
    return e;
  }
  if (const SignalChannel* cc = r.find(Quantity::CarrierSpeed)) {
    const auto [m, se] = mean_and_error(cc->values);
    e.input_rpm = model::sun_speed(st, m) * 60 / (2 * kPi);
    e.relative_std = std::fabs(se / m);
    e.source = "mean of the carrier_speed channel '" + cc->name + "' x (Zs+Zr)/Zs";
    return e;
  }
  const double dt = r.sample_interval_s();
  if (const SignalChannel* tc = r.find(Quantity::Tacho)) {
    const auto edges = tacho_edges(r, *tc);
    if (edges.size() >= 3) {
      const double T = edges.back() - edges.front();
      const double rpm = 60.0 * static_cast<double>(edges.size() - 1) / T;
      if (std::fabs(rpm / r.operating.input_speed_rpm - 1) < 0.2) {
        e.input_rpm = rpm;
        e.relative_std = dt / std::sqrt(6.0) / T;
        e.source = "tacho '" + tc->name + "': " + std::to_string(edges.size() - 1) + " revolutions";
        return e;
      }
    }
  }
  // The sidecar's nominal speed, refined on the strongest of the first three mesh
  // harmonics of the accelerometers (maximum of the Hann-windowed DTFT).
  e.input_rpm = r.operating.input_speed_rpm;
  const Kinematics k0 = kinematics(st, e.input_rpm);
  const double T = r.time_s.back() - r.time_s.front();
  const SignalChannel* best = nullptr;
  double best_ratio = 0, best_f = 0;
  for (const auto& c : r.channels) {
    if (c.quantity == Quantity::Tacho || c.quantity == Quantity::SunSpeed || c.quantity == Quantity::CarrierSpeed)
      continue;
    double rms = 0;
    const double m = mean_of(c.values);
    for (double v : c.values) rms += (v - m) * (v - m);
    rms = std::sqrt(rms / static_cast<double>(c.values.size())) + 1e-300;
    for (int h = 1; h <= 3; ++h) {
      const double f = h * k0.mesh_Hz;
      if (f > 0.4 / dt) continue;
      const double a = hann_dtft_abs(c.values, r.time_s, f) / (0.5 * static_cast<double>(c.values.size())) / rms;
      if (a > best_ratio) best_ratio = a, best = &c, best_f = f;
    }
  }
  e.relative_std = 1e-3;
  e.source = "sidecar input_speed_rpm (no speed channel or tacho)";
  if (best) {
    // Golden-section search for the peak within +-1 bin.
    double a = best_f - 1.0 / T, b = best_f + 1.0 / T;
    const double g = (std::sqrt(5.0) - 1) / 2;
    double c1 = b - g * (b - a), c2 = a + g * (b - a);
    double f1 = hann_dtft_abs(best->values, r.time_s, c1), f2 = hann_dtft_abs(best->values, r.time_s, c2);
    for (int it = 0; it < 60 && b - a > 1e-7 / T; ++it) {
      if (f1 > f2) {
        b = c2, c2 = c1, f2 = f1, c1 = b - g * (b - a), f1 = hann_dtft_abs(best->values, r.time_s, c1);
      } else {
        a = c1, c1 = c2, f1 = f2, c2 = a + g * (b - a), f2 = hann_dtft_abs(best->values, r.time_s, c2);
      }
    }
    const double f = 0.5 * (a + b);
    e.input_rpm *= f / best_f;
    // Cramer-Rao bound of a sinusoid's frequency (x1.5 for the Hann window).
    const NoiseEstimate ne = estimate_white_noise(best->values);
    const double A = hann_dtft_abs(best->values, r.time_s, f) / (0.25 * static_cast<double>(best->values.size()));
    const double n = static_cast<double>(best->values.size());
    const double sd_f = 1.5 * std::sqrt(12.0 * ne.variance / (A * A * n * n * n)) / (2 * kPi * dt);
    e.relative_std = std::max(sd_f / f, 1e-9);
    e.source = "sidecar input_speed_rpm refined on the mesh line at " + std::to_string(f) + " Hz of '" + best->name + "'";
  }
  return e;
}

std::vector<double> carrier_angle(const Recording& r, const model::StageSpec& st, const SpeedEstimate& speed,
                                  std::string* source) {
  const double ratio = model::carrier_to_sun_ratio(st);
  std::vector<double> th;
  std::string src;
  const double omega_c = speed.input_rpm * 2 * kPi / 60 * ratio;
  // One mesh period in samples: the moving average removes the speed's vibration at every
  // mesh harmonic (its zeros) and keeps its slow variations.
  const double mesh_samples = 2 * kPi / (omega_c * st.ring.teeth) / r.sample_interval_s();
  if (const SignalChannel* c = r.find(Quantity::SunSpeed)) {
    th = cumulative_integral(r.time_s, mesh_period_average(c->values, mesh_samples), ratio);
    src = "integral of '" + c->name + "' x Zs/(Zs+Zr), averaged over one mesh period";
  } else if (const SignalChannel* cc = r.find(Quantity::CarrierSpeed)) {
    th = cumulative_integral(r.time_s, mesh_period_average(cc->values, mesh_samples), 1.0);
    src = "integral of '" + cc->name + "', averaged over one mesh period";
  } else {
    std::vector<double> edges;
    if (const SignalChannel* tc = r.find(Quantity::Tacho)) edges = tacho_edges(r, *tc);
    th.resize(r.time_s.size());
    if (edges.size() >= 3) {
      // Sun angle 2 pi n at edge n, linear in between, the mean speed outside.
      const double omega_s = omega_c / ratio;
      std::size_t e = 0;
      for (std::size_t j = 0; j < r.time_s.size(); ++j) {
        const double t = r.time_s[j];
        while (e + 2 < edges.size() && edges[e + 1] <= t) ++e;
        double s;
        if (t < edges.front())
          s = (t - edges.front()) * omega_s;
        else if (t > edges.back())
          s = 2 * kPi * static_cast<double>(edges.size() - 1) + (t - edges.back()) * omega_s;
        else
          s = 2 * kPi * (static_cast<double>(e) + (t - edges[e]) / (edges[e + 1] - edges[e]));
        th[j] = s * ratio;
      }
      const double t0 = th.front();
      for (double& v : th) v -= t0;
      src = "tacho edges (one per sun revolution)";
    } else {
      for (std::size_t j = 0; j < r.time_s.size(); ++j) th[j] = omega_c * (r.time_s[j] - r.time_s.front());
      src = "constant speed " + std::to_string(speed.input_rpm) + " rpm (no speed channel or tacho)";
    }
  }
  for (std::size_t j = 1; j < th.size(); ++j)
    require(th[j] > th[j - 1], "recording", r.source, ": the carrier angle (", src, ") does not increase at sample ",
            j, "; a speed channel must be positive (give scale = -1 for an encoder counting backwards)");
  if (source) *source = src;
  return th;
}

namespace {
/// Adds y e^{-i k phi / R}, k = 0 .. re.size() - 1, to (re, im) by one complex
/// rotation per k (no trigonometric call per bin); with_drift also adds
/// phi y e^{-i k phi / R} to (gre, gim) for angle_fourier's drift derivative.
/// A template so the plain transform's inner loop carries no branch and no
/// second accumulator.
template <bool with_drift>
void add_rotating_terms(double y, double phi, double R, std::vector<double>& re, std::vector<double>& im,
                        std::vector<double>& gre, std::vector<double>& gim) {
  const double step = -phi / R;
  const double cr = std::cos(step), ci = std::sin(step);
  double zr = y, zi = 0;
  for (std::size_t k = 0; k < re.size(); ++k) {
    re[k] += zr;
    im[k] += zi;
    if constexpr (with_drift) {
      gre[k] += phi * zr;
      gim[k] += phi * zi;
    }
    const double t = zr * cr - zi * ci;
    zi = zr * ci + zi * cr;
    zr = t;
  }
}
}  // namespace

std::vector<std::complex<double>> angle_fourier(std::span<const double> x, std::span<const double> angle,
                                                double a0, double R, int max_bin,
                                                std::vector<std::complex<double>>* drift) {
  const std::size_t n = x.size();
  require(n == angle.size() && n >= 4, "signal", "need >= 4 samples with angles");
  const double span = 2 * kPi * R, a1 = a0 + span;
  require(a0 >= angle.front() - 1e-12 && a1 <= angle.back() + 1e-9, "window", "angles [", a0, ", ", a1,
          "] rad are not covered by the samples [", angle.front(), ", ", angle.back(), "]");
  // Points of the trapezoidal rule: the window's ends (interpolated) and the samples inside.
  std::vector<double> phi, val;
  auto interp = [&](double a) {
    std::size_t j = static_cast<std::size_t>(std::lower_bound(angle.begin(), angle.end(), a) - angle.begin());
    if (j == 0) return x[0];
    if (j >= n) return x[n - 1];
    const double f = (a - angle[j - 1]) / (angle[j] - angle[j - 1]);
    return x[j - 1] + f * (x[j] - x[j - 1]);
  };
  phi.push_back(0.0);
  val.push_back(interp(a0));
  for (std::size_t j = static_cast<std::size_t>(std::upper_bound(angle.begin(), angle.end(), a0) - angle.begin());
       j < n && angle[j] < a1; ++j) {
    phi.push_back(angle[j] - a0);
    val.push_back(x[j]);
  }
  phi.push_back(span);
  val.push_back(interp(a1));
  const std::size_t m = phi.size();
  std::vector<double> w(m);
  for (std::size_t i = 0; i < m; ++i)
    w[i] = 0.5 * ((i + 1 < m ? phi[i + 1] : phi[i]) - (i > 0 ? phi[i - 1] : phi[i])) / span;
  double mean = 0;
  for (std::size_t i = 0; i < m; ++i) mean += w[i] * val[i];
  const std::size_t nb = static_cast<std::size_t>(max_bin) + 1;
  std::vector<double> re(nb, 0.0), im(nb, 0.0), gre(drift ? nb : 0, 0.0), gim(gre.size(), 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    const double y = w[i] * (val[i] - mean);
    if (y == 0) continue;
    if (drift)
      add_rotating_terms<true>(y, phi[i], R, re, im, gre, gim);
    else
      add_rotating_terms<false>(y, phi[i], R, re, im, gre, gim);
  }
  std::vector<std::complex<double>> c(nb);
  for (std::size_t k = 0; k < nb; ++k) c[k] = {re[k], im[k]};
  if (drift) {
    const double y1 = val.back() - mean;
    drift->assign(nb, {0.0, 0.0});
    for (std::size_t k = 1; k < nb; ++k) {
      const std::complex<double> dk = y1 - c[k] + std::complex<double>(0.0, static_cast<double>(k) / R) *
                                                      std::complex<double>(gre[k], gim[k]);
      (*drift)[k] = dk / span;
    }
  }
  return c;
}

namespace {
/// In windows of Q mesh cycles (Q < Zr) the carrier family is unresolved. A housing
/// accelerometer sees the planets pass its transfer-path window once per Zr / N mesh cycles:
/// every line it carries is a carrier-family line, so it is not compared at all.
void drop_housing_channels(const Recording& rec, RecordingSpectra& s) {
  std::vector<int> keep;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < s.channels.size(); ++i)
    if (rec.channels[static_cast<std::size_t>(s.channels[i])].quantity != Quantity::HousingAcceleration) {
      keep.push_back(s.channels[i]);
      names.push_back(s.channel_names[i]);
    }
  require(!keep.empty(), "recording", rec.source,
          ": no channel left; in halves shorter than a carrier revolution only speed and mesh-acceleration "
          "channels are compared (a housing channel's lines all belong to the unresolved carrier family)");
  s.channels = std::move(keep);
  s.channel_names = std::move(names);
}

/// make_layout for a window of R carrier revolutions (whole or not), with the lines of the
/// families `resolved` rejects left out (listed in L.unresolved).
template <class Resolved>
FeatureLayout layout_for_window(const Kinematics& k, int planets, double R, double max_order, const LayoutOptions& o,
                                Resolved resolved) {
  FeatureLayout L;
  L.window_revolutions = R;
  L.max_bin = static_cast<int>(std::floor(max_order * R));
  L.max_order = static_cast<double>(L.max_bin) / R;
  const double zr = k.ring_teeth;
  const int jc = o.carrier_sidebands > 0 ? o.carrier_sidebands : 4 * planets;
  L.mesh_harmonics = std::min(o.max_mesh_harmonics, static_cast<int>(std::floor(L.max_order / zr)));
  const int a_max = std::min(o.max_mesh_harmonics, static_cast<int>(std::floor((L.max_order + jc) / zr)));
  for (Component f : kAllComponents) {
    if (!resolved(f)) {
      L.unresolved.push_back(f);
      continue;
    }
    const double of = carrier_orders(k, f);
    const int jb = f == Component::Mesh ? 0 : std::max(1, static_cast<int>(std::ceil(jc / of - 1e-9)));
    for (auto& l : order_lines(k, f, a_max, jb, L.max_order)) L.lines.push_back(std::move(l));
  }
  std::map<int, std::vector<int>> bins;
  for (std::size_t i = 0; i < L.lines.size(); ++i) {
    const double pos = L.lines[i].order * R;
    const long b0 = std::lround(pos);
    const double d = pos - static_cast<double>(b0);
    auto add = [&](long b) {
      if (b >= 1 && b <= L.max_bin) bins[static_cast<int>(b)].push_back(static_cast<int>(i));
    };
    add(b0);
    // A line more than a quarter bin off its bin also counts in the neighbour. Line orders are
    // ratios of tooth counts computed from the measured speeds, so a line exactly a quarter bin
    // off (planet lines Zr R / Zp = 65 * 3 / 20 = 9.75 bins apart, say) lands at 0.25 +- round-off:
    // the round-off decided, and two recordings of one operating point got different cells and
    // could not be compared (session 37). Within 1e-9 bin of the quarter it is the quarter: the
    // family ratios' denominators are Zs, Zp (and 1), so a distance that is not the quarter differs
    // from it by at least 1 / (4 Zs Zp), far above 1e-9.
    if (std::fabs(d) > 0.25 + 1e-9) add(b0 + (d > 0 ? 1 : -1));
  }
  L.family_cells.assign(5, {});
  for (auto& [b, lines] : bins) {
    FeatureCell c;
    c.bin = b;
    c.order = static_cast<double>(b) / R;
    c.lines = lines;
    c.segment = static_cast<int>(std::lround(c.order / zr));
    std::vector<Component> fams;
    for (int li : lines)
      if (std::find(fams.begin(), fams.end(), L.lines[static_cast<std::size_t>(li)].family) == fams.end())
        fams.push_back(L.lines[static_cast<std::size_t>(li)].family);
    for (Component f : fams) L.family_cells[static_cast<std::size_t>(f)].push_back(static_cast<int>(L.cells.size()));
    L.cell_families.push_back(fams);
    L.cells.push_back(std::move(c));
  }
  for (int b = 1; b <= L.max_bin; ++b)
    if (!bins.count(b)) L.noise_bins.push_back(b);
  L.segments = static_cast<int>(std::lround(L.max_order / zr)) + 1;
  return L;
}
}  // namespace

FeatureLayout make_layout(const Kinematics& k, int planets, int R, double max_order, const LayoutOptions& o) {
  require(R >= 1, "revolutions", "must be >= 1");
  FeatureLayout L = layout_for_window(k, planets, R, max_order, o, [](Component) { return true; });
  L.revolutions = R;
  return L;
}

FeatureLayout make_layout_mesh_cycles(const Kinematics& k, int planets, int Q, double max_order,
                                      const LayoutOptions& o) {
  require(Q >= 1, "mesh_cycles", "must be >= 1");
  FeatureLayout L = layout_for_window(k, planets, static_cast<double>(Q) / k.ring_teeth, max_order, o,
                                      [&](Component f) { return k.completes_periods(f, Q); });
  L.revolutions = 0;
  L.mesh_cycles = Q;
  return L;
}

int min_recording_mesh_cycles(int sun_teeth) { return 2 * sun_teeth; }

int short_window_mesh_cycles(const Kinematics& k, double mesh_cycles) {
  const int half = static_cast<int>(std::floor(mesh_cycles / 2 + 1e-9));
  const int both = std::lcm(k.sun_teeth, k.planet_teeth);
  const int unit = half >= both ? both : k.sun_teeth;
  return unit * (half / unit);
}

// analyse_recording's phases, in order. Each fills its part of RecordingSpectra.
namespace {

/// The channels the model predicts (all but a tacho), checked against the time axis and the stage.
void select_channels(const Recording& rec, const model::StageSpec& stage, RecordingSpectra& s) {
  const std::size_t n = rec.time_s.size();
  for (std::size_t c = 0; c < rec.channels.size(); ++c) {
    const auto& ch = rec.channels[c];
    if (ch.quantity == Quantity::Tacho) continue;
    require(ch.values.size() == n, "recording", "channel '", ch.name, "' has ", ch.values.size(),
            " samples, the time axis ", n);
    if (ch.quantity == Quantity::MeshAccelerationSunPlanet || ch.quantity == Quantity::MeshAccelerationPlanetRing)
      require(ch.planet >= 0 && ch.planet < stage.planet_count, "recording", "channel '", ch.name, "': planet ",
              ch.planet, " does not exist (", stage.planet_count, " planets)");
    s.channels.push_back(static_cast<int>(c));
    s.channel_names.push_back(ch.name);
  }
  require(!s.channels.empty(), "recording", rec.source, ": no channel the model can predict");
}

/// The feature layout: halves of whole carrier revolutions, or of whole mesh cycles when the
/// recording is shorter than two revolutions (docs/diagnose.md §2 "Short recordings").
void choose_layout(const Recording& rec, const model::StageSpec& stage, const OrderAnalysisOptions& o,
                   RecordingSpectra& s) {
  const double dt = rec.sample_interval_s();
  const double total = s.carrier_angle.back() - s.carrier_angle.front();
  const int revs = static_cast<int>(std::floor(total / (2 * kPi) + 1e-9));
  const double fs = 1.0 / dt;
  const double edge = o.layout.band_fraction * fs / s.kinematics.carrier_Hz;
  const double max_order = o.max_order > 0 ? std::min(edge, o.max_order) : edge;
  if (revs >= 2 && o.mesh_cycles == 0) {
    const int R = std::max(1, std::min(revs / 2, o.max_window_revolutions));
    s.layout = make_layout(s.kinematics, stage.planet_count, R, max_order, o.layout);
  } else {
    // Too short for two halves of whole carrier revolutions (or asked for): halves of Q whole
    // mesh cycles.
    const double cycles = total / (2 * kPi) * s.kinematics.ring_teeth;
    const int need = min_recording_mesh_cycles(s.kinematics.sun_teeth);
    const int Q = o.mesh_cycles > 0 ? o.mesh_cycles : short_window_mesh_cycles(s.kinematics, cycles);
    require(Q > 0 && cycles >= need, "recording", rec.source, ": ", cycles, " mesh cycles (", total / (2 * kPi),
            " carrier revolutions); the diagnosis needs at least ", need,
            " mesh cycles: a fit and a held-out half of one sun period (Zs = ", s.kinematics.sun_teeth,
            " mesh cycles) each");
    require(2 * Q <= cycles + 1e-9, "recording", rec.source, ": ", cycles, " mesh cycles, fewer than two halves of ",
            Q, " mesh cycles");
    s.layout = make_layout_mesh_cycles(s.kinematics, stage.planet_count, Q, max_order, o.layout);
    drop_housing_channels(rec, s);
  }
  require(s.layout.mesh_harmonics >= 1, "recording", rec.source, ": sample rate ", fs,
          " Hz leaves no mesh harmonic (", s.kinematics.mesh_Hz, " Hz) below ", o.layout.band_fraction, " fs");
}

/// The fit and held-out windows and every channel's order amplitudes in each (with their
/// derivatives in the angle reference's drift when the angle comes from a speed channel).
void window_amplitudes(const Recording& rec, RecordingSpectra& s) {
  const double R = s.layout.window_revolutions;
  const double total = s.carrier_angle.back() - s.carrier_angle.front();
  auto window = [&](std::string name, double a0) {
    OrderWindow w;
    w.name = std::move(name);
    w.angle_begin_rad = a0;
    const auto& th = s.carrier_angle;
    w.first_sample = static_cast<std::size_t>(std::lower_bound(th.begin(), th.end(), a0) - th.begin());
    w.last_sample =
        static_cast<std::size_t>(std::lower_bound(th.begin(), th.end(), a0 + 2 * kPi * R) - th.begin()) - 1;
    w.t_begin_s = rec.time_s[w.first_sample];
    w.t_end_s = rec.time_s[w.last_sample];
    return w;
  };
  s.windows.push_back(window("fit", 0.0));
  s.windows.push_back(window("held_out", total - 2 * kPi * R - 1e-9 * total));
  const std::size_t nc = s.channels.size();
  s.amplitude.assign(2, std::vector<std::vector<double>>(nc));
  const bool drifts = s.angle_reference == AngleReference::SunSpeed || s.angle_reference == AngleReference::CarrierSpeed;
  if (drifts) s.amplitude_drift.assign(2, std::vector<std::vector<double>>(nc));
#pragma omp parallel for schedule(dynamic, 1) collapse(2)
  for (int w = 0; w < 2; ++w)
    for (int c = 0; c < static_cast<int>(nc); ++c) {
      const auto& ch = rec.channels[static_cast<std::size_t>(s.channels[static_cast<std::size_t>(c)])];
      std::vector<std::complex<double>> dX;
      const auto X = angle_fourier(ch.values, s.carrier_angle, s.windows[static_cast<std::size_t>(w)].angle_begin_rad,
                                   R, s.layout.max_bin, drifts ? &dX : nullptr);
      std::vector<double> a(X.size()), da(drifts ? X.size() : 0, 0.0);
      for (std::size_t k = 0; k < X.size(); ++k) {
        a[k] = std::abs(X[k]);
        // d|c|/d delta = Re(conj(c) dc/d delta) / |c|
        if (drifts && a[k] > 0) da[k] = std::real(std::conj(X[k]) * dX[k]) / a[k];
      }
      s.amplitude[static_cast<std::size_t>(w)][static_cast<std::size_t>(c)] = std::move(a);
      if (drifts) s.amplitude_drift[static_cast<std::size_t>(w)][static_cast<std::size_t>(c)] = std::move(da);
    }
}

/// Family-wise false-alarm probability of find_alien_lines over a channel's bins: the diagnosis's
/// default alpha (a line found by chance at this rate only adds variance, never a finding).
constexpr double kAlienAlpha = 0.01;
/// Hann main-lobe half-width [bins]: a peak nearer than this to a labelled line is that line's.
constexpr double kHannMainLobeBins = 2.0;
/// Bins of the window a leak is followed (the rectangular kernel is below 0.5 % of the line beyond).
constexpr double kAlienLeakBins = 64.0;

/// Lines of channel c that no gear family makes (docs/diagnose.md §2, "Lines at no gear
/// order"): local maxima of the whole recording's Hann periodogram p_b (normalised as in
/// estimate_noise: white noise of per-sample variance s_w^2 reads s_w^2, exponential) above
/// ln(n / alpha) times the noise there (n the bins searched: a family-wise alpha under the
/// noise alone), farther than the Hann main lobe from every labelled line and from order 0.
/// Order by parabolic interpolation of ln p over the peak's neighbours; amplitude from the Hann
/// DTFT there (no scalloping loss).
std::vector<RecordingSpectra::AlienLine> find_alien_lines(const std::vector<double>& values, const std::vector<double>& time,
                                                          std::span<const std::complex<double>> X, double sw2, double wsum,
                                                          double df, double fc, const FeatureLayout& layout,
                                                          const std::vector<double>& noise_by_bin) {
  std::vector<RecordingSpectra::AlienLine> found;
  std::size_t last = 1;
  while (last + 1 < X.size() && static_cast<double>(last + 1) * df / fc <= layout.max_order) ++last;
  if (last < 3) return found;
  const double threshold = std::log(static_cast<double>(last) / kAlienAlpha);
  const double lobe = kHannMainLobeBins * df / fc;  // [orders]
  std::vector<double> labelled;
  for (const OrderLine& l : layout.lines) labelled.push_back(l.order);
  std::sort(labelled.begin(), labelled.end());
  auto p = [&](std::size_t b) { return std::norm(X[b]) / sw2; };
  for (std::size_t b = 2; b < last; ++b) {
    const double pb = p(b);
    if (!(pb > threshold * noise_by_bin[b]) || pb < p(b - 1) || pb < p(b + 1)) continue;
    const double l0 = std::log(p(b - 1)), l1 = std::log(pb), l2 = std::log(p(b + 1));
    const double den = l0 - 2 * l1 + l2;
    const double delta = den < 0 ? std::clamp(0.5 * (l0 - l2) / den, -0.5, 0.5) : 0.0;
    const double f = (static_cast<double>(b) + delta) * df;
    const double order = f / fc;
    if (order < lobe) continue;
    const auto it = std::lower_bound(labelled.begin(), labelled.end(), order);
    const double inf = std::numeric_limits<double>::infinity();
    const double near = std::min(it != labelled.end() ? *it - order : inf,
                                 it != labelled.begin() ? order - *(it - 1) : inf);
    if (near <= lobe) continue;
    found.push_back({order, 2 * hann_dtft_abs(values, time, f) / wsum});
  }
  return found;
}

/// Each cell's leak from the channel's alien lines through the window's rectangular kernel
/// |sinc(W (o - x))| (x the cell's order, W the window in revolutions; a line's |c_k| is half its
/// amplitude): {sum of squares, largest square}. Lines the baseline does not hold are left out.
std::vector<std::array<double, 2>> alien_leak(const std::vector<RecordingSpectra::AlienLine>& lines,
                                              const FeatureLayout& layout) {
  const double W = layout.window_revolutions;
  std::vector<std::array<double, 2>> leak(layout.cells.size(), {0.0, 0.0});
  for (std::size_t i = 0; i < layout.cells.size(); ++i)
    for (const auto& a : lines) {
      if (!a.in_baseline) continue;  // not the rig's own tone: left to the diagnosis
      const double d = W * (a.order - layout.cells[i].order);
      if (std::fabs(d) > kAlienLeakBins) continue;
      const double k = d == 0 ? 1.0 : std::sin(kPi * d) / (kPi * d);
      const double l2 = 0.25 * a.amplitude * a.amplitude * k * k;
      leak[i][0] += l2;
      leak[i][1] = std::max(leak[i][1], l2);
    }
  return leak;
}

/// The noise variance of every cell (see the comment inside).
void estimate_noise(const Recording& rec, const model::StageSpec& stage, RecordingSpectra& s) {
  const std::size_t n = rec.time_s.size();
  const double dt = rec.sample_interval_s();
  const double R = s.layout.window_revolutions;
  const std::size_t nc = s.channels.size();
  // Noise (docs/diagnose.md §2). The features' own bins are no place to measure it: lines that
  // are not integer orders leak into every bin of a rectangular window. So, per channel, the
  // Hann-windowed periodogram of the whole recording (leakage falls as 1/d^3), normalised so
  // that white noise of per-sample variance s_w^2 reads s_w^2, over the frequencies more than
  // 4 N + 8 carrier orders (or fewer, see below) from every mesh harmonic (and from 0): between the sideband groups,
  // where a gear signal has little. Its bins are exponential with mean s_w^2; estimated by the
  // truncated mean (exponential_mean). Global unless the per-segment estimates (between
  // consecutive mesh harmonics, +-2 segments) disagree beyond their errors (chi-square
  // homogeneity test at 1 %): coloured noise, local estimates. A window's bin then has noise
  // variance s_w^2 sum_j w_j^2 (its trapezoid weights, sum w_j = 1).
  const double zr = s.kinematics.ring_teeth;
  const int nseg = s.layout.segments;
  double w2[2];
  for (int w = 0; w < 2; ++w) {
    const auto& win = s.windows[static_cast<std::size_t>(w)];
    const auto& th = s.carrier_angle;
    double sum2 = 0;
    const double span = 2 * kPi * R;
    for (std::size_t j = win.first_sample; j <= win.last_sample; ++j) {
      const double lo = j > win.first_sample ? th[j - 1] : win.angle_begin_rad;
      const double hi = j < win.last_sample ? th[j + 1] : win.angle_begin_rad + span;
      const double wj = 0.5 * (hi - lo) / span;
      sum2 += wj * wj;
    }
    w2[w] = sum2;
  }
  const double w2mean = 0.5 * (w2[0] + w2[1]);
  s.noise_variance.assign(nc, {});
  s.noise_relative_se.assign(nc, {});
  s.noise_group.assign(nc, {});
  s.noise_floor.assign(nc, 0.0);
  s.noise_bins_used.assign(nc, 0);
  s.noise_local.assign(nc, false);
  s.alien_lines.assign(nc, {});
  s.alien_leak.assign(nc, {});
  {
    const std::size_t nn = n;
    const auto hw = signal::window_coefficients(signal::Window::Hann, nn);
    double sw2 = 0;
    for (double v : hw) sw2 += v * v;
    signal::RealFft fft(nn);
    std::vector<std::complex<double>> X(fft.bins());
    std::vector<double> y(nn);
    const double df = 1.0 / (static_cast<double>(nn) * dt);
    const double fc = s.kinematics.carrier_Hz;
    std::vector<std::size_t> kbins;
    std::vector<int> kseg;
    // Carrier orders kept clear of each mesh harmonic: k (N + 2), sidebands up to the k-th
    // planet-pass order and two more, k = 4 where that leaves at least kMinNoiseBins bins. A
    // stage with many planets on a small ring has its sideband groups touching (eight planets
    // on Zr = 74: 4 (N + 2) = 40 > Zr / 2, no bin left); k then steps down until enough bins
    // remain: the estimate takes sideband lines in with the noise, which the truncated mean
    // (exponential_mean) trims and which can only raise it (a less sensitive test, never a
    // more confident one).
    constexpr std::size_t kMinNoiseBins = 32;
    for (int k = 4; k >= 1; --k) {
      const double gap = k * (stage.planet_count + 2.0);
      kbins.clear();
      kseg.clear();
      for (std::size_t b = 1; b < X.size(); ++b) {
        const double ord = static_cast<double>(b) * df / fc;
        if (ord > s.layout.max_order) break;
        const double dist = std::fabs(ord - zr * std::round(ord / zr));
        if (dist <= gap) continue;
        kbins.push_back(b);
        kseg.push_back(std::min(nseg - 1, static_cast<int>(std::floor(ord / zr + 0.5))));
      }
      s.noise_clearance_orders = gap;
      if (kbins.size() >= kMinNoiseBins) break;
    }
    require(kbins.size() >= kMinNoiseBins, "recording", rec.source, ": only ", kbins.size(),
            " frequencies (of at least ", kMinNoiseBins, ") lie more than ", s.noise_clearance_orders,
            " carrier orders from every mesh harmonic (every ", zr, " orders) below order ", s.layout.max_order,
            ", over ", s.layout.revolutions, " analysed carrier revolutions: too few to estimate the noise; a longer "
            "recording has more frequencies between the gear lines");
    for (std::size_t c = 0; c < nc; ++c) {
      const auto& v = rec.channels[static_cast<std::size_t>(s.channels[c])].values;
      double mean = 0;
      for (double x : v) mean += x;
      mean /= static_cast<double>(nn);
      for (std::size_t j = 0; j < nn; ++j) y[j] = (v[j] - mean) * hw[j];
      fft.forward(y, X);
      std::vector<std::vector<double>> per_seg(static_cast<std::size_t>(nseg));
      std::vector<double> all;
      for (std::size_t i = 0; i < kbins.size(); ++i) {
        const double p = std::norm(X[kbins[i]]) / sw2;
        per_seg[static_cast<std::size_t>(kseg[i])].push_back(p);
        all.push_back(p);
      }
      // Neighbouring Hann bins are correlated: about 1.94 bins per independent value.
      constexpr double kHannBins = 1.944;
      double gse = 0;
      const double global = exponential_mean(all, &gse);
      gse *= std::sqrt(kHannBins);
      std::vector<double> local(static_cast<std::size_t>(nseg), global), lse(static_cast<std::size_t>(nseg), gse);
      double het = 0;
      int dof = 0;
      for (int seg = 0; seg < nseg; ++seg) {
        std::vector<double> p;
        for (int q = std::max(0, seg - 2); q <= std::min(nseg - 1, seg + 2); ++q)
          p.insert(p.end(), per_seg[static_cast<std::size_t>(q)].begin(), per_seg[static_cast<std::size_t>(q)].end());
        if (p.size() < 32) continue;
        local[static_cast<std::size_t>(seg)] = exponential_mean(p, &lse[static_cast<std::size_t>(seg)]);
        lse[static_cast<std::size_t>(seg)] *= std::sqrt(kHannBins);
        if (seg % 5 == 2) {  // roughly independent groups
          const double dd = (local[static_cast<std::size_t>(seg)] - global) /
                            (local[static_cast<std::size_t>(seg)] * lse[static_cast<std::size_t>(seg)]);
          het += dd * dd;
          ++dof;
        }
      }
      const bool coloured = dof >= 2 && het > chi2_quantile(dof, 0.01);
      s.noise_local[c] = coloured;
      s.noise_bins_used[c] = static_cast<int>(all.size());
      s.noise_sample_variance.push_back(global);
      {
        // Lines at no gear order, against the noise of their segment (coloured) or the channel's.
        std::vector<double> noise_by_bin(X.size(), global);
        if (coloured)
          for (std::size_t b = 0; b < X.size(); ++b)
            noise_by_bin[b] = local[static_cast<std::size_t>(
                std::min(nseg - 1, std::max(0, static_cast<int>(std::floor(static_cast<double>(b) * df / fc / zr + 0.5)))))];
        double wsum = 0;
        for (double w : hw) wsum += w;
        s.alien_lines[c] = find_alien_lines(v, rec.time_s, X, sw2, wsum, df, fc, s.layout, noise_by_bin);
      }
      for (const auto& cell : s.layout.cells) {
        const std::size_t seg = static_cast<std::size_t>(std::min(nseg - 1, std::max(0, cell.segment)));
        const double var = (coloured ? local[seg] : global) * w2mean;
        s.noise_variance[c].push_back(var);
        s.noise_relative_se[c].push_back(coloured ? lse[seg] : gse);
        s.noise_group[c].push_back(coloured ? static_cast<int>(seg) / 5 : 0);
        s.noise_floor[c] += var / static_cast<double>(s.layout.cells.size());
      }
    }
    // Reported: which lines more than one channel holds (the machine's rather than a sensor's).
    // No leak is carried until a baseline says which lines are the rig's (carry_baseline_alien_lines).
    mark_lines_in_other_channels(s.alien_lines, kHannMainLobeBins * df / fc);
    s.alien_tolerance = kHannMainLobeBins * df / fc;
    for (std::size_t c = 0; c < nc; ++c) s.alien_leak[c] = alien_leak(s.alien_lines[c], s.layout);
  }
}

/// The extra noise the angle reference's random walk leaks into the cells near strong lines.
void add_angle_drift_leak(const Recording& rec, const model::StageSpec& stage, RecordingSpectra& s) {
  const double R = s.layout.window_revolutions;
  const std::size_t nc = s.channels.size();
  const bool drifts = s.angle_reference == AngleReference::SunSpeed || s.angle_reference == AngleReference::CarrierSpeed;
  // The angle reference integrates a speed channel with white noise (per-sample variance
  // s_w^2): its error is a random walk B with diffusion D = s_w^2 dt k^2 (k = Zs/(Zs+Zr) for
  // the sun speed, 1 for the carrier speed). Over a window of length T, B(t) = B(T) t/T + a
  // Brownian bridge, independent of each other. A line of amplitude A at order o is phase
  // modulated by o times the error:
  //  * the linear part is one number per window, delta = B(T) ~ N(0, D T), shared by every
  //    line of every channel: the amplitudes move together along amplitude_drift (their
  //    derivative in delta). The comparison carries it as one low-rank column per window
  //    (compare.hpp), not as independent noise, because its leaks are correlated;
  //  * the bridge's Fourier coefficient d bins away has E|c_d|^2 = D T / (4 pi^2 d^2) (half the
  //    Brownian motion's D T / (2 pi^2 d^2), the other half being the linear part's
  //    E|B(T)|^2 / (4 pi^2 d^2)), so the line leaks A^2 o^2 D T / (4 pi^2 d^2) into the bins d
  //    away: independent extra noise power there.
  // With the per-bin noise variance of the speed channel, s_b^2 = s_w^2 / n, D T = s_b^2 T^2 k^2.
  if (drifts) {
    const Quantity q = s.angle_reference == AngleReference::SunSpeed ? Quantity::SunSpeed : Quantity::CarrierSpeed;
    const double k = q == Quantity::SunSpeed ? model::carrier_to_sun_ratio(stage) : 1.0;
    for (std::size_t c = 0; c < nc; ++c) {
      if (rec.channels[static_cast<std::size_t>(s.channels[c])].quantity != q) continue;
      const double T = 0.5 * ((s.windows[0].t_end_s - s.windows[0].t_begin_s) + (s.windows[1].t_end_s - s.windows[1].t_begin_s));
      s.angle_diffusion_T = s.noise_floor[c] * T * T * k * k;
      break;
    }
    constexpr int kD = RecordingSpectra::kBridgeBins;
    s.bridge_leak.assign(nc, std::vector<std::array<double, kD>>(s.layout.cells.size()));
    for (std::size_t c = 0; c < nc; ++c)
      for (std::size_t i = 0; i < s.layout.cells.size(); ++i) {
        const int b = s.layout.cells[i].bin;
        double leak = 0;
        auto& by_distance = s.bridge_leak[c][i];
        by_distance.fill(0.0);
        for (int d = -kD; d <= kD; ++d) {
          const int bl = b - d;
          if (d == 0 || bl < 1 || bl > s.layout.max_bin) continue;
          double p = 0;
          for (int w = 0; w < 2; ++w) {
            const double a = s.amplitude[static_cast<std::size_t>(w)][c][static_cast<std::size_t>(bl)];
            p += 0.5 * a * a;
          }
          const double ord = static_cast<double>(bl) / R;
          const double part = std::max(0.0, p - s.noise_variance[c][i]) * ord * ord * s.angle_diffusion_T / (4 * kPi * kPi * d * d);
          by_distance[static_cast<std::size_t>(std::abs(d) - 1)] += part;
          leak += part;
        }
        s.noise_variance[c][i] += leak;
      }
  }
}

} // namespace

RecordingSpectra analyse_recording(const Recording& rec, const model::StageSpec& stage,
                                   const OrderAnalysisOptions& o) {
  RecordingSpectra s;
  const std::size_t n = rec.time_s.size();
  const double dt = rec.sample_interval_s();
  require(n >= 64 && dt > 0, "recording", rec.source, ": too few samples (", n, ")");
  select_channels(rec, stage, s);
  s.speed = estimate_speed(rec, stage);
  s.kinematics = kinematics(stage, s.speed.input_rpm);
  s.carrier_angle = carrier_angle(rec, stage, s.speed, &s.angle_source);
  s.angle_reference = rec.find(Quantity::SunSpeed)       ? AngleReference::SunSpeed
                      : rec.find(Quantity::CarrierSpeed) ? AngleReference::CarrierSpeed
                      : s.angle_source.rfind("tacho", 0) == 0 ? AngleReference::Tacho
                                                               : AngleReference::ConstantSpeed;
  choose_layout(rec, stage, o, s);
  window_amplitudes(rec, s);
  estimate_noise(rec, stage, s);
  add_angle_drift_leak(rec, stage, s);
  return s;
}

std::string model_channel_name(const SignalChannel& c) {
  switch (c.quantity) {
  case Quantity::SunSpeed: return "sun/speed";
  case Quantity::CarrierSpeed: return "carrier/speed";
  case Quantity::MeshAccelerationSunPlanet: return "sun_planet/" + std::to_string(c.planet) + "/acceleration";
  case Quantity::MeshAccelerationPlanetRing: return "planet_ring/" + std::to_string(c.planet) + "/acceleration";
  case Quantity::HousingAcceleration: return "";
  case Quantity::Tacho: return "";
  }
  return "";
}

namespace {

/// An angle reference over one compared window: theta_j [rad] from 0 at the window's first
/// sample up to a few samples past 2 pi R (the interpolation stencil's right end).
struct ModelAngle {
  std::vector<double> theta;
};

/// The model's angle reference over its whole record, as the recording's: the integral of the
/// same speed channel averaged over one mesh period (or uniform time when the recording's angle
/// came from a tacho or a constant speed). theta_j [rad] from theta_0 = 0 at the record's first
/// sample.
std::vector<double> model_angle_record(const model::SimulationResult& r, const RecordingSpectra& s,
                                       const model::StageSpec& st) {
  const double dt = r.time_step_s;
  const model::Channel* ca = r.find("carrier/angle");
  if (!ca) throw SolverError("diagnose: the simulation has no channel 'carrier/angle'");
  const std::size_t n = ca->values.size();
  if (n < 8) throw SolverError("diagnose: the simulated record is empty");
  std::vector<double> th(n);
  const double ratio = st.sun.teeth / static_cast<double>(st.sun.teeth + st.ring.teeth);
  const model::Channel* speed = nullptr;
  double scale = 1;
  if (s.angle_reference == AngleReference::SunSpeed) speed = r.find("sun/speed"), scale = ratio;
  if (s.angle_reference == AngleReference::CarrierSpeed) speed = r.find("carrier/speed");
  if (speed) {
    const double omega = (ca->values.back() - ca->values.front()) / (static_cast<double>(n - 1) * dt);
    const double mesh_samples = 2 * kPi / (omega * st.ring.teeth) / dt;
    const auto w = mesh_period_average(speed->values, mesh_samples);
    th[0] = 0;
    for (std::size_t j = 1; j < n; ++j) th[j] = th[j - 1] + 0.5 * (w[j] + w[j - 1]) * dt * scale;
  } else {
    const double omega = (ca->values.back() - ca->values.front()) / (static_cast<double>(n - 1) * dt);
    for (std::size_t j = 0; j < n; ++j) th[j] = omega * dt * static_cast<double>(j);
  }
  return th;
}

/// Samples past 2 pi R that the cubic stencil may read.
constexpr std::size_t kStencilTail = 3;

/// One past the last sample a window of R carrier revolutions from sample `first` of the
/// record's angle `th` reads (the stencil's tail included); more than th.size() if it does not fit.
std::size_t window_end(const std::vector<double>& th, std::size_t first, double R) {
  return static_cast<std::size_t>(std::lower_bound(th.begin(), th.end(), th[first] + 2 * kPi * R) - th.begin()) +
         kStencilTail;
}

/// The angle of the window of R carrier revolutions that starts at sample `first` of the
/// record's angle `th`, from 0 at that sample up to a few samples past 2 pi R.
ModelAngle window_angle(const std::vector<double>& th, std::size_t first, double R) {
  const std::size_t end = window_end(th, first, R);
  if (end > th.size())
    throw SolverError(detail::concat("diagnose: the simulated record covers ", (th.back() - th[first]) / (2 * kPi),
                                     " carrier revolutions from the window's start, fewer than the ", R, " compared"));
  ModelAngle a;
  a.theta.assign(th.begin() + static_cast<long>(first), th.begin() + static_cast<long>(end));
  if (first > 0)
    for (double& v : a.theta) v -= th[first];
  return a;
}

/// |c_k|, k = 0 .. max_bin, of y (sampled at the angles theta) over its first R carrier
/// revolutions: y is resampled onto a uniform angle grid of about as many points as it has
/// samples there (cubic Lagrange; the model is sampled far above the analysed band, so the
/// interpolation error is negligible there) and transformed, c_k = (1/M) sum_j y(theta_j)
/// e^{-2 pi i j k / M}. *Why resampling, not an expansion in the angle deviation:* a torque
/// ripple of a few percent swings the angle by ~0.01 rad, q phi then reaches tens of radians at
/// the analysed orders q, where no truncated series holds.
/// Over W carrier revolutions, whole or not: against the angle in units of the window,
/// theta / W, the window is one revolution and bin k is still carrier order k / W.
/// The resampling is planned once per angle reference (signal::CubicResamplePlan) and applied to
/// every channel sampled at it: the channels of one simulation share their angle, and the
/// stencils' weights were a quarter of a diagnosis's spectra (perf, session 42).
class AngleSpectrum {
public:
  AngleSpectrum(const ModelAngle& a, double W, int max_bin) : max_bin_(max_bin) {
    const int whole = static_cast<int>(W);
    const bool integer = whole >= 1 && static_cast<double>(whole) == W;
    std::vector<double> scaled;
    if (!integer) {
      scaled.resize(a.theta.size());
      for (std::size_t j = 0; j < scaled.size(); ++j) scaled[j] = a.theta[j] / W;
    }
    const std::span<const double> theta = integer ? std::span<const double>(a.theta) : std::span<const double>(scaled);
    const int R = integer ? whole : 1;
    n_ = theta.size();
    const std::size_t inside = static_cast<std::size_t>(
        std::lower_bound(theta.begin(), theta.end(), 2 * kPi * R) - theta.begin());
    const int per_rev =
        std::max(2 * (max_bin / R + 1), static_cast<int>((inside + R / 2) / static_cast<std::size_t>(R)));
    M_ = static_cast<std::size_t>(per_rev) * static_cast<std::size_t>(R);
    plan_.emplace(theta, per_rev, M_);
    if (plan_->record_points() < M_)
      throw SolverError(detail::concat("diagnose: resampled record has ", plan_->record_points(), " points, fewer than ", M_));
  }

  /// The amplitudes of y, sampled at the plan's angles (its first n samples are read).
  std::vector<double> operator()(std::span<const double> y) const {
    std::vector<double> z = plan_->apply(y.first(n_));
    double mean = 0;
    for (double v : z) mean += v;
    mean /= static_cast<double>(M_);
    for (double& v : z) v -= mean;
    signal::RealFft& fft = signal::thread_real_fft(M_);
    std::vector<std::complex<double>> Y(fft.bins());
    fft.forward(z, Y);
    std::vector<double> out(static_cast<std::size_t>(max_bin_) + 1, 0.0);
    for (std::size_t k = 1; k < out.size() && k < Y.size(); ++k) out[k] = std::abs(Y[k]) / static_cast<double>(M_);
    return out;
  }

private:
  int max_bin_ = 0;
  std::size_t n_ = 0, M_ = 0;
  std::optional<signal::CubicResamplePlan> plan_;
};

/// Halves of Q mesh cycles only (docs/diagnose.md section 2, "Short recordings"): per channel and
/// bin, the mean square change of the model's amplitude when its window starts elsewhere in
/// the gear pattern, over kLeakWindows - 1 starts j Q / kLeakWindows mesh cycles (j >= 1) after
/// the first. Why: the planet, carrier and input-shaft lines complete no whole period in Q mesh
/// cycles, so they leak into the compared cells with a phase set by where a window starts; the
/// recording's halves start at places the model's one window does not share (no absolute
/// angle), and a healthy recording's chi2 followed the data segment by 6 noise standard
/// deviations (docs/diagnose-log.md, session 29). Empty when the record is too short for every
/// start. Housing channels (not compared in such halves) get 0.
std::vector<std::vector<double>> window_start_variance(const model::SimulationResult& r, const Recording& rec,
                                                       const RecordingSpectra& s, const std::vector<double>& th,
                                                       const std::vector<std::vector<double>>& first) {
  const double R = s.layout.window_revolutions;
  std::vector<std::vector<double>> var(first.size());
  for (std::size_t c = 0; c < first.size(); ++c) var[c].assign(first[c].size(), 0.0);
  for (int j = 1; j < kLeakWindows; ++j) {
    const double a0 = 2 * kPi * R * j / kLeakWindows;
    const std::size_t i0 = static_cast<std::size_t>(std::lower_bound(th.begin(), th.end(), a0) - th.begin());
    if (i0 >= th.size() || window_end(th, i0, R) > th.size()) return {};
    const AngleSpectrum spectrum(window_angle(th, i0, R), R, s.layout.max_bin);
    for (std::size_t c = 0; c < s.channels.size(); ++c) {
      const auto& rc = rec.channels[static_cast<std::size_t>(s.channels[c])];
      if (rc.quantity == Quantity::HousingAcceleration) continue;
      // Present: model_spectra found every non-housing channel before calling here.
      const model::Channel& mc = *r.find(model_channel_name(rc));
      const auto a = spectrum(std::span<const double>(mc.values).subspan(i0));
      for (std::size_t k = 0; k < a.size() && k < var[c].size(); ++k) {
        const double d = a[k] - first[c][k];
        var[c][k] += d * d / (kLeakWindows - 1);
      }
    }
  }
  return var;
}

} // namespace

model::OutputSelection model_channels(const Recording& rec, const RecordingSpectra& s,
                                      const model::SimulationConfig& config) {
  model::OutputSelection sel;
  sel.mesh_load_summary = false;  // the comparison reads time histories only
  sel.channels = {"carrier/angle", "sun/speed", "carrier/speed"};
  for (int i = 0; i < config.stage.planet_count; ++i) sel.channels.push_back("planet_ring/" + std::to_string(i) + "/force");
  // The ring_body housing path reads the ring's accelerations (model/sensor.hpp Eq. S3); the
  // simulation records them only for that path, so they are asked for only then.
  if (config.sensor.housing_path == model::HousingPath::RingBody) sel.channels.push_back("ring/");
  for (int ch : s.channels) {
    const std::string name = model_channel_name(rec.channels[static_cast<std::size_t>(ch)]);
    if (!name.empty()) sel.channels.push_back(name);
  }
  return sel;
}

ModelSpectra model_spectra(const model::SimulationResult& r, const Recording& rec, const RecordingSpectra& s,
                           const model::SimulationConfig& config, bool keep) {
  const double R = s.layout.window_revolutions;
  const std::vector<double> th = model_angle_record(r, s, config.stage);
  const ModelAngle ang = window_angle(th, 0, R);
  const std::size_t N = ang.theta.size();
  const AngleSpectrum spectrum(ang, R, s.layout.max_bin);
  const model::Channel* ca = r.find("carrier/angle");
  ModelSpectra m;
  m.time_step_s = r.time_step_s;
  for (const auto& sc : r.scalars) {
    if (sc.name == "steps_per_mesh_period") m.steps_per_mesh = static_cast<int>(sc.value);
    if (sc.name == "warmup_mesh_cycles") m.warmup_mesh_cycles = static_cast<int>(sc.value);
    if (sc.name == "planet_ring/working_pressure_angle") m.ring_pressure_angle_rad = sc.value;
    if (sc.name == "ring/mass") m.ring_mass_kg = sc.value;
  }
  if (const model::Channel* sp = r.find("sun/speed")) {
    double sum = 0;
    for (std::size_t j = 0; j < N; ++j) sum += sp->values[j];
    m.mean_input_rpm = sum / static_cast<double>(N) * 60 / (2 * kPi);
  }
  std::vector<double> psi = config.stage.planet_angles_rad;
  if (psi.empty())
    for (int i = 0; i < config.stage.planet_count; ++i) psi.push_back(2 * kPi * i / config.stage.planet_count);
  std::vector<std::span<const double>> forces;
  model::RingBodyAcceleration ring;
  const bool ring_body = config.sensor.housing_path == model::HousingPath::RingBody;
  auto need_forces = [&]() {
    if (!forces.empty()) return;
    for (int i = 0; i < config.stage.planet_count; ++i) {
      const model::Channel* f = r.find("planet_ring/" + std::to_string(i) + "/force");
      if (!f) throw SolverError("diagnose: the simulation has no ring-mesh force of planet " + std::to_string(i));
      forces.emplace_back(f->values.data(), N);
    }
    if (!ring_body) return;
    const model::Channel* ax = r.find("ring/acceleration_x");
    const model::Channel* ay = r.find("ring/acceleration_y");
    if (!ax || !ay || !(m.ring_mass_kg > 0))
      throw SolverError("diagnose: the simulation has no ring/acceleration_x, _y or ring/mass for the ring body");
    ring = {m.ring_mass_kg, std::span<const double>(ax->values.data(), N), std::span<const double>(ay->values.data(), N)};
  };
  for (int ch : s.channels) {
    const auto& rc = rec.channels[static_cast<std::size_t>(ch)];
    if (rc.quantity == Quantity::HousingAcceleration) {
      need_forces();
      model::SensorSettings sensor = config.sensor;
      if (sensor.housing_path == model::HousingPath::RingTranslation && !std::isfinite(m.ring_pressure_angle_rad))
        throw SolverError("diagnose: the simulation has no planet_ring/working_pressure_angle for the ring's translation");
      sensor.gain_m_s2_per_N = 1.0;
      sensor.angle_rad = rc.sensor_angle_rad;
      const auto h = model::housing_acceleration_history(sensor, psi, m.ring_pressure_angle_rad,
                                                          std::span<const double>(ca->values.data(), N), forces,
                                                          r.time_step_s, ring);
      m.amplitude.push_back(spectrum(h));
      continue;
    }
    const std::string name = model_channel_name(rc);
    const model::Channel* mc = r.find(name);
    if (!mc) throw SolverError("diagnose: the simulation has no channel '" + name + "'");
    m.amplitude.push_back(spectrum(mc->values));
  }
  if (s.layout.mesh_cycles > 0) m.leak_variance = window_start_variance(r, rec, s, th, m.amplitude);
  if (keep) {
    need_forces();
    for (const auto& f : forces) m.ring_force.emplace_back(f.begin(), f.end());
    m.ring_acceleration_x.assign(ring.x_m_s2.begin(), ring.x_m_s2.end());
    m.ring_acceleration_y.assign(ring.y_m_s2.begin(), ring.y_m_s2.end());
    m.carrier_angle.assign(ca->values.begin(), ca->values.begin() + static_cast<long>(N));
    m.planet_angles_rad = psi;
    m.angle_theta = ang.theta;
  }
  return m;
}

std::vector<double> housing_spectrum(const ModelSpectra& m, const model::SensorSettings& sensor, double angle_rad,
                                     double revolutions, int max_bin) {
  require(!m.ring_force.empty(), "model", "no sensor inputs kept for this simulation");
  model::SensorSettings s = sensor;
  s.gain_m_s2_per_N = 1.0;
  s.angle_rad = angle_rad;
  std::vector<std::span<const double>> f;
  for (const auto& v : m.ring_force) f.emplace_back(v);
  const auto y = model::housing_acceleration_history(s, m.planet_angles_rad, m.ring_pressure_angle_rad, m.carrier_angle,
                                                     f, m.time_step_s,
                                                     {m.ring_mass_kg, m.ring_acceleration_x, m.ring_acceleration_y});
  return AngleSpectrum(ModelAngle{m.angle_theta}, revolutions, max_bin)(y);
}

bool reference_covers(const RecordingSpectra& reference, const RecordingSpectra& recording) {
  const FeatureLayout& a = recording.layout;
  const FeatureLayout& b = reference.layout;
  if (a.revolutions != b.revolutions || a.mesh_cycles != b.mesh_cycles) return false;
  for (const std::string& c : recording.channel_names)
    if (std::find(reference.channel_names.begin(), reference.channel_names.end(), c) == reference.channel_names.end())
      return false;
  for (const FeatureCell& ca : a.cells) {
    const auto same = [&](const FeatureCell& cb) {  // as ModelComparison::match_baseline matches them
      return std::fabs(cb.order - ca.order) <= 1e-9 * std::max(1.0, std::fabs(ca.order));
    };
    if (std::none_of(b.cells.begin(), b.cells.end(), same)) return false;
  }
  return true;
}

std::optional<OrderAnalysisOptions> common_analysis_options(const Recording& recording, const model::StageSpec& stage,
                                                            const RecordingSpectra& recording_default,
                                                            const Recording& reference,
                                                            const model::StageSpec& reference_stage) {
  OrderAnalysisOptions o;
  const RecordingSpectra& a = recording_default;
  const RecordingSpectra b = analyse_recording(reference, reference_stage, o);
  if (reference_covers(b, a)) return o;
  if (a.layout.mesh_cycles == 0 && b.layout.mesh_cycles == 0) {
    o.max_window_revolutions = std::min(a.layout.revolutions, b.layout.revolutions);
  } else {
    const auto q = [](const RecordingSpectra& s) {
      return s.layout.mesh_cycles > 0 ? s.layout.mesh_cycles : std::numeric_limits<int>::max();
    };
    o.mesh_cycles = std::min(q(a), q(b));
  }
  const RecordingSpectra a2 = analyse_recording(recording, stage, o);
  const RecordingSpectra b2 = analyse_recording(reference, reference_stage, o);
  if (reference_covers(b2, a2)) return o;
  // The band edges: both up to the lower one, when the two share their sample rate (to 0.1 %:
  // the first time step of a column printed to 1e-8 s at 25 kHz is known to 2.5e-4 of itself),
  // so that the edges differ only by the measured speeds. Another sample rate stays refused: its
  // anti-aliasing and its noise per bin are another recording chain. The edge is max_bin / W; a
  // relative 1e-9 above it keeps floor(edge W) at max_bin against the round-off of the division
  // (W <= 3 revolutions or Q / Zr, max_bin < 1e6: far below 1e-9 of a bin).
  if (std::fabs(recording.sample_interval_s() / reference.sample_interval_s() - 1) > 1e-3) return std::nullopt;
  o.max_order = std::min(a2.layout.max_order, b2.layout.max_order) * (1 + 1e-9);
  if (reference_covers(analyse_recording(reference, reference_stage, o), analyse_recording(recording, stage, o)))
    return o;
  return std::nullopt;
}

void mark_lines_in_other_channels(std::vector<std::vector<RecordingSpectra::AlienLine>>& lines, double tolerance) {
  for (std::size_t c = 0; c < lines.size(); ++c)
    for (auto& a : lines[c]) {
      a.in_other_channels = false;
      for (std::size_t o = 0; o < lines.size() && !a.in_other_channels; ++o)
        if (o != c)
          for (const auto& b : lines[o])
            if (std::fabs(a.order - b.order) <= tolerance) {
              a.in_other_channels = true;
              break;
            }
    }
}


void carry_baseline_alien_lines(RecordingSpectra& s, const BaselineAlienLines& baseline, double tolerance) {
  const double tol = std::max(tolerance, baseline.tolerance);
  for (std::size_t c = 0; c < s.alien_lines.size(); ++c) {
    const auto it = baseline.orders.find(s.channel_names[c]);
    for (auto& a : s.alien_lines[c]) {
      a.in_baseline = false;
      if (it != baseline.orders.end())
        for (const double o : it->second)
          if (std::fabs(a.order - o) <= tol) a.in_baseline = true;
    }
    s.alien_leak[c] = alien_leak(s.alien_lines[c], s.layout);
  }
}

} // namespace pw::diagnose
