#include "diagnose/planet_pattern.hpp"

#include "core/error.hpp"
#include "core/format.hpp"
#include "core/statistics.hpp"

#include <algorithm>
#include <cmath>

namespace pw::diagnose {

int planet_pattern_order(int mesh_harmonic, int sun_teeth, int planets) {
  require(mesh_harmonic >= 1 && sun_teeth >= 1 && planets >= 1, "planet pattern order",
          "needs h >= 1, Zs >= 1 and N >= 1, got h = ", mesh_harmonic, ", Zs = ", sun_teeth, ", N = ", planets);
  const long long r = (static_cast<long long>(mesh_harmonic) * sun_teeth) % planets;
  return static_cast<int>(std::min<long long>(r, planets - r));
}

PlanetPattern planet_pattern(const std::vector<MeshHarmonicCell>& cells, const Kinematics& kin, double alpha) {
  PlanetPattern p;
  const int n = kin.planets, zs = kin.sun_teeth;
  if (n < 2 || zs < 1 || zs % n == 0 || cells.empty()) return p;
  p.applies = true;
  for (int k = 0; k <= n / 2; ++k) p.orders.push_back({k, 0.0, 0, 0.0, {}});
  p.significance_z = normal_quantile(alpha / static_cast<double>(p.orders.size()));
  for (const MeshHarmonicCell& c : cells) {
    PatternOrderExcess& o = p.orders[static_cast<std::size_t>(planet_pattern_order(c.harmonic, zs, n))];
    o.excess += c.excess[0] + c.excess[1];
    o.cells += 2;
    if (std::find(o.harmonics.begin(), o.harmonics.end(), c.harmonic) == o.harmonics.end()) o.harmonics.push_back(c.harmonic);
  }
  // rho^2 - 1 has mean 0 and variance 2 per cell for Gaussian residuals (locate.hpp, step 1).
  for (PatternOrderExcess& o : p.orders) {
    std::sort(o.harmonics.begin(), o.harmonics.end());
    o.z = o.cells > 0 ? o.excess / std::sqrt(2.0 * o.cells) : 0.0;
  }
  return p;
}

std::string planet_pattern_text(const PlanetPattern& p) {
  if (!p.applies) return "";
  // Presentation only: the first few harmonics of each order (report.json lists them all).
  constexpr std::size_t kHarmonicsNamed = 4;
  std::string orders;
  int highest = -1;
  for (const PatternOrderExcess& o : p.orders) {
    if (!(o.z > p.significance_z)) continue;
    highest = o.order;
    std::string hs;
    for (std::size_t i = 0; i < o.harmonics.size() && i < kHarmonicsNamed; ++i)
      hs += (hs.empty() ? "" : ", ") + std::to_string(o.harmonics[i]);
    if (o.harmonics.size() > kHarmonicsNamed) hs += ", ...";
    orders += (orders.empty() ? "" : ", ") + std::string("k = ") + std::to_string(o.order) + " (h " + hs +
              "; z = " + fmt("%.1f", o.z) + ")";
  }
  if (highest < 0) return "";
  std::string s = "; by the planets' mesh phasing the speed channels' mesh-harmonic excess needs a planet pattern of order " +
                  orders;
  if (highest == 0) return s + ": a change every planet shares";
  s += ": the planets do not share the mesh excitation equally";
  return s + (highest >= 2 ? ", and not in a first-order pattern alone (a carrier runout makes k = 1 only)"
                           : ", a first-order pattern (as a carrier runout makes)");
}

} // namespace pw::diagnose
