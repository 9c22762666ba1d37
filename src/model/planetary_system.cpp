#include "model/planetary_system.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace pw::model {

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
  pairs_.reserve(8);
  power_ = cfg.operating.input_power_W;
  sun_speed_ = sun_speed_abs_rad_s;
  carrier_speed_ = carrier_speed_abs_rad_s;
  sun_speed_rel_ = sun_speed_abs_rad_s - carrier_speed_abs_rad_s;
  mu_ = cfg.contact.friction_coefficient;
  v_eps_ = cfg.contact.friction_smoothing_m_s;
  ripple_ = cfg.imperfections.torque_ripple_fraction;
  ripple_order_ = cfg.imperfections.torque_ripple_order;
  sun_ecc_ = cfg.imperfections.sun_eccentricity_m;
  sun_ecc_phase_ = cfg.imperfections.sun_eccentricity_phase_rad;
  sun_row_ = structure_.bodies[structure_.sun_body].map.row(2);
  carrier_row_ = structure_.bodies[structure_.carrier_body].map.row(2);
  supp_force_.setZero(structure_.dofs);
  h_.setZero(structure_.dofs);
  q_roll_.setZero(structure_.dofs);
  // Ideal (loss-free) matching load torque; simulate() refines it so that the
  // stage holds its nominal speed in the presence of friction losses.
  load_torque_ = power_ / carrier_speed_;

  const Eigen::MatrixXd Minv = structure_.mass.inverse();
  for (int m = 0; m < nm; ++m) {
    const auto& mc = structure_.meshes[m];
    const bool sp = (m % 2 == 0);
    const int planet = m / 2;
    // Equivalent mass of the mesh coordinate delta = g.q: 1 / (g^T M^-1 g).
    const double m_eq = 1.0 / mc.g.dot(Minv * mc.g);
    damping_.push_back(2.0 * cfg.contact.mesh_damping_ratio * std::sqrt(family(m).mean_stiffness_N_m * m_eq));
    backlash_.push_back(sp ? cfg.contact.backlash_sun_planet_m : cfg.contact.backlash_planet_ring_m);
    mesh_error_.push_back(sp ? cfg.contact.mesh_error_sun_planet_m : cfg.contact.mesh_error_planet_ring_m);
    normals_.push_back(mc.normal);
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
    static_offset_.push_back(sp ? -mc.normal.dot(d_planet) : mc.normal.dot(d_planet));
  }
  engage_half_width_m_.assign(static_cast<std::size_t>(nm), 0.0);
}

void PlanetaryDynamics::set_engagement_smoothing(double dt_s) {
  require(dt_s >= 0 && std::isfinite(dt_s), "engagement smoothing", "time step ", dt_s, " s must be >= 0");
  for (std::size_t m = 0; m < engage_half_width_m_.size(); ++m)
    engage_half_width_m_[m] = 0.5 * std::fabs(structure_.meshes[m].nominal_roll_rate_m_s) * dt_s;
}

const FlankSet& PlanetaryDynamics::flank_a(int m) const {
  return m % 2 == 0 ? surfaces_.sun : surfaces_.planet_ring_side[m / 2];
}
const FlankSet& PlanetaryDynamics::flank_b(int m) const {
  return m % 2 == 0 ? surfaces_.planet_sun_side[m / 2] : surfaces_.ring;
}

double PlanetaryDynamics::input_torque_Nm(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v) const {
  const double w_s = sun_speed_ + sun_row_.dot(v);
  const double th_s = sun_speed_ * t + sun_row_.dot(q);
  return power_ / w_s * (1.0 + ripple_ * std::sin(ripple_order_ * th_s));
}

double PlanetaryDynamics::imposed_deflection(int m, double t) const {
  double d = static_offset_[m];
  if (m % 2 == 0 && sun_ecc_ != 0) {
    // Sun runout rotates with the sun, i.e. at the sun's speed relative to
    // the carrier in this frame; it displaces the sun (body A).
    const double phi = sun_speed_rel_ * t + sun_ecc_phase_;
    d += normals_[m].dot(sun_ecc_ * Eigen::Vector2d{std::cos(phi), std::sin(phi)});
  }
  return d;
}

void PlanetaryDynamics::force(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& g,
                              Eigen::MatrixXd* K, Eigen::MatrixXd* C) {
  const bool tangents = (K != nullptr && C != nullptr);
  supp_force_.noalias() = structure_.support_stiffness * q;
  g = -supp_force_;
  if (tangents) {
    *K = structure_.support_stiffness;
    C->setZero();
  }

  // Input: constant power P at the actual sun speed, with optional ripple;
  // dT/dw = -T/w enters C (it damps the rigid-body mode).
  const double w_s = sun_speed_ + sun_row_.dot(v);
  const double T_s = input_torque_Nm(t, q, v);
  g.noalias() += T_s * sun_row_.transpose();
  g.noalias() -= load_torque_ * carrier_row_.transpose();
  if (tangents) C->noalias() += (T_s / w_s) * sun_row_.transpose() * sun_row_;

  const int nm = static_cast<int>(structure_.meshes.size());
  for (int m = 0; m < nm; ++m) {
    const dynamics::MeshCoupling& mc = structure_.meshes[m];
    const MeshFamily& fam = family(m);
    const geometry::MeshPhase& phase = (m % 2 == 0) ? phases_[m / 2].sun_planet : phases_[m / 2].planet_ring;
    const FlankSet& fa = flank_a(m);
    const FlankSet& fb = flank_b(m);
    MeshState& st = states_[m];

    st.roll_m = mc.nominal_roll_rate_m_s * t + mc.roll.dot(q_roll_);
    st.deflection_m = mc.g.dot(q) + imposed_deflection(m, t);
    st.velocity_m_s = mc.g.dot(v);
    const double h = engage_half_width_m_[m];
    const int np =
        geometry::pairs_in_contact(fam.geometry, phase, fam.teeth_a, fam.teeth_b, st.roll_m, pairs_, h);
    if (np > MeshState::kMaxPairs)
      throw SolverError("more than " + std::to_string(MeshState::kMaxPairs) +
                        " tooth pairs in one mesh (contact ratio too high for MeshState)");
    st.pairs = np;

    // Elastic forces pair by pair; a pair entering or leaving contact within the step
    // counts with the share of the step it spends in contact (engagement_weight).
    const double xi_lo = fam.geometry.start_active_m, xi_hi = fam.geometry.end_active_m;
    st.pairs_engaged = 0;
    double k_sum = 0, k_active = 0, F_el = 0;
    std::array<double, MeshState::kMaxPairs> k_loaded{};  // k_j of pairs whose flanks touch
    for (int j = 0; j < st.pairs; ++j) {
      const geometry::ContactPair& p = pairs_[j];
      st.pair[j] = p;
      const double w = geometry::engagement_weight(fam.geometry, p.xi_m, h);
      st.pairs_engaged += w >= 0.5 ? 1 : 0;
      const double k = w * fam.stiffness(std::clamp(p.xi_m, xi_lo, xi_hi)) * fa.stiffness_factor(p.tooth_a) *
                       fb.stiffness_factor(p.tooth_b);
      const double e = fa.deviation_m(p.tooth_a, p.xi_m) + fb.deviation_m(p.tooth_b, p.xi_m) + mesh_error_[m];
      const double pen = st.deflection_m - e;
      k_sum += k;
      st.pair_force_N[j] = 0;
      if (pen > 0) {
        st.pair_force_N[j] = k * pen;
        k_loaded[j] = k;
        F_el += k * pen;
        k_active += k;
      }
    }
    // Coast-flank contact once the backlash is closed. The coast flanks'
    // pairs are approximated by the drive-side combined stiffness (the mesh
    // is symmetric; only the phase differs), see derivation §3.3.
    double F_back = 0;
    if (st.deflection_m < -backlash_[m] && k_sum > 0) {
      F_back = k_sum * (st.deflection_m + backlash_[m]);
      k_active += k_sum;
    }
    const bool contact = (F_el > 0 || F_back < 0);
    const double c = contact ? damping_[m] : 0.0;
    st.damping_force_N = c * st.velocity_m_s;
    st.force_N = F_el + F_back + st.damping_force_N;
    st.stiffness_N_m = k_sum;
    g.noalias() -= st.force_N * mc.g;
    if (tangents) K->noalias() += k_active * mc.g * mc.g.transpose();
    if (tangents && c > 0) C->noalias() += c * mc.g * mc.g.transpose();

    // Friction on the drive-flank pairs, each carrying its elastic force and
    // a stiffness-weighted share of the damping force.
    st.friction_N = 0;
    for (int j = 0; j < st.pairs; ++j) {
      const double xi = st.pair[j].xi_m;
      const double vs = mc.nominal_slide0_m_s + xi * mc.nominal_slide1_1_s + (mc.h0 + xi * mc.h1).dot(v);
      st.sliding_m_s[j] = vs;
      if (st.pair_force_N[j] <= 0) continue;
      const double kj = k_loaded[j];
      const double share = (k_sum > 0) ? kj / k_sum : 0.0;
      const double Fn = std::max(0.0, st.pair_force_N[j] + share * st.damping_force_N);
      st.pair_force_N[j] = Fn;
      if (mu_ == 0) continue;
      const double th = std::tanh(vs / v_eps_);
      const double Ff = mu_ * Fn * th;
      st.friction_N += Ff;
      g.noalias() -= Ff * (mc.h0 + xi * mc.h1);
      if (tangents) {
        h_ = mc.h0 + xi * mc.h1;
        K->noalias() += (mu_ * th * kj) * h_ * mc.g.transpose();
        C->noalias() += (mu_ * Fn * (1 - th * th) / v_eps_) * h_ * h_.transpose();
        if (c > 0) C->noalias() += (mu_ * th * share * c) * h_ * mc.g.transpose();
      }
    }
  }
}

} // namespace pw::model
