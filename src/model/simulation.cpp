#include "model/simulation.hpp"

#include "core/constants.hpp"
#include "core/error.hpp"
#include "core/prefault.hpp"
#include "dynamics/modal.hpp"
#include "model/memory_estimate.hpp"
#include "model/mesh_loads.hpp"
#include "model/sensor.hpp"
#include "model/validate.hpp"
#include "signal/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <stdexcept>

namespace pw::model {
namespace {

/// Fewest steps per period of the highest natural frequency: below it the average-acceleration
/// rule's period error, (2 pi / n)^2 / 12, exceeds 5 % and prepare() refuses the step.
constexpr double kMinStepsPerModePeriod = 8;

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

/// Slide-to-roll ratio |v_A - v_B| / v_flank of one flank of a mesh at roll
/// coordinate xi (docs/derivation.md §5, W1): the Archard depth per pass at
/// uniform load. Rolling speeds of the contact over the flanks, with
/// |omega| proportional to 1 / r_b (zero sliding at the pitch point), are
/// v_A = rho_A / r_bA and v_B = rho_B / r_bB, rho_A = xi,
/// rho_B = rho_B(xi_P) -+ (xi - xi_P) (external / internal B).
double slide_to_roll(const geometry::MeshGeometry& g, double xi, bool flank_of_a) {
  const double tan_a = std::tan(g.working_pressure_angle_rad);
  const double rho_bp = g.base_radius_b_m * tan_a;
  const double rho_b = g.kind == geometry::GearKind::External ? rho_bp - (xi - g.pitch_point_m)
                                                               : rho_bp + (xi - g.pitch_point_m);
  const double va = xi / g.base_radius_a_m, vb = rho_b / g.base_radius_b_m;
  return std::fabs(va - vb) / (flank_of_a ? va : vb);
}

/// Pre-existing worn profile (imperfections.worn_profile_depth_m): adds
/// depth * s(xi) / max_e s(xi_e) to every element of every tooth of the flank
/// family, s the flank's slide-to-roll ratio, so the family's largest depth
/// is `depth` (at the element centre nearest the flank's root end).
void apply_worn_profile(double depth, const geometry::MeshGeometry& g, bool flank_of_a, FlankSet& f) {
  if (depth == 0) return;
  std::vector<double> shape(f.elements());
  double smax = 0;
  for (int e = 0; e < f.elements(); ++e) {
    shape[e] = slide_to_roll(g, f.element_xi_m(e), flank_of_a);
    smax = std::max(smax, shape[e]);
  }
  if (!(smax > 0)) return;
  for (int t = 0; t < f.teeth(); ++t) {
    double* d = f.tooth_deviation(t);
    for (int e = 0; e < f.elements(); ++e) d[e] += depth * shape[e] / smax;
  }
}

/// Linear tip relief (contact.tip_relief_m, ISO 21771 "tip relief"): material
/// removed from each gear's tip, C_a at the tip and falling linearly to 0 over
/// the roll length L = extent (eps_alpha - 1) p_b from the tip (extent 1: the
/// long relief, from the point of single contact). Along the path of contact
/// A's tip is at end_active (xi grows towards A's tip) and B's at start_active
/// (geometry/mesh.hpp), for the internal mesh as for the external one. A pair's
/// deflection is reduced by the deviations of both its flanks, so a relieved
/// pair enters and leaves the load gradually (a load-dependent ramp, Tavakoli &
/// Houser 1986, J. Mech. Trans. Autom. Des. 108:86).
void apply_tip_relief(const ContactSettings& c, const geometry::MeshGeometry& g, bool flank_of_a, FlankSet& f) {
  if (c.tip_relief_m == 0) return;
  const double length = c.tip_relief_extent * (g.contact_ratio - 1) * g.base_pitch_m;
  if (!(length > 0)) return;  // contact ratio 1: no double contact to relieve
  for (int e = 0; e < f.elements(); ++e) {
    const double xi = f.element_xi_m(e);
    const double from_tip = flank_of_a ? g.end_active_m - xi : xi - g.start_active_m;
    const double depth = c.tip_relief_m * std::max(0.0, 1.0 - from_tip / length);
    for (int t = 0; t < f.teeth(); ++t) f.tooth_deviation(t)[e] += depth;
  }
}

/// The checks that need the geometry and the time step (validate.cpp has neither), made once
/// before anything runs so that a wear or campaign run fails as a bad input, not as a solver
/// failure half-way: the engagement ramp must leave every mesh within MeshState::kMaxPairs pairs
/// (a window of epsilon + r base pitches holds at most floor(epsilon + r) + 1), and a housing
/// mount must lie below the Nyquist frequency of the simulation's steps (the stored samples,
/// possibly decimated, are checked where they are made).
/// The ramp a window of epsilon + r base pitches may add before it holds kMaxPairs pairs, by a
/// relative 1e-9 inside the strict limit (so that the largest value passes the check below).
double ramp_room(const geometry::StageGeometry& geo) {
  const double eps = std::max(geo.sun_planet.contact_ratio, geo.planet_ring.contact_ratio);
  return std::max(0.0, (MeshState::kMaxPairs - 1 - eps) * (1 - 1e-9));
}

void check_step_dependent_keys(const SimulationConfig& c, const geometry::StageGeometry& geo, double dt_s) {
  const double r = c.contact.engagement_ramp;
  for (const geometry::MeshGeometry* g : {&geo.sun_planet, &geo.planet_ring})
    require(r == 0 || g->contact_ratio + r < MeshState::kMaxPairs - 1, "contact.engagement_ramp", r,
            " with a contact ratio of ", g->contact_ratio, " puts more than ", MeshState::kMaxPairs,
            " tooth pairs in one mesh; use at most ", MeshState::kMaxPairs - 1 - g->contact_ratio);
  const double mount_Hz = c.sensor.housing_mount_frequency_Hz;
  require(!(mount_Hz * dt_s >= 0.5), "sensor.housing_mount_frequency_Hz", mount_Hz,
          " Hz must lie below the Nyquist frequency ", 0.5 / dt_s, " Hz of the time step ", dt_s, " s");
}

bool has_tooth_level_features(const SimulationConfig& c) {
  const Imperfections& i = c.imperfections;
  return !i.teeth.empty() || i.sun_eccentricity_m != 0 || i.torque_ripple_fraction != 0;
}

/// Combined stiffness at mesh roll s (pair 0 enters at s = 0) [N/m].
double combined_stiffness(const MeshFamily& f, double s) {
  return stiffness::combined_stiffness(f.stiffness, f.geometry, f.geometry.start_active_m + s,
                                       f.engagement_ramp_half_width_m);
}

MeshFamily make_family(const geometry::GearSpec& a, const geometry::GearSpec& b, const geometry::MeshGeometry& mg,
                       const SimulationConfig& c, const StiffnessSettings::Harmonics& harmonics) {
  MeshFamily f;
  f.geometry = mg;
  stiffness::MeshStiffnessOptions opt;
  opt.bore_ratio = c.stage.bore_ratio;
  f.stiffness = stiffness::single_pair_stiffness(mg, a, b, c.stiffness, opt);
  f.teeth_a = a.teeth;
  f.teeth_b = b.teeth;
  f.mean_stiffness_N_m = stiffness::summarize(f.stiffness, mg).combined_mean_N_m;
  for (int h = 0; h < StiffnessSettings::Harmonics::kCount; ++h) {
    f.harmonic_cos_N_m[h] = harmonics.cos[h] * f.mean_stiffness_N_m;
    f.harmonic_sin_N_m[h] = harmonics.sin[h] * f.mean_stiffness_N_m;
  }
  f.corrected = harmonics.any();
  f.engagement_ramp_half_width_m = 0.5 * c.contact.engagement_ramp * mg.base_pitch_m;
  return f;
}

} // namespace

MassProperties mass_properties(const SimulationConfig& c, const geometry::StageGeometry& g) {
  // Sun and planets: steel discs between a bore (bore_ratio x root radius)
  // and the reference circle (teeth counted as half material). Carrier: two
  // side plates of radius 1.2 a', 10 mm thick. Ring: rim 3 modules thick
  // beyond the root circle. The seed gives none of these (REFERENCE.md). A mass or
  // inertia the configuration states (stage.sun_*, carrier_*, ring_*: > 0) replaces its estimate.
  MassProperties m;
  const auto& st = c.stage;
  auto disc = [&](const geometry::GearSpec& s, const geometry::GearGeometry& gg, double& mass, double& inertia) {
    const double ro = gg.reference_radius_m, ri = st.bore_ratio * gg.root_radius_m;
    mass = annulus_mass(s.material.density_kg_m3, ro, ri, s.face_width_m);
    inertia = 0.5 * mass * (ro * ro + ri * ri);
  };
  disc(st.sun, g.sun, m.sun_mass_kg, m.sun_inertia_kgm2);
  if (st.sun_mass_kg > 0) m.sun_mass_kg = st.sun_mass_kg;
  if (st.sun_inertia_kgm2 > 0) m.sun_inertia_kgm2 = st.sun_inertia_kgm2;
  // A rigid input shaft adds the motor to the sun; a flexible one puts it on its own coordinate.
  if (c.rig.input_shaft_stiffness_N_m_rad == 0) m.sun_inertia_kgm2 += st.input_inertia_kgm2;
  disc(st.planet, g.planet, m.planet_mass_kg, m.planet_inertia_kgm2);
  const double Rc = 1.2 * g.carrier_radius_m;
  m.carrier_mass_kg = st.carrier_mass_kg > 0 ? st.carrier_mass_kg
                                             : annulus_mass(st.sun.material.density_kg_m3, Rc, 0.0, 2 * 0.010);
  m.carrier_inertia_kgm2 = st.carrier_inertia_kgm2 > 0 ? st.carrier_inertia_kgm2 : 0.5 * m.carrier_mass_kg * Rc * Rc;
  if (c.rig.output_shaft_stiffness_N_m_rad == 0) m.carrier_inertia_kgm2 += st.output_inertia_kgm2;  // rigid output shaft
  const double ri = g.ring.root_radius_m, ro = ri + 3 * st.ring.module_m;
  m.ring_mass_kg = annulus_mass(st.ring.material.density_kg_m3, ro, ri, st.ring.face_width_m);
  m.ring_inertia_kgm2 = 0.5 * m.ring_mass_kg * (ro * ro + ri * ri);
  if (st.ring_mass_kg > 0) m.ring_mass_kg = st.ring_mass_kg;
  if (st.ring_inertia_kgm2 > 0) m.ring_inertia_kgm2 = st.ring_inertia_kgm2;
  return m;
}

double automatic_time_step(double T_mesh, double f_max, const SolverSettings& sv) {
  const double f_accurate = sv.accuracy_band_Hz > 0 ? std::min(f_max, sv.accuracy_band_Hz) : f_max;
  // A mode above the band gets a quarter of steps_per_mode_period (8 at the default 32: period
  // error (2 pi / 8)^2 / 12 = 5 %), never fewer than the 8 prepare() requires. A quarter, not a
  // constant 8, so that a finer steps_per_mode_period (the diagnosis's second discretization)
  // refines every term.
  const double steps_above_band = std::max(kMinStepsPerModePeriod, 0.25 * sv.steps_per_mode_period);
  return std::min({T_mesh / sv.min_steps_per_mesh, 1.0 / (f_accurate * sv.steps_per_mode_period),
                   1.0 / (steps_above_band * f_max)});
}

double largest_engagement_ramp(const SimulationConfig& config) {
  return std::min(ContactSettings::kMaxEngagementRamp, ramp_room(geometry::make_stage_geometry(config.stage)));
}

bool settles_without_tooth_level_features(const SimulationConfig& c) {
  return !c.imperfections.teeth.empty() || c.imperfections.sun_eccentricity_m != 0;
}

/// Whether make_tooth_surfaces() applies imperfections.teeth.
enum class ToothModifiers { Applied, Left_out };

/// The flanks' initial state: each tooth's deviations (worn profile, tip relief) and stiffness
/// factors (the tooth modifiers, when applied).
ToothSurfaces make_tooth_surfaces(const SimulationConfig& c, const geometry::StageGeometry& geo,
                                  ToothModifiers modifiers) {
  ToothSurfaces surf;
  const int N = c.stage.planet_count;
  const auto& gs = geo.sun_planet;
  const auto& gr = geo.planet_ring;
  surf.sun = FlankSet(c.stage.sun.teeth, c.wear.elements_per_flank, gs.start_active_m, gs.end_active_m);
  surf.ring = FlankSet(c.stage.ring.teeth, c.wear.elements_per_flank, gr.start_active_m, gr.end_active_m);
  for (int i = 0; i < N; ++i) {
    surf.planet_sun_side.emplace_back(c.stage.planet.teeth, c.wear.elements_per_flank, gs.start_active_m, gs.end_active_m);
    surf.planet_ring_side.emplace_back(c.stage.planet.teeth, c.wear.elements_per_flank, gr.start_active_m, gr.end_active_m);
  }
  if (modifiers == ToothModifiers::Applied) apply_tooth_modifiers(c.imperfections, surf);
  const double worn = c.imperfections.worn_profile_depth_m;
  apply_worn_profile(worn, gs, true, surf.sun);
  apply_worn_profile(worn, gr, false, surf.ring);
  for (int i = 0; i < N; ++i) {
    apply_worn_profile(worn, gs, false, surf.planet_sun_side[i]);
    apply_worn_profile(worn, gr, true, surf.planet_ring_side[i]);
  }
  apply_tip_relief(c.contact, gs, true, surf.sun);
  apply_tip_relief(c.contact, gr, false, surf.ring);
  for (int i = 0; i < N; ++i) {
    apply_tip_relief(c.contact, gs, false, surf.planet_sun_side[i]);
    apply_tip_relief(c.contact, gr, true, surf.planet_ring_side[i]);
  }
  return surf;
}

PreparedStage prepare(const SimulationConfig& c) {
  validate(c);
  PreparedStage p;
  p.geometry = geometry::make_stage_geometry(c.stage);
  const auto& geo = p.geometry;
  p.masses = mass_properties(c, geo);
  const double zs = c.stage.sun.teeth;
  p.sun_speed_rad_s = c.operating.input_speed_rpm * 2 * kPi / 60;
  p.carrier_speed_rad_s = carrier_speed(c.stage, p.sun_speed_rad_s);
  p.mesh_frequency_Hz = zs * (p.sun_speed_rad_s - p.carrier_speed_rad_s) / (2 * kPi);

  MeshFamily sp = make_family(c.stage.sun, c.stage.planet, geo.sun_planet, c, c.stiffness.sun_planet_harmonics);
  MeshFamily pr = make_family(c.stage.planet, c.stage.ring, geo.planet_ring, c, c.stiffness.planet_ring_harmonics);

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
  auto control = [](bool ideal_speed, bool loop) {
    return ideal_speed ? dynamics::MachineControl::IdealSpeed
                       : loop ? dynamics::MachineControl::SpeedLoop : dynamics::MachineControl::Torque;
  };
  dynamics::RigLayout rig;
  rig.input = {.machine_inertia_kgm2 = c.stage.input_inertia_kgm2,
               .shaft_N_m_rad = c.rig.input_shaft_stiffness_N_m_rad,
               .shaft_N_m_s_rad = c.rig.input_shaft_damping_N_m_s_rad,
               .control = control(c.rig.input_control == InputControl::Speed,
                                  c.rig.input_control == InputControl::SpeedLoop),
               .loop_integral_N_m_rad = c.rig.input_speed_loop_integral_N_m_rad,
               .loop_proportional_N_m_s_rad = c.rig.input_speed_loop_proportional_N_m_s_rad};
  rig.output = {.machine_inertia_kgm2 = c.stage.output_inertia_kgm2,
                .shaft_N_m_rad = c.rig.output_shaft_stiffness_N_m_rad,
                .shaft_N_m_s_rad = c.rig.output_shaft_damping_N_m_s_rad,
                .control = control(c.rig.load_control == LoadControl::Speed,
                                   c.rig.load_control == LoadControl::SpeedLoop),
                .loop_integral_N_m_rad = c.rig.load_speed_loop_integral_N_m_rad,
                .loop_proportional_N_m_s_rad = c.rig.load_speed_loop_proportional_N_m_s_rad};
  dynamics::LumpedStructure structure;
  if (c.solver.level == ModelLevel::Torsional) {
    structure = dynamics::build_torsional(l, rig);
  } else {
    dynamics::Bearings b;
    b.sun_N_m = c.bearings.sun_N_m;
    b.carrier_N_m = c.bearings.carrier_N_m;
    b.ring_N_m = c.bearings.ring_N_m;
    b.planet_N_m = c.bearings.planet_N_m;
    b.ring_torsional_N_m = c.bearings.ring_torsional_N_m;
    b.damping_ratio = c.bearings.damping_ratio;
    structure = dynamics::build_lateral_torsional(l, b, rig);
  }

  // Natural frequencies at the time-averaged mesh stiffness.
  std::vector<double> kbar;
  for (std::size_t i = 0; i < structure.meshes.size(); ++i)
    kbar.push_back(dynamics::MeshId::of(i).sun_planet() ? sp.mean_stiffness_N_m : pr.mean_stiffness_N_m);
  const Eigen::MatrixXd K = structure.support_stiffness + dynamics::mesh_stiffness_matrix(structure, kbar);
  const dynamics::ModalResult modal = dynamics::natural_frequencies(structure.mass, K);
  p.natural_frequencies_Hz = modal.frequencies_Hz;
  if (structure.has_rigid_mode) {
    // Mode 0 is the rigid rotation (sun and carrier free, ring held).
    const Eigen::RowVectorXd sun_row = structure.bodies[structure.sun_body].map.row(2);
    p.rigid_mode = modal.modes.col(0) / sun_row.dot(modal.modes.col(0));
  }
  const double f_max = p.natural_frequencies_Hz.maxCoeff();

  // Time step: resolve the mesh period and the stiffest mode (average
  // acceleration: relative period error ~ (omega dt)^2 / 12, 0.3 % at 32
  // steps per period), and fit a whole number of steps in a mesh period.
  const double T_mesh = 1.0 / p.mesh_frequency_Hz;
  const auto& sv = c.solver;
  double dt = sv.time_step_s;
  if (dt <= 0) dt = automatic_time_step(T_mesh, f_max, sv);
  const double w_max = 2 * kPi * f_max;
  if (2 * sv.newmark_beta < sv.newmark_gamma) {
    // Conditionally stable member of the family (e.g. linear acceleration).
    const double limit = 1.0 / (w_max * std::sqrt(0.5 * sv.newmark_gamma - sv.newmark_beta));
    require(dt <= limit, "solver.time_step_s", dt, " s exceeds the stability limit ", limit,
            " s of this Newmark scheme for the highest natural frequency ", f_max, " Hz");
  }
  const double dt_limit = 1.0 / (kMinStepsPerModePeriod * f_max);
  require(dt <= dt_limit, "solver.time_step_s", dt, " s gives fewer than ", kMinStepsPerModePeriod,
          " steps per period of the highest natural frequency (", f_max,
          " Hz); the response would be wrong. Use <= ", dt_limit, " s or 0 for automatic");
  p.steps_per_mesh = checked_steps_per_mesh(c, T_mesh, dt);
  p.time_step_s = T_mesh / p.steps_per_mesh;
  check_step_dependent_keys(c, geo, p.time_step_s);

  // Tooth flank state: deviations and stiffness factors per tooth.
  check_flank_memory(c);
  ToothSurfaces surf = make_tooth_surfaces(c, geo, ToothModifiers::Applied);
  p.dynamics = std::make_unique<PlanetaryDynamics>(c, std::move(structure), std::move(sp), std::move(pr),
                                                   geometry::mesh_phases(c.stage, geo), std::move(surf),
                                                   p.sun_speed_rad_s, p.carrier_speed_rad_s);
  // Sub-step engagement (derivation §3.4): pairs enter and leave contact over one step, or over
  // the gears' own engagement ramp (contact.engagement_ramp) where that is wider.
  p.dynamics->set_engagement_smoothing(c.solver.engagement_smoothing ? p.time_step_s : 0.0);
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
    // The planet-ring one sets the direction in which a planet pushes the ring (model/sensor.hpp
    // Eq. S2), which the diagnosis needs to compute the housing channel from the ring forces.
    out.push_back({name + "/working_pressure_angle", "rad", "working (operating) pressure angle alpha'",
                   f.geometry.working_pressure_angle_rad});
  }
  return out;
}

void Integration::throw_reversed(double sun_speed_rad_s) const {
  throw SolverError(detail::concat(
      "the simulated sun stopped turning forward at t = ", st.t, " s (sun speed ", sun_speed_rad_s,
      " rad/s, nominal ", p.sun_speed_rad_s, " rad/s): the response diverged and has no steady state to record. "
      "Either the time step (", p.time_step_s, " s) is too long for this load at this speed (set "
      "solver.steps_per_mode_period above ", c.solver.steps_per_mode_period,
      ", or solver.time_step_s or solver.accuracy_band_Hz so that the step is shorter), or the stage cannot run at ",
      c.operating.input_power_W, " W and ", c.operating.input_speed_rpm,
      " rpm (operating.input_power_W, operating.input_speed_rpm)"));
}

RingBodyReader::RingBodyReader(const dynamics::LumpedStructure& S)
    : x_(S.bodies[static_cast<std::size_t>(S.ring_body)].map.row(0)),
      y_(S.bodies[static_cast<std::size_t>(S.ring_body)].map.row(1)),
      mass_kg_(S.bodies[static_cast<std::size_t>(S.ring_body)].mass_kg) {}

Eigen::Vector2d RingBodyReader::fixed_frame(const Eigen::VectorXd& a, double carrier_angle_rad) const {
  // The lateral-torsional model's translations are Lin & Parker's (1999): carrier-fixed axes turning
  // with the carrier (dynamics/lumped_model.cpp). The fixed-frame acceleration of a point at u in
  // that frame is R(theta_c) (u'' + 2 Omega z x u' + Omega' z x u - Omega^2 u); the model itself
  // neglects the Coriolis and centripetal terms (dynamics/lumped_model.hpp), so only R(theta_c) u''
  // is kept here too. Relative to u'' at a line of angular frequency w they are 2 Omega_c / w and
  // (Omega_c / w)^2: a 600 rpm sun on 21/81 teeth turns the carrier at 12.9 rad/s, 0.4 % and 4e-6
  // of a 1 kHz line (the translational modes the ring_body path is for).
  const double ax = x_.dot(a), ay = y_.dot(a);
  const double c = std::cos(carrier_angle_rad), s = std::sin(carrier_angle_rad);
  return {c * ax - s * ay, s * ax + c * ay};
}

namespace {


/// Static start (seed Fig. 7 starts from the periodic state; the static
/// solution at the mean stiffness is the closest cheap guess). The rigid
/// rotation is free, so K is shifted by a tiny multiple of M.
void start_static(Integration& r) {
  PlanetaryDynamics& sys = r.sys();
  const auto& S = sys.structure();
  std::vector<double> kbar;
  for (std::size_t m = 0; m < S.meshes.size(); ++m) kbar.push_back(sys.family(static_cast<int>(m)).mean_stiffness_N_m);
  Eigen::MatrixXd K = S.support_stiffness + dynamics::mesh_stiffness_matrix(S, kbar);
  K += 1e-9 * K.diagonal().maxCoeff() / S.mass.diagonal().maxCoeff() * S.mass;
  const Eigen::VectorXd f = sys.nominal_input_torque_Nm() * sys.input_theta_row().transpose() -
                            sys.load_torque_Nm() * sys.output_theta_row().transpose();
  r.st.t = 0;
  r.st.v = Eigen::VectorXd::Zero(S.dofs);
  r.st.q = K.ldlt().solve(f);
  sys.set_roll_reference(r.st.q);
  r.solver.initialize(r.st);
}

struct WarmupStats {
  int cycles = 0;
  double residual = 1.0;
};

/// The speed the warm-up's loop holds (see warm_up()).
enum class SpeedLoop {
  SunSpeed,   ///< the sun's speed (the seed's choice; every result before session 20)
  RigidMode,  ///< the rigid mode's own speed r'Mv / r'Mr
};

/// Whole mesh periods until the deflections repeat and the load torque holds
/// the nominal speed (steady state w_s ~ 1/T_L at constant power, so
/// T_L <- T_L mean(w_s)/Omega_s converges in a few periods).
WarmupStats warm_up(Integration& r, const ProgressFn& report, double f0, double f1, SpeedLoop loop,
                    bool periodic_per_mesh, int cycles_done = 0) {
  const SimulationConfig& c = r.c;
  PreparedStage& p = r.p;
  PlanetaryDynamics& sys = r.sys();
  const int nm = static_cast<int>(sys.mesh_states().size());
  const int spm = p.steps_per_mesh;
  double f_low = 0;
  for (int i = 0; i < p.natural_frequencies_Hz.size(); ++i)
    if (p.natural_frequencies_Hz(i) > 1e-3 * p.natural_frequencies_Hz.maxCoeff()) {
      f_low = p.natural_frequencies_Hz(i);
      break;
    }
  const double zeta = std::max(c.contact.mesh_damping_ratio, 1e-3);
  const int settle_cycles =
      // Clamped before the cast: a very soft mode at a high speed would overflow int.
      static_cast<int>(std::clamp(std::ceil(10.0 / (zeta * 2 * kPi * f_low) * p.mesh_frequency_Hz), 3.0, 1e9));
  const int max_warm = c.solver.warmup_max_mesh_cycles;
  // Speed control acts on the rigid mode r (unit sun rotation): inertia
  // reflected to the sun I_eq = r'Mr, load torque reflected by k_r = carrier
  // rotation per sun rotation = Zs/(Zs+Zr). Averages are taken over whole
  // mesh periods, or, with tooth-level features, over the longer of one sun
  // and one planet revolution relative to the carrier (z mesh periods), so
  // that a damaged tooth or a ripple does not bias them.
  // Under ideal speed control (rig.load_control = speed) there is no rigid mode: the
  // load machine holds the speed, and only the periodicity is waited for.
  const bool speed_held_by_rig = !sys.structure().has_rigid_mode;
  const Eigen::VectorXd& rig = p.rigid_mode;
  const double I_eq = speed_held_by_rig ? 0.0 : rig.dot(sys.mass() * rig);
  // The speed the loop holds: the sun's (SpeedLoop::SunSpeed) or the rigid mode's own, the
  // mass-weighted projection (r'M v) / (r'M r) (SpeedLoop::RigidMode), which leaves every elastic
  // mode out exactly (they are M-orthogonal to r). The sun's speed carries them, and a loop
  // acting on it can feed them back (settle() below says when that happens and what then).
  const bool project = loop == SpeedLoop::RigidMode && !speed_held_by_rig;
  const Eigen::VectorXd Mr_per_I = project ? Eigen::VectorXd(sys.mass() * rig / I_eq) : Eigen::VectorXd();
  const auto rigid_speed = [&](const Eigen::VectorXd& v) {
    return project ? Mr_per_I.dot(v) : sys.sun_rotation(v);
  };
  const double k_r = speed_held_by_rig ? 1.0 : sys.output_theta_row().dot(rig);
  const int window = periodic_per_mesh ? 1 : std::max(c.stage.sun.teeth, c.stage.planet.teeth);
  // Torque ripple modulates the speed at k f_s, not a multiple of the mesh
  // period: average over whole ripple periods (the trend term then comes from
  // the speed means of the first and the last ripple period of the window).
  // (as the dynamics hold it: switched off while the stage settles without its features)
  const bool ripple = sys.aperiodic_excitation().torque_ripple_fraction != 0;
  const long ripple_steps =
      ripple ? std::max(1L, std::lround(2 * kPi / (c.imperfections.torque_ripple_order * p.sun_speed_rad_s) /
                                        p.time_step_s))
             : 0;
  long n_window = static_cast<long>(window) * spm;
  if (ripple) n_window = std::max(2L, (n_window + ripple_steps - 1) / ripple_steps) * ripple_steps;
  const double Omega = p.sun_speed_rad_s;
  const bool constant_power = c.rig.input_control == InputControl::Power;
  std::vector<double> prev(nm, 0.0);
  WarmupStats w;
  double progress = 0;
  int windows = 0;
  // A windowed warm-up runs at least two windows, also after a settled start that used the limit.
  for (w.cycles = cycles_done; w.cycles < max_warm || (!periodic_per_mesh && windows < 2);) {
    double mean_ws = 0, mean_as = 0, mean_Ts = 0, last_ws = 0, first_ws = 0, mean_sun_ws = 0;
    const long n = n_window;
    const long tail = ripple ? ripple_steps : spm;  // speed at the end: last mesh (or ripple) period
    for (long k = 0; k < n; ++k) {
      r.step();
      const double ws_sun = Omega + sys.sun_rotation(r.st.v);
      const double ws = project ? Omega + rigid_speed(r.st.v) : ws_sun;
      mean_ws += ws;
      mean_sun_ws += ws_sun;
      mean_as += rigid_speed(r.st.a);
      mean_Ts += sys.input_torque_Nm(r.st.t, r.st.q, r.st.v);
      if (k >= n - tail) last_ws += ws;
      if (k < tail) first_ws += ws;
    }
    const double dn = static_cast<double>(n);
    mean_ws /= dn;
    mean_as /= dn;
    mean_Ts /= dn;
    last_ws /= static_cast<double>(tail);
    first_ws /= static_cast<double>(tail);
    if (ripple) mean_as = (last_ws - first_ws) / ((dn - static_cast<double>(tail)) * p.time_step_s);
    w.cycles += static_cast<int>(std::lround(dn / spm));
    ++windows;
    // Steady state of the rigid mode at the nominal mean speed: the mean
    // torque balance I_eq a = T_s - k_r T_L - T_loss over the window gives
    // the loss torque. Shifting the rigid-mode speed to Omega (a shift along
    // a mass-orthogonal mode does not excite the elastic modes) scales the
    // mean input torque P <1/w> by mean(w)/Omega (the vibration's Jensen
    // excess <1/w> - 1/<w> stays), and the load torque that cancels the net
    // torque there follows in one step:
    //   T_L' = T_L + (T_s(Omega) - T_s(mean w) + I_eq a) / k_r,
    // T_s(Omega) - T_s(mean w) = T_s (mean(w)/Omega - 1) at constant power and 0 under torque
    // control (rig.input_control = torque: T_s = P / Omega_s at any speed). Applying the
    // constant-power term there over-corrected the load by T_s (mean(w)/Omega - 1) / k_r each
    // window and the warm-up diverged (the seed case with rig.input_control = "torque").
    const double input_torque_change = constant_power ? mean_Ts * (mean_ws / Omega - 1.0) : 0.0;
    if (!speed_held_by_rig) {
      sys.set_load_torque_Nm(sys.load_torque_Nm() + (input_torque_change + I_eq * mean_as) / k_r);
      r.st.v += (Omega - last_ws) * rig;
    }
    double dmax = 0, dchange = 0;
    for (int m = 0; m < nm; ++m) {
      const double d = sys.mesh_states()[m].deflection_m;
      dmax = std::max(dmax, std::fabs(d));
      dchange = std::max(dchange, std::fabs(d - prev[m]));
      prev[m] = d;
    }
    // Converged when the sun's own mean speed holds (the same as the rigid mode's without rig
    // shafts): with them, the gear train's slow modes on its shafts leave the rigid mode alone
    // and the mesh deflections nearly so, but not the sun's speed; the record waits for them.
    mean_sun_ws /= dn;
    const double speed_residual = std::fabs(mean_sun_ws / Omega - 1.0);
    w.residual = periodic_per_mesh ? std::max(dchange / std::max(dmax, 1e-30), speed_residual) : speed_residual;
    // Progress: how far the residual has fallen towards its tolerance on a
    // log scale (or the share of the fixed settle time), never backwards.
    const double frac = periodic_per_mesh
                            ? std::log(std::max(w.residual, 1e-300)) / std::log(c.solver.periodicity_tolerance)
                            : static_cast<double>(w.cycles) / settle_cycles;
    progress = std::clamp(frac, progress, 1.0);
    if (report) report(f0 + (f1 - f0) * progress, "warm-up");
    if (periodic_per_mesh && w.cycles >= 3 && w.residual < c.solver.periodicity_tolerance) break;
    if (!periodic_per_mesh && windows >= 2 && w.cycles >= settle_cycles &&
        speed_residual < c.solver.periodicity_tolerance)
      break;
  }
  return w;
}

/// The static start and the warm-up on `loop`. With a damaged tooth or a sun runout (tooth-level
/// features; a torque ripple alone is the exception below) the stage is first settled without them, to the periodicity of
/// every mesh period, and they are switched on after that for the windowed warm-up. Why: the
/// windowed warm-up corrects the load once per window of z mesh periods and stops on the mean
/// speed alone, so the torque steps of its first corrections set a lightly damped mode ringing
/// that it never sees. Measured on a calibrated rig model (indepsim3's setA4 at 500 rpm: a motor of
/// 2.5 kg m^2 behind an input shaft of 8268 N m/rad damped by 0.011 N m s/rad): a ring at 318.6
/// Hz of 0.107 rad/s in the sun speed, 2.7 times the mesh line, in a model whose only tooth-level
/// feature was a planet tooth of stiffness factor 1, i.e. none: its fit-half chi2 was 20.4 million
/// against 71 875 for the same model without it, and no tooth candidate could be fitted
/// (docs/diagnose-log.md, session 64). Settled without them first, a feature of size zero is the
/// stage without it, and a small one starts only its own small transient.
WarmupStats warm_up_from_static(Integration& r, const ProgressFn& report, double f1, SpeedLoop loop) {
  start_static(r);
  if (!has_tooth_level_features(r.c)) return warm_up(r, report, 0.0, f1, loop, true);
  // A torque ripple alone keeps the windowed warm-up from the static start (session 63's): settled
  // first, a ripple recording whose mesh is locked to time (stiffness.mesh_phase = nominal_time)
  // was no longer named (ctest diagnose.mesh_phase_of_a_torque_ripple; not understood yet,
  // docs/diagnose-log.md session 64).
  if (!settles_without_tooth_level_features(r.c)) return warm_up(r, report, 0.0, f1, loop, false);
  PlanetaryDynamics& sys = r.sys();
  const PlanetaryDynamics::AperiodicExcitation excitation = sys.aperiodic_excitation();
  ToothSurfaces featured = sys.surfaces();
  // Restored however the first phase ends (a solver error is retried by settle()).
  struct Restore {
    PlanetaryDynamics& sys;
    const PlanetaryDynamics::AperiodicExcitation& excitation;
    ToothSurfaces& featured;
    ~Restore() {
      sys.set_aperiodic_excitation(excitation);
      sys.surfaces() = featured;
    }
  };
  WarmupStats plain;
  {
    const Restore restore{sys, excitation, featured};
    sys.set_aperiodic_excitation({});
    sys.surfaces() = make_tooth_surfaces(r.c, r.p.geometry, ToothModifiers::Left_out);
    plain = warm_up(r, report, 0.0, 0.5 * f1, loop, true);
  }
  // The settled stage has had plain.cycles to shed the static start's transient: they count
  // towards the windowed warm-up's settling time and its limit (switching the features on starts
  // only a transient of their own size).
  return warm_up(r, report, 0.5 * f1, f1, loop, false, plain.cycles);
}

/// Static start and warm-up. The loop holds the sun's speed, as every result before session 20
/// did (bit-identical), unless a flexible rig shaft needs the rigid mode's own speed: a machine
/// on a soft shaft moves against the train at the shaft's slow mode, which the sun's window
/// mean carries (a 6 kg m^2 motor on a 2000 N m/rad shaft diverged, session 19). The sun's
/// speed also carries the elastic modes, and each load update, a torque step, excites them:
/// where their share of the window's mean sun acceleration outweighs the torque balance the
/// loop feeds them back and diverges (the seed stage at 1 kW: 100 000 rpm, windows of 36 us,
/// grew x1.2 every four windows until the roll reached 1e14 m; 50 000 rpm ended the warm-up
/// with a load torque of 2.6e11 N m). So when the sun-speed warm-up fails (a solver failure) or
/// ends at a load torque no steady state has (efficiency T_L Omega_c / P outside (0, 1]: the
/// stage cannot deliver more power than it takes), it is restarted from the static start on
/// the rigid mode's speed. Sets `loop` to the loop that was used.
WarmupStats settle(Integration& r, const ProgressFn& report, double f1, SpeedLoop& loop) {
  const SimulationConfig& c = r.c;
  PlanetaryDynamics& sys = r.sys();
  const bool shafts = c.rig.input_shaft_stiffness_N_m_rad > 0 || c.rig.output_shaft_stiffness_N_m_rad > 0;
  const double nominal_load = sys.load_torque_Nm();
  if (!shafts) {
    loop = SpeedLoop::SunSpeed;
    try {
      const WarmupStats w = warm_up_from_static(r, report, f1, loop);
      const double efficiency = sys.load_torque_Nm() * r.p.carrier_speed_rad_s / c.operating.input_power_W;
      if (!sys.structure().has_rigid_mode || (efficiency > 0 && efficiency <= 1)) return w;
      sys.set_load_torque_Nm(nominal_load);  // ended off any steady state: restart below
    } catch (const SolverError&) {
      sys.set_load_torque_Nm(nominal_load);  // diverged: restart below (a second failure is thrown)
    }
  }
  loop = SpeedLoop::RigidMode;
  return warm_up_from_static(r, report, f1, loop);
}

/// Per-planet means over every recorded step that the summary scalars need
/// whether or not the force channels are stored.
struct RecordStats {
  std::vector<double> mean_sun_planet_force_N;  ///< per planet [N]
  /// Mean angle and speed perturbations of the body held by the speed reference (the carrier
  /// under ideal speed control, the load machine under a speed loop) [rad], [rad/s].
  double mean_held_angle_rad = 0;
  double mean_held_speed_rad_s = 0;
  std::vector<Scalar> mesh_loads;      ///< MeshLoadRecorder's summary (mesh_loads.hpp)
};

/// A mesh's acceleration g . a, the same double as Eigen's g.dot(a). The three-planet torsional
/// stage's five coordinates take Eigen's fixed-size product: for five entries the dynamic-size
/// reduction and the fixed-size one sum in the same order, ((g0 a0 + g2 a2) + (g1 a1 + g3 a3)) +
/// g4 a4 (two packets of two, then the last entry), so the bits agree
/// (tests/model/test_mesh_acceleration.cpp). The dynamic product's size and alignment dispatch
/// were ~45 instructions per mesh and stored sample; the fixed one takes the record loop from 110 M
/// to 89 M instructions in bench_simulate 200 --record-cycles 20 (callgrind, session 69). Other
/// sizes keep the dynamic product, whose order the fixed-size one does not share in general.
double mesh_acceleration(const Eigen::VectorXd& g, const Eigen::VectorXd& a) {
  constexpr Eigen::Index kThreePlanetTorsionalDofs = 5;  // sun, carrier, three planets
  if (g.size() == kThreePlanetTorsionalDofs && a.size() == kThreePlanetTorsionalDofs) {
    using Vector5 = Eigen::Matrix<double, kThreePlanetTorsionalDofs, 1>;
    return Eigen::Map<const Vector5>(g.data()).dot(Eigen::Map<const Vector5>(a.data()));
  }
  return g.dot(a);
}

/// One output channel of the recording: its name, unit and description, and
/// where its samples go (null: not stored).
struct RecordChannel {
  std::string name, unit, description;
  double* samples = nullptr;
};

/// The per-mesh quantities of the recording, in their channel order.
enum class MeshQuantity : std::size_t { Deflection, Force, Acceleration, Stiffness, PairsInContact, Friction };
constexpr std::size_t kMeshQuantities = 6;

/// Where each channel of record_channels() sits: the mesh channels by mesh and
/// quantity, then the stage-level channels. The one place the order is spelled
/// out as numbers (record_channels() checks it builds the same count).
struct ChannelLayout {
  std::size_t meshes = 0, planets = 0;
  /// The ring body's accelerations are recorded (sensor.housing_path = ring_body, which needs the
  /// lateral-torsional model): two channels before the housing's. Other runs keep the channels
  /// and order they always had.
  bool ring_body = false;

  std::size_t mesh(dynamics::MeshId id, MeshQuantity q) const {
    return kMeshQuantities * static_cast<std::size_t>(id.index()) + static_cast<std::size_t>(q);
  }
  std::size_t mesh(int m, MeshQuantity q) const { return mesh(dynamics::MeshId::of(m), q); }
  std::size_t sun_speed() const { return kMeshQuantities * meshes; }
  std::size_t carrier_speed() const { return sun_speed() + 1; }
  std::size_t transmission_error() const { return sun_speed() + 2; }
  std::size_t input_torque() const { return sun_speed() + 3; }
  std::size_t load_sharing(int planet) const { return sun_speed() + 4 + static_cast<std::size_t>(planet); }
  std::size_t sun_angle() const { return sun_speed() + 4 + planets; }
  std::size_t carrier_angle() const { return sun_angle() + 1; }
  std::size_t ring_acceleration_x() const { return sun_angle() + 2; }
  std::size_t ring_acceleration_y() const { return sun_angle() + 3; }
  std::size_t housing() const { return sun_angle() + (ring_body ? 4 : 2); }
  std::size_t count() const { return housing() + 1; }
};

/// The channels of the recording in their documented order (docs/output-format.md),
/// the order ChannelLayout indexes.
std::vector<RecordChannel> record_channels(const dynamics::LumpedStructure& S, int planets, bool ring_body) {
  std::vector<RecordChannel> ch;
  auto add = [&](std::string name, std::string unit, std::string desc) {
    ch.push_back({std::move(name), std::move(unit), std::move(desc), nullptr});
  };
  for (const dynamics::MeshCoupling& mesh : S.meshes) {
    const std::string b = mesh.name + "/";
    add(b + "deflection", "m",
        "mesh deflection along the line of action incl. imposed errors (seed: penetration depth at the meshing "
        "line); positive compresses the drive flanks");
    add(b + "force", "N", "total dynamic normal mesh force (elastic + damping), summed over tooth pairs");
    add(b + "acceleration", "m/s^2", "relative acceleration of the two gears along the line of action");
    add(b + "stiffness", "N/m", "combined mesh stiffness of the pairs geometrically in mesh");
    add(b + "pairs_in_contact", "1", "number of tooth pairs in mesh (engagement weight >= 1/2)");
    add(b + "friction_force", "N", "sum of signed tooth friction forces (A's sliding direction on B)");
  }
  add("sun/speed", "rad/s", "absolute sun speed, as the encoder measures it (sensor.encoder_bandwidth_Hz)");
  add("carrier/speed", "rad/s", "absolute carrier speed, as the encoder measures it (sensor.encoder_bandwidth_Hz)");
  add("transmission_error", "m",
      "r_bs (theta_s - theta_c (Zs+Zr)/Zs), angular transmission error of the stage at the sun's base circle");
  add("sun/input_torque", "N m", "input torque on the sun");
  for (int i = 0; i < planets; ++i)
    add("load_sharing/" + std::to_string(i), "1", "N F_sp,i / sum_k F_sp,k: instantaneous load share of planet i");
  add("sun/angle", "rad", "absolute sun angle Omega_s t + perturbation (t = simulation time, 0 at the start)");
  add("carrier/angle", "rad",
      "absolute carrier angle Omega_c t + perturbation; planet i is at psi_i + carrier/angle in the housing frame");
  if (ring_body) {
    add("ring/acceleration_x", "m/s^2",
        "the ring body's translational acceleration along the fixed frame's x axis (the direction of planet 0 at "
        "carrier angle 0), lateral-torsional model; recorded for sensor.housing_path = ring_body");
    add("ring/acceleration_y", "m/s^2", "the same along the fixed frame's y axis (x turned 90 degrees counter-clockwise)");
  }
  add("housing/acceleration", "m/s^2",
      "housing accelerometer at sensor.angle_rad: planet-ring mesh force fluctuations through the transfer-path "
      "window, the ring's translation, or the ring body's acceleration times its mass (sensor.housing_path; "
      "model/sensor.hpp)");
  const ChannelLayout layout{S.meshes.size(), static_cast<std::size_t>(planets), ring_body};
  if (ch.size() != layout.count())  // a programming error: the two orders disagree
    throw std::logic_error(detail::concat("record_channels built ", ch.size(), " channels, ChannelLayout has ",
                                          layout.count()));
  return ch;
}

/// The sun's and the carrier's speed minus their nominal speeds [rad/s], what the encoders
/// filter (record()).
double sun_speed_change(Integration& r) { return r.sys().sun_rotation(r.st.v); }
double carrier_speed_change(Integration& r) { return r.sys().carrier_rotation(r.st.v); }

/// A speed channel's line-counting encoder (LineEncoder, SensorSettings::sun_encoder_lines and
/// carrier_encoder_lines) with the shaft it sits on; what it reports goes on to the bandwidth
/// low-pass as a change from the nominal speed, like the true speed's change.
struct LineCountedSpeed {
  LineEncoder encoder;
  double nominal_rad_s;
  bool sun;  ///< the sun shaft's encoder, else the carrier's

  double rotation(Integration& r, const Eigen::VectorXd& x) const {
    return sun ? r.sys().sun_rotation(x) : r.sys().carrier_rotation(x);
  }
  double angle_rad(Integration& r) const { return nominal_rad_s * r.st.t + rotation(r, r.st.q); }
  double change_rad_s(Integration& r) const { return rotation(r, r.st.v); }
  void start(Integration& r) {
    if (!encoder.passes()) encoder.start(r.st.t, angle_rad(r), nominal_rad_s + change_rad_s(r));
  }
  /// The speed change the encoder reports at the current step [rad/s] (the true change if ideal).
  double measured_change(Integration& r) {
    if (encoder.passes()) return change_rad_s(r);
    return encoder.step(r.st.t, angle_rad(r), nominal_rad_s + change_rad_s(r)) - nominal_rad_s;
  }
};

/// The speed encoders' pre-roll before the record (no-op for ideal encoders).
void settle_encoders(Integration& r, ButterworthFilter& sun_encoder, ButterworthFilter& carrier_encoder,
                     LineCountedSpeed& sun_lines, LineCountedSpeed& carrier_lines) {
  if (sun_encoder.passes()) return;
  const PreparedStage& p = r.p;
  const long spm = p.steps_per_mesh;
  // Whole mesh periods before the record, so that the filters' start transient has
  // decayed below 1e-12 of its size (and the record still starts on a mesh period).
  // A slow encoder would need more periods than the warm-up may take (1 mHz: 6300 s of
  // simulated time, half an hour of computing, seemingly hung): then the filters start the
  // record in the periodic steady state of the last pre-roll period's speeds
  // (ButterworthFilter::set_periodic_state). That is exact for a steady state that repeats every
  // mesh period, so one period of pre-roll suffices; with tooth-level features or a ripple
  // the pre-roll runs solver.warmup_max_mesh_cycles periods, and the part of the speed that
  // does not repeat per mesh period leaves a transient of at most exp(-sigma T_pre) of its
  // size.
  constexpr double kSettled = 1e-12;
  const double settle = sun_encoder.settling_time_s(kSettled);
  const double settle_periods = std::ceil(settle / (static_cast<double>(spm) * p.time_step_s));
  const long max_periods = r.c.solver.warmup_max_mesh_cycles;
  const bool periodic_start = settle_periods > static_cast<double>(max_periods);
  const long pre_periods = !periodic_start             ? static_cast<long>(settle_periods)
                           : has_tooth_level_features(r.c) ? max_periods
                                                           : 1;
  const long pre = spm * pre_periods;
  std::vector<double> last_sun, last_carrier;
  if (periodic_start) {
    last_sun.resize(static_cast<std::size_t>(spm));
    last_carrier.resize(static_cast<std::size_t>(spm));
  }
  for (long k = 0; k < pre; ++k) {
    r.step();
    const double ws = sun_lines.measured_change(r), wc = carrier_lines.measured_change(r);
    if (periodic_start) {
      if (const long j = k - (pre - spm); j >= 0) {
        last_sun[static_cast<std::size_t>(j)] = ws;
        last_carrier[static_cast<std::size_t>(j)] = wc;
      }
    } else {
      sun_encoder.step(ws);
      carrier_encoder.step(wc);
    }
  }
  if (periodic_start) {
    sun_encoder.set_periodic_state(last_sun);
    carrier_encoder.set_periodic_state(last_carrier);
  }
}

/// The housing accelerometer's channel of a record (model/sensor.hpp) from its stored inputs: each
/// planet's ring-mesh force (planet_pass subtracts its mean over the record), the carrier angle,
/// and for ring_body the ring's accelerations and mass.
std::vector<double> housing_channel(Integration& r, const SimulationResult& out, const ChannelLayout& at,
                                    const std::vector<std::size_t>& stored_index, double ring_mass_kg) {
  const auto stored = [&](std::size_t k) -> const std::vector<double>& { return out.channels[stored_index[k]].values; };
  std::vector<std::span<const double>> ring_force;
  for (int i = 0; i < r.c.stage.planet_count; ++i)
    ring_force.emplace_back(stored(at.mesh(dynamics::MeshId{i, dynamics::MeshKind::PlanetRing}, MeshQuantity::Force)));
  RingBodyAcceleration ring;
  if (at.ring_body) ring = {ring_mass_kg, stored(at.ring_acceleration_x()), stored(at.ring_acceleration_y())};
  return housing_acceleration_history(r.c.sensor, r.p.geometry.planet_angles_rad,
                                      r.p.geometry.planet_ring.working_pressure_angle_rad, stored(at.carrier_angle()),
                                      ring_force, out.time_step_s, ring);
}

/// Recording of `cycles` mesh periods into the selected channels of `out`.
RecordStats record(Integration& r, int cycles, SimulationResult& out, const OutputSelection& sel, const ProgressFn& report,
                   double f0, double f1) {
  PreparedStage& p = r.p;
  PlanetaryDynamics& sys = r.sys();
  const auto& S = sys.structure();
  const int nm = static_cast<int>(S.meshes.size());
  const int N = r.c.stage.planet_count;
  const int spm = p.steps_per_mesh;
  const std::int64_t nrec = static_cast<std::int64_t>(cycles) * spm;  // 1e6 cycles x spm overflows int
  const std::int64_t dec = std::max(1, sel.decimation);
  const std::int64_t nstore = (nrec + dec - 1) / dec;  // steps k = 0, dec, 2 dec, ... < nrec
  out.time_step_s = p.time_step_s * static_cast<double>(dec);
  const double mount_Hz = r.c.sensor.housing_mount_frequency_Hz;
  require(!(mount_Hz * out.time_step_s >= 0.5), "sensor.housing_mount_frequency_Hz", mount_Hz,
          " Hz must lie below the Nyquist frequency ", 0.5 / out.time_step_s,
          " Hz of the stored samples (time step x output.time_history_decimation)");
  resize_prefaulted(out.time_s, static_cast<std::size_t>(nstore));

  const bool ring_body = r.c.sensor.housing_path == HousingPath::RingBody;
  std::vector<RecordChannel> ch = record_channels(S, N, ring_body);
  const ChannelLayout at{S.meshes.size(), static_cast<std::size_t>(N), ring_body};
  const std::size_t g_housing = at.housing();
  auto ring_force_channel = [&](int i) {
    return at.mesh(dynamics::MeshId{i, dynamics::MeshKind::PlanetRing}, MeshQuantity::Force);
  };
  // The housing sensor is computed from the ring-mesh forces and the carrier
  // angle (and for ring_body the ring's accelerations) after the run: store
  // those too while it is wanted, drop them after.
  std::vector<bool> wanted(ch.size()), needed(ch.size());
  for (std::size_t k = 0; k < ch.size(); ++k) wanted[k] = needed[k] = sel.selects(ch[k].name);
  if (wanted[g_housing]) {
    needed[at.carrier_angle()] = true;
    for (int i = 0; i < N; ++i) needed[ring_force_channel(i)] = true;
    if (ring_body) needed[at.ring_acceleration_x()] = needed[at.ring_acceleration_y()] = true;
  }
  std::vector<std::size_t> stored_index(ch.size(), 0);
  for (std::size_t k = 0; k < ch.size(); ++k) {
    if (!needed[k] || k == g_housing) continue;
    stored_index[k] = out.channels.size();
    out.channels.push_back({ch[k].name, ch[k].unit, ch[k].description, {}});
    resize_prefaulted(out.channels.back().values, static_cast<std::size_t>(nstore));
  }
  for (std::size_t k = 0; k < ch.size(); ++k)
    if (needed[k] && k != g_housing) ch[k].samples = out.channels[stored_index[k]].values.data();

  auto put = [&](std::size_t k, std::int64_t j, double v) {
    if (ch[k].samples) ch[k].samples[j] = v;
  };
  const double ratio = (r.c.stage.sun.teeth + r.c.stage.ring.teeth) / static_cast<double>(r.c.stage.sun.teeth);
  const double rbs = p.geometry.sun.base_radius_m;
  RecordStats stats;
  // Speed encoders with a finite bandwidth: the filters see every step, stored or not.
  const SensorSettings& sn = r.c.sensor;
  ButterworthFilter sun_encoder(sn.encoder_bandwidth_Hz, sn.encoder_filter_order, p.time_step_s);
  ButterworthFilter carrier_encoder(sn.encoder_bandwidth_Hz, sn.encoder_filter_order, p.time_step_s);
  // The encoders filter the speeds' deviations from nominal and add the nominal speed back
  // (the filter is linear, so the output is the same): a filter far below the sampling rate
  // (K = tan(pi f_c dt) ~ 1e-5 for 1 Hz) has a DC gain 1 only to ~1e-16 / K^2 in its
  // direct-form coefficients, 1e-6 at 1 Hz, which on the absolute speed shifted the encoder
  // channel by 4e-6 rad/s at 100 rpm, 1.6 % of its filtered mesh ripple.
  sun_encoder.reset(sun_speed_change(r));
  carrier_encoder.reset(carrier_speed_change(r));
  LineCountedSpeed sun_lines{LineEncoder(sn.sun_encoder_lines, sn.sun_encoder_phase_rad), p.sun_speed_rad_s, true};
  LineCountedSpeed carrier_lines{LineEncoder(sn.carrier_encoder_lines, sn.carrier_encoder_phase_rad),
                                 p.carrier_speed_rad_s, false};
  sun_lines.start(r);
  carrier_lines.start(r);
  settle_encoders(r, sun_encoder, carrier_encoder, sun_lines, carrier_lines);
  const double t0 = r.st.t;
  const RingBodyReader ring(S);
  MeshLoadRecorder loads(p.geometry, r.c.stage, sys.nominal_input_torque_Nm());
  // The body the speed reference holds (the motor's end or the load's), for the mean torque of
  // its spring; only the speed-controlled rigs need it.
  const bool held_by_rig = !sys.structure().has_rigid_mode;
  const Eigen::RowVectorXd& held = sys.structure().speed_reference_at_input ? sys.input_theta_row()
                                                                             : sys.output_theta_row();
  for (std::int64_t k = 0; k < nrec; ++k) {
    r.step();
    const double w_sun = p.sun_speed_rad_s + sun_encoder.step(sun_lines.measured_change(r));
    const double w_carrier = p.carrier_speed_rad_s + carrier_encoder.step(carrier_lines.measured_change(r));
    const auto& ms = sys.mesh_states();
    if (sel.mesh_load_summary) loads.add(ms);
    if (held_by_rig) {
      stats.mean_held_angle_rad += held.dot(r.st.q) / static_cast<double>(nrec);
      stats.mean_held_speed_rad_s += held.dot(r.st.v) / static_cast<double>(nrec);
    }
    if (report && k % spm == 0) report(f0 + (f1 - f0) * static_cast<double>(k) / static_cast<double>(nrec), "recording");
    if (k % dec != 0) continue;
    const std::int64_t j = k / dec;
    out.time_s[j] = r.st.t - t0;
    double fsum = 0;
    for (int m = 0; m < nm; ++m) {
      put(at.mesh(m, MeshQuantity::Deflection), j, ms[m].deflection_m);
      put(at.mesh(m, MeshQuantity::Force), j, ms[m].force_N);
      const std::size_t acc = at.mesh(m, MeshQuantity::Acceleration);
      if (ch[acc].samples) put(acc, j, mesh_acceleration(S.meshes[m].g, r.st.a));
      put(at.mesh(m, MeshQuantity::Stiffness), j, ms[m].stiffness_N_m);
      put(at.mesh(m, MeshQuantity::PairsInContact), j, ms[m].pairs_engaged);
      put(at.mesh(m, MeshQuantity::Friction), j, ms[m].friction_N);
      if (dynamics::MeshId::of(m).sun_planet()) fsum += ms[m].force_N;
    }
    put(at.sun_speed(), j, w_sun);
    put(at.carrier_speed(), j, w_carrier);
    if (ch[at.transmission_error()].samples)
      put(at.transmission_error(), j,
          rbs * (sys.sun_rotation(r.st.q) - ratio * sys.carrier_rotation(r.st.q)));
    if (ch[at.input_torque()].samples) put(at.input_torque(), j, sys.input_torque_Nm(r.st.t, r.st.q, r.st.v));
    for (int i = 0; i < N; ++i) {
      const double F_sp = ms[static_cast<std::size_t>(dynamics::MeshId{i, dynamics::MeshKind::SunPlanet}.index())].force_N;
      put(at.load_sharing(i), j, fsum != 0 ? N * F_sp / fsum : 0.0);
    }
    put(at.sun_angle(), j, p.sun_speed_rad_s * r.st.t + sys.sun_rotation(r.st.q));
    const double carrier_angle = p.carrier_speed_rad_s * r.st.t + sys.carrier_rotation(r.st.q);
    put(at.carrier_angle(), j, carrier_angle);
    if (ring_body) {
      const Eigen::Vector2d a_ring = ring.fixed_frame(r.st.a, carrier_angle);
      put(at.ring_acceleration_x(), j, a_ring.x());
      put(at.ring_acceleration_y(), j, a_ring.y());
    }
  }
  if (wanted[g_housing]) {
    std::vector<double> h = housing_channel(r, out, at, stored_index, ring.mass_kg());
    // Last, as in the documented order (record_channels).
    out.channels.push_back({ch[g_housing].name, ch[g_housing].unit, ch[g_housing].description, std::move(h)});
  }
  std::erase_if(out.channels, [&](const Channel& c) { return !sel.selects(c.name); });
  out.scalars.push_back({"record_start_time", "s",
                         "simulation time at which the recording starts: time_history/time + record_start_time is "
                         "the time of the absolute angles (sun/angle, carrier/angle)",
                         t0});
  // The diagnosis computes the ring_body housing channel again at other sensor angles from the
  // ring's accelerations and needs the mass (model/sensor.hpp, Eq. S3); only then, so that the
  // other paths' outputs stay as they were.
  if (ring_body)
    out.scalars.push_back({"ring/mass", "kg", "the ring body's mass in the lateral-torsional model (Eq. S3's m_r)",
                           ring.mass_kg()});
  if (sel.mesh_load_summary) {
    stats.mesh_loads = loads.scalars();
    for (int i = 0; i < N; ++i)
      stats.mean_sun_planet_force_N.push_back(loads.mean_force_N(dynamics::MeshId{i, dynamics::MeshKind::SunPlanet}.index()));
  }
  return stats;
}

} // namespace

namespace {

/// Every selected name must select some channel: a typo would otherwise
/// silently store nothing.
void check_selection(const OutputSelection& sel, const std::vector<RecordChannel>& channels) {
  for (const std::string& name : sel.channels) {
    const OutputSelection one{{name}, 1};
    bool found = false;
    for (const RecordChannel& c : channels) found = found || one.selects(c.name);
    if (found) continue;
    std::string list;
    for (const RecordChannel& c : channels) list += (list.empty() ? "" : ", ") + c.name;
    throw InputError("output.channels", "no time-history channel '" + name + "'; channels are: " + list);
  }
}

std::size_t selected_channels(const OutputSelection& sel, const std::vector<RecordChannel>& channels) {
  return static_cast<std::size_t>(
      std::count_if(channels.begin(), channels.end(), [&](const RecordChannel& c) { return sel.selects(c.name); }));
}

} // namespace

bool OutputSelection::selects(const std::string& channel) const {
  if (channels.empty()) return true;
  for (const std::string& c : channels)
    if (c == channel || (c.ends_with('/') && channel.starts_with(c))) return true;
  return false;
}

SimulationResult simulate(const SimulationConfig& c, const ProgressFn& progress, const OutputSelection& output,
                          const WearPhase& wear) {
  if (c.wear.mesh_cycles > 0 && !wear)
    throw std::logic_error("model::simulate: wear.mesh_cycles > 0 needs the wear loop; call wear::simulate()");
  require(output.decimation >= 1, "output.time_history_decimation", "must be >= 1 (every k-th step), got ",
          output.decimation);
  PreparedStage p = prepare(c);
  PlanetaryDynamics& sys = *p.dynamics;
  const auto& S = sys.structure();
  const int nm = static_cast<int>(S.meshes.size());
  const int N = c.stage.planet_count;
  const bool ring_body = c.sensor.housing_path == HousingPath::RingBody;
  check_selection(output, record_channels(S, N, ring_body));
  // Refuse what cannot be stored before the (possibly long) warm-up.
  check_run_memory(c, p.steps_per_mesh, output.decimation,
                   selected_channels(output, record_channels(S, N, ring_body)));
  const bool wear_on = c.wear.mesh_cycles > 0;
  const double f_warm = wear_on ? 0.05 : 0.3, f_wear = wear_on ? 0.9 : f_warm;

  Integration run(p, c);
  SpeedLoop loop = SpeedLoop::SunSpeed;
  const WarmupStats warm = settle(run, progress, f_warm, loop);
  SimulationResult r;
  if (wear_on) wear(run, r, progress, f_warm, f_wear);
  const RecordStats rec = record(run, c.solver.record_mesh_cycles, r, output, progress, f_wear, 1.0);
  if (progress) progress(1.0, "done");

  const double dt = p.time_step_s;
  const int spm = p.steps_per_mesh;
  auto scalar = [&](std::string name, std::string unit, std::string desc, double v) {
    r.scalars.push_back({std::move(name), std::move(unit), std::move(desc), v});
  };
  scalar("time_step", "s", "Newmark time step", dt);
  scalar("steps_per_mesh_period", "1", "time steps per mesh period", spm);
  scalar("mesh_frequency", "Hz", "mesh frequency Zs (f_s - f_c) at the nominal speed", p.mesh_frequency_Hz);
  scalar("sun_speed", "rad/s", "nominal absolute sun speed", p.sun_speed_rad_s);
  scalar("carrier_speed", "rad/s", "nominal carrier speed", p.carrier_speed_rad_s);
  // Under speed control the torque of the machine that holds the speed is its feed-forward plus
  // the mean torque of its spring to the speed reference: the ideal control's shaft twist, or
  // the loop's integral and proportional terms (they take up the friction losses). The load
  // machine's acts against the carrier's rotation, the motor's with the sun's.
  const int held = S.speed_reference_spring;
  const bool motor_holds = held >= 0 && S.speed_reference_at_input;
  // A machine's feed-forward plus `sign` times its spring's mean torque k mean(theta) + c mean(w).
  const auto with_reference = [&](double feed_forward, double sign) {
    const dynamics::Spring& sp = S.springs[static_cast<std::size_t>(held)];
    return feed_forward + sign * sp.stiffness * rec.mean_held_angle_rad + sign * sp.damping * rec.mean_held_speed_rad_s;
  };
  const double input_torque = motor_holds ? with_reference(sys.nominal_input_torque_Nm(), -1.0) : sys.nominal_input_torque_Nm();
  const double load_torque = held >= 0 && !motor_holds ? with_reference(sys.load_torque_Nm(), 1.0) : sys.load_torque_Nm();
  scalar("input_torque", "N m",
         motor_holds ? "mean input torque: P / Omega_s plus the speed control's mean torque" : "mean input torque P / Omega_s",
         input_torque);
  scalar("load_torque", "N m", "mean load torque on the carrier at the nominal speed", load_torque);
  // The input power is P unless the motor holds the speed (then T_s Omega_s, the losses included).
  const double input_power_W = motor_holds ? input_torque * p.sun_speed_rad_s : c.operating.input_power_W;
  scalar("efficiency", "1", "T_load Omega_c / P_in: mesh efficiency of the stage (friction losses)",
         load_torque * p.carrier_speed_rad_s / input_power_W);
  scalar("warmup_mesh_cycles", "1", "mesh periods integrated before recording", warm.cycles);
  scalar("warmup_speed_loop", "1",
         "speed the warm-up's loop held: 0 the sun's, 1 the rigid mode's (with flexible rig shafts, or after the "
         "sun's diverged or ended off any steady state; docs/derivation.md section 3.4)",
         loop == SpeedLoop::RigidMode ? 1.0 : 0.0);
  scalar("periodicity_residual", "1", "relative change of mesh deflections over the last warm-up mesh period",
         warm.residual);
  const dynamics::NewmarkStatistics& solver_stats = run.solver.statistics();
  scalar("time_steps", "1", "time steps integrated in total (warm-up, wear windows, recording)",
         static_cast<double>(solver_stats.steps));
  scalar("mean_force_evaluations", "1", "force (Newton residual) evaluations per time step, averaged",
         static_cast<double>(solver_stats.force_evaluations) / static_cast<double>(std::max(1L, solver_stats.steps)));
  for (int i = 0; i < p.natural_frequencies_Hz.size(); ++i)
    scalar("natural_frequency/" + std::to_string(i), "Hz", "natural frequency of the linearized time-averaged model",
           p.natural_frequencies_Hz(i));
  for (int m = 0; m < nm; ++m)
    scalar("mesh_damping/" + S.meshes[m].name, "N s/m", "viscous mesh damping coefficient", sys.mesh_damping_N_s_m(m));
  // Load-sharing factor per planet: N mean(F_sp,i) / sum_k mean(F_sp,k).
  const std::vector<double>& mean_f = rec.mean_sun_planet_force_N;
  double tot = 0;
  for (double x : mean_f) tot += x;
  for (int i = 0; i < N && !mean_f.empty(); ++i)  // empty: OutputSelection::mesh_load_summary off
    scalar("load_sharing_factor/" + std::to_string(i), "1", "N mean(F_sp,i) / sum_k mean(F_sp,k)",
           tot != 0 ? N * mean_f[i] / tot : 0.0);
  for (const Scalar& sc : rec.mesh_loads) r.scalars.push_back(sc);
  if (wear_on) {
    for (const auto& fh : r.wear.flanks) {
      const std::size_t per = static_cast<std::size_t>(fh.teeth) * fh.elements;
      double mx = 0;
      for (std::size_t k = fh.depth_m.size() - per; k < fh.depth_m.size(); ++k) mx = std::max(mx, fh.depth_m[k]);
      scalar("max_wear/" + fh.name, "m", "maximum wear depth of this flank family at the end", mx);
    }
    scalar("wear_updates", "1", "number of wear updates", static_cast<double>(r.wear.mesh_cycles.size() - 1));
    scalar("worn_mesh_cycles", "1", "mesh cycles worn through", r.wear.mesh_cycles.back());
  }
  for (auto& s : stiffness_scalars(p)) r.scalars.push_back(std::move(s));
  r.curves = stiffness_curves(p);
  return r;
}

} // namespace pw::model
