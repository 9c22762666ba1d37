#include "journal.hpp"

#include "campaign.hpp"

#include "core/error.hpp"
#include "io/io_error.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

namespace pw::sweep {
namespace {

constexpr std::uint32_t kJournalMagic = 0x314a5750;  // "PWJ1" little-endian
constexpr std::uint32_t kJournalVersion = 1;
constexpr std::string_view kEntryPrefix = "case-";
constexpr std::string_view kEntrySuffix = ".rec";
constexpr std::string_view kTempSuffix = ".tmp";

std::string errno_text() { return std::strerror(errno); }

/// Writes all bytes to fd; false with errno on failure.
bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  (void)::fsync(fd);  // best effort: some file systems refuse
  ::close(fd);
}

bool is_entry_name(const std::string& name) {
  return name.size() > kEntryPrefix.size() + kEntrySuffix.size() && name.starts_with(kEntryPrefix) &&
         name.ends_with(kEntrySuffix);
}

} // namespace

std::filesystem::path Journal::directory_for(const std::filesystem::path& archive) {
  std::filesystem::path p = archive;
  p += ".journal";
  return p;
}

Journal::Journal(std::filesystem::path directory, std::uint64_t campaign_hash)
    : dir_(std::move(directory)), hash_(campaign_hash) {}

Journal::~Journal() { unlock(); }

void Journal::lock() {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) throw io::IoError(dir_.string() + ": cannot create the journal directory: " + ec.message());
  const std::filesystem::path path = dir_ / "lock";
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) throw io::IoError(path.string() + ": cannot open the journal lock: " + errno_text());
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int saved = errno;
    ::close(fd);
    if (saved == EWOULDBLOCK)
      throw io::IoError(dir_.string() + ": another planetwear sweep is running on this archive (its journal is locked)");
    throw io::IoError(path.string() + ": cannot lock the journal: " + std::strerror(saved));
  }
  lock_fd_ = fd;
  // Temporary entries of a killed run: never complete, never needed.
  std::vector<std::filesystem::path> stale;
  for (const auto& e : std::filesystem::directory_iterator(dir_, ec)) {
    const std::string name = e.path().filename().string();
    if (name.starts_with(kEntryPrefix) && name.ends_with(kTempSuffix)) stale.push_back(e.path());
  }
  remove(stale);
}

void Journal::unlock() noexcept {
  if (lock_fd_ >= 0) {
    ::flock(lock_fd_, LOCK_UN);
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
}

std::filesystem::path Journal::append(std::int64_t index, std::span<const char> bytes) {
  char name[64];
  std::snprintf(name, sizeof name, "case-%010lld.rec", static_cast<long long>(index));
  const std::filesystem::path path = dir_ / name;
  std::filesystem::path temp = path;
  temp += kTempSuffix;

  ByteWriter header;
  header.u32(kJournalMagic);
  header.u32(kJournalVersion);
  header.i64(static_cast<std::int64_t>(hash_));
  header.i64(index);
  header.i64(static_cast<std::int64_t>(bytes.size()));
  header.i64(static_cast<std::int64_t>(fnv1a64(std::string_view(bytes.data(), bytes.size()))));
  const std::vector<char> head = header.take();

  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw io::IoError(temp.string() + ": cannot create journal entry: " + errno_text());
  const bool ok = write_all(fd, head.data(), head.size()) && write_all(fd, bytes.data(), bytes.size()) &&
                  ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  if (!ok) {
    ::unlink(temp.c_str());
    throw io::IoError(temp.string() + ": cannot write journal entry: " + std::strerror(saved));
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    const int e = errno;
    ::unlink(temp.c_str());
    throw io::IoError(path.string() + ": cannot move journal entry into place: " + std::strerror(e));
  }
  sync_directory(dir_);
  return path;
}

std::vector<Journal::Entry> Journal::read(std::vector<std::string>& notes) const {
  std::vector<Entry> entries;
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) return entries;
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(dir_, ec))
    if (is_entry_name(e.path().filename().string())) files.push_back(e.path());
  if (ec) throw io::IoError(dir_.string() + ": cannot list the journal: " + ec.message());
  std::sort(files.begin(), files.end());
  for (const auto& path : files) {
    std::ifstream in(path, std::ios::binary);
    const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in.eof() && in.fail()) throw io::IoError(path.string() + ": cannot read journal entry");
    try {
      ByteReader header(bytes);
      if (header.u32() != kJournalMagic) throw RecordFormatError("not a journal entry");
      if (header.u32() != kJournalVersion) throw RecordFormatError("unknown journal format version");
      const auto hash = static_cast<std::uint64_t>(header.i64());
      const std::int64_t index = header.i64();
      const std::int64_t size = header.i64();
      const auto checksum = static_cast<std::uint64_t>(header.i64());
      constexpr std::size_t head = 2 * sizeof(std::uint32_t) + 4 * sizeof(std::int64_t);
      if (hash != hash_)
        throw InputError("", detail::concat(path.string(), ": journal entry of another campaign (input hash ",
                                            hex64(hash), ", this campaign ", hex64(hash_),
                                            "); the campaign changed since the interrupted run"));
      if (size < 0 || static_cast<std::size_t>(size) != bytes.size() - head)
        throw RecordFormatError("payload truncated");
      const std::span<const char> payload(bytes.data() + head, static_cast<std::size_t>(size));
      if (fnv1a64(std::string_view(payload.data(), payload.size())) != checksum)
        throw RecordFormatError("checksum mismatch");
      CaseRecord record = deserialize(payload);
      if (record.index != index) throw RecordFormatError("case index differs from the header's");
      entries.push_back({path, std::move(record)});
    } catch (const RecordFormatError& e) {
      notes.push_back(path.string() + ": ignored (" + e.what() + "); the case will be run again");
    }
  }
  return entries;
}

void Journal::remove(const std::vector<std::filesystem::path>& entries) noexcept {
  for (const auto& p : entries) {
    std::error_code ec;
    std::filesystem::remove(p, ec);
  }
}

void Journal::clear() const {
  std::error_code ec;
  if (!std::filesystem::is_directory(dir_, ec)) return;
  std::vector<std::filesystem::path> doomed;
  for (const auto& e : std::filesystem::directory_iterator(dir_, ec)) {
    const std::string name = e.path().filename().string();
    if (is_entry_name(name) || (name.starts_with(kEntryPrefix) && name.ends_with(kTempSuffix))) doomed.push_back(e.path());
  }
  for (const auto& p : doomed)
    if (!std::filesystem::remove(p, ec) && ec) throw io::IoError(p.string() + ": cannot delete: " + ec.message());
}

void Journal::remove_directory() noexcept {
  std::error_code ec;
  std::filesystem::remove(dir_ / "lock", ec);
  unlock();
  std::filesystem::remove(dir_, ec);  // fails harmlessly if not empty
}

} // namespace pw::sweep
