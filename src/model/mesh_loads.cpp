#include "model/mesh_loads.hpp"

#include "stiffness/hertz_contact.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace pw::model {
namespace {

/// E* / (pi b) of a mesh of gears a and b: p0^2 = (E*/(pi b)) F / R.
double pressure_factor(const geometry::GearSpec& a, const geometry::GearSpec& b) {
  const double Es = stiffness::contact_modulus(a.material.youngs_modulus_Pa, a.material.poisson_ratio,
                                               b.material.youngs_modulus_Pa, b.material.poisson_ratio);
  return Es / (std::numbers::pi * std::min(a.face_width_m, b.face_width_m));
}

} // namespace

MeshLoadRecorder::MeshLoadRecorder(const geometry::StageGeometry& g, const StageSpec& stage, double input_torque_Nm)
    : families_{Family{"sun_planet", g.sun_planet, pressure_factor(stage.sun, stage.planet)},
                Family{"planet_ring", g.planet_ring, pressure_factor(stage.planet, stage.ring)}},
      planets_(stage.planet_count),
      static_force_N_(input_torque_Nm / (stage.planet_count * g.sun_planet.base_radius_a_m)),
      meshes_(2 * static_cast<std::size_t>(stage.planet_count)) {}

void MeshLoadRecorder::add(const std::vector<MeshState>& states) {
  ++steps_;
  for (std::size_t m = 0; m < meshes_.size(); ++m) {
    const MeshState& st = states[m];
    PerMesh& acc = meshes_[m];
    acc.sum_N += st.force_N;
    acc.max_N = std::max(acc.max_N, st.force_N);
    const Family& fam = families_[dynamics::MeshId::of(m).sun_planet() ? 0 : 1];
    const bool internal = fam.mesh.kind == geometry::GearKind::Internal;
    for (int j = 0; j < st.pairs; ++j) {
      const double F = st.pair_force_N[j];
      if (!(F > 0)) continue;
      const double xi = st.pair[j].xi_m;
      const double rho_a = geometry::curvature_radius_a(fam.mesh, xi), rho_b = geometry::curvature_radius_b(fam.mesh, xi);
      if (!(rho_a > 0 && rho_b > 0)) continue;  // engagement-widened window beyond a base circle: no flank there
      const double p2 = fam.pressure_factor * F / stiffness::equivalent_radius(rho_a, rho_b, internal);
      if (p2 > acc.max_p0_squared) {
        acc.max_p0_squared = p2;
        acc.xi_at_max_p0 = xi;
      }
    }
  }
}

double MeshLoadRecorder::mean_force_N(int mesh) const {
  return steps_ > 0 ? meshes_.at(static_cast<std::size_t>(mesh)).sum_N / static_cast<double>(steps_) : 0.0;
}

std::vector<Scalar> MeshLoadRecorder::scalars() const {
  std::vector<Scalar> out;
  if (steps_ == 0) return out;
  for (std::size_t f = 0; f < families_.size(); ++f) {
    const Family& fam = families_[f];
    double sum = 0, mx = 0, kv = 0, p2 = 0, xi = 0;
    int planet = 0;
    for (int i = 0; i < planets_; ++i) {
      const std::size_t m = 2 * static_cast<std::size_t>(i) + f;
      const PerMesh& a = meshes_[m];
      const double mean = mean_force_N(static_cast<int>(m));
      sum += mean;
      mx = std::max(mx, a.max_N);
      if (mean > 0) kv = std::max(kv, a.max_N / mean);
      if (a.max_p0_squared > p2) {
        p2 = a.max_p0_squared;
        xi = a.xi_at_max_p0;
        planet = i;
      }
    }
    const std::string b = std::string("mesh_load/") + fam.name + "/";
    out.push_back({b + "static_force", "N", "nominal mesh force T_in / (N r_bs): equal sharing, no dynamics",
                   static_force_N_});
    out.push_back({b + "mean_force", "N", "mean dynamic normal mesh force, averaged over the planets' meshes",
                   sum / planets_});
    out.push_back({b + "max_force", "N", "largest dynamic normal mesh force of any planet's mesh", mx});
    out.push_back({b + "dynamic_factor", "1", "K_v: max over meshes of (largest / mean dynamic mesh force)", kv});
    out.push_back({b + "max_contact_pressure", "Pa",
                   "largest Hertzian peak pressure p0 = sqrt(F' E* / (pi R)) of any loaded tooth pair", std::sqrt(p2)});
    out.push_back({b + "max_contact_pressure_planet", "1", "planet whose mesh had the largest contact pressure",
                   static_cast<double>(planet)});
    out.push_back({b + "max_contact_pressure_position", "m",
                   "where: distance of that contact from the pitch point along the line of action, positive towards "
                   "the driving gear's tip",
                   xi - fam.mesh.pitch_point_m});
  }
  return out;
}

} // namespace pw::model
