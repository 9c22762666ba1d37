#include "dynamics/small_lu.hpp"

#include <cmath>
#include <utility>

namespace pw::dynamics {

void SmallLU::resize(int n) {
  n_ = n;
  lu_.assign(static_cast<std::size_t>(n) * n, 0.0);
  perm_.assign(static_cast<std::size_t>(n), 0);
  work_.assign(static_cast<std::size_t>(n), 0.0);
}

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

void SmallLU::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
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
