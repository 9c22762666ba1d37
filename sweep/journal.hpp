// The journal of a running campaign: one small file per finished case in
// "<archive>.journal/", written atomically (temporary file, fsync, rename),
// so that a case finished since the last checkpoint survives a kill -9.
// Checkpoints merge the entries into the archive and delete them
// (docs/archive-format.md, "Crash safety").
//
// Entry file "case-<index>.rec": a header (magic "PWJ1", format version,
// campaign input hash, case index, payload size, FNV-1a 64 checksum of the
// payload) followed by the serialized CaseRecord (case_record.hpp).
//
// The directory also holds "lock", flock(2)-ed by the running campaign so
// that a second run on the same archive is refused while the first is alive
// (the kernel drops the lock when a process dies, even by kill -9).
#pragma once

#include "case_record.hpp"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace pw::sweep {

class Journal {
public:
  /// "<archive>.journal"
  static std::filesystem::path directory_for(const std::filesystem::path& archive);

  /// Does not touch the file system.
  Journal(std::filesystem::path directory, std::uint64_t campaign_hash);
  ~Journal();
  Journal(const Journal&) = delete;
  Journal& operator=(const Journal&) = delete;

  const std::filesystem::path& directory() const noexcept { return dir_; }

  /// Creates the directory if needed and takes its lock; throws
  /// pw::io::IoError if another process holds it or on file-system errors.
  void lock();
  /// Releases the lock (also done by the destructor).
  void unlock() noexcept;

  /// Writes one finished case; returns the entry's path. Throws io::IoError.
  std::filesystem::path append(std::int64_t index, std::span<const char> record_bytes);

  struct Entry {
    std::filesystem::path path;
    CaseRecord record;
  };
  /// Every entry of this campaign, in case order. Entries that are corrupt
  /// (bad checksum, truncated) are skipped with a note in `notes`; an entry of
  /// another campaign (other hash) throws pw::InputError, since resuming would
  /// mix two campaigns. Stale temporary files are ignored.
  std::vector<Entry> read(std::vector<std::string>& notes) const;

  /// Deletes entry files (best effort; missing files are fine).
  static void remove(const std::vector<std::filesystem::path>& entries) noexcept;
  /// Deletes every entry and temporary file of the directory (not the lock).
  void clear() const;
  /// Removes the lock and the directory if nothing else is in it.
  void remove_directory() noexcept;

private:
  std::filesystem::path dir_;
  std::uint64_t hash_;
  int lock_fd_ = -1;
};

} // namespace pw::sweep
