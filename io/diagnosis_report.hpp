// Writes a diagnose::Diagnosis into a report directory (docs/diagnose.md §6):
//
//   report.json    machine-readable: verdict, summary, rule, fitted parameters
//                  with standard errors, residuals before/after per window and
//                  channel, located families/lines/rotations, every candidate
//                  with why it won or lost, timing
//   report.md      the same for people, referencing the PNGs
//   report.html    the same as a self-contained page (PNG <img> beside it)
//   data/*.csv     spectra and synchronous averages before/after (plot input)
//
// The PNGs (spectra_*.png, tsa_*.png) are drawn afterwards by
// scripts/plot_diagnosis.py from data/*.csv; the reports reference them and
// say so if they are missing. Each file is written atomically.
#pragma once

#include "diagnose/diagnose.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace pw::io {

struct ReportContext {
  std::string recording_path, config_path, command_line, version;
  std::string calibration_path;  ///< --calibration file, empty: none
  std::vector<std::string> calibration_at_bound;  ///< its calibrated values that are bounds, not fits
  std::string baseline_path;     ///< --baseline recording (differential diagnosis), empty: none
  std::string baseline_summary;  ///< diagnose::BaselineReference::summary
  std::vector<std::string> baseline_at_bound;  ///< diagnose::BaselineReference::at_bound
  /// With a calibration: which reference it was judged against (its own recording at this
  /// operating point, or its budget alone) and why.
  std::string calibration_reference;
  /// With --baseline: its operating point against the recording's, and what follows from it.
  std::string baseline_operating_point;
  bool plots_available = true;  ///< false: say in the reports that no PNGs were drawn
  std::string plots_note;       ///< why not, if not
  int ranks = 1;                ///< MPI ranks that simulated (rank 0's threads + one per other rank)
};

/// Writes report.json, data/*.csv, report.md and report.html into `dir`
/// (created if missing). Throws pw::io::IoError on file-system failures.
void write_diagnosis_report(const std::filesystem::path& dir, const diagnose::Diagnosis& d, const ReportContext& ctx);

/// Rewrites only report.md and report.html (after the plots were attempted).
void write_diagnosis_documents(const std::filesystem::path& dir, const diagnose::Diagnosis& d,
                               const ReportContext& ctx);

/// File-name-safe form of a series name ("spectrum/housing_acc" -> "spectrum_housing_acc").
std::string series_file_stem(const std::string& name);

} // namespace pw::io
