#include "diagnose/compare.hpp"

#include "core/error.hpp"
#include "model/sensor.hpp"
#include "model/simulation.hpp"
#include "signal/fft.hpp"
#include "signal/spectrum.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace pw::diagnose {
namespace {

constexpr std::size_t kCacheEntries = 24;

bool tooth_level(const model::SimulationConfig& c) {
  const auto& i = c.imperfections;
  return !i.teeth.empty() || i.sun_eccentricity_m != 0 || i.torque_ripple_fraction != 0;
}

/// A configuration's identity for the cache: every field that changes the dynamics (not the sensor).
/// Gear materials are left out: one ModelComparison serves one gear set.
std::string config_key(const model::SimulationConfig& c) {
  char buf[64];
  std::string k;
  auto add = [&](double v) {
    std::snprintf(buf, sizeof buf, "%.17g,", v);
    k += buf;
  };
  const auto& s = c.stage;
  for (const auto* g : {&s.sun, &s.planet, &s.ring}) {
    add(g->teeth); add(g->module_m); add(g->pressure_angle_rad); add(g->profile_shift); add(g->addendum_coef);
    add(g->dedendum_coef); add(g->root_fillet_coef); add(g->face_width_m);
  }
  add(s.planet_count); for (double a : s.planet_angles_rad) add(a);
  add(s.carrier_inertia_kgm2); add(s.carrier_mass_kg); add(s.bore_ratio);
  add(c.operating.input_speed_rpm); add(c.operating.input_power_W);
  add(c.stiffness.samples_per_pair); add(c.stiffness.include_fillet_foundation); add(c.stiffness.scale);
  const auto& ct = c.contact;
  add(ct.friction_coefficient); add(ct.friction_smoothing_m_s); add(ct.mesh_damping_ratio);
  add(ct.backlash_sun_planet_m); add(ct.backlash_planet_ring_m); add(ct.mesh_error_sun_planet_m);
  add(ct.mesh_error_planet_ring_m);
  const auto& im = c.imperfections;
  k += "|";
  for (double e : im.pin_error_m) add(e);
  add(im.sun_eccentricity_m); add(im.sun_eccentricity_phase_rad); add(im.carrier_eccentricity_m);
  add(im.carrier_eccentricity_phase_rad); add(im.torque_ripple_fraction); add(im.torque_ripple_order);
  add(im.worn_profile_depth_m);
  for (const auto& t : im.teeth) {
    add(static_cast<int>(t.body)); add(t.planet); add(t.tooth); add(t.stiffness_factor); add(t.profile_deviation_m);
  }
  k += "|";
  const auto& b = c.bearings;
  add(b.sun_N_m); add(b.carrier_N_m); add(b.ring_N_m); add(b.planet_N_m); add(b.ring_torsional_N_m);
  const auto& v = c.solver;
  add(static_cast<int>(v.level)); add(v.time_step_s); add(v.min_steps_per_mesh); add(v.steps_per_mode_period);
  add(v.newmark_beta); add(v.newmark_gamma); add(v.newton_tolerance); add(v.newton_max_iterations);
  add(v.warmup_max_mesh_cycles); add(v.periodicity_tolerance);
  return k;
}

const model::Scalar* scalar(const model::SimulationResult& r, const std::string& name) {
  for (const auto& s : r.scalars)
    if (s.name == name) return &s;
  return nullptr;
}

} // namespace

double SimulatedSignals::t_end_s() const {
  const std::size_t n = carrier_angle_rad.size();
  return t0_s + static_cast<double>(n > 0 ? n - 1 : 0) * dt_s;
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

ModelComparison::ModelComparison(const Recording& recording, const model::SimulationConfig& base,
                                 double earliest_start_s, CompareOptions options)
    : rec_(recording), base_(base), opt_(options) {
  kin_ = diagnose::kinematics(base.stage, base.operating.input_speed_rpm);
  const std::size_t n_all = rec_.time_s.size();
  const double dt = rec_.sample_interval_s();
  require(n_all >= 64 && dt > 0, "recording", rec_.source, ": too few samples (", n_all, ")");
  for (std::size_t c = 0; c < rec_.channels.size(); ++c) {
    const auto& ch = rec_.channels[c];
    if (ch.quantity == Quantity::Tacho) continue;
    require(ch.values.size() == n_all, "recording", "channel '", ch.name, "' has ", ch.values.size(),
            " samples, the time axis ", n_all);
    if (ch.quantity == Quantity::MeshAccelerationSunPlanet || ch.quantity == Quantity::MeshAccelerationPlanetRing)
      require(ch.planet >= 0 && ch.planet < base.stage.planet_count, "recording", "channel '", ch.name,
              "': planet ", ch.planet, " does not exist (", base.stage.planet_count, " planets)");
    used_.push_back(static_cast<int>(c));
    noise_.push_back(estimate_white_noise(ch.values));
  }
  require(!used_.empty(), "recording", rec_.source, ": no channel the model can predict");

  const double T = opt_.window_carrier_revolutions / kin_.carrier_Hz;
  const std::size_t n = static_cast<std::size_t>(std::llround(T / dt));
  std::size_t i_a = 0;
  while (i_a < n_all && rec_.time_s[i_a] < earliest_start_s) ++i_a;
  require(i_a + 2 * n <= n_all, "recording",
          rec_.source, ": ", static_cast<double>(n_all) * dt, " s from t = ", rec_.time_s[0], " s leaves less than two analysis windows of ",
          opt_.window_carrier_revolutions, " carrier revolution(s) (", T, " s each) after t = ", earliest_start_s, " s");
  const int k_max = static_cast<int>(std::floor(opt_.max_mesh_harmonic * kin_.mesh_Hz * static_cast<double>(n) * dt));
  require(k_max < static_cast<int>(n / 2) - 2, "recording", rec_.source, ": sample rate ", 1 / dt,
          " Hz is too low for ", opt_.max_mesh_harmonic, " mesh harmonics (", opt_.max_mesh_harmonic * kin_.mesh_Hz,
          " Hz)");
  auto make = [&](std::string name, std::size_t begin) {
    AnalysisWindow w;
    w.name = std::move(name);
    w.begin = begin;
    w.count = n;
    w.t_begin_s = rec_.time_s[begin];
    w.t_end_s = rec_.time_s[begin] + static_cast<double>(n) * dt;
    w.k_min = opt_.k_min;
    w.k_max = k_max;
    return w;
  };
  windows_.push_back(make("fit", i_a));
  windows_.push_back(make("held_out", n_all - n));
  for (const auto& w : windows_) {
    std::vector<std::vector<std::complex<double>>> per;
    for (int c : used_) {
      std::span<const double> x(rec_.channels[static_cast<std::size_t>(c)].values.data() + w.begin, w.count);
      per.push_back(hann_bins(x, w.k_min, w.k_max));
    }
    rec_bins_.push_back(std::move(per));
  }
}

int ModelComparison::dof(int w) const {
  const auto& win = window(w);
  return 2 * (win.k_max - win.k_min + 1) * static_cast<int>(used_.size());
}

std::vector<std::complex<double>> ModelComparison::hann_bins(std::span<const double> x, int k_min, int k_max) const {
  const std::size_t n = x.size();
  const auto w = signal::window_coefficients(signal::Window::Hann, n);
  double mean = 0;
  for (double v : x) mean += v;
  mean /= static_cast<double>(n);
  std::vector<double> y(n);
  for (std::size_t j = 0; j < n; ++j) y[j] = (x[j] - mean) * w[j];
  signal::RealFft fft(n);
  std::vector<std::complex<double>> X(fft.bins());
  fft.forward(y, X);
  return {X.begin() + k_min, X.begin() + k_max + 1};
}

std::shared_ptr<const SimulatedSignals> ModelComparison::simulate(const model::SimulationConfig& config, double t_end,
                                                                  double fixed_dt) const {
  model::SimulationConfig c = config;
  if (fixed_dt > 0) c.solver.time_step_s = fixed_dt;
  const double fm = kin_.mesh_Hz;
  const double t_a = windows_.front().t_begin_s;
  const int cap = static_cast<int>(std::floor(t_a * fm)) - 1;
  require(cap >= 3, "recording", rec_.source, ": the fit window starts at t = ", t_a,
          " s, too early for the model's warm-up (>= 4 mesh periods); the time axis must be the absolute time "
          "of the model (docs/recordings.md)");
  c.solver.warmup_max_mesh_cycles = std::min(c.solver.warmup_max_mesh_cycles, cap);
  const std::string key = config_key(c) + "#" + std::to_string(t_end);
  const int cls = tooth_level(c) ? 1 : 0;
  int guess = 3;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (auto it = cache_.find(key); it != cache_.end()) return it->second;
    if (auto it = warmup_seen_.find(cls); it != warmup_seen_.end()) guess = std::max(3, it->second - 3);
  }
  guess = std::min(guess, c.solver.warmup_max_mesh_cycles);
  c.solver.record_mesh_cycles = std::max(1, static_cast<int>(std::ceil(t_end * fm)) - guess + 3);
  const auto clock0 = std::chrono::steady_clock::now();
  model::SimulationResult r;
  for (int attempt = 0;; ++attempt) {
    model::validate(c);
    r = model::simulate(c);
    const double t0 = scalar(r, "record_start_time")->value;
    const double t_last = t0 + r.time_s.back();
    if (t_last >= t_end + 2 * r.time_step_s) break;
    if (attempt >= 2)
      throw SolverError(detail::concat("diagnose: simulation record ends at ", t_last, " s, before ", t_end, " s"));
    c.solver.record_mesh_cycles += static_cast<int>(std::ceil((t_end + 2 * r.time_step_s - t_last) * fm)) + 1;
  }
  auto s = std::make_shared<SimulatedSignals>();
  // time_s[k] = (k + 1) dt after the record start (simulation.cpp): sample k at t0_s + (k + 1) dt.
  s->t0_s = scalar(r, "record_start_time")->value + r.time_s.front();
  s->dt_s = r.time_step_s;
  s->warmup_mesh_cycles = static_cast<int>(scalar(r, "warmup_mesh_cycles")->value);
  s->steps_per_mesh = static_cast<int>(scalar(r, "steps_per_mesh_period")->value);
  bool housing = false;
  for (int ch : used_) {
    const auto& rc = rec_.channels[static_cast<std::size_t>(ch)];
    const std::string name = model_channel_name(rc);
    if (name.empty()) {
      housing = true;
      s->channels.emplace_back();
      continue;
    }
    const model::Channel* mc = r.find(name);
    if (!mc) throw SolverError("diagnose: the simulation has no channel '" + name + "'");
    s->channels.push_back(mc->values);
  }
  const model::Channel* ca = r.find("carrier/angle");
  if (!ca) throw SolverError("diagnose: the simulation has no channel 'carrier/angle'");
  s->carrier_angle_rad = ca->values;
  if (housing)
    for (int i = 0; i < c.stage.planet_count; ++i) s->ring_force_N.push_back(r.find("planet_ring/" + std::to_string(i) + "/force")->values);
  s->planet_angles_rad = c.stage.planet_angles_rad;
  if (s->planet_angles_rad.empty())
    for (int i = 0; i < c.stage.planet_count; ++i)
      s->planet_angles_rad.push_back(2 * std::numbers::pi * i / c.stage.planet_count);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
  std::lock_guard<std::mutex> lock(mutex_);
  ++sims_;
  sim_seconds_ += secs;
  warmup_seen_[cls] = s->warmup_mesh_cycles;
  cache_[key] = s;
  cache_order_.push_back(key);
  if (cache_order_.size() > kCacheEntries) {
    cache_.erase(cache_order_.front());
    cache_order_.erase(cache_order_.begin());
  }
  return s;
}

long ModelComparison::simulations() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sims_;
}
double ModelComparison::simulation_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sim_seconds_;
}

std::vector<double> ModelComparison::fine_signal(const SimulatedSignals& sim, const model::SimulationConfig& config,
                                                 int ch_pos, double t_begin, std::size_t n_fine,
                                                 double dt_fine) const {
  const auto& rc = rec_.channels[static_cast<std::size_t>(used_[static_cast<std::size_t>(ch_pos)])];
  std::vector<double> housing;
  const std::vector<double>* src = &sim.channels[static_cast<std::size_t>(ch_pos)];
  if (rc.quantity == Quantity::HousingAcceleration) {
    model::SensorSettings s = config.sensor;
    s.angle_rad = rc.sensor_angle_rad;
    s.gain_m_s2_per_N = 1.0;
    std::vector<std::span<const double>> forces;
    for (const auto& f : sim.ring_force_N) forces.emplace_back(f);
    housing = model::housing_acceleration_history(s, sim.planet_angles_rad, sim.carrier_angle_rad, forces);
    src = &housing;
  }
  std::vector<double> y(n_fine);
  for (std::size_t m = 0; m < n_fine; ++m)
    y[m] = interpolate_uniform(*src, sim.t0_s, sim.dt_s, t_begin + static_cast<double>(m) * dt_fine);
  return y;
}

WindowComparison ModelComparison::compare(const SimulatedSignals& sim, const model::SimulationConfig& config, int w,
                                          bool profile_gain) const {
  const AnalysisWindow& win = window(w);
  const double dt = rec_.sample_interval_s();
  require(sim.t0_s <= win.t_begin_s + 1e-12 && sim.t_end_s() >= win.t_end_s - 1e-12, "simulation",
          "does not cover the window [", win.t_begin_s, ", ", win.t_end_s, "] s (it covers [", sim.t0_s, ", ",
          sim.t_end_s(), "])");
  const int q = std::max(1, static_cast<int>(std::lround(dt / sim.dt_s)));
  const std::size_t n = win.count, n_fine = n * static_cast<std::size_t>(q);
  const std::size_t nc = used_.size();
  std::vector<std::vector<std::complex<double>>> model_bins(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    // The last fine sample is at t_begin + (n q - 1) dt / q <= t_end - dt / q, inside the record.
    const auto y = fine_signal(sim, config, static_cast<int>(c), win.t_begin_s, n_fine, dt / q);
    auto b = hann_bins(y, win.k_min, win.k_max);
    for (auto& v : b) v /= static_cast<double>(q);
    model_bins[c] = std::move(b);
  }
  WindowComparison out;
  out.sensor_gain = config.sensor.gain_m_s2_per_N;
  auto sd = [&](std::size_t c) { return std::sqrt(3.0 * static_cast<double>(n) * noise_[c].variance / 16.0); };
  bool any_housing = false;
  if (profile_gain) {
    double num = 0, den = 0;
    for (std::size_t c = 0; c < nc; ++c) {
      if (rec_.channels[static_cast<std::size_t>(used_[c])].quantity != Quantity::HousingAcceleration) continue;
      any_housing = true;
      const double s2 = sd(c) * sd(c);
      for (std::size_t k = 0; k < model_bins[c].size(); ++k) {
        num += std::real(std::conj(model_bins[c][k]) * rec_bins_[static_cast<std::size_t>(w)][c][k]) / s2;
        den += std::norm(model_bins[c][k]) / s2;
      }
    }
    if (any_housing && den > 0) {
      out.sensor_gain = num / den;
      out.sensor_gain_std = std::sqrt(kHannChi2Scale / den);
    }
  }
  for (std::size_t c = 0; c < nc; ++c) {
    const bool housing = rec_.channels[static_cast<std::size_t>(used_[c])].quantity == Quantity::HousingAcceleration;
    const double g = housing ? out.sensor_gain : 1.0;
    const double s = sd(c);
    double chi2 = 0;
    for (std::size_t k = 0; k < model_bins[c].size(); ++k) {
      const std::complex<double> d = (rec_bins_[static_cast<std::size_t>(w)][c][k] - g * model_bins[c][k]) / s;
      out.residual.push_back(d.real());
      out.residual.push_back(d.imag());
      chi2 += std::norm(d);
    }
    out.chi2_per_channel.push_back(chi2);
    out.dof_per_channel.push_back(2 * static_cast<int>(model_bins[c].size()));
    out.chi2 += chi2;
  }
  return out;
}

namespace {
/// Brick-wall band limit (0, max_Hz] of a real signal sampled every dt (mean removed).
std::vector<double> band_limit(std::vector<double> y, double dt, double max_Hz) {
  const std::size_t n = y.size();
  signal::RealFft fft(n);
  std::vector<std::complex<double>> X(fft.bins());
  fft.forward(y, X);
  const double df = 1.0 / (static_cast<double>(n) * dt);
  X[0] = 0;
  for (std::size_t k = 1; k < X.size(); ++k)
    if (static_cast<double>(k) * df > max_Hz) X[k] = 0;
  fft.inverse(X, y);
  return y;
}
} // namespace

std::vector<double> ModelComparison::model_on_recording(const SimulatedSignals& sim,
                                                        const model::SimulationConfig& config, double gain, int ch_pos,
                                                        std::size_t begin, std::size_t count, double max_Hz) const {
  const double dt = rec_.sample_interval_s();
  const int q = std::max(1, static_cast<int>(std::lround(dt / sim.dt_s)));
  auto y = fine_signal(sim, config, ch_pos, rec_.time_s[begin], count * static_cast<std::size_t>(q), dt / q);
  y = band_limit(std::move(y), dt / q, max_Hz);
  const bool housing = rec_.channels[static_cast<std::size_t>(used_[static_cast<std::size_t>(ch_pos)])].quantity ==
                       Quantity::HousingAcceleration;
  std::vector<double> out(count);
  for (std::size_t j = 0; j < count; ++j) out[j] = y[j * static_cast<std::size_t>(q)] * (housing ? gain : 1.0);
  return out;
}

std::vector<double> ModelComparison::recording_band_limited(int ch_pos, std::size_t begin, std::size_t count,
                                                            double max_Hz) const {
  const auto& v = rec_.channels[static_cast<std::size_t>(used_[static_cast<std::size_t>(ch_pos)])].values;
  std::vector<double> y(v.begin() + static_cast<long>(begin), v.begin() + static_cast<long>(begin + count));
  return band_limit(std::move(y), rec_.sample_interval_s(), max_Hz);
}

} // namespace pw::diagnose
