// printf-style formatting of one number into a std::string, for messages and
// report sentences ("chi2 " + fmt("%.0f", chi2)).
#pragma once

#include <cstdio>
#include <string>

namespace pw {

inline std::string fmt(const char* printf_format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, printf_format, v);
  return buf;
}

} // namespace pw
