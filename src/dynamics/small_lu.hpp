// LU factorization with partial pivoting for the small dense iteration
// matrices of the time step (5 x 5 torsional, 18 x 18 lateral-torsional with
// three planets, at most ~110 x 110 with 32 planets).
//
// Why not Eigen::PartialPivLU: for n = 5 its blocked, dynamic-size code spends
// most of its time in set-up and dispatch (measured: a fresh factorization
// every step made the step 1.7x slower with it, docs/benchmark.md). The
// textbook right-looking elimination below (Golub & Van Loan, Algorithm 3.4.1)
// does n^3/3 multiply-adds on a buffer allocated once, with no dispatch.
// Same algorithm as LAPACK's dgetf2 (row pivoting on the largest |entry| of
// the column), so the pivot order -- and hence the rounding -- is the textbook one.
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace pw::dynamics {

/// x = A^-1 b for A^-1 column-major N x N: x = sum_j col_j b_j, the columns in order (x must not
/// alias b). SmallLU::apply_inverse's arithmetic for a size known at compile time, inline for
/// callers that know it (the Newmark step of a fixed size, newmark.cpp).
template <int N>
inline void multiply_by_inverse(const double* __restrict inv, const double* __restrict b, double* __restrict x) {
  double y[N];
  for (int i = 0; i < N; ++i) y[i] = inv[i] * b[0];
  for (int j = 1; j < N; ++j)
    for (int i = 0; i < N; ++i) y[i] += inv[i + j * N] * b[j];
  for (int i = 0; i < N; ++i) x[i] = y[i];
}

class SmallLU {
public:
  SmallLU() = default;
  explicit SmallLU(int n) { resize(n); }
  void resize(int n);
  int size() const { return n_; }

  /// Factorizes P A = L U (A square, size n). Returns false if a pivot is
  /// exactly zero (A singular); the factorization is then unusable.
  bool factorize(const Eigen::MatrixXd& a);
  /// x = A^-1 b with the last factorization (x may alias b).
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  /// The same with the loops of any size (solve() unrolls common sizes; tests compare the two).
  void solve_generic(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;

  /// Forms A^-1 from the last factorization (n solves), for apply_inverse().
  void compute_inverse();
  /// x = A^-1 b as the product with the inverse formed by compute_inverse() (x must not alias
  /// b). *Why:* the back substitution is a chain of n dependent divisions (~150 cycles for
  /// n = 5, 12 % of a time step); a matrix-vector product has no such chain, and the chord
  /// iterations reuse one factorization for hundreds of steps. Same solution to round-off
  /// (forming the inverse from a backward-stable LU: error ~ cond(A) eps |x|).
  void apply_inverse(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  /// The inverse formed by compute_inverse(), column-major n x n (for multiply_by_inverse).
  const double* inverse_data() const { return inverse_.data(); }

private:
  int n_ = 0;
  std::vector<double> lu_;   // column-major n x n: L below the diagonal (unit diagonal implied), U on and above
  std::vector<int> perm_;    // row perm_[i] of A is row i of P A
  mutable std::vector<double> work_;
  std::vector<double> inverse_;  // column-major n x n, from compute_inverse()
  // The unrolled kernels for n_ (small_lu.cpp), chosen once in resize(); null: the generic loops.
  void (*solve_kernel_)(const double* lu, const int* perm, const double* b, double* x) = nullptr;
  void (*multiply_kernel_)(const double* inverse, const double* b, double* x) = nullptr;
};

} // namespace pw::dynamics
