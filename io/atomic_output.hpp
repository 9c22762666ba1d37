// Crash-safe output files: write to a temporary file beside the destination,
// move it into place only when everything has been written.
//
//   pw::io::AtomicOutput out("results/run.h5");      // checks the directory
//   {
//     auto file = pw::io::H5File::create(out.temp_path());
//     pw::io::write_simulation(file, config, result, spectra);
//     file.close();
//   }
//   out.commit();  // fsync, then rename "run.h5.partial-<pid>" -> "run.h5"
//
// If anything throws before commit(), the destructor deletes the temporary
// file: a failed run leaves no partial output, and an existing file at the
// destination is untouched until the new one is complete (rename(2) replaces
// it atomically on POSIX file systems).
#pragma once

#include <filesystem>
#include <string>

namespace pw::io {

class AtomicOutput {
public:
  /// Throws pw::io::IoError if the destination's directory does not exist, the
  /// destination is a directory, or (overwrite = false) a file already exists
  /// there. Removes a stale temporary file of the same name.
  explicit AtomicOutput(std::filesystem::path destination, bool overwrite = true);
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  /// Removes the temporary file unless commit() succeeded. Never throws.
  ~AtomicOutput();

  /// "<destination>.partial-<pid>", in the destination's directory.
  const std::filesystem::path& temp_path() const noexcept { return temp_; }
  const std::filesystem::path& destination() const noexcept { return destination_; }
  bool committed() const noexcept { return committed_; }

  /// Flushes the temporary file to disk and moves it onto the destination
  /// (overwrite = false: fails with IoError, keeping both files' contents, if
  /// the destination appeared meanwhile). The file must have been closed.
  void commit();

private:
  std::filesystem::path destination_;
  std::filesystem::path temp_;
  bool overwrite_;
  bool committed_ = false;
};

/// Writes `text` to `path` through an AtomicOutput (all or nothing); throws IoError.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

} // namespace pw::io
