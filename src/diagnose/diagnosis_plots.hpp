// The data behind the plots of a diagnosis report (io/diagnosis_report.hpp writes them as CSV,
// scripts/plot_diagnosis.py draws them): order spectra of the held-out half, whitened residuals
// per cell, the feature table, and the located synchronous averages. Internal to src/diagnose.
#pragma once

#include "diagnose/compare.hpp"
#include "diagnose/diagnose.hpp"

#include <vector>

namespace pw::diagnose {

/// The three models of a diagnosis as amplitudes per channel and DFT bin, with their gains.
struct ReportedModels {
  const std::vector<std::vector<double>>& nominal;   ///< the gear set as given (nuisance gains)
  const std::vector<std::vector<double>>& nuisance;  ///< nuisance-fitted (nuisance gains)
  const std::vector<std::vector<double>>& final_model;  ///< the named winner's, else the nuisance-fitted
  const std::vector<double>& final_gains;
  /// The lead's fitted model when a candidate leads but is not named (else null): where it falls
  /// short is what a reader of an "unexplained residual" looks for first.
  const std::vector<std::vector<double>>* lead = nullptr;
  const std::vector<double>* lead_gains = nullptr;
};

/// Appends the plot series of diagnosis d to d.plots.
void tabulate_plots(Diagnosis& d, const ModelComparison& cmp, const Recording& recording, const ReportedModels& m);

} // namespace pw::diagnose
