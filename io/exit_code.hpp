// The exit codes of the planetwear command, in one place (docs/cli.md has the
// table). Every front end (apps/planetwear.cpp, the sweep driver) maps an
// exception to its code with exit_code_of() and prints it with
// error_message(), so a failure class has one code and one message form.
#pragma once

#include <exception>
#include <string>

namespace pw::io {

enum class ExitCode : int {
  Ok = 0,             ///< success (also --help, --version)
  BadInput = 1,       ///< pw::InputError, a command-line parse error, an estimate over the memory limit
  SolverFailure = 2,  ///< pw::SolverError
  IoFailure = 3,      ///< pw::io::IoError: a file could not be read, written or renamed
  Incomplete = 4,     ///< wear stopped early (results written); sweep: some cases failed
  Internal = 5,       ///< anything else (std::bad_alloc despite the estimate, a bug): please report
};

inline int to_int(ExitCode c) { return static_cast<int>(c); }

/// The code of the exception `e` (see ExitCode).
ExitCode exit_code_of(const std::exception_ptr& e);

/// The one-line report of `e` for stderr: "planetwear: error: " followed by
/// the failure class where it helps ("solver failed: ", "I/O: ") and what().
std::string error_message(const std::exception_ptr& e);

/// The prefix of every error line the command prints.
inline constexpr const char* kErrorPrefix = "planetwear: error: ";

} // namespace pw::io
