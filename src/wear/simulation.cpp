#include "wear/simulation.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "model/sensor.hpp"
#include "signal/spectrum.hpp"
#include "wear/flank_wear.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pw::wear {

using model::Channel;
using model::FlankWearHistory;
using model::PlanetaryDynamics;
using model::SimulationConfig;
using model::WearHistory;
using model::WearSettings;
using model::WearSnapshot;

namespace {

/// Chordal tooth thickness on the reference circle [m] (external gears
/// m(pi/2 + 2x tan a); the ring tooth m(pi/2 - 2x tan a)).
double reference_thickness(const geometry::GearSpec& g) {
  const double sgn = g.kind == geometry::GearKind::External ? 1.0 : -1.0;
  return g.module_m * (kPi / 2 + sgn * 2 * g.profile_shift * std::tan(g.pressure_angle_rad));
}

/// Minimum number of wear updates, so that the wear history and the
/// wear-dynamics coupling are resolved even when wear is small compared
/// with the elastic deflection.
constexpr int kMinWearUpdates = 8;
/// Mesh cycles each window runs before booking wear, to let the dynamics
/// settle on the updated profiles (the transient decays in < 1 mesh period
/// for the default damping, see warm-up).
constexpr int kWindowSettleCycles = 2;
/// Snapshot channels: penetration depth and mesh-line acceleration of
/// planet 0's two meshes (seed Figs. 10-12), then the absolute carrier angle
/// and the housing accelerometer (model/sensor.hpp) for the condition
/// indicators (docs/indicators.md); wear.snapshot_record_mesh_cycles long.
WearSnapshot record_snapshot(model::Integration& r, double mesh_cycles, wear::FlankWearAccumulator* acc) {
  const int spm = r.p.steps_per_mesh;
  const std::int64_t n = static_cast<std::int64_t>(r.c.wear.snapshot_record_mesh_cycles) * spm;
  const int planets = r.c.stage.planet_count;
  std::vector<double> carrier_angle(static_cast<std::size_t>(n));
  std::vector<std::vector<double>> ring_force(static_cast<std::size_t>(planets), std::vector<double>(static_cast<std::size_t>(n)));
  // The ring body's fixed-frame accelerations for sensor.housing_path = ring_body (Eq. S3), else none.
  const bool ring_body = r.c.sensor.housing_path == model::HousingPath::RingBody;
  const model::RingBodyReader ring(r.sys().structure());
  std::vector<double> ring_x(ring_body ? static_cast<std::size_t>(n) : 0), ring_y(ring_x.size());
  WearSnapshot s;
  s.mesh_cycles = mesh_cycles;
  s.time_s.resize(n);
  const char* names[] = {"sun_planet/0/deflection", "sun_planet/0/acceleration", "planet_ring/0/deflection",
                         "planet_ring/0/acceleration"};
  for (const char* nm : names) {
    const std::string name(nm);
    const bool acc_ch = name.ends_with("acceleration");
    s.channels.push_back({name, acc_ch ? "m/s^2" : "m",
                          acc_ch ? "relative acceleration along the line of action" : "mesh deflection (penetration depth)",
                          std::vector<double>(n)});
  }
  const auto& S = r.sys().structure();
  const double t0 = r.st.t;
  for (std::int64_t k = 0; k < n; ++k) {
    r.step();
    if (acc) acc->accumulate(r.p.time_step_s);
    s.time_s[k] = r.st.t - t0;
    const auto& ms = r.sys().mesh_states();
    s.channels[0].values[k] = ms[0].deflection_m;
    s.channels[1].values[k] = S.meshes[0].g.dot(r.st.a);
    s.channels[2].values[k] = ms[1].deflection_m;
    s.channels[3].values[k] = S.meshes[1].g.dot(r.st.a);
    carrier_angle[k] = r.p.carrier_speed_rad_s * r.st.t + r.sys().carrier_rotation(r.st.q);
    if (ring_body) {
      const Eigen::Vector2d a_ring = ring.fixed_frame(r.st.a, carrier_angle[k]);
      ring_x[k] = a_ring.x();
      ring_y[k] = a_ring.y();
    }
    for (int i = 0; i < planets; ++i) ring_force[i][k] = ms[2 * static_cast<std::size_t>(i) + 1].force_N;
  }
  for (const Channel& ch : s.channels) {
    const signal::Spectrum sp = signal::amplitude_spectrum(ch.values, r.p.time_step_s, signal::Window::Hann);
    s.spectra.push_back({ch.name, "frequency", "Hz", "amplitude", ch.unit,
                         "amplitude spectrum, Hann window, " + sp.scaling, sp.frequency_Hz, sp.amplitude});
  }
  std::vector<std::span<const double>> forces(ring_force.begin(), ring_force.end());
  Channel housing{"housing/acceleration", "m/s^2",
                  "housing accelerometer at sensor.angle_rad through sensor.housing_path (model/sensor.hpp): "
                  "planet-ring force fluctuations about their means over the snapshot (planet_pass) or the "
                  "ring's translation (ring_translation) or the ring body's acceleration times its mass (ring_body)",
                  model::housing_acceleration_history(r.c.sensor, r.p.geometry.planet_angles_rad,
                                                      r.p.geometry.planet_ring.working_pressure_angle_rad, carrier_angle, forces,
                                                      r.p.time_step_s, {ring.mass_kg(), ring_x, ring_y})};
  const signal::Spectrum hs = signal::amplitude_spectrum(housing.values, r.p.time_step_s, signal::Window::Hann);
  s.spectra.push_back({housing.name, "frequency", "Hz", "amplitude", housing.unit,
                       "amplitude spectrum, Hann window, " + hs.scaling, hs.frequency_Hz, hs.amplitude});
  s.channels.push_back(std::move(housing));
  s.channels.push_back({"carrier/angle", "rad",
                        "absolute carrier angle Omega_c t + perturbation (t = simulation time); planet i is at "
                        "psi_i + carrier/angle in the housing frame",
                        std::move(carrier_angle)});
  return s;
}

/// The flank families' histories before the first state: names, teeth, elements and
/// each element's distance from the pitch point. Families f: 0 sun, 1..N planet sun
/// sides, N+1..2N planet ring sides, 2N+1 ring (FlankWearAccumulator's order).
std::vector<FlankWearHistory> empty_flank_histories(const PlanetaryDynamics& sys,
                                                    const std::vector<model::FlankSet*>& sets, int N) {
  const int F = static_cast<int>(sets.size());
  std::vector<FlankWearHistory> out;
  for (int f = 0; f < F; ++f) {
    FlankWearHistory fh;
    const int i = f <= N ? f - 1 : f - 1 - N;
    fh.name = f == 0 ? "sun" : f == F - 1 ? "ring"
                                          : "planet_" + std::to_string(i) + (f <= N ? "/sun_side" : "/ring_side");
    fh.teeth = sets[f]->teeth();
    fh.elements = sets[f]->elements();
    // Distance from the pitch point, positive towards this gear's tip:
    // xi - xi_P on the driver (sun, planet ring side), xi_P - xi otherwise.
    const bool driver = (f == 0) || (f > N && f < F - 1);
    const double xp = sys.family(f == 0 || (f >= 1 && f <= N) ? 0 : 1).geometry.pitch_point_m;
    for (int e = 0; e < fh.elements; ++e)
      fh.distance_from_pitch_point_m.push_back(driver ? sets[f]->element_xi_m(e) - xp : xp - sets[f]->element_xi_m(e));
    out.push_back(std::move(fh));
  }
  return out;
}

/// Backlash grows by the flank material removed on both gears of a mesh (mean
/// over teeth and profile, since `initial`; derivation §5), from the design
/// backlash b_sp0 (sun-planet) and b_pr0 (planet-ring).
void grow_backlash(PlanetaryDynamics& sys, const std::vector<model::FlankSet*>& sets,
                   const std::vector<std::vector<double>>& initial, double b_sp0, double b_pr0) {
  const int F = static_cast<int>(sets.size());
  const int N = (F - 2) / 2;
  auto mean_wear = [&](int f) {
    const auto& d = sets[f]->deviations();
    double s = 0;
    for (std::size_t k = 0; k < d.size(); ++k) s += d[k] - initial[f][k];
    return s / static_cast<double>(d.size());
  };
  double w_sun = mean_wear(0), w_ring = mean_wear(F - 1), w_ps = 0, w_pr = 0;
  for (int i = 0; i < N; ++i) {
    w_ps += mean_wear(1 + i) / N;
    w_pr += mean_wear(1 + N + i) / N;
  }
  for (int m = 0; m < 2 * N; ++m)
    sys.set_backlash_m(m, dynamics::MeshId::of(m).sun_planet() ? b_sp0 + w_sun + w_ps : b_pr0 + w_pr + w_ring);
}

} // namespace

/// The coupled wear loop (docs/derivation.md §5): dynamic window -> wear
/// rate per element -> extrapolate over dN cycles (bounded increment) ->
/// update profiles and backlash -> repeat.
model::WearHistory run_wear(model::Integration& r, const model::ProgressFn& report, double f0, double f1) {
  const SimulationConfig& c = r.c;
  const WearSettings& ws = c.wear;
  PlanetaryDynamics& sys = r.sys();
  const int N = c.stage.planet_count;
  const double kappa = ws.archard_K > 0 ? ws.archard_K / ws.hardness_Pa : ws.coefficient_m2_N;
  wear::FlankWearAccumulator acc(sys, c, kappa);
  const int F = acc.families();
  const int window = ws.window_mesh_cycles > 0
                         ? ws.window_mesh_cycles
                         : std::max({c.stage.planet.teeth, (c.stage.ring.teeth + N - 1) / N,
                                     (c.stage.sun.teeth + N - 1) / N}) + 1;
  const int spm = r.p.steps_per_mesh;
  const double dt = r.p.time_step_s;
  // Increment bound: a fraction of the static sun-mesh deflection.
  const double delta_static = sys.nominal_input_torque_Nm() / (N * r.p.geometry.sun.base_radius_m) /
                              sys.family(0).mean_stiffness_N_m;
  const double bound = ws.max_increment_fraction * delta_static;
  const double limit = ws.max_wear_fraction_of_thickness *
                       std::min({reference_thickness(c.stage.sun), reference_thickness(c.stage.planet),
                                 reference_thickness(c.stage.ring)});
  const double total = ws.mesh_cycles;
  std::vector<double> targets = ws.snapshot_mesh_cycles;
  if (targets.empty()) targets = {0.0, total};
  std::sort(targets.begin(), targets.end());
  std::vector<bool> taken(targets.size(), false);

  WearHistory h;
  std::vector<model::FlankSet*> sets;
  for (int f = 0; f < F; ++f) sets.push_back(&acc.flank_set(sys.surfaces(), f));
  h.flanks = empty_flank_histories(sys, sets, N);
  const double b_sp0 = c.contact.backlash_sun_planet_m, b_pr0 = c.contact.backlash_planet_ring_m;
  auto push_state = [&](double cycles) {
    h.mesh_cycles.push_back(cycles);
    for (int f = 0; f < F; ++f) {
      const auto& d = sets[f]->deviations();
      h.flanks[f].depth_m.insert(h.flanks[f].depth_m.end(), d.begin(), d.end());
    }
    h.backlash_m.push_back(sys.backlash_m(0));
    h.backlash_m.push_back(sys.backlash_m(1));
  };
  // Profile deviations present before wear (damage) are not wear: record
  // wear as the change since the start.
  std::vector<std::vector<double>> initial(F);
  for (int f = 0; f < F; ++f) initial[f] = sets[f]->deviations();
  push_state(0.0);

  std::vector<std::vector<double>> rate(F);
  double done = 0;
  int updates = 0;
  const auto clock0 = std::chrono::steady_clock::now();
  while (done < total) {
    for (std::int64_t k = 0; k < std::int64_t{kWindowSettleCycles} * spm; ++k) r.step();
    acc.begin_window();
    int booked = 0;
    for (std::size_t s = 0; s < targets.size(); ++s)
      if (!taken[s] && targets[s] <= done + 0.5) {
        h.snapshots.push_back(record_snapshot(r, done, &acc));
        for (std::size_t u = s; u < targets.size(); ++u)
          if (targets[u] <= done + 0.5) taken[u] = true;
        booked = c.wear.snapshot_record_mesh_cycles;
        break;
      }
    double mean_ws = 0;
    for (std::int64_t k = std::int64_t{booked} * spm; k < std::int64_t{window} * spm; ++k) {
      r.step();
      acc.accumulate(dt);
      mean_ws += sys.sun_rotation(r.st.v);
    }
    // Friction losses change as the profiles wear: keep the load torque at
    // the value that holds the nominal speed (as in the warm-up), so that
    // windows and snapshots stay at the recording's operating point.
    if (window > booked && sys.structure().has_rigid_mode)
      sys.set_load_torque_Nm(sys.load_torque_Nm() *
                             (1.0 + mean_ws / (static_cast<double>(window - booked) * spm) / r.p.sun_speed_rad_s));
    double max_rate = 0;
    for (int f = 0; f < F; ++f) {
      if (!acc.wear_rate_per_cycle(f, rate[f]))
        throw InputError("wear.window_mesh_cycles",
                         detail::concat(window, " mesh cycles let no tooth of flank family ", h.flanks[f].name,
                                        " complete a contact pass; use a longer window"));
      for (double x : rate[f]) max_rate = std::max(max_rate, x);
    }
    double dN = total - done;
    dN = std::min(dN, total / kMinWearUpdates);
    if (max_rate > 0) dN = std::min(dN, bound / max_rate);
    dN = std::min(std::max(dN, 1.0), total - done);
    // Microelement update: independent per element, so any thread count
    // gives the same numbers (each element is written by one thread, with
    // the same arithmetic).
    for (int f = 0; f < F; ++f) {
      double* d = sets[f]->deviations().data();
      const double* rf = rate[f].data();
      const long n = static_cast<long>(rate[f].size());
#pragma omp parallel for schedule(static)
      for (long e = 0; e < n; ++e) d[e] += rf[e] * dN;
    }
    grow_backlash(sys, sets, initial, b_sp0, b_pr0);
    done += dN;
    ++updates;
    push_state(done);
    double wmax = 0;
    for (int f = 0; f < F; ++f) wmax = std::max(wmax, sets[f]->max_deviation_m());
    if (report) {
      const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock0).count();
      report(f0 + (f1 - f0) * done / total,
             detail::concat("wear ", static_cast<long>(done), "/", static_cast<long>(total), " cycles, update ",
                            updates, ", max ", wmax * 1e6, " um, ", el, " s"));
    }
    if (wmax > limit) {
      h.stop_reason = detail::concat("wear stopped after ", done, " mesh cycles: maximum flank wear ", wmax,
                                     " m exceeds wear.max_wear_fraction_of_thickness = ",
                                     ws.max_wear_fraction_of_thickness, " of the tooth thickness (", limit, " m)");
      break;
    }
  }
  // Remaining snapshot targets (typically the last one) at the final state.
  for (std::size_t s = 0; s < targets.size(); ++s)
    if (!taken[s]) {
      h.snapshots.push_back(record_snapshot(r, done, nullptr));
      break;
    }
  // Report wear, not pre-existing deviations.
  for (int f = 0; f < F; ++f) {
    auto& d = h.flanks[f].depth_m;
    const std::size_t per = initial[f].size();
    for (std::size_t k = 0; k < d.size(); ++k) d[k] -= initial[f][k % per];
  }
  return h;
}


model::SimulationResult simulate(const model::SimulationConfig& config, const model::ProgressFn& progress,
                                 const model::OutputSelection& output) {
  return model::simulate(config, progress, output,
                         [](model::Integration& run, model::SimulationResult& result, const model::ProgressFn& report,
                            double f0, double f1) { result.wear = run_wear(run, report, f0, f1); });
}

} // namespace pw::wear
