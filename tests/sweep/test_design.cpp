// Designs of experiments: case order and values of every design type, the
// stratification of Latin hypercubes, the A/B/AB_i structure of Saltelli
// designs (and that its estimators recover the Ishigami function's known
// Sobol' indices), CSV case lists, and every rejection with the key named.
#include "sweep/design.hpp"

#include "core/error.hpp"
#include "io/test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>
#include <string>
#include <vector>

namespace pw::sweep {
namespace {

using pw::test::contains;
using pw::test::thrown;

Factor ranged(std::string key, double lo, double hi, Scale scale = Scale::Linear) {
  Factor f;
  f.key = std::move(key);
  f.unit = "-";
  f.min = lo;
  f.max = hi;
  f.scale = scale;
  return f;
}

Factor leveled(std::string key, std::vector<double> levels) {
  Factor f;
  f.key = std::move(key);
  f.unit = "-";
  f.levels = std::move(levels);
  return f;
}

/// make_design() throws InputError naming `param` with `text` in the message.
::testing::AssertionResult rejected(const std::vector<Factor>& factors, const DesignSpec& spec,
                                    const std::string& param, const std::string& text) {
  const auto e = thrown<InputError>([&] { (void)make_design(factors, spec); });
  if (!e) return ::testing::AssertionFailure() << "accepted; expected an error naming " << param;
  if (e->parameter() != param)
    return ::testing::AssertionFailure() << "named '" << e->parameter() << "' instead of '" << param << "': " << e->what();
  return contains(e->what(), text);
}

TEST(FullFactorial, FirstFactorVariesSlowest) {
  DesignSpec spec;
  spec.type = DesignType::FullFactorial;
  const auto cases = make_design({leveled("a", {1, 2}), leveled("b", {10, 20, 30})}, spec);
  ASSERT_EQ(cases.size(), 6u);
  const double expected[6][2] = {{1, 10}, {1, 20}, {1, 30}, {2, 10}, {2, 20}, {2, 30}};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(cases[i].values, (std::vector<double>{expected[i][0], expected[i][1]})) << "case " << i;
    EXPECT_EQ(cases[i].role, "");
    EXPECT_EQ(cases[i].row, -1);
  }
}

TEST(FullFactorial, PointsSpanTheBoundsExactlyOnLinearAndLogScales) {
  DesignSpec spec;
  spec.type = DesignType::FullFactorial;
  spec.points = 3;
  const auto cases = make_design({ranged("lin", 0.1, 0.3), ranged("log", 1e-17, 1e-15, Scale::Log)}, spec);
  ASSERT_EQ(cases.size(), 9u);
  EXPECT_EQ(cases[0].values[0], 0.1);
  EXPECT_DOUBLE_EQ(cases[3].values[0], 0.2);
  EXPECT_EQ(cases[8].values[0], 0.3);
  EXPECT_EQ(cases[0].values[1], 1e-17);
  EXPECT_NEAR(cases[1].values[1], 1e-16, 1e-16 * 1e-12);  // geometric midpoint
  EXPECT_EQ(cases[2].values[1], 1e-15);
}

TEST(FullFactorial, IntegerKeysTakeWholeLevelsOnly) {
  DesignSpec spec;
  spec.type = DesignType::FullFactorial;
  Factor f = leveled("stage.planet_count", {3, 6.5});
  f.integer = true;
  EXPECT_TRUE(rejected({f}, spec, "factors[0].levels", "must be a whole number, got 6.5"));
  Factor g = ranged("solver.record_mesh_cycles", 1, 3);
  g.integer = true;
  g.points = 5;  // 1, 1.5, 2, 2.5, 3 -> repeated whole numbers
  EXPECT_TRUE(rejected({g}, spec, "factors[0].points", "repeat the level"));
  g.points = 3;
  const auto cases = make_design({g}, spec);
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_EQ(cases[1].values[0], 2.0);
}

TEST(FullFactorial, RejectionsNameTheCampaignKey) {
  DesignSpec spec;
  spec.type = DesignType::FullFactorial;
  spec.points = 3;
  EXPECT_TRUE(rejected({ranged("a", 400, 100)}, spec, "factors[0].max", "bounds reversed"));
  EXPECT_TRUE(rejected({ranged("a", 100, 100)}, spec, "factors[0].max", "a fixed value belongs in [base.set]"));
  Factor outside = ranged("a", 100, 400);
  outside.levels = {100, 500};
  EXPECT_TRUE(rejected({outside}, spec, "factors[0].levels", "is above max = 400"));
  EXPECT_TRUE(rejected({leveled("a", {1, 2, 1})}, spec, "factors[0].levels", "listed twice"));
  EXPECT_TRUE(rejected({ranged("a", 0, 1, Scale::Log)}, spec, "factors[0].min", "needs min > 0"));
  spec.points = 0;
  EXPECT_TRUE(rejected({ranged("a", 1, 2)}, spec, "factors[0].levels", "needs levels = [...] or min, max and points"));
  EXPECT_TRUE(rejected({}, spec, "factors", "at least one"));
}

TEST(LatinHypercube, OnePointInEachStratumOfEveryFactor) {
  const long long n = 50;
  const int d = 3;
  const auto u = latin_hypercube_unit(n, d, 42);
  ASSERT_EQ(u.size(), static_cast<std::size_t>(n * d));
  for (int j = 0; j < d; ++j) {
    std::set<long long> strata;
    for (long long i = 0; i < n; ++i) {
      const double x = u[static_cast<std::size_t>(i * d + j)];
      ASSERT_GE(x, 0.0);
      ASSERT_LT(x, 1.0);
      strata.insert(static_cast<long long>(std::floor(x * n)));
    }
    EXPECT_EQ(strata.size(), static_cast<std::size_t>(n)) << "factor " << j;
  }
}

TEST(LatinHypercube, SameSeedSameDesignOtherSeedOtherDesign) {
  EXPECT_EQ(latin_hypercube_unit(16, 3, 7), latin_hypercube_unit(16, 3, 7));
  EXPECT_NE(latin_hypercube_unit(16, 3, 7), latin_hypercube_unit(16, 3, 8));
}

TEST(LatinHypercube, LogScaleStratifiesTheLogarithm) {
  DesignSpec spec;
  spec.type = DesignType::LatinHypercube;
  spec.samples = 20;
  spec.seed = 1;
  const auto cases = make_design({ranged("k", 2e-17, 1e-16, Scale::Log), ranged("s", 150, 400)}, spec);
  ASSERT_EQ(cases.size(), 20u);
  std::set<int> strata;
  for (const auto& c : cases) {
    const double k = c.values[0];
    ASSERT_GE(k, 2e-17);
    ASSERT_LE(k, 1e-16);
    strata.insert(static_cast<int>(std::floor(20 * std::log(k / 2e-17) / std::log(5.0))));
  }
  EXPECT_EQ(strata.size(), 20u);
}

TEST(LatinHypercube, RejectsNoSamplesMissingBoundsAndLevels) {
  DesignSpec spec;
  spec.type = DesignType::LatinHypercube;
  spec.samples = 0;
  EXPECT_TRUE(rejected({ranged("a", 1, 2)}, spec, "design.samples", "must be > 0"));
  spec.samples = 4;
  Factor f = ranged("a", 1, 2);
  f.max.reset();
  EXPECT_TRUE(rejected({f}, spec, "factors[0].max", "needs bounds"));
  EXPECT_TRUE(rejected({leveled("a", {1, 2})}, spec, "factors[0].levels", "only used by full_factorial"));
}

TEST(Saltelli, CasesAreAThenABiThenBPerRow) {
  DesignSpec spec;
  spec.type = DesignType::Saltelli;
  spec.base_samples = 8;
  const std::vector<Factor> f = {ranged("a", 0, 1), ranged("b", 10, 20), ranged("c", 1, 100, Scale::Log)};
  const auto cases = make_design(f, spec);
  const int d = 3;
  ASSERT_EQ(cases.size(), static_cast<std::size_t>(8 * (d + 2)));
  for (long long j = 0; j < 8; ++j) {
    const auto at = static_cast<std::size_t>(j * (d + 2));
    const DesignPoint& A = cases[at];
    const DesignPoint& B = cases[at + d + 1];
    EXPECT_EQ(A.role, "A");
    EXPECT_EQ(B.role, "B");
    for (int i = 0; i < d; ++i) {
      const DesignPoint& AB = cases[at + 1 + static_cast<std::size_t>(i)];
      EXPECT_EQ(AB.role, "AB_" + std::to_string(i));
      EXPECT_EQ(AB.row, j);
      for (int k = 0; k < d; ++k) EXPECT_EQ(AB.values[k], k == i ? B.values[k] : A.values[k]) << "AB_" << i;
    }
    EXPECT_EQ(A.row, j);
    EXPECT_EQ(B.row, j);
  }
  // Without a seed, row 0 is the origin (every minimum) and row 1 Sobol'
  // point 1 = (1/2, ..., 1/2): the middle of every range.
  EXPECT_EQ(cases[0].values, (std::vector<double>{0.0, 10.0, 1.0}));
  EXPECT_EQ(cases[d + 2].values[0], 0.5);
  EXPECT_EQ(cases[d + 2].values[1], 15.0);
  EXPECT_NEAR(cases[d + 2].values[2], 10.0, 1e-12);
}

TEST(Saltelli, SeedShiftsTheSequenceDigitally) {
  const auto plain = saltelli_unit(16, 2, 0), shifted = saltelli_unit(16, 2, 5);
  EXPECT_NE(plain.A, shifted.A);
  EXPECT_NE(shifted.A[0], 0.0);
  // A digital shift keeps the stratification of the first 16 points of every
  // column of A and B.
  for (const auto* m : {&plain.A, &plain.B, &shifted.A, &shifted.B})
    for (int k = 0; k < 2; ++k) {
      std::set<int> strata;
      for (int j = 0; j < 16; ++j) strata.insert(static_cast<int>((*m)[static_cast<std::size_t>(2 * j + k)] * 16));
      EXPECT_EQ(strata.size(), 16u) << "column " << k;
    }
}

TEST(Saltelli, EstimatorsRecoverTheIshigamiIndices) {
  // Ishigami function on [-pi, pi]^3, a = 7, b = 0.1: analytic first-order
  // indices S = (0.3139, 0.4424, 0) and total indices ST = (0.5576, 0.4424,
  // 0.2437) (Saltelli et al. 2010, Sobol' & Levitan 1999).
  const double pi = std::numbers::pi;
  DesignSpec spec;
  spec.type = DesignType::Saltelli;
  spec.base_samples = 4096;
  const std::vector<Factor> f = {ranged("x1", -pi, pi), ranged("x2", -pi, pi), ranged("x3", -pi, pi)};
  const auto cases = make_design(f, spec);
  auto y = [](const DesignPoint& p) {
    const double x1 = p.values[0], x2 = p.values[1], x3 = p.values[2];
    return std::sin(x1) + 7 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
  };
  const int d = 3;
  const auto N = static_cast<std::size_t>(spec.base_samples);
  const double n = static_cast<double>(N);
  std::vector<double> fA(N), fB(N), fAB(N * d);
  for (std::size_t j = 0; j < N; ++j) {
    fA[j] = y(cases[j * (d + 2)]);
    for (int i = 0; i < d; ++i) fAB[j * d + i] = y(cases[j * (d + 2) + 1 + i]);
    fB[j] = y(cases[j * (d + 2) + d + 1]);
  }
  double mean = 0, var = 0;
  for (std::size_t j = 0; j < N; ++j) mean += (fA[j] + fB[j]) / (2 * n);
  for (std::size_t j = 0; j < N; ++j) var += ((fA[j] - mean) * (fA[j] - mean) + (fB[j] - mean) * (fB[j] - mean)) / (2 * n);
  const double S[3] = {0.3139, 0.4424, 0.0}, ST[3] = {0.5576, 0.4424, 0.2437};
  for (int i = 0; i < d; ++i) {
    double first = 0, total = 0;
    for (std::size_t j = 0; j < N; ++j) {
      first += fB[j] * (fAB[j * d + i] - fA[j]) / n;                                   // Saltelli 2010 (b)
      total += (fA[j] - fAB[j * d + i]) * (fA[j] - fAB[j * d + i]) / (2 * n);      // Jansen 1999 (f)
    }
    EXPECT_NEAR(first / var, S[i], 0.03) << "first-order index of x" << i + 1;
    EXPECT_NEAR(total / var, ST[i], 0.03) << "total index of x" << i + 1;
  }
}

TEST(Saltelli, RejectsNoSamplesAndTooManyFactors) {
  DesignSpec spec;
  spec.type = DesignType::Saltelli;
  spec.base_samples = 0;
  EXPECT_TRUE(rejected({ranged("a", 0, 1)}, spec, "design.base_samples", "must be > 0"));
  spec.base_samples = 4;
  std::vector<Factor> many;
  for (int i = 0; i < 1834; ++i) many.push_back(ranged(std::to_string(i), 0, 1));
  EXPECT_TRUE(rejected(many, spec, "factors", "at most 1833 factors"));
}

TEST(CaseList, RowsInFileOrderColumnsInFactorOrder) {
  DesignSpec spec;
  spec.type = DesignType::List;
  spec.list_name = "cases.csv";
  spec.list_text = "# comment\nb, a\n2, 1\n\n20,10\n\"3\",1.5e2\n";
  const auto cases = make_design({ranged("a", 0, 1000), ranged("b", 0, 1000)}, spec);
  ASSERT_EQ(cases.size(), 3u);
  EXPECT_EQ(cases[0].values, (std::vector<double>{1, 2}));
  EXPECT_EQ(cases[1].values, (std::vector<double>{10, 20}));
  EXPECT_EQ(cases[2].values, (std::vector<double>{150, 3}));
}

TEST(CaseList, RejectionsNameFileLineAndColumn) {
  DesignSpec spec;
  spec.type = DesignType::List;
  spec.list_name = "cases.csv";
  const std::vector<Factor> f = {ranged("a", 0, 10), ranged("b", 0, 10)};
  spec.list_text = "a,b,c\n1,2,3\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "cases.csv:1: column 'c' is not a factor"));
  spec.list_text = "a\n1\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "no column for factor 'b'"));
  spec.list_text = "a,b\n1,x\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "cases.csv:2: 'x' in column b is not a number"));
  spec.list_text = "a,b\n1\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "cases.csv:2: 1 values, the header has 2 columns"));
  spec.list_text = "a,b\n1,20\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "is above max = 10"));
  spec.list_text = "a,b\n";
  EXPECT_TRUE(rejected(f, spec, "design.file", "zero cases"));
}

} // namespace
} // namespace pw::sweep
