// The loads a gear engineer reads first, accumulated over every recorded time
// step (stored or not): per mesh family the nominal static force, the mean and
// largest dynamic mesh force, the dynamic factor, and the largest Hertzian
// contact pressure of any loaded tooth pair with where it occurred.
//
//   static force      F_0 = T_in / (N r_bs)            equal sharing, no dynamics [N]
//                     (the planet-ring mesh carries the same force: the planet's
//                     torque balance F_sp r_bp = F_pr r_bp, friction neglected)
//   dynamic factor    K_v = max over meshes m of max_t F_m(t) / mean_t F_m(t)
//                     (ISO 6336-1's K_v as a ratio of peak to mean load of one mesh;
//                     unequal sharing between planets is the load-sharing factor's)
//   contact pressure  p_0 = sqrt(F' E* / (pi R)), F' = F_pair / b, 1/R = 1/rho_A +- 1/rho_B
//                     (Hertz line contact, Johnson 1985 Eq. 4.45; b the narrower face)
//
// The pressure is the Hertzian peak at the pair's simulated load, not ISO 6336-2's
// nominal contact stress with its factors; it is compared with an allowable
// (sigma_Hlim, ISO 6336-5) only in the summary the user reads.
#pragma once

#include "config/stage.hpp"
#include "geometry/mesh.hpp"
#include "model/planetary_system.hpp"
#include "model/result.hpp"

#include <array>
#include <vector>

namespace pw::model {

class MeshLoadRecorder {
public:
  /// `input_torque_Nm`: the mean input torque P / Omega_s [N m].
  MeshLoadRecorder(const geometry::StageGeometry& geometry, const StageSpec& stage, double input_torque_Nm);
  /// One recorded time step: the states of all 2N meshes (sun-planet i at 2i).
  void add(const std::vector<MeshState>& states);
  /// "mesh_load/<family>/<quantity>" scalars (SI units), empty before the first add().
  std::vector<Scalar> scalars() const;
  /// Mean dynamic normal force of mesh m (sun-planet i at 2i) over the steps added [N]; 0 before any.
  double mean_force_N(int mesh) const;

private:
  struct Family {
    const char* name;
    geometry::MeshGeometry mesh;
    double pressure_factor = 0;  // E* / (pi b) [Pa/m]: p0^2 = factor F / R
  };
  struct PerMesh {
    double sum_N = 0, max_N = 0;
    double max_p0_squared = 0;  // [Pa^2]
    double xi_at_max_p0 = 0;    // [m]
  };
  std::array<Family, 2> families_;
  int planets_;
  double static_force_N_;
  long steps_ = 0;
  std::vector<PerMesh> meshes_;
};

} // namespace pw::model
