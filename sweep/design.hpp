// Designs of experiments over campaign factors (pure: no MPI, no files).
//
// A factor is one configuration key varied over a range or a list of levels;
// a design turns the factors into an ordered list of cases (one value per
// factor each). Types (docs/campaigns.md):
//
//   full_factorial  every combination of the factors' levels; the first factor
//                   varies slowest (like itertools.product). Levels are the
//                   factor's `levels`, else `points` values from min to max
//                   (equally spaced, or geometrically for scale = "log").
//   list            the rows of a CSV table whose header names the factors.
//   latin_hypercube `samples` cases, one in each of `samples` equal strata per
//                   factor (McKay, Beckman & Conover 1979): for each factor j a
//                   random permutation pi_j, u_ij = (pi_j(i) + U_ij) / n.
//   saltelli        the Saltelli (2010) sampling scheme for first-order and
//                   total Sobol' indices: a Sobol' sequence in 2d dimensions
//                   gives two N x d matrices A (columns 0..d-1) and B (d..2d-1),
//                   and AB_i = A with column i taken from B; N (d + 2) cases
//                   ordered per row j as A_j, AB_0,j, ..., AB_(d-1),j, B_j (the
//                   layout of SALib's sobol sampler with calc_second_order =
//                   False, so SALib's analyzer can use the results directly).
//                   Rows are Sobol' points 0..N-1, so N = 2^m gives balanced
//                   samples (each factor's range split into N equal strata,
//                   one point in each; not dropping the first point keeps this,
//                   Owen 2020). A non-zero seed applies a random digital
//                   shift (XOR with one random 32-bit word per dimension),
//                   which keeps the net properties and moves row 0 off the
//                   origin (seed = 0: row 0 is every factor's minimum).
//
// Unit-cube values u in [0, 1) map to a factor as min + u (max - min), or
// exp(ln min + u (ln max - ln min)) for scale = "log", or through the inverse
// CDF of the factor's distribution (distribution.hpp: normal, lognormal,
// triangular). A latin_hypercube may be given a target rank correlation
// (rank_correlation.hpp, Iman & Conover 1982). Values of integer keys
// are rounded to the nearest whole number (ties away from zero).
//
// Reference: A. Saltelli et al., "Variance based sensitivity analysis of model
// output. Design and estimator for the total sensitivity index", Computer
// Physics Communications 181 (2010) 259-270, doi:10.1016/j.cpc.2009.09.018.
//
// Random numbers: std::mt19937_64 (its output sequence is fixed by the C++
// standard) turned into doubles and bounded integers by the code in
// design.cpp, so a seed gives the same design with every compiler.
#pragma once

#include "distribution.hpp"
#include "rank_correlation.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pw::sweep {

enum class Scale { Linear, Log };

/// One varied configuration key.
struct Factor {
  std::string key;              ///< config key path, e.g. "operating.input_speed_rpm"
  std::string unit;             ///< the key's documented unit, e.g. "rpm"
  std::optional<double> min;    ///< lower bound, in `unit`
  std::optional<double> max;    ///< upper bound, in `unit`
  std::vector<double> levels;   ///< explicit levels (full_factorial only)
  std::optional<int> points;    ///< levels between min and max (full_factorial; default design.points)
  Scale scale = Scale::Linear;
  /// latin_hypercube, saltelli: the values' distribution (uniform over [min, max] by
  /// default; normal and lognormal are truncated to min/max when given).
  Distribution distribution;
  bool integer = false;         ///< the key takes whole numbers
};

enum class DesignType { FullFactorial, List, LatinHypercube, Saltelli };

/// The [design] table.
struct DesignSpec {
  DesignType type = DesignType::FullFactorial;
  int points = 0;                ///< full_factorial: levels of factors without levels/points
  std::string list_text;         ///< list: the CSV text
  std::string list_name;         ///< list: file name, for messages
  long long samples = 0;         ///< latin_hypercube: number of cases
  long long base_samples = 0;    ///< saltelli: N
  std::uint64_t seed = 0;        ///< latin_hypercube, saltelli
  /// latin_hypercube: target rank (Spearman) correlation of the factors, imposed by
  /// Iman-Conover (rank_correlation.hpp); size 0 = none (the plain hypercube).
  SquareMatrix correlation;
};

/// One case of a design.
struct DesignPoint {
  std::vector<double> values;  ///< one per factor, in the factors' units
  std::string role;            ///< saltelli: "A", "B" or "AB_<i>"; else ""
  long long row = -1;          ///< saltelli: row j of the sample matrices; else -1
};

/// Largest number of cases a design may produce.
inline constexpr long long kMaxCases = 10'000'000;

/// The cases of `spec` over `factors`. Throws pw::InputError naming the
/// campaign key ("factors[1].max", "design.samples", "design.file") for: no
/// factors, bounds missing or reversed (min >= max), levels outside the
/// bounds, repeated levels, non-positive values on a log scale, non-whole
/// values of integer keys, points < 2, samples or base_samples <= 0, list rows
/// with missing, extra or unparsable values, too many factors for the Sobol'
/// table, zero cases or more than kMaxCases, distribution parameters out of range
/// ("factors[0].std_dev"), a distribution on a design that does not sample, a
/// correlation that is not a valid correlation matrix of the factors
/// ("design.correlation") or on a design other than latin_hypercube.
std::vector<DesignPoint> make_design(const std::vector<Factor>& factors, const DesignSpec& spec);

// --- building blocks (tested separately) -----------------------------------

/// The levels of factor `index` in a full factorial design (design.points as default).
std::vector<double> factorial_levels(const Factor& f, int default_points, std::size_t index);

/// n x d Latin hypercube in [0, 1)^d, row-major.
std::vector<double> latin_hypercube_unit(long long n, int d, std::uint64_t seed);

/// The Saltelli matrices A, B (each N x d, row-major) from Sobol' points
/// 0..N-1 in 2d dimensions, digitally shifted when seed != 0.
struct SaltelliMatrices {
  std::vector<double> A, B;
};
SaltelliMatrices saltelli_unit(long long N, int d, std::uint64_t seed);

/// u in [0, 1) -> factor value (scale or distribution, rounding of integer keys).
double from_unit(double u, const Factor& f);

/// Spearman rank correlation of the factor values of `cases` (what a sampled
/// design achieved; the plain Latin hypercube's spurious correlations included).
SquareMatrix achieved_rank_correlation(const std::vector<DesignPoint>& cases, int factors);

/// The numbers of a CSV table whose header names every factor once; rows in
/// file order, values in factor order. Blank lines and lines starting with '#'
/// are skipped.
std::vector<std::vector<double>> parse_case_list(const std::string& csv_text, const std::vector<Factor>& factors,
                                                 const std::string& source_name);

} // namespace pw::sweep
