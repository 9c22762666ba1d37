#include "design.hpp"

#include "sobol.hpp"
#include "random_index.hpp"

#include "core/error.hpp"
#include "io/csv_fields.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <sstream>

namespace pw::sweep {
namespace {

std::string factor_param(std::size_t index, const char* field) {
  return "factors[" + std::to_string(index) + "]." + field;
}

/// Uniform double in [0, 1) from the top 53 bits of one engine output.
double unit_double(std::mt19937_64& engine) { return static_cast<double>(engine() >> 11) * 0x1p-53; }

bool is_whole(double v) { return std::isfinite(v) && std::floor(v) == v; }

double round_half_away(double v) { return v < 0 ? -std::floor(-v + 0.5) : std::floor(v + 0.5); }

/// The bounds factor `i` gives (either may be absent): finite, min < max, whole for integer keys.
void check_given_bounds(const Factor& f, std::size_t i) {
  if (f.min) require(std::isfinite(*f.min), factor_param(i, "min"), f.key, ": must be finite, got ", *f.min);
  if (f.max) require(std::isfinite(*f.max), factor_param(i, "max"), f.key, ": must be finite, got ", *f.max);
  if (f.min && f.max)
    require(*f.min < *f.max, factor_param(i, "max"), f.key, ": max = ", *f.max, " ", f.unit, " is ",
            *f.min == *f.max ? "equal to" : "below", " min = ", *f.min, " ", f.unit,
            *f.min == *f.max ? " (a fixed value belongs in [base.set])" : " (bounds reversed)");
  if (f.integer) {
    if (f.min)
      require(is_whole(*f.min), factor_param(i, "min"), f.key, " is an integer key: min must be a whole number, got ",
              *f.min);
    if (f.max)
      require(is_whole(*f.max), factor_param(i, "max"), f.key, " is an integer key: max must be a whole number, got ",
              *f.max);
  }
}

/// Bounds of factor `i`: present, finite, min < max, positive for log scale,
/// whole for integer keys.
void check_bounds(const Factor& f, std::size_t i) {
  require(f.min.has_value(), factor_param(i, "min"), f.key, ": this design needs bounds min and max");
  require(f.max.has_value(), factor_param(i, "max"), f.key, ": this design needs bounds min and max");
  check_given_bounds(f, i);
  if (f.scale == Scale::Log)
    require(*f.min > 0, factor_param(i, "min"), f.key, ": scale = \"log\" needs min > 0, got ", *f.min);
}

/// A value of a factor from its levels or a case list: finite, within bounds if
/// given, whole for integer keys, positive on a log scale.
void check_value(const Factor& f, double v, const std::string& param, const std::string& where) {
  require(std::isfinite(v), param, f.key, ": ", where, " must be finite, got ", v);
  if (f.min) require(v >= *f.min, param, f.key, ": ", where, " = ", v, " ", f.unit, " is below min = ", *f.min, " ", f.unit);
  if (f.max) require(v <= *f.max, param, f.key, ": ", where, " = ", v, " ", f.unit, " is above max = ", *f.max, " ", f.unit);
  if (f.integer) require(is_whole(v), param, f.key, " is an integer key: ", where, " must be a whole number, got ", v);
  if (f.scale == Scale::Log) require(v > 0, param, f.key, ": scale = \"log\" needs positive values, got ", v);
}

/// A sampled factor's distribution: parameters finite and in range, bounds consistent.
void check_distribution(const Factor& f, std::size_t i) {
  const Distribution& d = f.distribution;
  const std::string name(to_string(d.kind));
  require(f.scale == Scale::Linear, factor_param(i, "scale"), f.key, ": scale = \"log\" is for uniform factors; a ",
          name, " factor's spacing follows from its distribution (a log-normal one: distribution = \"lognormal\")");
  check_given_bounds(f, i);
  if (d.kind == DistributionKind::Triangular) {
    require(f.min && f.max, factor_param(i, f.min ? "max" : "min"), f.key,
            ": a triangular distribution needs min, mode and max");
    require(std::isfinite(d.mode) && d.mode >= *f.min && d.mode <= *f.max, factor_param(i, "mode"), f.key,
            ": mode must lie in [min, max] = [", *f.min, ", ", *f.max, "] ", f.unit, ", got ", d.mode);
    return;
  }
  require(std::isfinite(d.mean), factor_param(i, "mean"), f.key, ": must be finite, got ", d.mean);
  require(std::isfinite(d.std_dev) && d.std_dev > 0, factor_param(i, "std_dev"), f.key, ": must be > 0 [", f.unit,
          "], got ", d.std_dev);
  if (d.kind == DistributionKind::LogNormal) {
    require(d.mean > 0, factor_param(i, "mean"), f.key, ": a lognormal factor's mean must be > 0, got ", d.mean);
    if (f.max) require(*f.max > 0, factor_param(i, "max"), f.key, ": a lognormal factor takes positive values; max = ",
                       *f.max, " leaves none");
  }
  // The truncated range must carry probability: the inverse CDF of an empty range is meaningless.
  const double lo = f.min.value_or(-std::numeric_limits<double>::infinity());
  const double hi = f.max.value_or(std::numeric_limits<double>::infinity());
  const double a = inverse_cdf(d, 0.0, lo, hi), b = inverse_cdf(d, std::nextafter(1.0, 0.0), lo, hi);
  require(a < b, factor_param(i, f.min ? "min" : "max"), f.key, ": the truncation [", lo, ", ", hi, "] ", f.unit,
          " holds no probability of the ", name, " distribution (mean ", d.mean, ", std_dev ", d.std_dev, ")");
}

/// Bounds or distribution of a factor a sampled design (latin_hypercube, saltelli) draws.
void check_sampled(const Factor& f, std::size_t i) {
  if (f.distribution.kind == DistributionKind::Uniform)
    check_bounds(f, i);
  else
    check_distribution(f, i);
}

void require_no_levels(const Factor& f, std::size_t i, const char* design) {
  require(f.levels.empty(), factor_param(i, "levels"), f.key, ": levels are only used by full_factorial designs, not ",
          design);
  require(!f.points, factor_param(i, "points"), f.key, ": points are only used by full_factorial designs, not ", design);
}

long long checked_product(long long a, long long b, const std::string& param) {
  require(b == 0 || a <= kMaxCases / b, param, "the design has more than ", kMaxCases, " cases");
  return a * b;
}

std::string trim(const std::string& s) { return std::string(io::trim_space(s)); }

} // namespace

double from_unit(double u, const Factor& f) {
  if (f.distribution.kind != DistributionKind::Uniform) {
    const double v = inverse_cdf(f.distribution, u, f.min.value_or(-std::numeric_limits<double>::infinity()),
                                 f.max.value_or(std::numeric_limits<double>::infinity()));
    return f.integer ? round_half_away(v) : v;
  }
  const double lo = *f.min, hi = *f.max;
  double v = f.scale == Scale::Log ? std::exp(std::log(lo) + u * (std::log(hi) - std::log(lo))) : lo + u * (hi - lo);
  v = std::clamp(v, lo, hi);  // guards the last ulp of exp/log and of lo + u (hi - lo)
  return f.integer ? round_half_away(v) : v;
}

SquareMatrix achieved_rank_correlation(const std::vector<DesignPoint>& cases, int factors) {
  std::vector<double> sample;
  sample.reserve(cases.size() * static_cast<std::size_t>(factors));
  for (const DesignPoint& p : cases) sample.insert(sample.end(), p.values.begin(), p.values.end());
  return spearman(sample, static_cast<long long>(cases.size()), factors);
}

std::vector<double> factorial_levels(const Factor& f, int default_points, std::size_t i) {
  require(f.distribution.kind == DistributionKind::Uniform, factor_param(i, "distribution"), f.key,
          ": distributions are drawn by latin_hypercube and saltelli designs; a full_factorial takes levels");
  if (!f.levels.empty()) {
    require(!f.points, factor_param(i, "points"), f.key, ": give levels or points, not both");
    std::set<double> seen;
    for (std::size_t k = 0; k < f.levels.size(); ++k) {
      const double v = f.levels[k];
      check_value(f, v, factor_param(i, "levels"), "level " + std::to_string(k));
      require(seen.insert(v).second, factor_param(i, "levels"), f.key, ": level ", v, " is listed twice");
    }
    return f.levels;
  }
  const int n = f.points.value_or(default_points);
  require(n != 0 || f.points, factor_param(i, "levels"), f.key,
          ": full_factorial needs levels = [...] or min, max and points (per factor or in [design])");
  require(n >= 2, f.points ? factor_param(i, "points") : std::string("design.points"), f.key, ": points must be >= 2, got ",
          n, " (a fixed value belongs in [base.set])");
  check_bounds(f, i);
  std::vector<double> levels(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double u = static_cast<double>(k) / (n - 1);
    double v = f.scale == Scale::Log ? std::exp(std::log(*f.min) + u * (std::log(*f.max) - std::log(*f.min)))
                                     : *f.min + u * (*f.max - *f.min);
    if (k == 0) v = *f.min;
    if (k == n - 1) v = *f.max;
    levels[k] = f.integer ? round_half_away(v) : v;
  }
  for (int k = 1; k < n; ++k)
    require(levels[k] != levels[k - 1], f.points ? factor_param(i, "points") : std::string("design.points"), f.key,
            " is an integer key: ", n, " points between ", *f.min, " and ", *f.max, " repeat the level ", levels[k]);
  return levels;
}

std::vector<double> latin_hypercube_unit(long long n, int d, std::uint64_t seed) {
  std::mt19937_64 engine(seed);
  const auto N = static_cast<std::size_t>(n);
  std::vector<double> u(N * static_cast<std::size_t>(d));
  std::vector<std::size_t> perm(N);
  for (int j = 0; j < d; ++j) {
    for (std::size_t k = 0; k < N; ++k) perm[k] = k;
    shuffle(perm, engine);
    for (std::size_t k = 0; k < N; ++k) {
      const double x = (static_cast<double>(perm[k]) + unit_double(engine)) / static_cast<double>(N);
      u[k * d + j] = std::min(x, std::nextafter(1.0, 0.0));
    }
  }
  return u;
}

SaltelliMatrices saltelli_unit(long long N, int d, std::uint64_t seed) {
  const SobolSequence sobol(2 * d);
  std::vector<std::uint32_t> shift(static_cast<std::size_t>(2 * d), 0);
  if (seed != 0) {
    std::mt19937_64 engine(seed);
    for (auto& s : shift) s = static_cast<std::uint32_t>(engine() >> 32);
  }
  SaltelliMatrices m;
  m.A.reserve(static_cast<std::size_t>(N) * d);
  m.B.reserve(static_cast<std::size_t>(N) * d);
  for (long long j = 0; j < N; ++j) {
    const auto bits = sobol.point_bits(static_cast<std::uint64_t>(j));
    for (int k = 0; k < d; ++k) m.A.push_back(static_cast<double>(bits[k] ^ shift[k]) * 0x1p-32);
    for (int k = 0; k < d; ++k) m.B.push_back(static_cast<double>(bits[d + k] ^ shift[d + k]) * 0x1p-32);
  }
  return m;
}

std::vector<std::vector<double>> parse_case_list(const std::string& csv_text, const std::vector<Factor>& factors,
                                                 const std::string& source_name) {
  std::istringstream in(csv_text);
  std::string line;
  int line_no = 0;
  std::vector<int> column_of;  // column index of each factor
  std::size_t columns = 0;
  std::vector<std::vector<double>> rows;
  auto where = [&](int l) { return source_name + ":" + std::to_string(l); };
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    const auto fields = io::split_fields(t);
    if (column_of.empty()) {
      columns = fields.size();
      column_of.assign(factors.size(), -1);
      for (std::size_t c = 0; c < fields.size(); ++c) {
        const auto it = std::find_if(factors.begin(), factors.end(), [&](const Factor& f) { return f.key == fields[c]; });
        require(it != factors.end(), "design.file", where(line_no), ": column '", fields[c],
                "' is not a factor; declare it in a [[factors]] table (key, unit)");
        const auto fi = static_cast<std::size_t>(it - factors.begin());
        require(column_of[fi] < 0, "design.file", where(line_no), ": column '", fields[c], "' appears twice");
        column_of[fi] = static_cast<int>(c);
      }
      for (std::size_t fi = 0; fi < factors.size(); ++fi)
        require(column_of[fi] >= 0, "design.file", where(line_no), ": the header has no column for factor '",
                factors[fi].key, "'");
      continue;
    }
    require(fields.size() == columns, "design.file", where(line_no), ": ", fields.size(), " values, the header has ",
            columns, " columns");
    std::vector<double> row(factors.size());
    for (std::size_t fi = 0; fi < factors.size(); ++fi) {
      const std::string& s = fields[static_cast<std::size_t>(column_of[fi])];
      double v = 0;
      const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
      require(!s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size(), "design.file", where(line_no),
              ": '", s, "' in column ", factors[fi].key, " is not a number");
      check_value(factors[fi], v, "design.file", where(line_no) + ": value of " + factors[fi].key);
      row[fi] = v;
    }
    rows.push_back(std::move(row));
  }
  require(!column_of.empty(), "design.file", source_name, ": no header line naming the factors");
  return rows;
}

std::vector<DesignPoint> make_design(const std::vector<Factor>& factors, const DesignSpec& spec) {
  require(!factors.empty(), "factors", "a campaign needs at least one [[factors]] table");
  const int d = static_cast<int>(factors.size());
  std::vector<DesignPoint> cases;
  switch (spec.type) {
  case DesignType::FullFactorial: {
    std::vector<std::vector<double>> levels;
    long long n = 1;
    for (std::size_t i = 0; i < factors.size(); ++i) {
      levels.push_back(factorial_levels(factors[i], spec.points, i));
      n = checked_product(n, static_cast<long long>(levels.back().size()), "design");
    }
    cases.reserve(static_cast<std::size_t>(n));
    std::vector<std::size_t> idx(factors.size(), 0);
    for (long long c = 0; c < n; ++c) {
      DesignPoint p;
      for (std::size_t i = 0; i < factors.size(); ++i) p.values.push_back(levels[i][idx[i]]);
      cases.push_back(std::move(p));
      for (std::size_t i = factors.size(); i-- > 0;) {  // last factor fastest
        if (++idx[i] < levels[i].size()) break;
        idx[i] = 0;
      }
    }
    break;
  }
  case DesignType::List: {
    for (std::size_t i = 0; i < factors.size(); ++i) {
      require_no_levels(factors[i], i, "list");
      require(factors[i].distribution.kind == DistributionKind::Uniform, factor_param(i, "distribution"),
              factors[i].key, ": distributions are drawn by latin_hypercube and saltelli designs, not list");
    }
    for (auto& row : parse_case_list(spec.list_text, factors, spec.list_name)) cases.push_back({std::move(row), "", -1});
    require(static_cast<long long>(cases.size()) <= kMaxCases, "design.file", "more than ", kMaxCases, " cases");
    break;
  }
  case DesignType::LatinHypercube: {
    require(spec.samples > 0, "design.samples", "must be > 0, got ", spec.samples);
    require(spec.samples <= kMaxCases, "design.samples", "must be <= ", kMaxCases, ", got ", spec.samples);
    for (std::size_t i = 0; i < factors.size(); ++i) {
      require_no_levels(factors[i], i, "latin_hypercube");
      check_sampled(factors[i], i);
    }
    auto u = latin_hypercube_unit(spec.samples, d, spec.seed);
    if (spec.correlation.size > 0) {
      require(spec.correlation.size == d, "design.correlation", "is ", spec.correlation.size, " x ",
              spec.correlation.size, " but the campaign has ", d, " factors (one row and column per factor, in "
              "the order of the [[factors]] tables)");
      const std::string problem = correlation_matrix_problem(spec.correlation);
      require(problem.empty(), "design.correlation", problem);
      impose_rank_correlation(u, spec.samples, d, spec.correlation, spec.seed);
    }
    for (long long c = 0; c < spec.samples; ++c) {
      DesignPoint p;
      for (int j = 0; j < d; ++j) p.values.push_back(from_unit(u[static_cast<std::size_t>(c) * d + j], factors[j]));
      cases.push_back(std::move(p));
    }
    break;
  }
  case DesignType::Saltelli: {
    require(spec.base_samples > 0, "design.base_samples", "must be > 0, got ", spec.base_samples);
    require(2 * d <= SobolSequence::kMaxDimensions, "factors", "saltelli designs take at most ",
            SobolSequence::kMaxDimensions / 2, " factors (2d Sobol' dimensions), got ", d);
    require(spec.base_samples <= kMaxCases / (d + 2), "design.base_samples", spec.base_samples, " x (", d,
            " + 2) cases exceed the limit of ", kMaxCases);
    for (std::size_t i = 0; i < factors.size(); ++i) {
      require_no_levels(factors[i], i, "saltelli");
      check_sampled(factors[i], i);
    }
    const SaltelliMatrices m = saltelli_unit(spec.base_samples, d, spec.seed);
    auto point = [&](long long j, int replaced_from_B /* -1: A, d: B */) {
      DesignPoint p;
      p.row = j;
      for (int k = 0; k < d; ++k) {
        const bool from_b = replaced_from_B == d || replaced_from_B == k;
        const double u = (from_b ? m.B : m.A)[static_cast<std::size_t>(j) * d + k];
        p.values.push_back(from_unit(u, factors[k]));
      }
      p.role = replaced_from_B < 0 ? "A" : replaced_from_B == d ? "B" : "AB_" + std::to_string(replaced_from_B);
      return p;
    };
    for (long long j = 0; j < spec.base_samples; ++j) {
      cases.push_back(point(j, -1));
      for (int k = 0; k < d; ++k) cases.push_back(point(j, k));
      cases.push_back(point(j, d));
    }
    break;
  }
  }
  require(!cases.empty(), spec.type == DesignType::List ? "design.file" : "design", "the design has zero cases");
  return cases;
}

} // namespace pw::sweep
