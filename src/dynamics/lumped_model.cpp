#include "dynamics/lumped_model.hpp"

#include "core/error.hpp"

#include <cmath>
#include <string>

namespace pw::dynamics {
namespace {

Eigen::Vector2d rot90(const Eigen::Vector2d& v) { return {-v.y(), v.x()}; }  // z x v

Eigen::RowVectorXd theta_row(const Body& b) { return b.map.row(2); }

/// Mesh geometry in the carrier frame (docs/derivation.md §3.2). Sun-planet:
/// the sun pushes the planet along n = sin(a) e_r + cos(a) e_t (outwards and
/// forwards); T_A = r_bs (cos(a) e_r - sin(a) e_t). Planet-ring: the planet
/// pushes the ring along n = sin(a) e_r - cos(a) e_t; T_A = O_p + r_bp z x n.
void place_sun_planet(MeshCoupling& m, double psi, double alpha, double r_bs) {
  const Eigen::Vector2d er{std::cos(psi), std::sin(psi)}, et = rot90(er);
  m.normal = std::sin(alpha) * er + std::cos(alpha) * et;
  m.tangent_point_a = r_bs * (std::cos(alpha) * er - std::sin(alpha) * et);
}

void place_planet_ring(MeshCoupling& m, double psi, double alpha, double a, double r_bp) {
  const Eigen::Vector2d er{std::cos(psi), std::sin(psi)}, et = rot90(er);
  m.normal = std::sin(alpha) * er - std::cos(alpha) * et;
  m.tangent_point_a = a * er + r_bp * rot90(m.normal);
}

Body make_body(std::string name, int n, double mass, double inertia, Eigen::Vector2d centre) {
  Body b;
  b.name = std::move(name);
  b.mass_kg = mass;
  b.inertia_kgm2 = inertia;
  b.centre_m = centre;
  b.map = Eigen::MatrixXd::Zero(3, n);
  return b;
}

void check_layout(const StageLayout& l) {
  require(l.sun_base_radius_m > 0 && l.planet_base_radius_m > 0 && l.ring_base_radius_m > 0, "stage",
          "base radii must be positive");
  require(l.carrier_radius_m > 0, "stage", "carrier radius must be positive");
  require(!l.planet_angles_rad.empty(), "stage.planet_count", "at least one planet is needed");
  require(l.sun_inertia_kgm2 > 0 && l.planet_inertia_kgm2 > 0 && l.carrier_inertia_kgm2 > 0, "stage",
          "sun, planet and carrier inertias must be positive [kg m^2]");
}

/// Viscous damper of a support of stiffness k [N/m or N m/rad] holding a body of mass (or
/// inertia) m at damping ratio zeta: c = 2 zeta sqrt(k m), the single-degree-of-freedom
/// oscillator's; 0 when zeta is 0, so that undamped supports stay exactly undamped.
double damper_for_ratio(double zeta, double k, double m) { return zeta > 0 ? 2 * zeta * std::sqrt(k * m) : 0.0; }

/// The rig's machines and shafts (RigLayout): bodies on their own rotation
/// coordinates from `first_dof` on, and the shaft springs with their dampers.
void add_rig(LumpedStructure& s, const RigLayout& rig, int first_dof) {
  int dof = first_dof;
  auto machine = [&](const std::string& name, double inertia) {
    Body b = make_body(name, s.dofs, 0.0, inertia, {0, 0});
    b.map(2, dof) = 1;
    s.dof_names.push_back("theta_" + name);
    ++dof;
    s.bodies.push_back(std::move(b));
    return static_cast<int>(s.bodies.size()) - 1;
  };
  auto spring = [&](const std::string& name, int a, int b, double k, double c) {
    Spring sp;
    sp.name = name;
    sp.body_a = a;
    sp.body_b = b;
    sp.torsional = true;
    sp.stiffness = k;
    sp.damping = c;
    s.springs.push_back(sp);
  };
  // Ties body `b` to the speed reference (a spring to ground in the perturbation coordinates).
  auto hold = [&](const std::string& name, int b, double k, double c, bool at_input) {
    spring(name, b, -1, k, c);
    s.speed_reference_spring = static_cast<int>(s.springs.size()) - 1;
    s.speed_reference_at_input = at_input;
    s.has_rigid_mode = false;
  };
  // One end: its machine (behind the shaft, or the stage body itself when the shaft is rigid),
  // the shaft, and the speed control; returns the body its torque acts on. Under ideal speed
  // control the shaft's far end turns at the nominal speed and the feed-forward torque stays
  // on the stage body.
  auto attach = [&](const RigEnd& e, const std::string& end, const std::string& machine_name, int stage_body,
                    bool at_input) {
    int body = stage_body;
    if (e.shaft_N_m_rad > 0) {
      if (e.control == MachineControl::IdealSpeed) {
        hold(end + "_shaft", stage_body, e.shaft_N_m_rad, e.shaft_N_m_s_rad, at_input);
      } else {
        body = machine(machine_name, e.machine_inertia_kgm2);
        spring(end + "_shaft", body, stage_body, e.shaft_N_m_rad, e.shaft_N_m_s_rad);
      }
    }
    if (e.control == MachineControl::SpeedLoop)
      hold(end + "_speed_loop", body, e.loop_integral_N_m_rad, e.loop_proportional_N_m_s_rad, at_input);
    return body;
  };
  s.input_body = attach(rig.input, "input", "motor", s.sun_body, true);
  s.output_body = attach(rig.output, "output", "load", s.carrier_body, false);
}

void check_rig_end(const RigEnd& e, const char* inertia_key, const char* shaft_key, const char* loop_key) {
  require(e.shaft_N_m_rad <= 0 || e.control == MachineControl::IdealSpeed || e.machine_inertia_kgm2 > 0, inertia_key,
          "a machine behind a flexible shaft needs a positive inertia [kg m^2]");
  require(e.control != MachineControl::IdealSpeed || e.shaft_N_m_rad > 0, shaft_key,
          "ideal speed control needs a flexible shaft");
  require(e.control != MachineControl::SpeedLoop || (e.loop_integral_N_m_rad > 0 && e.loop_proportional_N_m_s_rad > 0),
          loop_key, "a speed loop needs positive integral and proportional gains");
}

void check_rig(const RigLayout& rig) {
  check_rig_end(rig.input, "stage.input_inertia_kgm2", "rig.input_shaft_stiffness_N_m_rad",
                "rig.input_speed_loop_integral_N_m_rad");
  check_rig_end(rig.output, "stage.output_inertia_kgm2", "rig.output_shaft_stiffness_N_m_rad",
                "rig.load_speed_loop_integral_N_m_rad");
  require(!(rig.input.holds_speed() && rig.output.holds_speed()), "rig.load_control",
          "one machine holds the speed: the load must be torque-controlled when the motor holds the speed");
}

/// Adds the 2N meshes (sun-planet i at 2i, planet-ring i at 2i+1) with their
/// roll vectors and nominal motion; geometry vectors come from assemble().
void add_meshes(LumpedStructure& s, const StageLayout& l, int carrier_theta_dof) {
  for (std::size_t i = 0; i < l.planet_angles_rad.size(); ++i) {
    const double psi = l.planet_angles_rad[i];
    const int p = s.planet_bodies[i];
    MeshCoupling sp;
    sp.name = "sun_planet/" + std::to_string(i);
    sp.body_a = s.sun_body;
    sp.body_b = p;
    place_sun_planet(sp, psi, l.sun_planet_pressure_angle_rad, l.sun_base_radius_m);
    MeshCoupling pr;
    pr.name = "planet_ring/" + std::to_string(i);
    pr.body_a = p;
    pr.body_b = s.ring_body;
    place_planet_ring(pr, psi, l.planet_ring_pressure_angle_rad, l.carrier_radius_m, l.planet_base_radius_m);
    // Roll distances (mesh.hpp): sun-planet s = r_bs (theta_s - theta_c);
    // planet-ring s = r_br (theta_c - theta_r): the mesh advances as the ring
    // turns backwards relative to the carrier.
    const Eigen::RowVectorXd th_c = carrier_theta_dof >= 0 ? theta_row(s.bodies[s.carrier_body])
                                                           : Eigen::RowVectorXd::Zero(s.dofs);
    sp.roll = (l.sun_base_radius_m * (theta_row(s.bodies[s.sun_body]) - th_c)).transpose();
    pr.roll = (l.ring_base_radius_m * (th_c - theta_row(s.bodies[s.ring_body]))).transpose();
    sp.nominal_roll_rate_m_s = l.sun_base_radius_m * l.sun_speed_rel_rad_s;
    pr.nominal_roll_rate_m_s = -l.ring_base_radius_m * l.ring_speed_rel_rad_s;
    s.meshes.push_back(std::move(sp));
    s.meshes.push_back(std::move(pr));
  }
}

/// Nominal motion in the carrier frame: body centres at rest, sun and ring
/// turning at their relative speeds, each planet at the speed that makes its
/// sun mesh roll without deflection. The sliding speed of a mesh is then
/// t . (w_A z x (C - O_A) - w_B z x (C - O_B)), linear in xi.
void set_nominal_motion(LumpedStructure& s, const StageLayout& l) {
  std::vector<double> w(s.bodies.size(), 0.0);
  w[s.sun_body] = l.sun_speed_rel_rad_s;
  w[s.ring_body] = l.ring_speed_rel_rad_s;
  auto arm = [&](const MeshCoupling& m, int body) {
    return m.normal.dot(rot90(m.tangent_point_a - s.bodies[body].centre_m));
  };
  for (std::size_t i = 0; i < s.planet_bodies.size(); ++i) {
    const MeshCoupling& sp = s.meshes[static_cast<std::size_t>(MeshId{static_cast<int>(i), MeshKind::SunPlanet}.index())];
    w[s.planet_bodies[i]] = w[sp.body_a] * arm(sp, sp.body_a) / arm(sp, sp.body_b);
  }
  for (MeshCoupling& m : s.meshes) {
    m.nominal_speed_a_rad_s = w[m.body_a];
    m.nominal_speed_b_rad_s = w[m.body_b];
    const Eigen::Vector2d t = rot90(m.normal);
    auto slide = [&](double xi) {
      const Eigen::Vector2d c = m.tangent_point_a + xi * m.normal;
      return t.dot(w[m.body_a] * rot90(c - s.bodies[m.body_a].centre_m) -
                   w[m.body_b] * rot90(c - s.bodies[m.body_b].centre_m));
    };
    m.nominal_slide0_m_s = slide(0.0);
    m.nominal_slide1_1_s = slide(1.0) - m.nominal_slide0_m_s;
  }
}

} // namespace

Eigen::MatrixXd point_map(const Body& b, const Eigen::Vector2d& p) {
  // v(p) = v_centre + omega z x (p - c)
  const Eigen::Vector2d arm = rot90(p - b.centre_m);
  Eigen::MatrixXd P(2, b.map.cols());
  P.row(0) = b.map.row(0) + arm.x() * b.map.row(2);
  P.row(1) = b.map.row(1) + arm.y() * b.map.row(2);
  return P;
}

SparseCoupling sparse_coupling(const MeshCoupling& m) {
  SparseCoupling c;
  const auto n = m.g.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    const bool used = m.g(i) != 0 || m.h0(i) != 0 || m.h1(i) != 0 || (m.roll.size() == n && m.roll(i) != 0);
    if (!used) continue;
    if (c.entries == SparseCoupling::kMaxEntries)
      throw SolverError(detail::concat("mesh ", m.name, " couples more than ", SparseCoupling::kMaxEntries,
                                       " coordinates (SparseCoupling::kMaxEntries)"));
    const int k = c.entries++;
    c.dof[k] = static_cast<int>(i);
    c.g[k] = m.g(i);
    c.h0[k] = m.h0(i);
    c.h1[k] = m.h1(i);
    c.roll[k] = m.roll.size() == n ? m.roll(i) : 0.0;
  }
  return c;
}

void assemble(LumpedStructure& s) {
  const int n = s.dofs;
  s.mass = Eigen::MatrixXd::Zero(n, n);
  for (const Body& b : s.bodies) {
    const Eigen::Vector3d md{b.mass_kg, b.mass_kg, b.inertia_kgm2};
    s.mass.noalias() += b.map.transpose() * md.asDiagonal() * b.map;
  }
  s.support_stiffness = Eigen::MatrixXd::Zero(n, n);
  s.support_damping = Eigen::MatrixXd::Zero(n, n);
  for (const Spring& sp : s.springs) {
    Eigen::RowVectorXd d;
    if (sp.torsional) {
      d = theta_row(s.bodies[sp.body_a]);
      if (sp.body_b >= 0) d -= theta_row(s.bodies[sp.body_b]);
    } else {
      d = sp.direction.transpose() * point_map(s.bodies[sp.body_a], sp.point_m);
      if (sp.body_b >= 0) d -= sp.direction.transpose() * point_map(s.bodies[sp.body_b], sp.point_m);
    }
    s.support_stiffness.noalias() += sp.stiffness * d.transpose() * d;
    if (sp.damping != 0) s.support_damping.noalias() += sp.damping * d.transpose() * d;
  }
  for (MeshCoupling& m : s.meshes) {
    const Body& A = s.bodies[m.body_a];
    const Body& B = s.bodies[m.body_b];
    const Eigen::Vector2d t = rot90(m.normal);
    auto rel = [&](double xi) {
      const Eigen::Vector2d c = m.tangent_point_a + xi * m.normal;
      return Eigen::MatrixXd(point_map(A, c) - point_map(B, c));
    };
    const Eigen::MatrixXd r0 = rel(0.0), r1 = rel(1.0);
    m.g = (m.normal.transpose() * r0).transpose();
    m.h0 = (t.transpose() * r0).transpose();
    m.h1 = (t.transpose() * r1).transpose() - m.h0;
  }
}

int rig_dofs(const RigLayout& rig) {
  int n = 0;
  for (const RigEnd* e : {&rig.input, &rig.output})
    n += e->shaft_N_m_rad > 0 && e->control != MachineControl::IdealSpeed ? 1 : 0;
  return n;
}

LumpedStructure build_torsional(const StageLayout& l, const RigLayout& rig) {
  check_layout(l);
  check_rig(rig);
  const int N = static_cast<int>(l.planet_angles_rad.size());
  LumpedStructure s;
  s.dofs = 2 + N + rig_dofs(rig);
  s.dof_names = {"theta_sun", "theta_carrier"};
  for (int i = 0; i < N; ++i) s.dof_names.push_back("theta_planet_" + std::to_string(i));
  const int n = s.dofs;
  s.bodies.push_back(make_body("sun", n, l.sun_mass_kg, l.sun_inertia_kgm2, {0, 0}));
  s.bodies[0].map(2, 0) = 1;
  s.bodies.push_back(make_body("carrier", n, l.carrier_mass_kg, l.carrier_inertia_kgm2, {0, 0}));
  s.bodies[1].map(2, 1) = 1;
  s.bodies.push_back(make_body("ring", n, l.ring_mass_kg, l.ring_inertia_kgm2, {0, 0}));  // fixed: zero map
  s.sun_body = 0;
  s.carrier_body = 1;
  s.ring_body = 2;
  for (int i = 0; i < N; ++i) {
    const double psi = l.planet_angles_rad[i];
    const Eigen::Vector2d O = l.carrier_radius_m * Eigen::Vector2d{std::cos(psi), std::sin(psi)};
    Body p = make_body("planet_" + std::to_string(i), n, l.planet_mass_kg, l.planet_inertia_kgm2, O);
    // Rigid pin: the planet centre moves with the carrier rotation, z x O.
    p.map(0, 1) = -O.y();
    p.map(1, 1) = O.x();
    p.map(2, 2 + i) = 1;
    s.planet_bodies.push_back(static_cast<int>(s.bodies.size()));
    s.bodies.push_back(std::move(p));
  }
  add_rig(s, rig, 2 + N);
  add_meshes(s, l, 1);
  assemble(s);
  set_nominal_motion(s, l);
  return s;
}

LumpedStructure build_lateral_torsional(const StageLayout& l, const Bearings& k, const RigLayout& rig) {
  check_layout(l);
  check_rig(rig);
  require(l.ring_inertia_kgm2 > 0 && l.ring_mass_kg > 0 && l.carrier_mass_kg > 0 && l.sun_mass_kg > 0 &&
              l.planet_mass_kg > 0,
          "stage", "the lateral-torsional model needs positive masses and inertias of all bodies");
  const int N = static_cast<int>(l.planet_angles_rad.size());
  LumpedStructure s;
  s.dofs = 9 + 3 * N + rig_dofs(rig);
  const int n = s.dofs;
  for (const char* b : {"sun", "ring", "carrier"})
    for (const char* c : {"x", "y", "theta"}) s.dof_names.push_back(std::string(c) + "_" + b);
  for (int i = 0; i < N; ++i)
    for (const char* c : {"zeta", "eta", "theta"}) s.dof_names.push_back(std::string(c) + "_planet_" + std::to_string(i));
  s.bodies.push_back(make_body("sun", n, l.sun_mass_kg, l.sun_inertia_kgm2, {0, 0}));
  s.bodies.push_back(make_body("ring", n, l.ring_mass_kg, l.ring_inertia_kgm2, {0, 0}));
  s.bodies.push_back(make_body("carrier", n, l.carrier_mass_kg, l.carrier_inertia_kgm2, {0, 0}));
  for (int b = 0; b < 3; ++b)
    for (int c = 0; c < 3; ++c) s.bodies[b].map(c, 3 * b + c) = 1;
  s.sun_body = 0;
  s.ring_body = 1;
  s.carrier_body = 2;
  for (int i = 0; i < N; ++i) {
    const double psi = l.planet_angles_rad[i];
    const Eigen::Vector2d er{std::cos(psi), std::sin(psi)}, et = rot90(er);
    Body p = make_body("planet_" + std::to_string(i), n, l.planet_mass_kg, l.planet_inertia_kgm2,
                       l.carrier_radius_m * er);
    const int q0 = 9 + 3 * i;
    // zeta radial, eta tangential, in the planet's carrier-fixed frame.
    p.map(0, q0) = er.x();
    p.map(1, q0) = er.y();
    p.map(0, q0 + 1) = et.x();
    p.map(1, q0 + 1) = et.y();
    p.map(2, q0 + 2) = 1;
    s.planet_bodies.push_back(static_cast<int>(s.bodies.size()));
    s.bodies.push_back(std::move(p));
    // Planet bearing: radial and tangential springs between planet centre and
    // the carrier's pin point (Lin & Parker's k_p).
    for (const Eigen::Vector2d& d : {er, et}) {
      Spring sp;
      sp.name = "planet_bearing_" + std::to_string(i);
      sp.body_a = s.planet_bodies.back();
      sp.body_b = s.carrier_body;
      sp.point_m = l.carrier_radius_m * er;
      sp.direction = d;
      sp.stiffness = k.planet_N_m;
      sp.damping = damper_for_ratio(k.damping_ratio, k.planet_N_m,
                                   l.planet_mass_kg * l.carrier_mass_kg / (l.planet_mass_kg + l.carrier_mass_kg));
      s.springs.push_back(sp);
    }
  }
  auto ground_xy = [&](int body, double kk, const char* nm) {
    for (const Eigen::Vector2d& d : {Eigen::Vector2d{1, 0}, Eigen::Vector2d{0, 1}}) {
      Spring sp;
      sp.name = nm;
      sp.body_a = body;
      sp.direction = d;
      sp.stiffness = kk;
      sp.damping = damper_for_ratio(k.damping_ratio, kk, s.bodies[static_cast<std::size_t>(body)].mass_kg);
      s.springs.push_back(sp);
    }
  };
  ground_xy(s.sun_body, k.sun_N_m, "sun_bearing");
  ground_xy(s.ring_body, k.ring_N_m, "ring_support");
  ground_xy(s.carrier_body, k.carrier_N_m, "carrier_bearing");
  // Torsional supports given, as in Lin & Parker, on u = r theta [N/m]:
  // k_theta = k_u r^2 [N m/rad].
  auto ground_theta = [&](int body, double ku, double r, const char* nm) {
    if (ku <= 0) return;
    Spring sp;
    sp.name = nm;
    sp.body_a = body;
    sp.torsional = true;
    sp.stiffness = ku * r * r;
    sp.damping = damper_for_ratio(k.damping_ratio, sp.stiffness, s.bodies[static_cast<std::size_t>(body)].inertia_kgm2);
    s.springs.push_back(sp);
  };
  ground_theta(s.sun_body, k.sun_torsional_N_m, l.sun_base_radius_m, "sun_torsional");
  ground_theta(s.ring_body, k.ring_torsional_N_m, l.ring_base_radius_m, "ring_torsional");
  ground_theta(s.carrier_body, k.carrier_torsional_N_m, l.carrier_radius_m, "carrier_torsional");
  add_rig(s, rig, 9 + 3 * N);
  add_meshes(s, l, 8);
  assemble(s);
  set_nominal_motion(s, l);
  return s;
}

} // namespace pw::dynamics
