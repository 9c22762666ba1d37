// Rank correlation (sweep/rank_correlation.hpp): Spearman's rho against closed
// forms; Iman-Conover keeps every column's values (a Latin hypercube stays one,
// one case per stratum) and brings the rank correlation to the target; invalid
// targets are rejected with the reason.
#include "sweep/design.hpp"

#include "core/error.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pw::sweep {
namespace {

SquareMatrix matrix(int d, std::vector<double> v) { return {d, std::move(v)}; }

TEST(Spearman, MonotoneColumnsCorrelateOneAndReversedMinusOne) {
  // Columns: x, exp(x) (monotone, nonlinear), -x^3 (reversed).
  std::vector<double> s;
  for (int i = 0; i < 20; ++i) {
    const double x = 0.37 * i - 2;
    s.insert(s.end(), {x, std::exp(x), -x * x * x});
  }
  const SquareMatrix r = spearman(s, 20, 3);
  EXPECT_NEAR(r(0, 1), 1.0, 1e-14);
  EXPECT_NEAR(r(0, 2), -1.0, 1e-14);
  EXPECT_NEAR(r(1, 2), -1.0, 1e-14);
  EXPECT_DOUBLE_EQ(r(1, 1), 1.0);
}

TEST(Spearman, TiesShareTheirAverageRankAsInTheTextbookExample) {
  // x = (1, 2, 2, 3), y = (1, 3, 2, 4): ranks x = (0, 1.5, 1.5, 3), y = (0, 2, 1, 3);
  // Pearson of the ranks = 4.5 / sqrt(4.5 * 5) = sqrt(0.9) (the untied formula
  // 1 - 6 sum d^2 / (n (n^2 - 1)) would give 1 - 6 * 0.5 / 60 = 0.95 instead).
  const SquareMatrix r = spearman({1, 1, 2, 3, 2, 2, 3, 4}, 4, 2);
  EXPECT_NEAR(r(0, 1), std::sqrt(0.9), 1e-14);
}

TEST(ImanConover, KeepsEveryStratumAndMeetsTheTarget) {
  const long long n = 2000;
  const int d = 3;
  std::vector<double> u = latin_hypercube_unit(n, d, 11);
  const SquareMatrix target = matrix(3, {1, 0.7, -0.4, 0.7, 1, 0, -0.4, 0, 1});
  const SquareMatrix before = spearman(u, n, d);
  impose_rank_correlation(u, n, d, target, 11);
  // Every stratum [k/n, (k+1)/n) of every column still holds exactly one value.
  for (int j = 0; j < d; ++j) {
    std::vector<int> hits(static_cast<std::size_t>(n), 0);
    for (long long i = 0; i < n; ++i) ++hits[static_cast<std::size_t>(u[i * d + j] * n)];
    EXPECT_EQ(*std::min_element(hits.begin(), hits.end()), 1) << "column " << j;
    EXPECT_EQ(*std::max_element(hits.begin(), hits.end()), 1) << "column " << j;
  }
  const SquareMatrix after = spearman(u, n, d);
  // The plain hypercube's spurious correlations are O(1/sqrt(n)) = 0.022; the imposed ones
  // meet the target to that order (the scores' Pearson correlation is the mapped target
  // exactly; the ranks' differs by sampling error).
  const double tol = 3 / std::sqrt(static_cast<double>(n));
  for (int i = 0; i < d; ++i)
    for (int j = i + 1; j < d; ++j) {
      EXPECT_LT(std::fabs(before(i, j)), tol) << i << "," << j;
      EXPECT_NEAR(after(i, j), target(i, j), tol) << i << "," << j;
    }
}

TEST(ImanConover, SameSeedSameRearrangement) {
  std::vector<double> a = latin_hypercube_unit(50, 2, 5), b = a;
  const SquareMatrix t = matrix(2, {1, 0.5, 0.5, 1});
  impose_rank_correlation(a, 50, 2, t, 5);
  impose_rank_correlation(b, 50, 2, t, 5);
  EXPECT_EQ(a, b);
}

TEST(ImanConover, InvalidTargetsAreRejectedWithTheReason) {
  EXPECT_EQ(correlation_matrix_problem(matrix(2, {1, 0.5, 0.5, 1})), "");
  EXPECT_TRUE(pw::test::contains(correlation_matrix_problem(matrix(2, {1, 0.5, 0.4, 1})), "not symmetric"));
  EXPECT_TRUE(pw::test::contains(correlation_matrix_problem(matrix(2, {2, 0.5, 0.5, 1})), "diagonal"));
  EXPECT_TRUE(pw::test::contains(correlation_matrix_problem(matrix(2, {1, 1.5, 1.5, 1})), "outside [-1, 1]"));
  // 0.9, 0.9, -0.9 among three variables is impossible.
  EXPECT_TRUE(pw::test::contains(correlation_matrix_problem(matrix(3, {1, 0.9, 0.9, 0.9, 1, -0.9, 0.9, -0.9, 1})),
                                 "positive definite"));
  std::vector<double> u = latin_hypercube_unit(2, 2, 1);
  const auto e = pw::test::thrown<InputError>(
      [&] { impose_rank_correlation(u, 2, 2, matrix(2, {1, 0.5, 0.5, 1}), 1); });
  ASSERT_TRUE(e);
  EXPECT_EQ(e->parameter(), "design.samples");
}

} // namespace
} // namespace pw::sweep
