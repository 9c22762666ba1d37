#include "model/simulation.hpp"

#include "core/error.hpp"
#include "dynamics/modal.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pw::model {
namespace {

constexpr double kPi = std::numbers::pi;
/// Microelements per flank for the profile-deviation grid (wear issue makes
/// it configurable; 64 resolves a tip-relief-like deviation to ~0.2 mm).
constexpr int kDefaultElements = 64;

double annulus_mass(double rho, double r_out, double r_in, double width) {
  return rho * kPi * (r_out * r_out - r_in * r_in) * width;
}

/// Turns a tooth modifier into flank-state changes (stiffness factor of the
/// tooth; deviation on the flank(s) it loads).
void apply_tooth_modifiers(const Imperfections& imp, ToothSurfaces& s) {
  for (const ToothModifier& t : imp.teeth) {
    auto apply = [&](FlankSet& f) {
      f.set_stiffness_factor(t.tooth, f.stiffness_factor(t.tooth) * t.stiffness_factor);
      if (t.profile_deviation_m != 0) f.add_uniform(t.tooth, t.profile_deviation_m);
    };
    switch (t.body) {
    case Body::Sun: apply(s.sun); break;
    case Body::Ring: apply(s.ring); break;
    case Body::Planet:
      apply(s.planet_sun_side[t.planet]);
      apply(s.planet_ring_side[t.planet]);
      break;
    }
  }
}

bool has_tooth_level_features(const SimulationConfig& c) {
  const Imperfections& i = c.imperfections;
  return !i.teeth.empty() || i.sun_eccentricity_m != 0 || i.torque_ripple_fraction != 0;
}

/// Combined stiffness at mesh roll s (pair 0 enters at s = 0) [N/m].
double combined_stiffness(const MeshFamily& f, double s) {
  return stiffness::combined_stiffness(f.stiffness, f.geometry, f.geometry.start_active_m + s);
}

MeshFamily make_family(const geometry::GearSpec& a, const geometry::GearSpec& b, const geometry::MeshGeometry& mg,
                       const SimulationConfig& c) {
  MeshFamily f;
  f.geometry = mg;
  stiffness::MeshStiffnessOptions opt;
  opt.bore_ratio = c.stage.bore_ratio;
  f.stiffness = stiffness::single_pair_stiffness(mg, a, b, c.stiffness, opt);
  f.teeth_a = a.teeth;
  f.teeth_b = b.teeth;
  f.mean_stiffness_N_m = stiffness::summarize(f.stiffness, mg).combined_mean_N_m;
  return f;
}

} // namespace

MassProperties mass_properties(const SimulationConfig& c, const geometry::StageGeometry& g) {
  // Sun and planets: steel discs between a bore (bore_ratio x root radius)
  // and the reference circle (teeth counted as half material). Carrier: two
  // side plates of radius 1.2 a', 10 mm thick. Ring: rim 3 modules thick
  // beyond the root circle. The seed gives none of these (REFERENCE.md).
  MassProperties m;
  const auto& st = c.stage;
  auto disc = [&](const geometry::GearSpec& s, const geometry::GearGeometry& gg, double& mass, double& inertia) {
    const double ro = gg.reference_radius_m, ri = st.bore_ratio * gg.root_radius_m;
    mass = annulus_mass(s.material.density_kg_m3, ro, ri, s.face_width_m);
    inertia = 0.5 * mass * (ro * ro + ri * ri);
  };
  disc(st.sun, g.sun, m.sun_mass_kg, m.sun_inertia_kgm2);
  disc(st.planet, g.planet, m.planet_mass_kg, m.planet_inertia_kgm2);
  const double Rc = 1.2 * g.carrier_radius_m;
  m.carrier_mass_kg = st.carrier_mass_kg > 0 ? st.carrier_mass_kg
                                             : annulus_mass(st.sun.material.density_kg_m3, Rc, 0.0, 2 * 0.010);
  m.carrier_inertia_kgm2 = st.carrier_inertia_kgm2 > 0 ? st.carrier_inertia_kgm2 : 0.5 * m.carrier_mass_kg * Rc * Rc;
  const double ri = g.ring.root_radius_m, ro = ri + 3 * st.ring.module_m;
  m.ring_mass_kg = annulus_mass(st.ring.material.density_kg_m3, ro, ri, st.ring.face_width_m);
  m.ring_inertia_kgm2 = 0.5 * m.ring_mass_kg * (ro * ro + ri * ri);
  return m;
}

PreparedStage prepare(const SimulationConfig& c) {
  validate(c);
  PreparedStage p;
  p.geometry = geometry::make_stage_geometry(c.stage);
  const auto& geo = p.geometry;
  p.masses = mass_properties(c, geo);
  const double zs = c.stage.sun.teeth, zr = c.stage.ring.teeth;
  p.sun_speed_rad_s = c.operating.input_speed_rpm * 2 * kPi / 60;
  p.carrier_speed_rad_s = p.sun_speed_rad_s * zs / (zs + zr);
  p.mesh_frequency_Hz = zs * (p.sun_speed_rad_s - p.carrier_speed_rad_s) / (2 * kPi);

  MeshFamily sp = make_family(c.stage.sun, c.stage.planet, geo.sun_planet, c);
  MeshFamily pr = make_family(c.stage.planet, c.stage.ring, geo.planet_ring, c);

  dynamics::StageLayout l;
  l.sun_base_radius_m = geo.sun.base_radius_m;
  l.planet_base_radius_m = geo.planet.base_radius_m;
  l.ring_base_radius_m = geo.ring.base_radius_m;
  l.carrier_radius_m = geo.carrier_radius_m;
  l.sun_planet_pressure_angle_rad = geo.sun_planet.working_pressure_angle_rad;
  l.planet_ring_pressure_angle_rad = geo.planet_ring.working_pressure_angle_rad;
  l.planet_angles_rad = geo.planet_angles_rad;
  const MassProperties& m = p.masses;
  l.sun_mass_kg = m.sun_mass_kg;
  l.sun_inertia_kgm2 = m.sun_inertia_kgm2;
  l.planet_mass_kg = m.planet_mass_kg;
  l.planet_inertia_kgm2 = m.planet_inertia_kgm2;
  l.carrier_mass_kg = m.carrier_mass_kg;
  l.carrier_inertia_kgm2 = m.carrier_inertia_kgm2;
  l.ring_mass_kg = m.ring_mass_kg;
  l.ring_inertia_kgm2 = m.ring_inertia_kgm2;
  l.sun_speed_rel_rad_s = p.sun_speed_rad_s - p.carrier_speed_rad_s;
  l.ring_speed_rel_rad_s = -p.carrier_speed_rad_s;
  dynamics::LumpedStructure structure;
  if (c.solver.level == ModelLevel::Torsional) {
    structure = dynamics::build_torsional(l);
  } else {
    dynamics::Bearings b;
    b.sun_N_m = c.bearings.sun_N_m;
    b.carrier_N_m = c.bearings.carrier_N_m;
    b.ring_N_m = c.bearings.ring_N_m;
    b.planet_N_m = c.bearings.planet_N_m;
    b.ring_torsional_N_m = c.bearings.ring_torsional_N_m;
    structure = dynamics::build_lateral_torsional(l, b);
  }

  // Natural frequencies at the time-averaged mesh stiffness.
  std::vector<double> kbar;
  for (std::size_t i = 0; i < structure.meshes.size(); ++i)
    kbar.push_back(i % 2 == 0 ? sp.mean_stiffness_N_m : pr.mean_stiffness_N_m);
  const Eigen::MatrixXd K = structure.support_stiffness + dynamics::mesh_stiffness_matrix(structure, kbar);
  p.natural_frequencies_Hz = dynamics::natural_frequencies(structure.mass, K).frequencies_Hz;
  const double f_max = p.natural_frequencies_Hz.maxCoeff();

  // Time step: resolve the mesh period and the stiffest mode (average
  // acceleration: relative period error ~ (omega dt)^2 / 12, 0.3 % at 32
  // steps per period), and fit a whole number of steps in a mesh period.
  const double T_mesh = 1.0 / p.mesh_frequency_Hz;
  const auto& sv = c.solver;
  double dt = sv.time_step_s;
  if (dt <= 0) dt = std::min(T_mesh / sv.min_steps_per_mesh, 1.0 / (f_max * sv.steps_per_mode_period));
  const double w_max = 2 * kPi * f_max;
  if (2 * sv.newmark_beta < sv.newmark_gamma) {
    // Conditionally stable member of the family (e.g. linear acceleration).
    const double limit = 1.0 / (w_max * std::sqrt(0.5 * sv.newmark_gamma - sv.newmark_beta));
    require(dt <= limit, "solver.time_step_s", dt, " s exceeds the stability limit ", limit,
            " s of this Newmark scheme for the highest natural frequency ", f_max, " Hz");
  }
  require(dt <= 1.0 / (8 * f_max), "solver.time_step_s", dt,
          " s gives fewer than 8 steps per period of the highest natural frequency (", f_max,
          " Hz); the response would be wrong. Use <= ", 1.0 / (8 * f_max), " s or 0 for automatic");
  p.steps_per_mesh = static_cast<int>(std::ceil(T_mesh / dt - 1e-9));
  p.time_step_s = T_mesh / p.steps_per_mesh;

  // Tooth flank state: deviations and stiffness factors per tooth.
  ToothSurfaces surf;
  const int N = c.stage.planet_count;
  const auto& gs = geo.sun_planet;
  const auto& gr = geo.planet_ring;
  surf.sun = FlankSet(c.stage.sun.teeth, kDefaultElements, gs.start_active_m, gs.end_active_m);
  surf.ring = FlankSet(c.stage.ring.teeth, kDefaultElements, gr.start_active_m, gr.end_active_m);
  for (int i = 0; i < N; ++i) {
    surf.planet_sun_side.emplace_back(c.stage.planet.teeth, kDefaultElements, gs.start_active_m, gs.end_active_m);
    surf.planet_ring_side.emplace_back(c.stage.planet.teeth, kDefaultElements, gr.start_active_m, gr.end_active_m);
  }
  apply_tooth_modifiers(c.imperfections, surf);

  p.dynamics = std::make_unique<PlanetaryDynamics>(c, std::move(structure), std::move(sp), std::move(pr),
                                                   geometry::mesh_phases(c.stage, geo), std::move(surf),
                                                   p.sun_speed_rad_s, p.carrier_speed_rad_s);
  return p;
}

std::vector<Curve> stiffness_curves(const PreparedStage& p) {
  std::vector<Curve> out;
  for (int m = 0; m < 2; ++m) {
    const MeshFamily& f = p.dynamics->family(m);
    const std::string name = m == 0 ? "sun_planet" : "planet_ring";
    Curve single{name + "/single_pair", "distance_from_pitch_point", "m", "stiffness", "N/m",
                 "single tooth-pair mesh stiffness vs signed distance of the contact point from the pitch point "
                 "along the line of action (positive towards the driving gear's tip)",
                 {}, {}};
    constexpr int n = 400;
    const auto& g = f.geometry;
    for (int i = 0; i <= n; ++i) {
      const double xi = g.start_active_m + (g.end_active_m - g.start_active_m) * i / n;
      single.x.push_back(xi - g.pitch_point_m);
      single.y.push_back(f.stiffness(xi));
    }
    Curve comb{name + "/combined", "time_in_mesh_periods", "1", "stiffness", "N/m",
               "combined mesh stiffness (sum over pairs in contact) over one mesh period, t = 0 when a new pair "
               "enters",
               {}, {}};
    for (int i = 0; i <= n; ++i) {
      comb.x.push_back(static_cast<double>(i) / n);
      comb.y.push_back(combined_stiffness(f, g.base_pitch_m * i / n));
    }
    out.push_back(std::move(single));
    out.push_back(std::move(comb));
  }
  return out;
}

std::vector<Scalar> stiffness_scalars(const PreparedStage& p) {
  std::vector<Scalar> out;
  for (int m = 0; m < 2; ++m) {
    const MeshFamily& f = p.dynamics->family(m);
    const std::string name = m == 0 ? "sun_planet" : "planet_ring";
    const stiffness::MeshStiffnessSummary s = stiffness::summarize(f.stiffness, f.geometry);
    out.push_back({name + "/single_pair_max_stiffness", "N/m", "maximum single-pair mesh stiffness",
                   s.max_single_pair_N_m});
    out.push_back({name + "/combined_max_stiffness", "N/m", "maximum combined mesh stiffness", s.combined_max_N_m});
    out.push_back({name + "/combined_min_stiffness", "N/m", "minimum combined mesh stiffness", s.combined_min_N_m});
    out.push_back({name + "/mean_stiffness", "N/m", "time-averaged combined mesh stiffness", f.mean_stiffness_N_m});
    out.push_back({name + "/first_harmonic_stiffness", "N/m",
                   "amplitude of the mesh-frequency harmonic of the combined stiffness (seed Table 2 'first "
                   "stiffness excitation')",
                   s.first_harmonic_N_m});
    out.push_back({name + "/contact_ratio", "1", "transverse contact ratio", f.geometry.contact_ratio});
  }
  return out;
}

SimulationResult simulate(const SimulationConfig& c, const ProgressFn& progress) {
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const auto& S = sys.structure();
  const int n = S.dofs;
  const int nm = static_cast<int>(S.meshes.size());
  const int N = c.stage.planet_count;
  const double dt = p.time_step_s;
  const int spm = p.steps_per_mesh;
  const auto report = [&](double f, const std::string& phase) {
    if (progress) progress(f, phase);
  };

  dynamics::NewmarkSolver solver(sys, dt, {c.solver.newmark_beta, c.solver.newmark_gamma},
                                 {c.solver.newton_tolerance, c.solver.newton_max_iterations});

  // Static start (seed Fig. 7 starts from the periodic state; the static
  // solution at the mean stiffness is the closest cheap guess). The rigid
  // rotation is free, so shift K by a tiny multiple of M.
  dynamics::NewmarkState st;
  st.t = 0;
  st.v = Eigen::VectorXd::Zero(n);
  {
    std::vector<double> kbar;
    for (int m = 0; m < nm; ++m) kbar.push_back(sys.family(m).mean_stiffness_N_m);
    Eigen::MatrixXd K = S.support_stiffness + dynamics::mesh_stiffness_matrix(S, kbar);
    K += 1e-9 * K.diagonal().maxCoeff() / S.mass.diagonal().maxCoeff() * S.mass;
    const Eigen::VectorXd f = sys.nominal_input_torque_Nm() * sys.sun_theta_row().transpose() -
                              sys.load_torque_Nm() * sys.carrier_theta_row().transpose();
    st.q = K.ldlt().solve(f);
  }
  sys.set_roll_reference(st.q);
  solver.initialize(st);

  // Warm-up: whole mesh periods until the deflections repeat and the load
  // torque holds the nominal speed (steady state w_s ~ 1/T_L at constant
  // power, so T_L <- T_L * mean(w_s)/Omega_s converges in a few periods).
  const bool periodic_per_mesh = !has_tooth_level_features(c);
  double f_low = 0;
  for (int i = 0; i < p.natural_frequencies_Hz.size(); ++i)
    if (p.natural_frequencies_Hz(i) > 1e-3 * p.natural_frequencies_Hz.maxCoeff()) {
      f_low = p.natural_frequencies_Hz(i);
      break;
    }
  const double zeta = std::max(c.contact.mesh_damping_ratio, 1e-3);
  const int settle_cycles =
      std::max(3, static_cast<int>(std::ceil(10.0 / (zeta * 2 * kPi * f_low) * p.mesh_frequency_Hz)));
  const int max_warm = c.solver.warmup_max_mesh_cycles;
  std::vector<double> prev_defl(nm, 0.0);
  int warm = 0;
  double residual = 1.0;
  double warm_progress = 0.0;
  long newton_total = 0, steps_total = 0;
  for (warm = 1; warm <= max_warm; ++warm) {
    double mean_ws = 0;
    for (int k = 0; k < spm; ++k) {
      newton_total += solver.step(st);
      sys.set_roll_reference(st.q);
      ++steps_total;
      mean_ws += p.sun_speed_rad_s + sys.sun_theta_row().dot(st.v);
    }
    mean_ws /= spm;
    sys.set_load_torque_Nm(sys.load_torque_Nm() * mean_ws / p.sun_speed_rad_s);
    double dmax = 0, dchange = 0;
    for (int m = 0; m < nm; ++m) {
      const double d = sys.mesh_states()[m].deflection_m;
      dmax = std::max(dmax, std::fabs(d));
      dchange = std::max(dchange, std::fabs(d - prev_defl[m]));
      prev_defl[m] = d;
    }
    residual = std::max(dchange / std::max(dmax, 1e-30), std::fabs(mean_ws / p.sun_speed_rad_s - 1.0));
    // Progress of the warm-up: how far the periodicity residual has fallen
    // towards its tolerance on a log scale (or the share of the fixed settle
    // time), never moving backwards.
    const double frac = periodic_per_mesh
                            ? std::log(std::max(residual, 1e-300)) / std::log(c.solver.periodicity_tolerance)
                            : static_cast<double>(warm) / settle_cycles;
    warm_progress = std::clamp(frac, warm_progress, 1.0);
    report(0.3 * warm_progress, "warm-up");
    if (warm >= 3 && periodic_per_mesh && residual < c.solver.periodicity_tolerance) break;
    if (!periodic_per_mesh && warm >= settle_cycles) break;
  }
  warm = std::min(warm, max_warm);

  // Recording: preallocate every channel, then integrate.
  const int nrec = c.solver.record_mesh_cycles * spm;
  SimulationResult r;
  r.time_step_s = dt;
  r.time_s.resize(nrec);
  struct MeshChannels {
    std::vector<double> *defl, *force, *acc, *stiff, *pairs, *fric;
  };
  auto add = [&](std::string name, std::string unit, std::string desc) {
    r.channels.push_back({std::move(name), std::move(unit), std::move(desc), std::vector<double>(nrec)});
  };
  for (int m = 0; m < nm; ++m) {
    const std::string b = S.meshes[m].name + "/";
    add(b + "deflection", "m",
        "mesh deflection along the line of action incl. imposed errors (seed: penetration depth at the meshing "
        "line); positive compresses the drive flanks");
    add(b + "force", "N", "total dynamic normal mesh force (elastic + damping), summed over tooth pairs");
    add(b + "acceleration", "m/s^2", "relative acceleration of the two gears along the line of action");
    add(b + "stiffness", "N/m", "combined mesh stiffness of the pairs geometrically in mesh");
    add(b + "pairs_in_contact", "1", "number of tooth pairs geometrically in mesh");
    add(b + "friction_force", "N", "sum of signed tooth friction forces (A's sliding direction on B)");
  }
  add("sun/speed", "rad/s", "absolute sun speed");
  add("carrier/speed", "rad/s", "absolute carrier speed");
  add("transmission_error", "m",
      "r_bs (theta_s - theta_c (Zs+Zr)/Zs), angular transmission error of the stage at the sun's base circle");
  add("sun/input_torque", "N m", "input torque on the sun");
  for (int i = 0; i < N; ++i)
    add("load_sharing/" + std::to_string(i), "1", "N F_sp,i / sum_k F_sp,k: instantaneous load share of planet i");
  std::vector<MeshChannels> mch(nm);
  for (int m = 0; m < nm; ++m) {
    auto* base = &r.channels[6 * m];
    mch[m] = {&base[0].values, &base[1].values, &base[2].values, &base[3].values, &base[4].values, &base[5].values};
  }
  auto& ch_ws = r.channels[6 * nm].values;
  auto& ch_wc = r.channels[6 * nm + 1].values;
  auto& ch_te = r.channels[6 * nm + 2].values;
  auto& ch_ts = r.channels[6 * nm + 3].values;
  const double ratio = (c.stage.sun.teeth + c.stage.ring.teeth) / static_cast<double>(c.stage.sun.teeth);
  const double rbs = p.geometry.sun.base_radius_m;
  const double t0 = st.t;
  for (int k = 0; k < nrec; ++k) {
    newton_total += solver.step(st);
    sys.set_roll_reference(st.q);
    ++steps_total;
    r.time_s[k] = st.t - t0;
    const auto& ms = sys.mesh_states();
    double fsum = 0;
    for (int m = 0; m < nm; ++m) {
      (*mch[m].defl)[k] = ms[m].deflection_m;
      (*mch[m].force)[k] = ms[m].force_N;
      (*mch[m].acc)[k] = S.meshes[m].g.dot(st.a);
      (*mch[m].stiff)[k] = ms[m].stiffness_N_m;
      (*mch[m].pairs)[k] = ms[m].pairs;
      (*mch[m].fric)[k] = ms[m].friction_N;
      if (m % 2 == 0) fsum += ms[m].force_N;
    }
    const double ws = p.sun_speed_rad_s + sys.sun_theta_row().dot(st.v);
    ch_ws[k] = ws;
    ch_wc[k] = p.carrier_speed_rad_s + sys.carrier_theta_row().dot(st.v);
    ch_te[k] = rbs * (sys.sun_theta_row().dot(st.q) - ratio * sys.carrier_theta_row().dot(st.q));
    ch_ts[k] = sys.input_torque_Nm(st.t, st.q, st.v);
    for (int i = 0; i < N; ++i)
      r.channels[6 * nm + 4 + i].values[k] = fsum != 0 ? N * ms[2 * i].force_N / fsum : 0.0;
    if (k % spm == 0) report(0.3 + 0.7 * k / nrec, "recording");
  }
  report(1.0, "done");

  // Scalars.
  auto scalar = [&](std::string name, std::string unit, std::string desc, double v) {
    r.scalars.push_back({std::move(name), std::move(unit), std::move(desc), v});
  };
  scalar("time_step", "s", "Newmark time step", dt);
  scalar("steps_per_mesh_period", "1", "time steps per mesh period", spm);
  scalar("mesh_frequency", "Hz", "mesh frequency Zs (f_s - f_c) at the nominal speed", p.mesh_frequency_Hz);
  scalar("sun_speed", "rad/s", "nominal absolute sun speed", p.sun_speed_rad_s);
  scalar("carrier_speed", "rad/s", "nominal carrier speed", p.carrier_speed_rad_s);
  scalar("input_torque", "N m", "mean input torque P / Omega_s", sys.nominal_input_torque_Nm());
  scalar("load_torque", "N m", "carrier load torque that holds the nominal speed", sys.load_torque_Nm());
  scalar("efficiency", "1", "T_load Omega_c / P: mesh efficiency of the stage (friction losses)",
         sys.load_torque_Nm() * p.carrier_speed_rad_s / c.operating.input_power_W);
  scalar("warmup_mesh_cycles", "1", "mesh periods integrated before recording", warm);
  scalar("periodicity_residual", "1", "relative change of mesh deflections over the last warm-up mesh period",
         residual);
  scalar("mean_newton_iterations", "1", "Newton iterations per time step, averaged",
         static_cast<double>(newton_total) / static_cast<double>(std::max(1L, steps_total)));
  for (int i = 0; i < p.natural_frequencies_Hz.size(); ++i)
    scalar("natural_frequency/" + std::to_string(i), "Hz", "natural frequency of the linearized time-averaged model",
           p.natural_frequencies_Hz(i));
  for (int m = 0; m < nm; ++m)
    scalar("mesh_damping/" + S.meshes[m].name, "N s/m", "viscous mesh damping coefficient", sys.mesh_damping_N_s_m(m));
  // Load-sharing factor per planet: N mean(F_sp,i) / sum_k mean(F_sp,k).
  std::vector<double> mean_f(N, 0.0);
  for (int i = 0; i < N; ++i) {
    const auto& v = *mch[2 * i].force;
    for (double x : v) mean_f[i] += x / nrec;
  }
  double tot = 0;
  for (double x : mean_f) tot += x;
  for (int i = 0; i < N; ++i)
    scalar("load_sharing_factor/" + std::to_string(i), "1", "N mean(F_sp,i) / sum_k mean(F_sp,k)",
           tot != 0 ? N * mean_f[i] / tot : 0.0);
  for (auto& s : stiffness_scalars(p)) r.scalars.push_back(std::move(s));
  r.curves = stiffness_curves(p);
  return r;
}

} // namespace pw::model
