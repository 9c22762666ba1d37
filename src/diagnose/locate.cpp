#include "diagnose/locate.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pw::diagnose {

double normal_quantile(double p) {
  // Upper quantile: z with P(Z > z) = p.
  require(p > 0 && p < 1, "p", "must be in (0, 1), got ", p);
  const double q = 1 - p;  // lower-tail probability
  // Acklam's approximation of the inverse normal CDF.
  static const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                             1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  static const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                             6.680131188771972e+01, -1.328068155288572e+01};
  static const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                             -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  static const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                             3.754408661907416e+00};
  double x;
  if (q < 0.02425) {
    const double t = std::sqrt(-2 * std::log(q));
    x = (((((c[0] * t + c[1]) * t + c[2]) * t + c[3]) * t + c[4]) * t + c[5]) /
        ((((d[0] * t + d[1]) * t + d[2]) * t + d[3]) * t + 1);
  } else if (q > 1 - 0.02425) {
    const double t = std::sqrt(-2 * std::log(1 - q));
    x = -(((((c[0] * t + c[1]) * t + c[2]) * t + c[3]) * t + c[4]) * t + c[5]) /
        ((((d[0] * t + d[1]) * t + d[2]) * t + d[3]) * t + 1);
  } else {
    const double t = q - 0.5, r = t * t;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * t /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  // One Newton step on the CDF.
  const double e = 0.5 * std::erfc(-x / std::numbers::sqrt2) - q;
  const double u = e * std::sqrt(2 * std::numbers::pi) * std::exp(x * x / 2);
  return x - u / (1 + x * u / 2);
}

double chi2_quantile(double nu, double alpha) {
  require(nu > 0, "nu", "must be > 0, got ", nu);
  const double z = normal_quantile(alpha);
  const double h = 2.0 / (9.0 * nu);
  const double t = 1 - h + z * std::sqrt(h);
  return nu * t * t * t;
}

namespace {


/// Normalized periodogram value at frequency f (nearest bin).
double at(const std::vector<double>& P, double df, double f) {
  const long k = std::lround(f / df);
  if (k < 1 || k >= static_cast<long>(P.size()) - 1) return 1.0;
  return P[static_cast<std::size_t>(k)];
}

} // namespace

Location locate(const ModelComparison& cmp, const SimulatedSignals& sim, const model::SimulationConfig& config,
                double gain, const LocateOptions& opt) {
  const Recording& rec = cmp.recording();
  const Kinematics& kin = cmp.kinematics();
  const double dt = rec.sample_interval_s();
  const double f_max = 3.5 * kin.mesh_Hz;  // the band the fit compares (CompareOptions)
  // Usable span: from the fit window to the last sample the simulation covers.
  const std::size_t begin = cmp.window(0).begin;
  std::size_t end = rec.time_s.size();
  while (end > begin && rec.time_s[end - 1] > sim.t_end_s() - dt) --end;
  require(end > begin + 64, "simulation", "covers too little of the recording to locate anything");
  const std::size_t count = end - begin;
  const double t0 = rec.time_s[begin];
  const double df = 1.0 / (static_cast<double>(count) * dt);

  Location loc;
  const int nfam = 5;
  std::vector<std::vector<KinematicLine>> fam_lines(nfam);
  for (int f = 0; f < nfam; ++f)
    fam_lines[static_cast<std::size_t>(f)] =
        family_lines(kin, static_cast<Component>(f), 3, opt.max_sideband, f_max);
  // Sideband lines that fall on a mesh harmonic's bin belong to the mesh family.
  auto on_mesh_harmonic = [&](double f) {
    const double a = std::round(f / kin.mesh_Hz);
    return a >= 1 && std::fabs(f - a * kin.mesh_Hz) < 1.5 * df;
  };
  std::vector<double> excess(nfam, 0.0), n_lines(nfam, 0.0);
  std::vector<std::vector<double>> excess_ch(nfam);
  std::vector<LocatedLine> all_lines;
  std::vector<std::vector<double>> residuals;
  const auto& used = cmp.channels();
  for (std::size_t c = 0; c < used.size(); ++c) {
    const SignalChannel& ch = rec.channels[static_cast<std::size_t>(used[c])];
    auto r = cmp.recording_band_limited(static_cast<int>(c), begin, count, f_max);
    const auto m = cmp.model_on_recording(sim, config, gain, static_cast<int>(c), begin, count, f_max);
    for (std::size_t j = 0; j < count; ++j) r[j] -= m[j];
    auto P = normalized_periodogram(r);
    const double s2 = cmp.noise()[c].variance;
    for (double& v : P) v /= s2;
    for (int f = 0; f < nfam; ++f) {
      double e = 0, n = 0;
      for (const auto& l : fam_lines[static_cast<std::size_t>(f)]) {
        if (f != static_cast<int>(Component::Mesh) && on_mesh_harmonic(l.frequency_Hz)) continue;
        e += at(P, df, l.frequency_Hz) - 1.0;
        n += 1;
      }
      excess[static_cast<std::size_t>(f)] += e;
      n_lines[static_cast<std::size_t>(f)] += n;
      excess_ch[static_cast<std::size_t>(f)].push_back(e);
    }
    // Strongest individual bins in the band, labelled.
    std::vector<std::size_t> idx;
    for (std::size_t k = 2; k < P.size() && static_cast<double>(k) * df <= f_max; ++k) idx.push_back(k);
    const std::size_t top = std::min<std::size_t>(idx.size(), 8);
    std::partial_sort(idx.begin(), idx.begin() + static_cast<long>(top), idx.end(),
                      [&](std::size_t a, std::size_t b) { return P[a] > P[b]; });
    for (std::size_t i = 0; i < top; ++i) {
      const std::size_t k = idx[i];
      // Local maxima only (a line spreads over the Hann main lobe).
      if (P[k] < P[k - 1] || P[k] < P[k + 1]) continue;
      LocatedLine L;
      L.frequency_Hz = static_cast<double>(k) * df;
      L.channel = ch.name;
      L.excess = P[k] - 1.0;
      for (int f = 0; f < nfam; ++f)
        for (const auto& l : fam_lines[static_cast<std::size_t>(f)])
          if (std::fabs(l.frequency_Hz - L.frequency_Hz) <= 0.75 * df)
            L.labels.push_back(l.label + " (" + to_string(static_cast<Component>(f)) + ")");
      if (L.labels.empty()) L.labels.push_back("no kinematic line within half a bin");
      all_lines.push_back(std::move(L));
    }
    residuals.push_back(std::move(r));
  }
  std::sort(all_lines.begin(), all_lines.end(), [](const auto& a, const auto& b) { return a.excess > b.excess; });
  if (all_lines.size() > static_cast<std::size_t>(opt.max_lines_reported))
    all_lines.resize(static_cast<std::size_t>(opt.max_lines_reported));
  loc.lines = std::move(all_lines);

  loc.significance_z = normal_quantile(opt.family_alpha / nfam);
  for (int f = 0; f < nfam; ++f) {
    FamilyEvidence fe;
    fe.family = static_cast<Component>(f);
    fe.lines = static_cast<int>(n_lines[static_cast<std::size_t>(f)]);
    fe.z = fe.lines > 0 ? excess[static_cast<std::size_t>(f)] / std::sqrt(n_lines[static_cast<std::size_t>(f)]) : 0.0;
    const auto& ec = excess_ch[static_cast<std::size_t>(f)];
    const auto it = std::max_element(ec.begin(), ec.end());
    if (it != ec.end())
      fe.strongest_channel = rec.channels[static_cast<std::size_t>(used[static_cast<std::size_t>(it - ec.begin())])].name;
    fe.meaning = family_meaning(fe.family);
    loc.evidence.family_z[f] = fe.z;
    loc.families.push_back(fe);
  }
  std::sort(loc.families.begin(), loc.families.end(), [](const auto& a, const auto& b) { return a.z > b.z; });

  // Synchronous averages of the residual per rotating component. Channel preference: a sun-planet mesh
  // channel for the sun and planets, a planet-ring mesh channel for the carrier (ring teeth), then any
  // accelerometer.
  ToothMap map(config);
  auto pick = [&](Quantity first, Quantity second) {
    for (Quantity q : {first, second, Quantity::HousingAcceleration})
      for (std::size_t c = 0; c < used.size(); ++c)
        if (rec.channels[static_cast<std::size_t>(used[c])].quantity == q) return static_cast<int>(c);
    return -1;
  };
  const struct {
    Component comp;
    Quantity first, second;
  } rot[] = {{Component::Sun, Quantity::MeshAccelerationSunPlanet, Quantity::MeshAccelerationPlanetRing},
             {Component::Planet, Quantity::MeshAccelerationSunPlanet, Quantity::MeshAccelerationPlanetRing},
             {Component::Carrier, Quantity::MeshAccelerationPlanetRing, Quantity::MeshAccelerationSunPlanet}};
  for (const auto& rr : rot) {
    const int c = pick(rr.first, rr.second);
    if (c < 0) continue;
    const SignalChannel& ch = rec.channels[static_cast<std::size_t>(used[static_cast<std::size_t>(c)])];
    const int period = static_cast<int>(std::lround(kin.period_mesh_cycles(rr.comp)));
    const auto tsa = synchronous_average(residuals[static_cast<std::size_t>(c)], t0, dt, kin.mesh_Hz, period,
                                         opt.samples_per_cycle);
    RotationEvidence re;
    re.component = rr.comp;
    re.channel = ch.name;
    re.planet = ch.quantity == Quantity::HousingAcceleration ? 0 : ch.planet;
    re.averages = tsa.averages;
    re.samples_per_cycle = opt.samples_per_cycle;
    if (tsa.averages > 0) {
      const auto pk = tsa_energy_peak(tsa);
      re.peak_mesh_cycle = pk.mesh_cycle;
      re.peak_to_mean = pk.peak_to_mean;
      re.peak_angle_rad = 2 * std::numbers::pi * pk.mesh_cycle / period;
      const bool ring_mesh = ch.quantity == Quantity::MeshAccelerationPlanetRing;
      const auto mesh = ring_mesh ? ToothMap::Mesh::PlanetRing : ToothMap::Mesh::SunPlanet;
      if (rr.comp == Component::Sun)
        re.tooth = map.nearest_tooth(model::Body::Sun, re.planet, ToothMap::Mesh::SunPlanet, pk.mesh_cycle);
      else if (rr.comp == Component::Planet)
        re.tooth = map.nearest_tooth(model::Body::Planet, re.planet, mesh, pk.mesh_cycle);
      else
        re.tooth = map.nearest_tooth(model::Body::Ring, re.planet, ToothMap::Mesh::PlanetRing, pk.mesh_cycle);
      re.tsa_residual = tsa.values;
      const int f = static_cast<int>(rr.comp);
      loc.evidence.peak_mesh_cycle[f] = pk.mesh_cycle;
      loc.evidence.peak_planet[f] = re.planet;
      loc.evidence.peak_from_ring_mesh[f] = ring_mesh;
    }
    loc.rotations.push_back(std::move(re));
  }

  // Input-shaft orders: strongest lines j f_s (a = 0) in the speed channels, else in any channel.
  std::vector<std::pair<double, double>> orders;  // (excess, order)
  for (std::size_t c = 0; c < used.size(); ++c) {
    const SignalChannel& ch = rec.channels[static_cast<std::size_t>(used[c])];
    const bool speed = ch.quantity == Quantity::SunSpeed || ch.quantity == Quantity::CarrierSpeed;
    auto P = normalized_periodogram(residuals[c]);
    for (double& v : P) v /= cmp.noise()[c].variance;
    for (int j = 1; j <= opt.max_sideband; ++j) {
      const double f = j * kin.sun_Hz;
      if (f > f_max || on_mesh_harmonic(f)) continue;
      orders.push_back({(at(P, df, f) - 1.0) * (speed ? 10.0 : 1.0), static_cast<double>(j)});
    }
  }
  std::sort(orders.begin(), orders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& o : orders)
    if (std::find(loc.input_orders.begin(), loc.input_orders.end(), o.second) == loc.input_orders.end() &&
        loc.input_orders.size() < 3)
      loc.input_orders.push_back(o.second);
  loc.evidence.input_orders = loc.input_orders;
  return loc;
}

} // namespace pw::diagnose
