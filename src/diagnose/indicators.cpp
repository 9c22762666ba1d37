// Gear condition indicators of a planetary stage's signals (indicators.hpp).
#include "diagnose/indicators.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "diagnose/order_analysis.hpp"
#include "signal/resample.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace pw::diagnose {

namespace {

void check_options(const IndicatorOptions& o, int planets) {
  require(o.samples_per_mesh == 0 || (o.samples_per_mesh >= kMinSamplesPerMesh && o.samples_per_mesh <= kMaxSamplesPerMesh),
          "--samples-per-mesh", "must be 0 (automatic) or in [", kMinSamplesPerMesh, ", ", kMaxSamplesPerMesh, "], got ",
          o.samples_per_mesh);
  require(o.shaft_harmonics >= 0 && o.shaft_harmonics <= kMaxShaftHarmonics, "--shaft-harmonics", "must lie in [0, ",
          kMaxShaftHarmonics, "], got ", o.shaft_harmonics);
  require(o.planet_window_half_width_rad == 0 ||
              (o.planet_window_half_width_rad > 0 && o.planet_window_half_width_rad <= kPi),
          "--planet-window-deg", "the half-width must be 0 (automatic: 180/N deg = ", 180.0 / planets,
          " deg) or in (0, 180] deg, got ", o.planet_window_half_width_rad * 180 / kPi, " deg");
  require(o.min_planet_window_weight > 0 && o.min_planet_window_weight <= 1, "min_planet_window_weight",
          "must lie in (0, 1], got ", o.min_planet_window_weight);
}

std::vector<double> planet_angles(const model::SimulationConfig& c) {
  std::vector<double> psi = c.stage.planet_angles_rad;
  if (psi.empty())
    for (int i = 0; i < c.stage.planet_count; ++i) psi.push_back(2 * kPi * i / c.stage.planet_count);
  return psi;
}

/// S: the option, or the recording's samples per mesh cycle rounded up (at least kMinSamplesPerMesh).
int samples_per_mesh(std::span<const double> time_s, std::span<const double> theta_c, int zr, int option) {
  if (option > 0) return option;
  const double mesh_cycles = zr * (theta_c.back() - theta_c.front()) / (2 * kPi);
  const double per_mesh = static_cast<double>(time_s.size() - 1) / mesh_cycles;
  return std::clamp(static_cast<int>(std::ceil(per_mesh)), kMinSamplesPerMesh, kMaxSamplesPerMesh);
}

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(4);
  os << v;
  return os.str();
}

/// Plain TSA over revolutions of `teeth` mesh cycles each.
bool plain_average(std::span<const double> t, std::span<const double> x, std::span<const double> mesh_rad, int teeth,
                   int s, GearAverage& out, std::string& why) {
  const double cycles = (mesh_rad.back() - mesh_rad.front()) / (2 * kPi);
  if (cycles < teeth) {
    why = "needs one revolution of " + std::to_string(teeth) + " mesh cycles, the signal holds " + fmt(cycles);
    return false;
  }
  std::vector<double> gear_angle(mesh_rad.size());
  for (std::size_t j = 0; j < gear_angle.size(); ++j) gear_angle[j] = mesh_rad[j] / teeth;
  const signal::AngleDomainSignal a = signal::angular_resample(t, x, gear_angle, teeth * s);
  const int per_rev = teeth * s;
  if (a.values.size() < static_cast<std::size_t>(per_rev)) {
    why = "needs one revolution of " + std::to_string(teeth) + " mesh cycles, the signal holds " + fmt(cycles);
    return false;
  }
  out.tsa = signal::time_synchronous_average(a.values, per_rev);
  out.revolutions = static_cast<int>(a.values.size() / static_cast<std::size_t>(per_rev));
  out.method = "TSA";
  return true;
}

/// Planet-separated TSA of planet i from a housing signal (indicators.hpp).
bool planet_separated_average(std::span<const double> t, std::span<const double> x, std::span<const double> mesh_rad,
                              const model::SimulationConfig& c, double psi_i, double sensor_rad, int s, double h,
                              double min_weight, GearAverage& out, std::string& why) {
  const int zp = c.stage.planet.teeth, zr = c.stage.ring.teeth;
  const signal::AngleDomainSignal a = signal::angular_resample(t, x, mesh_rad, s);
  std::vector<double> w(a.values.size());
  for (std::size_t j = 0; j < w.size(); ++j)
    w[j] = signal::hann_angle_window(psi_i + a.angle_rad[j] / zr - sensor_rad, h);
  const int period = zp * s;
  if (a.values.size() < static_cast<std::size_t>(period)) {
    why = "needs one planet revolution of " + std::to_string(zp) + " mesh cycles";
    return false;
  }
  const signal::WeightedAverage avg = signal::weighted_synchronous_average(a.values, w, period);
  const double least = *std::min_element(avg.weight_sum.begin(), avg.weight_sum.end());
  if (!(least >= min_weight)) {
    why = "the sensor window (half-width " + fmt(h * 180 / kPi) + " deg) covers some planet tooth positions with weight " +
          fmt(least) + " < " + fmt(min_weight) + " over " + std::to_string(avg.periods) +
          " planet revolutions: record more carrier revolutions or widen --planet-window-deg";
    return false;
  }
  out.tsa = avg.average;
  out.revolutions = avg.periods;
  out.method = "planet-separated TSA (Hann window in carrier angle, half-width " + fmt(h * 180 / kPi) + " deg)";
  return true;
}

std::string history_key(const std::string& channel, const GearAverage& a) {
  return channel + "|" + a.gear + "|" + std::to_string(a.planet);
}

} // namespace

std::vector<GearAverage> gear_averages(std::span<const double> time_s, std::span<const double> theta_c,
                                       const ChannelSignal& ch, const model::SimulationConfig& c,
                                       const IndicatorOptions& o, std::vector<SkippedAverage>* skipped) {
  const int planets = c.stage.planet_count;
  check_options(o, planets);
  require(time_s.size() == ch.values.size() && theta_c.size() == ch.values.size(), ch.name,
          "time, carrier angle and values differ in length (", time_s.size(), ", ", theta_c.size(), ", ",
          ch.values.size(), ")");
  require(time_s.size() >= 4, ch.name, "needs at least 4 samples, got ", time_s.size());
  const int zs = c.stage.sun.teeth, zp = c.stage.planet.teeth, zr = c.stage.ring.teeth;
  const int s = samples_per_mesh(time_s, theta_c, zr, o.samples_per_mesh);
  std::vector<double> mesh_rad(theta_c.size());  // 2 pi u
  for (std::size_t j = 0; j < mesh_rad.size(); ++j) mesh_rad[j] = zr * theta_c[j];

  struct Want {
    const char* gear;
    int planet;
    int teeth;
    bool separated;
  };
  std::vector<Want> want;
  switch (ch.quantity) {
  case Quantity::HousingAcceleration:
    want.push_back({"sun", -1, zs, false});
    for (int i = 0; i < planets; ++i) want.push_back({"planet", i, zp, true});
    want.push_back({"carrier", -1, zr, false});
    break;
  case Quantity::MeshAccelerationSunPlanet:
    want = {{"sun", -1, zs, false}, {"planet", ch.planet, zp, false}};
    break;
  case Quantity::MeshAccelerationPlanetRing:
    want = {{"planet", ch.planet, zp, false}, {"carrier", -1, zr, false}};
    break;
  default:
    return {};
  }
  const std::vector<double> psi = planet_angles(c);
  const double h = o.planet_window_half_width_rad > 0 ? o.planet_window_half_width_rad : kPi / planets;
  std::vector<GearAverage> out;
  for (const Want& wt : want) {
    GearAverage a;
    a.gear = wt.gear;
    a.planet = wt.planet;
    a.teeth = wt.teeth;
    a.samples_per_mesh = s;
    std::string why;
    const bool ok = wt.separated
                        ? planet_separated_average(time_s, ch.values, mesh_rad, c, psi[static_cast<std::size_t>(wt.planet)],
                                                   ch.sensor_angle_rad, s, h, o.min_planet_window_weight, a, why)
                        : plain_average(time_s, ch.values, mesh_rad, wt.teeth, s, a, why);
    if (ok)
      out.push_back(std::move(a));
    else if (skipped)
      skipped->push_back({wt.gear, wt.planet, ch.name + ": " + why});
  }
  return out;
}

std::vector<IndicatorRow> channel_indicators(std::span<const double> time_s, std::span<const double> theta_c,
                                             const ChannelSignal& ch, const model::SimulationConfig& c,
                                             const IndicatorOptions& o, std::vector<SkippedAverage>* skipped,
                                             RunHistory* history, bool keep_tsa) {
  std::vector<IndicatorRow> rows;
  for (GearAverage& a : gear_averages(time_s, theta_c, ch, c, o, skipped)) {
    IndicatorRow r;
    r.channel = ch.name;
    r.quantity = to_string(ch.quantity);
    r.unit = ch.unit;
    const signal::GearOrders orders{a.teeth, std::min(o.shaft_harmonics, std::max(a.teeth - 2, 0))};
    if (history) {
      auto& [res, env] = (*history)[history_key(ch.name, a)];
      r.values = signal::condition_indicators(a.tsa, orders, res, env);
      res.push_back(r.values.residual_variance);
      env.push_back(r.values.envelope_variance);
    } else {
      r.values = signal::condition_indicators(a.tsa, orders);
    }
    if (!keep_tsa) a.tsa.clear();
    r.average = std::move(a);
    rows.push_back(std::move(r));
  }
  return rows;
}

std::vector<IndicatorRow> recording_indicators(const Recording& rec, const model::SimulationConfig& c,
                                               const IndicatorOptions& o, std::vector<SkippedAverage>* skipped,
                                               std::string* angle_source, bool keep_tsa) {
  const SpeedEstimate speed = estimate_speed(rec, c.stage);
  std::vector<double> theta = carrier_angle(rec, c.stage, speed, angle_source);
  // Absolute angle: the carrier turned at the estimated speed since t = 0 (docs/recordings.md "Angles").
  const double omega_c = model::carrier_speed(c.stage, speed.input_rpm * 2 * kPi / 60);
  for (double& v : theta) v += omega_c * rec.time_s.front();
  std::vector<IndicatorRow> rows;
  for (const SignalChannel& sc : rec.channels) {
    const ChannelSignal ch{sc.name, sc.quantity, sc.unit, sc.planet, sc.sensor_angle_rad, sc.values};
    for (IndicatorRow& r : channel_indicators(rec.time_s, theta, ch, c, o, skipped, nullptr, keep_tsa))
      rows.push_back(std::move(r));
  }
  return rows;
}

std::span<const IndicatorField> indicator_fields() {
  using CI = signal::ConditionIndicators;
  static const IndicatorField fields[] = {
      {"rms", "signal", &CI::rms},
      {"peak_to_peak", "signal", &CI::peak_to_peak},
      {"kurtosis", "1", &CI::kurtosis},
      {"crest_factor", "1", &CI::crest_factor},
      {"fm0", "1", &CI::fm0},
      {"fm4", "1", &CI::fm4},
      {"m6a", "1", &CI::m6a},
      {"m8a", "1", &CI::m8a},
      {"na4", "1", &CI::na4},
      {"nb4", "1", &CI::nb4},
      {"energy_ratio", "1", &CI::energy_ratio},
      {"sideband_level_factor", "1", &CI::sideband_level_factor},
  };
  return fields;
}

} // namespace pw::diagnose
