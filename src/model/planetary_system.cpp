#include "model/planetary_system.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace pw::model {
namespace {

/// Largest share of a mesh's stiffness in contact that the harmonic correction may remove [-].
constexpr double kMaxStiffnessRemoved = 0.9;

/// tanh(x), the smoothed sign of the sliding speed, with its saturated tails
/// taken exactly: for |x| > 19.07 the double nearest tanh(x) is +-1 (checked
/// against glibc over [19, 23] in steps of 1e-7), so pairs that slide faster
/// than 19 v_eps skip the exp.
/// Inside, tanh x = (e^{2x} - 1) / (e^{2x} + 1) with one exp (glibc's tanh
/// goes through expm1, 3x the cost): the same function to an absolute error of
/// a few ulp of 1, i.e. a friction force changed by < 1e-15 of mu F_n.
double smooth_sign(double x) {
  constexpr double kSaturated = 19.1;
  if (std::fabs(x) > kSaturated) return std::copysign(1.0, x);
  const double e = std::exp(2 * x);
  return (e - 1) / (e + 1);
}

/// n mod z in [0, z) (geometry::pairs_in_contact's tooth numbering).
int wrap_tooth(long long n, int z) {
  const long long r = n % z;
  return static_cast<int>(r < 0 ? r + z : r);
}

/// std::ceil and std::floor, bit for bit, by truncation: x86-64 without SSE4.1 (the default build)
/// has no rounding instruction, and the library's ceil and floor were 2.5 % of a torsional run's
/// instructions; these save 0.8 % of them (callgrind, session 32). Truncation toward zero is exact for
/// |x| < 2^52 (every such double's integer part fits a long long); beyond, and for NaN and the
/// infinities, the library functions decide.
double ceil_exact(double x) {
  if (!(std::fabs(x) < 0x1p52)) return std::ceil(x);
  const double t = static_cast<double>(static_cast<long long>(x));
  return t < x ? t + 1.0 : t;
}
double floor_exact(double x) {
  if (!(std::fabs(x) < 0x1p52)) return std::floor(x);
  const double t = static_cast<double>(static_cast<long long>(x));
  return t > x ? t - 1.0 : t;
}

/// n_first <= n_last, false for NaN (a non-finite roll): no pairs then, as in pairs_in_contact.
bool n_first_le(double n_first, double n_last) { return n_first <= n_last; }

/// geometry::engagement_weight with the reciprocal of the ramp width 2h precomputed (a
/// multiplication instead of two divisions; round-off only): the share of the step a pair at xi
/// spends inside [start, end] when the window is widened by h on both sides
/// (docs/derivation.md §3.4). h = 0: sharp switching.
// Inlined by force: the per-mesh geometry split per entry count (update_mesh_geometry<NE>) left
// it out of line (1.5 % of a torsional step, perf, session 32).
[[gnu::always_inline]] inline double engagement_weight(const geometry::MeshGeometry& mesh, double xi_m,
                                                       double half_width_m, double inv_width_1_m) {
  if (!(half_width_m > 0)) return (xi_m >= mesh.start_active_m && xi_m <= mesh.end_active_m) ? 1.0 : 0.0;
  const double in = std::clamp((xi_m - (mesh.start_active_m - half_width_m)) * inv_width_1_m, 0.0, 1.0);
  const double out = std::clamp(((mesh.end_active_m + half_width_m) - xi_m) * inv_width_1_m, 0.0, 1.0);
  return std::min(in, out);
}

/// stiffness::PairStiffnessCurve::operator() (linear interpolation in the uniform table, 0
/// outside it) with its index scale (n - 1) / (xi_n - xi_0), its ends and its last interval fixed
/// at construction (MeshScales): the same arithmetic without the table's size and end look-ups.
[[gnu::always_inline]] inline double pair_stiffness(const std::vector<double>& k_N_m, double x0_m, double x1_m,
                                                    std::size_t last, double index_scale_1_m, double xi_m) {
  if (!(xi_m >= x0_m && xi_m <= x1_m)) return 0.0;  // also every xi for a table of < 2 points
  const double u = (xi_m - x0_m) * index_scale_1_m;
  std::size_t i = static_cast<std::size_t>(u);
  if (i > last) i = last;
  const double f = u - static_cast<double>(i);
  const double* k = k_N_m.data();
  return k[i] + f * (k[i + 1] - k[i]);
}

/// Indices of the non-zero entries of `row`, ascending.
std::vector<int> nonzeros(const Eigen::RowVectorXd& row) {
  std::vector<int> nz;
  for (Eigen::Index i = 0; i < row.size(); ++i)
    if (row(i) != 0) nz.push_back(static_cast<int>(i));
  return nz;
}

} // namespace

RotationRow::RotationRow(const Eigen::RowVectorXd& row) : row_(row) {
  const std::vector<int> nz = nonzeros(row);
  unit_ = nz.size() == 1 ? nz.front() : -1;
  if (unit_ >= 0) c_ = row(unit_);
}

bool PlanetaryDynamics::torsional_coordinates(const std::vector<MeshRecord>& meshes) {
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const dynamics::SparseCoupling& sc = meshes[m].sparse;
    const int planet = static_cast<int>(m / 2);
    const bool sun_planet = m % 2 == 0;
    const std::array<int, 3> expected = sun_planet ? std::array<int, 3>{0, 1, 2 + planet} : std::array<int, 3>{1, 2 + planet, -1};
    if (sc.entries != (sun_planet ? 3 : 2)) return false;
    for (int k = 0; k < sc.entries; ++k)
      if (sc.dof[k] != expected[k]) return false;
  }
  return true;
}

PlanetaryDynamics::PlanetaryDynamics(const SimulationConfig& cfg, dynamics::LumpedStructure structure,
                                     MeshFamily sun_planet, MeshFamily planet_ring,
                                     std::vector<geometry::PlanetPhases> phases, ToothSurfaces surfaces,
                                     double sun_speed_abs_rad_s, double carrier_speed_abs_rad_s)
    : structure_(std::move(structure)),
      sun_planet_(std::move(sun_planet)),
      planet_ring_(std::move(planet_ring)),
      phases_(std::move(phases)),
      surfaces_(std::move(surfaces)) {
  const int nm = static_cast<int>(structure_.meshes.size());
  states_.assign(nm, MeshState{});
  mesh_.assign(static_cast<std::size_t>(nm), MeshRecord{});
  power_ = cfg.operating.input_power_W;
  sun_speed_ = sun_speed_abs_rad_s;
  carrier_speed_ = carrier_speed_abs_rad_s;
  sun_speed_rel_ = sun_speed_abs_rad_s - carrier_speed_abs_rad_s;
  mu_ = cfg.contact.friction_coefficient;
  v_eps_ = cfg.contact.friction_smoothing_m_s;
  inv_v_eps_ = 1.0 / v_eps_;
  ripple_ = cfg.imperfections.torque_ripple_fraction;
  ripple_order_ = cfg.imperfections.torque_ripple_order;
  sun_ecc_ = cfg.imperfections.sun_eccentricity_m;
  sun_ecc_phase_ = cfg.imperfections.sun_eccentricity_phase_rad;
  sun_row_ = structure_.bodies[structure_.sun_body].map.row(2);
  carrier_row_ = structure_.bodies[structure_.carrier_body].map.row(2);
  input_row_ = structure_.bodies[structure_.input_body].map.row(2);
  output_row_ = structure_.bodies[structure_.output_body].map.row(2);
  sun_rotation_ = RotationRow(sun_row_);
  carrier_rotation_ = RotationRow(carrier_row_);
  input_rotation_ = RotationRow(input_row_);
  constant_power_ = cfg.rig.input_control == InputControl::Power;
  q_roll_.setZero(structure_.dofs);
  roll_follows_rotation_ = cfg.stiffness.mesh_phase == MeshPhase::Rotation;
  // Ideal (loss-free) matching load torque; simulate() refines it so that the
  // stage holds its nominal speed in the presence of friction losses.
  load_torque_ = power_ / carrier_speed_;

  const Eigen::MatrixXd Minv = structure_.mass.inverse();
  for (int m = 0; m < nm; ++m) {
    const auto& mc = structure_.meshes[m];
    const dynamics::MeshId id = dynamics::MeshId::of(m);
    const bool sp = id.sun_planet();
    const int planet = id.planet;
    // Equivalent mass of the mesh coordinate delta = g.q: 1 / (g^T M^-1 g).
    const double m_eq = 1.0 / mc.g.dot(Minv * mc.g);
    MeshRecord& rec = mesh_[m];
    rec.damping_N_s_m = 2.0 * cfg.contact.mesh_damping_ratio * std::sqrt(family(m).mean_stiffness_N_m * m_eq);
    rec.backlash_m = sp ? cfg.contact.backlash_sun_planet_m : cfg.contact.backlash_planet_ring_m;
    rec.mesh_error_m = sp ? cfg.contact.mesh_error_sun_planet_m : cfg.contact.mesh_error_planet_ring_m;
    rec.normal = mc.normal;
    // Imposed displacements that are constant in the carrier frame (pin
    // position error along the carrier's tangent, carrier runout): delta
    // changes by n . (d_A - d_B) with d the displacement of the planet (B in
    // the sun mesh, A in the ring mesh).
    const double psi = structure_.bodies[structure_.planet_bodies[planet]].centre_m.norm() > 0
                           ? std::atan2(structure_.bodies[structure_.planet_bodies[planet]].centre_m.y(),
                                        structure_.bodies[structure_.planet_bodies[planet]].centre_m.x())
                           : 0.0;
    const Eigen::Vector2d et{-std::sin(psi), std::cos(psi)};
    Eigen::Vector2d d_planet = Eigen::Vector2d::Zero();
    if (!cfg.imperfections.pin_error_m.empty()) d_planet += cfg.imperfections.pin_error_m[planet] * et;
    const double ec = cfg.imperfections.carrier_eccentricity_m, ph = cfg.imperfections.carrier_eccentricity_phase_rad;
    d_planet += ec * Eigen::Vector2d{std::cos(ph), std::sin(ph)};
    rec.static_offset_m = sp ? -mc.normal.dot(d_planet) : mc.normal.dot(d_planet);
  }
  for (int m = 0; m < nm; ++m) {
    const MeshFamily& fam = family(m);
    const std::vector<double>& x = fam.stiffness.xi_m;
    mesh_[m].scales.inv_base_pitch_1_m = 1.0 / fam.geometry.base_pitch_m;
    MeshScales& sc = mesh_[m].scales;
    if (x.size() >= 2) {
      sc.stiffness_index_1_m = static_cast<double>(x.size() - 1) / (x.back() - x.front());
      sc.stiffness_x0_m = x.front();
      sc.stiffness_x1_m = x.back();
      sc.stiffness_last = x.size() - 2;
    }
    mesh_[m].sparse = dynamics::sparse_coupling(structure_.meshes[m]);
  }
  bool sp3_pr2 = nm % 2 == 0, all7 = true;
  for (int m = 0; m < nm; ++m) {
    sp3_pr2 = sp3_pr2 && mesh_[m].sparse.entries == (dynamics::MeshId::of(m).sun_planet() ? 3 : 2);
    all7 = all7 && mesh_[m].sparse.entries == 7;
  }
  entry_pattern_ = sp3_pr2 ? EntryPattern::SunPlanet3Ring2 : all7 ? EntryPattern::All7 : EntryPattern::Mixed;
  if (sp3_pr2 && torsional_coordinates(mesh_)) entry_pattern_ = EntryPattern::Torsional;
  input_row_nz_ = nonzeros(input_row_);
  output_row_nz_ = nonzeros(output_row_);
  const Eigen::MatrixXd& S = structure_.support_stiffness;
  for (Eigen::Index j = 0; j < S.cols(); ++j)
    for (Eigen::Index i = 0; i < S.rows(); ++i)
      if (S(i, j) != 0) support_nz_.push_back({static_cast<int>(i), static_cast<int>(j), S(i, j)});
  const Eigen::MatrixXd& D = structure_.support_damping;
  for (Eigen::Index j = 0; j < D.cols(); ++j)
    for (Eigen::Index i = 0; i < D.rows(); ++i)
      if (D(i, j) != 0) damping_nz_.push_back({static_cast<int>(i), static_cast<int>(j), D(i, j)});
}

void PlanetaryDynamics::set_engagement_smoothing(double dt_s) {
  require(dt_s >= 0 && std::isfinite(dt_s), "engagement smoothing", "time step ", dt_s, " s must be >= 0");
  for (std::size_t m = 0; m < mesh_.size(); ++m) {
    MeshRecord& rec = mesh_[m];
    const double step_half_m = 0.5 * std::fabs(structure_.meshes[m].nominal_roll_rate_m_s) * dt_s;
    rec.engage_half_width_m = std::max(step_half_m, family(static_cast<int>(m)).engagement_ramp_half_width_m);
    rec.scales.inv_engage_width_1_m = rec.engage_half_width_m > 0 ? 1.0 / (2 * rec.engage_half_width_m) : 0.0;
  }
  ++contact_epoch_;
}

const FlankSet& PlanetaryDynamics::flank_a(int m) const {
  const dynamics::MeshId id = dynamics::MeshId::of(m);
  return id.sun_planet() ? surfaces_.sun : surfaces_.planet_ring_side[static_cast<std::size_t>(id.planet)];
}
const FlankSet& PlanetaryDynamics::flank_b(int m) const {
  const dynamics::MeshId id = dynamics::MeshId::of(m);
  return id.sun_planet() ? surfaces_.planet_sun_side[static_cast<std::size_t>(id.planet)] : surfaces_.ring;
}

double PlanetaryDynamics::input_torque_Nm(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  const double w_in = sun_speed_ + input_rotation_.of(v);
  const double mean = power_ / (constant_power_ ? w_in : sun_speed_);
  // A motor that holds the speed adds its spring to the speed reference (shaft or loop).
  const int held = structure_.speed_reference_spring;
  const double hold = held >= 0 && structure_.speed_reference_at_input
                          ? -(structure_.springs[held].stiffness * input_rotation_.of(q) +
                              structure_.springs[held].damping * input_rotation_.of(v))
                          : 0.0;
  if (ripple_ == 0) return mean + hold;
  const double th_in = sun_speed_ * t + input_rotation_.of(q);
  return mean * (1.0 + ripple_ * std::sin(ripple_order_ * th_in)) + hold;
}

Eigen::Vector2d PlanetaryDynamics::sun_runout_m(double t) const {
  // Sun runout rotates with the sun, i.e. at the sun's speed relative to
  // the carrier in this frame; it displaces the sun (body A of every sun mesh).
  if (sun_ecc_ == 0) return Eigen::Vector2d::Zero();
  const double phi = sun_speed_rel_ * t + sun_ecc_phase_;
  return sun_ecc_ * Eigen::Vector2d{std::cos(phi), std::sin(phi)};
}

double PlanetaryDynamics::imposed_deflection(int m, const Eigen::Vector2d& sun_runout_m) const {
  const MeshRecord& rec = mesh_[m];
  double d = rec.static_offset_m;
  if (dynamics::MeshId::of(m).sun_planet() && sun_ecc_ != 0) d += rec.normal.dot(sun_runout_m);
  return d;
}

// Inlined into update_contact_geometry, its one caller: 3-4 % of a torsional step (measured,
// docs/benchmark.md session 22); GCC's size heuristic leaves it out of line otherwise.
[[gnu::always_inline]] inline PlanetaryDynamics::PairWindow PlanetaryDynamics::pair_window(int m, double s_m) {
  // geometry::pairs_in_contact's arithmetic (the same n_first, n_last and xi_n = u - n p_b, so the
  // same pairs bit for bit) without its output vector and its two 64-bit modulos per call: the
  // window's first pair index moves by 0 or 1 per step, so its tooth indices are advanced by
  // counting from the previous step's, and the modulo is taken only after a jump.
  const MeshFamily& fam = family(m);
  const geometry::MeshGeometry& mg = fam.geometry;
  const dynamics::MeshId id = dynamics::MeshId::of(m);
  const auto& planet_phases = phases_[static_cast<std::size_t>(id.planet)];
  const geometry::MeshPhase& phase = id.sun_planet() ? planet_phases.sun_planet : planet_phases.planet_ring;
  MeshRecord& rec = mesh_[m];
  const double margin = rec.engage_half_width_m;
  PairWindow w;
  w.u_m = phase.xi0_m + s_m;  // xi_n = u - n p_b
  const double inv_pb = rec.scales.inv_base_pitch_1_m;
  w.n_first = ceil_exact((w.u_m - mg.end_active_m - margin) * inv_pb);
  const double n_last = floor_exact((w.u_m - mg.start_active_m + margin) * inv_pb);
  w.count = n_first_le(w.n_first, n_last) ? static_cast<int>(n_last - w.n_first) + 1 : 0;
  if (w.count == 0) return w;
  ToothCursor& cur = rec.cursor;
  const long long k0 = static_cast<long long>(w.n_first);
  const long long step = k0 - cur.k0;
  if (cur.valid && step >= 0 && step <= kCursorMaxAdvance) {
    for (long long i = 0; i < step; ++i) {
      if (++cur.tooth_a == fam.teeth_a) cur.tooth_a = 0;
      if (++cur.tooth_b == fam.teeth_b) cur.tooth_b = 0;
    }
  } else {
    cur.tooth_a = wrap_tooth(phase.tooth_a0 + k0, fam.teeth_a);
    cur.tooth_b = wrap_tooth(phase.tooth_b0 + k0, fam.teeth_b);
  }
  cur.k0 = k0;
  cur.valid = true;
  w.tooth_a = cur.tooth_a;
  w.tooth_b = cur.tooth_b;
  return w;
}

double MeshFamily::stiffness_correction_N_m(double u_m) const {
  // Phase in mesh cycles reduced to [0, 1) before the sine: u grows with the run.
  const double cycles = u_m / geometry.base_pitch_m;
  const double x = 2 * std::numbers::pi * (cycles - std::floor(cycles));
  const double c1 = std::cos(x), s1 = std::sin(x);
  double c = 1, s = 0, dk = 0;
  for (int h = 0; h < StiffnessSettings::Harmonics::kCount; ++h) {
    const double cn = c * c1 - s * s1;  // cos((h+1) x), sin((h+1) x) by the angle-sum recurrence
    s = s * c1 + c * s1;
    c = cn;
    dk += harmonic_cos_N_m[h] * c + harmonic_sin_N_m[h] * s;
  }
  return dk;
}

// Inlined into update_contact_geometry, its one caller, by force: the per-mesh call's set-up and
// register saves were ~10 % of the geometry's instructions (callgrind, session 41).
template <int NE>
[[gnu::always_inline]] inline void PlanetaryDynamics::update_mesh_geometry(int m, double t,
                                                                           const Eigen::Vector2d& runout) {
  const dynamics::MeshCoupling& mc = structure_.meshes[m];
  MeshRecord& rec = mesh_[m];
  const dynamics::SparseCoupling& sc = rec.sparse;
  const int ne = NE > 0 ? NE : sc.entries;
  const MeshFamily& fam = family(m);
  const geometry::MeshGeometry& mg = fam.geometry;
  const FlankSet& fa = flank_a(m);
  const FlankSet& fb = flank_b(m);
  MeshState& st = states_[m];

  double roll_q = 0;
  for (int k = 0; k < ne; ++k) roll_q += sc.roll[k] * q_roll_(sc.dof[k]);
  st.roll_m = mc.nominal_roll_rate_m_s * t + roll_q;
  rec.imposed_m = imposed_deflection(m, runout);
  const double h = rec.engage_half_width_m;
  const PairWindow win = pair_window(m, st.roll_m);
  const int np = win.count;
  if (np > MeshState::kMaxPairs) [[unlikely]]
    throw SolverError(detail::concat("more than ", MeshState::kMaxPairs, " tooth pairs in one mesh (", np,
                                     " at t = ", t, " s, roll ", st.roll_m, " m, window margin ", h, " m, base pitch ",
                                     mg.base_pitch_m, " m)"));
  st.pairs = np;
  st.first_pair = rec.cursor.k0;

  // A pair entering or leaving contact within the step counts with the
  // share of the step it spends in contact (engagement_weight).
  const double xi_lo = mg.start_active_m, xi_hi = mg.end_active_m;
  const bool pristine_a = fa.pristine(), pristine_b = fb.pristine();
  const bool same_grid_a_b = !pristine_a && fa.same_grid(fb);
  const bool unit_a = fa.unit_factors(), unit_b = fb.unit_factors();
  st.pairs_engaged = 0;
  double k_sum = 0;
  int ta = win.tooth_a, tb = win.tooth_b;
  double n = win.n_first;
  for (int j = 0; j < np; ++j, n += 1.0) {
    geometry::ContactPair& p = st.pair[j];
    p = {win.u_m - n * mg.base_pitch_m, ta, tb};
    if (++ta == fam.teeth_a) ta = 0;
    if (++tb == fam.teeth_b) tb = 0;
    PairGeometry& pg = rec.pairs[j];
    const double w = engagement_weight(mg, p.xi_m, h, rec.scales.inv_engage_width_1_m);
    st.pairs_engaged += w >= 0.5 ? 1 : 0;
    // Untouched flanks (FlankSet::pristine) contribute a factor 1 and a deviation 0: skipped.
    pg.k_N_m = w * pair_stiffness(fam.stiffness.k_N_m, rec.scales.stiffness_x0_m, rec.scales.stiffness_x1_m,
                                  rec.scales.stiffness_last, rec.scales.stiffness_index_1_m,
                                  std::clamp(p.xi_m, xi_lo, xi_hi));
    if (!unit_a) pg.k_N_m *= fa.stiffness_factor(p.tooth_a);
    if (!unit_b) pg.k_N_m *= fb.stiffness_factor(p.tooth_b);
    // The two flanks of a mesh share one element grid (same_grid_a_b): one grid point serves both.
    const FlankSet::GridPoint gp_a = pristine_a ? FlankSet::GridPoint{} : fa.grid_point(p.xi_m);
    const FlankSet::GridPoint gp_b = pristine_b ? FlankSet::GridPoint{} : same_grid_a_b ? gp_a : fb.grid_point(p.xi_m);
    const double dev_a = pristine_a ? 0.0 : fa.deviation_m(p.tooth_a, gp_a);
    const double dev_b = pristine_b ? 0.0 : fb.deviation_m(p.tooth_b, gp_b);
    pg.deviation_m = dev_a + dev_b + rec.mesh_error_m;
    pg.slide_nominal_m_s = mc.nominal_slide0_m_s + p.xi_m * mc.nominal_slide1_1_s;
    for (int k = 0; k < ne; ++k) pg.h[k] = sc.h0[k] + p.xi_m * sc.h1[k];
    k_sum += pg.k_N_m;
  }
  if (fam.corrected && k_sum > 0) {
    // The calibrated harmonics change the combined stiffness by dK(u); the pairs share it in
    // proportion to their stiffness, so their shares (and the damping's) are unchanged. At most
    // kMaxStiffnessRemoved of the stiffness in contact is taken away: a larger correction would
    // leave a mesh in contact without stiffness, which no stiffness law has.
    const double f = std::max(1.0 + fam.stiffness_correction_N_m(win.u_m) / k_sum, 1.0 - kMaxStiffnessRemoved);
    for (int j = 0; j < np; ++j) rec.pairs[j].k_N_m *= f;
    k_sum *= f;
  }
  st.stiffness_N_m = k_sum;
  const double inv_k_sum = k_sum > 0 ? 1.0 / k_sum : 0.0;
  for (int j = 0; j < np; ++j) rec.pairs[j].share = rec.pairs[j].k_N_m * inv_k_sum;
}

void PlanetaryDynamics::update_contact_geometry(double t) {
  const int nm = static_cast<int>(structure_.meshes.size());
  const Eigen::Vector2d runout = sun_runout_m(t);  // one sin/cos per step, not per sun mesh
  // The entry loops unrolled for the torsional (2, 3) and lateral-torsional (7) meshes, as in
  // add_mesh_force: the same sums in the same order. The meshes in their order; a stage whose entry
  // counts follow a known pattern (entry_pattern_) is walked without a switch per mesh.
  switch (entry_pattern_) {
  case EntryPattern::Torsional:
  case EntryPattern::SunPlanet3Ring2:
    for (int m = 0; m < nm; m += 2) {
      update_mesh_geometry<3>(m, t, runout);
      update_mesh_geometry<2>(m + 1, t, runout);
    }
    break;
  case EntryPattern::All7:
    for (int m = 0; m < nm; ++m) update_mesh_geometry<7>(m, t, runout);
    break;
  case EntryPattern::Mixed:
    for (int m = 0; m < nm; ++m) {
      switch (mesh_[m].sparse.entries) {
      case 2: update_mesh_geometry<2>(m, t, runout); break;
      case 3: update_mesh_geometry<3>(m, t, runout); break;
      case 7: update_mesh_geometry<7>(m, t, runout); break;
      default: update_mesh_geometry<0>(m, t, runout); break;
      }
    }
    break;
  }
  geometry_t_ = t;
  geometry_epoch_ = contact_epoch_;
}

// Inlined into force() by force: the mesh loop then keeps the raw vectors, the friction constants
// and the tangent flag in registers across the meshes instead of setting them up per call through
// a dispatch function (callgrind, session 41). `d` reads q, v and accumulates into g for entry k
// of the mesh (IndexedCoordinates, TorsionalCoordinates); K and C are indexed by sc.dof.
template <int NE, class Coordinates>
[[gnu::always_inline]] inline void PlanetaryDynamics::add_mesh_force_n(int m, Coordinates& d, Eigen::MatrixXd* K,
                                                                       Eigen::MatrixXd* C) {
  const bool tangents = (K != nullptr && C != nullptr);
  const MeshRecord& rec = mesh_[m];
  const dynamics::SparseCoupling& sc = rec.sparse;
  const auto& pgs = rec.pairs;
  const int ne = NE > 0 ? NE : sc.entries;
  MeshState& st = states_[m];
  const double mu = mu_, inv_v_eps = inv_v_eps_;

  double gq = 0, gv = 0;
  for (int k = 0; k < ne; ++k) {
    gq += sc.g[k] * d.q(k);
    gv += sc.g[k] * d.v(k);
  }
  // Locals carry the values the stores into g below would otherwise make the compiler reload
  // from the mesh state (a double store may alias any double).
  const double deflection = gq + rec.imposed_m;
  st.deflection_m = deflection;
  st.velocity_m_s = gv;

  // Elastic forces pair by pair (drive flanks).
  const int np = st.pairs;
  const double k_sum = st.stiffness_N_m;
  double k_active = 0, F_el = 0;
  for (int j = 0; j < np; ++j) {
    const double k = pgs[j].k_N_m;
    const double pen = deflection - pgs[j].deviation_m;
    st.pair_force_N[j] = 0;
    if (pen > 0) {
      st.pair_force_N[j] = k * pen;
      F_el += k * pen;
      k_active += k;
    }
  }
  // Coast-flank contact once the backlash is closed. The coast flanks'
  // pairs are approximated by the drive-side combined stiffness (the mesh
  // is symmetric; only the phase differs), see derivation §3.3.
  double F_back = 0;
  const double backlash = rec.backlash_m;
  if (deflection < -backlash && k_sum > 0) {
    F_back = k_sum * (deflection + backlash);
    k_active += k_sum;
  }
  const bool contact = (F_el > 0 || F_back < 0);
  const double c = contact ? rec.damping_N_s_m : 0.0;
  const double F_d = c * gv;
  const double F = F_el + F_back + F_d;
  st.damping_force_N = F_d;
  st.force_N = F;
  for (int k = 0; k < ne; ++k) d.subtract(k, F * sc.g[k]);
  if (tangents) {
    for (int b = 0; b < ne; ++b)
      for (int a = 0; a < ne; ++a) {
        (*K)(sc.dof[a], sc.dof[b]) += (k_active * sc.g[a]) * sc.g[b];
        if (c > 0) (*C)(sc.dof[a], sc.dof[b]) += (c * sc.g[a]) * sc.g[b];
      }
  }

  // Friction on the drive-flank pairs, each carrying its elastic force and
  // a stiffness-weighted share of the damping force.
  double friction = 0;
  for (int j = 0; j < np; ++j) {
    const auto& h = pgs[j].h;
    double hv = 0;
    for (int k = 0; k < ne; ++k) hv += h[k] * d.v(k);
    const double vs = pgs[j].slide_nominal_m_s + hv;
    st.sliding_m_s[j] = vs;
    const double F_pair = st.pair_force_N[j];
    if (F_pair <= 0) continue;  // its flanks do not touch
    const double kj = pgs[j].k_N_m;
    const double share = pgs[j].share;  // k_j / k_sum
    const double Fn = std::max(0.0, F_pair + share * F_d);
    st.pair_force_N[j] = Fn;
    if (mu == 0) continue;
    const double th = smooth_sign(vs * inv_v_eps);
    const double Ff = mu * Fn * th;
    friction += Ff;
    for (int k = 0; k < ne; ++k) d.subtract(k, Ff * h[k]);
    if (tangents) {
      const double kk = mu * th * kj;
      const double cc = mu * Fn * (1 - th * th) * inv_v_eps;
      const double cd = mu * th * share * c;
      for (int b = 0; b < ne; ++b)
        for (int a = 0; a < ne; ++a) {
          (*K)(sc.dof[a], sc.dof[b]) += (kk * h[a]) * sc.g[b];
          (*C)(sc.dof[a], sc.dof[b]) += (cc * h[a]) * h[b];
          if (c > 0) (*C)(sc.dof[a], sc.dof[b]) += (cd * h[a]) * sc.g[b];
        }
    }
  }
  st.friction_N = friction;
}

namespace {
/// A mesh's entries through its coupling's coordinate indices (any stage): q[dof[k]], g[dof[k]].
struct IndexedCoordinates {
  const double* qd;
  const double* vd;
  double* gd;
  const int* dof;
  double q(int k) const { return qd[dof[k]]; }
  double v(int k) const { return vd[dof[k]]; }
  void subtract(int k, double x) { gd[dof[k]] -= x; }
};

/// The entries of planet i's torsional meshes (PlanetaryDynamics::EntryPattern::Torsional):
/// sun-planet on (theta_s, theta_c, theta_p), planet-ring on (theta_c, theta_p), the ring fixed.
/// The sun's and the carrier's coordinates are read once per evaluation and their generalized
/// forces summed in locals across the planets, the planet's in a local across its two meshes:
/// with the coordinates in registers the mesh loop loads no index and stores no force entry per
/// term. Each entry receives the same subtractions in the same order as through g[dof[k]].
template <bool SunPlanet>
struct TorsionalCoordinates {
  const double (&qs)[3];  // (theta_s, theta_c, theta_p) of the planet
  const double (&vs)[3];
  double (&gs)[3];        // their generalized forces, accumulated
  static constexpr int first = SunPlanet ? 0 : 1;
  double q(int k) const { return qs[first + k]; }
  double v(int k) const { return vs[first + k]; }
  void subtract(int k, double x) { gs[first + k] -= x; }
};
} // namespace

void PlanetaryDynamics::add_torsional_mesh_forces(const double* __restrict q, const double* __restrict v,
                                                  double* __restrict g) {
  const int planets = static_cast<int>(mesh_.size()) / 2;
  double qs[3] = {q[0], q[1], 0}, vs[3] = {v[0], v[1], 0}, gs[3] = {g[0], g[1], 0};
  for (int i = 0; i < planets; ++i) {
    qs[2] = q[2 + i];
    vs[2] = v[2 + i];
    gs[2] = g[2 + i];
    TorsionalCoordinates<true> sun{qs, vs, gs};
    add_mesh_force_n<3>(2 * i, sun, nullptr, nullptr);
    TorsionalCoordinates<false> ring{qs, vs, gs};
    add_mesh_force_n<2>(2 * i + 1, ring, nullptr, nullptr);
    g[2 + i] = gs[2];
  }
  g[0] = gs[0];
  g[1] = gs[1];
}

void PlanetaryDynamics::force(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& g,
                              Eigen::MatrixXd* K, Eigen::MatrixXd* C) {
  const bool tangents = (K != nullptr && C != nullptr);
  // Support springs: g = -S q over S's non-zeros.
  g.setZero();
  for (const SupportEntry& e : support_nz_) g(e.row) -= e.k * q(e.col);
  for (const SupportEntry& e : damping_nz_) g(e.row) -= e.k * v(e.col);
  if (tangents) {
    *K = structure_.support_stiffness;
    if (damping_nz_.empty())
      C->setZero();
    else
      *C = structure_.support_damping;
  }

  // Input (on the sun, or on the motor behind the input shaft): constant power P
  // at the actual speed, with optional ripple; dT/dw = -T/w enters C (it damps the
  // rigid-body mode). A torque-controlled motor gives P/Omega_s, no speed feedback.
  double w_rel = 0;
  for (int i : input_row_nz_) w_rel += input_row_(i) * v(i);
  const double w_in = sun_speed_ + w_rel;
  double T_s = power_ / (constant_power_ ? w_in : sun_speed_);
  if (ripple_ != 0) T_s *= 1.0 + ripple_ * std::sin(ripple_order_ * (sun_speed_ * t + input_row_.dot(q)));
  for (int i : input_row_nz_) g(i) += T_s * input_row_(i);
  for (int i : output_row_nz_) g(i) -= load_torque_ * output_row_(i);
  if (tangents && constant_power_)
    for (int b : input_row_nz_)
      for (int a : input_row_nz_) (*C)(a, b) += ((T_s / w_in) * input_row_(a)) * input_row_(b);

  // The contact geometry (pairs, stiffnesses, deviations) is fixed by the
  // lagged roll reference: evaluated once per step, reused by Newton.
  if (geometry_epoch_ != contact_epoch_ || geometry_t_ != t) update_contact_geometry(t);
  const int nm = static_cast<int>(structure_.meshes.size());
  IndexedCoordinates d{q.data(), v.data(), g.data(), nullptr};
  auto mesh_force = [&]<int NE>(int m) {
    d.dof = mesh_[m].sparse.dof.data();
    add_mesh_force_n<NE>(m, d, K, C);
  };
  // The entry loops unrolled for the torsional (2, 3) and lateral-torsional (7) meshes; the meshes in
  // their order, without a switch per mesh where the entry counts follow a known pattern.
  switch (entry_pattern_) {
  case EntryPattern::Torsional:
    if (!tangents) {
      add_torsional_mesh_forces(q.data(), v.data(), g.data());
      break;
    }
    [[fallthrough]];  // the tangents through the coupling's indices
  case EntryPattern::SunPlanet3Ring2:
    for (int m = 0; m < nm; m += 2) {
      mesh_force.template operator()<3>(m);      // torsional sun-planet
      mesh_force.template operator()<2>(m + 1);  // torsional planet-ring (ring fixed)
    }
    break;
  case EntryPattern::All7:
    for (int m = 0; m < nm; ++m) mesh_force.template operator()<7>(m);
    break;
  case EntryPattern::Mixed:
    for (int m = 0; m < nm; ++m) {
      switch (mesh_[m].sparse.entries) {
      case 2: mesh_force.template operator()<2>(m); break;
      case 3: mesh_force.template operator()<3>(m); break;
      case 7: mesh_force.template operator()<7>(m); break;
      default: mesh_force.template operator()<0>(m); break;
      }
    }
    break;
  }
}

} // namespace pw::model
