// Natural frequencies of the linearized, time-averaged model:
// (K_support + sum_m k_m g_m g_m^T) phi = omega^2 M phi.
#pragma once

#include "dynamics/lumped_model.hpp"

#include <Eigen/Dense>

#include <vector>

namespace pw::dynamics {

struct ModalResult {
  Eigen::VectorXd frequencies_Hz;  ///< ascending; rigid-body modes give ~0
  Eigen::MatrixXd modes;           ///< mass-normalized mode shapes (columns)
};

/// Sum of k_m g_m g_m^T over the meshes; k_N_m[m] is mesh m's stiffness [N/m].
Eigen::MatrixXd mesh_stiffness_matrix(const LumpedStructure& s, const std::vector<double>& k_N_m);

/// Generalized symmetric eigenproblem K phi = omega^2 M phi (M positive definite).
ModalResult natural_frequencies(const Eigen::MatrixXd& M, const Eigen::MatrixXd& K);

} // namespace pw::dynamics
