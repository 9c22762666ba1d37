// Screening of the candidate library (docs/diagnose.md §5, step 6): each candidate variant is
// moved from its no-effect value to a moderate one, parameter by parameter, on top of the
// nuisance-fitted model (one simulation each, in parallel), and so are the nuisance parameters
// (2 % steps). The secants J give a joint Gauss-Newton step from there and its predicted
// improvement S = r' J (J'J)^-1 J' r minus what the nuisance directions alone give: the score
// statistic of the omitted physics, ~chi2(k) if the candidate is absent. The candidates with
// the largest S are fitted, starting at that step (one-parameter ones: or at the best point of
// a grid over their box). Internal to src/diagnose.
#pragma once

#include "diagnose/fit_context.hpp"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace pw::diagnose {

/// The secant step of a nuisance parameter at its fitted value x: 2 % of x, or of its box's span
/// (upper - lower) where x is exactly 0; downwards where upwards would leave the box; 0 (the
/// direction left out) when neither gives a finite scale.
double nuisance_secant_step(double x, const ParameterSpec& spec);

/// One candidate variant, screened from the nuisance-fitted model.
struct Screen {
  const Candidate* c = nullptr;
  Variant v;
  std::vector<ParameterSpec> spec;
  std::vector<std::vector<double>> cols;      ///< secant of each own parameter (whitened residual per unit)
  std::vector<double> start, nuisance_start;  ///< where its fit starts
  double start_step_fraction = 1;             ///< of the linearized step (backtrack_starts)
  double S = 0;                               ///< predicted chi2 improvement
  bool failed = false;                        ///< a screening simulation failed
  /// Saturating: its effect, beyond what the nuisance can mimic, exceeds chi2_{1-alpha}(k).
  bool visible = false;
  /// With transfer parameters (ParameterSpec::transfer): the screening repeated with every
  /// transfer parameter at its screening value (Screening::linearize): the residual there with the
  /// other own parameters at 'absent', and each of those moved to its screening value (empty for
  /// the transfer ones; all empty where a simulation failed or the candidate has none).
  std::vector<double> transfer_base;
  std::vector<std::vector<double>> transfer_moved;
  /// S and the start come from that second screening (it predicted the larger improvement).
  bool screened_at_transfer_values = false;
};

/// Indices of the best variant (largest S; the first on ties) of each candidate, largest S first
/// (stable: candidates of equal S keep the library's order).
std::vector<std::size_t> best_per_candidate(const std::vector<Screen>& screens);
/// Of `best`, those fitted: sensor-only and visible saturating variants always (a sensor-only
/// fit costs no simulation; a saturating one's S is not a linear prediction), the others with
/// S > 0, largest first, up to `max_candidates`.
std::vector<std::size_t> shortlist(const std::vector<Screen>& screens, const std::vector<std::size_t>& best,
                                   int max_candidates);

/// Of `best`, the candidates the shortlist's cap left unfitted that the screening cannot tell
/// from the lead (predicted improvement `lead_S`): S > 0 and S >= lead_S - margin, where margin
/// = chi2_{1-alpha}(1), the smallest chi2 difference one more parameter must make to count
/// (ranking.hpp's test). Without them the verdict's rival test (condition (d)) compares the
/// lead with the candidates the cap happened to keep: seed3p rec_41, a planet tooth the
/// screening put at 17.0 against a ring tooth's 18.5, was named ring_tooth_damage with the
/// planet tooth never fitted (docs/diagnose-log.md, session 27). Largest S first.
std::vector<std::size_t> screened_rivals(const std::vector<Screen>& screens, const std::vector<std::size_t>& best,
                                         const std::vector<std::size_t>& shortlist, double lead_S, double margin);

/// The points of Screening::grid_starts's transfer grid: every combination of the grid values
/// (Screening::grid_values) of the transfer parameters of `spec`, the first transfer parameter
/// varying slowest; the other parameters at their screening values (a moderate size, as the
/// screening moved it). `start` gives the vector's length and is otherwise overwritten.
std::vector<std::vector<double>> transfer_grid(const std::vector<ParameterSpec>& spec, const std::vector<double>& start);

/// Where a fit starts after backtrack_start: x, its chi2, the fraction of the step it lies at
/// (1: the start as given), the given start's chi2 and the chi2 evaluations made.
struct BacktrackedStart {
  std::vector<double> x;
  double chi2 = 0, fraction = 1, start_chi2 = 0;
  int evaluations = 0;
};
/// The backtracking of Screening::backtrack_starts, pure: from `start`, while chi2 is not below
/// `absent_chi2` (the chi2 at `absent`), the step from `absent` is halved, up to max_halvings
/// times (geometrically for log-scale parameters); the first point below `absent_chi2`, else the
/// best point tried (the start itself when none is better).
BacktrackedStart backtrack_start(const std::vector<ParameterSpec>& spec, const std::vector<double>& start,
                                 const std::vector<double>& absent, double absent_chi2, int max_halvings,
                                 const std::function<double(const std::vector<double>&)>& chi2);

class Screening {
public:
  Screening(FitContext& ctx, double alpha);

  /// The variants of every candidate `wanted` accepts, proposed from the located evidence.
  void add_variants(const std::function<bool(const Candidate&)>& wanted, const LocatedEvidence& evidence,
                    const ToothMap& teeth);
  std::size_t variants() const { return screens_.size(); }
  /// Simulations simulate_secants() runs.
  std::size_t simulations() const { return tasks_.size() + nspec_.size(); }

  /// One simulation per candidate parameter and per nuisance parameter, in parallel.
  void simulate_secants();
  /// Each variant's S and its start (joint Gauss-Newton step with an active set; saturating
  /// candidates: the chi2 change actually simulated, with the nuisance refitted linearly).
  void linearize();
  /// The best variant of each candidate, largest S first (the free function below).
  std::vector<std::size_t> best_per_candidate() const { return diagnose::best_per_candidate(screens_); }
  /// Those fitted (the free function below).
  std::vector<std::size_t> shortlist(const std::vector<std::size_t>& best, int max_candidates) const {
    return diagnose::shortlist(screens_, best, max_candidates);
  }
  /// The unfitted rivals of a lead (the free function below).
  std::vector<std::size_t> screened_rivals(const std::vector<std::size_t>& best, const std::vector<std::size_t>& shortlist,
                                           double lead_S, double margin) const {
    return diagnose::screened_rivals(screens_, best, shortlist, lead_S, margin);
  }
  /// One-parameter candidates respond far from linearly over their box (a 10 % torque ripple
  /// swings the seed's sun speed by +-16 % through resonances; a softened tooth changes the
  /// contact pattern): the linearized step can start LM in the wrong basin near "absent".
  /// Their starts become the best of that step and a grid over the box (fit-half chi2).
  /// A candidate with transfer parameters (ParameterSpec::transfer: how its size reaches the
  /// sensors, the machines' inertias behind a torque ripple) acts through the product of its
  /// size and a transfer that can be wrong by decades at the start; at the motor's speed-source
  /// stand-in a ripple of any fraction hardly moves the speeds, so the size's secant and LM's
  /// gradient vanish together. Its start becomes the best of the linearized step and a grid over
  /// every combination of its transfer parameters' grid values (kGridPoints each, at most
  /// kMaxGriddedTransfers of them), its own parameters at their screening values. *Why:* on
  /// fresh4 rec_13 (a ripple of 0.06 at order 2, 1000 rpm) the fit stayed at the stand-in and
  /// explained 0 % of the excess; with the rig's true inertias stated it fits 0.0586 and explains
  /// 86 % (docs/diagnose-log.md, session 59).
  void grid_starts(const std::vector<std::size_t>& shortlist, const std::function<void(const std::string&)>& say);
  /// A start that fits the fit half worse than the candidate at its 'absent' values with the
  /// nuisance-fitted values (chi2 `absent_chi2`, the nuisance-only model) is a Gauss-Newton step
  /// that overshot: it is moved back towards 'absent' along the same step, halving it up to
  /// kBacktracks times (the backtracking line search of damped Gauss-Newton, Nocedal & Wright
  /// 2006, Alg. 3.1, with the sufficient-decrease constant 0), to the first point that fits
  /// better than 'absent'; where none does, to the best point tried. Without it LM descends from
  /// the overshoot into a far basin and returns a fit worse than the candidate's own absence:
  /// a 4 um carrier runout of the independent corpus (seed3p rec_35) was fitted at 39 um with
  /// chi2 41.9 M against the nuisance-only 8.55 M (docs/diagnose-log.md, session 35).
  /// Saturating and sensor-only variants keep their starts (no step to shorten).
  void backtrack_starts(const std::vector<std::size_t>& list, double absent_chi2,
                        const std::function<void(const std::string&)>& say);
  /// Halvings of an overshooting start's step (backtrack_starts): down to 1/64 of it. A cost
  /// cap, one simulation each, not a tuned value: where 1/64 of the step still fits no better
  /// than 'absent', the step's direction is not one along which the candidate improves the fit
  /// near 'absent', and LM starts from the best point tried.
  static constexpr int kBacktracks = 6;
  /// Simulations grid_starts(shortlist) runs (the grid and each linearized start).
  std::size_t grid_simulations(const std::vector<std::size_t>& shortlist) const;
  /// Values per one-parameter candidate in the grid of starts (at the centres of equal cells).
  static constexpr int kGridPoints = 6;
  /// Transfer parameters gridded jointly (kGridPoints^2 = 36 simulations for the ripple's two
  /// machines); a candidate with more keeps its linearized start (a cost cap: none has more).
  static constexpr std::size_t kMaxGriddedTransfers = 2;
  /// The grid of starts over one parameter's box: kGridPoints values at the centres of equal
  /// cells (of ln x where the parameter is fitted on a log scale).
  static std::vector<double> grid_values(const ParameterSpec& ps);

  const Screen& operator[](std::size_t i) const { return screens_[i]; }

private:
  /// The joint Gauss-Newton step of one non-saturating variant and the nuisance on the box:
  /// sets its S, start and nuisance start (linearize()).
  void joint_step(Screen& sc, const std::vector<std::size_t>& nuse, const Eigen::Ref<const Eigen::VectorXd>& r_res,
                  double S_nuis) const;
  /// The same step from the screening at the transfer parameters' screening values (Screen::
  /// transfer_base): where it predicts a larger improvement, it sets S, the start (the transfer
  /// parameters at those values) and the nuisance start. *Why:* a size that acts through a
  /// transfer parameter has no direction at the transfer's 'absent' -- at the motor's speed-source
  /// stand-in a ripple hardly moves the speeds -- so its score there is near zero whatever the
  /// recording holds. The score test of a parameter whose effect depends on another that the null
  /// leaves unidentified is the supremum of the scores over that other's values (Davies 1987,
  /// Biometrika 74, 33-43); two values, 'absent' and the screening value, are its coarsest form.
  /// Measured: indepsim4 setD4 rec_11, a ripple of 0.034 at order 2, screened S = 2.2 at the
  /// stand-in and was never fitted; fitted alone it explains 62 % of the excess and is named
  /// (docs/diagnose-log.md, session 68).
  void transfer_screen_step(Screen& sc, const std::vector<std::size_t>& nuse,
                            const Eigen::Ref<const Eigen::VectorXd>& r_res, double S_nuis) const;

  /// One screening simulation: `param` moved to its screening value from 'absent' (kBase: none),
  /// the transfer parameters at 'absent' or, with at_transfer_values, at their screening values.
  struct Task {
    static constexpr std::size_t kBase = static_cast<std::size_t>(-1);
    std::size_t screen, param;
    bool at_transfer_values = false;
  };

  FitContext& ctx_;
  double alpha_;
  std::vector<Screen> screens_;
  std::vector<Task> tasks_;
  std::vector<double> res0_;                 ///< whitened fit-half residual of the nuisance-fitted model
  std::vector<ParameterSpec> nspec_;         ///< nuisance parameters
  std::vector<double> nstep_;                ///< their secant steps
  std::vector<std::vector<double>> ncols_;   ///< their secants (empty: the simulation failed)
};

} // namespace pw::diagnose
