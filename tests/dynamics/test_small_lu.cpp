// SmallLU: the factorization the time step uses for its iteration matrix.
#include "dynamics/small_lu.hpp"

#include <gtest/gtest.h>

#include <random>

using pw::dynamics::SmallLU;

namespace {

/// A random n x n matrix with entries of mixed magnitude (1e-3 .. 1e3), as an
/// iteration matrix M + gamma dt C + beta dt^2 K has.
Eigen::MatrixXd mixed_matrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-3.0, 3.0);
  Eigen::MatrixXd a(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) a(i, j) = u(rng) * std::pow(10.0, e(rng));
  return a;
}

} // namespace

TEST(SmallLU, SolvesToTheBackwardErrorOfPartialPivoting) {
  // Backward stability of Gaussian elimination with partial pivoting (Golub &
  // Van Loan Thm 3.4.2): |A x - b| <= c n eps |A| |x| with a small growth
  // factor; 1e3 eps n is far above that and far below any real defect.
  for (int n : {1, 2, 5, 18, 40}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      const Eigen::MatrixXd a = mixed_matrix(n, seed);
      const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
      SmallLU lu(n);
      ASSERT_TRUE(lu.factorize(a));
      Eigen::VectorXd x;
      lu.solve(b, x);
      const double scale = a.cwiseAbs().maxCoeff() * x.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff();
      EXPECT_LE((a * x - b).lpNorm<Eigen::Infinity>(), 1e3 * n * 2.2e-16 * scale) << "n " << n << " seed " << seed;
    }
  }
}

TEST(SmallLU, PivotsWhenTheLeadingEntryIsZero) {
  // Without row exchanges the first pivot would be 0.
  Eigen::MatrixXd a(3, 3);
  a << 0, 1, 2, 1, 0, 3, 4, -3, 8;
  const Eigen::Vector3d x_true(1.0, -2.0, 0.5);
  SmallLU lu(3);
  ASSERT_TRUE(lu.factorize(a));
  Eigen::VectorXd x;
  lu.solve(a * x_true, x);
  EXPECT_NEAR((x - x_true).norm(), 0.0, 1e-14);
}

TEST(SmallLU, ReportsASingularMatrix) {
  Eigen::MatrixXd a(3, 3);
  a << 1, 2, 3, 2, 4, 6, 0, 0, 0;  // rank 1
  SmallLU lu(3);
  EXPECT_FALSE(lu.factorize(a));
}

TEST(SmallLU, SolveMayOverwriteItsRightHandSide) {
  const Eigen::MatrixXd a = mixed_matrix(6, 7);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(6);
  SmallLU lu(6);
  ASSERT_TRUE(lu.factorize(a));
  Eigen::VectorXd x;
  lu.solve(b, x);
  lu.solve(b, b);
  EXPECT_EQ((x - b).lpNorm<Eigen::Infinity>(), 0.0);
}

TEST(SmallLU, UnrolledSolveIsBitIdenticalToTheGenericLoops) {
  // solve() unrolls the sizes of the time step's iteration matrices; its arithmetic is the
  // generic loops' in the same order, so the two agree to the last bit (a round-off change
  // here would change every simulation's digits).
  for (int n : {3, 4, 5, 6, 7, 8, 9, 10, 18, 19, 20, 21, 22, 23}) {
    for (unsigned seed = 1; seed <= 4; ++seed) {
      const Eigen::MatrixXd a = mixed_matrix(n, 100 * seed + static_cast<unsigned>(n));
      const Eigen::VectorXd b = mixed_matrix(n, seed).col(0);
      SmallLU lu(n);
      ASSERT_TRUE(lu.factorize(a));
      Eigen::VectorXd x_fast, x_generic;
      lu.solve(b, x_fast);
      lu.solve_generic(b, x_generic);
      ASSERT_EQ(x_fast.size(), n);
      for (int i = 0; i < n; ++i) EXPECT_EQ(x_fast(i), x_generic(i)) << "n " << n << " seed " << seed << " i " << i;
    }
  }
}

TEST(SmallLU, AgreesWithEigensPartialPivLUOnWellConditionedMatrices) {
  // Diagonally dominant random matrices (condition number ~ 10): both factorizations are
  // backward stable, so the solutions agree to a few hundred ulp of |x|.
  for (int n : {3, 5, 8, 18, 23, 30}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      std::mt19937 rng(seed * 31 + static_cast<unsigned>(n));
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      Eigen::MatrixXd a(n, n);
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) a(i, j) = u(rng);
      a.diagonal().array() += 2.0 * n;
      Eigen::VectorXd b(n);
      for (int i = 0; i < n; ++i) b(i) = u(rng);
      SmallLU lu(n);
      ASSERT_TRUE(lu.factorize(a));
      Eigen::VectorXd x;
      lu.solve(b, x);
      const Eigen::VectorXd x_eigen = a.partialPivLu().solve(b);
      EXPECT_LE((x - x_eigen).lpNorm<Eigen::Infinity>(), 1e3 * 2.2e-16 * x_eigen.lpNorm<Eigen::Infinity>())
          << "n " << n << " seed " << seed;
    }
  }
}

TEST(SmallLU, ProductWithTheInverseSolvesLikeTheSubstitutions) {
  // apply_inverse (the chord iterations' x = A^-1 b) against the forward/back substitutions, on
  // the sizes it unrolls and on generic ones: the same solution to a few hundred ulp of |x| for
  // well-conditioned matrices, and the residual at the backward-error level.
  for (int n : {1, 2, 5, 11, 18, 23, 30}) {
    for (unsigned seed = 1; seed <= 5; ++seed) {
      Eigen::MatrixXd a = mixed_matrix(n, seed + 50);
      a.diagonal().array() += 2.0 * a.cwiseAbs().rowwise().sum().array();  // diagonally dominant
      const Eigen::VectorXd b = mixed_matrix(n, seed + 70).col(0);
      SmallLU lu(n);
      ASSERT_TRUE(lu.factorize(a));
      lu.compute_inverse();
      Eigen::VectorXd x_sub, x_inv;
      lu.solve(b, x_sub);
      lu.apply_inverse(b, x_inv);
      ASSERT_EQ(x_inv.size(), n);
      EXPECT_LE((x_inv - x_sub).lpNorm<Eigen::Infinity>(), 1e3 * 2.2e-16 * x_sub.lpNorm<Eigen::Infinity>())
          << "n " << n << " seed " << seed;
      const double scale = a.cwiseAbs().maxCoeff() * x_inv.cwiseAbs().maxCoeff() + b.cwiseAbs().maxCoeff();
      EXPECT_LE((a * x_inv - b).lpNorm<Eigen::Infinity>(), 1e3 * n * 2.2e-16 * scale) << "n " << n;
    }
  }
}
