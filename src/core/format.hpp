// printf-style formatting of one number into a std::string, for messages and
// report sentences ("chi2 " + fmt("%.0f", chi2)).
#pragma once

#include <array>
#include <charconv>
#include <cstdio>
#include <string>

namespace pw {

/// The shortest decimal text that reads back as exactly v (std::to_chars): for values a
/// user copies into a --set line or a file, so that they reproduce the run bit for bit.
inline std::string round_trip(double v) {
  std::array<char, 64> buf{};
  return std::string(buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr);
}

inline std::string fmt(const char* printf_format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, v);
  return buf;
}

} // namespace pw
