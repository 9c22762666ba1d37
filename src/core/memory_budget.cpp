#include "core/memory_budget.hpp"

#include "core/error.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

namespace pw {
namespace {

/// Half the physical memory leaves room for the OS, the page cache and other
/// users of a shared machine; a process whose plan exceeds it is almost
/// certainly a typo (cycles x 1000) rather than an intended run.
constexpr double kPhysicalFraction = 0.5;

struct Limit {
  std::uint64_t bytes;
  std::string source;  ///< for messages
};

Limit machine_limit() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long page_size = sysconf(_SC_PAGE_SIZE);
  // sysconf fails only on exotic systems: then no estimate can be refused on
  // physical-memory grounds, and the environment variable is the only limit.
  double bytes = pages > 0 && page_size > 0 ? kPhysicalFraction * static_cast<double>(pages) * static_cast<double>(page_size)
                                            : 1e300;
  std::string source = "half of the physical memory; set " + std::string(kMemoryLimitVariable) + " to change it";
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY && static_cast<double>(as.rlim_cur) < bytes) {
    bytes = static_cast<double>(as.rlim_cur);
    source = "the address-space limit, ulimit -v; set " + std::string(kMemoryLimitVariable) + " lower to change it";
  }
  const double cap = static_cast<double>(UINT64_MAX / 2);
  return {static_cast<std::uint64_t>(std::min(bytes, cap)), source};
}

Limit current_limit() {
  const char* env = std::getenv(kMemoryLimitVariable);
  if (env && *env) return {parse_byte_size(env, kMemoryLimitVariable), "from " + std::string(kMemoryLimitVariable) + "=" + env};
  return machine_limit();
}

} // namespace

std::uint64_t parse_byte_size(const std::string& text, const std::string& param) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  std::string suffix(end);
  for (char& ch : suffix) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (suffix.ends_with("IB")) suffix.resize(suffix.size() - 2);
  else if (suffix.ends_with("B")) suffix.resize(suffix.size() - 1);
  const std::string_view units = "KMGT";
  double scale = 1;
  if (suffix.size() == 1 && units.find(suffix[0]) != std::string_view::npos)
    scale = std::pow(1024.0, static_cast<double>(units.find(suffix[0]) + 1));
  else if (!suffix.empty())
    scale = -1;
  const double bytes = number * scale;
  require(end != begin && scale > 0 && std::isfinite(bytes) && bytes >= 1 && bytes < 9e18, param,
          "must be a positive size in bytes, optionally with a suffix K, M, G or T (e.g. 512M, 2G), got '", text,
          "'");
  return static_cast<std::uint64_t>(bytes);
}

std::string format_bytes(double bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"};
  int u = 0;
  while (bytes >= 1024 && u < 6) {
    bytes /= 1024;
    ++u;
  }
  char buf[64];
  std::snprintf(buf, sizeof buf, u == 0 ? "%.0f %s" : "%.3g %s", bytes, units[u]);
  return buf;
}

std::uint64_t memory_limit_bytes() { return current_limit().bytes; }

void require_memory(double bytes, const std::string& param, const std::string& what, const std::string& remedy) {
  const Limit limit = current_limit();
  if (bytes <= static_cast<double>(limit.bytes)) return;
  throw InputError(param, detail::concat(what, " would need about ", format_bytes(bytes), ", more than the memory limit ",
                                         format_bytes(static_cast<double>(limit.bytes)), " (", limit.source, "); ",
                                         remedy));
}

} // namespace pw
