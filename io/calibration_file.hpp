// The calibration file written by `planetwear calibrate` and read by
// `planetwear diagnose --calibration` (docs/diagnose.md §6a): a TOML document
//
//   [calibration]
//   alpha = 0.01                          # of the budgets' upper confidence limits
//   recordings = ["/data/healthy1.csv", ...]  # what it was made from (absolute paths)
//   sidecars = ["/data/healthy1.json", ...]   # their sidecars (optional; default: the name with .json)
//   speeds_rpm = [1000.0, ...]            # their input speeds [rpm]
//   verdicts = ["unexplained_residual", ...]  # each one's nuisance-only verdict before calibration
//   rig_elements = ["encoder_bandwidth"]  # candidates fitted as nuisance
//   overrides = ["stiffness.scale=1.21", ...]  # the calibrated model, as --set assignments
//   [[discrepancy]]                       # one per (quantity, family)
//   quantity = "sun_speed"                # docs/recordings.md quantity names
//   family = "mesh"                       # kinematic family (docs/diagnose.md §1)
//   relative_variance = 0.04              # sigma_rel^2 estimate [-]
//   relative_variance_se = 0.01           # [-]
//   relative_cells = 120
//   absolute_variance = 1e-8              # sigma_abs^2 [channel SI unit^2]
//   absolute_variance_se = 2e-9
//   absolute_cells = 800
//   relative_variance_per_recording = [0.05, 0.03]
// Written atomically; a read error names the file and the key.
#pragma once

#include "diagnose/calibration.hpp"

#include <filesystem>

namespace pw::io {

void write_calibration(const diagnose::Calibration& calibration, const std::filesystem::path& path);
/// Throws pw::InputError naming the file and key for a malformed file, IoError if unreadable.
diagnose::Calibration read_calibration(const std::filesystem::path& path);

} // namespace pw::io
