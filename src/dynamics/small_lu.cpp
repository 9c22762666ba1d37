#include "dynamics/small_lu.hpp"

#include <cmath>
#include <utility>

namespace pw::dynamics {

bool SmallLU::factorize(const Eigen::MatrixXd& a) {
  if (a.rows() != n_ || a.cols() != n_) resize(static_cast<int>(a.rows()));
  const int n = n_;
  double* lu = lu_.data();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) lu[i + j * n] = a(i, j);
  for (int i = 0; i < n; ++i) perm_[i] = i;
  for (int k = 0; k < n; ++k) {
    double* colk = lu + k * n;
    int p = k;
    double big = std::fabs(colk[k]);
    for (int i = k + 1; i < n; ++i)
      if (std::fabs(colk[i]) > big) {
        big = std::fabs(colk[i]);
        p = i;
      }
    if (big == 0.0) return false;
    if (p != k) {
      for (int j = 0; j < n; ++j) std::swap(lu[k + j * n], lu[p + j * n]);
      std::swap(perm_[k], perm_[p]);
    }
    const double inv = 1.0 / colk[k];
    for (int i = k + 1; i < n; ++i) colk[i] *= inv;
    for (int j = k + 1; j < n; ++j) {
      double* colj = lu + j * n;
      const double ukj = colj[k];
      if (ukj == 0.0) continue;
      for (int i = k + 1; i < n; ++i) colj[i] -= colk[i] * ukj;
    }
  }
  return true;
}

namespace {

/// x = (P A)^-1 P b from the packed factors: SmallLU::solve's arithmetic in the same order, for
/// a size known at compile time. *Why:* for n = 5 the generic loops' trip-count tests and the
/// work buffer cost more than the 25 multiply-adds (12 % of a time step, docs/benchmark.md
/// session 17); unrolled, the solve is a straight dependency chain. The zero-skip of the
/// generic forward substitution is dropped: subtracting l_ij * 0 changes at most a zero's sign.
template <int N>
void solve_fixed(const double* lu, const int* perm, const double* b, double* x) {
  double y[N];
  for (int i = 0; i < N; ++i) y[i] = b[perm[i]];
  for (int j = 0; j < N; ++j) {  // forward substitution, unit-diagonal L (column-oriented)
    const double yj = y[j];
    const double* colj = lu + j * N;
    for (int i = j + 1; i < N; ++i) y[i] -= colj[i] * yj;
  }
  for (int j = N - 1; j >= 0; --j) {  // back substitution with U
    const double* colj = lu + j * N;
    y[j] /= colj[j];
    const double yj = y[j];
    for (int i = 0; i < j; ++i) y[i] -= colj[i] * yj;
  }
  for (int i = 0; i < N; ++i) x[i] = y[i];
}

using FixedSolve = void (*)(const double*, const int*, const double*, double*);

/// multiply_by_inverse through a function pointer (apply_inverse's kernel for n_).
template <int N>
void multiply_fixed(const double* inv, const double* b, double* x) {
  multiply_by_inverse<N>(inv, b, x);
}

using FixedMultiply = void (*)(const double*, const double*, double*);

/// The sizes with unrolled kernels: the torsional stage with 1-6 planets and up to two rig
/// machines (3-10 coordinates), the lateral-torsional one with 3-4 planets (18-23). One list
/// for both kernels, so that they cannot disagree.
template <int... N>
struct FixedSizes {
  static FixedSolve solve(int n) {
    FixedSolve f = nullptr;
    ((n == N ? (f = solve_fixed<N>, 0) : 0), ...);
    return f;
  }
  static FixedMultiply multiply(int n) {
    FixedMultiply f = nullptr;
    ((n == N ? (f = multiply_fixed<N>, 0) : 0), ...);
    return f;
  }
};
using UnrolledSizes = FixedSizes<3, 4, 5, 6, 7, 8, 9, 10, 18, 19, 20, 21, 22, 23>;

/// The unrolled kernels for size n, or nullptr.
FixedSolve fixed_solve_for(int n) { return UnrolledSizes::solve(n); }
FixedMultiply fixed_multiply_for(int n) { return UnrolledSizes::multiply(n); }

} // namespace

void SmallLU::resize(int n) {
  n_ = n;
  lu_.assign(static_cast<std::size_t>(n) * n, 0.0);
  perm_.assign(static_cast<std::size_t>(n), 0);
  work_.assign(static_cast<std::size_t>(n), 0.0);
  solve_kernel_ = fixed_solve_for(n);
  multiply_kernel_ = fixed_multiply_for(n);
}

void SmallLU::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  const int n = n_;
  if (solve_kernel_) {
    if (x.size() != n) x.resize(n);
    solve_kernel_(lu_.data(), perm_.data(), b.data(), x.data());  // x may alias b: the kernel reads b first
    return;
  }
  solve_generic(b, x);
}

void SmallLU::compute_inverse() {
  const int n = n_;
  inverse_.assign(static_cast<std::size_t>(n) * n, 0.0);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n), col(n);
  for (int j = 0; j < n; ++j) {
    e(j) = 1.0;
    solve(e, col);
    e(j) = 0.0;
    for (int i = 0; i < n; ++i) inverse_[static_cast<std::size_t>(i + j * n)] = col(i);
  }
}

void SmallLU::apply_inverse(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  const int n = n_;
  if (x.size() != n) x.resize(n);
  if (multiply_kernel_) {
    multiply_kernel_(inverse_.data(), b.data(), x.data());
    return;
  }
  const double* inv = inverse_.data();
  for (int i = 0; i < n; ++i) x(i) = inv[i] * b(0);
  for (int j = 1; j < n; ++j)
    for (int i = 0; i < n; ++i) x(i) += inv[i + j * n] * b(j);
}

void SmallLU::solve_generic(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  const int n = n_;
  const double* lu = lu_.data();
  double* y = work_.data();
  for (int i = 0; i < n; ++i) y[i] = b(perm_[i]);
  // Forward substitution with unit-diagonal L (column-oriented).
  for (int j = 0; j < n; ++j) {
    const double yj = y[j];
    if (yj == 0.0) continue;
    const double* colj = lu + j * n;
    for (int i = j + 1; i < n; ++i) y[i] -= colj[i] * yj;
  }
  // Back substitution with U.
  for (int j = n - 1; j >= 0; --j) {
    const double* colj = lu + j * n;
    y[j] /= colj[j];
    const double yj = y[j];
    for (int i = 0; i < j; ++i) y[i] -= colj[i] * yj;
  }
  if (x.size() != n) x.resize(n);
  for (int i = 0; i < n; ++i) x(i) = y[i];
}

} // namespace pw::dynamics
