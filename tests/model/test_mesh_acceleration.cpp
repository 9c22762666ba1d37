// The record loop's mesh acceleration g . a (src/model/simulation.cpp, mesh_acceleration) takes
// Eigen's fixed-size product for five coordinates on the premise that it sums in the same order
// as the dynamic-size product every other size keeps. Checked here, bit for bit, so that an Eigen
// whose reductions change order fails a test instead of moving the mesh acceleration channels.
#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <random>

namespace {

TEST(MeshAcceleration, FixedSizeFiveDotIsTheDynamicDotBitForBit) {
  constexpr int kDofs = 5;               // the three-planet torsional stage's coordinates
  constexpr int kDraws = 200000;         // random vector pairs
  constexpr int kBinades = 40;           // entries spread over 2^-20 .. 2^20: cancellation and rounding
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto entry = [&] { return std::ldexp(unit(rng), static_cast<int>(rng() % kBinades) - kBinades / 2); };
  using Vector5 = Eigen::Matrix<double, kDofs, 1>;
  long differing = 0;
  for (int i = 0; i < kDraws; ++i) {
    Eigen::VectorXd g(kDofs), a(kDofs);
    for (int k = 0; k < kDofs; ++k) {
      a(k) = entry();
      g(k) = rng() % 3 == 0 ? 0.0 : entry();  // a mesh row is sparse: zeros where it couples nothing
    }
    const double fixed = Eigen::Map<const Vector5>(g.data()).dot(Eigen::Map<const Vector5>(a.data()));
    if (std::bit_cast<std::uint64_t>(fixed) != std::bit_cast<std::uint64_t>(g.dot(a))) ++differing;
  }
  EXPECT_EQ(differing, 0) << "of " << kDraws;
}

} // namespace
