// The campaign archive: one HDF5 file holding the design, the status of
// every case and the per-case results, indexed by case (layout:
// docs/archive-format.md). Always written whole into a new file (the driver
// renames it onto the archive atomically); never modified in place.
//
//   /                       attrs format = "planetwear.campaign", format_version,
//                           software_version, build_flags, created_utc,
//                           units_convention, complete, cases, cases_done,
//                           cases_failed, cases_pending
//   /campaign/toml          campaign file text;  /campaign/base_config_toml,
//                           /campaign/list_csv (list designs); attrs name,
//                           description, design_type, input_hash, design_hash, ...
//   /design/<column>        1-D over cases: case, <factor key> [unit], status,
//                           message, wall_time [s], rank, sample_role, sample_row
//   /results/scalars/<name>                       [cases]          NaN = not done
//   /results/wear/<family>/depth_final            [cases, elements] mean over teeth
//   /results/wear/<family>/depth_final_max        [cases, elements] max over teeth
//   /results/wear/<family>/distance_from_pitch_point [cases, elements]
//   /results/wear/<family>/elements               [cases] int, 0 = none
//   /results/spectra/frequency, /results/spectra/bins, /results/spectra/<channel>
//   /results/time_history/time, /samples, /<channel>   (decimation > 0)
//
// Rows of cases that are not done, and columns beyond a case's own length,
// hold NaN.
#pragma once

#include "campaign.hpp"
#include "case_record.hpp"

#include <cstdint>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace pw::sweep {

inline constexpr std::string_view kArchiveFormat = "planetwear.campaign";
inline constexpr std::int64_t kArchiveFormatVersion = 1;

/// Provenance of the run writing the archive (root attributes).
struct ArchiveRunInfo {
  int mpi_ranks = 1;
  std::size_t case_begin = 0, case_end = 0;  ///< the slice this run computes (root attributes)
};

/// Writes the whole archive into a new file `path` (an existing file is
/// truncated: pass a temporary path). `records[i]` is case i's record or null
/// (pending); records.size() must equal the number of cases. Throws
/// pw::io::IoError on HDF5 failures and std::invalid_argument for records that
/// do not fit the campaign (index out of range or at the wrong position,
/// spectra of one case on different frequency axes).
void write_archive(const std::filesystem::path& path, const Campaign& campaign,
                   std::span<const std::shared_ptr<const CaseRecord>> records, const ArchiveRunInfo& info);

/// What a resumed run needs from an existing archive.
struct ArchiveContents {
  std::string input_hash, design_hash;  ///< hex, as written
  std::size_t cases = 0;
  std::size_t case_begin = 0, case_end = 0;  ///< slice of the run that wrote it (0, cases when absent)
  std::vector<CaseRecord> records;      ///< every done or failed case, in case order
};

/// Reads an archive written by write_archive(). Throws pw::io::IoError if it
/// cannot be read or is not a campaign archive of a known format version.
ArchiveContents read_archive(const std::filesystem::path& path);

} // namespace pw::sweep
