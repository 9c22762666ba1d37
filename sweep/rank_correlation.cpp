#include "rank_correlation.hpp"
#include "random_index.hpp"

#include "core/error.hpp"

#include <boost/math/distributions/normal.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>

namespace pw::sweep {
namespace {

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;


/// Ranks 0..n-1 of column j (ties: their average rank).
std::vector<double> ranks(const double* column, long long n, int stride) {
  std::vector<long long> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0LL);
  std::stable_sort(order.begin(), order.end(),
                   [&](long long a, long long b) { return column[a * stride] < column[b * stride]; });
  std::vector<double> r(static_cast<std::size_t>(n));
  for (long long k = 0; k < n;) {
    long long e = k + 1;
    while (e < n && column[order[e] * stride] == column[order[k] * stride]) ++e;
    const double average = 0.5 * static_cast<double>(k + e - 1);
    for (long long i = k; i < e; ++i) r[static_cast<std::size_t>(order[i])] = average;
    k = e;
  }
  return r;
}

Matrix to_matrix(const SquareMatrix& c) {
  Matrix m(c.size, c.size);
  for (int i = 0; i < c.size; ++i)
    for (int j = 0; j < c.size; ++j) m(i, j) = c(i, j);
  return m;
}

/// Pearson correlation of the columns of x (n x d).
Matrix pearson(const Matrix& x) {
  const Matrix centred = x.rowwise() - x.colwise().mean();
  Matrix cov = centred.transpose() * centred;
  const Eigen::VectorXd s = cov.diagonal().cwiseSqrt();
  for (int i = 0; i < cov.rows(); ++i)
    for (int j = 0; j < cov.cols(); ++j) cov(i, j) = (s(i) > 0 && s(j) > 0) ? cov(i, j) / (s(i) * s(j)) : (i == j);
  return cov;
}

} // namespace

std::string correlation_matrix_problem(const SquareMatrix& c) {
  const int d = c.size;
  std::ostringstream why;
  for (int i = 0; i < d; ++i) {
    if (c(i, i) != 1.0) {
      why << "diagonal entry [" << i << "][" << i << "] is " << c(i, i) << ", must be 1";
      return why.str();
    }
    for (int j = 0; j < d; ++j) {
      if (!(std::fabs(c(i, j)) <= 1.0)) {
        why << "entry [" << i << "][" << j << "] = " << c(i, j) << " is outside [-1, 1]";
        return why.str();
      }
      if (std::fabs(c(i, j) - c(j, i)) > 1e-12) {
        why << "not symmetric: [" << i << "][" << j << "] = " << c(i, j) << " but [" << j << "][" << i
            << "] = " << c(j, i);
        return why.str();
      }
    }
  }
  Eigen::LLT<Matrix> llt(to_matrix(c));
  if (llt.info() != Eigen::Success)
    return "not positive definite (no set of variables has these correlations; e.g. a strong positive "
           "correlation of A with B and of B with C forces one of A with C)";
  return "";
}

void impose_rank_correlation(std::vector<double>& unit, long long n, int d, const SquareMatrix& target,
                             std::uint64_t seed) {
  require(n > d, "design.samples", "a correlation needs more samples than factors (", d, "), got ", n);
  // (1) Scores in independent random orders (a stream of its own: the unit sample's stays as it was).
  std::vector<double> scores(static_cast<std::size_t>(n));
  const boost::math::normal_distribution<> standard;
  for (long long k = 0; k < n; ++k)
    scores[static_cast<std::size_t>(k)] =
        boost::math::quantile(standard, static_cast<double>(k + 1) / static_cast<double>(n + 1));
  std::mt19937_64 engine(seed ^ 0x5851f42d4c957f2dULL);
  Matrix R(n, d);
  for (int j = 0; j < d; ++j) {
    std::vector<double> col = scores;
    shuffle(col, engine);
    for (long long i = 0; i < n; ++i) R(i, j) = col[static_cast<std::size_t>(i)];
  }
  // (2), (3) R* = R E^-T P^T.
  const Eigen::LLT<Matrix> t(pearson(R));
  require(t.info() == Eigen::Success, "design.samples", "the ", n,
          " samples' scores are too few to carry the correlation; take more samples");
  // The scores are normal, and for normal variables Spearman's rho_S and Pearson's rho are
  // related by rho = 2 sin(pi rho_S / 6) (Pearson 1907; Kruskal 1958): the target of the
  // scores' Pearson correlation is that of the ranks mapped through it, so that the
  // design's rank correlation -- what the user gave and what is printed -- meets the target.
  // Should the mapped matrix lose positive definiteness, the target itself is used.
  Matrix scores_target = to_matrix(target);
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j)
      if (i != j) scores_target(i, j) = 2 * std::sin(std::numbers::pi * target(i, j) / 6);
  Eigen::LLT<Matrix> p(scores_target);
  if (p.info() != Eigen::Success) p.compute(to_matrix(target));
  const Matrix E = t.matrixL(), P = p.matrixL();
  const Matrix S = P * E.inverse();  // R* = R S^T
  const Matrix Rstar = R * S.transpose();
  // (4) Rearrange each column of the sample to R*'s ranks.
  for (int j = 0; j < d; ++j) {
    std::vector<double> sorted(static_cast<std::size_t>(n));
    for (long long i = 0; i < n; ++i) sorted[static_cast<std::size_t>(i)] = unit[static_cast<std::size_t>(i * d + j)];
    std::sort(sorted.begin(), sorted.end());
    std::vector<long long> order(static_cast<std::size_t>(n));  // rows by ascending R*(., j)
    std::iota(order.begin(), order.end(), 0LL);
    std::stable_sort(order.begin(), order.end(), [&](long long a, long long b) { return Rstar(a, j) < Rstar(b, j); });
    for (long long k = 0; k < n; ++k)
      unit[static_cast<std::size_t>(order[static_cast<std::size_t>(k)] * d + j)] = sorted[static_cast<std::size_t>(k)];
  }
}

SquareMatrix spearman(const std::vector<double>& sample, long long n, int d) {
  Matrix r(n, d);
  for (int j = 0; j < d; ++j) {
    const std::vector<double> rk = ranks(sample.data() + j, n, d);
    for (long long i = 0; i < n; ++i) r(i, j) = rk[static_cast<std::size_t>(i)];
  }
  const Matrix c = pearson(r);
  SquareMatrix out{d, std::vector<double>(static_cast<std::size_t>(d) * d)};
  for (int i = 0; i < d; ++i)
    for (int j = 0; j < d; ++j) out.values[static_cast<std::size_t>(i) * d + j] = c(i, j);
  return out;
}

} // namespace pw::sweep
