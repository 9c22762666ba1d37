// Error types of the physics library.
//
// One exception type per failure class, each carrying a message a user can act
// on: the parameter, its value and the allowed range (HighFive/CLI11 style).
// Validation happens once, at the edge (config reading, model construction);
// inner numerical loops do not re-check their inputs.
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

namespace pw {

/// Invalid user input: a parameter outside its allowed range, an impossible
/// gear geometry, an unknown key. `parameter()` names the offending input.
class InputError : public std::runtime_error {
public:
  InputError(std::string parameter, const std::string& message)
      : std::runtime_error(parameter.empty() ? message : parameter + ": " + message),
        parameter_(std::move(parameter)) {}
  const std::string& parameter() const noexcept { return parameter_; }

private:
  std::string parameter_;
};

/// The numerical solution failed (Newton did not converge, the time step is
/// unstable, the response diverged). Not a programming error: the message says
/// which setting to change.
class SolverError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
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
