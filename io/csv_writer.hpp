// Time histories as CSV, for users without h5py:
//
//   time_s,sun_planet/0/deflection [m],sun_planet/0/force [N],...
//   0,1.2345e-06,678.9,...
//
// One row per sample, one column per channel, header "name [unit]"; numbers in
// shortest round-trip form ("nan" for NaN). pandas: pd.read_csv(p).
#pragma once

#include "model/result.hpp"

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

namespace pw::io {

struct CsvOptions {
  /// Channels to write, in this order; empty = all, in result order.
  std::vector<std::string> channels{};
};

/// Throws pw::InputError naming an unknown channel in options.channels and
/// std::invalid_argument if a channel is not as long as result.time_s.
void write_csv(std::ostream& out, const model::SimulationResult& result, const CsvOptions& options = {});

/// Writes the file atomically (AtomicOutput): on any error no file is left
/// and an existing file at `path` is untouched. Throws pw::io::IoError for
/// file-system failures.
void write_csv(const std::filesystem::path& path, const model::SimulationResult& result,
               const CsvOptions& options = {});

} // namespace pw::io
