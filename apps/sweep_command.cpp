#include "sweep_command.hpp"

#include "core/error.hpp"
#include "sweep/campaign.hpp"
#include "sweep/driver.hpp"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iostream>
#include <string_view>
#include <tuple>

namespace pw::app {

CLI::App* add_sweep_command(CLI::App& app, SweepCommandOptions& o) {
  CLI::App* s = app.add_subcommand(
      "sweep", "Run a campaign (full factorial, list, Latin hypercube or Saltelli design over any configuration "
               "keys) on 1..P MPI ranks into one HDF5 archive; `mpirun -np P planetwear sweep ...` for P ranks");
  s->add_option("campaign", o.campaign, "campaign TOML file (docs/campaigns.md)")->required()->check(CLI::ExistingFile);
  s->add_option("-o,--output", o.output, "archive to write (HDF5; docs/archive-format.md)");
  CLI::Option* resume = s->add_flag("--resume", o.resume,
                                    "continue an interrupted campaign: run only the cases the archive and its "
                                    "journal do not hold (refused if the campaign changed)");
  CLI::Option* force = s->add_flag("--force", o.force, "replace an existing archive (it is kept until the new one "
                                                       "is in place)");
  resume->excludes(force);
  s->add_flag("-q,--quiet", o.quiet, "no progress on stderr");
  s->add_option("--checkpoint-cases", o.checkpoint_cases, "rewrite the archive after this many finished cases")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  s->add_option("--checkpoint-seconds", o.checkpoint_seconds, "... or after this many seconds [s]")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  s->add_flag("--dry-run", o.dry_run, "check the campaign and every case, print the cases, write nothing");
  s->add_option("--cases", o.cases,
                "run only cases BEGIN <= i < END (BEGIN:END, END may be omitted = to the last case), e.g. one "
                "array-job task; the archive still lists every case, the others pending "
                "(merge slices with scripts/merge_archives.py)");
  return s;
}

namespace {
/// "BEGIN:END" -> [begin, end); END empty = all. Throws InputError naming --cases.
std::pair<std::size_t, std::size_t> parse_case_range(const std::string& text) {
  const auto fail = [&] {
    return InputError("--cases", "expected BEGIN:END with 0 <= BEGIN < END (case indices), got '" + text + "'");
  };
  const auto colon = text.find(':');
  if (colon == std::string::npos) throw fail();
  auto number = [&](std::string_view s, std::size_t fallback) {
    if (s.empty()) return fallback;
    std::size_t v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc{} || p != s.data() + s.size()) throw fail();
    return v;
  };
  const std::string_view all(text);
  const std::size_t b = number(all.substr(0, colon), 0);
  const std::size_t e = number(all.substr(colon + 1), static_cast<std::size_t>(-1));
  if (b >= e) throw fail();
  return {b, e};
}
} // namespace

int run_sweep(const SweepCommandOptions& o) {
  std::size_t begin = 0, end = static_cast<std::size_t>(-1);
  if (!o.cases.empty()) std::tie(begin, end) = parse_case_range(o.cases);
  if (o.dry_run) {
    const sweep::Campaign c = sweep::read_campaign(o.campaign);
    sweep::validate_cases(c);
    std::printf("%s: %s design, %zu cases, %zu factors\n", o.campaign.c_str(),
                std::string(sweep::to_string(c.design.type)).c_str(), c.cases.size(), c.factors.size());
    std::printf("%8s", "case");
    for (const auto& f : c.factors) std::printf("  %s [%s]", f.key.c_str(), f.unit.c_str());
    std::printf("%s\n", c.design.type == sweep::DesignType::Saltelli ? "  role  row" : "");
    for (std::size_t i = begin; i < std::min(end, c.cases.size()); ++i) {
      std::printf("%8zu", i);
      for (std::size_t k = 0; k < c.factors.size(); ++k) {
        const int width = static_cast<int>(c.factors[k].key.size() + c.factors[k].unit.size() + 3);
        std::printf("  %*.10g", width, c.cases[i].values[k]);
      }
      if (!c.cases[i].role.empty()) std::printf("  %s  %lld", c.cases[i].role.c_str(), c.cases[i].row);
      std::printf("\n");
    }
    for (const std::string& line : sweep::rank_correlation_report(c)) std::printf("%s\n", line.c_str());
    return 0;
  }
  require(!o.output.empty(), "--output", "required: the archive to write, e.g. -o results.h5");
  sweep::SweepOptions s;
  s.campaign = o.campaign;
  s.output = o.output;
  s.resume = o.resume;
  s.force = o.force;
  s.quiet = o.quiet;
  s.checkpoint_cases = o.checkpoint_cases;
  s.checkpoint_seconds = o.checkpoint_seconds;
  s.case_begin = begin;
  s.case_end = end;
  return sweep::run_sweep(s, std::cerr);
}

} // namespace pw::app
