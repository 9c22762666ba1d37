// Error type of the file formats (TOML reading, HDF5 and CSV writing).
#pragma once

#include "core/error.hpp"

namespace pw::io {

/// A file could not be read, written, created or renamed. The message names
/// the file and, for HDF5, the object path inside it, followed by the
/// library's own explanation (HDF5 error stack, errno text).
class IoError : public Error {
public:
  using Error::Error;
};

} // namespace pw::io
