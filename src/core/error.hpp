// Error types of the physics library.
//
// One base, pw::Error, and one exception type per failure class derived from
// it (InputError, SolverError here; io::IoError in io/io_error.hpp;
// sweep::RecordFormatError), each carrying a message a user can act on: the
// parameter, its value and the allowed range (HighFive/CLI11 style).
// io/exit_code.hpp maps each class to the command's exit code.
// Validation happens once, at the edge (config reading, model construction);
// inner numerical loops do not re-check their inputs.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace pw {

/// Base of every exception planetwear throws on purpose (what() is the whole
/// message). Anything else reaching a front end is a bug or std::bad_alloc.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// Invalid user input: a parameter outside its allowed range, an impossible
/// gear geometry, an unknown key. `parameter()` names the offending input.
class InputError : public Error {
public:
  InputError(std::string parameter, const std::string& message)
      : Error(parameter.empty() ? message : parameter + ": " + message),
        parameter_(std::move(parameter)) {}
  const std::string& parameter() const noexcept { return parameter_; }

private:
  std::string parameter_;
};

/// The numerical solution failed (Newton did not converge, the time step is
/// unstable, the response diverged). Not a programming error: the message says
/// which setting to change.
class SolverError : public Error {
public:
  using Error::Error;
};

namespace detail {
template <class... Args>
std::string concat(const Args&... args) {
  std::ostringstream os;
  os.precision(10);
  (os << ... << args);
  return os.str();
}
} // namespace detail

/// Always-on check of a user-facing condition (cf. MFEM_VERIFY / AssertThrow):
/// throws InputError naming `param` with the streamed message.
template <class... Args>
inline void require(bool condition, const std::string& param, const Args&... message) {
  if (!condition) throw InputError(param, detail::concat(message...));
}

} // namespace pw
