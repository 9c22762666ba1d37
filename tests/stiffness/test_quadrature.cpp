// Gauss-Legendre rules (stiffness/quadrature.hpp) against Boost.Math's
// tabulated ones. *Why the project keeps its own:* the order is a run-time
// setting (MeshStiffnessOptions::quadrature_points), while
// boost::math::quadrature::gauss<double, N> fixes N at compile time; this test
// shows the two agree, so the choice costs nothing in accuracy.
#include "stiffness/quadrature.hpp"

#include <boost/math/quadrature/gauss.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>

namespace pw::stiffness {
namespace {

/// Boost stores the non-negative nodes (ascending) and their weights of the symmetric rule.
template <unsigned N>
void expect_same_rule() {
  using Boost = boost::math::quadrature::gauss<double, N>;
  const GaussLegendreRule ours = gauss_legendre(static_cast<int>(N));
  const auto& x = Boost::abscissa();
  const auto& w = Boost::weights();
  ASSERT_EQ(ours.size(), static_cast<int>(N));
  for (std::size_t k = 0; k < x.size(); ++k) {
    // Our nodes ascend over [-1, 1]: node N-1-k' mirrors. The positive node x_k is ours at (N-1)/2 + k
    // for odd N (x_0 = 0) and N/2 + k for even N.
    const std::size_t i = (N % 2 == 1) ? (N - 1) / 2 + k : N / 2 + k;
    EXPECT_NEAR(ours.nodes[i], x[k], 2e-15) << "N = " << N << ", node " << k;
    EXPECT_NEAR(ours.weights[i], w[k], 2e-15) << "N = " << N << ", weight " << k;
    EXPECT_NEAR(ours.nodes[N - 1 - i], -x[k], 2e-15) << "N = " << N << ", mirrored node " << k;
  }
}

TEST(GaussLegendre, NodesAndWeightsEqualBoostMathsTabulatedRules) {
  expect_same_rule<7>();
  expect_same_rule<10>();
  expect_same_rule<15>();
  expect_same_rule<20>();
  expect_same_rule<24>();  // the default order of the beam-energy integrals
  expect_same_rule<30>();
}

} // namespace
} // namespace pw::stiffness
