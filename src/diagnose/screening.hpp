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

/// One candidate variant, screened from the nuisance-fitted model.
struct Screen {
  const Candidate* c = nullptr;
  Variant v;
  std::vector<ParameterSpec> spec;
  std::vector<std::vector<double>> cols;      ///< secant of each own parameter (whitened residual per unit)
  std::vector<double> start, nuisance_start;  ///< where its fit starts
  double S = 0;                               ///< predicted chi2 improvement
  bool failed = false;                        ///< a screening simulation failed
  /// Saturating: its effect, beyond what the nuisance can mimic, exceeds chi2_{1-alpha}(k).
  bool visible = false;
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
  void grid_starts(const std::vector<std::size_t>& shortlist, const std::function<void(const std::string&)>& say);
  /// Simulations grid_starts(shortlist) runs (the grid and each linearized start).
  std::size_t grid_simulations(const std::vector<std::size_t>& shortlist) const;
  /// Values per one-parameter candidate in the grid of starts (at the centres of equal cells).
  static constexpr int kGridPoints = 6;
  /// The grid of starts over one parameter's box: kGridPoints values at the centres of equal
  /// cells (of ln x where the parameter is fitted on a log scale).
  static std::vector<double> grid_values(const ParameterSpec& ps);

  const Screen& operator[](std::size_t i) const { return screens_[i]; }

private:
  /// The joint Gauss-Newton step of one non-saturating variant and the nuisance on the box:
  /// sets its S, start and nuisance start (linearize()).
  void joint_step(Screen& sc, const std::vector<std::size_t>& nuse, const Eigen::Ref<const Eigen::VectorXd>& r_res,
                  double S_nuis) const;

  struct Task {
    std::size_t screen, param;
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
