// Rank correlation of a sampled design: imposing a target (Iman & Conover
// 1982) and measuring what a design achieved (Spearman's rho).
//
// Iman-Conover, on an n x d sample whose columns are the factors' unit-cube
// values: (1) a score matrix R whose columns are independent random
// permutations of the van der Waerden scores Phi^-1(k / (n + 1)), k = 1..n;
// (2) T = corr(R) = E E^T and the target C = P P^T (Cholesky; C's entries mapped
// from rank to normal-score correlation, 2 sin(pi c / 6));
// (3) R* = R E^-T P^T has correlation C exactly; (4) each column of the sample
// is rearranged to have the ranks of R*'s column. Only the pairing of the
// values changes: every column keeps its values, so a Latin hypercube stays
// one (each stratum still holds one case) and every marginal distribution is
// unchanged. Rank correlation is invariant under the monotone map from u to a
// factor value, so the target is the Spearman correlation of the factor values.
//
// Reference: R. L. Iman and W. J. Conover, "A distribution-free approach to
// inducing rank correlation among input variables", Communications in
// Statistics - Simulation and Computation 11(3) (1982) 311-334,
// doi:10.1080/03610918208812265. Dakota's LHS uses the same method for its
// uncertain_correlation_matrix.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace pw::sweep {

/// A d x d matrix, row-major.
struct SquareMatrix {
  int size = 0;
  std::vector<double> values;
  double operator()(int i, int j) const { return values[static_cast<std::size_t>(i) * size + j]; }
};

/// Why `c` is not a valid d x d correlation matrix ("" if it is): symmetric to
/// 1e-12, unit diagonal, off-diagonal entries in [-1, 1], positive definite.
std::string correlation_matrix_problem(const SquareMatrix& c);

/// Rearranges the columns of the n x d row-major `unit` sample (Iman-Conover,
/// above) towards the rank correlation `target`. Deterministic for a seed.
/// Needs n > d (the scores' correlation must be positive definite); throws
/// pw::InputError ("design.samples") otherwise.
void impose_rank_correlation(std::vector<double>& unit, long long n, int d, const SquareMatrix& target,
                             std::uint64_t seed);

/// Spearman's rank correlation of the columns of an n x d row-major sample
/// (ties share their average rank; a constant column correlates 0 with the others).
SquareMatrix spearman(const std::vector<double>& sample, long long n, int d);

} // namespace pw::sweep
