#include "sobol.hpp"

#include <boost/random/sobol.hpp>

#include <stdexcept>
#include <string>

namespace pw::sweep {
namespace {

// 32-bit direction numbers, as in Joe & Kuo's reference program.
using BoostSobol = boost::random::sobol_engine<std::uint32_t, 32>;
static_assert(SobolSequence::kMaxDimensions <= boost::random::default_sobol_table::max_dimension,
              "the Sobol' table of Boost.Random is smaller than SobolSequence::kMaxDimensions");

} // namespace

SobolSequence::SobolSequence(int dimensions) : dimensions_(dimensions) {
  if (dimensions < 1 || dimensions > kMaxDimensions)
    throw std::invalid_argument("Sobol sequence: " + std::to_string(dimensions) + " dimensions requested, 1.." +
                                std::to_string(kMaxDimensions) + " available");
}

std::vector<std::uint32_t> SobolSequence::point_bits(std::uint64_t index) const {
  if (index >= kMaxPoints)
    throw std::out_of_range("Sobol sequence: point " + std::to_string(index) + " beyond the 2^32 points available");
  std::vector<std::uint32_t> x(static_cast<std::size_t>(dimensions_), 0);
  if (index == 0) return x;  // the origin, which Boost's sequence leaves out
  // Boost's point k is the (k + 1)-th point of the Gray-code sequence: seek, then read one vector.
  BoostSobol engine(static_cast<std::size_t>(dimensions_));
  engine.seed(static_cast<std::uint32_t>(index - 1));
  for (auto& v : x) v = engine();
  return x;
}

std::vector<double> SobolSequence::point(std::uint64_t index) const {
  const auto bits = point_bits(index);
  std::vector<double> x(bits.size());
  for (std::size_t j = 0; j < bits.size(); ++j) x[j] = static_cast<double>(bits[j]) * 0x1p-32;
  return x;
}

} // namespace pw::sweep
