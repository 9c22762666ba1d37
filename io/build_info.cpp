#include "build_info.hpp"

namespace pw::io {
std::string software_version() { return PLANETWEAR_VERSION; }
std::string build_flags() { return PLANETWEAR_BUILD_FLAGS; }
} // namespace pw::io
