#include "io/atomic_output.hpp"


#include "io/io_error.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>

#include <fcntl.h>
#include <unistd.h>

namespace pw::io {
namespace {

std::string errno_text() { return std::strerror(errno); }

/// fsync(2) of a file or directory; false with errno set on failure.
bool sync_path(const std::filesystem::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) return false;
  const bool ok = ::fsync(fd) == 0;
  const int saved = errno;
  ::close(fd);
  errno = saved;
  return ok;
}

} // namespace

AtomicOutput::AtomicOutput(std::filesystem::path destination, bool overwrite)
    : destination_(std::move(destination)), overwrite_(overwrite) {
  if (destination_.empty() || !destination_.has_filename())
    throw IoError("output path '" + destination_.string() + "' does not name a file");
  const std::filesystem::path directory =
      destination_.has_parent_path() ? destination_.parent_path() : std::filesystem::path(".");
  std::error_code ec;
  if (!std::filesystem::is_directory(directory, ec))
    throw IoError(destination_.string() + ": output directory '" + directory.string() + "' does not exist");
  if (std::filesystem::is_directory(destination_, ec))
    throw IoError(destination_.string() + ": is a directory, expected a file name");
  if (!overwrite_ && std::filesystem::exists(destination_, ec))
    throw IoError(destination_.string() + ": file exists and overwriting was not allowed");
  temp_ = destination_;
  temp_ += ".partial-" + std::to_string(::getpid());
  std::filesystem::remove(temp_, ec);  // left over by a crashed process with our pid
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

void AtomicOutput::commit() {
  if (committed_) throw IoError(destination_.string() + ": output already committed");
  std::error_code ec;
  if (!std::filesystem::is_regular_file(temp_, ec))
    throw IoError(destination_.string() + ": nothing to commit, temporary file '" + temp_.string() +
                  "' was not written");
  if (!sync_path(temp_, O_RDONLY))
    throw IoError(temp_.string() + ": cannot flush to disk: " + errno_text());
  if (overwrite_) {
    if (::rename(temp_.c_str(), destination_.c_str()) != 0)
      throw IoError(destination_.string() + ": cannot move '" + temp_.string() + "' into place: " + errno_text());
  } else {
    // link(2) fails with EEXIST instead of replacing: an atomic no-clobber move.
    if (::link(temp_.c_str(), destination_.c_str()) != 0)
      throw IoError(destination_.string() + ": cannot move '" + temp_.string() + "' into place: " + errno_text());
    ::unlink(temp_.c_str());
  }
  committed_ = true;
  // Make the rename itself durable (best effort: some file systems refuse).
  const std::filesystem::path directory =
      destination_.has_parent_path() ? destination_.parent_path() : std::filesystem::path(".");
  (void)sync_path(directory, O_RDONLY | O_DIRECTORY);
}

void write_text_atomically(const std::filesystem::path& path, const std::string& text) {
  AtomicOutput out(path);
  {
    std::ofstream f(out.temp_path(), std::ios::binary);
    if (!f) throw IoError("cannot write '" + out.temp_path().string() + "'");
    f << text;
    f.close();
    if (!f) throw IoError("cannot write '" + out.temp_path().string() + "'");
  }
  out.commit();
}

} // namespace pw::io
