// The Lin & Parker (1999) reference model (lin_parker_reference.hpp) against
// the paper's published example: natural frequencies within 0.1%, and the
// mode structure the paper proves (rotational modes simple, translational
// modes double, planet modes of multiplicity N - 3).
#include "dynamics/lin_parker_reference.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

namespace {

namespace lp = pw::test::lin_parker;

// Lin & Parker 1999, example system with three planets [Hz].
constexpr double kRotational_Hz[] = {0.0, 1475.7, 1930.3, 2658.3, 7462.8, 11775.3};
constexpr double kTranslational_Hz[] = {743.2, 1102.4, 1896.0, 2276.4, 6986.3, 9647.9};
constexpr double kRelTol = 1e-3;  // the 0.1%; the table has 5 significant figures

enum class ModeType { Rotational, Translational, Planet, Mixed };

const char* name(ModeType t) {
  switch (t) {
    case ModeType::Rotational: return "rotational";
    case ModeType::Translational: return "translational";
    case ModeType::Planet: return "planet";
    case ModeType::Mixed: return "mixed";
  }
  return "?";
}

// Classifies a (possibly degenerate) group by which coordinates its modes
// use, following the paper's three mode types.
ModeType classify(const lp::ModeGroup& g, std::size_t planets) {
  const Eigen::MatrixXd& V = g.shapes;
  const double scale = V.cwiseAbs().maxCoeff();
  const double tol = 1e-7 * scale;
  double central_translation = 0, central_rotation = 0;
  for (Eigen::Index body : {lp::kCarrier, lp::kRing, lp::kSun}) {
    central_translation = std::max(central_translation, V.middleRows(body, 2).cwiseAbs().maxCoeff());
    central_rotation = std::max(central_rotation, V.row(body + 2).cwiseAbs().maxCoeff());
  }
  // Rotational: all planets move alike (the paper's "in-phase" planet motion).
  double planet_spread = 0;
  for (std::size_t n = 1; n < planets; ++n)
    planet_spread = std::max(planet_spread, (V.middleRows(lp::planet_offset(n), 3) -
                                             V.middleRows(lp::planet_offset(0), 3))
                                                .cwiseAbs()
                                                .maxCoeff());
  if (central_translation < tol && central_rotation < tol) return ModeType::Planet;
  if (central_translation < tol && planet_spread < tol && g.multiplicity == 1)
    return ModeType::Rotational;
  if (central_rotation < tol && g.multiplicity == 2) return ModeType::Translational;
  return ModeType::Mixed;
}

TEST(LinParkerReference, BlockMatricesEqualTheDeflectionEnergyAssembly) {
  for (int planets : {3, 4, 5}) {
    const auto p = lp::table1_example(planets);
    const Eigen::MatrixXd K_blocks = lp::stiffness_matrix(p);
    const Eigen::MatrixXd K_energy = lp::stiffness_from_deflections(p);
    const double diff = (K_blocks - K_energy).cwiseAbs().maxCoeff();
    EXPECT_LT(diff, 1e-12 * K_energy.cwiseAbs().maxCoeff()) << planets << " planets";
    EXPECT_LT((K_blocks - K_blocks.transpose()).cwiseAbs().maxCoeff(), 1e-6) << "K not symmetric";
  }
}

TEST(LinParkerReference, ExampleSystemMatchesPublishedFrequenciesWithinPointOnePercent) {
  const auto p = lp::table1_example(3);
  const auto groups = lp::natural_modes(lp::mass_matrix(p), lp::stiffness_matrix(p));

  std::vector<const lp::ModeGroup*> rotational, translational;
  int planet_mode_groups = 0, total = 0;
  for (const auto& g : groups) {
    total += g.multiplicity;
    switch (classify(g, p.psi.size())) {
      case ModeType::Rotational: rotational.push_back(&g); break;
      case ModeType::Translational: translational.push_back(&g); break;
      case ModeType::Planet: ++planet_mode_groups; break;
      case ModeType::Mixed:
        ADD_FAILURE() << "mode group at " << g.frequency_Hz << " Hz (multiplicity "
                      << g.multiplicity << ") fits none of the paper's mode types";
    }
  }
  EXPECT_EQ(total, 18);
  EXPECT_EQ(planet_mode_groups, 0) << "N = 3: planet modes have multiplicity N - 3 = 0";
  ASSERT_EQ(rotational.size(), std::size(kRotational_Hz));
  ASSERT_EQ(translational.size(), std::size(kTranslational_Hz));

  std::cout << "  Lin & Parker 1999, 3 planets   computed [Hz]   published [Hz]   rel. diff\n";
  auto check = [](const char* type, const lp::ModeGroup& g, double published) {
    const double rel = published > 0 ? (g.frequency_Hz - published) / published : 0.0;
    std::cout << "  " << std::left << std::setw(14) << type << " x" << g.multiplicity
              << std::right << std::fixed << std::setprecision(2) << std::setw(26)
              << g.frequency_Hz << std::setw(17) << std::setprecision(1) << published
              << std::setw(12) << std::scientific << std::setprecision(1) << rel << "\n"
              << std::defaultfloat;
    if (published == 0)
      EXPECT_LT(g.frequency_Hz, 1e-3) << "rigid-body mode (k_su = k_cu = 0)";
    else
      EXPECT_NEAR(g.frequency_Hz, published, kRelTol * published) << type << " mode";
  };
  for (std::size_t i = 0; i < rotational.size(); ++i) {
    check("rotational", *rotational[i], kRotational_Hz[i]);
    EXPECT_EQ(rotational[i]->multiplicity, 1);
  }
  for (std::size_t i = 0; i < translational.size(); ++i) {
    check("translational", *translational[i], kTranslational_Hz[i]);
    EXPECT_EQ(translational[i]->multiplicity, 2);
  }
}

TEST(LinParkerReference, ModeStructureHoldsForMorePlanets) {
  // The paper's theorem: for N equally spaced planets there are 6 rotational
  // (simple), 6 translational (double) and 3 planet modes of multiplicity
  // N - 3, and nothing else.
  for (int planets : {4, 5, 6}) {
    const auto p = lp::table1_example(planets);
    const auto groups = lp::natural_modes(lp::mass_matrix(p), lp::stiffness_matrix(p));
    int rot = 0, trans = 0, planet = 0;
    for (const auto& g : groups) {
      switch (classify(g, p.psi.size())) {
        case ModeType::Rotational: ++rot; break;
        case ModeType::Translational: ++trans; break;
        case ModeType::Planet:
          ++planet;
          EXPECT_EQ(g.multiplicity, planets - 3) << planets << " planets, " << g.frequency_Hz << " Hz";
          break;
        case ModeType::Mixed:
          ADD_FAILURE() << planets << " planets: group at " << g.frequency_Hz << " Hz (x"
                        << g.multiplicity << ") is " << name(ModeType::Mixed);
      }
    }
    EXPECT_EQ(rot, 6) << planets << " planets";
    EXPECT_EQ(trans, 6) << planets << " planets";
    EXPECT_EQ(planet, 3) << planets << " planets";
  }
}

} // namespace
