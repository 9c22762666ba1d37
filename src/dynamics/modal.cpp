#include "dynamics/modal.hpp"

#include "core/error.hpp"

#include <cmath>
#include <numbers>

namespace pw::dynamics {

Eigen::MatrixXd mesh_stiffness_matrix(const LumpedStructure& s, const std::vector<double>& k) {
  require(k.size() == s.meshes.size(), "mesh stiffness", "need one value per mesh (", s.meshes.size(), "), got ",
          k.size());
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(s.dofs, s.dofs);
  for (std::size_t m = 0; m < s.meshes.size(); ++m) K.noalias() += k[m] * s.meshes[m].g * s.meshes[m].g.transpose();
  return K;
}

ModalResult natural_frequencies(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K) {
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (K + K.transpose()), 0.5 * (M + M.transpose()));
  if (es.info() != Eigen::Success) throw SolverError("modal analysis failed: mass matrix not positive definite");
  ModalResult r;
  r.frequencies_Hz = es.eigenvalues().unaryExpr(
      [](double l) { return std::sqrt(std::fmax(l, 0.0)) / (2 * std::numbers::pi); });
  r.modes = es.eigenvectors();
  return r;
}

} // namespace pw::dynamics
