#include "wear/flank_wear.hpp"

#include "wear/archard.hpp"

#include <algorithm>
#include <cmath>

namespace pw::wear {

FlankWearAccumulator::FlankWearAccumulator(const model::PlanetaryDynamics& sys, const model::SimulationConfig& c,
                                           double kappa)
    : sys_(sys), kappa_(kappa) {
  const auto& st = c.stage;
  planets_ = st.planet_count;
  width_sp_m_ = std::min(st.sun.face_width_m, st.planet.face_width_m);
  width_pr_m_ = std::min(st.planet.face_width_m, st.ring.face_width_m);
  const auto& gsp = sys.family(0).geometry;
  const auto& gpr = sys.family(1).geometry;
  const model::ToothSurfaces& s = sys.surfaces();
  // rho(xi) of each family's flank: rho = c0 + sgn xi (mesh.hpp).
  auto make = [&](const model::FlankSet& fs, double rb, double c0, double sgn, double per_cycle) {
    Family f;
    f.teeth = fs.teeth();
    f.elements = fs.elements();
    for (int e = 0; e < f.elements; ++e) {
      const double x0 = fs.xi_min_m() + e * fs.element_width_m(), x1 = x0 + fs.element_width_m();
      f.arc_length_m.push_back(involute_arc_length(rb, c0 + sgn * x0, c0 + sgn * x1));
    }
    f.wear_m.assign(static_cast<std::size_t>(f.teeth) * f.elements, 0.0);
    f.passes.assign(f.teeth, 0);
    f.passes_per_cycle = per_cycle;
    fam_.push_back(std::move(f));
  };
  const double N = planets_;
  make(s.sun, gsp.base_radius_a_m, 0.0, 1.0, N / st.sun.teeth);
  for (int i = 0; i < planets_; ++i)
    make(s.planet_sun_side[i], gsp.base_radius_b_m, gsp.tangent_distance_m, -1.0, 1.0 / st.planet.teeth);
  for (int i = 0; i < planets_; ++i) make(s.planet_ring_side[i], gpr.base_radius_a_m, 0.0, 1.0, 1.0 / st.planet.teeth);
  make(s.ring, gpr.base_radius_b_m, gpr.tangent_distance_m, 1.0, N / st.ring.teeth);
  const int E = c.wear.elements_per_flank;
  const std::size_t meshes = sys.mesh_states().size();
  pending_.resize(meshes);
  same_grid_.resize(meshes);
  for (std::size_t m = 0; m < meshes; ++m) {
    const dynamics::MeshId id = dynamics::MeshId::of(m);
    const model::FlankSet& sa = id.sun_planet() ? s.sun : s.planet_ring_side[static_cast<std::size_t>(id.planet)];
    const model::FlankSet& sb = id.sun_planet() ? s.planet_sun_side[static_cast<std::size_t>(id.planet)] : s.ring;
    same_grid_[m] = sa.same_grid(sb) ? 1 : 0;
    for (auto& p : pending_[m].slot) {
      p.wa.assign(E, 0.0);
      if (!same_grid_[m]) p.wb.assign(E, 0.0);
    }
  }
}

model::FlankSet& FlankWearAccumulator::flank_set(model::ToothSurfaces& s, int f) const {
  if (f == 0) return s.sun;
  if (f <= planets_) return s.planet_sun_side[f - 1];
  if (f <= 2 * planets_) return s.planet_ring_side[f - 1 - planets_];
  return s.ring;
}

void FlankWearAccumulator::begin_window() {
  for (auto& f : fam_) {
    std::fill(f.wear_m.begin(), f.wear_m.end(), 0.0);
    std::fill(f.passes.begin(), f.passes.end(), 0);
  }
  for (MeshPasses& mp : pending_) mp.count = 0;  // passes under way are dropped
  window_start_ = true;
}

void FlankWearAccumulator::book(int fi, int tooth, const std::vector<double>& w) {
  Family& f = fam_[fi];
  double* dst = f.wear_m.data() + static_cast<std::size_t>(tooth) * f.elements;
  for (int e = 0; e < f.elements; ++e) dst[e] += w[e] / f.arc_length_m[static_cast<std::size_t>(e)];
  ++f.passes[tooth];
}

void FlankWearAccumulator::update_passes(MeshPasses& mp, const model::MeshState& ms, long long first, int fa, int fb,
                                         bool shared) {
  const int count = ms.pairs;
  // Pairs that left the window complete their pass (sequence order; they have distinct teeth,
  // so the order does not change the sums).
  for (long long n = mp.first; n < mp.first + mp.count; ++n) {
    if (n >= first && n < first + count) continue;
    const Pending& p = mp.at(n);
    if (!p.partial) {
      book(fa, p.tooth_a, p.wa);
      book(fb, p.tooth_b, shared ? p.wa : p.wb);
    }
  }
  // Pairs that entered start a pass; those in contact when the window opened are partial.
  for (int j = 0; j < count; ++j) {
    if (mp.holds(first + j)) continue;
    Pending& p = mp.at(first + j);
    p.partial = window_start_;
    p.tooth_a = ms.pair[j].tooth_a;
    p.tooth_b = ms.pair[j].tooth_b;
    std::fill(p.wa.begin(), p.wa.end(), 0.0);
    std::fill(p.wb.begin(), p.wb.end(), 0.0);  // empty on a shared grid
  }
  mp.first = first;
  mp.count = count;
}

void FlankWearAccumulator::accumulate(double dt) {
  const auto& states = sys_.mesh_states();
  const model::ToothSurfaces& surf = sys_.surfaces();
  for (std::size_t m = 0; m < states.size(); ++m) {
    const model::MeshState& ms = states[m];
    const dynamics::MeshId id = dynamics::MeshId::of(m);
    const bool sp = id.sun_planet();
    const int i = id.planet;
    const int fa = sp ? 0 : 1 + planets_ + i;
    const int fb = sp ? 1 + i : 2 * planets_ + 1;
    const model::FlankSet& sa = sp ? surf.sun : surf.planet_ring_side[i];
    const model::FlankSet& sb = sp ? surf.planet_sun_side[i] : surf.ring;
    const double width = sp ? width_sp_m_ : width_pr_m_;
    const bool shared = same_grid_[m] != 0;
    MeshPasses& mp = pending_[m];
    const int count = ms.pairs;
    const long long first = count > 0 ? ms.first_pair : mp.first;
    if (first != mp.first || count != mp.count) update_passes(mp, ms, first, fa, fb, shared);
    for (int j = 0; j < count; ++j) {
      const double F = ms.pair_force_N[j];
      if (F <= 0) continue;
      // (W2): dh_e = kappa F' |v_s| dt / l_e on each flank; the division by l_e waits for book().
      const double base = kappa_ * (F / width) * std::fabs(ms.sliding_m_s[j]) * dt;
      const double xi = ms.pair[j].xi_m;
      Pending& p = mp.at(first + j);
      p.wa[static_cast<std::size_t>(sa.element_at(xi))] += base;
      if (!shared) p.wb[static_cast<std::size_t>(sb.element_at(xi))] += base;
    }
  }
  window_start_ = false;
}

bool FlankWearAccumulator::wear_rate_per_cycle(int fi, std::vector<double>& out) const {
  const Family& f = fam_[fi];
  out.assign(f.wear_m.size(), 0.0);
  std::vector<double> mean(f.elements, 0.0);
  int visited = 0;
  for (int t = 0; t < f.teeth; ++t) {
    if (f.passes[t] == 0) continue;
    ++visited;
    for (int e = 0; e < f.elements; ++e) {
      const double r = f.wear_m[static_cast<std::size_t>(t) * f.elements + e] / f.passes[t] * f.passes_per_cycle;
      out[static_cast<std::size_t>(t) * f.elements + e] = r;
      mean[e] += r;
    }
  }
  if (visited == 0) return false;
  for (int t = 0; t < f.teeth; ++t) {
    if (f.passes[t] != 0) continue;
    for (int e = 0; e < f.elements; ++e) out[static_cast<std::size_t>(t) * f.elements + e] = mean[e] / visited;
  }
  return true;
}

} // namespace pw::wear
