#include "diagnose/locate.hpp"

#include "core/error.hpp"
#include "core/statistics.hpp"

#include "diagnose/features.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace pw::diagnose {

namespace {
std::string family_label(const OrderLine& l) { return l.label + " (" + to_string(l.family) + ")"; }

/// The cells of the speed channels (pure rotations of the sun and the carrier) that carry a mesh
/// harmonic h f_m, with each half's rho^2 - 1: planet_pattern's input.
std::vector<MeshHarmonicCell> speed_mesh_harmonic_cells(const ModelComparison& cmp, const WindowScore& fit,
                                                        const WindowScore& held) {
  const RecordingSpectra& sp = cmp.spectra();
  const FeatureLayout& L = sp.layout;
  const int ncell = cmp.cells();
  std::vector<MeshHarmonicCell> out;
  for (int c = 0; c < cmp.channels(); ++c) {
    const Quantity q = cmp.recording().channels[static_cast<std::size_t>(sp.channels[static_cast<std::size_t>(c)])].quantity;
    if (q != Quantity::SunSpeed && q != Quantity::CarrierSpeed) continue;
    for (int i = 0; i < ncell; ++i)
      for (int li : L.cells[static_cast<std::size_t>(i)].lines) {
        const OrderLine& l = L.lines[static_cast<std::size_t>(li)];
        if (l.family != Component::Mesh || l.sideband != 0 || l.mesh_harmonic < 1) continue;
        const std::size_t f = static_cast<std::size_t>(c * ncell + i);
        out.push_back({l.mesh_harmonic, {fit.rho[f] * fit.rho[f] - 1.0, held.rho[f] * held.rho[f] - 1.0}});
        break;
      }
  }
  return out;
}
} // namespace

Location locate(const ModelComparison& cmp, const WindowScore& fit, const WindowScore& held,
                const std::vector<std::vector<double>>& model, const LocateOptions& opt) {
  const RecordingSpectra& sp = cmp.spectra();
  const FeatureLayout& L = sp.layout;
  const Kinematics& kin = sp.kinematics;
  const int nc = cmp.channels(), ncell = cmp.cells();
  Location loc;
  const WindowScore* ws[2] = {&fit, &held};
  // Per cell (both halves): excess rho^2 - 1.
  std::vector<double> ex(static_cast<std::size_t>(nc * ncell), 0.0);
  for (int w = 0; w < 2; ++w)
    for (std::size_t f = 0; f < ex.size(); ++f) ex[f] += ws[w]->rho[f] * ws[w]->rho[f] - 1.0;
  double total_pos = 0;
  for (double e : ex) total_pos += std::max(e, 0.0);
  loc.excess = 0;
  for (double e : ex) loc.excess += e;

  loc.significance_z = normal_quantile(opt.family_alpha / 5);
  for (Component f : kAllComponents) {
    FamilyEvidence fe;
    fe.family = f;
    fe.meaning = family_meaning(f);
    fe.frequency_Hz = kin.frequency_Hz(f);
    fe.carrier_orders = carrier_orders(kin, f);
    const auto& cells = L.family_cells[static_cast<std::size_t>(f)];
    double e = 0, share = 0, best = -1e300;
    for (int c = 0; c < nc; ++c) {
      double ec = 0;
      for (int i : cells) {
        const std::size_t k = static_cast<std::size_t>(c * ncell + i);
        ec += ex[k];
        share += std::max(ex[k], 0.0) / static_cast<double>(L.cell_families[static_cast<std::size_t>(i)].size());
      }
      e += ec;
      if (ec > best) best = ec, fe.strongest_channel = sp.channel_names[static_cast<std::size_t>(c)];
    }
    fe.cells = 2 * nc * static_cast<int>(cells.size());
    fe.z = fe.cells > 0 ? e / std::sqrt(2.0 * fe.cells) : 0.0;
    fe.share = total_pos > 0 ? share / total_pos : 0.0;
    loc.evidence.family_z[static_cast<int>(f)] = fe.z;
    loc.families.push_back(fe);
  }
  std::sort(loc.families.begin(), loc.families.end(), [](const auto& a, const auto& b) { return a.z > b.z; });

  // Strongest cells.
  std::vector<std::size_t> idx(ex.size());
  for (std::size_t k = 0; k < idx.size(); ++k) idx[k] = k;
  const std::size_t top = std::min<std::size_t>(idx.size(), static_cast<std::size_t>(opt.max_lines_reported));
  std::partial_sort(idx.begin(), idx.begin() + static_cast<long>(top), idx.end(),
                    [&](std::size_t a, std::size_t b) { return ex[a] > ex[b]; });
  for (std::size_t t = 0; t < top; ++t) {
    const std::size_t k = idx[t];
    const int c = static_cast<int>(k) / ncell, i = static_cast<int>(k) % ncell;
    const FeatureCell& cell = L.cells[static_cast<std::size_t>(i)];
    LocatedLine l;
    l.order = cell.order;
    l.frequency_Hz = cell.order * kin.carrier_Hz;
    l.channel = sp.channel_names[static_cast<std::size_t>(c)];
    l.quantity = cmp.recording().channels[static_cast<std::size_t>(sp.channels[static_cast<std::size_t>(c)])].quantity;
    l.chi2 = 0.5 * (ex[k] + 2.0);
    l.recording_amplitude = 0.5 * (cmp.recording_amplitude(0, static_cast<int>(k)) + cmp.recording_amplitude(1, static_cast<int>(k)));
    l.model_amplitude = fit.gains[static_cast<std::size_t>(c)] *
                        model[static_cast<std::size_t>(c)][static_cast<std::size_t>(cell.bin)];
    for (int li : cell.lines) l.labels.push_back(family_label(L.lines[static_cast<std::size_t>(li)]));
    loc.lines.push_back(std::move(l));
  }

  loc.planet_pattern = planet_pattern(speed_mesh_harmonic_cells(cmp, fit, held), kin, opt.family_alpha);

  // Input-shaft orders: excess per |b| over cells of input-shaft lines not shared with the mesh harmonics.
  {
    std::map<int, double> per_b;
    for (int i = 0; i < ncell; ++i) {
      const FeatureCell& cell = L.cells[static_cast<std::size_t>(i)];
      bool mesh = false;
      for (int li : cell.lines) mesh = mesh || L.lines[static_cast<std::size_t>(li)].family == Component::Mesh;
      if (mesh) continue;
      for (int li : cell.lines) {
        const OrderLine& l = L.lines[static_cast<std::size_t>(li)];
        if (l.family != Component::InputShaft) continue;
        for (int c = 0; c < nc; ++c) per_b[std::abs(l.sideband)] += ex[static_cast<std::size_t>(c * ncell + i)];
      }
    }
    std::vector<std::pair<double, int>> v;
    for (auto [b, e] : per_b) v.push_back({e, b});
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& [e, b] : v)
      if (e > 0 && loc.input_orders.size() < 3) loc.input_orders.push_back(b);
    loc.evidence.input_orders = loc.input_orders;
  }

  // Synchronous average of the recording over the leading rotating component.
  const Recording& rec = cmp.recording();
  auto pick = [&](std::initializer_list<Quantity> qs) {
    for (Quantity q : qs)
      for (int c = 0; c < nc; ++c)
        if (rec.channels[static_cast<std::size_t>(sp.channels[static_cast<std::size_t>(c)])].quantity == q) return c;
    return -1;
  };
  std::vector<FamilyEvidence> order = loc.families;
  if (opt.rotation_family >= 0)
    std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto&) {
      return static_cast<int>(a.family) == opt.rotation_family;
    });
  for (const auto& fe : order) {
    if (fe.family != Component::Sun && fe.family != Component::Planet && fe.family != Component::Carrier) continue;
    const int c = fe.family == Component::Carrier
                      ? pick({Quantity::MeshAccelerationPlanetRing, Quantity::HousingAcceleration,
                              Quantity::MeshAccelerationSunPlanet})
                      : pick({Quantity::MeshAccelerationSunPlanet, Quantity::MeshAccelerationPlanetRing,
                              Quantity::HousingAcceleration});
    if (c < 0) break;
    const SignalChannel& ch = rec.channels[static_cast<std::size_t>(sp.channels[static_cast<std::size_t>(c)])];
    RotationEvidence re;
    re.component = fe.family;
    re.channel = ch.name;
    re.period_mesh_cycles = static_cast<int>(std::lround(kin.period_mesh_cycles(fe.family)));
    re.samples_per_cycle = opt.samples_per_cycle;
    // The mesh-cycle coordinate u = Zr theta_c / 2 pi from the recording's carrier angle; the
    // recording's samples are uniform in time and the speed nearly constant, so u is resampled
    // as a function of time at the mean mesh frequency.
    const double dt = rec.sample_interval_s();
    const auto tsa = synchronous_average(ch.values, 0.0, dt, kin.mesh_Hz, re.period_mesh_cycles, re.samples_per_cycle);
    re.averages = tsa.averages;
    if (tsa.averages > 0) {
      const auto pk = tsa_energy_peak(tsa);
      re.peak_angle_rad = 2 * std::numbers::pi * pk.mesh_cycle / re.period_mesh_cycles;
      re.peak_to_mean = pk.peak_to_mean;
      re.tsa = tsa.values;
    }
    re.reference = "the first sample of the recording";
    re.tooth_note = "tooth index unidentifiable: amplitudes carry no phase and the recording has no carrier-angle "
                    "reference; the severity is fitted on a canonical tooth";
    loc.rotations.push_back(std::move(re));
    break;
  }
  return loc;
}

} // namespace pw::diagnose
