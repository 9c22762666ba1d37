// Version and build flags embedded in every output file.
#pragma once

#include <string>

namespace pw::io {
std::string software_version();  ///< e.g. "0.1.0"
std::string build_flags();       ///< build type, compiler and version
} // namespace pw::io
