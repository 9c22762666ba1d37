#pragma once
// The simulations a diagnosis still expects to run, step by step, and the percentage and ETA
// its progress lines show (issue 19.5).
//
// A diagnosis's length is decided as it runs: whether candidates are fitted at all, how many
// the screening shortlists, whether the winner's place is searched. Its cost is almost all
// simulations of one gear set at one speed, each costing about the same. So the forecast counts
// simulations: each step's expected count is set when what it depends on is known (the
// screening's tasks once the candidates' variants are listed, the fits once the shortlist is),
// from the same loop bounds the steps run (each Levenberg-Marquardt fit to its Jacobian cap with
// one accepted step per iteration), and the wall time per simulation is the one measured so far
// in this run. Steps that turn out not to run drop out, so the percentage can jump forwards; a
// fit that converges early finishes sooner than forecast; rejected LM steps take longer.
#include <array>
#include <cstddef>
#include <string>

namespace pw::diagnose {

/// Simulations one Levenberg-Marquardt fit of `parameters` runs when it uses all its
/// `iterations` and accepts its first trial step each time (fit.cpp: one start, then per
/// iteration a forward-difference Jacobian of `parameters` columns and one trial).
long lm_simulations(std::size_t parameters, int iterations);

class SimulationForecast {
public:
  static constexpr int kSteps = 13;  ///< steps 1..12 of docs/diagnose.md §5, and 13 = the verdict and report

  /// The simulations step `step` (1..kSteps) is expected to run (replaces an earlier estimate).
  void expect(int step, long simulations);
  /// Step `step` starts: the estimates of the steps before it no longer count.
  void begin(int step);
  /// Simulations the current and later steps are still expected to run, given the `done_in_step`
  /// simulations run since the current step began.
  long remaining(long done_in_step) const;

  struct Estimate {
    bool known = false;      ///< false before any simulation has been timed
    double percent = 0;      ///< simulations done / (done + still expected), in %
    double seconds_left = 0; ///< still expected x wall seconds per simulation so far
  };
  /// The estimate after `done` simulations in total (`done_in_step` of them in the current step),
  /// `wall_s` seconds after the first one started.
  Estimate estimate(long done, long done_in_step, double wall_s) const;

private:
  std::array<long, kSteps + 1> expected_{};  ///< index 1..kSteps
  int current_ = 1;
};

/// "46 %, ETA 6 min 20 s", or "" when nothing is known yet.
std::string to_string(const SimulationForecast::Estimate& e);

} // namespace pw::diagnose
